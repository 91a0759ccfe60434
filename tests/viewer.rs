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
        .with_size([1100.0, 760.0])
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
