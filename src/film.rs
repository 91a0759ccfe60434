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

use std::ops::Range;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::color::luminance;
use crate::settings::{Term, TermSet};

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
    /// Samples per pixel accumulated so far.
    pub samples: u32,
    /// The pass indices accumulated, in order, as runs of consecutive passes.
    passes: Vec<Range<u32>>,
}

impl TermBuffer {
    fn new(pixels: usize) -> Self {
        Self {
            sum: vec![DVec3::ZERO; pixels],
            luminance: vec![Welford::default(); pixels],
            samples: 0,
            passes: Vec::new(),
        }
    }

    /// Adds one sample per pixel, from pass `pass`: term `term` of each pixel's `radiance`.
    fn add_pass(&mut self, term: usize, pass: u32, radiance: &[[Vec3; Term::COUNT]]) {
        let n = (self.samples + 1) as f64;
        self.sum
            .par_iter_mut()
            .zip(self.luminance.par_iter_mut())
            .zip(radiance.par_iter())
            .for_each(|((sum, stats), sample)| {
                let l = sample[term];
                *sum += l.as_dvec3();
                let y = luminance(l) as f64;
                let delta = y - stats.mean;
                stats.mean += delta / n;
                stats.m2 += delta * (y - stats.mean);
            });
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

    /// Mean radiance of pixel `i` (zero before any sample).
    pub fn mean(&self, i: usize) -> DVec3 {
        if self.samples == 0 {
            DVec3::ZERO
        } else {
            self.sum[i] / self.samples as f64
        }
    }

    /// Standard error of pixel `i`'s mean luminance (zero below two samples).
    pub fn standard_error(&self, i: usize) -> f64 {
        if self.samples < 2 {
            return 0.0;
        }
        let n = self.samples as f64;
        (self.luminance[i].m2 / (n - 1.0) / n).sqrt()
    }
}

/// Per-term accumulators of an image.
#[derive(Clone, Debug)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    terms: [Option<TermBuffer>; Term::COUNT],
}

impl Film {
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
