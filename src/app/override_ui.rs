//! The editor of B's changes in the Comparison group: one row per setting a
//! lecturer compares, each "as A" until a value is chosen.

use eframe::egui;

use crate::course::Choice;
use crate::course::{
    BrdfOverride, Integrator, LightMode, MAX_SAMPLES_PER_VERTEX, RenderSettings, Term,
};
use crate::render::settings_override::{SettingsOverride, terms_phrase};

/// The rows: light mode, material, terms, integrator, the estimators.
pub fn override_ui(ui: &mut egui::Ui, b: &mut SettingsOverride, a: &RenderSettings) {
    choice(ui, "B lights", &mut b.light_mode, a.light_mode, light_text);
    choice(ui, "B material", &mut b.brdf, a.brdf, brdf_text);
    terms_ui(ui, b, a);
    choice(ui, "B integrator", &mut b.integrator, a.integrator, |i| {
        i.label().into()
    });
    // the strategies are the fast integrator's
    let fast = b.integrator.unwrap_or(a.integrator) == Integrator::Fast;
    ui.add_enabled_ui(fast, |ui| {
        choice(
            ui,
            "B light sampling",
            &mut b.light_sampling,
            a.light_sampling,
            |v| v.label().into(),
        );
        choice(
            ui,
            "B indirect sampling",
            &mut b.indirect_sampling,
            a.indirect_sampling,
            |v| v.label().into(),
        );
        ui.horizontal(|ui| {
            count(ui, "light ×", &mut b.light_samples, a.light_samples);
            count(
                ui,
                "indirect ×",
                &mut b.indirect_samples,
                a.indirect_samples,
            );
        });
    });
    choice(ui, "B sampler", &mut b.sampler, a.sampler, |v| {
        v.label().into()
    });
    if !b.is_empty()
        && ui
            .button("B as A")
            .on_hover_text("B changes nothing")
            .clicked()
    {
        *b = SettingsOverride::default();
    }
}

/// A combo box: "as A (A's value)", then every value.
fn choice<T: Choice + PartialEq>(
    ui: &mut egui::Ui,
    label: &str,
    value: &mut Option<T>,
    a: T,
    text: impl Fn(T) -> String,
) {
    let as_a = format!("as A ({})", text(a));
    egui::ComboBox::from_label(label)
        .selected_text(value.map_or_else(|| as_a.clone(), &text))
        .show_ui(ui, |ui| {
            ui.selectable_value(value, None, as_a);
            for choice in T::iter() {
                ui.selectable_value(value, Some(choice), text(choice));
            }
        });
}

/// A sample count of B's, ticked to differ from A's.
fn count(ui: &mut egui::Ui, prefix: &str, value: &mut Option<u32>, a: u32) {
    let mut own = value.is_some();
    ui.checkbox(&mut own, "")
        .on_hover_text(format!("B's own count ({prefix} {a} in A)"));
    let mut n = value.unwrap_or(a);
    ui.add_enabled(
        own,
        egui::DragValue::new(&mut n)
            .range(1..=MAX_SAMPLES_PER_VERTEX)
            .prefix(prefix),
    );
    *value = own.then_some(n);
}

/// "as A", or B's own terms (at least one).
fn terms_ui(ui: &mut egui::Ui, b: &mut SettingsOverride, a: &RenderSettings) {
    ui.horizontal(|ui| {
        let mut own = b.terms.is_some();
        ui.checkbox(&mut own, "B terms").on_hover_text(format!(
            "B's own terms (A: {}); off: B shows A's terms",
            terms_phrase(a.terms)
        ));
        let mut terms = b.terms.unwrap_or(a.terms);
        ui.add_enabled_ui(own, |ui| {
            for term in Term::ALL {
                let mut on = terms.contains(term);
                if ui.checkbox(&mut on, term.label()).changed() {
                    let toggled = terms.with(term, on);
                    if !toggled.is_empty() {
                        terms = toggled;
                    }
                }
            }
        });
        b.terms = own.then_some(terms);
    });
}

fn light_text(mode: LightMode) -> String {
    match mode {
        LightMode::Authored => "as authored",
        LightMode::Point => "all point",
        LightMode::Area => "all extended",
    }
    .into()
}

fn brdf_text(brdf: BrdfOverride) -> String {
    match brdf {
        BrdfOverride::Authored => "as authored",
        BrdfOverride::Lambert => "Lambert",
        BrdfOverride::Phong => "Phong",
        BrdfOverride::Mirror => "mirror",
        BrdfOverride::Glass => "glass",
    }
    .into()
}
