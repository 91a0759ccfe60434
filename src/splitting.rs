//! Splitting at the first hit: how many continuations per camera sample
//! reach a given error soonest (`RenderSettings::auto_indirect_samples`).
//!
//! A sample with M continuations is X = A + (1/M) Σⱼ Yⱼ: A what the camera
//! segment and the first vertex's light samples bring (L0, L1), Yⱼ what
//! continuation j brings (L2 and beyond). With
//!
//! ```text
//! V_b = Var(A + E[Y | first vertex])   the noise of the first vertex
//! V_w = E[Var(Y | first vertex)]       the noise of a continuation
//! ```
//!
//! a sample's variance is V_b + V_w / M and its cost C₁ + M C₂ (C₁ the rays
//! up to the continuations, C₂ those of one continuation). The time to a
//! given variance of the mean is proportional to their product, least at
//!
//! ```text
//! M* = √( V_w C₁ / (V_b C₂) )
//! ```
//!
//! the classic optimum of splitting (Arnold's "diffuse samples" set by
//! hand). A pilot measures the four figures: [`PILOT_SAMPLES`] independent
//! samples with M = 2 at each pixel of a grid over the image. For one
//! sample, (Y₁ − Y₂)² / 2 is an unbiased estimate of V_w; over a pixel's
//! samples, the sample variance of X one of V_b + V_w / 2. Each pixel's
//! figures are weighted by 1 / (X̄² + ε), the weights of relMSE
//! (`metrics`), so M* minimises the time to a relMSE; the channels are
//! averaged. Costs are counted in rays. The choice is thus a function of the
//! scene, the settings and the seed: the same whatever the thread count.
//!
//! M* is rounded to a power of two, so that the Sobol and stratified
//! samplers give each sample's continuations an aligned block of points,
//! and kept within 1..=[`MAX_AUTO_INDIRECT_SAMPLES`]. The time is flat
//! near the optimum, and the model is that of independent numbers: with
//! them M* is rounded to the nearest power of two. The stratified and
//! Sobol samplers spread a sample's continuations over consecutive points,
//! which cancels their noise faster than 1/M: there it is rounded up. On
//! the Cornell box (L0+L1+L2, 256², M* ≈ 2.8) the time to relMSE 10⁻³ was,
//! with M = 1, 2, 4, 8: Sobol 3.0, 2.4, 2.05, 2.5 s; with independent
//! numbers relMSE × time at 64 spp was 8.0, 7.2, 7.5 (×10⁻³ s) for M = 1, 2, 4.
//! Scenes whose continuations bring nothing (terms L0, L1 only, mirrors
//! everywhere) keep M = 1 without a pilot.

use glam::Vec3;
use rayon::prelude::*;

use crate::integrator::{ContinuationSplit, RayCounts, RenderContext};
use crate::metrics::RELMSE_EPSILON;
use crate::sampling::SampleStream;
use crate::settings::Sampler;

/// Pilot samples per grid pixel.
pub const PILOT_SAMPLES: u32 = 8;
/// Grid pixels per side of the pilot, at most (fewer for a smaller image).
pub const PILOT_GRID: u32 = 48;
/// The most continuations the pilot chooses.
pub const MAX_AUTO_INDIRECT_SAMPLES: u32 = 16;
/// Seeds the pilot's numbers apart from the image's.
const PILOT_SEED: u64 = 0x7069_6c6f_745f_6d21;

/// What the pilot measured and chose.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SplitChoice {
    /// Continuations per first hit.
    pub count: u32,
    /// M* before rounding (0 when no pilot ran).
    pub optimum: f64,
    /// V_b and V_w, relMSE-weighted sums over the grid.
    pub between: f64,
    pub within: f64,
    /// C₁ and C₂: rays per sample before the continuations, and per continuation.
    pub first_rays: f64,
    pub continuation_rays: f64,
}

/// The pilot's sums over the pixels of one grid row.
#[derive(Clone, Copy, Debug, Default)]
struct PilotSums {
    total_variance: f64,
    within: f64,
    first_rays: u64,
    continuation_rays: u64,
    samples: u64,
}

impl PilotSums {
    fn add(&mut self, other: &PilotSums) {
        self.total_variance += other.total_variance;
        self.within += other.within;
        self.first_rays += other.first_rays;
        self.continuation_rays += other.continuation_rays;
        self.samples += other.samples;
    }
}

/// Whether the settings' terms use a continuation of the first hit at all.
fn continuations_matter(context: &RenderContext) -> bool {
    let settings = &context.settings;
    let last = settings
        .terms
        .max_reflections()
        .unwrap_or(0)
        .min(settings.max_bounces);
    // below L2 a continuation only finds lights for L1, which is not split
    last >= 2
}

/// Runs the pilot on `context` and chooses the continuations per first hit.
pub fn choose_indirect_samples(context: &RenderContext) -> SplitChoice {
    if !continuations_matter(context) {
        return SplitChoice {
            count: 1,
            ..SplitChoice::default()
        };
    }
    let settings = &context.settings;
    let (columns, rows) = (
        settings.width.min(PILOT_GRID),
        settings.height.min(PILOT_GRID),
    );
    // summed row by row, in order: the same total whatever the threads
    let row_sums: Vec<PilotSums> = (0..rows)
        .into_par_iter()
        .map(|row| pilot_row(context, row, rows, columns))
        .collect();
    let mut sums = PilotSums::default();
    for row in &row_sums {
        sums.add(row);
    }
    let round_up = settings.sampler != Sampler::Independent;
    choice_from(&sums, round_up)
}

/// The pilot samples of grid row `row` (of `rows`), `columns` pixels wide.
fn pilot_row(context: &RenderContext, row: u32, rows: u32, columns: u32) -> PilotSums {
    let settings = &context.settings;
    let y = (row as u64 * settings.height as u64 / rows as u64) as u32;
    let mut sums = PilotSums::default();
    let mut counts = RayCounts::default();
    let mut values = [0.0f64; PILOT_SAMPLES as usize];
    for column in 0..columns {
        let x = (column as u64 * settings.width as u64 / columns as u64) as u32;
        let pixel = y as u64 * settings.width as u64 + x as u64;
        let mut within = 0.0;
        for (sample, value) in values.iter_mut().enumerate() {
            let stream = SampleStream::new(settings.seed ^ PILOT_SEED, pixel, sample as u64);
            let before = counts.total();
            let (radiance, split) = context.pilot_sample(x, y, &stream, &mut counts);
            *value = channel_mean(radiance.iter().sum());
            within += continuation_noise(&split);
            sums.first_rays += split.first_rays - before;
            sums.continuation_rays += split.continuation_rays - split.first_rays;
        }
        let n = PILOT_SAMPLES as f64;
        let mean = values.iter().sum::<f64>() / n;
        let variance = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
        let weight = 1.0 / (mean * mean + RELMSE_EPSILON);
        sums.total_variance += weight * variance;
        sums.within += weight * within / n;
        sums.samples += PILOT_SAMPLES as u64;
    }
    sums
}

/// (Y₁ − Y₂)² / 2 for one sample's two continuations: unbiased for V_w.
fn continuation_noise(split: &ContinuationSplit) -> f64 {
    let [y1, y2] = split.continuations.map(channel_mean);
    0.5 * (y1 - y2) * (y1 - y2)
}

fn channel_mean(radiance: Vec3) -> f64 {
    (radiance.x as f64 + radiance.y as f64 + radiance.z as f64) / 3.0
}

/// M* from the pilot's sums (measured with M = 2), rounded to the nearest
/// power of two, or `round_up` to the next.
fn choice_from(sums: &PilotSums, round_up: bool) -> SplitChoice {
    let samples = sums.samples.max(1) as f64;
    let first_rays = sums.first_rays as f64 / samples;
    let continuation_rays = sums.continuation_rays as f64 / samples / 2.0;
    let within = sums.within;
    let between = sums.total_variance - within / 2.0;
    let mut choice = SplitChoice {
        count: 1,
        optimum: 1.0,
        between,
        within,
        first_rays,
        continuation_rays,
    };
    if !(within > 0.0 && continuation_rays > 0.0) {
        return choice; // the continuations bring no noise, or nothing at all
    }
    choice.optimum = if between > 0.0 {
        (within * first_rays.max(1.0) / (between * continuation_rays)).sqrt()
    } else {
        f64::INFINITY // all the noise is the continuations'
    };
    choice.count = power_of_two_near(choice.optimum, round_up).clamp(1, MAX_AUTO_INDIRECT_SAMPLES);
    choice
}

/// The power of two nearest `m` on a log scale, or `up` the least one ≥ m
/// (1 for m ≤ 1, saturating at 2³¹).
fn power_of_two_near(m: f64, up: bool) -> u32 {
    if m.is_nan() || m <= 1.0 {
        return 1;
    }
    let exponent = if up {
        m.log2().ceil()
    } else {
        m.log2().round()
    };
    1u32 << exponent.min(31.0) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_optimum_follows_the_formula() {
        // V_w = 8 V_b and C₁ = C₂: M* = √8 ≈ 2.83, nearest power of two 4
        let sums = PilotSums {
            total_variance: 1.0 + 8.0 / 2.0,
            within: 8.0,
            first_rays: 200,
            continuation_rays: 400,
            samples: 100,
        };
        let choice = choice_from(&sums, false);
        assert!((choice.optimum - 8f64.sqrt()).abs() < 1e-12);
        assert_eq!(choice.count, 4);
        assert_eq!(choice_from(&sums, true).count, 4);
        assert!((choice.between - 1.0).abs() < 1e-12);
    }

    #[test]
    fn noiseless_continuations_are_not_split_and_noisy_ones_are_capped() {
        let quiet = PilotSums {
            total_variance: 1.0,
            within: 0.0,
            first_rays: 100,
            continuation_rays: 200,
            samples: 100,
        };
        assert_eq!(choice_from(&quiet, true).count, 1);
        let loud = PilotSums {
            within: 2.0,
            ..quiet
        };
        assert_eq!(choice_from(&loud, false).count, MAX_AUTO_INDIRECT_SAMPLES);
    }

    #[test]
    fn powers_of_two_are_nearest_on_a_log_scale() {
        assert_eq!(power_of_two_near(0.3, true), 1);
        assert_eq!(power_of_two_near(f64::NAN, false), 1);
        assert_eq!(power_of_two_near(1.41, false), 1);
        assert_eq!(power_of_two_near(1.42, false), 2);
        assert_eq!(power_of_two_near(1.01, true), 2);
        assert_eq!(power_of_two_near(5.0, false), 4);
        assert_eq!(power_of_two_near(5.0, true), 8);
        assert_eq!(power_of_two_near(6.0, false), 8);
        assert_eq!(power_of_two_near(f64::INFINITY, false), 1 << 31);
    }
}
