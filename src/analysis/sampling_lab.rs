//! The sampling lab: does a strategy draw its directions at p with the
//! density the estimator divides by? Many directions are drawn at p with
//! the strategy's own routine (independent numbers), binned on Ω⁺, and
//! each bin's count is compared with N times the integral of the density
//! over the bin, by a χ² test (`super::chi2`), as Nori's warp test does
//! for a warp alone, but here with the scene's lights, occluders and BRDF.
//!
//! The bins are equal in solid angle: `RINGS` rings of equal width in
//! 1 − cos θ (the square of the radius on the equal-area map, where
//! dω = d(1 − cos θ) dφ) times `SECTORS` sectors of φ, and one more bin,
//! *elsewhere*, for what lands outside them: a direction below p's
//! horizon, a point light's Dirac, a sample that finds nothing (a light
//! seen from behind). Its probability is 1 less the bins'.
//!
//! A density that is wrong on purpose can be tested instead of the
//! strategy's own ([`Against`]): the test then rejects, which shows that
//! it can.

use std::f64::consts::PI;

use glam::{Vec2, Vec3};

use crate::course::{IndirectSampling, Sampler, Term};
use crate::transport::context::RenderContext;
use crate::transport::light::Light;
use crate::transport::sampler::SampleStream;
use crate::transport::warps::{
    UNIFORM_HEMISPHERE_PDF, cosine_hemisphere, cosine_hemisphere_pdf, uniform_hemisphere,
};

use super::chi2::{Chi2, chi2_test};
use super::domains::lights_along;
use super::hemisphere::{IntegrandMap, ShadingPoint};
use super::strategy_samples::{Strategy, direction_density, directions_distribution, strategies};
use crate::geometry::accel::Hit;

/// Rings of the bins, equal in 1 − cos θ.
pub const RINGS: u32 = 16;
/// Sectors of the bins, equal in φ.
pub const SECTORS: u32 = 32;
/// The lab's verdict: rejected below this p-value.
pub const SIGNIFICANCE: f64 = 0.01;

/// Levels a bin's integral is refined to, at least and at most: each
/// level splits a piece into four.
const LEAST_DEPTH: u32 = 2;
const MOST_DEPTH: u32 = 11;

/// The density the counts are compared with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Against {
    /// The strategy's own density, as the estimator divides by it.
    #[default]
    Own,
    /// Uniform over Ω⁺: 1/(2π).
    Uniform,
    /// cos θ / π.
    Cosine,
    /// A classic mistake with light sampling by area: the density of a
    /// point of a light taken as d²/A, without the cosine at the light.
    WithoutLightCosine,
}

impl Against {
    pub const ALL: [Against; 4] = [
        Against::Own,
        Against::Uniform,
        Against::Cosine,
        Against::WithoutLightCosine,
    ];

    /// In words, as the lab offers it.
    pub fn name(self) -> &'static str {
        match self {
            Against::Own => "its own density",
            Against::Uniform => "uniform, 1/(2π)",
            Against::Cosine => "cos θ / π",
            Against::WithoutLightCosine => "d²/A (the light's cosine forgotten)",
        }
    }

    /// Whether it is offered for `strategy` (the mistake is about lights).
    pub fn applies(self, strategy: Strategy) -> bool {
        self != Against::WithoutLightCosine || strategy == Strategy::Light
    }
}

/// Why the lab cannot test at p.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum LabError {
    #[error("this strategy draws no samples for {0} with the current sampling settings")]
    NotUsed(Term),
    #[error("the BRDF at p is a Dirac (mirror or glass): its one direction has no density")]
    DeltaBrdf,
    #[error("there is no extended light: a point light is a Dirac, with no density to test")]
    NoExtendedLight,
}

/// The counts, the bins' probabilities and the verdict.
#[derive(Clone, Debug)]
pub struct SamplingLab {
    pub term: Term,
    pub strategy: Strategy,
    pub against: Against,
    /// Directions drawn.
    pub drawn: u64,
    /// Counts of bin `ring * SECTORS + sector`, then *elsewhere*.
    pub observed: Vec<u64>,
    /// Each bin's probability under the density tested against.
    pub probabilities: Vec<f64>,
    /// The integral of that density over Ω⁺ (1 less *elsewhere*'s share).
    pub density_integral: f64,
    pub chi2: Chi2,
}

impl SamplingLab {
    /// The bins, then *elsewhere*.
    pub const BINS: usize = (RINGS * SECTORS) as usize + 1;

    /// Whether the test accepts the density at [`SIGNIFICANCE`].
    pub fn accepted(&self) -> bool {
        self.chi2.p_value >= SIGNIFICANCE
    }

    /// The bin of the direction `w_local` (unit, p's frame); *elsewhere*
    /// below the horizon.
    pub fn bin_of(w_local: Vec3) -> usize {
        if w_local.z <= 0.0 {
            return Self::BINS - 1;
        }
        let (one_minus_cos, phi) = ring_coordinates(w_local);
        let ring = ((one_minus_cos * RINGS as f64) as u32).min(RINGS - 1);
        let sector = ((phi / (2.0 * PI) * SECTORS as f64) as u32).min(SECTORS - 1);
        (ring * SECTORS + sector) as usize
    }

    /// The bin under the disk point `disk` of the equal-area map, if inside.
    pub fn bin_at(disk: Vec2) -> Option<usize> {
        let r2 = disk.length_squared();
        if r2 >= 1.0 {
            return None;
        }
        let ring = ((r2 * RINGS as f32) as u32).min(RINGS - 1);
        let phi = (disk.y as f64).atan2(disk.x as f64).rem_euclid(2.0 * PI);
        let sector = ((phi / (2.0 * PI) * SECTORS as f64) as u32).min(SECTORS - 1);
        Some((ring * SECTORS + sector) as usize)
    }

    /// Observed and expected counts of bin `bin`.
    pub fn counts(&self, bin: usize) -> (u64, f64) {
        (
            self.observed[bin],
            self.probabilities[bin] * self.drawn as f64,
        )
    }
}

impl SamplingLab {
    /// The observed and the expected density (1/sr: count over N times
    /// the bin's solid angle) at each pixel of a `size`×`size` image of
    /// the equal-area disk; zero outside it.
    pub fn density_images(&self, size: u32) -> (Vec<f32>, Vec<f32>) {
        let per_bin = self.drawn.max(1) as f64 * BIN_SOLID_ANGLE;
        (0..size * size)
            .map(|i| {
                let centre = IntegrandMap::disk_point(size, i % size, i / size, Vec2::splat(0.5));
                match Self::bin_at(centre) {
                    Some(bin) => {
                        let (observed, expected) = self.counts(bin);
                        (
                            (observed as f64 / per_bin) as f32,
                            (expected / per_bin) as f32,
                        )
                    }
                    None => (0.0, 0.0),
                }
            })
            .unzip()
    }
}

/// The solid angle of a bin (sr).
pub const BIN_SOLID_ANGLE: f64 = 2.0 * PI / (RINGS * SECTORS) as f64;

/// (1 − cos θ, φ ∈ [0, 2π)) of a unit direction, accurate for small θ.
fn ring_coordinates(w: Vec3) -> (f64, f64) {
    let (x, y, z) = (w.x as f64, w.y as f64, w.z as f64);
    let one_minus_cos = if z > 0.0 {
        (x * x + y * y) / (1.0 + z)
    } else {
        1.0 - z
    };
    (one_minus_cos, y.atan2(x).rem_euclid(2.0 * PI))
}

/// The direction of (1 − cos θ, φ).
fn ring_direction(one_minus_cos: f64, phi: f64) -> Vec3 {
    let cos = 1.0 - one_minus_cos;
    let sin = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
    Vec3::new(
        (sin * phi.cos()) as f32,
        (sin * phi.sin()) as f32,
        cos as f32,
    )
}

/// Draws `samples` directions at p with `strategy` (as the estimator of
/// `term` draws them, with independent numbers from `seed`) and tests
/// them against the density `against`.
pub fn sampling_lab(
    context: &RenderContext,
    p: &ShadingPoint,
    term: Term,
    strategy: Strategy,
    against: Against,
    samples: u32,
    seed: u64,
) -> Result<SamplingLab, LabError> {
    let (light, directions) = strategies(context, term);
    let used = match strategy {
        Strategy::Light => light.is_some(),
        Strategy::Directions => directions.is_some(),
    };
    if !used {
        return Err(LabError::NotUsed(term));
    }
    let distribution = directions_distribution(context, term);
    match strategy {
        Strategy::Light if context.lights.lights.iter().all(Light::is_delta) => {
            return Err(LabError::NoExtendedLight);
        }
        Strategy::Directions if distribution == IndirectSampling::Brdf && p.brdf.is_delta() => {
            return Err(LabError::DeltaBrdf);
        }
        _ => {}
    }
    let draw = |i: u32| {
        let stream = SampleStream::with_sampler(Sampler::Independent, seed, i as u64, 0);
        draw_direction(context, p, strategy, distribution, &stream)
    };
    let mut observed = vec![0u64; SamplingLab::BINS];
    let mut in_bin: Vec<Vec<(f64, f64)>> = vec![Vec::new(); SamplingLab::BINS - 1];
    for i in 0..samples {
        let drawn = draw(i);
        let bin = drawn.map_or(SamplingLab::BINS - 1, SamplingLab::bin_of);
        observed[bin] += 1;
        if let (Some(points), Some(w)) = (in_bin.get_mut(bin), drawn) {
            points.push(ring_coordinates(w));
        }
    }
    let density = |w_local: Vec3| -> f64 {
        match against {
            Against::Own => direction_density(context, p, term, strategy, w_local) as f64,
            Against::Uniform => UNIFORM_HEMISPHERE_PDF as f64,
            Against::Cosine => cosine_hemisphere_pdf(w_local.z) as f64,
            Against::WithoutLightCosine => light_density_without_cosine(context, p, w_local),
        }
    };
    // a tenth of a bin count's standard deviation (in probability)
    let n = samples.max(1) as f64;
    let tolerance_of = |probability: f64| 0.1 * (probability.max(1.0 / n) / n).sqrt();
    let mut probabilities: Vec<f64> = (0..SamplingLab::BINS - 1)
        .map(|bin| {
            let (ring, sector) = (bin as u32 / SECTORS, bin as u32 % SECTORS);
            let piece = Piece {
                one_minus_cos: (ring as f64 / RINGS as f64, (ring + 1) as f64 / RINGS as f64),
                phi: (
                    sector as f64 / SECTORS as f64 * 2.0 * PI,
                    (sector + 1) as f64 / SECTORS as f64 * 2.0 * PI,
                ),
            };
            let centre = density(piece.direction_at(0.5, 0.5));
            let tolerance = tolerance_of(centre * piece.solid_angle());
            let corners = piece.corners(&density);
            piece.integral(&density, (centre, corners), &in_bin[bin], tolerance, 0)
        })
        .collect();
    let density_integral: f64 = probabilities.iter().sum();
    probabilities.push((1.0 - density_integral).max(0.0));
    Ok(SamplingLab {
        term,
        strategy,
        against,
        drawn: samples as u64,
        chi2: chi2_test(&observed, &probabilities),
        observed,
        probabilities,
        density_integral,
    })
}

/// One direction drawn at p (p's frame), or `None` when the draw gives
/// none (nothing reflected, a light seen from behind) or a Dirac.
fn draw_direction(
    context: &RenderContext,
    p: &ShadingPoint,
    strategy: Strategy,
    distribution: IndirectSampling,
    stream: &SampleStream,
) -> Option<Vec3> {
    let u = stream.uniform2(1);
    match strategy {
        Strategy::Light => {
            let lights = &context.lights;
            let (index, probability) = lights.pick(stream.uniform(0))?;
            if lights.lights[index].is_delta() {
                return None;
            }
            let sample = lights.sample_light(&context.scene, &p.point, index, probability, u)?;
            Some(p.frame.to_local(sample.wi).normalize())
        }
        Strategy::Directions => match distribution {
            IndirectSampling::Uniform => Some(uniform_hemisphere(u)),
            IndirectSampling::Cosine => Some(cosine_hemisphere(u)),
            IndirectSampling::Brdf => p.brdf.sample(p.wo_local, u).map(|s| s.wi),
        },
    }
}

/// The wrong density of [`Against::WithoutLightCosine`]: Σ P(light) d²/A
/// over the triangle lights along the direction (a sphere light keeps its
/// own density: the mistake is about points on a surface).
fn light_density_without_cosine(context: &RenderContext, p: &ShadingPoint, w_local: Vec3) -> f64 {
    let w = p.frame.to_world(w_local).normalize();
    let lights = &context.lights;
    lights_along(context, p.point.spawn_ray(w))
        .iter()
        .map(|behind| match (behind.hit, &behind.point) {
            (Hit::Sphere { sphere, .. }, _) => {
                lights.sphere_emission(sphere, p.point.p, w).1 as f64
            }
            (Hit::Triangle { .. }, Some(point)) => match lights.lights[behind.light as usize] {
                Light::Triangle { area, .. } => {
                    let distance2 = (point.p - p.point.p).length_squared() as f64;
                    lights.selection_probability(behind.light as usize) as f64 * distance2
                        / area as f64
                }
                _ => 0.0,
            },
            _ => 0.0,
        })
        .sum()
}

/// A piece of a bin: a rectangle of (1 − cos θ, φ), where dω = d(1 − cos θ) dφ.
#[derive(Clone, Copy)]
struct Piece {
    one_minus_cos: (f64, f64),
    phi: (f64, f64),
}

impl Piece {
    fn solid_angle(&self) -> f64 {
        (self.one_minus_cos.1 - self.one_minus_cos.0) * (self.phi.1 - self.phi.0)
    }

    /// The direction at fractions (`a`, `b`) across it.
    fn direction_at(&self, a: f64, b: f64) -> Vec3 {
        let lerp = |(lo, hi): (f64, f64), t: f64| lo + (hi - lo) * t;
        ring_direction(lerp(self.one_minus_cos, a), lerp(self.phi, b))
    }

    fn quarters(&self) -> [Piece; 4] {
        let w_mid = 0.5 * (self.one_minus_cos.0 + self.one_minus_cos.1);
        let phi_mid = 0.5 * (self.phi.0 + self.phi.1);
        let ws = [(self.one_minus_cos.0, w_mid), (w_mid, self.one_minus_cos.1)];
        let phis = [(self.phi.0, phi_mid), (phi_mid, self.phi.1)];
        [0, 1, 2, 3].map(|k| Piece {
            one_minus_cos: ws[k / 2],
            phi: phis[k % 2],
        })
    }

    fn contains(&self, (w, phi): (f64, f64)) -> bool {
        (self.one_minus_cos.0..self.one_minus_cos.1).contains(&w)
            && (self.phi.0..self.phi.1).contains(&phi)
    }

    /// ∫ density dω over the piece, adaptively: the midpoint rule on its
    /// quarters, `centre` the density at its middle and `corners` at its
    /// corners ([`Piece::corners`]' order), refined (the tolerance halved
    /// per level) until the rule agrees with the piece's own midpoint
    /// within `tolerance` and the density's spread over the nine points
    /// looked at, times the piece's solid angle, is within it too: a
    /// density's edge (a light's outline, the seam of two triangles
    /// sampled by solid angle) is followed down to small pieces. A piece
    /// where the density is zero at every point looked at but samples fell
    /// is refined too, so that no small source is missed.
    fn integral(
        &self,
        density: &impl Fn(Vec3) -> f64,
        (centre, corners): (f64, [f64; 4]),
        points: &[(f64, f64)],
        tolerance: f64,
        depth: u32,
    ) -> f64 {
        let quarters = self.quarters();
        let middles = quarters.map(|q| density(q.direction_at(0.5, 0.5)));
        let area = self.solid_angle();
        let (whole, fine) = (centre * area, middles.iter().sum::<f64>() * area / 4.0);
        let edges = [(0.5, 0.0), (0.0, 0.5), (1.0, 0.5), (0.5, 1.0)]
            .map(|(a, b)| density(self.direction_at(a, b)));
        let looked_at = corners.iter().chain(&edges).chain(&middles);
        let largest = looked_at.clone().fold(centre, |a, &b| a.max(b));
        let smallest = looked_at.fold(centre, |a, &b| a.min(b));
        let missed = largest == 0.0 && !points.is_empty();
        let settled = (fine - whole).abs() <= tolerance
            && (largest - smallest) * area <= tolerance
            && !missed;
        if depth + 1 >= MOST_DEPTH || (depth + 1 >= LEAST_DEPTH && settled) {
            return fine;
        }
        // the 3×3 points of the piece: corners, edges' middles, centre;
        // quarter k spans w's half k / 2 and φ's half k % 2
        let [w0_phi0, w0_phi1, w1_phi0, w1_phi1] = corners;
        let [phi0, w0, w1, phi1] = edges; // the middles of the edges φ = φ0, w = w0, …
        let quarter_corners = [
            [w0_phi0, w0, phi0, centre],
            [w0, w0_phi1, centre, phi1],
            [phi0, centre, w1_phi0, w1],
            [centre, phi1, w1, w1_phi1],
        ];
        quarters
            .iter()
            .zip(middles)
            .zip(quarter_corners)
            .map(|((quarter, middle), corners)| {
                let inside: Vec<(f64, f64)> = points
                    .iter()
                    .copied()
                    .filter(|&w| quarter.contains(w))
                    .collect();
                quarter.integral(
                    density,
                    (middle, corners),
                    &inside,
                    0.5 * tolerance,
                    depth + 1,
                )
            })
            .sum()
    }

    /// The density at its corners, in the order (w, φ) = (low, low),
    /// (low, high), (high, low), (high, high).
    fn corners(&self, density: &impl Fn(Vec3) -> f64) -> [f64; 4] {
        [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)]
            .map(|(a, b)| density(self.direction_at(a, b)))
    }
}
