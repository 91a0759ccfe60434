//! The [`Scene`] built from a checked file: the builder every part of the walk
//! adds to, and the warnings that sum up what was skipped.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use gltf::Document;
use gltf::buffer::Data as BufferData;

use super::{GltfFile, Loaded, label};
use crate::scene::Scene;

/// Fills a [`Scene`] from a checked file, one node at a time.
pub(super) struct SceneBuilder<'f> {
    pub(super) document: &'f Document,
    pub(super) buffers: &'f [BufferData],
    pub(super) base_dir: Option<&'f Path>,
    pub(super) scene: Scene,
    /// glTF material index (None: the default material) → scene material id.
    pub(super) material_ids: HashMap<Option<usize>, u32>,
    /// glTF texture index → scene texture id.
    pub(super) texture_ids: HashMap<usize, u32>,
    /// Per glTF mesh: whether a node of the scene placed it.
    pub(super) placed_meshes: Vec<bool>,
    pub(super) degenerate_triangles: usize,
    /// Warnings already recorded, to record each once.
    pub(super) warned: HashSet<String>,
}

impl<'f> SceneBuilder<'f> {
    pub(super) fn new(file: &'f GltfFile, name: &str, base_dir: Option<&'f Path>) -> Self {
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

    /// The scene, once `load_bytes` has checked the node graph and the
    /// scene's size.
    pub(super) fn build(mut self) -> Loaded<Scene> {
        let animations = self.document.animations().len();
        if animations > 0 {
            self.warn(format!(
                "{animations} animation(s) ignored; the scene is loaded at rest"
            ));
        }
        self.walk_scene()?;
        self.add_summary_warnings();
        self.scene.shrink_to_fit();
        Ok(self.scene)
    }

    /// Records a warning once.
    pub(super) fn warn(&mut self, warning: String) {
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
