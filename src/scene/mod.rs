//! The scene: what a file said, flattened into world space.
//!
//! A [`Scene`] is plain data with `u32` ids: one vertex pool (positions,
//! optional shading normals, two UV sets), triangles that index it, materials
//! in the glTF metallic-roughness form, textures decoded to linear RGB,
//! punctual lights and cameras. Policy (which terms, which light mode, BRDF
//! override) lives in [`crate::course::RenderSettings`]; derived structures
//! (BVH, light table) are built from the scene, never cached inside it.
//!
//! Units follow the course (`docs/conventions.md`): metres, emitted radiance
//! in W·m⁻²·sr⁻¹, radiant intensity in W·sr⁻¹, irradiance in W·m⁻².

pub mod builtin;
pub mod edits;
pub mod error;
pub mod gltf;
pub mod texture;

use glam::{Affine3A, Vec2, Vec3};
use serde::{Deserialize, Serialize};

pub use texture::{Texture, TextureRef, WrapMode};

/// Index meaning "none" in `u32` id fields.
pub const NO_ID: u32 = u32::MAX;

/// Everything the renderer needs to know about a scene, in world space.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// A name for messages (file name, or the built-in scene's name).
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals in world space, unit length; only read for
    /// triangles with `smooth == true`. Like the UV sets, either empty (no
    /// vertex has one, so nothing is stored) or one per vertex, see
    /// [`append_vertex_attribute`].
    pub normals: Vec<Vec3>,
    /// Texture coordinates, set 0 and set 1: empty, or one per vertex (zero
    /// where the file had none). [`Scene::uv`] reads them.
    pub uv0: Vec<Vec2>,
    pub uv1: Vec<Vec2>,
    pub triangles: Vec<Triangle>,
    /// One entry per mesh instance (glTF node × primitive), for selection and messages.
    pub objects: Vec<Object>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub lights: Vec<PunctualLight>,
    pub cameras: Vec<Camera>,
    /// Non-fatal problems met while loading (unsupported features skipped, …).
    pub warnings: Vec<String>,
}

/// A triangle of the scene; vertices are indices into the scene's vertex pool,
/// counter-clockwise seen from the front (glTF winding).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub vertices: [u32; 3],
    pub material: u32,
    /// Interpolate the vertex normals; false means use the geometric normal.
    pub smooth: bool,
}

/// A mesh instance: what a click in the viewport selects.
#[derive(Clone, Debug, Default)]
pub struct Object {
    pub name: String,
    pub material: u32,
    /// Its scene triangles, which are contiguous: the object of a triangle
    /// is found by [`Scene::object_of_triangle`], not stored with each one.
    pub triangles: std::ops::Range<u32>,
}

/// A glTF metallic-roughness material, as authored, with
/// `KHR_materials_transmission` and `KHR_materials_ior`.
/// [`Material::brdf_model`] maps it onto the course's four models.
#[derive(Clone, Debug)]
pub struct Material {
    pub name: String,
    /// Linear RGB base colour factor.
    pub base_color: Vec3,
    pub base_color_texture: Option<TextureRef>,
    pub metallic: f32,
    pub roughness: f32,
    /// Emitted radiance (W·m⁻²·sr⁻¹ per channel): emissiveFactor × emissive strength.
    pub emission: Vec3,
    pub emission_texture: Option<TextureRef>,
    /// Emits and is seen from both faces (glTF `doubleSided`).
    pub double_sided: bool,
    /// The share of the dielectric part that is glass (glTF
    /// `transmissionFactor`, in [0, 1]): that share of the material is
    /// smooth glass, the rest its metallic-roughness model.
    pub transmission: f32,
    /// Index of refraction of the inside (glTF `KHR_materials_ior`, ≥ 1);
    /// the outside is air, 1.
    pub ior: f32,
}

impl Default for Material {
    fn default() -> Self {
        // the glTF default material: white, metallic 1, roughness 1
        Self {
            name: "default".into(),
            base_color: Vec3::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            emission: Vec3::ZERO,
            emission_texture: None,
            double_sided: false,
            transmission: 0.0,
            ior: crate::course::DEFAULT_IOR,
        }
    }
}

impl Material {
    /// A matte (Lambert) material of albedo `albedo`.
    pub fn lambert(name: &str, albedo: Vec3) -> Self {
        Self {
            name: name.into(),
            base_color: albedo,
            metallic: 0.0,
            roughness: 1.0,
            ..Self::default()
        }
    }

    /// A perfect mirror of reflectance `reflectance`.
    pub fn mirror(name: &str, reflectance: Vec3) -> Self {
        Self {
            name: name.into(),
            base_color: reflectance,
            metallic: 1.0,
            roughness: 0.0,
            ..Self::default()
        }
    }

    /// Smooth glass of index of refraction `ior`, its refraction tinted by `tint`.
    pub fn glass(name: &str, tint: Vec3, ior: f32) -> Self {
        Self {
            name: name.into(),
            base_color: tint,
            metallic: 0.0,
            roughness: 0.0,
            transmission: 1.0,
            ior,
            ..Self::default()
        }
    }

    /// A black Lambert surface emitting radiance `radiance` from its front face.
    pub fn emitter(name: &str, radiance: Vec3) -> Self {
        Self {
            emission: radiance,
            ..Self::lambert(name, Vec3::ZERO)
        }
    }

    /// Whether any part of the surface can emit light.
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// The weight of glass in the material: the transmission of its
    /// dielectric part, transmission × (1 − metallic) (glTF: a metal
    /// transmits nothing).
    pub fn glass_weight(&self) -> f32 {
        (self.transmission * (1.0 - self.metallic)).clamp(0.0, 1.0)
    }

    /// The course's model of the material: glass when it is glass alone,
    /// else its metallic-roughness model ([`Material::opaque_model`]).
    pub fn brdf_model(&self) -> BrdfModel {
        if self.glass_weight() >= 1.0 {
            BrdfModel::Glass
        } else {
            self.opaque_model()
        }
    }

    /// The course's mapping of metallic-roughness onto its three reflection
    /// models (the part of the material that is not glass).
    pub fn opaque_model(&self) -> BrdfModel {
        if self.metallic <= 0.0 && self.roughness >= 1.0 {
            BrdfModel::Lambert
        } else if self.metallic >= 1.0 && self.roughness <= 0.0 {
            BrdfModel::Mirror
        } else {
            let alpha = (self.roughness * self.roughness).max(1e-4);
            let exponent = (2.0 / (alpha * alpha) - 2.0).clamp(0.0, 1e6);
            BrdfModel::Phong { exponent }
        }
    }
}

/// Which of the course's models a material uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BrdfModel {
    Lambert,
    Phong {
        exponent: f32,
    },
    Mirror,
    /// Smooth glass (a dielectric interface).
    Glass,
}

/// A `KHR_lights_punctual` light. `intensity` is `color × intensity`: radiant
/// intensity (W·sr⁻¹) for point and spot lights, irradiance (W·m⁻²) for
/// directional lights.
#[derive(Clone, Debug, PartialEq)]
pub struct PunctualLight {
    pub name: String,
    pub kind: PunctualKind,
    pub position: Vec3,
    /// Unit direction the light points to (its node's −Z); unused for point lights.
    pub direction: Vec3,
    pub intensity: Vec3,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PunctualKind {
    Point,
    /// Cone half-angles in radians, `0 ≤ inner < outer ≤ π/2`.
    Spot {
        inner_cone_angle: f32,
        outer_cone_angle: f32,
    },
    Directional,
}

/// A camera: `world_from_camera` places it; it looks down its −Z with +Y up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Camera {
    pub name: String,
    pub world_from_camera: Affine3A,
    pub projection: Projection,
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Projection {
    /// Vertical field of view in radians.
    Perspective { yfov: f32 },
    /// Half the visible height in metres (glTF `ymag`).
    Orthographic { half_height: f32 },
}

/// Axis-aligned bounds of a set of points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub const EMPTY: Bounds = Bounds {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    pub fn diagonal(&self) -> f32 {
        if self.is_empty() {
            0.0
        } else {
            (self.max - self.min).length()
        }
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
}

impl Scene {
    /// Bounds of the triangles and punctual light positions (not directional lights).
    pub fn bounds(&self) -> Bounds {
        let mut bounds = Bounds::EMPTY;
        for t in &self.triangles {
            for &v in &t.vertices {
                bounds.grow(self.positions[v as usize]);
            }
        }
        for l in &self.lights {
            if l.kind != PunctualKind::Directional {
                bounds.grow(l.position);
            }
        }
        bounds
    }

    /// The object scene triangle `triangle` belongs to.
    pub fn object_of_triangle(&self, triangle: u32) -> u32 {
        self.objects
            .partition_point(|o| o.triangles.end <= triangle) as u32
    }

    /// The scene triangles of `object`.
    pub fn triangles_of_object(&self, object: u32) -> &[Triangle] {
        let range = &self.objects[object as usize].triangles;
        &self.triangles[range.start as usize..range.end as usize]
    }

    /// Texture coordinates of set `set` (0 or 1; higher sets read set 1) at
    /// `vertex`: zero where the scene stores none.
    pub fn uv(&self, set: u32, vertex: u32) -> Vec2 {
        let column = if set == 0 { &self.uv0 } else { &self.uv1 };
        column.get(vertex as usize).copied().unwrap_or(Vec2::ZERO)
    }

    /// Gives back the spare capacity of the geometry arrays once a scene is
    /// complete (they grew by doubling while it was read).
    pub fn shrink_to_fit(&mut self) {
        self.positions.shrink_to_fit();
        self.normals.shrink_to_fit();
        self.uv0.shrink_to_fit();
        self.uv1.shrink_to_fit();
        self.triangles.shrink_to_fit();
    }

    /// The camera a render uses: the scene's first, or one framing the bounds.
    pub fn default_camera(&self) -> Camera {
        self.cameras
            .first()
            .cloned()
            .unwrap_or_else(|| framing_camera(self.bounds()))
    }

    /// Adds a material and returns its id.
    pub fn add_material(&mut self, material: Material) -> u32 {
        self.materials.push(material);
        (self.materials.len() - 1) as u32
    }

    /// Adds an object made of flat (geometric-normal) triangles and returns its id.
    /// `triangles` index `positions`, counter-clockwise from the front.
    pub fn add_mesh(
        &mut self,
        name: &str,
        material: u32,
        positions: &[Vec3],
        triangles: &[[u32; 3]],
    ) -> u32 {
        let object = self.objects.len() as u32;
        let first = self.triangles.len() as u32;
        self.objects.push(Object {
            name: name.into(),
            material,
            triangles: first..first + triangles.len() as u32,
        });
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(positions);
        let (before, count) = (base as usize, positions.len());
        append_vertex_attribute(&mut self.normals, None, before, count, Vec3::Z);
        append_vertex_attribute(&mut self.uv0, None, before, count, Vec2::ZERO);
        append_vertex_attribute(&mut self.uv1, None, before, count, Vec2::ZERO);
        self.triangles.extend(triangles.iter().map(|t| Triangle {
            vertices: [t[0] + base, t[1] + base, t[2] + base],
            material,
            smooth: false,
        }));
        object
    }
}

/// Appends to a per-vertex attribute `column` the values of `count` vertices
/// just added after the first `before`. A column stays empty until some
/// vertex has a value, so a scene without normals or UVs stores none; from
/// then on it holds one value per vertex, `default` for the vertices that
/// had none.
pub fn append_vertex_attribute<T: Copy>(
    column: &mut Vec<T>,
    values: Option<&[T]>,
    before: usize,
    count: usize,
    default: T,
) {
    match values {
        Some(values) => {
            debug_assert_eq!(values.len(), count);
            column.resize(before, default);
            column.extend_from_slice(values);
        }
        None if column.is_empty() => {}
        None => column.resize(before + count, default),
    }
}

/// A camera placed on +Z of the bounds' centre, framing their bounding sphere
/// with a 45° vertical field of view.
pub fn framing_camera(bounds: Bounds) -> Camera {
    let yfov = 45f32.to_radians();
    let (center, radius) = if bounds.is_empty() {
        (Vec3::ZERO, 1.0)
    } else {
        (bounds.center(), (0.5 * bounds.diagonal()).max(1e-6))
    };
    let distance = radius / (0.5 * yfov).sin();
    Camera {
        name: "framing".into(),
        world_from_camera: Affine3A::from_translation(center + Vec3::Z * distance),
        projection: Projection::Perspective { yfov },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vertex_attribute_is_stored_for_every_vertex_or_none() {
        let mut column: Vec<u8> = Vec::new();
        // two meshes without the attribute: nothing stored
        append_vertex_attribute(&mut column, None, 0, 3, 0);
        append_vertex_attribute(&mut column, None, 3, 2, 0);
        assert!(column.is_empty());
        // the first mesh with it back-fills the vertices before with the default
        append_vertex_attribute(&mut column, Some(&[7, 8]), 5, 2, 0);
        assert_eq!(column, [0, 0, 0, 0, 0, 7, 8]);
        // and from then on a mesh without it is padded
        append_vertex_attribute(&mut column, None, 7, 1, 0);
        assert_eq!(column, [0, 0, 0, 0, 0, 7, 8, 0]);
    }

    #[test]
    fn each_triangle_finds_its_object() {
        let mut scene = Scene::default();
        let grey = scene.add_material(Material::lambert("grey", Vec3::ONE));
        let corners = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE];
        let pair = [[0, 1, 2], [1, 3, 2]];
        scene.add_mesh("a", grey, &corners, &pair);
        scene.add_mesh("b", grey, &corners, &pair[..1]);
        scene.add_mesh("c", grey, &corners, &pair);
        let objects: Vec<u32> = (0..5).map(|t| scene.object_of_triangle(t)).collect();
        assert_eq!(objects, [0, 0, 1, 2, 2]);
        assert_eq!(scene.triangles_of_object(1), &scene.triangles[2..3]);
    }
}
