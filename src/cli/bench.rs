//! `lumiere bench`: error against time, ray throughput and scaling, written
//! as CSV files and plots into a folder.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use lumiere::course::Choice;
use lumiere::course::{LightSampling, Sampler};
use lumiere::tools::bench::error_curve::{ErrorBench, Estimator};
use lumiere::tools::bench::peer::Peer;
use lumiere::tools::bench::run::{BenchConfig, run as run_sections};
use lumiere::tools::bench::scaling::ScalingBench;
use lumiere::tools::bench::{BenchError, Progress, Section};
use lumiere::{Film, RenderSettings};

use super::options::SceneOptions;
use super::parsers::IndirectSamples;
use super::{Failure, check_settings, worker_pool};

/// The arguments of `lumiere bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// A .gltf/.glb file, or a built-in scene: `cornell` (the default) or another `lumiere lessons` lists.
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

/// The bench's progress on a spinner (hidden if stderr is not a terminal).
struct Spinner(ProgressBar);

impl Spinner {
    /// A spinner with the elapsed time and the current step.
    fn new() -> Self {
        if !std::io::stderr().is_terminal() {
            return Self(ProgressBar::hidden());
        }
        let bar = ProgressBar::new_spinner();
        bar.enable_steady_tick(Duration::from_millis(200));
        bar.set_style(
            ProgressStyle::with_template("{spinner} {elapsed} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        Self(bar)
    }
}

impl Progress for Spinner {
    fn message(&self, text: &str) {
        self.0.set_message(text.to_string());
    }
}

/// The settings of the bench's renders: the scene options, 256×256 unless given.
fn bench_settings(args: &BenchArgs) -> RenderSettings {
    let mut settings = args.options.settings();
    settings.width = args.options.width.unwrap_or(256);
    settings.height = args.options.height.unwrap_or(256);
    settings
}

/// Every check of the bench's arguments: the settings, the sections, the
/// reference's sample count against the curves', the films of the resolution rows.
fn check(args: &BenchArgs, settings: &RenderSettings) -> Result<(), Failure> {
    check_settings(settings, settings.terms)?;
    if args.only.is_empty() {
        return Err(Failure::usage_message(
            "--only names no section (expected error, throughput or scaling)",
        ));
    }
    if args.reference.is_none() {
        let curve_ends = [
            ("--max-spp", Some(args.max_spp)),
            ("--extend-spp", args.extend_spp),
        ];
        for (option, spp) in curve_ends {
            if let Some(spp) = spp
                && args.reference_spp < spp
            {
                return Err(Failure::usage_message(format_args!(
                    "--reference-spp {} is below {option} {spp}: the reference must converge further than the curves",
                    args.reference_spp
                )));
            }
        }
    }
    for &size in &args.resolutions {
        Film::check_memory(size, size, settings.terms).map_err(Failure::usage)?;
    }
    Ok(())
}

/// The estimators of the error curves: each strategy with each sampler
/// (default: --light-sampling with all samplers), with one continuation and
/// with the pilot's choice unless --indirect-samples says which.
fn estimators(args: &BenchArgs, settings: &RenderSettings) -> Vec<Estimator> {
    let strategies = if args.strategies.is_empty() {
        vec![settings.light_sampling]
    } else {
        args.strategies.clone()
    };
    let samplers = if args.samplers.is_empty() {
        Sampler::all()
    } else {
        args.samplers.clone()
    };
    let pairs = Estimator::all_pairs(&strategies, &samplers, settings.adaptive);
    match args.options.indirect_samples {
        None => Estimator::with_auto_split(&pairs),
        Some(IndirectSamples::Auto) => pairs
            .into_iter()
            .map(|e| Estimator {
                auto_split: true,
                ..e
            })
            .collect(),
        Some(IndirectSamples::Count(_)) => pairs,
    }
}

/// The sections' configuration from the arguments.
fn config(args: &BenchArgs, settings: RenderSettings) -> BenchConfig {
    let extend_spp = args.extend_spp.unwrap_or_else(|| {
        args.max_spp
            .saturating_mul(8)
            .min(args.reference_spp / 2)
            .max(args.max_spp)
    });
    let mut triangle_counts: Vec<u64> = (4..9)
        .map(|k| 10u64.pow(k))
        .take_while(|&n| n < args.max_triangles)
        .collect();
    triangle_counts.push(args.max_triangles);
    BenchConfig {
        sections: args.only.clone(),
        error: ErrorBench {
            scene: args.scene.clone(),
            settings: settings.clone(),
            estimators: estimators(args, &settings),
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
    }
}

/// Runs the sections into the output folder and prints their summary.
pub fn run(args: &BenchArgs) -> Result<(), Failure> {
    let settings = bench_settings(args);
    check(args, &settings)?;
    let config = config(args, settings);
    let pool = worker_pool(args.threads)?;
    let spinner = Spinner::new();
    let report = pool.install(|| run_sections(&config, &args.output, &spinner));
    spinner.0.finish_and_clear();
    let report = report.map_err(|e| match e {
        BenchError::Invalid(_) => Failure::usage(e),
        e => Failure::runtime(e),
    })?;
    print!("{}", report.summary());
    Ok(())
}
