//! Light transport: how the radiance of each term is estimated.
//!
//! | file | what it holds |
//! |---|---|
//! | `lecture.rs` | the lecture's estimator, L0 + L1 + L2 + L3+ as the slides write them |
//! | `fast.rs` | the fast path tracer: MIS, splitting, skipped work, counters |
//! | `brdf.rs` | Lambert, Phong and the mirror: evaluation and sampling |
//! | `fresnel.rs` | the Fresnel reflectance of a smooth dielectric interface |
//! | `lights.rs` | the light sources, and which one a light sample draws |
//! | `light_points.rs` | how a point or direction on an extended light is drawn |
//! | `sources.rs` | a quality for each source: sources switched off, or with their own light samples |
//! | `surface.rs` | what a ray hit, seen as a surface: normals, emission, BRDF |
//! | `sampler.rs` | random numbers: independent, stratified, Sobol |
//! | `warps.rs` | uniform numbers → directions and points with known densities; the alias table; MIS heuristics |
//! | `splitting.rs` | the pilot that chooses continuations per first hit |
//! | `continuations.rs` | the continuations per pixel the samples take |
//! | `counts.rs`, `tally.rs`, `path_log.rs` | what a sample counts and logs (the fast integrator's bookkeeping) |

pub mod brdf;
pub mod continuations;
pub mod counts;
pub mod fast;
pub mod fresnel;
pub mod lecture;
pub mod light_points;
pub mod lights;
pub mod path_log;
pub mod sampler;
pub mod sources;
pub mod splitting;
pub mod surface;
mod tally;
pub mod warps;

use glam::Vec3;

use crate::geometry::Ray;
use crate::render::context::RenderContext;
use crate::render::settings::{Integrator, Term, TermSet};
use crate::transport::counts::RayCounts;
use crate::transport::sampler::{SampleStream, dim};

/// Radiance of one sample, per term.
pub type TermRadiance = [Vec3; Term::COUNT];

/// The film's guard: a term whose radiance is not finite or is negative
/// (a numerical accident; radiance cannot be negative) is set to zero, and the
/// sample counted in `counts.invalid_samples`. Zeroing biases the pixel
/// slightly dark, so the count must stay 0; the stress suite checks it does.
#[inline(always)]
pub(crate) fn guard_sample(mut radiance: TermRadiance, counts: &mut RayCounts) -> TermRadiance {
    let mut invalid = false;
    for term in &mut radiance {
        if !(term.is_finite() && term.min_element() >= 0.0) {
            *term = Vec3::ZERO;
            invalid = true;
        }
    }
    counts.invalid_samples += u64::from(invalid);
    radiance
}

impl RenderContext {
    /// One sample of pixel (`x`, `y`): its radiance per term.
    pub fn sample_pixel(
        &self,
        x: u32,
        y: u32,
        stream: &SampleStream,
        counts: &mut RayCounts,
    ) -> TermRadiance {
        self.sample_pixel_terms(x, y, stream, counts, self.settings.terms)
    }

    /// [`RenderContext::sample_pixel`] for the terms of `terms` only (a
    /// subset of the settings' terms): the others come out zero and their
    /// work is skipped. A term's value does not depend on which others are
    /// computed: each random dimension belongs to one vertex and one use.
    pub fn sample_pixel_terms(
        &self,
        x: u32,
        y: u32,
        stream: &SampleStream,
        counts: &mut RayCounts,
        terms: TermSet,
    ) -> TermRadiance {
        let ray = self.camera.generate(x, y, stream.uniform2(dim::PIXEL));
        let terms = terms.intersection(self.settings.terms);
        let radiance = self.integrate(ray, stream, terms, self.continuations.at(x, y), counts);
        guard_sample(radiance, counts)
    }

    /// Radiance arriving along `ray` (unit direction), per term, with the
    /// continuations of the whole image; unguarded.
    pub fn trace(&self, ray: Ray, stream: &SampleStream, counts: &mut RayCounts) -> TermRadiance {
        let (terms, splits) = (self.settings.terms, self.continuations.count);
        self.integrate(ray, stream, terms, splits, counts)
    }

    /// The chosen integrator's radiance along `ray` for `terms`, with
    /// `splits` continuations at the first hit (the fast one's); unguarded.
    fn integrate(
        &self,
        ray: Ray,
        stream: &SampleStream,
        terms: TermSet,
        splits: u32,
        counts: &mut RayCounts,
    ) -> TermRadiance {
        match self.settings.integrator {
            Integrator::Fast => fast::radiance(self, ray, stream, terms, splits, counts),
            Integrator::Lecture => {
                // the lecture integrator counts nothing itself: its samples
                // are counted here, as camera rays (adaptive sampling and the
                // viewer's progress read them)
                counts.camera += 1;
                lecture::radiance(self, &ray, stream, terms)
            }
        }
    }
}
