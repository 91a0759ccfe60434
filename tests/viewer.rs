//! The viewer's widgets, clicked by their labels in a headless egui (wgpu on
//! the machine's Vulkan/GL driver), and the render worker's response.
#![cfg(feature = "gui")]

use std::time::{Duration, Instant};

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lumiere::app::{LumiereApp, ViewOptions};
use lumiere::progressive::Snapshot;
use lumiere::{BrdfOverride, LightMode, RenderSettings, Term};

fn harness() -> Harness<'static, LumiereApp> {
    let options = ViewOptions {
        settings: RenderSettings {
            width: 64,
            height: 48,
            ..RenderSettings::default()
        },
        ..ViewOptions::default()
    };
    let mut harness = Harness::builder()
        .with_size([1100.0, 1000.0])
        .wgpu()
        .build_eframe(|cc| LumiereApp::new(cc, options).expect("the Cornell box loads"));
    harness.run_steps(2);
    harness
}

/// Steps the UI until the worker's snapshot satisfies `done` (60 s at most).
fn wait_for(
    harness: &mut Harness<'static, LumiereApp>,
    what: &str,
    done: impl Fn(&Snapshot) -> bool,
) -> Snapshot {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        harness.step();
        let snapshot = harness.state().snapshot();
        if done(&snapshot) {
            return (*snapshot).clone();
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn switching_l2_off_hides_it_without_restarting_the_film() {
    let mut harness = harness();
    let before = wait_for(&mut harness, "4 spp", |s| s.samples_per_pixel() >= 4);
    harness.get_by_label("L2").click();
    harness.run_steps(2);
    assert!(!harness.state().state.settings.terms.contains(Term::L2));
    let after = wait_for(&mut harness, "more samples without L2", |s| {
        !s.terms.contains(Term::L2)
            && s.term_samples[Term::L1.index()] > before.term_samples[Term::L1.index()] + 2
    });
    assert_eq!(
        after.restarts, before.restarts,
        "a term switched off must not restart the film"
    );
    // and back on: still the same film
    harness.get_by_label("L2").click();
    let shown = wait_for(&mut harness, "L2 shown", |s| s.terms.contains(Term::L2));
    assert_eq!(shown.restarts, before.restarts);
}

#[test]
fn light_mode_and_brdf_controls_change_the_settings_and_restart() {
    let mut harness = harness();
    let before = wait_for(&mut harness, "a pass", |s| s.samples_per_pixel() >= 1);
    harness.get_by_label("All point").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.settings.light_mode, LightMode::Point);
    let restarted = wait_for(&mut harness, "the restart", |s| {
        s.restarts > before.restarts
    });

    harness.get_by_label("BRDF").click();
    harness.run_steps(2);
    harness.get_by_label("Mirror").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.settings.brdf, BrdfOverride::Mirror);
    wait_for(&mut harness, "another restart", |s| {
        s.restarts > restarted.restarts
    });
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
