//! The built-in lesson in the viewer: it opens on the step asked for, the
//! keys of a presenter's clicker step through it, and each step's settings
//! reach the render worker; its texts are drawn over the image.
#![cfg(feature = "gui")]

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lumiere::app::{LumiereApp, ViewOptions};
use lumiere::lesson::{Lang, Lesson};
use lumiere::{LightMode, RenderSettings};

#[path = "common/viewer.rs"]
mod viewer;

use viewer::wait_for;

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;

/// The viewer on the built-in lesson's step `step` (from 0), in `lang`.
fn lesson_harness(step: usize, lang: Lang) -> Harness<'static, LumiereApp> {
    let options = ViewOptions {
        settings: RenderSettings {
            width: WIDTH,
            height: HEIGHT,
            ..RenderSettings::default()
        },
        lesson: Some(Lesson::load("simulation-notions").expect("the built-in lesson")),
        step,
        lang,
        ..ViewOptions::default()
    };
    let mut harness = Harness::builder()
        .with_size([1100.0, 800.0])
        .wgpu()
        .build_eframe(|cc| LumiereApp::new(cc, options).expect("the lesson opens"));
    harness.run_steps(2);
    harness
}

/// Waits until the worker renders step `index`'s settings and shows its title.
fn assert_step_reaches_the_worker(harness: &mut Harness<'static, LumiereApp>, index: usize) {
    let lesson = Lesson::load("simulation-notions").unwrap();
    let view = lesson.view(index, WIDTH, HEIGHT).unwrap();
    assert_eq!(harness.state().lesson.step, index);
    wait_for(harness, &format!("step {}'s settings", index + 1), |s| {
        s.source
            .as_ref()
            .is_some_and(|source| source.settings == view.settings)
    });
    assert_eq!(harness.state().state.display, view.display);
    assert_eq!(harness.state().state.stop_at_spp, Some(view.spp));
    let lang = harness.state().lesson.lang;
    let title = format!("{}. {}", index + 1, lesson.steps[index].title.get(lang));
    harness.run_steps(2);
    // the overlay is painted, not a widget: its text is in the frame's shapes
    let painted = harness.output().shapes.iter().any(
        |clipped| matches!(&clipped.shape, egui::Shape::Text(text) if text.galley.text() == title),
    );
    assert!(painted, "the title '{title}' is not drawn");
}

#[test]
fn the_clicker_keys_step_through_the_lesson_and_each_step_reaches_the_worker() {
    let mut harness = lesson_harness(2, Lang::Fr);
    assert_step_reaches_the_worker(&mut harness, 2);
    let last = Lesson::load("simulation-notions").unwrap().steps.len() - 1;
    for (key, expected) in [
        (egui::Key::ArrowRight, 3),
        (egui::Key::PageDown, 4),
        (egui::Key::ArrowLeft, 3),
        (egui::Key::PageUp, 2),
        (egui::Key::Home, 0),
    ] {
        harness.key_press(key);
        harness.run_steps(2);
        assert_step_reaches_the_worker(&mut harness, expected);
    }
    // every step can be shown on this film, one key press each
    for expected in 1..=last {
        harness.key_press(egui::Key::ArrowRight);
        harness.run_steps(1);
        assert_eq!(
            harness.state().lesson.step,
            expected,
            "{:?}",
            harness.state().message
        );
    }
    harness.key_press(egui::Key::Home);
    harness.run_steps(1);
    // past either end, the lesson stays on its first or last step
    harness.key_press(egui::Key::ArrowLeft);
    harness.run_steps(2);
    assert_eq!(harness.state().lesson.step, 0);
    harness.state_mut().lesson.step = last;
    harness.key_press(egui::Key::ArrowRight);
    harness.run_steps(2);
    assert_eq!(harness.state().lesson.step, last);
}

/// The Lesson group: a lesson file that cannot be read is reported and
/// changes nothing; the built-in lesson opens from the list; F5 enters and
/// leaves presentation mode, which hides the side panel.
#[test]
fn the_lesson_group_opens_lessons_refuses_broken_ones_and_presents() {
    let mut harness = viewer::harness();
    let before = harness.state().state.clone();
    let broken = std::env::temp_dir().join(format!("lumiere-broken-{}.toml", std::process::id()));
    std::fs::write(&broken, "name = \"x\"\n[[steps]\n").unwrap();
    harness.get_by_label("Lesson").click();
    harness.run_steps(2);
    harness.state_mut().lesson.file_field = broken.to_string_lossy().into_owned();
    harness.get_by_label("Open").click();
    harness.run_steps(2);
    let message = harness.state().message.clone().unwrap_or_default();
    assert!(
        message.contains(&*broken.to_string_lossy()) && message.contains("line 2"),
        "{message}"
    );
    assert!(harness.state().lesson.lesson.is_none());
    assert_eq!(
        harness.state().state,
        before,
        "a broken lesson changed the settings"
    );
    let _ = std::fs::remove_file(&broken);

    harness.get_by_label("lesson").click();
    harness.run_steps(2);
    harness.get_by_label("simulation-notions").click();
    harness.run_steps(2);
    assert_eq!(harness.state().lesson.step, 0);
    assert_step_reaches_the_worker(&mut harness, 0);

    assert!(harness.query_by_label("Terms").is_some());
    harness.key_press(egui::Key::F5);
    harness.run_steps(2);
    assert!(harness.state().lesson.presenting);
    assert!(
        harness.query_by_label("Terms").is_none(),
        "the side panel is shown"
    );
    harness.key_press(egui::Key::F5);
    harness.run_steps(2);
    assert!(harness.query_by_label("Terms").is_some());
}

/// A clicker held down, back and forth: hundreds of key presses, one frame
/// each, as fast as a key repeats. No frame blocks, the step always follows
/// the keys, memory stays flat, and the last step's settings reach the worker.
#[test]
fn a_clicker_held_down_never_blocks_the_interface_nor_grows_memory() {
    use std::time::{Duration, Instant};
    let resident = || {
        let statm = std::fs::read_to_string("/proc/self/statm").unwrap();
        statm
            .split_whitespace()
            .nth(1)
            .unwrap()
            .parse::<u64>()
            .unwrap()
            * 4096
    };
    let mut harness = lesson_harness(0, Lang::En);
    let last = Lesson::load("simulation-notions").unwrap().steps.len() - 1;
    let mut expected = 0usize;
    let mut state = 0x2545_f491u64;
    let mut settled = 0;
    for press in 0..600 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let key = match state >> 60 {
            0 => egui::Key::Home,
            1..=6 => egui::Key::ArrowLeft,
            _ => egui::Key::ArrowRight,
        };
        expected = match key {
            egui::Key::Home => 0,
            egui::Key::ArrowLeft => expected.saturating_sub(1),
            _ => (expected + 1).min(last),
        };
        let start = Instant::now();
        harness.key_press(key);
        harness.run_steps(1);
        assert!(
            start.elapsed() < Duration::from_secs(2),
            "press {press}: the frame took {:?}",
            start.elapsed()
        );
        assert_eq!(harness.state().lesson.step, expected, "press {press}");
        if press == 99 {
            settled = resident();
        }
    }
    assert_step_reaches_the_worker(&mut harness, expected);
    let end = resident();
    assert!(
        end <= settled + (64 << 20),
        "resident memory grew from {} MB to {} MB over 500 presses",
        settled >> 20,
        end >> 20
    );
}

/// The Scene group's library: every built-in scene with a thumbnail
/// rendered in the background (each a picture, not a blank), its name and
/// description; clicking one loads it and the worker renders it.
#[test]
fn the_scene_library_shows_thumbnails_and_loads_the_scene_clicked() {
    let mut harness = viewer::harness();
    harness.get_by_label("Scene").click();
    harness.run_steps(2);
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    let count = lumiere::scene::builtin::SCENES.len();
    while harness.state().thumbnails.ready() < count {
        assert!(
            std::time::Instant::now() < deadline,
            "the thumbnails never came"
        );
        harness.step();
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    // the library is below the panel's fold: scroll to it (an animation)
    harness.get_by_label("penumbra").scroll_to_me();
    harness.run_steps(30);
    harness.get_by_label("penumbra").click();
    harness.run_steps(2);
    assert_eq!(harness.state().scene_spec, "penumbra");
    wait_for(&mut harness, "the penumbra scene", |s| {
        s.source.as_ref().is_some_and(|source| {
            source
                .scene
                .upgrade()
                .is_some_and(|scene| scene.name == harness_scene_name())
        })
    });
    // each thumbnail is a picture: lit pixels and dark ones, and no two alike
    let pictures: Vec<Vec<u8>> = lumiere::scene::builtin::SCENES
        .iter()
        .map(|scene| {
            let image = lumiere::app::thumbnails::thumbnail(scene.name).unwrap();
            image
                .pixels
                .iter()
                .flat_map(|p| [p.r(), p.g(), p.b()])
                .collect()
        })
        .collect();
    for (scene, picture) in lumiere::scene::builtin::SCENES.iter().zip(&pictures) {
        let lit = picture.iter().filter(|&&v| v > 64).count();
        let dark = picture.iter().filter(|&&v| v < 16).count();
        assert!(
            lit > 100 && dark > 10,
            "{}: {lit} lit, {dark} dark",
            scene.name
        );
    }
    for i in 0..pictures.len() {
        for j in 0..i {
            assert_ne!(pictures[i], pictures[j]);
        }
    }
}

fn harness_scene_name() -> String {
    lumiere::scene::builtin::load("penumbra").unwrap().name
}

/// The step comparing point and extended lights splits the image: A with
/// point lights left, B with extended ones right, each reaching its own
/// worker and labelled; the next step, which has no split, shows A alone.
#[test]
fn a_step_with_a_split_shows_a_and_b_and_the_next_step_a_alone() {
    let lesson = Lesson::load("simulation-notions").unwrap();
    let index = lesson
        .steps
        .iter()
        .position(|s| s.slug == "point-and-extended")
        .expect("the step comparing point and extended lights");
    let view = lesson.view(index, WIDTH, HEIGHT).unwrap();
    let mut b = view.split_settings().expect("the step splits the image");
    assert_eq!(view.settings.light_mode, LightMode::Point);
    assert_eq!(b.light_mode, LightMode::Area);
    b.seed += 1;
    let mut harness = lesson_harness(index, Lang::En);
    assert!(harness.state().compare.enabled);
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    loop {
        harness.step();
        let shown = harness.state().compare.composite().is_some_and(|c| {
            let settings = |s: &lumiere::render::progressive::Snapshot| {
                s.source.as_ref().map(|source| source.settings.clone())
            };
            settings(&c.a) == Some(view.settings.clone())
                && settings(&c.b) == Some(b.clone())
                && !c.a.preview
                && !c.b.preview
        });
        if shown {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "timed out waiting for A and B"
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    harness.run_steps(2);
    assert_eq!(
        harness
            .get_all_by_label_contains("A: point lights · ")
            .count(),
        1
    );
    assert_eq!(
        harness
            .get_all_by_label_contains("B: extended lights · ")
            .count(),
        1
    );

    harness.key_press(egui::Key::ArrowRight);
    harness.run_steps(2);
    assert_eq!(harness.state().lesson.step, index + 1);
    assert!(!harness.state().compare.enabled);
    assert!(harness.state().compare.snapshot().is_none());
    assert!(harness.query_by_label_contains("B: ").is_none());
}
