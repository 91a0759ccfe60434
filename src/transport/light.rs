//! One light source: what it is ([`Light`], a spot's [`Cone`]), what a
//! sample of it gives ([`LightSample`]), and how a point or a direction is
//! drawn on an extended light: a triangle by area (uniform point, pdf
//! d² / (A cos θ′)) or by solid angle (Arvo's spherical triangle, pdf 1/Ω),
//! a sphere by the cone of directions it subtends (pdf 1 / (2π (1 − cos
//! θ_max))). `transport::lights` picks the light and calls these.

use glam::{DVec3, Vec2, Vec3};
use std::f32::consts::PI;

use crate::geometry::accel::{Sphere, intersect_sphere};
use crate::geometry::{Frame, Ray, interpolate_point, offset_ray_origin};
use crate::scene::Scene;
use crate::transport::surface::SurfacePoint;
use crate::transport::warps::{
    spherical_triangle, spherical_triangle_area, uniform_cone, uniform_cone_pdf, uniform_triangle,
};

/// Shadow rays stop this fraction short of the light point (pbrt's ShadowEpsilon):
/// both ends are already offset off their surfaces, this only absorbs the
/// rounding of `origin + t·direction` near t = 1.
pub(crate) const SHADOW_EPSILON: f32 = 1e-4;

/// The angular profile of a spot light (glTF KHR_lights_punctual falloff).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Unit direction the light points to.
    pub axis: Vec3,
    pub cos_inner: f32,
    pub cos_outer: f32,
}

impl Cone {
    /// Fraction of the peak intensity emitted along unit `direction`:
    /// squared linear ramp in cos θ between the outer and inner cones.
    pub fn falloff(&self, direction: Vec3) -> f32 {
        let scale = 1.0 / (self.cos_inner - self.cos_outer).max(1e-3);
        let t = ((self.axis.dot(direction) - self.cos_outer) * scale).clamp(0.0, 1.0);
        t * t
    }

    /// Solid angle ∫ falloff dω (approximate: the mean of the two cones').
    pub(crate) fn solid_angle(&self) -> f32 {
        2.0 * PI * (1.0 - 0.5 * (self.cos_inner + self.cos_outer))
    }
}

/// One light source of a render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// An emissive scene triangle, with what a light sample on it reads
    /// copied from the scene: a sample then costs no triangle, vertex or
    /// material lookups and no normal.
    Triangle {
        triangle: u32,
        area: f32,
        /// Its corners, as the scene stores them.
        corners: [Vec3; 3],
        /// Unit geometric normal of its front face.
        normal: Vec3,
        /// Emitted radiance, when it is the same all over the triangle (no
        /// emission texture); else it is looked up per point.
        uniform_radiance: Option<Vec3>,
        double_sided: bool,
    },
    /// A point light of intensity I (W/sr), optionally restricted to a cone.
    Point {
        position: Vec3,
        intensity: Vec3,
        cone: Option<Cone>,
    },
    /// An area light collapsed to a point: I(ω) = radiance_area · max(0, n·ω).
    CosinePoint {
        position: Vec3,
        normal: Vec3,
        radiance_area: Vec3,
        two_sided: bool,
    },
    /// Parallel light of irradiance E (W/m²) arriving from `towards_light`.
    Directional {
        towards_light: Vec3,
        irradiance: Vec3,
    },
    /// A point light made extended: sphere `sphere` of the accel.
    Sphere {
        sphere: Sphere,
        intensity: Vec3,
        cone: Option<Cone>,
    },
}

impl Light {
    /// Whether the light is a Dirac in position or direction (BRDF sampling cannot hit it).
    pub fn is_delta(&self) -> bool {
        !matches!(self, Light::Triangle { .. } | Light::Sphere { .. })
    }

    /// Radiant intensity of a point-like light towards unit `direction`.
    pub(crate) fn intensity_towards(intensity: Vec3, cone: &Option<Cone>, direction: Vec3) -> Vec3 {
        match cone {
            Some(c) => intensity * c.falloff(direction),
            None => intensity,
        }
    }
}

/// Incident light drawn at a surface point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the surface towards the light.
    pub wi: Vec3,
    /// Incident radiance (Dirac lights: I/d² or E).
    pub radiance: Vec3,
    /// Solid-angle density including the light's selection probability
    /// (Dirac lights: the selection probability).
    pub pdf: f32,
    pub delta: bool,
    /// The ray whose occlusion hides the light.
    pub shadow_ray: Ray,
    /// Sphere the shadow ray ends on, not to be counted as an occluder.
    pub target_sphere: Option<u32>,
}

/// How a point on an emissive triangle is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriangleSampling {
    /// Uniform in area: pdf d² / (A cos θ_q) in solid angle.
    #[default]
    Area,
    /// Uniform in the solid angle Ω the triangle subtends: pdf 1/Ω; area
    /// sampling where Ω is outside [`SOLID_ANGLE_RANGE`].
    SolidAngle,
}

/// Solid angles (sr) sampled as spherical triangles; outside, f32 and f64
/// rounding make Arvo's method unreliable and area sampling takes over
/// (pbrt-v4's bounds).
pub const SOLID_ANGLE_RANGE: std::ops::RangeInclusive<f64> = 3e-4..=6.22;

/// The light that point `b` (barycentrics) of triangle light `light`
/// sends to `at`, with the shadow ray between them and the solid-angle pdf
/// of uniform area sampling. The point, its error bound and its normal are
/// those [`SurfacePoint::new`] gives, computed from the light's own copy.
#[inline(always)]
pub(crate) fn light_point_sample(
    scene: &Scene,
    at: &SurfacePoint,
    light: &Light,
    b: Vec3,
) -> Option<LightSample> {
    let &Light::Triangle {
        triangle,
        area,
        corners: [p0, p1, p2],
        normal,
        uniform_radiance,
        double_sided,
    } = light
    else {
        return None;
    };
    let (p, p_error) = interpolate_point(b, p0, p1, p2);
    let to_light = p - at.p;
    let distance2 = to_light.length_squared();
    if distance2 <= 0.0 {
        return None;
    }
    let wi = to_light / distance2.sqrt();
    let radiance = match uniform_radiance {
        // one-sided emission faces the front only, as SurfacePoint::emitted says
        Some(radiance) if double_sided || normal.dot(-wi) > 0.0 => radiance,
        Some(_) => Vec3::ZERO,
        None => SurfacePoint::new(scene, triangle, b).emitted(scene, -wi),
    };
    let cos_light = normal.dot(-wi).abs();
    if radiance.max_element() <= 0.0 || cos_light <= 0.0 {
        return None;
    }
    let origin = offset_ray_origin(at.p, at.p_error, at.ng, wi);
    let target = offset_ray_origin(p, p_error, normal, -wi);
    Some(LightSample {
        wi,
        radiance,
        pdf: distance2 / (cos_light * area),
        delta: false,
        shadow_ray: Ray::new(origin, target - origin, 1.0 - SHADOW_EPSILON),
        target_sphere: None,
    })
}

/// Solid angle (sr) that scene triangle `triangle` subtends from `from`.
pub(crate) fn triangle_solid_angle(scene: &Scene, triangle: u32, from: Vec3) -> f64 {
    let [a, b, c] = directions_to_triangle(scene, triangle, from);
    spherical_triangle_area(a, b, c)
}

/// Unit directions (f64) from `from` to the vertices of scene triangle `triangle`.
pub(crate) fn directions_to_triangle(scene: &Scene, triangle: u32, from: Vec3) -> [DVec3; 3] {
    let from = from.as_dvec3();
    scene.triangles[triangle as usize]
        .vertices
        .map(|v| (scene.positions[v as usize].as_dvec3() - from).normalize_or_zero())
}

/// A uniform direction in the solid angle an emissive triangle subtends from
/// `at` (area sampling outside [`SOLID_ANGLE_RANGE`]), and the light point it meets.
pub(crate) fn sample_triangle_solid_angle(
    scene: &Scene,
    at: &SurfacePoint,
    light: &Light,
    triangle: u32,
    u: Vec2,
) -> Option<LightSample> {
    let [a, b, c] = directions_to_triangle(scene, triangle, at.p);
    if !SOLID_ANGLE_RANGE.contains(&spherical_triangle_area(a, b, c)) {
        return light_point_sample(scene, at, light, uniform_triangle(u));
    }
    let (direction, pdf) = spherical_triangle(a, b, c, u)?;
    // the point of the triangle along the direction, as barycentrics
    let [p0, p1, p2] = scene.triangles[triangle as usize]
        .vertices
        .map(|v| scene.positions[v as usize].as_dvec3());
    let (e1, e2) = (p1 - p0, p2 - p0);
    let s1 = direction.cross(e2);
    let divisor = s1.dot(e1);
    if divisor == 0.0 {
        return None;
    }
    let s = at.p.as_dvec3() - p0;
    let b1 = (s.dot(s1) / divisor).clamp(0.0, 1.0);
    let b2 = (direction.dot(s.cross(e1)) / divisor).clamp(0.0, 1.0);
    let (b1, b2) = if b1 + b2 > 1.0 {
        (b1 / (b1 + b2), b2 / (b1 + b2))
    } else {
        (b1, b2)
    };
    let barycentrics = Vec3::new((1.0 - b1 - b2) as f32, b1 as f32, b2 as f32);
    let mut sample = light_point_sample(scene, at, light, barycentrics)?;
    sample.pdf = pdf as f32;
    Some(sample)
}

/// The cone of directions from `from` to `sphere`: its axis and 1 − cos θmax
/// (`None` from inside the sphere).
pub(crate) fn cone_of(sphere: &Sphere, from: Vec3) -> Option<(Vec3, f32)> {
    let to_center = sphere.center - from;
    let distance2 = to_center.length_squared();
    let r2 = sphere.radius * sphere.radius;
    if distance2 <= r2 {
        return None;
    }
    let sin2_max = r2 / distance2;
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    // 1 − cos = sin² / (1 + cos), exact for small cones
    Some((to_center / distance2.sqrt(), sin2_max / (1.0 + cos_max)))
}

/// A direction in the cone a sphere light subtends from `at`.
pub(crate) fn sample_sphere(
    at: &SurfacePoint,
    sphere: &Sphere,
    intensity: Vec3,
    cone: &Option<Cone>,
    u: Vec2,
    sphere_index: u32,
) -> Option<LightSample> {
    let (axis, one_minus_cos) = cone_of(sphere, at.p)?;
    let wi = Frame::from_z(axis)
        .to_world(uniform_cone(u, one_minus_cos))
        .normalize();
    let probe = Ray::new(at.p, wi, f32::INFINITY);
    // a grazing direction may miss by rounding: take the point of closest approach
    let t =
        intersect_sphere(&probe, sphere, f32::INFINITY).unwrap_or((sphere.center - at.p).dot(wi));
    let target = at.p + t * wi;
    let radiance =
        Light::intensity_towards(intensity, cone, -wi) / (PI * sphere.radius * sphere.radius);
    let origin = offset_ray_origin(at.p, at.p_error, at.ng, wi);
    Some(LightSample {
        wi,
        radiance,
        pdf: uniform_cone_pdf(one_minus_cos),
        delta: false,
        shadow_ray: Ray::new(origin, target - origin, 1.0 - SHADOW_EPSILON),
        target_sphere: Some(sphere_index),
    })
}
