//! Render settings: plain data, separate from the scene and from runtime state.
//!
//! Every enum here is a closed set with `ALL` and `label()`, so the command
//! line, the viewer and saved settings share one list of names.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;
use strum::{Display, EnumIter, EnumString, IntoEnumIterator, IntoStaticStr};

/// A lighting term of the course: the light that reached the camera after
/// exactly k reflections (L3+: three or more).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Term {
    L0,
    L1,
    L2,
    L3Plus,
}

impl Term {
    pub const ALL: [Term; 4] = [Term::L0, Term::L1, Term::L2, Term::L3Plus];
    pub const COUNT: usize = 4;

    pub fn label(self) -> &'static str {
        match self {
            Term::L0 => "L0",
            Term::L1 => "L1",
            Term::L2 => "L2",
            Term::L3Plus => "L3+",
        }
    }

    /// The term a path with `reflections` reflections belongs to.
    pub fn of_reflections(reflections: u32) -> Term {
        match reflections {
            0 => Term::L0,
            1 => Term::L1,
            2 => Term::L2,
            _ => Term::L3Plus,
        }
    }

    pub fn index(self) -> usize {
        self as usize
    }

    /// One-line description (English).
    pub fn description(self) -> &'static str {
        match self {
            Term::L0 => "emission: light emitted by the surface the camera sees",
            Term::L1 => "direct lighting: light from the sources, reflected once",
            Term::L2 => "indirect lighting: light reflected twice",
            Term::L3Plus => "three reflections or more (the rest of the full solution)",
        }
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

/// A set of terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct TermSet {
    bits: u8,
}

impl Default for TermSet {
    fn default() -> Self {
        TermSet::COURSE
    }
}

impl TermSet {
    pub const NONE: TermSet = TermSet { bits: 0 };
    pub const ALL: TermSet = TermSet { bits: 0b1111 };
    /// The default of the course: L0 + L1 + L2.
    pub const COURSE: TermSet = TermSet { bits: 0b0111 };

    pub fn only(term: Term) -> Self {
        Self {
            bits: 1 << term.index(),
        }
    }

    pub fn contains(self, term: Term) -> bool {
        self.bits & (1 << term.index()) != 0
    }

    /// Whether the term of paths with `reflections` reflections is in the set.
    pub fn contains_reflections(self, reflections: u32) -> bool {
        self.contains(Term::of_reflections(reflections))
    }

    pub fn with(self, term: Term, on: bool) -> Self {
        let bit = 1 << term.index();
        Self {
            bits: if on {
                self.bits | bit
            } else {
                self.bits & !bit
            },
        }
    }

    pub fn is_empty(self) -> bool {
        self.bits == 0
    }

    /// The terms in both sets.
    pub fn intersection(self, other: TermSet) -> Self {
        Self {
            bits: self.bits & other.bits,
        }
    }

    pub fn iter(self) -> impl Iterator<Item = Term> {
        Term::ALL.into_iter().filter(move |&t| self.contains(t))
    }

    /// The most reflections a path needs for these terms (`u32::MAX` with L3+).
    pub fn max_reflections(self) -> Option<u32> {
        self.iter().last().map(|t| match t {
            Term::L3Plus => u32::MAX,
            t => t.index() as u32,
        })
    }
}

impl fmt::Display for TermSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let labels: Vec<&str> = self.iter().map(Term::label).collect();
        f.write_str(&labels.join(","))
    }
}

impl FromStr for TermSet {
    type Err = String;

    /// `L0,L1,L2`, `all`, case-insensitive; `L3` is accepted for `L3+`.
    fn from_str(s: &str) -> Result<Self, String> {
        let mut set = TermSet::NONE;
        for word in s.split(',').map(str::trim) {
            let term = match word.to_ascii_uppercase().as_str() {
                "ALL" => {
                    set = TermSet::ALL;
                    continue;
                }
                "L0" => Term::L0,
                "L1" => Term::L1,
                "L2" => Term::L2,
                "L3+" | "L3" => Term::L3Plus,
                _ => {
                    return Err(format!(
                        "unknown term '{word}' (expected L0, L1, L2, L3+ or all, separated by commas)"
                    ));
                }
            };
            set = set.with(term, true);
        }
        if set.is_empty() {
            return Err("no term selected".into());
        }
        Ok(set)
    }
}

/// Which kind of light sources a render uses (the course's point ↔ extended swap).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<LightMode>)]
pub enum LightMode {
    /// As the scene defines them.
    #[default]
    Authored,
    /// Every area light becomes a point light at its centroid (cosine lobe, same power).
    Point,
    /// Every point or spot light becomes a sphere light of the light radius (same power).
    Area,
}

/// A global replacement of every material's reflection model.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<BrdfOverride>)]
pub enum BrdfOverride {
    /// Each material's own model (from its metallic-roughness parameters).
    #[default]
    Authored,
    Lambert,
    Phong,
    Mirror,
    /// Smooth glass of index of refraction `glass_ior`, tinted by the base colour.
    Glass,
}

/// How direct lighting from extended lights is estimated at each vertex.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<LightSampling>)]
pub enum LightSampling {
    /// Uniform points on the light's surface (pdf 1/A, converted to solid angle).
    Area,
    /// Uniform directions in the solid angle a triangle subtends (Arvo's
    /// spherical triangle sampling); area sampling for tiny or huge angles.
    SolidAngle,
    /// Sample the BRDF and count the directions that hit a light.
    Brdf,
    /// Uniform directions on the hemisphere that happen to see a light.
    Hemisphere,
    /// Light (area) and BRDF sampling combined by multiple importance sampling.
    #[default]
    Mis,
}

/// The weighting of the two strategies of `LightSampling::Mis`.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<MisHeuristic>)]
pub enum MisHeuristic {
    /// w = p_a / (p_a + p_b).
    Balance,
    /// w = p_a² / (p_a² + p_b²).
    #[default]
    Power,
}

/// How the direction of the next reflection (L2, L3+) is drawn.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<IndirectSampling>)]
pub enum IndirectSampling {
    /// pdf 1/2π.
    Uniform,
    /// pdf cos θ/π.
    Cosine,
    /// The BRDF's own sampling routine (pdf ∝ f cos θ where it can).
    #[default]
    Brdf,
}

/// How a light is picked for a light sample.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<LightSelection>)]
pub enum LightSelection {
    /// Every light with the same probability.
    Uniform,
    /// In proportion to emitted power.
    #[default]
    Power,
}

/// Where the random numbers of a sample come from.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<Sampler>)]
pub enum Sampler {
    /// Independent uniform numbers (plain Monte Carlo).
    Independent,
    /// Jittered strata: each dimension pair of a block of samples covers a grid.
    Stratified,
    /// Owen-scrambled Sobol points (quasi-Monte Carlo), scrambled per pixel:
    /// the default, the fastest to a given error measured.
    #[default]
    Sobol,
}

/// Which estimator computes the terms.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<Integrator>)]
pub enum Integrator {
    /// The lecture's estimator, written as the slides write it
    /// (`transport/lecture.rs`): one light sample and one BRDF direction per
    /// point, nothing else.
    Lecture,
    /// The fast path tracer (`transport/fast.rs`): the strategies, MIS,
    /// splitting and skipped work of the other settings.
    #[default]
    Fast,
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

/// The curve that maps exposed radiance to display values (display and PNG only).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<Tonemap>)]
pub enum Tonemap {
    /// Clamp to [0, 1].
    #[default]
    None,
    /// c / (1 + c) per channel.
    Reinhard,
    /// Narkowicz's fit of the ACES filmic curve.
    Aces,
}

impl Tonemap {
    /// The curve applied to one exposed linear value; the result is in [0, 1].
    pub fn apply(self, c: f32) -> f32 {
        let c = c.max(0.0);
        let mapped = match self {
            Tonemap::None => c,
            Tonemap::Reinhard => c / (1.0 + c),
            Tonemap::Aces => (c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14),
        };
        mapped.clamp(0.0, 1.0)
    }
}

/// How the viewer lays the image out.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    EnumIter,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "kebab-case", ascii_case_insensitive, parse_err_ty = String, parse_err_fn = unknown_choice::<Layout>)]
pub enum Layout {
    /// The sum of the visible terms.
    #[default]
    Single,
    /// L0 | L1 | L2 | their sum, side by side, from the same render
    /// (`crate::render::four_up`).
    FourUp,
}

/// How radiance becomes a picture: exposure (stops), then the tonemap, then
/// sRGB; and, in the viewer, the layout.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DisplaySettings {
    pub exposure: f32,
    pub tonemap: Tonemap,
    /// The viewer's layout (renders and EXR files show the sum).
    pub layout: Layout,
}

/// A closed set of options (light mode, BRDF, strategies, sampler, …):
/// strum derives the list of its values (`iter`), their names (kebab-case,
/// the same on the command line, in the viewer, the strips and the bench)
/// and the parser (any case), whose error lists the choices.
pub trait Choice: Copy + IntoEnumIterator + Into<&'static str> {
    /// The value's name.
    fn label(self) -> &'static str {
        self.into()
    }

    /// Every value, in declaration order.
    fn all() -> Vec<Self> {
        Self::iter().collect()
    }
}

impl<T: Copy + IntoEnumIterator + Into<&'static str>> Choice for T {}

/// The parse error of an unknown name `s` of the closed set `T`.
pub fn unknown_choice<T: Choice>(s: &str) -> String {
    let names: Vec<&str> = T::iter().map(T::label).collect();
    format!(
        "unknown value '{s}' (expected one of: {})",
        names.join(", ")
    )
}

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
            glass_ior: crate::scene::DEFAULT_IOR,
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
        if self.width == 0 || self.height == 0 {
            return Err(format!(
                "image size {}×{} is empty",
                self.width, self.height
            ));
        }
        if self.terms.is_empty() {
            return Err("no term selected".into());
        }
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
        for (i, source) in self.sources.iter().enumerate() {
            if source.name.is_empty() {
                return Err("a source's quality needs the source's name".into());
            }
            if self.sources[..i].iter().any(|s| s.name == source.name) {
                return Err(format!("source '{}' is given twice", source.name));
            }
            if let Some(count) = source.samples
                && !(1..=MAX_SAMPLES_PER_VERTEX).contains(&count)
            {
                return Err(format!(
                    "light samples {count} of source '{}' must be within 1..={MAX_SAMPLES_PER_VERTEX}",
                    source.name
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn term_sets_parse_and_print() {
        assert_eq!("L0,L1,L2".parse::<TermSet>().unwrap(), TermSet::COURSE);
        assert_eq!("all".parse::<TermSet>().unwrap(), TermSet::ALL);
        assert_eq!(
            "l3+".parse::<TermSet>().unwrap(),
            TermSet::only(Term::L3Plus)
        );
        assert!("L4".parse::<TermSet>().is_err());
        assert_eq!(TermSet::ALL.to_string(), "L0,L1,L2,L3+");
        assert_eq!(TermSet::only(Term::L2).max_reflections(), Some(2));
        assert_eq!(TermSet::ALL.max_reflections(), Some(u32::MAX));
    }

    #[test]
    fn enums_parse_their_labels() {
        for m in LightMode::all() {
            assert_eq!(m.label().parse::<LightMode>().unwrap(), m);
        }
        for b in BrdfOverride::all() {
            assert_eq!(b.label().parse::<BrdfOverride>().unwrap(), b);
        }
        assert!("points".parse::<LightMode>().is_err());
        for s in LightSampling::all() {
            assert_eq!(s.label().parse::<LightSampling>().unwrap(), s);
        }
        for s in IndirectSampling::all() {
            assert_eq!(s.label().parse::<IndirectSampling>().unwrap(), s);
        }
        for s in Sampler::all() {
            assert_eq!(s.label().parse::<Sampler>().unwrap(), s);
        }
        assert_eq!(
            "Solid-Angle".parse::<LightSampling>(),
            Ok(LightSampling::SolidAngle)
        );
    }
}
