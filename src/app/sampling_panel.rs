//! The Sampling group: the integrator, the fast one's strategies, the
//! sampler, the presets and adaptive sampling, with what each choice does.

use eframe::egui;
use strum::IntoEnumIterator;

use crate::course::Choice;
use crate::course::{
    Adaptive, IndirectSampling, Integrator, LightSampling, LightSelection, MAX_SAMPLES_PER_VERTEX,
    MisHeuristic, RenderSettings, Sampler,
};

/// The estimators: how direct lighting, the next reflection and the random
/// numbers are drawn. Every choice is unbiased; only the noise differs.
pub fn sampling_ui(ui: &mut egui::Ui, settings: &mut RenderSettings) {
    egui::CollapsingHeader::new("Sampling")
        .default_open(true)
        .show(ui, |ui| {
            combo(ui, "integrator", &mut settings.integrator, integrator_hint);
            // the strategies below are the fast integrator's
            let fast = settings.integrator == Integrator::Fast;
            ui.add_enabled_ui(fast, |ui| strategies_ui(ui, settings));
            combo(ui, "sampler", &mut settings.sampler, sampler_hint);
            estimator_presets_ui(ui, settings);
            adaptive_ui(ui, &mut settings.adaptive);
        });
}

/// The two estimators a lecturer switches between: the default, the
/// fastest measured, and plain Monte Carlo, whose noise the lessons teach.
fn estimator_presets_ui(ui: &mut egui::Ui, settings: &mut RenderSettings) {
    ui.horizontal(|ui| {
        let fastest = RenderSettings::default();
        if ui
            .button("fastest (default)")
            .on_hover_text(
                "Sobol points and the pilot's continuations per first hit: \
                 the fastest to a given error that lumiere measured",
            )
            .clicked()
        {
            settings.sampler = fastest.sampler;
            settings.auto_indirect_samples = fastest.auto_indirect_samples;
        }
        if ui
            .button("plain Monte Carlo")
            .on_hover_text(
                "Independent numbers and one continuation per first hit: \
                 the noise of the course, falling as 1/√N",
            )
            .clicked()
        {
            settings.sampler = Sampler::Independent;
            settings.indirect_samples = 1;
            settings.auto_indirect_samples = false;
        }
    });
}

/// The fast integrator's estimators: direct and indirect strategies, MIS
/// weights, samples per vertex, splitting and light selection.
fn strategies_ui(ui: &mut egui::Ui, settings: &mut RenderSettings) {
    combo(
        ui,
        "direct (L1)",
        &mut settings.light_sampling,
        light_sampling_hint,
    );
    ui.add_enabled_ui(settings.light_sampling == LightSampling::Mis, |ui| {
        ui.horizontal(|ui| {
            ui.label("MIS weights");
            for heuristic in MisHeuristic::iter() {
                ui.radio_value(&mut settings.mis_heuristic, heuristic, heuristic.label())
                    .on_hover_text(match heuristic {
                        MisHeuristic::Balance => "w = p_light / (p_light + p_brdf)",
                        MisHeuristic::Power => "w = p_light² / (p_light² + p_brdf²)",
                    });
            }
        });
    });
    combo(
        ui,
        "indirect (L2, L3+)",
        &mut settings.indirect_sampling,
        indirect_sampling_hint,
    );
    ui.horizontal(|ui| {
        ui.add(
            egui::DragValue::new(&mut settings.light_samples)
                .range(1..=MAX_SAMPLES_PER_VERTEX)
                .prefix("light samples "),
        )
        .on_hover_text(
            "Light samples per vertex (shadow rays, or gathered directions), each weighted 1/N",
        );
        ui.add_enabled(
            !settings.auto_indirect_samples,
            egui::DragValue::new(&mut settings.indirect_samples)
                .range(1..=MAX_SAMPLES_PER_VERTEX)
                .prefix("indirect samples "),
        )
        .on_hover_text("Continuations per first hit (splitting), each weighted 1/M");
        ui.checkbox(&mut settings.auto_indirect_samples, "auto")
            .on_hover_text(
                "Let a short pilot choose the continuations per first hit that \
                         reach a given relative error soonest (more when the indirect \
                         light is the noisier part)",
            );
    });
    ui.horizontal(|ui| {
        ui.label("pick lights");
        for selection in LightSelection::iter() {
            ui.radio_value(&mut settings.light_selection, selection, selection.label())
                .on_hover_text(match selection {
                    LightSelection::Uniform => "Every light with the same probability",
                    LightSelection::Power => "In proportion to emitted power",
                });
        }
    });
}

fn integrator_hint(integrator: Integrator) -> &'static str {
    match integrator {
        Integrator::Lecture => {
            "The lecture's estimator (transport/lecture.rs): L0 + L1 + L2 + L3+ as the slides \
             write them, one light sample and one BRDF direction per point; the strategies \
             below do not apply. The path view still draws the fast integrator's paths."
        }
        Integrator::Fast => {
            "The fast path tracer (transport/fast.rs): the strategies below, MIS, splitting \
             and skipped work; it agrees with the lecture's estimator in the mean"
        }
    }
}

/// Adaptive sampling: a checkbox, then the threshold (in percent) and the
/// samples every pixel gets first.
fn adaptive_ui(ui: &mut egui::Ui, adaptive: &mut Option<Adaptive>) {
    ui.horizontal(|ui| {
        let mut on = adaptive.is_some();
        ui.checkbox(&mut on, "adaptive").on_hover_text(
            "Stop sampling a pixel's term once its standard error falls below a fraction \
             of the pixel's value. Leave it off to compare noise: every pixel then gets \
             the same samples.",
        );
        if on != adaptive.is_some() {
            *adaptive = on.then(Adaptive::default);
        }
        if let Some(adaptive) = adaptive {
            let mut percent = adaptive.threshold * 100.0;
            let threshold = ui
                .add(
                    egui::DragValue::new(&mut percent)
                        .range(0.01..=100.0)
                        .speed(0.05)
                        .suffix(" %"),
                )
                .on_hover_text("Standard error at which a pixel's term stops, relative to the pixel's luminance");
            if threshold.changed() {
                adaptive.threshold = percent / 100.0;
            }
            ui.add(
                egui::DragValue::new(&mut adaptive.min_samples)
                    .range(Adaptive::MIN_SAMPLES..=65536)
                    .prefix("min spp "),
            )
            .on_hover_text("Samples every pixel gets before its error is judged");
        }
    });
}

/// A combo box over a closed set, with a hint per value.
fn combo<T: Choice + PartialEq>(
    ui: &mut egui::Ui,
    label: &str,
    value: &mut T,
    hint: fn(T) -> &'static str,
) {
    egui::ComboBox::from_label(label)
        .selected_text(value.label())
        .show_ui(ui, |ui| {
            for v in T::iter() {
                ui.selectable_value(value, v, v.label())
                    .on_hover_text(hint(v));
            }
        })
        .response
        .on_hover_text(hint(*value));
}

fn light_sampling_hint(strategy: LightSampling) -> &'static str {
    match strategy {
        LightSampling::Area => {
            "Uniform points on the light: pdf = d² / (A cos θ_light) in solid angle.\nNoisy near large lights, where d² is small."
        }
        LightSampling::SolidAngle => {
            "Uniform directions in the solid angle the light subtends (spherical triangles): pdf = 1/Ω.\nArea sampling for tiny or huge angles."
        }
        LightSampling::Brdf => {
            "Sample the BRDF and count the directions that hit a light: pdf ∝ f cos θ.\nGood for glossy surfaces and large lights; blind to point lights."
        }
        LightSampling::Hemisphere => {
            "Uniform directions on the hemisphere, pdf = 1/2π: only those that happen to see the source count.\nThe noisiest."
        }
        LightSampling::Mis => {
            "Light and BRDF samples, each weighted by multiple importance sampling: robust everywhere."
        }
    }
}

fn indirect_sampling_hint(strategy: IndirectSampling) -> &'static str {
    match strategy {
        IndirectSampling::Uniform => "pdf = 1/2π over the hemisphere",
        IndirectSampling::Cosine => "pdf = cos θ / π: exact for Lambert's f cos θ",
        IndirectSampling::Brdf => {
            "The BRDF's own sampling (cosine for Lambert, the lobe for Phong, the mirror direction)"
        }
    }
}

fn sampler_hint(sampler: Sampler) -> &'static str {
    match sampler {
        Sampler::Independent => "Independent uniform numbers: error falls as 1/√N",
        Sampler::Stratified => "Jittered strata over blocks of 16 samples",
        Sampler::Sobol => {
            "Owen-scrambled Sobol points (the default): lower error for smooth integrands"
        }
    }
}
