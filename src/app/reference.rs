//! The viewer's error measurement: a reference (captured in the background
//! or loaded from an EXR), the RMSE and relMSE of each new image against it
//! (see `crate::analysis::metrics`), and the curves of the convergence plot.
//!
//! An image is measured only when it shows what the reference is valid for
//! (`crate::analysis::capture::ReferenceKey`): same scene object, camera, size, terms
//! and radiance settings; the estimator may differ.

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use eframe::egui;
use glam::Vec3;

use super::LumiereApp;
use crate::analysis::capture::{ReferenceCapture, ReferenceJob, ReferenceKey};
use crate::analysis::convergence::{CurveSet, ErrorPoint, EstimatorKey, RunId};
use crate::analysis::metrics::{ReferenceImage, image_error};
use crate::platform::time::Instant;
use crate::render::export::load_exr;
use crate::render::progressive::Snapshot;

/// The two renderers whose images are measured: the main one and, when
/// comparing, the second estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    A,
    B,
}

impl Side {
    pub const ALL: [Side; 2] = [Side::A, Side::B];

    pub fn label(self) -> &'static str {
        match self {
            Side::A => "A",
            Side::B => "B",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// The last error measured on one side.
#[derive(Clone, Copy, Debug)]
pub struct Measured {
    pub estimator: EstimatorKey,
    pub point: ErrorPoint,
}

/// Reference bookkeeping and measurements (the image itself is `LumiereApp::reference`).
pub struct ErrorTracking {
    /// What `LumiereApp::reference` is valid for.
    pub key: Option<ReferenceKey>,
    capture: Option<ReferenceCapture>,
    /// Samples per pixel of the next capture.
    pub capture_spp: u32,
    /// Text of the EXR path field.
    pub exr_field: String,
    /// The latest error of each side, while its image matches the reference.
    pub latest: [Option<Measured>; 2],
    /// (renderer, generation) of the snapshot each side measured last.
    measured: [Option<(u64, u64)>; 2],
    pub curves: CurveSet,
    pub show_plot: bool,
    /// Plot relMSE instead of RMSE.
    pub plot_relmse: bool,
    /// How long the last measurement took (conversion and error).
    pub measure_time: Duration,
}

impl Default for ErrorTracking {
    fn default() -> Self {
        Self {
            key: None,
            capture: None,
            capture_spp: 1024,
            exr_field: String::new(),
            latest: [None; 2],
            measured: [None; 2],
            curves: CurveSet::default(),
            show_plot: false,
            plot_relmse: false,
            measure_time: Duration::ZERO,
        }
    }
}

impl ErrorTracking {
    /// A reference capture is under way (the live renderers pause meanwhile).
    pub fn capturing(&self) -> bool {
        self.capture.is_some()
    }
}

/// Installs a new reference: earlier measurements and curves are forgotten.
fn set_reference(app: &mut LumiereApp, image: ReferenceImage, key: ReferenceKey) {
    app.message = Some(format!("reference: {}", image.label));
    app.reference = Some(Arc::new(image));
    let errors = &mut app.errors;
    errors.key = Some(key);
    errors.latest = [None; 2];
    errors.measured = [None; 2];
    errors.curves.clear();
}

/// Whether the reference (if any) is valid for what the controls now show.
pub fn reference_matches_view(app: &LumiereApp) -> bool {
    app.errors.key.as_ref().is_some_and(|key| {
        key.matches(
            &Arc::downgrade(&app.scene),
            &app.camera,
            &app.state.settings,
        )
    })
}

/// Starts rendering the current view to `capture_spp` in the background.
pub fn start_capture(app: &mut LumiereApp, ctx: &egui::Context) {
    let job = ReferenceJob::new(
        Arc::clone(&app.scene),
        app.camera.clone(),
        &app.state.settings,
        app.errors.capture_spp,
    );
    let repaint = super::waker::Waker::new(ctx);
    app.errors.capture = Some(ReferenceCapture::spawn(job, move || repaint.wake()));
    app.message = Some("capturing a reference…".into());
}

/// Takes the finished capture, if any.
pub fn poll_capture(app: &mut LumiereApp) {
    if !app
        .errors
        .capture
        .as_ref()
        .is_some_and(ReferenceCapture::is_finished)
    {
        return;
    }
    let Some(capture) = app.errors.capture.take() else {
        return;
    };
    match capture.join() {
        Some((image, key)) => set_reference(app, image, key),
        None => app.message = Some("reference capture cancelled".into()),
    }
}

/// Loads an EXR as the reference of the current view; it must have the image's size.
pub fn load_reference_exr(app: &mut LumiereApp, path: &str) -> Result<(), String> {
    let path = Path::new(path.trim());
    let (width, height, radiance) = load_exr(path).map_err(|e| e.to_string())?;
    let settings = &app.state.settings;
    if (width, height) != (settings.width, settings.height) {
        return Err(format!(
            "{}: the reference is {width}×{height}, the image {}×{}",
            path.display(),
            settings.width,
            settings.height
        ));
    }
    let label = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    );
    let key = ReferenceKey::new(&app.scene, &app.camera, settings);
    let image = ReferenceImage {
        width,
        height,
        radiance,
        label,
    };
    set_reference(app, image, key);
    Ok(())
}

/// Measures `snapshot` of `side` (rendered by worker number `renderer`) if it
/// is new and shows what the reference is valid for; records it on its curve.
pub fn measure(app: &mut LumiereApp, side: Side, renderer: u64, snapshot: &Snapshot) {
    let errors = &mut app.errors;
    let (Some(reference), Some(key)) = (&app.reference, &errors.key) else {
        return;
    };
    let id = (renderer, snapshot.generation);
    if snapshot.preview || errors.measured[side.index()] == Some(id) {
        return;
    }
    errors.measured[side.index()] = Some(id);
    let Some(source) = &snapshot.source else {
        return;
    };
    let same_size = (snapshot.width, snapshot.height) == (reference.width, reference.height);
    if !same_size || !key.matches_source(source) {
        errors.latest[side.index()] = None;
        return;
    }
    let started = Instant::now();
    let image: Vec<Vec3> = snapshot
        .radiance
        .iter()
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect();
    let Some(error) = image_error(&image, &reference.radiance) else {
        return;
    };
    errors.measure_time = started.elapsed();
    let estimator = EstimatorKey::of(&source.settings);
    let point = ErrorPoint {
        samples_per_pixel: snapshot.samples_per_pixel(),
        seconds: snapshot.elapsed.as_secs_f64(),
        error,
    };
    errors.latest[side.index()] = Some(Measured { estimator, point });
    let run = RunId {
        renderer,
        restart: snapshot.restarts,
    };
    errors.curves.record(estimator, run, point);
}

/// The "Error" group of the side panel.
pub fn error_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Error")
        .default_open(app.reference.is_some())
        .show(ui, |ui| {
            capture_ui(app, ui);
            // a reference EXR by its path (not in a browser)
            if super::files::READS_PATHS {
                ui.horizontal(|ui| {
                    let label = ui.label("EXR");
                    let field = ui
                        .text_edit_singleline(&mut app.errors.exr_field)
                        .labelled_by(label.id)
                        .on_hover_text("A linear EXR of the current view, its size");
                    let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    if ui.button("Load EXR").clicked() || enter {
                        let path = app.errors.exr_field.clone();
                        if let Err(e) = load_reference_exr(app, &path) {
                            app.message = Some(format!("error: {e}"));
                        }
                    }
                });
            }
            readout_ui(app, ui);
            ui.horizontal(|ui| {
                ui.checkbox(&mut app.errors.show_plot, "Convergence plot");
                if ui
                    .button("Restart render")
                    .on_hover_text("Start the image (and B's) again from 1 spp: a new curve")
                    .clicked()
                {
                    super::split::restart(app, &ui.ctx().clone());
                }
            });
        });
}

fn capture_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    if let Some(capture) = &app.errors.capture {
        let (done, target) = capture.progress();
        ui.horizontal(|ui| {
            ui.add(
                egui::ProgressBar::new(done as f32 / target.max(1) as f32)
                    .desired_width(170.0)
                    .text(format!("{done} / {target} spp")),
            );
            if ui.button("Cancel").clicked() {
                capture.cancel();
            }
        });
        ui.label(
            egui::RichText::new("the live render waits for the capture")
                .weak()
                .small(),
        );
        return;
    }
    ui.horizontal(|ui| {
        // on a page with one thread the capture would hold the page until done
        let capture = ui
            .add_enabled(
                !crate::platform::threads::ONE_THREAD,
                egui::Button::new("Capture reference"),
            )
            .on_hover_text(
                "Render the current view to this many samples per pixel, with a seed of its own",
            )
            .on_disabled_hover_text(
                "Needs the page's Web Workers: serve the site with `lumiere serve`, \
                 which makes the page cross-origin isolated",
            );
        if capture.clicked() {
            start_capture(app, &ui.ctx().clone());
        }
        ui.add(
            egui::DragValue::new(&mut app.errors.capture_spp)
                .range(1..=1_000_000)
                .suffix(" spp"),
        );
    });
}

fn readout_ui(app: &LumiereApp, ui: &mut egui::Ui) {
    let Some(reference) = &app.reference else {
        ui.label(
            egui::RichText::new("no reference: capture one or load an EXR")
                .weak()
                .small(),
        );
        return;
    };
    ui.label(egui::RichText::new(format!("reference: {}", reference.label)).small());
    if !reference_matches_view(app) {
        ui.colored_label(
            ui.visuals().warn_fg_color,
            "reference is for other settings",
        )
        .on_hover_text(
            "It was made for another scene, camera, size, terms, light mode or BRDF; errors are measured only against the view it was made for",
        );
        return;
    }
    let sides = if app.compare.enabled {
        &Side::ALL[..]
    } else {
        &Side::ALL[..1]
    };
    for &side in sides {
        if let Some(measured) = &app.errors.latest[side.index()] {
            let point = &measured.point;
            ui.label(format!(
                "{} RMSE {:.3e} · relMSE {:.3e} · {} spp",
                side.label(),
                point.error.rmse,
                point.error.relmse,
                point.samples_per_pixel
            ))
            .on_hover_text(format!(
                "{}: RMSE in W/(m²·sr), relMSE unitless (see the user guide); measured in {:.1} ms",
                measured.estimator.label(),
                app.errors.measure_time.as_secs_f64() * 1e3
            ));
        }
    }
}
