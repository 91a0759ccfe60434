//! The pixel probe on screen: a click picks a pixel, a thread traces its
//! samples again (`crate::analysis::probe`), a window shows each visible term's
//! statistics and the histogram of its sample luminance, and a marker shows
//! the pixel on the image.
//!
//! The path view draws over the image the rays of one of the pixel's samples
//! (`crate::analysis::path_view`): it is traced again on the UI thread (one sample: a
//! few microseconds) with the probe's render context.
//!
//! The probe keeps its own render context (lights and BVH built for the
//! scene being rendered), rebuilt only when the scene or the light mode
//! changes. It refreshes itself as the film gains samples, at most every
//! [`REFRESH_INTERVAL`].

use std::sync::{Arc, Mutex};
use std::time::Duration;

use eframe::egui;
use egui_plot::{Bar, BarChart, Plot, VLine};

use crate::analysis::path_view::{
    self, PathLine, PathSample, RayRole, path_lines, segment_luminance,
};
use crate::analysis::probe::{FilmPixel, MAX_PROBE_SAMPLES, PixelProbe, TermProbe, trace_pixel};
use crate::course::{LightMode, RenderSettings, Term, TermSet};
use crate::geometry::Ray;
use crate::platform::threads::{self, Job};
use crate::platform::time::Instant;
use crate::render::film::Film;
use crate::render::progressive::ViewRequest;
use crate::scene::Scene;
use crate::transport::context::RenderContext;
use crate::transport::continuations::Continuations;
use crate::transport::path_log::{PathLog, SegmentKind};

/// Shortest time between two refreshes of the probe while the film converges.
pub const REFRESH_INTERVAL: Duration = Duration::from_millis(500);

/// The probe window's id (its area's place in egui's memory).
pub const PROBE_WINDOW_ID: &str = "lumiere pixel probe";

/// Bins of the histograms.
const HISTOGRAM_BINS: usize = 40;

/// Where the image is on screen and how film pixels map to it: what an
/// overlay painter needs.
#[derive(Clone, Copy, Debug)]
pub struct ImageMapping {
    /// The image's rectangle, in points.
    pub rect: egui::Rect,
    pub width: u32,
    pub height: u32,
}

impl ImageMapping {
    /// The screen point of film coordinates (`x`, `y`) (pixel centres at +0.5).
    pub fn pixel_to_screen(&self, x: f32, y: f32) -> egui::Pos2 {
        self.rect.min
            + egui::vec2(
                x / self.width as f32 * self.rect.width(),
                y / self.height as f32 * self.rect.height(),
            )
    }

    /// The film pixel under screen point `pos`, if it is on the image.
    pub fn screen_to_pixel(&self, pos: egui::Pos2) -> Option<(u32, u32)> {
        if !self.rect.contains(pos) {
            return None;
        }
        let uv = (pos - self.rect.min) / self.rect.size();
        let x = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        Some((x, y))
    }

    /// The screen rectangle of film pixel (`x`, `y`).
    pub fn pixel_rect(&self, x: u32, y: u32) -> egui::Rect {
        egui::Rect::from_min_max(
            self.pixel_to_screen(x as f32, y as f32),
            self.pixel_to_screen(x as f32 + 1.0, y as f32 + 1.0),
        )
    }
}

/// A render context for probing, and what it was built for.
struct ProbeContext {
    scene: Arc<Scene>,
    light_mode: LightMode,
    light_radius: Option<f32>,
    context: RenderContext,
}

/// A finished probe.
pub struct ProbeResult {
    pub probe: PixelProbe,
    /// Time to read the film and trace the samples again.
    pub duration: Duration,
    /// Samples per pixel of the film when it was read (the fewest among the probed terms).
    pub samples_per_pixel: u32,
    /// The terms rendered.
    pub terms: TermSet,
}

/// The probed pixel, its latest result and the job computing the next.
#[derive(Default)]
pub struct ProbeState {
    /// The pixel picked last; `None`: no probe.
    pub pixel: Option<(u32, u32)>,
    pub result: Option<Arc<ProbeResult>>,
    job: Option<Job<Option<ProbeResult>>>,
    /// Film generation and spp the last job was started for.
    started_for: Option<((u32, u32), u64)>,
    started_at: Option<Instant>,
    cache: Arc<Mutex<Option<ProbeContext>>>,
    /// The path of one sample, drawn over the image.
    pub path: PathView,
}

/// Which sample's path is drawn, and its rays.
#[derive(Default)]
pub struct PathView {
    /// Whether the rays are drawn over the image.
    pub hidden: bool,
    /// The sample shown: a number, or the brightest (followed as the film grows).
    pub sample: PathSample,
    pub recorded: Option<RecordedPath>,
}

/// The rays of one traced sample, for the probe result they belong to.
pub struct RecordedPath {
    result: Arc<ProbeResult>,
    /// Position of the sample among the probe's passes (from 0), and its pass.
    pub position: usize,
    pub pass: u32,
    pub log: PathLog,
    pub lines: Vec<PathLine>,
}

impl PathView {
    /// Whether the recorded path is the one `result` and the choice of sample ask for.
    fn is_current(&self, result: &Arc<ProbeResult>) -> bool {
        self.recorded.as_ref().is_some_and(|r| {
            Arc::ptr_eq(&r.result, result) && Some(r.position) == self.position(&result.probe)
        })
    }

    /// The position among `probe`'s passes of the sample to show.
    fn position(&self, probe: &PixelProbe) -> Option<usize> {
        let count = probe.passes.len();
        match self.sample {
            _ if count == 0 => None,
            PathSample::Number(n) => Some((n.max(1) as usize - 1).min(count - 1)),
            PathSample::Brightest => probe.brightest(),
        }
    }
}

impl ProbeState {
    /// Probes pixel (`x`, `y`) from now on.
    pub fn pick(&mut self, x: u32, y: u32) {
        self.pixel = Some((x, y));
        self.result = None;
        self.started_for = None;
    }

    pub fn close(&mut self) {
        self.pixel = None;
        self.result = None;
        self.started_for = None;
        self.path.recorded = None;
    }

    /// Whether the result shown is for the current pixel at `samples_per_pixel`
    /// and no job runs (for scripted screenshots).
    pub fn is_settled(&self, samples_per_pixel: u32) -> bool {
        self.pixel.is_none()
            || (self.job.is_none()
                && self.result.as_ref().is_some_and(|r| {
                    r.samples_per_pixel == samples_per_pixel
                        && (self.path.hidden || self.path.is_current(r))
                }))
    }

    /// Traces again the sample the path view shows, if it changed. Waits
    /// (returns false) while a probe job holds the render context.
    pub fn refresh_path(&mut self) -> bool {
        let Some(result) = &self.result else {
            self.path.recorded = None;
            return true;
        };
        if self.path.hidden || self.path.is_current(result) {
            return true;
        }
        let Some(position) = self.path.position(&result.probe) else {
            self.path.recorded = None;
            return true;
        };
        let Ok(cache) = self.cache.try_lock() else {
            return false;
        };
        let Some(probe_context) = cache.as_ref() else {
            return true;
        };
        let context = &probe_context.context;
        let pass = result.probe.passes[position];
        let log = result.probe.record_path(context, pass);
        let lines = path_lines(&log, &context.camera, context.settings.terms);
        self.path.recorded = Some(RecordedPath {
            result: Arc::clone(result),
            position,
            pass,
            log,
            lines,
        });
        true
    }

    /// Collects a finished job; starts one when the pixel changed, or the
    /// film (`generation`) did and the last refresh is old enough.
    pub fn update(
        &mut self,
        ctx: &egui::Context,
        request: &ViewRequest,
        generation: u64,
        film: Option<Arc<Mutex<Film>>>,
        continuations: Continuations,
    ) {
        if self.job.as_ref().is_some_and(|j| j.is_finished())
            && let Some(job) = self.job.take()
        {
            let result = job.join().flatten();
            // a result for a pixel picked since is dropped
            if let Some(result) = result.filter(|r| Some((r.probe.x, r.probe.y)) == self.pixel) {
                self.result = Some(Arc::new(result));
            }
        }
        // before a new job takes the render context
        if !self.refresh_path() {
            ctx.request_repaint();
        }
        let Some(pixel) = self.pixel else {
            return;
        };
        if self.job.is_some() || self.started_for == Some((pixel, generation)) {
            return;
        }
        let pixel_changed = self.started_for.is_none_or(|(p, _)| p != pixel);
        let recent = self
            .started_at
            .is_some_and(|t| t.elapsed() < REFRESH_INTERVAL);
        if !pixel_changed && recent {
            // come back when the refresh is due
            ctx.request_repaint_after(REFRESH_INTERVAL);
            return;
        }
        let Some(film) = film else {
            return;
        };
        let request = request.clone();
        let cache = Arc::clone(&self.cache);
        let repaint = super::waker::Waker::new(ctx);
        self.started_for = Some((pixel, generation));
        self.started_at = Some(Instant::now());
        self.job = Some(threads::spawn("lumiere probe", move || {
            let result = run_probe(&request, &film, &cache, pixel, continuations);
            repaint.wake();
            result
        }));
    }
}

/// Reads the pixel from the film and traces its samples again.
fn run_probe(
    request: &ViewRequest,
    film: &Mutex<Film>,
    cache: &Mutex<Option<ProbeContext>>,
    (x, y): (u32, u32),
    continuations: Continuations,
) -> Option<ProbeResult> {
    let started = Instant::now();
    let settings = &request.settings;
    let terms = settings.terms;
    let (pixel, samples_per_pixel) = {
        let film = film.lock().unwrap_or_else(|p| p.into_inner());
        if x >= film.width || y >= film.height {
            return None;
        }
        let spp = terms.iter().map(|t| film.samples(t)).min().unwrap_or(0);
        (FilmPixel::read(&film, x, y, terms, MAX_PROBE_SAMPLES), spp)
    };
    let mut cache = cache.lock().unwrap_or_else(|p| p.into_inner());
    let fresh = cache.as_ref().is_some_and(|c| {
        Arc::ptr_eq(&c.scene, &request.scene)
            && c.light_mode == settings.light_mode
            && c.light_radius == settings.light_radius
    });
    if !fresh {
        *cache = Some(ProbeContext {
            scene: Arc::clone(&request.scene),
            light_mode: settings.light_mode,
            light_radius: settings.light_radius,
            // the render's continuations come from its snapshot: no pilot here
            context: RenderContext::new(
                Arc::clone(&request.scene),
                RenderSettings {
                    auto_indirect_samples: false,
                    ..settings.clone()
                },
            ),
        });
    }
    let probe_context = cache.as_mut()?;
    let context = &mut probe_context.context;
    context.settings = settings.clone();
    context.set_camera(&request.camera);
    // the film's samples took the render's counts: traced again with them
    context.continuations = continuations;
    let probe = trace_pixel(context, &pixel);
    Some(ProbeResult {
        probe,
        duration: started.elapsed(),
        samples_per_pixel,
        terms,
    })
}

/// The marker of the probed pixel, and whatever else is drawn over the image.
pub fn paint_overlay(painter: &egui::Painter, mapping: &ImageMapping, probe: &ProbeState) {
    let Some((x, y)) = probe.pixel else {
        return;
    };
    if x >= mapping.width || y >= mapping.height {
        return;
    }
    // at least a few points wide, so the pixel is visible when the image is fitted
    let pixel = mapping.pixel_rect(x, y);
    let marker =
        egui::Rect::from_center_size(pixel.center(), pixel.size().max(egui::vec2(7.0, 7.0)));
    painter.rect_stroke(
        marker.expand(1.0),
        0.0,
        egui::Stroke::new(1.0, egui::Color32::BLACK),
        egui::StrokeKind::Outside,
    );
    painter.rect_stroke(
        marker,
        0.0,
        egui::Stroke::new(1.5, egui::Color32::YELLOW),
        egui::StrokeKind::Outside,
    );
    let c = marker.center();
    let reach = marker.width() / 2.0 + 8.0;
    for (from, to) in [
        (c - egui::vec2(reach, 0.0), c - egui::vec2(reach - 5.0, 0.0)),
        (c + egui::vec2(reach - 5.0, 0.0), c + egui::vec2(reach, 0.0)),
        (c - egui::vec2(0.0, reach), c - egui::vec2(0.0, reach - 5.0)),
        (c + egui::vec2(0.0, reach - 5.0), c + egui::vec2(0.0, reach)),
    ] {
        painter.line_segment([from, to], egui::Stroke::new(1.5, egui::Color32::YELLOW));
    }
    if !probe.path.hidden
        && let Some(path) = &probe.path.recorded
    {
        paint_path(&painter.with_clip_rect(mapping.rect), mapping, &path.lines);
    }
}

/// The rays of one sample: each line over a dark outline so it shows on any image.
fn paint_path(painter: &egui::Painter, mapping: &ImageMapping, lines: &[PathLine]) {
    let screen = |p: glam::Vec2| mapping.pixel_to_screen(p.x, p.y);
    let outline = egui::Color32::from_black_alpha(160);
    for line in lines {
        let (from, to) = (screen(line.from), screen(line.to));
        let colour = role_colour(line.role);
        if line.role == RayRole::Camera {
            // seen end-on: the camera ray is a ring around its hit
            painter.circle_stroke(to, 5.0, egui::Stroke::new(3.5, outline));
            painter.circle_stroke(to, 5.0, egui::Stroke::new(2.0, colour));
            continue;
        }
        let width = if matches!(line.role, RayRole::GatherMissed { .. }) {
            1.0
        } else {
            2.0
        };
        if line.role.is_dashed() {
            painter.add(egui::Shape::dashed_line(
                &[from, to],
                egui::Stroke::new(width, colour),
                6.0,
                4.0,
            ));
        } else {
            let edge = if line.role.is_refracted() {
                let [r, g, b] = path_view::outline_rgb(line.role);
                egui::Color32::from_rgb(r, g, b)
            } else {
                outline
            };
            painter.line_segment([from, to], egui::Stroke::new(width + 1.5, edge));
            painter.line_segment([from, to], egui::Stroke::new(width, colour));
        }
        if line.ends_on_film && !matches!(line.role, RayRole::GatherMissed { .. }) {
            painter.circle_filled(to, 3.0, colour);
        }
    }
}

/// The colour of a ray in the path view (`crate::analysis::path_view` lists them).
pub fn role_colour(role: RayRole) -> egui::Color32 {
    let [r, g, b] = path_view::role_rgb(role);
    egui::Color32::from_rgb(r, g, b)
}

/// A bounce of the drawn path picked in the path view: the integral is
/// to be shown at q, where it lands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PickedBounce {
    /// The continuation leaving p, as traced.
    pub bounce: Ray,
    /// The sample whose path it is (from 1).
    pub sample: u32,
}

/// The probe's window, within `area` (off a lesson's texts); closing it
/// ends the probe. `integral_shown` shows the integral at p beside it;
/// what it returns is a bounce picked to show the integral at q.
pub fn probe_window(
    ctx: &egui::Context,
    probe: &mut ProbeState,
    integral_shown: &mut bool,
    area: egui::Rect,
) -> Option<PickedBounce> {
    let (x, y) = probe.pixel?;
    let mut picked = None;
    let mut open = true;
    egui::Window::new("Pixel probe")
        .id(egui::Id::unique(PROBE_WINDOW_ID))
        .open(&mut open)
        .default_pos(area.right_top() + egui::vec2(-380.0, 8.0))
        .default_width(340.0)
        .constrain_to(area)
        .max_height(area.height() - 16.0)
        .resizable(true)
        .show(ctx, |ui| {
            ui.horizontal(|ui| {
                ui.label(format!("pixel ({x}, {y})"));
                ui.checkbox(integral_shown, "the integral at p")
                    .on_hover_text(
                        "The integrand over the hemisphere at the point this pixel sees",
                    );
            });
            let Some(result) = probe.result.clone() else {
                ui.spinner();
                return;
            };
            ui.label(
                egui::RichText::new(format!(
                    "{} spp · traced again in {:.1} ms ({} rays)",
                    result.samples_per_pixel,
                    result.duration.as_secs_f64() * 1e3,
                    result.probe.rays.total()
                ))
                .weak()
                .small(),
            );
            if result.probe.terms.is_empty() {
                ui.label("no samples yet");
            }
            egui::ScrollArea::vertical().show(ui, |ui| {
                egui::CollapsingHeader::new("Path of one sample")
                    .default_open(true)
                    .show(ui, |ui| {
                        picked = path_ui(ui, &mut probe.path, &result.probe, result.terms);
                    });
                for term in &result.probe.terms {
                    term_ui(ui, term);
                }
            });
        });
    if !open {
        probe.close();
    } else {
        probe.refresh_path();
    }
    picked
}

/// The choice of the sample whose path is drawn, and the list of its rays;
/// returns a bounce from p whose "∫ at q" was clicked.
fn path_ui(
    ui: &mut egui::Ui,
    path: &mut PathView,
    probe: &PixelProbe,
    terms: TermSet,
) -> Option<PickedBounce> {
    let mut shown = !path.hidden;
    ui.checkbox(&mut shown, "Draw its rays on the image")
        .on_hover_text("The rays this sample traced, projected into the view, coloured by term");
    path.hidden = !shown;
    let count = probe.passes.len();
    if count == 0 {
        return None;
    }
    let position = path.position(probe).unwrap_or(0);
    ui.horizontal(|ui| {
        let mut number = position as u32 + 1;
        ui.label("sample");
        let changed = ui
            .add(egui::DragValue::new(&mut number).range(1..=count as u32))
            .on_hover_text("Which of the pixel's samples, in the order the film summed them")
            .changed();
        ui.label(format!("of {count}"));
        let previous = ui.add_enabled(number > 1, egui::Button::new("<")).clicked();
        let next = ui
            .add_enabled((number as usize) < count, egui::Button::new(">"))
            .clicked();
        if changed || previous || next {
            number = (number + u32::from(next)).saturating_sub(u32::from(previous)).max(1);
            path.sample = PathSample::Number(number);
        }
        let mut brightest = path.sample == PathSample::Brightest;
        if ui
            .toggle_value(&mut brightest, "Brightest")
            .on_hover_text("Show the sample of largest luminance (a firefly's path), and follow it as samples come in")
            .changed()
        {
            path.sample = if brightest {
                PathSample::Brightest
            } else {
                PathSample::Number(position as u32 + 1)
            };
        }
    });
    let Some(recorded) = &path.recorded else {
        ui.spinner();
        return None;
    };
    let mut picked = None;
    ui.label(
        egui::RichText::new(format!(
            "this sample's luminance: {:.4} W/(m²·sr)",
            probe.pass_luminance[recorded.position]
        ))
        .weak()
        .small(),
    );
    egui::Grid::new("probe path")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            for segment in &recorded.log.segments {
                let role = RayRole::of(segment, terms);
                let (rect, _) =
                    ui.allocate_exact_size(egui::vec2(14.0, 10.0), egui::Sense::hover());
                let y = rect.center().y;
                let stroke = egui::Stroke::new(2.0, role_colour(role));
                if role.is_dashed() {
                    ui.painter().add(egui::Shape::dashed_line(
                        &[egui::pos2(rect.left(), y), egui::pos2(rect.right(), y)],
                        stroke,
                        3.0,
                        2.0,
                    ));
                } else {
                    ui.painter().line_segment(
                        [egui::pos2(rect.left(), y), egui::pos2(rect.right(), y)],
                        stroke,
                    );
                }
                ui.horizontal(|ui| {
                    ui.label(role.describe());
                    // a continuation leaving p (filed under p's L1): its end is q
                    let leaves_p = matches!(segment.kind, SegmentKind::Bounce { .. })
                        && segment.term == Term::L1;
                    if leaves_p
                        && ui
                            .small_button("∫ at q")
                            .on_hover_text(
                                "The integral at q, where this bounce lands: the nested integral of L2",
                            )
                            .clicked()
                    {
                        picked = Some(PickedBounce {
                            bounce: segment.ray,
                            sample: recorded.position as u32 + 1,
                        });
                    }
                });
                let added = segment_luminance(segment);
                ui.label(if added > 0.0 {
                    format!("+{added:.4}")
                } else {
                    String::new()
                })
                .on_hover_text("Luminance this ray added to its term, W/(m²·sr)");
                ui.end_row();
            }
        });
    picked
}

/// Statistics and histogram of one term of the probed pixel.
fn term_ui(ui: &mut egui::Ui, term: &TermProbe) {
    ui.separator();
    ui.strong(format!(
        "{} — {}",
        term.term.label(),
        term.term.description()
    ));
    let (lo, hi) = term.interval_95();
    egui::Grid::new(("probe", term.term.index()))
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            let mut row = |name: &str, value: String, hint: &str| {
                ui.label(name).on_hover_text(hint);
                ui.label(value);
                ui.end_row();
            };
            let m = term.mean;
            row(
                "mean RGB",
                format!("{:.4}, {:.4}, {:.4}", m.x, m.y, m.z),
                "Mean radiance per channel, W/(m²·sr)",
            );
            row(
                "mean luminance",
                format!("{:.4}", term.mean_luminance()),
                "Ȳ = Σ Y / N, W/(m²·sr)",
            );
            row(
                "standard error",
                format!("{:.4}", term.standard_error),
                "se = √(s² / N): the noise of the mean; it falls as 1/√N",
            );
            row(
                "95% interval",
                format!("{lo:.4} … {hi:.4}"),
                "Ȳ ± 1.96 se: where the converged value lies, 19 times out of 20",
            );
            row(
                "N",
                term.film_samples.to_string(),
                "Samples of this term in the pixel",
            );
            row(
                "largest sample",
                format!("{:.1}% of the sum", 100.0 * term.largest_share),
                "max Y / Σ Y: close to 100%, one sample (a firefly) makes the pixel",
            );
        });
    if !term.is_complete() {
        ui.label(
            egui::RichText::new(format!(
                "statistics of the first {} of {} samples",
                term.samples.len(),
                term.film_samples
            ))
            .weak()
            .small(),
        );
    } else if !term.reproduces_film() {
        ui.colored_label(
            ui.visuals().warn_fg_color,
            "these samples differ from the film's (it has changed since): probing again",
        );
    }
    histogram_ui(ui, term);
}

fn histogram_ui(ui: &mut egui::Ui, term: &TermProbe) {
    let histogram = term.histogram(HISTOGRAM_BINS);
    let width = histogram.bin_width;
    let bars: Vec<Bar> = histogram
        .counts
        .iter()
        .enumerate()
        .map(|(k, &count)| Bar::new((k as f64 + 0.5) * width, count as f64).width(width))
        .collect();
    let colour = term_colour(term.term);
    Plot::new(("probe histogram", term.term.index()))
        .height(90.0)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .show_y(false)
        .include_y(0.0)
        .x_axis_label("sample luminance")
        .show(ui, |plot| {
            plot.bar_chart(BarChart::new("samples", bars).color(colour));
            plot.vline(
                VLine::new("mean", term.mean_luminance())
                    .stroke(egui::Stroke::new(1.5, egui::Color32::WHITE)),
            );
        });
}

fn term_colour(term: Term) -> egui::Color32 {
    let [r, g, b] = path_view::term_rgb(term);
    egui::Color32::from_rgb(r, g, b)
}
