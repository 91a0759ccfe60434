//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use glam::Vec3;
use lumiere::analysis::metrics::{ImageError, image_error};
use lumiere::geometry::Ray;
use lumiere::render::{Budget, RenderStats, render};
use lumiere::transport::counts::RayCounts;
use lumiere::transport::sampler::SampleStream;
use lumiere::transport::splitting::choose_continuations;
use lumiere::{Film, RenderContext, RenderSettings, Scene, Term, TermSet};

/// Adds the plane z = 0, 2·`half_side` wide, facing +z.
pub fn add_floor(scene: &mut Scene, material: u32, half_side: f32) {
    let s = half_side;
    let plane = [
        Vec3::new(-s, -s, 0.0),
        Vec3::new(s, -s, 0.0),
        Vec3::new(s, s, 0.0),
        Vec3::new(-s, s, 0.0),
    ];
    scene.add_mesh("plane", material, &plane, &[[0, 1, 2], [0, 2, 3]]);
}

/// Renders `scene` with `settings` at `spp` samples per pixel.
pub fn render_film(scene: Scene, settings: &RenderSettings, spp: u32) -> Film {
    render_with_stats(scene, settings, spp).0
}

/// [`render_film`], with what the render did. Every render must be free of
/// invalid samples: the film's guard zeroes a NaN, infinite or negative
/// sample before it reaches the film, so only its count can show one.
pub fn render_with_stats(scene: Scene, settings: &RenderSettings, spp: u32) -> (Film, RenderStats) {
    let mut context = RenderContext::new(scene, settings.clone());
    // as `lumiere render` does: the pilot, if the settings ask for it
    choose_continuations(&mut context);
    let mut film = Film::new(settings.width, settings.height);
    let stats = render(&context, &mut film, Budget::Samples(spp), |_| {});
    assert_no_invalid_samples(&stats.rays);
    (film, stats)
}

/// The samples a command's renders dropped (NaN, infinite or negative
/// radiance), summed over its summary lines "… N invalid samples dropped"
/// (`lumiere strip` prints one per row); panics if it printed none.
pub fn invalid_samples(output: &std::process::Output) -> u64 {
    let stdout = String::from_utf8_lossy(&output.stdout);
    let counts: Vec<u64> = stdout
        .lines()
        .filter_map(|line| line.strip_suffix(" invalid samples dropped"))
        .map(|before| {
            let count = before.rsplit(' ').next().unwrap_or_default();
            count
                .parse()
                .unwrap_or_else(|_| panic!("not a count: {count:?} in {stdout}"))
        })
        .collect();
    assert!(
        !counts.is_empty(),
        "no invalid sample count in the output: {stdout}"
    );
    counts.iter().sum()
}

/// Asserts the guard dropped no sample (NaN, infinite or negative radiance).
#[track_caller]
pub fn assert_no_invalid_samples(counts: &RayCounts) {
    assert_eq!(
        counts.invalid_samples, 0,
        "{} samples had NaN, infinite or negative radiance",
        counts.invalid_samples
    );
}

/// Settings of a small image with only `terms`.
pub fn small(width: u32, height: u32, terms: TermSet) -> RenderSettings {
    RenderSettings {
        width,
        height,
        terms,
        ..RenderSettings::default()
    }
}

/// Image mean of a term's luminance and its standard error (pixels are independent).
pub fn mean_and_error(film: &Film, term: Term) -> (f64, f64) {
    let buffer = film.term(term).expect("term rendered");
    let n = film.pixel_count() as f64;
    let mean = (0..film.pixel_count())
        .map(|i| lumiere::course::color::luminance(buffer.mean(i).as_vec3()) as f64)
        .sum::<f64>()
        / n;
    let variance: f64 = (0..film.pixel_count())
        .map(|i| buffer.standard_error(i).powi(2))
        .sum::<f64>();
    (mean, variance.sqrt() / n)
}

/// Each pixel's error against `reference`, measured as `image_error`
/// measures a whole image (squared and relative squared, over the channels).
pub fn pixel_errors(image: &[Vec3], reference: &[Vec3]) -> Vec<ImageError> {
    assert_eq!(image.len(), reference.len());
    image
        .iter()
        .zip(reference)
        .map(|(p, r)| image_error(&[*p], &[*r]).expect("one pixel each"))
        .collect()
}

/// Mean and standard error of the per-pixel differences `a` − `b`. Pixels
/// are independent, and a reference's own noise adds the same expected
/// amount to two images' errors against it, so for squared errors the mean
/// estimates MSE(a) − MSE(b).
pub fn paired_difference(a: &[f64], b: &[f64]) -> (f64, f64) {
    assert_eq!(a.len(), b.len());
    let n = a.len() as f64;
    let differences: Vec<f64> = a.iter().zip(b).map(|(a, b)| a - b).collect();
    let mean = differences.iter().sum::<f64>() / n;
    let variance = differences.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// Relative error allowed, beyond the noise, for f32 arithmetic where the
/// closed form is exact: a sample's value is a chain of a few dozen f32
/// operations, each rounded by at most 2⁻²⁴ ≈ 6·10⁻⁸ of its result, so at
/// most a few 10⁻⁶ even if every rounding went the same way.
pub const F32_ROUNDING: f64 = 1e-5;

/// The relative error a closed form for a sphere of radius `radius` centred
/// at the origin can have on its tessellation, `scene`'s triangles: a
/// light at the centre sees each facet at distances between h (the
/// facet's plane) and `radius`, so its irradiance I cos θ / d² = I h / d³
/// lies within [h/R, (R/h)²] of I/R². Returns the larger excursion for the
/// closest plane, (R/h)² − 1.
pub fn sphere_tessellation_error(scene: &Scene, radius: f64) -> f64 {
    let closest = scene
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.vertices.map(|v| scene.positions[v as usize].as_dvec3());
            let n = (b - a).cross(c - a).normalize();
            n.dot(a).abs()
        })
        .fold(f64::INFINITY, f64::min);
    (radius / closest).powi(2) - 1.0
}

/// Asserts `measured` agrees with `expected` within `z` standard errors plus
/// a relative allowance `systematic` for known modelling error (tessellation).
pub fn assert_agrees(what: &str, measured: (f64, f64), expected: f64, z: f64, systematic: f64) {
    let (mean, error) = measured;
    let tolerance = z * error + systematic * expected.abs();
    assert!(
        (mean - expected).abs() <= tolerance,
        "{what}: measured {mean:.6} ± {error:.2e}, expected {expected:.6} (tolerance {tolerance:.2e}, z = {:.2})",
        (mean - expected) / error.max(1e-30)
    );
}

pub fn corpus_dir() -> PathBuf {
    let dir = std::env::var_os("LUMIERE_GLTF_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/gltf-corpus"));
    assert!(
        dir.is_dir(),
        "glTF corpus not found at {} (clone `shared/` beside the repository or set LUMIERE_GLTF_CORPUS)",
        dir.display()
    );
    dir
}

/// The .gltf and .glb files under `dir`, recursively, sorted.
pub fn gltf_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "gltf" || e == "glb") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// Irradiance at p (normal n) from a Lambertian polygon of radiance L:
/// E = L/2 · |Σ θᵢ n·(vᵢ × vᵢ₊₁)/|vᵢ × vᵢ₊₁||  (Lambert, 1760).
pub fn polygon_irradiance(p: Vec3, n: Vec3, corners: &[Vec3], radiance: f64) -> f64 {
    let mut sum = 0.0f64;
    for i in 0..corners.len() {
        let a = (corners[i] - p).as_dvec3().normalize();
        let b = (corners[(i + 1) % corners.len()] - p)
            .as_dvec3()
            .normalize();
        let theta = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += theta * n.as_dvec3().dot(a.cross(b).normalize());
    }
    radiance / 2.0 * sum.abs()
}

/// Mean and standard error of a term along `ray` over `n` samples of seed `seed`.
pub fn estimate(context: &RenderContext, ray: Ray, term: Term, n: u64, seed: u64) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    let mut counts = RayCounts::default();
    for i in 0..n {
        let stream = SampleStream::new(seed, 0, i);
        // `trace` is unguarded: a NaN or a negative value reaches the test
        let radiance =
            lumiere::transport::trace(context, ray, &stream, context.settings.terms, &mut counts);
        assert!(
            radiance
                .iter()
                .all(|l| l.is_finite() && l.min_element() >= 0.0),
            "sample {i} of seed {seed}: {radiance:?}"
        );
        let value = radiance[term.index()].x as f64;
        sum += value;
        sum2 += value * value;
    }
    let mean = sum / n as f64;
    let variance = (sum2 / n as f64 - mean * mean).max(0.0);
    (mean, (variance / n as f64).sqrt())
}

/// A GLB container around `json` and an optional BIN chunk (both padded).
pub fn glb(json: impl AsRef<[u8]>, bin: Option<&[u8]>) -> Vec<u8> {
    let mut json = json.as_ref().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut chunks = Vec::new();
    chunks.extend((json.len() as u32).to_le_bytes());
    chunks.extend(b"JSON");
    chunks.extend(&json);
    if let Some(bin) = bin {
        let mut bin = bin.to_vec();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        chunks.extend((bin.len() as u32).to_le_bytes());
        chunks.extend(b"BIN\0");
        chunks.extend(&bin);
    }
    let mut file = b"glTF".to_vec();
    file.extend(2u32.to_le_bytes());
    file.extend((12 + chunks.len() as u32).to_le_bytes());
    file.extend(chunks);
    file
}

pub const GLB_JSON: &str = r#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
"bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":36}]}"#;

pub fn triangle_bin() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// A handwritten glTF file of `tests/data/gltf`.
pub fn data_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gltf")
        .join(name)
}

/// The text of a handwritten glTF file.
pub fn read_data(name: &str) -> String {
    std::fs::read_to_string(data_path(name)).unwrap()
}

/// Two positions equal within 10⁻⁵.
#[track_caller]
pub fn assert_close(actual: Vec3, expected: Vec3) {
    assert!(
        (actual - expected).length() < 1e-5,
        "{actual} is not {expected}"
    );
}

/// Worst and mean difference (8-bit codes) between a screenshot's image in
/// `rect` ([x, y, width, height], screenshot pixels), sampled at each film
/// pixel's centre, and `expected`, over `rows` of `expected`.
pub fn screen_difference(
    screen: &image::RgbImage,
    [x, y, w, h]: [u32; 4],
    expected: &image::RgbImage,
    rows: std::ops::Range<u32>,
) -> (i32, f64) {
    let (mut worst, mut total, mut count) = (0i32, 0i64, 0i64);
    for j in rows {
        for i in 0..expected.width() {
            let sx = x + ((i as f32 + 0.5) * w as f32 / expected.width() as f32) as u32;
            let sy = y + ((j as f32 + 0.5) * h as f32 / expected.height() as f32) as u32;
            let shown = screen.get_pixel(sx, sy).0;
            let want = expected.get_pixel(i, j).0;
            for c in 0..3 {
                let d = (shown[c] as i32 - want[c] as i32).abs();
                worst = worst.max(d);
                total += d as i64;
                count += 1;
            }
        }
    }
    (worst, total as f64 / count as f64)
}

/// `lumiere serve FOLDER` on a free port of 127.0.0.1; stopped when dropped.
pub struct Served {
    child: std::process::Child,
    pub port: u16,
}

impl Served {
    pub fn start(folder: &Path) -> Self {
        Self::start_with(folder, &[])
    }

    /// `lumiere serve --port 0 FOLDER` with more `options`.
    pub fn start_with(folder: &Path, options: &[&str]) -> Self {
        use std::io::BufRead;
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
            .args(["serve", "--port", "0"])
            .args(options)
            .arg(folder)
            .stdout(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut line = String::new();
        std::io::BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        // "serving DIR at http://127.0.0.1:PORT/ (Ctrl+C stops)"
        let port = line
            .split("127.0.0.1:")
            .nth(1)
            .and_then(|rest| rest.split('/').next())
            .and_then(|port| port.parse().ok())
            .unwrap_or_else(|| panic!("no port in {line:?}"));
        Self { child, port }
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
