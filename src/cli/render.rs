//! `lumiere render`: one scene to an EXR or PNG image.

use std::path::{Path, PathBuf};
use std::time::Duration;

use clap::Args;

use lumiere::course::Integrator;
use lumiere::render::display::DisplaySettings;
use lumiere::render::export::{ImageFormat, save_image};
use lumiere::render::sidecar::Sidecar;
use lumiere::render::{Budget, render};
use lumiere::scene::Camera;
use lumiere::transport::continuations::Continuations;
use lumiere::transport::splitting::choose_continuations;
use lumiere::{Film, RenderContext, RenderSettings};

use super::options::SceneOptions;
use super::parsers::parse_seconds;
use super::{
    Failure, check_settings, check_sources, load_scene, progress_bar, summary, update_bar,
    worker_pool,
};

/// The arguments of `lumiere render`.
#[derive(Args)]
pub struct RenderArgs {
    /// A .gltf/.glb file, or a built-in scene: `cornell` (the default) or another `lumiere lessons` lists.
    scene: Option<String>,
    /// Output image; its extension picks the format (.exr or .png).
    #[arg(short, long)]
    output: PathBuf,
    /// Samples per pixel (default 64, or the sidecar's).
    #[arg(long, conflicts_with = "time", value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    spp: Option<u32>,
    /// Render for this many seconds instead of a fixed sample count.
    #[arg(long, value_parser = parse_seconds)]
    time: Option<f64>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// A screenshot's JSON sidecar: its scene, camera, settings and spp replace the options above.
    #[arg(long)]
    settings: Option<PathBuf>,
    #[command(flatten)]
    options: SceneOptions,
}

/// What a render does, from the options or from a sidecar.
struct RenderJob {
    scene: String,
    /// What the viewer changed in the scene (from a sidecar).
    edits: lumiere::scene::edits::SceneEdits,
    camera: Option<Camera>,
    settings: RenderSettings,
    display: DisplaySettings,
    budget: Budget,
}

impl RenderJob {
    /// The job the options describe, or the one of `--settings`'s sidecar
    /// (its sample count unless `--spp` or `--time` is given).
    fn from_args(args: &RenderArgs) -> Result<Self, Failure> {
        let time_budget = args.time.map(|s| Budget::Time(Duration::from_secs_f64(s)));
        let Some(path) = &args.settings else {
            return Ok(Self {
                scene: args.scene.clone().unwrap_or_else(|| "cornell".into()),
                edits: Default::default(),
                camera: None,
                settings: args.options.settings(),
                display: args.options.display(),
                budget: time_budget.unwrap_or(Budget::Samples(args.spp.unwrap_or(64))),
            });
        };
        let sidecar = Sidecar::load(path).map_err(Failure::runtime)?;
        let spp = args.spp.unwrap_or(sidecar.samples_per_pixel.max(1));
        Ok(Self {
            scene: args.scene.clone().unwrap_or(sidecar.scene),
            edits: sidecar.edits,
            camera: Some(sidecar.camera),
            settings: sidecar.settings,
            display: sidecar.display,
            budget: time_budget.unwrap_or(Budget::Samples(spp)),
        })
    }
}

/// Every check of a render's arguments: the output's format (first, as a
/// bad extension is reported even when the sidecar cannot be read), then
/// the job's settings and film.
fn check(output: &Path, job: Result<RenderJob, Failure>) -> Result<RenderJob, Failure> {
    if ImageFormat::from_path(output).is_none() {
        return Err(Failure::usage_message(format_args!(
            "{}: unknown image format (the output must end in .exr or .png)",
            output.display()
        )));
    }
    let job = job?;
    check_settings(&job.settings, job.settings.terms)?;
    Ok(job)
}

/// Renders the scene, saves the image and prints the summary.
pub fn run(args: &RenderArgs) -> Result<(), Failure> {
    let job = check(&args.output, RenderJob::from_args(args))?;
    let settings = job.settings.clone();
    let mut scene = load_scene(&job.scene)?;
    if let Some(path) = &args.settings {
        job.edits
            .apply(&mut scene)
            .map_err(|e| Failure::runtime(anyhow::anyhow!("{}: {e}", path.display())))?;
    }
    check_sources(&settings, &scene, &job.scene)?;
    let pool = worker_pool(args.threads)?;
    let (film, stats, continuations) = pool.install(|| {
        let mut context = RenderContext::with_camera(scene, settings.clone(), job.camera.as_ref());
        choose_continuations(&mut context);
        let mut film = Film::new(settings.width, settings.height);
        let bar = progress_bar(job.budget);
        let stats = render(&context, &mut film, job.budget, |s| {
            update_bar(&bar, s, job.budget)
        });
        bar.finish_and_clear();
        (film, stats, context.continuations.clone())
    });
    let pixels = film.radiance(settings.terms);
    save_image(
        &args.output,
        settings.width,
        settings.height,
        &pixels,
        job.display,
    )
    .map_err(Failure::runtime)?;
    println!("{}", summary(&stats));
    if settings.integrator == Integrator::Lecture {
        println!("the lecture integrator counts its samples only: the rays above are camera rays");
    }
    if settings.adaptive.is_some() {
        let traced = stats.rays.camera as f64 / film.pixel_count() as f64;
        println!(
            "adaptive: {traced:.1} samples traced per pixel on average, of {} passes",
            stats.samples_per_pixel
        );
    }
    if settings.auto_indirect_samples {
        println!("{}", describe_continuations(&continuations));
    }
    println!("skipped: {}", stats.rays.skipped.describe());
    Ok(())
}

/// What `--indirect-samples auto` chose: one count, or the range of the
/// regions' counts and their mean over the image.
fn describe_continuations(continuations: &Continuations) -> String {
    match continuations.map {
        None => format!(
            "indirect samples: {} per first hit (auto)",
            continuations.count
        ),
        Some(ref map) => format!(
            "indirect samples: {} per first hit (auto), by region over {}×{} regions, {:.2} on average",
            continuations.label(),
            map.columns,
            map.rows,
            continuations.mean()
        ),
    }
}
