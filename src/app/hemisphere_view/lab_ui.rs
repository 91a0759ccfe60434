//! The sampling lab in the window: many directions drawn at p by one
//! strategy, their histogram beside the density it should follow, and
//! the χ² verdict (`crate::analysis::sampling_lab`). It runs in the
//! background, once per choice, like the map's rounds.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use eframe::egui;

use crate::analysis::hemisphere::ShadingPoint;
use crate::analysis::hemisphere_colour::{ColouredMap, colour_values_up_to};
use crate::analysis::noise::{Scale, Unit, format_tick};
use crate::analysis::sampling_lab::{Against, SIGNIFICANCE, SamplingLab, sampling_lab};
use crate::analysis::strategy_samples::{DrawnSamples, Strategy};
use crate::course::RenderSettings;
use crate::platform::threads::{self, Job};
use crate::platform::time::Instant;

use super::map_ui::strategy_colour;
use super::{Asked, Contexts, MAP_POINTS, fresh_context};

/// Directions a lab draws, at most: beyond, the bins' integrals (to about
/// 10⁻⁵) are no longer finer than the counts' noise.
const MOST_LAB_SAMPLES: u32 = 200_000;

/// Side of the lab's two histograms, in pixels of the disk image.
const LAB_IMAGE_SIZE: u32 = 96;

/// What a lab is run for: two equal ones give the same counts.
#[derive(Clone, Debug, PartialEq)]
struct LabAsked {
    at: Asked,
    /// The view's own settings: the strategies the film draws with.
    samples_settings: RenderSettings,
    strategy: Strategy,
    against: Against,
    samples: u32,
    /// Which draw (a new seed each "draw again").
    draw: u64,
}

/// A lab's outcome and what it was run for.
pub struct LabComputed {
    asked: LabAsked,
    pub outcome: Result<SamplingLab, String>,
    pub duration: Duration,
}

/// The lab's choices and its latest outcome.
pub struct LabView {
    /// Runs while its section of the window is open.
    pub open: bool,
    pub strategy: Strategy,
    pub against: Against,
    pub samples: u32,
    draw: u64,
    pub result: Option<Arc<LabComputed>>,
    job: Option<Job<LabComputed>>,
    /// The drawn and the expected densities, coloured on one bar.
    textures: Option<(*const LabComputed, [egui::TextureHandle; 2], ColouredMap)>,
}

impl Default for LabView {
    fn default() -> Self {
        Self {
            open: false,
            strategy: Strategy::Light,
            against: Against::Own,
            samples: 50_000,
            draw: 0,
            result: None,
            job: None,
            textures: None,
        }
    }
}

impl LabView {
    /// Whether the lab shown is for what is asked now and no job runs.
    pub(super) fn is_settled(&self, at: &Asked, samples_settings: &RenderSettings) -> bool {
        !self.open
            || (self.job.is_none()
                && self
                    .result
                    .as_ref()
                    .is_some_and(|r| r.asked == self.asked(at, samples_settings)))
    }

    fn asked(&self, at: &Asked, samples_settings: &RenderSettings) -> LabAsked {
        LabAsked {
            at: at.clone(),
            samples_settings: samples_settings.clone(),
            strategy: self.strategy,
            against: self.against,
            samples: self.samples,
            draw: self.draw,
        }
    }

    /// Collects a finished lab; starts one for what is asked if it has
    /// not run yet.
    pub(super) fn update(
        &mut self,
        ctx: &egui::Context,
        at: &Asked,
        samples_settings: &RenderSettings,
        cache: &Arc<Mutex<Contexts>>,
    ) {
        if self.job.as_ref().is_some_and(|j| j.is_finished())
            && let Some(job) = self.job.take()
            && let Some(computed) = job.join()
        {
            self.result = Some(Arc::new(computed));
        }
        if !self.open || self.job.is_some() {
            return;
        }
        let asked = self.asked(at, samples_settings);
        if self.result.as_ref().is_some_and(|r| r.asked == asked) {
            return;
        }
        let cache = Arc::clone(cache);
        let repaint = super::super::waker::Waker::new(ctx);
        self.job = Some(threads::spawn("lumiere sampling lab", move || {
            let computed = run(asked, &cache);
            repaint.wake();
            computed
        }));
    }
}

/// The lab for `asked`, with the samples' context kept in `cache`.
fn run(asked: LabAsked, cache: &Mutex<Contexts>) -> LabComputed {
    let started = Instant::now();
    let mut cache = cache.lock().unwrap_or_else(|p| p.into_inner());
    let at = &asked.at;
    let context = fresh_context(
        &mut cache.samples,
        &at.scene,
        &asked.samples_settings,
        &at.camera,
    );
    let ray = at.vertex.ray(context, at.pixel);
    let outcome = match ShadingPoint::seen(context, &ray) {
        None => Err(format!("there is no surface at {}", at.vertex.name())),
        Some(p) => {
            let seed = asked.samples_settings.seed ^ asked.draw.wrapping_mul(0x9e37_79b9_7f4a_7c15);
            sampling_lab(
                context,
                &p,
                at.term,
                asked.strategy,
                asked.against,
                asked.samples,
                seed,
            )
            .map_err(|e| e.to_string())
        }
    };
    LabComputed {
        asked,
        outcome,
        duration: started.elapsed(),
    }
}

/// The lab's section of the window, under the film's samples (`drawn`
/// says which strategies draw here).
pub(super) fn lab_ui(ui: &mut egui::Ui, lab: &mut LabView, drawn: &DrawnSamples) {
    ui.separator();
    let header = egui::CollapsingHeader::new("Sampling lab: χ² of a strategy at p")
        .id_salt("hemisphere sampling lab")
        .open(Some(lab.open))
        .show(ui, |ui| {
            let available: Vec<Strategy> = [
                (Strategy::Light, drawn.light),
                (Strategy::Directions, drawn.directions),
            ]
            .into_iter()
            .filter_map(|(s, how)| how.map(|_| s))
            .collect();
            if !available.contains(&lab.strategy)
                && let Some(&first) = available.first()
            {
                lab.strategy = first;
            }
            ui.horizontal(|ui| {
                for strategy in &available {
                    let name = match strategy {
                        Strategy::Light => "light samples",
                        Strategy::Directions => "directions",
                    };
                    let text = egui::RichText::new(name).color(strategy_colour(*strategy));
                    ui.selectable_value(&mut lab.strategy, *strategy, text);
                }
                if !lab.against.applies(lab.strategy) {
                    lab.against = Against::Own;
                }
                egui::ComboBox::from_id_salt("sampling lab density")
                    .selected_text(format!("against {}", lab.against.name()))
                    .show_ui(ui, |ui| {
                        for against in Against::ALL.into_iter().filter(|a| a.applies(lab.strategy)) {
                            ui.selectable_value(&mut lab.against, against, against.name());
                        }
                    })
                    .response
                    .on_hover_text("The density the counts are compared with: the strategy's own, or a wrong one, to see the test reject it");
            });
            ui.horizontal(|ui| {
                ui.add(
                    egui::Slider::new(&mut lab.samples, 1_000..=MOST_LAB_SAMPLES)
                        .logarithmic(true)
                        .text("directions"),
                );
                if ui
                    .button("draw again")
                    .on_hover_text("New random numbers: with the right density, p is uniform on [0, 1] from draw to draw")
                    .clicked()
                {
                    lab.draw += 1;
                }
            });
            let Some(result) = lab.result.clone() else {
                ui.spinner();
                return;
            };
            if lab.job.is_some() {
                ui.spinner();
            }
            match &result.outcome {
                Err(e) => {
                    ui.label(format!("No test here: {e}."));
                }
                Ok(tested) => histograms_ui(ui, lab, &result, tested),
            }
        });
    if header.header_response.clicked() {
        lab.open = !lab.open;
    }
}

/// The drawn and the expected densities side by side, their bar, the verdict.
fn histograms_ui(
    ui: &mut egui::Ui,
    lab: &mut LabView,
    result: &Arc<LabComputed>,
    tested: &SamplingLab,
) {
    let ctx = ui.ctx().clone();
    if lab
        .textures
        .as_ref()
        .is_none_or(|(of, _, _)| *of != Arc::as_ptr(result))
    {
        let (drawn, expected) = tested.density_images(LAB_IMAGE_SIZE);
        let top = drawn.iter().chain(&expected).fold(0.0f32, |a, &b| a.max(b));
        let colour = |values| colour_values_up_to(values, LAB_IMAGE_SIZE, Scale::Linear, Some(top));
        let (drawn, expected) = (colour(drawn), colour(expected));
        let load = |name, coloured: &ColouredMap| {
            let size = [LAB_IMAGE_SIZE as usize; 2];
            let image = egui::ColorImage::from_rgba_unmultiplied(size, &coloured.srgba);
            ctx.load_texture(name, image, egui::TextureOptions::NEAREST)
        };
        let handles = [
            load("lumiere lab drawn", &drawn),
            load("lumiere lab expected", &expected),
        ];
        lab.textures = Some((Arc::as_ptr(result), handles, expected));
    }
    let Some((_, handles, coloured)) = &lab.textures else {
        return;
    };
    let side = MAP_POINTS / 2.0 - 4.0;
    ui.horizontal(|ui| {
        for (handle, caption) in handles.iter().zip(["drawn", "expected"]) {
            ui.vertical(|ui| {
                ui.add(egui::Image::new((handle.id(), egui::vec2(side, side))));
                ui.label(egui::RichText::new(caption).small());
            });
        }
    });
    ui.label(
        egui::RichText::new(format!(
            "density of the directions, 0 to {} (1/sr), in {} bins of equal solid angle",
            format_tick(coloured.range.1, Unit::Radiance),
            SamplingLab::BINS - 1
        ))
        .small()
        .weak(),
    );
    let chi2 = tested.chi2;
    let (verdict, colour) = if tested.accepted() {
        ("accepted", egui::Color32::from_rgb(120, 210, 120))
    } else {
        ("rejected", egui::Color32::from_rgb(240, 90, 80))
    };
    ui.label(
        egui::RichText::new(format!(
            "χ² = {:.1} with {} degrees of freedom: p = {:.3}, {verdict} at {:.0}%",
            chi2.statistic,
            chi2.dof,
            chi2.p_value,
            SIGNIFICANCE * 100.0
        ))
        .color(colour)
        .strong(),
    )
    .on_hover_text("P(χ² ≥ this) if the directions follow the density: a small p says they do not");
    let (elsewhere, expected) = tested.counts(SamplingLab::BINS - 1);
    ui.label(
        egui::RichText::new(format!(
            "∫ density over Ω⁺ = {:.4} · elsewhere (below the horizon, a point light, none drawn): {elsewhere} drawn, {expected:.1} expected · {} directions in {:.0} ms",
            tested.density_integral,
            tested.drawn,
            result.duration.as_secs_f64() * 1e3
        ))
        .small()
        .weak(),
    );
}
