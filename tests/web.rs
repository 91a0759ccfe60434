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

/// Opens `query` on the served page, and drops the file `drop` on it if
/// given; the console's lines, after checking that the page reached its
/// samples (again, on the dropped scene) and logged no error.
fn open_page(
    server: &Served,
    modules: &Path,
    query: &str,
    drop: Option<&Path>,
    screenshot: &Path,
) -> String {
    let url = format!("http://127.0.0.1:{}/{query}", server.port);
    let mut check = Command::new("node");
    check
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/web/check.mjs"))
        .arg(&url)
        .arg(screenshot)
        .env("LUMIERE_NODE_MODULES", modules);
    if let Some(file) = drop {
        check.env("LUMIERE_DROP", file);
    }
    let out = check
        .output()
        .expect("node (Node.js) runs the page's check");
    let console = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{url}: the page did not reach its samples\n{console}\n{}",
        String::from_utf8_lossy(&out.stderr)
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
    let console = open_page(&server, &modules, "?spp=8", None, &shot);
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
        None,
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
    let console = open_page(&server, &modules, "?spp=8", Some(&gltf), &shot);
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
