//! "Save as shown": what the viewport shows — the image as displayed or a
//! noise view, A | B, the four-up, the probe's rays, a lesson step's texts
//! — gathered on the UI thread (shared images and a few strings), then
//! composed at the chosen size by `crate::tools::slides::shown` and written
//! as one PNG with the screenshot's JSON sidecar on a background thread.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use eframe::egui;

use super::files::{Outbox, Saved};
use super::{LumiereApp, four_up_view, split};
use crate::analysis::noise::FalseColour;
use crate::analysis::path_view::PathLine;
use crate::platform::threads::{self, Job};
use crate::render::display::DisplaySettings;
use crate::render::four_up::TILES;
use crate::render::progressive::Snapshot;
use crate::render::sidecar::Sidecar;
use crate::tools::slides::SlideTexts;
use crate::tools::slides::shown::{
    ShownImage, ShownPicture, ShownTile, SrgbImage, check_size, compose_shown,
};

/// What the viewport showed when the picture was asked for.
enum Shown {
    Image,
    Noise(Arc<FalseColour>),
    Split {
        image: Arc<Snapshot>,
        divider: u32,
        labels: [String; 2],
    },
    FourUp,
}

/// Where the picture goes.
pub enum Target {
    /// `lumiere-shown-NNN.png` in this folder, the first number free.
    Folder(PathBuf),
    /// This file (its sidecar beside it, `.json`).
    File(PathBuf),
}

/// One picture to compose and write, off the UI thread.
pub struct ShownJob {
    target: Target,
    size: (u32, u32),
    snapshot: Arc<Snapshot>,
    display: DisplaySettings,
    shown: Shown,
    paths: Vec<PathLine>,
    film: (u32, u32),
    texts: Option<SlideTexts>,
    sidecar: Sidecar,
}

/// The picture of what `app` shows now, at `size`, for `target`; refused
/// (with the reason) for a size out of range or before the first image.
pub fn job(app: &LumiereApp, target: Target, size: (u32, u32)) -> Result<ShownJob, String> {
    check_size(size.0, size.1)?;
    let snapshot = app.snapshot();
    if snapshot.radiance.is_empty() {
        return Err("nothing to save yet".into());
    }
    // as the viewport: a noise view replaces the image (A's, while comparing)
    let shown = if let Some(noise) = app.noise_image() {
        Shown::Noise(noise)
    } else if let Some(composite) = app.compare.composite() {
        Shown::Split {
            image: Arc::clone(&composite.image),
            divider: composite.divider_column,
            labels: split::labels(composite),
        }
    } else if four_up_view::active(app) {
        Shown::FourUp
    } else {
        Shown::Image
    };
    let probe = &app.probe;
    let paths = match (&probe.pixel, &probe.path.recorded) {
        (Some(_), Some(recorded)) if !probe.path.hidden => recorded.lines.clone(),
        _ => Vec::new(),
    };
    let lesson = &app.lesson;
    let texts = lesson
        .lesson
        .as_ref()
        .map(|l| SlideTexts::of(l, lesson.step, lesson.lang));
    Ok(ShownJob {
        target,
        size,
        snapshot,
        display: app.state.display,
        shown,
        paths,
        film: (app.state.settings.width, app.state.settings.height),
        texts,
        sidecar: app.sidecar(),
    })
}

impl ShownJob {
    /// Composes and writes the picture and its sidecar; says where.
    pub fn run(mut self) -> Result<Saved, String> {
        let (width, height) = self.size;
        let canvas = compose_shown(&self.picture(), width, height)?;
        let (mut outbox, stem) = match &self.target {
            Target::File(path) => {
                let folder = path.parent().unwrap_or(Path::new(""));
                let stem = path.file_stem().unwrap_or_default().to_string_lossy();
                (Outbox::new(folder)?, stem.into_owned())
            }
            Target::Folder(folder) => {
                let outbox = Outbox::new(folder)?;
                let stem = outbox.free_stem("lumiere-shown", ".png");
                (outbox, stem)
            }
        };
        outbox.write(&format!("{stem}.png"), canvas.png_bytes())?;
        self.sidecar.samples_per_pixel = self.snapshot.samples_per_pixel();
        outbox.write(&format!("{stem}.json"), self.sidecar.to_json().into_bytes())?;
        Ok(outbox.finish(&format!(" ({width}×{height}, as shown)")))
    }

    /// The viewport's picture as plain data: sRGB images, labels, rays, texts.
    fn picture(&self) -> ShownPicture {
        let display = self.display;
        let srgb = |s: &Snapshot, pixels: &[[f32; 4]]| {
            SrgbImage::from_radiance(s.width, s.height, pixels, display)
        };
        let snapshot = &self.snapshot;
        let image = match &self.shown {
            Shown::Image => ShownImage::Image(srgb(snapshot, &snapshot.radiance)),
            Shown::Noise(noise) => ShownImage::Noise(Arc::clone(noise)),
            Shown::Split {
                image,
                divider,
                labels,
            } => ShownImage::Split {
                image: srgb(image, &image.radiance),
                divider: *divider,
                labels: labels.clone(),
            },
            Shown::FourUp => {
                let pixels = snapshot.width as usize * snapshot.height as usize;
                let terms = snapshot.terms;
                let tiles = TILES.map(|tile| ShownTile {
                    image: tile
                        .pixels(snapshot)
                        .filter(|p| p.len() == pixels)
                        .map(|p| srgb(snapshot, p)),
                    label: tile.label(terms),
                    off: tile.is_off(terms),
                });
                ShownImage::FourUp {
                    tile_size: (snapshot.width, snapshot.height),
                    tiles: tiles.to_vec(),
                }
            }
        };
        ShownPicture {
            image,
            paths: self.paths.clone(),
            film: self.film,
            texts: self.texts.clone(),
        }
    }
}

/// The button: the picture at the Render group's size, in the screenshots'
/// folder, written in the background; a size out of range is refused in
/// the status bar.
pub fn save_as_shown(app: &mut LumiereApp) {
    let folder = PathBuf::from(&app.state.export_dir);
    match job(app, Target::Folder(folder), app.state.shown_size) {
        Ok(job) => {
            app.exports
                .push(threads::spawn("lumiere export", move || job.run()));
            app.message = Some("saving…".into());
        }
        Err(e) => app.message = Some(format!("error: {e}")),
    }
}

/// `--save-as-shown`: the picture a scripted run writes before it exits.
#[derive(Default)]
pub enum ScriptShown {
    /// None asked for, or written.
    #[default]
    Done,
    Pending(PathBuf),
    Running(Job<Result<Saved, String>>),
}

/// Scripted runs, once the image is final: writes the `--save-as-shown`
/// picture; true once it is written (or failed, which the run reports).
pub fn script_step(app: &mut LumiereApp, ctx: &egui::Context) -> bool {
    match std::mem::take(&mut app.script.shown) {
        ScriptShown::Done => return true,
        ScriptShown::Pending(path) => match job(app, Target::File(path), app.state.shown_size) {
            Ok(job) => {
                app.script.shown =
                    ScriptShown::Running(threads::spawn("lumiere export", || job.run()))
            }
            Err(e) => {
                app.script.failed(e);
                return true;
            }
        },
        ScriptShown::Running(handle) if handle.is_finished() => {
            match handle.join() {
                Some(Ok(done)) => eprintln!("{}", done.message),
                Some(Err(e)) => app.script.failed(e),
                None => app.script.failed("the picture could not be written".into()),
            }
            return true;
        }
        running => app.script.shown = running,
    }
    ctx.request_repaint_after(std::time::Duration::from_millis(20));
    false
}
