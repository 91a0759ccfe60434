//! The viewer in a web page, for real: the site `bash .ci/build-web OUT`
//! builds, served by `lumiere serve`, opened in headless Chromium driven by
//! `tests/web/check.mjs` (puppeteer-core). The page renders the built-in
//! scene, or a lesson step opened by its address, to the samples per pixel
//! its `spp=` asks for, its console shows no error, and the image on the
//! page is what `lumiere render` gives with the same settings.
//!
//! It needs the site in `LUMIERE_WEB_SITE` and puppeteer-core under
//! `LUMIERE_NODE_MODULES` (`.ci/run` sets both); without them it is
//! skipped and says so, or fails with `LUMIERE_REQUIRE_WEB=1`, as in CI.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

use common::{Served, screen_difference};

/// The site and the folder of puppeteer-core, or `None` after saying the
/// test is skipped.
fn site_or_skip() -> Option<(PathBuf, PathBuf)> {
    let site = std::env::var_os("LUMIERE_WEB_SITE").map(PathBuf::from);
    let modules = std::env::var_os("LUMIERE_NODE_MODULES").map(PathBuf::from);
    match (site, modules) {
        (Some(site), Some(modules)) if site.join("index.html").is_file() => Some((site, modules)),
        _ => {
            assert!(
                std::env::var_os("LUMIERE_REQUIRE_WEB").is_none(),
                "LUMIERE_REQUIRE_WEB is set but LUMIERE_WEB_SITE or LUMIERE_NODE_MODULES is missing"
            );
            eprintln!(
                "web test SKIPPED: set LUMIERE_WEB_SITE (bash .ci/build-web OUT) and LUMIERE_NODE_MODULES"
            );
            None
        }
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lumiere-web-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Runs `tests/web/check.mjs` on `url` (waiting at most `timeout` seconds)
/// with `actions`, its downloads beside `screenshot`: whether it reached
/// its samples, and what it printed.
fn check_page(
    url: &str,
    modules: &Path,
    actions: &str,
    screenshot: &Path,
    timeout: u32,
) -> (bool, String) {
    let downloads = downloads_of(screenshot);
    std::fs::create_dir_all(&downloads).unwrap();
    let out = Command::new("node")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/web/check.mjs"))
        .arg(url)
        .arg(screenshot)
        .arg(timeout.to_string())
        .env("LUMIERE_NODE_MODULES", modules)
        .env("LUMIERE_ACTIONS", actions)
        .env("LUMIERE_DOWNLOADS", &downloads)
        .output()
        .expect("node (Node.js) runs the page's check");
    let printed = format!(
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), printed)
}

/// Opens `query` on the served page and acts on it as `actions` say (the
/// JSON list `tests/web/check.mjs` takes); the console's lines, after
/// checking that the page reached its samples after each action and
/// logged no error.
fn open_page(
    server: &Served,
    modules: &Path,
    query: &str,
    actions: &str,
    screenshot: &Path,
) -> String {
    let url = format!("http://127.0.0.1:{}/{query}", server.port);
    let (reached, console) = check_page(&url, modules, actions, screenshot, 300);
    assert!(
        reached,
        "{url}: the page did not reach its samples\n{console}"
    );
    let errors: Vec<&str> = console
        .lines()
        .filter(|l| l.starts_with("error:") || l.starts_with("pageerror:"))
        .collect();
    assert!(
        errors.is_empty(),
        "{url}: errors on the console:\n{console}"
    );
    console
}

/// Where the page's downloads go: beside its screenshot.
fn downloads_of(screenshot: &Path) -> PathBuf {
    let stem = screenshot.file_stem().unwrap().to_string_lossy();
    screenshot.with_file_name(format!("{stem}-downloads"))
}

/// A path as a JSON string.
fn json_path(path: &Path) -> String {
    serde_json::to_string(path.to_str().unwrap()).unwrap()
}

/// The image's rectangle on the page, from the last "lumiere: reached …;
/// image at X Y size W H".
fn image_rect(console: &str) -> [u32; 4] {
    let line = console
        .lines()
        .rev()
        .find_map(|l| l.split_once("image at ").map(|(_, rest)| rest))
        .unwrap_or_else(|| panic!("the page did not report its image:\n{console}"));
    let numbers: Vec<u32> = line
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    [numbers[0], numbers[1], numbers[2], numbers[3]]
}

/// `lumiere render` of `args` as a PNG.
fn render(args: &[&str]) -> image::RgbImage {
    let png = scratch(&format!(
        "render-{}.png",
        args.join("_").replace(['/', ','], "-")
    ));
    let out = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(["render", "-o"])
        .arg(&png)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    image::open(&png).unwrap().to_rgb8()
}

/// The built-in scene, a lesson step opened by the page's address, and a
/// glTF file dropped on the page.
#[test]
fn the_page_renders_a_built_in_scene_a_lesson_step_and_a_dropped_gltf_as_lumiere_render_does() {
    let Some((site, modules)) = site_or_skip() else {
        return;
    };
    let server = Served::start(&site);

    let shot = scratch("page.png");
    // two workers: the viewer's render loop on one, both rendering
    let console = open_page(&server, &modules, "?spp=8&threads=2", "[]", &shot);
    assert!(console.contains("lumiere: 2 Web Workers"), "{console}");
    assert!(
        console.contains("lumiere: reached 8 samples per pixel"),
        "{console}"
    );
    let page = image::open(&shot).unwrap().to_rgb8();
    let expected = render(&["cornell", "--width", "640", "--height", "480", "--spp", "8"]);
    let (worst, mean) = screen_difference(&page, image_rect(&console), &expected, 0..480);
    assert!(
        worst <= 2 && mean < 0.5,
        "the page's image differs from the render: worst {worst}/255, mean {mean:.3}"
    );

    // step 3: L2 alone at +2 EV, between the title and caption bands
    let shot = scratch("lesson.png");
    let console = open_page(
        &server,
        &modules,
        "?lesson=simulation-notions&step=3&spp=8",
        "[]",
        &shot,
    );
    let page = image::open(&shot).unwrap().to_rgb8();
    let expected = render(&[
        "cornell",
        "--width",
        "640",
        "--height",
        "480",
        "--terms",
        "L2",
        "--exposure",
        "2",
        "--spp",
        "8",
    ]);
    let (worst, mean) = screen_difference(&page, image_rect(&console), &expected, 160..320);
    assert!(
        worst <= 2 && mean < 0.5,
        "the lesson step's image differs from the render: worst {worst}/255, mean {mean:.3}"
    );

    // a glTF file dropped on the page, as a student drops one
    let gltf = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/cornell-glass.gltf");
    let shot = scratch("dropped.png");
    let drop = format!(r#"[{{"drop": {}}}]"#, json_path(&gltf));
    let console = open_page(&server, &modules, "?spp=8", &drop, &shot);
    assert!(console.contains("dropped cornell-glass.gltf"), "{console}");
    let page = image::open(&shot).unwrap().to_rgb8();
    let gltf = gltf.to_str().unwrap();
    let expected = render(&[gltf, "--width", "640", "--height", "480", "--spp", "8"]);
    let (worst, mean) = screen_difference(&page, image_rect(&console), &expected, 0..480);
    assert!(
        worst <= 2 && mean < 0.5,
        "the dropped scene's image differs from the render: worst {worst}/255, mean {mean:.3}"
    );
}

/// A GLB opened with the file picker (Ctrl+O), the screenshot downloaded
/// (Ctrl+S: PNG, EXR, settings), and a term switched off (key 0), which the
/// page keeps in its local storage across a reload.
#[test]
fn the_page_opens_a_picked_glb_downloads_its_screenshot_and_keeps_its_settings() {
    let Some((site, modules)) = site_or_skip() else {
        return;
    };
    let server = Served::start(&site);
    let gltf = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/cornell-mirror.gltf");
    let glb = scratch("cornell-mirror.glb");
    std::fs::write(&glb, common::glb(std::fs::read(&gltf).unwrap(), None)).unwrap();
    let picked = scratch("picked.png");
    let actions = format!(
        r#"[{{"pick": {}, "shot": {}}}, {{"save": 3}}, {{"key": "Digit0"}}, {{"reload": true}}]"#,
        json_path(&glb),
        json_path(&picked)
    );
    let shot = scratch("reloaded.png");
    let console = open_page(&server, &modules, "?spp=8", &actions, &shot);
    assert!(console.contains("picked cornell-mirror.glb"), "{console}");

    // the picked scene, as `lumiere render` renders its glTF
    let gltf = gltf.to_str().unwrap();
    let expected = render(&[gltf, "--width", "640", "--height", "480", "--spp", "8"]);
    let page = image::open(&picked).unwrap().to_rgb8();
    let (worst, mean) = screen_difference(&page, image_rect(&console), &expected, 0..480);
    assert!(
        worst <= 2 && mean < 0.5,
        "the picked scene's image differs from the render: worst {worst}/255, mean {mean:.3}"
    );

    // its screenshot, downloaded: the image as displayed, its radiance, its settings
    let downloads = downloads_of(&shot);
    let named = |suffix: &str| {
        let files: Vec<PathBuf> = std::fs::read_dir(&downloads)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.to_string_lossy().ends_with(suffix))
            .collect();
        assert_eq!(files.len(), 1, "one {suffix} in {files:?}");
        files[0].clone()
    };
    let png = image::open(named(".png")).unwrap().to_rgb8();
    let (worst, mean) = screen_difference(&png, [0, 0, 640, 480], &expected, 0..480);
    assert!(
        worst <= 2 && mean < 0.5,
        "the downloaded PNG differs from the render: worst {worst}/255, mean {mean:.3}"
    );
    let exr = image::open(named(".exr")).unwrap();
    assert_eq!((exr.width(), exr.height()), (640, 480));
    let sidecar: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(named(".json")).unwrap()).unwrap();
    assert_eq!(sidecar["samples_per_pixel"], 8, "{sidecar}");
    assert_eq!(sidecar["scene"], "cornell-mirror.glb", "{sidecar}");
    let stem = |path: PathBuf| path.file_stem().unwrap().to_owned();
    assert_eq!(stem(named(".png")), stem(named(".json")));

    // after the reload, the built-in scene with L0 still off
    let page = image::open(&shot).unwrap().to_rgb8();
    let expected = render(&[
        "cornell", "--width", "640", "--height", "480", "--terms", "L1,L2", "--spp", "8",
    ]);
    let (worst, mean) = screen_difference(&page, image_rect(&console), &expected, 0..480);
    assert!(
        worst <= 2 && mean < 0.5,
        "after the reload, the image differs from L1+L2: worst {worst}/255, mean {mean:.3}"
    );
}

/// Served without the cross-origin-isolation headers, as a plain static
/// host serves it: the page says it renders on one thread, and does, to
/// the same image.
#[test]
fn a_page_that_is_not_cross_origin_isolated_renders_on_one_thread() {
    let Some((site, modules)) = site_or_skip() else {
        return;
    };
    let server = Served::start_with(&site, &["--no-isolation"]);
    let shot = scratch("one-thread.png");
    // the notice is read, then closed, as a student does
    let close = r##"[{"click": "#notice button"}]"##;
    let console = open_page(&server, &modules, "?spp=4", close, &shot);
    assert!(
        console.contains("lumiere: one thread (the page is not cross-origin isolated)"),
        "{console}"
    );
    assert!(!console.contains("Web Workers"), "{console}");
    let page = image::open(&shot).unwrap().to_rgb8();
    let expected = render(&["cornell", "--width", "640", "--height", "480", "--spp", "4"]);
    let (worst, mean) = screen_difference(&page, image_rect(&console), &expected, 0..480);
    assert!(
        worst <= 2 && mean < 0.5,
        "the one-thread page's image differs from the render: worst {worst}/255, mean {mean:.3}"
    );
}

/// An address the viewer cannot open is said in the page, over the canvas,
/// naming what is wrong: never a blank page.
#[test]
fn a_bad_address_is_explained_in_the_page() {
    let Some((site, modules)) = site_or_skip() else {
        return;
    };
    let server = Served::start(&site);
    let url = format!("http://127.0.0.1:{}/?lesson=no-such-lesson", server.port);
    let (reached, console) = check_page(&url, &modules, "[]", &scratch("bad-address.png"), 20);
    assert!(!reached, "{console}");
    let status = console
        .lines()
        .find_map(|l| l.strip_prefix("status: "))
        .unwrap_or_else(|| panic!("nothing said in the page:\n{console}"));
    assert!(
        status.starts_with("lumiere could not start") && status.contains("no-such-lesson"),
        "{status}"
    );
}
