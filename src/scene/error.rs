//! Errors of the library: each names the file (or built-in scene) and the problem.

use std::path::PathBuf;

/// A scene that could not be loaded.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", path.display())]
pub struct SceneError {
    /// The file (or built-in scene name) being loaded.
    pub path: PathBuf,
    /// What is wrong, in words a user can act on.
    pub problem: String,
}

impl SceneError {
    pub fn new(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            problem: problem.into(),
        }
    }
}
