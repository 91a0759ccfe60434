//! What a lesson step sets, with the names and values of lumiere's command
//! line, and the view it gives.

use serde::Deserialize;

use crate::analysis::noise::DisplayMode;
use crate::course::{
    BrdfOverride, IndirectSampling, Integrator, LightMode, LightSampling, MisHeuristic,
    RenderSettings, Sampler, SourceQuality, TermSet,
};
use crate::render::display::{DisplaySettings, Layout, Tonemap};
use crate::render::settings_override::{SettingsOverride, named};

/// Samples per pixel a step stops at, unless it says otherwise.
pub const DEFAULT_STEP_SPP: u32 = 64;

/// The settings a step (or a lesson's defaults) changes; what it leaves
/// out keeps its value from below.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepSettings {
    /// `cornell` or a glTF path.
    pub scene: Option<String>,
    #[serde(default, with = "named")]
    pub terms: Option<TermSet>,
    #[serde(default, with = "named")]
    pub lights: Option<LightMode>,
    pub light_radius: Option<f32>,
    #[serde(default, with = "named")]
    pub brdf: Option<BrdfOverride>,
    pub phong_exponent: Option<f32>,
    pub phong_specular: Option<f32>,
    /// The index of refraction of `brdf = "glass"`.
    pub glass_ior: Option<f32>,
    #[serde(default, with = "named")]
    pub light_sampling: Option<LightSampling>,
    #[serde(default, with = "named")]
    pub mis_heuristic: Option<MisHeuristic>,
    #[serde(default, with = "named")]
    pub indirect_sampling: Option<IndirectSampling>,
    pub light_samples: Option<u32>,
    pub indirect_samples: Option<u32>,
    #[serde(default, with = "named")]
    pub sampler: Option<Sampler>,
    #[serde(default, with = "named")]
    pub integrator: Option<Integrator>,
    /// Samples per pixel the step stops at.
    pub spp: Option<u32>,
    /// Exposure in EV (stops).
    pub exposure: Option<f32>,
    #[serde(default, with = "named")]
    pub tonemap: Option<Tonemap>,
    #[serde(default, with = "named")]
    pub display: Option<DisplayMode>,
    /// `four-up`: L0 | L1 | L2 | their sum.
    #[serde(default, with = "named")]
    pub layout: Option<Layout>,
    /// A pixel to probe, [x, y] from the top left: its samples' paths are drawn.
    pub probe: Option<[u32; 2]>,
    /// A quality for each source: `[{ name = "…", samples = 8 }, { name = "…", on = false }]`.
    pub sources: Option<Vec<SourceQuality>>,
    /// Split the image: A (the settings above) left, B (these changes to
    /// them) right, for the same time (`[steps.settings.split]`).
    pub split: Option<SettingsOverride>,
}

/// Everything a step shows.
#[derive(Clone, Debug, PartialEq)]
pub struct StepView {
    pub scene: String,
    pub settings: RenderSettings,
    pub display: DisplaySettings,
    pub display_mode: DisplayMode,
    pub spp: u32,
    pub probe: Option<(u32, u32)>,
    /// What B changes, when the image is split between A and B.
    pub split: Option<SettingsOverride>,
}

impl StepView {
    /// lumiere's defaults on a film of `width` × `height`.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            scene: "cornell".into(),
            settings: RenderSettings {
                width,
                height,
                ..RenderSettings::default()
            },
            display: DisplaySettings::default(),
            display_mode: DisplayMode::Image,
            spp: DEFAULT_STEP_SPP,
            probe: None,
            split: None,
        }
    }

    /// B's settings, when the image is split.
    pub fn split_settings(&self) -> Option<RenderSettings> {
        self.split.as_ref().map(|split| split.apply(&self.settings))
    }
}

impl StepSettings {
    /// Sets in `view` what these settings say.
    pub fn apply(&self, view: &mut StepView) {
        fn set<T: Clone>(target: &mut T, value: &Option<T>) {
            if let Some(value) = value {
                *target = value.clone();
            }
        }
        let s = &mut view.settings;
        set(&mut view.scene, &self.scene);
        set(&mut s.terms, &self.terms);
        set(&mut s.light_mode, &self.lights);
        if self.light_radius.is_some() {
            s.light_radius = self.light_radius;
        }
        set(&mut s.brdf, &self.brdf);
        set(&mut s.phong_exponent, &self.phong_exponent);
        set(&mut s.phong_specular, &self.phong_specular);
        set(&mut s.glass_ior, &self.glass_ior);
        set(&mut s.light_sampling, &self.light_sampling);
        set(&mut s.mis_heuristic, &self.mis_heuristic);
        set(&mut s.indirect_sampling, &self.indirect_sampling);
        set(&mut s.light_samples, &self.light_samples);
        if let Some(count) = self.indirect_samples {
            s.indirect_samples = count;
            s.auto_indirect_samples = false;
        }
        set(&mut s.sampler, &self.sampler);
        set(&mut s.integrator, &self.integrator);
        set(&mut s.sources, &self.sources);
        set(&mut view.spp, &self.spp);
        set(&mut view.display.exposure, &self.exposure);
        set(&mut view.display.tonemap, &self.tonemap);
        set(&mut view.display_mode, &self.display);
        set(&mut view.display.layout, &self.layout);
        if let Some([x, y]) = self.probe {
            view.probe = Some((x, y));
        }
        if self.split.is_some() {
            view.split = self.split.clone();
        }
    }
}
