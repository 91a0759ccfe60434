//! End to end: the real viewer window (X11, wgpu on Vulkan or GL) renders to
//! N spp and saves a screenshot of itself; the image region must match
//! `lumiere render` with the same settings pixel for pixel (same seed, same
//! sample indices), up to the shader's 8-bit rounding.
//!
//! Needs a display: DISPLAY, or `Xvfb` on the PATH (started here). Without
//! either it says so and does nothing, unless LUMIERE_REQUIRE_DISPLAY=1 (CI),
//! which makes that a failure.
#![cfg(feature = "gui")]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod common;

use common::screen_difference;

fn lumiere() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lumiere"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lumiere-window-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// An X server for the test: the session's, or a private Xvfb.
struct Display {
    name: String,
    xvfb: Option<Child>,
}

impl Drop for Display {
    fn drop(&mut self) {
        if let Some(child) = &mut self.xvfb {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

fn display() -> Option<Display> {
    if let Ok(name) = std::env::var("DISPLAY")
        && !name.is_empty()
    {
        return Some(Display { name, xvfb: None });
    }
    let name = format!(":{}", 90 + std::process::id() % 9);
    let child = Command::new("Xvfb")
        .args([
            name.as_str(),
            "-screen",
            "0",
            "1280x800x24",
            "-nolisten",
            "tcp",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .ok()?;
    std::thread::sleep(Duration::from_millis(800));
    Some(Display {
        name,
        xvfb: Some(child),
    })
}

/// Runs `command`, killing it after `limit`.
fn run_with_limit(mut command: Command, limit: Duration) -> std::process::Output {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("the viewer did not exit within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

/// "image at X Y size W H" from the viewer's stderr.
fn image_rect(stderr: &str) -> [u32; 4] {
    let line = stderr
        .lines()
        .find_map(|l| l.strip_prefix("image at "))
        .unwrap_or_else(|| panic!("the viewer did not report its image rectangle:\n{stderr}"));
    let numbers: Vec<u32> = line
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    [numbers[0], numbers[1], numbers[2], numbers[3]]
}

fn load_rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// The window tests one at a time: each starts its own Xvfb on a display
/// numbered after the process.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// The display, or `None` after saying on stderr that the test is skipped
/// (a failure instead with LUMIERE_REQUIRE_DISPLAY, as in CI).
fn display_or_skip() -> Option<Display> {
    let display = display();
    if display.is_none() {
        assert!(
            std::env::var("LUMIERE_REQUIRE_DISPLAY").is_err(),
            "no DISPLAY and no Xvfb: install xvfb (see .ci/run)"
        );
        // straight to the process's stderr, past the test harness's capture,
        // so that the skip shows in `cargo test`'s output
        let _ = writeln!(
            std::io::stderr(),
            "\nwindow test SKIPPED: no DISPLAY and no Xvfb on the PATH (install xvfb, see the README)"
        );
    }
    display
}

/// Runs `lumiere view` with `args` on `display` until it saves `shot` and
/// exits; its stderr.
fn run_viewer(display: &Display, args: &[&str], shot: &Path) -> String {
    let runtime_dir = scratch("xdg");
    std::fs::create_dir_all(&runtime_dir).unwrap();
    let mut view = lumiere();
    view.arg("view")
        .args(args)
        .arg("--screenshot")
        .arg(shot)
        .env("DISPLAY", &display.name)
        .env("XDG_RUNTIME_DIR", &runtime_dir)
        .env_remove("WAYLAND_DISPLAY");
    let output = run_with_limit(view, Duration::from_secs(180));
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "the viewer failed:\n{stderr}");
    stderr
}

/// The built-in lesson opened on step 3 (L2 alone, +2 EV) in a real window:
/// between the title band and the caption band the image is what
/// `lumiere render` gives with the step's settings.
#[test]
fn the_lesson_opens_on_a_step_in_a_real_window() {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let Some(display) = display_or_skip() else {
        return;
    };
    let shot = scratch("lesson.png");
    let shown = scratch("lesson-shown.png");
    let shown_arg = shown.to_str().unwrap();
    let stderr = run_viewer(
        &display,
        &[
            "--lesson",
            "simulation-notions",
            "--step",
            "3",
            "--width",
            "160",
            "--height",
            "120",
            "--exit-after-spp",
            "8",
            "--save-as-shown",
            shown_arg,
            "--shown-size",
            "640x360",
        ],
        &shot,
    );
    let lesson = lumiere::lesson::Lesson::load("simulation-notions").unwrap();
    let view = lesson.view(2, 160, 120).unwrap();
    assert_eq!(
        view.settings.terms,
        lumiere::TermSet::only(lumiere::Term::L2)
    );
    let reference = scratch("lesson-render.png");
    let render = lumiere()
        .args(["render", "cornell", "-o"])
        .arg(&reference)
        .args([
            "--width",
            "160",
            "--height",
            "120",
            "--terms",
            "L2",
            "--exposure",
            "2",
            "--sampler",
            "sobol",
            "--spp",
            "8",
        ])
        .output()
        .unwrap();
    assert!(
        render.status.success(),
        "{}",
        String::from_utf8_lossy(&render.stderr)
    );
    let window = load_rgb(&shot);
    let expected = load_rgb(&reference);
    // the middle third of the image, clear of the title and caption bands
    let (worst, mean) = screen_difference(&window, image_rect(&stderr), &expected, 40..80);
    assert!(
        worst <= 2 && mean < 0.5,
        "the lesson's image differs from the render: worst {worst}/255, mean {mean:.3}"
    );
    // saved as shown: the step's slide at 640×360, its image region the
    // render (enlarged by nearest neighbour), the texts around it
    assert!(stderr.contains("as shown"), "{stderr}");
    let picture = load_rgb(&shown);
    assert_eq!(picture.dimensions(), (640, 360));
    let layout = lumiere::tools::slides::SlideLayout::new(640, 360);
    let image = layout.image;
    let rect = [image.x, image.y, image.width, image.height];
    let (worst, mean) = screen_difference(&picture, rect, &expected, 0..expected.height());
    assert!(
        worst <= 1 && mean < 0.1,
        "the saved picture differs from the render: worst {worst}/255, mean {mean:.3}"
    );
    let title = layout.title_rect();
    let text = (title.y..title.bottom())
        .flat_map(|y| (title.x..title.right()).map(move |x| (x, y)))
        .filter(|&(x, y)| picture.get_pixel(x, y).0.iter().all(|&c| c > 170))
        .count();
    assert!(text > 100, "the step's title: {text} pixels");
    assert!(shown.with_extension("json").exists(), "the sidecar");
}

#[test]
fn viewer_screenshot_matches_the_command_line_render() {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let Some(display) = display_or_skip() else {
        return;
    };
    let settings = [
        "--width",
        "160",
        "--height",
        "120",
        "--terms",
        "L0,L1",
        "--exposure",
        "1",
    ];
    let shot = scratch("window.png");
    let mut args = vec!["cornell"];
    args.extend(settings);
    args.extend(["--exit-after-spp", "32"]);
    let stderr = run_viewer(&display, &args, &shot);

    let reference = scratch("render.png");
    let render = lumiere()
        .args(["render", "cornell", "-o"])
        .arg(&reference)
        .args(settings)
        .args(["--spp", "32"])
        .output()
        .unwrap();
    assert!(render.status.success());

    let window = load_rgb(&shot);
    let expected = load_rgb(&reference);
    // the panel is there: the window is wider than the image and not uniform on the left
    let [x, y, w, h] = image_rect(&stderr);
    assert!(
        x > 100 && window.width() >= x + w && window.height() >= y + h,
        "image rect {x} {y} {w} {h}"
    );
    let left: Vec<_> = (0..window.height())
        .map(|j| window.get_pixel(20, j).0)
        .collect();
    assert!(
        left.iter().any(|p| *p != left[0]),
        "the side panel is missing"
    );

    // the displayed image at each film pixel's centre
    let (worst, mean) = screen_difference(&window, [x, y, w, h], &expected, 0..expected.height());
    // the same radiance goes through the shader's 8-bit sRGB encoding and the
    // export's: the two may round a channel to neighbouring levels (1), and
    // a texel sampled at a pixel's edge may blend with its neighbour (2 at
    // most, on a few pixels); on average well under one level
    assert!(
        worst <= 2 && mean < 0.5,
        "displayed image differs from the render: worst {worst}/255, mean {mean:.3}"
    );
}
