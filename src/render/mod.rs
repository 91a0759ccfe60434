//! The render loop: passes of one sample per pixel, spread over threads.
//!
//! Pass s draws sample s of every pixel; the sample's random numbers come from
//! (sampler, seed, pixel, s) only, so the film is bit-identical whatever the
//! number of threads or the order in which tiles finish. Tiles are bands of
//! rows, handed to rayon's work-stealing pool (or, on a web page with one
//! thread, rendered in order a few at a time: [`render_pass_until`]). With
//! adaptive sampling the film decides, before each pass, which terms each
//! pixel still needs (`adaptive`); that too depends on the film alone.

pub mod adaptive;
pub mod display;
pub mod export;
pub mod film;
pub mod four_up;
pub mod progressive;
pub mod settings_override;
pub mod sidecar;

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use glam::Vec3;
use rayon::prelude::*;

use crate::course::TermRadiance;
use crate::course::{RenderSettings, Term, TermSet};
use crate::platform::time::Instant;
use crate::render::adaptive::terms_to_sample;
use crate::render::film::Film;
use crate::transport::context::RenderContext;
use crate::transport::counts::RayCounts;
use crate::transport::sample_pixel;
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
    let mut partial = PartialPass::new(context, film, pass);
    let width = film.width as usize;
    buffer
        .samples
        .resize(film.pixel_count(), [Vec3::ZERO; Term::COUNT]);
    let counts = buffer
        .samples
        .par_chunks_mut(width * TILE_ROWS)
        .enumerate()
        .map(|(tile, pixels)| {
            if cancel.load(Ordering::Relaxed) {
                return RayCounts::default();
            }
            partial.render_tile(context, width, tile, pixels)
        })
        .reduce(RayCounts::default, |mut a, b| {
            a.add(&b);
            a
        });
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    partial.counts = counts;
    Some(partial.finish(context, film, buffer))
}

/// A pass rendered a few tiles at a time, on one thread: a page without
/// Web Workers renders between its frames ([`render_pass_until`]).
pub struct PartialPass {
    pass: u32,
    /// Adaptive sampling: the terms each pixel still needs (None: all, everywhere).
    needed: Option<Vec<TermSet>>,
    next_tile: usize,
    counts: RayCounts,
}

impl PartialPass {
    /// Pass `pass` of `film`, no tile rendered yet.
    pub fn new(context: &RenderContext, film: &Film, pass: u32) -> Self {
        let terms = context.settings.terms;
        let needed = context
            .settings
            .adaptive
            .as_ref()
            .and_then(|adaptive| terms_to_sample(film, terms, adaptive));
        Self {
            pass,
            needed,
            next_tile: 0,
            counts: RayCounts::default(),
        }
    }

    /// Tile `tile` (its `pixels` of the pass's samples): one sample each.
    fn render_tile(
        &self,
        context: &RenderContext,
        width: usize,
        tile: usize,
        pixels: &mut [TermRadiance],
    ) -> RayCounts {
        let terms = context.settings.terms;
        let mut counts = RayCounts::default();
        for (offset, sample) in pixels.iter_mut().enumerate() {
            let index = tile * width * TILE_ROWS + offset;
            let (x, y) = ((index % width) as u32, (index / width) as u32);
            let pixel_terms = match &self.needed {
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
            let stream = sample_stream(&context.settings, index as u64, self.pass);
            *sample = sample_pixel(context, x, y, &stream, pixel_terms, &mut counts);
        }
        counts
    }

    /// Adds the pass's samples to `film`; what it traced.
    fn finish(&self, context: &RenderContext, film: &mut Film, buffer: &PassBuffer) -> RayCounts {
        let terms = context.settings.terms;
        match &self.needed {
            Some(needed) => film.add_pass_where(terms, self.pass, &buffer.samples, needed),
            None => film.add_pass(terms, self.pass, &buffer.samples),
        }
        self.counts
    }
}

/// Renders tiles of `partial`, in order, until `deadline` has passed (at
/// least one tile); once the last is done, adds the pass to `film` (the
/// same film as [`render_pass`]'s) and returns what it traced.
pub fn render_pass_until(
    context: &RenderContext,
    film: &mut Film,
    partial: &mut PartialPass,
    buffer: &mut PassBuffer,
    deadline: Instant,
) -> Option<RayCounts> {
    let width = film.width as usize;
    buffer
        .samples
        .resize(film.pixel_count(), [Vec3::ZERO; Term::COUNT]);
    let tiles = film.pixel_count().div_ceil(width * TILE_ROWS);
    while partial.next_tile < tiles {
        let tile = partial.next_tile;
        // the tile's pixels, as `par_chunks_mut` cuts them
        let pixels =
            tile * width * TILE_ROWS..((tile + 1) * width * TILE_ROWS).min(film.pixel_count());
        let counts = partial.render_tile(context, width, tile, &mut buffer.samples[pixels]);
        partial.counts.add(&counts);
        partial.next_tile += 1;
        if partial.next_tile < tiles && Instant::now() >= deadline {
            return None;
        }
    }
    Some(partial.finish(context, film, buffer))
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
