//! Work the settings and the scene make unnecessary is not done, and is counted.

mod common;

use std::f64::consts::PI;

use common::small;
use glam::Vec3;
use lumiere::course::LightSampling;
use lumiere::geometry::accel::Hit;
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::transport::counts::RayCounts;
use lumiere::transport::sampler::{SampleStream, dim};
use lumiere::{Film, LightMode, RenderContext, RenderSettings, Term, TermSet};

fn rays_of(settings: &RenderSettings, spp: u32) -> RayCounts {
    let context = RenderContext::new(builtin::cornell(), settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    let rays = render(&context, &mut film, Budget::Samples(spp), |_| {}).rays;
    common::assert_no_invalid_samples(&rays);
    rays
}

#[test]
fn l0_and_l1_with_area_sampling_trace_no_bounce_and_count_each_one_skipped() {
    let mut settings = small(32, 24, TermSet::only(Term::L0).with(Term::L1, true));
    settings.light_sampling = LightSampling::Area;
    let rays = rays_of(&settings, 4);
    assert_eq!(rays.bounce, 0);
    assert_eq!(rays.gather, 0);
    // every first vertex had no use for a continuation; each drew at most one
    // light sample (none on the light itself, which cannot see itself)
    let light_samples = rays.shadow + rays.skipped.shadow_rays;
    assert!(rays.skipped.shadow_rays > 0, "{rays:?}");
    assert!(
        rays.skipped.continuations >= light_samples && light_samples > 0,
        "{rays:?}"
    );
    assert_eq!(rays.skipped.direct_lighting, 0);
}

#[test]
fn l2_alone_estimates_no_direct_lighting_at_the_first_hit() {
    let rays = rays_of(&small(32, 24, TermSet::only(Term::L2)), 4);
    assert_eq!(rays.per_term[Term::L1.index()], 0, "{rays:?}");
    // one skipped estimate per first vertex: as many as an L1 render skips
    // continuations there (same camera rays)
    let mut l1 = small(32, 24, TermSet::only(Term::L1));
    l1.light_sampling = LightSampling::Area;
    let l1 = rays_of(&l1, 4);
    assert!(rays.skipped.direct_lighting > 0);
    assert_eq!(rays.skipped.direct_lighting, l1.skipped.continuations);
}

#[test]
fn point_lights_gather_no_direction_and_count_the_ones_skipped() {
    let mut settings = small(32, 24, TermSet::COURSE);
    settings.light_mode = LightMode::Point;
    let rays = rays_of(&settings, 4);
    assert_eq!(rays.gather, 0);
    assert!(rays.skipped.gathered > 0, "{rays:?}");
    // and with the area light, nothing is skipped for that reason
    let area = rays_of(&small(32, 24, TermSet::COURSE), 4);
    assert_eq!(area.skipped.gathered, 0);
    assert_eq!(area.skipped.roulette, 0, "roulette starts after L2");
}

#[test]
fn russian_roulette_ends_some_l3_paths() {
    let rays = rays_of(&small(32, 24, TermSet::ALL), 4);
    assert!(rays.skipped.roulette > 0, "{rays:?}");
    assert!(rays.skipped.describe().contains("Russian roulette"));
}

/// Russian roulette starts after the fourth reflection: capped at three
/// reflections (their last continuation traced only to find the emitter)
/// no path is ended by it, capped at four some are.
#[test]
fn russian_roulette_starts_after_the_fourth_reflection() {
    let roulette = |max_bounces: u32| {
        let mut settings = small(16, 16, TermSet::ALL);
        settings.max_bounces = max_bounces;
        let context = RenderContext::new(builtin::furnace(0.6, 1.0), settings.clone());
        let mut film = Film::new(settings.width, settings.height);
        let rays = render(&context, &mut film, Budget::Samples(4), |_| {}).rays;
        common::assert_no_invalid_samples(&rays);
        assert!(rays.bounce >= 2 * rays.camera, "{rays:?}");
        rays.skipped.roulette
    };
    assert_eq!(roulette(3), 0);
    assert!(roulette(4) > 0);
}

/// Under `mis` with L0 and L1 only, each first vertex's one continuation
/// only looks for a light, and searches the scene only if it meets one.
///
/// A cosine-distributed direction from a point p of normal n meets the light
/// polygons (occluded or not) with probability F(p) = E(p)/π, E the
/// irradiance from the polygons at radiance 1 clipped to p's hemisphere
/// (Lambert's formula, `polygon_irradiance`). Given the camera samples'
/// first vertices the searches are independent draws, so their count has
/// mean Σ F and variance Σ F(1 − F): a z-test of the searches made. The
/// light is small (Σ F ≈ 50 of about 8500 searches at 16 samples per pixel),
/// so skipping every search would be z ≈ −7.
#[test]
fn light_searches_that_meet_no_light_skip_the_scene_search_and_are_counted() {
    let settings = small(32, 24, TermSet::only(Term::L0).with(Term::L1, true));
    let context = RenderContext::new(builtin::cornell(), settings.clone());
    let scene = &context.scene;
    let lights: Vec<[Vec3; 3]> = scene
        .triangles
        .iter()
        .filter(|t| scene.materials[t.material as usize].is_emissive())
        .map(|t| t.vertices.map(|v| scene.positions[v as usize]))
        .collect();
    let (mut searches, mut scene_searches) = (0u64, 0u64);
    let (mut expected_searches, mut expected_scene_searches, mut variance) = (0u64, 0.0, 0.0);
    for pixel in 0..(settings.width * settings.height) {
        let (x, y) = (pixel % settings.width, pixel / settings.width);
        for sample in 0..16 {
            let stream = SampleStream::new(settings.seed, pixel as u64, sample);
            let mut rays = RayCounts::default();
            lumiere::transport::sample_pixel(
                &context,
                x,
                y,
                &stream,
                context.settings.terms,
                &mut rays,
            );
            common::assert_no_invalid_samples(&rays);
            searches += rays.bounce;
            scene_searches += rays.bounce - rays.skipped.scene_searches;

            // the same camera ray, and where it lands
            let ray = context.camera.generate(x, y, stream.uniform2(dim::PIXEL));
            let Some(Hit::Triangle { t, triangle, .. }) = context.accel.closest_hit(&ray) else {
                continue;
            };
            let triangle = &scene.triangles[triangle as usize];
            if scene.materials[triangle.material as usize].is_emissive() {
                continue; // the light reflects nothing: no continuation
            }
            let [a, b, c] = triangle.vertices.map(|v| scene.positions[v as usize]);
            let normal = (b - a).cross(c - a).normalize();
            let normal = if normal.dot(ray.direction) > 0.0 {
                -normal
            } else {
                normal
            };
            let p = ray.at(t);
            let f: f64 = lights
                .iter()
                .map(|light| {
                    let visible = clip_to_hemisphere(light, p, normal);
                    if visible.len() < 3 {
                        0.0
                    } else {
                        common::polygon_irradiance(p, normal, &visible, 1.0) / PI
                    }
                })
                .sum();
            expected_searches += 1;
            expected_scene_searches += f;
            variance += f * (1.0 - f);
        }
    }
    assert_eq!(searches, expected_searches, "one search per first vertex");
    let z = (scene_searches as f64 - expected_scene_searches) / variance.sqrt();
    assert!(
        z.abs() <= 4.5,
        "{scene_searches} of {searches} searches searched the scene, \
         {expected_scene_searches:.1} expected (z = {z:.2})"
    );

    // in a furnace everything emits: the search is the plain closest hit
    let furnace = RenderContext::new(builtin::furnace(0.5, 1.0), settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    let rays = render(&furnace, &mut film, Budget::Samples(4), |_| {}).rays;
    common::assert_no_invalid_samples(&rays);
    assert!(rays.bounce > 0, "{rays:?}");
    assert_eq!(rays.skipped.scene_searches, 0, "{rays:?}");
}

/// The part of `polygon` on the side of the plane through `p` that `normal`
/// points to (Sutherland–Hodgman).
fn clip_to_hemisphere(polygon: &[Vec3], p: Vec3, normal: Vec3) -> Vec<Vec3> {
    let height = |v: Vec3| normal.dot(v - p);
    let mut clipped = Vec::new();
    for (i, &a) in polygon.iter().enumerate() {
        let b = polygon[(i + 1) % polygon.len()];
        let (ha, hb) = (height(a), height(b));
        if ha > 0.0 {
            clipped.push(a);
        }
        if (ha > 0.0) != (hb > 0.0) {
            clipped.push(a + (b - a) * (ha / (ha - hb)));
        }
    }
    clipped
}
