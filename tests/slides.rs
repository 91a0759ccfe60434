//! `lumiere lesson --export`: one slide per step with the right names and
//! size, an index listing them, text in the title and caption bands, an
//! image region equal to a render of the step's settings, the language
//! changing the text only, noise views and the probe's rays drawn, GIFs of
//! the expected frames, and errors that name the file.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use image::codecs::gif::GifDecoder;
use image::{AnimationDecoder, RgbImage};
use lumiere::analysis::noise::{DisplayMode, NoiseView, false_colour};
use lumiere::course::color::linear_to_srgb;
use lumiere::lesson::{Lang, Lesson, StepView};
use lumiere::render::export::to_srgb8;
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::tools::slides::{BACKGROUND, BAND_COLOR, Rect, SlideLayout};
use lumiere::transport::splitting::choose_continuations;
use lumiere::{Film, RenderContext};

/// The slides' size in these tests, their samples per pixel and seed.
const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;
const SPP: u32 = 2;
const SEED: u64 = 5;

fn lumiere() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lumiere"))
}

/// A fresh folder for one test's files.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("lumiere-slides-tests-{}", std::process::id()))
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `lumiere lesson LESSON --export DIR ARGS`, which must succeed without invalid samples.
fn export(lesson: &str, dir: &Path, args: &[&str]) -> Output {
    let out = lumiere()
        .args(["lesson", lesson, "--export"])
        .arg(dir)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "lesson {lesson} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(common::invalid_samples(&out), 0, "lesson {args:?}");
    out
}

/// The built-in lesson exported at 320×180, 2 spp, seed 5, in `lang` (once per run).
fn built_in_export(lang: Lang) -> &'static Path {
    static FR: OnceLock<PathBuf> = OnceLock::new();
    static EN: OnceLock<PathBuf> = OnceLock::new();
    let cell = match lang {
        Lang::Fr => &FR,
        Lang::En => &EN,
    };
    cell.get_or_init(|| {
        let dir = temp_dir(&format!("built-in-{lang}"));
        let (w, h, spp, seed) = (WIDTH.to_string(), HEIGHT.to_string(), SPP.to_string(), SEED);
        let seed = seed.to_string();
        let lang = lang.to_string();
        let args = [
            "--width", &w, "--height", &h, "--spp", &spp, "--seed", &seed, "--lang", &lang,
        ];
        export("simulation-notions", &dir, &args);
        dir
    })
}

fn lesson() -> Lesson {
    Lesson::load("simulation-notions").unwrap()
}

fn layout() -> SlideLayout {
    SlideLayout::new(WIDTH, HEIGHT)
}

/// The slide files of step `i` (from 0): `NN-slug`.
fn stem(lesson: &Lesson, i: usize) -> String {
    format!("{:02}-{}", i + 1, lesson.steps[i].slug)
}

fn open(path: &Path) -> RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

fn crop(image: &RgbImage, rect: Rect) -> RgbImage {
    image::imageops::crop_imm(image, rect.x, rect.y, rect.width, rect.height).to_image()
}

/// Pixels of `rect` that are not `colour`.
fn pixels_unlike(image: &RgbImage, rect: Rect, colour: [u8; 3]) -> usize {
    crop(image, rect).pixels().filter(|p| p.0 != colour).count()
}

/// Step `i`'s view on the slides' film, with the tests' samples and seed.
/// The index of the step named `slug`.
fn index_of(lesson: &Lesson, slug: &str) -> usize {
    lesson
        .steps
        .iter()
        .position(|step| step.slug == slug)
        .unwrap_or_else(|| panic!("no step {slug}"))
}

fn step_view(lesson: &Lesson, i: usize, seed: u64, spp: u32) -> StepView {
    let image = layout().image;
    let mut view = lesson.view(i, image.width, image.height).unwrap();
    view.settings.seed = seed;
    view.spp = spp;
    view
}

/// A render of `view` as `lumiere render` makes one: its film after `view.spp` passes.
fn direct_film(view: &StepView) -> Film {
    let scene = builtin::load(&view.scene).unwrap();
    let mut context = RenderContext::new(scene, view.settings.clone());
    choose_continuations(&mut context);
    let mut film = Film::new(view.settings.width, view.settings.height);
    let stats = render(&context, &mut film, Budget::Samples(view.spp), |_| {});
    common::assert_no_invalid_samples(&stats.rays);
    film
}

/// [`direct_film`] as the PNG export shows it (exposure, tonemap, sRGB).
fn direct_render(view: &StepView) -> RgbImage {
    let film = direct_film(view);
    let srgb = to_srgb8(&film.radiance(view.settings.terms), view.display);
    RgbImage::from_raw(view.settings.width, view.settings.height, srgb).unwrap()
}

/// Pixels that differ between two images of one size.
fn differing(a: &RgbImage, b: &RgbImage) -> usize {
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count()
}

#[test]
fn the_export_writes_one_slide_per_step_with_its_name_and_size_and_an_index_of_them() {
    let dir = built_in_export(Lang::En);
    let lesson = lesson();
    let mut pngs: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".png"))
        .collect();
    pngs.sort();
    let expected: Vec<String> = (0..lesson.steps.len())
        .map(|i| format!("{}.png", stem(&lesson, i)))
        .collect();
    assert_eq!(pngs, expected);
    assert_eq!(pngs[0], "01-l0-emission.png");
    for name in &pngs {
        assert_eq!(
            open(&dir.join(name)).dimensions(),
            (WIDTH, HEIGHT),
            "{name}"
        );
    }
    let index = std::fs::read_to_string(dir.join("index.md")).unwrap();
    for (i, step) in lesson.steps.iter().enumerate() {
        let title = format!("## {}. {}", i + 1, step.title.en);
        assert!(index.contains(&title), "{title} not in the index");
        assert!(index.contains(&format!("({}.png)", stem(&lesson, i))));
        assert!(index.contains(&format!("`{}`", step.formula)));
        // Markdown's markup is escaped (L\_direct): read without the backslashes
        let unescaped = index.replace('\\', "");
        assert!(unescaped.contains(&step.caption.en), "step {}", i + 1);
    }
    // every step at the --spp given and the --seed
    let settings = index
        .matches(&format!(" · {SPP} spp, seed {SEED}\n"))
        .count();
    assert_eq!(settings, lesson.steps.len());
    assert!(index.contains("scene cornell, terms L2, exposure +2 EV"));
    assert!(!index.contains(".gif"), "no GIF without --gif");
}

#[test]
fn every_slide_has_its_title_and_caption_drawn_within_the_margins() {
    let dir = built_in_export(Lang::En);
    let lesson = lesson();
    let layout = layout();
    let (top, bottom) = (layout.top_band, layout.bottom_band);
    let margin = layout.side_margin.round() as u32;
    assert_eq!(
        BAND_COLOR, BACKGROUND,
        "the text is drawn on the slide's background"
    );
    for i in 0..lesson.steps.len() {
        let slide = open(&dir.join(format!("{}.png", stem(&lesson, i))));
        let title = pixels_unlike(&slide, layout.title_rect(), BAND_COLOR);
        let caption = pixels_unlike(&slide, layout.caption_rect(), BAND_COLOR);
        // a few letters at 9 px cover well over 50 pixels
        assert!(title > 50, "step {}: {title} title pixels", i + 1);
        assert!(caption > 50, "step {}: {caption} caption pixels", i + 1);
        // nothing spills into the side margins of the bands
        for band in [top, bottom] {
            for rect in [
                Rect::new(0, band.y, margin - 1, band.height),
                Rect::new(WIDTH - margin + 1, band.y, margin - 1, band.height),
            ] {
                assert_eq!(
                    pixels_unlike(&slide, rect, BAND_COLOR),
                    0,
                    "step {}: text in the margin {rect:?}",
                    i + 1
                );
            }
        }
    }
}

#[test]
fn the_image_region_is_the_render_of_the_steps_settings_and_the_probe_draws_its_rays() {
    let dir = built_in_export(Lang::En);
    let lesson = lesson();
    let image = layout().image;
    let mut probed = 0;
    for i in 0..lesson.steps.len() {
        let slide = open(&dir.join(format!("{}.png", stem(&lesson, i))));
        let view = step_view(&lesson, i, SEED, SPP);
        let region = crop(&slide, image);
        let direct = direct_render(&view);
        let differences = differing(&region, &direct);
        if let Some(mut b) = view.split_settings() {
            // A | B: A's columns left of the middle, B's (the next seed) right
            // of it, below the labels
            b.seed += 1;
            let b_view = StepView {
                settings: b,
                ..view.clone()
            };
            let b_direct = direct_render(&b_view);
            let (w, h) = (image.width, image.height);
            let below_labels = h / 4;
            let left = Rect::new(0, below_labels, w / 2 - 2, h - below_labels);
            let right = Rect::new(w / 2 + 2, below_labels, w - w / 2 - 2, h - below_labels);
            assert_eq!(
                differing(&crop(&region, left), &crop(&direct, left)),
                0,
                "step {}: A",
                i + 1
            );
            assert_eq!(
                differing(&crop(&region, right), &crop(&b_direct, right)),
                0,
                "step {}: B",
                i + 1
            );
            assert!(differing(&crop(&region, right), &crop(&direct, right)) > 0);
        } else if view.display.layout == lumiere::render::display::Layout::FourUp {
            // four tiles, two by two: L0 (top left) is dark but for the light,
            // the sum (bottom right) is lit
            let (w, h) = (image.width / 2, image.height / 2);
            let dark = |rect: Rect| {
                let tile = crop(&region, rect);
                tile.pixels()
                    .filter(|p| p.0.iter().all(|&c| c < 10))
                    .count() as f64
                    / (tile.width() * tile.height()) as f64
            };
            let l0 = dark(Rect::new(0, h / 4, w, h - h / 4));
            let sum = dark(Rect::new(w, h + h / 4, w, h - h / 4));
            assert!(l0 > 0.9 && sum < 0.5, "step {}: L0 {l0}, sum {sum}", i + 1);
        } else if view.probe.is_some() {
            // the rays: a few lines over the image, which is otherwise the render's
            probed += 1;
            let pixels = (image.width * image.height) as usize;
            assert!(differences > 20, "step {}: no rays drawn", i + 1);
            assert!(differences < pixels / 10, "step {}: {differences}", i + 1);
        } else {
            assert_eq!(differences, 0, "step {}", i + 1);
        }
    }
    assert_eq!(probed, 1, "the built-in lesson probes one pixel");
    // another seed is another image: the region follows --seed
    let sum = index_of(&lesson, "l0-l1-l2");
    let view = step_view(&lesson, sum, SEED + 1, SPP);
    let slide = open(&dir.join(format!("{}.png", stem(&lesson, sum))));
    assert!(differing(&crop(&slide, image), &direct_render(&view)) > 100);
}

#[test]
fn the_language_changes_the_texts_and_not_the_image() {
    let (fr, en) = (built_in_export(Lang::Fr), built_in_export(Lang::En));
    let lesson = lesson();
    let layout = layout();
    let mut titles_compared = 0;
    for (i, step) in lesson.steps.iter().enumerate() {
        let name = format!("{}.png", stem(&lesson, i));
        let (a, b) = (open(&fr.join(&name)), open(&en.join(&name)));
        assert_eq!(
            differing(&crop(&a, layout.image), &crop(&b, layout.image)),
            0,
            "step {}: the image is the same in both languages",
            i + 1
        );
        let top = differing(&crop(&a, layout.top_band), &crop(&b, layout.top_band));
        if step.title.fr == step.title.en {
            assert_eq!(top, 0, "step {}: same title, same band", i + 1);
        } else {
            titles_compared += 1;
            assert!(top > 20, "step {}: {top} title pixels differ", i + 1);
        }
        let bottom = differing(&crop(&a, layout.bottom_band), &crop(&b, layout.bottom_band));
        assert!(
            bottom > 50,
            "step {}: {bottom} caption pixels differ",
            i + 1
        );
    }
    assert!(titles_compared > 20, "{titles_compared}");
    let index = std::fs::read_to_string(fr.join("index.md")).unwrap();
    assert!(index.contains("## 2. L₁ : l'éclairage direct"), "{index}");
}

/// A lesson of `steps`, each (slug, settings lines).
fn lesson_file(dir: &Path, steps: &[(&str, &str)]) -> PathBuf {
    let mut text = String::from(
        "name = \"test\"\ntitle = { fr = \"Essai\", en = \"Test\" }\n[defaults]\nsampler = \"sobol\"\n",
    );
    for (slug, settings) in steps {
        text += &format!(
            "\n[[steps]]\nslug = \"{slug}\"\nformula = \"L = L₀\"\ntitle = {{ fr = \"Un\", en = \"One\" }}\ncaption = {{ fr = \"Une phrase.\", en = \"A sentence.\" }}\n[steps.settings]\n{settings}\n"
        );
    }
    let path = dir.join("test.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_noise_view_shows_its_false_colours_and_a_colour_bar() {
    let dir = temp_dir("noise");
    let file = lesson_file(&dir, &[("se", "display = \"standard-error\"\nspp = 4")]);
    let out_dir = dir.join("slides");
    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    export(
        file.to_str().unwrap(),
        &out_dir,
        &["--width", &w, "--height", &h, "--seed", "3"],
    );
    let slide = open(&out_dir.join("01-se.png"));
    let lesson = Lesson::load(file.to_str().unwrap()).unwrap();
    let view = step_view(&lesson, 0, 3, 4);
    assert_eq!(view.display_mode, DisplayMode::StandardError);
    let film = direct_film(&view);
    let noise_view = NoiseView {
        mode: DisplayMode::StandardError,
        ..NoiseView::default()
    };
    let colours = false_colour(&film, view.settings.terms, noise_view, None).unwrap();
    let srgb: Vec<u8> = colours
        .rgba
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]])
        .map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8)
        .collect();
    let expected = RgbImage::from_raw(view.settings.width, view.settings.height, srgb).unwrap();
    let layout = layout();
    let region = crop(&slide, layout.image);
    assert_eq!(differing(&region, &expected), 0, "the false colours");
    assert!(
        differing(&region, &direct_render(&view)) > 1000,
        "not the image"
    );
    // the colour bar and its labels in the right margin, none in the left one
    let right = layout.right_margin();
    let left = Rect::new(0, right.y, layout.image.x, right.height);
    assert!(pixels_unlike(&slide, right, BACKGROUND) > 200);
    assert_eq!(pixels_unlike(&slide, left, BACKGROUND), 0);
}

#[test]
fn the_gif_shows_the_slide_at_each_doubling_of_the_samples() {
    let dir = temp_dir("gif");
    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    export(
        "simulation-notions",
        &dir,
        &["--width", &w, "--height", &h, "--spp", "5", "--gif"],
    );
    let lesson = lesson();
    let layout = layout();
    let half = |r: Rect| Rect::new(r.x / 2, r.y / 2, r.width / 2, r.height / 2);
    // the image region at 5 spp, halved: the pixels well inside it, away from the label
    let inside = half(layout.image);
    let inside = Rect::new(
        inside.x + 2,
        inside.y + 2,
        inside.width / 2,
        inside.height / 2,
    );
    for i in 0..lesson.steps.len() {
        let path = dir.join(format!("{}.gif", stem(&lesson, i)));
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let frames = GifDecoder::new(file)
            .unwrap()
            .into_frames()
            .collect_frames()
            .unwrap();
        assert_eq!(frames.len(), 4, "{}: 1, 2, 4, 5 spp", path.display());
        let delays: Vec<u32> = frames
            .iter()
            .map(|f| {
                let (numerator, denominator) = f.delay().numer_denom_ms();
                numerator / denominator
            })
            .collect();
        assert_eq!(delays, [700, 700, 700, 2100]);
        let pictures: Vec<RgbImage> = frames
            .into_iter()
            .map(|f| image::DynamicImage::ImageRgba8(f.into_buffer()).to_rgb8())
            .collect();
        for picture in &pictures {
            assert_eq!(picture.dimensions(), (WIDTH / 2, HEIGHT / 2));
        }
        // the last frame is the PNG at half size, to the palette's error
        let png = open(&dir.join(format!("{}.png", stem(&lesson, i))));
        let png_half = halve(&png);
        let (last, png_half) = (crop(&pictures[3], inside), crop(&png_half, inside));
        let error = mean_difference(&last, &png_half);
        // 256 colours a frame: 4.4 levels at most over the 25 steps (measured)
        assert!(error < 6.0, "step {}: {error}", i + 1);
        // a noisy step converges: its first frame is farther from the PNG than its last
        let first = mean_difference(&crop(&pictures[0], inside), &png_half);
        if lesson.steps[i].slug.starts_with("noise-") {
            assert!(first > 2.0 * error, "step {}: {first} vs {error}", i + 1);
        }
    }
}

/// `image` at half its size, each pixel the mean of a 2 × 2 block.
fn halve(image: &RgbImage) -> RgbImage {
    RgbImage::from_fn(image.width() / 2, image.height() / 2, |x, y| {
        let block = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .map(|(dx, dy)| image.get_pixel(2 * x + dx, 2 * y + dy).0);
        image::Rgb(std::array::from_fn(|c| {
            ((block.iter().map(|p| p[c] as u32).sum::<u32>() + 2) / 4) as u8
        }))
    })
}

/// Mean absolute difference per channel between two images of one size.
fn mean_difference(a: &RgbImage, b: &RgbImage) -> f64 {
    let sum: u64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| x.abs_diff(*y) as u64)
        .sum();
    sum as f64 / a.as_raw().len() as f64
}

/// Runs `lumiere lesson ARGS`, which must fail with `code`; returns stderr.
fn refusal(args: &[&str], code: i32) -> String {
    let out = lumiere().arg("lesson").args(args).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

#[test]
fn broken_lessons_bad_sizes_and_unwritable_folders_are_refused_with_a_clear_message() {
    let dir = temp_dir("refusals");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    // a lesson file with an unknown field on line 7
    let file = lesson_file(&dir, &[("one", "colour = \"red\"")]);
    let text = std::fs::read_to_string(&file).unwrap();
    let line = text.lines().position(|l| l.starts_with("colour")).unwrap() + 1;
    let file = file.to_str().unwrap();
    let stderr = refusal(&[file, "--export", out], 1);
    assert!(stderr.contains(file), "{stderr}");
    assert!(stderr.contains(&format!("line {line}")), "{stderr}");
    assert!(stderr.contains("`colour`"), "{stderr}");
    assert!(!Path::new(out).exists(), "nothing written");

    let stderr = refusal(&["no-such-lesson", "--export", out], 1);
    assert!(
        stderr.contains("no-such-lesson") && stderr.contains("built in"),
        "{stderr}"
    );

    for (flag, value) in [("--width", "0"), ("--height", "0"), ("--width", "16385")] {
        let stderr = refusal(&["simulation-notions", "--export", out, flag, value], 2);
        assert!(
            stderr.contains(flag) && stderr.contains("1..=16384"),
            "{stderr}"
        );
    }
    let stderr = refusal(
        &["simulation-notions", "--export", out, "--height", "10"],
        2,
    );
    assert!(stderr.contains("between its text bands"), "{stderr}");

    // a folder inside a file cannot be made
    let blocker = dir.join("a-file");
    std::fs::write(&blocker, "").unwrap();
    let inside = blocker.join("slides");
    let inside = inside.to_str().unwrap();
    let stderr = refusal(&["simulation-notions", "--export", inside, "--spp", "1"], 1);
    assert!(
        stderr.contains(inside) && stderr.contains("cannot create"),
        "{stderr}"
    );

    // a difference view needs a reference image
    let file = lesson_file(&dir, &[("diff", "display = \"difference\"")]);
    let stderr = refusal(&[file.to_str().unwrap(), "--export", out], 1);
    assert!(
        stderr.contains("step 1 ('diff')") && stderr.contains("reference"),
        "{stderr}"
    );
}
