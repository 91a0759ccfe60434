//! A/B comparison: A (the viewer's settings) and B (A's settings with the
//! changes of a [`SettingsOverride`]: another light mode, material, set of
//! terms, integrator, light sampling, indirect sampling, sampler or sample
//! counts) render the same scene from the same camera at once, each on its
//! own pool of half the cores, so that after t seconds both have had the
//! same CPU time: of two estimators of one image, the better one shows less
//! noise. B uses the next seed, so the two noises are independent.
//!
//! The image shows A left and B right of a draggable divider, each half
//! labelled with what differs between them ("point lights" | "extended
//! lights"): the two snapshots are composed into one before the display
//! uploads it.

use std::sync::Arc;

use eframe::egui;

use super::LumiereApp;
use crate::course::{LightSampling, RenderSettings, TermSet};
use crate::render::progressive::{ProgressiveRenderer, Snapshot, ViewRequest};
use crate::render::settings_override::{SettingsOverride, side_labels};

/// Composed images count their generations from here, away from the workers'.
const COMPOSITE_GENERATION: u64 = 1 << 62;

/// The second image, B, and its renderer.
pub struct Compare {
    pub enabled: bool,
    /// What B changes from A's settings.
    pub b: SettingsOverride,
    pub renderer: Option<ProgressiveRenderer>,
    /// Worker number of B's renderer (see `LumiereApp::renderer_serial`).
    pub serial: u64,
    sent: Option<ViewRequest>,
    /// A's and B's settings, terms aside, when both were started.
    started_with: Option<(RenderSettings, RenderSettings)>,
    /// Where A ends, as a fraction of the image width.
    pub divider: f32,
    composite: Option<Composite>,
    composed: u64,
}

impl Default for Compare {
    fn default() -> Self {
        Self {
            enabled: false,
            b: default_b(),
            renderer: None,
            serial: 0,
            sent: None,
            started_with: None,
            divider: 0.5,
            composite: None,
            composed: 0,
        }
    }
}

/// What B changes when Compare is ticked with nothing chosen: the light
/// sampling, area instead of MIS.
pub fn default_b() -> SettingsOverride {
    SettingsOverride {
        light_sampling: Some(LightSampling::Area),
        ..SettingsOverride::default()
    }
}

/// An image made of A's columns left of `divider_column` and B's from it on.
#[derive(Clone, Debug)]
pub struct Composite {
    pub image: Arc<Snapshot>,
    pub a: Arc<Snapshot>,
    pub b: Arc<Snapshot>,
    pub divider_column: u32,
    /// The workers that made `a` and `b`.
    serials: (u64, u64),
}

impl Compare {
    /// B's latest snapshot, while comparing.
    pub fn snapshot(&self) -> Option<Arc<Snapshot>> {
        self.renderer.as_ref().map(ProgressiveRenderer::snapshot)
    }

    /// The image last composed, while comparing.
    pub fn composite(&self) -> Option<&Composite> {
        self.composite.as_ref().filter(|_| self.enabled)
    }
}

/// Threads per renderer when two share the machine.
fn threads_each() -> usize {
    (crate::platform::threads::available() / 2).max(1)
}

/// B's settings: A's with B's changes, and the next seed.
pub fn b_settings(app: &LumiereApp) -> RenderSettings {
    let mut settings = app.compare.b.apply(&app.state.settings);
    settings.seed = settings.seed.wrapping_add(1);
    settings
}

/// A's and B's settings but their terms: a change of either starts both
/// again together (a term switched on or off restarts neither).
fn started_key(app: &LumiereApp) -> (RenderSettings, RenderSettings) {
    let without_terms = |settings: RenderSettings| RenderSettings {
        terms: TermSet::NONE,
        ..settings
    };
    (
        without_terms(app.state.settings.clone()),
        without_terms(b_settings(app)),
    )
}

/// B's request: A's, with B's settings, no stop of its own but a pause once
/// it has had as much time as a stopped A.
fn request_b(app: &LumiereApp) -> ViewRequest {
    let mut request = app.view_request();
    request.settings = b_settings(app);
    request.stop_at_spp = None;
    request.term_images = false;
    if let Some(b) = app.compare.snapshot() {
        let a = app.snapshot();
        let caught_up = a.idle && !a.preview && b.elapsed >= a.elapsed;
        request.paused |= caught_up;
    }
    request
}

/// Starts A (and B when comparing) again from an empty film, at the same moment.
pub fn restart(app: &mut LumiereApp, ctx: &egui::Context) {
    let compare = app.compare.enabled;
    app.respawn_renderer(ctx, compare.then(threads_each));
    app.compare.renderer = None;
    app.compare.composite = None;
    app.compare.started_with = None;
    if compare {
        let request = request_b(app);
        let repaint = super::waker::Waker::new(ctx);
        app.compare.renderer = Some(ProgressiveRenderer::spawn_with_threads(
            request.clone(),
            Some(threads_each()),
            move || repaint.wake(),
        ));
        app.compare.serial = app.next_renderer_serial();
        app.compare.sent = Some(request);
        app.compare.started_with = Some(started_key(app));
    }
}

/// Starts, stops or updates B after the controls changed (call after A's sync).
pub fn sync(app: &mut LumiereApp, ctx: &egui::Context) {
    let compare = &app.compare;
    if !compare.enabled {
        if compare.renderer.is_some() {
            app.compare.renderer = None;
            app.compare.composite = None;
            app.compare.started_with = None;
            app.respawn_renderer(ctx, None);
        }
        return;
    }
    if compare.renderer.is_none() || compare.started_with.as_ref() != Some(&started_key(app)) {
        // a new pair of settings: both start together, so their times stay equal
        restart(app, ctx);
        return;
    }
    let request = request_b(app);
    let changed = app
        .compare
        .sent
        .as_ref()
        .is_none_or(|sent| *sent != request);
    if changed && let Some(renderer) = &app.compare.renderer {
        renderer.request(request.clone());
        app.compare.sent = Some(request);
    }
}

/// Whether B has nothing more to do (always, when not comparing).
pub fn settled(app: &LumiereApp) -> bool {
    app.compare.snapshot().is_none_or(|b| b.idle && !b.preview)
}

/// A's columns `0..divider_column` and B's from there, at `width`×`height`
/// (each snapshot scaled to it by nearest neighbour: previews are smaller).
pub fn compose(
    a: &Snapshot,
    b: &Snapshot,
    width: u32,
    height: u32,
    divider_column: u32,
) -> Vec<[f32; 4]> {
    let mut image = Vec::with_capacity(width as usize * height as usize);
    for y in 0..height {
        for x in 0..width {
            let side = if x < divider_column { a } else { b };
            let sx = (x as u64 * side.width as u64 / width as u64) as usize;
            let sy = (y as u64 * side.height as u64 / height as u64) as usize;
            image.push(side.radiance[sy * side.width as usize + sx]);
        }
    }
    image
}

/// What the viewport shows: A's snapshot, or A|B composed while comparing.
pub fn shown_snapshot(app: &mut LumiereApp, a: &Arc<Snapshot>) -> Arc<Snapshot> {
    let Some(b) = app.compare.snapshot().filter(|_| app.compare.enabled) else {
        return Arc::clone(a);
    };
    if b.radiance.is_empty() || a.radiance.is_empty() {
        return Arc::clone(if a.radiance.is_empty() { &b } else { a });
    }
    let (width, height) = (app.state.settings.width, app.state.settings.height);
    let divider_column = (app.compare.divider * width as f32).round() as u32;
    let serials = (app.renderer_serial, app.compare.serial);
    let compare = &mut app.compare;
    if let Some(composite) = &compare.composite
        && composite.serials == serials
        && composite.a.generation == a.generation
        && composite.b.generation == b.generation
        && composite.divider_column == divider_column
        && (composite.image.width, composite.image.height) == (width, height)
    {
        return Arc::clone(&composite.image);
    }
    compare.composed += 1;
    let image = Arc::new(Snapshot {
        generation: COMPOSITE_GENERATION + compare.composed,
        restarts: a.restarts,
        width,
        height,
        preview: a.preview || b.preview,
        radiance: compose(a, &b, width, height, divider_column),
        terms: a.terms,
        term_images: Default::default(),
        term_samples: a.term_samples,
        elapsed: a.elapsed,
        rays: a.rays,
        pixel_samples: a.pixel_samples,
        continuations: a.continuations.clone(),
        idle: a.idle && b.idle,
        source: a.source.clone(),
    });
    compare.composite = Some(Composite {
        image: Arc::clone(&image),
        a: Arc::clone(a),
        b,
        divider_column,
        serials,
    });
    image
}

/// Each half's label: the values of the settings that differ, its samples
/// per pixel and its time ("A: point lights · 64 spp · 1.2 s").
pub fn labels(composite: &Composite) -> [String; 2] {
    let settings = |snapshot: &Snapshot| snapshot.source.as_ref().map(|s| s.settings.clone());
    let (a_label, b_label) = match (settings(&composite.a), settings(&composite.b)) {
        (Some(a), Some(b)) => side_labels(&a, &b),
        _ => Default::default(),
    };
    let text = |side: &str, label: &str, snapshot: &Snapshot| {
        format!(
            "{side}: {label} · {} spp · {:.1} s",
            snapshot.samples_per_pixel(),
            snapshot.elapsed.as_secs_f64()
        )
    };
    [
        text("A", &a_label, &composite.a),
        text("B", &b_label, &composite.b),
    ]
}

/// Over the image: the divider (drag it) and each half's label.
pub fn overlay_ui(app: &mut LumiereApp, ui: &mut egui::Ui, rect: egui::Rect) {
    let Some(composite) = app.compare.composite().cloned() else {
        return;
    };
    let x = rect.min.x + app.compare.divider * rect.width();
    let handle = egui::Rect::from_x_y_ranges(x - 5.0..=x + 5.0, rect.y_range());
    let response = ui
        .interact(
            handle,
            egui::Id::unique("lumiere compare divider"),
            egui::Sense::drag(),
        )
        .on_hover_cursor(egui::CursorIcon::ResizeHorizontal);
    if response.dragged()
        && let Some(pointer) = response.interact_pointer_pos()
    {
        app.compare.divider = ((pointer.x - rect.min.x) / rect.width()).clamp(0.0, 1.0);
    }
    ui.painter().vline(
        x,
        rect.y_range(),
        egui::Stroke::new(2.0, egui::Color32::from_white_alpha(200)),
    );
    let [a_text, b_text] = labels(&composite);
    let inset = rect.shrink(6.0);
    let halves = [
        (
            egui::Rect::from_min_max(inset.min, egui::pos2(x - 6.0, inset.max.y)),
            egui::Layout::left_to_right(egui::Align::Min),
            a_text,
        ),
        (
            egui::Rect::from_min_max(egui::pos2(x + 6.0, inset.min.y), inset.max),
            egui::Layout::right_to_left(egui::Align::Min),
            b_text,
        ),
    ];
    // readable from the back of a room: in proportion to the image
    let size = (rect.height() / 36.0).clamp(12.0, 22.0);
    for (area, layout, text) in halves {
        if area.width() < 20.0 {
            continue;
        }
        ui.scope_builder(egui::UiBuilder::new().max_rect(area).layout(layout), |ui| {
            egui::Frame::new()
                .fill(egui::Color32::from_black_alpha(170))
                .inner_margin(4.0)
                .corner_radius(3.0)
                .show(ui, |ui| {
                    ui.add(
                        egui::Label::new(
                            egui::RichText::new(text)
                                .size(size)
                                .color(egui::Color32::WHITE),
                        )
                        .truncate(),
                    );
                });
        });
    }
}

/// The "Comparison" group of the side panel: the toggle and what B changes.
pub fn compare_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Comparison")
        .default_open(app.compare.enabled)
        .show(ui, |ui| {
            let was = app.compare.enabled;
            ui.checkbox(&mut app.compare.enabled, "Compare")
                .on_hover_text(
                    "Render B, the image with some settings changed, beside A for the same time: A left, B right of the divider",
                );
            if app.compare.enabled && !was && app.compare.b.is_empty() {
                app.compare.b = default_b();
            }
            if !app.compare.enabled {
                return;
            }
            let a = app.state.settings.clone();
            super::override_ui::override_ui(ui, &mut app.compare.b, &a);
            ui.label(
                egui::RichText::new(format!(
                    "A and B: {} thread(s) each; B uses the next seed",
                    threads_each()
                ))
                .weak()
                .small(),
            );
        });
}
