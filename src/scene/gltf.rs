//! glTF 2.0 loading.
use super::Scene;
use crate::error::SceneError;
use std::path::Path;

pub fn load(path: &Path) -> Result<Scene, SceneError> {
    Err(SceneError::new(path, "not yet"))
}

pub fn load_slice(
    _bytes: &[u8],
    name: &str,
    _base_dir: Option<&Path>,
) -> Result<Scene, SceneError> {
    Err(SceneError::new(name, "not yet"))
}
