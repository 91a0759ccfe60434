//! glTF loading: small handwritten files in `tests/data/gltf` (their shared
//! buffer is described in that folder's README), hand-built GLB bytes, and the
//! shared corpus of valid and invalid files (`../shared/gltf-corpus`).

mod common;

use std::path::Path;

use glam::{Vec2, Vec3};
use lumiere::scene::gltf::{load, load_slice};
use lumiere::scene::texture::srgb_to_linear;
use lumiere::scene::{Material, Projection, PunctualKind, Scene, Triangle, WrapMode};

use common::{GLB_JSON, assert_close, data_path, glb, read_data, triangle_bin};

fn load_data(name: &str) -> Scene {
    load(&data_path(name)).unwrap_or_else(|e| panic!("{name} should load: {e}"))
}

fn load_error(name: &str) -> String {
    match load(&data_path(name)) {
        Ok(_) => panic!("{name} should not load"),
        Err(e) => e.to_string(),
    }
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
    use lumiere::course::RenderSettings;
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
        resolve_brdf(material, material.base_color, &settings, || 0.5)
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
    let default = resolve_brdf(material, material.base_color, &settings, || 0.5);
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
    use lumiere::course::RenderSettings;
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
            let Brdf::Lambert { albedo } = point.brdf(&scene, &RenderSettings::default(), point.ng)
            else {
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

/// `cornell-glass`'s glass material with its extensions replaced by
/// `extensions` (JSON) and its roughness by `roughness`, loaded.
fn glass_variant(extensions: &str, roughness: f32) -> Result<lumiere::Scene, String> {
    let text = std::str::from_utf8(
        lumiere::scene::builtin::SCENES
            .iter()
            .find(|s| s.name == "cornell-glass")
            .unwrap()
            .gltf(),
    )
    .unwrap();
    let mut json: serde_json::Value = serde_json::from_str(text).unwrap();
    let materials = json["materials"].as_array_mut().unwrap();
    let glass = materials.iter_mut().find(|m| m["name"] == "glass").unwrap();
    glass["extensions"] = serde_json::from_str(extensions).unwrap();
    glass["pbrMetallicRoughness"]["roughnessFactor"] = roughness.into();
    load_slice(json.to_string().as_bytes(), "glass variant", None).map_err(|e| e.to_string())
}

fn glass_material(scene: &lumiere::Scene) -> &lumiere::scene::Material {
    scene.materials.iter().find(|m| m.name == "glass").unwrap()
}

/// KHR_materials_transmission and KHR_materials_ior: the built-in glass
/// block is glass of η 1.5, seen from inside with η inverted; another
/// index, a partial transmission (glass by that share, the rest the
/// material's own model), and the warnings for what is not modelled.
#[test]
fn transmission_and_ior_make_glass() {
    use lumiere::course::RenderSettings;
    use lumiere::scene::BrdfModel;
    use lumiere::transport::brdf::Brdf;
    use lumiere::transport::surface::{SurfacePoint, resolve_brdf};
    let scene = lumiere::scene::builtin::load("cornell-glass").unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let material = glass_material(&scene);
    assert_eq!((material.transmission, material.ior), (1.0, 1.5));
    assert_eq!(material.brdf_model(), BrdfModel::Glass);
    let block = scene
        .objects
        .iter()
        .find(|o| o.name == "glass block")
        .unwrap();
    let point = SurfacePoint::new(&scene, block.triangles.start, Vec3::splat(1.0 / 3.0));
    let settings = RenderSettings::default();
    let outside = point.brdf(&scene, &settings, point.ng);
    assert_eq!(
        outside,
        Brdf::Glass {
            tint: Vec3::ONE,
            eta: 1.5
        }
    );
    let inside = point.brdf(&scene, &settings, -point.ng);
    assert_eq!(
        inside,
        Brdf::Glass {
            tint: Vec3::ONE,
            eta: 1.0 / 1.5
        }
    );

    let denser = glass_variant(
        r#"{"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 2.4}}"#,
        0.0,
    )
    .unwrap();
    assert_eq!(glass_material(&denser).ior, 2.4);
    // without KHR_materials_ior: glTF's 1.5
    let default_ior = glass_variant(
        r#"{"KHR_materials_transmission": {"transmissionFactor": 1.0}}"#,
        0.0,
    )
    .unwrap();
    assert_eq!(glass_material(&default_ior).ior, 1.5);

    // transmission 0.3 on a Lambert material: glass at 30% of the points
    let partial = glass_variant(
        r#"{"KHR_materials_transmission": {"transmissionFactor": 0.3}}"#,
        1.0,
    )
    .unwrap();
    let material = glass_material(&partial);
    assert_eq!(material.brdf_model(), BrdfModel::Lambert);
    let picks = 10_000;
    let glass = (0..picks)
        .filter(|i| {
            let u = (*i as f32 + 0.5) / picks as f32;
            let brdf = resolve_brdf(material, material.base_color, &settings, || u);
            matches!(brdf, Brdf::Glass { .. })
        })
        .count();
    assert_eq!(glass, 3000);
    // the hashed pick at points of the block: a binomial share of 0.3 (|z| < 4.5)
    let block = partial
        .objects
        .iter()
        .find(|o| o.name == "glass block")
        .unwrap();
    let mut glass = 0u32;
    let mut points = 0u32;
    for triangle in block.triangles.clone() {
        for i in 0..400 {
            let b = Vec3::new(0.2 + 0.0015 * i as f32, 0.3, 0.5 - 0.0015 * i as f32);
            let point = SurfacePoint::new(&partial, triangle, b);
            points += 1;
            glass += u32::from(matches!(
                point.brdf(&partial, &settings, point.ng),
                Brdf::Glass { .. }
            ));
        }
    }
    let (n, p) = (points as f64, 0.3);
    let z = (glass as f64 - n * p) / (n * p * (1.0 - p)).sqrt();
    assert!(z.abs() < 4.5, "{glass} of {points} glass (z = {z:.2})");

    let rough = glass_variant(
        r#"{"KHR_materials_transmission": {"transmissionFactor": 1.0}}"#,
        0.4,
    )
    .unwrap();
    assert!(
        rough
            .warnings
            .iter()
            .any(|w| w.contains("rendered as smooth glass")),
        "{:?}",
        rough.warnings
    );
    let thin = glass_variant(
        r#"{"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 0.5}}"#,
        0.0,
    )
    .unwrap();
    assert_eq!(glass_material(&thin).ior, 1.0);
    assert!(
        thin.warnings
            .iter()
            .any(|w| w.contains("ior 0.5 raised to 1")),
        "{:?}",
        thin.warnings
    );
    // broken extensions are refused, naming the field
    let missing_texture = glass_variant(
        r#"{"KHR_materials_transmission": {"transmissionFactor": 1.0, "transmissionTexture": {"index": 99}}}"#,
        0.0,
    )
    .unwrap_err();
    assert!(
        missing_texture.contains("transmissionTexture"),
        "{missing_texture}"
    );
    let not_a_number =
        glass_variant(r#"{"KHR_materials_ior": {"ior": "dense"}}"#, 0.0).unwrap_err();
    assert!(not_a_number.contains("dense"), "{not_a_number}");
}
