//! Ray queries against the scene: closest hit and occlusion.
//!
//! Triangles go into an `obvhs` compressed wide BVH (CWBVH8). Its traversal
//! hands the closure an index into `bvh.primitive_indices`, so the triangle
//! vertices are copied once, at build, in that order; the closure then reads
//! them directly. The triangle test is our watertight one
//! ([`crate::geometry::intersect_triangle`]), not obvhs's Möller–Trumbore.
//! Sphere lights (point lights made extended) are few and are tested one by
//! one after the BVH. A set of at most 64 triangles (the Cornell box has
//! 38) skips the traversal: a vector test of all of them at once picks the
//! few the ray may hit (`accel/blocks.rs`), and only those get the exact test.
//!
//! A direction traced only to find a light (the path ends where it lands)
//! asks [`Accel::visible_emitter`]: when the emissive triangles are few they
//! have a BVH of their own, searched first; most such rays miss every light
//! and cost a few node tests instead of a full closest-hit search and the
//! shading of what they hit.
//!
//! The node test is ours too ([`intersect_node`]): obvhs's skips boxes closer
//! than a fixed t = 10⁻⁴ and rounds its slab distances either way, so rays
//! through the shared edges of two child boxes can miss both. Ours widens
//! each slab interval by a bound on its rounding error (the quantised child
//! planes are exact; the error comes from the ray's inverse direction and
//! the two fused steps), so a box the ray touches is never skipped.

use glam::{UVec2, Vec3, Vec3A, Vec4};
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};
use obvhs::cwbvh::{CwBvh, bvh2_to_cwbvh::bvh2_to_cwbvh};
use obvhs::{BvhBuildParams, ploc::PlocBuilder};

use crate::geometry::{Ray, ShearedRay, TriangleHit, gamma};
use crate::scene::Scene;

mod blocks;
use blocks::TriangleBlocks;

/// An emitting sphere (a sphere light); `light` is its index in the light table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    pub light: u32,
}

/// The question a ray asks of the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Query {
    /// [`Accel::closest_hit`]: camera rays and continuations that go on.
    ClosestHit,
    /// [`Accel::occluded`]: shadow rays.
    Occlusion,
    /// [`Accel::visible_emitter`]: directions traced only to find a light.
    VisibleEmitter,
}

/// What [`Accel::search_emitters`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmitterSearch {
    /// The first thing along the ray, if it emits.
    pub hit: Option<Hit>,
    /// Whether the whole scene's BVH was searched (false: the ray met no
    /// light's box or triangle, and that settled it).
    pub scene_searched: bool,
}

/// What a ray hit first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Hit {
    /// A scene triangle (its index in `Scene::triangles`) at barycentrics (b0, b1, b2).
    Triangle { t: f32, triangle: u32, b: Vec3 },
    /// Sphere number `sphere` of [`Accel::spheres`].
    Sphere { t: f32, sphere: u32 },
}

impl Hit {
    pub fn t(&self) -> f32 {
        match *self {
            Hit::Triangle { t, .. } | Hit::Sphere { t, .. } => t,
        }
    }
}

/// The acceleration structure of one scene under one light mode.
#[derive(Clone)]
pub struct Accel {
    triangles: TriangleBvh,
    /// The emissive triangles on their own, when they are few enough for a
    /// search of their own to pay (see [`Accel::visible_emitter`]).
    emitters: Option<TriangleBvh>,
    /// Whether each triangle of `triangles` (BVH order) is emissive.
    emissive: Vec<bool>,
    pub spheres: Vec<Sphere>,
}

/// Emitters may be at most this share of the triangles for
/// [`Accel::visible_emitter`] to search them first: past it most rays find
/// one, and the second query (is anything in front?) costs more than it saves.
const EMITTER_SHARE_FOR_OWN_BVH: f32 = 0.25;

impl Accel {
    /// Builds the BVH over the scene triangles for which `keep` is true, plus `spheres`.
    pub fn build(scene: &Scene, keep: impl Fn(u32) -> bool, spheres: Vec<Sphere>) -> Self {
        let all = 0..scene.triangles.len() as u32;
        // the usual case keeps every triangle: no list of them is made
        let kept: Option<Vec<u32>> =
            (!all.clone().all(&keep)).then(|| all.filter(|&i| keep(i)).collect());
        let is_emissive = |i: u32| {
            let material = scene.triangles[i as usize].material as usize;
            scene.materials[material].is_emissive()
        };
        let triangles = match &kept {
            Some(kept) => TriangleBvh::build(scene, kept.len(), |i| kept[i]),
            None => TriangleBvh::build(scene, scene.triangles.len(), |i| i as u32),
        };
        let emissive: Vec<bool> = triangles
            .scene_triangle
            .iter()
            .map(|&i| is_emissive(i))
            .collect();
        let emitter_ids: Vec<u32> = match &kept {
            Some(kept) => kept.iter().copied().filter(|&i| is_emissive(i)).collect(),
            None => (0..scene.triangles.len() as u32)
                .filter(|&i| is_emissive(i))
                .collect(),
        };
        let kept_count = triangles.scene_triangle.len();
        let few = emitter_ids.len() as f32 <= EMITTER_SHARE_FOR_OWN_BVH * kept_count as f32;
        let emitters =
            few.then(|| TriangleBvh::build(scene, emitter_ids.len(), |i| emitter_ids[i]));
        Self {
            triangles,
            emitters,
            emissive,
            spheres,
        }
    }

    /// Whether some query tests a triangle set in blocks instead of traversing its BVH.
    pub fn tests_in_blocks(&self) -> bool {
        std::iter::once(&self.triangles)
            .chain(&self.emitters)
            .any(|set| set.blocks.is_some())
    }

    /// A copy whose queries all traverse the CWBVHs: the yardstick the
    /// bench holds the renderer against.
    pub fn bvh_only(&self) -> Accel {
        let mut copy = self.clone();
        copy.triangles.blocks = None;
        if let Some(emitters) = &mut copy.emitters {
            emitters.blocks = None;
        }
        copy
    }

    /// Number of triangles in the BVH.
    pub fn triangle_count(&self) -> usize {
        self.triangles.scene_triangle.len()
    }

    /// The first thing `ray` hits in (0, t_max), if any.
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let traverse_ray = obvhs_ray(ray);
        let hit = self.triangles.closest(traverse_ray).map(|(_, hit)| hit);
        self.nearer_sphere(ray, hit)
    }

    /// The first thing `ray` hits in (0, t_max) if it is an emitter (a sphere
    /// light or an emissive triangle), else `None`: the only query a
    /// direction traced to find lights needs. Equal to `closest_hit` filtered
    /// to emitters, except where a non-emissive surface and an emitter meet
    /// the ray at the same t, where this one reports the surface (it is
    /// blocked). When emitters are few, it searches their own BVH first —
    /// most such rays miss every light and stop there — and only for a hit
    /// asks the scene whether a non-emissive triangle comes first (any hit).
    /// Such a ray is not followed further, so a leak it finds is not counted.
    pub fn visible_emitter(&self, ray: &Ray) -> Option<Hit> {
        self.search_emitters(ray).hit
    }

    /// [`Accel::visible_emitter`], saying whether it had to search the whole scene.
    pub fn search_emitters(&self, ray: &Ray) -> EmitterSearch {
        let traverse_ray = obvhs_ray(ray);
        let Some(emitters) = &self.emitters else {
            let (id, nearest) = self.triangles.closest(traverse_ray).unzip();
            let hit = self.nearer_sphere(ray, nearest);
            // a triangle hit is the nearest triangle, number `id`
            let emits = |hit: &Hit| {
                matches!(hit, Hit::Sphere { .. }) || id.is_some_and(|id| self.emissive[id])
            };
            return EmitterSearch {
                hit: hit.filter(emits),
                scene_searched: true,
            };
        };
        // most such rays miss the lights' box: no traversal for them
        let emitter = if emitters.bounds_may_meet(&traverse_ray) {
            emitters.closest(traverse_ray).map(|(_, hit)| hit)
        } else {
            None
        };
        let Some(hit) = self.nearer_sphere(ray, emitter) else {
            return EmitterSearch {
                hit: None,
                scene_searched: false,
            };
        };
        let before_hit = obvhs::ray::Ray {
            tmax: hit.t(),
            ..traverse_ray
        };
        let blocked = self.triangles.any(before_hit, |id| !self.emissive[id]);
        EmitterSearch {
            hit: (!blocked).then_some(hit),
            scene_searched: true,
        }
    }

    /// `hit`, or the nearest sphere `ray` meets before it.
    fn nearer_sphere(&self, ray: &Ray, mut hit: Option<Hit>) -> Option<Hit> {
        let mut t_max = hit.map_or(ray.t_max, |h| h.t());
        for (i, sphere) in self.spheres.iter().enumerate() {
            if let Some(t) = intersect_sphere(ray, sphere, t_max) {
                t_max = t;
                hit = Some(Hit::Sphere {
                    t,
                    sphere: i as u32,
                });
            }
        }
        hit
    }

    /// Whether anything blocks `ray` in (0, t_max), ignoring sphere `skip_sphere` (if any).
    pub fn occluded(&self, ray: &Ray, skip_sphere: Option<u32>) -> bool {
        let blocked_by_sphere = self.spheres.iter().enumerate().any(|(i, s)| {
            Some(i as u32) != skip_sphere && intersect_sphere(ray, s, ray.t_max).is_some()
        });
        blocked_by_sphere || self.triangles.any(obvhs_ray(ray), |_| true)
    }

    /// Closest hit by testing every triangle and sphere: the reference the BVH is checked against.
    pub fn brute_force_closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let sheared = ShearedRay::new(ray.origin.into(), ray.direction.into());
        let mut hit = None;
        let mut t_max = ray.t_max;
        for (id, [p0, p1, p2]) in self.triangles.vertices.iter().enumerate() {
            if let Some(h) = sheared.intersect(t_max, *p0, *p1, *p2) {
                t_max = h.t;
                hit = Some(self.triangles.hit(id, h));
            }
        }
        self.nearer_sphere(ray, hit)
    }
}

/// A set of scene triangles in an `obvhs` CWBVH, with their vertices copied in BVH order.
#[derive(Clone, Default)]
struct TriangleBvh {
    bvh: CwBvh,
    /// Vertices of each triangle, in BVH order.
    vertices: Vec<[Vec3A; 3]>,
    /// Scene triangle index of each BVH-ordered triangle.
    scene_triangle: Vec<u32>,
    /// The box around every triangle (min, max corners).
    bounds: [Vec3A; 2],
    /// The triangles again, in vector blocks, when they are few enough for
    /// testing them all to beat traversal.
    blocks: Option<TriangleBlocks>,
}

impl TriangleBvh {
    /// The BVH over the `count` scene triangles `id(0)`, …, `id(count − 1)`.
    fn build(scene: &Scene, count: usize, id: impl Fn(usize) -> u32) -> Self {
        if count == 0 {
            return Self::default();
        }
        let corners = |i: u32| {
            let t = &scene.triangles[i as usize];
            t.vertices.map(|v| Vec3A::from(scene.positions[v as usize]))
        };
        let mut bvh = build_cwbvh((0..count).map(|i| {
            let [v0, v1, v2] = corners(id(i));
            obvhs::triangle::Triangle { v0, v1, v2 }
        }));
        // the BVH's slots hold the `i` of `id(i)`: turned in place into
        // scene triangles, they replace the BVH's own copy
        let mut scene_triangle = std::mem::take(&mut bvh.primitive_indices);
        for slot in &mut scene_triangle {
            *slot = id(*slot as usize);
        }
        let vertices: Vec<[Vec3A; 3]> = scene_triangle.iter().map(|&i| corners(i)).collect();
        let corner_points = vertices.iter().flatten();
        let bounds = [
            corner_points
                .clone()
                .fold(Vec3A::INFINITY, |m, &p| m.min(p)),
            corner_points.fold(Vec3A::NEG_INFINITY, |m, &p| m.max(p)),
        ];
        let blocks = TriangleBlocks::new(&vertices);
        Self {
            bvh,
            vertices,
            scene_triangle,
            bounds,
            blocks,
        }
    }

    /// Whether `ray` may meet the box around every triangle in [0, tmax]:
    /// a slab test whose distances are widened by a bound on their rounding
    /// (the difference, the product and the inverse direction, as in
    /// [`intersect_node`]), so it is never false for a ray that hits one.
    #[inline(always)]
    fn bounds_may_meet(&self, ray: &obvhs::ray::Ray) -> bool {
        let t0 = (self.bounds[0] - ray.origin) * ray.inv_direction;
        let t1 = (self.bounds[1] - ray.origin) * ray.inv_direction;
        let slack = gamma(4);
        let near = t0.min(t1);
        let far = t0.max(t1);
        let near = (near - slack * near.abs()).max_element().max(0.0);
        let far = (far + slack * far.abs()).min_element();
        near <= far && near <= ray.tmax * (1.0 + 2.0 * gamma(3))
    }

    fn hit(&self, id: usize, hit: TriangleHit) -> Hit {
        Hit::Triangle {
            t: hit.t,
            triangle: self.scene_triangle[id],
            b: Vec3::new(hit.b0, hit.b1, hit.b2),
        }
    }

    /// The nearest triangle `ray` hits in (0, tmax]: its BVH index and hit.
    #[inline(always)]
    fn closest(&self, mut ray: obvhs::ray::Ray) -> Option<(usize, Hit)> {
        if self.scene_triangle.is_empty() {
            return None;
        }
        let sheared = ShearedRay::new(ray.origin, ray.direction);
        let mut best: Option<(usize, TriangleHit)> = None;
        if let Some(blocks) = &self.blocks {
            let mut t_max = ray.tmax;
            for id in set_bits(blocks.candidates(&sheared, t_max)) {
                let [p0, p1, p2] = self.vertices[id];
                if let Some(hit) = sheared.intersect(t_max, p0, p1, p2) {
                    best = Some((id, hit));
                    t_max = hit.t;
                }
            }
            return best.map(|(id, hit)| (id, self.hit(id, hit)));
        }
        let mut state = self.bvh.new_traversal(ray.direction);
        let mut node;
        obvhs::traverse!(
            self.bvh,
            node,
            state,
            intersect_node(node, &ray, state.oct_inv4),
            {
                let id = state.primitive_id as usize;
                let [p0, p1, p2] = self.vertices[id];
                if let Some(hit) = sheared.intersect(ray.tmax, p0, p1, p2) {
                    best = Some((id, hit));
                    ray.tmax = hit.t;
                }
            }
        );
        best.map(|(id, hit)| (id, self.hit(id, hit)))
    }

    /// Whether `ray` hits, in (0, tmax], a triangle whose BVH index passes `counts`.
    #[inline(always)]
    fn any(&self, ray: obvhs::ray::Ray, counts: impl Fn(usize) -> bool) -> bool {
        if self.scene_triangle.is_empty() {
            return false;
        }
        let sheared = ShearedRay::new(ray.origin, ray.direction);
        if let Some(blocks) = &self.blocks {
            return set_bits(blocks.candidates(&sheared, ray.tmax)).any(|id| {
                let [p0, p1, p2] = self.vertices[id];
                counts(id) && sheared.intersect(ray.tmax, p0, p1, p2).is_some()
            });
        }
        let mut state = self.bvh.new_traversal(ray.direction);
        let mut node;
        let mut blocked = false;
        'traversal: {
            obvhs::traverse!(
                self.bvh,
                node,
                state,
                intersect_node(node, &ray, state.oct_inv4),
                {
                    let id = state.primitive_id as usize;
                    let [p0, p1, p2] = self.vertices[id];
                    if counts(id) && sheared.intersect(ray.tmax, p0, p1, p2).is_some() {
                        blocked = true;
                        break 'traversal;
                    }
                }
            );
        }
        blocked
    }
}

/// The indices of the set bits of `mask`, lowest first.
#[inline(always)]
fn set_bits(mut mask: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let bit = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            bit
        })
    })
}

/// Scenes up to this many triangles get obvhs's most thorough build
/// (reinsertion over every node): a better tree for a build time that stays
/// small at this size. Larger scenes keep the fast build, whose time grows
/// far less with the triangle count.
const THOROUGH_BUILD_MAX_TRIANGLES: usize = 16_384;

/// obvhs's CWBVH build (PLOC, reinsertion, conversion to 8-wide nodes),
/// done in steps so that each step's inputs are freed before the next
/// allocates: the triangles once the leaves hold their boxes, the binary
/// BVH's parent links before the conversion (it reads only nodes and
/// primitive indices), and the converter's spare node capacity (sized for
/// one node per triangle, about ten times what it uses) at the end.
fn build_cwbvh(triangles: impl Iterator<Item = obvhs::triangle::Triangle>) -> CwBvh {
    let triangles: Vec<obvhs::triangle::Triangle> = triangles.collect();
    let count = triangles.len();
    let params = build_params(count);
    let mut bvh2 = PlocBuilder::new().build(
        params.ploc_search_distance,
        &triangles,
        (0..count as u32).collect(),
        params.sort_precision,
        params.search_depth_threshold,
    );
    drop(triangles);
    ReinsertionOptimizer::default().run(&mut bvh2, params.reinsertion_batch_ratio, None);
    bvh2.parents = Vec::new();
    bvh2.primitives_to_nodes = Vec::new();
    let mut cwbvh = bvh2_to_cwbvh(&bvh2, params.max_prims_per_leaf.clamp(1, 3), true, false);
    drop(bvh2);
    cwbvh.nodes.shrink_to_fit();
    cwbvh
}

/// The build parameters for `triangles` triangles. No spatial pre-splits:
/// their clipped boxes are rounded, not conservative, and a ray through a
/// split line could miss both halves.
fn build_params(triangles: usize) -> BvhBuildParams {
    let params = if triangles <= THOROUGH_BUILD_MAX_TRIANGLES {
        BvhBuildParams::very_slow_build()
    } else {
        BvhBuildParams::fast_build()
    };
    BvhBuildParams {
        pre_split: false,
        ..params
    }
}

/// The ray in obvhs's form, with an exact inverse direction: obvhs's own
/// constructor replaces components below f32::EPSILON by ±1/EPSILON,
/// which moves slab distances and makes near-axis rays miss boxes. Only
/// components too small to invert (|d| < 1e-30) are nudged, to keep
/// 0·∞ out of the slab arithmetic.
fn obvhs_ray(ray: &Ray) -> obvhs::ray::Ray {
    let direction = Vec3A::from(ray.direction);
    let invertible = direction.abs().cmpge(Vec3A::splat(1e-30));
    let safe = Vec3A::select(
        invertible,
        direction,
        Vec3A::splat(1e-30).copysign(direction),
    );
    obvhs::ray::Ray {
        origin: ray.origin.into(),
        direction,
        inv_direction: Vec3A::ONE / safe,
        tmin: 0.0,
        tmax: ray.t_max,
    }
}

/// Nearest intersection of `ray` with the sphere's surface in (0, t_max).
/// Uses the discriminant form of Hearn & Baker, accurate for distant spheres.
pub fn intersect_sphere(ray: &Ray, sphere: &Sphere, t_max: f32) -> Option<f32> {
    let length = ray.direction.length();
    if length == 0.0 {
        return None;
    }
    let d = ray.direction / length;
    let f = ray.origin - sphere.center;
    let b = -f.dot(d);
    let closest = f + b * d;
    let r2 = sphere.radius * sphere.radius;
    let discriminant = r2 - closest.length_squared();
    if discriminant < 0.0 {
        return None;
    }
    let root = discriminant.sqrt();
    let c = f.length_squared() - r2;
    // numerically stable pair of roots
    let q = b + root.copysign(b);
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q) };
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    let t_max_unit = t_max * length;
    [near, far]
        .into_iter()
        .find(|&t| t > 0.0 && t < t_max_unit)
        .map(|t| t / length)
}

/// Conservative ray test against the eight child boxes of a CWBVH node:
/// returns obvhs's hit mask. Each slab distance `q·a + b` (q the exact
/// quantised plane, q ≥ 0, a = extent/d, b = (p − o)/d) is widened by
/// γ·(q|a| + |b|), which bounds the rounding of a, b and the sum; written
/// `q·(a ∓ γ|a|) + (b ∓ γ|b|)`, the widened bounds cost one multiply-add per
/// plane, and γ(8) covers the two extra roundings of that form.
#[inline(always)]
fn intersect_node(node: &CwBvhNode, ray: &obvhs::ray::Ray, oct_inv4: u32) -> u32 {
    let a = node.compute_extent() * ray.inv_direction;
    let b = (Vec3A::from(node.p) - ray.origin) * ray.inv_direction;
    let slack = gamma(8);
    let (a_lo, a_hi) = (a - slack * a.abs(), a + slack * a.abs());
    let (b_lo, b_hi) = (b - slack * b.abs(), b + slack * b.abs());
    let t_max_ray = ray.tmax * (1.0 + 2.0 * gamma(3));
    // the sign of the inverse, not of the direction: −0.0 has a negative inverse
    let negative = ray.inv_direction.cmplt(Vec3A::ZERO);
    let planes = [
        (&node.child_min_x, &node.child_max_x, negative.test(0), 0),
        (&node.child_min_y, &node.child_max_y, negative.test(1), 1),
        (&node.child_min_z, &node.child_max_z, negative.test(2), 2),
    ];
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let mut hit_mask = 0;
    // four children at a time: each lane is one child's slab interval
    for group in 0..2 {
        let mut t_min = Vec4::ZERO;
        let mut t_max = Vec4::splat(t_max_ray);
        for (lo, hi, negative, axis) in planes {
            let (near, far) = if negative { (hi, lo) } else { (lo, hi) };
            let load = |q: &[u8; 8]| {
                let q = &q[4 * group..4 * group + 4];
                Vec4::new(q[0] as f32, q[1] as f32, q[2] as f32, q[3] as f32)
            };
            let (near, far) = (load(near), load(far));
            let t_near = near * a_lo[axis] + Vec4::splat(b_lo[axis]);
            let t_far = far * a_hi[axis] + Vec4::splat(b_hi[axis]);
            t_min = t_min.max(t_near);
            t_max = t_max.min(t_far);
        }
        let hits = t_min.cmple(t_max).bitmask();
        for lane in 0..4 {
            if hits & (1 << lane) != 0 {
                let child = 4 * group + lane;
                let child_bits = extract_byte64(child_bits8, child);
                let bit_index = extract_byte64(bit_index8, child);
                hit_mask |= child_bits << bit_index;
            }
        }
    }
    hit_mask
}
