//! Scripted runs of the viewer (`lumiere view --exit-after-spp`,
//! `--screenshot`, `--save-as-shown`, `--bench`, the web page's checks):
//! once the image has its samples, write what was asked and close.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use eframe::egui;

use super::{LumiereApp, ViewOptions, bench, export, shown, split};
use crate::course::TermSet;
use crate::render::progressive::Snapshot;

/// What a scripted run asked for and how far it is.
pub struct ScriptedRun {
    /// Render to this many samples per pixel, then write and close.
    pub exit_after_spp: Option<u32>,
    /// `--screenshot`: the window, saved once the image is final.
    screenshot: Option<PathBuf>,
    /// `--save-as-shown`: the picture to write before exiting.
    pub shown: shown::ScriptShown,
    /// What went wrong (the run then fails); shared with `run`.
    pub failure: Arc<Mutex<Option<String>>>,
    /// Set by the screenshot callback: the outcome of saving the window.
    window_shot: Arc<Mutex<Option<Result<PathBuf, String>>>>,
    window_shot_requested: bool,
    /// The image (worker, restart, terms) a scripted page last reported.
    #[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
    reported_film: Option<(u64, u64, TermSet)>,
    /// `--bench`: the viewer timing its own toggles and frames.
    pub bench: Option<bench::Bench>,
}

impl ScriptedRun {
    pub fn new(options: &ViewOptions) -> Self {
        Self {
            exit_after_spp: options.exit_after_spp,
            screenshot: options.screenshot.clone(),
            shown: options
                .save_as_shown
                .clone()
                .map_or(shown::ScriptShown::Done, shown::ScriptShown::Pending),
            failure: Arc::default(),
            window_shot: Arc::default(),
            window_shot_requested: false,
            reported_film: None,
            bench: options.bench.then(bench::Bench::default),
        }
    }

    /// A file could not be written: the run fails with `problem` (the first, if several).
    pub fn failed(&self, problem: String) {
        let mut failure = self.failure.lock().unwrap_or_else(|p| p.into_inner());
        failure.get_or_insert(problem);
    }
}

/// Once the image has enough samples and every view has caught up: writes
/// the picture asked for, then the window, and closes.
pub fn exit_when_done(app: &mut LumiereApp, ctx: &egui::Context, snapshot: &Snapshot) {
    if !is_final(app, ctx, snapshot) || !shown::script_step(app, ctx) {
        return;
    }
    match app.script.screenshot.clone() {
        Some(path) => save_window_and_close(app, ctx, path),
        None => close(app, ctx, snapshot),
    }
}

/// Whether the image is the run's last: the target reached (or nothing
/// left to do), the scene shown now, B settled, the noise view and the
/// probe caught up with the last pass.
fn is_final(app: &LumiereApp, ctx: &egui::Context, snapshot: &Snapshot) -> bool {
    let Some(target) = app.script.exit_after_spp else {
        return false;
    };
    // an idle worker short of the target has nothing left to do (adaptive
    // sampling has stopped every pixel): the run ends there
    let short = snapshot.samples_per_pixel() < target && !snapshot.idle;
    // the image of the scene shown now, not of one just replaced
    let current = snapshot
        .source
        .as_ref()
        .is_some_and(|s| s.scene.ptr_eq(&Arc::downgrade(&app.scene)));
    if snapshot.preview || short || !current || !split::settled(app) {
        return false;
    }
    let caught_up = app
        .noise_view
        .is_current(app.state.noise, snapshot.generation)
        && app.probe.is_settled(snapshot.samples_per_pixel())
        && app.hemisphere.is_settled(&app.sent, app.probe.pixel);
    if !caught_up {
        ctx.request_repaint_after(std::time::Duration::from_millis(20));
    }
    caught_up
}

/// Without a screenshot: the window closes; a page, which cannot close
/// itself, says so on its console once for each film and terms shown.
fn close(app: &mut LumiereApp, ctx: &egui::Context, snapshot: &Snapshot) {
    #[cfg(target_arch = "wasm32")]
    {
        let film = (app.renderer_serial, snapshot.restarts, snapshot.terms);
        if app.script.reported_film != Some(film) {
            app.script.reported_film = Some(film);
            super::web::report_reached(
                snapshot,
                app.image_rect.map(|r| r * ctx.pixels_per_point()),
            );
        }
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        let _ = (app, snapshot);
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }
}

/// Asks egui for the window's pixels, saves them to `path` when they come,
/// prints where the image is in them, and closes.
fn save_window_and_close(app: &mut LumiereApp, ctx: &egui::Context, path: PathBuf) {
    let run = &mut app.script;
    if !run.window_shot_requested {
        run.window_shot_requested = true;
        let outcome = Arc::clone(&run.window_shot);
        let repaint = ctx.clone();
        ctx.request_screenshot(move |image| {
            *outcome.lock().unwrap_or_else(|p| p.into_inner()) =
                Some(export::save_window(&path, &image).map(|()| path.clone()));
            repaint.request_repaint();
        });
        return;
    }
    let done = run
        .window_shot
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .take();
    let Some(outcome) = done else {
        ctx.request_repaint();
        return;
    };
    match outcome {
        Ok(path) => {
            eprintln!("saved {}", path.display());
            if let Some(rect) = app.image_rect {
                // in screenshot pixels, for scripts that crop the image out
                let r = rect * ctx.pixels_per_point();
                eprintln!(
                    "image at {:.0} {:.0} size {:.0} {:.0}",
                    r.min.x,
                    r.min.y,
                    r.width(),
                    r.height()
                );
            }
        }
        Err(e) => run.failed(e),
    }
    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
}

/// `--bench`: records this frame and toggles the BRDF when it is time.
pub fn bench_step(
    app: &mut LumiereApp,
    ctx: &egui::Context,
    snapshot: &Snapshot,
    started: crate::platform::time::Instant,
) {
    let Some(bench) = &mut app.script.bench else {
        return;
    };
    if !snapshot.idle {
        bench.frame_built(started.elapsed());
    }
    match bench.step(snapshot, app.state.settings.brdf) {
        bench::BenchStep::Wait => ctx.request_repaint(),
        bench::BenchStep::Toggle(brdf) => {
            app.state.settings.brdf = brdf;
            app.sync_renderer();
            if let Some(bench) = &mut app.script.bench {
                bench.posted(snapshot.generation);
            }
            ctx.request_repaint();
        }
        bench::BenchStep::Finished(report) => {
            println!("{report}");
            app.script.bench = None;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }
}
