//! `lumiere strip`: its size, tiles equal to renders of the same sample
//! counts, convergence along a row, rows of one option, and refused arguments.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use glam::Vec3;
use image::RgbImage;
use lumiere::course::color::srgb_to_linear;
use lumiere::render::export::to_srgb8;
use lumiere::scene::builtin;
use lumiere::tools::strip::{BAND_COLOR, StripLayout};
use lumiere::{Term, TermSet};

fn lumiere() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lumiere"))
}

fn temp_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lumiere-strip-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn run(args: &[&str], output: &Path) -> Output {
    let out = lumiere()
        .arg("strip")
        .arg("-o")
        .arg(output)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "strip {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(common::invalid_samples(&out), 0, "strip {args:?}");
    out
}

fn render_png(args: &[&str], output: &Path) -> RgbImage {
    let out = lumiere()
        .arg("render")
        .arg("-o")
        .arg(output)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(common::invalid_samples(&out), 0, "render {args:?}");
    image::open(output).unwrap().to_rgb8()
}

/// The tile at (`x0`, `y0`) of `strip`, `width` × `height`.
fn crop(strip: &RgbImage, x0: u32, y0: u32, width: u32, height: u32) -> RgbImage {
    image::imageops::crop_imm(strip, x0, y0, width, height).to_image()
}

/// Largest difference of one channel between two images of one size.
fn worst_difference(a: &RgbImage, b: &RgbImage) -> u8 {
    assert_eq!(a.dimensions(), b.dimensions());
    a.as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap()
}

fn labels(texts: &[&str]) -> Vec<String> {
    texts.iter().map(|s| s.to_string()).collect()
}

/// The strip is n tiles wide and one tile plus its band high; each tile is
/// the PNG `lumiere render` writes at that sample count with the same
/// options (same seed, same passes), exposure included.
#[test]
fn tiles_are_the_renders_of_their_sample_counts() {
    let (width, height) = (40, 30);
    let options = [
        "--terms",
        "L1",
        "--width",
        "40",
        "--height",
        "30",
        "--seed",
        "2",
        "--exposure",
        "1",
    ];
    let strip_path = temp_path("tiles.png");
    let mut args = vec!["cornell", "--spp", "1,3,8"];
    args.extend(options);
    let out = run(&args, &strip_path);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.starts_with("8 spp") && stdout.contains("rays") && stdout.lines().count() == 1,
        "summary: {stdout}"
    );

    let strip = image::open(&strip_path).unwrap().to_rgb8();
    let layout = StripLayout::new(width, height, labels(&["1 spp", "3 spp", "8 spp"]), vec![]);
    let band = layout.band_height();
    assert!(band > layout.text_size, "{layout:?}");
    assert_eq!(strip.dimensions(), (3 * width, height + band));

    let mut tiles = Vec::new();
    for (column, spp) in ["1", "3", "8"].into_iter().enumerate() {
        let mut args = vec!["--spp", spp];
        args.extend(options);
        let rendered = render_png(&args, &temp_path(&format!("render-{spp}.png")));
        let (x0, y0) = layout.tile_origin(0, column as u32);
        let tile = crop(&strip, x0, y0, width, height);
        let worst = worst_difference(&tile, &rendered);
        assert!(
            worst <= 1,
            "the {spp} spp tile differs from the render by {worst}/255"
        );
        tiles.push(tile);
    }
    assert!(
        worst_difference(&tiles[0], &tiles[1]) > 10,
        "the tiles should differ"
    );
    // the bands below the tiles are dark, each with its light label, whole:
    // no label pixel on the band's edges
    for column in 0..3 {
        let (x0, _) = layout.tile_origin(0, column);
        let band = crop(&strip, x0, height, width, band);
        assert!(band.pixels().any(|p| p.0[0] > 200) && band.pixels().any(|p| p.0[0] < 40));
        let edge = |x: u32, y: u32| x == 0 || y == 0 || x == width - 1 || y == band.height() - 1;
        let dark = BAND_COLOR[0] + 4;
        let touching = band
            .enumerate_pixels()
            .filter(|(x, y, p)| edge(*x, *y) && p.0[0] > dark);
        assert_eq!(
            touching.count(),
            0,
            "the label of column {column} is clipped"
        );
    }
}

/// Along a row the image converges: each tile is closer to a render of
/// 1024 spp than the one before (errors measured after the same display
/// mapping). Convergence, not correctness: the reference is lumiere's own.
///
/// The tiles and the reference have independent seeds and pixels are
/// independent, so the per-pixel differences of squared errors between two
/// tiles are independent draws whose mean estimates MSE(a) − MSE(b): a
/// paired one-sided z-test that the later tile's MSE is lower.
#[test]
fn the_tiles_of_a_row_converge_towards_a_reference_render() {
    // 3072 pixels: squared errors after the display mapping are skewed,
    // and fewer leave the step from 1 to 4 spp within a few standard errors
    let (width, height) = (64, 48);
    let strip_path = temp_path("converge.png");
    run(
        &[
            "--terms", "L1", "--width", "64", "--height", "48", "--spp", "1,4,64", "--seed", "5",
        ],
        &strip_path,
    );
    let strip = image::open(&strip_path).unwrap().to_rgb8();
    let layout = StripLayout::new(width, height, labels(&["1 spp", "4 spp", "64 spp"]), vec![]);

    let mut settings = common::small(width, height, TermSet::only(Term::L1));
    settings.seed = 1000;
    let reference =
        common::render_film(builtin::cornell(), &settings, 1024).radiance(settings.terms);
    let display = Default::default();
    let to_linear = |srgb: &[u8]| -> Vec<Vec3> {
        srgb.chunks_exact(3)
            .map(|c| Vec3::from_array([0, 1, 2].map(|i| srgb_to_linear(c[i] as f32 / 255.0))))
            .collect()
    };
    let reference = to_linear(&to_srgb8(&reference, display));
    let squared_errors = |column: u32| -> Vec<f64> {
        let (x0, y0) = layout.tile_origin(0, column);
        let tile = crop(&strip, x0, y0, width, height);
        common::pixel_errors(&to_linear(tile.as_raw()), &reference)
            .iter()
            .map(|e| e.rmse * e.rmse)
            .collect()
    };
    let tiles = [squared_errors(0), squared_errors(1), squared_errors(2)];
    let spp = [1, 4, 64];
    for (earlier, later) in [(0, 1), (1, 2)] {
        let (lowered, error) = common::paired_difference(&tiles[earlier], &tiles[later]);
        let z = lowered / error;
        assert!(
            z > 4.5,
            "MSE from {} to {} spp lowered by {lowered:.2e} ± {error:.1e} (z = {z:.2})",
            spp[earlier],
            spp[later]
        );
    }
}

/// `--rows` adds one labelled row per value; each row is the render with
/// that value, and prints its own summary line.
#[test]
fn rows_sweep_one_option() {
    let (width, height) = (24, 16);
    let strip_path = temp_path("rows.png");
    let options = ["--terms", "L1", "--seed", "3"];
    let mut args = vec![
        "--spp",
        "1,4",
        "--tile-width",
        "24",
        "--tile-height",
        "16",
        "--rows",
        "lights=authored,point",
    ];
    args.extend(options);
    let out = run(&args, &strip_path);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert!(lines[0].starts_with("lights=authored: 4 spp"), "{stdout}");
    assert!(lines[1].starts_with("lights=point: 4 spp"), "{stdout}");

    let strip = image::open(&strip_path).unwrap().to_rgb8();
    let layout = StripLayout::new(
        width,
        height,
        labels(&["1 spp", "4 spp"]),
        labels(&["authored", "point"]),
    );
    let left = layout.label_column_width();
    assert!(left > 0);
    assert_eq!(
        strip.dimensions(),
        (left + 2 * width, 2 * (height + layout.band_height()))
    );
    let (x0, y0) = layout.tile_origin(1, 1);
    let tile = crop(&strip, x0, y0, width, height);
    let mut args = vec![
        "--spp", "4", "--width", "24", "--height", "16", "--lights", "point",
    ];
    args.extend(options);
    let rendered = render_png(&args, &temp_path("rows-point.png"));
    assert!(worst_difference(&tile, &rendered) <= 1);
    let (x0, y0) = layout.tile_origin(0, 1);
    let authored = crop(&strip, x0, y0, width, height);
    assert!(
        worst_difference(&tile, &authored) > 10,
        "the rows should differ"
    );
    // the row labels are drawn in the left column
    let column = crop(&strip, 0, 0, left, height);
    assert!(column.pixels().any(|p| p.0[0] > 200));
}

#[test]
fn bad_arguments_exit_with_code_2_and_say_why() {
    let png = temp_path("bad.png");
    for (args, says) in [
        (vec!["--spp", "0"], "at least 1"),
        (vec!["--spp", "4,2"], "must increase"),
        (vec!["--spp", "abc"], "'abc' is not a sample count"),
        (vec!["--rows", "light-sampling"], "OPTION=V1,V2"),
        (vec!["--rows", "colour=red"], "unknown option 'colour'"),
        (
            vec!["--rows", "sampler=sobol,halton"],
            "unknown value 'halton'",
        ),
        (vec!["--rows", "indirect-samples=1,999"], "within 1..=256"),
        (
            vec!["--width", "8", "--tile-width", "8"],
            "cannot be used with",
        ),
        (
            vec!["--width", "9000", "--height", "10", "--spp", "1,2"],
            "is 18000×",
        ),
    ] {
        let result = lumiere()
            .args(["strip", "-o"])
            .arg(&png)
            .args(&args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
    let result = lumiere()
        .args(["strip", "-o", "strip.exr"])
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&result.stderr).contains("PNG only"));
}
