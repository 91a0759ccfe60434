//! The `lumiere` command line.
//!
//! Exit codes: 0 success, 1 a scene or image could not be loaded or written,
//! 2 bad arguments.

use std::io::IsTerminal;
use std::ops::{Bound, RangeBounds};
use std::path::PathBuf;
use std::process::ExitCode;
use std::str::FromStr;
use std::time::Duration;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use lumiere::analysis::noise::DisplayMode;
use lumiere::analysis::path_view::PathSample;
use lumiere::render::export::{ImageFormat, save_image};
use lumiere::render::settings::{
    Adaptive, DisplaySettings, IndirectSampling, Integrator, LightSampling, LightSelection,
    MAX_SAMPLES_PER_VERTEX, MisHeuristic, Sampler, Tonemap,
};
use lumiere::render::sidecar::Sidecar;
use lumiere::render::{Budget, RenderStats, render};
use lumiere::scene::Camera;
use lumiere::scene::builtin;
use lumiere::tools::bench::error_curve::{ErrorBench, Estimator};
use lumiere::tools::bench::memory::CountingAllocator;
use lumiere::tools::bench::peer::Peer;
use lumiere::tools::bench::run::{BenchConfig, run as run_bench_sections};
use lumiere::tools::bench::scaling::ScalingBench;
use lumiere::tools::bench::{Progress, Section};
use lumiere::tools::strip::{
    RowSweep, SampleCounts, StripImage, StripLayout, StripRow, render_strip,
};
use lumiere::transport::splitting::choose_continuations;
use lumiere::{BrdfOverride, Film, LightMode, RenderContext, RenderSettings, TermSet};

/// Counts heap bytes for `lumiere bench`'s memory figures (two relaxed atomics per allocation).
#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

#[derive(Parser)]
#[command(
    name = "lumiere",
    version,
    about = "A path tracer that teaches light transport, term by term",
    long_about = "A path tracer that teaches light transport, term by term.\nWithout a command, opens the viewer on the built-in Cornell box."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an image (EXR: linear radiance; PNG: exposure, tonemap, then sRGB).
    Render(RenderArgs),
    /// Open the interactive viewer.
    View(ViewArgs),
    /// One progressive render shown at several sample counts, side by side and labelled (PNG).
    Strip(StripArgs),
    /// The numerical stress suite: scenes that break naive tracers, with a table of invalid samples, leaks and energy errors.
    Stress(StressArgs),
    /// Measure error against time, ray throughput and scaling; write CSVs and plots into a folder.
    Bench(BenchArgs),
}

#[derive(Args)]
struct BenchArgs {
    /// A .gltf/.glb file, or `cornell` (the built-in Cornell box, the default).
    #[arg(default_value = "cornell")]
    scene: String,
    /// Folder of the CSV files, plots and cached reference.
    #[arg(short, long, default_value = "bench-out")]
    output: PathBuf,
    /// Sections to run: error, throughput, scaling (comma-separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "error,throughput,scaling"
    )]
    only: Vec<Section>,
    /// Error curves: the last sample count (the counts are 1, 2, 4, … up to it).
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    max_spp: u32,
    /// Error curves: a curve still above relMSE 1e-3 at --max-spp doubles its samples up to this
    /// many, the peer's too (default: 8 × --max-spp, at most half of --reference-spp).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    extend_spp: Option<u32>,
    /// Error curves: samples per pixel of the reference (rendered once, cached in the output folder).
    #[arg(long, default_value_t = 4096, value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    reference_spp: u32,
    /// Error curves: a linear EXR of the same size to measure against, instead of rendering one.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Error curves: direct-lighting strategies, one curve each (default: --light-sampling).
    #[arg(long, value_delimiter = ',')]
    strategies: Vec<LightSampling>,
    /// Error curves: samplers, one curve per strategy and sampler (default: all three).
    #[arg(long, value_delimiter = ',')]
    samplers: Vec<Sampler>,
    /// Error curves: also run this renderer's script (mitsuba: tests/reference/mitsuba_bench.py).
    #[arg(long)]
    peer: Option<Peer>,
    /// Error curves: merge a peer's rows (renderer,estimator,spp,seconds,rmse,relmse); repeatable.
    #[arg(long)]
    peer_csv: Vec<PathBuf>,
    /// Throughput: passes (samples per pixel) rendered and replayed.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=4096))]
    throughput_passes: u32,
    /// Throughput and the scaling section's triangle rows: timed runs of each measure; the fastest counts.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    repeats: u32,
    /// Scaling: the largest procedural scene (the counts are 10⁴, 10⁵, … up to it).
    #[arg(long, default_value_t = 1_000_000, value_parser = clap::value_parser!(u64).range(10..=20_000_000))]
    max_triangles: u64,
    /// Scaling: triangles of the glTF file written and loaded (0: none).
    #[arg(long, default_value_t = 1_000_000, value_parser = clap::value_parser!(u64).range(0..=20_000_000))]
    gltf_triangles: u64,
    /// Scaling: square image sizes of the resolution rows.
    #[arg(long, value_delimiter = ',', default_value = "128,256,512", value_parser = clap::value_parser!(u32).range(1..=8192))]
    resolutions: Vec<u32>,
    /// Scaling: worker thread counts of the thread rows.
    #[arg(long, value_delimiter = ',', default_value = "1,2", value_parser = clap::value_parser!(u32).range(1..=1024))]
    thread_counts: Vec<u32>,
    /// Scaling: samples per pixel of each timed render.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    scaling_spp: u32,
    /// Worker threads of every section but the thread rows (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    #[command(flatten)]
    options: SceneOptions,
}

/// What decides the radiance and its display: shared by `render`, `view` and `strip`.
#[derive(Args, Clone)]
struct SceneOptions {
    /// Image width [default: 640; bench: 256].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    width: Option<u32>,
    /// Image height [default: 480; bench: 256].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    height: Option<u32>,
    /// Lighting terms: L0 (emission), L1 (direct), L2 (one indirect bounce), L3+ (the rest); `all` = all four.
    #[arg(long, default_value = "L0,L1,L2")]
    terms: TermSet,
    /// Light sources: authored, point (area lights collapsed to points) or area (point lights made spheres).
    #[arg(long, default_value = "authored")]
    lights: LightMode,
    /// Radius in metres of the sphere lights of `--lights area` (default: 2% of the scene's diagonal).
    #[arg(long, value_parser = parse_light_radius)]
    light_radius: Option<f32>,
    /// Reflection model of every material: authored, lambert, phong or mirror.
    #[arg(long, default_value = "authored")]
    brdf: BrdfOverride,
    /// Phong exponent for `--brdf phong`.
    #[arg(long, default_value_t = 32.0, value_parser = parse_phong_exponent)]
    phong_exponent: f32,
    /// Most reflections per path (caps L3+).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    max_bounces: u32,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// The estimator: lecture (the course's L0 + L1 + L2 as the slides write it, `transport/lecture.rs`) or fast (the path tracer with the options below).
    #[arg(long, default_value = "fast")]
    integrator: Integrator,
    /// Direct lighting from extended lights: area, solid-angle, brdf, hemisphere or mis (light + BRDF).
    #[arg(long, default_value = "mis")]
    light_sampling: LightSampling,
    /// Weights of `--light-sampling mis`: balance or power.
    #[arg(long, default_value = "power")]
    mis_heuristic: MisHeuristic,
    /// Directions of the next reflection (L2, L3+): uniform, cosine or brdf.
    #[arg(long, default_value = "brdf")]
    indirect_sampling: IndirectSampling,
    /// Light samples (shadow rays or gathered directions) per vertex.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=MAX_SAMPLES_PER_VERTEX as i64))]
    light_samples: u32,
    /// Continuations per first hit (splitting), each weighted 1/M; `auto`: the count that reaches a given relMSE soonest, chosen by a pilot [default: 1; bench: 1 and auto]
    #[arg(long, value_parser = parse_indirect_samples)]
    indirect_samples: Option<IndirectSamples>,
    /// How a light is picked: uniform or power.
    #[arg(long, default_value = "power")]
    light_selection: LightSelection,
    /// Random numbers: independent, stratified (jittered) or sobol (Owen-scrambled).
    #[arg(long, default_value = "independent")]
    sampler: Sampler,
    /// Adaptive sampling: stop sampling a pixel's term once its standard error is below this fraction of the pixel's value (e.g. 0.01; default: off, every pixel gets every sample)
    #[arg(long, value_parser = parse_adaptive_threshold)]
    adaptive: Option<f32>,
    /// Adaptive sampling: samples every pixel gets before its error is judged.
    #[arg(long, default_value_t = Adaptive::default().min_samples, requires = "adaptive", value_parser = clap::value_parser!(u32).range(Adaptive::MIN_SAMPLES as i64..=1_000_000))]
    adaptive_min_spp: u32,
    /// Exposure in stops (PNG and display; the EXR stays linear).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_exposure)]
    exposure: f32,
    /// Tonemap (PNG and display): none (clamp), reinhard or aces.
    #[arg(long, default_value = "none")]
    tonemap: Tonemap,
}

#[derive(Args)]
struct RenderArgs {
    /// A .gltf/.glb file, or `cornell` (the built-in Cornell box, the default).
    scene: Option<String>,
    /// Output image; its extension picks the format (.exr or .png).
    #[arg(short, long)]
    output: PathBuf,
    /// Samples per pixel (default 64, or the sidecar's).
    #[arg(long, conflicts_with = "time", value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    spp: Option<u32>,
    /// Render for this many seconds instead of a fixed sample count.
    #[arg(long, value_parser = parse_seconds)]
    time: Option<f64>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// A screenshot's JSON sidecar: its scene, camera, settings and spp replace the options above.
    #[arg(long)]
    settings: Option<PathBuf>,
    #[command(flatten)]
    options: SceneOptions,
}

#[derive(Args)]
struct StressArgs {
    /// The test suite's sizes (seconds) instead of the full figures (10^6 rays and samples).
    #[arg(long)]
    quick: bool,
    /// Run only these cases (comma-separated; default: all).
    #[arg(long, value_delimiter = ',')]
    only: Vec<lumiere::tools::stress::Case>,
}

#[derive(Args)]
struct StripArgs {
    /// A .gltf/.glb file, or `cornell` (the built-in Cornell box, the default).
    #[arg(default_value = "cornell")]
    scene: String,
    /// Output image: a .png (labels are display pixels; no EXR).
    #[arg(short, long)]
    output: PathBuf,
    /// Samples per pixel of the tiles, increasing: one render, snapshotted at each count.
    #[arg(long, default_value = "1,4,16,64,256")]
    spp: SampleCounts,
    /// One row per value of an option, e.g. light-sampling=area,solid-angle,mis
    /// (terms are joined by '+': terms=L1,L2,L1+L2).
    #[arg(long)]
    rows: Option<RowSweep>,
    /// Width of each tile (the same as --width).
    #[arg(long, conflicts_with = "width", value_parser = clap::value_parser!(u32).range(1..=16384))]
    tile_width: Option<u32>,
    /// Height of each tile (the same as --height).
    #[arg(long, conflicts_with = "height", value_parser = clap::value_parser!(u32).range(1..=16384))]
    tile_height: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    #[command(flatten)]
    options: SceneOptions,
}

#[derive(Parser)]
struct ViewArgs {
    /// A .gltf/.glb file, or `cornell` (the built-in Cornell box, the default).
    #[arg(default_value = "cornell")]
    scene: String,
    /// Render to this many samples per pixel, then exit (saving --screenshot first).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    exit_after_spp: Option<u32>,
    /// With --exit-after-spp: a PNG of the whole window, taken by the viewer.
    #[arg(long, requires = "exit_after_spp")]
    screenshot: Option<PathBuf>,
    /// Measure the time from a toggle to the preview on screen and the UI frame time, print them, exit.
    #[arg(long, conflicts_with_all = ["exit_after_spp", "screenshot"])]
    bench: bool,
    /// A linear EXR of the starting view (same size): RMSE and relMSE are measured against it.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Open the convergence plot (error against spp and seconds).
    #[arg(long)]
    convergence_plot: bool,
    /// Compare, for equal time, with a second estimator using this light sampling.
    #[arg(long)]
    compare_light_sampling: Option<LightSampling>,
    /// The second estimator's indirect sampling (default: the first's).
    #[arg(long)]
    compare_indirect_sampling: Option<IndirectSampling>,
    /// The second estimator's sampler (default: the first's).
    #[arg(long)]
    compare_sampler: Option<Sampler>,
    /// What the image shows: image, standard-error, relative-error or sample-count.
    #[arg(long, default_value = "image")]
    display_mode: DisplayMode,
    /// Probe the pixel at X,Y (from the top left) from the start.
    #[arg(long, value_parser = parse_pixel)]
    probe: Option<(u32, u32)>,
    /// Which of the probed pixel's samples the path view draws: a number from 1, or `brightest`.
    #[arg(long, default_value = "1", requires = "probe")]
    probe_sample: PathSample,
    #[command(flatten)]
    options: SceneOptions,
}

/// `--indirect-samples`: a count, or `auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum IndirectSamples {
    Count(u32),
    Auto,
}

/// `--indirect-samples`: `auto` or a count within 1..=MAX_SAMPLES_PER_VERTEX.
fn parse_indirect_samples(s: &str) -> Result<IndirectSamples, String> {
    if s.eq_ignore_ascii_case("auto") {
        return Ok(IndirectSamples::Auto);
    }
    match s.parse::<u32>() {
        Ok(m) if (1..=MAX_SAMPLES_PER_VERTEX).contains(&m) => Ok(IndirectSamples::Count(m)),
        _ => Err(format!(
            "expected `auto` or a count within 1..={MAX_SAMPLES_PER_VERTEX}"
        )),
    }
}

/// `--probe`: a pixel `X,Y` from the top left.
fn parse_pixel(s: &str) -> Result<(u32, u32), String> {
    let parsed = s
        .split_once(',')
        .and_then(|(x, y)| Some((x.trim().parse().ok()?, y.trim().parse().ok()?)));
    parsed.ok_or_else(|| format!("'{s}' is not a pixel X,Y"))
}

/// Parses a finite number within `range`; `what` names the value (and its
/// unit) in the messages, e.g. "exposure in stops must be within -64..=64, not 99".
/// A number too large for `T` parses as infinite and is refused as not finite.
fn parse_in_range<T>(s: &str, range: impl RangeBounds<f64>, what: &str) -> Result<T, String>
where
    T: FromStr + Into<f64> + Copy,
{
    let value: T = s
        .parse()
        .map_err(|_| format!("{what} must be a number, not '{s}'"))?;
    let wide: f64 = value.into();
    if !wide.is_finite() {
        Err(format!(
            "{what} must be a finite number {}, not {s}",
            describe(&range)
        ))
    } else if !range.contains(&wide) {
        Err(format!("{what} must be {}, not {s}", describe(&range)))
    } else {
        Ok(value)
    }
}

/// A range in words: "within 0..=1e6", "greater than 0", "greater than 0 and at most 1".
fn describe(range: &impl RangeBounds<f64>) -> String {
    if let (Bound::Included(&low), Bound::Included(&high)) =
        (range.start_bound(), range.end_bound())
    {
        return format!("within {}..={}", number(low), number(high));
    }
    let low = match range.start_bound() {
        Bound::Included(&v) => Some(format!("at least {}", number(v))),
        Bound::Excluded(&v) => Some(format!("greater than {}", number(v))),
        Bound::Unbounded => None,
    };
    let high = match range.end_bound() {
        Bound::Included(&v) => Some(format!("at most {}", number(v))),
        Bound::Excluded(&v) => Some(format!("less than {}", number(v))),
        Bound::Unbounded => None,
    };
    match (low, high) {
        (Some(low), Some(high)) => format!("{low} and {high}"),
        (Some(bound), None) | (None, Some(bound)) => bound,
        (None, None) => "of any size".to_string(),
    }
}

/// A bound as written in the help: 64, 0.5, 1e6.
fn number(v: f64) -> String {
    if v.abs() >= 1e5 {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// `--light-radius`: metres, positive.
fn parse_light_radius(s: &str) -> Result<f32, String> {
    parse_in_range(
        s,
        (Bound::Excluded(0.0), Bound::Unbounded),
        "light radius in metres",
    )
}

/// `--phong-exponent`: within 0..=1e6.
fn parse_phong_exponent(s: &str) -> Result<f32, String> {
    parse_in_range(s, 0.0..=1e6, "Phong exponent")
}

/// `--adaptive`: a fraction of the pixel's value, within (0, 1].
fn parse_adaptive_threshold(s: &str) -> Result<f32, String> {
    parse_in_range(
        s,
        (Bound::Excluded(0.0), Bound::Included(1.0)),
        "adaptive threshold",
    )
    .map_err(|e| format!("{e} (a fraction: 0.01 stops at 1% standard error)"))
}

/// `--exposure`: stops, within -64..=64.
fn parse_exposure(s: &str) -> Result<f32, String> {
    parse_in_range(s, -64.0..=64.0, "exposure in stops")
}

/// `--time`: seconds, positive and at most 1e7.
fn parse_seconds(s: &str) -> Result<f64, String> {
    parse_in_range(
        s,
        (Bound::Excluded(0.0), Bound::Included(1e7)),
        "render time in seconds",
    )
}

impl SceneOptions {
    fn settings(&self) -> RenderSettings {
        RenderSettings {
            width: self.width.unwrap_or(640),
            height: self.height.unwrap_or(480),
            terms: self.terms,
            light_mode: self.lights,
            light_radius: self.light_radius,
            brdf: self.brdf,
            phong_exponent: self.phong_exponent,
            max_bounces: self.max_bounces,
            seed: self.seed,
            integrator: self.integrator,
            light_sampling: self.light_sampling,
            mis_heuristic: self.mis_heuristic,
            indirect_sampling: self.indirect_sampling,
            light_samples: self.light_samples,
            indirect_samples: match self.indirect_samples {
                Some(IndirectSamples::Count(m)) => m,
                _ => 1,
            },
            auto_indirect_samples: self.indirect_samples == Some(IndirectSamples::Auto),
            light_selection: self.light_selection,
            sampler: self.sampler,
            adaptive: self.adaptive.map(|threshold| Adaptive {
                threshold,
                min_samples: self.adaptive_min_spp,
            }),
            ..RenderSettings::default()
        }
    }

    fn display(&self) -> DisplaySettings {
        DisplaySettings {
            exposure: self.exposure,
            tonemap: self.tonemap,
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
        Some(Command::Render(args)) => run_render(&args),
        Some(Command::View(args)) => run_view(args, false),
        Some(Command::Strip(args)) => run_strip(&args),
        Some(Command::Stress(args)) => run_stress(&args),
        Some(Command::Bench(args)) => run_bench(&args),
        None => run_view(ViewArgs::parse_from(["view"]), true),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("error: {:#}", failure.error);
            ExitCode::from(failure.code)
        }
    }
}

/// What a render does, from the options or from a sidecar.
struct RenderJob {
    scene: String,
    camera: Option<Camera>,
    settings: RenderSettings,
    display: DisplaySettings,
    budget: Budget,
}

impl RenderJob {
    fn from_args(args: &RenderArgs) -> Result<Self, Failure> {
        let time_budget = args.time.map(|s| Budget::Time(Duration::from_secs_f64(s)));
        let Some(path) = &args.settings else {
            return Ok(Self {
                scene: args.scene.clone().unwrap_or_else(|| "cornell".into()),
                camera: None,
                settings: args.options.settings(),
                display: args.options.display(),
                budget: time_budget.unwrap_or(Budget::Samples(args.spp.unwrap_or(64))),
            });
        };
        let sidecar = Sidecar::load(path).map_err(|e| runtime(e.into()))?;
        let spp = args.spp.unwrap_or(sidecar.samples_per_pixel.max(1));
        Ok(Self {
            scene: args.scene.clone().unwrap_or(sidecar.scene),
            camera: Some(sidecar.camera),
            settings: sidecar.settings,
            display: sidecar.display,
            budget: time_budget.unwrap_or(Budget::Samples(spp)),
        })
    }
}

fn run_render(args: &RenderArgs) -> Result<(), Failure> {
    if ImageFormat::from_path(&args.output).is_none() {
        return Err(usage(anyhow::anyhow!(
            "{}: unknown image format (the output must end in .exr or .png)",
            args.output.display()
        )));
    }
    let job = RenderJob::from_args(args)?;
    let settings = job.settings.clone();
    settings.validate().map_err(|e| usage(anyhow::anyhow!(e)))?;
    Film::check_memory(settings.width, settings.height, settings.terms)
        .map_err(|e| usage(e.into()))?;
    let scene = builtin::load(&job.scene).map_err(|e| runtime(e.into()))?;
    for warning in &scene.warnings {
        eprintln!("warning: {}: {warning}", job.scene);
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0) as usize)
        .build()
        .context("cannot start the worker threads")
        .map_err(runtime)?;
    let (film, stats, continuations) = pool.install(|| {
        let mut context = RenderContext::with_camera(scene, settings.clone(), job.camera.as_ref());
        choose_continuations(&mut context);
        let mut film = Film::new(settings.width, settings.height);
        let bar = progress_bar(job.budget);
        let stats = render(&context, &mut film, job.budget, |s| {
            update_bar(&bar, s, job.budget)
        });
        bar.finish_and_clear();
        (film, stats, context.continuations.clone())
    });
    let pixels = film.radiance(settings.terms);
    save_image(
        &args.output,
        settings.width,
        settings.height,
        &pixels,
        job.display,
    )
    .map_err(|e| runtime(e.into()))?;
    println!("{}", summary(&stats));
    if settings.adaptive.is_some() {
        let traced = stats.rays.camera as f64 / film.pixel_count() as f64;
        println!(
            "adaptive: {traced:.1} samples traced per pixel on average, of {} passes",
            stats.samples_per_pixel
        );
    }
    if settings.auto_indirect_samples {
        println!("{}", describe_continuations(&continuations));
    }
    println!("skipped: {}", stats.rays.skipped.describe());
    Ok(())
}

fn run_stress(args: &StressArgs) -> Result<(), Failure> {
    use lumiere::tools::stress::{Case, Effort, table};
    let effort = if args.quick {
        Effort::Quick
    } else {
        Effort::Full
    };
    let cases: Vec<Case> = if args.only.is_empty() {
        Case::ALL.to_vec()
    } else {
        args.only.clone()
    };
    let bar = ProgressBar::new(cases.len() as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").expect("a valid template"),
    );
    let mut reports = Vec::new();
    for case in cases {
        bar.set_message(format!("{case}: {}", case.description()));
        reports.push(case.run(effort));
        bar.inc(1);
    }
    bar.finish_and_clear();
    print!("{}", table(&reports));
    let failed = reports.iter().filter(|r| !r.passed()).count();
    if failed > 0 {
        return Err(runtime(anyhow::anyhow!(
            "{failed} of {} stress cases failed",
            reports.len()
        )));
    }
    println!("all {} cases passed", reports.len());
    Ok(())
}

fn run_strip(args: &StripArgs) -> Result<(), Failure> {
    if ImageFormat::from_path(&args.output) != Some(ImageFormat::Png) {
        return Err(usage(anyhow::anyhow!(
            "{}: a strip is written as PNG only (its labels are display pixels); the output must end in .png",
            args.output.display()
        )));
    }
    let mut base = args.options.settings();
    base.width = args.tile_width.unwrap_or(base.width);
    base.height = args.tile_height.unwrap_or(base.height);
    let rows = match &args.rows {
        Some(sweep) => sweep.rows(&base),
        None => vec![StripRow {
            label: None,
            settings: base.clone(),
        }],
    };
    for row in &rows {
        row.settings
            .validate()
            .map_err(|e| usage(anyhow::anyhow!(e)))?;
    }
    for row in &rows {
        Film::check_memory(base.width, base.height, row.settings.terms)
            .map_err(|e| usage(e.into()))?;
    }
    let row_labels = rows.iter().filter_map(|r| r.label.clone()).collect();
    let layout = StripLayout::new(base.width, base.height, args.spp.labels(), row_labels);
    layout.check_size().map_err(|e| usage(anyhow::anyhow!(e)))?;
    let scene = builtin::load(&args.scene).map_err(|e| runtime(e.into()))?;
    for warning in &scene.warnings {
        eprintln!("warning: {}: {warning}", args.scene);
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0) as usize)
        .build()
        .context("cannot start the worker threads")
        .map_err(runtime)?;
    let mut image = StripImage::new(layout);
    let bar = strip_progress_bar(args.spp.max() as u64 * rows.len() as u64);
    let row_name = |r: usize| match (&args.rows, &rows[r].label) {
        (Some(sweep), Some(label)) => format!("{}={label}: ", sweep.option),
        _ => String::new(),
    };
    pool.install(|| {
        render_strip(
            scene.into(),
            &rows,
            &args.spp,
            args.options.display(),
            &mut image,
            |r, stats| {
                bar.set_position(r as u64 * args.spp.max() as u64 + stats.samples_per_pixel as u64);
                bar.set_message(row_name(r));
            },
            |r, stats| bar.suspend(|| println!("{}{}", row_name(r), summary(stats))),
        )
    });
    bar.finish_and_clear();
    image
        .save_png(&args.output)
        .map_err(|e| runtime(e.into()))?;
    Ok(())
}

/// The bench's progress on a spinner (hidden if stderr is not a terminal).
struct Spinner(ProgressBar);

impl Progress for Spinner {
    fn message(&self, text: &str) {
        self.0.set_message(text.to_string());
    }
}

fn run_bench(args: &BenchArgs) -> Result<(), Failure> {
    let mut settings = args.options.settings();
    settings.width = args.options.width.unwrap_or(256);
    settings.height = args.options.height.unwrap_or(256);
    settings.validate().map_err(|e| usage(anyhow::anyhow!(e)))?;
    Film::check_memory(settings.width, settings.height, settings.terms)
        .map_err(|e| usage(e.into()))?;
    if args.only.is_empty() {
        return Err(usage(anyhow::anyhow!(
            "--only names no section (expected error, throughput or scaling)"
        )));
    }
    if args.reference.is_none() && args.reference_spp < args.max_spp {
        return Err(usage(anyhow::anyhow!(
            "--reference-spp {} is below --max-spp {}: the reference must converge further than the curves",
            args.reference_spp,
            args.max_spp
        )));
    }
    if let Some(extend) = args.extend_spp
        && args.reference.is_none()
        && args.reference_spp < extend
    {
        return Err(usage(anyhow::anyhow!(
            "--reference-spp {} is below --extend-spp {extend}: the reference must converge further than the curves",
            args.reference_spp
        )));
    }
    let extend_spp = args.extend_spp.unwrap_or_else(|| {
        args.max_spp
            .saturating_mul(8)
            .min(args.reference_spp / 2)
            .max(args.max_spp)
    });
    for &size in &args.resolutions {
        Film::check_memory(size, size, settings.terms).map_err(|e| usage(e.into()))?;
    }
    let strategies = if args.strategies.is_empty() {
        vec![settings.light_sampling]
    } else {
        args.strategies.clone()
    };
    // the samplers are what the error curves compare first: all of them unless asked
    let samplers = if args.samplers.is_empty() {
        Sampler::ALL.to_vec()
    } else {
        args.samplers.clone()
    };
    let pairs = Estimator::all_pairs(&strategies, &samplers, settings.adaptive);
    // each curve with one continuation, then with the pilot's choice, unless asked
    let estimators = match args.options.indirect_samples {
        None => Estimator::with_auto_split(&pairs),
        Some(IndirectSamples::Auto) => pairs
            .into_iter()
            .map(|e| Estimator {
                auto_split: true,
                ..e
            })
            .collect(),
        Some(IndirectSamples::Count(_)) => pairs,
    };
    let mut triangle_counts: Vec<u64> = (4..9)
        .map(|k| 10u64.pow(k))
        .take_while(|&n| n < args.max_triangles)
        .collect();
    triangle_counts.push(args.max_triangles);
    let config = BenchConfig {
        sections: args.only.clone(),
        error: ErrorBench {
            scene: args.scene.clone(),
            settings: settings.clone(),
            estimators,
            max_spp: args.max_spp,
            extend_spp,
            reference_spp: args.reference_spp,
            reference: args.reference.clone(),
        },
        peer: args.peer,
        peer_csvs: args.peer_csv.clone(),
        throughput_passes: args.throughput_passes,
        throughput_repeats: args.repeats,
        scaling: ScalingBench {
            triangle_counts,
            gltf_triangles: args.gltf_triangles,
            resolutions: args.resolutions.clone(),
            thread_counts: args.thread_counts.iter().map(|&n| n as usize).collect(),
            triangle_image_size: 128,
            spp: args.scaling_spp,
            repeats: args.repeats,
            settings,
        },
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0) as usize)
        .build()
        .context("cannot start the worker threads")
        .map_err(runtime)?;
    let spinner = Spinner(if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new_spinner();
        bar.enable_steady_tick(Duration::from_millis(200));
        bar.set_style(
            ProgressStyle::with_template("{spinner} {elapsed} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar
    } else {
        ProgressBar::hidden()
    });
    let report = pool.install(|| run_bench_sections(&config, &args.output, &spinner));
    spinner.0.finish_and_clear();
    let report = report.map_err(|e| match e {
        lumiere::tools::bench::BenchError::Invalid(_) => usage(e.into()),
        e => runtime(e.into()),
    })?;
    print!("{}", report.summary());
    Ok(())
}

#[cfg(feature = "gui")]
fn run_view(args: ViewArgs, restore: bool) -> Result<(), Failure> {
    let settings = args.options.settings();
    settings.validate().map_err(|e| usage(anyhow::anyhow!(e)))?;
    // the viewer can switch every term on
    Film::check_memory(settings.width, settings.height, TermSet::ALL)
        .map_err(|e| usage(e.into()))?;
    let comparing = args.compare_light_sampling.is_some()
        || args.compare_indirect_sampling.is_some()
        || args.compare_sampler.is_some();
    let compare = comparing.then(|| {
        let mut estimator = lumiere::analysis::convergence::EstimatorKey::of(&settings);
        estimator.light_sampling = args
            .compare_light_sampling
            .unwrap_or(estimator.light_sampling);
        estimator.indirect_sampling = args
            .compare_indirect_sampling
            .unwrap_or(estimator.indirect_sampling);
        estimator.sampler = args.compare_sampler.unwrap_or(estimator.sampler);
        estimator
    });
    let options = lumiere::app::ViewOptions {
        scene: args.scene,
        settings,
        display: args.options.display(),
        exit_after_spp: args.exit_after_spp,
        screenshot: args.screenshot,
        restore,
        bench: args.bench,
        reference: args.reference,
        compare,
        convergence_plot: args.convergence_plot,
        display_mode: args.display_mode,
        probe: args.probe,
        probe_sample: args.probe_sample,
    };
    lumiere::app::run(options).map_err(|e| runtime(anyhow::anyhow!(e)))
}

#[cfg(not(feature = "gui"))]
fn run_view(_args: ViewArgs, _restore: bool) -> Result<(), Failure> {
    Err(usage(anyhow::anyhow!(
        "this lumiere was built without the viewer (the `gui` feature); use `lumiere render`"
    )))
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

/// A bar over all the passes of a strip (rows × the largest count), if stderr is a terminal.
fn strip_progress_bar(passes: u64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(passes);
    bar.set_style(
        ProgressStyle::with_template("{msg}{bar:40} {pos}/{len} passes  {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
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

/// What `--indirect-samples auto` chose: one count, or the range of the
/// regions' counts and their mean over the image.
fn describe_continuations(
    continuations: &lumiere::transport::continuations::Continuations,
) -> String {
    match continuations.map {
        None => format!(
            "indirect samples: {} per first hit (auto)",
            continuations.count
        ),
        Some(ref map) => format!(
            "indirect samples: {} per first hit (auto), by region over {}×{} regions, {:.2} on average",
            continuations.label(),
            map.columns,
            map.rows,
            continuations.mean()
        ),
    }
}

fn summary(stats: &RenderStats) -> String {
    format!(
        "{} spp, {:.2} s, {} rays, {:.1} Mrays/s, {} invalid samples dropped",
        stats.samples_per_pixel,
        stats.elapsed.as_secs_f64(),
        stats.rays.total(),
        stats.mrays_per_second(),
        stats.rays.invalid_samples,
    )
}
