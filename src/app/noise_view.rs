//! Noise views on screen: the false-colour image, computed off the UI thread
//! whenever a new snapshot arrives or the view changes, and its legend.
//!
//! The values and colours come from `crate::analysis::noise`; this module only decides
//! when to compute them (one job at a time, always for the latest snapshot)
//! and draws the colour bar with its ticks, unit and mode.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use eframe::egui;

use crate::analysis::metrics::ReferenceImage;
use crate::analysis::noise::{
    self, DisplayMode, FalseColour, NO_VALUE_SRGB, NoiseSource, NoiseView, Scale, format_tick,
};
use crate::course::TermSet;
use crate::platform::threads::{self, Job};
use crate::platform::time::Instant;
use crate::render::film::Film;

/// Height of the legend strip under the image, in points.
pub const LEGEND_HEIGHT: f32 = 46.0;

/// What a false-colour image was computed from.
#[derive(Clone, Debug, PartialEq)]
struct Inputs {
    view: NoiseView,
    visible: TermSet,
    generation: u64,
    /// Identity of the reference (its allocation), for the difference.
    reference: Option<usize>,
}

type Outcome = Result<(FalseColour, Duration), String>;

/// The false-colour image on screen and the job computing the next one.
#[derive(Default)]
pub struct NoiseViewState {
    shown: Option<(Inputs, u64, Arc<FalseColour>)>,
    job: Option<(Inputs, Job<Outcome>)>,
    serial: u64,
    /// Why the view cannot be shown (e.g. the reference's size differs).
    pub problem: Option<String>,
    /// Time the last image took to compute (lock, values, percentiles, colours).
    pub last_duration: Option<Duration>,
}

impl NoiseViewState {
    /// Collects a finished job and starts one for `view` of the latest
    /// snapshot (`generation`) when the image shown is out of date.
    pub fn update(
        &mut self,
        ctx: &egui::Context,
        view: NoiseView,
        visible: TermSet,
        generation: u64,
        film: Option<Arc<Mutex<Film>>>,
        reference: Option<&Arc<ReferenceImage>>,
    ) {
        if self
            .job
            .as_ref()
            .is_some_and(|(_, handle)| handle.is_finished())
            && let Some((inputs, handle)) = self.job.take()
        {
            match handle.join() {
                Some(Ok((image, duration))) => {
                    self.serial += 1;
                    self.shown = Some((inputs, self.serial, Arc::new(image)));
                    self.last_duration = Some(duration);
                    self.problem = None;
                }
                Some(Err(problem)) => {
                    self.shown = None;
                    self.problem = Some(problem);
                }
                None => self.problem = Some("the noise view failed".into()),
            }
        }
        if view.mode == DisplayMode::Image {
            self.shown = None;
            self.problem = None;
            return;
        }
        let inputs = Inputs {
            view,
            visible,
            generation,
            reference: reference.map(|r| Arc::as_ptr(r) as usize),
        };
        let up_to_date = self.shown.as_ref().is_some_and(|(i, ..)| *i == inputs);
        if up_to_date || self.job.is_some() {
            return;
        }
        let Some(film) = film else {
            return;
        };
        let reference = reference.cloned();
        let repaint = super::waker::Waker::new(ctx);
        let job = threads::spawn("lumiere noise view", move || {
            let started = Instant::now();
            // the lock is held for the values only: the worker waits little
            let values = {
                let film = film.lock().unwrap_or_else(|p| p.into_inner());
                noise::noise_values(&film, visible, view, reference.as_deref())
                    .map(|values| (film.width, film.height, values))
            };
            let outcome = values
                .map(|(width, height, values)| {
                    let image = noise::colour_values(width, height, view, values);
                    (image, started.elapsed())
                })
                .map_err(|e| e.to_string());
            repaint.wake();
            outcome
        });
        self.job = Some((inputs, job));
    }

    /// The false-colour image of `view`, if one is ready (perhaps one snapshot old).
    pub fn image(&self, view: NoiseView) -> Option<(u64, Arc<FalseColour>)> {
        self.shown
            .as_ref()
            .filter(|(inputs, ..)| inputs.view == view)
            .map(|(_, serial, image)| (*serial, Arc::clone(image)))
    }

    /// Whether the image shown is the one of `view` at `generation` (for scripted screenshots).
    pub fn is_current(&self, view: NoiseView, generation: u64) -> bool {
        view.mode == DisplayMode::Image
            || self.problem.is_some()
            || self
                .shown
                .as_ref()
                .is_some_and(|(i, ..)| i.view == view && i.generation == generation)
    }
}

/// The modes offered: the difference only with a reference image.
pub fn available_modes(has_reference: bool) -> impl Iterator<Item = DisplayMode> {
    DisplayMode::ALL
        .into_iter()
        .filter(move |&m| has_reference || m != DisplayMode::Difference)
}

/// Whether the mode describes one term or the visible sum (the others: the image).
pub fn has_source(mode: DisplayMode) -> bool {
    matches!(
        mode,
        DisplayMode::StandardError | DisplayMode::RelativeError | DisplayMode::SampleCount
    )
}

/// The legend's title: mode, whose samples, unit.
pub fn legend_title(
    image: &FalseColour,
    visible: TermSet,
    reference: Option<&ReferenceImage>,
) -> String {
    let view = image.view;
    let of = match (view.mode, view.source) {
        (DisplayMode::Difference, _) => format!(
            "image − reference ({})",
            reference.map_or("?", |r| r.label.as_str())
        ),
        (_, NoiseSource::Visible) => format!("of {}", visible.to_string().replace(',', "+")),
        (_, NoiseSource::Term(t)) => format!("of {}", t.label()),
    };
    let scale = if image.scale == Scale::Log {
        ", log scale"
    } else {
        ""
    };
    format!("{} {of}\n{}{scale}", view.mode.title(), image.unit.symbol())
}

fn colour32([r, g, b]: [f32; 3]) -> egui::Color32 {
    let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
    egui::Color32::from_rgb(byte(r), byte(g), byte(b))
}

/// Draws the legend of `image` in `rect`: title, colour bar, ticks, and the
/// colour of pixels without a value.
pub fn legend_ui(
    ui: &mut egui::Ui,
    rect: egui::Rect,
    image: &FalseColour,
    visible: TermSet,
    reference: Option<&ReferenceImage>,
) {
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, egui::Color32::from_gray(16));
    let title_rect = egui::Rect::from_min_size(
        rect.min + egui::vec2(10.0, 5.0),
        egui::vec2(250.0, rect.height() - 8.0),
    );
    ui.scope_builder(egui::UiBuilder::new().max_rect(title_rect), |ui| {
        ui.add(egui::Label::new(legend_title(image, visible, reference)).extend());
    });
    let bar_left = title_rect.right() + 12.0;
    let bar_right = (rect.right() - 110.0).min(bar_left + 480.0);
    if bar_right <= bar_left + 40.0 {
        return;
    }
    let bar = egui::Rect::from_min_max(
        egui::pos2(bar_left, rect.top() + 8.0),
        egui::pos2(bar_right, rect.top() + 22.0),
    );
    // the bar: one quad per step, in the map's own sRGB colours
    let steps = 128;
    let mut mesh = egui::Mesh::default();
    for k in 0..steps {
        let (t0, t1) = (k as f32 / steps as f32, (k + 1) as f32 / steps as f32);
        let colour = colour32(image.map.srgb((t0 + t1) / 2.0));
        let (x0, x1) = (bar.left() + t0 * bar.width(), bar.left() + t1 * bar.width());
        mesh.add_colored_rect(egui::Rect::from_x_y_ranges(x0..=x1, bar.y_range()), colour);
    }
    painter.add(mesh);
    let text = ui.visuals().text_color();
    let font = egui::FontId::proportional(11.0);
    let ticks = 5;
    for k in 0..ticks {
        let t = k as f32 / (ticks - 1) as f32;
        let x = bar.left() + t * bar.width();
        painter.line_segment(
            [
                egui::pos2(x, bar.bottom()),
                egui::pos2(x, bar.bottom() + 4.0),
            ],
            egui::Stroke::new(1.0, text),
        );
        let align = match k {
            0 => egui::Align2::LEFT_TOP,
            k if k == ticks - 1 => egui::Align2::RIGHT_TOP,
            _ => egui::Align2::CENTER_TOP,
        };
        painter.text(
            egui::pos2(x, bar.bottom() + 5.0),
            align,
            format_tick(image.value_at(t), image.unit),
            font.clone(),
            text,
        );
    }
    if image.has_missing_values() {
        let swatch = egui::Rect::from_min_size(
            egui::pos2(bar.right() + 14.0, bar.top()),
            egui::vec2(14.0, bar.height()),
        );
        painter.rect_filled(swatch, 0.0, colour32(NO_VALUE_SRGB));
        painter.text(
            egui::pos2(swatch.right() + 4.0, swatch.center().y),
            egui::Align2::LEFT_CENTER,
            "mean 0",
            font,
            text,
        );
    }
}
