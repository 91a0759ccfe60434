//! What the viewer changed in a loaded scene — an object's material, a
//! light's strength — as data a screenshot's sidecar records, so that
//! `lumiere render --settings` applies them to the file it loads again.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::{Material, Scene};

/// The edits of a scene, against the scene as loaded.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SceneEdits {
    /// Objects whose material changed.
    pub objects: Vec<ObjectEdit>,
    /// Punctual lights whose intensity (or irradiance) changed.
    pub lights: Vec<LightEdit>,
}

/// An object's material as edited (the parameters the viewer changes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObjectEdit {
    /// Index of the object in the scene (glTF node × primitive order).
    pub object: u32,
    pub base_color: Vec3,
    pub metallic: f32,
    pub roughness: f32,
    /// Emitted radiance, W·m⁻²·sr⁻¹.
    pub emission: Vec3,
    /// Glass share and index of refraction (absent from older sidecars:
    /// opaque, 1.5).
    #[serde(default)]
    pub transmission: f32,
    #[serde(default = "default_ior")]
    pub ior: f32,
}

fn default_ior() -> f32 {
    crate::course::DEFAULT_IOR
}

/// A punctual light's colour × intensity as edited.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LightEdit {
    pub light: u32,
    pub intensity: Vec3,
}

impl SceneEdits {
    /// What `edited` changed of `original` (the same file, as loaded).
    pub fn between(original: &Scene, edited: &Scene) -> Self {
        let mut edits = Self::default();
        for (i, (before, after)) in original.objects.iter().zip(&edited.objects).enumerate() {
            let (a, b) = (
                &original.materials[before.material as usize],
                &edited.materials[after.material as usize],
            );
            let changed = a.base_color != b.base_color
                || a.metallic != b.metallic
                || a.roughness != b.roughness
                || a.emission != b.emission
                || a.transmission != b.transmission
                || a.ior != b.ior;
            if changed {
                edits.objects.push(ObjectEdit {
                    object: i as u32,
                    base_color: b.base_color,
                    metallic: b.metallic,
                    roughness: b.roughness,
                    emission: b.emission,
                    transmission: b.transmission,
                    ior: b.ior,
                });
            }
        }
        for (i, (a, b)) in original.lights.iter().zip(&edited.lights).enumerate() {
            if a.intensity != b.intensity {
                edits.lights.push(LightEdit {
                    light: i as u32,
                    intensity: b.intensity,
                });
            }
        }
        edits
    }

    pub fn is_empty(&self) -> bool {
        self.objects.is_empty() && self.lights.is_empty()
    }

    /// Applies the edits to `scene` (the file they were recorded on); an
    /// edit of an object or light the scene does not have, or a value no
    /// material may have, is refused.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), String> {
        for edit in &self.objects {
            if edit.object as usize >= scene.objects.len() {
                return Err(format!(
                    "the edit of object {} does not fit a scene of {} objects",
                    edit.object,
                    scene.objects.len()
                ));
            }
            let valid = edit.base_color.is_finite()
                && edit.emission.is_finite()
                && edit.base_color.min_element() >= 0.0
                && edit.emission.min_element() >= 0.0
                && (0.0..=1.0).contains(&edit.metallic)
                && (0.0..=1.0).contains(&edit.roughness)
                && (0.0..=1.0).contains(&edit.transmission)
                && edit.ior.is_finite()
                && edit.ior >= 1.0;
            if !valid {
                return Err(format!(
                    "the edit of object {} has invalid values",
                    edit.object
                ));
            }
            let material = scene.own_material(edit.object);
            material.base_color = edit.base_color;
            material.metallic = edit.metallic;
            material.roughness = edit.roughness;
            material.emission = edit.emission;
            material.transmission = edit.transmission;
            material.ior = edit.ior;
        }
        for edit in &self.lights {
            let Some(light) = scene.lights.get_mut(edit.light as usize) else {
                return Err(format!(
                    "the edit of light {} does not fit a scene of {} lights",
                    edit.light,
                    scene.lights.len()
                ));
            };
            if !(edit.intensity.is_finite() && edit.intensity.min_element() >= 0.0) {
                return Err(format!(
                    "the edit of light {} has an invalid intensity",
                    edit.light
                ));
            }
            light.intensity = edit.intensity;
        }
        Ok(())
    }
}

impl Scene {
    /// The material of `object` alone: if other objects share it, the
    /// object gets a copy first, so that editing it changes nothing else.
    pub fn own_material(&mut self, object: u32) -> &mut Material {
        let current = self.objects[object as usize].material;
        let shared = self
            .objects
            .iter()
            .enumerate()
            .any(|(i, o)| i as u32 != object && o.material == current);
        let material = if shared {
            let mut copy = self.materials[current as usize].clone();
            copy.name = format!("{} ({})", copy.name, self.objects[object as usize].name);
            let id = self.add_material(copy);
            self.objects[object as usize].material = id;
            let range = self.objects[object as usize].triangles.clone();
            for t in &mut self.triangles[range.start as usize..range.end as usize] {
                t.material = id;
            }
            id
        } else {
            current
        };
        &mut self.materials[material as usize]
    }
}
