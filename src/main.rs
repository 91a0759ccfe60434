//! The `lumiere` command line.
//!
//! Exit codes: 0 success, 1 a scene or image could not be loaded or written,
//! 2 bad arguments.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use lumiere::export::{ImageFormat, save_image};
use lumiere::render::{Budget, RenderStats, render};
use lumiere::scene::builtin;
use lumiere::settings::{DisplaySettings, Tonemap};
use lumiere::{BrdfOverride, Film, LightMode, RenderContext, RenderSettings, TermSet};

#[derive(Parser)]
#[command(
    name = "lumiere",
    version,
    about = "A path tracer that teaches light transport, term by term"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an image (EXR: linear radiance; PNG: exposure, then sRGB).
    Render(RenderArgs),
}

#[derive(Args)]
struct RenderArgs {
    /// A .gltf/.glb file, or `cornell` (the built-in Cornell box).
    #[arg(default_value = "cornell")]
    scene: String,
    /// Output image; its extension picks the format (.exr or .png).
    #[arg(short, long)]
    output: PathBuf,
    #[arg(long, default_value_t = 640, value_parser = clap::value_parser!(u32).range(1..=16384))]
    width: u32,
    #[arg(long, default_value_t = 480, value_parser = clap::value_parser!(u32).range(1..=16384))]
    height: u32,
    /// Samples per pixel.
    #[arg(long, default_value_t = 64, conflicts_with = "time", value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    spp: u32,
    /// Render for this many seconds instead of a fixed sample count.
    #[arg(long, value_parser = parse_seconds)]
    time: Option<f64>,
    /// Lighting terms: L0 (emission), L1 (direct), L2 (one indirect bounce), L3+ (the rest); `all` = all four.
    #[arg(long, default_value = "L0,L1,L2")]
    terms: TermSet,
    /// Light sources: authored, point (area lights collapsed to points) or area (point lights made spheres).
    #[arg(long, default_value = "authored")]
    lights: LightMode,
    /// Radius in metres of the sphere lights of `--lights area` (default: 2% of the scene's diagonal).
    #[arg(long, value_parser = parse_positive)]
    light_radius: Option<f32>,
    /// Reflection model of every material: authored, lambert, phong or mirror.
    #[arg(long, default_value = "authored")]
    brdf: BrdfOverride,
    /// Phong exponent for `--brdf phong`.
    #[arg(long, default_value_t = 32.0, value_parser = parse_exponent)]
    phong_exponent: f32,
    /// Most reflections per path (caps L3+).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    max_bounces: u32,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Exposure in stops for the PNG (the EXR stays linear).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_exposure)]
    exposure: f32,
    /// Tonemap for the PNG: none (clamp), reinhard or aces.
    #[arg(long, default_value = "none")]
    tonemap: Tonemap,
}

fn parse_seconds(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("'{s}' is not a number of seconds"))?;
    if v.is_finite() && v > 0.0 && v <= 1e7 {
        Ok(v)
    } else {
        Err(format!(
            "{s} seconds is not a positive duration (at most 1e7)"
        ))
    }
}

fn parse_positive(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|_| format!("'{s}' is not a number"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{s} must be a positive number"))
    }
}

fn parse_exponent(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|_| format!("'{s}' is not a number"))?;
    if v.is_finite() && (0.0..=1e6).contains(&v) {
        Ok(v)
    } else {
        Err(format!("Phong exponent {s} must be within 0..=1e6"))
    }
}

fn parse_exposure(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .parse()
        .map_err(|_| format!("'{s}' is not a number of stops"))?;
    if v.is_finite() && (-64.0..=64.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("exposure {s} must be within -64..=64 stops"))
    }
}

impl RenderArgs {
    fn settings(&self) -> RenderSettings {
        RenderSettings {
            width: self.width,
            height: self.height,
            terms: self.terms,
            light_mode: self.lights,
            light_radius: self.light_radius,
            brdf: self.brdf,
            phong_exponent: self.phong_exponent,
            max_bounces: self.max_bounces,
            seed: self.seed,
            ..RenderSettings::default()
        }
    }

    fn budget(&self) -> Budget {
        match self.time {
            Some(seconds) => Budget::Time(Duration::from_secs_f64(seconds)),
            None => Budget::Samples(self.spp),
        }
    }
}

/// A failure and the exit code it maps to.
struct Failure {
    code: u8,
    error: anyhow::Error,
}

fn usage(error: anyhow::Error) -> Failure {
    Failure { code: 2, error }
}

fn runtime(error: anyhow::Error) -> Failure {
    Failure { code: 1, error }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => run_render(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("error: {:#}", failure.error);
            ExitCode::from(failure.code)
        }
    }
}

fn run_render(args: &RenderArgs) -> Result<(), Failure> {
    if ImageFormat::from_path(&args.output).is_none() {
        return Err(usage(anyhow::anyhow!(
            "{}: unknown image format (the output must end in .exr or .png)",
            args.output.display()
        )));
    }
    let settings = args.settings();
    settings.validate().map_err(|e| usage(anyhow::anyhow!(e)))?;
    check_memory(settings.width, settings.height).map_err(usage)?;
    let scene = builtin::load(&args.scene).map_err(|e| runtime(e.into()))?;
    for warning in &scene.warnings {
        eprintln!("warning: {}: {warning}", args.scene);
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0) as usize)
        .build()
        .context("cannot start the worker threads")
        .map_err(runtime)?;
    let (film, stats) = pool.install(|| {
        let context = RenderContext::new(scene, settings.clone());
        let mut film = Film::new(settings.width, settings.height);
        let bar = progress_bar(args.budget());
        let stats = render(&context, &mut film, args.budget(), |s| {
            update_bar(&bar, s, args.budget())
        });
        bar.finish_and_clear();
        (film, stats)
    });
    let pixels = film.radiance(settings.terms);
    save_image(
        &args.output,
        settings.width,
        settings.height,
        &pixels,
        DisplaySettings {
            exposure: args.exposure,
            tonemap: args.tonemap,
        },
    )
    .map_err(|e| runtime(e.into()))?;
    println!("{}", summary(&stats));
    Ok(())
}

/// Refuses images whose film would not fit comfortably in memory.
fn check_memory(width: u32, height: u32) -> anyhow::Result<()> {
    // per pixel: 4 terms × (Σ f64×3 + Welford f64×2) + one pass of f32×3×4
    let bytes_per_pixel = 4 * (24 + 16) + 48;
    let bytes = width as u64 * height as u64 * bytes_per_pixel;
    let limit = 8u64 << 30;
    if bytes > limit {
        anyhow::bail!(
            "a {width}×{height} image needs about {:.1} GiB of film; the limit is {} GiB",
            bytes as f64 / (1u64 << 30) as f64,
            limit >> 30
        );
    }
    Ok(())
}

fn progress_bar(budget: Budget) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let (length, template) = match budget {
        Budget::Samples(n) => (n as u64, "{bar:40} {pos}/{len} spp  {elapsed}  {msg}"),
        Budget::Time(t) => (t.as_millis() as u64, "{bar:40} {msg}"),
    };
    let bar = ProgressBar::new(length);
    bar.set_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

fn update_bar(bar: &ProgressBar, stats: &RenderStats, budget: Budget) {
    match budget {
        Budget::Samples(_) => bar.set_position(stats.samples_per_pixel as u64),
        Budget::Time(_) => bar.set_position(stats.elapsed.as_millis() as u64),
    }
    bar.set_message(format!(
        "{} spp, {:.1} Mrays/s",
        stats.samples_per_pixel,
        stats.mrays_per_second()
    ));
}

fn summary(stats: &RenderStats) -> String {
    format!(
        "{} spp, {:.2} s, {} rays, {:.1} Mrays/s",
        stats.samples_per_pixel,
        stats.elapsed.as_secs_f64(),
        stats.rays.total(),
        stats.mrays_per_second()
    )
}
