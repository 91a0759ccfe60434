//! The million-samples case: one pixel of the furnace sampled pass by pass,
//! without the thread pool, to show that the film's running sums do not
//! drift over 10⁶ samples.

use glam::Vec3;

use super::cases::furnace_terms;
use super::scenes::{furnace_scene, glowing_wall};
use super::{Case, CaseReport, Effort, term_mean};
use crate::course::color::luminance;
use crate::course::{RenderSettings, Term, TermSet};
use crate::render::film::Film;
use crate::transport::context::RenderContext;
use crate::transport::counts::RayCounts;
use crate::transport::sample_pixel;

/// One pixel of the furnace (ρ = 0.5, E = 1) for 10⁶ passes: L0 is exactly
/// 1 in every sample, so its mean must be exactly 1 (a drifting sum would
/// not be); L1 and L2 must agree with ρE and ρ²E within their noise.
pub(super) fn run(effort: Effort) -> CaseReport {
    let passes: u32 = match effort {
        Effort::Quick => 100_000,
        Effort::Full => 1_000_000,
    };
    let mut report = CaseReport::new(Case::MillionSamples);
    let scene = furnace_scene(1.0, Vec3::ZERO, glowing_wall(0.5, 1.0), 48, 24);
    let settings = RenderSettings {
        width: 1,
        height: 1,
        terms: TermSet::COURSE,
        ..RenderSettings::default()
    };
    let context = RenderContext::new(scene, settings);
    let mut film = Film::new(1, 1);
    let mut counts = RayCounts::default();
    let stream_settings = &context.settings;
    let mut radiance = [[Vec3::ZERO; Term::COUNT]];
    for pass in 0..passes {
        // one pixel: no thread pool, one sample at a time
        let stream = crate::render::sample_stream(stream_settings, 0, pass);
        radiance[0] = sample_pixel(&context, 0, 0, &stream, context.settings.terms, &mut counts);
        film.add_pass(stream_settings.terms, pass, &radiance);
    }
    report.samples = passes as u64;
    report.add_counts(&counts, true, "1 pixel");
    let exact = furnace_terms(0.5, 1.0, 16);
    for term in [Term::L0, Term::L1, Term::L2] {
        let measured = term_mean(&film, term, |_| true);
        report.check_energy("1 pixel", term, measured, exact[term.index()], 0.0);
    }
    // L0 is the same in every sample: its sum must not drift by a single bit
    let l0 = film.term(Term::L0).map(|b| b.mean(0));
    let expected = luminance(Vec3::ONE) as f64;
    if l0.is_none_or(|m| (luminance(m.as_vec3()) as f64 - expected).abs() > 0.0) {
        report
            .failures
            .push(format!("L0 drifted: {l0:?} after {passes} samples"));
    }
    report
}
