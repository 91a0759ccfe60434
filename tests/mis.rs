//! Multiple importance sampling where its weights matter: a small square
//! light over a glossy Phong plane. Near the mirror direction the BRDF's
//! density is of the light's order, away from it far smaller, so weights
//! that do not sum to one for every direction bias L1 by many standard
//! errors. The expected L1 is the rendering equation integrated over the
//! light's area by quadrature, in f64, with the Phong formula written out
//! here rather than taken from the renderer.

mod common;

use std::f64::consts::PI;
use std::sync::Arc;

use common::{add_floor, assert_agrees, estimate};
use glam::{DVec3, Vec3};
use lumiere::course::{BrdfOverride, LightSampling, MisHeuristic};
use lumiere::geometry::Ray;
use lumiere::scene::{Material, Scene};
use lumiere::transport::context::RenderContext;
use lumiere::{RenderSettings, Term, TermSet};

/// The floor's base colour; the Phong override makes kd = ρ(1 − ks).
const ALBEDO: f64 = 0.8;
const SPECULAR: f64 = 0.5;
/// The light: a square of half-side 0.1 m at height 1 m, facing down.
const LIGHT_HALF_SIDE: f64 = 0.1;
const LIGHT_HEIGHT: f64 = 1.0;
const RADIANCE: f64 = 5.0;
/// Samples per estimate.
const SAMPLES: u64 = 20_000;
/// Relative error allowed beyond the noise: the quadrature's (cells of
/// 0.5 mm against a lobe at least 8 cm wide on the light, so about 10⁻⁶)
/// and f32 geometry's, with a margin.
const SYSTEMATIC: f64 = 1e-5;

fn scene() -> Scene {
    let mut scene = Scene::default();
    let floor = scene.add_material(Material::lambert("floor", Vec3::splat(ALBEDO as f32)));
    add_floor(&mut scene, floor, 20.0);
    let light = scene.add_material(Material::emitter("light", Vec3::splat(RADIANCE as f32)));
    let (h, z) = (LIGHT_HALF_SIDE as f32, LIGHT_HEIGHT as f32);
    let corners = [
        Vec3::new(-h, -h, z),
        Vec3::new(-h, h, z),
        Vec3::new(h, h, z),
        Vec3::new(h, -h, z),
    ];
    scene.add_mesh("light", light, &corners, &[[0, 1, 2], [0, 2, 3]]);
    scene
}

/// The floor's BRDF as the Phong override defines it (`brdf.rs`'s table):
/// f = kd/π + ks (n+2)/(2π) cosⁿα, α between `wi` and the mirror of `wo`;
/// and its sampling density, the lobes picked by the luminance of kd and ks:
/// (1 − P) cos θ/π + P (n+1)/(2π) cosⁿα.
struct Phong {
    kd: f64,
    ks: f64,
    exponent: f64,
}

impl Phong {
    fn new(exponent: f64) -> Self {
        Self {
            kd: ALBEDO * (1.0 - SPECULAR),
            ks: SPECULAR,
            exponent,
        }
    }

    fn lobe(&self, wo: DVec3, wi: DVec3) -> f64 {
        let mirror = DVec3::new(-wo.x, -wo.y, wo.z);
        wi.dot(mirror).max(0.0).powf(self.exponent)
    }

    fn eval(&self, wo: DVec3, wi: DVec3) -> f64 {
        self.kd / PI + self.ks * (self.exponent + 2.0) / (2.0 * PI) * self.lobe(wo, wi)
    }

    fn pdf(&self, wo: DVec3, wi: DVec3) -> f64 {
        let specular = self.ks / (self.kd + self.ks);
        (1.0 - specular) * wi.z / PI
            + specular * (self.exponent + 1.0) / (2.0 * PI) * self.lobe(wo, wi)
    }
}

/// Per light point q seen from floor point p towards the viewer `wo`: the
/// integrand of L1 over the light's area, f L cos θ cos θ′ / d², and the
/// light's density in solid angle when it is sampled by area, d² / (A cos θ′).
fn over_the_light(p: DVec3, wo: DVec3, phong: &Phong, mut visit: impl FnMut(f64, f64, f64)) {
    const STEPS: usize = 400;
    let side = 2.0 * LIGHT_HALF_SIDE;
    let cell = (side / STEPS as f64).powi(2);
    for i in 0..STEPS {
        for j in 0..STEPS {
            let q = DVec3::new(
                -LIGHT_HALF_SIDE + (i as f64 + 0.5) / STEPS as f64 * side,
                -LIGHT_HALF_SIDE + (j as f64 + 0.5) / STEPS as f64 * side,
                LIGHT_HEIGHT,
            );
            let to_light = q - p;
            let distance_sq = to_light.length_squared();
            let wi = to_light / distance_sq.sqrt();
            // the light faces −z: cos θ′ = wi·z, as cos θ at the floor
            let cos = wi.z;
            let integrand = phong.eval(wo, wi) * RADIANCE * cos * cos / distance_sq;
            let light_pdf = distance_sq / (side * side * cos);
            visit(integrand * cell, light_pdf, phong.pdf(wo, wi));
        }
    }
}

/// L1 at `p` towards `wo` (midpoint rule, 160,000 points: the integrand is
/// smooth over the light, the error far below the Monte Carlo tolerance).
fn expected_l1(p: DVec3, wo: DVec3, phong: &Phong) -> f64 {
    let mut sum = 0.0;
    over_the_light(p, wo, phong, |value, _, _| sum += value);
    sum
}

/// How far L1 moves if the balance heuristic's weight is applied to the
/// light samples and the BRDF samples keep weight 1: by ∫ w_light f L cos dω
/// (with the area density; the solid-angle one is close for this small light).
fn one_sided_bias(p: DVec3, wo: DVec3, phong: &Phong) -> f64 {
    let mut sum = 0.0;
    over_the_light(p, wo, phong, |value, light_pdf, brdf_pdf| {
        sum += value * light_pdf / (light_pdf + brdf_pdf)
    });
    sum
}

/// A floor point and the unit direction towards the viewer whose mirror
/// direction points at `aim` (a point on the light, or beside it).
fn view(p: DVec3, aim: DVec3) -> (DVec3, DVec3) {
    let wi = (aim - p).normalize();
    (p, DVec3::new(-wi.x, -wi.y, wi.z))
}

/// Every MIS variant (balance and power heuristics, one or four light
/// samples, one or four BRDF samples) and the unweighted strategies give
/// the quadrature's L1 within 4.5 standard errors, at points whose mirror
/// direction meets the light's centre, its edge, or misses it, for a wide
/// (n = 20) and a sharp (n = 200) lobe. The test checks that it can tell:
/// a heuristic applied on one side only would be off by at least 10
/// tolerances at some point of each lobe.
#[test]
fn mis_weights_sum_to_one_where_light_and_brdf_densities_differ() {
    let scene = Arc::new(scene());
    let course = "L1,L2".parse::<TermSet>().expect("terms");
    let views = [
        view(
            DVec3::new(0.5, 0.0, 0.0),
            DVec3::new(0.0, 0.0, LIGHT_HEIGHT),
        ),
        view(
            DVec3::new(0.5, 0.0, 0.0),
            DVec3::new(0.09, 0.05, LIGHT_HEIGHT),
        ),
        view(
            DVec3::new(-0.3, 0.4, 0.0),
            DVec3::new(0.6, -0.2, LIGHT_HEIGHT),
        ),
    ];
    for exponent in [20.0, 200.0] {
        let phong = Phong::new(exponent);
        let base = RenderSettings {
            width: 1,
            height: 1,
            terms: TermSet::only(Term::L1),
            brdf: BrdfOverride::Phong,
            phong_exponent: exponent as f32,
            phong_specular: SPECULAR as f32,
            ..RenderSettings::default()
        };
        let mut sets = Vec::new();
        for mis_heuristic in [MisHeuristic::Balance, MisHeuristic::Power] {
            for (light_samples, indirect_samples, terms) in
                [(1, 1, base.terms), (4, 1, base.terms), (1, 4, course)]
            {
                sets.push(RenderSettings {
                    light_sampling: LightSampling::Mis,
                    mis_heuristic,
                    light_samples,
                    indirect_samples,
                    terms,
                    ..base.clone()
                });
            }
        }
        for light_sampling in [
            LightSampling::Area,
            LightSampling::SolidAngle,
            LightSampling::Brdf,
        ] {
            sets.push(RenderSettings {
                light_sampling,
                ..base.clone()
            });
        }
        let (mut largest_bias_in_tolerances, mut largest_z) = (0.0f64, 0.0f64);
        for settings in &sets {
            let context = RenderContext::new(scene.clone(), settings.clone());
            for (k, &(p, wo)) in views.iter().enumerate() {
                let ray = Ray::new((p + 2.0 * wo).as_vec3(), (-wo).as_vec3(), f32::INFINITY);
                let measured = estimate(&context, ray, Term::L1, SAMPLES, 7 + k as u64);
                let expected = expected_l1(p, wo, &phong);
                let what = format!(
                    "n {exponent}, view {k}, {} {} N={} M={}",
                    settings.light_sampling,
                    settings.mis_heuristic,
                    settings.light_samples,
                    settings.indirect_samples
                );
                assert_agrees(&what, measured, expected, 4.5, SYSTEMATIC);
                largest_z = largest_z.max((measured.0 - expected).abs() / measured.1);
                if settings.light_sampling == LightSampling::Mis {
                    let tolerance = 4.5 * measured.1 + SYSTEMATIC * expected;
                    let bias = one_sided_bias(p, wo, &phong);
                    largest_bias_in_tolerances = largest_bias_in_tolerances.max(bias / tolerance);
                }
            }
        }
        eprintln!(
            "n {exponent}: largest |z| {largest_z:.2}; a one-sided heuristic would move L1 by up to {largest_bias_in_tolerances:.0} tolerances"
        );
        assert!(
            largest_bias_in_tolerances > 10.0,
            "n {exponent}: a one-sided heuristic would move L1 by only {largest_bias_in_tolerances:.1} tolerances"
        );
    }
}
