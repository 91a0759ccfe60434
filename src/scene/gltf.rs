//! glTF 2.0 loading (`.gltf` with embedded or external buffers, `.glb`).
//!
//! Supported: the node hierarchy (TRS and matrices) of the default scene,
//! triangle primitives with or without indices and normals, two UV sets,
//! metallic-roughness materials with base colour and emissive textures
//! (sRGB-decoded), `KHR_materials_emissive_strength`, `KHR_lights_punctual`
//! and cameras. Units and mappings are those of `docs/conventions.md`:
//! emissive = radiance (W·m⁻²·sr⁻¹), punctual `color × intensity` = radiant
//! intensity (W·sr⁻¹) or irradiance (W·m⁻²) for directional lights.
//!
//! The `gltf` crate validates references between JSON objects, not the data.
//! Everything it would trust is checked here first (GLB framing, accessor
//! ranges, index values, finite numbers, node cycles), and any panic left in
//! the crate is caught and reported as an error: a bad file never takes the
//! program down.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use glam::{Affine3A, Mat3, Mat4, Vec2, Vec3};
use gltf::Document;
use gltf::accessor::{Accessor, DataType};
use gltf::mesh::Mode;

use super::{
    Camera, Material, Object, Projection, PunctualKind, PunctualLight, Scene, Texture, TextureRef,
    Triangle, WrapMode,
};
use crate::color::srgb_to_linear;
use crate::error::SceneError;

/// Extensions whose absence would change the image; others are ignored with a warning.
const SUPPORTED_EXTENSIONS: [&str; 3] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_texture_transform",
];

/// Loads a `.gltf` or `.glb` file; external buffers and images are resolved next to it.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let bytes = std::fs::read(path)
        .map_err(|e| SceneError::new(path, format!("cannot read the file: {e}")))?;
    let name = path.display().to_string();
    let base_dir = path.parent().unwrap_or(Path::new("."));
    load_slice(&bytes, &name, Some(base_dir))
}

/// Loads glTF or GLB bytes. `name` appears in messages and as the scene's name;
/// `base_dir` resolves external URIs (`None`: only embedded data is allowed).
pub fn load_slice(bytes: &[u8], name: &str, base_dir: Option<&Path>) -> Result<Scene, SceneError> {
    let fail = |problem: String| SceneError::new(name, problem);
    check_glb_framing(bytes).map_err(fail)?;
    let result = quietly_catching_panics(|| Loader::run(bytes, name, base_dir));
    match result {
        Ok(inner) => inner.map_err(fail),
        Err(message) => Err(fail(format!(
            "malformed file (the glTF parser failed: {message})"
        ))),
    }
}

/// Runs `f`, turning a panic into `Err(message)` without printing it.
fn quietly_catching_panics<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = catch_unwind(AssertUnwindSafe(f));
    std::panic::set_hook(previous);
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "internal error".into())
    })
}

/// Checks a GLB container's header and chunk lengths against the real size
/// (the crate trusts them and can underflow or allocate from a lying header).
fn check_glb_framing(bytes: &[u8]) -> Result<(), String> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let word = |offset: usize| -> Option<u32> {
        bytes
            .get(offset..offset + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let version = word(4).ok_or("GLB header is truncated (fewer than 12 bytes)")?;
    if version != 2 {
        return Err(format!("GLB version {version} is not supported (only 2)"));
    }
    let total = word(8).ok_or("GLB header is truncated (fewer than 12 bytes)")? as usize;
    if total < 20 || total > bytes.len() {
        return Err(format!(
            "GLB header declares {total} bytes but the file has {} (truncated or corrupt)",
            bytes.len()
        ));
    }
    let mut offset = 12;
    let mut first = true;
    while offset < total {
        let (Some(length), Some(kind)) = (word(offset), word(offset + 4)) else {
            return Err(format!("GLB chunk header at byte {offset} is truncated"));
        };
        let end = offset + 8 + length as usize;
        if end > total {
            return Err(format!(
                "GLB chunk at byte {offset} declares {length} bytes, past the end of the file ({total} bytes)"
            ));
        }
        if first && kind != 0x4E4F_534A {
            return Err("GLB's first chunk is not JSON".into());
        }
        first = false;
        offset = end;
    }
    Ok(())
}

/// Loading state: the document, its decoded data and the scene being filled.
struct Loader {
    document: Document,
    buffers: Vec<gltf::buffer::Data>,
    images: Vec<gltf::image::Data>,
    scene: Scene,
    /// glTF material index (None: default material) → scene material id.
    materials: HashMap<Option<usize>, u32>,
    /// glTF texture index → scene texture id.
    textures: HashMap<usize, u32>,
}

impl Loader {
    fn run(bytes: &[u8], name: &str, base_dir: Option<&Path>) -> Result<Scene, String> {
        let gltf =
            gltf::Gltf::from_slice(bytes).map_err(|e| format!("not a valid glTF file: {e}"))?;
        check_extensions(&gltf.document)?;
        let buffers = gltf::import_buffers(&gltf.document, base_dir, gltf.blob.clone())
            .map_err(|e| format!("cannot load a buffer: {e}"))?;
        for (buffer, data) in gltf.document.buffers().zip(&buffers) {
            if data.len() < buffer.length() {
                return Err(format!(
                    "buffer {} declares {} bytes but holds {}",
                    buffer.index(),
                    buffer.length(),
                    data.len()
                ));
            }
        }
        let images = gltf::import_images(&gltf.document, base_dir, &buffers)
            .map_err(|e| format!("cannot load an image: {e}"))?;
        let mut loader = Loader {
            document: gltf.document,
            buffers,
            images,
            scene: Scene {
                name: name.into(),
                ..Scene::default()
            },
            materials: HashMap::new(),
            textures: HashMap::new(),
        };
        loader.warn_about_unused_extensions();
        loader.walk_scene()?;
        Ok(loader.scene)
    }

    fn warn_about_unused_extensions(&mut self) {
        for extension in self.document.extensions_used() {
            if !SUPPORTED_EXTENSIONS.contains(&extension) {
                self.scene.warnings.push(format!(
                    "extension {extension} is not supported and is ignored"
                ));
            }
        }
    }

    /// Visits the nodes of the default scene (or of the first, or every root).
    fn walk_scene(&mut self) -> Result<(), String> {
        // the nodes borrow the document while the scene is filled
        let document = self.document.clone();
        let roots: Vec<usize> = match self
            .document
            .default_scene()
            .or_else(|| self.document.scenes().next())
        {
            Some(scene) => scene.nodes().map(|n| n.index()).collect(),
            None => {
                let mut is_child = vec![false; self.document.nodes().count()];
                for node in self.document.nodes() {
                    for child in node.children() {
                        is_child[child.index()] = true;
                    }
                }
                (0..is_child.len()).filter(|&i| !is_child[i]).collect()
            }
        };
        let mut visited = vec![false; self.document.nodes().count()];
        let mut stack: Vec<(usize, Mat4)> = roots
            .into_iter()
            .rev()
            .map(|i| (i, Mat4::IDENTITY))
            .collect();
        while let Some((index, parent)) = stack.pop() {
            if std::mem::replace(&mut visited[index], true) {
                return Err(format!(
                    "node {index} is reached twice (a cycle or a shared child in the node hierarchy)"
                ));
            }
            let node = document
                .nodes()
                .nth(index)
                .ok_or("node index out of range")?;
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            let world = parent * local;
            if !world.is_finite() {
                return Err(format!(
                    "node {} has a non-finite transform",
                    node_name(&node)
                ));
            }
            self.add_node(&node, world)?;
            for child in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((child.index(), world));
            }
        }
        Ok(())
    }

    fn add_node(&mut self, node: &gltf::Node, world: Mat4) -> Result<(), String> {
        if let Some(mesh) = node.mesh() {
            if world.determinant().abs() < 1e-30 {
                return Err(format!(
                    "node {} has a singular transform (zero scale)",
                    node_name(node)
                ));
            }
            for primitive in mesh.primitives() {
                self.add_primitive(node, &mesh, &primitive, world)?;
            }
        }
        if let Some(camera) = node.camera() {
            self.add_camera(node, &camera, world)?;
        }
        if let Some(light) = node.light() {
            self.add_light(node, &light, world)?;
        }
        Ok(())
    }

    fn add_primitive(
        &mut self,
        node: &gltf::Node,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
        world: Mat4,
    ) -> Result<(), String> {
        let what = format!(
            "mesh {} primitive {}",
            mesh.name()
                .map_or(mesh.index().to_string(), |n| format!("\"{n}\"")),
            primitive.index()
        );
        if primitive.mode() != Mode::Triangles {
            self.scene.warnings.push(format!(
                "{what}: mode {:?} is not supported (only triangles); skipped",
                primitive.mode()
            ));
            return Ok(());
        }
        let position_accessor = primitive
            .get(&gltf::Semantic::Positions)
            .ok_or_else(|| format!("{what}: no POSITION attribute"))?;
        for (_, accessor) in primitive.attributes() {
            check_accessor(&accessor, &self.buffers).map_err(|e| format!("{what}: {e}"))?;
        }
        if let Some(indices) = primitive.indices() {
            if !matches!(
                indices.data_type(),
                DataType::U8 | DataType::U16 | DataType::U32
            ) {
                return Err(format!(
                    "{what}: indices must be unsigned bytes, shorts or ints, not {:?}",
                    indices.data_type()
                ));
            }
            check_accessor(&indices, &self.buffers).map_err(|e| format!("{what}: indices: {e}"))?;
        }
        let reader = primitive.reader(|b| self.buffers.get(b.index()).map(|d| &d.0[..]));
        let local_positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| format!("{what}: POSITION cannot be read"))?
            .map(Vec3::from_array)
            .collect();
        if local_positions.len() != position_accessor.count() {
            return Err(format!("{what}: POSITION has fewer values than its count"));
        }
        let vertex_count = local_positions.len();
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        let positions: Vec<Vec3> = local_positions
            .iter()
            .map(|p| world.transform_point3(*p))
            .collect();
        if let Some(bad) = positions.iter().position(|p| !p.is_finite()) {
            return Err(format!("{what}: vertex {bad} has a non-finite position"));
        }
        let normals: Option<Vec<Vec3>> = reader
            .read_normals()
            .map(|n| {
                n.map(|n| (normal_matrix * Vec3::from_array(n)).normalize_or_zero())
                    .collect::<Vec<_>>()
            })
            .filter(|n: &Vec<Vec3>| {
                n.len() == vertex_count && n.iter().all(|v| v.is_finite() && *v != Vec3::ZERO)
            });
        let uv = |set: u32| -> Vec<Vec2> {
            reader
                .read_tex_coords(set)
                .map(|t| t.into_f32().map(Vec2::from_array).collect::<Vec<_>>())
                .filter(|t| t.len() == vertex_count)
                .unwrap_or_else(|| vec![Vec2::ZERO; vertex_count])
        };
        let (uv0, uv1) = (uv(0), uv(1));
        let indices: Vec<u32> = match reader.read_indices() {
            Some(indices) => indices.into_u32().collect(),
            None => (0..vertex_count as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(format!(
                "{what}: index {bad} out of range ({vertex_count} vertices)"
            ));
        }
        let material = self.material(primitive.material())?;
        let object = self.scene.objects.len() as u32;
        self.scene.objects.push(Object {
            name: node
                .name()
                .or(mesh.name())
                .map_or_else(|| format!("mesh {}", mesh.index()), str::to_string),
            material,
        });
        let base = self.scene.positions.len() as u32;
        let smooth = normals.is_some();
        self.scene.positions.extend(positions);
        self.scene
            .normals
            .extend(normals.unwrap_or_else(|| vec![Vec3::Z; vertex_count]));
        self.scene.uv0.extend(uv0);
        self.scene.uv1.extend(uv1);
        // a mirroring transform turns counter-clockwise into clockwise: restore the front face
        let flip = world.determinant() < 0.0;
        for t in indices.chunks_exact(3) {
            let (a, b, c) = (t[0] + base, t[1] + base, t[2] + base);
            self.scene.triangles.push(Triangle {
                vertices: if flip { [a, c, b] } else { [a, b, c] },
                material,
                object,
                smooth,
            });
        }
        Ok(())
    }

    /// The scene material for a glTF material (created on first use).
    fn material(&mut self, material: gltf::Material) -> Result<u32, String> {
        if let Some(&id) = self.materials.get(&material.index()) {
            return Ok(id);
        }
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor();
        let emission = Vec3::from_array(material.emissive_factor())
            * material.emissive_strength().unwrap_or(1.0);
        let name = material.name().map_or_else(
            || {
                material
                    .index()
                    .map_or("default".into(), |i| format!("material {i}"))
            },
            str::to_string,
        );
        if !emission.is_finite() || emission.min_element() < 0.0 {
            return Err(format!(
                "material {name}: emission {emission} must be finite and non-negative"
            ));
        }
        if pbr.metallic_roughness_texture().is_some() {
            self.scene.warnings.push(format!(
                "material {name}: the metallic-roughness texture is ignored (factors are used)"
            ));
        }
        let converted = Material {
            name,
            base_color: Vec3::new(r, g, b).max(Vec3::ZERO),
            base_color_texture: self.texture(pbr.base_color_texture())?,
            metallic: pbr.metallic_factor().clamp(0.0, 1.0),
            roughness: pbr.roughness_factor().clamp(0.0, 1.0),
            emission,
            emission_texture: self.texture(material.emissive_texture())?,
            double_sided: material.double_sided(),
        };
        let id = self.scene.add_material(converted);
        self.materials.insert(material.index(), id);
        Ok(id)
    }

    /// The scene texture for a colour texture reference (sRGB-decoded).
    fn texture(&mut self, info: Option<gltf::texture::Info>) -> Result<Option<TextureRef>, String> {
        let Some(info) = info else {
            return Ok(None);
        };
        let uv_set = match info.tex_coord() {
            set @ (0 | 1) => set,
            other => {
                self.scene.warnings.push(format!(
                    "texture coordinate set {other} is not supported; set 0 is used"
                ));
                0
            }
        };
        let texture = info.texture();
        let id = match self.textures.get(&texture.index()) {
            Some(&id) => id,
            None => {
                let image = self
                    .images
                    .get(texture.source().index())
                    .ok_or_else(|| format!("texture {} has no image", texture.index()))?;
                let sampler = texture.sampler();
                let decoded = Texture {
                    name: texture.name().unwrap_or("texture").into(),
                    width: image.width,
                    height: image.height,
                    texels: decode_srgb_image(image)
                        .map_err(|e| format!("texture {}: {e}", texture.index()))?,
                    wrap_s: wrap_mode(sampler.wrap_s()),
                    wrap_t: wrap_mode(sampler.wrap_t()),
                };
                self.scene.textures.push(decoded);
                let id = (self.scene.textures.len() - 1) as u32;
                self.textures.insert(texture.index(), id);
                id
            }
        };
        Ok(Some(TextureRef {
            texture: id,
            uv_set,
        }))
    }

    fn add_camera(
        &mut self,
        node: &gltf::Node,
        camera: &gltf::Camera,
        world: Mat4,
    ) -> Result<(), String> {
        let name = camera
            .name()
            .or(node.name())
            .unwrap_or("camera")
            .to_string();
        let projection = match camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let yfov = p.yfov();
                if !(yfov.is_finite() && yfov > 0.0 && yfov < std::f32::consts::PI) {
                    return Err(format!("camera {name}: yfov {yfov} must be within (0, π)"));
                }
                Projection::Perspective { yfov }
            }
            gltf::camera::Projection::Orthographic(o) => {
                let ymag = o.ymag().abs();
                if !(ymag.is_finite() && ymag > 0.0) {
                    return Err(format!("camera {name}: ymag {} must be positive", o.ymag()));
                }
                Projection::Orthographic { half_height: ymag }
            }
        };
        self.scene.cameras.push(Camera {
            name,
            world_from_camera: rigid_part(world).ok_or("camera node has a degenerate transform")?,
            projection,
        });
        Ok(())
    }

    fn add_light(
        &mut self,
        node: &gltf::Node,
        light: &gltf::khr_lights_punctual::Light,
        world: Mat4,
    ) -> Result<(), String> {
        use gltf::khr_lights_punctual::Kind;
        let name = light.name().or(node.name()).unwrap_or("light").to_string();
        let intensity = Vec3::from_array(light.color()) * light.intensity();
        if !intensity.is_finite() || intensity.min_element() < 0.0 {
            return Err(format!(
                "light {name}: color × intensity = {intensity} must be finite and non-negative"
            ));
        }
        let kind = match light.kind() {
            Kind::Point => PunctualKind::Point,
            Kind::Directional => PunctualKind::Directional,
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let half_pi = std::f32::consts::FRAC_PI_2;
                if !(0.0 < outer_cone_angle
                    && outer_cone_angle <= half_pi
                    && inner_cone_angle >= 0.0)
                {
                    return Err(format!(
                        "light {name}: spot cone angles inner {inner_cone_angle}, outer {outer_cone_angle} must satisfy 0 ≤ inner < outer ≤ π/2"
                    ));
                }
                let inner = if inner_cone_angle < outer_cone_angle {
                    inner_cone_angle
                } else {
                    self.scene.warnings.push(format!(
                        "light {name}: inner cone angle {inner_cone_angle} ≥ outer {outer_cone_angle}; using a hard edge"
                    ));
                    outer_cone_angle * 0.999
                };
                PunctualKind::Spot {
                    inner_cone_angle: inner,
                    outer_cone_angle,
                }
            }
        };
        let direction = world.transform_vector3(-Vec3::Z).normalize_or_zero();
        if kind != PunctualKind::Point && direction == Vec3::ZERO {
            return Err(format!(
                "light {name}: its node's transform has no direction"
            ));
        }
        self.scene.lights.push(PunctualLight {
            name,
            kind,
            position: world.transform_point3(Vec3::ZERO),
            direction,
            intensity,
        });
        Ok(())
    }
}

fn node_name(node: &gltf::Node) -> String {
    node.name()
        .map_or_else(|| node.index().to_string(), |n| format!("\"{n}\""))
}

/// Rejects files that require extensions lumiere does not implement.
fn check_extensions(document: &Document) -> Result<(), String> {
    let unsupported: Vec<&str> = document
        .extensions_required()
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
        .collect();
    if unsupported.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "requires unsupported extension(s): {}",
            unsupported.join(", ")
        ))
    }
}

/// Checks that an accessor's elements lie inside its buffer view and buffer.
fn check_accessor(accessor: &Accessor, buffers: &[gltf::buffer::Data]) -> Result<(), String> {
    let count = accessor.count();
    let element = accessor.size();
    if let Some(view) = accessor.view() {
        let stride = view.stride().unwrap_or(element);
        let needed = if count == 0 {
            0
        } else {
            accessor.offset() + stride * (count - 1) + element
        };
        if needed > view.length() {
            return Err(format!(
                "accessor {} needs {needed} bytes but its buffer view has {}",
                accessor.index(),
                view.length()
            ));
        }
        let buffer_length = buffers.get(view.buffer().index()).map_or(0, |b| b.len());
        if view.offset() + view.length() > buffer_length {
            return Err(format!(
                "buffer view {} ends at byte {} but its buffer has {buffer_length}",
                view.index(),
                view.offset() + view.length()
            ));
        }
    }
    if let Some(sparse) = accessor.sparse() {
        if sparse.count() > count {
            return Err(format!(
                "accessor {}: more sparse values than elements",
                accessor.index()
            ));
        }
        for view in [sparse.indices().view(), sparse.values().view()] {
            let buffer_length = buffers.get(view.buffer().index()).map_or(0, |b| b.len());
            if view.offset() + view.length() > buffer_length {
                return Err(format!(
                    "sparse buffer view {} lies outside its buffer",
                    view.index()
                ));
            }
        }
    }
    Ok(())
}

/// Rotation and translation of an affine transform (scale and shear removed).
fn rigid_part(world: Mat4) -> Option<Affine3A> {
    let (_, rotation, translation) = world.to_scale_rotation_translation();
    let rotation = rotation.normalize();
    (rotation.is_finite() && translation.is_finite())
        .then(|| Affine3A::from_rotation_translation(rotation, translation))
}

fn wrap_mode(mode: gltf::texture::WrappingMode) -> WrapMode {
    match mode {
        gltf::texture::WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
        gltf::texture::WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => WrapMode::Repeat,
    }
}

/// Linear RGB texels of a colour image (8- and 16-bit values are sRGB-encoded).
fn decode_srgb_image(image: &gltf::image::Data) -> Result<Vec<Vec3>, String> {
    use gltf::image::Format;
    let texels = image.width as usize * image.height as usize;
    let (channels, bytes_per_channel) = match image.format {
        Format::R8 => (1, 1),
        Format::R8G8 => (2, 1),
        Format::R8G8B8 => (3, 1),
        Format::R8G8B8A8 => (4, 1),
        Format::R16 => (1, 2),
        Format::R16G16 => (2, 2),
        Format::R16G16B16 => (3, 2),
        Format::R16G16B16A16 => (4, 2),
        Format::R32G32B32FLOAT => (3, 4),
        Format::R32G32B32A32FLOAT => (4, 4),
    };
    let stride = channels * bytes_per_channel;
    if image.pixels.len() < texels * stride {
        return Err("image data is shorter than its size".into());
    }
    let channel = |texel: &[u8], c: usize| -> f32 {
        let c = c.min(channels - 1);
        let at = c * bytes_per_channel;
        match bytes_per_channel {
            1 => srgb_to_linear(texel[at] as f32 / 255.0),
            2 => srgb_to_linear(u16::from_le_bytes([texel[at], texel[at + 1]]) as f32 / 65535.0),
            _ => f32::from_le_bytes([texel[at], texel[at + 1], texel[at + 2], texel[at + 3]]),
        }
    };
    Ok(image.pixels[..texels * stride]
        .chunks_exact(stride)
        .map(|t| {
            if channels == 2 {
                // luminance + alpha: grey
                Vec3::splat(channel(t, 0))
            } else {
                Vec3::new(channel(t, 0), channel(t, 1), channel(t, 2))
            }
        })
        .collect())
}
