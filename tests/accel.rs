//! The BVH agrees with brute force, and closed meshes do not leak.

use glam::Vec3;
use lumiere::geometry::Ray;
use lumiere::geometry::accel::{Accel, Hit, Sphere};
use lumiere::scene::builtin::uv_sphere;
use lumiere::scene::{Material, Scene};
use lumiere::transport::sampler::SampleStream;
use lumiere::transport::warps::uniform_sphere;

fn random_point(stream: &SampleStream, d: u32, extent: f32) -> Vec3 {
    (Vec3::new(
        stream.uniform(d),
        stream.uniform(d + 1),
        stream.uniform(d + 2),
    ) * 2.0
        - 1.0)
        * extent
}

/// A soup of random triangles of mixed sizes, every `emitter_every`-th one
/// emissive (none if 0), and the scene it came from.
fn soup_scene(emitter_every: u32) -> Scene {
    let mut scene = Scene::default();
    let grey = scene.add_material(Material::lambert("grey", Vec3::splat(0.5)));
    let light = scene.add_material(Material::emitter("light", Vec3::ONE));
    let mut positions = Vec::new();
    for i in 0..3000u64 {
        let s = SampleStream::new(1, i, 0);
        let center = random_point(&s, 0, 10.0);
        let size = if i % 10 == 0 { 3.0 } else { 0.3 };
        for k in 0..3 {
            positions.push(center + random_point(&s, 3 + 3 * k, size));
        }
    }
    let (mut dull, mut lit) = (Vec::new(), Vec::new());
    for i in 0..3000u32 {
        let triangle = [3 * i, 3 * i + 1, 3 * i + 2];
        if emitter_every > 0 && i.is_multiple_of(emitter_every) {
            lit.push(triangle);
        } else {
            dull.push(triangle);
        }
    }
    scene.add_mesh("soup", grey, &positions, &dull);
    if !lit.is_empty() {
        scene.add_mesh("lights", light, &positions, &lit);
    }
    scene
}

fn two_spheres() -> Vec<Sphere> {
    vec![
        Sphere {
            center: Vec3::new(1.0, 2.0, 3.0),
            radius: 1.5,
            light: 0,
        },
        Sphere {
            center: Vec3::new(-4.0, 0.0, 1.0),
            radius: 0.5,
            light: 1,
        },
    ]
}

/// The soup with no emitter, plus two spheres.
fn soup() -> Accel {
    Accel::build(&soup_scene(0), |_| true, two_spheres())
}

/// A ray of the i-th test: from inside the soup's box, one in three bounded.
fn test_ray(i: u64) -> Ray {
    let s = SampleStream::new(2, i, 0);
    let origin = random_point(&s, 0, 14.0);
    let direction = uniform_sphere(s.uniform2(3));
    let t_max = if i.is_multiple_of(3) {
        5.0
    } else {
        f32::INFINITY
    };
    Ray::new(origin, direction, t_max)
}

/// The emitter search gives the closest hit when that is an emitter, and
/// nothing otherwise: with few emitters (their own BVH, searched first) and
/// with many (the plain closest hit, filtered).
#[test]
fn visible_emitter_is_the_closest_hit_when_that_emits() {
    for emitter_every in [2, 13] {
        let scene = soup_scene(emitter_every);
        let accel = Accel::build(&scene, |_| true, two_spheres());
        let emissive = |triangle: u32| {
            let material = scene.triangles[triangle as usize].material;
            scene.materials[material as usize].is_emissive()
        };
        let emits = |hit: &Hit| match *hit {
            Hit::Sphere { .. } => true,
            Hit::Triangle { triangle, .. } => emissive(triangle),
        };
        // the emitters alone, to tell the rays whose emitter is hidden
        let lights_only = Accel::build(&scene, emissive, two_spheres());
        let (mut found, mut hidden) = (0, 0);
        for i in 0..20_000u64 {
            let ray = test_ray(i);
            let closest = accel.closest_hit(&ray);
            let expected = closest.filter(emits);
            let got = accel.visible_emitter(&ray);
            assert_eq!(
                got, expected,
                "ray {i}, one triangle in {emitter_every} emissive: closest hit {closest:?}"
            );
            found += usize::from(got.is_some());
            // an emitter behind the closest hit must not be reported
            hidden += usize::from(expected.is_none() && lights_only.closest_hit(&ray).is_some());
        }
        assert!(
            found > 300 && hidden > 50,
            "one in {emitter_every}: {found} emitters seen, {hidden} hidden: too few to test"
        );
    }
}

#[test]
fn bvh_closest_hits_match_brute_force() {
    let accel = soup();
    let mut hits = 0;
    for i in 0..20_000u64 {
        let ray = test_ray(i);
        let fast = accel.closest_hit(&ray);
        let slow = accel.brute_force_closest_hit(&ray);
        match (fast, slow) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                hits += 1;
                assert_eq!(a.t(), b.t(), "ray {i}: different distances");
                if let (Hit::Triangle { triangle: ta, .. }, Hit::Triangle { triangle: tb, .. }) =
                    (a, b)
                {
                    let _ = (ta, tb); // equal t: either triangle is a correct answer
                }
            }
            _ => panic!("ray {i}: BVH says {fast:?}, brute force says {slow:?}"),
        }
        assert_eq!(
            accel.occluded(&ray, None),
            slow.is_some(),
            "ray {i}: occlusion disagrees"
        );
    }
    assert!(
        hits > 5_000,
        "too few hits ({hits}) for the test to mean anything"
    );
}

/// Few triangles are tested in blocks, not traversed; every query answers
/// as the CWBVH's traversal does: the Cornell box, and soups of the sizes
/// around the limit (64), with some emitters.
#[test]
fn small_sets_tested_in_blocks_answer_as_the_bvh_does() {
    let soup = soup_scene(5);
    let cornell = lumiere::scene::builtin::cornell();
    let cases = [(&cornell, 38), (&soup, 12), (&soup, 64), (&soup, 65)];
    for (scene, count) in cases {
        let accel = Accel::build(scene, |i| i < count, two_spheres());
        assert_eq!(accel.tests_in_blocks(), count <= 64, "{count} triangles");
        let bvh = accel.bvh_only();
        assert!(!bvh.tests_in_blocks());
        let mut hits = 0;
        for i in 0..20_000u64 {
            let mut ray = test_ray(i);
            if count == 38 {
                // from inside the box (0..5.5 on each axis)
                ray.origin = ray.origin.abs() * (5.0 / 14.0) + 0.25;
            } else if i % 2 == 0 {
                // at a corner or the centre of one of the triangles
                let corners = scene.triangles[(i / 2) as usize % count as usize]
                    .vertices
                    .map(|v| scene.positions[v as usize]);
                let target = match i % 8 {
                    0 => corners[0],
                    _ => (corners[0] + corners[1] + corners[2]) / 3.0,
                };
                ray.direction = (target - ray.origin).normalize();
            }
            let (fast, slow) = (accel.closest_hit(&ray), bvh.closest_hit(&ray));
            assert_eq!(
                fast.map(|h| h.t()),
                slow.map(|h| h.t()),
                "{count} triangles, ray {i}"
            );
            hits += usize::from(fast.is_some());
            assert_eq!(
                accel.occluded(&ray, None),
                bvh.occluded(&ray, None),
                "ray {i}"
            );
            let (fast, slow) = (accel.visible_emitter(&ray), bvh.visible_emitter(&ray));
            assert_eq!(
                fast.map(|h| h.t()),
                slow.map(|h| h.t()),
                "ray {i}: emitters"
            );
        }
        assert!(
            hits > 2_000,
            "{count} triangles: {hits} hits, too few to test"
        );
    }
}

/// Rays from inside a closed tessellated sphere, aimed exactly at its
/// vertices and edge midpoints, must all hit it (watertight test).
#[test]
fn closed_sphere_does_not_leak_through_vertices_or_edges() {
    for (center, radius) in [(Vec3::ZERO, 1.0), (Vec3::splat(1e4), 3.0)] {
        let mut scene = Scene::default();
        let material = scene.add_material(Material::lambert("grey", Vec3::splat(0.5)));
        let (positions, triangles) = uv_sphere(center, radius, 64, 32, true);
        scene.add_mesh("sphere", material, &positions, &triangles);
        let accel = Accel::build(&scene, |_| true, vec![]);
        let mut targets: Vec<Vec3> = positions.clone();
        for t in &triangles {
            for k in 0..3 {
                targets.push(0.5 * (positions[t[k] as usize] + positions[t[(k + 1) % 3] as usize]));
            }
        }
        let origins = [center, center + Vec3::new(0.1, -0.2, 0.3) * radius];
        let mut leaks = 0;
        for origin in origins {
            for target in &targets {
                let ray = Ray::new(origin, *target - origin, f32::INFINITY);
                if accel.closest_hit(&ray).is_none() {
                    leaks += 1;
                }
            }
        }
        assert_eq!(leaks, 0, "rays escaped the closed sphere at {center}");
    }
}
