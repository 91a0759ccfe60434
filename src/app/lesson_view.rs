//! A lesson in the viewer: the step shown, the keys that step through it
//! (→ or PageDown next, ← or PageUp previous, Home the first: a
//! presenter's clicker sends these), and its title, formula and caption
//! drawn over the image, large enough to read from the back of a room.

use std::sync::Arc;

use eframe::egui;

use super::LumiereApp;
use crate::lesson::{Lang, Lesson};

/// The lesson open in the viewer, if any, and where it is.
#[derive(Clone, Debug, Default)]
pub struct LessonState {
    pub lesson: Option<Arc<Lesson>>,
    /// The step shown, from 0.
    pub step: usize,
    pub lang: Lang,
    /// Presentation mode: no side panel, the interface scaled for a projector.
    pub presenting: bool,
    /// Text of the lesson file field.
    pub file_field: String,
    /// The height of the bands the texts cover at the top and the bottom
    /// of the image (points), as drawn last frame: the split's labels go
    /// between them.
    pub bands: (f32, f32),
}

/// The key that enters and leaves presentation mode.
pub const PRESENT_KEY: egui::Key = egui::Key::F5;

/// The Lesson group: open a built-in lesson or a file, step through it,
/// choose the language, present.
pub fn lesson_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Lesson")
        .default_open(app.lesson.lesson.is_some())
        .show(ui, |ui| {
            let open_name = app.lesson.lesson.as_ref().map(|l| l.name.clone());
            let mut chosen = None;
            egui::ComboBox::from_label("lesson")
                .selected_text(open_name.as_deref().unwrap_or("none"))
                .show_ui(ui, |ui| {
                    for (name, _) in crate::lesson::BUILTIN {
                        if ui
                            .selectable_label(open_name.as_deref() == Some(name), *name)
                            .clicked()
                        {
                            chosen = Some(name.to_string());
                        }
                    }
                })
                .response
                .on_hover_text("The built-in lessons: the course's lecture, step by step");
            ui.horizontal(|ui| {
                let field = ui.add(
                    egui::TextEdit::singleline(&mut app.lesson.file_field)
                        .hint_text("lesson.toml")
                        .desired_width(150.0),
                );
                let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                if (ui.button("Open").clicked() || enter) && !app.lesson.file_field.is_empty() {
                    chosen = Some(app.lesson.file_field.clone());
                }
            });
            if let Some(name) = chosen {
                // a lesson that cannot be read leaves everything as it is
                match Lesson::load(&name) {
                    Ok(lesson) => open(app, lesson, 0),
                    Err(e) => app.message = Some(format!("error: {e}")),
                }
            }
            let Some(lesson) = app.lesson.lesson.clone() else {
                return;
            };
            ui.horizontal(|ui| {
                let step = app.lesson.step;
                if ui
                    .add_enabled(step > 0, egui::Button::new("◀"))
                    .on_hover_text("Previous step (← or PageUp)")
                    .clicked()
                {
                    show_step(app, step - 1);
                }
                ui.label(format!("step {} of {}", step + 1, lesson.steps.len()));
                if ui
                    .add_enabled(step + 1 < lesson.steps.len(), egui::Button::new("▶"))
                    .on_hover_text("Next step (→ or PageDown)")
                    .clicked()
                {
                    show_step(app, step + 1);
                }
                if ui.button("Close").on_hover_text("Close the lesson").clicked() {
                    app.lesson.lesson = None;
                }
            });
            ui.horizontal(|ui| {
                for lang in [Lang::Fr, Lang::En] {
                    ui.radio_value(&mut app.lesson.lang, lang, lang.to_string());
                }
                ui.checkbox(&mut app.lesson.presenting, "present")
                    .on_hover_text("Presentation mode (F5): no side panel, the interface scaled for a projector");
            });
            ui.add(
                egui::Slider::new(&mut app.state.ui_scale, 0.75..=3.0)
                    .text("interface scale"),
            )
            .on_hover_text("The size of the whole interface, in presentation mode too");
        });
}

/// Opens `lesson` on step `step` (from 0; clamped to the last).
pub fn open(app: &mut LumiereApp, lesson: Lesson, step: usize) {
    app.lesson.lesson = Some(Arc::new(lesson));
    show_step(app, step);
}

/// Shows step `index` of the open lesson: its scene, settings, display,
/// sample count and split (A | B, or none) replace the current ones (the
/// film restarts).
pub fn show_step(app: &mut LumiereApp, index: usize) {
    let Some(lesson) = app.lesson.lesson.clone() else {
        return;
    };
    let index = index.min(lesson.steps.len() - 1);
    let (width, height) = (app.state.settings.width, app.state.settings.height);
    let view = match lesson.view(index, width, height) {
        Ok(view) => view,
        Err(e) => {
            app.message = Some(format!("error: step {}: {e}", index + 1));
            return;
        }
    };
    let fail = |app: &mut LumiereApp, e: &dyn std::fmt::Display| {
        app.message = Some(format!("error: step {}: {e}", index + 1));
    };
    // the step's scene, checked with its sources before anything changes
    let new_scene = if view.scene != app.scene_spec {
        match crate::scene::builtin::load(&view.scene) {
            Ok(scene) => Some(scene),
            Err(e) => return fail(app, &e),
        }
    } else {
        None
    };
    let scene = new_scene.as_ref().unwrap_or(&app.scene);
    if let Err(e) = crate::transport::sources::check(&view.settings, scene) {
        return fail(app, &format!("{}: {e}", view.scene));
    }
    app.lesson.step = index;
    if let Some(scene) = new_scene {
        app.show_scene(&view.scene, scene);
    }
    app.state.settings = view.settings;
    app.state.display = view.display;
    app.state.noise.mode = view.display_mode;
    app.state.stop_at_spp = Some(view.spp);
    if let Some((x, y)) = view.probe {
        app.probe.pick(x, y);
    }
    // the step's split, A | B, or none
    app.compare.enabled = view.split.is_some();
    if let Some(b) = view.split {
        app.compare.b = b;
    }
    app.message = Some(format!(
        "{} — step {} of {}",
        lesson.title.get(app.lesson.lang),
        index + 1,
        lesson.steps.len()
    ));
}

/// The keys of a presenter's clicker, while no text field has the focus,
/// and F5 for presentation mode.
pub fn shortcuts(app: &mut LumiereApp, ctx: &egui::Context) {
    if ctx.memory(|m| m.focused().is_some()) {
        return;
    }
    if ctx.input(|i| i.key_pressed(PRESENT_KEY)) {
        app.lesson.presenting = !app.lesson.presenting;
    }
    if app.lesson.lesson.is_none() {
        return;
    }
    let pressed = |keys: &[egui::Key]| ctx.input(|i| keys.iter().any(|&k| i.key_pressed(k)));
    let step = app.lesson.step;
    if pressed(&[egui::Key::ArrowRight, egui::Key::PageDown]) {
        show_step(app, step + 1);
    } else if pressed(&[egui::Key::ArrowLeft, egui::Key::PageUp]) {
        show_step(app, step.saturating_sub(1));
    } else if pressed(&[egui::Key::Home]) {
        show_step(app, 0);
    }
}

/// Draws the step's title and formula at the top of `image` and its caption
/// at the bottom, each on a dark band, in sizes relative to the image.
pub fn overlay(app: &mut LumiereApp, ctx: &egui::Context, image: egui::Rect) {
    let Some(lesson) = &app.lesson.lesson else {
        app.lesson.bands = (0.0, 0.0);
        return;
    };
    let step = &lesson.steps[app.lesson.step];
    let lang = app.lesson.lang;
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Foreground,
        egui::Id::unique("lesson overlay"),
    ));
    // sizes in proportion to the image, so that a projector's scale keeps them readable
    let unit = (image.height() / 24.0).clamp(12.0, 48.0);
    let margin = unit * 0.5;
    let width = image.width() - 2.0 * margin;
    let band = egui::Color32::from_black_alpha(170);
    let text = |string: &str, size: f32| {
        painter.layout(
            string.to_owned(),
            egui::FontId::proportional(size),
            egui::Color32::WHITE,
            width,
        )
    };
    let title = text(
        &format!("{}. {}", app.lesson.step + 1, step.title.get(lang)),
        unit * 1.2,
    );
    let formula = text(&step.formula, unit);
    let top = egui::Rect::from_min_size(
        image.min,
        egui::vec2(
            image.width(),
            title.size().y + formula.size().y + 3.0 * margin,
        ),
    );
    painter.rect_filled(top, 0.0, band);
    let title_pos = image.min + egui::vec2(margin, margin);
    let formula_pos = title_pos + egui::vec2(0.0, title.size().y + margin);
    painter.galley(title_pos, title, egui::Color32::WHITE);
    painter.galley(formula_pos, formula, egui::Color32::WHITE);

    let caption = text(step.caption.get(lang), unit * 0.8);
    let bottom = egui::Rect::from_min_max(
        egui::pos2(image.min.x, image.max.y - caption.size().y - 2.0 * margin),
        image.max,
    );
    painter.rect_filled(bottom, 0.0, band);
    painter.galley(
        bottom.min + egui::vec2(margin, margin),
        caption,
        egui::Color32::WHITE,
    );
    app.lesson.bands = (top.height(), bottom.height());
}
