//! glTF 2.0 loading (`.gltf` and `.glb`), flattened into a world-space [`Scene`].
//!
//! What is read:
//! * the default scene (else the first scene, else every root node), walking
//!   the node hierarchy and composing TRS and matrix transforms;
//! * mesh primitives in `TRIANGLES` mode, plus `TRIANGLE_STRIP` and
//!   `TRIANGLE_FAN` (converted to triangles), indexed or not, sparse accessors
//!   included; attributes `POSITION`, `NORMAL`, `TEXCOORD_0` and `TEXCOORD_1`;
//! * metallic-roughness materials: base colour factor and texture, metallic
//!   and roughness factors, emissive factor × `KHR_materials_emissive_strength`,
//!   emissive texture, `doubleSided`; `KHR_materials_transmission`'s factor
//!   and `KHR_materials_ior` (glass: every transmissive material is the
//!   boundary of a solid, as with `KHR_materials_volume`, never a thin wall);
//! * PNG and JPEG textures (embedded, in a buffer view or in a file beside the
//!   scene), decoded once to linear RGB, with their sampler's wrap modes;
//! * `KHR_lights_punctual` point, spot and directional lights;
//! * perspective and orthographic cameras, in scene-walk order.
//!
//! Skipped with a warning in [`Scene::warnings`]: points and lines,
//! `metallicRoughnessTexture`, `transmissionTexture`, normal maps, alpha
//! modes, `KHR_texture_transform`,
//! skins, morph targets, animations and any other extension the file uses.
//! Occlusion maps and the alpha of colours are ignored silently. A file that
//! *requires* an extension other than `KHR_lights_punctual`,
//! `KHR_materials_emissive_strength`, `KHR_materials_transmission`,
//! `KHR_materials_ior` or `KHR_texture_transform` is refused.
//!
//! Units, as in the course: metres; angles in radians; linear RGB per
//! channel. Emissive factor × strength is radiance (W·m⁻²·sr⁻¹). A light's
//! `color × intensity` is radiant intensity (W·sr⁻¹) for point and spot
//! lights and irradiance (W·m⁻²) for directional ones, taken as is (no
//! photometric conversion); `range` is ignored. Colour textures are
//! sRGB-decoded at load; shading normals use the inverse transpose of the
//! world matrix; a mirroring transform has its triangles' winding reversed so
//! the glTF front face stays the front face.
//!
//! Robustness: the `gltf` crate checks references between JSON objects but
//! not the data, and panics on some malformed input. So every length, range,
//! index and value is checked before the crate reads it; memory follows the
//! file's size (every declared length is checked against the bytes present
//! before anything is allocated from it; zero-filled accessors and images
//! against caps); and any panic that still happens inside the crate is
//! reported as an error. `docs/robustness.md` lists every check with its test.
//!
//! The way through: `glb` and `validate` read and check the file, `accessors`
//! its buffers; `build` then walks the `nodes`, adding `meshes` (with their
//! `materials` and `textures`), `cameras` and `lights`.

mod accessors;
mod build;
mod cameras;
mod glb;
mod lights;
mod materials;
mod meshes;
mod nodes;
mod panics;
mod textures;
mod validate;

use std::path::Path;

use gltf::Document;
use gltf::buffer::Data as BufferData;

use crate::scene::Scene;
use crate::scene::error::SceneError;
use build::SceneBuilder;
use panics::catch_panics;

/// What went wrong, in words; [`SceneError`] adds the file name.
type Problem = String;
type Loaded<T> = Result<T, Problem>;

/// Loads a .gltf or .glb file (external buffers/images resolved relative to it).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let bytes = std::fs::read(path)
        .map_err(|e| SceneError::new(path, format!("cannot read the file: {e}")))?;
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |name| name.to_string_lossy().into_owned(),
    );
    let base_dir = path.parent().unwrap_or(Path::new(""));
    load_bytes(&bytes, &name, Some(base_dir)).map_err(|problem| SceneError::new(path, problem))
}

/// Loads glTF/GLB bytes; `name` is used in messages and as Scene::name; `base_dir` resolves external URIs (None: only embedded data URIs / GLB BIN allowed).
pub fn load_slice(bytes: &[u8], name: &str, base_dir: Option<&Path>) -> Result<Scene, SceneError> {
    load_bytes(bytes, name, base_dir).map_err(|problem| SceneError::new(name, problem))
}

fn load_bytes(bytes: &[u8], name: &str, base_dir: Option<&Path>) -> Loaded<Scene> {
    catch_panics(|| {
        let file = read_gltf(bytes, base_dir)?;
        nodes::check_node_graph(&file.document)?;
        meshes::check_scene_size(&file.document)?;
        SceneBuilder::new(&file, name, base_dir).build()
    })
}

/// A parsed and checked glTF file: every buffer view and accessor lies inside
/// its data, so the crate's readers can be used without panicking.
struct GltfFile {
    document: Document,
    buffers: Vec<BufferData>,
    warnings: Vec<String>,
}

fn read_gltf(bytes: &[u8], base_dir: Option<&Path>) -> Loaded<GltfFile> {
    let (json, bin) = if glb::is_glb(bytes) {
        glb::split(bytes)?
    } else {
        (bytes, None)
    };
    let root = validate::parse_json(json)?;
    validate::check_version(&root)?;
    validate::check_required_extensions(&root)?;
    validate::check_crate_preconditions(&root, base_dir)?;
    let warnings = validate::extension_warnings(&root);
    let document = validate::validate(root)?;
    let buffers = accessors::load_buffers(&document, base_dir, bin)?;
    accessors::check_views(&document, &buffers)?;
    accessors::check_accessors(&document, &buffers)?;
    Ok(GltfFile {
        document,
        buffers,
        warnings,
    })
}

/// `kind "name"` when the object is named, else `kind index`.
fn label(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(name) => format!("{kind} \"{name}\""),
        None => format!("{kind} {index}"),
    }
}
