//! The pixel probe: the samples behind one pixel of the film.
//!
//! The film keeps sums, not samples. The probe traces the pixel's samples
//! again with the same random streams ([`sample_stream`]) and the pass
//! indices the film recorded, in the same order: they are the samples the
//! film summed, and their mean and standard error equal the film's to the last
//! bit. For the luminances Y₁ … Y_N of one term's samples:
//!
//! ```text
//! mean            Ȳ  = Σ Y / N
//! standard error  se = √(s² / N),  s² = Σ (Y − Ȳ)² / (N − 1)   (Welford, as the film)
//! 95 % interval   Ȳ ± 1.96 se
//! largest share   max Y / Σ Y      (close to 1: one sample, a firefly, makes the pixel)
//! ```
//!
//! At most [`MAX_PROBE_SAMPLES`] samples per term are traced again (the first
//! ones); the film's own mean and error are reported beside them.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::course::TermRadiance;
use crate::course::color::luminance;
use crate::course::{Term, TermSet};
use crate::render::film::{Film, Welford};
use crate::render::sample_stream;
use crate::transport::context::RenderContext;
use crate::transport::counts::RayCounts;
use crate::transport::path_log::PathLog;
use crate::transport::{sample_pixel, sample_pixel_logged};

/// Most samples of one term a probe traces again (about 0.1 s for deep paths).
pub const MAX_PROBE_SAMPLES: u32 = 16_384;

/// Half-width of the 95 % interval, in standard errors.
pub const Z_95: f64 = 1.96;

/// One term of a probed pixel.
#[derive(Clone, Debug)]
pub struct TermProbe {
    pub term: Term,
    /// The film's sample count N for this term.
    pub film_samples: u32,
    /// The film's mean radiance and standard error of the mean luminance.
    pub film_mean: DVec3,
    pub film_standard_error: f64,
    /// The traced samples' radiance, in the film's order (the first
    /// `min(N, MAX_PROBE_SAMPLES)`).
    pub samples: Vec<Vec3>,
    /// Mean radiance of the traced samples.
    pub mean: DVec3,
    /// Mean and standard error of their luminance.
    pub luminance: Welford,
    pub standard_error: f64,
    /// max Y / Σ Y over the traced samples (0 if all are black).
    pub largest_share: f64,
}

impl TermProbe {
    /// Mean luminance of the traced samples.
    pub fn mean_luminance(&self) -> f64 {
        self.luminance.mean
    }

    /// The 95 % confidence interval of the mean luminance.
    pub fn interval_95(&self) -> (f64, f64) {
        let half = Z_95 * self.standard_error;
        (self.mean_luminance() - half, self.mean_luminance() + half)
    }

    /// Whether every sample of the film was traced again.
    pub fn is_complete(&self) -> bool {
        self.samples.len() == self.film_samples as usize
    }

    /// Whether the traced samples give the film's mean (to float precision):
    /// false means the film was rendered from another scene, camera or setting.
    pub fn reproduces_film(&self) -> bool {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-30);
        self.is_complete()
            && (0..3).all(|c| close(self.mean[c], self.film_mean[c]))
            && close(self.standard_error, self.film_standard_error)
    }

    /// Luminance of each traced sample.
    pub fn luminances(&self) -> impl Iterator<Item = f64> + '_ {
        self.samples.iter().map(|&l| luminance(l) as f64)
    }

    /// Histogram of the traced samples' luminance in `bins` equal bins from 0
    /// to the largest.
    pub fn histogram(&self, bins: usize) -> Histogram {
        let bins = bins.max(1);
        let max = self.luminances().fold(0.0f64, f64::max);
        let width = if max > 0.0 { max / bins as f64 } else { 1.0 };
        let mut counts = vec![0u32; bins];
        for y in self.luminances() {
            counts[((y / width) as usize).min(bins - 1)] += 1;
        }
        Histogram {
            bin_width: width,
            counts,
        }
    }
}

/// Counts of values in bins [k·w, (k+1)·w), the last one closed.
#[derive(Clone, Debug, PartialEq)]
pub struct Histogram {
    pub bin_width: f64,
    pub counts: Vec<u32>,
}

/// The probed pixel: one entry per term that has samples.
#[derive(Clone, Debug)]
pub struct PixelProbe {
    pub x: u32,
    pub y: u32,
    /// Row-major index in the film.
    pub index: usize,
    pub terms: Vec<TermProbe>,
    /// The passes traced, in increasing order (the union over the terms).
    pub passes: Vec<u32>,
    /// Luminance of each pass's sample summed over the probed terms.
    pub pass_luminance: Vec<f64>,
    /// Rays traced to probe it.
    pub rays: RayCounts,
}

/// What the film knows of one pixel: for each term, the passes it received
/// (at most the first `max_samples`) and its statistics. Reading it is quick,
/// so the film's lock is held only for that, not while tracing.
#[derive(Clone, Debug)]
pub struct FilmPixel {
    pub x: u32,
    pub y: u32,
    /// Row-major index in the film.
    pub index: usize,
    terms: Vec<FilmPixelTerm>,
}

#[derive(Clone, Debug)]
struct FilmPixelTerm {
    term: Term,
    passes: Vec<u32>,
    samples: u32,
    mean: DVec3,
    standard_error: f64,
}

impl FilmPixel {
    /// Pixel (`x`, `y`) of `film`, for each term of `terms` that has samples.
    pub fn read(film: &Film, x: u32, y: u32, terms: TermSet, max_samples: u32) -> Self {
        assert!(x < film.width && y < film.height, "pixel outside the film");
        let index = y as usize * film.width as usize + x as usize;
        let terms = terms
            .iter()
            .filter_map(|term| {
                let buffer = film.term(term).filter(|b| b.samples > 0)?;
                // a pixel's samples are those of the term's first passes (see `film`)
                let samples = buffer.pixel_samples(index);
                Some(FilmPixelTerm {
                    term,
                    passes: buffer
                        .passes()
                        .take(samples.min(max_samples) as usize)
                        .collect(),
                    samples,
                    mean: buffer.mean(index),
                    standard_error: buffer.standard_error(index),
                })
            })
            .collect();
        Self { x, y, index, terms }
    }
}

/// Traces again the samples of `pixel`.
///
/// `context` must be the one the film was rendered with (scene, settings,
/// camera); its `settings.terms` must include the probed terms (the other
/// terms do not change a term's samples).
pub fn trace_pixel(context: &RenderContext, pixel: &FilmPixel) -> PixelProbe {
    let mut rays = RayCounts::default();
    // a pass traced once serves every term that received it
    let mut traced: HashMap<u32, TermRadiance> = HashMap::new();
    let terms = pixel
        .terms
        .iter()
        .map(|film_term| {
            let term = film_term.term;
            let samples: Vec<Vec3> = film_term
                .passes
                .iter()
                .map(|&pass| {
                    traced.entry(pass).or_insert_with(|| {
                        let stream = sample_stream(&context.settings, pixel.index as u64, pass);
                        sample_pixel(
                            context,
                            pixel.x,
                            pixel.y,
                            &stream,
                            context.settings.terms,
                            &mut rays,
                        )
                    })[term.index()]
                })
                .collect();
            term_probe(
                term,
                samples,
                film_term.samples,
                film_term.mean,
                film_term.standard_error,
            )
        })
        .collect();
    let mut passes: Vec<u32> = traced.keys().copied().collect();
    passes.sort_unstable();
    let probed = pixel.terms.iter().map(|t| t.term.index());
    let pass_luminance = passes
        .iter()
        .map(|pass| {
            let radiance = &traced[pass];
            probed.clone().map(|t| luminance(radiance[t]) as f64).sum()
        })
        .collect();
    PixelProbe {
        x: pixel.x,
        y: pixel.y,
        index: pixel.index,
        terms,
        passes,
        pass_luminance,
        rays,
    }
}

impl PixelProbe {
    /// The position in [`PixelProbe::passes`] of the sample of largest
    /// luminance over the probed terms (the first of equals).
    pub fn brightest(&self) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (k, &y) in self.pass_luminance.iter().enumerate() {
            if best.is_none_or(|(_, b)| y > b) {
                best = Some((k, y));
            }
        }
        best.map(|(k, _)| k)
    }

    /// Traces again the sample of pass `pass` of this pixel, recording its rays.
    /// `context` must be the one the probe was traced with.
    pub fn record_path(&self, context: &RenderContext, pass: u32) -> PathLog {
        let stream = sample_stream(&context.settings, self.index as u64, pass);
        let mut log = PathLog::default();
        sample_pixel_logged(
            context,
            self.x,
            self.y,
            &stream,
            &mut RayCounts::default(),
            &mut log,
        );
        log
    }
}

/// Traces again the samples of pixel (`x`, `y`) of `film` for each term of
/// `terms` that has samples, at most `max_samples` per term (see [`trace_pixel`]).
pub fn probe_pixel(
    context: &RenderContext,
    film: &Film,
    x: u32,
    y: u32,
    terms: TermSet,
    max_samples: u32,
) -> PixelProbe {
    trace_pixel(context, &FilmPixel::read(film, x, y, terms, max_samples))
}

/// The statistics of one term's traced `samples`, summed as the film sums them.
fn term_probe(
    term: Term,
    samples: Vec<Vec3>,
    film_samples: u32,
    film_mean: DVec3,
    film_standard_error: f64,
) -> TermProbe {
    let mut sum = DVec3::ZERO;
    let mut stats = Welford::default();
    let (mut luminance_sum, mut largest) = (0.0f64, 0.0f64);
    for (k, &l) in samples.iter().enumerate() {
        sum += l.as_dvec3();
        let y = luminance(l) as f64;
        let delta = y - stats.mean;
        stats.mean += delta / (k + 1) as f64;
        stats.m2 += delta * (y - stats.mean);
        luminance_sum += y;
        largest = largest.max(y);
    }
    let n = samples.len() as f64;
    let standard_error = if samples.len() < 2 {
        0.0
    } else {
        (stats.m2 / (n - 1.0) / n).sqrt()
    };
    TermProbe {
        term,
        film_samples,
        film_mean,
        film_standard_error,
        mean: if samples.is_empty() {
            DVec3::ZERO
        } else {
            sum / n
        },
        luminance: stats,
        standard_error,
        largest_share: if luminance_sum > 0.0 {
            largest / luminance_sum
        } else {
            0.0
        },
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_of_known_samples() {
        let samples = [1.0f32, 2.0, 4.0, 9.0].map(Vec3::splat).to_vec();
        let probe = term_probe(Term::L1, samples, 4, DVec3::splat(4.0), 0.0);
        assert!((probe.mean_luminance() - 4.0).abs() < 1e-12);
        // s² = (9 + 4 + 0 + 25) / 3
        let se = (38.0f64 / 3.0 / 4.0).sqrt();
        assert!((probe.standard_error - se).abs() < 1e-9);
        let (lo, hi) = probe.interval_95();
        assert!((hi - lo - 2.0 * 1.96 * se).abs() < 1e-9);
        assert!((probe.largest_share - 9.0 / 16.0).abs() < 1e-12);
        let histogram = probe.histogram(3);
        assert_eq!(histogram.counts, [2, 1, 1]);
        assert!((histogram.bin_width - 3.0).abs() < 1e-12);
    }
}
