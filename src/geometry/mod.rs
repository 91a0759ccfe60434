//! Rays, shading frames and robust floating-point geometry.
//!
//! * [`intersect_triangle`] is the watertight test of Woop, Benthin and Wald
//!   (as in pbrt-v4): the ray is sheared so it runs along +z, the edge
//!   functions are evaluated in 2D with exact signs (products in f64),
//!   and a hit is accepted only when its t exceeds a bound on t's rounding
//!   error. Rays through shared edges and vertices of a closed mesh hit one of
//!   the triangles; none slips through.
//! * Spawned rays start at [`offset_ray_origin`]: the hit point pushed along
//!   the geometric normal by the bound of its own rounding error, then rounded
//!   one ulp further (pbrt-v4 `OffsetRayOrigin`). No fixed epsilon: the offset
//!   scales with the magnitude of the coordinates. Hit points are interpolated
//!   in f64 and rounded once ([`interpolate_point`]), so the bound is one ulp.

pub mod accel;
pub mod camera;

use glam::{Vec3, Vec3A, Vec3Swizzles};

/// γ(n) = nε / (1 − nε), the bound on the relative error of n f32 operations.
pub const fn gamma(n: i32) -> f32 {
    let e = f32::EPSILON * 0.5;
    (n as f32 * e) / (1.0 - n as f32 * e)
}

/// A ray `origin + t·direction` for `t` in (0, `t_max`). The direction need
/// not be unit length; `t` is measured in units of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub direction: Vec3,
    pub t_max: f32,
}

impl Ray {
    pub fn new(origin: Vec3, direction: Vec3, t_max: f32) -> Self {
        Self {
            origin,
            direction,
            t_max,
        }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }
}

/// An orthonormal frame whose z axis is a given unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub x: Vec3,
    pub y: Vec3,
    pub z: Vec3,
}

impl Frame {
    /// Duff et al. 2017, "Building an orthonormal basis, revisited".
    pub fn from_z(z: Vec3) -> Self {
        let sign = 1f32.copysign(z.z);
        let a = -1.0 / (sign + z.z);
        let b = z.x * z.y * a;
        Self {
            x: Vec3::new(1.0 + sign * z.x * z.x * a, sign * b, -sign * z.x),
            y: Vec3::new(b, sign + z.y * z.y * a, -z.y),
            z,
        }
    }

    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    pub fn to_world(&self, v: Vec3) -> Vec3 {
        v.x * self.x + v.y * self.y + v.z * self.z
    }
}

/// The next representable f32 above `v` (towards +∞).
pub fn next_float_up(v: f32) -> f32 {
    if v.is_infinite() && v > 0.0 {
        return v;
    }
    let v = if v == -0.0 { 0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v >= 0.0 { bits + 1 } else { bits - 1 };
    f32::from_bits(bits)
}

/// The next representable f32 below `v` (towards −∞).
pub fn next_float_down(v: f32) -> f32 {
    -next_float_up(-v)
}

/// A ray origin for leaving the surface point `p` (with absolute rounding
/// error at most `p_error` per axis) towards `w`, on the side of the
/// geometric normal `ng` that `w` points to.
#[inline]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, ng: Vec3, w: Vec3) -> Vec3 {
    let d = ng.abs().dot(p_error);
    let offset = if w.dot(ng) < 0.0 { -d * ng } else { d * ng };
    let po = p + offset;
    Vec3::from_array(std::array::from_fn(|axis| {
        step_towards(po[axis], offset[axis])
    }))
}

/// [`next_float_up`] of `v` where `towards` > 0, [`next_float_down`] where
/// it is < 0, `v` where it is 0: the same steps, on the bits, without
/// branches (the offset's signs vary from ray to ray; branching on them
/// made this a twentieth of a Cornell box profile).
#[inline(always)]
fn step_towards(v: f32, towards: f32) -> f32 {
    const SIGN: u32 = 1 << 31;
    let (bits, direction) = (v.to_bits(), towards.to_bits() & SIGN);
    let magnitude = bits & !SIGN;
    let away_from_zero = bits & SIGN == direction;
    let stepped = if magnitude == 0 {
        // ±0: the smallest subnormal on `towards`'s side
        direction | 1
    } else if !away_from_zero {
        bits - 1
    } else if magnitude == f32::INFINITY.to_bits() {
        bits
    } else {
        bits + 1
    };
    if towards == 0.0 {
        v
    } else {
        f32::from_bits(stepped)
    }
}

/// The point of barycentrics `b` on triangle (p0, p1, p2), and a bound on
/// its error per axis.
///
/// The sum is taken in f64, with the barycentrics normalised to sum to 1,
/// where the products err by 2⁻⁵³ relative, then rounded once to f32: each
/// coordinate is within half an ulp of the interpolated point, bounded here
/// by a whole one, ε|p|. The f32 sum of pbrt's interpolation errs by up to
/// γ(7)·Σ|bᵢpᵢ|, about seven times more: 7 cm instead of 1 cm at 10⁵ m from
/// the origin, an offset that moves the point where light is measured.
pub fn interpolate_point(b: Vec3, p0: Vec3, p1: Vec3, p2: Vec3) -> (Vec3, Vec3) {
    // barycentrics that do not sum to 1 exactly would scale the point about
    // the origin, off the triangle's plane: normalised, any weights keep it
    // on the plane
    let b = b.as_dvec3() / (b.x as f64 + b.y as f64 + b.z as f64);
    let exact = b.x * p0.as_dvec3() + b.y * p1.as_dvec3() + b.z * p2.as_dvec3();
    let p = exact.as_vec3();
    // the f64 rounding, and subnormal results, in case |p| is far below the terms
    let b = b.as_vec3();
    let magnitude = (b.x * p0).abs() + (b.y * p1).abs() + (b.z * p2).abs();
    let residue = magnitude * (2.0f32).powi(-48) + Vec3::splat(f32::MIN_POSITIVE);
    (p, p.abs() * f32::EPSILON + residue)
}

/// `a·b − c·d` for f32 inputs: the products are exact in f64 (24-bit
/// mantissas), so the difference is correctly rounded and its sign is exact,
/// which is what makes the edge tests watertight (and needs no FMA unit).
#[inline]
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    (a as f64 * b as f64 - c as f64 * d as f64) as f32
}

/// A ray–triangle hit: distance and barycentrics of (p0, p1, p2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub b0: f32,
    pub b1: f32,
    pub b2: f32,
}

/// A ray prepared for watertight triangle tests: the permutation that makes
/// its dominant axis z and the shear that maps it onto +z, computed once and
/// reused for every triangle it meets.
#[derive(Clone, Copy, Debug)]
pub struct ShearedRay {
    origin: Vec3A,
    direction: Vec3A,
    /// Index of the dominant axis (it becomes z).
    kz: u8,
    shear: Vec3A,
}

impl ShearedRay {
    pub fn new(origin: Vec3A, direction: Vec3A) -> Self {
        let kz = direction.abs().max_position() as u8;
        let d = Self::permute_axes(kz, direction);
        Self {
            origin,
            direction,
            kz,
            shear: Vec3A::new(-d.x / d.z, -d.y / d.z, 1.0 / d.z),
        }
    }

    /// The ray origin, the dominant axis `kz` and the shear (x, y, z): what a
    /// vectorised test needs to repeat [`ShearedRay::intersect`]'s first steps.
    pub(crate) fn frame(&self) -> (Vec3A, u8, Vec3A) {
        (self.origin, self.kz, self.shear)
    }

    /// (x, y, z) reordered so that axis `kz` comes last, keeping the cyclic order.
    #[inline(always)]
    fn permute_axes(kz: u8, v: Vec3A) -> Vec3A {
        match kz {
            0 => v.yzx(),
            1 => v.zxy(),
            _ => v,
        }
    }

    /// The distance along the ray to the plane of (p0, p1, p2), computed in
    /// f64 (the f32 inputs' differences and products are nearly exact), if it
    /// is positive.
    #[cold]
    fn plane_distance(&self, p0: Vec3A, p1: Vec3A, p2: Vec3A) -> Option<f32> {
        let (p0, p1, p2) = (p0.as_dvec3(), p1.as_dvec3(), p2.as_dvec3());
        let normal = (p1 - p0).cross(p2 - p0);
        let towards = normal.dot(self.direction.as_dvec3());
        let t = normal.dot(p0 - self.origin.as_dvec3()) / towards;
        (t > 0.0 && t.is_finite()).then_some(t as f32)
    }

    /// Watertight intersection with triangle (p0, p1, p2) (Woop, Benthin,
    /// Wald 2013; pbrt-v4): the hit with `0 < t < t_max`, or `None`.
    #[inline]
    pub fn intersect(&self, t_max: f32, p0: Vec3A, p1: Vec3A, p2: Vec3A) -> Option<TriangleHit> {
        // translate to the ray origin, permute, shear so the ray runs along +z
        let sheared = |p: Vec3A| {
            let q = Self::permute_axes(self.kz, p - self.origin);
            Vec3A::new(
                q.x + self.shear.x * q.z,
                q.y + self.shear.y * q.z,
                q.z * self.shear.z,
            )
        };
        let (p0t, p1t, p2t) = (sheared(p0), sheared(p1), sheared(p2));

        // edge functions, with exact signs
        let e0 = difference_of_products(p1t.x, p2t.y, p1t.y, p2t.x);
        let e1 = difference_of_products(p2t.x, p0t.y, p2t.y, p0t.x);
        let e2 = difference_of_products(p0t.x, p1t.y, p0t.y, p1t.x);
        if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
            return None;
        }
        let det = e0 + e1 + e2;
        if det == 0.0 || !det.is_finite() {
            return None;
        }

        // scaled distance, tested against (0, t_max) without dividing
        let t_scaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
        if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
            return None;
        }
        if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
            return None;
        }
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;

        // reject hits whose t is not provably positive
        let max_zt = Vec3A::new(p0t.z, p1t.z, p2t.z).abs().max_element();
        let max_xt = Vec3A::new(p0t.x, p1t.x, p2t.x).abs().max_element();
        let max_yt = Vec3A::new(p0t.y, p1t.y, p2t.y).abs().max_element();
        let delta_z = gamma(3) * max_zt;
        let delta_x = gamma(5) * (max_xt + max_zt);
        let delta_y = gamma(5) * (max_yt + max_zt);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = Vec3A::new(e0, e1, e2).abs().max_element();
        let delta_t =
            3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
        let t = if t > delta_t {
            t
        } else {
            // The bound grows with the triangle's size (a 40 m wall: 1 cm), and a
            // wall that close is common (a bounce near a corner). Decide in f64
            // from the triangle's plane instead: rays leave their surface from
            // origins offset off it, so its own plane is strictly behind them.
            self.plane_distance(p0, p1, p2)?
        };
        Some(TriangleHit {
            t,
            b0: e0 * inv_det,
            b1: e1 * inv_det,
            b2: e2 * inv_det,
        })
    }
}

/// Watertight ray–triangle intersection of one ray with one triangle
/// (see [`ShearedRay`] to test many triangles against one ray).
pub fn intersect_triangle(
    origin: Vec3A,
    direction: Vec3A,
    t_max: f32,
    p0: Vec3A,
    p1: Vec3A,
    p2: Vec3A,
) -> Option<TriangleHit> {
    ShearedRay::new(origin, direction).intersect(t_max, p0, p1, p2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_large_triangle_close_ahead_is_hit_and_the_one_left_is_not() {
        // the side wall of a 1 × 1 × 40 m corridor, and a ray leaving the top
        // wall 2 mm from it: the f32 bound on t (1 cm here) cannot decide
        let wall = [
            Vec3A::new(1.0, 0.0, 0.0),
            Vec3A::new(1.0, 1.0, 0.0),
            Vec3A::new(1.0, 1.0, 40.0),
        ];
        let origin = Vec3A::new(0.99806, 0.999_999_5, 1.455_761_2);
        let direction = (Vec3A::new(15.718_858, -13.778_135, 35.615_75) - origin).normalize();
        let hit = intersect_triangle(origin, direction, f32::INFINITY, wall[0], wall[1], wall[2])
            .expect("the wall 5 mm ahead");
        assert!((hit.t - 0.005_274_86).abs() < 1e-6, "t = {}", hit.t);
        // leaving the wall from a point offset off it: no hit on the wall itself
        let on_wall = Vec3::new(1.0, 0.7, 20.0);
        let inward = -Vec3::X;
        let leaving = offset_ray_origin(on_wall, Vec3::splat(gamma(7) * 20.0), Vec3::X, inward);
        for direction in [
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(-1e-3, 0.3, 1.0),
            Vec3::new(-1e-6, -0.5, -1.0),
        ] {
            let direction = Vec3A::from(direction.normalize());
            assert!(
                intersect_triangle(
                    leaving.into(),
                    direction,
                    f32::INFINITY,
                    wall[0],
                    wall[1],
                    wall[2]
                )
                .is_none(),
                "self-intersection leaving along {direction}"
            );
        }
    }

    #[test]
    fn frame_is_orthonormal() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let f = Frame::from_z(n);
            assert!(f.x.dot(f.y).abs() < 1e-6 && f.x.dot(f.z).abs() < 1e-6);
            assert!((f.x.length() - 1.0).abs() < 1e-6 && (f.y.length() - 1.0).abs() < 1e-6);
            assert!((f.x.cross(f.y) - f.z).length() < 1e-5);
            let v = Vec3::new(0.3, -0.4, 0.5);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-6);
        }
    }

    #[test]
    fn triangle_hit_and_miss() {
        let (p0, p1, p2) = (
            Vec3A::new(0.0, 0.0, 0.0),
            Vec3A::new(1.0, 0.0, 0.0),
            Vec3A::new(0.0, 1.0, 0.0),
        );
        let o = Vec3A::new(0.25, 0.25, 1.0);
        let hit = intersect_triangle(o, -Vec3A::Z, f32::INFINITY, p0, p1, p2).unwrap();
        assert!((hit.t - 1.0).abs() < 1e-6);
        assert!((hit.b1 - 0.25).abs() < 1e-6 && (hit.b2 - 0.25).abs() < 1e-6);
        assert!(intersect_triangle(o, -Vec3A::Z, 0.5, p0, p1, p2).is_none());
        assert!(intersect_triangle(o, Vec3A::Z, f32::INFINITY, p0, p1, p2).is_none());
        let outside = Vec3A::new(0.75, 0.75, 1.0);
        assert!(intersect_triangle(outside, -Vec3A::Z, f32::INFINITY, p0, p1, p2).is_none());
    }

    #[test]
    fn offset_origin_leaves_the_surface_on_the_right_side() {
        let p = Vec3::new(1e4, 3.0, -2e3);
        let err = Vec3::splat(1e-3);
        let n = Vec3::Y;
        assert!(offset_ray_origin(p, err, n, Vec3::Y).y > p.y);
        assert!(offset_ray_origin(p, err, n, -Vec3::Y).y < p.y);
        assert_eq!(next_float_up(0.0), f32::from_bits(1));
        // the branch-free step is next_float_up / _down, value for value
        let values = [
            0.0,
            -0.0,
            f32::from_bits(1),
            -f32::from_bits(1),
            1.0,
            -1.0,
            f32::MIN_POSITIVE,
            -3.5e7,
            f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for v in values {
            assert_eq!(
                step_towards(v, 2.0).to_bits(),
                next_float_up(v).to_bits(),
                "{v} up"
            );
            assert_eq!(
                step_towards(v, -2.0).to_bits(),
                next_float_down(v).to_bits(),
                "{v} down"
            );
            assert_eq!(step_towards(v, 0.0).to_bits(), v.to_bits(), "{v} stays");
        }
        assert!(next_float_down(1.0) < 1.0);
    }
}
