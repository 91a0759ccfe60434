//! The render loop: passes of one sample per pixel, spread over threads.
//!
//! Pass s draws sample s of every pixel; the sample's random numbers come from
//! (sampler, seed, pixel, s) only, so the film is bit-identical whatever the
//! number of threads or the order in which tiles finish. Tiles are bands of
//! rows, handed to rayon's work-stealing pool. With adaptive sampling the
//! film decides, before each pass, which terms each pixel still needs
//! (`adaptive`); that too depends on the film alone.

pub mod adaptive;
pub mod color;
pub mod context;
pub mod export;
pub mod film;
pub mod four_up;
pub mod progressive;
pub mod settings;
pub mod settings_override;
pub mod sidecar;

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use glam::Vec3;
use rayon::prelude::*;

use crate::platform::time::Instant;
use crate::render::adaptive::terms_to_sample;
use crate::render::context::RenderContext;
use crate::render::film::Film;
use crate::render::settings::{RenderSettings, Term};
use crate::transport::TermRadiance;
use crate::transport::counts::RayCounts;
use crate::transport::sampler::SampleStream;

/// Rows per tile: small enough to balance two to many cores, large enough
/// that scheduling costs nothing next to the paths.
const TILE_ROWS: usize = 4;

/// When to stop a render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    Samples(u32),
    Time(Duration),
}

/// What a render did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    pub samples_per_pixel: u32,
    pub elapsed: Duration,
    pub rays: RayCounts,
}

impl RenderStats {
    pub fn mrays_per_second(&self) -> f64 {
        self.rays.total() as f64 / self.elapsed.as_secs_f64().max(1e-9) / 1e6
    }
}

/// The random numbers of sample `pass` of pixel `pixel` (row-major index):
/// the one place that decides them, shared by the passes and the pixel probe.
pub fn sample_stream(settings: &RenderSettings, pixel: u64, pass: u32) -> SampleStream {
    SampleStream::with_sampler(settings.sampler, settings.seed, pixel, pass as u64)
}

/// Reusable memory for the samples of one pass.
#[derive(Default)]
pub struct PassBuffer {
    samples: Vec<TermRadiance>,
}

/// Renders pass `pass` (sample index) of every pixel into `film`.
pub fn render_pass(
    context: &RenderContext,
    film: &mut Film,
    pass: u32,
    buffer: &mut PassBuffer,
) -> RayCounts {
    render_pass_cancellable(context, film, pass, buffer, &AtomicBool::new(false))
        .expect("a pass that cannot be cancelled completes")
}

/// [`render_pass`] that gives up, leaving `film` untouched, once `cancel` is
/// set (checked between tiles): `None` if it was cancelled.
pub fn render_pass_cancellable(
    context: &RenderContext,
    film: &mut Film,
    pass: u32,
    buffer: &mut PassBuffer,
    cancel: &AtomicBool,
) -> Option<RayCounts> {
    let width = film.width as usize;
    let terms = context.settings.terms;
    buffer
        .samples
        .resize(film.pixel_count(), [Vec3::ZERO; Term::COUNT]);
    // adaptive sampling: the terms each pixel still needs (None: all, everywhere)
    let needed = context
        .settings
        .adaptive
        .as_ref()
        .and_then(|adaptive| terms_to_sample(film, terms, adaptive));
    let counts = buffer
        .samples
        .par_chunks_mut(width * TILE_ROWS)
        .enumerate()
        .map(|(tile, pixels)| {
            let mut counts = RayCounts::default();
            if cancel.load(Ordering::Relaxed) {
                return counts;
            }
            for (offset, sample) in pixels.iter_mut().enumerate() {
                let index = tile * width * TILE_ROWS + offset;
                let (x, y) = ((index % width) as u32, (index / width) as u32);
                let pixel_terms = match &needed {
                    Some(needed) => {
                        let stopped = terms.iter().filter(|&t| !needed[index].contains(t));
                        counts.skipped.converged += stopped.count() as u64;
                        needed[index]
                    }
                    None => terms,
                };
                if pixel_terms.is_empty() {
                    *sample = [Vec3::ZERO; Term::COUNT];
                    continue;
                }
                let stream = sample_stream(&context.settings, index as u64, pass);
                *sample = context.sample_pixel_terms(x, y, &stream, &mut counts, pixel_terms);
            }
            counts
        })
        .reduce(RayCounts::default, |mut a, b| {
            a.add(&b);
            a
        });
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    match &needed {
        Some(needed) => film.add_pass_where(terms, pass, &buffer.samples, needed),
        None => film.add_pass(terms, pass, &buffer.samples),
    }
    Some(counts)
}

/// Renders until `budget` is spent (at least one pass), calling `progress`
/// after each pass with the stats so far.
pub fn render(
    context: &RenderContext,
    film: &mut Film,
    budget: Budget,
    progress: impl FnMut(&RenderStats),
) -> RenderStats {
    render_cancellable(context, film, budget, &AtomicBool::new(false), progress)
        .expect("a render that cannot be cancelled completes")
}

/// [`render`] that gives up once `cancel` is set (checked between tiles):
/// `None` if it was cancelled, the film then holding the passes completed.
pub fn render_cancellable(
    context: &RenderContext,
    film: &mut Film,
    budget: Budget,
    cancel: &AtomicBool,
    mut progress: impl FnMut(&RenderStats),
) -> Option<RenderStats> {
    let start = Instant::now();
    let mut stats = RenderStats::default();
    let mut buffer = PassBuffer::default();
    let first_pass = Term::ALL
        .iter()
        .filter(|t| context.settings.terms.contains(**t))
        .map(|&t| film.samples(t))
        .min()
        .unwrap_or(0);
    loop {
        let counts = render_pass_cancellable(
            context,
            film,
            first_pass + stats.samples_per_pixel,
            &mut buffer,
            cancel,
        )?;
        stats.rays.add(&counts);
        stats.samples_per_pixel += 1;
        stats.elapsed = start.elapsed();
        progress(&stats);
        let done = match budget {
            Budget::Samples(n) => stats.samples_per_pixel >= n,
            Budget::Time(limit) => stats.elapsed >= limit,
        };
        if done {
            return Some(stats);
        }
    }
}
