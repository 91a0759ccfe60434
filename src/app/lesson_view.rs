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
    /// Steps opened so far: each opening asks for a new film
    /// (`ViewRequest::film`), even when only the terms change.
    pub opened: u64,
}

/// The key that enters and leaves presentation mode.
pub const PRESENT_KEY: egui::Key = egui::Key::F5;

/// What the Lesson group asks the app to do: both replace the scene and
/// the settings.
pub enum LessonAction {
    /// Open the built-in lesson or the lesson file of this name, on its first step.
    Open(String),
    /// Show this step of the open lesson.
    ShowStep(usize),
}

/// The Lesson group: open a built-in lesson or a file, step through it,
/// choose the language, present, the interface's scale. Edits `state`;
/// opening and stepping come back as an action for the app.
pub fn lesson_ui(
    ui: &mut egui::Ui,
    state: &mut LessonState,
    ui_scale: &mut f32,
) -> Option<LessonAction> {
    let mut action = None;
    egui::CollapsingHeader::new("Lesson")
        .default_open(state.lesson.is_some())
        .show(ui, |ui| {
            let open_name = state.lesson.as_ref().map(|l| l.name.clone());
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
            // a lesson file of one's own, by its path (not in a browser)
            if super::files::READS_PATHS {
                ui.horizontal(|ui| {
                    let field = ui.add(
                        egui::TextEdit::singleline(&mut state.file_field)
                            .hint_text("lesson.toml")
                            .desired_width(150.0),
                    );
                    let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    if (ui.button("Open").clicked() || enter) && !state.file_field.is_empty() {
                        chosen = Some(state.file_field.clone());
                    }
                });
            }
            if let Some(name) = chosen {
                action = Some(LessonAction::Open(name));
            }
            let Some(lesson) = state.lesson.clone() else {
                return;
            };
            ui.horizontal(|ui| {
                let step = state.step;
                if ui
                    .add_enabled(step > 0, egui::Button::new("◀"))
                    .on_hover_text("Previous step (← or PageUp)")
                    .clicked()
                {
                    action = Some(LessonAction::ShowStep(step - 1));
                }
                ui.label(format!("step {} of {}", step + 1, lesson.steps.len()));
                if ui
                    .add_enabled(step + 1 < lesson.steps.len(), egui::Button::new("▶"))
                    .on_hover_text("Next step (→ or PageDown)")
                    .clicked()
                {
                    action = Some(LessonAction::ShowStep(step + 1));
                }
                if ui
                    .button("Close")
                    .on_hover_text("Close the lesson")
                    .clicked()
                {
                    state.lesson = None;
                }
            });
            ui.horizontal(|ui| {
                for lang in [Lang::Fr, Lang::En] {
                    ui.radio_value(&mut state.lang, lang, lang.to_string());
                }
                ui.checkbox(&mut state.presenting, "present").on_hover_text(
                    "Presentation mode (F5): no side panel, the interface scaled for a projector",
                );
            });
            ui.add(egui::Slider::new(ui_scale, 0.75..=3.0).text("interface scale"))
                .on_hover_text("The size of the whole interface, in presentation mode too");
        });
    action
}

/// Does what the Lesson group asked: a lesson that cannot be read leaves
/// everything as it is, and says why.
pub fn act(app: &mut LumiereApp, action: LessonAction) {
    match action {
        LessonAction::Open(name) => match Lesson::load(&name) {
            Ok(lesson) => open(app, lesson, 0),
            Err(e) => app.message = Some(format!("error: {e}")),
        },
        LessonAction::ShowStep(step) => show_step(app, step),
    }
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
    app.lesson.opened += 1;
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

/// A lesson step's texts, laid out: the title and the formula in a band
/// above the image, the caption in a band below it.
pub struct Bands {
    pub top: egui::Rect,
    pub bottom: egui::Rect,
    title: Arc<egui::Galley>,
    formula: Arc<egui::Galley>,
    caption: Arc<egui::Galley>,
    margin: f32,
}

/// The bands of the open lesson's step across `area`, the space the image
/// and its texts share: the image goes between them, so the texts never
/// cover the picture. Sizes follow the area's height, so that the texts
/// stay readable from the back of a room whatever the window.
pub fn bands(app: &LumiereApp, ctx: &egui::Context, area: egui::Rect) -> Option<Bands> {
    let lesson = app.lesson.lesson.as_ref()?;
    let step = &lesson.steps[app.lesson.step];
    let lang = app.lesson.lang;
    let unit = (area.height() / 28.0).clamp(11.0, 48.0);
    let margin = unit * 0.5;
    let width = area.width() - 2.0 * margin;
    let text = |string: String, size: f32, colour: egui::Color32| {
        ctx.fonts_mut(|fonts| fonts.layout(string, egui::FontId::proportional(size), colour, width))
    };
    let title = text(
        format!("{}. {}", app.lesson.step + 1, step.title.get(lang)),
        unit * 1.2,
        egui::Color32::WHITE,
    );
    let formula = text(step.formula.clone(), unit, FORMULA_COLOUR);
    let caption = text(
        step.caption.get(lang).to_owned(),
        unit * 0.8,
        egui::Color32::WHITE,
    );
    let top_height = title.size().y + formula.size().y + 3.0 * margin;
    let bottom_height = caption.size().y + 2.0 * margin;
    let top = egui::Rect::from_min_size(area.min, egui::vec2(area.width(), top_height));
    let bottom =
        egui::Rect::from_min_max(egui::pos2(area.min.x, area.max.y - bottom_height), area.max);
    Some(Bands {
        top,
        bottom,
        title,
        formula,
        caption,
        margin,
    })
}

/// The formula's colour, as on the exported slides.
const FORMULA_COLOUR: egui::Color32 = egui::Color32::from_rgb(255, 214, 153);

impl Bands {
    /// The space left for the image between the bands of `area`.
    pub fn image_area(&self, area: egui::Rect) -> egui::Rect {
        egui::Rect::from_min_max(
            egui::pos2(area.min.x, self.top.max.y),
            egui::pos2(area.max.x, self.bottom.min.y.max(self.top.max.y + 1.0)),
        )
    }

    /// Draws the texts in their bands.
    pub fn paint(&self, painter: &egui::Painter) {
        let margin = egui::vec2(self.margin, self.margin);
        let title_pos = self.top.min + margin;
        let formula_pos = title_pos + egui::vec2(0.0, self.title.size().y + self.margin);
        painter.galley(title_pos, Arc::clone(&self.title), egui::Color32::WHITE);
        painter.galley(formula_pos, Arc::clone(&self.formula), FORMULA_COLOUR);
        painter.galley(
            self.bottom.min + margin,
            Arc::clone(&self.caption),
            egui::Color32::WHITE,
        );
    }
}
