//! A quality for each source — the lecture: "pas obligé de traiter toutes
//! les sources ; choix de la qualité de la simulation pour chaque source".
//!
//! With `settings.sources` empty, direct lighting at a vertex draws its
//! `light_samples` lights by power ([`crate::transport::lights`]). With a
//! quality for each source, every source s that is on gets its own N_s
//! light samples (its `samples`, else `light_samples`):
//!
//! ```text
//! L_direct ≈ Σ_s (1/N_s) Σ_{k=1..N_s} L_e(q_k) f_r cos θ_k / (P(t_k | s) pdf(q_k | t_k))
//! ```
//!
//! A source made of several lights (the triangles of an emitter) picks one,
//! t, with probability P(t | s) ∝ its power. Each source's average is an
//! unbiased estimate of its own direct lighting, so the sum is unbiased
//! whatever the counts. The N = Σ N_s samples of a vertex are laid out
//! source after source ("slots"): sample j draws from the source of slot j.
//!
//! MIS weighs a point q of light t by the expected number of light samples
//! landing near it, N_s P(t | s) pdf(q | t): the table's selection
//! probability of t is N_s P(t | s) / N, so the weights the integrators
//! write for N samples drawn with probabilities P(t) hold unchanged.
//!
//! A source switched off emits nothing: its emission is zero in the scene
//! the render reads ([`switch_off`]), so no term sees it.

use std::sync::Arc;

use crate::course::{LightSelection, MAX_SOURCE_SAMPLES_PER_VERTEX, RenderSettings, SourceQuality};
use crate::scene::Scene;
use crate::transport::warps::AliasTable;

/// A light source as the user sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum SourceKey {
    /// The glTF punctual light of that index.
    Light(u32),
    /// Every emissive triangle of the material of that index.
    Emitter(u32),
}

impl SourceKey {
    /// The source's name in the scene (its light's or its material's).
    pub fn name(self, scene: &Scene) -> &str {
        match self {
            SourceKey::Light(i) => &scene.lights[i as usize].name,
            SourceKey::Emitter(m) => &scene.materials[m as usize].name,
        }
    }
}

/// The sources of `scene`: its punctual lights, then its emissive materials.
pub fn sources(scene: &Scene) -> Vec<SourceKey> {
    let lights = (0..scene.lights.len() as u32).map(SourceKey::Light);
    let emitters = (0..scene.materials.len() as u32)
        .filter(|&m| scene.materials[m as usize].is_emissive())
        .map(SourceKey::Emitter);
    lights.chain(emitters).collect()
}

/// The quality `settings` give the source `key`, if they name it.
fn quality_of<'a>(
    settings: &'a RenderSettings,
    scene: &Scene,
    key: SourceKey,
) -> Option<&'a SourceQuality> {
    let name = key.name(scene);
    settings.sources.iter().find(|q| q.name == name)
}

/// Checks that every source `settings` name is a source of `scene`, and
/// that the samples of all the sources together stay within
/// [`MAX_SOURCE_SAMPLES_PER_VERTEX`].
pub fn check(settings: &RenderSettings, scene: &Scene) -> Result<(), String> {
    if settings.sources.is_empty() {
        return Ok(());
    }
    let all = sources(scene);
    for quality in &settings.sources {
        if !all.iter().any(|&key| key.name(scene) == quality.name) {
            let names: Vec<String> = all
                .iter()
                .map(|&key| format!("'{}'", key.name(scene)))
                .collect();
            return Err(format!(
                "the scene has no light source named '{}' (its sources: {})",
                quality.name,
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            ));
        }
    }
    let total: u32 = all
        .iter()
        .filter_map(|&key| samples_of(settings, scene, key))
        .sum();
    if total > MAX_SOURCE_SAMPLES_PER_VERTEX {
        return Err(format!(
            "the sources' light samples add up to {total} per vertex, more than {MAX_SOURCE_SAMPLES_PER_VERTEX}"
        ));
    }
    Ok(())
}

/// N_s of source `key`: `None` if it is switched off.
fn samples_of(settings: &RenderSettings, scene: &Scene, key: SourceKey) -> Option<u32> {
    match quality_of(settings, scene, key) {
        Some(quality) if !quality.on => None,
        Some(quality) => Some(quality.samples.unwrap_or(settings.light_samples)),
        None => Some(settings.light_samples),
    }
    .map(|n| n.max(1))
}

/// `scene` with the sources `settings` switch off emitting nothing (the
/// same scene, not a copy, when none is).
pub fn switch_off(scene: Arc<Scene>, settings: &RenderSettings) -> Arc<Scene> {
    let off: Vec<SourceKey> = sources(&scene)
        .into_iter()
        .filter(|&key| samples_of(settings, &scene, key).is_none())
        .collect();
    if off.is_empty() {
        return scene;
    }
    let mut scene = Arc::unwrap_or_clone(scene);
    for key in off {
        match key {
            SourceKey::Light(i) => scene.lights[i as usize].intensity = glam::Vec3::ZERO,
            SourceKey::Emitter(m) => scene.materials[m as usize].emission = glam::Vec3::ZERO,
        }
    }
    Arc::new(scene)
}

/// The light samples of a vertex with a quality for each source: which
/// source each sample draws from, and how a source picks one of its lights.
#[derive(Clone, Debug, Default)]
pub struct SourceBudget {
    /// Source (index into `sources`) of each of the N samples of a vertex.
    slots: Vec<u32>,
    sources: Vec<BudgetedSource>,
}

#[derive(Clone, Debug)]
struct BudgetedSource {
    /// The source's lights (indices into the light table).
    lights: Vec<u32>,
    /// P(t | s): one of them, by power (or uniformly over those that emit).
    selection: AliasTable,
    /// N_s.
    samples: u32,
}

impl SourceBudget {
    /// The budget of the lights whose sources are `keys` and powers
    /// `powers`, and each light's selection weight N_s P(t | s) (zero for a
    /// light no sample draws).
    pub fn build(
        scene: &Scene,
        settings: &RenderSettings,
        keys: &[SourceKey],
        powers: &[f32],
    ) -> (Self, Vec<f32>) {
        let mut weights = vec![0.0; keys.len()];
        let mut budget = SourceBudget::default();
        let mut distinct: Vec<SourceKey> = keys.to_vec();
        distinct.sort();
        distinct.dedup();
        for key in distinct {
            let Some(samples) = samples_of(settings, scene, key) else {
                continue;
            };
            let lights: Vec<u32> = (0..keys.len() as u32)
                .filter(|&l| keys[l as usize] == key)
                .collect();
            let within: Vec<f32> = lights
                .iter()
                .map(|&l| {
                    let power = powers[l as usize];
                    match settings.light_selection {
                        LightSelection::Power => power,
                        LightSelection::Uniform => f32::from(power > 0.0),
                    }
                })
                .collect();
            let selection = AliasTable::new(&within);
            if selection.is_empty() {
                continue; // emits nothing: its samples would add nothing
            }
            for (k, &light) in lights.iter().enumerate() {
                weights[light as usize] = samples as f32 * selection.pmf(k);
            }
            let index = budget.sources.len() as u32;
            budget
                .slots
                .extend(std::iter::repeat_n(index, samples as usize));
            budget.sources.push(BudgetedSource {
                lights,
                selection,
                samples,
            });
        }
        (budget, weights)
    }

    /// N: the light samples of a vertex, over all the sources.
    pub fn samples_per_vertex(&self) -> u32 {
        self.slots.len() as u32
    }

    /// Sample `slot`'s light, from one uniform number `u`: the light's
    /// index, P(t | s), N_s, and `u` remapped to a fresh uniform number.
    #[inline]
    pub fn pick(&self, slot: u32, u: f32) -> Option<(usize, f32, u32, f32)> {
        let source = &self.sources[*self.slots.get(slot as usize)? as usize];
        let (k, probability, remapped) = source.selection.sample_remapped(u)?;
        Some((
            source.lights[k] as usize,
            probability,
            source.samples,
            remapped,
        ))
    }
}
