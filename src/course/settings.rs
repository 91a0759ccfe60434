//! `RenderSettings`: everything that decides the radiance a render
//! estimates, as plain serde data apart from the scene and from runtime
//! state; its limits, and the check of what a file or a caller could get wrong.

use serde::{Deserialize, Serialize};

use crate::course::options::{
    BrdfOverride, IndirectSampling, Integrator, LightMode, LightSampling, LightSelection,
    MisHeuristic, Sampler,
};
use crate::course::terms::TermSet;

/// The index of refraction of glass when a file gives none (glTF's
/// default), and of the glass override's default.
pub const DEFAULT_IOR: f32 = 1.5;

/// The largest index of refraction a setting may ask for (germanium's is
/// about 4; beyond, nothing real).
pub const MAX_IOR: f32 = 5.0;

/// Everything that decides the radiance a render estimates (not how long it runs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub terms: TermSet,
    pub light_mode: LightMode,
    /// Radius of the sphere lights in `LightMode::Area`; `None`: 2% of the scene's diagonal.
    pub light_radius: Option<f32>,
    pub brdf: BrdfOverride,
    /// Phong exponent n used by `BrdfOverride::Phong`.
    pub phong_exponent: f32,
    /// Specular weight ks used by `BrdfOverride::Phong` (kd = base colour × (1 − ks)).
    pub phong_specular: f32,
    /// Index of refraction used by `BrdfOverride::Glass` (authored glass
    /// keeps its own).
    pub glass_ior: f32,
    /// Most reflections a path may have (caps L3+).
    pub max_bounces: u32,
    pub seed: u64,
    /// The estimator: the lecture's, or the fast one (the default).
    pub integrator: Integrator,
    /// Estimator of direct lighting from extended lights.
    pub light_sampling: LightSampling,
    pub mis_heuristic: MisHeuristic,
    /// How the direction of the next reflection is drawn.
    pub indirect_sampling: IndirectSampling,
    /// Light samples (shadow rays, or gathered directions) per vertex.
    pub light_samples: u32,
    /// Continuations per first hit (splitting), each weighted 1/M.
    pub indirect_samples: u32,
    /// Choose the continuations per first hit for the scene instead
    /// (`splitting`): the count that reaches a given relMSE soonest,
    /// estimated from a pilot before the first pass; `indirect_samples` is
    /// then ignored.
    pub auto_indirect_samples: bool,
    pub light_selection: LightSelection,
    pub sampler: Sampler,
    /// Adaptive sampling, if on; `None` (the default): every pixel gets every pass.
    pub adaptive: Option<Adaptive>,
    /// A quality for each source: sources switched off, or given their own
    /// number of light samples. Empty (the default): every source is on and
    /// `light_selection` shares the `light_samples` among them.
    pub sources: Vec<SourceQuality>,
}

/// Most light or indirect samples per vertex a render accepts.
pub const MAX_SAMPLES_PER_VERTEX: u32 = 256;

/// Most light samples per vertex over all the sources together, with a
/// quality for each source.
pub const MAX_SOURCE_SAMPLES_PER_VERTEX: u32 = 4 * MAX_SAMPLES_PER_VERTEX;

/// One light source's quality. A source is named as in the scene: a glTF
/// light by its name, an emitter by its emissive material's name (all the
/// triangles of that material are one source); an entry applies to every
/// source of that name.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SourceQuality {
    pub name: String,
    /// Off: the source emits nothing, in every term.
    #[serde(default = "switched_on")]
    pub on: bool,
    /// Light samples per vertex drawn on this source alone; `None`: `light_samples`.
    #[serde(default)]
    pub samples: Option<u32>,
}

fn switched_on() -> bool {
    true
}

impl SourceQuality {
    /// Checks this entry, given the entries before it.
    fn validate(&self, before: &[SourceQuality]) -> Result<(), String> {
        if self.name.is_empty() {
            return Err("a source's quality needs the source's name".into());
        }
        if before.iter().any(|s| s.name == self.name) {
            return Err(format!("source '{}' is given twice", self.name));
        }
        if let Some(count) = self.samples
            && !(1..=MAX_SAMPLES_PER_VERTEX).contains(&count)
        {
            return Err(format!(
                "light samples {count} of source '{}' must be within 1..={MAX_SAMPLES_PER_VERTEX}",
                self.name
            ));
        }
        Ok(())
    }

    /// The source `name`, on, with `samples` light samples of its own.
    pub fn samples(name: &str, samples: u32) -> Self {
        Self {
            name: name.into(),
            on: true,
            samples: Some(samples),
        }
    }

    /// The source `name`, switched off.
    pub fn off(name: &str) -> Self {
        Self {
            name: name.into(),
            on: false,
            samples: None,
        }
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            terms: TermSet::COURSE,
            light_mode: LightMode::Authored,
            light_radius: None,
            brdf: BrdfOverride::Authored,
            phong_exponent: 32.0,
            phong_specular: 0.25,
            glass_ior: DEFAULT_IOR,
            max_bounces: 64,
            seed: 0,
            integrator: Integrator::default(),
            light_sampling: LightSampling::default(),
            mis_heuristic: MisHeuristic::default(),
            indirect_sampling: IndirectSampling::default(),
            light_samples: 1,
            indirect_samples: 1,
            auto_indirect_samples: true,
            light_selection: LightSelection::default(),
            sampler: Sampler::default(),
            adaptive: None,
            sources: Vec::new(),
        }
    }
}

impl RenderSettings {
    /// Checks the values a file or a caller could get wrong; the message says which and why.
    pub fn validate(&self) -> Result<(), String> {
        self.validate_image()?;
        self.validate_materials()?;
        self.validate_sampling()?;
        self.sources
            .iter()
            .enumerate()
            .try_for_each(|(i, source)| source.validate(&self.sources[..i]))
    }

    /// The image and the terms.
    fn validate_image(&self) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!(
                "image size {}×{} is empty",
                self.width, self.height
            ));
        }
        if self.terms.is_empty() {
            return Err("no term selected".into());
        }
        Ok(())
    }

    /// The light radius and the overrides' parameters.
    fn validate_materials(&self) -> Result<(), String> {
        if let Some(r) = self.light_radius
            && !(r.is_finite() && r > 0.0)
        {
            return Err(format!(
                "light radius {r} must be a positive number of metres"
            ));
        }
        if !(self.phong_exponent.is_finite() && (0.0..=1e6).contains(&self.phong_exponent)) {
            return Err(format!(
                "Phong exponent {} must be within 0..=1e6",
                self.phong_exponent
            ));
        }
        if !(0.0..=1.0).contains(&self.phong_specular) {
            return Err(format!(
                "Phong specular weight {} must be within 0..=1",
                self.phong_specular
            ));
        }
        if !(self.glass_ior.is_finite() && (1.0..=MAX_IOR).contains(&self.glass_ior)) {
            return Err(format!(
                "index of refraction {} must be within 1..={MAX_IOR}",
                self.glass_ior
            ));
        }
        Ok(())
    }

    /// The path length, samples per vertex and adaptive sampling.
    fn validate_sampling(&self) -> Result<(), String> {
        if self.max_bounces == 0 {
            return Err("max bounces must be at least 1".into());
        }
        if let Some(adaptive) = &self.adaptive {
            adaptive.validate()?;
        }
        for (name, count) in [
            ("light samples", self.light_samples),
            ("indirect samples", self.indirect_samples),
        ] {
            if !(1..=MAX_SAMPLES_PER_VERTEX).contains(&count) {
                return Err(format!(
                    "{name} {count} must be within 1..={MAX_SAMPLES_PER_VERTEX}"
                ));
            }
        }
        Ok(())
    }
}

/// Adaptive sampling: a pixel's term stops receiving samples once its
/// standard error is a small enough fraction of the pixel's value.
///
/// Off by default (`RenderSettings::adaptive` is `None`): the noise lessons
/// need every pixel to get the same samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Adaptive {
    /// A term of a pixel stops once its standard error (of the luminance) is
    /// at most this fraction of the pixel's luminance Y, summed over the
    /// rendered terms; of √(Y² + 10⁻²) to be exact, which is Y on bright
    /// pixels and keeps dark ones from taking every sample (`crate::render::adaptive`).
    pub threshold: f32,
    /// Samples every pixel receives before its error is judged.
    pub min_samples: u32,
}

impl Default for Adaptive {
    fn default() -> Self {
        Self {
            threshold: 0.01,
            // fewer samples often underestimate the error of a pixel (a
            // bright bounce not yet drawn): it stops early and keeps a large
            // error
            min_samples: 128,
        }
    }
}

// Settings are compared and hashed as keys (`convergence::EstimatorKey`);
// a validated threshold is never NaN, so equality is an equivalence.
impl Eq for Adaptive {}

impl std::hash::Hash for Adaptive {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.threshold.to_bits().hash(state);
        self.min_samples.hash(state);
    }
}

impl Adaptive {
    /// The smallest `min_samples` accepted: a standard error from fewer samples is meaningless.
    pub const MIN_SAMPLES: u32 = 4;

    /// Checks the values a file or a caller could get wrong.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.threshold.is_finite() && self.threshold > 0.0 && self.threshold <= 1.0) {
            return Err(format!(
                "adaptive threshold {} must be a fraction within (0, 1] (0.01: stop at 1% standard error)",
                self.threshold
            ));
        }
        if self.min_samples < Self::MIN_SAMPLES {
            return Err(format!(
                "adaptive minimum of {} samples per pixel must be at least {} (a standard error needs several samples)",
                self.min_samples,
                Self::MIN_SAMPLES
            ));
        }
        Ok(())
    }
}
