//! The viewer's pictures: what the window shows after a control is clicked,
//! read back from the rendered window (so that a fault anywhere between the
//! worker and the screen shows), and compared with what the light transport
//! says it must be.
#![cfg(feature = "gui")]

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::Vec3;
use lumiere::app::LumiereApp;
use lumiere::render::color::{linear_to_srgb, srgb_to_linear};
use lumiere::render::progressive::Snapshot;
use lumiere::render::settings::DisplaySettings;
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::{Film, RenderContext, Term, TermSet};

#[path = "common/viewer.rs"]
mod viewer_harness;
use viewer_harness::{WindowShot, harness, wait_for};

/// Steps the UI until the worker is idle with `done` true, then photographs
/// the window once a frame has drawn that snapshot.
fn shot_when(
    harness: &mut Harness<'static, LumiereApp>,
    what: &str,
    done: impl Fn(&Snapshot) -> bool,
) -> (Snapshot, WindowShot) {
    let snapshot = wait_for(harness, what, |s| s.idle && done(s));
    harness.run_steps(2);
    (snapshot, WindowShot::take(harness))
}

/// The film the worker accumulated for `snapshot`, rendered again by the
/// library through the scene's camera (the viewer's at start): sample s of
/// pixel i takes its random numbers from (sampler, seed, i, s) alone, so the
/// same settings and passes give the same film, bit for bit, with each
/// term's means and standard errors.
fn film_of(snapshot: &Snapshot) -> Film {
    let settings = &snapshot.source.as_ref().expect("a rendered image").settings;
    let context = RenderContext::new(builtin::cornell(), settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    render(
        &context,
        &mut film,
        Budget::Samples(snapshot.samples_per_pixel()),
        |_| {},
    );
    film
}

/// The linear value the viewer's blit puts on screen for `radiance` with
/// the default display (2^EV, then the tonemap), before sRGB encoding.
fn displayed(radiance: Vec3) -> [f64; 3] {
    let display = DisplaySettings::default();
    radiance
        .to_array()
        .map(|c| display.tonemap.apply(c * display.exposure.exp2()) as f64)
}

/// What the screen should show of `terms` of `film`, pixel by pixel.
fn displayed_image(film: &Film, terms: TermSet) -> Vec<[f64; 3]> {
    film.radiance(terms).into_iter().map(displayed).collect()
}

fn to_linear(code: u8) -> f64 {
    srgb_to_linear(code as f32 / 255.0) as f64
}

/// Largest gap, in 8-bit codes, between a code on screen and the exact
/// sRGB value it stands for: half a code from rounding to the nearest, and
/// 0.1 more that the graphics APIs allow their float-to-8-bit conversion.
const CODE_ERROR: f64 = 0.6;

/// The most the linear value shown as `code` can differ from the exact
/// one: `CODE_ERROR` codes, in linear units. The sRGB curve is convex, so
/// `CODE_ERROR` times the wider of the neighbouring codes bounds it.
fn linear_error(code: u8) -> f64 {
    let below = to_linear(code) - to_linear(code.saturating_sub(1));
    let above = to_linear(code.saturating_add(1)) - to_linear(code);
    CODE_ERROR * below.max(above)
}

/// Mean over pixels and channels.
fn mean(pixels: &[[f64; 3]]) -> f64 {
    pixels.iter().flatten().sum::<f64>() / (3 * pixels.len()) as f64
}

/// The linear values on screen, film pixel by film pixel.
fn shown_linear(shot: &WindowShot) -> Vec<[f64; 3]> {
    shot.film_colours()
        .into_iter()
        .map(|p| p.map(to_linear))
        .collect()
}

/// Asserts that every film pixel on screen is `expected` (linear) within
/// `CODE_ERROR` codes.
fn assert_shows(shot: &WindowShot, expected: &[[f64; 3]], what: &str) {
    for (i, (shown, expected)) in shot.film_colours().iter().zip(expected).enumerate() {
        for (&code, &value) in shown.iter().zip(expected) {
            let exact = 255.0 * linear_to_srgb(value as f32) as f64;
            assert!(
                (code as f64 - exact).abs() <= CODE_ERROR,
                "pixel {i} shows {shown:?}, {what} is {exact:.1} in 8-bit sRGB"
            );
        }
    }
}

/// Switched off, L2 leaves the screen showing L0+L1 of the same film;
/// switched on again, it comes back with the samples it kept.
#[test]
fn switching_l2_off_hides_it_without_restarting_the_film() {
    let mut harness = harness();
    assert_eq!(harness.state().state.display, DisplaySettings::default());
    harness.state_mut().state.stop_at_spp = Some(16);
    let (before, with_l2) = shot_when(&mut harness, "16 spp", |s| s.samples_per_pixel() >= 16);

    harness.get_by_label("L2").click();
    harness.run_steps(2);
    assert!(!harness.state().state.settings.terms.contains(Term::L2));
    let (after, without_l2) = shot_when(&mut harness, "the image without L2", |s| {
        !s.terms.contains(Term::L2)
    });
    assert_eq!(
        after.restarts, before.restarts,
        "a term switched off must not restart the film"
    );
    assert_eq!(after.term_samples, before.term_samples);

    harness.get_by_label("L2").click();
    let (reshown, with_l2_again) =
        shot_when(&mut harness, "L2 shown", |s| s.terms.contains(Term::L2));
    assert_eq!(reshown.restarts, before.restarts);

    // the worker's film, term by term
    let film = film_of(&before);
    let all = displayed_image(&film, TermSet::COURSE);
    let l0_l1 = displayed_image(&film, TermSet::COURSE.with(Term::L2, false));
    assert_shows(&with_l2, &all, "L0+L1+L2");
    assert_shows(&without_l2, &l0_l1, "L0+L1");
    assert_shows(&with_l2_again, &all, "L0+L1+L2, kept while hidden");

    // The mean on screen drops by L2's share of the display. Each value is
    // within `linear_error` of the exact one in both pictures, so the drop
    // is within the mean of their sum.
    let (shown_with, shown_without) = (shown_linear(&with_l2), shown_linear(&without_l2));
    let drop_shown = mean(&shown_with) - mean(&shown_without);
    let drop_expected = mean(&all) - mean(&l0_l1);
    let codes = with_l2
        .film_colours()
        .into_iter()
        .zip(without_l2.film_colours());
    let tolerance = codes
        .flat_map(|(a, b)| (0..3).map(move |c| linear_error(a[c]) + linear_error(b[c])))
        .sum::<f64>()
        / (3 * shown_with.len()) as f64;
    assert!(
        (drop_shown - drop_expected).abs() <= tolerance,
        "the mean dropped by {drop_shown:.5}, L2 shows {drop_expected:.5} (± {tolerance:.5})"
    );
    // L2's drop stands far outside the rounding, so a screen that kept L2
    // (a drop of 0) fails the check above by 7 tolerances at least
    assert!(
        drop_expected > 8.0 * tolerance,
        "L2 {drop_expected:.5}, tolerance {tolerance:.5}"
    );

    // hidden, L2 is no longer rendered; the other terms go on, on the same film
    harness.get_by_label("L2").click();
    harness.state_mut().state.stop_at_spp = None;
    let more = wait_for(&mut harness, "more samples without L2", |s| {
        !s.terms.contains(Term::L2)
            && s.term_samples[Term::L1.index()] > before.term_samples[Term::L1.index()] + 2
    });
    assert_eq!(more.restarts, before.restarts);
    assert_eq!(
        more.term_samples[Term::L2.index()],
        before.term_samples[Term::L2.index()]
    );
}
