//! The `lumiere` command line: parses the arguments and runs the subcommand
//! (`src/cli/`, one file each).
//!
//! Exit codes: 0 success, 1 a scene or image could not be loaded or written,
//! 2 bad arguments.

mod cli;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use lumiere::tools::bench::memory::CountingAllocator;

use cli::bench::BenchArgs;
use cli::lesson::LessonArgs;
use cli::lessons::LessonsArgs;
use cli::probe::ProbeArgs;
use cli::render::RenderArgs;
use cli::serve::ServeArgs;
use cli::stress::StressArgs;
use cli::strip::StripArgs;
use cli::view::ViewArgs;

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
    /// List the built-in lessons (with their steps) and scenes.
    Lessons(LessonsArgs),
    /// Export a lesson as slides: each step rendered with its title, formula and caption (PNG, GIF with --gif), and an index.md.
    Lesson(LessonArgs),
    /// The integral at one pixel's first hit: its integrand over the hemisphere (EXR), the quadrature and the estimator's mean.
    Probe(ProbeArgs),
    /// Serve the web build's folder (`bash .ci/build-web OUT`) on 127.0.0.1, with the headers its threads need.
    Serve(ServeArgs),
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Some(Command::Render(args)) => cli::render::run(&args),
        Some(Command::View(args)) => cli::view::run(args, false),
        Some(Command::Strip(args)) => cli::strip::run(&args),
        Some(Command::Stress(args)) => cli::stress::run(&args),
        Some(Command::Bench(args)) => cli::bench::run(&args),
        Some(Command::Lessons(args)) => cli::lessons::run(&args),
        Some(Command::Lesson(args)) => cli::lesson::run(&args),
        Some(Command::Probe(args)) => cli::probe::run(&args),
        Some(Command::Serve(args)) => cli::serve::run(&args),
        None => cli::view::run(ViewArgs::defaults(), true),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => failure.report(),
    }
}
