//! glTF files that lie or carry what no renderer can use — lying sizes,
//! non-finite data, odd lights and transforms, images claiming more texels
//! than they hold — each refused with a message naming the file and the
//! problem, never a panic (hand-built GLB bytes; the valid files and the
//! corpus are in `gltf_loading.rs`).

mod common;

use std::path::Path;

use glam::Vec3;
use lumiere::scene::PunctualKind;
use lumiere::scene::gltf::{load, load_slice};

use common::{GLB_JSON, assert_close, glb, read_data, triangle_bin};

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
        with_node_trs("\"rotation\":[0,0,0,2]"),
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
    let bytes = glb(spot(0.2, 0.5), Some(&triangle_bin()));
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

    let bytes = glb(spot(0.5, 0.5), Some(&triangle_bin()));
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
        &glb(textured_json(honest.len()), Some(&bin)),
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
    let scene = load_slice(&glb(sparse(1), Some(&bin([1, 0]))), "sparse.glb", None)
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
