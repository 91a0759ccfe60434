//! The JSON sidecar written next to every screenshot: every setting needed
//! to render the same image again (`lumiere render --settings FILE`).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::course::RenderSettings;
use crate::render::display::DisplaySettings;
use crate::render::settings_override::SettingsOverride;
use crate::scene::Camera;
use crate::scene::edits::SceneEdits;

/// Every setting of a screenshot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    /// The scene: `cornell` or a path to a glTF file.
    pub scene: String,
    pub camera: Camera,
    /// Resolution, terms, light mode, BRDF override, seed, bounces.
    pub settings: RenderSettings,
    pub display: DisplaySettings,
    /// Samples per pixel of the image (the fewest among its terms).
    pub samples_per_pixel: u32,
    /// What the viewer changed in the scene (materials, lights' strengths).
    #[serde(default, skip_serializing_if = "SceneEdits::is_empty")]
    pub edits: SceneEdits,
    /// The viewer's A/B comparison, when the screenshot shows one: what B
    /// changed from `settings` (the PNG shows A | B; the EXR and
    /// `render --settings` are A's image).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<SettingsOverride>,
}

/// A sidecar that could not be read or written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", path.display())]
pub struct SidecarError {
    pub path: PathBuf,
    pub problem: String,
}

impl Sidecar {
    /// The file's text, as [`Sidecar::save`] writes it.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("settings serialise")
    }

    pub fn load(path: &Path) -> Result<Self, SidecarError> {
        let fail = |problem: String| SidecarError {
            path: path.to_path_buf(),
            problem,
        };
        let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
        let sidecar: Sidecar = serde_json::from_str(&text)
            .map_err(|e| fail(format!("not a lumiere settings file: {e}")))?;
        sidecar.settings.validate().map_err(fail)?;
        Ok(sidecar)
    }

    pub fn save(&self, path: &Path) -> Result<(), SidecarError> {
        std::fs::write(path, self.to_json()).map_err(|e| SidecarError {
            path: path.to_path_buf(),
            problem: format!("cannot write: {e}"),
        })
    }
}
