//! The sphere-leaks case: no rendering, only the BVH. Rays from inside a
//! closed tessellated sphere, at the origin and 10⁴ m out, aimed at its
//! vertices and edge midpoints (where watertightness is tested hardest) and
//! at random points; every one must hit.

use glam::Vec3;

use super::{Case, CaseReport, Effort};
use crate::geometry::Ray;
use crate::geometry::accel::Accel;
use crate::scene::builtin::uv_sphere;
use crate::scene::{Material, Scene};

/// Rays from points near the centre of a closed tessellated sphere towards
/// its vertices, the midpoints of its edges and random points: all must hit.
pub(super) fn run(effort: Effort) -> CaseReport {
    let rays_per_centre: u64 = match effort {
        Effort::Quick => 50_000,
        Effort::Full => 1_000_000,
    };
    let mut report = CaseReport::new(Case::SphereLeaks);
    for centre in [Vec3::ZERO, Vec3::splat(1e4)] {
        let mut scene = Scene::default();
        let material = scene.add_material(Material::lambert("sphere", Vec3::splat(0.5)));
        let (positions, triangles) = uv_sphere(centre, 1.0, 64, 32, true);
        scene.add_mesh("sphere", material, &positions, &triangles);
        let accel = Accel::build(&scene, |_| true, Vec::new());
        let mut targets: Vec<Vec3> = positions.clone();
        for t in &triangles {
            for e in 0..3 {
                let (a, b) = (positions[t[e] as usize], positions[t[(e + 1) % 3] as usize]);
                targets.push(0.5 * (a + b));
            }
        }
        let mut rng = SplitMix(centre.x.to_bits() as u64 ^ 0x5eed);
        let mut leaks = 0u64;
        for k in 0..rays_per_centre {
            // half the rays from the centre itself, half from points near it
            let origin = if k % 2 == 0 {
                centre
            } else {
                centre + 0.1 * Vec3::new(rng.signed(), rng.signed(), rng.signed())
            };
            let target = if k % 3 == 2 {
                centre + Vec3::new(rng.signed(), rng.signed(), rng.signed())
            } else {
                targets[(rng.next() % targets.len() as u64) as usize]
            };
            let direction = (target - origin).normalize_or_zero();
            if direction == Vec3::ZERO {
                continue;
            }
            let ray = Ray::new(origin, direction, f32::INFINITY);
            if accel.closest_hit(&ray).is_none() {
                leaks += 1;
            }
        }
        report.variants += 1;
        report.samples += rays_per_centre;
        report.leaked_rays += leaks;
        if leaks > 0 {
            report.failures.push(format!(
                "centre {centre}: {leaks} of {rays_per_centre} rays escaped"
            ));
        }
    }
    report
}

/// A small deterministic generator for the sphere's rays.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [−1, 1).
    fn signed(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }
}
