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
//!   emissive texture, `doubleSided`;
//! * PNG and JPEG textures (embedded, in a buffer view or in a file beside the
//!   scene), decoded once to linear RGB, with their sampler's wrap modes;
//! * `KHR_lights_punctual` point, spot and directional lights;
//! * perspective and orthographic cameras, in scene-walk order.
//!
//! Skipped with a warning in [`Scene::warnings`]: points and lines,
//! `metallicRoughnessTexture`, normal maps, alpha modes, `KHR_texture_transform`,
//! skins, morph targets, animations and any other extension the file uses.
//! Occlusion maps and the alpha of colours are ignored silently. A file that
//! *requires* an extension other than `KHR_lights_punctual`,
//! `KHR_materials_emissive_strength` or `KHR_texture_transform` is refused.
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
//! not the data, and panics on some malformed input. So this module checks
//! the GLB framing, buffer view and accessor ranges (sparse ones included),
//! index values, finiteness of positions, normals, UVs and transforms, and
//! the node graph (no cycles, one parent per node) before reading anything.
//! Memory follows the file's size: every declared length is checked against
//! the bytes present before anything is allocated from it, except accessors
//! without a buffer view (at most 64 MiB of zeros) and images (their declared
//! size is checked against a cap and against what their encoded bytes can
//! hold before decoding); external URIs must name regular files. Any panic
//! that still happens inside the crate is caught and reported as an error.
//! `docs/robustness.md` lists every check with its test.

use std::borrow::Cow;
use std::cell::Cell;
use std::collections::{HashMap, HashSet};
use std::f32::consts::{FRAC_PI_2, PI};
use std::io::Cursor;
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::{Once, OnceLock};

use glam::{Affine3A, Mat3, Mat4, Quat, Vec2, Vec3, Vec4};
use gltf::Document;
use gltf::accessor::{Accessor, DataType, Dimensions, Item};
use gltf::buffer::Data as BufferData;
use gltf::mesh::{Mode, Semantic};
use gltf::scene::Transform;
use image::DynamicImage;

use super::texture::srgb_to_linear;
use super::{
    Camera, Material, Object, Projection, PunctualKind, PunctualLight, Scene, Texture, TextureRef,
    Triangle, WrapMode, append_vertex_attribute,
};
use crate::render::film::memory_ceiling;
use crate::scene::error::SceneError;

/// What went wrong, in words; [`SceneError`] adds the file name.
type Problem = String;
type Loaded<T> = Result<T, Problem>;

/// Extensions a file may list in `extensionsRequired`.
const ACCEPTED_REQUIRED_EXTENSIONS: [&str; 3] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_texture_transform",
];

/// Extensions that are read (every other one is ignored with a warning).
const READ_EXTENSIONS: [&str; 2] = ["KHR_lights_punctual", "KHR_materials_emissive_strength"];

/// Largest size in bytes of an accessor without a buffer view (its elements
/// are zeros, allocated from the declared count alone).
const MAX_ZERO_FILLED_BYTES: usize = 64 << 20;

/// Largest number of triangles, and of vertices, in a loaded scene (instancing
/// lets a small file describe more geometry than memory holds).
const MAX_SCENE_ELEMENTS: usize = 1 << 26;

/// Heap bytes a triangle takes at the peak of loading a scene and building
/// its BVH: `lumiere bench` measures 296 for a file of positions only, one
/// vertex per triangle (docs/benchmarks.md); an unindexed mesh with normals
/// and two UV sets adds 3 × 28 bytes of vertex data. Rounded up.
const PEAK_BYTES_PER_TRIANGLE: u64 = 512;

/// The most triangles a scene may have, and why: [`MAX_SCENE_ELEMENTS`], and
/// no more than fit with their BVH in the memory a film may take
/// ([`memory_ceiling`]), so that instancing a mesh many times is refused with
/// a message rather than by the allocator.
fn scene_triangle_limit() -> (usize, String) {
    static LIMIT: OnceLock<(usize, String)> = OnceLock::new();
    LIMIT.get_or_init(compute_scene_triangle_limit).clone()
}

fn compute_scene_triangle_limit() -> (usize, String) {
    let (ceiling, reason) = memory_ceiling();
    let by_memory = ceiling / PEAK_BYTES_PER_TRIANGLE;
    if by_memory >= MAX_SCENE_ELEMENTS as u64 {
        return (MAX_SCENE_ELEMENTS, "the loader's limit".to_string());
    }
    let gib = ceiling as f64 / (1u64 << 30) as f64;
    (
        by_memory as usize,
        format!(
            "about {PEAK_BYTES_PER_TRIANGLE} bytes each with the BVH; the limit is {gib:.1} GiB, {reason}"
        ),
    )
}

/// Largest world-space coordinate of a vertex, in metres (about seven light
/// hours): beyond it the BVH builder's surface areas, times triangle counts,
/// overflow f32 and its partitioning fails.
const MAX_COORDINATE: f32 = 1e12;

/// Largest texture width or height accepted.
const MAX_TEXTURE_SIDE: u32 = 16384;

/// Largest number of texels in a texture (8192 × 4096; 384 MiB as linear RGB f32).
const MAX_TEXTURE_TEXELS: u64 = 1 << 25;

/// Texels an encoded image may declare per byte of its encoding: deflate
/// expands at most about 1032:1, and a 1-bit PNG packs 8 pixels in a byte.
/// A header declaring more is lying about the data that follows.
const MAX_TEXELS_PER_ENCODED_BYTE: u64 = 8 * 1032;

/// Texels any encoded image may declare, however small its encoding.
const MIN_TEXEL_ALLOWANCE: u64 = 1 << 16;

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
        SceneBuilder::new(&file, name, base_dir).build()
    })
}

// ---------------------------------------------------------------------------
// Panics

thread_local! {
    /// Whether a panic on this thread is expected to be caught by `catch_panics`.
    static QUIET_PANICS: Cell<bool> = const { Cell::new(false) };
}

/// Runs `load`, turning a panic inside it (a malformed file reaching an
/// assertion in the gltf crate) into a problem, without printing the panic.
fn catch_panics<T>(load: impl FnOnce() -> Loaded<T>) -> Loaded<T> {
    install_quiet_panic_hook();
    let was_quiet = QUIET_PANICS.replace(true);
    let outcome = panic::catch_unwind(AssertUnwindSafe(load));
    QUIET_PANICS.set(was_quiet);
    outcome.unwrap_or_else(|payload| {
        Err(format!(
            "malformed file (the glTF reader failed: {})",
            panic_message(payload.as_ref())
        ))
    })
}

/// Wraps the process's panic hook, once, so that panics on a thread inside
/// `catch_panics` print nothing; panics elsewhere reach the previous hook.
fn install_quiet_panic_hook() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if !QUIET_PANICS.try_with(Cell::get).unwrap_or(false) {
                previous(info);
            }
        }));
    });
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> &str {
    if let Some(text) = payload.downcast_ref::<&str>() {
        text
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text
    } else {
        "unknown panic"
    }
}

// ---------------------------------------------------------------------------
// The file: container, JSON, validation, buffers

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
    let root = parse_json(json)?;
    check_version(&root)?;
    check_required_extensions(&root)?;
    check_crate_preconditions(&root, base_dir)?;
    let warnings = extension_warnings(&root);
    let document = validate(root)?;
    let buffers = load_buffers(&document, base_dir, bin)?;
    check_views(&document, &buffers)?;
    check_accessors(&document, &buffers)?;
    Ok(GltfFile {
        document,
        buffers,
        warnings,
    })
}

/// The binary container: a 12-byte header, then chunks (JSON first, then an optional BIN).
mod glb {
    use super::Loaded;

    const MAGIC: &[u8; 4] = b"glTF";
    const HEADER_LEN: usize = 12;
    const CHUNK_HEADER_LEN: usize = 8;
    const JSON: [u8; 4] = *b"JSON";
    const BIN: [u8; 4] = *b"BIN\0";

    pub(super) fn is_glb(bytes: &[u8]) -> bool {
        bytes.starts_with(MAGIC)
    }

    /// Splits a GLB file into its JSON chunk and its BIN chunk (if any),
    /// checking every declared length against the bytes really present.
    pub(super) fn split(bytes: &[u8]) -> Loaded<(&[u8], Option<&[u8]>)> {
        if bytes.len() < HEADER_LEN {
            return Err(format!(
                "GLB file of {} bytes is shorter than its 12-byte header",
                bytes.len()
            ));
        }
        let version = read_u32(bytes, 4);
        if version != 2 {
            return Err(format!("GLB version {version} is not supported (only 2)"));
        }
        let total = read_u32(bytes, 8) as usize;
        if total > bytes.len() {
            return Err(format!(
                "GLB header declares {total} bytes but the file has only {}",
                bytes.len()
            ));
        }
        if total < HEADER_LEN + CHUNK_HEADER_LEN {
            return Err(format!(
                "GLB header declares {total} bytes, too few for a JSON chunk (at least 20)"
            ));
        }
        let mut chunks = Chunks {
            bytes: &bytes[..total],
            offset: HEADER_LEN,
            number: 0,
        };
        let json = match chunks.next_chunk()? {
            Some((JSON, data)) => data,
            Some((kind, _)) => {
                return Err(format!(
                    "the first GLB chunk must be JSON, not {:?}",
                    String::from_utf8_lossy(&kind)
                ));
            }
            None => return Err("GLB file has no JSON chunk".into()),
        };
        let mut bin = None;
        while let Some((kind, data)) = chunks.next_chunk()? {
            // chunks of unknown types are skipped, as the specification asks
            if kind == BIN && bin.is_none() {
                bin = Some(data);
            }
        }
        Ok((json, bin))
    }

    struct Chunks<'a> {
        bytes: &'a [u8],
        offset: usize,
        number: usize,
    }

    impl<'a> Chunks<'a> {
        fn next_chunk(&mut self) -> Loaded<Option<([u8; 4], &'a [u8])>> {
            let remaining = self.bytes.len() - self.offset;
            if remaining == 0 {
                return Ok(None);
            }
            if remaining < CHUNK_HEADER_LEN {
                return Err(format!(
                    "GLB chunk {} header is truncated ({remaining} of 8 bytes)",
                    self.number
                ));
            }
            let length = read_u32(self.bytes, self.offset) as usize;
            let mut kind = [0; 4];
            kind.copy_from_slice(&self.bytes[self.offset + 4..self.offset + 8]);
            let start = self.offset + CHUNK_HEADER_LEN;
            if length > self.bytes.len() - start {
                return Err(format!(
                    "GLB chunk {} ({:?}) declares {length} bytes but only {} remain",
                    self.number,
                    String::from_utf8_lossy(&kind),
                    self.bytes.len() - start
                ));
            }
            self.offset = start + length;
            self.number += 1;
            Ok(Some((kind, &self.bytes[start..start + length])))
        }
    }

    fn read_u32(bytes: &[u8], at: usize) -> u32 {
        u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
    }
}

fn parse_json(json: &[u8]) -> Loaded<gltf::json::Root> {
    // tolerate a UTF-8 byte order mark and NUL padding, which some writers emit
    let json = json.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(json);
    let end = json
        .iter()
        .rposition(|&b| b != 0)
        .map_or(0, |last| last + 1);
    gltf::json::deserialize::from_slice(&json[..end])
        .map_err(|e| format!("not a valid glTF JSON document: {e}"))
}

fn check_version(root: &gltf::json::Root) -> Loaded<()> {
    let version = &root.asset.version;
    if version.split('.').next() == Some("2") {
        Ok(())
    } else {
        Err(format!(
            "glTF version {version} is not supported (only 2.x)"
        ))
    }
}

fn check_required_extensions(root: &gltf::json::Root) -> Loaded<()> {
    let unsupported: Vec<&str> = root
        .extensions_required
        .iter()
        .map(String::as_str)
        .filter(|name| !ACCEPTED_REQUIRED_EXTENSIONS.contains(name))
        .collect();
    match unsupported.as_slice() {
        [] => Ok(()),
        [name] => Err(format!(
            "the file requires extension {name}, which is not supported"
        )),
        names => Err(format!(
            "the file requires extensions {}, which are not supported",
            names.join(", ")
        )),
    }
}

fn extension_warnings(root: &gltf::json::Root) -> Vec<String> {
    root.extensions_used
        .iter()
        .filter(|name| !READ_EXTENSIONS.contains(&name.as_str()))
        .map(|name| {
            if name == "KHR_texture_transform" {
                "extension KHR_texture_transform is not supported: texture offsets, \
                 rotations and scales are ignored"
                    .to_string()
            } else {
                format!("extension {name} is not supported; ignored")
            }
        })
        .collect()
}

/// Checks what the crate would otherwise hit with an index or an `unwrap`
/// while validating or reading (it panics instead of reporting).
fn check_crate_preconditions(root: &gltf::json::Root, base_dir: Option<&Path>) -> Loaded<()> {
    check_position_accessor_indices(root)?;
    check_camera_projections(root)?;
    let buffer_uris = root
        .buffers
        .iter()
        .enumerate()
        .filter_map(|(i, b)| Some((format!("buffer {i}"), b.uri.as_deref()?)));
    let image_uris = root
        .images
        .iter()
        .enumerate()
        .filter_map(|(i, image)| Some((format!("image {i}"), image.uri.as_deref()?)));
    for (owner, uri) in buffer_uris.chain(image_uris) {
        check_uri(&owner, uri, base_dir)?;
    }
    Ok(())
}

/// The crate's validation indexes `accessors[POSITION]` without a bounds check.
fn check_position_accessor_indices(root: &gltf::json::Root) -> Loaded<()> {
    use gltf::json::validation::Checked;
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive
                .attributes
                .get(&Checked::Valid(Semantic::Positions));
            if let Some(index) = position
                && index.value() >= root.accessors.len()
            {
                return Err(format!(
                    "mesh {m} primitive {p}: POSITION refers to accessor {index}, which does not exist"
                ));
            }
        }
    }
    Ok(())
}

/// The crate unwraps the projection object named by a camera's `type`.
fn check_camera_projections(root: &gltf::json::Root) -> Loaded<()> {
    use gltf::json::camera::Type;
    use gltf::json::validation::Checked;
    for (i, camera) in root.cameras.iter().enumerate() {
        let missing = match camera.type_ {
            Checked::Valid(Type::Perspective) => {
                camera.perspective.is_none().then_some("perspective")
            }
            Checked::Valid(Type::Orthographic) => {
                camera.orthographic.is_none().then_some("orthographic")
            }
            Checked::Invalid => None, // reported by validation
        };
        if let Some(kind) = missing {
            return Err(format!(
                "camera {i} has type {kind} but no \"{kind}\" object"
            ));
        }
    }
    Ok(())
}

/// External references need a base directory; relative URIs must
/// percent-decode to UTF-8 (the crate unwraps the decoding); what they name
/// must be a regular file (a device or a pipe would be read without end).
fn check_uri(owner: &str, uri: &str, base_dir: Option<&Path>) -> Loaded<()> {
    if uri.starts_with("data:") {
        return Ok(());
    }
    let Some(base_dir) = base_dir else {
        return Err(format!(
            "{owner} refers to the external file \"{uri}\", but the scene was given as bytes \
             without a directory to resolve it"
        ));
    };
    // the crate's resolution: file: URIs as paths, other schemes refused, the rest relative
    let path = if let Some(path) = uri.strip_prefix("file://").or(uri.strip_prefix("file:")) {
        PathBuf::from(path)
    } else if uri.contains(':') {
        return Ok(());
    } else {
        let decoded = percent_decode(uri).ok_or_else(|| {
            format!("{owner}: URI \"{uri}\" does not percent-decode to valid UTF-8")
        })?;
        base_dir.join(decoded)
    };
    match std::fs::metadata(&path) {
        Ok(metadata) if !metadata.is_file() => {
            Err(format!("{owner}: \"{uri}\" is not a regular file"))
        }
        _ => Ok(()),
    }
}

fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let escape = bytes
            .get(i + 1..i + 3)
            .filter(|hex| bytes[i] == b'%' && hex.iter().all(u8::is_ascii_hexdigit));
        match escape {
            Some(hex) => {
                decoded.push(hex_value(hex[0]) << 4 | hex_value(hex[1]));
                i += 3;
            }
            None => {
                decoded.push(bytes[i]);
                i += 1;
            }
        }
    }
    String::from_utf8(decoded).ok()
}

fn hex_value(digit: u8) -> u8 {
    match digit {
        b'0'..=b'9' => digit - b'0',
        b'a'..=b'f' => digit - b'a' + 10,
        _ => digit - b'A' + 10,
    }
}

/// Runs the crate's validation of references and enumerations, tolerating
/// what this loader handles itself.
fn validate(root: gltf::json::Root) -> Loaded<Document> {
    use gltf::json::validation::Validate;
    let mut problems = Vec::new();
    root.validate(&root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        if !is_tolerated(path.as_str(), error) {
            problems.push(format!("{}: {error}", path.as_str()));
        }
    });
    if problems.is_empty() {
        return Ok(Document::from_json_without_validation(root));
    }
    let shown = problems.len().min(5);
    let mut message = format!("invalid glTF: {}", problems[..shown].join("; "));
    if problems.len() > shown {
        message += &format!(" (and {} more)", problems.len() - shown);
    }
    Err(message)
}

fn is_tolerated(path: &str, error: gltf::json::validation::Error) -> bool {
    use gltf::json::validation::Error;
    // the specification: an accessor without a buffer view holds zeros
    let zero_accessor =
        error == Error::Missing && path.starts_with("accessors[") && path.ends_with("].bufferView");
    // already checked against ACCEPTED_REQUIRED_EXTENSIONS
    let accepted_extension = error == Error::Unsupported && path.starts_with("extensionsRequired");
    zero_accessor || accepted_extension
}

fn load_buffers(
    document: &Document,
    base_dir: Option<&Path>,
    bin: Option<&[u8]>,
) -> Loaded<Vec<BufferData>> {
    let mut blob = bin.map(<[u8]>::to_vec);
    document
        .buffers()
        .map(|buffer| load_buffer(&buffer, base_dir, &mut blob))
        .collect()
}

fn load_buffer(
    buffer: &gltf::Buffer,
    base_dir: Option<&Path>,
    blob: &mut Option<Vec<u8>>,
) -> Loaded<BufferData> {
    let label = match buffer.source() {
        gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => {
            format!("buffer {} (\"{uri}\")", buffer.index())
        }
        _ => format!("buffer {}", buffer.index()),
    };
    if let gltf::buffer::Source::Bin = buffer.source() {
        let Some(bin) = blob.as_ref() else {
            return Err(format!(
                "{label} has no uri and there is no (unclaimed) GLB BIN chunk"
            ));
        };
        if bin.len() < buffer.length() {
            return Err(format!(
                "{label}: byteLength is {} but the GLB BIN chunk holds only {} bytes",
                buffer.length(),
                bin.len()
            ));
        }
    }
    let data = BufferData::from_source_and_blob(buffer.source(), base_dir, blob)
        .map_err(|e| format!("{label}: cannot load: {e}"))?;
    if data.len() < buffer.length() {
        return Err(format!(
            "{label}: byteLength is {} but the data holds only {} bytes",
            buffer.length(),
            data.len()
        ));
    }
    Ok(data)
}

fn check_views(document: &Document, buffers: &[BufferData]) -> Loaded<()> {
    for view in document.views() {
        let buffer = view.buffer();
        let available = buffer.length().min(buffers[buffer.index()].len());
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|end| end > available) {
            return Err(format!(
                "buffer view {}: {} bytes from byte {} do not fit buffer {} ({available} bytes)",
                view.index(),
                view.length(),
                view.offset(),
                buffer.index()
            ));
        }
    }
    Ok(())
}

fn check_accessors(document: &Document, buffers: &[BufferData]) -> Loaded<()> {
    for accessor in document.accessors() {
        check_accessor(&accessor, buffers)
            .map_err(|problem| format!("accessor {}: {problem}", accessor.index()))?;
    }
    Ok(())
}

/// Checks that every element the crate will read lies inside the buffer view.
fn check_accessor(accessor: &Accessor, buffers: &[BufferData]) -> Loaded<()> {
    let count = accessor.count();
    if count == 0 {
        return Err("count is 0".into());
    }
    let element_size = accessor.size();
    match accessor.view() {
        Some(view) => check_strided_range("data", &view, accessor.offset(), element_size, count)?,
        None if count.saturating_mul(element_size) > MAX_ZERO_FILLED_BYTES => {
            return Err(format!(
                "count {count} of {element_size}-byte elements without a buffer view \
                 (at most {} MiB of zeros are accepted)",
                MAX_ZERO_FILLED_BYTES >> 20
            ));
        }
        None => {}
    }
    if let Some(sparse) = accessor.sparse() {
        check_sparse(&sparse, count, element_size, buffers)?;
    }
    Ok(())
}

/// `count` elements of `element_size` bytes, `stride` apart (the view's
/// `byteStride`, else packed), from `offset`, must fit in `view`.
fn check_strided_range(
    what: &str,
    view: &gltf::buffer::View,
    offset: usize,
    element_size: usize,
    count: usize,
) -> Loaded<()> {
    let stride = view.stride().unwrap_or(element_size);
    if stride < element_size {
        return Err(format!(
            "{what}: byteStride {stride} is smaller than the element size {element_size}"
        ));
    }
    let end = stride
        .checked_mul(count - 1)
        .and_then(|span| span.checked_add(offset))
        .and_then(|span| span.checked_add(element_size));
    if end.is_some_and(|end| end <= view.length()) {
        Ok(())
    } else {
        Err(format!(
            "{what}: {count} elements of {element_size} bytes (stride {stride}) from byte \
             {offset} do not fit buffer view {} ({} bytes)",
            view.index(),
            view.length()
        ))
    }
}

fn check_sparse(
    sparse: &gltf::accessor::sparse::Sparse,
    count: usize,
    element_size: usize,
    buffers: &[BufferData],
) -> Loaded<()> {
    let sparse_count = sparse.count();
    if sparse_count == 0 || sparse_count > count {
        return Err(format!(
            "sparse count {sparse_count} must lie between 1 and the accessor count {count}"
        ));
    }
    let indices = sparse.indices();
    let index_size = indices.index_type().size();
    check_strided_range(
        "sparse indices",
        &indices.view(),
        indices.offset(),
        index_size,
        sparse_count,
    )?;
    let values = sparse.values();
    check_strided_range(
        "sparse values",
        &values.view(),
        values.offset(),
        element_size,
        sparse_count,
    )?;
    check_sparse_indices(&indices, sparse_count, count, buffers)
}

/// Sparse indices must be strictly increasing and below the accessor count
/// (the crate silently drops values otherwise).
fn check_sparse_indices(
    indices: &gltf::accessor::sparse::Indices,
    sparse_count: usize,
    count: usize,
    buffers: &[BufferData],
) -> Loaded<()> {
    let view = indices.view();
    let data = &buffers[view.buffer().index()][view.offset()..view.offset() + view.length()];
    let size = indices.index_type().size();
    let stride = view.stride().unwrap_or(size);
    let mut previous = None;
    for k in 0..sparse_count {
        let at = indices.offset() + k * stride;
        let index = data[at..at + size]
            .iter()
            .rev()
            .fold(0usize, |value, &byte| (value << 8) | usize::from(byte));
        if index >= count {
            return Err(format!(
                "sparse index {index} out of range ({count} elements)"
            ));
        }
        if previous.is_some_and(|previous| index <= previous) {
            return Err("sparse indices are not strictly increasing".into());
        }
        previous = Some(index);
    }
    Ok(())
}

/// Reads every element of `accessor` as `T` (whose layout the caller has
/// checked); an accessor without buffer view or sparse data holds zeros.
fn read_accessor<T: Item + Clone>(accessor: &Accessor, buffers: &[BufferData]) -> Loaded<Vec<T>> {
    if accessor.view().is_none() && accessor.sparse().is_none() {
        return Ok(vec![T::zero(); accessor.count()]);
    }
    let buffer_data = |buffer: gltf::Buffer| buffers.get(buffer.index()).map(|data| &data[..]);
    let items: Vec<T> = gltf::accessor::Iter::new(accessor.clone(), buffer_data)
        .ok_or_else(|| format!("accessor {}: data out of range", accessor.index()))?
        .collect();
    if items.len() != accessor.count() {
        return Err(format!(
            "accessor {}: read {} elements instead of {}",
            accessor.index(),
            items.len(),
            accessor.count()
        ));
    }
    Ok(items)
}

/// e.g. "VEC3 of FLOAT".
fn layout_name(accessor: &Accessor) -> String {
    let dimensions = match accessor.dimensions() {
        Dimensions::Scalar => "SCALAR",
        Dimensions::Vec2 => "VEC2",
        Dimensions::Vec3 => "VEC3",
        Dimensions::Vec4 => "VEC4",
        Dimensions::Mat2 => "MAT2",
        Dimensions::Mat3 => "MAT3",
        Dimensions::Mat4 => "MAT4",
    };
    let component = match accessor.data_type() {
        DataType::I8 => "BYTE",
        DataType::U8 => "UNSIGNED_BYTE",
        DataType::I16 => "SHORT",
        DataType::U16 => "UNSIGNED_SHORT",
        DataType::U32 => "UNSIGNED_INT",
        DataType::F32 => "FLOAT",
    };
    format!("{dimensions} of {component}")
}

fn is_vec3_of_float(accessor: &Accessor) -> bool {
    accessor.dimensions() == Dimensions::Vec3 && accessor.data_type() == DataType::F32
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

/// `kind "name"` when the object is named, else `kind index`.
fn label(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(name) => format!("{kind} \"{name}\""),
        None => format!("{kind} {index}"),
    }
}

// ---------------------------------------------------------------------------
// Node graph and transforms

/// Refuses node graphs that are not forests: a node listed as the child of
/// two nodes, or a cycle (which would make a naive walk recurse forever).
fn check_node_graph(document: &Document) -> Loaded<()> {
    let nodes = &document.as_json().nodes;
    let node_label = |i: usize| label("node", i, nodes[i].name.as_deref());
    let mut parents: Vec<Option<usize>> = vec![None; nodes.len()];
    for (parent, node) in nodes.iter().enumerate() {
        for child in node.children.iter().flatten().map(|c| c.value()) {
            if let Some(first) = parents[child] {
                return Err(if first == parent {
                    format!(
                        "{} lists {} twice as a child",
                        node_label(parent),
                        node_label(child)
                    )
                } else {
                    format!(
                        "{} is a child of both {} and {} (a node may have only one parent)",
                        node_label(child),
                        node_label(first),
                        node_label(parent)
                    )
                });
            }
            parents[child] = Some(parent);
        }
    }
    if let Some(cycle) = find_parent_cycle(&parents) {
        let names: Vec<String> = cycle.into_iter().map(node_label).collect();
        return Err(format!("node cycle: {}", names.join(" → ")));
    }
    Ok(())
}

/// With at most one parent per node, a cycle is a chain of parents that comes
/// back to itself. Returns it from parent to child, closed (first = last).
fn find_parent_cycle(parents: &[Option<usize>]) -> Option<Vec<usize>> {
    #[derive(Clone, Copy, PartialEq)]
    enum State {
        Unseen,
        OnChain,
        Done,
    }
    let mut states = vec![State::Unseen; parents.len()];
    for start in 0..parents.len() {
        let mut chain = Vec::new();
        let mut at = Some(start);
        while let Some(node) = at {
            match states[node] {
                State::Done => break,
                State::OnChain => {
                    let begin = chain.iter().position(|&n| n == node).unwrap_or(0);
                    let mut cycle: Vec<usize> = chain[begin..].to_vec();
                    cycle.push(node);
                    cycle.reverse();
                    return Some(cycle);
                }
                State::Unseen => {
                    states[node] = State::OnChain;
                    chain.push(node);
                    at = parents[node];
                }
            }
        }
        for node in chain {
            states[node] = State::Done;
        }
    }
    None
}

/// The nodes the walk starts from: the default scene's, else the first
/// scene's, else (a file without scenes) every node without a parent.
fn scene_roots(document: &Document) -> Vec<gltf::Node<'_>> {
    if let Some(scene) = document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        return scene.nodes().collect();
    }
    let mut has_parent = vec![false; document.nodes().len()];
    for child in document.nodes().flat_map(|node| node.children()) {
        has_parent[child.index()] = true;
    }
    document
        .nodes()
        .filter(|node| !has_parent[node.index()])
        .collect()
}

/// An affine transform from a glTF (column-major) matrix.
fn affine_from_matrix(columns: [[f32; 4]; 4]) -> Loaded<Affine3A> {
    let matrix = Mat4::from_cols_array_2d(&columns);
    if !matrix.is_finite() {
        return Err("matrix is not finite".into());
    }
    let last_row = matrix.row(3);
    if (last_row - Vec4::W).abs().max_element() > 1e-6 {
        return Err(format!(
            "matrix is not affine (its last row is {last_row}, not 0 0 0 1)"
        ));
    }
    Ok(Affine3A::from_mat4(matrix))
}

/// Refuses world transforms that are not finite or flatten space (det ≈ 0,
/// relative to the lengths of the axes).
fn check_world_transform(world: &Affine3A) -> Loaded<()> {
    if !world.is_finite() {
        return Err("world transform is not finite".into());
    }
    let linear = world.matrix3.as_dmat3();
    let axes_volume = linear.x_axis.length() * linear.y_axis.length() * linear.z_axis.length();
    let determinant = linear.determinant();
    if axes_volume > 0.0 && determinant.abs() > 1e-9 * axes_volume {
        Ok(())
    } else {
        Err(format!(
            "world transform is singular (determinant {determinant:e}): it flattens space"
        ))
    }
}

/// Where a mesh instance goes: its world transform and what derives from it.
struct Placement {
    world: Affine3A,
    /// Inverse transpose of the linear part, scaled to avoid overflow (normals are renormalized).
    normal_matrix: Mat3,
    /// The transform mirrors (negative determinant): triangle windings are reversed.
    mirrored: bool,
}

impl Placement {
    fn new(world: Affine3A) -> Self {
        let linear = world.matrix3.as_dmat3();
        let inverse_transpose = linear.inverse().transpose();
        let largest = inverse_transpose
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        Self {
            world,
            normal_matrix: (inverse_transpose * (1.0 / largest)).as_mat3(),
            mirrored: linear.determinant() < 0.0,
        }
    }
}

/// The rotation and translation of `world`, its scale and shear removed:
/// the camera keeps its viewing direction (−Z) and, as far as possible, its up (+Y).
fn rigid_part(world: &Affine3A) -> Affine3A {
    let back = Vec3::from(world.matrix3.z_axis).normalize();
    let up_axis = Vec3::from(world.matrix3.y_axis);
    let up = (up_axis - back * up_axis.dot(back)).normalize();
    let right = up.cross(back);
    Affine3A::from_mat3_translation(Mat3::from_cols(right, up, back), world.translation.into())
}

// ---------------------------------------------------------------------------
// Primitive assembly

/// One primitive's vertex attributes, in its mesh's local space.
struct PrimitiveVertices {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uv0: Option<Vec<Vec2>>,
    uv1: Option<Vec<Vec2>>,
}

/// Refuses, before any geometry is read, a scene whose placed meshes draw
/// more triangles than [`scene_triangle_limit`] (a small file can place a
/// large mesh many times).
fn check_scene_size(document: &Document) -> Loaded<()> {
    let mut reached = vec![false; document.nodes().len()];
    let mut pending = scene_roots(document);
    let mut triangles: u64 = 0;
    while let Some(node) = pending.pop() {
        // the walk reports nodes reached twice; here they are counted once
        if std::mem::replace(&mut reached[node.index()], true) {
            continue;
        }
        if let Some(mesh) = node.mesh() {
            triangles += mesh.primitives().map(|p| drawn_triangles(&p)).sum::<u64>();
        }
        pending.extend(node.children());
    }
    let (limit, why) = scene_triangle_limit();
    if triangles > limit as u64 {
        return Err(format!(
            "the scene places {triangles} triangles, more than {limit} ({why})"
        ));
    }
    Ok(())
}

/// How many triangles a primitive draws, from its index (or vertex) count.
fn drawn_triangles(primitive: &gltf::Primitive) -> u64 {
    let count = primitive
        .indices()
        .or_else(|| primitive.get(&Semantic::Positions))
        .map_or(0, |accessor| accessor.count() as u64);
    match primitive.mode() {
        Mode::Triangles => count / 3,
        Mode::TriangleStrip | Mode::TriangleFan => count.saturating_sub(2),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => 0,
    }
}

fn draws_triangles(mode: Mode) -> bool {
    matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    )
}

/// Vertex corners of the triangles a primitive of a triangle mode draws, and
/// how many indices were left over (not enough for a last triangle).
fn assemble_triangles(mode: Mode, indices: &[u32]) -> (Vec<[u32; 3]>, usize) {
    let n = indices.len();
    // strips and fans use every index once they have three
    let strip_left_over = if n < 3 { n } else { 0 };
    match mode {
        Mode::Triangles => {
            let triangles = indices
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            (triangles, n % 3)
        }
        // the specification's strip: triangle i is (i, i+1+i%2, i+2-i%2)
        Mode::TriangleStrip => {
            let triangles = (0..n.saturating_sub(2))
                .map(|i| {
                    let odd = i % 2;
                    [indices[i], indices[i + 1 + odd], indices[i + 2 - odd]]
                })
                .collect();
            (triangles, strip_left_over)
        }
        // the specification's fan: triangle i is (i+1, i+2, 0)
        Mode::TriangleFan => {
            let triangles = (0..n.saturating_sub(2))
                .map(|i| [indices[i + 1], indices[i + 2], indices[0]])
                .collect();
            (triangles, strip_left_over)
        }
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => (Vec::new(), n),
    }
}

/// Whether the vertex normals of triangle (a, b, c) all lie along its face
/// normal (either way, to 10⁻⁶ in cosine): a flat face, whose shading normal
/// is the face normal, so nothing is interpolated per hit. Degenerate
/// triangles have no face normal and keep their vertex normals.
fn normals_are_the_face_normal(a: Vec3, b: Vec3, c: Vec3, normals: [Vec3; 3]) -> bool {
    let face = (b - a).cross(c - a).normalize_or_zero();
    face != Vec3::ZERO && normals.iter().all(|n| n.dot(face).abs() >= 1.0 - 1e-6)
}

fn is_degenerate(a: Vec3, b: Vec3, c: Vec3) -> bool {
    (b - a).cross(c - a).length_squared() == 0.0
}

// ---------------------------------------------------------------------------
// Materials, textures, lights, cameras: conversions without scene state

/// `emissiveFactor × KHR_materials_emissive_strength`, a radiance.
fn emission_radiance(material: &gltf::Material) -> Loaded<Vec3> {
    let factor = Vec3::from(material.emissive_factor());
    let strength = material.emissive_strength().unwrap_or(1.0);
    if !factor.is_finite() || factor.min_element() < 0.0 {
        return Err(format!(
            "emissiveFactor {factor} must be finite and non-negative"
        ));
    }
    if !strength.is_finite() || strength < 0.0 {
        return Err(format!(
            "emissiveStrength {strength} must be finite and non-negative"
        ));
    }
    let radiance = factor * strength;
    if !radiance.is_finite() {
        return Err(format!("emission {factor} × {strength} overflows"));
    }
    Ok(radiance)
}

fn wrap_mode(mode: gltf::texture::WrappingMode) -> WrapMode {
    match mode {
        gltf::texture::WrappingMode::Repeat => WrapMode::Repeat,
        gltf::texture::WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        gltf::texture::WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
    }
}

/// Decodes a PNG or JPEG (or any format the `image` crate was built with),
/// trusting the bytes' signature over the declared MIME type. The size the
/// header declares is checked before any texel is allocated.
fn decode_image(encoded: &[u8], mime_type: Option<&str>) -> Loaded<DynamicImage> {
    let (width, height) = image_reader(encoded, mime_type)?
        .into_dimensions()
        .map_err(|e| format!("cannot read the header: {e}"))?;
    check_image_size(width, height, encoded.len())?;
    let mut reader = image_reader(encoded, mime_type)?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    // four channels of 32-bit floats is the widest pixel the decoder produces
    limits.max_alloc = Some(MAX_TEXTURE_TEXELS * 16);
    reader.limits(limits);
    let image = reader.decode().map_err(|e| format!("cannot decode: {e}"))?;
    if image.width() == 0 || image.height() == 0 {
        return Err("image is empty".into());
    }
    Ok(image)
}

fn image_reader<'a>(
    encoded: &'a [u8],
    mime_type: Option<&str>,
) -> Loaded<image::ImageReader<Cursor<&'a [u8]>>> {
    let mut reader = image::ImageReader::new(Cursor::new(encoded));
    if let Some(format) = mime_type.and_then(image::ImageFormat::from_mime_type) {
        reader.set_format(format);
    }
    reader
        .with_guessed_format()
        .map_err(|e| format!("cannot read: {e}"))
}

/// Refuses a declared image size that is empty, too large, or more than
/// `encoded_len` bytes of any encoding can describe.
fn check_image_size(width: u32, height: u32, encoded_len: usize) -> Loaded<()> {
    let texels = u64::from(width) * u64::from(height);
    if texels == 0 {
        return Err(format!("image is empty ({width}×{height})"));
    }
    if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE || texels > MAX_TEXTURE_TEXELS {
        return Err(format!(
            "{width}×{height} texels is above the limit ({MAX_TEXTURE_SIDE} per side, \
             {MAX_TEXTURE_TEXELS} in all)"
        ));
    }
    let allowance = (encoded_len as u64)
        .saturating_mul(MAX_TEXELS_PER_ENCODED_BYTE)
        .max(MIN_TEXEL_ALLOWANCE);
    if texels > allowance {
        return Err(format!(
            "the header declares {width}×{height} texels, more than {encoded_len} bytes \
             of encoded data can hold"
        ));
    }
    Ok(())
}

/// Texels as linear RGB, rows top first; 8- and 16-bit values are sRGB-decoded
/// when `srgb`, float values are taken as linear. Alpha is dropped, grey replicated.
fn linear_texels(image: &DynamicImage, srgb: bool) -> Loaded<Vec<Vec3>> {
    let unorm8 = |v: u8| f32::from(v) / 255.0;
    let unorm16 = |v: u16| f32::from(v) / 65535.0;
    let float = |v: f32| if v.is_finite() { v } else { 0.0 };
    Ok(match image {
        DynamicImage::ImageLuma8(i) => to_texels(i.as_raw(), 1, unorm8, srgb),
        DynamicImage::ImageLumaA8(i) => to_texels(i.as_raw(), 2, unorm8, srgb),
        DynamicImage::ImageRgb8(i) => to_texels(i.as_raw(), 3, unorm8, srgb),
        DynamicImage::ImageRgba8(i) => to_texels(i.as_raw(), 4, unorm8, srgb),
        DynamicImage::ImageLuma16(i) => to_texels(i.as_raw(), 1, unorm16, srgb),
        DynamicImage::ImageLumaA16(i) => to_texels(i.as_raw(), 2, unorm16, srgb),
        DynamicImage::ImageRgb16(i) => to_texels(i.as_raw(), 3, unorm16, srgb),
        DynamicImage::ImageRgba16(i) => to_texels(i.as_raw(), 4, unorm16, srgb),
        DynamicImage::ImageRgb32F(i) => to_texels(i.as_raw(), 3, float, false),
        DynamicImage::ImageRgba32F(i) => to_texels(i.as_raw(), 4, float, false),
        other => return Err(format!("unsupported pixel format {:?}", other.color())),
    })
}

fn to_texels<T: Copy>(
    raw: &[T],
    channels: usize,
    to_unit: impl Fn(T) -> f32,
    srgb: bool,
) -> Vec<Vec3> {
    raw.chunks_exact(channels)
        .map(|pixel| {
            let rgb = if channels >= 3 {
                Vec3::new(to_unit(pixel[0]), to_unit(pixel[1]), to_unit(pixel[2]))
            } else {
                Vec3::splat(to_unit(pixel[0]))
            };
            if srgb { rgb.map(srgb_to_linear) } else { rgb }
        })
        .collect()
}

fn projection(camera: &gltf::Camera) -> Loaded<Projection> {
    match camera.projection() {
        gltf::camera::Projection::Perspective(perspective) => {
            let yfov = perspective.yfov();
            if yfov.is_finite() && yfov > 0.0 && yfov < PI {
                Ok(Projection::Perspective { yfov })
            } else {
                Err(format!("yfov {yfov} must be an angle between 0 and π"))
            }
        }
        gltf::camera::Projection::Orthographic(orthographic) => {
            let ymag = orthographic.ymag();
            if ymag.is_finite() && ymag != 0.0 {
                Ok(Projection::Orthographic {
                    half_height: ymag.abs(),
                })
            } else {
                Err(format!("ymag {ymag} must be finite and non-zero"))
            }
        }
    }
}

/// `color × intensity`, refused if negative or not finite.
fn light_intensity(light: &gltf::khr_lights_punctual::Light) -> Loaded<Vec3> {
    let color = Vec3::from(light.color());
    let strength = light.intensity();
    if !strength.is_finite() || strength < 0.0 {
        return Err(format!(
            "intensity {strength} must be finite and non-negative"
        ));
    }
    if !color.is_finite() || color.min_element() < 0.0 {
        return Err(format!("color {color} must be finite and non-negative"));
    }
    let intensity = color * strength;
    if !intensity.is_finite() {
        return Err(format!("intensity {color} × {strength} overflows"));
    }
    Ok(intensity)
}

// ---------------------------------------------------------------------------
// The scene walk

/// Fills a [`Scene`] from a checked file, one node at a time.
struct SceneBuilder<'f> {
    document: &'f Document,
    buffers: &'f [BufferData],
    base_dir: Option<&'f Path>,
    scene: Scene,
    /// glTF material index (None: the default material) → scene material id.
    material_ids: HashMap<Option<usize>, u32>,
    /// glTF texture index → scene texture id.
    texture_ids: HashMap<usize, u32>,
    /// Per glTF mesh: whether a node of the scene placed it.
    placed_meshes: Vec<bool>,
    degenerate_triangles: usize,
    /// Warnings already recorded, to record each once.
    warned: HashSet<String>,
}

impl<'f> SceneBuilder<'f> {
    fn new(file: &'f GltfFile, name: &str, base_dir: Option<&'f Path>) -> Self {
        Self {
            document: &file.document,
            buffers: &file.buffers,
            base_dir,
            scene: Scene {
                name: name.to_string(),
                warnings: file.warnings.clone(),
                ..Scene::default()
            },
            material_ids: HashMap::new(),
            texture_ids: HashMap::new(),
            placed_meshes: vec![false; file.document.meshes().len()],
            degenerate_triangles: 0,
            warned: file.warnings.iter().cloned().collect(),
        }
    }

    fn build(mut self) -> Loaded<Scene> {
        check_node_graph(self.document)?;
        check_scene_size(self.document)?;
        let animations = self.document.animations().len();
        if animations > 0 {
            self.warn(format!(
                "{animations} animation(s) ignored; the scene is loaded at rest"
            ));
        }
        self.walk(scene_roots(self.document))?;
        self.add_summary_warnings();
        self.scene.shrink_to_fit();
        Ok(self.scene)
    }

    /// Records a warning once.
    fn warn(&mut self, warning: String) {
        if self.warned.insert(warning.clone()) {
            self.scene.warnings.push(warning);
        }
    }

    fn add_summary_warnings(&mut self) {
        self.warn_unplaced_meshes();
        if self.degenerate_triangles > 0 {
            self.warn(format!(
                "{} degenerate (zero-area) triangle(s) kept",
                self.degenerate_triangles
            ));
        }
        if self.scene.triangles.is_empty() {
            self.warn("the scene has no triangles".into());
        }
    }

    /// Meshes no node of the scene places are not loaded: say so.
    fn warn_unplaced_meshes(&mut self) {
        let unplaced: Vec<String> = self
            .document
            .meshes()
            .filter(|mesh| !self.placed_meshes[mesh.index()])
            .map(|mesh| label("mesh", mesh.index(), mesh.name()))
            .collect();
        if !unplaced.is_empty() {
            self.warn(format!(
                "{} not placed by any node of the scene; ignored",
                list_some(&unplaced)
            ));
        }
    }

    /// Depth-first, parents before children, children in file order; each
    /// node is reached once (`check_node_graph` refused cycles and shared children).
    fn walk(&mut self, roots: Vec<gltf::Node<'f>>) -> Loaded<()> {
        let mut reached = vec![false; self.document.nodes().len()];
        let mut pending: Vec<(gltf::Node<'f>, Affine3A)> = roots
            .into_iter()
            .rev()
            .map(|root| (root, Affine3A::IDENTITY))
            .collect();
        while let Some((node, parent_world)) = pending.pop() {
            let node_label = label("node", node.index(), node.name());
            if std::mem::replace(&mut reached[node.index()], true) {
                return Err(format!(
                    "{node_label} is reached twice from the scene's roots \
                     (listed twice, or a root that is also a child)"
                ));
            }
            let world = parent_world * self.local_transform(&node, &node_label)?;
            self.add_node_contents(&node, &world, &node_label)?;
            let children: Vec<gltf::Node<'f>> = node.children().collect();
            pending.extend(children.into_iter().rev().map(|child| (child, world)));
        }
        Ok(())
    }

    fn local_transform(&mut self, node: &gltf::Node, node_label: &str) -> Loaded<Affine3A> {
        match node.transform() {
            Transform::Matrix { matrix } => {
                affine_from_matrix(matrix).map_err(|problem| format!("{node_label}: {problem}"))
            }
            Transform::Decomposed {
                translation,
                rotation,
                scale,
            } => {
                let (translation, scale) = (Vec3::from(translation), Vec3::from(scale));
                let rotation = Quat::from_array(rotation);
                if !translation.is_finite() || !scale.is_finite() || !rotation.is_finite() {
                    return Err(format!(
                        "{node_label}: translation, rotation or scale is not finite"
                    ));
                }
                let rotation = self.unit_rotation(rotation, node_label)?;
                Ok(Affine3A::from_scale_rotation_translation(
                    scale,
                    rotation,
                    translation,
                ))
            }
        }
    }

    /// Normalizes a rotation quaternion, with a warning if it was far from unit length.
    fn unit_rotation(&mut self, rotation: Quat, node_label: &str) -> Loaded<Quat> {
        let length = rotation.length();
        if length < 1e-6 {
            return Err(format!("{node_label}: rotation is a zero quaternion"));
        }
        if (length - 1.0).abs() > 1e-3 {
            self.warn(format!(
                "{node_label}: rotation {rotation} is not a unit quaternion (length {length}); normalized"
            ));
        }
        Ok(rotation / length)
    }

    fn add_node_contents(
        &mut self,
        node: &gltf::Node<'f>,
        world: &Affine3A,
        node_label: &str,
    ) -> Loaded<()> {
        let (mesh, camera, light) = (node.mesh(), node.camera(), node.light());
        if mesh.is_none() && camera.is_none() && light.is_none() {
            return Ok(());
        }
        check_world_transform(world).map_err(|problem| format!("{node_label}: {problem}"))?;
        if let Some(mesh) = mesh {
            if node.skin().is_some() {
                self.warn(format!(
                    "{node_label}: skinning is not supported; the mesh is drawn unskinned"
                ));
            }
            self.add_mesh_instance(node, &mesh, world)?;
        }
        if let Some(camera) = camera {
            self.add_camera(node, &camera, world, node_label)?;
        }
        if let Some(light) = light {
            self.add_light(node, &light, world)?;
        }
        Ok(())
    }

    // --- meshes

    fn add_mesh_instance(
        &mut self,
        node: &gltf::Node,
        mesh: &gltf::Mesh<'f>,
        world: &Affine3A,
    ) -> Loaded<()> {
        self.placed_meshes[mesh.index()] = true;
        let placement = Placement::new(*world);
        let object_name = node
            .name()
            .or(mesh.name())
            .map_or_else(|| format!("mesh {}", mesh.index()), String::from);
        for primitive in mesh.primitives() {
            let primitive_label = format!(
                "{} primitive {}",
                label("mesh", mesh.index(), mesh.name()),
                primitive.index()
            );
            self.add_primitive(&primitive, &placement, &object_name, &primitive_label)?;
        }
        Ok(())
    }

    fn add_primitive(
        &mut self,
        primitive: &gltf::Primitive<'f>,
        placement: &Placement,
        object_name: &str,
        primitive_label: &str,
    ) -> Loaded<()> {
        let mode = primitive.mode();
        if !draws_triangles(mode) {
            self.warn(format!(
                "{primitive_label}: mode {} is not supported (triangles only); skipped",
                mode_name(mode)
            ));
            return Ok(());
        }
        if primitive.morph_targets().next().is_some() {
            self.warn(format!("{primitive_label}: morph targets ignored"));
        }
        let vertices = self.read_vertices(primitive, primitive_label)?;
        let indices = self.read_indices(primitive, vertices.positions.len(), primitive_label)?;
        let (triangles, left_over) = assemble_triangles(mode, &indices);
        if left_over > 0 {
            self.warn(format!(
                "{primitive_label}: {left_over} trailing index(es) do not make a whole triangle; ignored"
            ));
        }
        if triangles.is_empty() {
            self.warn(format!("{primitive_label}: no triangle; skipped"));
            return Ok(());
        }
        let (max_triangles, why) = scene_triangle_limit();
        if self.scene.triangles.len() + triangles.len() > max_triangles {
            return Err(format!(
                "{primitive_label}: the scene would have more than {max_triangles} triangles ({why})"
            ));
        }
        let material = self.material_id(primitive.material())?;
        let (first_vertex, smooth_vertices) =
            self.append_vertices(&vertices, placement, primitive_label)?;
        let first_triangle = self.scene.triangles.len() as u32;
        for corners in &triangles {
            let corners = if placement.mirrored {
                [corners[0], corners[2], corners[1]]
            } else {
                *corners
            };
            self.append_triangle(corners, first_vertex, &smooth_vertices, material);
        }
        self.scene.objects.push(Object {
            name: object_name.to_string(),
            material,
            triangles: first_triangle..self.scene.triangles.len() as u32,
        });
        Ok(())
    }

    fn read_vertices(
        &mut self,
        primitive: &gltf::Primitive,
        primitive_label: &str,
    ) -> Loaded<PrimitiveVertices> {
        let positions = primitive
            .get(&Semantic::Positions)
            .ok_or_else(|| format!("{primitive_label}: no POSITION attribute"))?;
        if !is_vec3_of_float(&positions) {
            return Err(format!(
                "{primitive_label}: POSITION accessor {} is {}, not VEC3 of FLOAT",
                positions.index(),
                layout_name(&positions)
            ));
        }
        let positions: Vec<Vec3> = read_accessor::<[f32; 3]>(&positions, self.buffers)?
            .into_iter()
            .map(Vec3::from)
            .collect();
        let count = positions.len();
        Ok(PrimitiveVertices {
            normals: self.read_normals(primitive, count, primitive_label)?,
            uv0: self.read_tex_coords(primitive, 0, count, primitive_label)?,
            uv1: self.read_tex_coords(primitive, 1, count, primitive_label)?,
            positions,
        })
    }

    fn read_normals(
        &mut self,
        primitive: &gltf::Primitive,
        count: usize,
        primitive_label: &str,
    ) -> Loaded<Option<Vec<Vec3>>> {
        let Some(accessor) = primitive.get(&Semantic::Normals) else {
            return Ok(None);
        };
        if !is_vec3_of_float(&accessor) {
            self.warn(format!(
                "{primitive_label}: NORMAL accessor {} is {}, not VEC3 of FLOAT; normals ignored",
                accessor.index(),
                layout_name(&accessor)
            ));
            return Ok(None);
        }
        check_attribute_count(&accessor, count, "NORMAL", primitive_label)?;
        let normals: Vec<Vec3> = read_accessor::<[f32; 3]>(&accessor, self.buffers)?
            .into_iter()
            .map(Vec3::from)
            .collect();
        check_finite(&normals, |n| n.is_finite(), "NORMAL", primitive_label)?;
        Ok(Some(normals))
    }

    /// `TEXCOORD_<set>` as floats (normalized integers divided out); `None`
    /// when absent or unreadable (the scene then reads zeros).
    fn read_tex_coords(
        &mut self,
        primitive: &gltf::Primitive,
        set: u32,
        count: usize,
        primitive_label: &str,
    ) -> Loaded<Option<Vec<Vec2>>> {
        let Some(accessor) = primitive.get(&Semantic::TexCoords(set)) else {
            return Ok(None);
        };
        let name = format!("TEXCOORD_{set}");
        check_attribute_count(&accessor, count, &name, primitive_label)?;
        let buffers = self.buffers;
        let uvs: Vec<Vec2> = match (accessor.dimensions(), accessor.data_type()) {
            (Dimensions::Vec2, DataType::F32) => read_accessor::<[f32; 2]>(&accessor, buffers)?
                .into_iter()
                .map(Vec2::from)
                .collect(),
            (Dimensions::Vec2, DataType::U8) => read_accessor::<[u8; 2]>(&accessor, buffers)?
                .into_iter()
                .map(|[u, v]| Vec2::new(u.into(), v.into()) / 255.0)
                .collect(),
            (Dimensions::Vec2, DataType::U16) => read_accessor::<[u16; 2]>(&accessor, buffers)?
                .into_iter()
                .map(|[u, v]| Vec2::new(u.into(), v.into()) / 65535.0)
                .collect(),
            _ => {
                self.warn(format!(
                    "{primitive_label}: {name} accessor {} is {}, not VEC2 of FLOAT, \
                     UNSIGNED_BYTE or UNSIGNED_SHORT; zeros used",
                    accessor.index(),
                    layout_name(&accessor)
                ));
                return Ok(None);
            }
        };
        check_finite(&uvs, |uv| uv.is_finite(), &name, primitive_label)?;
        Ok(Some(uvs))
    }

    /// The primitive's indices (0, 1, 2, … without an index accessor), each
    /// checked against the vertex count.
    fn read_indices(
        &self,
        primitive: &gltf::Primitive,
        vertex_count: usize,
        primitive_label: &str,
    ) -> Loaded<Vec<u32>> {
        let Some(accessor) = primitive.indices() else {
            return Ok((0..vertex_count as u32).collect());
        };
        // the crate reaches `unreachable!()` for any other index layout
        let indices: Vec<u32> = match (accessor.dimensions(), accessor.data_type()) {
            (Dimensions::Scalar, DataType::U8) => {
                widen(read_accessor::<u8>(&accessor, self.buffers)?)
            }
            (Dimensions::Scalar, DataType::U16) => {
                widen(read_accessor::<u16>(&accessor, self.buffers)?)
            }
            (Dimensions::Scalar, DataType::U32) => read_accessor::<u32>(&accessor, self.buffers)?,
            _ => {
                return Err(format!(
                    "{primitive_label}: index accessor {} is {}; indices must be SCALAR of \
                     UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT",
                    accessor.index(),
                    layout_name(&accessor)
                ));
            }
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(format!(
                "{primitive_label}: index {bad} out of range ({vertex_count} vertices)"
            ));
        }
        Ok(indices)
    }

    /// Appends the primitive's vertices in world space; returns the id of the
    /// first one and, per vertex, whether it has a usable shading normal.
    fn append_vertices(
        &mut self,
        vertices: &PrimitiveVertices,
        placement: &Placement,
        primitive_label: &str,
    ) -> Loaded<(u32, Vec<bool>)> {
        let first = self.scene.positions.len();
        if first + vertices.positions.len() > MAX_SCENE_ELEMENTS {
            return Err(format!(
                "{primitive_label}: the scene would have more than {MAX_SCENE_ELEMENTS} vertices"
            ));
        }
        for (i, &local) in vertices.positions.iter().enumerate() {
            let world = placement.world.transform_point3(local);
            if !world.is_finite() {
                return Err(format!(
                    "{primitive_label}: vertex {i} position {local} is not finite in world space"
                ));
            }
            let extent = world.abs().max_element();
            if extent > MAX_COORDINATE {
                return Err(format!(
                    "{primitive_label}: vertex {i} has a world-space coordinate of {extent:.3e} m, \
                     beyond ±{MAX_COORDINATE:e} m"
                ));
            }
            self.scene.positions.push(world);
        }
        let count = vertices.positions.len();
        // a normal that vanishes (zero, or crushed by the transform) is no
        // shading normal: its vertex is not smooth and stores +Z
        let mut smooth = vec![false; count];
        let world_normals: Option<Vec<Vec3>> = vertices.normals.as_ref().map(|normals| {
            let world = |(i, &local): (usize, &Vec3)| {
                let n = (placement.normal_matrix * local).normalize_or_zero();
                smooth[i] = n != Vec3::ZERO;
                if smooth[i] { n } else { Vec3::Z }
            };
            normals.iter().enumerate().map(world).collect()
        });
        let scene = &mut self.scene;
        let normals = world_normals.as_deref();
        append_vertex_attribute(&mut scene.normals, normals, first, count, Vec3::Z);
        let (uv0, uv1) = (vertices.uv0.as_deref(), vertices.uv1.as_deref());
        append_vertex_attribute(&mut scene.uv0, uv0, first, count, Vec2::ZERO);
        append_vertex_attribute(&mut scene.uv1, uv1, first, count, Vec2::ZERO);
        Ok((first as u32, smooth))
    }

    fn append_triangle(
        &mut self,
        corners: [u32; 3],
        first_vertex: u32,
        smooth_vertices: &[bool],
        material: u32,
    ) {
        let vertices = corners.map(|corner| first_vertex + corner);
        let [a, b, c] = vertices.map(|v| self.scene.positions[v as usize]);
        if is_degenerate(a, b, c) {
            self.degenerate_triangles += 1;
        }
        let has_normals = corners
            .iter()
            .all(|&corner| smooth_vertices[corner as usize]);
        let smooth = has_normals && {
            let normals = vertices.map(|v| self.scene.normals[v as usize]);
            !normals_are_the_face_normal(a, b, c, normals)
        };
        self.scene.triangles.push(Triangle {
            vertices,
            material,
            smooth,
        });
    }

    // --- materials and textures

    /// The scene id of a glTF material, converting it on first use.
    fn material_id(&mut self, material: gltf::Material<'f>) -> Loaded<u32> {
        let key = material.index();
        if let Some(&id) = self.material_ids.get(&key) {
            return Ok(id);
        }
        let converted = match key {
            None => Material::default(),
            Some(_) => self.convert_material(&material)?,
        };
        let id = self.scene.add_material(converted);
        self.material_ids.insert(key, id);
        Ok(id)
    }

    fn convert_material(&mut self, material: &gltf::Material<'f>) -> Loaded<Material> {
        let index = material.index().unwrap_or_default();
        let material_label = label("material", index, material.name());
        let pbr = material.pbr_metallic_roughness();
        let [red, green, blue, _alpha] = pbr.base_color_factor();
        let base_color = Vec3::new(
            self.unit_factor(red, "baseColorFactor", &material_label)?,
            self.unit_factor(green, "baseColorFactor", &material_label)?,
            self.unit_factor(blue, "baseColorFactor", &material_label)?,
        );
        let metallic =
            self.unit_factor(pbr.metallic_factor(), "metallicFactor", &material_label)?;
        let roughness =
            self.unit_factor(pbr.roughness_factor(), "roughnessFactor", &material_label)?;
        let emission = emission_radiance(material)
            .map_err(|problem| format!("{material_label}: {problem}"))?;
        let base_color_texture = match pbr.base_color_texture() {
            Some(info) => Some(self.texture_ref(&info, &material_label, "baseColorTexture")?),
            None => None,
        };
        let emission_texture = match material.emissive_texture() {
            Some(info) => Some(self.texture_ref(&info, &material_label, "emissiveTexture")?),
            None => None,
        };
        self.warn_ignored_material_parts(material, &material_label, emission);
        Ok(Material {
            name: material
                .name()
                .map_or_else(|| format!("material {index}"), String::from),
            base_color,
            base_color_texture,
            metallic,
            roughness,
            emission,
            emission_texture,
            double_sided: material.double_sided(),
        })
    }

    /// A factor clamped to [0, 1], with a warning if it was outside; refused if not finite.
    fn unit_factor(&mut self, value: f32, field: &str, material_label: &str) -> Loaded<f32> {
        if !value.is_finite() {
            return Err(format!("{material_label}: {field} {value} is not finite"));
        }
        let clamped = value.clamp(0.0, 1.0);
        if clamped != value {
            self.warn(format!(
                "{material_label}: {field} {value} clamped to [0, 1]"
            ));
        }
        Ok(clamped)
    }

    fn warn_ignored_material_parts(
        &mut self,
        material: &gltf::Material,
        material_label: &str,
        emission: Vec3,
    ) {
        if material
            .pbr_metallic_roughness()
            .metallic_roughness_texture()
            .is_some()
        {
            self.warn(format!(
                "{material_label}: metallicRoughnessTexture ignored; the metallic and roughness factors are used"
            ));
        }
        if material.normal_texture().is_some() {
            self.warn(format!("{material_label}: normalTexture ignored"));
        }
        let alpha_mode = match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => None,
            gltf::material::AlphaMode::Mask => Some("MASK"),
            gltf::material::AlphaMode::Blend => Some("BLEND"),
        };
        if let Some(alpha_mode) = alpha_mode {
            self.warn(format!(
                "{material_label}: alphaMode {alpha_mode} ignored; the surface is opaque"
            ));
        }
        if material.emissive_texture().is_some() && emission == Vec3::ZERO {
            self.warn(format!(
                "{material_label}: emissiveTexture has no effect (the emission factor is zero)"
            ));
        }
    }

    fn texture_ref(
        &mut self,
        info: &gltf::texture::Info<'f>,
        material_label: &str,
        slot: &str,
    ) -> Loaded<TextureRef> {
        let uv_set = match info.tex_coord() {
            set @ (0 | 1) => set,
            set => {
                self.warn(format!(
                    "{material_label}: {slot} reads TEXCOORD_{set}; only sets 0 and 1 are loaded, set 0 used"
                ));
                0
            }
        };
        let texture = self.texture_id(&info.texture())?;
        Ok(TextureRef { texture, uv_set })
    }

    /// The scene id of a glTF texture, decoding its image on first use (as an
    /// sRGB colour texture: base colour and emission are the only ones read).
    fn texture_id(&mut self, texture: &gltf::Texture<'f>) -> Loaded<u32> {
        if let Some(&id) = self.texture_ids.get(&texture.index()) {
            return Ok(id);
        }
        let image = texture.source();
        let image_label = label("image", image.index(), image.name());
        let decoded = self
            .load_image(image.index())
            .map_err(|problem| format!("{image_label}: {problem}"))?;
        let texels =
            linear_texels(&decoded, true).map_err(|problem| format!("{image_label}: {problem}"))?;
        let sampler = texture.sampler();
        let name = texture
            .name()
            .or(image.name())
            .map_or_else(|| format!("texture {}", texture.index()), String::from);
        self.scene.textures.push(Texture {
            name,
            width: decoded.width(),
            height: decoded.height(),
            texels,
            wrap_s: wrap_mode(sampler.wrap_s()),
            wrap_t: wrap_mode(sampler.wrap_t()),
        });
        let id = (self.scene.textures.len() - 1) as u32;
        self.texture_ids.insert(texture.index(), id);
        Ok(id)
    }

    /// Finds an image's encoded bytes (buffer view, data URI or file) and decodes them.
    fn load_image(&self, index: usize) -> Loaded<DynamicImage> {
        let json = &self.document.as_json().images[index];
        let mime_type = json.mime_type.as_ref().map(|m| m.0.as_str());
        let encoded: Cow<[u8]> = match (&json.buffer_view, &json.uri) {
            (Some(view), _) => {
                let view = self
                    .document
                    .views()
                    .nth(view.value())
                    .ok_or("bufferView does not exist")?;
                let buffer = &self.buffers[view.buffer().index()];
                Cow::Borrowed(&buffer[view.offset()..view.offset() + view.length()])
            }
            (None, Some(uri)) => {
                let source = gltf::buffer::Source::Uri(uri);
                let data = BufferData::from_source(source, self.base_dir)
                    .map_err(|e| format!("cannot read \"{}\": {e}", short_uri(uri)))?;
                Cow::Owned(data.0)
            }
            (None, None) => return Err("has neither a uri nor a bufferView".into()),
        };
        decode_image(&encoded, mime_type)
    }

    // --- cameras and lights

    fn add_camera(
        &mut self,
        node: &gltf::Node,
        camera: &gltf::Camera,
        world: &Affine3A,
        node_label: &str,
    ) -> Loaded<()> {
        let camera_label = label("camera", camera.index(), camera.name());
        let projection =
            projection(camera).map_err(|problem| format!("{camera_label}: {problem}"))?;
        if world.matrix3.determinant() < 0.0 {
            self.warn(format!(
                "{node_label}: the transform of {camera_label} mirrors; the mirroring is ignored"
            ));
        }
        let name = camera
            .name()
            .or(node.name())
            .map_or_else(|| format!("camera {}", camera.index()), String::from);
        self.scene.cameras.push(Camera {
            name,
            world_from_camera: rigid_part(world),
            projection,
        });
        Ok(())
    }

    fn add_light(
        &mut self,
        node: &gltf::Node,
        light: &gltf::khr_lights_punctual::Light,
        world: &Affine3A,
    ) -> Loaded<()> {
        let light_label = label("light", light.index(), light.name());
        let intensity =
            light_intensity(light).map_err(|problem| format!("{light_label}: {problem}"))?;
        let kind = match light.kind() {
            gltf::khr_lights_punctual::Kind::Point => PunctualKind::Point,
            gltf::khr_lights_punctual::Kind::Directional => PunctualKind::Directional,
            gltf::khr_lights_punctual::Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => self.spot_cone(inner_cone_angle, outer_cone_angle, &light_label)?,
        };
        let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        if direction == Vec3::ZERO {
            return Err(format!(
                "{light_label}: its node's −Z axis has no direction"
            ));
        }
        let name = light
            .name()
            .or(node.name())
            .map_or_else(|| format!("light {}", light.index()), String::from);
        self.scene.lights.push(PunctualLight {
            name,
            kind,
            position: world.translation.into(),
            direction,
            intensity,
        });
        Ok(())
    }

    /// Requires 0 ≤ inner < outer ≤ π/2; an inner angle not below the outer
    /// one is moved just below it, with a warning.
    fn spot_cone(&mut self, inner: f32, outer: f32, light_label: &str) -> Loaded<PunctualKind> {
        if !(outer > 0.0 && outer <= FRAC_PI_2) {
            return Err(format!(
                "{light_label}: outerConeAngle {outer} must lie in (0, π/2]"
            ));
        }
        if !inner.is_finite() || inner < 0.0 {
            return Err(format!(
                "{light_label}: innerConeAngle {inner} must be finite and non-negative"
            ));
        }
        let inner = if inner >= outer {
            self.warn(format!(
                "{light_label}: innerConeAngle {inner} is not below outerConeAngle {outer}; moved just below it"
            ));
            outer.next_down()
        } else {
            inner
        };
        Ok(PunctualKind::Spot {
            inner_cone_angle: inner,
            outer_cone_angle: outer,
        })
    }
}

fn check_attribute_count(
    accessor: &Accessor,
    vertex_count: usize,
    attribute: &str,
    primitive_label: &str,
) -> Loaded<()> {
    if accessor.count() == vertex_count {
        Ok(())
    } else {
        Err(format!(
            "{primitive_label}: {attribute} has {} elements but POSITION has {vertex_count}",
            accessor.count()
        ))
    }
}

/// Refuses an attribute with a NaN or infinite component, naming the first such vertex.
fn check_finite<V: std::fmt::Display>(
    values: &[V],
    is_finite: impl Fn(&V) -> bool,
    attribute: &str,
    primitive_label: &str,
) -> Loaded<()> {
    match values.iter().position(|v| !is_finite(v)) {
        None => Ok(()),
        Some(i) => Err(format!(
            "{primitive_label}: vertex {i} {attribute} {} is not finite",
            values[i]
        )),
    }
}

/// The first few items of a list, joined, e.g. "a, b, c and 4 more".
fn list_some(items: &[String]) -> String {
    const SHOWN: usize = 4;
    if items.len() <= SHOWN {
        items.join(", ")
    } else {
        format!(
            "{} and {} more",
            items[..SHOWN].join(", "),
            items.len() - SHOWN
        )
    }
}

fn widen<T: Into<u32>>(indices: Vec<T>) -> Vec<u32> {
    indices.into_iter().map(Into::into).collect()
}

/// A URI for messages: data URIs are cut after their header.
fn short_uri(uri: &str) -> &str {
    if uri.starts_with("data:") {
        uri.split(',').next().unwrap_or(uri)
    } else {
        uri
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_normals_along_the_face_normal_make_a_flat_triangle() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!(normals_are_the_face_normal(a, b, c, [Vec3::Z; 3]));
        // either way round: the shading frame faces the ray regardless
        assert!(normals_are_the_face_normal(a, b, c, [Vec3::NEG_Z; 3]));
        // a normal tilted by a degree is a curved surface's
        let tilted = Vec3::new(1f32.to_radians().sin(), 0.0, 1f32.to_radians().cos());
        assert!(!normals_are_the_face_normal(
            a,
            b,
            c,
            [Vec3::Z, tilted, Vec3::Z]
        ));
        // a degenerate triangle has no face normal to compare with
        assert!(!normals_are_the_face_normal(a, b, 2.0 * b, [Vec3::Z; 3]));
    }
}
