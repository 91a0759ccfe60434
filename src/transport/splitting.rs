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
//! the classic optimum of splitting. A pilot measures the four figures: [`PILOT_SAMPLES`] independent
//! samples with M = 2 at each pixel of a grid over the image. For one
//! sample, (Y₁ − Y₂)² / 2 is an unbiased estimate of V_w; over a pixel's
//! samples, the sample variance of X one of V_b + V_w / 2. Each pixel's
//! figures are weighted by 1 / (X̄² + ε), the weights of relMSE
//! (`metrics`), so M* minimises the time to a relMSE; the channels are
//! averaged. Costs are counted in rays. The choice is thus a function of the
//! scene, the settings and the seed: the same whatever the thread count.
//!
//! M* is rounded to a power of two (so that Sobol and stratified points
//! give each sample's continuations an aligned block; up for those two
//! samplers, whose continuations cancel faster than 1/M, to the nearest for
//! independent numbers), within 1..=[`MAX_AUTO_INDIRECT_SAMPLES`]. Scenes
//! whose continuations bring nothing keep M = 1 without a pilot.
//!
//! ## Region by region
//!
//! The noise is not spread evenly (on the Cornell box the ceiling is all
//! L2, the lit floor mostly L1), so the grid is also cut into regions of
//! [`REGION_GRID`]² pixels, each with its own sums, and region r takes the
//! M_r that minimise the time to a relMSE of the whole image:
//!
//! ```text
//! V = Σ_r V_b,r + V_w,r / M_r        K = Σ_r n_r (C₁,r + M_r C₂,r)
//! ∂(V K)/∂M_r = 0  ⇒  M_r = √( V_w,r K / (V n_r C₂,r) )
//! ```
//!
//! (n_r the region's pilot samples), a fixed point found by iteration from
//! M*, each M_r rounded as M* is. A pixel's samples take its region's
//! count ([`SplitMap`]), each continuation weighted 1/M_r: every pixel
//! stays unbiased, and only where the noise goes changes.

use std::sync::Arc;

use glam::Vec3;
use rayon::prelude::*;

use crate::course::Sampler;
use crate::course::error::RELMSE_EPSILON;
use crate::transport::context::RenderContext;
use crate::transport::continuations::{Continuations, SplitMap};
use crate::transport::counts::ContinuationSplit;
use crate::transport::counts::RayCounts;
use crate::transport::pilot_sample;
use crate::transport::sampler::SampleStream;

/// Pilot samples per grid pixel.
pub const PILOT_SAMPLES: u32 = 8;
/// Grid pixels per side of the pilot, at most (fewer for a smaller image).
pub const PILOT_GRID: u32 = 48;
/// The most continuations the pilot chooses.
pub const MAX_AUTO_INDIRECT_SAMPLES: u32 = 16;
/// Grid pixels per side of a region of the pilot's map: 6² pixels of 8
/// samples, 288 samples to measure a region's noise.
pub const REGION_GRID: u32 = 6;
/// Rounds of the fixed-point iteration for the regions' counts.
const REGION_ITERATIONS: u32 = 32;
/// Seeds the pilot's numbers apart from the image's.
const PILOT_SEED: u64 = 0x7069_6c6f_745f_6d21;

/// What the pilot measured and chose.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SplitChoice {
    /// Continuations per first hit, for the whole image (the formula over
    /// the sums of every region).
    pub count: u32,
    /// M* before rounding (0 when no pilot ran).
    pub optimum: f64,
    /// V_b and V_w, relMSE-weighted sums over the grid.
    pub between: f64,
    pub within: f64,
    /// C₁ and C₂: rays per sample before the continuations, and per continuation.
    pub first_rays: f64,
    pub continuation_rays: f64,
    /// The count of each region, when they differ.
    pub map: Option<Arc<SplitMap>>,
}

impl SplitChoice {
    /// The continuations the samples take.
    pub fn continuations(&self) -> Continuations {
        Continuations {
            count: self.count.max(1),
            map: self.map.clone(),
        }
    }
}

/// The pilot's sums over some of the grid's pixels (a region, a row of
/// regions, or the whole grid).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
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

    /// V_b: the total variance less the continuations' share at M = 2.
    fn between(&self) -> f64 {
        self.total_variance - self.within / 2.0
    }

    /// C₁ and C₂ per sample.
    fn costs(&self) -> (f64, f64) {
        let samples = self.samples.max(1) as f64;
        (
            self.first_rays as f64 / samples,
            self.continuation_rays as f64 / samples / 2.0,
        )
    }
}

/// Sets the continuations per first hit `context`'s samples take: the
/// settings' count, or with `auto_indirect_samples` the pilot's choice
/// through the context's camera (the view decides where the noise is).
/// Call it once the settings and the camera of a film are final.
pub fn choose_continuations(context: &mut RenderContext) {
    context.continuations = if context.settings.auto_indirect_samples {
        choose_indirect_samples(context).continuations()
    } else {
        Continuations::uniform(context.settings.indirect_samples)
    };
}

/// Whether the settings' terms use a continuation of the first hit at all.
fn continuations_matter(context: &RenderContext) -> bool {
    let settings = &context.settings;
    let last = settings.terms.last_reflection(settings.max_bounces);
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
    let grid = PilotGrid::new(settings.width, settings.height);
    // summed row by row, in order: the same totals whatever the threads
    let row_sums: Vec<Vec<PilotSums>> = (0..grid.rows)
        .into_par_iter()
        .map(|row| pilot_row(context, &grid, row))
        .collect();
    let mut regions = vec![PilotSums::default(); (grid.region_columns * grid.region_rows) as usize];
    for (row, sums) in row_sums.iter().enumerate() {
        let region_row = grid.region_row(row as u32);
        for (column, region) in sums.iter().enumerate() {
            regions[(region_row * grid.region_columns) as usize + column].add(region);
        }
    }
    let round_up = settings.sampler != Sampler::Independent;
    let mut choice = choice_from(&regions, round_up);
    let counts = region_counts(&regions, choice.optimum, round_up);
    if counts.iter().any(|&c| c != counts[0]) {
        choice.map = Some(Arc::new(SplitMap {
            width: settings.width,
            height: settings.height,
            columns: grid.region_columns,
            rows: grid.region_rows,
            counts,
        }));
    }
    choice
}

/// The pilot's pixels: a grid of at most [`PILOT_GRID`]² pixels spread
/// over the image, grouped into regions of about [`REGION_GRID`]² of them.
struct PilotGrid {
    width: u32,
    height: u32,
    columns: u32,
    rows: u32,
    region_columns: u32,
    region_rows: u32,
}

impl PilotGrid {
    fn new(width: u32, height: u32) -> Self {
        let (columns, rows) = (width.min(PILOT_GRID), height.min(PILOT_GRID));
        Self {
            width,
            height,
            columns,
            rows,
            region_columns: columns.div_ceil(REGION_GRID).max(1),
            region_rows: rows.div_ceil(REGION_GRID).max(1),
        }
    }

    /// The image column of grid column `column`.
    fn x(&self, column: u32) -> u32 {
        (column as u64 * self.width as u64 / self.columns as u64) as u32
    }

    fn y(&self, row: u32) -> u32 {
        (row as u64 * self.height as u64 / self.rows as u64) as u32
    }

    /// The region column of grid column `column`: the one its image pixel is in, as [`SplitMap`] tiles the image.
    fn region_column(&self, column: u32) -> u32 {
        (self.x(column) as u64 * self.region_columns as u64 / self.width as u64) as u32
    }

    fn region_row(&self, row: u32) -> u32 {
        (self.y(row) as u64 * self.region_rows as u64 / self.height as u64) as u32
    }
}

/// The pilot samples of grid row `row`, summed by region.
fn pilot_row(context: &RenderContext, grid: &PilotGrid, row: u32) -> Vec<PilotSums> {
    let settings = &context.settings;
    let y = grid.y(row);
    let mut regions = vec![PilotSums::default(); grid.region_columns as usize];
    let mut counts = RayCounts::default();
    let mut values = [0.0f64; PILOT_SAMPLES as usize];
    for column in 0..grid.columns {
        let x = grid.x(column);
        let sums = &mut regions[grid.region_column(column) as usize];
        let pixel = y as u64 * settings.width as u64 + x as u64;
        let mut within = 0.0;
        for (sample, value) in values.iter_mut().enumerate() {
            let stream = SampleStream::new(settings.seed ^ PILOT_SEED, pixel, sample as u64);
            let before = counts.total();
            let (radiance, split) = pilot_sample(context, x, y, &stream, &mut counts);
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
    regions
}

/// (Y₁ − Y₂)² / 2 for one sample's two continuations: unbiased for V_w.
fn continuation_noise(split: &ContinuationSplit) -> f64 {
    let [y1, y2] = split.continuations.map(channel_mean);
    0.5 * (y1 - y2) * (y1 - y2)
}

fn channel_mean(radiance: Vec3) -> f64 {
    (radiance.x as f64 + radiance.y as f64 + radiance.z as f64) / 3.0
}

/// M* of the whole image from the sums of its regions (measured with
/// M = 2), rounded to the nearest power of two, or `round_up` to the next.
fn choice_from(regions: &[PilotSums], round_up: bool) -> SplitChoice {
    let mut sums = PilotSums::default();
    for region in regions {
        sums.add(region);
    }
    let (first_rays, continuation_rays) = sums.costs();
    let within = sums.within;
    let between = sums.between();
    let mut choice = SplitChoice {
        count: 1,
        optimum: 1.0,
        between,
        within,
        first_rays,
        continuation_rays,
        map: None,
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

/// The count of each region: the M_r that minimise the time to a given
/// relMSE of the whole image, (Σ_r V_b,r + V_w,r / M_r) · (Σ_r n_r (C₁,r +
/// M_r C₂,r)) with n_r its pilot samples, rounded as the whole image's.
/// Setting each derivative to zero gives M_r = √(V_w,r K / (V n_r C₂,r)),
/// V and K the two factors: a region gets continuations in proportion to
/// the square root of its continuation noise per ray, so the dark corners
/// where L2 is most of the relative noise split more than the lit walls.
/// The fixed point is found by iteration from the whole image's M*.
fn region_counts(regions: &[PilotSums], start: f64, round_up: bool) -> Vec<u32> {
    let max = MAX_AUTO_INDIRECT_SAMPLES as f64;
    let start = if start.is_finite() {
        start.clamp(1.0, max)
    } else {
        max
    };
    let mut counts = vec![start; regions.len()];
    for _ in 0..REGION_ITERATIONS {
        let mut variance = 0.0;
        let mut cost = 0.0;
        for (region, &m) in regions.iter().zip(&counts) {
            let (first, continuation) = region.costs();
            variance += region.between().max(0.0) + region.within / m;
            cost += region.samples as f64 * (first + m * continuation);
        }
        if !(variance > 0.0 && cost > 0.0) {
            break;
        }
        for (region, m) in regions.iter().zip(&mut counts) {
            let (_, continuation) = region.costs();
            let per_ray = variance * region.samples as f64 * continuation;
            *m = if region.within > 0.0 && per_ray > 0.0 {
                (region.within * cost / per_ray).sqrt().clamp(1.0, max)
            } else {
                1.0
            };
        }
    }
    counts
        .iter()
        .map(|&m| power_of_two_near(m, round_up).clamp(1, MAX_AUTO_INDIRECT_SAMPLES))
        .collect()
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
        let choice = choice_from(&[sums], false);
        assert!((choice.optimum - 8f64.sqrt()).abs() < 1e-12);
        assert_eq!(choice.count, 4);
        assert_eq!(choice_from(&[sums], true).count, 4);
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
        assert_eq!(choice_from(&[quiet], true).count, 1);
        let loud = PilotSums {
            within: 2.0,
            ..quiet
        };
        assert_eq!(choice_from(&[loud], false).count, MAX_AUTO_INDIRECT_SAMPLES);
    }

    #[test]
    fn regions_split_as_the_square_root_of_their_continuation_noise() {
        // two regions alike but for the continuations' noise, 16 times
        // larger in the second: at the optimum M₂ = 4 M₁
        let quiet = PilotSums {
            total_variance: 1.0 + 0.5 / 2.0,
            within: 0.5,
            first_rays: 300,
            continuation_rays: 600,
            samples: 100,
        };
        let loud = PilotSums {
            total_variance: 1.0 + 8.0 / 2.0,
            within: 8.0,
            ..quiet
        };
        let regions = [quiet, loud];
        let counts = region_counts(&regions, 2.0, false);
        assert_eq!(counts[1], 4 * counts[0], "{counts:?}");
        // the fixed point, before rounding: M_r = √(V_w,r K / (V n_r C₂))
        let m = |m1: f64| {
            let m2 = 4.0 * m1;
            let variance = 2.0 + 0.5 / m1 + 8.0 / m2;
            let cost = 100.0 * (3.0 + m1 * 3.0) + 100.0 * (3.0 + m2 * 3.0);
            (0.5 * cost / (variance * 100.0 * 3.0)).sqrt()
        };
        let mut m1 = 1.0;
        for _ in 0..100 {
            m1 = m(m1);
        }
        assert_eq!(counts[0], power_of_two_near(m1, false), "{m1}");
        // a region whose continuations bring no noise is not split
        let silent = PilotSums {
            total_variance: 1.0,
            within: 0.0,
            ..quiet
        };
        assert_eq!(region_counts(&[silent, loud], 2.0, true)[0], 1);
    }

    #[test]
    fn a_map_tiles_the_image_and_averages_over_its_pixels() {
        let map = SplitMap {
            width: 10,
            height: 4,
            columns: 3,
            rows: 2,
            counts: vec![1, 2, 4, 8, 16, 1],
        };
        assert_eq!(map.at(0, 0), 1);
        assert_eq!(map.at(3, 1), 1); // ⌊3·3/10⌋ = 0
        assert_eq!(map.at(4, 1), 2);
        assert_eq!(map.at(9, 3), 1);
        assert_eq!(map.at(5, 2), 16);
        assert_eq!(map.range(), (1, 16));
        // the mean over the 40 pixels, pixel by pixel
        let sum: u32 = (0..4)
            .flat_map(|y| (0..10).map(move |x| (x, y)))
            .map(|(x, y)| map.at(x, y))
            .sum();
        assert!(
            (map.mean() - sum as f64 / 40.0).abs() < 1e-12,
            "{}",
            map.mean()
        );
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
