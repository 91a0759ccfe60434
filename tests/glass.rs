//! Glass: energy kept in a white furnace, rays through a slab leaving
//! parallel to themselves, closed glass objects that never let a ray out
//! unseen, and the same image whatever the thread count.

mod common;

use std::sync::Arc;

use glam::{Vec2, Vec3};
use lumiere::course::Integrator;
use lumiere::geometry::Ray;
use lumiere::geometry::accel::Hit;
use lumiere::scene::Material;
use lumiere::scene::builtin::{self, closed_box, furnace, uv_sphere};
use lumiere::transport::sampler::SampleStream;
use lumiere::transport::surface::{SurfacePoint, leaves_on_its_side};
use lumiere::{RenderContext, RenderSettings, Scene, Term, TermSet};

use common::{mean_and_error, render_film, small};

/// A scene of one glass object, `tint` and index `ior`, and no light.
fn glass_scene(positions: &[Vec3], triangles: &[[u32; 3]], tint: Vec3, ior: f32) -> Scene {
    let mut scene = Scene::default();
    let glass = scene.add_material(Material::glass("glass", tint, ior));
    scene.add_mesh("glass", glass, positions, triangles);
    scene
}

/// Inside a closed sphere that emits Le = 1 and reflects nothing, a clear
/// glass sphere (T = 1) loses nothing: reflection keeps F/F = 1, a path in
/// and out of it gets 1/η² · η² = 1, so every path that reaches the wall
/// brings 1 and every pixel's L0 + L1 + L2 + L3+ is 1 (Russian roulette
/// keeps the mean). The glass shows in L1 (the wall seen reflected in it)
/// and L2 (the wall seen through it, two refractions); both integrators.
#[test]
fn a_white_furnace_with_a_glass_sphere_keeps_its_radiance() {
    let mut scene = furnace(0.0, 1.0);
    let glass = scene.add_material(Material::glass("glass", Vec3::ONE, 1.5));
    let (positions, triangles) = uv_sphere(Vec3::new(0.0, 0.0, -0.55), 0.3, 48, 24, false);
    scene.add_mesh("glass sphere", glass, &positions, &triangles);
    for integrator in [Integrator::Fast, Integrator::Lecture] {
        let settings = RenderSettings {
            integrator,
            // a faceted sphere traps light by total internal reflection:
            // at the default cap of 64 bounces, the paths it cuts carry
            // 0.7% of the image (their roulette weights grow as 1/0.95ᵏ)
            max_bounces: 100_000,
            ..small(32, 32, TermSet::ALL)
        };
        let film = render_film(scene.clone(), &settings, 64);
        let terms = Term::ALL.map(|term| mean_and_error(&film, term));
        let total: f64 = terms.iter().map(|(mean, _)| mean).sum();
        let error = terms.iter().map(|(_, e)| e * e).sum::<f64>().sqrt();
        assert!(
            (total - 1.0).abs() <= 4.5 * error + 1e-5,
            "{integrator}: L0 + L1 + L2 + L3+ = {total:.6} ± {error:.1e}, terms {terms:?}"
        );
        // the sphere covers part of the image: its reflection (L1) and what
        // is seen through it (L2) are there, and L0 is what it leaves of the wall
        assert!(
            terms[1].0 > 0.002 && terms[2].0 > 0.05,
            "{integrator}: {terms:?}"
        );
        assert!(terms[0].0 < 0.95, "{integrator}: {terms:?}");
    }
}

/// The camera inside a clear glass ball (η = 1.5) at the centre of a black
/// furnace wall emitting E = 1: each camera ray meets the ball from inside
/// at normal incidence and leaves with probability 1 − F, F = (0.5/2.5)² =
/// 0.04, its radiance scaled by n_glass²/n_air² = 2.25 (radiance is η²
/// denser in glass: `docs/conventions.md`); the rest reflects back through
/// the centre to the opposite side, and so on. So L0 = 0 and
/// L_k = F^(k−1) (1 − F) · 2.25 for k ≥ 1, L3+ = F² · 2.25. The facets of
/// the tessellated ball tilt the incidence by up to 2°, which moves F by
/// under 10⁻⁴ of itself (F is flat at normal incidence).
#[test]
fn inside_glass_radiance_is_eta_squared_denser() {
    let mut scene = furnace(0.0, 1.0);
    let glass = scene.add_material(Material::glass("glass", Vec3::ONE, 1.5));
    let (positions, triangles) = uv_sphere(Vec3::ZERO, 0.5, 96, 48, false);
    scene.add_mesh("glass ball", glass, &positions, &triangles);
    let f = 0.04f64;
    let expected = [0.0, (1.0 - f) * 2.25, f * (1.0 - f) * 2.25, f * f * 2.25];
    for integrator in [Integrator::Fast, Integrator::Lecture] {
        let settings = RenderSettings {
            integrator,
            // a faceted sphere traps light by total internal reflection:
            // at the default cap of 64 bounces, the paths it cuts carry
            // 0.7% of the image (their roulette weights grow as 1/0.95ᵏ)
            max_bounces: 100_000,
            ..small(32, 32, TermSet::ALL)
        };
        let film = render_film(scene.clone(), &settings, 64);
        for term in Term::ALL {
            let (mean, error) = mean_and_error(&film, term);
            let exact = expected[term.index()];
            assert!(
                (mean - exact).abs() <= 4.5 * error + 1e-3 * exact + 1e-6,
                "{integrator} {term}: {mean:.6} ± {error:.1e}, expected {exact:.6}"
            );
        }
    }
}

/// A direction through glass `point`'s surface drawn by its model with the
/// pair `u`, and the ray leaving along it; `None` if none leaves.
fn interact(context: &RenderContext, hit: &Hit, ray: &Ray, u: Vec2) -> Option<(Ray, bool)> {
    let Hit::Triangle { triangle, b, .. } = *hit else {
        return None;
    };
    let point = SurfacePoint::new(&context.scene, triangle, b);
    let wo = -ray.direction;
    let brdf = point.brdf(&context.scene, &context.settings, wo);
    let (frame, ng) = point.frame_towards(wo);
    let sample = brdf.sample(frame.to_local(wo), u)?;
    let wi = frame.to_world(sample.wi).normalize();
    assert!(
        leaves_on_its_side(wi, ng, sample.wi),
        "a flat face cannot tilt a direction across"
    );
    Some((point.spawn_ray(wi), sample.wi.z < 0.0))
}

/// Through a slab with parallel faces a ray refracts in and out: it leaves
/// parallel to itself, shifted sideways by t sin(θi − θt) / cos θt.
#[test]
fn a_ray_through_a_glass_slab_leaves_parallel_to_itself() {
    let thickness = 0.1f32;
    let (positions, triangles) = closed_box(
        Vec3::new(-50.0, -50.0, -thickness),
        Vec3::new(50.0, 50.0, 0.0),
        false,
    );
    let eta = 1.5f32;
    let context = RenderContext::new(
        glass_scene(&positions, &triangles, Vec3::ONE, eta),
        RenderSettings::default(),
    );
    // numbers that always pick refraction (F < 0.999 below 80°)
    let refract = Vec2::new(0.999, 0.5);
    for degrees in [0.0f32, 15.0, 30.0, 45.0, 60.0, 75.0] {
        for azimuth in [0.0f32, 1.0, 2.5] {
            let theta = degrees.to_radians();
            let direction = Vec3::new(
                theta.sin() * azimuth.cos(),
                theta.sin() * azimuth.sin(),
                -theta.cos(),
            );
            let ray = Ray::new(
                Vec3::new(0.3, -0.2, 1.0) - direction * 0.5,
                direction,
                f32::INFINITY,
            );
            let top = context.accel.closest_hit(&ray).expect("the slab");
            let (inside, refracted) = interact(&context, &top, &ray, refract).unwrap();
            assert!(refracted);
            let bottom = context
                .accel
                .closest_hit(&inside)
                .expect("the slab's far face");
            let (out, refracted) = interact(&context, &bottom, &inside, refract).unwrap();
            assert!(refracted);
            assert!(
                (out.direction - direction).length() < 2e-6,
                "{degrees}°: left along {}, came along {direction}",
                out.direction
            );
            // the sideways shift between the line of the incoming ray and the
            // outgoing one
            let theta_t = (theta.sin() / eta).asin();
            let expected = thickness * (theta - theta_t).sin() / theta_t.cos();
            let offset = out.origin - ray.origin;
            let shift = (offset - direction * offset.dot(direction)).length();
            assert!(
                (shift - expected).abs() < 1e-5,
                "{degrees}°: shifted {shift}, Snell says {expected}"
            );
        }
    }
}

/// Rays that enter a closed glass object stay inside until they refract
/// out: each segment that starts inside meets the object again, on its
/// inner (back) face, never the scene's emptiness or a front face it
/// slipped through. Paths of up to 24 interactions drawn by the glass
/// model (reflections, refractions, total internal reflections) on a
/// tessellated sphere, a box and a thin sheet-like box.
#[test]
fn a_closed_glass_object_never_lets_a_ray_out_unseen() {
    let shapes = [
        uv_sphere(Vec3::new(0.2, -0.1, 0.3), 0.7, 64, 32, false),
        closed_box(
            Vec3::new(-0.4, -0.3, -0.5),
            Vec3::new(0.5, 0.35, 0.45),
            false,
        ),
        closed_box(
            Vec3::new(-2.0, -2.0, -0.002),
            Vec3::new(2.0, 2.0, 0.002),
            false,
        ),
    ];
    for (shape, (positions, triangles)) in shapes.iter().enumerate() {
        let context = RenderContext::new(
            glass_scene(positions, triangles, Vec3::ONE, 1.5),
            RenderSettings::default(),
        );
        let (mut inside_segments, mut leaks) = (0u64, 0u64);
        for path in 0..20_000u64 {
            let stream = SampleStream::new(5, shape as u64, path);
            // from a point on a sphere of radius 3 towards a point near the centre
            let u = stream.uniform2(0);
            let (z, phi) = (1.0 - 2.0 * u.x, std::f32::consts::TAU * u.y);
            let r = (1.0 - z * z).max(0.0).sqrt();
            let origin = 3.0 * Vec3::new(r * phi.cos(), r * phi.sin(), z);
            let target = (stream.uniform2(1).extend(stream.uniform(3)) - 0.5) * 0.6;
            let mut ray = Ray::new(origin, (target - origin).normalize(), f32::INFINITY);
            let mut inside = false;
            for interaction in 0..24u32 {
                let hit = context.accel.closest_hit(&ray);
                if inside {
                    inside_segments += 1;
                    let from_inside = hit.is_some_and(|hit| {
                        let Hit::Triangle { triangle, b, .. } = hit else {
                            return false;
                        };
                        SurfacePoint::new(&context.scene, triangle, b)
                            .ng
                            .dot(ray.direction)
                            > 0.0
                    });
                    if !from_inside {
                        leaks += 1;
                        break;
                    }
                }
                let Some(hit) = hit else { break };
                let u = stream.uniform2(4 + 2 * interaction);
                let Some((next, refracted)) = interact(&context, &hit, &ray, u) else {
                    break;
                };
                inside ^= refracted;
                ray = next;
            }
        }
        assert!(
            inside_segments > 10_000,
            "shape {shape}: {inside_segments} segments inside"
        );
        assert_eq!(
            leaks, 0,
            "shape {shape}: {leaks} of {inside_segments} segments inside leaked"
        );
    }
}

/// With a fixed seed the Cornell box with a glass block gives the same
/// image, to the bit, on 1, 2 and 3 threads, with either integrator.
#[test]
fn glass_gives_the_same_image_for_any_thread_count() {
    let scene = Arc::new(builtin::load("cornell-glass").unwrap());
    for integrator in [Integrator::Fast, Integrator::Lecture] {
        let settings = RenderSettings {
            integrator,
            ..small(40, 30, TermSet::ALL)
        };
        let render_with = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| render_film((*scene).clone(), &settings, 4).radiance(TermSet::ALL))
        };
        let one = render_with(1);
        assert!(one.iter().any(|p| p.max_element() > 0.0));
        for threads in [2, 3] {
            let bits = |image: &[Vec3]| -> Vec<[u32; 3]> {
                image
                    .iter()
                    .map(|p| p.to_array().map(f32::to_bits))
                    .collect()
            };
            assert_eq!(
                bits(&one),
                bits(&render_with(threads)),
                "{integrator}: {threads} threads"
            );
        }
    }
}
