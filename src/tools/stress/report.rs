//! What a case measured and how it is judged: invalid samples and leaks
//! must be 0, a term's mean must match its exact value within the noise
//! (z beyond the case's systematic tolerance below [`Z_LIMIT`]) or, with no
//! noise, within [`NOISELESS_TOLERANCE`]; and the table `lumiere stress`
//! prints.

use std::time::Duration;

use super::Case;
use crate::course::Choice;
use crate::course::Term;
use crate::render::film::Film;
use crate::transport::counts::RayCounts;

/// Largest |z| of a noisy term's mean against its exact value.
pub const Z_LIMIT: f64 = 5.0;

/// Largest relative error of a term with no noise (every sample equal):
/// f32 rounding only. A sample is a chain of a few dozen f32 operations,
/// each rounded by at most 2⁻²⁴ ≈ 6·10⁻⁸, so a few 10⁻⁶ at worst.
pub const NOISELESS_TOLERANCE: f64 = 1e-5;

/// What one case measured.
#[derive(Clone, Debug)]
pub struct CaseReport {
    pub case: Case,
    /// Renders (light modes × settings) or ray batches.
    pub variants: u32,
    /// Samples rendered, or rays traced for the sphere case.
    pub samples: u64,
    pub invalid_samples: u64,
    pub leaked_rays: u64,
    /// Largest relative error of a term with a known value, if any.
    pub energy_error: Option<f64>,
    /// Largest |z| among the noisy terms with a known value, counting only
    /// the deviation beyond the case's systematic tolerance.
    pub worst_z: Option<f64>,
    pub time: Duration,
    /// What went wrong, empty if the case passed.
    pub failures: Vec<String>,
}

impl CaseReport {
    pub(super) fn new(case: Case) -> Self {
        Self {
            case,
            variants: 0,
            samples: 0,
            invalid_samples: 0,
            leaked_rays: 0,
            energy_error: None,
            worst_z: None,
            time: Duration::ZERO,
            failures: Vec::new(),
        }
    }

    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }

    /// Files the counts of one render, failing on invalid samples and, in a
    /// closed scene, on leaks.
    pub(super) fn add_counts(&mut self, counts: &RayCounts, closed: bool, variant: &str) {
        self.variants += 1;
        self.invalid_samples += counts.invalid_samples;
        if counts.invalid_samples > 0 {
            self.failures.push(format!(
                "{variant}: {} invalid samples",
                counts.invalid_samples
            ));
        }
        if closed {
            self.leaked_rays += counts.escaped;
            if counts.escaped > 0 {
                self.failures
                    .push(format!("{variant}: {} rays leaked", counts.escaped));
            }
        }
    }

    /// Compares a term's measured mean with its exact value.
    pub(super) fn check_energy(
        &mut self,
        variant: &str,
        term: Term,
        measured: Mean,
        exact: f64,
        tolerance: f64,
    ) {
        if exact == 0.0 {
            // nothing may reach this term: a single sample would be an error
            if measured.value != 0.0 {
                self.failures.push(format!(
                    "{variant}: {} = {:.3e}, exact 0",
                    term.label(),
                    measured.value
                ));
            }
            return;
        }
        let error = (measured.value - exact).abs() / exact.abs();
        self.energy_error = Some(self.energy_error.unwrap_or(0.0).max(error));
        if measured.standard_error > 0.0 {
            let z = (measured.value - exact) / measured.standard_error;
            // the deviation beyond the case's systematic tolerance, in standard errors
            let excess = ((measured.value - exact).abs() - tolerance * exact.abs()).max(0.0)
                / measured.standard_error;
            self.worst_z = Some(self.worst_z.unwrap_or(0.0).max(excess));
            if excess > Z_LIMIT {
                self.failures.push(format!(
                    "{variant}: {} = {:.6} ± {:.2e}, exact {exact:.6} (z = {z:.1})",
                    term.label(),
                    measured.value,
                    measured.standard_error
                ));
            }
        } else if error > NOISELESS_TOLERANCE {
            self.failures.push(format!(
                "{variant}: {} = {:.6}, exact {exact:.6} (no noise; error {error:.1e})",
                term.label(),
                measured.value
            ));
        }
    }
}

/// A term's image mean and its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mean {
    pub value: f64,
    pub standard_error: f64,
}

/// The mean luminance of `term` over the pixels of `film` where `keep` holds,
/// and its standard error (pixels are independent; one pixel: its own error).
pub fn term_mean(film: &Film, term: Term, keep: impl Fn(usize) -> bool) -> Mean {
    let Some(buffer) = film.term(term) else {
        return Mean {
            value: 0.0,
            standard_error: 0.0,
        };
    };
    let pixels: Vec<usize> = (0..film.pixel_count()).filter(|&i| keep(i)).collect();
    if pixels.len() == 1 {
        return Mean {
            value: buffer.luminance[pixels[0]].mean,
            standard_error: buffer.standard_error(pixels[0]),
        };
    }
    let n = pixels.len().max(1) as f64;
    let values: Vec<f64> = pixels.iter().map(|&i| buffer.luminance[i].mean).collect();
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    Mean {
        value: mean,
        standard_error: (variance / n).sqrt(),
    }
}

/// The table `lumiere stress` prints.
pub fn table(reports: &[CaseReport]) -> String {
    let mut out = format!(
        "{:<18} {:>8} {:>10} {:>8} {:>7} {:>12} {:>7} {:>8}  {}\n",
        "case", "variants", "samples", "invalid", "leaked", "energy err", "|z|", "time", "result"
    );
    for r in reports {
        let energy = r
            .energy_error
            .map_or("—".to_string(), |e| format!("{e:.2e}"));
        let z = r.worst_z.map_or("—".to_string(), |z| format!("{z:.2}"));
        out += &format!(
            "{:<18} {:>8} {:>10} {:>8} {:>7} {:>12} {:>7} {:>7.2}s  {}\n",
            r.case.label(),
            r.variants,
            r.samples,
            r.invalid_samples,
            r.leaked_rays,
            energy,
            z,
            r.time.as_secs_f64(),
            if r.passed() { "ok" } else { "FAILED" }
        );
        for failure in &r.failures {
            out += &format!("    {failure}\n");
        }
    }
    out
}
