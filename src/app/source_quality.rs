//! The Lights group's "a quality for each source": each source of the
//! scene switched on or off, with its own number of light samples per
//! vertex (`crate::transport::sources`).

use eframe::egui;

use crate::course::{MAX_SAMPLES_PER_VERTEX, RenderSettings, SourceQuality};
use crate::scene::Scene;
use crate::transport::sources;

/// Edits `settings.sources` for the sources of `scene`.
pub fn source_quality_ui(ui: &mut egui::Ui, settings: &mut RenderSettings, scene: &Scene) {
    let mut per_source = !settings.sources.is_empty();
    let names: Vec<String> = sources::sources(scene)
        .into_iter()
        .map(|key| key.name(scene).to_string())
        .collect();
    let toggle = ui
        .add_enabled(
            !names.is_empty(),
            egui::Checkbox::new(&mut per_source, "a quality for each source"),
        )
        .on_hover_text(
            "Each source gets its own light samples per vertex, drawn on it alone, \
             or is switched off (it then emits nothing). Off: the light samples are \
             shared among the sources by power.",
        );
    if toggle.changed() {
        settings.sources = if per_source {
            let samples = settings.light_samples;
            let mut qualities: Vec<SourceQuality> = Vec::new();
            for name in &names {
                if !qualities.iter().any(|q| &q.name == name) {
                    qualities.push(SourceQuality::samples(name, samples));
                }
            }
            qualities
        } else {
            Vec::new()
        };
    }
    if settings.sources.is_empty() {
        return;
    }
    let light_samples = settings.light_samples;
    for quality in &mut settings.sources {
        ui.horizontal(|ui| {
            ui.checkbox(&mut quality.on, quality.name.clone())
                .on_hover_text("off: the source emits nothing, in every term");
            let mut samples = quality.samples.unwrap_or(light_samples);
            let field = ui.add_enabled(
                quality.on,
                egui::DragValue::new(&mut samples)
                    .range(1..=MAX_SAMPLES_PER_VERTEX)
                    .suffix(" samples"),
            );
            if field.changed() {
                quality.samples = Some(samples);
            }
        });
    }
    let total: u32 = settings
        .sources
        .iter()
        .filter(|q| q.on)
        .map(|q| q.samples.unwrap_or(light_samples))
        .sum();
    ui.label(
        egui::RichText::new(format!("{total} light samples per vertex in all"))
            .weak()
            .small(),
    );
}
