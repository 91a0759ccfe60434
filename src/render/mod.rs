//! The render loop: passes of one sample per pixel, spread over threads.
//!
//! Pass s draws sample s of every pixel; the sample's random numbers come from
//! (sampler, seed, pixel, s) only, so the film is bit-identical whatever the
//! number of threads or the order in which tiles finish. Tiles are bands of
//! rows, handed to rayon's work-stealing pool (or, on a web page with one
//! thread, a few at a time between frames: [`Pass`]). With
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
    Pass::new(context, film, pass)
        .render(context, film, buffer, &Until::completed())
        .expect("a pass that cannot be stopped completes")
}

/// When [`Pass::render`] stops before the pass is complete, checked between
/// tiles: once `cancel` is set (a new request: the viewer's worker), or
/// once `deadline` has passed (a page on one thread renders between its
/// frames), after at least one tile.
#[derive(Clone, Copy)]
pub struct Until<'a> {
    pub cancel: Option<&'a AtomicBool>,
    pub deadline: Option<Instant>,
}

impl<'a> Until<'a> {
    /// Never before the pass is complete.
    pub fn completed() -> Self {
        Self {
            cancel: None,
            deadline: None,
        }
    }

    fn cancelled(&self) -> bool {
        self.cancel
            .is_some_and(|cancel| cancel.load(Ordering::Relaxed))
    }

    /// Until `cancel` is set.
    pub fn cancelled_by(cancel: &'a AtomicBool) -> Self {
        Self {
            cancel: Some(cancel),
            deadline: None,
        }
    }
}

/// One pass (sample index) over the film, tile by tile: the one way a
/// pass is rendered. [`Pass::render`] renders the tiles not done yet, on
/// every thread of the pool, until the pass is complete or [`Until`] says
/// stop; the pass keeps the tiles done for the next call. Each sample
/// depends on its pixel and the pass only, so which tiles ran in which
/// call changes nothing in the film.
pub struct Pass {
    pass: u32,
    /// Adaptive sampling: the terms each pixel still needs (None: all, everywhere).
    needed: Option<Vec<TermSet>>,
    /// Which tiles hold their samples in the buffer.
    done: Vec<bool>,
    counts: RayCounts,
}

impl Pass {
    /// Pass `pass` of `film`, no tile rendered yet.
    pub fn new(context: &RenderContext, film: &Film, pass: u32) -> Self {
        let terms = context.settings.terms;
        let needed = context
            .settings
            .adaptive
            .as_ref()
            .and_then(|adaptive| terms_to_sample(film, terms, adaptive));
        let tiles = film.pixel_count().div_ceil(film.width as usize * TILE_ROWS);
        Self {
            pass,
            needed,
            done: vec![false; tiles],
            counts: RayCounts::default(),
        }
    }

    /// Renders the tiles not done yet until `until` says stop: `None`, the
    /// film untouched, if it stopped first; else adds the pass's samples to
    /// `film` (the one the pass was made for) and returns what it traced.
    /// `buffer` holds the samples between calls.
    pub fn render(
        &mut self,
        context: &RenderContext,
        film: &mut Film,
        buffer: &mut PassBuffer,
        until: &Until,
    ) -> Option<RayCounts> {
        let width = film.width as usize;
        buffer
            .samples
            .resize(film.pixel_count(), [Vec3::ZERO; Term::COUNT]);
        // past the deadline, the one tile a call renders at least
        let first_claimed = AtomicBool::new(false);
        let may_start = || {
            !until.cancelled()
                && (until
                    .deadline
                    .is_none_or(|deadline| Instant::now() < deadline)
                    || !first_claimed.swap(true, Ordering::Relaxed))
        };
        let (pass, needed) = (self.pass, self.needed.as_deref());
        let counts = buffer
            .samples
            .par_chunks_mut(width * TILE_ROWS)
            .zip(self.done.par_iter_mut())
            .enumerate()
            .map(|(tile, (pixels, done))| {
                if *done || !may_start() {
                    return RayCounts::default();
                }
                *done = true;
                render_tile(context, pass, needed, width, tile, pixels)
            })
            .reduce(RayCounts::default, |mut a, b| {
                a.add(&b);
                a
            });
        self.counts.add(&counts);
        if self.done.contains(&false) {
            return None;
        }
        let terms = context.settings.terms;
        match needed {
            Some(needed) => film.add_pass_where(terms, pass, &buffer.samples, needed),
            None => film.add_pass(terms, pass, &buffer.samples),
        }
        Some(self.counts)
    }
}

/// Tile `tile` (its `pixels` of the pass's samples): one sample each.
fn render_tile(
    context: &RenderContext,
    pass: u32,
    needed: Option<&[TermSet]>,
    width: usize,
    tile: usize,
    pixels: &mut [TermRadiance],
) -> RayCounts {
    let terms = context.settings.terms;
    let mut counts = RayCounts::default();
    for (offset, sample) in pixels.iter_mut().enumerate() {
        let index = tile * width * TILE_ROWS + offset;
        let (x, y) = ((index % width) as u32, (index / width) as u32);
        let pixel_terms = match needed {
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
        *sample = sample_pixel(context, x, y, &stream, pixel_terms, &mut counts);
    }
    counts
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
        let pass = first_pass + stats.samples_per_pixel;
        let counts = Pass::new(context, film, pass).render(
            context,
            film,
            &mut buffer,
            &Until::cancelled_by(cancel),
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
