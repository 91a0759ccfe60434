//! `lumiere lesson NAME|FILE --export DIR`: every step of a lesson rendered
//! as a slide (`DIR/NN-slug.png`, with `--gif` a convergence animation
//! `DIR/NN-slug.gif`) and `DIR/index.md` listing them. The layout is
//! described in `lumiere::tools::slides`.

use std::collections::HashMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::anyhow;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use lumiere::analysis::noise::DisplayMode;
use lumiere::lesson::{Lang, Lesson, StepView};
use lumiere::scene::Scene;
use lumiere::tools::slides::{
    GifWriter, IndexEntry, MAX_SLIDE_SIDE, Slide, SlideLayout, SlideTexts, file_stem,
    index_markdown, render_slide, settings_summary,
};

use super::{Failure, check_settings, check_sources, load_scene, summary, worker_pool};

/// The arguments of `lumiere lesson`.
#[derive(Args)]
pub struct LessonArgs {
    /// A built-in lesson (`lumiere lessons` lists them) or a lesson file.
    lesson: String,
    /// Write every step as a slide into this folder (created if missing):
    /// NN-slug.png and index.md.
    #[arg(long, value_name = "DIR")]
    export: PathBuf,
    /// Samples per pixel of every step, in place of each step's own (for quick drafts).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    spp: Option<u32>,
    /// Slide width in pixels.
    #[arg(long, default_value_t = 1920, value_parser = clap::value_parser!(u32).range(1..=MAX_SLIDE_SIDE as i64))]
    width: u32,
    /// Slide height in pixels (the text sizes follow it).
    #[arg(long, default_value_t = 1080, value_parser = clap::value_parser!(u32).range(1..=MAX_SLIDE_SIDE as i64))]
    height: u32,
    /// The language of the titles and captions: fr or en.
    #[arg(long, default_value = "en")]
    lang: Lang,
    /// Also write NN-slug.gif: the slide at 1, 2, 4, … samples per pixel, at half size, looping.
    #[arg(long)]
    gif: bool,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Seed of every step's random numbers (default: 0, as the viewer's).
    #[arg(long)]
    seed: Option<u64>,
}

/// A step ready to render: its settings on the slide's film and its files.
struct Job {
    view: StepView,
    texts: SlideTexts,
    stem: String,
}

/// Every check before rendering: the lesson, the slide's size, each step's
/// settings and film. Returns the layout and the jobs.
fn prepare(args: &LessonArgs, lesson: &Lesson) -> Result<(SlideLayout, Vec<Job>), Failure> {
    let layout = SlideLayout::new(args.width, args.height);
    layout.check().map_err(Failure::usage_message)?;
    let (width, height) = (layout.image.width, layout.image.height);
    let count = lesson.steps.len();
    let mut jobs = Vec::with_capacity(count);
    for (i, step) in lesson.steps.iter().enumerate() {
        let at = |e: String| {
            Failure::runtime(anyhow!(
                "{}: step {} ('{}'): {e}",
                args.lesson,
                i + 1,
                step.slug
            ))
        };
        let mut view = lesson.view(i, width, height).map_err(at)?;
        if view.display_mode == DisplayMode::Difference {
            return Err(at(
                "display 'difference' needs a reference image, which a slide has not".into(),
            ));
        }
        view.spp = args.spp.unwrap_or(view.spp);
        if let Some(seed) = args.seed {
            view.settings.seed = seed;
        }
        check_settings(&view.settings, view.settings.terms)?;
        jobs.push(Job {
            texts: SlideTexts::of(lesson, i, args.lang),
            stem: file_stem(i + 1, count, &step.slug),
            view,
        });
    }
    Ok((layout, jobs))
}

/// The command that makes these slides, for the index.
fn command_line(args: &LessonArgs) -> String {
    let mut command = format!(
        "lumiere lesson {} --export {} --width {} --height {} --lang {}",
        args.lesson,
        args.export.display(),
        args.width,
        args.height,
        args.lang
    );
    if let Some(spp) = args.spp {
        command += &format!(" --spp {spp}");
    }
    if let Some(seed) = args.seed {
        command += &format!(" --seed {seed}");
    }
    if args.gif {
        command += " --gif";
    }
    command
}

/// A bar over every pass of every step, if stderr is a terminal.
fn lesson_progress_bar(passes: u64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(passes);
    bar.set_style(
        ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} passes  {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// Writes `text` to `path`, the error naming the file.
fn write_file(path: &Path, text: &str) -> Result<(), Failure> {
    std::fs::write(path, text)
        .map_err(|e| Failure::runtime(anyhow!("{}: cannot write: {e}", path.display())))
}

/// Renders every step of the lesson into its slide, writes them and the index.
pub fn run(args: &LessonArgs) -> Result<(), Failure> {
    let start = Instant::now();
    let lesson = Lesson::load(&args.lesson).map_err(Failure::runtime)?;
    let (layout, jobs) = prepare(args, &lesson)?;
    let dir = &args.export;
    std::fs::create_dir_all(dir).map_err(|e| {
        Failure::runtime(anyhow!("{}: cannot create the folder: {e}", dir.display()))
    })?;
    let entries: Vec<IndexEntry> = jobs
        .iter()
        .map(|job| IndexEntry {
            texts: job.texts.clone(),
            stem: job.stem.clone(),
            settings: settings_summary(&job.view),
            gif: args.gif,
        })
        .collect();
    // the index first: an unwritable folder is found before any rendering
    let index = index_markdown(&lesson, args.lang, &layout, &command_line(args), &entries);
    write_file(&dir.join("index.md"), &index)?;

    let pool = worker_pool(args.threads)?;
    let total: u64 = jobs.iter().map(|job| job.view.spp as u64).sum();
    let bar = lesson_progress_bar(total);
    let mut scenes: HashMap<String, Arc<Scene>> = HashMap::new();
    let mut done = 0u64;
    for job in &jobs {
        let scene = match scenes.get(&job.view.scene) {
            Some(scene) => scene.clone(),
            None => {
                let scene: Arc<Scene> = bar.suspend(|| load_scene(&job.view.scene))?.into();
                scenes.insert(job.view.scene.clone(), scene.clone());
                scene
            }
        };
        check_sources(&job.view.settings, &scene, &job.view.scene)?;
        bar.set_message(job.stem.clone());
        let slide = Slide::new(layout.clone(), &job.texts);
        let gif_path = dir.join(format!("{}.gif", job.stem));
        let mut gif = match args.gif {
            true => Some(GifWriter::create(&gif_path).map_err(Failure::runtime)?),
            false => None,
        };
        let mut gif_error = None;
        let rendered = pool.install(|| {
            render_slide(
                scene,
                &job.view,
                &slide,
                args.gif,
                |stats| bar.set_position(done + stats.samples_per_pixel as u64),
                |count, frame| {
                    if let Some(gif) = &mut gif
                        && gif_error.is_none()
                        && let Err(e) = gif.push(frame, count == job.view.spp)
                    {
                        gif_error = Some(e);
                    }
                },
            )
        });
        drop(gif);
        if let Some(e) = gif_error {
            return Err(Failure::runtime(e));
        }
        done += job.view.spp as u64;
        let png = dir.join(format!("{}.png", job.stem));
        rendered
            .slide
            .to_rgb_image()
            .save(&png)
            .map_err(|e| Failure::runtime(anyhow!("{}: {e}", png.display())))?;
        bar.suspend(|| println!("{}: {}", job.stem, summary(&rendered.stats)));
    }
    bar.finish_and_clear();
    println!(
        "{} slides of {}×{} px in {}, {:.1} s",
        jobs.len(),
        layout.width,
        layout.height,
        dir.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
