//! The sampling strategies of the integrator: every direct-lighting strategy
//! and every continuation distribution estimates the same closed forms, they
//! agree with each other on the Cornell box, and they differ in noise as the
//! course says.

mod common;

use std::sync::Arc;

use common::{
    F32_ROUNDING, add_floor, assert_agrees, estimate, mean_and_error, polygon_irradiance, small,
    sphere_tessellation_error,
};
use glam::Vec3;
use lumiere::course::Choice;
use lumiere::course::{IndirectSampling, LightSampling, LightSelection, MisHeuristic};
use lumiere::geometry::Ray;
use lumiere::scene::builtin::{self, furnace, point_in_sphere};
use lumiere::scene::{Material, PunctualKind, PunctualLight, Scene};
use lumiere::transport::context::RenderContext;
use lumiere::transport::counts::RayCounts;
use lumiere::transport::path_log::{PathLog, SegmentKind};
use lumiere::transport::sampler::SampleStream;
use lumiere::{Film, LightMode, RenderSettings, Term, TermSet};

const ALBEDO: f32 = 0.5;
const RADIANCE: f32 = 4.0;
const HALF_SIDE: f32 = 0.25;

// ── scenes and closed forms ───────────────────────────────────────────

/// Corners of a square light centred at `center`, facing −z (counter-clockwise seen from below).
fn light_corners(center: Vec3) -> [Vec3; 4] {
    let h = HALF_SIDE;
    [
        center + Vec3::new(-h, -h, 0.0),
        center + Vec3::new(-h, h, 0.0),
        center + Vec3::new(h, h, 0.0),
        center + Vec3::new(h, -h, 0.0),
    ]
}

/// A Lambert plane z = 0 (albedo ALBEDO, 40 m wide) under square lights of
/// the given (centre, radiance).
fn plane_under_lights(lights: &[(Vec3, f32)]) -> Scene {
    let mut scene = Scene::default();
    let floor = scene.add_material(Material::lambert("floor", Vec3::splat(ALBEDO)));
    add_floor(&mut scene, floor, 20.0);
    for (i, &(center, radiance)) in lights.iter().enumerate() {
        let material = scene.add_material(Material::emitter(
            &format!("light {i}"),
            Vec3::splat(radiance),
        ));
        scene.add_mesh(
            "light",
            material,
            &light_corners(center),
            &[[0, 1, 2], [0, 2, 3]],
        );
    }
    scene
}

/// L1 of floor point (x, y, 0) under square lights of the given (centre, radiance).
fn floor_l1(x: f32, y: f32, lights: &[(Vec3, f32)]) -> f64 {
    let p = Vec3::new(x, y, 0.0);
    lights
        .iter()
        .map(|&(c, l)| polygon_irradiance(p, Vec3::Z, &light_corners(c), l as f64))
        .sum::<f64>()
        * ALBEDO as f64
        / std::f64::consts::PI
}

/// A ray that reaches floor point (x, y, 0) from the side.
fn ray_to_floor(x: f32, y: f32) -> Ray {
    let target = Vec3::new(x, y, 0.0);
    let origin = target + Vec3::new(1.5, 0.3, 0.4);
    Ray::new(origin, (target - origin).normalize(), f32::INFINITY)
}

/// Renders a shared scene with `settings` at `spp` samples per pixel.
fn render_shared(scene: &Arc<Scene>, settings: &RenderSettings, spp: u32) -> Film {
    let context = RenderContext::new(scene.clone(), settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    let stats = lumiere::render::render(
        &context,
        &mut film,
        lumiere::render::Budget::Samples(spp),
        |_| {},
    );
    common::assert_no_invalid_samples(&stats.rays);
    film
}

/// `base` with the given strategies.
fn with(
    base: &RenderSettings,
    light_sampling: LightSampling,
    indirect_sampling: IndirectSampling,
) -> RenderSettings {
    RenderSettings {
        light_sampling,
        indirect_sampling,
        ..base.clone()
    }
}

/// A short name of the strategies of `s`, for messages.
fn describe(s: &RenderSettings) -> String {
    format!(
        "{}/{} {} N={} M={} {}",
        s.light_sampling,
        s.indirect_sampling,
        s.mis_heuristic,
        s.light_samples,
        s.indirect_samples,
        s.light_selection
    )
}

/// The strategy sets the tests run: every light strategy with BRDF
/// continuations, every continuation with MIS, and the MIS variants.
fn strategy_sets(base: &RenderSettings) -> Vec<RenderSettings> {
    let mut sets: Vec<RenderSettings> = LightSampling::all()
        .iter()
        .map(|&l| with(base, l, IndirectSampling::Brdf))
        .collect();
    for indirect in [IndirectSampling::Uniform, IndirectSampling::Cosine] {
        sets.push(with(base, LightSampling::Mis, indirect));
    }
    sets.push(RenderSettings {
        mis_heuristic: MisHeuristic::Balance,
        ..base.clone()
    });
    sets
}

/// `base` with N light samples and M continuations.
fn repeated(base: &RenderSettings, light_samples: u32, indirect_samples: u32) -> RenderSettings {
    RenderSettings {
        light_samples,
        indirect_samples,
        ..base.clone()
    }
}

// ── closed forms ─────────────────────────────────────────────────────

/// L1 of a square light over a Lambert plane (Lambert's polygon formula),
/// with every direct-lighting strategy, with N = 4 light samples, and with
/// M = 4 continuations that go on to L2 and double as MIS's gathered
/// directions (one light sample against four BRDF samples).
#[test]
fn every_light_strategy_matches_lamberts_polygon_formula() {
    let lights = [(Vec3::new(0.0, 0.0, 1.0), RADIANCE)];
    let scene = Arc::new(plane_under_lights(&lights));
    let base = small(1, 1, TermSet::only(Term::L1));
    let mut sets = strategy_sets(&base);
    for light_sampling in [
        LightSampling::Area,
        LightSampling::Hemisphere,
        LightSampling::Mis,
    ] {
        sets.push(repeated(
            &with(&base, light_sampling, IndirectSampling::Brdf),
            4,
            1,
        ));
    }
    let with_l2 = small(1, 1, "L1,L2".parse().expect("terms"));
    for mis_heuristic in [MisHeuristic::Balance, MisHeuristic::Power] {
        sets.push(RenderSettings {
            mis_heuristic,
            ..repeated(&with_l2, 1, 4)
        });
    }
    for settings in sets {
        let context = RenderContext::new(scene.clone(), settings.clone());
        for (x, y) in [(0.0, 0.0), (0.3, 0.1), (2.0, -1.0)] {
            let measured = estimate(&context, ray_to_floor(x, y), Term::L1, 20_000, 23);
            let what = format!("{} L1 at ({x}, {y})", describe(&settings));
            assert_agrees(&what, measured, floor_l1(x, y, &lights), 4.5, F32_ROUNDING);
        }
    }
}

/// Two lights of unequal power (radiance 8 and 0.5): with uniform selection
/// each is picked with probability ½, with power selection 16:1, and both
/// estimate the sum of the two polygon formulas.
#[test]
fn uniform_and_power_light_selection_agree_with_two_unequal_lights() {
    let lights = [
        (Vec3::new(0.0, 0.0, 1.0), 8.0),
        (Vec3::new(1.0, 0.5, 0.7), 0.5),
    ];
    let scene = Arc::new(plane_under_lights(&lights));
    for selection in LightSelection::all() {
        for light_sampling in [
            LightSampling::Area,
            LightSampling::SolidAngle,
            LightSampling::Mis,
        ] {
            let settings = RenderSettings {
                light_selection: selection,
                ..with(
                    &small(1, 1, TermSet::only(Term::L1)),
                    light_sampling,
                    IndirectSampling::Brdf,
                )
            };
            let context = RenderContext::new(scene.clone(), settings.clone());
            // four triangle lights: two of each quad
            let probabilities: Vec<f32> = (0..4)
                .map(|i| context.lights.selection_probability(i))
                .collect();
            let expected = match selection {
                LightSelection::Uniform => [0.25, 0.25, 0.25, 0.25],
                LightSelection::Power => [8.0 / 17.0, 8.0 / 17.0, 0.5 / 17.0, 0.5 / 17.0],
            };
            for (p, e) in probabilities.iter().zip(expected) {
                assert!((p - e).abs() < 1e-5, "{selection}: {probabilities:?}");
            }
            for (x, y) in [(0.2, 0.0), (1.0, 0.6)] {
                let measured = estimate(&context, ray_to_floor(x, y), Term::L1, 20_000, 23);
                let what = format!("{} L1 at ({x}, {y})", describe(&settings));
                assert_agrees(&what, measured, floor_l1(x, y, &lights), 4.5, F32_ROUNDING);
            }
        }
    }
}

/// A Dirac light keeps weight 1 under every strategy: the quad collapsed to
/// a cosine point gives the inverse-square law exactly, and a point light
/// beside an area light is still found by the `brdf` and `hemisphere`
/// strategies (which gather the area light).
#[test]
fn dirac_lights_are_light_sampled_by_every_strategy() {
    let center = Vec3::new(0.0, 0.0, 1.0);
    let scene = Arc::new(plane_under_lights(&[(center, RADIANCE)]));
    let area = (2.0 * HALF_SIDE as f64).powi(2);
    for light_sampling in LightSampling::all() {
        let settings = RenderSettings {
            light_mode: LightMode::Point,
            ..with(
                &small(1, 1, TermSet::only(Term::L1)),
                light_sampling,
                IndirectSampling::Brdf,
            )
        };
        let context = RenderContext::new(scene.clone(), settings);
        for (x, y) in [(0.0, 0.0), (0.8, 0.5)] {
            let p = Vec3::new(x, y, 0.0).as_dvec3();
            let d = center.as_dvec3() - p;
            let cos = d.z / d.length();
            let expected =
                ALBEDO as f64 / std::f64::consts::PI * RADIANCE as f64 * area * cos * cos
                    / d.length_squared();
            let (measured, _) = estimate(&context, ray_to_floor(x, y), Term::L1, 16, 23);
            assert!(
                (measured - expected).abs() < F32_ROUNDING * expected,
                "{light_sampling} point L1 at ({x}, {y}): {measured}, expected {expected}"
            );
        }
    }

    // an area light and a point light together
    let intensity = 3.0f32;
    let point = Vec3::new(-1.0, 0.5, 1.5);
    let mut mixed = plane_under_lights(&[(center, RADIANCE)]);
    mixed.lights.push(PunctualLight {
        name: "point".into(),
        kind: PunctualKind::Point,
        position: point,
        direction: -Vec3::Z,
        intensity: Vec3::splat(intensity),
    });
    let mixed = Arc::new(mixed);
    for light_sampling in LightSampling::all() {
        let settings = with(
            &small(1, 1, TermSet::only(Term::L1)),
            light_sampling,
            IndirectSampling::Brdf,
        );
        let context = RenderContext::new(mixed.clone(), settings.clone());
        for (x, y) in [(0.0, 0.0), (-0.6, 0.4)] {
            let d = (point - Vec3::new(x, y, 0.0)).as_dvec3();
            let from_point = ALBEDO as f64 / std::f64::consts::PI * intensity as f64 * d.z
                / d.length()
                / d.length_squared();
            let expected = floor_l1(x, y, &[(center, RADIANCE)]) + from_point;
            let measured = estimate(&context, ray_to_floor(x, y), Term::L1, 20_000, 23);
            let what = format!("{} area + point L1 at ({x}, {y})", describe(&settings));
            assert_agrees(&what, measured, expected, 4.5, F32_ROUNDING);
        }
    }
}

/// The furnace (closed sphere emitting Le, albedo ρ): L1 = ρ Le with every
/// strategy (two thousand triangle lights, near and far), L2 = ρ² Le and
/// L3+ = ρ³ Le / (1 − ρ) with every continuation distribution, with N = 4
/// light samples and with M = 4 continuations.
#[test]
fn every_strategy_matches_the_furnace() {
    let (albedo, emission) = (0.6f64, 1.5f64);
    let scene = Arc::new(furnace(albedo as f32, emission as f32));
    let expected = [
        (Term::L1, albedo * emission),
        (Term::L2, albedo.powi(2) * emission),
        (Term::L3Plus, albedo.powi(3) * emission / (1.0 - albedo)),
    ];
    for (term, value) in expected {
        let base = small(12, 12, TermSet::only(term));
        let mut sets = strategy_sets(&base);
        sets.push(repeated(&base, 4, 1));
        sets.push(repeated(&base, 1, 4));
        sets.push(repeated(
            &with(&base, LightSampling::Area, IndirectSampling::Cosine),
            4,
            4,
        ));
        sets.push(with(
            &base,
            LightSampling::Hemisphere,
            IndirectSampling::Uniform,
        ));
        for settings in sets {
            let film = render_shared(&scene, &settings, 48);
            let what = format!("furnace {term} with {}", describe(&settings));
            assert_agrees(&what, mean_and_error(&film, term), value, 4.5, F32_ROUNDING);
        }
    }
}

/// A sphere light (a point light made extended) inside a diffuse sphere:
/// L1 = ρ I / (π R²) whether the sphere is light-sampled, gathered, or both.
#[test]
fn sphere_light_strategies_match_the_closed_form() {
    let (albedo, intensity, radius, light_radius) = (0.5f64, 3.0f64, 2.0f64, 0.3f64);
    let mut scene = point_in_sphere(albedo as f32, intensity as f32, radius as f32);
    scene.cameras[0].world_from_camera = glam::Affine3A::from_rotation_translation(
        glam::Quat::from_rotation_y(std::f32::consts::PI),
        Vec3::new(0.0, 0.0, 1.0),
    );
    let tessellation = sphere_tessellation_error(&scene, radius);
    let scene = Arc::new(scene);
    let l1 = albedo * intensity / (std::f64::consts::PI * radius * radius);
    let base = RenderSettings {
        light_mode: LightMode::Area,
        light_radius: Some(light_radius as f32),
        ..small(12, 12, TermSet::only(Term::L1))
    };
    for light_sampling in [
        LightSampling::Area,
        LightSampling::Brdf,
        LightSampling::Hemisphere,
        LightSampling::Mis,
    ] {
        let settings = with(&base, light_sampling, IndirectSampling::Brdf);
        let film = render_shared(&scene, &settings, 64);
        let what = format!("sphere light L1 with {}", describe(&settings));
        let systematic = tessellation + F32_ROUNDING;
        assert_agrees(&what, mean_and_error(&film, Term::L1), l1, 4.5, systematic);
    }
}

/// MIS needs the density of a light point found by a ray to be the one
/// light sampling drew it with: for area and solid-angle sampling (near
/// lights as spherical triangles, far ones by area), uniform or power
/// selection, and sphere lights.
///
/// The two densities differ only by f32 rounding (ε = 2⁻²³). Each is about
/// ten roundings of ε/2 (selection, lengths, cosine, quotient): 10ε for the
/// pair. A triangle's area density is sel·d²/(A cos θ_l) = sel·d³/(A h), h the
/// height of p over the light's plane, the same for every point of it; the
/// point the ray hits is the sampled one moved within the plane by the
/// rounding of the two constructions, δ ≤ 4ε|p| (the ray's origin offset),
/// 2εd (its direction), 8ε|x| (two interpolations of x), each stretched by
/// d/h where the ray meets the plane, and the density moves by 3 δd/d ≤ 3δ/h:
/// in all ≤ 24ε(|p| + |x| + d)/h more. A sphere's and a spherical triangle's
/// densities are the same formula of the same p: 10ε.
#[test]
fn light_pdf_queries_match_the_sampled_densities() {
    use lumiere::geometry::accel::Hit;
    use lumiere::transport::surface::SurfacePoint;
    let mut scene = plane_under_lights(&[
        (Vec3::new(0.0, 0.0, 1.0), 8.0),
        (Vec3::new(1.0, 0.5, 0.2), 0.5),
    ]);
    scene.lights.push(PunctualLight {
        name: "point".into(),
        kind: PunctualKind::Point,
        position: Vec3::new(-1.0, 0.5, 1.5),
        direction: -Vec3::Z,
        intensity: Vec3::splat(3.0),
    });
    let scene = Arc::new(scene);
    let mut checked = [0u32; 3];
    for light_sampling in [LightSampling::Area, LightSampling::SolidAngle] {
        for light_selection in LightSelection::all() {
            let settings = RenderSettings {
                light_sampling,
                light_selection,
                light_mode: LightMode::Area,
                light_radius: Some(0.1),
                ..RenderSettings::default()
            };
            let context = RenderContext::new(scene.clone(), settings);
            for (x, y) in [(0.0, 0.0), (0.9, 0.4), (15.0, 15.0)] {
                // the floor triangle under (x, y)
                let down = Ray::new(Vec3::new(x, y, 0.1), -Vec3::Z, f32::INFINITY);
                let Some(Hit::Triangle { triangle, b, .. }) = context.accel.closest_hit(&down)
                else {
                    panic!("no floor under ({x}, {y})");
                };
                let at = SurfacePoint::new(&scene, triangle, b);
                for i in 0..2000 {
                    let s = SampleStream::new(9, 0, i);
                    let Some(light) =
                        context
                            .lights
                            .sample(&scene, &at, s.uniform(0), s.uniform2(1))
                    else {
                        continue;
                    };
                    if light.delta {
                        continue;
                    }
                    let ray = at.spawn_ray(light.wi);
                    let target = light.shadow_ray.at(1.0);
                    let hit = context
                        .accel
                        .closest_hit(&ray)
                        .expect("a light sample towards nothing");
                    if (ray.at(hit.t()) - target).length() > 1e-3 {
                        continue; // another light is in the way
                    }
                    let (found, kind, allowance) = match hit {
                        Hit::Triangle { triangle, b, .. } => {
                            let hit = SurfacePoint::new(&scene, triangle, b);
                            let pdf = context.lights.pdf_triangle(&scene, at.p, triangle, &hit);
                            let height = hit.ng.dot(hit.p - at.p).abs();
                            let lengths = at.p.length() + hit.p.length() + (hit.p - at.p).length();
                            (pdf, 0, 24.0 * lengths / height)
                        }
                        Hit::Sphere { sphere, .. } => {
                            let pdf = context.lights.sphere_emission(sphere, at.p, light.wi).1;
                            (pdf, 1, 0.0)
                        }
                    };
                    let solid_angle = light_sampling == LightSampling::SolidAngle && kind == 0;
                    checked[if solid_angle { 2 } else { kind }] += 1;
                    let tolerance = (10.0 + allowance) * f32::EPSILON;
                    assert!(
                        (found - light.pdf).abs() <= tolerance * light.pdf,
                        "{light_sampling}/{light_selection} at ({x}, {y}): sampled pdf {}, queried {found}, \
                         relative tolerance {tolerance:.1e}",
                        light.pdf
                    );
                }
            }
        }
    }
    assert!(checked.iter().all(|&n| n > 1000), "{checked:?}");
}

// ── agreement on the Cornell box ─────────────────────────────────────

/// The pixel means of `term`'s luminance, grouped into square blocks of
/// `block` × `block` pixels (row-major blocks; the image a whole number of them).
fn block_pixels(film: &Film, term: Term, block: u32) -> Vec<Vec<f64>> {
    let buffer = film.term(term).expect("term rendered");
    let (w, h) = (film.width, film.height);
    let mut blocks = Vec::new();
    for by in 0..h / block {
        for bx in 0..w / block {
            let mut pixels = Vec::new();
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    let i = (y * w + x) as usize;
                    pixels.push(lumiere::course::color::luminance(buffer.mean(i).as_vec3()) as f64);
                }
            }
            blocks.push(pixels);
        }
    }
    blocks
}

/// Every strategy renders the same L1 and the same L2 of the Cornell box:
/// image means within 4.5 standard errors of the default's, and so each
/// 16×16 quarter of the image. The strategies render with a seed other than
/// the default's, so the two images are independent.
///
/// A quarter is tested pixel by pixel: each pixel's difference of means
/// between the strategy and the default has expectation zero and the pixels
/// are independent, so the mean difference over the quarter is a z-test
/// whose standard error comes from the spread of its 256 differences. The
/// test needs that mean to be nearly normal: where the light is seen
/// edge-on a gathered direction finds it once in hundreds, and the block
/// must hold enough samples (16 384 here) to draw those rare hits many
/// times; an 8×8 block's 4 096 do not, and its mean is too skewed.
#[test]
fn all_strategies_agree_on_the_cornell_box() {
    // the side of a quarter of the 32×32 image
    const QUARTER: u32 = 16;
    let scene = Arc::new(builtin::cornell());
    for term in [Term::L1, Term::L2] {
        let base = small(32, 32, TermSet::only(term));
        let reference = render_shared(&scene, &base, 64);
        let (reference_mean, reference_error) = mean_and_error(&reference, term);
        let reference_blocks = block_pixels(&reference, term, QUARTER);
        let mut sets = strategy_sets(&base);
        sets.remove(LightSampling::all().len() - 1); // the default itself
        sets.push(repeated(&base, 4, 4));
        for settings in sets {
            let settings = RenderSettings {
                seed: base.seed + 1,
                ..settings
            };
            let film = render_shared(&scene, &settings, 64);
            let (mean, error) = mean_and_error(&film, term);
            let combined = (error * error + reference_error * reference_error).sqrt();
            let z = (mean - reference_mean) / combined;
            assert!(
                z.abs() < 4.5,
                "Cornell {term} with {}: {mean:.5} ± {error:.1e}, default {reference_mean:.5} ± {reference_error:.1e} (z = {z:.2})",
                describe(&settings)
            );
            for (i, (block, reference)) in block_pixels(&film, term, QUARTER)
                .iter()
                .zip(&reference_blocks)
                .enumerate()
            {
                let (difference, error) = common::paired_difference(block, reference);
                let z = difference / error.max(1e-12);
                assert!(
                    z.abs() < 4.5,
                    "Cornell {term} block {i} with {}: differs from the default by {difference:.2e} ± {error:.1e} (z = {z:.2})",
                    describe(&settings),
                );
            }
        }
    }
}

/// The course's lesson on noise: at equal samples, direct lighting of the
/// Cornell box is less noisy when the light is sampled (`area`,
/// `solid-angle`, `mis`) than when directions drawn uniformly
/// (`hemisphere`) or by the BRDF (`brdf`) have to find it.
///
/// Noise is a pixel's variance of the mean, its squared standard error.
/// Pixel by pixel the difference of those between two strategies estimates
/// the difference of their variances; pixels are independent, so the mean
/// difference over the image is a one-sided z-test that the light-sampled
/// variance is lower. (A pixel whose samples all missed the light's rare
/// hits reports too little variance for `hemisphere` and `brdf`: that makes
/// the test harder to pass, not easier.)
#[test]
fn light_sampling_is_less_noisy_than_hemisphere_sampling() {
    let scene = Arc::new(builtin::cornell());
    let base = small(32, 32, TermSet::only(Term::L1));
    let variances = |light_sampling| {
        let settings = with(&base, light_sampling, IndirectSampling::Brdf);
        let film = render_shared(&scene, &settings, 32);
        let buffer = film.term(Term::L1).expect("L1");
        (0..film.pixel_count())
            .map(|i| buffer.standard_error(i).powi(2))
            .collect::<Vec<f64>>()
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let gathered = [LightSampling::Hemisphere, LightSampling::Brdf].map(|l| (l, variances(l)));
    for light_sampling in [
        LightSampling::Area,
        LightSampling::SolidAngle,
        LightSampling::Mis,
    ] {
        let sampled = variances(light_sampling);
        for (gathering, gathered) in &gathered {
            let (lowered, error) = common::paired_difference(gathered, &sampled);
            let z = lowered / error;
            assert!(
                z > 4.5,
                "{light_sampling}: mean variance {:.2e}, {gathering} {:.2e} (z = {z:.2})",
                mean(&sampled),
                mean(gathered)
            );
        }
    }
}

// ── work and path recording ──────────────────────────────────────────

/// Rays are spent only where a strategy needs them: light-only strategies
/// trace no gathered direction and, for L1 alone, no continuation;
/// gathering-only strategies trace no shadow ray to an area light; the
/// defaults reuse the continuation as the gathered direction.
#[test]
fn strategies_trace_only_the_rays_they_use() {
    let rays = |settings: &RenderSettings| {
        common::render_with_stats(builtin::cornell(), settings, 2)
            .1
            .rays
    };
    let l1 = small(16, 12, TermSet::only(Term::L1));
    let area = rays(&with(&l1, LightSampling::Area, IndirectSampling::Brdf));
    assert_eq!((area.gather, area.bounce), (0, 0), "{area:?}");
    assert!(area.shadow > 0);
    let brdf = rays(&with(&l1, LightSampling::Brdf, IndirectSampling::Brdf));
    assert_eq!((brdf.shadow, brdf.gather), (0, 0), "{brdf:?}");
    assert!(
        brdf.bounce > 0,
        "the continuation is the gathered direction"
    );
    let defaults = rays(&small(16, 12, TermSet::COURSE));
    assert_eq!(defaults.gather, 0, "{defaults:?}");
    let cosine = rays(&with(
        &small(16, 12, TermSet::COURSE),
        LightSampling::Mis,
        IndirectSampling::Cosine,
    ));
    assert!(cosine.gather > 0, "{cosine:?}");
    assert_eq!(cosine.per_term.iter().sum::<u64>(), cosine.total());
}

/// A recorded sample returns what an unrecorded one does, its segments'
/// contributions sum to it term by term, and it logs one segment per ray.
#[test]
fn recorded_paths_add_up_to_the_sample() {
    let scene = Arc::new(builtin::cornell());
    let base = small(24, 24, TermSet::ALL);
    let mut sets = strategy_sets(&base);
    sets.push(repeated(&base, 3, 2));
    sets.push(repeated(
        &with(&base, LightSampling::Hemisphere, IndirectSampling::Uniform),
        2,
        3,
    ));
    // a pixel that sees the light, and three that see walls, blocks and floor
    let l0 = render_shared(&scene, &small(24, 24, TermSet::only(Term::L0)), 1);
    let light = (0..24 * 24)
        .find(|&i| l0.term(Term::L0).unwrap().mean(i).x > 0.0)
        .expect("the light is in view") as u32;
    let pixels = [(light % 24, light / 24), (5, 18), (20, 9), (12, 20)];
    let mut nonzero = [false; Term::COUNT];
    for settings in sets {
        let context = RenderContext::new(scene.clone(), settings.clone());
        for (i, (x, y)) in pixels.into_iter().enumerate() {
            for sample in 0..8 {
                let stream = SampleStream::new(5, i as u64, sample);
                let mut counts = RayCounts::default();
                let plain = lumiere::transport::sample_pixel(
                    &context,
                    x,
                    y,
                    &stream,
                    context.settings.terms,
                    &mut counts,
                );
                let mut recorded_counts = RayCounts::default();
                let mut log = PathLog::default();
                let radiance = lumiere::transport::sample_pixel_logged(
                    &context,
                    x,
                    y,
                    &stream,
                    &mut recorded_counts,
                    &mut log,
                );
                assert_eq!(radiance, plain, "{}", describe(&settings));
                assert_eq!(recorded_counts, counts);
                common::assert_no_invalid_samples(&counts);
                assert_eq!(log.segments.len() as u64, counts.total());
                let camera = log
                    .segments
                    .iter()
                    .filter(|s| s.kind == SegmentKind::Camera)
                    .count();
                assert_eq!(camera, 1);
                let sums = log.radiance();
                for term in Term::ALL {
                    let (sum, value) = (sums[term.index()], radiance[term.index()]);
                    assert!(
                        (sum - value).abs().max_element() <= 1e-5 * value.abs().max_element(),
                        "{} {term}: segments sum to {sum}, sample {value}",
                        describe(&settings)
                    );
                    nonzero[term.index()] |= value.max_element() > 0.0;
                }
            }
        }
    }
    assert_eq!(nonzero, [true; Term::COUNT], "every term was exercised");
}
