//! `lumiere view`: the interactive viewer (feature `gui`).

use std::path::PathBuf;

use clap::Parser;

use lumiere::analysis::noise::DisplayMode;
use lumiere::analysis::path_view::PathSample;
use lumiere::course::{
    BrdfOverride, IndirectSampling, Integrator, LightMode, LightSampling, Sampler, TermSet,
};
use lumiere::lesson::Lang;
use lumiere::render::display::Layout;

use super::Failure;
use super::options::SceneOptions;
use super::parsers::{parse_pixel, parse_png_path, parse_shown_size};

/// The arguments of `lumiere view` (and of `lumiere` without a command).
#[derive(Parser)]
pub struct ViewArgs {
    /// A .gltf/.glb file, or a built-in scene: `cornell` (the default) or another `lumiere lessons` lists.
    #[arg(default_value = "cornell")]
    scene: String,
    /// Render to this many samples per pixel, then exit (saving --save-as-shown and --screenshot first).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    exit_after_spp: Option<u32>,
    /// With --exit-after-spp: a PNG of the whole window, taken by the viewer.
    #[arg(long, requires = "exit_after_spp")]
    screenshot: Option<PathBuf>,
    /// With --exit-after-spp: a PNG of the picture as shown (as "Save as shown"), and its settings (.json) beside it.
    #[arg(long, requires = "exit_after_spp", value_parser = parse_png_path)]
    save_as_shown: Option<PathBuf>,
    /// The size of --save-as-shown's picture, WIDTHxHEIGHT (each side 16 to 16384 pixels).
    #[arg(long, default_value = "1920x1080", requires = "save_as_shown", value_parser = parse_shown_size)]
    shown_size: (u32, u32),
    /// Measure the time from a toggle to the preview on screen and the UI frame time, print them, exit.
    #[arg(long, conflicts_with_all = ["exit_after_spp", "screenshot"])]
    bench: bool,
    /// A linear EXR of the starting view (same size): RMSE and relMSE are measured against it.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Open the convergence plot (error against spp and seconds).
    #[arg(long)]
    convergence_plot: bool,
    /// Compare with B, A's settings with this light sampling: A left, B right, for the same time.
    #[arg(long)]
    compare_light_sampling: Option<LightSampling>,
    /// Compare with B, A's settings with this indirect sampling.
    #[arg(long)]
    compare_indirect_sampling: Option<IndirectSampling>,
    /// Compare with B, A's settings with this sampler.
    #[arg(long)]
    compare_sampler: Option<Sampler>,
    /// Compare with B, A's settings with these lights: authored, point or area.
    #[arg(long)]
    compare_lights: Option<LightMode>,
    /// Compare with B, A's settings with this BRDF: authored, lambert, phong or mirror.
    #[arg(long)]
    compare_brdf: Option<BrdfOverride>,
    /// Compare with B, A's settings with these terms, e.g. L0,L1.
    #[arg(long)]
    compare_terms: Option<TermSet>,
    /// Compare with B, A's settings with this integrator: fast or lecture.
    #[arg(long)]
    compare_integrator: Option<Integrator>,
    /// What the image shows: image, standard-error, relative-error or sample-count.
    #[arg(long, default_value = "image")]
    display_mode: DisplayMode,
    /// The image's layout: single, or four-up (L0 | L1 | L2 | their sum, from one render).
    #[arg(long, default_value = "single")]
    layout: Layout,
    /// Probe the pixel at X,Y (from the top left) from the start.
    #[arg(long, value_parser = parse_pixel)]
    probe: Option<(u32, u32)>,
    /// Which of the probed pixel's samples the path view draws: a number from 1, or `brightest`.
    #[arg(long, default_value = "1", requires = "probe")]
    probe_sample: PathSample,
    /// Open a lesson: a built-in one by name (`lumiere lessons` lists them) or a lesson file.
    #[arg(long)]
    lesson: Option<String>,
    /// With --lesson: the step to open on, from 1.
    #[arg(long, default_value = "1", requires = "lesson", value_parser = clap::value_parser!(u32).range(1..))]
    step: u32,
    /// The language of a lesson's texts: fr or en.
    #[arg(long, default_value = "en")]
    lang: Lang,
    /// Start in presentation mode (F5): no side panel.
    #[arg(long)]
    present: bool,
    #[command(flatten)]
    options: SceneOptions,
}

impl ViewArgs {
    /// The arguments of `lumiere` without a command: every default.
    pub fn defaults() -> Self {
        Self::parse_from(["view"])
    }
}

/// Every check of the viewer's arguments: the settings, and a film holding
/// every term (the viewer can switch each on).
#[cfg(feature = "gui")]
fn check(settings: &lumiere::RenderSettings) -> Result<(), Failure> {
    super::check_settings(settings, lumiere::TermSet::ALL)
}

/// Opens the viewer; `restore` brings back the last session's window and
/// settings (`lumiere` without a command).
#[cfg(feature = "gui")]
pub fn run(args: ViewArgs, restore: bool) -> Result<(), Failure> {
    let settings = args.options.settings();
    check(&settings)?;
    let lesson = match &args.lesson {
        Some(name) => {
            let lesson = lumiere::lesson::Lesson::load(name).map_err(Failure::runtime)?;
            if args.step as usize > lesson.steps.len() {
                return Err(Failure::usage_message(format!(
                    "--step {}: the lesson {name} has {} steps",
                    args.step,
                    lesson.steps.len()
                )));
            }
            Some(lesson)
        }
        None => None,
    };
    let b = lumiere::render::settings_override::SettingsOverride {
        light_sampling: args.compare_light_sampling,
        indirect_sampling: args.compare_indirect_sampling,
        sampler: args.compare_sampler,
        light_mode: args.compare_lights,
        brdf: args.compare_brdf,
        terms: args.compare_terms,
        integrator: args.compare_integrator,
        ..Default::default()
    };
    check(&b.apply(&settings))?;
    let compare = (!b.is_empty()).then_some(b);
    if compare.is_some() && args.layout == Layout::FourUp {
        return Err(Failure::usage_message(
            "--layout four-up shows the terms of one render; it cannot be combined with --compare-…",
        ));
    }
    let display = lumiere::render::display::DisplaySettings {
        layout: args.layout,
        ..args.options.display()
    };
    let options = lumiere::app::ViewOptions {
        scene: args.scene,
        settings,
        display,
        exit_after_spp: args.exit_after_spp,
        screenshot: args.screenshot,
        shown_size: args.save_as_shown.is_some().then_some(args.shown_size),
        save_as_shown: args.save_as_shown,
        restore,
        bench: args.bench,
        reference: args.reference,
        compare,
        convergence_plot: args.convergence_plot,
        display_mode: args.display_mode,
        probe: args.probe,
        probe_sample: args.probe_sample,
        lesson,
        step: args.step as usize - 1,
        lang: args.lang,
        present: args.present,
    };
    lumiere::app::run(options).map_err(|e| Failure::runtime(anyhow::anyhow!(e)))
}

/// Refuses: this build has no viewer.
#[cfg(not(feature = "gui"))]
pub fn run(_args: ViewArgs, _restore: bool) -> Result<(), Failure> {
    Err(Failure::usage_message(
        "this lumiere was built without the viewer (the `gui` feature); use `lumiere render`",
    ))
}
