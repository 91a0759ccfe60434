//! The lecture integrator (`transport/lecture.rs`) against the fast one,
//! term by term: two unbiased estimators of the same terms must agree in
//! the mean. Each scene is rendered by both, with independent seeds, and the
//! image means of every term are compared by a z-test on their difference.
//! This holds the fast integrator (MIS, splitting, skipped work) to the
//! lecture's plain estimator, and the lecture's to the fast one's, on every
//! light kind (area, point, spot, directional, sphere) and every BRDF.

mod common;

use std::path::Path;

use glam::Vec3;
use lumiere::course::Choice;
use lumiere::course::{Adaptive, Integrator, LightSampling, Sampler};
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::scene::{Material, PunctualKind, PunctualLight};
use lumiere::transport::continuations::{Continuations, SplitMap};
use lumiere::transport::splitting::choose_continuations;
use lumiere::{BrdfOverride, Film, LightMode, RenderContext, RenderSettings, Scene, Term, TermSet};

use common::{add_floor, assert_no_invalid_samples, mean_and_error, render_film};

/// Two estimates of one mean disagree beyond chance past this |z|: a
/// correct pair does with probability 6.8·10⁻⁶, so over the 250 or so
/// comparisons here about 2·10⁻³ (with fixed seeds: once and for all).
const Z_LIMIT: f64 = 4.5;

/// The image means of every term under both integrators, compared.
fn assert_integrators_agree(what: &str, scene: &Scene, settings: &RenderSettings, spp: u32) {
    assert_fast_agrees_with_lecture(what, scene, settings, settings, spp, |_| {});
}

/// The image means of every term, rendered by the fast integrator with
/// `fast` (its context then set up by `prepare`) and by the lecture
/// integrator with `lecture`, compared.
fn assert_fast_agrees_with_lecture(
    what: &str,
    scene: &Scene,
    fast: &RenderSettings,
    lecture: &RenderSettings,
    spp: u32,
    prepare: impl Fn(&mut RenderContext),
) {
    let render_with = |settings: &RenderSettings, integrator, seed| {
        let settings = RenderSettings {
            integrator,
            seed: seed + settings.seed,
            terms: TermSet::ALL,
            ..settings.clone()
        };
        let mut context = RenderContext::new(scene.clone(), settings.clone());
        prepare(&mut context);
        let mut film = Film::new(settings.width, settings.height);
        let stats = render(&context, &mut film, Budget::Samples(spp), |_| {});
        assert_no_invalid_samples(&stats.rays);
        film
    };
    let fast = render_with(fast, Integrator::Fast, 11);
    let lecture = render_with(lecture, Integrator::Lecture, 12);
    for term in Term::ALL {
        let (fast_mean, fast_error) = mean_and_error(&fast, term);
        let (lecture_mean, lecture_error) = mean_and_error(&lecture, term);
        let error = (fast_error.powi(2) + lecture_error.powi(2)).sqrt();
        let z = (fast_mean - lecture_mean) / error.max(1e-30);
        // a term that is zero in both is zero in both exactly
        if fast_mean == 0.0 && lecture_mean == 0.0 {
            continue;
        }
        assert!(
            z.abs() < Z_LIMIT,
            "{what}, {}: fast {fast_mean:.6} ± {fast_error:.1e}, lecture {lecture_mean:.6} ± {lecture_error:.1e}, z = {z:.2}",
            term.label()
        );
    }
}

fn settings(width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        ..RenderSettings::default()
    }
}

fn data_scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    builtin::load(path.to_str().unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

/// An open scene lit by one light of each punctual kind: a floor, a grey
/// block on it and a mirror-like panel, under the sun, a point light and a
/// spot light.
fn punctual_scene() -> Scene {
    let mut scene = Scene {
        name: "punctual".into(),
        ..Scene::default()
    };
    let floor = scene.add_material(Material::lambert("floor", Vec3::new(0.7, 0.6, 0.5)));
    add_floor(&mut scene, floor, 2.0);
    let grey = scene.add_material(Material {
        roughness: 0.4,
        metallic: 0.0,
        ..Material::lambert("block", Vec3::splat(0.6))
    });
    // a block 0.6 wide and 0.5 tall on the floor (z up)
    let (s, h) = (0.3, 0.5);
    let corners = [
        Vec3::new(-s, -s, 0.0),
        Vec3::new(s, -s, 0.0),
        Vec3::new(s, s, 0.0),
        Vec3::new(-s, s, 0.0),
        Vec3::new(-s, -s, h),
        Vec3::new(s, -s, h),
        Vec3::new(s, s, h),
        Vec3::new(-s, s, h),
    ];
    let faces = [
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    scene.add_mesh("block", grey, &corners, &faces);
    let mirror = scene.add_material(Material::mirror("panel", Vec3::splat(0.8)));
    let panel = [
        Vec3::new(-1.5, 1.2, 0.0),
        Vec3::new(1.5, 1.2, 0.0),
        Vec3::new(1.5, 1.2, 1.2),
        Vec3::new(-1.5, 1.2, 1.2),
    ];
    scene.add_mesh("panel", mirror, &panel, &[[0, 2, 1], [0, 3, 2]]);
    let light = |name: &str, kind, position, direction: Vec3, intensity| PunctualLight {
        name: name.into(),
        kind,
        position,
        direction: direction.normalize(),
        intensity,
    };
    scene.lights = vec![
        light(
            "sun",
            PunctualKind::Directional,
            Vec3::ZERO,
            Vec3::new(0.3, 0.4, -1.0),
            Vec3::splat(1.5),
        ),
        light(
            "point",
            PunctualKind::Point,
            Vec3::new(-0.8, -0.6, 1.0),
            Vec3::NEG_Z,
            Vec3::new(2.0, 1.5, 1.0),
        ),
        light(
            "spot",
            PunctualKind::Spot {
                inner_cone_angle: 0.3,
                outer_cone_angle: 0.6,
            },
            Vec3::new(0.6, -0.8, 1.4),
            Vec3::new(-0.2, 0.3, -1.0),
            Vec3::splat(4.0),
        ),
    ];
    scene
}

#[test]
fn the_integrators_agree_on_the_cornell_box_under_every_light_mode_and_brdf() {
    for light_mode in LightMode::all() {
        for brdf in BrdfOverride::all() {
            let settings = RenderSettings {
                light_mode,
                brdf,
                ..settings(24, 18)
            };
            let what = format!("cornell, lights {light_mode}, brdf {brdf}");
            assert_integrators_agree(&what, &builtin::cornell(), &settings, 512);
        }
    }
}

#[test]
fn the_integrators_agree_on_every_test_scene() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".gltf"))
        .collect();
    names.sort();
    assert!(names.len() >= 8, "{names:?}");
    for name in names {
        let scene = data_scene(&name);
        for light_mode in LightMode::all() {
            let settings = RenderSettings {
                light_mode,
                ..settings(24, 18)
            };
            let what = format!("{name}, lights {light_mode}");
            assert_integrators_agree(&what, &scene, &settings, 512);
        }
    }
}

/// Glass: the Cornell box's glass block under every light mode (the
/// caustics of a point light cannot be found by either), and a block half
/// glass, half Lambert (glTF transmission 0.5), each a Dirac that neither
/// integrator can sample a light from.
#[test]
fn the_integrators_agree_through_glass() {
    let glass_box = builtin::load("cornell-glass").unwrap();
    for light_mode in LightMode::all() {
        let settings = RenderSettings {
            light_mode,
            ..settings(24, 18)
        };
        let what = format!("cornell-glass, lights {light_mode}");
        assert_integrators_agree(&what, &glass_box, &settings, 512);
    }
    let mut half = glass_box.clone();
    for material in &mut half.materials {
        if material.transmission > 0.0 {
            material.transmission = 0.5;
            material.roughness = 1.0;
            material.base_color = Vec3::new(0.9, 0.6, 0.3);
        }
    }
    assert_integrators_agree("cornell, block half glass", &half, &settings(24, 18), 512);
}

#[test]
fn the_integrators_agree_under_the_sun_a_point_and_a_spot_light() {
    let scene = punctual_scene();
    for light_mode in [LightMode::Authored, LightMode::Area] {
        for brdf in BrdfOverride::all() {
            let settings = RenderSettings {
                light_mode,
                brdf,
                light_radius: Some(0.15),
                ..settings(24, 18)
            };
            let what = format!("punctual, lights {light_mode}, brdf {brdf}");
            assert_integrators_agree(&what, &scene, &settings, 512);
        }
    }
}

/// The fast integrator's other estimators (strategies, samplers, splitting)
/// keep the lecture's means too.
#[test]
fn the_fast_integrators_strategies_agree_with_the_lecture() {
    let scene = data_scene("cornell-glossy.gltf");
    for light_sampling in LightSampling::all() {
        let settings = RenderSettings {
            light_sampling,
            sampler: Sampler::Sobol,
            indirect_samples: 2,
            ..settings(24, 18)
        };
        let what = format!("cornell-glossy, light sampling {light_sampling}");
        assert_integrators_agree(&what, &scene, &settings, 1024);
    }
}

/// The fast integrator's sampling options whose own tests check only
/// convergence to lumiere's renders keep the lecture's means too: the
/// stratified sampler, adaptive sampling (a pixel stops on its own error
/// estimate), a map of continuation counts (1 and 8 in a checkerboard of
/// regions) and the pilot's automatic choice of counts.
#[test]
fn the_fast_integrators_sampling_options_agree_with_the_lecture() {
    let scene = builtin::cornell();
    // plain Monte Carlo, each option changed from there
    let base = RenderSettings {
        sampler: Sampler::Independent,
        auto_indirect_samples: false,
        ..settings(24, 18)
    };
    let stratified = RenderSettings {
        sampler: Sampler::Stratified,
        ..base.clone()
    };
    assert_integrators_agree("cornell, stratified", &scene, &stratified, 1024);
    let adaptive = RenderSettings {
        adaptive: Some(Adaptive {
            threshold: 0.02,
            min_samples: 64,
        }),
        ..base.clone()
    };
    assert_fast_agrees_with_lecture("cornell, adaptive", &scene, &adaptive, &base, 1024, |_| {});
    let map = SplitMap {
        width: 24,
        height: 18,
        columns: 4,
        rows: 3,
        counts: (0..12)
            .map(|i| if (i + i / 4) % 2 == 0 { 8 } else { 1 })
            .collect(),
    };
    let split = |context: &mut RenderContext| {
        if context.settings.integrator == Integrator::Fast {
            context.continuations = Continuations {
                count: 1,
                map: Some(std::sync::Arc::new(map.clone())),
            };
        }
    };
    assert_fast_agrees_with_lecture("cornell, map ×1/×8", &scene, &base, &base, 512, split);
    let auto = RenderSettings {
        auto_indirect_samples: true,
        ..base.clone()
    };
    assert_fast_agrees_with_lecture("cornell, auto", &scene, &auto, &base, 512, |context| {
        choose_continuations(context)
    });
}

/// A z-test that cannot fail proves nothing: the fast integrator's L1 is
/// compared with the lecture's under a light 5% brighter, and the same
/// test must reject it.
#[test]
fn the_comparison_rejects_a_wrong_mean() {
    let settings = RenderSettings {
        terms: TermSet::only(Term::L1),
        ..settings(24, 18)
    };
    let fast = render_film(builtin::cornell(), &settings, 128);
    let mut brighter = builtin::cornell();
    for material in &mut brighter.materials {
        material.emission *= 1.05;
    }
    let lecture = render_film(
        brighter,
        &RenderSettings {
            integrator: Integrator::Lecture,
            seed: 5,
            ..settings
        },
        128,
    );
    let (a, ea) = mean_and_error(&fast, Term::L1);
    let (b, eb) = mean_and_error(&lecture, Term::L1);
    let z = (a - b) / (ea * ea + eb * eb).sqrt();
    assert!(z.abs() > Z_LIMIT, "a 5% brighter light passed: z = {z:.2}");
}
