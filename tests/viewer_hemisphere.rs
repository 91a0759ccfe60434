//! The integral at p in the viewer: a probe click opens the view of the
//! integrand over the hemisphere at the pixel's first hit, it follows the
//! term asked for, and a lesson step's probe opens it without covering the
//! step's texts.
#![cfg(feature = "gui")]

use std::time::{Duration, Instant};

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::{Vec2, Vec3};
use lumiere::analysis::hemisphere::{Vertex, integrand_map};
use lumiere::app::hemisphere_view::{
    HEMISPHERE_WINDOW_ID, HEMISPHERE_WINDOW_TITLE, MAP_SIZE, ROUNDS,
};
use lumiere::app::probe_view::PROBE_WINDOW_ID;
use lumiere::app::{LumiereApp, ViewOptions};
use lumiere::lesson::{Lang, Lesson};
use lumiere::{RenderContext, RenderSettings, Term, TermSet};

#[path = "common/viewer.rs"]
mod viewer_harness;
use viewer_harness::{harness, wait_for};

fn wait_for_app(
    harness: &mut Harness<'static, LumiereApp>,
    what: &str,
    done: impl Fn(&LumiereApp) -> bool,
) {
    let deadline = Instant::now() + Duration::from_secs(120);
    while !done(harness.state()) {
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        harness.step();
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A short click at `pos`.
fn click(harness: &mut Harness<'static, LumiereApp>, pos: egui::Pos2) {
    let button = |pressed| egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::default(),
    };
    harness.event(egui::Event::PointerMoved(pos));
    harness.step();
    harness.event(button(true));
    harness.step();
    harness.event(button(false));
    harness.run_steps(2);
}

/// A viewer stopped at `spp` samples per pixel, with the probe on the
/// back wall under the light (every bounce from it stays in the box);
/// `before` looks at the window before the click.
fn probe_the_back_wall(
    spp: u32,
    before: impl FnOnce(&mut Harness<'static, LumiereApp>),
) -> (Harness<'static, LumiereApp>, (u32, u32)) {
    let mut harness = harness();
    harness.state_mut().state.stop_at_spp = Some(spp);
    wait_for(&mut harness, "the film's samples", |s| {
        s.idle && s.samples_per_pixel() >= spp
    });
    before(&mut harness);
    harness.get_by_label("Probe").click();
    harness.run_steps(2);
    let rect = harness.state().image_rect().expect("the image is drawn");
    click(
        &mut harness,
        rect.min + egui::vec2(rect.width() * 0.5, rect.height() * 0.3),
    );
    let pixel = harness.state().probe.pixel.expect("a pixel is probed");
    (harness, pixel)
}

/// The map the view shows for `term` at `pixel` is the one `analysis`
/// computes for the pixel-centre ray, round after round up to the last.
fn assert_shows_the_map(harness: &mut Harness<'static, LumiereApp>, pixel: (u32, u32), term: Term) {
    wait_for_app(harness, "the last round of the map", |app| {
        app.hemisphere.result.as_ref().is_some_and(|r| {
            r.pixel() == pixel && r.vertex() == Vertex::FirstHit && r.term() == term && r.is_final()
        })
    });
    harness.run_steps(2);
    harness.get_by_label(HEMISPHERE_WINDOW_TITLE);
    let app = harness.state();
    let result = app.hemisphere.result.clone().unwrap();
    let outcome = result.outcome.as_ref().expect("a map at p");
    assert_eq!(outcome.map.directions_per_pixel, *ROUNDS.last().unwrap());
    let settings = RenderSettings {
        terms: TermSet::ALL,
        auto_indirect_samples: false,
        ..app.state.settings.clone()
    };
    let context = RenderContext::with_camera(
        std::sync::Arc::clone(&app.scene),
        settings.clone(),
        Some(&app.camera),
    );
    let ray = context.camera.generate(pixel.0, pixel.1, Vec2::splat(0.5));
    let expected = integrand_map(
        &context,
        &ray,
        TermSet::only(term),
        MAP_SIZE,
        outcome.map.directions_per_pixel,
        settings.seed,
    )
    .unwrap();
    assert_eq!(
        outcome.map.values, expected.values,
        "the view's map is the analysis'"
    );
    assert!(luminance_sum(&outcome.map.values) > 0.0);
}

fn luminance_sum(values: &[Vec3]) -> f32 {
    values.iter().map(|v| v.x + v.y + v.z).sum()
}

#[test]
fn a_probe_click_opens_the_integral_at_p_for_the_term_asked() {
    let (mut harness, pixel) = probe_the_back_wall(4, |harness| {
        assert!(harness.query_by_label(HEMISPHERE_WINDOW_TITLE).is_none());
    });
    // L0, L1 and L2 are shown: the view integrates L1, the lowest integral term
    assert_shows_the_map(&mut harness, pixel, Term::L1);
    let domains = harness
        .state()
        .hemisphere
        .result
        .as_ref()
        .unwrap()
        .outcome
        .as_ref()
        .unwrap()
        .at_point
        .domains
        .clone();
    assert_eq!(domains.names, ["light"], "the light's domain is on the map");
    // the samples drawn at p are the film's: over the film's 4 samples
    // their mean is the probe's, to rounding
    wait_for_app(&mut harness, "the probe", |app| app.probe.result.is_some());
    let probe = harness.state().probe.result.clone().unwrap();
    let probed = probe
        .probe
        .terms
        .iter()
        .find(|t| t.term == Term::L1)
        .unwrap();
    let computed = harness.state().hemisphere.result.clone().unwrap();
    let drawn = &computed.outcome.as_ref().unwrap().at_point.drawn;
    let first: Vec<f32> = drawn.per_pass[..4]
        .iter()
        .map(|v| lumiere::course::color::luminance(*v))
        .collect();
    let mean = first.iter().sum::<f32>() as f64 / 4.0;
    assert!(
        (mean - probed.mean_luminance()).abs() <= 1e-5 * mean.abs().max(1e-6),
        "drawn {mean} vs probed {}",
        probed.mean_luminance()
    );
    // L2 asked for: the map of one indirect bounce, zero where the light is seen
    // the window's L2, after the Terms group's
    harness
        .get_all_by_label("L2")
        .last()
        .expect("the window's L2")
        .click();
    harness.run_steps(2);
    assert_shows_the_map(&mut harness, pixel, Term::L2);
    let result = harness.state().hemisphere.result.clone().unwrap();
    let map = &result.outcome.as_ref().unwrap().map;
    let size = MAP_SIZE as usize;
    let inside = |i: usize| domains.source[i].is_some() && domains.visible[i];
    let interior: Vec<usize> = (size + 1..size * size - size - 1)
        .filter(|&i| {
            [i, i - 1, i + 1, i - size, i + size]
                .into_iter()
                .all(inside)
        })
        .collect();
    assert!(!interior.is_empty(), "the light covers pixels of the map");
    assert!(
        interior.iter().all(|&i| map.values[i] == Vec3::ZERO),
        "L2 inside Ω_s"
    );
    // closed from its window, reopened from the probe's
    let hemisphere_rect = harness
        .ctx
        .memory(|m| m.area_rect(egui::Id::unique(HEMISPHERE_WINDOW_ID)))
        .unwrap();
    click(
        &mut harness,
        hemisphere_rect.right_top() + egui::vec2(-14.0, 14.0),
    );
    assert!(
        !harness.state().hemisphere.shown,
        "the window's close button hides the view"
    );
    assert!(harness.query_by_label(HEMISPHERE_WINDOW_TITLE).is_none());
    harness.get_by_label("the integral at p").click();
    harness.run_steps(2);
    assert!(harness.state().hemisphere.shown);
}

/// Step 25 of the built-in lesson probes a pixel of the floor with only L2
/// shown: the view opens on L2, and neither window covers the step's
/// title, formula or caption.
#[test]
fn a_lesson_steps_probe_opens_the_view_beside_its_texts() {
    let (width, height) = (64, 48);
    let lesson = Lesson::load("simulation-notions").expect("the built-in lesson");
    let index = lesson
        .steps
        .iter()
        .position(|s| s.settings.probe.is_some())
        .expect("a step probes a pixel");
    let options = ViewOptions {
        settings: RenderSettings {
            width,
            height,
            ..RenderSettings::default()
        },
        lesson: Some(lesson.clone()),
        step: index,
        lang: Lang::Fr,
        ..ViewOptions::default()
    };
    let mut harness = Harness::builder()
        .with_size([1100.0, 800.0])
        .wgpu()
        .build_eframe(|cc| LumiereApp::new(cc, options).expect("the lesson opens"));
    harness.run_steps(2);
    let view = lesson.view(index, width, height).unwrap();
    let pixel = view.probe.expect("the step's probe");
    assert_eq!(harness.state().probe.pixel, Some(pixel));
    let term = harness.state().hemisphere.term_for(view.settings.terms);
    assert_shows_the_map(&mut harness, pixel, term);
    harness.run_steps(3);
    let area = harness.state().windows_area().expect("the image's area");
    for id in [PROBE_WINDOW_ID, HEMISPHERE_WINDOW_ID] {
        let rect = harness
            .ctx
            .memory(|m| m.area_rect(egui::Id::unique(id)))
            .expect("the window is shown");
        assert!(
            area.expand(0.5).contains_rect(rect),
            "{id}: {rect:?} leaves {area:?}, over the step's texts"
        );
    }
}

/// The sampling lab in the window: opened, it tests the light samples at
/// p against their own density and accepts; against a uniform density it
/// rejects, and the window says so.
#[test]
fn the_sampling_lab_accepts_the_strategys_density_and_rejects_a_wrong_one() {
    use lumiere::analysis::sampling_lab::Against;
    use lumiere::analysis::strategy_samples::Strategy;
    let (mut harness, pixel) = probe_the_back_wall(1, |_| {});
    assert_shows_the_map(&mut harness, pixel, Term::L1);
    let verdict = |harness: &mut Harness<'static, LumiereApp>, against: Against| {
        let lab = &mut harness.state_mut().hemisphere.lab;
        (lab.open, lab.strategy, lab.against, lab.samples) =
            (true, Strategy::Light, against, 20_000);
        harness.run_steps(2);
        wait_for_app(harness, "the sampling lab", |app| {
            let lab = &app.hemisphere.lab;
            lab.result.as_ref().is_some_and(|r| {
                r.outcome
                    .as_ref()
                    .is_ok_and(|t| t.against == against && t.drawn == 20_000)
            })
        });
        harness.run_steps(3);
        let result = harness.state().hemisphere.lab.result.clone().unwrap();
        let tested = result.outcome.as_ref().unwrap().clone();
        let word = if tested.accepted() {
            "accepted"
        } else {
            "rejected"
        };
        let shown = harness.query_by_label_contains(word).is_some();
        (tested, shown)
    };
    let (own, shown) = verdict(&mut harness, Against::Own);
    assert!(own.accepted(), "own density: p = {}", own.chi2.p_value);
    assert!(own.chi2.dof >= 3, "the light covers several bins");
    assert!(shown, "the window states the verdict");
    let (uniform, shown) = verdict(&mut harness, Against::Uniform);
    assert!(!uniform.accepted() && uniform.chi2.p_value < 1e-12);
    assert!(shown, "the window states the verdict");
}

/// The nested integral from the path view: "∫ at q" on the drawn path's
/// bounce from p opens the view at q, where the bounce lands, with the
/// same map as the analysis computes along the bounce; "back to p" returns.
#[test]
fn the_path_view_opens_the_integral_at_q() {
    use lumiere::app::hemisphere_view::HEMISPHERE_WINDOW_TITLE_AT_Q;
    let (mut harness, pixel) = probe_the_back_wall(2, |_| {});
    assert_shows_the_map(&mut harness, pixel, Term::L1);
    wait_for_app(&mut harness, "the drawn path", |app| {
        app.probe.path.recorded.is_some()
    });
    harness.run_steps(2);
    assert!(
        harness
            .query_by_label(HEMISPHERE_WINDOW_TITLE_AT_Q)
            .is_none()
    );
    harness
        .get_all_by_label("∫ at q")
        .next()
        .expect("the path's bounce from p offers the integral at q")
        .click();
    harness.run_steps(2);
    let bounce = harness
        .state()
        .hemisphere
        .at_q
        .as_ref()
        .expect("q is picked")
        .bounce;
    wait_for_app(&mut harness, "the last round of the map at q", |app| {
        app.hemisphere
            .result
            .as_ref()
            .is_some_and(|r| r.vertex() == Vertex::Second { bounce } && r.is_final())
    });
    harness.run_steps(3);
    assert!(
        harness
            .query_by_label(HEMISPHERE_WINDOW_TITLE_AT_Q)
            .is_some()
    );
    let computed = harness.state().hemisphere.result.clone().unwrap();
    let outcome = computed
        .outcome
        .as_ref()
        .expect("q is on a wall of the box");
    // the map at q is the analysis' along the bounce
    let app = harness.state();
    let settings = RenderSettings {
        terms: TermSet::ALL,
        auto_indirect_samples: false,
        ..app.state.settings.clone()
    };
    let context = RenderContext::with_camera(
        std::sync::Arc::clone(&app.scene),
        settings.clone(),
        Some(&app.camera),
    );
    let last = *ROUNDS.last().unwrap();
    let map = integrand_map(
        &context,
        &bounce,
        TermSet::only(Term::L1),
        MAP_SIZE,
        last,
        settings.seed,
    )
    .unwrap();
    assert_eq!(outcome.map.values, map.values, "the same map at q");
    harness.get_by_label("← back to p").click();
    harness.run_steps(2);
    assert!(harness.state().hemisphere.at_q.is_none());
    assert_shows_the_map(&mut harness, pixel, Term::L1);
    assert!(harness.query_by_label(HEMISPHERE_WINDOW_TITLE).is_some());
}
