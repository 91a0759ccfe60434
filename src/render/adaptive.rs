//! Adaptive sampling: which terms of which pixels still need samples.
//!
//! Before each pass, term t of pixel i is sampled again while
//!
//! ```text
//! n_t(i) < min_samples   or   σ_t(i) > threshold · √(Y(i)² + ε),   Y(i) = Σ_s Ȳ_s(i)
//! ```
//!
//! with n_t(i) its samples, σ_t(i) = √(M2 / (n − 1) / n) the standard error
//! of its mean luminance ([`crate::render::film::TermBuffer::standard_error`]), Ȳ_s(i)
//! the mean luminance of each rendered term s and ε = 10⁻² the ε of relMSE
//! ([`crate::analysis::metrics`]): a pixel stops once its expected share of relMSE,
//! σ² / (Y² + ε), is below threshold². On bright pixels that is a relative
//! error of `threshold`; on dark ones (Y below 0.1 W·m⁻²·sr⁻¹) an absolute
//! error of 0.1 · `threshold`, so black pixels do not take every sample.
//! Each term's error is judged against the whole pixel, so a term that adds
//! little to a pixel stops early there. A pixel none of whose terms needs
//! samples is not traced at all, and one that needs only some is traced for
//! those only (the integrator skips the others' work).
//!
//! Once a term of a pixel has stopped it never resumes, even if the other
//! terms' means later move the bound: its samples stay those of the term's
//! first passes, which is what lets the pixel probe trace them again.
//!
//! Stopping on the samples' own estimate of their error biases a pixel a
//! little (a run of similar samples looks converged early, and a pixel whose
//! first samples all missed a small light stops at zero); `min_samples`
//! bounds that, and the mode is off by default: noise lessons need every
//! pixel sampled alike.

use rayon::prelude::*;

use crate::course::error::RELMSE_EPSILON;
use crate::course::{Adaptive, Term, TermSet};
use crate::render::film::{Film, TermBuffer};

/// The terms each pixel is to receive in the next pass, or `None` when every
/// pixel receives all of `terms` (no pixel has stopped yet).
pub fn terms_to_sample(film: &Film, terms: TermSet, adaptive: &Adaptive) -> Option<Vec<TermSet>> {
    let buffers: Vec<(Term, Option<&TermBuffer>)> = terms
        .iter()
        .map(|t| (t, film.term(t).filter(|b| b.samples > 0)))
        .collect();
    // nothing can have stopped before every term has its minimum
    if buffers
        .iter()
        .all(|(_, b)| b.is_none_or(|b| b.samples < adaptive.min_samples && !b.is_adaptive()))
    {
        return None;
    }
    let sampled: Vec<TermSet> = (0..film.pixel_count())
        .into_par_iter()
        .map(|i| pixel_terms(&buffers, i, adaptive))
        .collect();
    if sampled.iter().all(|&s| s == terms) {
        None
    } else {
        Some(sampled)
    }
}

/// The terms pixel `i` still needs.
fn pixel_terms(buffers: &[(Term, Option<&TermBuffer>)], i: usize, adaptive: &Adaptive) -> TermSet {
    let value: f64 = buffers
        .iter()
        .filter_map(|(_, b)| b.map(|b| b.luminance[i].mean))
        .sum();
    let bound = adaptive.threshold as f64 * (value * value + RELMSE_EPSILON).sqrt();
    buffers.iter().fold(TermSet::NONE, |set, &(term, buffer)| {
        let needed = match buffer {
            None => true,
            Some(b) => {
                b.is_complete(i)
                    && (b.pixel_samples(i) < adaptive.min_samples || b.standard_error(i) > bound)
            }
        };
        set.with(term, needed)
    })
}
