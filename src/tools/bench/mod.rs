//! `lumiere bench`: how fast the renderer converges, how fast it traces, how it scales.
//!
//! Three sections, each writing a CSV (and a PNG plot) into one folder:
//!
//! * [`error_curve`] — error against time: relMSE and RMSE of renders of
//!   N = 1, 2, 4, … samples per pixel against a high-spp reference, one curve
//!   per estimator; the figure of merit is the time to reach relMSE ≤ 10⁻²
//!   and ≤ 10⁻³ (log-log interpolation). Rows from a peer renderer
//!   (`renderer,estimator,spp,seconds,rmse,relmse`) join the same plot.
//! * [`throughput`] — rays per second of the full renderer against a replay
//!   of exactly the rays it traced through the BVH alone: the ratio says how
//!   much of the time is traversal and how much is shading and sampling.
//! * [`scaling`] — load and build time, memory per triangle and Mrays/s for
//!   procedural scenes of growing size and a real glTF file; cost against
//!   resolution and thread count.
//!
//! Nothing here times itself against a target: the figures are reported,
//! the targets live in `docs/benchmarks.md`.

pub mod csv;
pub mod error_curve;
pub mod machine;
pub mod memory;
pub mod peer;
pub mod plot;
pub mod run;
pub mod scaling;
pub mod throughput;

use strum::{Display, EnumIter, EnumString, IntoStaticStr};

use crate::course::unknown_choice;
use std::fmt;
use std::path::PathBuf;

/// The parts of a bench, selectable with `--only`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, EnumIter, IntoStaticStr, EnumString, Display)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<Section>)]
pub enum Section {
    Error,
    Throughput,
    Scaling,
}

/// A bench that could not run: names the file or the option at fault.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error("{}: {problem}", path.display())]
    File { path: PathBuf, problem: String },
    #[error(transparent)]
    Scene(#[from] crate::SceneError),
    #[error(transparent)]
    Image(#[from] crate::render::export::ExportError),
    #[error("{0}")]
    Invalid(String),
}

impl BenchError {
    pub fn file(path: impl Into<PathBuf>, problem: impl fmt::Display) -> Self {
        Self::File {
            path: path.into(),
            problem: problem.to_string(),
        }
    }
}

/// Progress messages of a running bench (the command line shows them on a spinner).
pub trait Progress {
    fn message(&self, text: &str);
}

/// Progress that goes nowhere (tests).
pub struct Silent;

impl Progress for Silent {
    fn message(&self, _text: &str) {}
}

/// A list of positive integers, comma-separated: sample counts, triangle counts, resolutions.
pub fn parse_counts(s: &str, what: &str) -> Result<Vec<u64>, String> {
    let counts: Result<Vec<u64>, String> = s
        .split(',')
        .map(|c| {
            let c = c.trim();
            c.parse::<u64>()
                .ok()
                .filter(|&n| n > 0)
                .ok_or_else(|| format!("'{c}' is not a positive {what}"))
        })
        .collect();
    let counts = counts?;
    if counts.is_empty() {
        return Err(format!("no {what} given"));
    }
    Ok(counts)
}

/// A thread pool of exactly `threads` workers (0: one per core).
pub fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, BenchError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| BenchError::Invalid(format!("cannot start {threads} worker threads: {e}")))
}
