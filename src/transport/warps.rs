//! Warps and densities: how uniform numbers become directions, points and
//! choices, each with a known density.
//!
//! Each warp maps the unit square to a domain with a known density:
//!
//! | warp | domain | pdf |
//! |---|---|---|
//! | [`cosine_hemisphere`] | directions, z ≥ 0 | cos θ / π (solid angle) |
//! | [`uniform_hemisphere`] | directions, z ≥ 0 | 1 / 2π |
//! | [`uniform_sphere`] | all directions | 1 / 4π |
//! | [`uniform_cone`] | directions within θmax of +z | 1 / (2π (1 − cos θmax)) |
//! | [`phong_lobe`] | directions around +z | (n + 1)/(2π) cosⁿ α |
//! | [`uniform_triangle`] | barycentrics | 1 / area |
//! | [`spherical_triangle`] | directions towards a triangle | 1 / Ω (solid angle) |
//! | [`concentric_disk`] | the unit disk | 1 / π |
//!
//! [`AliasTable`] picks an index in proportion to given weights in O(1).
//!
//! **Spherical triangles** (Arvo 1995). The directions from a point towards
//! a triangle's vertices, a, b, c, bound a spherical triangle of area (solid
//! angle) Ω = α + β + γ − π, α, β, γ its angles, or, better conditioned,
//! tan(Ω/2) = |a·(b×c)| / (1 + a·b + b·c + c·a) (Van Oosterom and Strackee
//! 1983). [`spherical_triangle`] draws directions uniformly inside it: u₀
//! picks the sub-triangle a b ĉ of area u₀·Ω (ĉ on the arc from a to c), u₁ a
//! point on the arc from b to ĉ with the density that makes the whole uniform.

use glam::{DVec3, Vec2, Vec3};
use std::f32::consts::PI;

/// Cosine-weighted direction on the hemisphere z ≥ 0 (Malley: a uniform disk point lifted).
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density of [`cosine_hemisphere`] w.r.t. solid angle.
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) / PI
}

/// Uniform direction on the hemisphere z ≥ 0.
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (cos_phi, sin_phi) = cos_sin_turn(u.y);
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

pub const UNIFORM_HEMISPHERE_PDF: f32 = 1.0 / (2.0 * PI);

/// Uniform direction on the unit sphere.
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (cos_phi, sin_phi) = cos_sin_turn(u.y);
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

/// Uniform direction inside the cone of half-angle θmax around +z, given
/// 1 − cos θmax (passed as such: it is tiny for small cones and 1 − cos loses it).
pub fn uniform_cone(u: Vec2, one_minus_cos_max: f32) -> Vec3 {
    let one_minus_cos = u.x * one_minus_cos_max;
    let cos_theta = 1.0 - one_minus_cos;
    // sin²θ = (1 − cos θ)(1 + cos θ): exact for tiny cones, where 1 − cos²θ
    // would leave sin θ only a handful of values
    let sin_theta = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
    let (cos_phi, sin_phi) = cos_sin_turn(u.y);
    Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
}

/// Density of [`uniform_cone`] w.r.t. solid angle.
pub fn uniform_cone_pdf(one_minus_cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * one_minus_cos_max)
}

/// Direction around +z with density ∝ cosⁿ α (α the angle to +z).
pub fn phong_lobe(u: Vec2, exponent: f32) -> Vec3 {
    let cos_alpha = u.x.powf(1.0 / (exponent + 1.0));
    let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
    let (cos_phi, sin_phi) = cos_sin_turn(u.y);
    Vec3::new(sin_alpha * cos_phi, sin_alpha * sin_phi, cos_alpha)
}

/// Density of [`phong_lobe`] w.r.t. solid angle, given cos α.
pub fn phong_lobe_pdf(cos_alpha: f32, exponent: f32) -> f32 {
    if cos_alpha <= 0.0 {
        0.0
    } else {
        (exponent + 1.0) / (2.0 * PI) * cos_alpha.powf(exponent)
    }
}

/// Uniform point on a triangle, as barycentrics (b0, b1, b2) (Heitz's low-distortion warp).
pub fn uniform_triangle(u: Vec2) -> Vec3 {
    let (b0, b1) = if u.x < u.y {
        let b0 = u.x / 2.0;
        (b0, u.y - b0)
    } else {
        let b1 = u.y / 2.0;
        (u.x - b1, b1)
    };
    Vec3::new(b0, b1, 1.0 - b0 - b1)
}

/// Solid angle (sr) of the spherical triangle of unit directions `a`, `b`,
/// `c` (Van Oosterom–Strackee): 0 for a degenerate triangle, at most 2π.
pub fn spherical_triangle_area(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let triple = a.dot(b.cross(c)).abs();
    2.0 * triple.atan2(1.0 + a.dot(b) + b.dot(c) + c.dot(a))
}

/// Uniform direction inside the spherical triangle of unit directions `a`,
/// `b`, `c` (Arvo's method, in f64), with its density 1/Ω w.r.t. solid
/// angle (Ω from [`spherical_triangle_area`]). `None` for a degenerate triangle.
pub fn spherical_triangle(a: DVec3, b: DVec3, c: DVec3, u: Vec2) -> Option<(DVec3, f64)> {
    let solid_angle = spherical_triangle_area(a, b, c);
    // the planes through the origin and each side; the angles between them
    let (n_ab, n_bc, n_ca) = (a.cross(b), b.cross(c), c.cross(a));
    if n_ab.length_squared() == 0.0 || n_bc.length_squared() == 0.0 || n_ca.length_squared() == 0.0
    {
        return None;
    }
    let (n_ab, n_bc, n_ca) = (n_ab.normalize(), n_bc.normalize(), n_ca.normalize());
    let alpha = angle_between(n_ab, -n_ca);
    let beta = angle_between(n_bc, -n_ab);
    let gamma = angle_between(n_ca, -n_bc);
    let angle_excess = alpha + beta + gamma - std::f64::consts::PI;

    // the sub-triangle a b ĉ of area u₀·Ω: cos of its side from a to ĉ
    let sub_area = u.x as f64 * angle_excess;
    let (s, t) = (sub_area - alpha).sin_cos();
    let (sin_alpha, cos_alpha) = alpha.sin_cos();
    let k_u = t - cos_alpha;
    let k_v = s + sin_alpha * a.dot(b);
    let cos_side = ((k_v * t - k_u * s) * cos_alpha - k_v) / ((k_v * s + k_u * t) * sin_alpha);
    if !cos_side.is_finite() || solid_angle <= 0.0 {
        return None;
    }
    let cos_side = cos_side.clamp(-1.0, 1.0);
    let c_hat = cos_side * a + (1.0 - cos_side * cos_side).max(0.0).sqrt() * orthogonal_part(c, a);

    // a point on the arc from b to ĉ, cos θ to b uniform in [ĉ·b, 1]
    let cos_theta = 1.0 - u.y as f64 * (1.0 - c_hat.dot(b));
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let direction = cos_theta * b + sin_theta * orthogonal_part(c_hat, b);
    Some((direction.normalize(), 1.0 / solid_angle))
}

/// The unit part of `v` orthogonal to unit `axis` (zero if `v` is along it).
fn orthogonal_part(v: DVec3, axis: DVec3) -> DVec3 {
    (v - v.dot(axis) * axis).normalize_or_zero()
}

/// Angle between unit vectors, accurate near 0 and π (unlike acos of the dot).
fn angle_between(v1: DVec3, v2: DVec3) -> f64 {
    if v1.dot(v2) < 0.0 {
        std::f64::consts::PI - 2.0 * ((v1 + v2).length() / 2.0).min(1.0).asin()
    } else {
        2.0 * ((v2 - v1).length() / 2.0).min(1.0).asin()
    }
}

/// Uniform point on the unit disk (Shirley–Chiu concentric map).
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    // θ = π/4 · y/x nearer the x axis, π/2 − π/4 · x/y nearer the y axis,
    // whose cosine and sine are the sine and cosine of π/4 · x/y
    let near_x = o.x.abs() > o.y.abs();
    let (r, across) = if near_x { (o.x, o.y) } else { (o.y, o.x) };
    let (sin, cos) = sin_cos_octant(PI / 4.0 * (across / r));
    let (along_x, along_y) = if near_x { (cos, sin) } else { (sin, cos) };
    r * Vec2::new(along_x, along_y)
}

/// (sin x, cos x) for |x| ≤ π/4, within two ulps there: the minimax
/// polynomials of Cephes' `sinf` and `cosf`. The warps' angles need no
/// general range reduction, which libm's `sincosf` spent a tenth of the
/// warps' time on.
#[inline(always)]
pub fn sin_cos_octant(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let sin = x + x * x2 * (-1.666_665_5e-1 + x2 * (8.332_161e-3 + x2 * -1.951_529_6e-4));
    let cos_tail = 4.166_664_6e-2 + x2 * (-1.388_731_6e-3 + x2 * 2.443_315_7e-5);
    let cos = 1.0 - 0.5 * x2 + x2 * x2 * cos_tail;
    (sin, cos)
}

/// (cos φ, sin φ) of φ = 2π·u, u in [0, 1]: the nearest quarter turn q,
/// then [`sin_cos_octant`] of the rest, rotated by q quarter turns.
#[inline(always)]
pub fn cos_sin_turn(u: f32) -> (f32, f32) {
    let quarters = u * 4.0;
    // u ≥ 0: truncation rounds down
    let q = (quarters + 0.5) as u32;
    let (sin, cos) = sin_cos_octant((quarters - q as f32) * (PI / 2.0));
    // turns 0..3: (c, s), (−s, c), (−c, −s), (s, −c)
    let (cos_phi, sin_phi) = if q & 1 == 0 { (cos, sin) } else { (sin, cos) };
    let negate = |v: f32, yes: bool| f32::from_bits(v.to_bits() ^ (yes as u32) << 31);
    (
        negate(cos_phi, (q + 1) & 2 != 0),
        negate(sin_phi, q & 2 != 0),
    )
}

/// The power heuristic (β = 2) weight of a strategy of density `pdf_a` against `pdf_b`.
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let (a, b) = (pdf_a * pdf_a, pdf_b * pdf_b);
    if a == 0.0 {
        0.0
    } else if !(a + b).is_finite() {
        // one density overflowed: the larger one takes all the weight
        if pdf_a >= pdf_b { 1.0 } else { 0.0 }
    } else {
        a / (a + b)
    }
}

/// The balance heuristic weight of a strategy of density `pdf_a` against `pdf_b`.
pub fn balance_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    if pdf_a == 0.0 {
        0.0
    } else if !(pdf_a + pdf_b).is_finite() {
        if pdf_a >= pdf_b { 1.0 } else { 0.0 }
    } else {
        pdf_a / (pdf_a + pdf_b)
    }
}

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Walker's alias method: picks index i with probability wᵢ / Σw in O(1).
#[derive(Clone, Debug, Default)]
pub struct AliasTable {
    /// Probability of keeping bin i rather than taking its alias.
    keep: Vec<f32>,
    alias: Vec<u32>,
    /// Normalised probability of each index.
    pmf: Vec<f32>,
}

impl AliasTable {
    /// Builds the table; negative and non-finite weights count as zero.
    /// All-zero (or empty) weights give an empty table that picks nothing.
    pub fn new(weights: &[f32]) -> Self {
        let clean: Vec<f64> = weights
            .iter()
            .map(|&w| {
                if w.is_finite() && w > 0.0 {
                    w as f64
                } else {
                    0.0
                }
            })
            .collect();
        let total: f64 = clean.iter().sum();
        if total <= 0.0 {
            return Self::default();
        }
        let n = clean.len();
        let pmf: Vec<f32> = clean.iter().map(|w| (w / total) as f32).collect();
        let mut scaled: Vec<f64> = clean.iter().map(|w| w / total * n as f64).collect();
        let mut keep = vec![1.0f32; n];
        let mut alias: Vec<u32> = (0..n as u32).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) =
            (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
            keep[s] = scaled[s] as f32;
            alias[s] = l as u32;
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // leftovers are 1 up to rounding
        Self { keep, alias, pmf }
    }

    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }

    /// Picks an index from one uniform number in [0, 1); returns it with its probability.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        self.sample_remapped(u)
            .map(|(index, probability, _)| (index, probability))
    }

    /// [`AliasTable::sample`], plus `u` remapped to a fresh uniform number
    /// in [0, 1) (pbrt-v4's `uRemapped`): `u` falls in one interval of
    /// [0, 1) per (bin, keep or alias), and its position inside that
    /// interval, rescaled, is uniform whichever index the interval picks.
    /// The map is monotone on each interval, so stratified numbers stay
    /// stratified: a second number for free, with the bits `u` had beyond
    /// the choice (log₂ n fewer).
    pub fn sample_remapped(&self, u: f32) -> Option<(usize, f32, f32)> {
        if self.pmf.is_empty() {
            return None;
        }
        let n = self.pmf.len();
        let scaled = u * n as f32;
        let bin = (scaled as usize).min(n - 1);
        let frac = (scaled - bin as f32).clamp(0.0, ONE_MINUS_EPSILON);
        let keep = self.keep[bin];
        let (index, remapped) = if frac < keep {
            (bin, frac / keep)
        } else {
            (self.alias[bin] as usize, (frac - keep) / (1.0 - keep))
        };
        Some((index, self.pmf[index], remapped.min(ONE_MINUS_EPSILON)))
    }

    /// Probability of picking `index`.
    pub fn pmf(&self, index: usize) -> f32 {
        self.pmf.get(index).copied().unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_polynomial_sines_and_cosines_are_within_two_ulps_of_one() {
        let worst = |f: &dyn Fn(f64) -> (f32, f32, f64, f64), n: usize| {
            (0..=n).fold(0.0f64, |worst, i| {
                let (sin, cos, exact_sin, exact_cos) = f(i as f64 / n as f64);
                let error = (sin as f64 - exact_sin)
                    .abs()
                    .max((cos as f64 - exact_cos).abs());
                worst.max(error)
            })
        };
        let octant = worst(
            &|t| {
                let x = ((2.0 * t - 1.0) * std::f64::consts::FRAC_PI_4) as f32;
                let (sin, cos) = sin_cos_octant(x);
                (sin, cos, (x as f64).sin(), (x as f64).cos())
            },
            100_000,
        );
        let turn = worst(
            &|u| {
                let u = u as f32;
                let (cos, sin) = cos_sin_turn(u);
                let phi = std::f64::consts::TAU * u as f64;
                (sin, cos, phi.sin(), phi.cos())
            },
            100_000,
        );
        // an ulp of 1 is 2^-23 (1.2e-7)
        assert!(octant < 2.4e-7, "octant: {octant:e}");
        assert!(turn < 2.4e-7, "turn: {turn:e}");
        // the quarter turns themselves are exact
        assert_eq!(cos_sin_turn(0.0), (1.0, 0.0));
        assert_eq!(cos_sin_turn(0.25), (0.0, 1.0));
        assert_eq!(cos_sin_turn(0.5), (-1.0, 0.0));
        assert_eq!(cos_sin_turn(1.0), (1.0, 0.0));
    }

    /// Weights 1 : 0 : 3 : 6 over four bins: the table sends the intervals
    /// [0, 0.1) of u to index 0, [0.1, 0.5) and [0.75, 0.95) to 3, [0.5, 0.75)
    /// and [0.95, 1) to 2. Evenly spaced u = (i + ½)/n put exactly n(b − a)
    /// points in [a, b) when na and nb are whole: with n = 10⁵ every count is
    /// n·pᵢ exactly. Each u lies half a spacing (5·10⁻⁶) from every interval
    /// end, far beyond the f32 rounding of u and of the keep probabilities
    /// (about 10⁻⁷), so none can cross.
    #[test]
    fn alias_table_frequencies_match_weights() {
        let weights = [1.0, 0.0, 3.0, 6.0];
        let table = AliasTable::new(&weights);
        let mut counts = [0u32; 4];
        let n = 100_000;
        for i in 0..n {
            let (index, _) = table.sample((i as f32 + 0.5) / n as f32).unwrap();
            counts[index] += 1;
        }
        let expected = weights.map(|w| (w as f64 / 10.0 * n as f64).round() as u32);
        assert_eq!(counts, expected);
        // the probability, w/Σw rounded once to f32
        assert_eq!(table.pmf(3), 0.6);
    }

    #[test]
    fn alias_table_of_zero_weights_is_empty() {
        assert!(
            AliasTable::new(&[0.0, -1.0, f32::NAN])
                .sample(0.5)
                .is_none()
        );
    }
}
