//! The film: one accumulator per term, holding running sums, not samples.
//!
//! For term t and pixel i after N samples the film keeps Σ L (f64 per
//! channel, so 10⁶ samples add without drift) and, for the noise views,
//! Welford's running mean and M2 of the sample luminance, from which
//!
//! ```text
//! mean = Σ L / N,   variance = M2 / (N − 1),   standard error = √(variance / N).
//! ```
//!
//! A term's buffers exist only once the term has been rendered; each term
//! counts its own samples per pixel, so a term switched on later starts from
//! zero while the others keep theirs. Each term also records the pass indices
//! it received (a hidden term skips passes), so that a pixel's samples can be
//! traced again exactly (`probe`).
//!
//! With adaptive sampling (`crate::render::adaptive`) a pass may leave out some
//! pixels of a term; the term then keeps a count per pixel. A pixel that
//! misses a pass of its term never gets another, so its N samples are those
//! of the term's first N passes.

use std::ops::Range;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::course::color::luminance;
use crate::course::{Term, TermSet};
use crate::platform::memory::memory_ceiling;

// ---------------------------------------------------------------------------
// Memory

/// Film bytes per pixel for one term: Σ radiance (3 × f64), Welford's mean
/// and M2 (2 × f64), and its sample count once adaptive sampling leaves
/// pixels out (u32).
pub const TERM_BYTES_PER_PIXEL: u64 = 3 * 8 + 2 * 8 + 4;

/// Bytes per pixel of one pass's samples on their way to the film: an RGB
/// f32 triple for each of the four terms, whichever are kept.
pub const PASS_BYTES_PER_PIXEL: u64 = Term::COUNT as u64 * 3 * 4;

/// An image whose film would not fit the memory ceiling.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "a {width}×{height} image with {terms} term(s) needs about {:.1} GiB of film \
     ({bytes_per_pixel} bytes per pixel: {per_term} per term for its running sums \
     and statistics, {per_pass} for a pass's samples); the limit is {:.1} GiB ({ceiling_reason})",
    gib(*bytes),
    gib(*ceiling),
    per_term = TERM_BYTES_PER_PIXEL,
    per_pass = PASS_BYTES_PER_PIXEL
)]
pub struct FilmTooLarge {
    pub width: u32,
    pub height: u32,
    /// How many terms the film holds.
    pub terms: usize,
    pub bytes_per_pixel: u64,
    /// The estimated bytes of the film.
    pub bytes: u64,
    /// The ceiling, from [`memory_ceiling`].
    pub ceiling: u64,
    pub ceiling_reason: &'static str,
}

fn gib(bytes: u64) -> f64 {
    bytes as f64 / (1u64 << 30) as f64
}

/// Bytes per pixel of a film holding `terms`, with the pass buffer that fills it.
pub fn bytes_per_pixel(terms: TermSet) -> u64 {
    terms.iter().count() as u64 * TERM_BYTES_PER_PIXEL + PASS_BYTES_PER_PIXEL
}

/// Welford's running statistics of one pixel's sample luminance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Welford {
    pub mean: f64,
    pub m2: f64,
}

/// The accumulated samples of one term.
#[derive(Clone, Debug, Default)]
pub struct TermBuffer {
    /// Σ radiance per pixel.
    pub sum: Vec<DVec3>,
    pub luminance: Vec<Welford>,
    /// Passes accumulated so far: the samples of every pixel that none left out.
    pub samples: u32,
    /// Samples of each pixel, once a pass has left some pixel out (adaptive sampling).
    pixel_samples: Option<Vec<u32>>,
    /// The pass indices accumulated, in order, as runs of consecutive passes.
    passes: Vec<Range<u32>>,
}

impl TermBuffer {
    fn new(pixels: usize) -> Self {
        Self {
            sum: vec![DVec3::ZERO; pixels],
            luminance: vec![Welford::default(); pixels],
            samples: 0,
            pixel_samples: None,
            passes: Vec::new(),
        }
    }

    /// Adds one sample per pixel, from pass `pass`: term `term` of each pixel's `radiance`.
    fn add_pass(&mut self, term: usize, pass: u32, radiance: &[[Vec3; Term::COUNT]]) {
        if let Some(counts) = &mut self.pixel_samples {
            // some pixels were left out before: each counts its own
            self.sum
                .par_iter_mut()
                .zip(self.luminance.par_iter_mut())
                .zip(counts.par_iter_mut())
                .zip(radiance.par_iter())
                .for_each(|(((sum, stats), count), sample)| {
                    *count += 1;
                    accumulate(sum, stats, *count, sample[term]);
                });
        } else {
            let n = self.samples + 1;
            self.sum
                .par_iter_mut()
                .zip(self.luminance.par_iter_mut())
                .zip(radiance.par_iter())
                .for_each(|((sum, stats), sample)| accumulate(sum, stats, n, sample[term]));
        }
        self.record_pass(pass);
    }

    /// Adds pass `pass` to the pixels where `sampled(i)` is true; the others
    /// keep their samples (and are never sampled again by this term, by the
    /// callers' rule: see [`TermBuffer::is_complete`]).
    fn add_pass_where(
        &mut self,
        term: usize,
        pass: u32,
        radiance: &[[Vec3; Term::COUNT]],
        sampled: impl Fn(usize) -> bool + Sync,
    ) {
        let samples = self.samples;
        let counts = self
            .pixel_samples
            .get_or_insert_with(|| vec![samples; radiance.len()]);
        self.sum
            .par_iter_mut()
            .zip(self.luminance.par_iter_mut())
            .zip(counts.par_iter_mut())
            .zip(radiance.par_iter())
            .enumerate()
            .for_each(|(i, (((sum, stats), count), sample))| {
                if sampled(i) {
                    *count += 1;
                    accumulate(sum, stats, *count, sample[term]);
                }
            });
        self.record_pass(pass);
    }

    fn record_pass(&mut self, pass: u32) {
        self.samples += 1;
        match self.passes.last_mut() {
            Some(run) if run.end == pass => run.end += 1,
            _ => self.passes.push(pass..pass + 1),
        }
    }

    /// The pass indices of the accumulated samples, in the order they were added.
    pub fn passes(&self) -> impl Iterator<Item = u32> + '_ {
        self.passes.iter().flat_map(Clone::clone)
    }

    /// Samples of pixel `i`.
    pub fn pixel_samples(&self, i: usize) -> u32 {
        self.pixel_samples.as_ref().map_or(self.samples, |c| c[i])
    }

    /// Whether pixel `i` has received every pass of this term (a pixel that
    /// missed one is done for good: its samples stay those of the first passes).
    pub fn is_complete(&self, i: usize) -> bool {
        self.pixel_samples(i) == self.samples
    }

    /// Whether some pixel has fewer samples than others.
    pub fn is_adaptive(&self) -> bool {
        self.pixel_samples.is_some()
    }

    /// Mean radiance of pixel `i` (zero before any sample).
    pub fn mean(&self, i: usize) -> DVec3 {
        match self.pixel_samples(i) {
            0 => DVec3::ZERO,
            n => self.sum[i] / n as f64,
        }
    }

    /// Standard error of pixel `i`'s mean luminance (zero below two samples).
    pub fn standard_error(&self, i: usize) -> f64 {
        let n = self.pixel_samples(i);
        if n < 2 {
            return 0.0;
        }
        let n = n as f64;
        (self.luminance[i].m2 / (n - 1.0) / n).sqrt()
    }
}

/// Adds sample `radiance`, the `n`-th of its pixel, to the running sum and
/// Welford's statistics of its luminance.
#[inline]
fn accumulate(sum: &mut DVec3, stats: &mut Welford, n: u32, radiance: Vec3) {
    *sum += radiance.as_dvec3();
    let y = luminance(radiance) as f64;
    let delta = y - stats.mean;
    stats.mean += delta / n as f64;
    stats.m2 += delta * (y - stats.mean);
}

/// Per-term accumulators of an image.
#[derive(Clone, Debug)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    terms: [Option<TermBuffer>; Term::COUNT],
}

impl Film {
    /// Checks that a `width`×`height` film of `terms` fits under [`memory_ceiling`].
    pub fn check_memory(width: u32, height: u32, terms: TermSet) -> Result<(), FilmTooLarge> {
        let per_pixel = bytes_per_pixel(terms);
        let bytes = u64::from(width) * u64::from(height) * per_pixel;
        let (ceiling, ceiling_reason) = memory_ceiling();
        if bytes <= ceiling {
            return Ok(());
        }
        Err(FilmTooLarge {
            width,
            height,
            terms: terms.iter().count(),
            bytes_per_pixel: per_pixel,
            bytes,
            ceiling,
            ceiling_reason,
        })
    }

    /// A film for `terms`, refused (before any allocation) if it would not fit in memory.
    pub fn try_new(width: u32, height: u32, terms: TermSet) -> Result<Self, FilmTooLarge> {
        Self::check_memory(width, height, terms)?;
        Ok(Self::new(width, height))
    }

    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            terms: Default::default(),
        }
    }

    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The buffer of `term`, if it has been rendered.
    pub fn term(&self, term: Term) -> Option<&TermBuffer> {
        self.terms[term.index()].as_ref()
    }

    /// Samples per pixel of `term` (0 if never rendered).
    pub fn samples(&self, term: Term) -> u32 {
        self.term(term).map_or(0, |b| b.samples)
    }

    /// Adds pass `pass` (the sample index of its random numbers):
    /// `radiance[i][t]` is pixel i's sample of term t; only the terms of
    /// `terms` are accumulated.
    pub fn add_pass(&mut self, terms: TermSet, pass: u32, radiance: &[[Vec3; Term::COUNT]]) {
        let pixels = self.pixel_count();
        assert_eq!(radiance.len(), pixels, "pass size differs from the film's");
        for term in terms.iter() {
            let buffer = self.terms[term.index()].get_or_insert_with(|| TermBuffer::new(pixels));
            buffer.add_pass(term.index(), pass, radiance);
        }
    }

    /// [`Film::add_pass`] in which pixel i receives term t only where
    /// `sampled[i]` contains t (adaptive sampling).
    pub fn add_pass_where(
        &mut self,
        terms: TermSet,
        pass: u32,
        radiance: &[[Vec3; Term::COUNT]],
        sampled: &[TermSet],
    ) {
        let pixels = self.pixel_count();
        assert_eq!(radiance.len(), pixels, "pass size differs from the film's");
        assert_eq!(sampled.len(), pixels, "mask size differs from the film's");
        for term in terms.iter() {
            let buffer = self.terms[term.index()].get_or_insert_with(|| TermBuffer::new(pixels));
            buffer.add_pass_where(term.index(), pass, radiance, |i| sampled[i].contains(term));
        }
    }

    /// Forgets the samples of `term`.
    pub fn clear_term(&mut self, term: Term) {
        self.terms[term.index()] = None;
    }

    /// Mean radiance per pixel, summed over `terms`, row-major from the top.
    pub fn radiance(&self, terms: TermSet) -> Vec<Vec3> {
        let mut image = vec![DVec3::ZERO; self.pixel_count()];
        for term in terms.iter() {
            if let Some(buffer) = self.term(term) {
                for (i, pixel) in image.iter_mut().enumerate() {
                    *pixel += buffer.mean(i);
                }
            }
        }
        image.into_iter().map(|p| p.as_vec3()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn film_memory_is_estimated_per_term_and_capped() {
        assert_eq!(bytes_per_pixel(TermSet::ALL), 4 * 44 + 48);
        assert_eq!(bytes_per_pixel(TermSet::only(Term::L1)), 44 + 48);
        let error = Film::try_new(16384, 16384, TermSet::ALL).unwrap_err();
        assert_eq!(error.bytes, 16384 * 16384 * 224);
        assert!(
            error.to_string().contains("needs about 56.0 GiB"),
            "{error}"
        );
        assert!(Film::try_new(640, 480, TermSet::ALL).is_ok());
    }

    #[test]
    fn welford_matches_two_pass_variance() {
        let mut film = Film::new(1, 1);
        let values = [1.0f32, 2.0, 4.0, 8.0];
        for (pass, v) in [0, 1, 5, 6].into_iter().zip(values) {
            film.add_pass(
                TermSet::only(Term::L1),
                pass,
                &[[Vec3::ZERO, Vec3::splat(v), Vec3::ZERO, Vec3::ZERO]],
            );
        }
        let buffer = film.term(Term::L1).unwrap();
        let mean = 3.75f64;
        let variance = values
            .iter()
            .map(|&v| (v as f64 - mean).powi(2))
            .sum::<f64>()
            / 3.0;
        assert!((buffer.mean(0).x - mean).abs() < 1e-12);
        assert!((buffer.standard_error(0) - (variance / 4.0).sqrt()).abs() < 1e-6);
        assert!(film.term(Term::L0).is_none());
        assert_eq!(film.samples(Term::L1), 4);
        assert_eq!(buffer.passes().collect::<Vec<_>>(), [0, 1, 5, 6]);
    }
}
