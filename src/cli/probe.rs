//! `lumiere probe`: the integral at one pixel's first hit, as a map of the
//! hemisphere, its quadrature and the estimator's mean there.

use std::path::PathBuf;

use clap::Args;
use glam::Vec2;

use lumiere::analysis::hemisphere::{HemisphereError, IntegrandMap, estimator_mean, integrand_map};
use lumiere::course::color::luminance;
use lumiere::render::display::DisplaySettings;
use lumiere::render::export::{ImageFormat, save_image};
use lumiere::{RenderContext, RenderSettings, Term, TermSet};

use super::options::SceneOptions;
use super::parsers::parse_pixel;
use super::{Failure, check_settings, check_sources, load_scene, worker_pool};

/// The arguments of `lumiere probe`.
#[derive(Args)]
pub struct ProbeArgs {
    /// A .gltf/.glb file, or a built-in scene: `cornell` (the default) or another `lumiere lessons` lists.
    scene: Option<String>,
    /// The pixel X,Y, from the top left as in the images: the integral is taken at the first hit p of the ray through its centre.
    #[arg(long, value_parser = parse_pixel)]
    pixel: (u32, u32),
    /// Write the integrand of the terms (`--terms`, L0 left out: it is no integral) over the hemisphere at p: a linear EXR of the equal-area disk (docs/hemisphere.md), or a PNG to look at (its mean shown as mid-grey).
    #[arg(long)]
    hemisphere: PathBuf,
    /// The map's side, in pixels.
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(8..=2048))]
    size: u32,
    /// Directions traced per pixel of the map (stratified).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=4096))]
    directions: u32,
    /// Samples of the render's estimator along the same ray, for its mean at p.
    #[arg(long, default_value_t = 4096, value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    samples: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    #[command(flatten)]
    options: SceneOptions,
}

/// The exposure a PNG of the map is shown with: the map's mean over the
/// disk as mid-grey.
fn png_exposure(map: &IntegrandMap) -> f32 {
    let disk_pixels = std::f32::consts::PI / 4.0 * map.values.len() as f32;
    let mean = map.values.iter().map(|&v| luminance(v)).sum::<f32>() / disk_pixels;
    if mean > 0.0 {
        (0.18 / mean).log2()
    } else {
        0.0
    }
}

/// The map for a PNG: outside the disk, where there are no directions, a
/// dark grey once exposed, so that the hemisphere's rim shows.
fn look_at(map: &IntegrandMap) -> Vec<glam::Vec3> {
    let outside = glam::Vec3::splat(0.04 * (-png_exposure(map)).exp2());
    let size = map.size;
    (0..size * size)
        .map(|i| {
            let centre = IntegrandMap::disk_point(size, i % size, i / size, Vec2::splat(0.5));
            if centre.length() > 1.0 {
                outside
            } else {
                map.values[i as usize]
            }
        })
        .collect()
}

/// Maps the integrand, writes it, prints the quadrature beside the estimator's mean.
pub fn run(args: &ProbeArgs) -> Result<(), Failure> {
    let Some(format) = ImageFormat::from_path(&args.hemisphere) else {
        return Err(Failure::usage_message(format_args!(
            "{}: unknown image format (the map must end in .exr, or .png for a look at it)",
            args.hemisphere.display()
        )));
    };
    let settings = args.options.settings();
    check_settings(&settings, settings.terms)?;
    let (x, y) = args.pixel;
    if x >= settings.width || y >= settings.height {
        return Err(Failure::usage_message(format_args!(
            "--pixel {x},{y} is outside the {}×{} image",
            settings.width, settings.height
        )));
    }
    let terms = settings.terms.with(Term::L0, false);
    if terms.is_empty() {
        return Err(Failure::usage_message(
            "L0 is the emission p sends, not an integral: --terms needs L1, L2 or L3+",
        ));
    }
    let name = args.scene.clone().unwrap_or_else(|| "cornell".into());
    let scene = load_scene(&name)?;
    check_sources(&settings, &scene, &name)?;
    let pool = worker_pool(args.threads)?;
    let (map, (mean, mean_error), p) = pool.install(|| {
        // every term: the map traces the terms arriving along each direction
        let all_terms = RenderSettings {
            terms: TermSet::ALL,
            ..settings.clone()
        };
        let context = RenderContext::new(scene, all_terms);
        let ray = context.camera.generate(x, y, Vec2::splat(0.5));
        let map = integrand_map(
            &context,
            &ray,
            terms,
            args.size,
            args.directions,
            settings.seed,
        );
        let pixel = y as u64 * settings.width as u64 + x as u64;
        let mean = estimator_mean(&context, &ray, terms, pixel, args.samples);
        let p = lumiere::analysis::hemisphere::ShadingPoint::seen(&context, &ray)
            .map(|p| (p.point.p, p.frame.z));
        (map, mean, p)
    });
    let map = map.map_err(|e: HemisphereError| {
        Failure::runtime(anyhow::anyhow!("{name}, pixel {x},{y}: {e}"))
    })?;
    let pixels = match format {
        ImageFormat::Exr => map.values.clone(),
        ImageFormat::Png => look_at(&map),
    };
    let display = match format {
        ImageFormat::Exr => DisplaySettings::default(),
        ImageFormat::Png => DisplaySettings {
            exposure: png_exposure(&map),
            ..DisplaySettings::default()
        },
    };
    save_image(&args.hemisphere, map.size, map.size, &pixels, display).map_err(Failure::runtime)?;
    let quadrature = map.quadrature();
    let (quadrature_y, mean_y) = (luminance(quadrature) as f64, luminance(mean) as f64);
    // a point light alone has no noise: float rounding is then the error
    let rounding = 1e-5 * quadrature_y.abs().max(mean_y.abs());
    let combined = (map.integral_standard_error.powi(2) + mean_error.powi(2))
        .sqrt()
        .max(rounding);
    let difference = quadrature_y - mean_y;
    let rgb = |v: glam::Vec3| format!("{:.6} {:.6} {:.6}", v.x, v.y, v.z);
    if let Some((point, normal)) = p {
        println!("point: {}", rgb(point));
        println!("normal: {}", rgb(normal));
    }
    println!("terms: {terms}");
    println!(
        "projection: equal-area disk (dω = 2 dx dy), the view from p out along its normal, the scene's up at the top"
    );
    println!("map: {}", args.hemisphere.display());
    println!("point lights: {}", map.diracs.len());
    println!(
        "point lights hidden: {}",
        map.diracs.iter().filter(|d| d.occluded).count()
    );
    println!("quadrature: {quadrature_y:.6}");
    println!("quadrature rgb: {}", rgb(quadrature));
    println!(
        "quadrature standard error: {:.6}",
        map.integral_standard_error
    );
    println!("estimator mean: {mean_y:.6}");
    println!("estimator mean rgb: {}", rgb(mean));
    println!("estimator standard error: {mean_error:.6}");
    println!(
        "z: {:.2}",
        if combined > 0.0 {
            difference / combined
        } else {
            0.0
        }
    );
    Ok(())
}
