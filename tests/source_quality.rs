//! A quality for each source: every source on or off, with its own number
//! of light samples, checked against closed forms (Lambert's polygon
//! formula, the inverse-square law) with counts that differ, in both
//! integrators.

mod common;

use common::{add_floor, estimate, polygon_irradiance};

use glam::Vec3;
use lumiere::course::{Integrator, LightSampling, SourceQuality};
use lumiere::geometry::Ray;
use lumiere::scene::{Material, PunctualKind, PunctualLight, Scene};
use lumiere::transport::context::RenderContext;
use lumiere::transport::counts::RayCounts;
use lumiere::transport::sampler::SampleStream;
use lumiere::{RenderSettings, Term, TermSet};

const ALBEDO: f64 = 0.5;

/// A square light of radiance `radiance`, half side `h`, centred on `c`, facing −z.
struct Quad {
    name: &'static str,
    center: Vec3,
    half_side: f32,
    radiance: f32,
}

impl Quad {
    fn corners(&self) -> [Vec3; 4] {
        let h = self.half_side;
        [
            self.center + Vec3::new(-h, -h, 0.0),
            self.center + Vec3::new(-h, h, 0.0),
            self.center + Vec3::new(h, h, 0.0),
            self.center + Vec3::new(h, -h, 0.0),
        ]
    }
}

const BIG: Quad = Quad {
    name: "big",
    center: Vec3::new(0.0, 0.0, 1.0),
    half_side: 0.25,
    radiance: 4.0,
};
const SMALL: Quad = Quad {
    name: "small",
    center: Vec3::new(0.7, 0.2, 0.8),
    half_side: 0.08,
    radiance: 30.0,
};
const BULB_POSITION: Vec3 = Vec3::new(-0.5, 0.4, 1.5);
const BULB_INTENSITY: f32 = 3.0;

/// A Lambert floor under two square lights of their own materials and a point light.
fn three_sources() -> Scene {
    let mut scene = Scene::default();
    let floor = scene.add_material(Material::lambert("floor", Vec3::splat(ALBEDO as f32)));
    add_floor(&mut scene, floor, 20.0);
    for quad in [BIG, SMALL] {
        let material = scene.add_material(Material::emitter(quad.name, Vec3::splat(quad.radiance)));
        scene.add_mesh(
            quad.name,
            material,
            &quad.corners(),
            &[[0, 1, 2], [0, 2, 3]],
        );
    }
    scene.lights.push(PunctualLight {
        name: "bulb".into(),
        kind: PunctualKind::Point,
        position: BULB_POSITION,
        direction: -Vec3::Z,
        intensity: Vec3::splat(BULB_INTENSITY),
    });
    scene
}

/// L1 at floor point p from the sources `on` names: ρ/π Σ E_s.
fn expected_l1(p: Vec3, on: &[&str]) -> f64 {
    let mut irradiance = 0.0;
    for quad in [BIG, SMALL] {
        if on.contains(&quad.name) {
            irradiance += polygon_irradiance(p, Vec3::Z, &quad.corners(), quad.radiance as f64);
        }
    }
    if on.contains(&"bulb") {
        let d = (BULB_POSITION - p).as_dvec3();
        irradiance += BULB_INTENSITY as f64 * (d.z / d.length()) / d.length_squared();
    }
    ALBEDO / std::f64::consts::PI * irradiance
}

/// A ray that reaches floor point (x, y, 0) from the side.
fn ray_to_floor(x: f32, y: f32) -> Ray {
    let target = Vec3::new(x, y, 0.0);
    let origin = target + Vec3::new(1.5, 0.3, 0.4);
    Ray::new(origin, (target - origin).normalize(), f32::INFINITY)
}

const POINTS: [(f32, f32); 3] = [(0.0, 0.0), (0.6, 0.3), (-0.7, 0.6)];

fn settings(
    sources: Vec<SourceQuality>,
    sampling: LightSampling,
    integrator: Integrator,
) -> RenderSettings {
    RenderSettings {
        terms: TermSet::only(Term::L1),
        light_sampling: sampling,
        integrator,
        sources,
        ..RenderSettings::default()
    }
}

#[test]
fn counts_that_differ_keep_direct_lighting_unbiased() {
    let sources = vec![
        SourceQuality::samples("big", 1),
        SourceQuality::samples("small", 5),
        SourceQuality::samples("bulb", 2),
    ];
    for integrator in [Integrator::Fast, Integrator::Lecture] {
        for sampling in [
            LightSampling::Area,
            LightSampling::Mis,
            LightSampling::SolidAngle,
        ] {
            let context = RenderContext::new(
                three_sources(),
                settings(sources.clone(), sampling, integrator),
            );
            for (x, y) in POINTS {
                let p = Vec3::new(x, y, 0.0);
                let expected = expected_l1(p, &["big", "small", "bulb"]);
                let measured = estimate(&context, ray_to_floor(x, y), Term::L1, 20_000, 5);
                common::assert_agrees(
                    &format!("{integrator:?} {sampling:?}: L1 at ({x}, {y})"),
                    measured,
                    expected,
                    4.5,
                    common::F32_ROUNDING,
                );
            }
        }
    }
}

#[test]
fn a_source_switched_off_adds_nothing_in_any_term() {
    let sources = vec![
        SourceQuality::off("small"),
        SourceQuality::samples("big", 3),
    ];
    for integrator in [Integrator::Fast, Integrator::Lecture] {
        let context = RenderContext::new(
            three_sources(),
            settings(sources.clone(), LightSampling::Mis, integrator),
        );
        for (x, y) in POINTS {
            let p = Vec3::new(x, y, 0.0);
            let expected = expected_l1(p, &["big", "bulb"]);
            let measured = estimate(&context, ray_to_floor(x, y), Term::L1, 20_000, 7);
            common::assert_agrees(
                &format!("{integrator:?}: L1 at ({x}, {y}) without the small light"),
                measured,
                expected,
                4.5,
                common::F32_ROUNDING,
            );
        }
    }
    // seen straight on, the switched-off light is black (L0), the other is not
    let looking_up = |at: Vec3| Ray::new(Vec3::new(at.x, at.y, 0.1), Vec3::Z, f32::INFINITY);
    let all_terms = |sources| RenderSettings {
        terms: TermSet::ALL,
        sources,
        ..RenderSettings::default()
    };
    let on = RenderContext::new(three_sources(), all_terms(Vec::new()));
    let off = RenderContext::new(three_sources(), all_terms(sources));
    let (seen_on, _) = estimate(&on, looking_up(SMALL.center), Term::L0, 4, 1);
    let (seen_off, _) = estimate(&off, looking_up(SMALL.center), Term::L0, 4, 1);
    let (big_off, _) = estimate(&off, looking_up(BIG.center), Term::L0, 4, 1);
    assert_eq!(seen_on, SMALL.radiance as f64);
    assert_eq!(seen_off, 0.0, "the small light is off");
    assert_eq!(big_off, BIG.radiance as f64);
}

/// Point lights only: each sample draws every source its own number of
/// times, not a random one, so the estimate has no variance at all, and
/// a vertex casts Σ N_s shadow rays.
#[test]
fn every_source_gets_exactly_its_own_samples() {
    let mut scene = three_sources();
    scene
        .materials
        .iter_mut()
        .for_each(|m| m.emission = Vec3::ZERO);
    scene.lights.push(PunctualLight {
        name: "second bulb".into(),
        kind: PunctualKind::Point,
        position: Vec3::new(0.8, -0.3, 1.2),
        direction: -Vec3::Z,
        intensity: Vec3::splat(7.0),
    });
    let (x, y) = (0.2, 0.1);
    let p = Vec3::new(x, y, 0.0).as_dvec3();
    let expected: f64 = scene
        .lights
        .iter()
        .map(|light| {
            let d = light.position.as_dvec3() - p;
            ALBEDO / std::f64::consts::PI * light.intensity.x as f64 * (d.z / d.length())
                / d.length_squared()
        })
        .sum();
    let per_source = vec![
        SourceQuality::samples("bulb", 1),
        SourceQuality::samples("second bulb", 3),
    ];
    let context = RenderContext::new(
        scene.clone(),
        settings(per_source, LightSampling::Mis, Integrator::Fast),
    );
    let (mean, error) = estimate(&context, ray_to_floor(x, y), Term::L1, 64, 3);
    assert_eq!(error, 0.0, "a sample draws each source, not a random one");
    assert!(
        (mean - expected).abs() <= common::F32_ROUNDING * expected,
        "{mean} vs {expected}"
    );
    let mut counts = RayCounts::default();
    lumiere::transport::trace(
        &context,
        ray_to_floor(x, y),
        &SampleStream::new(3, 0, 0),
        context.settings.terms,
        &mut counts,
    );
    assert_eq!(counts.shadow, 4, "1 + 3 shadow rays");
    // sharing the same 4 samples by power picks the lights at random: noise
    let shared = RenderContext::new(
        scene,
        RenderSettings {
            light_samples: 4,
            ..settings(Vec::new(), LightSampling::Mis, Integrator::Fast)
        },
    );
    let (_, shared_error) = estimate(&shared, ray_to_floor(x, y), Term::L1, 64, 3);
    assert!(shared_error > 1e-3 * expected, "{shared_error}");
}

/// The quality of a source changes its noise, not its mean: the small,
/// bright light's shadow-ray estimate with 16 samples has about a quarter
/// of the standard error it has with 1.
#[test]
fn more_samples_on_a_source_lower_its_noise() {
    let error_with = |samples: u32| {
        let sources = vec![
            SourceQuality::samples("small", samples),
            SourceQuality::off("big"),
            SourceQuality::off("bulb"),
        ];
        let context = RenderContext::new(
            three_sources(),
            settings(sources, LightSampling::Area, Integrator::Fast),
        );
        // the small light's penumbra: under its edge, no occluder, area sampling
        estimate(&context, ray_to_floor(0.9, 0.2), Term::L1, 4_000, 9).1
    };
    let ratio = error_with(1) / error_with(16);
    assert!(
        (3.0..5.3).contains(&ratio),
        "noise ratio {ratio}, expected ≈ 4"
    );
}

#[test]
fn the_command_line_names_sources_and_refuses_unknown_ones() {
    let out = std::env::temp_dir().join("lumiere-source-quality.png");
    let run = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
            .args([
                "render", "cornell", "--width", "32", "--height", "24", "--spp", "2", "-o",
            ])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };
    let unknown = run(&["--source", "no such lamp=4"]);
    assert_eq!(unknown.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&unknown.stderr);
    assert!(
        stderr.contains("cornell") && stderr.contains("no such lamp") && stderr.contains("'light'"),
        "{stderr}"
    );
    let bad_count = run(&["--source", "light=0"]);
    assert_eq!(bad_count.status.code(), Some(2));
    // the Cornell box's only source off: every term is black
    let off = run(&["--source", "light=off", "--terms", "all"]);
    assert!(
        off.status.success(),
        "{}",
        String::from_utf8_lossy(&off.stderr)
    );
    assert_eq!(common::invalid_samples(&off), 0);
    let image = image::open(&out).unwrap().to_rgb8();
    assert!(image.pixels().all(|p| p.0 == [0, 0, 0]), "the light is off");
    let on = run(&["--source", "light=4"]);
    assert!(on.status.success());
    let image = image::open(&out).unwrap().to_rgb8();
    assert!(image.pixels().any(|p| p.0 != [0, 0, 0]));
}
