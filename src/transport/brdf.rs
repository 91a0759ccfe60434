//! The course's materials, in the local shading frame: three reflection
//! models and glass.
//!
//! Directions are unit vectors pointing away from the surface: `wo` towards
//! the viewer, `wi` towards the light; z is the shading normal, on the side
//! `wo` arrives from (reflection is two-sided). Only glass transmits: a
//! sampled `wi.z < 0` is a refraction into the other side; the other models
//! give zero there.
//!
//! | model | f_r(wo, wi) | sampling |
//! |---|---|---|
//! | Lambert | ρ / π | cosine hemisphere, pdf cos θ / π |
//! | Phong (normalised, modified) | kd/π + ks (n+2)/(2π) cosⁿ α | lobe picked ∝ luminance of kd, ks by the first number of the pair, which then places the direction; cosine hemisphere or cosⁿ α around the mirror direction (pdf (n+1)/(2π) cosⁿ α) |
//! | Mirror | R δ(wi − mirror(wo)) / cos θ | the mirror direction (a Dirac) |
//! | Glass | F δ(wi − mirror(wo)) / cos θ + (1 − F) T/η² δ(wi − refract(wo)) / cos θ | reflection with probability F (Fresnel), else refraction (two Diracs) |
//!
//! α is the angle between `wi` and the mirror direction of `wo`. `eval`
//! returns f without the cosine; a sample's `weight` is f·cos θ / pdf.
//! A Dirac has no density: `eval` and `pdf` of a mirror or glass are zero,
//! and their samples carry `delta = true` with weight R (mirror), 1
//! (glass, reflected: F / F) or T/η² (glass, refracted: (1 − F) T/η² / (1 − F)).
//!
//! For glass η = n_far / n_near, the index of refraction on the side a
//! refracted `wi` leaves into over the one on `wo`'s side (1.5 entering
//! glass from air, 1/1.5 leaving it). Radiance crossing the interface is
//! scaled by 1/η² (the solid angle it fills is compressed by η²): a path that
//! enters and leaves a glass object gets η² · 1/η² = 1, and only T, the
//! tint (the base colour), remains (`docs/conventions.md`).

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

use crate::course::color::luminance;
use crate::geometry::Frame;
use crate::transport::fresnel::fresnel_dielectric;
use crate::transport::warps::{cosine_hemisphere, cosine_hemisphere_pdf, phong_lobe};

/// A reflection model with its parameters resolved at one surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Brdf {
    /// Matte: albedo ρ.
    Lambert { albedo: Vec3 },
    /// Glossy: diffuse kd, specular ks (kd + ks ≤ 1 per channel), exponent n.
    Phong { kd: Vec3, ks: Vec3, exponent: f32 },
    /// Perfect mirror of reflectance R.
    Mirror { reflectance: Vec3 },
    /// Smooth glass: Fresnel reflection, and refraction tinted by T, with
    /// η = n_far / n_near (the module's doc).
    Glass { tint: Vec3, eta: f32 },
}

/// A direction drawn from a BRDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrdfSample {
    /// Unit direction towards the light, local frame.
    pub wi: Vec3,
    /// f · cos θ / pdf (for a Dirac: the reflectance).
    pub weight: Vec3,
    /// Solid-angle density of `wi`; for a Dirac, the probability of the
    /// lobe drawn (1 for a mirror, F or 1 − F for glass).
    pub pdf: f32,
    pub delta: bool,
}

/// The mirror direction of `wo` about the local normal +z.
pub fn reflect(wo: Vec3) -> Vec3 {
    Vec3::new(-wo.x, -wo.y, wo.z)
}

/// The direction refracted from `wo` (`wo.z` > 0) into the other side, where
/// the index of refraction is η times `wo`'s: Snell's law sin θ_t = sin θ_i / η,
/// the tangential part scaled by −1/η and the normal part −cos θ_t. `None`
/// past the critical angle (total internal reflection).
pub fn refract(wo: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = wo.z.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(Vec3::new(-wo.x / eta, -wo.y / eta, -cos_t))
}

impl Brdf {
    /// Whether the model is a Dirac (no light sampling possible).
    pub fn is_delta(&self) -> bool {
        matches!(self, Brdf::Mirror { .. } | Brdf::Glass { .. })
    }

    /// The same material seen from its back: glass's η inverted (the ray is
    /// inside); the reflection models are two-sided and stay as they are.
    pub fn seen_from_behind(self) -> Brdf {
        match self {
            Brdf::Glass { tint, eta } => Brdf::Glass {
                tint,
                eta: 1.0 / eta,
            },
            other => other,
        }
    }

    /// Whether the model reflects nothing (a black surface).
    pub fn is_black(&self) -> bool {
        match *self {
            Brdf::Lambert { albedo } => albedo.max_element() <= 0.0,
            Brdf::Phong { kd, ks, .. } => kd.max_element() <= 0.0 && ks.max_element() <= 0.0,
            Brdf::Mirror { reflectance } => reflectance.max_element() <= 0.0,
            // an interface reflects unless the two indices are equal
            Brdf::Glass { tint, eta } => eta == 1.0 && tint.max_element() <= 0.0,
        }
    }

    /// f_r(wo, wi), without the cosine.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.eval_and_pdf(wo, wi).0
    }

    /// Solid-angle density with which [`Brdf::sample`] returns `wi`.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_and_pdf(wo, wi).1
    }

    /// [`Brdf::eval`] and [`Brdf::pdf`] together: a Phong model raises cos α
    /// to the n-th once for both (`powf` was a twentieth of a Phong render).
    #[inline]
    pub fn eval_and_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        match *self {
            Brdf::Lambert { albedo } => (albedo * FRAC_1_PI, cosine_hemisphere_pdf(wi.z)),
            Brdf::Phong { kd, ks, exponent } => {
                // the lobe is zero past 90° from the mirror direction, also
                // for n = 0 (where powf would give 0⁰ = 1): f then vanishes
                // exactly where the lobe's sampling density does
                let cos_alpha = wi.dot(reflect(wo));
                let lobe = if cos_alpha > 0.0 {
                    cos_alpha.powf(exponent)
                } else {
                    0.0
                };
                let p_spec = Self::specular_probability(kd, ks);
                let f = kd * FRAC_1_PI + ks * ((exponent + 2.0) / (2.0 * PI) * lobe);
                let pdf = (1.0 - p_spec) * cosine_hemisphere_pdf(wi.z)
                    + p_spec * ((exponent + 1.0) / (2.0 * PI) * lobe);
                (f, pdf)
            }
            Brdf::Mirror { .. } | Brdf::Glass { .. } => (Vec3::ZERO, 0.0),
        }
    }

    /// Probability of choosing the specular lobe of a Phong model.
    fn specular_probability(kd: Vec3, ks: Vec3) -> f32 {
        let (d, s) = (luminance(kd).max(0.0), luminance(ks).max(0.0));
        if d + s <= 0.0 { 0.0 } else { s / (d + s) }
    }

    /// Draws `wi` given `wo` from the pair `u`. A Phong model picks its lobe
    /// with `u.x` and stretches the part of `u.x` that picked it back over
    /// [0, 1) (`pick_lobe`), so a stratified pair stays stratified over the
    /// two lobes together instead of being split between them by an
    /// unrelated number. Glass reflects when `u.x` < F and refracts
    /// otherwise. `None` when the drawn direction is below the surface or
    /// nothing is reflected.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 || self.is_black() {
            return None;
        }
        let wi = match *self {
            Brdf::Glass { tint, eta } => return Some(sample_glass(tint, eta, wo, u.x)),
            Brdf::Mirror { reflectance } => {
                return Some(BrdfSample {
                    wi: reflect(wo),
                    weight: reflectance,
                    pdf: 1.0,
                    delta: true,
                });
            }
            Brdf::Lambert { .. } => cosine_hemisphere(u),
            Brdf::Phong { kd, ks, exponent } => {
                let (specular, u) = pick_lobe(Self::specular_probability(kd, ks), u);
                if specular {
                    Frame::from_z(reflect(wo)).to_world(phong_lobe(u, exponent))
                } else {
                    cosine_hemisphere(u)
                }
            }
        };
        let (f, pdf) = self.eval_and_pdf(wo, wi);
        if wi.z <= 0.0 || pdf <= 0.0 {
            return None;
        }
        Some(BrdfSample {
            wi,
            weight: f * wi.z / pdf,
            pdf,
            delta: false,
        })
    }
}

/// Smooth glass: the mirror direction with probability F, weight F / F = 1;
/// otherwise the refracted one, weight (1 − F) T/η² / (1 − F) = T/η².
/// Past the critical angle F = 1: always reflected.
fn sample_glass(tint: Vec3, eta: f32, wo: Vec3, u: f32) -> BrdfSample {
    let reflectance = fresnel_dielectric(wo.z, eta);
    let refracted = if u < reflectance {
        None
    } else {
        refract(wo, eta)
    };
    match refracted {
        Some(wi) => BrdfSample {
            wi,
            weight: tint / (eta * eta),
            pdf: 1.0 - reflectance,
            delta: true,
        },
        None => BrdfSample {
            wi: reflect(wo),
            weight: Vec3::ONE,
            pdf: reflectance,
            delta: true,
        },
    }
}

/// Whether `u.x` picks the lobe of probability `p` (the interval [0, p)),
/// and the pair with `u.x` mapped back onto [0, 1) from the interval that
/// picked.
#[inline]
fn pick_lobe(p: f32, u: Vec2) -> (bool, Vec2) {
    const BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;
    let (picked, x) = if u.x < p {
        (true, u.x / p)
    } else {
        (false, (u.x - p) / (1.0 - p))
    };
    (picked, Vec2::new(x.min(BELOW_ONE), u.y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::fresnel::fresnel_dielectric;
    use crate::transport::sampler::SampleStream;

    /// Monte Carlo estimate of the directional albedo ∫ f cos dω by BRDF sampling.
    fn albedo(brdf: &Brdf, wo: Vec3, n: u32) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            let s = SampleStream::new(1, 0, i as u64);
            if let Some(sample) = brdf.sample(wo, s.uniform2(1)) {
                sum += sample.weight;
            }
        }
        sum / n as f32
    }

    #[test]
    fn lambert_albedo_is_rho() {
        let brdf = Brdf::Lambert {
            albedo: Vec3::new(0.2, 0.5, 0.8),
        };
        let a = albedo(&brdf, Vec3::new(0.3, 0.0, 0.954).normalize(), 1000);
        assert!((a - Vec3::new(0.2, 0.5, 0.8)).abs().max_element() < 1e-5);
    }

    /// Mean and standard error of the red channel of ∫ f cos dω estimated by
    /// BRDF sampling (weights f·cos/pdf, 0 when no direction is drawn), with
    /// each drawn sample checked against `eval` and `pdf` of its direction.
    fn sampled_albedo(brdf: &Brdf, wo: Vec3, n: u32, seed: u64) -> (f64, f64) {
        let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
        for i in 0..n {
            let stream = SampleStream::new(seed, 0, i as u64);
            let Some(sample) = brdf.sample(wo, stream.uniform2(1)) else {
                continue;
            };
            let (f, pdf) = brdf.eval_and_pdf(wo, sample.wi);
            assert_eq!(sample.pdf, pdf, "the sample's pdf is the density's");
            // weight = f cos θ / pdf, to a few roundings
            let expected = f * sample.wi.z / pdf;
            assert!(
                (sample.weight - expected).abs().max_element()
                    <= 4.0 * f32::EPSILON * expected.max_element(),
                "{brdf:?}: weight {} for f cos/pdf {expected}",
                sample.weight
            );
            let w = sample.weight.x as f64;
            sum += w;
            sum_sq += w * w;
        }
        let mean = sum / n as f64;
        (mean, ((sum_sq / n as f64 - mean * mean) / n as f64).sqrt())
    }

    /// Asserts a Monte Carlo estimate (mean, standard error) agrees with an
    /// exact value within 4.5 standard errors (one failure in 150,000 by
    /// chance) and the rounding of f32 weights.
    fn assert_estimates(what: &str, (mean, error): (f64, f64), exact: f64) {
        let tolerance = 4.5 * error + 1e-6 * exact;
        assert!(
            (mean - exact).abs() <= tolerance,
            "{what}: {mean:.6} ± {error:.1e}, exact {exact:.6} (z = {:.1})",
            (mean - exact) / error
        );
    }

    /// At normal incidence the mirror direction is the normal, α = θ, and the
    /// lobe lies whole above the surface: ∫ ks (n+2)/(2π) cosⁿθ cos θ dω =
    /// ks (n+2) ∫₀¹ μⁿ⁺¹ dμ = ks, so the albedo is kd + ks exactly, for
    /// every exponent. A lobe normalised by (n+1)/(2π) would give
    /// kd + ks (n+1)/(n+2).
    #[test]
    fn phong_albedo_at_normal_incidence_is_kd_plus_ks() {
        for (kd, ks) in [(0.0, 1.0), (0.3, 0.6)] {
            for exponent in [0.0, 1.0, 5.0, 20.0, 100.0, 1000.0] {
                let brdf = Brdf::Phong {
                    kd: Vec3::splat(kd),
                    ks: Vec3::splat(ks),
                    exponent,
                };
                let estimate = sampled_albedo(&brdf, Vec3::Z, 100_000, 3);
                let what = format!("kd {kd}, ks {ks}, n {exponent}");
                assert_estimates(&what, estimate, (kd + ks) as f64);
            }
        }
    }

    /// ∫ ks (n+2)/(2π) cosⁿα max(cos θ, 0) dω over the lobe around the
    /// mirror direction r of `wo`, by a midpoint rule in (t, φ) with
    /// t = cosⁿ⁺¹α (dω = dt dφ / ((n+1) cosⁿα)): the integrand is then
    /// ks (n+2)/((n+1) 2π) max(cos θ, 0), smooth but for the horizon's kink.
    fn phong_lobe_albedo_by_quadrature(wo: Vec3, exponent: f64, ks: f64) -> f64 {
        let r = reflect(wo).as_dvec3();
        let frame = Frame::from_z(reflect(wo));
        let (tx, ty) = (frame.x.as_dvec3(), frame.y.as_dvec3());
        let steps = 1500;
        let mut sum = 0.0;
        for i in 0..steps {
            let t = (i as f64 + 0.5) / steps as f64;
            let cos_alpha = t.powf(1.0 / (exponent + 1.0));
            let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
            for j in 0..steps {
                let phi = (j as f64 + 0.5) / steps as f64 * std::f64::consts::TAU;
                let wi = r * cos_alpha + (tx * phi.cos() + ty * phi.sin()) * sin_alpha;
                sum += wi.z.max(0.0);
            }
        }
        let cell = std::f64::consts::TAU / (steps * steps) as f64;
        ks * (exponent + 2.0) / ((exponent + 1.0) * std::f64::consts::TAU) * sum * cell
    }

    /// Away from normal incidence part of the lobe dips below the horizon:
    /// BRDF sampling must still estimate ∫ f cos dω, here computed by
    /// quadrature of `eval`'s formula, kd/π integrating to kd exactly.
    #[test]
    fn phong_sampling_estimates_the_albedo_at_oblique_incidence() {
        let (kd, ks) = (0.2f32, 0.7f32);
        for theta_degrees in [45.0f32, 75.0] {
            let theta = theta_degrees.to_radians();
            let wo = Vec3::new(theta.sin(), 0.0, theta.cos());
            for exponent in [1.0f32, 20.0, 300.0] {
                let brdf = Brdf::Phong {
                    kd: Vec3::splat(kd),
                    ks: Vec3::splat(ks),
                    exponent,
                };
                let exact =
                    kd as f64 + phong_lobe_albedo_by_quadrature(wo, exponent as f64, ks as f64);
                let estimate = sampled_albedo(&brdf, wo, 100_000, 4);
                let what = format!("θo {theta_degrees}°, n {exponent}");
                assert_estimates(&what, estimate, exact);
            }
        }
    }

    /// The glTF default material (metallic 1, roughness 1) is Phong with
    /// n = 0: f = ks/π on the half-space around the mirror direction r, and
    /// what BRDF sampling estimates must be ∫ f cos dω. That region of the
    /// hemisphere is a lune between the horizon and the plane ⊥ r, whose
    /// projected solid angle is, by Lambert's formula over its two half great
    /// circles (normals n and r), ½(π + π cos θo): the albedo is
    /// ks (1 + cos θo)/2, below 1 away from normal incidence. Uniform
    /// directions on the hemisphere measure it independently of the
    /// sampling routine; the two estimates must agree within 4.5 of their
    /// combined standard errors, each with the closed form, and the energy
    /// the uniform directions measure must be below 1 by 4.5 of its own.
    #[test]
    fn phong_with_exponent_zero_is_sampled_where_it_reflects() {
        let brdf = Brdf::Phong {
            kd: Vec3::ZERO,
            ks: Vec3::ONE,
            exponent: 0.0,
        };
        let theta_o = 60f32.to_radians();
        let wo = Vec3::new(theta_o.sin(), 0.0, theta_o.cos());
        let exact = (1.0 + wo.z as f64) / 2.0;
        let n = 200_000;
        let sampled = sampled_albedo(&brdf, wo, n, 1);
        let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
        for i in 0..n {
            let s = SampleStream::new(2, 0, i as u64);
            let wi = crate::transport::warps::uniform_hemisphere(s.uniform2(0));
            let value =
                brdf.eval(wo, wi).x * wi.z / crate::transport::warps::UNIFORM_HEMISPHERE_PDF;
            sum += value as f64;
            sum_sq += (value as f64).powi(2);
        }
        let mean = sum / n as f64;
        let standard_error = ((sum_sq / n as f64 - mean * mean) / n as f64).sqrt();
        let uniform = (mean, standard_error);

        let combined = (sampled.1.powi(2) + uniform.1.powi(2)).sqrt();
        let z = (sampled.0 - uniform.0) / combined;
        assert!(
            z.abs() <= 4.5,
            "BRDF sampling {sampled:?}, uniform directions {uniform:?} (z = {z:.2})"
        );
        assert_estimates("BRDF sampling", sampled, exact);
        assert_estimates("uniform directions", uniform, exact);
        assert!(
            uniform.0 + 4.5 * uniform.1 < 1.0,
            "energy {uniform:?} is not below 1"
        );
    }

    /// The numbers that pick a lobe, stretched, are spread evenly over
    /// [0, 1) again: n equally spaced u.x give each lobe its share of them,
    /// equally spaced (to rounding), so stratification survives the pick.
    #[test]
    fn a_picked_lobe_gets_its_share_of_the_pair_spread_evenly() {
        let n = 1 << 12;
        for p in [0.0, 0.1, 0.37, 0.5, 0.9, 1.0] {
            let mut picked: [Vec<f32>; 2] = [Vec::new(), Vec::new()];
            for i in 0..n {
                let x = (i as f32 + 0.5) / n as f32;
                let (specular, u) = pick_lobe(p, Vec2::new(x, 0.25));
                assert!(
                    (0.0..1.0).contains(&u.x) && u.y == 0.25,
                    "p {p}, x {x}: {u}"
                );
                picked[specular as usize].push(u.x);
            }
            let expected = (p * n as f32).round() as usize;
            assert!(
                picked[1].len().abs_diff(expected) <= 1,
                "p {p}: {} specular",
                picked[1].len()
            );
            for lobe in picked.iter().filter(|l| l.len() > 1) {
                let spacing = 1.0 / lobe.len() as f32;
                for pair in lobe.windows(2) {
                    let step = pair[1] - pair[0];
                    assert!(
                        (step - spacing).abs() < 1e-3 * spacing + 1e-6,
                        "p {p}: step {step}"
                    );
                }
            }
        }
    }

    /// Glass's two Dirac lobes, counted as such: every sample is exactly
    /// the mirror or the refracted direction, with weight 1 or T/η², and
    /// the counts of each follow F and 1 − F (χ² with one degree of
    /// freedom below 15.1, a chance of 10⁻⁴), from air and from inside,
    /// where past the critical angle every sample is reflected.
    #[test]
    fn glass_draws_its_two_lobes_with_the_fresnel_probabilities() {
        let n = 20_000u32;
        let tint = Vec3::new(0.9, 0.8, 0.7);
        for eta in [1.5f32, 1.0 / 1.5] {
            for degrees in [0.0f32, 30.0, 41.0, 60.0, 85.0] {
                let theta = degrees.to_radians();
                let wo = Vec3::new(theta.sin() * 0.6, theta.sin() * 0.8, theta.cos());
                let glass = Brdf::Glass { tint, eta };
                let reflectance = fresnel_dielectric(wo.z, eta);
                let refracted = refract(wo, eta);
                let mut reflected = 0u32;
                for i in 0..n {
                    let stream = SampleStream::new(7, 0, i as u64);
                    let sample = glass.sample(wo, stream.uniform2(5)).unwrap();
                    assert!(sample.delta);
                    if sample.wi == reflect(wo) {
                        reflected += 1;
                        assert_eq!((sample.weight, sample.pdf), (Vec3::ONE, reflectance));
                    } else {
                        assert_eq!(Some(sample.wi), refracted, "η {eta}, {degrees}°");
                        assert_eq!(sample.weight, tint / (eta * eta));
                        assert_eq!(sample.pdf, 1.0 - reflectance);
                    }
                }
                if refracted.is_none() {
                    assert_eq!(
                        reflected, n,
                        "total internal reflection, η {eta}, {degrees}°"
                    );
                    continue;
                }
                let expected = [
                    reflectance as f64 * n as f64,
                    (1.0 - reflectance as f64) * n as f64,
                ];
                let observed = [reflected as f64, (n - reflected) as f64];
                let chi2: f64 = observed
                    .iter()
                    .zip(expected)
                    .map(|(o, e)| (o - e).powi(2) / e)
                    .sum();
                assert!(
                    chi2 < 15.1,
                    "η {eta}, {degrees}°: χ² = {chi2:.1}, {reflected} of {n} reflected, F = {reflectance}"
                );
            }
        }
    }

    /// Snell's law: the refracted direction is a unit vector on the other
    /// side, in the plane of `wo` and the normal, with η sin θ_t = sin θ_i;
    /// and refracting it back from the other side gives `wo` again.
    #[test]
    fn refraction_follows_snells_law_both_ways() {
        for eta in [1.33f32, 1.5, 2.4, 1.0 / 1.5] {
            for degrees in [0.0f32, 10.0, 35.0, 41.0] {
                let theta = degrees.to_radians();
                let wo = Vec3::new(theta.sin() * 0.28, -theta.sin() * 0.96, theta.cos());
                let wi = refract(wo, eta).unwrap();
                assert!((wi.length() - 1.0).abs() < 1e-6 && wi.z < 0.0);
                let (sin_i, sin_t) = (wo.truncate().length(), wi.truncate().length());
                assert!((eta * sin_t - sin_i).abs() < 1e-6, "η {eta}, {degrees}°");
                assert!(
                    wo.truncate().perp_dot(wi.truncate()).abs() < 1e-6,
                    "coplanar"
                );
                assert!(wo.truncate().dot(wi.truncate()) <= 0.0, "across the normal");
                // from the other side the frame's z is flipped and η inverted
                let back = refract(Vec3::new(wi.x, wi.y, -wi.z), 1.0 / eta).unwrap();
                let back = Vec3::new(back.x, back.y, -back.z);
                assert!(
                    (back - wo).length() < 1e-5,
                    "η {eta}, {degrees}°: {back} vs {wo}"
                );
            }
        }
        assert_eq!(
            refract(Vec3::new(0.8, 0.0, 0.6), 1.0 / 1.5),
            None,
            "past the critical angle"
        );
    }

    #[test]
    fn mirror_is_a_dirac() {
        let brdf = Brdf::Mirror {
            reflectance: Vec3::splat(0.9),
        };
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let s = brdf.sample(wo, Vec2::ZERO).unwrap();
        assert!(s.delta);
        assert_eq!(s.wi, Vec3::new(-0.6, 0.0, 0.8));
        assert_eq!(brdf.eval(wo, s.wi), Vec3::ZERO);
        assert_eq!(brdf.pdf(wo, s.wi), 0.0);
    }
}
