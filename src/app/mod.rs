//! The viewer: an eframe window around the progressive renderer.
//!
//! The UI thread only draws: it posts a [`ViewRequest`] to the render worker
//! whenever a control changes something, and shows the latest snapshot
//! through the wgpu blit of [`display`]. Settings persist between runs
//! (eframe storage); runtime handles (worker, scene) do not.

mod bench;
mod convergence;
pub mod display;
mod export;
mod files;
pub mod four_up_view;
pub mod hemisphere_view;
mod interact;
pub mod lesson_view;
pub mod noise_view;
mod override_ui;
mod panels;
pub mod probe_view;
pub mod reference;
mod sampling_panel;
mod scene_panel;
mod script;
mod shown;
mod source_quality;
pub mod split;
pub mod thumbnails;
mod viewport;
mod waker;
#[cfg(target_arch = "wasm32")]
pub mod web;

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use eframe::egui;
use serde::{Deserialize, Serialize};

use crate::analysis::metrics::ReferenceImage;
use crate::analysis::noise::{DisplayMode, NoiseView};
use crate::course::RenderSettings;
use crate::render::display::DisplaySettings;
use crate::render::progressive::{ProgressiveRenderer, Snapshot, ViewRequest};
use crate::scene::{Camera, Scene, builtin};

/// How the viewer starts (from the command line).
#[derive(Clone, Debug)]
pub struct ViewOptions {
    /// `cornell` or a glTF path.
    pub scene: String,
    pub settings: RenderSettings,
    pub display: DisplaySettings,
    /// Render to this many samples per pixel, save `save_as_shown` and
    /// `screenshot` (if any) and exit.
    pub exit_after_spp: Option<u32>,
    pub screenshot: Option<PathBuf>,
    /// A PNG of the picture as shown, at `shown_size` (or the Render group's size).
    pub save_as_shown: Option<PathBuf>,
    pub shown_size: Option<(u32, u32)>,
    /// Restore the settings of the previous run (not for scripted runs).
    pub restore: bool,
    /// Measure toggle-to-preview latency and UI frame times, print them and exit.
    pub bench: bool,
    /// An EXR of the starting view to measure the error against.
    pub reference: Option<PathBuf>,
    /// Compare from the start with B: A's settings with these changes.
    pub compare: Option<crate::render::settings_override::SettingsOverride>,
    /// Open the convergence plot.
    pub convergence_plot: bool,
    /// What the image shows first (radiance or a noise view).
    pub display_mode: DisplayMode,
    /// A pixel to probe from the start.
    pub probe: Option<(u32, u32)>,
    /// The probed sample whose path is drawn.
    pub probe_sample: crate::analysis::path_view::PathSample,
    /// A lesson to open, on step `step` (from 0), its texts in `lang`.
    pub lesson: Option<crate::lesson::Lesson>,
    pub step: usize,
    pub lang: crate::lesson::Lang,
    /// Start in presentation mode.
    pub present: bool,
}

impl Default for ViewOptions {
    fn default() -> Self {
        Self {
            scene: "cornell".into(),
            settings: RenderSettings::default(),
            display: DisplaySettings::default(),
            exit_after_spp: None,
            screenshot: None,
            save_as_shown: None,
            shown_size: None,
            restore: false,
            bench: false,
            reference: None,
            compare: None,
            convergence_plot: false,
            display_mode: DisplayMode::Image,
            probe: None,
            probe_sample: crate::analysis::path_view::PathSample::default(),
            lesson: None,
            step: 0,
            lang: crate::lesson::Lang::default(),
            present: false,
        }
    }
}

/// What persists between runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Persisted {
    pub settings: RenderSettings,
    pub display: DisplaySettings,
    pub stop_at_spp: Option<u32>,
    /// Also write one EXR per term with each screenshot.
    pub per_term_exr: bool,
    /// Folder where screenshots go.
    pub export_dir: String,
    /// The image or a noise view (mode, whose samples, scale).
    pub noise: NoiseView,
    /// The size of the interface (egui's zoom factor), for a projector.
    pub ui_scale: f32,
    /// Set the exposure from each new image: its mean luminance shown as
    /// mid-grey (a dim term such as L2 alone becomes visible).
    pub auto_exposure: bool,
    /// The size of the pictures "Save as shown" writes, in pixels.
    pub shown_size: (u32, u32),
}

impl Default for Persisted {
    fn default() -> Self {
        Self {
            settings: RenderSettings::default(),
            display: DisplaySettings::default(),
            stop_at_spp: None,
            per_term_exr: false,
            export_dir: ".".into(),
            noise: NoiseView::default(),
            ui_scale: 1.0,
            auto_exposure: false,
            shown_size: crate::tools::slides::shown::DEFAULT_SIZE,
        }
    }
}

const STORAGE_KEY: &str = "lumiere";

impl Persisted {
    /// The settings a run starts with: the command line's, or, when asked
    /// and valid, those the previous run saved in `storage`.
    fn at_start(options: &ViewOptions, storage: Option<&dyn eframe::Storage>) -> Self {
        let mut state = Persisted {
            settings: options.settings.clone(),
            display: options.display,
            noise: NoiseView {
                mode: options.display_mode,
                ..NoiseView::default()
            },
            ..Persisted::default()
        };
        if options.restore
            && let Some(saved) =
                storage.and_then(|s| eframe::get_value::<Persisted>(s, STORAGE_KEY))
            && saved.settings.validate().is_ok()
        {
            state = saved;
        }
        if let Some(size) = options.shown_size {
            state.shown_size = size;
        }
        state
    }
}

/// The viewer application. Its `pub` fields are the state the viewer's
/// tests read and set through the egui harness; the rest is its own.
pub struct LumiereApp {
    pub state: Persisted,
    pub scene_spec: String,
    pub scene: Arc<Scene>,
    pub camera: Camera,
    pub paused: bool,
    renderer: ProgressiveRenderer,
    /// The request last sent to the worker.
    sent: ViewRequest,
    /// Text of the scene path field.
    scene_field: String,
    /// The last problem or event to show in the status bar.
    pub message: Option<String>,
    /// What a scripted run asked for, and the bench.
    script: script::ScriptedRun,
    /// Where the image was drawn last frame (points).
    image_rect: Option<egui::Rect>,
    /// Where the image may be, between a lesson's texts (points): the
    /// probe's windows stay there, off the texts.
    windows_area: Option<egui::Rect>,
    orbit: interact::Orbit,
    /// The object clicked last, if any.
    pub selected: Option<u32>,
    /// A BVH over every triangle of the scene it was built for, to pick objects.
    picking: Option<(Arc<Scene>, crate::geometry::accel::Accel)>,
    /// Save the settings for the next run (only the plain `lumiere` viewer does).
    persist: bool,
    /// The image's zoom and pan.
    zoom: viewport::Zoom,
    exports: Vec<crate::platform::threads::Job<Result<files::Saved, String>>>,
    /// Scene files dropped on the window (read in the background in the browser).
    dropped: files::Dropped,
    /// Ctrl+O on the desktop: the Scene group opens on its file field.
    open_file_requested: bool,
    /// On a page with one thread, when the last render between frames ended.
    rendered_until: Option<crate::platform::time::Instant>,
    /// The converged image errors are measured against (and differences drawn from).
    pub reference: Option<Arc<ReferenceImage>>,
    /// What the reference is valid for, its capture, the errors and curves.
    pub errors: reference::ErrorTracking,
    /// The A/B comparison with a second image.
    pub compare: split::Compare,
    /// The four-up layout's image and tiles.
    pub four_up: four_up_view::FourUpState,
    /// Number of the worker now rendering A (each spawn takes the next).
    renderer_serial: u64,
    spawned: u64,
    noise_view: noise_view::NoiseViewState,
    /// The pixel probe: its pixel, result and job.
    pub probe: probe_view::ProbeState,
    /// The integral at the probed point: the integrand over its hemisphere.
    pub hemisphere: hemisphere_view::HemisphereView,
    /// A click on the image probes the pixel instead of selecting the object.
    pub probe_tool: bool,
    /// The lesson open, if any, and its step.
    pub lesson: lesson_view::LessonState,
    /// The emitting area of each material, for the light panel.
    emitter_areas: interact::EmitterAreas,
    /// The scene library's thumbnails, rendered the first time it is shown.
    pub thumbnails: thumbnails::Thumbnails,
}

/// Forgets the qualities `settings` give sources `scene` does not have
/// (those of a scene shown before).
fn keep_sources_of(settings: &mut crate::course::RenderSettings, scene: &Scene) {
    let names: Vec<&str> = crate::transport::sources::sources(scene)
        .into_iter()
        .map(|key| key.name(scene))
        .collect();
    settings
        .sources
        .retain(|quality| names.contains(&quality.name.as_str()));
}

impl LumiereApp {
    /// Creates the app: loads the scene, installs the GPU blit, starts the worker.
    pub fn new(cc: &eframe::CreationContext<'_>, options: ViewOptions) -> Result<Self, String> {
        let mut state = Persisted::at_start(&options, cc.storage);
        if let Some(render_state) = &cc.wgpu_render_state {
            display::install(render_state);
        }
        install_fonts(&cc.egui_ctx);
        let scene = Arc::new(builtin::load(&options.scene).map_err(|e| e.to_string())?);
        crate::transport::sources::check(&options.settings, &scene)
            .map_err(|e| format!("{}: {e}", options.scene))?;
        keep_sources_of(&mut state.settings, &scene);
        let camera = scene.default_camera();
        let script = script::ScriptedRun::new(&options);
        let request = ViewRequest {
            scene: Arc::clone(&scene).into(),
            settings: state.settings.clone(),
            camera: camera.clone(),
            paused: false,
            stop_at_spp: script.exit_after_spp.or(state.stop_at_spp),
            // the first frame asks for them if the four-up is shown
            term_images: false,
            film: 0,
        };
        waker::install(&cc.egui_ctx);
        let waker = waker::Waker::new(&cc.egui_ctx);
        let renderer = ProgressiveRenderer::spawn(request.clone(), move || waker.wake());
        let mut app = Self {
            message: scene.warnings.first().map(|w| format!("warning: {w}")),
            state,
            scene_field: options.scene.clone(),
            scene_spec: options.scene.clone(),
            scene,
            camera,
            paused: false,
            renderer,
            sent: request,
            script,
            image_rect: None,
            windows_area: None,
            orbit: interact::Orbit::default(),
            selected: None,
            picking: None,
            persist: options.restore,
            zoom: viewport::Zoom::default(),
            exports: Vec::new(),
            dropped: files::Dropped::default(),
            open_file_requested: false,
            rendered_until: None,
            reference: None,
            errors: reference::ErrorTracking::default(),
            compare: split::Compare::default(),
            four_up: four_up_view::FourUpState::default(),
            renderer_serial: 1,
            spawned: 1,
            noise_view: noise_view::NoiseViewState::default(),
            probe: probe_view::ProbeState::default(),
            hemisphere: hemisphere_view::HemisphereView::default(),
            probe_tool: false,
            lesson: lesson_view::LessonState::default(),
            emitter_areas: interact::EmitterAreas::default(),
            thumbnails: thumbnails::Thumbnails::default(),
        };
        app.open_as_asked(options)?;
        Ok(app)
    }

    /// What the command line asks the viewer to show first: a probed pixel,
    /// a lesson step, the convergence plot, B, a reference.
    fn open_as_asked(&mut self, options: ViewOptions) -> Result<(), String> {
        self.probe.path.sample = options.probe_sample;
        if let Some((x, y)) = options.probe {
            self.probe.pick(x, y);
        }
        self.lesson.lang = options.lang;
        self.lesson.presenting = options.present;
        if let Some(lesson) = options.lesson {
            lesson_view::open(self, lesson, options.step);
        }
        self.errors.show_plot = options.convergence_plot;
        if let Some(b) = options.compare {
            // B and the one-thread A start with the first frame (split::sync)
            self.compare.enabled = true;
            self.compare.b = b;
        }
        if let Some(path) = &options.reference {
            reference::load_reference_exr(self, &path.to_string_lossy())?;
        }
        Ok(())
    }

    /// A number for the next worker spawned, to tell their snapshots apart.
    fn next_renderer_serial(&mut self) -> u64 {
        self.spawned += 1;
        self.spawned
    }

    /// Replaces A's worker by a new one on the current request (an empty film),
    /// on `threads` threads of its own or on all cores.
    fn respawn_renderer(&mut self, ctx: &egui::Context, threads: Option<usize>) {
        let request = self.view_request();
        let repaint = waker::Waker::new(ctx);
        self.renderer =
            ProgressiveRenderer::spawn_with_threads(request.clone(), threads, move || {
                repaint.wake()
            });
        self.sent = request;
        self.renderer_serial = self.next_renderer_serial();
    }

    /// What the worker should render, from the current controls.
    pub fn view_request(&self) -> ViewRequest {
        ViewRequest {
            scene: Arc::clone(&self.scene).into(),
            settings: self.state.settings.clone(),
            camera: self.camera.clone(),
            // a reference capture gets the cores to itself
            paused: self.paused || self.errors.capturing(),
            stop_at_spp: self.script.exit_after_spp.or(self.state.stop_at_spp),
            term_images: four_up_view::active(self),
            film: self.lesson.opened,
        }
    }

    /// Sends the current request if a control changed it.
    fn sync_renderer(&mut self) {
        let request = self.view_request();
        if request != self.sent {
            self.renderer.request(request.clone());
            self.sent = request;
        }
    }

    /// Where the image was drawn last frame, in points.
    pub fn image_rect(&self) -> Option<egui::Rect> {
        self.image_rect
    }

    /// Where the probe's windows may be: the image's area, off a lesson's
    /// texts (points).
    pub fn windows_area(&self) -> Option<egui::Rect> {
        self.windows_area
    }

    /// The latest image the worker published.
    pub fn snapshot(&self) -> Arc<Snapshot> {
        self.renderer.snapshot()
    }

    /// The noise view shown, if any: the mode is not the image and its
    /// false colour is ready (it can be one snapshot old).
    pub fn noise_image(&self) -> Option<Arc<crate::analysis::noise::FalseColour>> {
        self.noise_view
            .image(self.state.noise)
            .map(|(_, image)| image)
    }

    /// Recomputes the noise view and the probe when the snapshot or the view changed.
    fn update_views(&mut self, ctx: &egui::Context, snapshot: &Snapshot) {
        if self.reference.is_none() && self.state.noise.mode == DisplayMode::Difference {
            self.state.noise.mode = DisplayMode::Image;
        }
        self.noise_view.update(
            ctx,
            self.state.noise,
            self.sent.settings.terms,
            snapshot.generation,
            self.renderer.film(),
            self.reference.as_ref(),
        );
        self.probe.update(
            ctx,
            &self.sent,
            snapshot.generation,
            self.renderer.film(),
            snapshot.continuations.clone(),
        );
        self.hemisphere
            .update(ctx, &self.sent, self.probe.pixel, &snapshot.continuations);
    }

    /// Replaces the scene by the one at `spec`; on failure keeps the current one.
    pub fn load_scene(&mut self, spec: &str) {
        match builtin::load(spec) {
            Ok(scene) => self.show_scene(spec, scene),
            Err(e) => self.message = Some(format!("error: {e}")),
        }
    }

    /// Shows `scene`, loaded from `spec`, through its own camera.
    pub fn show_scene(&mut self, spec: &str, scene: Scene) {
        self.message = Some(match scene.warnings.first() {
            Some(w) => format!("loaded {spec} (warning: {w})"),
            None => format!("loaded {spec}"),
        });
        self.camera = scene.default_camera();
        self.orbit = interact::Orbit::default();
        self.selected = None;
        keep_sources_of(&mut self.state.settings, &scene);
        self.scene = Arc::new(scene);
        self.scene_spec = spec.to_string();
        self.scene_field = spec.to_string();
    }

    /// What the viewer changed in the scene since it was loaded (nothing if
    /// its file can no longer be read).
    pub fn scene_edits(&self) -> crate::scene::edits::SceneEdits {
        builtin::load(&self.scene_spec)
            .map(|original| crate::scene::edits::SceneEdits::between(&original, &self.scene))
            .unwrap_or_default()
    }

    /// Every setting back to its default (the film's size too), the scene
    /// reloaded from its file without its per-object and per-light edits,
    /// the camera back to the scene's, the lesson closed.
    pub fn reset_to_defaults(&mut self) {
        self.state = Persisted::default();
        self.lesson = lesson_view::LessonState::default();
        let spec = self.scene_spec.clone();
        self.load_scene(&spec);
        self.message = Some("every setting is back to its default".into());
    }

    /// Saves the image as displayed (PNG), its radiance (EXR), optionally one
    /// EXR per term, and the JSON sidecar, on a background thread.
    pub fn save_screenshot(&mut self) {
        let snapshot = self.snapshot();
        if snapshot.radiance.is_empty() {
            self.message = Some("nothing to save yet".into());
            return;
        }
        let job = export::ScreenshotJob {
            folder: PathBuf::from(&self.state.export_dir),
            snapshot,
            shown: match self.compare.composite() {
                Some(composite) => export::Shown::Split(Arc::clone(&composite.image)),
                None if four_up_view::active(self) => export::Shown::FourUp,
                None => export::Shown::Image,
            },
            film: self.renderer.film(),
            per_term_exr: self.state.per_term_exr,
            sidecar: self.sidecar(),
        };
        self.exports.push(crate::platform::threads::spawn(
            "lumiere export",
            move || job.run(),
        ));
        self.message = Some("saving…".into());
    }

    /// Saves the picture as the viewport shows it at the Render group's size
    /// (`state.shown_size`), laid out as a slide with a lesson's texts, as
    /// one PNG with the JSON sidecar, on a background thread; the status
    /// bar says where, or why not (a size out of range).
    pub fn save_as_shown(&mut self) {
        shown::save_as_shown(self);
    }

    /// The JSON sidecar of the image (its sample count set when written).
    fn sidecar(&self) -> crate::render::sidecar::Sidecar {
        crate::render::sidecar::Sidecar {
            scene: self.scene_spec.clone(),
            camera: self.camera.clone(),
            settings: self.state.settings.clone(),
            display: self.state.display,
            samples_per_pixel: 0,
            edits: self.scene_edits(),
            split: self.compare.enabled.then(|| self.compare.b.clone()),
        }
    }

    /// On a page with one thread, the renderers' work for this frame, and
    /// another frame while work remains; elsewhere their threads render
    /// and this does nothing. The render takes three quarters of the time:
    /// three times what the page spent since the last render (drawing,
    /// waiting for the screen), from 25 to 200 ms.
    fn render_between_frames(&mut self, ctx: &egui::Context) {
        use std::time::Duration;
        let started = crate::platform::time::Instant::now();
        let outside = self
            .rendered_until
            .map_or(Duration::ZERO, |end| started - end);
        let budget = (3 * outside).clamp(Duration::from_millis(25), Duration::from_millis(200));
        let mut more = self.renderer.run_between_frames(budget);
        if let Some(b) = &self.compare.renderer {
            more |= b.run_between_frames(budget);
        }
        self.rendered_until = more.then(crate::platform::time::Instant::now);
        if more {
            ctx.request_repaint();
        }
    }
}

impl eframe::App for LumiereApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let started = crate::platform::time::Instant::now();
        if let Some(bench) = &mut self.script.bench {
            bench.frame_started(started);
        }
        let ctx = ui.ctx().clone();
        files::open_dropped(self, &ctx);
        files::collect_exports(self);
        panels::shortcuts(self, &ctx);
        lesson_view::shortcuts(self, &ctx);
        let snapshot = self.snapshot();
        #[cfg(target_arch = "wasm32")]
        web::report_first_image(&snapshot);
        if self.state.auto_exposure
            && let Some(exposure) = auto_exposure(&snapshot)
        {
            self.state.display.exposure = exposure;
        }
        reference::poll_capture(self);
        let serial = self.renderer_serial;
        reference::measure(self, reference::Side::A, serial, &snapshot);
        if let Some(b) = self.compare.snapshot() {
            let serial = self.compare.serial;
            reference::measure(self, reference::Side::B, serial, &b);
        }
        let scale = self.state.ui_scale.clamp(0.5, 4.0);
        if ctx.zoom_factor() != scale {
            ctx.set_zoom_factor(scale);
        }
        panels::status_bar(self, ui, &snapshot);
        if !self.lesson.presenting {
            panels::side_panel(self, ui);
        }
        self.update_views(&ctx, &snapshot);
        let shown = split::shown_snapshot(self, &snapshot);
        let image_rect = viewport::viewport(self, ui, &shown);
        self.image_rect = Some(image_rect);
        convergence::plot_window(self, &ctx);
        let windows_area = self.windows_area.unwrap_or(ctx.content_rect());
        if let Some(picked) = probe_view::probe_window(
            &ctx,
            &mut self.probe,
            &mut self.hemisphere.shown,
            windows_area,
        ) {
            self.hemisphere
                .open_at_q(&self.probe, &self.sent.camera, picked);
        }
        hemisphere_view::hemisphere_window(
            &ctx,
            &mut self.hemisphere,
            self.probe.pixel,
            &self.sent,
            windows_area,
        );
        script::bench_step(self, &ctx, &snapshot, started);
        self.sync_renderer();
        split::sync(self, &ctx);
        self.render_between_frames(&ctx);
        script::exit_when_done(self, &ctx, &snapshot);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        // scripted and command-line runs must not overwrite the user's settings
        if self.persist {
            eframe::set_value(storage, STORAGE_KEY, &self.state);
        }
    }
}

/// The exposure (EV) that shows `snapshot`'s mean luminance Ȳ as mid-grey:
/// log₂(0.18 / Ȳ), to a tenth of a stop (so that noise does not make it
/// flicker), within the slider's ±10; none for a black image.
fn auto_exposure(snapshot: &Snapshot) -> Option<f32> {
    if snapshot.radiance.is_empty() {
        return None;
    }
    let mean = snapshot
        .radiance
        .iter()
        .map(|p| crate::course::color::luminance(glam::Vec3::new(p[0], p[1], p[2])) as f64)
        .sum::<f64>()
        / snapshot.radiance.len() as f64;
    (mean > 0.0)
        .then(|| ((0.18 / mean).log2() as f32 * 10.0).round() / 10.0)
        .map(|ev| ev.clamp(-10.0, 10.0))
}

/// egui's fonts, then DejaVu Sans for what they lack: the lessons' formulas
/// need subscripts (L₀, Lₑ), arrows and more of Unicode's mathematics.
fn install_fonts(ctx: &egui::Context) {
    const NAME: &str = "DejaVu Sans";
    let mut fonts = egui::FontDefinitions::default();
    fonts.font_data.insert(
        NAME.into(),
        Arc::new(egui::FontData::from_static(include_bytes!(
            "../../assets/fonts/DejaVuSans.ttf"
        ))),
    );
    for family in [egui::FontFamily::Proportional, egui::FontFamily::Monospace] {
        fonts.families.entry(family).or_default().push(NAME.into());
    }
    ctx.set_fonts(fonts);
}

/// Opens the viewer window and runs until it is closed.
#[cfg(not(target_arch = "wasm32"))]
pub fn run(options: ViewOptions) -> Result<(), String> {
    let native_options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("lumiere")
            .with_inner_size([1280.0, 800.0])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        persist_window: options.restore,
        ..Default::default()
    };
    let failure: Arc<Mutex<Option<String>>> = Arc::default();
    let failure_in_app = Arc::clone(&failure);
    let result = eframe::run_native(
        "lumiere",
        native_options,
        Box::new(move |cc| match LumiereApp::new(cc, options) {
            Ok(mut app) => {
                app.script.failure = Arc::clone(&failure_in_app);
                Ok(Box::new(app))
            }
            Err(e) => {
                *failure_in_app.lock().unwrap_or_else(|p| p.into_inner()) = Some(e.clone());
                Err(e.into())
            }
        }),
    );
    if let Some(problem) = failure.lock().unwrap_or_else(|p| p.into_inner()).take() {
        return Err(problem);
    }
    result.map_err(|e| format!("cannot open the window: {e} (is there a display? DISPLAY or WAYLAND_DISPLAY must be set)"))
}
