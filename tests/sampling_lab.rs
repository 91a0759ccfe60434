//! The sampling lab at a point of a real scene: every strategy the
//! estimators draw with passes the χ² test against its own density (light
//! sampling by area and by solid angle, quad and sphere lights, BRDF
//! sampling of Lambert and Phong, uniform and cosine continuations), and
//! the same test rejects a wrong density (uniform, cos θ, the light's
//! cosine forgotten). Fixed seeds: the verdicts are deterministic.

use glam::Vec2;

use lumiere::analysis::hemisphere::ShadingPoint;
use lumiere::analysis::sampling_lab::{Against, LabError, SamplingLab, sampling_lab};
use lumiere::analysis::strategy_samples::Strategy;
use lumiere::course::{IndirectSampling, LightMode, LightSampling};
use lumiere::scene::builtin;
use lumiere::{BrdfOverride, RenderContext, RenderSettings, Term, TermSet};

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;
const SAMPLES: u32 = 100_000;
/// Smallest p-value a right density may show at these fixed seeds.
const ACCEPT: f64 = 1e-4;
/// Largest p-value a wrong density may show.
const REJECT: f64 = 1e-12;

fn context(scene: &str, settings: RenderSettings) -> RenderContext {
    let settings = RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        terms: TermSet::ALL,
        ..settings
    };
    RenderContext::new(builtin::load(scene).unwrap(), settings)
}

fn point(context: &RenderContext, (x, y): (u32, u32)) -> ShadingPoint {
    let ray = context.camera.generate(x, y, Vec2::splat(0.5));
    ShadingPoint::seen(context, &ray).expect("a surface at the pixel")
}

fn lab(
    context: &RenderContext,
    pixel: (u32, u32),
    term: Term,
    strategy: Strategy,
    against: Against,
) -> SamplingLab {
    let p = point(context, pixel);
    sampling_lab(context, &p, term, strategy, against, SAMPLES, 11)
        .unwrap_or_else(|e| panic!("no lab at {pixel:?}: {e}"))
}

fn assert_accepts(what: &str, lab: &SamplingLab) {
    assert!(
        lab.chi2.p_value >= ACCEPT,
        "{what}: χ² = {:.1} with {} dof, p = {:.2e}",
        lab.chi2.statistic,
        lab.chi2.dof,
        lab.chi2.p_value
    );
    assert!(lab.accepted() || lab.chi2.p_value >= ACCEPT);
}

fn assert_rejects(what: &str, lab: &SamplingLab) {
    assert!(
        lab.chi2.p_value < REJECT && !lab.accepted(),
        "{what}: p = {:.2e} should reject (χ² = {:.1}, {} dof)",
        lab.chi2.p_value,
        lab.chi2.statistic,
        lab.chi2.dof
    );
}

/// The floor, the back wall under the light and the red wall of the box;
/// the floor beside the tall box sees part of the light past its edge.
const CORNELL_PIXELS: [(u32, u32); 3] = [(32, 44), (32, 15), (10, 40)];

#[test]
fn light_sampling_draws_with_its_density() {
    for sampling in [LightSampling::Area, LightSampling::SolidAngle] {
        let cornell = context(
            "cornell",
            RenderSettings {
                light_sampling: sampling,
                ..RenderSettings::default()
            },
        );
        for pixel in CORNELL_PIXELS {
            let what = format!("{sampling:?} at {pixel:?}");
            let result = lab(&cornell, pixel, Term::L1, Strategy::Light, Against::Own);
            assert_accepts(&what, &result);
            // every direction drawn reaches the light: none lost but below the horizon
            assert!(result.density_integral > 0.0, "{what}: no density");
        }
    }
    // small sphere lights, a cone each, several lights to pick from
    let spheres = context(
        "cornell-point",
        RenderSettings {
            light_mode: LightMode::Area,
            ..RenderSettings::default()
        },
    );
    for pixel in CORNELL_PIXELS {
        let result = lab(&spheres, pixel, Term::L1, Strategy::Light, Against::Own);
        assert_accepts(&format!("sphere lights at {pixel:?}"), &result);
    }
}

#[test]
fn brdf_and_hemisphere_sampling_draw_with_their_density() {
    for brdf in [BrdfOverride::Lambert, BrdfOverride::Phong] {
        let cornell = context(
            "cornell",
            RenderSettings {
                brdf,
                ..RenderSettings::default()
            },
        );
        for pixel in CORNELL_PIXELS {
            let what = format!("{brdf:?} BRDF sampling at {pixel:?}");
            let result = lab(
                &cornell,
                pixel,
                Term::L1,
                Strategy::Directions,
                Against::Own,
            );
            assert_accepts(&what, &result);
            if brdf == BrdfOverride::Lambert {
                // cos θ / π integrates to 1 over Ω⁺: nothing is lost
                assert!(
                    (result.density_integral - 1.0).abs() < 1e-3,
                    "{what}: ∫ pdf = {}",
                    result.density_integral
                );
            }
        }
    }
    for indirect in [IndirectSampling::Uniform, IndirectSampling::Cosine] {
        let cornell = context(
            "cornell",
            RenderSettings {
                indirect_sampling: indirect,
                ..RenderSettings::default()
            },
        );
        let result = lab(
            &cornell,
            (32, 44),
            Term::L2,
            Strategy::Directions,
            Against::Own,
        );
        assert_accepts(&format!("{indirect:?} continuations"), &result);
    }
}

#[test]
fn the_lab_rejects_a_wrong_density() {
    let cornell = context("cornell", RenderSettings::default());
    let floor = (32, 44);
    let light = |against| lab(&cornell, floor, Term::L1, Strategy::Light, against);
    assert_rejects("light samples against uniform", &light(Against::Uniform));
    assert_rejects(
        "light samples by area against d²/A",
        &light(Against::WithoutLightCosine),
    );
    let phong = context(
        "cornell",
        RenderSettings {
            brdf: BrdfOverride::Phong,
            ..RenderSettings::default()
        },
    );
    let phong_lab = lab(
        &phong,
        (32, 15),
        Term::L1,
        Strategy::Directions,
        Against::Cosine,
    );
    assert_rejects("Phong BRDF sampling against cos θ/π", &phong_lab);
    // and a right density under another name is accepted: Lambert draws by cos θ
    let lambert = context(
        "cornell",
        RenderSettings {
            brdf: BrdfOverride::Lambert,
            ..RenderSettings::default()
        },
    );
    let lambert_lab = lab(
        &lambert,
        floor,
        Term::L1,
        Strategy::Directions,
        Against::Cosine,
    );
    assert_accepts("Lambert BRDF sampling against cos θ/π", &lambert_lab);
}

#[test]
fn the_bins_are_equal_in_solid_angle_and_cover_the_hemisphere() {
    let cornell = context("cornell", RenderSettings::default());
    let uniform = lab(
        &cornell,
        (32, 44),
        Term::L1,
        Strategy::Directions,
        Against::Uniform,
    );
    let bins = SamplingLab::BINS - 1;
    for bin in 0..bins {
        let probability = uniform.probabilities[bin];
        assert!(
            (probability * bins as f64 - 1.0).abs() < 1e-6,
            "bin {bin}: {probability}"
        );
    }
    let elsewhere = uniform.probabilities[bins];
    assert!(elsewhere < 1e-6, "elsewhere: {elsewhere}");
    // a map point's bin is the bin of its direction
    for (x, y) in [(0.1f32, 0.2f32), (-0.5, 0.3), (0.0, -0.9), (0.7, -0.15)] {
        let disk = Vec2::new(x, y);
        let w = lumiere::analysis::hemisphere::disk_to_direction(disk).unwrap();
        assert_eq!(SamplingLab::bin_at(disk), Some(SamplingLab::bin_of(w)));
    }
}

#[test]
fn what_cannot_be_tested_is_refused_with_the_reason() {
    let points = context("cornell-point", RenderSettings::default());
    let p = point(&points, (32, 44));
    let result = sampling_lab(&points, &p, Term::L1, Strategy::Light, Against::Own, 100, 1);
    assert_eq!(result.unwrap_err(), LabError::NoExtendedLight);
    let area_only = context(
        "cornell",
        RenderSettings {
            light_sampling: LightSampling::Area,
            ..RenderSettings::default()
        },
    );
    let p = point(&area_only, (32, 44));
    let result = sampling_lab(
        &area_only,
        &p,
        Term::L1,
        Strategy::Directions,
        Against::Own,
        100,
        1,
    );
    assert_eq!(result.unwrap_err(), LabError::NotUsed(Term::L1));
    let mirror = context(
        "cornell",
        RenderSettings {
            brdf: BrdfOverride::Mirror,
            ..RenderSettings::default()
        },
    );
    let p = point(&mirror, (32, 44));
    let result = sampling_lab(
        &mirror,
        &p,
        Term::L1,
        Strategy::Directions,
        Against::Own,
        100,
        1,
    );
    assert_eq!(result.unwrap_err(), LabError::DeltaBrdf);
}
