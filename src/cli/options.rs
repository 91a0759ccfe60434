//! The scene options shared by `render`, `view`, `strip` and `bench`.

use clap::Args;

use lumiere::course::{
    Adaptive, IndirectSampling, Integrator, LightSampling, LightSelection, MAX_SAMPLES_PER_VERTEX,
    MisHeuristic, Sampler, SourceQuality,
};
use lumiere::render::display::{DisplaySettings, Tonemap};
use lumiere::{BrdfOverride, LightMode, RenderSettings, TermSet};

use super::parsers::{
    IndirectSamples, parse_adaptive_threshold, parse_exposure, parse_indirect_samples, parse_ior,
    parse_light_radius, parse_phong_exponent, parse_source_quality,
};

/// What decides the radiance and its display: shared by `render`, `view` and `strip`.
#[derive(Args, Clone)]
pub struct SceneOptions {
    /// Image width [default: 640; bench: 256].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    /// Image height [default: 480; bench: 256].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Lighting terms: L0 (emission), L1 (direct), L2 (one indirect bounce), L3+ (the rest); `all` = all four.
    #[arg(long, default_value = "L0,L1,L2")]
    pub terms: TermSet,
    /// Light sources: authored, point (area lights collapsed to points) or area (point lights made spheres).
    #[arg(long, default_value = "authored")]
    pub lights: LightMode,
    /// Radius in metres of the sphere lights of `--lights area` (default: 2% of the scene's diagonal).
    #[arg(long, value_parser = parse_light_radius)]
    pub light_radius: Option<f32>,
    /// Model of every material: authored, lambert, phong, mirror or glass.
    #[arg(long, default_value = "authored")]
    pub brdf: BrdfOverride,
    /// Phong exponent for `--brdf phong`.
    #[arg(long, default_value_t = 32.0, value_parser = parse_phong_exponent)]
    pub phong_exponent: f32,
    /// Index of refraction for `--brdf glass` (authored glass keeps its own).
    #[arg(long, default_value_t = 1.5, value_parser = parse_ior)]
    pub ior: f32,
    /// Most reflections per path (caps L3+).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub max_bounces: u32,
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// The estimator: lecture (the course's L0 + L1 + L2 as the slides write it, `transport/lecture.rs`) or fast (the path tracer with the options below).
    #[arg(long, default_value = "fast")]
    pub integrator: Integrator,
    /// Direct lighting from extended lights: area, solid-angle, brdf, hemisphere or mis (light + BRDF).
    #[arg(long, default_value = "mis")]
    pub light_sampling: LightSampling,
    /// Weights of `--light-sampling mis`: balance or power.
    #[arg(long, default_value = "power")]
    pub mis_heuristic: MisHeuristic,
    /// Directions of the next reflection (L2, L3+): uniform, cosine or brdf.
    #[arg(long, default_value = "brdf")]
    pub indirect_sampling: IndirectSampling,
    /// Light samples (shadow rays or gathered directions) per vertex.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=MAX_SAMPLES_PER_VERTEX as i64))]
    pub light_samples: u32,
    /// Continuations per first hit (splitting), each weighted 1/M; `auto`: the count that reaches a given relMSE soonest, chosen by a pilot [default: auto; bench: 1 and auto]
    #[arg(long, value_parser = parse_indirect_samples)]
    pub indirect_samples: Option<IndirectSamples>,
    /// How a light is picked: uniform or power.
    #[arg(long, default_value = "power")]
    pub light_selection: LightSelection,
    /// A quality for each source, repeatable: `NAME=N` gives the source NAME (a light's or an emissive material's name) its own N light samples per vertex, `NAME=off` switches it off (it emits nothing).
    #[arg(long = "source", value_name = "NAME=N|off", value_parser = parse_source_quality)]
    pub sources: Vec<SourceQuality>,
    /// Random numbers: independent, stratified (jittered) or sobol (Owen-scrambled, the fastest to a given error).
    #[arg(long, default_value = "sobol")]
    pub sampler: Sampler,
    /// Adaptive sampling: stop sampling a pixel's term once its standard error is below this fraction of the pixel's value (e.g. 0.01; default: off, every pixel gets every sample)
    #[arg(long, value_parser = parse_adaptive_threshold)]
    pub adaptive: Option<f32>,
    /// Adaptive sampling: samples every pixel gets before its error is judged.
    #[arg(long, default_value_t = Adaptive::default().min_samples, requires = "adaptive", value_parser = clap::value_parser!(u32).range(Adaptive::MIN_SAMPLES as i64..=1_000_000))]
    pub adaptive_min_spp: u32,
    /// Exposure in stops (PNG and display; the EXR stays linear).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_exposure)]
    pub exposure: f32,
    /// Tonemap (PNG and display): none (clamp), reinhard or aces.
    #[arg(long, default_value = "none")]
    pub tonemap: Tonemap,
}

impl SceneOptions {
    /// The render settings these options ask for (640×480 unless given).
    pub fn settings(&self) -> RenderSettings {
        RenderSettings {
            width: self.width.unwrap_or(640),
            height: self.height.unwrap_or(480),
            terms: self.terms,
            light_mode: self.lights,
            light_radius: self.light_radius,
            brdf: self.brdf,
            phong_exponent: self.phong_exponent,
            glass_ior: self.ior,
            max_bounces: self.max_bounces,
            seed: self.seed,
            integrator: self.integrator,
            light_sampling: self.light_sampling,
            mis_heuristic: self.mis_heuristic,
            indirect_sampling: self.indirect_sampling,
            light_samples: self.light_samples,
            indirect_samples: match self.indirect_samples {
                Some(IndirectSamples::Count(m)) => m,
                _ => 1,
            },
            auto_indirect_samples: matches!(
                self.indirect_samples,
                None | Some(IndirectSamples::Auto)
            ),
            light_selection: self.light_selection,
            sampler: self.sampler,
            adaptive: self.adaptive.map(|threshold| Adaptive {
                threshold,
                min_samples: self.adaptive_min_spp,
            }),
            sources: self.sources.clone(),
            ..RenderSettings::default()
        }
    }

    /// The exposure and tonemap of the PNG and the display.
    pub fn display(&self) -> DisplaySettings {
        DisplaySettings {
            exposure: self.exposure,
            tonemap: self.tonemap,
            ..DisplaySettings::default()
        }
    }
}
