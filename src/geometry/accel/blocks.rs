//! A small set of triangles tested all at once, sixteen lanes wide.
//!
//! For a few dozen triangles (the Cornell box has 38) a BVH's node tests,
//! stack and branches cost more than testing every triangle with wide
//! vector instructions. [`TriangleBlocks`] stores the vertices in
//! structure-of-arrays blocks of [`LANES`] triangles, and
//! [`TriangleBlocks::candidates`] returns, as a bit mask, the triangles the
//! ray may hit in (0, t_max); only those get the exact watertight test
//! ([`ShearedRay::intersect`]), which decides.
//!
//! **Why the mask is conservative.** The lanes repeat the exact test's f32
//! steps (translate, permute, shear: same operations, same roundings, so
//! the same sheared vertices). The exact test then forms each edge function
//! `e = a·b − c·d` in f64 and rounds once; the lanes form it in f32, within
//! `s = γ₃(|a·b| + |c·d|)` of the exact value. Rounding is monotonic, so
//! the f32 `e` never has the sign opposite to the exact one: the edge signs
//! are compared as they are. The scaled distance `t̃ = Σ eᵢ zᵢ` is widened
//! by `5 Σ sᵢ|zᵢ|` and the determinant by `5 Σ sᵢ` (bounds on their
//! errors), and every test is written as "not provably outside", so a NaN
//! keeps its triangle. A triangle the exact test hits is therefore always
//! in the mask; a few it misses are in it too, and it rejects them.
//!
//! The lane arithmetic is written once, as plain loops over arrays; it is
//! compiled for AVX-512 and for AVX2 as well as for the baseline target,
//! and the widest the processor has is chosen at build time.

use glam::Vec3A;

use crate::geometry::{ShearedRay, gamma};

/// Triangles per block: one AVX-512 register of f32.
pub const LANES: usize = 16;

/// Triangles in the last block when they are this few or fewer: half the
/// lanes' work for it (the Cornell box's 38 are 16 + 16 + 6).
const TAIL_LANES: usize = 8;

/// The most triangles kept in blocks (one u64 mask). On rays through random
/// triangles the blocks beat the CWBVH by 30% at 12 triangles, 10–20% at
/// 38 to 64: the margin shrinks as the count grows.
pub const MAX_TRIANGLES: usize = 64;

/// The nine coordinates (vertex-major: p0.x, p0.y, p0.z, p1.x, …) of `N` triangles.
#[derive(Clone, Copy)]
#[repr(C, align(64))]
struct Block<const N: usize>([[f32; N]; 9]);

impl<const N: usize> Block<N> {
    /// The block of `triangles` (at most `N`), padded with zeros.
    fn of(triangles: &[[Vec3A; 3]]) -> Self {
        let mut block = Block([[0.0; N]; 9]);
        for (lane, triangle) in triangles.iter().enumerate() {
            for (vertex, p) in triangle.iter().enumerate() {
                for axis in 0..3 {
                    block.0[3 * vertex + axis][lane] = p[axis];
                }
            }
        }
        block
    }
}

/// The candidate test for every block, compiled for one instruction set.
type Kernel = fn(&[Block<LANES>], Option<&Block<TAIL_LANES>>, &RayLanes) -> u64;

/// A small triangle set in [`LANES`]-wide blocks.
#[derive(Clone)]
pub struct TriangleBlocks {
    blocks: Vec<Block<LANES>>,
    /// The last few triangles, after `blocks`, when they fit in [`TAIL_LANES`].
    tail: Option<Block<TAIL_LANES>>,
    /// Set for each lane that holds a triangle (the last block is padded).
    occupied: u64,
    kernel: Kernel,
}

/// The ray as each lane needs it: origin and shear, already permuted.
struct RayLanes {
    /// Which vertex coordinate becomes x, y and z of the sheared frame.
    axes: [usize; 3],
    origin: [f32; 3],
    shear: [f32; 3],
    t_max: f32,
}

impl TriangleBlocks {
    /// The blocks of `vertices` (their order is the mask's bit order), if
    /// they are at most [`MAX_TRIANGLES`].
    pub fn new(vertices: &[[Vec3A; 3]]) -> Option<Self> {
        if vertices.is_empty() || vertices.len() > MAX_TRIANGLES {
            return None;
        }
        let remainder = vertices.len() % LANES;
        let (whole, last) = if (1..=TAIL_LANES).contains(&remainder) {
            vertices.split_at(vertices.len() - remainder)
        } else {
            (vertices, &[][..])
        };
        let blocks = whole.chunks(LANES).map(Block::of).collect();
        let tail = (!last.is_empty()).then(|| Block::of(last));
        let occupied = u64::MAX >> (64 - vertices.len());
        Some(Self {
            blocks,
            tail,
            occupied,
            kernel: best_kernel(),
        })
    }

    /// Bit i set: triangle i may be hit in (0, t_max); clear only if the
    /// exact test would miss it.
    #[inline]
    pub fn candidates(&self, ray: &ShearedRay, t_max: f32) -> u64 {
        let (origin, kz, shear) = ray.frame();
        let kz = kz as usize;
        let ray = RayLanes {
            axes: [(kz + 1) % 3, (kz + 2) % 3, kz],
            origin: origin.to_array(),
            shear: shear.to_array(),
            t_max,
        };
        (self.kernel)(&self.blocks, self.tail.as_ref(), &ray) & self.occupied
    }

    /// [`TriangleBlocks::candidates`] with `kernel`.
    #[cfg(test)]
    fn candidates_with(&self, kernel: Kernel, ray: &ShearedRay, t_max: f32) -> u64 {
        Self {
            kernel,
            ..self.clone()
        }
        .candidates(ray, t_max)
    }
}

/// The kernels this processor runs, widest first; the baseline is last.
fn kernels() -> Vec<Kernel> {
    let mut kernels: Vec<Kernel> = Vec::new();
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor has AVX-512F
            kernels.push(|blocks, tail, ray| unsafe { candidates_avx512(blocks, tail, ray) });
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2
            kernels.push(|blocks, tail, ray| unsafe { candidates_avx2(blocks, tail, ray) });
        }
    }
    kernels.push(candidates_plain);
    kernels
}

/// The widest kernel this processor runs.
fn best_kernel() -> Kernel {
    kernels()[0]
}

// The kernels below turn each block's lanes into mask bits with the
// instruction set's own mask extraction: written as `bit << lane` and an OR
// over the lanes, LLVM left the comparisons half-vectorised and folded
// the bits with a shuffle tree, a quarter of the kernel's time.

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn candidates_avx512(
    blocks: &[Block<LANES>],
    tail: Option<&Block<TAIL_LANES>>,
    ray: &RayLanes,
) -> u64 {
    use std::arch::x86_64::*;
    candidates_of(
        blocks,
        tail,
        ray,
        |lanes| {
            // SAFETY: `lanes` is 16 u32, the 64 bytes read
            let lanes = unsafe { _mm512_loadu_si512(lanes.as_ptr().cast()) };
            _mm512_test_epi32_mask(lanes, lanes) as u32
        },
        |lanes| {
            // SAFETY: `lanes` is 8 u32, the 32 bytes read
            let lanes = unsafe { _mm256_loadu_ps(lanes.as_ptr().cast()) };
            _mm256_movemask_ps(lanes) as u32
        },
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn candidates_avx2(
    blocks: &[Block<LANES>],
    tail: Option<&Block<TAIL_LANES>>,
    ray: &RayLanes,
) -> u64 {
    use std::arch::x86_64::*;
    // SAFETY (both): each read of 8 u32 lies within `lanes`
    let eight = |lanes: *const u32| _mm256_movemask_ps(unsafe { _mm256_loadu_ps(lanes.cast()) });
    candidates_of(
        blocks,
        tail,
        ray,
        |lanes| (eight(lanes.as_ptr()) | eight(lanes[8..].as_ptr()) << 8) as u32,
        |lanes| eight(lanes.as_ptr()) as u32,
    )
}

fn candidates_plain(
    blocks: &[Block<LANES>],
    tail: Option<&Block<TAIL_LANES>>,
    ray: &RayLanes,
) -> u64 {
    candidates_of(blocks, tail, ray, lane_bits, lane_bits)
}

/// One bit per lane, set where the lane is all ones (the portable form).
#[inline(always)]
fn lane_bits<const N: usize>(lanes: &[u32; N]) -> u32 {
    let mut bits = 0;
    for (i, &lane) in lanes.iter().enumerate() {
        bits |= (lane & 1) << i;
    }
    bits
}

#[inline(always)]
fn candidates_of(
    blocks: &[Block<LANES>],
    tail: Option<&Block<TAIL_LANES>>,
    ray: &RayLanes,
    bits: impl Fn(&[u32; LANES]) -> u32,
    tail_bits: impl Fn(&[u32; TAIL_LANES]) -> u32,
) -> u64 {
    let mut mask = 0;
    for (b, block) in blocks.iter().enumerate() {
        mask |= (bits(&block_candidates(block, ray)) as u64) << (LANES * b);
    }
    if let Some(tail) = tail {
        mask |= (tail_bits(&block_candidates(tail, ray)) as u64) << (LANES * blocks.len());
    }
    mask
}

/// Edge functions smaller than this may have been flushed to 0 by the
/// exact test (a product of two f32 near 2⁻¹⁰³ rounds to a multiple of 2⁻¹²⁶).
const TINY: f32 = 1e-36;

/// The candidate lanes of one block (see the module's notes): all ones
/// where the ray may hit the lane's triangle, else zero. Plain loops over
/// the lanes, without closures, so that they vectorise.
// The negated comparisons are the point: a NaN must keep its triangle.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
#[inline(always)]
fn block_candidates<const N: usize>(block: &Block<N>, ray: &RayLanes) -> [u32; N] {
    let [sx, sy, sz] = ray.shear;
    // sheared vertices, as ShearedRay::intersect computes them
    let mut x = [[0.0; N]; 3];
    let mut y = [[0.0; N]; 3];
    let mut z = [[0.0; N]; 3];
    for vertex in 0..3 {
        let [px, py, pz] = ray.axes.map(|axis| &block.0[3 * vertex + axis]);
        let [ox, oy, oz] = ray.axes.map(|axis| ray.origin[axis]);
        for i in 0..N {
            let (qx, qy, qz) = (px[i] - ox, py[i] - oy, pz[i] - oz);
            x[vertex][i] = qx + sx * qz;
            y[vertex][i] = qy + sy * qz;
            z[vertex][i] = qz * sz;
        }
    }
    let slack = 5.0 * gamma(3);
    let far = ray.t_max * (1.0 + gamma(2));
    let mut lanes = [0u32; N];
    for i in 0..N {
        let (x0, x1, x2) = (x[0][i], x[1][i], x[2][i]);
        let (y0, y1, y2) = (y[0][i], y[1][i], y[2][i]);
        let (z0, z1, z2) = (z[0][i], z[1][i], z[2][i]);
        let (a0, b0) = (x1 * y2, y1 * x2);
        let (a1, b1) = (x2 * y0, y2 * x0);
        let (a2, b2) = (x0 * y1, y0 * x1);
        let (e0, e1, e2) = (a0 - b0, a1 - b1, a2 - b2);
        // each eᵢ is within sᵢ = γ₃(|aᵢ| + |bᵢ|) of the exact test's
        let s0 = a0.abs() + b0.abs();
        let s1 = a1.abs() + b1.abs();
        let s2 = a2.abs() + b2.abs();
        let t = e0 * z0 + e1 * z1 + e2 * z2;
        // |eᵢ| ≤ (1 + ε)(|aᵢ| + |bᵢ|), so the bounds 2 Σ (sᵢ + γ₄|eᵢ|)|zᵢ|
        // and 2 (Σ sᵢ + γ₃ Σ |eᵢ|) are below 5 Σ sᵢ|zᵢ| and 5 Σ sᵢ
        let t_slack = slack * (s0 * z0.abs() + s1 * z1.abs() + s2 * z2.abs());
        let det = e0 + e1 + e2;
        let det_slack = slack * (s0 + s1 + s2);
        // The edge signs need almost no slack: rounding is monotonic, so the
        // f32 difference of the rounded products never has the sign opposite
        // to the exact one (it may be 0, which both sides accept). Only
        // below 2⁻¹⁰³, where the exact test's f64 → f32 rounding can flush
        // a difference to 0, is a sign not trusted.
        // det > 0 possible: every edge ≥ 0, 0 < t_scaled ≤ t_max·det
        let positive = !(e0 < -TINY)
            & !(e1 < -TINY)
            & !(e2 < -TINY)
            & !(t + t_slack <= 0.0)
            & !(t - t_slack > far * (det + det_slack));
        // det < 0 possible: every edge ≤ 0, t_max·det ≤ t_scaled < 0
        let negative = !(e0 > TINY)
            & !(e1 > TINY)
            & !(e2 > TINY)
            & !(t - t_slack >= 0.0)
            & !(t + t_slack < far * (det - det_slack));
        lanes[i] = ((positive | negative) as u32).wrapping_neg();
    }
    lanes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A test ray: origin, direction, t_max.
    type TestRay = (Vec3A, Vec3A, f32);

    /// Fixed-seed numbers in [−1, 1): SplitMix64.
    struct Numbers(u64);

    fn mix64(mut z: u64) -> u64 {
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    impl Numbers {
        fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            (mix64(self.0) >> 40) as f32 / (1u64 << 23) as f32 - 1.0
        }
        fn point(&mut self, scale: f32) -> Vec3A {
            Vec3A::new(self.next(), self.next(), self.next()) * scale
        }
    }

    /// Quads (two triangles sharing an edge) and loose triangles, rays aimed
    /// at shared edges, vertices and random points, some from far away.
    /// Odd seeds put the scene far from the origin, where the sheared
    /// coordinates are large and the edge functions' roundings matter most.
    fn cases(seed: u64) -> (Vec<[Vec3A; 3]>, Vec<TestRay>) {
        let mut numbers = Numbers(seed);
        let centre = Vec3A::splat(if seed % 2 == 1 { 3000.0 } else { 0.0 });
        let mut triangles = Vec::new();
        while triangles.len() < 62 {
            let mut corner = || centre + numbers.point(2.0);
            let (a, b, c) = (corner(), corner(), corner());
            triangles.push([a, b, c]);
            triangles.push([c, b, a + (b - a) + (c - a)]);
        }
        triangles.push([0.0; 3].map(|_| centre + numbers.point(5.0)));
        let mut rays = Vec::new();
        for i in 0..4000 {
            let [p0, p1, p2] = triangles[i % triangles.len()];
            let target = match i % 4 {
                0 => p1 + (p2 - p1) * numbers.next().abs(),
                1 => p0,
                2 => p0 * 0.2 + p1 * 0.3 + p2 * 0.5,
                _ => centre + numbers.point(2.0),
            };
            let distance = if i % 8 < 4 { 3.0 } else { 3000.0 };
            let origin = target + numbers.point(1.0).normalize_or(Vec3A::X) * distance;
            let direction = (target - origin).normalize();
            let t_max = if i % 3 == 0 {
                f32::INFINITY
            } else {
                distance * (0.5 + numbers.next().abs())
            };
            rays.push((origin, direction, t_max));
        }
        (triangles, rays)
    }

    #[test]
    fn every_exact_hit_is_a_candidate_and_most_misses_are_not() {
        let (mut hits, mut candidates, mut tests, mut at_t_max) = (0, 0, 0, 0);
        for seed in 0..8 {
            let (mut triangles, rays) = cases(seed);
            // whole blocks, a tail of a few, a block and a tail, one block padded
            triangles.truncate([63, 38, 7, 16, 63, 38, 2, 25][seed as usize]);
            let blocks = TriangleBlocks::new(&triangles).expect("few triangles");
            for &(origin, direction, t_max) in &rays {
                let ray = ShearedRay::new(origin, direction);
                let mask = blocks.candidates(&ray, t_max);
                for (k, &kernel) in kernels().iter().enumerate() {
                    let other = blocks.candidates_with(kernel, &ray, t_max);
                    assert_eq!(mask, other, "kernel {k} disagrees with the best");
                }
                let baseline = blocks.candidates_with(candidates_plain, &ray, t_max);
                assert_eq!(mask, baseline, "the baseline disagrees");
                assert_eq!(
                    mask >> triangles.len(),
                    0,
                    "padding lanes are never candidates"
                );
                for (i, &[p0, p1, p2]) in triangles.iter().enumerate() {
                    let hit = ray.intersect(t_max, p0, p1, p2).is_some();
                    let candidate = mask >> i & 1 == 1;
                    assert!(
                        !hit || candidate,
                        "triangle {i} is hit but not a candidate (seed {seed}, origin {origin}, direction {direction}, t_max {t_max})"
                    );
                    hits += hit as u32;
                    // a ray that ends where it meets the triangle (a shadow ray's end)
                    if let Some(h) = ray.intersect(f32::INFINITY, p0, p1, p2) {
                        let ends_there = blocks.candidates(&ray, h.t) >> i & 1 == 1;
                        let hits_there = ray.intersect(h.t, p0, p1, p2).is_some();
                        assert!(
                            !hits_there || ends_there,
                            "triangle {i} is hit at t_max = t but not a candidate"
                        );
                        at_t_max += hits_there as u32;
                    }
                    candidates += candidate as u32;
                    tests += 1;
                }
            }
        }
        // aimed rays hit often, and often still at t_max = t; the mask keeps few of the misses
        assert!(
            at_t_max > hits / 2,
            "{at_t_max} hits at t_max = t of {hits}"
        );
        assert!(hits > tests / 40, "{hits} hits of {tests}");
        assert!(
            candidates - hits < (tests - hits) / 500,
            "{candidates} candidates for {hits} hits of {tests}"
        );
    }

    #[test]
    fn rays_grazing_a_shared_edge_keep_the_triangle_they_hit() {
        // The ray runs along +z through the origin, so the sheared frame is
        // the world's; the edge from (a, b) to (−c, −d) passes within an f32
        // rounding of the ray, where the f32 edge function may have the
        // wrong sign. Of the two triangles on either side, the exact test
        // hits at least one; it must stay a candidate.
        let mut numbers = Numbers(7);
        let ray = ShearedRay::new(Vec3A::ZERO, Vec3A::Z);
        let mut kept = 0;
        for _ in 0..4000 {
            let (a, b) = (numbers.next(), numbers.next());
            // (−c, −d) = −(c/a)(a, b): the origin lies between the two ends
            let c = numbers.next().abs().max(0.01).copysign(a);
            let d = b * c / a;
            let (p1, p2) = (Vec3A::new(a, b, 1.0), Vec3A::new(-c, -d, 1.0));
            let side = Vec3A::new(-b, a, 0.0) * 0.5;
            let triangles = [[p1 + side, p1, p2], [p1 - side, p2, p1]];
            let blocks = TriangleBlocks::new(&triangles).expect("two triangles");
            let mask = blocks.candidates(&ray, f32::INFINITY);
            for (i, &[p0, p1, p2]) in triangles.iter().enumerate() {
                if ray.intersect(f32::INFINITY, p0, p1, p2).is_some() {
                    assert!(
                        mask >> i & 1 == 1,
                        "edge ({a}, {b}) to ({}, {d}): triangle {i} lost",
                        -c
                    );
                    kept += 1;
                }
            }
        }
        assert!(kept >= 4000, "the exact test is watertight: {kept} hits");
    }

    #[test]
    fn too_many_triangles_or_none_get_no_blocks() {
        let triangle = [Vec3A::ZERO, Vec3A::X, Vec3A::Y];
        assert!(TriangleBlocks::new(&[]).is_none());
        assert!(TriangleBlocks::new(&vec![triangle; MAX_TRIANGLES]).is_some());
        assert!(TriangleBlocks::new(&vec![triangle; MAX_TRIANGLES + 1]).is_none());
    }
}
