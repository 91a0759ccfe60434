//! The viewer's widgets, clicked by their labels in a headless egui (wgpu on
//! the machine's Vulkan/GL driver), and the render worker's response.
#![cfg(feature = "gui")]

use std::sync::Arc;
use std::time::{Duration, Instant};

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lumiere::analysis::metrics::ReferenceImage;
use lumiere::analysis::noise::DisplayMode;
use lumiere::analysis::path_view::RayRole;
use lumiere::app::LumiereApp;
use lumiere::app::probe_view::PROBE_WINDOW_ID;
use lumiere::course::Integrator;
use lumiere::render::progressive::Snapshot;
use lumiere::{BrdfOverride, LightMode, Term};

#[path = "common/viewer.rs"]
mod viewer_harness;
use viewer_harness::{WindowShot, harness, wait_for};

#[test]
fn the_lecture_integrator_is_a_choice_of_the_sampling_group() {
    let mut harness = harness();
    let fast = wait_for(&mut harness, "16 spp", |s| s.samples_per_pixel() >= 16);
    harness.get_by_label("integrator").click();
    harness.run_steps(2);
    harness.get_by_label("lecture").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.settings.integrator,
        Integrator::Lecture
    );
    let lecture = wait_for(&mut harness, "16 spp of the lecture's", |s| {
        s.restarts > fast.restarts
            && s.samples_per_pixel() >= 16
            && s.source
                .as_ref()
                .is_some_and(|source| source.settings.integrator == Integrator::Lecture)
    });
    // another estimator ran: same scene, other noise (that the two agree
    // in the mean is tests/lecture.rs's to check, with their errors)
    assert!(
        lecture
            .radiance
            .iter()
            .any(|p| p[..3].iter().any(|&c| c > 0.0))
    );
    assert_ne!(
        fast.radiance, lecture.radiance,
        "the lecture integrator's image is the fast one's"
    );
}

#[test]
fn pause_button_and_keyboard_shortcuts() {
    let mut harness = harness();
    harness.get_by_label("Pause").click();
    harness.run_steps(2);
    assert!(harness.state().paused);
    let paused = wait_for(&mut harness, "the worker to idle", |s| {
        s.idle || s.generation > 0
    });
    std::thread::sleep(Duration::from_millis(200));
    harness.step();
    let later = harness.state().snapshot();
    assert!(
        later.samples_per_pixel() <= paused.samples_per_pixel() + 1,
        "paused, yet still rendering"
    );
    harness.get_by_label("Resume").click();
    harness.run_steps(2);
    assert!(!harness.state().paused);

    harness.key_press(egui::Key::Num0);
    harness.run_steps(2);
    assert!(!harness.state().state.settings.terms.contains(Term::L0));
    harness.key_press(egui::Key::L);
    harness.run_steps(2);
    assert_eq!(harness.state().state.settings.light_mode, LightMode::Point);
    harness.key_press(egui::Key::B);
    harness.run_steps(2);
    assert_eq!(harness.state().state.settings.brdf, BrdfOverride::Lambert);
}

/// Presses and releases the primary button at `from`, moving to `to` in between.
fn mouse_drag(harness: &mut Harness<'static, LumiereApp>, from: egui::Pos2, to: egui::Pos2) {
    let button = |pos, pressed| egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::default(),
    };
    harness.event(egui::Event::PointerMoved(from));
    harness.step();
    harness.event(button(from, true));
    harness.step();
    // a click must be short: no intermediate frames when the pointer does not move
    if to != from {
        for k in 1..=4 {
            harness.event(egui::Event::PointerMoved(
                from + (to - from) * (k as f32 / 4.0),
            ));
            harness.step();
        }
    }
    harness.event(button(to, false));
    harness.run_steps(2);
}

#[test]
fn clicking_an_object_selects_it_and_its_model_can_change_alone() {
    let mut harness = harness();
    let rect = harness.state().image_rect().expect("the image is drawn");
    // the red wall: left of the image, half-way down
    let on_red_wall = rect.min + egui::vec2(rect.width() * 0.22, rect.height() * 0.5);
    mouse_drag(&mut harness, on_red_wall, on_red_wall);
    let app = harness.state();
    let selected = app.selected.expect("a click selects an object") as usize;
    assert_eq!(app.scene.objects[selected].name, "red wall (left)");

    harness.get_by_label("model").click();
    harness.run_steps(2);
    harness.get_by_label("Mirror").click();
    harness.run_steps(2);
    let scene = &harness.state().scene;
    let material = &scene.materials[scene.objects[selected].material as usize];
    assert_eq!(material.brdf_model(), lumiere::scene::BrdfModel::Mirror);
    let floor = scene.objects.iter().find(|o| o.name == "floor").unwrap();
    assert_eq!(
        scene.materials[floor.material as usize].brdf_model(),
        lumiere::scene::BrdfModel::Lambert,
        "other objects keep their material"
    );
}

/// The selection's model can be glass: the wall becomes glass alone (its
/// glTF transmission 1), and its index of refraction appears; the global
/// material choice has glass too, which the worker renders.
#[test]
fn an_object_and_every_material_can_become_glass() {
    let mut harness = harness();
    let rect = harness.state().image_rect().expect("the image is drawn");
    let on_red_wall = rect.min + egui::vec2(rect.width() * 0.22, rect.height() * 0.5);
    mouse_drag(&mut harness, on_red_wall, on_red_wall);
    let selected = harness.state().selected.expect("a click selects an object") as usize;
    harness.get_by_label("model").click();
    harness.run_steps(2);
    harness.get_by_label("Glass").click();
    harness.run_steps(2);
    let scene = &harness.state().scene;
    let material = &scene.materials[scene.objects[selected].material as usize];
    assert_eq!(material.brdf_model(), lumiere::scene::BrdfModel::Glass);
    assert_eq!((material.transmission, material.ior), (1.0, 1.5));
    assert!(harness.get_all_by_label("η (index of refraction)").count() >= 1);

    harness.get_by_label("BRDF").click();
    harness.run_steps(2);
    harness.get_all_by_label("Glass").last().unwrap().click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.settings.brdf,
        lumiere::BrdfOverride::Glass
    );
    wait_for(&mut harness, "a pass with glass everywhere", |s| {
        s.samples_per_pixel() >= 1
            && s.source
                .as_ref()
                .is_some_and(|source| source.settings.brdf == lumiere::BrdfOverride::Glass)
    });
}

#[test]
fn dragging_the_image_orbits_the_camera_and_restarts() {
    let mut harness = harness();
    let before = wait_for(&mut harness, "a pass", |s| s.samples_per_pixel() >= 1);
    let camera = harness.state().camera.clone();
    let rect = harness.state().image_rect().expect("the image is drawn");
    mouse_drag(
        &mut harness,
        rect.center(),
        rect.center() + egui::vec2(60.0, 0.0),
    );
    let moved = &harness.state().camera;
    assert_ne!(
        moved.world_from_camera, camera.world_from_camera,
        "a drag must turn the camera"
    );
    assert_eq!(harness.state().selected, None, "a drag is not a click");
    wait_for(&mut harness, "the restart", |s| {
        s.restarts > before.restarts
    });
}

#[test]
fn pixel_zoom_shows_each_film_pixel_as_a_square() {
    let mut harness = harness();
    harness.get_by_label("4×").click();
    harness.run_steps(3);
    let rect = harness.state().image_rect().expect("the image is drawn");
    let ppp = harness.ctx.pixels_per_point();
    assert_eq!(
        (rect.width() * ppp, rect.height() * ppp),
        (64.0 * 4.0, 48.0 * 4.0)
    );
    harness.get_by_label("Fit").click();
    harness.run_steps(3);
    assert!(harness.state().image_rect().unwrap().width() > 64.0 * 4.0 / ppp);
}

#[test]
fn a_broken_scene_file_shows_its_error_and_the_scene_stays() {
    let mut harness = harness();
    let broken = std::env::temp_dir().join(format!("lumiere-broken-{}.gltf", std::process::id()));
    std::fs::write(&broken, b"{ not json").unwrap();
    harness.get_by_label("Scene").click();
    harness.run_steps(2);
    // the last group of the panel: scroll it into view, as a user would
    harness.get_by_label("Load").scroll_to_me();
    harness.run_steps(2);
    let field = harness.get_by_label("file");
    field.focus();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::A);
    harness.run_steps(1);
    harness
        .get_by_label("file")
        .type_text(&format!("{}", broken.display()));
    harness.run_steps(2);
    harness.get_by_label("Load").click();
    harness.run_steps(2);
    let app = harness.state();
    let message = app.message.clone().unwrap_or_default();
    assert!(
        message.starts_with("error:") && message.contains("lumiere-broken"),
        "{message}"
    );
    assert!(
        !message.contains("cannot read"),
        "the typed path replaced the field's text: {message}"
    );
    assert_eq!(app.scene.name, "cornell", "the previous scene stays");
}

/// Steps the UI until the app satisfies `done` (60 s at most).
fn wait_for_app(
    harness: &mut Harness<'static, LumiereApp>,
    what: &str,
    done: impl Fn(&LumiereApp) -> bool,
) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while !done(harness.state()) {
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        harness.step();
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The colour on screen at film pixel (`x`, `y`).
fn screen_colour(harness: &mut Harness<'static, LumiereApp>, x: u32, y: u32) -> [u8; 3] {
    WindowShot::take(harness).colour_at(x, y)
}

/// A pixel whose value sits in the middle of the colour bar.
fn mid_range_pixel(app: &LumiereApp) -> (u32, u32) {
    let image = app.noise_image().expect("a noise view is shown");
    let i = image
        .values
        .iter()
        .position(|&v| (0.3..0.7).contains(&image.position(v)))
        .expect("some pixel in the middle of the range");
    ((i % 64) as u32, (i / 64) as u32)
}

/// The false colour `crate::analysis::noise` chose for film pixel (`x`, `y`), as sRGB bytes.
fn expected_colour(app: &LumiereApp, x: u32, y: u32) -> [u8; 3] {
    let image = app.noise_image().expect("a noise view is shown");
    let linear = image.rgba[(y * 64 + x) as usize];
    std::array::from_fn(|c| {
        (lumiere::course::color::linear_to_srgb(linear[c]) * 255.0).round() as u8
    })
}

fn close_colours(a: [u8; 3], b: [u8; 3]) -> bool {
    a.iter().zip(b).all(|(&a, b)| a.abs_diff(b) <= 2)
}

#[test]
fn display_modes_recolour_the_image_and_show_their_legend() {
    let mut harness = harness();
    harness.state_mut().state.stop_at_spp = Some(8);
    // exposure and tonemap apply to the image only, never to false colour
    harness.state_mut().state.display.exposure = 1.5;
    harness.state_mut().state.display.tonemap = lumiere::render::display::Tonemap::Reinhard;
    wait_for(&mut harness, "8 spp", |s| {
        s.idle && s.samples_per_pixel() >= 8
    });
    harness.run_steps(2);
    assert!(
        harness
            .query_by_label_contains("Standard error of")
            .is_none()
    );
    let radiance_shot = WindowShot::take(&mut harness);

    harness.get_by_label("mode").click();
    harness.run_steps(2);
    harness.get_by_label("Standard error").click();
    wait_for_app(&mut harness, "the standard-error view", |app| {
        app.noise_image().is_some()
    });
    harness.run_steps(2);
    let image = harness.state().noise_image().unwrap();
    assert_eq!(image.view.mode, DisplayMode::StandardError);
    assert!(
        image.range.1 > 0.0,
        "8 samples of the Cornell box are noisy"
    );
    // the shader shows the map's colours as they are: no exposure, no tonemap
    let (x, y) = mid_range_pixel(harness.state());
    let radiance = radiance_shot.colour_at(x, y);
    let shown = screen_colour(&mut harness, x, y);
    assert!(
        close_colours(shown, expected_colour(harness.state(), x, y)),
        "{shown:?} on screen"
    );
    assert!(!close_colours(shown, radiance), "the image did not change");
    harness.get_by_label_contains("Standard error of L0+L1+L2");

    // V: the next mode
    harness.key_press(egui::Key::V);
    wait_for_app(&mut harness, "the relative-error view", |app| {
        app.noise_image()
            .is_some_and(|i| i.view.mode == DisplayMode::RelativeError)
    });
    harness.run_steps(2);
    harness.get_by_label_contains("Relative error of");
    let (x, y) = mid_range_pixel(harness.state());
    let shown = screen_colour(&mut harness, x, y);
    assert!(close_colours(shown, expected_colour(harness.state(), x, y)));

    harness.state_mut().state.noise.mode = DisplayMode::Image;
    harness.run_steps(3);
    assert!(
        harness
            .query_by_label_contains("Relative error of")
            .is_none()
    );
    let shot = WindowShot::take(&mut harness);
    for (x, y) in [(x, y), (32, 21), (10, 40)] {
        assert!(close_colours(
            shot.colour_at(x, y),
            radiance_shot.colour_at(x, y)
        ));
    }
}

#[test]
fn the_difference_view_needs_a_reference_and_is_signed() {
    let mut harness = harness();
    harness.state_mut().state.stop_at_spp = Some(4);
    wait_for(&mut harness, "4 spp", |s| {
        s.idle && s.samples_per_pixel() >= 4
    });
    harness.get_by_label("mode").click();
    harness.run_steps(2);
    assert!(
        harness.query_by_label("Difference").is_none(),
        "no reference, no difference"
    );
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);

    // a synthetic reference: uniform grey of luminance 0.1
    harness.state_mut().reference = Some(Arc::new(ReferenceImage {
        width: 64,
        height: 48,
        radiance: vec![glam::Vec3::splat(0.1); 64 * 48],
        label: "grey 0.1".into(),
    }));
    harness.get_by_label("mode").click();
    harness.run_steps(2);
    harness.get_by_label("Difference").click();
    wait_for_app(&mut harness, "the difference view", |app| {
        app.noise_image()
            .is_some_and(|i| i.view.mode == DisplayMode::Difference)
    });
    harness.run_steps(2);
    harness.get_by_label_contains("image − reference (grey 0.1)");
    let app = harness.state();
    let image = app.noise_image().unwrap();
    assert_eq!(image.range.0, -image.range.1, "a symmetric range");
    let film = app.snapshot();
    for (value, pixel) in image.values.iter().zip(&film.radiance) {
        let y = lumiere::course::color::luminance(glam::Vec3::from_slice(&pixel[..3]));
        assert!((value - (y - 0.1)).abs() < 1e-4);
    }
    assert!(image.values.iter().any(|&v| v < 0.0) && image.values.iter().any(|&v| v > 0.0));
    let (x, y) = mid_range_pixel(harness.state());
    let shown = screen_colour(&mut harness, x, y);
    assert!(close_colours(shown, expected_colour(harness.state(), x, y)));
}

#[test]
fn a_probe_click_shows_the_pixel_statistics_with_n_equal_to_the_spp() {
    let mut harness = harness();
    harness.state_mut().state.stop_at_spp = Some(6);
    let done = wait_for(&mut harness, "6 spp", |s| {
        s.idle && s.samples_per_pixel() >= 6
    });
    probe_the_back_wall(&mut harness, &done);
}

/// With the splitting pilot on, the film's samples take its count of
/// continuations, and the probe traces them again with that count.
#[test]
fn with_auto_splitting_the_probe_traces_with_the_renders_count() {
    let mut harness = harness();
    harness.state_mut().state.settings.auto_indirect_samples = true;
    harness.state_mut().state.stop_at_spp = Some(6);
    let done = wait_for(&mut harness, "6 spp, split", |s| {
        s.idle
            && s.samples_per_pixel() >= 6
            && s.source
                .as_ref()
                .is_some_and(|s| s.settings.auto_indirect_samples)
    });
    assert!(done.continuations.range().1 > 1, "{:?}", done.continuations);
    harness.get_by_label(&format!("indirect ×{} (auto)", done.continuations.label()));
    probe_the_back_wall(&mut harness, &done);
}

/// Probes the back wall of the idle film `done` and checks that the probe
/// reproduces the film, then its path view, then closes it.
fn probe_the_back_wall(harness: &mut Harness<'static, LumiereApp>, done: &Snapshot) {
    // the integral at p, which refines while the window is photographed
    // below, has tests of its own (viewer_hemisphere.rs)
    harness.state_mut().hemisphere.shown = false;
    harness.get_by_label("Probe").click();
    harness.run_steps(2);
    assert!(harness.state().probe_tool);
    let rect = harness.state().image_rect().expect("the image is drawn");
    // the back wall, lit by all three terms
    let on_back_wall = rect.min + egui::vec2(rect.width() * 0.5, rect.height() * 0.45);
    mouse_drag(harness, on_back_wall, on_back_wall);
    assert_eq!(
        harness.state().selected,
        None,
        "a probe click selects nothing"
    );
    let (x, y) = harness.state().probe.pixel.expect("a pixel is probed");
    assert_eq!((x, y), (32, 21));
    wait_for_app(harness, "the probe", |app| app.probe.result.is_some());
    harness.run_steps(2);
    harness.get_by_label("Pixel probe");
    harness.get_by_label("pixel (32, 21)");
    let result = harness.state().probe.result.clone().unwrap();
    assert_eq!(result.samples_per_pixel, done.samples_per_pixel());
    assert_eq!(result.probe.terms.len(), 3, "L0, L1, L2");
    for term in &result.probe.terms {
        assert_eq!(term.film_samples, done.samples_per_pixel());
        assert!(term.reproduces_film(), "{:?}", term.term);
    }
    let l1 = &result.probe.terms[1];
    assert!(l1.mean_luminance() > 0.0 && l1.standard_error > 0.0);
    path_view_draws_the_sample_rays(harness);
    // and the window closes
    harness.get_by_label("Clear probe").click();
    harness.run_steps(2);
    assert!(harness.query_by_label("Pixel probe").is_none());
}

/// The probed pixel's path view: the first sample's rays, drawn where they
/// project; then the brightest sample; then hidden.
fn path_view_draws_the_sample_rays(harness: &mut Harness<'static, LumiereApp>) {
    wait_for_app(harness, "the path", |app| app.probe.path.recorded.is_some());
    harness.run_steps(2);
    harness.get_by_label("camera ray");
    let recorded = harness.state().probe.path.recorded.as_ref().unwrap();
    assert_eq!(recorded.position, 0);
    assert_eq!(recorded.lines[0].role, RayRole::Camera);
    let lines: Vec<(egui::Pos2, egui::Pos2)> = recorded
        .lines
        .iter()
        .map(|l| (l.from, l.to))
        .map(|(a, b)| (egui::pos2(a.x, a.y), egui::pos2(b.x, b.y)))
        .collect();
    assert!(
        lines.len() >= 3,
        "camera ray, shadow ray, bounce: {lines:?}"
    );

    // the pointer out of the way, and the probe window's place, where a
    // click changes the window itself
    let park_pointer = |harness: &mut Harness<'static, LumiereApp>| {
        harness.event(egui::Event::PointerMoved(egui::pos2(2.0, 990.0)));
        harness.run_steps(2);
    };
    park_pointer(harness);
    let shown = WindowShot::take(harness);
    harness.get_by_label("Draw its rays on the image").click();
    park_pointer(harness);
    assert!(harness.state().probe.path.hidden);
    let hidden = WindowShot::take(harness);
    let ppp = harness.ctx.pixels_per_point();
    let window = harness
        .ctx
        .memory(|m| m.area_rect(egui::Id::unique(PROBE_WINDOW_ID)))
        .expect("the probe window is shown")
        * ppp;
    // every pixel of the image the drawing changed lies on a projected ray
    let rect = shown.image_rect;
    let to_screen = |p: egui::Pos2| {
        rect.min + egui::vec2(p.x / 64.0 * rect.width(), p.y / 48.0 * rect.height())
    };
    let distance = |q: egui::Pos2, (a, b): (egui::Pos2, egui::Pos2)| {
        let (a, b) = (to_screen(a), to_screen(b));
        let ab = b - a;
        let t = ((q - a).dot(ab) / ab.length_sq().max(1e-6)).clamp(0.0, 1.0);
        (a + ab * t - q).length()
    };
    let (mut changed, mut on_rays) = (0, 0);
    for y in rect.min.y as u32..rect.max.y as u32 {
        for x in rect.min.x as u32..rect.max.x as u32 {
            let q = egui::pos2(x as f32 + 0.5, y as f32 + 0.5);
            if window.expand(16.0).contains(q) {
                continue;
            }
            if shown.window.get_pixel(x, y) != hidden.window.get_pixel(x, y) {
                changed += 1;
                // the camera ray is a ring of radius 5 points around its hit
                if lines.iter().any(|&l| distance(q, l) < 9.0) {
                    on_rays += 1;
                }
            }
        }
    }
    assert!(changed > 200, "{changed} pixels drawn");
    assert!(
        on_rays as f64 >= 0.95 * changed as f64,
        "{on_rays} of {changed} changed pixels lie on the rays"
    );

    harness.get_by_label("Draw its rays on the image").click();
    harness.get_by_label("Brightest").click();
    harness.run_steps(2);
    wait_for_app(harness, "the brightest sample's path", |app| {
        let probe = &app.probe;
        let brightest = probe.result.as_ref().and_then(|r| r.probe.brightest());
        probe.path.recorded.as_ref().map(|r| Some(r.position)) == Some(brightest)
    });
    let probe = &harness.state().probe;
    let result = probe.result.as_ref().unwrap();
    let position = probe.path.recorded.as_ref().unwrap().position;
    let max = result
        .probe
        .pass_luminance
        .iter()
        .cloned()
        .fold(0.0, f64::max);
    assert_eq!(result.probe.pass_luminance[position], max);
}

#[test]
fn the_adaptive_checkbox_stops_converged_pixels_and_unticked_samples_all() {
    use lumiere::course::Adaptive;
    let mut harness = harness();
    let before = wait_for(&mut harness, "a pass", |s| s.samples_per_pixel() >= 1);
    harness.get_by_label("adaptive").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.settings.adaptive,
        Some(Adaptive::default())
    );
    let passes = Adaptive::default().min_samples + 16;
    let adaptive = wait_for(&mut harness, "passes past the minimum", |s| {
        s.restarts > before.restarts && s.samples_per_pixel() >= passes
    });
    // the pixels that stopped were not traced in the later passes
    let pixels = 64 * 48;
    let every_pass = adaptive.samples_per_pixel() as u64 * pixels;
    assert!(
        adaptive.pixel_samples < every_pass,
        "{} samples traced, {every_pass} with every pixel in every pass",
        adaptive.pixel_samples
    );
    harness.get_by_label("adaptive").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.settings.adaptive, None);
    let uniform = wait_for(&mut harness, "uniform passes", |s| {
        s.restarts > adaptive.restarts && s.samples_per_pixel() >= 4
    });
    assert_eq!(
        uniform.pixel_samples,
        uniform.samples_per_pixel() as u64 * pixels
    );
}

/// "Reset to defaults" undoes a class's tinkering: every setting, the
/// scene's light edits and the display go back to lumiere's defaults, and
/// the worker renders them.
#[test]
fn reset_to_defaults_brings_every_setting_back() {
    let mut harness = harness();
    harness.get_by_label("All point").click();
    harness.state_mut().state.display.exposure = 3.0;
    let light = harness
        .state()
        .scene
        .materials
        .iter()
        .position(|m| m.is_emissive())
        .unwrap();
    std::sync::Arc::make_mut(&mut harness.state_mut().scene).materials[light].emission *= 2.0;
    harness.run_steps(2);
    harness.get_by_label("Reset to defaults").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state, lumiere::app::Persisted::default());
    let authored = lumiere::scene::builtin::cornell();
    assert_eq!(
        harness.state().scene.materials[light].emission,
        authored.materials[light].emission
    );
    wait_for(&mut harness, "the default settings", |s| {
        s.source
            .as_ref()
            .is_some_and(|source| source.settings == lumiere::RenderSettings::default())
    });
}

/// The light's strength is shown in the unit of what it is: the Cornell
/// box's area light as a radiance Lₑ (W/m²/sr), collapsed to a point as the
/// peak intensity I = Lₑ A (W/sr); its power Φ = π A Lₑ is the same in both.
#[test]
fn light_units_follow_the_light_mode_and_the_power_stays() {
    let mut harness = harness();
    let scene = lumiere::scene::builtin::cornell();
    let (index, light) = scene
        .materials
        .iter()
        .enumerate()
        .find(|(_, m)| m.is_emissive())
        .unwrap();
    let area: f32 = scene
        .triangles
        .iter()
        .filter(|t| t.material as usize == index)
        .map(|t| {
            let [a, b, c] = t.vertices.map(|v| scene.positions[v as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum();
    let radiance = light.emission.max_element();
    let power = format!("Φ = {:.4} W", std::f32::consts::PI * area * radiance);
    harness.get_by_label(&format!("{} (Lₑ, W/m²/sr)", light.name));
    harness.get_by_label(&power);
    harness.get_by_label("All point").click();
    harness.run_steps(2);
    harness.get_by_label(&format!("{} (I, W/sr)", light.name));
    harness.get_by_label(&power);
}

/// The Lights group's "a quality for each source": ticking it gives every
/// source its own light samples; a source unticked reaches the worker
/// switched off, and the Cornell box, whose only source it is, goes black.
#[test]
fn each_source_can_be_given_its_own_samples_or_switched_off() {
    use lumiere::course::SourceQuality;
    let mut harness = harness();
    harness.get_by_label("a quality for each source").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.settings.sources,
        vec![SourceQuality::samples("light", 1)]
    );
    harness.get_by_label("light").click();
    harness.run_steps(2);
    let done = wait_for(&mut harness, "the light switched off at the worker", |s| {
        s.source
            .as_ref()
            .is_some_and(|source| source.settings.sources.first().is_some_and(|q| !q.on))
            && s.samples_per_pixel() >= 2
    });
    let brightest = done
        .radiance
        .iter()
        .map(|l| l[0].max(l[1]).max(l[2]))
        .fold(0.0f32, f32::max);
    assert_eq!(brightest, 0.0, "the only source is off");
}

/// Automatic exposure shows the image's mean luminance Ȳ as mid-grey:
/// L2 alone, dark at 0 EV, gets log₂(0.18 / Ȳ), several stops up.
#[test]
fn auto_exposure_brings_l2_alone_to_mid_grey() {
    let mut harness = harness();
    harness.get_by_label("L0").click();
    harness.get_by_label("L1").click();
    harness.get_by_label("auto EV").click();
    harness.run_steps(2);
    assert!(harness.state().state.auto_exposure);
    let shown = wait_for(&mut harness, "8 spp of L2 alone", |s| {
        s.terms == lumiere::TermSet::only(Term::L2) && s.samples_per_pixel() >= 8
    });
    harness.run_steps(2);
    let shown = if harness.state().snapshot().generation == shown.generation {
        shown
    } else {
        (*harness.state().snapshot()).clone()
    };
    let mean = shown
        .radiance
        .iter()
        .map(|p| lumiere::course::color::luminance(glam::Vec3::new(p[0], p[1], p[2])) as f64)
        .sum::<f64>()
        / shown.radiance.len() as f64;
    let expected = (0.18 / mean).log2() as f32;
    let exposure = harness.state().state.display.exposure;
    // rounded to a tenth of a stop
    assert!(
        (exposure - expected).abs() <= 0.05 + 1e-4,
        "{exposure} EV, expected {expected}"
    );
    assert!(exposure > 2.0, "L2 alone needs several stops: {exposure}");
}
