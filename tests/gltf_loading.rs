//! glTF loading: small handwritten files in `tests/data/gltf` (their shared
//! buffer is described in that folder's README), hand-built GLB bytes, and the
//! shared corpus of valid and invalid files (`../shared/gltf-corpus`).

mod common;

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use lumiere::scene::gltf::{load, load_slice};
use lumiere::scene::texture::srgb_to_linear;
use lumiere::scene::{Material, Projection, PunctualKind, Scene, Triangle, WrapMode};

fn data_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gltf")
        .join(name)
}

fn load_data(name: &str) -> Scene {
    load(&data_path(name)).unwrap_or_else(|e| panic!("{name} should load: {e}"))
}

fn load_error(name: &str) -> String {
    match load(&data_path(name)) {
        Ok(_) => panic!("{name} should not load"),
        Err(e) => e.to_string(),
    }
}

fn read_data(name: &str) -> String {
    std::fs::read_to_string(data_path(name)).unwrap()
}

#[track_caller]
fn assert_close(actual: Vec3, expected: Vec3) {
    assert!(
        (actual - expected).length() < 1e-5,
        "{actual} is not {expected}"
    );
}

fn object_id(scene: &Scene, name: &str) -> u32 {
    let id = scene.objects.iter().position(|o| o.name == name);
    id.unwrap_or_else(|| panic!("no object {name}")) as u32
}

fn triangles_of<'s>(scene: &'s Scene, name: &str) -> Vec<&'s Triangle> {
    let object = object_id(scene, name);
    scene.triangles_of_object(object).iter().collect()
}

fn corners(scene: &Scene, triangle: &Triangle) -> [Vec3; 3] {
    triangle.vertices.map(|v| scene.positions[v as usize])
}

fn geometric_normal(scene: &Scene, triangle: &Triangle) -> Vec3 {
    let [a, b, c] = corners(scene, triangle);
    (b - a).cross(c - a).normalize()
}

/// Each per-vertex attribute is stored for every vertex or for none.
fn assert_pool_lengths_match(scene: &Scene) {
    let n = scene.positions.len();
    for (name, len) in [
        ("normals", scene.normals.len()),
        ("uv0", scene.uv0.len()),
        ("uv1", scene.uv1.len()),
    ] {
        assert!(
            len == 0 || len == n,
            "{name}: {len} values for {n} vertices"
        );
    }
}

#[test]
fn node_hierarchy_composes_trs_and_matrices() {
    let scene = load_data("hierarchy.gltf");
    assert_eq!(scene.name, "hierarchy.gltf");
    // NotInScene is not reachable from the default scene
    assert_eq!(scene.objects.len(), 2);
    assert_pool_lengths_match(&scene);

    // translate (10,0,0) · rotate 90° about Z · scale 2 · matrix translate (1,0,0)
    let child = triangles_of(&scene, "Child");
    assert_eq!(child.len(), 1);
    let [a, b, c] = corners(&scene, child[0]);
    assert_close(a, Vec3::new(10.0, 4.0, 0.0));
    assert_close(b, Vec3::new(8.0, 2.0, 0.0));
    assert_close(c, Vec3::new(10.0, 2.0, 2.0));

    // column-major matrix: x += 0.5 y, then translate (0,0,-3)
    let [a, b, c] = corners(&scene, triangles_of(&scene, "Sheared")[0]);
    assert_close(a, Vec3::new(1.0, 0.0, -3.0));
    assert_close(b, Vec3::new(0.5, 1.0, -3.0));
    assert_close(c, Vec3::new(0.0, 0.0, -2.0));
}

#[test]
fn cameras_come_in_walk_order_without_scale() {
    let scene = load_data("cameras.gltf");
    let names: Vec<&str> = scene.cameras.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["Narrow", "Wide", "Plan"]);

    let first = scene.default_camera();
    assert_eq!(first.name, "Narrow");
    assert_eq!(first.projection, Projection::Perspective { yfov: 0.5 });
    let eye = first.world_from_camera;
    assert_close(eye.translation.into(), Vec3::new(0.0, 1.0, 5.0));
    // rotated 90° about Y: looks down −X, up stays +Y; the node's scale 3 is gone
    assert_close(eye.transform_vector3(Vec3::NEG_Z), Vec3::NEG_X);
    assert_close(eye.transform_vector3(Vec3::Y), Vec3::Y);
    assert_close(eye.transform_vector3(Vec3::X), Vec3::NEG_Z);

    let plan = &scene.cameras[2];
    assert_eq!(
        plan.projection,
        Projection::Orthographic { half_height: 3.0 }
    );
    assert_close(
        plan.world_from_camera.transform_vector3(Vec3::NEG_Z),
        Vec3::NEG_Y,
    );
    assert_close(
        plan.world_from_camera.translation.into(),
        Vec3::new(0.0, 10.0, 0.0),
    );
}

#[test]
fn normals_are_transformed_by_the_inverse_transpose() {
    let scene = load_data("normals.gltf");
    assert_pool_lengths_match(&scene);

    let flat = triangles_of(&scene, "Flat");
    assert_eq!(flat.len(), 1);
    assert!(!flat[0].smooth, "no NORMAL attribute: geometric normal");
    assert_close(corners(&scene, flat[0])[0], Vec3::new(-2.0, 0.0, 0.0));

    // scale (2,1,1) maps the normal (1,1,1) to (1/2,1,1) ∝ (1,2,2)/3, not (2,1,1)
    let smooth = triangles_of(&scene, "Smooth");
    // transformed right, its normals lie along its face normal: it is flat
    // (shaded with the face normal); transformed by the matrix itself they
    // would not, and it would stay smooth
    assert!(!smooth[0].smooth);
    for v in smooth[0].vertices {
        assert_close(scene.normals[v as usize], Vec3::new(1.0, 2.0, 2.0) / 3.0);
    }
    assert_close(
        geometric_normal(&scene, smooth[0]),
        Vec3::new(1.0, 2.0, 2.0) / 3.0,
    );

    let [a, b, _] = smooth[0].vertices.map(|v| v as usize);
    assert_eq!(scene.uv0[b], Vec2::new(1.0, 0.0));
    assert_eq!(scene.uv1[a], Vec2::new(0.25, 0.5));
    let flat_vertex = flat[0].vertices[1] as usize;
    assert_eq!(scene.uv0[flat_vertex], Vec2::ZERO, "absent UVs are zero");
}

#[test]
fn primitives_without_indices_strips_and_fans_become_triangles() {
    let scene = load_data("modes.gltf");
    // list (1) + strip (2) + fan (2); lines and points skipped
    assert_eq!(scene.triangles.len(), 5);
    assert_eq!(scene.objects.len(), 3);
    assert_pool_lengths_match(&scene);
    // positions only: no normal or UV is stored
    assert!(scene.normals.is_empty() && scene.uv0.is_empty() && scene.uv1.is_empty());
    assert_eq!(scene.uv(0, 0), Vec2::ZERO);

    // each object's triangles, numbered from its own first vertex
    let by_object = |object: u32| -> Vec<[u32; 3]> {
        let triangles = scene.triangles_of_object(object);
        let base = triangles.iter().flat_map(|t| t.vertices).min().unwrap();
        triangles
            .iter()
            .map(|t| t.vertices.map(|v| v - base))
            .collect()
    };
    assert_eq!(by_object(0), [[0, 1, 2]]);
    assert_eq!(
        by_object(1),
        [[0, 1, 2], [1, 3, 2]],
        "strip keeps the winding"
    );
    assert_eq!(by_object(2), [[1, 2, 0], [2, 3, 0]], "fan around vertex 0");
    for t in scene.triangles_of_object(1) {
        assert_close(geometric_normal(&scene, t), Vec3::Z);
    }

    let warned = |needle: &str| scene.warnings.iter().any(|w| w.contains(needle));
    assert!(
        warned("mesh \"Modes\" primitive 3: mode LINES"),
        "{:?}",
        scene.warnings
    );
    assert!(
        warned("mesh \"Modes\" primitive 4: mode POINTS"),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn punctual_lights_take_position_direction_and_intensity_from_their_nodes() {
    let scene = load_data("lights.gltf");
    assert_eq!(scene.lights.len(), 3);
    let light = |name: &str| scene.lights.iter().find(|l| l.name == name).unwrap();

    let bulb = light("Bulb");
    assert_eq!(bulb.kind, PunctualKind::Point);
    assert_close(bulb.position, Vec3::new(1.0, 2.0, 4.0));
    assert_close(bulb.intensity, Vec3::new(8.0, 4.0, 2.0));

    // rotated 90° about X under a non-uniform scale: −Z points to +Y, unit length
    let lamp = light("Lamp");
    assert_eq!(
        lamp.kind,
        PunctualKind::Spot {
            inner_cone_angle: 0.2,
            outer_cone_angle: 0.6
        }
    );
    assert_close(lamp.position, Vec3::new(0.0, 4.0, 1.0));
    assert_close(lamp.direction, Vec3::Y);
    assert_close(lamp.intensity, Vec3::splat(20.0));

    let sun = light("Sun");
    assert_eq!(sun.kind, PunctualKind::Directional);
    assert_close(sun.direction, Vec3::NEG_Y);
    assert_close(sun.intensity, Vec3::new(3.0, 3.0, 1.5));
}

#[test]
fn negative_light_intensity_is_refused() {
    let text = read_data("lights.gltf").replace("\"intensity\": 8", "\"intensity\": -8");
    let error = load_slice(text.as_bytes(), "lights.gltf", None).unwrap_err();
    assert!(error.to_string().contains("light \"Bulb\""), "{error}");
}

#[test]
fn materials_map_factors_emission_and_textures() {
    let scene = load_data("materials.gltf");
    // materials are converted on first use: "Unused" is not
    assert_eq!(scene.materials.len(), 3);
    assert_eq!(scene.textures.len(), 2, "one texture per glTF texture used");

    let lamp =
        &scene.materials[scene.objects[object_id(&scene, "Lamp") as usize].material as usize];
    assert_eq!(lamp.name, "Glow");
    assert_close(lamp.emission, Vec3::new(10.0, 5.0, 0.0));
    assert!(lamp.is_emissive());
    let emissive = lamp.emission_texture.expect("emissive texture");
    assert_eq!(emissive.uv_set, 0);
    let grey = &scene.textures[emissive.texture as usize];
    assert_eq!((grey.width, grey.height), (1, 1));
    assert_close(grey.texels[0], Vec3::splat(srgb_to_linear(188.0 / 255.0)));

    let panel =
        &scene.materials[scene.objects[object_id(&scene, "Panel") as usize].material as usize];
    assert_eq!(panel.name, "Painted");
    assert_close(panel.base_color, Vec3::new(0.5, 0.25, 1.0));
    assert_eq!(panel.metallic, 0.25);
    assert_eq!(panel.roughness, 0.75);
    assert!(panel.double_sided);
    assert!(!lamp.double_sided);
    assert_eq!(panel.emission, Vec3::ZERO);
    let base = panel.base_color_texture.expect("base colour texture");
    assert_eq!(base.uv_set, 1);
    let stripe = &scene.textures[base.texture as usize];
    assert_eq!((stripe.width, stripe.height), (2, 1));
    assert_close(
        stripe.texels[0],
        Vec3::new(1.0, srgb_to_linear(128.0 / 255.0), 0.0),
    );
    assert_close(
        stripe.texels[1],
        Vec3::new(0.0, srgb_to_linear(64.0 / 255.0), 1.0),
    );
    assert!((stripe.texels[0].y - 0.215_860_5).abs() < 1e-5);
    assert_eq!(stripe.wrap_s, WrapMode::ClampToEdge);
    assert_eq!(stripe.wrap_t, WrapMode::MirroredRepeat);
    assert_eq!(grey.wrap_s, WrapMode::Repeat, "no sampler: repeat");
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("material \"Painted\": metallicRoughnessTexture")),
        "{:?}",
        scene.warnings
    );

    let bare =
        &scene.materials[scene.objects[object_id(&scene, "Bare") as usize].material as usize];
    let default = Material::default();
    assert_eq!(bare.name, default.name);
    assert_eq!((bare.metallic, bare.roughness), (1.0, 1.0));
    assert_eq!(bare.base_color, Vec3::ONE);
}

#[test]
fn embedded_images_load_from_bytes_without_a_base_directory() {
    let bytes = std::fs::read(data_path("materials.gltf")).unwrap();
    let scene = load_slice(&bytes, "materials.gltf", None).unwrap();
    assert_eq!(scene.textures.len(), 2);
    assert!(scene.textures.iter().any(|t| (t.width, t.height) == (2, 1)));
}

#[test]
fn mirrored_transform_reverses_the_winding() {
    let scene = load_data("mirrored.gltf");
    let plain = triangles_of(&scene, "Plain")[0];
    let mirror = triangles_of(&scene, "Mirror")[0];
    let front = Vec3::ONE.normalize();
    assert_close(geometric_normal(&scene, plain), front);
    // the mirror image of the front normal, and the shading normals agree
    let mirrored_front = Vec3::new(-1.0, 1.0, 1.0).normalize();
    assert_close(geometric_normal(&scene, mirror), mirrored_front);
    for v in mirror.vertices {
        assert_close(scene.normals[v as usize], mirrored_front);
    }
}

#[test]
fn unsupported_required_extension_is_refused() {
    let error = load_error("unsupported_extension.gltf");
    assert!(error.contains("KHR_draco_mesh_compression"), "{error}");
    assert!(
        error.starts_with(
            &data_path("unsupported_extension.gltf")
                .display()
                .to_string()
        )
    );
}

#[test]
fn required_texture_transform_is_ignored_with_a_warning() {
    let scene = load_data("texture_transform.gltf");
    assert_eq!(scene.triangles.len(), 1);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("KHR_texture_transform")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn node_cycle_is_refused() {
    let error = load_error("node_cycle.gltf");
    assert!(error.contains("cycle"), "{error}");
    assert!(
        error.contains("\"Ping\"") && error.contains("\"Pong\""),
        "{error}"
    );
}

#[test]
fn index_out_of_range_is_refused() {
    let error = load_error("index_out_of_range.gltf");
    assert!(
        error.ends_with(
            "index_out_of_range.gltf: mesh \"Box\" primitive 0: index 5 out of range (3 vertices)"
        ),
        "{error}"
    );
}

#[test]
fn float_index_accessor_is_refused_without_panic() {
    let error = load_error("float_indices.gltf");
    assert!(error.contains("mesh \"Floaty\" primitive 0"), "{error}");
    assert!(error.contains("FLOAT"), "{error}");
}

#[test]
fn singular_world_transform_is_refused_naming_the_node() {
    let text = read_data("normals.gltf").replace("\"scale\": [2, 1, 1]", "\"scale\": [0, 1, 1]");
    let error = load_slice(text.as_bytes(), "flattened.gltf", None).unwrap_err();
    let error = error.to_string();
    assert!(
        error.starts_with("flattened.gltf: node \"Smooth\""),
        "{error}"
    );
    assert!(error.contains("singular"), "{error}");
}

#[test]
fn external_buffer_needs_a_base_directory() {
    let text = read_data("hierarchy.gltf");
    let start = text.find("data:application").unwrap();
    let end = start + text[start..].find('"').unwrap();
    let external = format!("{}geometry.bin{}", &text[..start], &text[end..]);
    let error = load_slice(external.as_bytes(), "external.gltf", None).unwrap_err();
    assert!(
        error.to_string().contains("external file \"geometry.bin\""),
        "{error}"
    );
}

/// A GLB container around `json` and an optional BIN chunk (both padded).
fn glb(json: &str, bin: Option<&[u8]>) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut chunks = Vec::new();
    chunks.extend((json.len() as u32).to_le_bytes());
    chunks.extend(b"JSON");
    chunks.extend(&json);
    if let Some(bin) = bin {
        let mut bin = bin.to_vec();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        chunks.extend((bin.len() as u32).to_le_bytes());
        chunks.extend(b"BIN\0");
        chunks.extend(&bin);
    }
    let mut file = b"glTF".to_vec();
    file.extend(2u32.to_le_bytes());
    file.extend((12 + chunks.len() as u32).to_le_bytes());
    file.extend(chunks);
    file
}

const GLB_JSON: &str = r#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
"bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":36}]}"#;

fn triangle_bin() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

#[test]
fn glb_bytes_load_from_a_slice() {
    let bytes = glb(GLB_JSON, Some(&triangle_bin()));
    let scene = load_slice(&bytes, "triangle.glb", None).unwrap();
    assert_eq!(scene.name, "triangle.glb");
    assert_eq!(scene.triangles.len(), 1);
    assert_close(scene.positions[1], Vec3::X);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn glb_with_lying_lengths_is_refused() {
    let good = glb(GLB_JSON, Some(&triangle_bin()));

    let mut too_long = good.clone();
    too_long[8..12].copy_from_slice(&(good.len() as u32 + 4).to_le_bytes());
    let error = load_slice(&too_long, "long.glb", None).unwrap_err();
    assert!(error.to_string().contains("declares"), "{error}");

    let mut big_chunk = good.clone();
    big_chunk[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(load_slice(&big_chunk, "chunk.glb", None).is_err());

    assert!(load_slice(&good[..16], "cut.glb", None).is_err());

    let short_bin = glb(GLB_JSON, Some(&triangle_bin()[..24]));
    let error = load_slice(&short_bin, "short.glb", None).unwrap_err();
    assert!(error.to_string().contains("buffer 0"), "{error}");
}

// ---------------------------------------------------------------------------
// The shared corpus

#[test]
fn every_valid_corpus_file_loads() {
    let files = common::gltf_files(&common::corpus_dir().join("valid"));
    assert!(files.len() >= 10, "valid corpus has {} files", files.len());
    for path in &files {
        let scene = load(path).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            !scene.triangles.is_empty(),
            "{}: no triangles",
            path.display()
        );
        assert_pool_lengths_match(&scene);
        for t in &scene.triangles {
            assert!(
                t.vertices
                    .iter()
                    .all(|&v| (v as usize) < scene.positions.len())
            );
        }
    }
}

#[test]
fn corpus_specifics_are_read() {
    let valid = common::corpus_dir().join("valid");
    let cameras = load(&valid.join("Cameras.gltf")).unwrap();
    assert_eq!(cameras.cameras.len(), 2);
    assert!(
        matches!(cameras.cameras[0].projection, Projection::Perspective { yfov } if (yfov - 0.7).abs() < 1e-6)
    );
    assert!(
        matches!(cameras.cameras[1].projection, Projection::Orthographic { half_height } if half_height == 1.0)
    );

    // the sparse values raise three vertices to y = 4
    let sparse = load(&valid.join("SimpleSparseAccessor.gltf")).unwrap();
    assert_eq!(sparse.bounds().max.y, 4.0);

    let textured = load(&valid.join("BoxTextured.gltf")).unwrap();
    assert_eq!(textured.textures.len(), 1);
    assert!(
        textured
            .materials
            .iter()
            .any(|m| m.base_color_texture.is_some())
    );
}

#[test]
fn every_invalid_corpus_file_is_refused_or_warned_without_panic() {
    let root = common::corpus_dir().join("invalid");
    let files = common::gltf_files(&root);
    assert!(!files.is_empty(), "invalid corpus is empty");
    let mut failures = Vec::new();
    for path in &files {
        let shown = path.strip_prefix(&root).unwrap().display().to_string();
        match std::panic::catch_unwind(|| load(path)) {
            Err(_) => failures.push(format!("{shown}: panicked")),
            Ok(Err(error)) => eprintln!("Err   {shown}: {}", error.problem),
            Ok(Ok(scene)) if !scene.warnings.is_empty() => {
                eprintln!("Warn  {shown}: {}", scene.warnings.join(" | "))
            }
            Ok(Ok(_)) => failures.push(format!("{shown}: loaded without error or warning")),
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

// ---------------------------------------------------------------------------
// Hardening: lying sizes, non-finite data, odd lights and transforms

/// Loads GLB bytes built from `json` and `bin`, expecting an error; returns its message.
#[track_caller]
fn glb_error(json: &str, bin: &[u8]) -> String {
    match load_slice(&glb(json, Some(bin)), "bad.glb", None) {
        Ok(_) => panic!("should not load: {json}"),
        Err(error) => {
            let message = error.to_string();
            assert!(message.starts_with("bad.glb: "), "{message}");
            message
        }
    }
}

#[test]
fn accessor_beyond_its_buffer_view_is_refused() {
    let one_more = GLB_JSON.replace("\"count\":3", "\"count\":4");
    let error = glb_error(&one_more, &triangle_bin());
    assert!(
        error.contains("accessor 0: data: 4 elements of 12 bytes")
            && error.contains("do not fit buffer view 0 (36 bytes)"),
        "{error}"
    );

    // a count that would need 48 GB is refused before anything is allocated
    let huge = GLB_JSON.replace("\"count\":3", "\"count\":4000000000");
    let error = glb_error(&huge, &triangle_bin());
    assert!(error.contains("accessor 0"), "{error}");

    let offset = GLB_JSON.replace("\"bufferView\":0,", "\"bufferView\":0,\"byteOffset\":4,");
    let error = glb_error(&offset, &triangle_bin());
    assert!(error.contains("from byte 4 do not fit"), "{error}");
}

#[test]
fn buffer_view_beyond_its_buffer_is_refused() {
    let shifted = GLB_JSON.replace(
        "\"bufferViews\":[{\"buffer\":0,",
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":8,",
    );
    let error = glb_error(&shifted, &triangle_bin());
    assert!(
        error.contains("buffer view 0: 36 bytes from byte 8 do not fit buffer 0"),
        "{error}"
    );
}

#[test]
fn buffer_longer_than_its_data_is_refused() {
    let lying = GLB_JSON.replace(
        "\"buffers\":[{\"byteLength\":36}]",
        "\"buffers\":[{\"byteLength\":4000000000}]",
    );
    let error = glb_error(&lying, &triangle_bin());
    assert!(
        error.contains("buffer 0: byteLength is 4000000000"),
        "{error}"
    );
}

#[test]
fn zero_filled_accessor_with_a_huge_count_is_refused() {
    let zeros = GLB_JSON
        .replace(
            "\"accessors\":[",
            "\"accessors\":[{\"componentType\":5126,\"count\":16777216,\"type\":\"MAT4\"},",
        )
        .replace("\"POSITION\":0", "\"POSITION\":1");
    let error = glb_error(&zeros, &triangle_bin());
    assert!(
        error.contains("accessor 0: count 16777216 of 64-byte elements without a buffer view"),
        "{error}"
    );
}

/// A triangle with positions, normals and UVs in one buffer (36 + 36 + 24 bytes).
const ATTRIBUTES_JSON: &str = r#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"name":"Tri","primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}}]}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":0,"byteOffset":36,"componentType":5126,"count":3,"type":"VEC3"},
{"bufferView":0,"byteOffset":72,"componentType":5126,"count":3,"type":"VEC2"}],
"bufferViews":[{"buffer":0,"byteLength":96}],"buffers":[{"byteLength":96}]}"#;

/// The floats of [`ATTRIBUTES_JSON`]'s buffer, with float `at` replaced by `value`.
fn attributes_bin(at: usize, value: f32) -> Vec<u8> {
    let mut floats = vec![
        0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, // positions
        0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, // normals
        0.0, 0.0, 1.0, 0.0, 0.0, 1.0, // uvs
    ];
    floats[at] = value;
    floats.iter().flat_map(|v| v.to_le_bytes()).collect()
}

#[test]
fn non_finite_positions_normals_and_uvs_are_refused() {
    let scene = load_slice(
        &glb(ATTRIBUTES_JSON, Some(&attributes_bin(0, 0.0))),
        "ok.glb",
        None,
    );
    assert!(scene.is_ok(), "{:?}", scene.err());

    let error = glb_error(ATTRIBUTES_JSON, &attributes_bin(4, f32::NAN));
    assert!(
        error.contains("mesh \"Tri\" primitive 0: vertex 1 position")
            && error.contains("not finite"),
        "{error}"
    );
    // finite, but beyond what the BVH's arithmetic holds (a misaligned buffer view reads such values)
    let error = glb_error(ATTRIBUTES_JSON, &attributes_bin(3, 4.6e24));
    assert!(
        error.contains(
            "mesh \"Tri\" primitive 0: vertex 1 has a world-space coordinate of 4.600e24 m, \
             beyond ±1e12 m"
        ),
        "{error}"
    );
    let error = glb_error(ATTRIBUTES_JSON, &attributes_bin(15, f32::INFINITY));
    assert!(
        error.contains("mesh \"Tri\" primitive 0: vertex 2 NORMAL") && error.contains("not finite"),
        "{error}"
    );
    let error = glb_error(ATTRIBUTES_JSON, &attributes_bin(19, f32::NEG_INFINITY));
    assert!(
        error.contains("mesh \"Tri\" primitive 0: vertex 0 TEXCOORD_0")
            && error.contains("not finite"),
        "{error}"
    );
}

/// [`GLB_JSON`] with `"rotation"`/`"translation"` etc. given by `trs` on its node.
fn with_node_trs(trs: &str) -> String {
    GLB_JSON.replace(
        "\"nodes\":[{\"mesh\":0}]",
        &format!("\"nodes\":[{{\"name\":\"N\",\"mesh\":0,{trs}}}]"),
    )
}

#[test]
fn non_unit_rotation_is_normalised_with_a_warning() {
    let bytes = glb(
        &with_node_trs("\"rotation\":[0,0,0,2]"),
        Some(&triangle_bin()),
    );
    let scene = load_slice(&bytes, "rotation.glb", None).unwrap();
    assert_close(scene.positions[1], Vec3::X);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.starts_with("node \"N\": rotation") && w.contains("normalized")),
        "{:?}",
        scene.warnings
    );

    let error = glb_error(&with_node_trs("\"rotation\":[0,0,0,0]"), &triangle_bin());
    assert!(
        error.contains("node \"N\": rotation is a zero quaternion"),
        "{error}"
    );
}

#[test]
fn overflowing_transform_is_refused_naming_the_node() {
    // 1e39 does not fit an f32: it reads as infinity
    let error = glb_error(
        &with_node_trs("\"translation\":[1e39,0,0]"),
        &triangle_bin(),
    );
    assert!(
        error.contains("node \"N\": ") && error.contains("not finite"),
        "{error}"
    );

    let matrix = "\"matrix\":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,0]";
    let error = glb_error(&with_node_trs(matrix), &triangle_bin());
    assert!(
        error.contains("node \"N\": matrix is not affine"),
        "{error}"
    );
}

/// [`GLB_JSON`] with a second node holding spot light `spot` (the light's JSON object).
fn with_light(light: &str) -> String {
    GLB_JSON
        .replace(
            "\"nodes\":[{\"mesh\":0}]",
            "\"nodes\":[{\"mesh\":0},{\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}]",
        )
        .replace("\"nodes\":[0]", "\"nodes\":[0,1]")
        .replace(
            "\"asset\":{\"version\":\"2.0\"},",
            &format!(
                "\"asset\":{{\"version\":\"2.0\"}},\"extensionsUsed\":[\"KHR_lights_punctual\"],\
                 \"extensions\":{{\"KHR_lights_punctual\":{{\"lights\":[{light}]}}}},"
            ),
        )
}

#[test]
fn spot_cone_angles_are_checked() {
    let spot = |inner: f32, outer: f32| {
        with_light(&format!(
            "{{\"name\":\"S\",\"type\":\"spot\",\"intensity\":1,\"spot\":{{\"innerConeAngle\":{inner},\"outerConeAngle\":{outer}}}}}"
        ))
    };
    let bytes = glb(&spot(0.2, 0.5), Some(&triangle_bin()));
    let scene = load_slice(&bytes, "spot.glb", None).unwrap();
    assert!(matches!(
        scene.lights[0].kind,
        PunctualKind::Spot { inner_cone_angle, outer_cone_angle }
            if inner_cone_angle == 0.2 && outer_cone_angle == 0.5
    ));

    let error = glb_error(&spot(0.2, 2.0), &triangle_bin());
    assert!(
        error.contains("light \"S\": outerConeAngle 2 must lie in (0, π/2]"),
        "{error}"
    );
    let error = glb_error(&spot(-0.1, 0.5), &triangle_bin());
    assert!(
        error.contains("light \"S\": innerConeAngle -0.1"),
        "{error}"
    );

    let bytes = glb(&spot(0.5, 0.5), Some(&triangle_bin()));
    let scene = load_slice(&bytes, "spot.glb", None).unwrap();
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("innerConeAngle 0.5 is not below")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn negative_light_intensity_in_a_glb_is_refused() {
    let light = with_light("{\"name\":\"P\",\"type\":\"point\",\"intensity\":-3}");
    let error = glb_error(&light, &triangle_bin());
    assert!(
        error.contains("light \"P\": intensity -3 must be finite and non-negative"),
        "{error}"
    );
}

/// CRC-32 (ISO-HDLC, as PNG uses) of `bytes`.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &byte in bytes {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A 1×1 PNG whose header then claims `width`×`height` (its CRC kept valid).
fn png_claiming(width: u32, height: u32) -> Vec<u8> {
    let mut png = Vec::new();
    image::RgbImage::from_pixel(1, 1, image::Rgb([200, 100, 50]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    // signature (8), IHDR length (4), "IHDR" (4), width, height, …, CRC after 13 bytes of data
    png[16..20].copy_from_slice(&width.to_be_bytes());
    png[20..24].copy_from_slice(&height.to_be_bytes());
    let crc = crc32(&png[12..29]);
    png[29..33].copy_from_slice(&crc.to_be_bytes());
    png
}

/// [`GLB_JSON`] whose triangle's material has a base colour texture: a PNG of `png_len` bytes after the triangle.
fn textured_json(png_len: usize) -> String {
    GLB_JSON
        .replace("\"attributes\":{\"POSITION\":0}", "\"attributes\":{\"POSITION\":0},\"material\":0")
        .replace(
            "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"buffers\":[{\"byteLength\":36}]",
            &format!(
                "\"bufferViews\":[{{\"buffer\":0,\"byteLength\":36}},{{\"buffer\":0,\"byteOffset\":36,\"byteLength\":{png_len}}}],\
                 \"buffers\":[{{\"byteLength\":{}}}],\
                 \"materials\":[{{\"pbrMetallicRoughness\":{{\"baseColorTexture\":{{\"index\":0}}}}}}],\
                 \"textures\":[{{\"source\":0}}],\
                 \"images\":[{{\"name\":\"Liar\",\"bufferView\":1,\"mimeType\":\"image/png\"}}]",
                36 + png_len
            ),
        )
}

#[test]
fn image_header_claiming_more_texels_than_its_data_is_refused() {
    let honest = png_claiming(1, 1);
    let mut bin = triangle_bin();
    bin.extend(&honest);
    let scene = load_slice(
        &glb(&textured_json(honest.len()), Some(&bin)),
        "png.glb",
        None,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.textures.len(), 1);

    // 8000 × 4000 texels (384 MB as linear RGB) from a few dozen bytes
    let liar = png_claiming(8000, 4000);
    let mut bin = triangle_bin();
    bin.extend(&liar);
    let error = glb_error(&textured_json(liar.len()), &bin);
    assert!(
        error.contains("image \"Liar\": the header declares 8000×4000 texels"),
        "{error}"
    );

    let giant = png_claiming(100_000, 100_000);
    let mut bin = triangle_bin();
    bin.extend(&giant);
    let error = glb_error(&textured_json(giant.len()), &bin);
    assert!(error.contains("above the limit"), "{error}");
}

#[test]
fn buffer_uri_naming_a_directory_or_device_is_refused() {
    let directory = std::env::temp_dir().join(format!("lumiere-uri-{}", std::process::id()));
    std::fs::create_dir_all(directory.join("folder.bin")).unwrap();
    let text = read_data("hierarchy.gltf");
    let start = text.find("data:application").unwrap();
    let end = start + text[start..].find('"').unwrap();
    for uri in ["folder.bin", "file:///dev/zero"] {
        if uri.contains("/dev/") && !Path::new("/dev/zero").exists() {
            continue;
        }
        let path = directory.join("external.gltf");
        std::fs::write(&path, format!("{}{uri}{}", &text[..start], &text[end..])).unwrap();
        let error = load(&path).unwrap_err().to_string();
        assert!(
            error.contains(&format!("\"{uri}\" is not a regular file")),
            "{error}"
        );
    }
    std::fs::remove_dir_all(&directory).unwrap();
}

#[test]
fn sparse_indices_beyond_the_count_or_unordered_are_refused() {
    // one sparse value (12 bytes at 40) for the vertex named by the byte at 36
    let sparse = |count: u32| {
        GLB_JSON
            .replace(
                "\"max\":[1,1,0]}",
                &format!(
                    "\"max\":[1,1,0],\"sparse\":{{\"count\":{count},\
                     \"indices\":{{\"bufferView\":1,\"componentType\":5121}},\
                     \"values\":{{\"bufferView\":2}}}}}}"
                ),
            )
            .replace(
                "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"buffers\":[{\"byteLength\":36}]",
                "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},\
                 {\"buffer\":0,\"byteOffset\":36,\"byteLength\":2},\
                 {\"buffer\":0,\"byteOffset\":40,\"byteLength\":24}],\
                 \"buffers\":[{\"byteLength\":64}]",
            )
    };
    let bin = |indices: [u8; 2]| {
        let mut bin = triangle_bin();
        bin.extend([indices[0], indices[1], 0, 0]);
        bin.extend(
            [0.0f32, 4.0, 0.0, 0.0, 5.0, 0.0]
                .iter()
                .flat_map(|v| v.to_le_bytes()),
        );
        bin
    };
    let scene = load_slice(&glb(&sparse(1), Some(&bin([1, 0]))), "sparse.glb", None)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_close(scene.positions[1], Vec3::new(0.0, 4.0, 0.0));

    let error = glb_error(&sparse(1), &bin([5, 0]));
    assert!(
        error.contains("accessor 0: sparse index 5 out of range (3 elements)"),
        "{error}"
    );
    let error = glb_error(&sparse(2), &bin([2, 1]));
    assert!(
        error.contains("sparse indices are not strictly increasing"),
        "{error}"
    );
    let error = glb_error(&sparse(4), &bin([0, 1]));
    assert!(
        error.contains("sparse count 4 must lie between 1 and"),
        "{error}"
    );
}

#[test]
fn a_mesh_placed_too_many_times_is_refused_before_its_geometry_is_read() {
    // 2²⁰ triangles of zero-filled positions (no buffer), placed by 70 nodes:
    // 73 million triangles, beyond 2²⁶ and beyond what memory holds with a BVH
    let nodes = vec![r#"{"mesh":0}"#; 70].join(",");
    let roots = (0..70).map(|i| i.to_string()).collect::<Vec<_>>().join(",");
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[{roots}]}}],"nodes":[{nodes}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"accessors":[{{"componentType":5126,"count":3145728,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}}]}}"#
    );
    let started = std::time::Instant::now();
    let error = load_slice(json.as_bytes(), "instances.gltf", None)
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with("instances.gltf: the scene places 73400320 triangles, more than "),
        "{error}"
    );
    // refused by counting, not after building 73 million triangles
    assert!(
        started.elapsed().as_secs_f64() < 5.0,
        "{:?}",
        started.elapsed()
    );
}

#[test]
fn the_textured_cornell_box_reads_its_checker_in_linear_values() {
    // the file the Mitsuba texture check renders (tests/reference/README.md);
    // the light reads the same checker as its emissive texture
    let scene = load(Path::new("tests/data/cornell-textured.gltf")).unwrap();
    let checker = scene
        .materials
        .iter()
        .find(|m| m.name == "checker")
        .expect("the back wall's material");
    let texture = &scene.textures[checker.base_color_texture.unwrap().texture as usize];
    // texel centres of the 4×4 image: (0, 0) yellow, (1, 0) blue
    let yellow = texture.sample(Vec2::new(0.125, 0.125));
    let blue = texture.sample(Vec2::new(0.375, 0.125));
    let expected = |rgb: [u8; 3]| Vec3::from(rgb.map(|c| srgb_to_linear(c as f32 / 255.0)));
    assert!(
        (yellow - expected([230, 200, 40])).abs().max_element() < 1e-5,
        "{yellow}"
    );
    assert!(
        (blue - expected([40, 90, 220])).abs().max_element() < 1e-5,
        "{blue}"
    );
    let light = scene
        .materials
        .iter()
        .find(|m| m.is_emissive())
        .expect("the light");
    assert_eq!(
        light.emission_texture.map(|t| t.texture),
        checker.base_color_texture.map(|t| t.texture)
    );
}

#[test]
fn the_glossy_cornell_box_maps_its_materials_onto_phong() {
    // the file the Mitsuba Phong check renders (tests/reference/README.md)
    use lumiere::render::settings::RenderSettings;
    use lumiere::transport::brdf::Brdf;
    use lumiere::transport::surface::resolve_brdf;
    let scene = load(Path::new("tests/data/cornell-glossy.gltf")).unwrap();
    let settings = RenderSettings::default();
    let brdf = |name: &str| {
        let material = scene
            .materials
            .iter()
            .find(|m| m.name == name)
            .unwrap_or_else(|| panic!("no material {name}"));
        resolve_brdf(material, material.base_color, &settings)
    };
    let Brdf::Phong { kd, ks, exponent } = brdf("glossy floor") else {
        panic!("the floor is not Phong");
    };
    // metallic 0, roughness 0.5: α = 0.25, n = 2/α² − 2
    assert!((exponent - 30.0).abs() < 1e-3, "{exponent}");
    assert!((ks - Vec3::splat(0.04)).abs().max_element() < 1e-6, "{ks}");
    assert!((kd.x - 0.885809).abs() < 1e-6, "{kd}");
    let Brdf::Phong { kd, ks, exponent } = brdf("brass") else {
        panic!("the tall block is not Phong");
    };
    assert!((exponent - 131.2778).abs() < 1e-2, "{exponent}");
    assert_eq!(kd, Vec3::ZERO);
    assert!((ks - Vec3::new(0.91, 0.78, 0.42)).abs().max_element() < 1e-6);
    // the short block has no material: glTF's default, metallic 1 and roughness 1
    let short_block = scene
        .objects
        .iter()
        .find(|o| o.name == "short block")
        .expect("the short block");
    let material = &scene.materials[short_block.material as usize];
    let default = resolve_brdf(material, material.base_color, &settings);
    assert_eq!(
        default,
        Brdf::Phong {
            kd: Vec3::ZERO,
            ks: Vec3::ONE,
            exponent: 0.0
        }
    );
}

#[test]
fn a_primitive_reads_each_texture_at_its_own_uv_set() {
    // the file the Mitsuba check of two uv sets renders (tests/reference/README.md):
    // the back wall glows with the checker at TEXCOORD_0 and reflects it at TEXCOORD_1
    use lumiere::render::settings::RenderSettings;
    use lumiere::transport::brdf::Brdf;
    use lumiere::transport::surface::SurfacePoint;
    let scene = load(Path::new("tests/data/cornell-two-uv-sets.gltf")).unwrap();
    let wall = scene
        .objects
        .iter()
        .find(|o| o.name == "back wall")
        .expect("the back wall");
    let material = &scene.materials[wall.material as usize];
    let base = material.base_color_texture.expect("a base colour texture");
    let emission = material.emission_texture.expect("an emissive texture");
    assert_eq!((base.uv_set, emission.uv_set), (1, 0));
    let texture = &scene.textures[base.texture as usize];
    let mut differing = 0;
    for triangle in wall.triangles.clone() {
        for b in [Vec3::splat(1.0 / 3.0), Vec3::new(0.7, 0.2, 0.1)] {
            let point = SurfacePoint::new(&scene, triangle, b);
            let (uv0, uv1) = (point.uv(&scene, 0), point.uv(&scene, 1));
            // set 1 is set 0 with u and v swapped and doubled
            assert!((uv1 - 2.0 * Vec2::new(uv0.y, uv0.x)).length() < 1e-5);
            let Brdf::Lambert { albedo } = point.brdf(&scene, &RenderSettings::default()) else {
                panic!("the wall is Lambert");
            };
            let reflected = material.base_color * texture.sample(uv1);
            assert!((albedo - reflected).abs().max_element() < 1e-6, "{albedo}");
            let emitted = point.emitted(&scene, point.ng);
            let glowing = material.emission * texture.sample(uv0);
            assert!((emitted - glowing).abs().max_element() < 1e-6, "{emitted}");
            differing += usize::from((texture.sample(uv0) - texture.sample(uv1)).length() > 0.1);
        }
    }
    // the sets read different texels, so reading the wrong one would show
    assert!(differing >= 2, "{differing}");
}
