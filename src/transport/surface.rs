//! What a ray hit, seen as a surface: position with its error bound, normals,
//! texture coordinates, emitted radiance and the BRDF there.
//!
//! Emission is one-sided (the front face, by winding) unless the material is
//! double-sided; reflection is two-sided: the shading frame is flipped to the
//! side the ray arrives from. Glass is not: its front face is the outside,
//! so a ray arriving on the back is inside, and sees η inverted.

use glam::{Vec2, Vec3};

use crate::course::{BrdfOverride, RenderSettings};
use crate::geometry::{Frame, Ray, interpolate_point, offset_ray_origin};
use crate::scene::{BrdfModel, Material, Scene, TextureRef};
use crate::transport::brdf::Brdf;
use crate::transport::sampler::mix64;

/// Unit normal of the front face of triangle (p0, p1, p2), counter-clockwise
/// seen from the front; +Z for a degenerate triangle.
#[inline(always)]
pub fn geometric_normal(p0: Vec3, p1: Vec3, p2: Vec3) -> Vec3 {
    (p1 - p0).cross(p2 - p0).normalize_or(Vec3::Z)
}

/// A point on a scene triangle.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    pub p: Vec3,
    /// Bound on the absolute rounding error of `p`, per axis.
    pub p_error: Vec3,
    /// Unit geometric normal of the front face (counter-clockwise winding).
    pub ng: Vec3,
    /// Unit shading normal (interpolated, or `ng`), on the front side.
    pub ns: Vec3,
    /// Barycentrics on the triangle: texture coordinates are interpolated
    /// from them only where a texture is read ([`SurfacePoint::uv`]).
    pub b: Vec3,
    pub triangle: u32,
    pub material: u32,
}

impl SurfacePoint {
    /// The point at barycentrics `b` of scene triangle `triangle`.
    pub fn new(scene: &Scene, triangle: u32, b: Vec3) -> Self {
        let tri = &scene.triangles[triangle as usize];
        let [i0, i1, i2] = tri.vertices.map(|v| v as usize);
        let (p0, p1, p2) = (
            scene.positions[i0],
            scene.positions[i1],
            scene.positions[i2],
        );
        let (p, p_error) = interpolate_point(b, p0, p1, p2);
        let ng = geometric_normal(p0, p1, p2);
        let ns = if tri.smooth {
            let n = b.x * scene.normals[i0] + b.y * scene.normals[i1] + b.z * scene.normals[i2];
            let n = n.normalize_or(ng);
            if n.dot(ng) < 0.0 { -n } else { n }
        } else {
            ng
        };
        Self {
            p,
            p_error,
            ng,
            ns,
            b,
            triangle,
            material: tri.material,
        }
    }

    /// The shading frame on the side of `wo`, and the geometric normal on that side.
    pub fn frame_towards(&self, wo: Vec3) -> (Frame, Vec3) {
        if self.ng.dot(wo) >= 0.0 {
            (Frame::from_z(self.ns), self.ng)
        } else {
            (Frame::from_z(-self.ns), -self.ng)
        }
    }

    /// A ray leaving the surface in direction `w` (unbounded).
    pub fn spawn_ray(&self, w: Vec3) -> Ray {
        Ray::new(
            offset_ray_origin(self.p, self.p_error, self.ng, w),
            w,
            f32::INFINITY,
        )
    }

    /// Texture coordinates of set `set` (0 or 1; higher sets read set 1).
    pub fn uv(&self, scene: &Scene, set: u32) -> Vec2 {
        let [i0, i1, i2] = scene.triangles[self.triangle as usize]
            .vertices
            .map(|v| scene.uv(set, v));
        self.b.x * i0 + self.b.y * i1 + self.b.z * i2
    }

    fn texture(&self, scene: &Scene, texture: Option<TextureRef>) -> Vec3 {
        texture.map_or(Vec3::ONE, |t| {
            scene.textures[t.texture as usize].sample(self.uv(scene, t.uv_set))
        })
    }

    /// Radiance emitted towards `wo` (unit, away from the surface).
    #[inline]
    pub fn emitted(&self, scene: &Scene, wo: Vec3) -> Vec3 {
        let material = &scene.materials[self.material as usize];
        if !material.is_emissive() || !(material.double_sided || self.ng.dot(wo) > 0.0) {
            return Vec3::ZERO;
        }
        material.emission * self.texture(scene, material.emission_texture)
    }

    /// The material's model here, seen from unit `wo`, after the global
    /// override of `settings`. A material partly glass is glass or its other
    /// model, picked by a number hashed from the point and `wo` (pbrt-v4's
    /// `MixMaterial`): a random choice with the glass weight as its
    /// probability, which needs no dimension of the sample.
    pub fn brdf(&self, scene: &Scene, settings: &RenderSettings, wo: Vec3) -> Brdf {
        let material = &scene.materials[self.material as usize];
        let base = material.base_color * self.texture(scene, material.base_color_texture);
        let brdf = resolve_brdf(material, base, settings, || mix_number(self.p, wo));
        if self.ng.dot(wo) >= 0.0 {
            brdf
        } else {
            brdf.seen_from_behind()
        }
    }
}

/// Whether world direction `wi`, drawn as `wi_local` in a shading frame
/// whose z is on `ng`'s side, leaves on the same side of the geometric
/// surface: a reflected direction above it, a refracted one below. A shading
/// normal can tilt a direction across; such a direction is dropped.
#[inline(always)]
pub fn leaves_on_its_side(wi: Vec3, ng: Vec3, wi_local: Vec3) -> bool {
    let across = wi.dot(ng);
    if wi_local.z > 0.0 {
        across > 0.0
    } else {
        across < 0.0
    }
}

/// A number in [0, 1) hashed from a point and a direction.
fn mix_number(p: Vec3, wo: Vec3) -> f32 {
    let mut hash = 0u64;
    for value in [p.x, p.y, p.z, wo.x, wo.y, wo.z] {
        hash = mix64(hash ^ u64::from(value.to_bits()));
    }
    (hash >> 40) as f32 / (1u64 << 24) as f32
}

/// The model of `material` at one point: glass always at glass weight 1,
/// never at 0, else when `pick()` < the weight; otherwise its
/// metallic-roughness model.
#[inline]
fn authored_model(material: &Material, pick: impl FnOnce() -> f32) -> BrdfModel {
    let weight = material.glass_weight();
    if weight >= 1.0 || (weight > 0.0 && pick() < weight) {
        BrdfModel::Glass
    } else {
        material.opaque_model()
    }
}

/// The course's mapping of a material (with base colour `base` already
/// textured) onto Lambert, Phong, mirror or glass, honouring the global
/// override, seen from the front. A material partly glass is glass when
/// `pick()` (a number in [0, 1), read only then) falls below its glass
/// weight.
pub fn resolve_brdf(
    material: &Material,
    base: Vec3,
    settings: &RenderSettings,
    pick: impl FnOnce() -> f32,
) -> Brdf {
    let override_phong = || {
        let ks = settings.phong_specular;
        Brdf::Phong {
            kd: base * (1.0 - ks),
            ks: Vec3::splat(ks),
            exponent: settings.phong_exponent,
        }
    };
    match settings.brdf {
        BrdfOverride::Lambert => Brdf::Lambert { albedo: base },
        BrdfOverride::Mirror => Brdf::Mirror { reflectance: base },
        BrdfOverride::Phong => override_phong(),
        BrdfOverride::Glass => Brdf::Glass {
            tint: base,
            eta: settings.glass_ior,
        },
        BrdfOverride::Authored => match authored_model(material, pick) {
            BrdfModel::Lambert => Brdf::Lambert { albedo: base },
            BrdfModel::Glass => Brdf::Glass {
                tint: base,
                eta: material.ior,
            },
            BrdfModel::Mirror => Brdf::Mirror { reflectance: base },
            BrdfModel::Phong { exponent } => {
                let metallic = material.metallic.clamp(0.0, 1.0);
                let kd = base * (1.0 - metallic);
                let ks = Vec3::splat(0.04).lerp(base, metallic);
                // energy conservation: kd + ks ≤ 1 in every channel
                let scale = (kd + ks).max_element().max(1.0);
                Brdf::Phong {
                    kd: kd / scale,
                    ks: ks / scale,
                    exponent,
                }
            }
        },
    }
}
