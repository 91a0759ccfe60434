//! The subcommands of the `lumiere` command line, one file each, and what
//! they share: the failure type and its exit codes, the checks of the render
//! settings, the worker pool, the progress bar and the summary line.

pub mod bench;
pub mod lesson;
pub mod lessons;
pub mod options;
pub mod parsers;
pub mod probe;
pub mod render;
pub mod serve;
pub mod stress;
pub mod strip;
pub mod view;

use std::io::IsTerminal;
use std::process::ExitCode;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::ThreadPool;

use lumiere::render::{Budget, RenderStats};
use lumiere::scene::{Scene, builtin};
use lumiere::{Film, RenderSettings, TermSet};

/// Exit code of a scene or image that cannot be loaded or written.
pub const EXIT_RUNTIME: u8 = 1;
/// Exit code of bad arguments (clap exits with it too).
pub const EXIT_USAGE: u8 = 2;

/// A failure and the exit code it maps to.
pub struct Failure {
    code: u8,
    error: anyhow::Error,
}

impl Failure {
    /// Bad arguments: exit code 2.
    pub fn usage(error: impl Into<anyhow::Error>) -> Self {
        Self {
            code: EXIT_USAGE,
            error: error.into(),
        }
    }

    /// Bad arguments described by a message: exit code 2.
    pub fn usage_message(message: impl std::fmt::Display) -> Self {
        Self::usage(anyhow::anyhow!("{message}"))
    }

    /// A scene or image that cannot be loaded or written: exit code 1.
    pub fn runtime(error: impl Into<anyhow::Error>) -> Self {
        Self {
            code: EXIT_RUNTIME,
            error: error.into(),
        }
    }

    /// Prints the error on stderr and returns its exit code.
    pub fn report(self) -> ExitCode {
        eprintln!("error: {:#}", self.error);
        ExitCode::from(self.code)
    }
}

/// The checks every render's settings pass: their own consistency, then
/// whether a film of their size holding `terms` fits in memory.
pub fn check_settings(settings: &RenderSettings, terms: TermSet) -> Result<(), Failure> {
    settings.validate().map_err(Failure::usage_message)?;
    Film::check_memory(settings.width, settings.height, terms).map_err(Failure::usage)
}

/// Checks that the sources `settings` give a quality name sources of
/// `scene`, loaded from `name`.
pub fn check_sources(settings: &RenderSettings, scene: &Scene, name: &str) -> Result<(), Failure> {
    lumiere::transport::sources::check(settings, scene)
        .map_err(|e| Failure::usage_message(format_args!("{name}: {e}")))
}

/// Loads a scene file or built-in scene by name, printing its warnings.
pub fn load_scene(name: &str) -> Result<Scene, Failure> {
    let scene = builtin::load(name).map_err(Failure::runtime)?;
    for warning in &scene.warnings {
        eprintln!("warning: {name}: {warning}");
    }
    Ok(scene)
}

/// A pool of `threads` workers (`None`: one per core).
pub fn worker_pool(threads: Option<u32>) -> Result<ThreadPool, Failure> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0) as usize)
        .build()
        .context("cannot start the worker threads")
        .map_err(Failure::runtime)
}

/// A bar over a render's budget (samples or milliseconds), if stderr is a terminal.
pub fn progress_bar(budget: Budget) -> ProgressBar {
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

/// Moves a [`progress_bar`] to a render's progress and shows its speed.
pub fn update_bar(bar: &ProgressBar, stats: &RenderStats, budget: Budget) {
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

/// A bar over all the passes of a strip (rows × the largest count), if stderr is a terminal.
pub fn strip_progress_bar(passes: u64) -> ProgressBar {
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

/// One line of a finished render's figures: samples, time, rays, speed, dropped samples.
pub fn summary(stats: &RenderStats) -> String {
    format!(
        "{} spp, {:.2} s, {} rays, {:.1} Mrays/s, {} invalid samples dropped",
        stats.samples_per_pixel,
        stats.elapsed.as_secs_f64(),
        stats.rays.total(),
        stats.mrays_per_second(),
        stats.rays.invalid_samples,
    )
}
