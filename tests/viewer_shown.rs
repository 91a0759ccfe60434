//! "Save as shown" in the viewer: the PNG it writes at a chosen size holds
//! the image as displayed (scaled, its aspect kept), a noise view with its
//! colour bar, a lesson step's texts laid out as its slide, A | B with both
//! labels, the four-up's tiles; a size out of range writes nothing.
#![cfg(feature = "gui")]

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use lumiere::analysis::noise::DisplayMode;
use lumiere::app::{LumiereApp, ViewOptions};
use lumiere::lesson::{Lang, Lesson};
use lumiere::render::display::{DisplaySettings, Layout, Tonemap};
use lumiere::render::export::to_srgb8;
use lumiere::render::settings_override::SettingsOverride;
use lumiere::tools::slides::shown::MAX_SIDE;
use lumiere::tools::slides::{BACKGROUND, Rect, Slide, SlideLayout, SlideTexts};
use lumiere::{RenderSettings, Term, TermSet};

#[path = "common/viewer.rs"]
mod viewer;
use viewer::{harness_with_film, wait_for};

/// The size every test saves at.
const SIZE: (u32, u32) = (640, 360);

/// A folder of its own for test `name`, empty.
fn folder(name: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("lumiere-shown-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    folder
}

/// Presses "Save as shown" with `size` and waits for the status bar to
/// say it is done; the message.
fn save_as_shown(
    harness: &mut Harness<'static, LumiereApp>,
    folder: &Path,
    size: (u32, u32),
) -> String {
    let app = harness.state_mut();
    app.state.export_dir = folder.to_string_lossy().into_owned();
    app.state.shown_size = size;
    app.message = None;
    app.save_as_shown();
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let message = harness.state().message.clone().unwrap_or_default();
        if message.starts_with("saved") || message.starts_with("error") {
            return message;
        }
        assert!(Instant::now() < deadline, "still {message:?}");
        harness.step();
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The first picture saved in `folder`.
fn load(folder: &Path) -> image::RgbImage {
    let path = folder.join("lumiere-shown-001.png");
    image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

fn pixel(image: &image::RgbImage, x: u32, y: u32) -> [u8; 3] {
    image.get_pixel(x, y).0
}

/// The film pixels, first and last, that picture pixel `i` of `to` covers
/// of `from`: its footprint [i·from/to, (i+1)·from/to).
fn covered(i: u32, from: u32, to: u32) -> (u32, u32) {
    let (i, from, to) = (i as u64, from as u64, to as u64);
    ((i * from / to) as u32, (((i + 1) * from - 1) / to) as u32)
}

/// Asserts that `region` of `picture` shows `srgb` (`width`×`height`,
/// RGB8) enlarged, where `check(x, y)`: a pixel within one film pixel is
/// its value (within a code), one on the edge between film pixels lies
/// between theirs.
fn assert_region_shows(
    picture: &image::RgbImage,
    region: Rect,
    (width, height): (u32, u32),
    srgb: &[u8],
    check: impl Fn(u32, u32) -> bool,
    what: &str,
) {
    let mut exact = 0;
    for y in region.y..region.y + region.height {
        for x in region.x..region.x + region.width {
            if !check(x, y) {
                continue;
            }
            let (x0, x1) = covered(x - region.x, width, region.width);
            let (y0, y1) = covered(y - region.y, height, region.height);
            let shown = pixel(picture, x, y);
            for c in 0..3 {
                let film = (y0..=y1)
                    .flat_map(|fy| (x0..=x1).map(move |fx| (fy * width + fx) as usize * 3 + c))
                    .map(|i| srgb[i]);
                let (lo, hi) = film.fold((255u8, 0u8), |(lo, hi), v| (lo.min(v), hi.max(v)));
                assert!(
                    (lo.saturating_sub(1)..=hi.saturating_add(1)).contains(&shown[c]),
                    "{what}: picture ({x}, {y}) is {shown:?}, film ({x0}..={x1}, {y0}..={y1}) spans {lo}..={hi} in channel {c}"
                );
            }
            exact += usize::from((x0, y0) == (x1, y1));
        }
    }
    assert!(
        exact > 1000,
        "{what}: only {exact} pixels within one film pixel"
    );
}

/// The film's radiance as the PNG export shows it.
fn srgb(radiance: &[[f32; 4]], display: DisplaySettings) -> Vec<u8> {
    let rgb: Vec<glam::Vec3> = radiance
        .iter()
        .map(|p| glam::Vec3::new(p[0], p[1], p[2]))
        .collect();
    to_srgb8(&rgb, display)
}

/// Pixels of `rect` that are light grey to white: text.
fn text_pixels(image: &image::RgbImage, rect: Rect) -> usize {
    (rect.y..rect.y + rect.height)
        .flat_map(|y| (rect.x..rect.x + rect.width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = pixel(image, x, y);
            p.iter().all(|&c| c >= 170) && p[0].abs_diff(p[2]) < 30
        })
        .count()
}

/// (a) The plain image: the picture is 640×360, the 4:3 film 480×360 in
/// its middle, each film pixel a 3×3 block of its exposed, tonemapped sRGB
/// value; dark margins; the sidecar beside it.
#[test]
fn the_image_is_saved_as_displayed_scaled_to_the_chosen_size() {
    let mut harness = harness_with_film(160, 120);
    let display = DisplaySettings {
        exposure: 1.0,
        tonemap: Tonemap::Reinhard,
        layout: Layout::Single,
    };
    harness.state_mut().state.display = display;
    harness.state_mut().state.stop_at_spp = Some(4);
    let snapshot = wait_for(&mut harness, "4 spp", |s| {
        s.idle && !s.preview && s.samples_per_pixel() >= 4
    });
    let folder = folder("plain");
    let message = save_as_shown(&mut harness, &folder, SIZE);
    assert!(message.contains("lumiere-shown-001.png"), "{message}");
    let picture = load(&folder);
    assert_eq!(picture.dimensions(), SIZE);
    let region = Rect::new(80, 0, 480, 360);
    let film = srgb(&snapshot.radiance, display);
    assert_region_shows(
        &picture,
        region,
        (160, 120),
        &film,
        |_, _| true,
        "the image",
    );
    for y in [0, 180, 359] {
        for x in [0, 79, 560, 639] {
            assert_eq!(pixel(&picture, x, y), BACKGROUND, "margin ({x}, {y})");
        }
    }
    let sidecar =
        lumiere::render::sidecar::Sidecar::load(&folder.join("lumiere-shown-001.json")).unwrap();
    assert_eq!(sidecar.samples_per_pixel, snapshot.samples_per_pixel());
    assert_eq!(sidecar.display, display);
    let _ = std::fs::remove_dir_all(&folder);
}

/// (b) A noise view: its false colours, and right of them a colour bar
/// whose colours run from the map's top to its bottom, with its title.
#[test]
fn a_noise_view_is_saved_with_its_colour_bar() {
    let mut harness = harness_with_film(160, 120);
    harness.state_mut().state.stop_at_spp = Some(4);
    harness.state_mut().state.noise.mode = DisplayMode::StandardError;
    wait_for(&mut harness, "4 spp", |s| {
        s.idle && !s.preview && s.samples_per_pixel() >= 4
    });
    let deadline = Instant::now() + Duration::from_secs(60);
    while harness.state().noise_image().is_none() {
        assert!(Instant::now() < deadline, "no noise view");
        harness.step();
        std::thread::sleep(Duration::from_millis(10));
    }
    harness.run_steps(4);
    let noise = harness.state().noise_image().unwrap();
    let folder = folder("noise");
    let message = save_as_shown(&mut harness, &folder, SIZE);
    assert!(message.starts_with("saved"), "{message}");
    let picture = load(&folder);
    assert_eq!(picture.dimensions(), SIZE);
    // the image: 480×360, moved left to leave the bar and its title room
    let left = (0..SIZE.0)
        .find(|&x| pixel(&picture, x, 180) != BACKGROUND)
        .unwrap();
    assert!(left < 80, "the image starts at {left}");
    let region = Rect::new(left, 0, 480, 360);
    let colours = lumiere::tools::slides::false_colour_srgb8(&noise);
    assert_region_shows(
        &picture,
        region,
        (160, 120),
        &colours,
        |_, _| true,
        "the map",
    );
    // the colour bar: a column right of the image whose colour changes all along
    let margin = Rect::new(region.x + 480, 0, SIZE.0 - region.x - 480, 360);
    let bar = (margin.x..SIZE.0).find(|&x| {
        let mut column: Vec<[u8; 3]> = (0..360).map(|y| pixel(&picture, x, y)).collect();
        column.dedup();
        column.len() > 120
    });
    let x = bar.expect("a colour bar right of the image");
    let (top, bottom) = (pixel(&picture, x, 60), pixel(&picture, x, 330));
    assert!(
        top[1] > bottom[1] + 100,
        "yellow above violet: {top:?} {bottom:?}"
    );
    // its mode, unit and range
    assert!(text_pixels(&picture, margin) > 40);
    let _ = std::fs::remove_dir_all(&folder);
}

/// (c) A lesson step: the title, formula and caption bands are those of the
/// step's slide in the viewer's language, pixel for pixel, with text in
/// them; the image region is the film as displayed, as in (a).
#[test]
fn a_lesson_step_is_saved_as_its_slide() {
    let lesson = Lesson::load("simulation-notions").unwrap();
    // a step of one image (no split, no four-up)
    let step = lesson
        .steps
        .iter()
        .position(|s| s.slug == "direct-extended")
        .unwrap();
    let options = ViewOptions {
        settings: RenderSettings {
            width: 160,
            height: 120,
            ..RenderSettings::default()
        },
        lesson: Some(lesson.clone()),
        step,
        lang: Lang::Fr,
        ..ViewOptions::default()
    };
    let mut harness = Harness::builder()
        .with_size([1100.0, 900.0])
        .wgpu()
        .build_eframe(|cc| LumiereApp::new(cc, options).expect("the lesson opens"));
    harness.run_steps(2);
    harness.state_mut().state.stop_at_spp = Some(4);
    let view = lesson.view(step, 160, 120).unwrap();
    let snapshot = wait_for(&mut harness, "the step at 4 spp", |s| {
        s.idle
            && !s.preview
            && s.samples_per_pixel() >= 4
            && s.source
                .as_ref()
                .is_some_and(|src| src.settings == view.settings)
    });
    let folder = folder("lesson");
    let message = save_as_shown(&mut harness, &folder, SIZE);
    assert!(message.starts_with("saved"), "{message}");
    let picture = load(&folder);
    assert_eq!(picture.dimensions(), SIZE);
    let layout = SlideLayout::new(SIZE.0, SIZE.1);
    let slide = Slide::new(layout.clone(), &SlideTexts::of(&lesson, step, Lang::Fr)).canvas();
    for band in [layout.top_band, layout.bottom_band] {
        for y in band.y..band.bottom() {
            for x in 0..SIZE.0 {
                assert_eq!(pixel(&picture, x, y), slide.pixel(x, y), "({x}, {y})");
            }
        }
    }
    assert!(
        text_pixels(&picture, layout.title_rect()) > 100,
        "the title"
    );
    assert!(
        text_pixels(&picture, layout.caption_rect()) > 100,
        "the caption"
    );
    // English texts differ: the bands are the viewer's language
    let english = Slide::new(layout.clone(), &SlideTexts::of(&lesson, step, Lang::En)).canvas();
    let caption = layout.caption_rect();
    let differs = (caption.y..caption.bottom())
        .any(|y| (caption.x..caption.right()).any(|x| english.pixel(x, y) != slide.pixel(x, y)));
    assert!(differs);
    let film = srgb(&snapshot.radiance, view.display);
    assert_region_shows(
        &picture,
        layout.image,
        (160, 120),
        &film,
        |_, _| true,
        "the image",
    );
    let _ = std::fs::remove_dir_all(&folder);
}

/// (d) A | B: A's image left of the divider, B's right (B shows L0 alone,
/// so the halves differ where the other terms light the box), each half
/// labelled at its top.
#[test]
fn the_split_is_saved_with_both_halves_and_their_labels() {
    let mut harness = harness_with_film(160, 120);
    let app = harness.state_mut();
    app.state.stop_at_spp = Some(4);
    app.compare.enabled = true;
    app.compare.b = SettingsOverride {
        terms: Some(TermSet::only(Term::L0)),
        ..SettingsOverride::default()
    };
    let deadline = Instant::now() + Duration::from_secs(60);
    let composite = loop {
        harness.step();
        let app = harness.state();
        let done = app.compare.composite().filter(|c| {
            c.a.idle && c.b.idle && !c.a.preview && !c.b.preview && c.a.samples_per_pixel() >= 4
        });
        if let Some(composite) = done.cloned()
            && app
                .compare
                .snapshot()
                .is_some_and(|b| b.generation == composite.b.generation)
        {
            break composite;
        }
        assert!(Instant::now() < deadline, "timed out waiting for A and B");
        std::thread::sleep(Duration::from_millis(10));
    };
    harness.run_steps(2);
    let folder = folder("split");
    let message = save_as_shown(&mut harness, &folder, SIZE);
    assert!(message.starts_with("saved"), "{message}");
    let picture = load(&folder);
    let region = Rect::new(80, 0, 480, 360);
    let divider = 80 + composite.divider_column * 3;
    assert_eq!(divider, 320);
    let display = DisplaySettings::default();
    let shown = srgb(&composite.image.radiance, display);
    // below the labels, off the divider: A | B
    let clear = |x: u32, y: u32| y > 40 && x.abs_diff(divider) > 3;
    assert_region_shows(&picture, region, (160, 120), &shown, clear, "A | B");
    // B's half is not A's image: L0 alone is black but for the light
    let a = srgb(&composite.a.radiance, display);
    let (mut differ, mut total) = (0u64, 0u64);
    for y in (60..360).step_by(3) {
        for x in (divider + 6..560).step_by(3) {
            let i = ((y / 3) * 160 + (x - 80) / 3) as usize * 3;
            let p = pixel(&picture, x, y);
            differ += (0..3).map(|c| p[c].abs_diff(a[i + c]) as u64).sum::<u64>();
            total += 3;
        }
    }
    assert!(
        differ / total > 20,
        "B's half looks like A: {}",
        differ / total
    );
    // the divider, and a label at the top of each half
    assert!(pixel(&picture, divider, 200).iter().all(|&c| c >= 200));
    let band = 30;
    let a_label = Rect::new(80, 0, 240 - 5, band);
    let b_label = Rect::new(divider + 5, 0, 240 - 5, band);
    assert!(text_pixels(&picture, a_label) > 40, "A's label");
    assert!(text_pixels(&picture, b_label) > 40, "B's label");
    let _ = std::fs::remove_dir_all(&folder);
}

/// The four-up: four tiles two by two in a 16:9 picture, the sum tile the
/// image, the L0 tile L0's own.
#[test]
fn the_four_up_is_saved_as_its_tiles() {
    let mut harness = harness_with_film(64, 48);
    harness.state_mut().state.stop_at_spp = Some(4);
    harness.state_mut().state.display.layout = Layout::FourUp;
    let snapshot = wait_for(&mut harness, "each term's image", |s| {
        s.idle && !s.preview && s.term_images[..3].iter().all(Option::is_some)
    });
    let folder = folder("four-up");
    let message = save_as_shown(&mut harness, &folder, SIZE);
    assert!(message.starts_with("saved"), "{message}");
    let picture = load(&folder);
    let display = DisplaySettings::default();
    // below each tile's label: rows from a third of the tile down
    let below_label = |_: u32, y: u32| y % 180 > 60;
    let sum = srgb(&snapshot.radiance, display);
    let tile = |column: u32, row: u32| Rect::new(80 + 240 * column, 180 * row, 240, 180);
    // off the seams between the tiles
    let inside = |rect: Rect| {
        move |x: u32, y: u32| {
            below_label(x, y) && x > rect.x + 2 && x + 3 < rect.right() && y + 3 < rect.bottom()
        }
    };
    assert_region_shows(
        &picture,
        tile(1, 1),
        (64, 48),
        &sum,
        inside(tile(1, 1)),
        "the sum tile",
    );
    let l0 = srgb(
        snapshot.term_images[Term::L0.index()].as_ref().unwrap(),
        display,
    );
    assert_region_shows(
        &picture,
        tile(0, 0),
        (64, 48),
        &l0,
        inside(tile(0, 0)),
        "the L0 tile",
    );
    assert!(
        text_pixels(&picture, Rect::new(80, 0, 120, 25)) > 20,
        "L0's label"
    );
    let _ = std::fs::remove_dir_all(&folder);
}

/// (e) A size out of range is refused in the status bar; nothing is written.
#[test]
fn a_size_out_of_range_is_refused_and_nothing_written() {
    let mut harness = harness_with_film(64, 48);
    harness.state_mut().state.stop_at_spp = Some(1);
    wait_for(&mut harness, "an image", |s| s.idle && !s.preview);
    let folder = folder("refused");
    for size in [(8, 360), (640, MAX_SIDE + 1)] {
        let message = save_as_shown(&mut harness, &folder, size);
        assert!(
            message.starts_with("error") && message.contains("16..=16384"),
            "{message}"
        );
        assert!(
            message.contains(&format!("{}×{}", size.0, size.1)),
            "{message}"
        );
    }
    assert!(!folder.exists(), "nothing is written, not even the folder");
}

/// The command line refuses a size out of range or a picture that is not a
/// PNG before any window opens (exit code 2), and writes nothing.
#[test]
fn the_command_line_refuses_a_bad_size_or_name() {
    let folder = folder("cli");
    std::fs::create_dir_all(&folder).unwrap();
    let png = folder.join("shown.png");
    let jpg = folder.join("shown.jpg");
    let cases: [(&[&str], &str); 3] = [
        (
            &[
                "--save-as-shown",
                png.to_str().unwrap(),
                "--shown-size",
                "8x8",
            ],
            "16..=16384",
        ),
        (
            &[
                "--save-as-shown",
                png.to_str().unwrap(),
                "--shown-size",
                "wide",
            ],
            "WIDTHxHEIGHT",
        ),
        (
            &["--save-as-shown", jpg.to_str().unwrap()],
            "must end in .png",
        ),
    ];
    for (args, says) in cases {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
            .args(["view", "--exit-after-spp", "1"])
            .args(args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
    assert_eq!(std::fs::read_dir(&folder).unwrap().count(), 0);
    let _ = std::fs::remove_dir_all(&folder);
}
