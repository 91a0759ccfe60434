//! The viewer's pictures: what the window shows after a control is clicked,
//! read back from the rendered window (so that a fault anywhere between the
//! worker and the screen shows), and compared with what the light transport
//! says it must be.
#![cfg(feature = "gui")]

use std::ops::RangeInclusive;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::{Vec2, Vec3};
use lumiere::app::LumiereApp;
use lumiere::app::four_up_view::TileView;
use lumiere::course::color::{linear_to_srgb, luminance, srgb_to_linear};
use lumiere::render::display::{DisplaySettings, Layout};
use lumiere::render::progressive::Snapshot;
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::transport::splitting::choose_continuations;
use lumiere::{BrdfOverride, Film, LightMode, RenderContext, Term, TermSet};

#[path = "common/viewer.rs"]
mod viewer_harness;
use viewer_harness::{WindowShot, harness, harness_with_film, harness_with_window, wait_for};

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
    let mut context = RenderContext::new(builtin::cornell(), settings.clone());
    choose_continuations(&mut context);
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

/// The name of the object the camera sees at the centre of film pixel
/// (`x`, `y`) (the app's picking).
fn object_at(harness: &mut Harness<'static, LumiereApp>, x: u32, y: u32) -> Option<String> {
    let app = harness.state_mut();
    let (width, height) = (app.state.settings.width, app.state.settings.height);
    let uv = Vec2::new(
        (x as f32 + 0.5) / width as f32,
        (y as f32 + 0.5) / height as f32,
    );
    let object = app.pick(uv)?;
    Some(app.scene.objects[object as usize].name.clone())
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
    // (the worker learns that L2 is off while it is still held at its
    // sample count, then the hold is lifted: no pass of L2 can slip between)
    harness.get_by_label("L2").click();
    harness.run_steps(2);
    wait_for(&mut harness, "L2 off", |s| !s.terms.contains(Term::L2));
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

/// The shadow test's film: large enough that the area light's penumbra on
/// the red wall spans a few pixels.
const SHADOW_FILM: (u32, u32) = (128, 96);
/// Rows of that film in which the tall block's shadow on the red wall has
/// a nearly vertical edge, and columns that run from the lit wall, across
/// the edge, into the shadow.
const SHADOW_ROWS: RangeInclusive<u32> = 64..=78;
const SHADOW_COLUMNS: RangeInclusive<u32> = 21..=33;

/// The width of the shadow's edge over `SHADOW_ROWS`, in pixels.
struct EdgeWidth {
    mean: f64,
    /// Of the mean, from the spread of the rows (noise and the edge's own
    /// variation along the wall).
    standard_error: f64,
}

impl EdgeWidth {
    /// Measured on the red channel (the red wall reflects red only).
    fn measure(shot: &WindowShot) -> Self {
        let widths: Vec<f64> = SHADOW_ROWS
            .map(|y| {
                let red: Vec<f64> = SHADOW_COLUMNS
                    .map(|x| to_linear(shot.colour_at(x, y)[0]))
                    .collect();
                rise_20_80(&red)
            })
            .collect();
        let n = widths.len() as f64;
        let mean = widths.iter().sum::<f64>() / n;
        let variance = widths.iter().map(|w| (w - mean).powi(2)).sum::<f64>() / (n - 1.0);
        Self {
            mean,
            standard_error: (variance / n).sqrt(),
        }
    }
}

/// The distance, in pixels, over which `profile` falls from 20 % to 80 % of
/// the way from the lit level (the mean of its first three values) to the
/// shadow's (its last three), each crossing interpolated between pixels.
/// A step edge seen through square pixels is a one-pixel ramp: 0.6 px; a
/// penumbra adds its width.
fn rise_20_80(profile: &[f64]) -> f64 {
    let n = profile.len();
    let lit = profile[..3].iter().sum::<f64>() / 3.0;
    let shadow = profile[n - 3..].iter().sum::<f64>() / 3.0;
    let crossing = |fraction: f64| {
        let level = lit - fraction * (lit - shadow);
        let x = (1..n)
            .find(|&x| profile[x] < level)
            .expect("the profile falls to the shadow");
        let (a, b) = (profile[x - 1], profile[x]);
        (x - 1) as f64 + ((a - level) / (a - b)).clamp(0.0, 1.0)
    };
    crossing(0.8) - crossing(0.2)
}

/// A point light casts hard shadows: its shadow edges are steps where the
/// authored area light's are penumbrae.
#[test]
fn all_point_lights_restart_and_sharpen_the_shadow_edges() {
    let (width, height) = SHADOW_FILM;
    let mut harness = harness_with_film(width, height);
    // 256 spp: the rows' spread then gives the mean width a standard error
    // under 0.1 px, against a narrowing of about a pixel
    harness.state_mut().state.stop_at_spp = Some(256);
    let (area, area_shot) = shot_when(&mut harness, "256 spp", |s| s.samples_per_pixel() >= 256);
    for y in SHADOW_ROWS {
        for x in SHADOW_COLUMNS {
            let object = object_at(&mut harness, x, y);
            assert_eq!(
                object.as_deref(),
                Some("red wall (left)"),
                "pixel ({x}, {y})"
            );
        }
    }

    harness.get_by_label("All point").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.settings.light_mode, LightMode::Point);
    let (_, point_shot) = shot_when(&mut harness, "the restart, 256 spp", |s| {
        s.restarts > area.restarts && s.samples_per_pixel() >= 256
    });

    let area_edge = EdgeWidth::measure(&area_shot);
    let point_edge = EdgeWidth::measure(&point_shot);
    // a step: 0.6 px through square pixels, plus the edge's slant across the
    // rows and the noise
    assert!(
        point_edge.mean < 1.0,
        "the point light's shadow edge rises over {:.2} px",
        point_edge.mean
    );
    let noise = area_edge.standard_error.hypot(point_edge.standard_error);
    assert!(
        area_edge.mean - point_edge.mean > 8.0 * noise,
        "the edge rises over {:.2} px with the area light, {:.2} px with the point (± {noise:.2})",
        area_edge.mean,
        point_edge.mean
    );
}

/// Film pixels (row-major indices) on which the camera sees one of the blocks.
fn block_pixels(harness: &mut Harness<'static, LumiereApp>) -> Vec<usize> {
    let settings = &harness.state().state.settings;
    let (width, height) = (settings.width, settings.height);
    let mut blocks = Vec::new();
    for y in 0..height {
        for x in 0..width {
            if object_at(harness, x, y).is_some_and(|name| name.ends_with(" block")) {
                blocks.push((y * width + x) as usize);
            }
        }
    }
    blocks
}

/// Mirrors instead of the blocks' white Lambertian surfaces: the blocks'
/// pixels change far beyond their noise.
#[test]
fn the_mirror_brdf_restarts_and_changes_the_blocks() {
    let mut harness = harness();
    harness.state_mut().state.stop_at_spp = Some(16);
    let (authored, authored_shot) =
        shot_when(&mut harness, "16 spp", |s| s.samples_per_pixel() >= 16);
    harness.get_by_label("BRDF").click();
    harness.run_steps(2);
    harness.get_by_label("Mirror").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.settings.brdf, BrdfOverride::Mirror);
    let (mirror, mirror_shot) = shot_when(&mut harness, "the restart, 16 spp", |s| {
        s.restarts > authored.restarts && s.samples_per_pixel() >= 16
    });

    // the blocks' mean displayed luminance, before and after
    let blocks = block_pixels(&mut harness);
    // the two blocks fill about an eighth of the image
    assert!(
        blocks.len() > 64 * 48 / 10,
        "the blocks cover {} pixels",
        blocks.len()
    );
    let n = blocks.len() as f64;
    let blocks_mean = |shot: &WindowShot, value: &dyn Fn([u8; 3]) -> f64| {
        let colours = shot.film_colours();
        blocks.iter().map(|&i| value(colours[i])).sum::<f64>() / n
    };
    let shown = |colour: [u8; 3]| luminance(colour.map(to_linear).map(|c| c as f32).into()) as f64;
    let change = blocks_mean(&mirror_shot, &shown) - blocks_mean(&authored_shot, &shown);
    // Its uncertainty: the Monte Carlo noise of both means (each pixel's
    // standard error summed over the terms, a bound for correlated terms),
    // and the 8-bit rounding of both pictures.
    let (authored_film, mirror_film) = (film_of(&authored), film_of(&mirror));
    let standard_error = |film: &Film, i: usize| {
        TermSet::COURSE
            .iter()
            .map(|t| film.term(t).expect("rendered").standard_error(i))
            .sum::<f64>()
    };
    let noise = blocks
        .iter()
        .map(|&i| {
            standard_error(&authored_film, i).powi(2) + standard_error(&mirror_film, i).powi(2)
        })
        .sum::<f64>()
        .sqrt()
        / n;
    let rounding =
        |colour: [u8; 3]| luminance(colour.map(linear_error).map(|c| c as f32).into()) as f64;
    let rounding = blocks_mean(&authored_shot, &rounding) + blocks_mean(&mirror_shot, &rounding);
    // ten standard errors beyond the rounding: no noise moves a mean that far
    assert!(
        change.abs() > 10.0 * noise + rounding,
        "the blocks' luminance changed by {change:.4} (noise {noise:.4}, rounding {rounding:.4})"
    );
}

/// The colour on screen of each film pixel of a four-up tile, row by row;
/// `None` under the tile's label.
fn tile_colours(shot: &WindowShot, view: &TileView, ppp: f32) -> Vec<Option<[u8; 3]>> {
    let rect = view.rect * ppp;
    let label = view.label_rect.map(|r| r.expand(2.0) * ppp);
    let (width, height) = (shot.film_width, shot.film_height);
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let point = rect.min
                + egui::vec2(
                    (x as f32 + 0.5) / width as f32 * rect.width(),
                    (y as f32 + 0.5) / height as f32 * rect.height(),
                );
            if label.is_some_and(|l| l.contains(point)) {
                return None;
            }
            let p = shot.window.get_pixel(point.x as u32, point.y as u32);
            Some([p[0], p[1], p[2]])
        })
        .collect()
}

/// The 8-bit sRGB code the blit gives a linear `value` (default display).
fn code_of(value: f32) -> f64 {
    255.0 * linear_to_srgb(displayed(Vec3::splat(value))[0] as f32) as f64
}

/// Asserts that the film pixels of a tile on screen (where no label covers
/// them) show `image` within `CODE_ERROR` codes.
fn assert_tile_shows(tile: &[Option<[u8; 3]>], image: &[[f32; 4]], what: &str) {
    for (i, (shown, value)) in tile.iter().zip(image).enumerate() {
        if let Some(shown) = shown {
            for (&code, &value) in shown.iter().zip(value) {
                assert!(
                    (code as f64 - code_of(value)).abs() <= CODE_ERROR,
                    "pixel {i} of the {what} tile shows {shown:?}, {value} is {:.1}",
                    code_of(value)
                );
            }
        }
    }
}

/// The four-up: four labelled tiles of one render. L0's is black but for
/// the light; each tile shows its own term of the worker's snapshot; the
/// sum tile is, pixel by pixel, the three others added (within the 8-bit
/// rounding, where nothing clips); switched off, L2 leaves an empty tile
/// saying "off" and the sum loses it.
#[test]
fn the_four_up_shows_each_term_and_their_sum_from_one_render() {
    let mut harness = harness();
    harness.state_mut().state.stop_at_spp = Some(16);
    harness.get_by_label("four-up").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.display.layout, Layout::FourUp);
    let (snapshot, shot) = shot_when(&mut harness, "16 spp of each term", |s| {
        s.samples_per_pixel() >= 16 && s.term_images[..3].iter().all(Option::is_some)
    });
    let ppp = harness.ctx.pixels_per_point();
    let views = harness.state().four_up.tiles.clone();
    assert_eq!(
        views.iter().map(|v| v.label.as_str()).collect::<Vec<_>>(),
        [
            "L0 emission",
            "L1 direct",
            "L2 indirect (one bounce)",
            "L0+L1+L2"
        ]
    );
    for view in &views {
        harness.get_by_label(&view.label);
        assert!(!view.off && view.label_rect.is_some());
    }
    // 2 × 2 in this tall window, the tiles of equal size and aligned
    let [a, b, c, d] = [0, 1, 2, 3].map(|i| views[i].rect);
    assert!(a.min.y == b.min.y && c.min.y == d.min.y && c.min.y >= a.max.y - 0.01);
    assert!(a.min.x == c.min.x && b.min.x == d.min.x && b.min.x >= a.max.x - 0.01);
    assert!(
        views
            .iter()
            .all(|v| (v.rect.size() - a.size()).length() < 0.01)
    );

    let tiles: Vec<Vec<Option<[u8; 3]>>> = views
        .iter()
        .map(|view| tile_colours(&shot, view, ppp))
        .collect();
    // each term's tile shows that term of the worker's snapshot
    let term = |t: Term| snapshot.term_images[t.index()].as_ref().unwrap();
    assert_tile_shows(&tiles[0], term(Term::L0), "L0");
    assert_tile_shows(&tiles[1], term(Term::L1), "L1");
    assert_tile_shows(&tiles[2], term(Term::L2), "L2");
    assert_tile_shows(&tiles[3], &snapshot.radiance, "sum");
    // L0: black but for the light, a small part of the image
    let lit = tiles[0]
        .iter()
        .flatten()
        .filter(|c| **c != [0, 0, 0])
        .count();
    let seen = tiles[0].iter().flatten().count();
    assert!(
        lit > 0 && lit * 20 < seen,
        "{lit} of {seen} pixels of L0 are not black"
    );
    for (shown, value) in tiles[0].iter().zip(term(Term::L0)) {
        if shown.is_some_and(|c| c != [0, 0, 0]) {
            assert!(value[..3].iter().any(|&v| v > 0.0), "L0 is 0 there");
        }
    }
    // the sum tile is the three others added, where no value clips
    let mut compared = 0;
    let pixels = tiles[0].iter().zip(&tiles[1]).zip(&tiles[2]).zip(&tiles[3]);
    for (i, (((l0, l1), l2), sum)) in pixels.enumerate() {
        let (Some(l0), Some(l1), Some(l2), Some(sum)) = (l0, l1, l2, sum) else {
            continue;
        };
        if sum.contains(&255) {
            continue;
        }
        compared += 1;
        for k in 0..3 {
            let added = to_linear(l0[k]) + to_linear(l1[k]) + to_linear(l2[k]);
            let tolerance = [l0[k], l1[k], l2[k], sum[k]]
                .map(linear_error)
                .iter()
                .sum::<f64>();
            assert!(
                (to_linear(sum[k]) - added).abs() <= tolerance,
                "pixel {i}: the sum shows {}, L0 + L1 + L2 shows {added} (± {tolerance})",
                to_linear(sum[k])
            );
        }
    }
    assert!(compared > tiles[3].len() / 2, "{compared} pixels compared");

    // L2 off: its tile empty, saying so; the sum without it; no restart
    harness.get_by_label("L2").click();
    harness.run_steps(2);
    let (without, shot) = shot_when(&mut harness, "the image without L2", |s| {
        !s.terms.contains(Term::L2)
    });
    assert_eq!(without.restarts, snapshot.restarts);
    let views = harness.state().four_up.tiles.clone();
    assert!(views[2].off && !views[0].off && !views[1].off && !views[3].off);
    assert_eq!(views[3].label, "L0+L1");
    harness.get_by_label("off");
    harness.get_by_label("L0+L1");
    // "off" is written in the middle: the rest of the tile is the background
    let empty = tile_colours(&shot, &views[2], ppp);
    let (width, rows) = (shot.film_width as usize, shot.film_height as usize);
    for (i, colour) in empty.iter().enumerate() {
        let y = i / width;
        if let Some(colour) = colour
            && (y < rows / 3 || y >= 2 * rows / 3)
        {
            assert_eq!(*colour, [24, 24, 24], "pixel {i} of the empty tile");
        }
    }
    let sum = tile_colours(&shot, &views[3], ppp);
    assert_tile_shows(&sum, &without.radiance, "L0+L1");
}

/// A wide viewport takes the four tiles in a row; a screenshot's PNG holds
/// the four tiles in a row, labelled below, and its sidecar the layout.
#[test]
fn the_four_up_is_a_row_in_a_wide_window_and_in_the_screenshot() {
    let mut harness = harness_with_window(64, 48, [2400.0, 620.0]);
    harness.state_mut().state.stop_at_spp = Some(4);
    harness.key_press(egui::Key::Num4);
    harness.run_steps(2);
    assert_eq!(harness.state().state.display.layout, Layout::FourUp);
    shot_when(&mut harness, "4 spp of each term", |s| {
        s.samples_per_pixel() >= 4 && s.term_images[..3].iter().all(Option::is_some)
    });
    let views = harness.state().four_up.tiles.clone();
    assert_eq!(views.len(), 4);
    for pair in views.windows(2) {
        assert_eq!(pair[0].rect.min.y, pair[1].rect.min.y);
        assert!(pair[1].rect.min.x >= pair[0].rect.max.x - 0.01);
    }

    let folder = std::env::temp_dir().join(format!("lumiere-four-up-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    harness.state_mut().state.export_dir = folder.to_string_lossy().into_owned();
    harness.state_mut().save_screenshot();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while !harness
        .state()
        .message
        .as_deref()
        .is_some_and(|m| m.starts_with("saved"))
    {
        assert!(
            std::time::Instant::now() < deadline,
            "{:?}",
            harness.state().message
        );
        harness.step();
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let png = image::open(folder.join("lumiere-001.png"))
        .unwrap()
        .to_rgb8();
    assert_eq!(png.width(), 4 * 64);
    assert!(png.height() > 48, "the labels' band below the tiles");
    let sidecar =
        lumiere::render::sidecar::Sidecar::load(&folder.join("lumiere-001.json")).unwrap();
    assert_eq!(sidecar.display.layout, Layout::FourUp);
    let exr = lumiere::render::export::load_exr(&folder.join("lumiere-001.exr")).unwrap();
    assert_eq!(
        (exr.0, exr.1),
        (64, 48),
        "the EXR is the image of the terms"
    );
    let _ = std::fs::remove_dir_all(&folder);
}
