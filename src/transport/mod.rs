//! Light transport: how the radiance of each term is estimated.
//!
//! The estimators' entry points, one per use, are the functions below; each
//! reads a [`RenderContext`]:
//!
//! | entry point | use |
//! |---|---|
//! | [`sample_pixel`] | a sample of a pixel for the film, guarded |
//! | [`trace`] | the radiance along any ray (tests, closed-form checks), unguarded |
//! | [`pilot_sample`] | the splitting pilot's sample: what each of two continuations brought |
//! | [`sample_pixel_logged`] | a pixel's sample that logs its rays (path view, bench replay) |
//!
//! | file | what it holds |
//! |---|---|
//! | `context.rs` | `RenderContext`, what every sample reads, and the entry points of the estimators |
//! | `lecture.rs` | the lecture's estimator, L0 + L1 + L2 + L3+ as the slides write them |
//! | `fast.rs` | the fast path tracer: MIS, splitting, skipped work, counters |
//! | `brdf.rs` | Lambert, Phong and the mirror: evaluation and sampling |
//! | `fresnel.rs` | the Fresnel reflectance of a smooth dielectric interface |
//! | `lights.rs` | the light sources, and which one a light sample draws |
//! | `light.rs` | one light: its kinds, what a sample of it gives, how a point or direction on it is drawn |
//! | `sources.rs` | a quality for each source: sources switched off, or with their own light samples |
//! | `surface.rs` | what a ray hit, seen as a surface: normals, emission, BRDF |
//! | `sampler.rs` | random numbers: independent, stratified, Sobol |
//! | `warps.rs` | uniform numbers → directions and points with known densities; the alias table; MIS heuristics |
//! | `roulette.rs` | Russian roulette: one rule, and where each integrator starts it |
//! | `splitting.rs` | the pilot that chooses continuations per first hit |
//! | `continuations.rs` | the continuations per pixel the samples take |
//! | `counts.rs`, `tally.rs`, `path_log.rs` | what a sample counts and logs (the fast integrator's bookkeeping) |

pub mod brdf;
pub mod context;
pub mod continuations;
pub mod counts;
pub mod fast;
pub mod fresnel;
pub mod lecture;
pub mod light;
pub mod lights;
pub mod path_log;
pub mod roulette;
pub mod sampler;
pub mod sources;
pub mod splitting;
pub mod surface;
mod tally;
pub mod warps;

use glam::Vec3;

use crate::course::{Integrator, TermRadiance, TermSet};
use crate::geometry::Ray;
use crate::transport::context::RenderContext;
use crate::transport::counts::ContinuationSplit;
use crate::transport::counts::RayCounts;
use crate::transport::path_log::PathLog;
use crate::transport::sampler::{SampleStream, dim};

/// One sample of pixel (`x`, `y`) for the film: its radiance per term,
/// for the terms of `terms` within the settings' (adaptive sampling asks
/// for fewer; the others come out zero and their work is skipped), with
/// the pixel's continuations per first hit; guarded ([`guard_sample`]).
/// A term's value does not depend on which others are computed: each
/// random dimension belongs to one vertex and one use.
pub fn sample_pixel(
    context: &RenderContext,
    x: u32,
    y: u32,
    stream: &SampleStream,
    terms: TermSet,
    counts: &mut RayCounts,
) -> TermRadiance {
    let ray = context.camera.generate(x, y, stream.uniform2(dim::PIXEL));
    let terms = terms.intersection(context.settings.terms);
    let radiance = integrate(
        context,
        ray,
        stream,
        terms,
        context.continuations.at(x, y),
        counts,
    );
    guard_sample(radiance, counts)
}

/// Radiance arriving along `ray` (unit direction), per term, for `terms`
/// (those of the settings; the others come out zero) with the continuations of the whole image; unguarded. The checks and
/// the hemisphere view trace rays that start anywhere, not at the camera.
pub fn trace(
    context: &RenderContext,
    ray: Ray,
    stream: &SampleStream,
    terms: TermSet,
    counts: &mut RayCounts,
) -> TermRadiance {
    integrate(
        context,
        ray,
        stream,
        terms,
        context.continuations.count,
        counts,
    )
}

/// One sample of pixel (`x`, `y`) by the fast integrator with two
/// continuations at the first hit, whatever the settings say, and what
/// each continuation brought: the splitting pilot's measurement.
pub fn pilot_sample(
    context: &RenderContext,
    x: u32,
    y: u32,
    stream: &SampleStream,
    counts: &mut RayCounts,
) -> (TermRadiance, ContinuationSplit) {
    let ray = context.camera.generate(x, y, stream.uniform2(dim::PIXEL));
    let (radiance, split) = fast::pilot_radiance(context, ray, stream, counts);
    (guard_sample(radiance, counts), split)
}

/// [`sample_pixel`] by the fast integrator, for the
/// settings' terms, appending every ray it traces to `log`.
pub fn sample_pixel_logged(
    context: &RenderContext,
    x: u32,
    y: u32,
    stream: &SampleStream,
    counts: &mut RayCounts,
    log: &mut PathLog,
) -> TermRadiance {
    let ray = context.camera.generate(x, y, stream.uniform2(dim::PIXEL));
    let splits = context.continuations.at(x, y);
    let radiance = fast::logged_radiance(context, ray, stream, splits, counts, log);
    guard_sample(radiance, counts)
}

/// [`trace`] by the fast integrator, for the settings' terms, appending
/// every ray it traces to `log`: the hemisphere view draws the estimator's
/// samples at a path's second vertex q this way, along the bounce p → q.
pub fn trace_logged(
    context: &RenderContext,
    ray: Ray,
    stream: &SampleStream,
    counts: &mut RayCounts,
    log: &mut PathLog,
) -> TermRadiance {
    let splits = context.continuations.count;
    fast::logged_radiance(context, ray, stream, splits, counts, log)
}

/// The chosen integrator's radiance along `ray` for `terms`, with
/// `splits` continuations at the first hit (the fast one's); unguarded.
fn integrate(
    context: &RenderContext,
    ray: Ray,
    stream: &SampleStream,
    terms: TermSet,
    splits: u32,
    counts: &mut RayCounts,
) -> TermRadiance {
    match context.settings.integrator {
        Integrator::Fast => fast::radiance(context, ray, stream, terms, splits, counts),
        Integrator::Lecture => {
            // the lecture integrator counts nothing itself: its samples
            // are counted here, as camera rays (adaptive sampling and the
            // viewer's progress read them)
            counts.camera += 1;
            lecture::radiance(context, &ray, stream, terms)
        }
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_guard_zeroes_invalid_terms_and_counts_the_sample_once() {
        let mut counts = RayCounts::default();
        let valid = [Vec3::ZERO, Vec3::new(0.5, 1.0, 2.0), Vec3::ONE, Vec3::ZERO];
        assert_eq!(guard_sample(valid, &mut counts), valid);
        assert_eq!(counts.invalid_samples, 0);
        let invalid = [
            Vec3::new(f32::INFINITY, 0.0, 0.0),
            Vec3::new(0.5, f32::NAN, 2.0),
            Vec3::ONE,
            Vec3::new(0.0, -1e-9, 0.0),
        ];
        let guarded = guard_sample(invalid, &mut counts);
        assert_eq!(guarded, [Vec3::ZERO, Vec3::ZERO, Vec3::ONE, Vec3::ZERO]);
        assert_eq!(counts.invalid_samples, 1);
    }
}
