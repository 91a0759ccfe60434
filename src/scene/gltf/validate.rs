//! The JSON document, parsed and checked before the `gltf` crate reads it: its
//! version and required extensions, what the crate would index or unwrap
//! unchecked (it panics instead of reporting), external URIs, then the crate's
//! own validation of references and enumerations.

use std::path::{Path, PathBuf};

use gltf::Document;
use gltf::mesh::Semantic;
use percent_encoding::percent_decode_str;

use super::Loaded;

/// Extensions a file may list in `extensionsRequired`.
const ACCEPTED_REQUIRED_EXTENSIONS: [&str; 5] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_texture_transform",
];

/// Extensions that are read (every other one is ignored with a warning).
const READ_EXTENSIONS: [&str; 4] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
];

pub(super) fn parse_json(json: &[u8]) -> Loaded<gltf::json::Root> {
    // tolerate a UTF-8 byte order mark and NUL padding, which some writers emit
    let json = json.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(json);
    let end = json
        .iter()
        .rposition(|&b| b != 0)
        .map_or(0, |last| last + 1);
    gltf::json::deserialize::from_slice(&json[..end])
        .map_err(|e| format!("not a valid glTF JSON document: {e}"))
}

pub(super) fn check_version(root: &gltf::json::Root) -> Loaded<()> {
    let version = &root.asset.version;
    if version.split('.').next() == Some("2") {
        Ok(())
    } else {
        Err(format!(
            "glTF version {version} is not supported (only 2.x)"
        ))
    }
}

pub(super) fn check_required_extensions(root: &gltf::json::Root) -> Loaded<()> {
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

pub(super) fn extension_warnings(root: &gltf::json::Root) -> Vec<String> {
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
pub(super) fn check_crate_preconditions(
    root: &gltf::json::Root,
    base_dir: Option<&Path>,
) -> Loaded<()> {
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
        let decoded = percent_decode_str(uri).decode_utf8().map_err(|_| {
            format!("{owner}: URI \"{uri}\" does not percent-decode to valid UTF-8")
        })?;
        base_dir.join(&*decoded)
    };
    match std::fs::metadata(&path) {
        Ok(metadata) if !metadata.is_file() => {
            Err(format!("{owner}: \"{uri}\" is not a regular file"))
        }
        _ => Ok(()),
    }
}

/// Runs the crate's validation of references and enumerations, tolerating
/// what this loader handles itself.
pub(super) fn validate(root: gltf::json::Root) -> Loaded<Document> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_uris_are_percent_decoded_before_they_are_resolved() {
        let directory =
            std::env::temp_dir().join(format!("lumiere-check-uri-{}", std::process::id()));
        for folder in ["a folder", "é"] {
            std::fs::create_dir_all(directory.join(folder)).unwrap();
        }
        // the escapes name the folders, which are not regular files
        for uri in ["a%20folder", "%C3%A9"] {
            let error = check_uri("buffer 0", uri, Some(&directory)).unwrap_err();
            assert!(error.contains("is not a regular file"), "{error}");
        }
        // escapes that are not UTF-8 are refused; a '%' without two hex digits stays as is
        let error = check_uri("buffer 0", "%FF.bin", Some(&directory)).unwrap_err();
        assert!(
            error.contains("does not percent-decode to valid UTF-8"),
            "{error}"
        );
        assert!(check_uri("buffer 0", "100%.bin", Some(&directory)).is_ok());
        std::fs::remove_dir_all(&directory).unwrap();
    }
}
