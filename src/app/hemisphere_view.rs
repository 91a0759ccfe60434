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

use crate::analysis::domains::{DomainLabel, SourceDomains, source_domains};
use crate::analysis::hemisphere::{
    Factor, HemisphereError, IntegrandMap, ShadingPoint, Vertex, direction_to_disk, integrand_map,
};
use crate::analysis::hemisphere_colour::{ColouredMap, colour_map, colour_values};
use crate::analysis::noise::Scale;
use crate::analysis::strategy_samples::{
    DrawnSamples, Strategy, drawn_samples, sampled_terms, strategy_density,
};
use crate::course::{RenderSettings, Term, TermSet};
use crate::geometry::Ray;
use crate::platform::threads::{self, Job};
use crate::platform::time::Instant;
use crate::render::progressive::{SharedScene, ViewRequest};
use crate::scene::Camera;
use crate::transport::context::RenderContext;
use crate::transport::continuations::Continuations;

use super::probe_view::{PickedBounce, ProbeState};

mod lab_ui;
mod map_ui;

pub use lab_ui::{LabComputed, LabView};

/// The map's side, in pixels: each a direction stratum of 2·(2/128)² sr.
pub const MAP_SIZE: u32 = 128;

/// Directions per pixel of the map, round after round. A page on one
/// thread computes a round between two frames: it stops at the second.
pub const ROUNDS: [u32; 4] = [1, 4, 16, 64];

/// The film's samples of the pixel drawn at p, at most (the view draws the first N).
pub const MOST_DRAWN_SAMPLES: u32 = 1024;

/// The window's id.
pub const HEMISPHERE_WINDOW_ID: &str = "lumiere integral at p";

/// The window's title.
pub const HEMISPHERE_WINDOW_TITLE: &str = "The integral at p";

/// Its title at a path's second vertex.
pub const HEMISPHERE_WINDOW_TITLE_AT_Q: &str = "The integral at q";

/// Side of the map on screen, in points.
pub const MAP_POINTS: f32 = 260.0;

/// What a map is computed for: two equal ones give the same map.
#[derive(Clone, Debug, PartialEq)]
struct Asked {
    scene: SharedScene,
    /// The view's settings with every term: the map traces the terms
    /// arriving along each direction whatever is shown.
    settings: RenderSettings,
    camera: Camera,
    pixel: (u32, u32),
    /// p, or a second vertex q of one of the pixel's paths.
    vertex: Vertex,
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

    /// Where the integral is taken: p, or q one bounce further.
    pub fn vertex(&self) -> Vertex {
        self.asked.vertex
    }

    /// Whether it is the last round's (or no map can be made).
    pub fn is_final(&self) -> bool {
        self.outcome.is_err() || self.round + 1 >= rounds()
    }
}

/// What a round computed.
pub struct Outcome {
    pub map: IntegrandMap,
    /// What the first round found and the later ones keep.
    pub at_point: Arc<AtPoint>,
    /// The vertex and its normal, in the scene.
    pub point: glam::Vec3,
    pub normal: glam::Vec3,
    /// ωo on the map: towards the camera from p, back to p from q.
    pub outgoing: Vec2,
}

/// What does not change from round to round: the sources' domains, the
/// film's samples at p and each strategy's density.
pub struct AtPoint {
    pub domains: SourceDomains,
    /// The domains' outlines and names (disk coordinates), found once.
    pub outline: Vec<(Vec2, Vec2)>,
    pub labels: Vec<DomainLabel>,
    pub drawn: DrawnSamples,
    pub light_density: Option<Vec<f32>>,
    pub directions_density: Option<Vec<f32>>,
}

impl AtPoint {
    pub fn density(&self, strategy: Strategy) -> Option<&Vec<f32>> {
        match strategy {
            Strategy::Light => self.light_density.as_ref(),
            Strategy::Directions => self.directions_density.as_ref(),
        }
    }
}

/// What the map shows: a factor of the integrand, or a strategy's density.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapShows {
    Factor(Factor),
    Density(Strategy),
}

/// The view's choices and its latest map.
pub struct HemisphereView {
    /// Shown while a pixel is probed.
    pub shown: bool,
    /// The term integrated; `None`: the lowest integral term shown.
    pub term: Option<Term>,
    pub shows: MapShows,
    pub scale: Scale,
    /// The film's samples at p drawn over the map, and how many.
    pub samples_shown: bool,
    pub samples_drawn: u32,
    /// The sampling lab's choices and outcome.
    pub lab: LabView,
    /// The second vertex q picked in the path view, if the view is there
    /// rather than at p.
    pub at_q: Option<SecondVertex>,
    pub result: Option<Arc<Computed>>,
    job: Option<Job<Option<Computed>>>,
    cache: Arc<Mutex<Contexts>>,
    texture: Option<(TextureOf, egui::TextureHandle, ColouredMap)>,
}

impl Default for HemisphereView {
    fn default() -> Self {
        Self {
            shown: true,
            term: None,
            shows: MapShows::Factor(Factor::Integrand),
            scale: Scale::Linear,
            samples_shown: true,
            samples_drawn: 16,
            lab: LabView::default(),
            at_q: None,
            result: None,
            job: None,
            cache: Arc::default(),
            texture: None,
        }
    }
}

/// A second vertex q of a probed pixel's path, where the view integrates
/// instead of p while the pixel and the camera stay.
#[derive(Clone, Debug, PartialEq)]
pub struct SecondVertex {
    pub pixel: (u32, u32),
    pub camera: Camera,
    /// The continuation leaving p that lands on q.
    pub bounce: Ray,
    /// The sample whose path it belongs to (from 1).
    pub sample: u32,
}

/// What the texture shows.
#[derive(Clone, Copy, PartialEq)]
struct TextureOf {
    result: *const Computed,
    shows: MapShows,
    scale: Scale,
}

/// The render contexts the rounds reuse: the map's, with every term, and
/// the samples', the view's own.
#[derive(Default)]
struct Contexts {
    map: Option<RenderContext>,
    samples: Option<RenderContext>,
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
        let samples_settings = samples_settings(request, asked.term);
        self.lab.is_settled(&asked, &samples_settings)
            && self.job.is_none()
            && self
                .result
                .as_ref()
                .is_some_and(|r| r.asked == asked && self.is_last_round(r))
    }

    fn is_last_round(&self, computed: &Computed) -> bool {
        computed.is_final()
    }

    /// The second vertex the view integrates at, if it is for `pixel`
    /// seen through `camera`.
    pub fn second_vertex(&self, pixel: (u32, u32), camera: &Camera) -> Option<&SecondVertex> {
        self.at_q
            .as_ref()
            .filter(|q| q.pixel == pixel && q.camera == *camera)
    }

    /// Shows the integral at q, where `picked` (a bounce of the probed
    /// pixel's drawn path) lands.
    pub fn open_at_q(&mut self, probe: &ProbeState, camera: &Camera, picked: PickedBounce) {
        let Some(pixel) = probe.pixel else { return };
        self.shown = true;
        self.at_q = Some(SecondVertex {
            pixel,
            camera: camera.clone(),
            bounce: picked.bounce,
            sample: picked.sample,
        });
    }

    /// Where the integral is taken for `pixel` seen through `camera`.
    fn vertex(&self, pixel: (u32, u32), camera: &Camera) -> Vertex {
        self.second_vertex(pixel, camera)
            .map_or(Vertex::FirstHit, |q| Vertex::Second { bounce: q.bounce })
    }

    fn asked(&self, request: &ViewRequest, pixel: (u32, u32)) -> Asked {
        let vertex = self.vertex(pixel, &request.camera);
        Asked {
            scene: request.scene.clone(),
            settings: RenderSettings {
                terms: TermSet::ALL,
                auto_indirect_samples: false,
                ..request.settings.clone()
            },
            camera: request.camera.clone(),
            pixel,
            vertex,
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
        continuations: &Continuations,
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
        let asked = self.asked(request, pixel);
        let samples_settings = samples_settings(request, asked.term);
        self.lab.update(ctx, &asked, &samples_settings, &self.cache);
        if self.job.is_some() {
            return; // what it computes may be stale: the next round catches up
        }
        let (round, at_point) = match &self.result {
            Some(r) if r.asked == asked => {
                if self.is_last_round(r) {
                    return;
                }
                let at_point = r.outcome.as_ref().ok().map(|o| Arc::clone(&o.at_point));
                (r.round + 1, at_point)
            }
            _ => (0, None),
        };
        let cache = Arc::clone(&self.cache);
        let repaint = super::waker::Waker::new(ctx);
        let continuations = continuations.clone();
        self.job = Some(threads::spawn("lumiere hemisphere", move || {
            let samples = (samples_settings, continuations);
            let computed = compute(asked, round, at_point, samples, &cache);
            repaint.wake();
            Some(computed)
        }));
    }

    /// The texture of the map's `factor` on `scale`, made when they change.
    fn texture(
        &mut self,
        ctx: &egui::Context,
        computed: &Arc<Computed>,
    ) -> Option<egui::TextureId> {
        let outcome = computed.outcome.as_ref().ok()?;
        let of = TextureOf {
            result: Arc::as_ptr(computed),
            shows: self.shows,
            scale: self.scale,
        };
        // coloured and uploaded when what is shown changes, not every frame
        if self.texture.as_ref().is_none_or(|(t, _, _)| *t != of) {
            let coloured = match self.shows {
                MapShows::Factor(factor) => colour_map(&outcome.map, factor, self.scale),
                MapShows::Density(strategy) => {
                    let density = outcome.at_point.density(strategy)?.clone();
                    colour_values(density, outcome.map.size, self.scale)
                }
            };
            let size = [coloured.size as usize, coloured.size as usize];
            let image = egui::ColorImage::from_rgba_unmultiplied(size, &coloured.srgba);
            let handle =
                ctx.load_texture("lumiere hemisphere", image, egui::TextureOptions::NEAREST);
            self.texture = Some((of, handle, coloured));
        }
        self.texture.as_ref().map(|(_, h, _)| h.id())
    }

    /// The map as last coloured for the texture.
    fn coloured(&self) -> Option<&ColouredMap> {
        self.texture.as_ref().map(|(_, _, coloured)| coloured)
    }
}

/// The settings the film's samples at p are drawn with: the view's, with
/// `term` rendered.
fn samples_settings(request: &ViewRequest, term: Term) -> RenderSettings {
    RenderSettings {
        terms: sampled_terms(request.settings.terms, term),
        auto_indirect_samples: false,
        ..request.settings.clone()
    }
}

fn rounds() -> usize {
    if threads::ONE_THREAD { 2 } else { ROUNDS.len() }
}

/// One round of the map for `asked`, with the render contexts kept in
/// `cache` (rebuilt when the scene or the settings change); the first
/// round finds what the others keep ([`AtPoint`]), the film's samples with
/// `samples`' settings and continuations.
fn compute(
    asked: Asked,
    round: usize,
    at_point: Option<Arc<AtPoint>>,
    (samples_settings, continuations): (RenderSettings, Continuations),
    cache: &Mutex<Contexts>,
) -> Computed {
    let started = Instant::now();
    let mut cache = cache.lock().unwrap_or_else(|p| p.into_inner());
    let cache = &mut *cache;
    let context = fresh_context(&mut cache.map, &asked.scene, &asked.settings, &asked.camera);
    let ray = asked.vertex.ray(context, asked.pixel);
    let terms = TermSet::only(asked.term);
    let map = integrand_map(
        context,
        &ray,
        terms,
        MAP_SIZE,
        ROUNDS[round],
        asked.settings.seed,
    );
    let outcome = map.and_then(|map| {
        let p = ShadingPoint::seen(context, &ray).ok_or(HemisphereError::NoSurface)?;
        let (point, normal) = (p.point.p, p.frame.z);
        let outgoing = direction_to_disk(p.wo_local);
        let at_point = match at_point {
            Some(at_point) => at_point,
            None => {
                let domains = source_domains(context, &p, MAP_SIZE);
                let context = fresh_context(
                    &mut cache.samples,
                    &asked.scene,
                    &samples_settings,
                    &asked.camera,
                );
                context.continuations = continuations;
                let drawn = drawn_samples(
                    context,
                    &p,
                    asked.pixel,
                    asked.vertex,
                    asked.term,
                    MOST_DRAWN_SAMPLES,
                );
                let density =
                    |strategy| strategy_density(context, &p, asked.term, strategy, MAP_SIZE);
                Arc::new(AtPoint {
                    outline: domains.outline(),
                    labels: domains.labels(),
                    light_density: drawn.light.map(|_| density(Strategy::Light)),
                    directions_density: drawn.directions.map(|_| density(Strategy::Directions)),
                    domains,
                    drawn,
                })
            }
        };
        Ok(Outcome {
            map,
            at_point,
            point,
            normal,
            outgoing,
        })
    });
    Computed {
        asked,
        round,
        outcome,
        duration: started.elapsed(),
    }
}

/// The context in `slot`, rebuilt if it is not for `scene` and `settings`,
/// looking through `camera`.
fn fresh_context<'a>(
    slot: &'a mut Option<RenderContext>,
    scene: &SharedScene,
    settings: &RenderSettings,
    camera: &Camera,
) -> &'a mut RenderContext {
    let fresh = slot
        .as_ref()
        .is_some_and(|c| Arc::ptr_eq(&c.scene, &scene.0) && c.settings == *settings);
    if !fresh {
        *slot = Some(RenderContext::new(Arc::clone(&scene.0), settings.clone()));
    }
    let context = slot.as_mut().expect("built above");
    context.set_camera(camera);
    context
}

/// The window of the integral at p (or at q, a path's second vertex),
/// while a pixel is probed and the view is shown; `area` keeps it off a
/// lesson's texts.
pub fn hemisphere_window(
    ctx: &egui::Context,
    view: &mut HemisphereView,
    pixel: Option<(u32, u32)>,
    request: &ViewRequest,
    area: egui::Rect,
) {
    let Some((x, y)) = pixel.filter(|_| view.shown) else {
        return;
    };
    let visible = request.settings.terms;
    let at_q = view.second_vertex((x, y), &request.camera).cloned();
    let vertex = view.vertex((x, y), &request.camera);
    let title = if at_q.is_some() {
        HEMISPHERE_WINDOW_TITLE_AT_Q
    } else {
        HEMISPHERE_WINDOW_TITLE
    };
    let mut open = true;
    egui::Window::new(title)
        .id(egui::Id::unique(HEMISPHERE_WINDOW_ID))
        .open(&mut open)
        .default_pos(area.left_top() + egui::vec2(8.0, 8.0))
        .default_width(MAP_POINTS)
        .constrain_to(area)
        .max_height(area.height() - 16.0)
        .default_height(area.height() - 16.0)
        .resizable(false)
        .show(ctx, |ui| {
            if let Some(q) = &at_q {
                map_ui::second_vertex_ui(ui, view, q);
            }
            map_ui::choices_ui(ui, view, visible);
            let Some(computed) = view.result.clone() else {
                ui.spinner();
                return;
            };
            if computed.asked.pixel != (x, y) || computed.vertex() != vertex {
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
                    let height = (area.height() - 110.0).max(120.0);
                    egui::ScrollArea::vertical()
                        .max_height(height)
                        .show(ui, |ui| {
                            if let Some(texture) = view.texture(ctx, &computed)
                                && let Some(coloured) = view.coloured()
                            {
                                map_ui::map_ui(
                                    ui,
                                    view,
                                    texture,
                                    coloured,
                                    outcome,
                                    computed.term(),
                                );
                            }
                            map_ui::numbers_ui(ui, &computed, outcome);
                            map_ui::samples_ui(ui, view, &computed, outcome);
                            lab_ui::lab_ui(ui, &mut view.lab, &outcome.at_point.drawn);
                        });
                }
            }
        });
    if !open {
        view.shown = false;
    }
}
