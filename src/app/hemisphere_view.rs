//! The integral at the probed point p, on screen: the integrand of a term
//! over the hemisphere Ω⁺ at p (`crate::analysis::hemisphere`), the
//! sources' domains Ω_s outlined and named (`crate::analysis::domains`),
//! the point lights as marked directions, one factor at a time if asked,
//! with its colour bar, its unit and the quadrature.
//!
//! It is computed in the background, in rounds of more directions per
//! pixel of the map ([`ROUNDS`]): each round a job of its own, started
//! when the last one is in, so that a change of pixel, term, settings or
//! camera is taken up by the next round and the interface never waits.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use eframe::egui;
use glam::Vec2;

use crate::analysis::domains::{SourceDomains, source_domains};
use crate::analysis::hemisphere::{
    Factor, HemisphereError, IntegrandMap, ShadingPoint, integrand_map,
};
use crate::analysis::hemisphere_colour::{ColouredMap, colour_map};
use crate::analysis::noise::{ColourMap, Scale, Unit, format_tick};
use crate::course::color::luminance;
use crate::course::{RenderSettings, Term, TermSet};
use crate::platform::threads::{self, Job};
use crate::platform::time::Instant;
use crate::render::progressive::{SharedScene, ViewRequest};
use crate::scene::Camera;
use crate::transport::context::RenderContext;

/// The map's side, in pixels: each a direction stratum of 2·(2/128)² sr.
pub const MAP_SIZE: u32 = 128;

/// Directions per pixel of the map, round after round. A page on one
/// thread computes a round between two frames: it stops at the second.
pub const ROUNDS: [u32; 4] = [1, 4, 16, 64];

/// The window's id.
pub const HEMISPHERE_WINDOW_ID: &str = "lumiere integral at p";

/// The window's title.
pub const HEMISPHERE_WINDOW_TITLE: &str = "The integral at p";

/// Side of the map on screen, in points.
const MAP_POINTS: f32 = 260.0;

/// What a map is computed for: two equal ones give the same map.
#[derive(Clone, Debug, PartialEq)]
struct Asked {
    scene: SharedScene,
    /// The view's settings with every term: the map traces the terms
    /// arriving along each direction whatever is shown.
    settings: RenderSettings,
    camera: Camera,
    pixel: (u32, u32),
    term: Term,
}

/// A map, and what it was computed for.
pub struct Computed {
    asked: Asked,
    /// Index in [`ROUNDS`].
    pub round: usize,
    pub outcome: Result<Outcome, HemisphereError>,
    pub duration: Duration,
}

impl Computed {
    /// The term the map integrates.
    pub fn term(&self) -> Term {
        self.asked.term
    }

    /// The pixel whose first hit is p.
    pub fn pixel(&self) -> (u32, u32) {
        self.asked.pixel
    }

    /// Whether it is the last round's (or no map can be made).
    pub fn is_final(&self) -> bool {
        self.outcome.is_err() || self.round + 1 >= rounds()
    }
}

/// What a round computed.
pub struct Outcome {
    pub map: IntegrandMap,
    pub domains: Arc<SourceDomains>,
    /// p and its normal, in the scene.
    pub point: glam::Vec3,
    pub normal: glam::Vec3,
}

/// The view's choices and its latest map.
pub struct HemisphereView {
    /// Shown while a pixel is probed.
    pub shown: bool,
    /// The term integrated; `None`: the lowest integral term shown.
    pub term: Option<Term>,
    pub factor: Factor,
    pub scale: Scale,
    pub result: Option<Arc<Computed>>,
    job: Option<Job<Option<Computed>>>,
    cache: Arc<Mutex<Option<RenderContext>>>,
    texture: Option<(TextureOf, egui::TextureHandle)>,
}

impl Default for HemisphereView {
    fn default() -> Self {
        Self {
            shown: true,
            term: None,
            factor: Factor::Integrand,
            scale: Scale::Linear,
            result: None,
            job: None,
            cache: Arc::default(),
            texture: None,
        }
    }
}

/// What the texture shows.
#[derive(Clone, Copy, PartialEq)]
struct TextureOf {
    result: *const Computed,
    factor: Factor,
    scale: Scale,
}

impl HemisphereView {
    /// The term the map integrates when `visible` are shown.
    pub fn term_for(&self, visible: TermSet) -> Term {
        self.term.unwrap_or_else(|| {
            [Term::L1, Term::L2, Term::L3Plus]
                .into_iter()
                .find(|&t| visible.contains(t))
                .unwrap_or(Term::L1)
        })
    }

    /// Whether the map shown is the last round's for `request` at `pixel`
    /// and no job runs (for scripted screenshots).
    pub fn is_settled(&self, request: &ViewRequest, pixel: Option<(u32, u32)>) -> bool {
        let Some(pixel) = pixel.filter(|_| self.shown) else {
            return true;
        };
        let asked = self.asked(request, pixel);
        self.job.is_none()
            && self
                .result
                .as_ref()
                .is_some_and(|r| r.asked == asked && self.is_last_round(r))
    }

    fn is_last_round(&self, computed: &Computed) -> bool {
        computed.is_final()
    }

    fn asked(&self, request: &ViewRequest, pixel: (u32, u32)) -> Asked {
        Asked {
            scene: request.scene.clone(),
            settings: RenderSettings {
                terms: TermSet::ALL,
                auto_indirect_samples: false,
                ..request.settings.clone()
            },
            camera: request.camera.clone(),
            pixel,
            term: self.term_for(request.settings.terms),
        }
    }

    /// Collects a finished round; starts the next one, or the first for
    /// what is asked now.
    pub fn update(
        &mut self,
        ctx: &egui::Context,
        request: &ViewRequest,
        pixel: Option<(u32, u32)>,
    ) {
        if self.job.as_ref().is_some_and(|j| j.is_finished())
            && let Some(job) = self.job.take()
            && let Some(computed) = job.join().flatten()
        {
            self.result = Some(Arc::new(computed));
        }
        let Some(pixel) = pixel.filter(|_| self.shown) else {
            return;
        };
        if self.job.is_some() {
            return; // what it computes may be stale: the next round catches up
        }
        let asked = self.asked(request, pixel);
        let (round, domains) = match &self.result {
            Some(r) if r.asked == asked => {
                if self.is_last_round(r) {
                    return;
                }
                let domains = r.outcome.as_ref().ok().map(|o| Arc::clone(&o.domains));
                (r.round + 1, domains)
            }
            _ => (0, None),
        };
        let cache = Arc::clone(&self.cache);
        let repaint = super::waker::Waker::new(ctx);
        self.job = Some(threads::spawn("lumiere hemisphere", move || {
            let computed = compute(asked, round, domains, &cache);
            repaint.wake();
            Some(computed)
        }));
    }

    /// The texture of the map's `factor` on `scale`, made when they change.
    fn texture(
        &mut self,
        ctx: &egui::Context,
        computed: &Arc<Computed>,
    ) -> Option<(egui::TextureId, ColouredMap)> {
        let outcome = computed.outcome.as_ref().ok()?;
        let coloured = colour_map(&outcome.map, self.factor, self.scale);
        let of = TextureOf {
            result: Arc::as_ptr(computed),
            factor: self.factor,
            scale: self.scale,
        };
        if self.texture.as_ref().is_none_or(|(t, _)| *t != of) {
            let size = [coloured.size as usize, coloured.size as usize];
            let image = egui::ColorImage::from_rgba_unmultiplied(size, &coloured.srgba);
            let handle =
                ctx.load_texture("lumiere hemisphere", image, egui::TextureOptions::NEAREST);
            self.texture = Some((of, handle));
        }
        self.texture.as_ref().map(|(_, h)| (h.id(), coloured))
    }
}

fn rounds() -> usize {
    if threads::ONE_THREAD { 2 } else { ROUNDS.len() }
}

/// One round of the map for `asked`, with the render context kept in
/// `cache` (rebuilt when the scene or the settings change).
fn compute(
    asked: Asked,
    round: usize,
    domains: Option<Arc<SourceDomains>>,
    cache: &Mutex<Option<RenderContext>>,
) -> Computed {
    let started = Instant::now();
    let mut cache = cache.lock().unwrap_or_else(|p| p.into_inner());
    let fresh = cache
        .as_ref()
        .is_some_and(|c| Arc::ptr_eq(&c.scene, &asked.scene.0) && c.settings == asked.settings);
    if !fresh {
        *cache = Some(RenderContext::new(
            Arc::clone(&asked.scene.0),
            asked.settings.clone(),
        ));
    }
    let context = cache.as_mut().expect("built above");
    context.set_camera(&asked.camera);
    let (x, y) = asked.pixel;
    let ray = context.camera.generate(x, y, Vec2::splat(0.5));
    let terms = TermSet::only(asked.term);
    let outcome = integrand_map(
        context,
        &ray,
        terms,
        MAP_SIZE,
        ROUNDS[round],
        asked.settings.seed,
    )
    .and_then(|map| {
        let p = ShadingPoint::seen(context, &ray).ok_or(HemisphereError::NoSurface)?;
        let domains = domains.unwrap_or_else(|| Arc::new(source_domains(context, &p, MAP_SIZE)));
        Ok(Outcome {
            map,
            domains,
            point: p.point.p,
            normal: p.frame.z,
        })
    });
    Computed {
        asked,
        round,
        outcome,
        duration: started.elapsed(),
    }
}

/// The window of the integral at p, while a pixel is probed and the view is
/// shown; `area` keeps it off a lesson's texts.
pub fn hemisphere_window(
    ctx: &egui::Context,
    view: &mut HemisphereView,
    pixel: Option<(u32, u32)>,
    visible: TermSet,
    area: egui::Rect,
) {
    let Some((x, y)) = pixel.filter(|_| view.shown) else {
        return;
    };
    let mut open = true;
    egui::Window::new(HEMISPHERE_WINDOW_TITLE)
        .id(egui::Id::unique(HEMISPHERE_WINDOW_ID))
        .open(&mut open)
        .default_pos(area.left_top() + egui::vec2(8.0, 8.0))
        .default_width(MAP_POINTS)
        .constrain_to(area)
        .resizable(false)
        .show(ctx, |ui| {
            choices_ui(ui, view, visible);
            let Some(computed) = view.result.clone() else {
                ui.spinner();
                return;
            };
            if computed.asked.pixel != (x, y) {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label(format!("pixel ({x}, {y})"));
                });
            }
            match &computed.outcome {
                Err(e) => {
                    ui.label(format!("No map at pixel {:?}: {e}.", computed.asked.pixel));
                }
                Ok(outcome) => {
                    if let Some((texture, coloured)) = view.texture(ctx, &computed) {
                        map_ui(ui, texture, &coloured, outcome, &computed);
                    }
                    numbers_ui(ui, view, &computed, outcome);
                }
            }
        });
    if !open {
        view.shown = false;
    }
}

/// The term, the factor and the scale.
fn choices_ui(ui: &mut egui::Ui, view: &mut HemisphereView, visible: TermSet) {
    ui.horizontal(|ui| {
        let shown = view.term_for(visible);
        for term in [Term::L1, Term::L2, Term::L3Plus] {
            if ui
                .selectable_label(shown == term, term.label())
                .on_hover_text(term_formula(term))
                .clicked()
            {
                view.term = Some(term);
            }
        }
        ui.separator();
        egui::ComboBox::from_id_salt("hemisphere factor")
            .selected_text(factor_label(view.factor))
            .show_ui(ui, |ui| {
                for factor in Factor::ALL {
                    ui.selectable_value(&mut view.factor, factor, factor_label(factor));
                }
            })
            .response
            .on_hover_text("The integrand, or one of its factors alone");
        ui.separator();
        ui.selectable_value(&mut view.scale, Scale::Linear, "linear");
        ui.selectable_value(&mut view.scale, Scale::Log, "log");
    });
}

fn factor_label(factor: Factor) -> &'static str {
    match factor {
        Factor::Integrand => "L_i · f_r · cos θ",
        Factor::Incident => "L_i alone",
        Factor::Brdf => "f_r alone",
        Factor::Cosine => "cos θ alone",
    }
}

/// What the term integrates, in the lecture's words.
pub fn term_formula(term: Term) -> &'static str {
    match term {
        Term::L1 => {
            "L1(p) = ∫ over Σ Ωs of Le(q, −ω) f_r(p, ω → ωo) cos θ dω, plus each point light"
        }
        Term::L2 => "L2(p) = ∫ over Ω = Ω⁺ − ΩS of L_direct(q, −ω) f_r(p, ω → ωo) cos θ dω",
        _ => "L3+(p) = ∫ over Ω⁺ of (L2 + L3+)(q, −ω) f_r(p, ω → ωo) cos θ dω",
    }
}

/// The disk, its outlines, names and marks, and the colour bar.
fn map_ui(
    ui: &mut egui::Ui,
    texture: egui::TextureId,
    coloured: &ColouredMap,
    outcome: &Outcome,
    computed: &Computed,
) {
    let (response, painter) =
        ui.allocate_painter(egui::vec2(MAP_POINTS, MAP_POINTS), egui::Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 0.0, egui::Color32::from_gray(24));
    let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
    painter.image(texture, rect, uv, egui::Color32::WHITE);
    // disk (x right, y up) → screen
    let screen = |d: Vec2| rect.center() + egui::vec2(d.x, -d.y) * rect.width() / 2.0;
    let rim = egui::Stroke::new(1.0, egui::Color32::from_gray(140));
    painter.circle_stroke(rect.center(), rect.width() / 2.0, rim);
    let outline = egui::Stroke::new(1.5, egui::Color32::WHITE);
    for (a, b) in outcome.domains.outline() {
        painter.line_segment([screen(a), screen(b)], outline);
    }
    let font = egui::FontId::proportional(12.0);
    for label in outcome.domains.labels() {
        let text = format!("Ω {}", label.name);
        let at = screen(label.below) + egui::vec2(0.0, 2.0);
        painter.text(
            at + egui::vec2(1.0, 1.0),
            egui::Align2::CENTER_TOP,
            &text,
            font.clone(),
            egui::Color32::BLACK,
        );
        painter.text(
            at,
            egui::Align2::CENTER_TOP,
            &text,
            font.clone(),
            egui::Color32::WHITE,
        );
    }
    if computed.asked.term == Term::L1 {
        // a point light below p's horizon sends nothing: it has no place on the map
        for dirac in outcome.map.diracs.iter().filter(|d| d.direction.z > 0.0) {
            let at = screen(dirac.disk);
            let colour = if dirac.occluded {
                egui::Color32::from_gray(150)
            } else {
                egui::Color32::from_rgb(255, 220, 80)
            };
            let stroke = egui::Stroke::new(2.0, colour);
            for d in [
                egui::vec2(6.0, 0.0),
                egui::vec2(0.0, 6.0),
                egui::vec2(4.0, 4.0),
                egui::vec2(4.0, -4.0),
            ] {
                painter.line_segment([at - d, at + d], stroke);
            }
            let hidden = if dirac.occluded { " (hidden)" } else { "" };
            painter.text(
                at + egui::vec2(8.0, -8.0),
                egui::Align2::LEFT_BOTTOM,
                format!("δ {}{hidden}", dirac.name),
                font.clone(),
                colour,
            );
        }
    }
    painter.text(
        rect.center_top() + egui::vec2(0.0, 2.0),
        egui::Align2::CENTER_TOP,
        "up",
        egui::FontId::proportional(10.0),
        egui::Color32::from_gray(170),
    );
    if let Some(pos) = response.hover_pos() {
        hover_ui(&response, pos, rect, coloured, outcome);
    }
    colour_bar_ui(ui, coloured);
}

/// The value under the pointer, and the direction.
fn hover_ui(
    response: &egui::Response,
    pos: egui::Pos2,
    rect: egui::Rect,
    coloured: &ColouredMap,
    outcome: &Outcome,
) {
    let uv = (pos - rect.min) / rect.size();
    let size = coloured.size;
    let (column, row) = ((uv.x * size as f32) as u32, (uv.y * size as f32) as u32);
    if column >= size || row >= size {
        return;
    }
    let centre = IntegrandMap::disk_point(size, column, row, Vec2::splat(0.5));
    let Some(w) = crate::analysis::hemisphere::disk_to_direction(centre) else {
        return;
    };
    let index = (row * size + column) as usize;
    let value = outcome.map.layer(coloured.factor)[index];
    let source = outcome.domains.source[index]
        .map(|s| {
            let seen = if outcome.domains.visible[index] {
                ""
            } else {
                ", hidden"
            };
            format!(" · in Ω of {}{seen}", outcome.domains.names[s as usize])
        })
        .unwrap_or_default();
    response.clone().on_hover_text(format!(
        "θ = {:.0}°{source}\n{} = {} {}",
        w.z.clamp(-1.0, 1.0).acos().to_degrees(),
        factor_label(coloured.factor),
        format_tick(value, Unit::Radiance),
        coloured.factor.unit()
    ));
}

/// The colour bar under the map, with its ticks and unit.
fn colour_bar_ui(ui: &mut egui::Ui, coloured: &ColouredMap) {
    let (response, painter) =
        ui.allocate_painter(egui::vec2(MAP_POINTS, 46.0), egui::Sense::hover());
    let bar = egui::Rect::from_min_size(response.rect.min, egui::vec2(MAP_POINTS, 12.0));
    let steps = 64;
    let mut mesh = egui::Mesh::default();
    for k in 0..steps {
        let (t0, t1) = (k as f32 / steps as f32, (k + 1) as f32 / steps as f32);
        let [r, g, b] = ColourMap::Sequential.srgb((t0 + t1) / 2.0);
        let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
        let colour = egui::Color32::from_rgb(byte(r), byte(g), byte(b));
        let (x0, x1) = (bar.left() + t0 * bar.width(), bar.left() + t1 * bar.width());
        mesh.add_colored_rect(egui::Rect::from_x_y_ranges(x0..=x1, bar.y_range()), colour);
    }
    painter.add(mesh);
    let text = ui.visuals().text_color();
    let font = egui::FontId::proportional(11.0);
    for (t, align) in [
        (0.0, egui::Align2::LEFT_TOP),
        (0.5, egui::Align2::CENTER_TOP),
        (1.0, egui::Align2::RIGHT_TOP),
    ] {
        let x = bar.left() + t * bar.width();
        painter.text(
            egui::pos2(x, bar.bottom() + 2.0),
            align,
            format_tick(coloured.value_at(t), Unit::Radiance),
            font.clone(),
            text,
        );
    }
    let scale = match coloured.scale {
        Scale::Linear => "linear",
        Scale::Log => "log",
    };
    painter.text(
        egui::pos2(bar.center().x, bar.bottom() + 16.0),
        egui::Align2::CENTER_TOP,
        format!(
            "{} ({}), {scale}",
            factor_label(coloured.factor),
            coloured.factor.unit()
        ),
        font,
        text,
    );
}

/// The quadrature, the point lights, and how the map was made.
fn numbers_ui(ui: &mut egui::Ui, view: &HemisphereView, computed: &Computed, outcome: &Outcome) {
    let map = &outcome.map;
    let term = computed.asked.term;
    ui.label(format!(
        "∫ {} over Ω⁺ = {:.5} ± {:.5} W/m²/sr",
        term.label(),
        luminance(map.integral),
        map.integral_standard_error
    ))
    .on_hover_text("The map's quadrature (luminance), with its standard error");
    if term == Term::L1 && !map.diracs.is_empty() {
        let diracs: f32 = map.diracs.iter().map(|d| luminance(d.radiance)).sum();
        let below = map.diracs.iter().filter(|d| d.direction.z <= 0.0).count();
        let below = match below {
            0 => String::new(),
            n => format!(", {n} below the horizon"),
        };
        ui.label(format!(
            "+ {} point light(s){below}: {:.5}  →  {} = {:.5} W/m²/sr",
            map.diracs.len(),
            diracs,
            term.label(),
            luminance(map.quadrature())
        ));
    }
    let refining = !view.is_last_round(computed);
    ui.horizontal(|ui| {
        if refining {
            ui.spinner();
        }
        ui.add(egui::Label::new(
            egui::RichText::new(format!(
                "p = ({:.3}, {:.3}, {:.3}) · {} direction(s) per pixel of {}² · {:.0} ms · equal-area disk, zenith at the centre",
                outcome.point.x,
                outcome.point.y,
                outcome.point.z,
                map.directions_per_pixel,
                map.size,
                computed.duration.as_secs_f64() * 1e3
            ))
            .small()
            .weak(),
        ).wrap());
    });
}
