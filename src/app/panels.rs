//! The viewer's widgets: side panel groups, status bar, shortcuts.
//! Each group edits the plain state it is given (the settings, the display
//! settings, the camera); `side_panel` hands each its part of the app, and
//! `LumiereApp::sync_renderer` then tells the worker what changed. Buttons
//! that change most of the app (a lesson's step, a reset) come back as
//! actions; the groups that load a scene, select an object or start B
//! take the app.

use eframe::egui;
use strum::IntoEnumIterator;

use super::{LumiereApp, Persisted, interact, reference, split};
use super::{lesson_view, noise_view};
use crate::analysis::noise::{DisplayMode, NoiseSource, Scale};
use crate::course::Choice;
use crate::course::{BrdfOverride, LightMode, MAX_IOR, RenderSettings, Term, TermSet};
use crate::render::display::{DisplaySettings, Tonemap};
use crate::render::progressive::Snapshot;
use crate::scene::{Camera, Scene};
use std::sync::Arc;

/// French name and formula of each term, shown on hover (from the course).
fn term_tooltip(term: Term) -> &'static str {
    match term {
        Term::L0 => {
            "Emission (fr: émission)\nL0(p, ωo) = Le(p, ωo)\nThe light emitted by the surface the camera sees.\n\
             Computed in transport/lecture.rs: emission"
        }
        Term::L1 => {
            "Direct lighting (fr: éclairage direct)\nL1 = Σ_s ∫_Ωs Le(q, −ω) fr(p, ω→ωo) |cos θ| dω\nLight from the sources, reflected once (or refracted once: a refraction counts as a reflection).\n\
             Mirror and glass cannot sample a light: their L1 is the light seen in their one direction.\n\
             Computed in transport/lecture.rs: direct_lighting"
        }
        Term::L2 => {
            "Indirect lighting (fr: éclairage indirect)\nL2 = ∫_(Ω+ − ΩS) L_direct(q, −ω) fr(p, ω→ωo) |cos θ| dω\nLight reflected twice: q's direct lighting, reflected at p.\n\
             A light seen through a glass block is L2 (two refractions).\n\
             Computed in transport/lecture.rs: radiance_by_term (l[2] = …), from bounce and direct_lighting at q"
        }
        Term::L3Plus => {
            "Three reflections or more (fr: trois réflexions et plus)\nL3+ = L − L0 − L1 − L2\nThe rest of the full solution.\n\
             The room seen through glass, and a caustic under it (light → glass → glass → floor → eye), are L3.\n\
             Computed in transport/lecture.rs: beyond_two_reflections"
        }
    }
}

/// Keyboard: 0–3 toggle L0–L3+, 4 the four-up layout, L cycles the light
/// mode, B the BRDF, V the display mode, P the probe tool, Space pauses,
/// Ctrl+S saves a screenshot.
pub fn shortcuts(app: &mut LumiereApp, ctx: &egui::Context) {
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    let pressed = |key| ctx.input(|i| i.key_pressed(key) && !i.modifiers.command);
    for (key, term) in [
        (egui::Key::Num0, Term::L0),
        (egui::Key::Num1, Term::L1),
        (egui::Key::Num2, Term::L2),
        (egui::Key::Num3, Term::L3Plus),
    ] {
        if pressed(key) {
            toggle_term(&mut app.state.settings.terms, term);
        }
    }
    let settings = &mut app.state.settings;
    if pressed(egui::Key::L) {
        settings.light_mode = next(&LightMode::all(), settings.light_mode);
    }
    if pressed(egui::Key::B) {
        settings.brdf = next(&BrdfOverride::all(), settings.brdf);
    }
    if pressed(egui::Key::Space) {
        app.paused = !app.paused;
    }
    if pressed(egui::Key::V) {
        let modes: Vec<DisplayMode> =
            noise_view::available_modes(app.reference.is_some()).collect();
        app.state.noise.mode = next(&modes, app.state.noise.mode);
    }
    if pressed(egui::Key::P) {
        app.probe_tool = !app.probe_tool;
    }
    if pressed(egui::Key::Num4) {
        super::four_up_view::toggle(app);
    }
    if ctx.input_mut(|i| i.consume_key(egui::Modifiers::COMMAND, egui::Key::S)) {
        app.save_screenshot();
    }
    if ctx.input_mut(|i| i.consume_key(egui::Modifiers::COMMAND, egui::Key::O)) {
        super::scene_panel::open_file(app);
    }
}

fn next<T: Copy + PartialEq>(all: &[T], current: T) -> T {
    let index = all.iter().position(|&v| v == current).unwrap_or(0);
    all[(index + 1) % all.len()]
}

/// Switches `term` on or off, keeping at least one term on.
fn toggle_term(terms: &mut TermSet, term: Term) {
    let toggled = terms.with(term, !terms.contains(term));
    if !toggled.is_empty() {
        *terms = toggled;
    }
}

pub fn status_bar(app: &LumiereApp, ui: &mut egui::Ui, snapshot: &Snapshot) {
    egui::Panel::bottom("status").show(ui, |ui| {
        ui.horizontal_wrapped(|ui| {
            let state = if app.paused {
                "paused"
            } else if snapshot.preview {
                "preview"
            } else if snapshot.idle {
                "done"
            } else {
                "rendering"
            };
            ui.label(format!("{} spp", snapshot.samples_per_pixel()));
            ui.separator();
            ui.label(format!("{:.1} s", snapshot.elapsed.as_secs_f64()));
            ui.separator();
            ui.label(format!(
                "{:.2} M samples/s",
                snapshot.samples_per_second() / 1e6
            ));
            ui.separator();
            ui.label(format!("{:.1} Mrays/s", snapshot.mrays_per_second()));
            ui.separator();
            if snapshot.source.as_ref().is_some_and(|s| s.settings.auto_indirect_samples) {
                ui.label(format!("indirect ×{} (auto)", snapshot.continuations.label()))
                    .on_hover_text(
                        "Continuations per first hit chosen by the splitting pilot, \
                         region by region: more where the indirect light is most of the noise",
                    );
                ui.separator();
            }
            let rays = snapshot.rays;
            let per_term: Vec<String> = Term::ALL
                .iter()
                .map(|t| format!("{} {}", t.label(), rays.per_term[t.index()]))
                .collect();
            ui.label(format!("rays: {}", per_term.join(", "))).on_hover_text(format!(
                "Rays traced since the last restart, filed under the lowest term each serves.\nBy kind: {} camera, {} shadow, {} gathered (to find lights), {} bounce",
                rays.camera, rays.shadow, rays.gather, rays.bounce
            ));
            ui.separator();
            let skipped = rays.skipped;
            ui.label(format!("skipped {} rays", skipped.rays()))
                .on_hover_text(format!(
                    "Work the settings and the scene made unnecessary, since the last restart: {}",
                    skipped.describe()
                ));
            ui.separator();
            let invalid = rays.invalid_samples;
            let text = format!("{invalid} invalid");
            let hint = "Samples with a NaN, infinite or negative value, dropped (zeroed) before the film: it should stay 0";
            if invalid == 0 {
                ui.label(text).on_hover_text(hint);
            } else {
                ui.colored_label(ui.visuals().warn_fg_color, text)
                    .on_hover_text(hint);
            }
            ui.separator();
            ui.label(state);
            if let Some(message) = &app.message {
                ui.separator();
                ui.label(message);
            }
        });
    });
}

pub fn side_panel(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::Panel::left("controls")
        .default_size(300.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                let lesson = lesson_view::lesson_ui(ui, &mut app.lesson, &mut app.state.ui_scale);
                if let Some(action) = lesson {
                    lesson_view::act(app, action);
                }
                terms_ui(ui, &mut app.state.settings.terms);
                lights_ui(
                    ui,
                    &mut app.state.settings,
                    &mut app.scene,
                    &mut app.emitter_areas,
                );
                materials_ui(ui, &mut app.state.settings);
                super::sampling_panel::sampling_ui(ui, &mut app.state.settings);
                interact::selection_ui(app, ui);
                camera_ui(ui, &app.scene, &mut app.camera, &mut app.orbit);
                display_ui(app, ui);
                match render_ui(ui, &mut app.state, &mut app.paused) {
                    Some(RenderAction::SaveScreenshot) => app.save_screenshot(),
                    Some(RenderAction::SaveAsShown) => app.save_as_shown(),
                    Some(RenderAction::ResetToDefaults) => app.reset_to_defaults(),
                    None => {}
                }
                super::scene_panel::scene_ui(app, ui);
                reference::error_ui(app, ui);
                split::compare_ui(app, ui);
            });
        });
}

/// The terms' checkboxes.
fn terms_ui(ui: &mut egui::Ui, terms: &mut TermSet) {
    egui::CollapsingHeader::new("Terms")
        .default_open(true)
        .show(ui, |ui| {
            for term in Term::ALL {
                let mut on = terms.contains(term);
                ui.horizontal(|ui| {
                    let response = ui
                        .checkbox(&mut on, term.label())
                        .on_hover_text(term_tooltip(term));
                    ui.label(egui::RichText::new(term.description()).weak().small())
                        .on_hover_text(term_tooltip(term));
                    if response.changed() {
                        toggle_term(terms, term);
                    }
                });
            }
        });
}

/// The light mode, the spheres' radius, each light's power (which edits
/// `scene`) and each source's quality.
fn lights_ui(
    ui: &mut egui::Ui,
    settings: &mut RenderSettings,
    scene: &mut Arc<Scene>,
    emitter_areas: &mut interact::EmitterAreas,
) {
    egui::CollapsingHeader::new("Lights").default_open(true).show(ui, |ui| {
        for (mode, text, hint) in [
            (LightMode::Authored, "As authored", "The scene's own lights"),
            (
                LightMode::Point,
                "All point",
                "Every area light becomes a point light at its centroid, same power: hard shadows",
            ),
            (
                LightMode::Area,
                "All extended",
                "Every point light becomes a sphere light, same power: soft shadows",
            ),
        ] {
            ui.radio_value(&mut settings.light_mode, mode, text).on_hover_text(hint);
        }
        let diagonal = scene.bounds().diagonal().max(1e-3);
        let mut radius = settings.light_radius.unwrap_or(0.02 * diagonal);
        let slider = egui::Slider::new(&mut radius, (1e-3 * diagonal)..=(0.25 * diagonal))
            .logarithmic(true)
            .text("radius (m)");
        let enabled = settings.light_mode == LightMode::Area;
        let radius_changed = ui
            .add_enabled(enabled, slider)
            .on_hover_text("Radius of the sphere lights; their power stays the same, only the shadows change")
            .changed();
        if radius_changed {
            settings.light_radius = Some(radius);
        }
        ui.label(egui::RichText::new("power of each light").weak().small());
        interact::light_power_ui(ui, settings, scene, emitter_areas);
        super::source_quality::source_quality_ui(ui, settings, scene);
    });
}

/// Every material's model (the BRDF override), Phong's exponent, glass's η.
fn materials_ui(ui: &mut egui::Ui, settings: &mut RenderSettings) {
    egui::CollapsingHeader::new("Materials")
        .default_open(true)
        .show(ui, |ui| {
            egui::ComboBox::from_label("BRDF")
                .selected_text(brdf_text(settings.brdf))
                .show_ui(ui, |ui| {
                    for brdf in BrdfOverride::iter() {
                        let choice = ui.selectable_value(&mut settings.brdf, brdf, brdf_text(brdf));
                        if brdf == BrdfOverride::Glass {
                            choice.on_hover_text(interact::GLASS_TOOLTIP);
                        }
                    }
                });
            ui.add_enabled(
                settings.brdf == BrdfOverride::Phong,
                egui::Slider::new(&mut settings.phong_exponent, 1.0..=10_000.0)
                    .logarithmic(true)
                    .text("Phong exponent"),
            );
            ui.add_enabled(
                settings.brdf == BrdfOverride::Glass,
                egui::Slider::new(&mut settings.glass_ior, 1.0..=MAX_IOR)
                    .text("glass η")
                    .custom_formatter(|v, _| format!("{v:.2}")),
            )
            .on_hover_text("Index of refraction of --brdf glass: water 1.33, glass 1.5, diamond 2.42 (authored glass keeps its own)");
        });
}

fn brdf_text(brdf: BrdfOverride) -> &'static str {
    match brdf {
        BrdfOverride::Authored => "As authored",
        BrdfOverride::Lambert => "Lambert",
        BrdfOverride::Phong => "Phong",
        BrdfOverride::Mirror => "Mirror",
        BrdfOverride::Glass => "Glass",
    }
}

/// The scene's cameras, and back to its first (a new camera forgets the orbit).
fn camera_ui(ui: &mut egui::Ui, scene: &Scene, camera: &mut Camera, orbit: &mut interact::Orbit) {
    egui::CollapsingHeader::new("Camera")
        .default_open(false)
        .show(ui, |ui| {
            egui::ComboBox::from_label("view")
                .selected_text(camera.name.clone())
                .show_ui(ui, |ui| {
                    for choice in &scene.cameras {
                        let name = choice.name.clone();
                        if ui.selectable_value(camera, choice.clone(), name).clicked() {
                            *orbit = interact::Orbit::default();
                        }
                    }
                });
            if ui
                .button("Reset")
                .on_hover_text("Back to the scene's first camera")
                .clicked()
            {
                *camera = scene.default_camera();
                *orbit = interact::Orbit::default();
            }
            ui.label(
                egui::RichText::new(
                    "drag: orbit · right/middle drag: pan · scroll: dolly · click: select",
                )
                .weak()
                .small(),
            );
        });
}

/// The zoom, the exposure and tonemap, the noise views and the probe, the layout.
fn display_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Display")
        .default_open(true)
        .show(ui, |ui| {
            app.zoom.ui(ui);
            exposure_ui(ui, &mut app.state.display, &mut app.state.auto_exposure);
            noise_ui(app, ui);
            super::four_up_view::layout_ui(app, ui);
        });
}

/// The exposure, by hand or from the image, and the tonemap.
fn exposure_ui(ui: &mut egui::Ui, display: &mut DisplaySettings, auto_exposure: &mut bool) {
    ui.horizontal(|ui| {
        ui.add_enabled(
            !*auto_exposure,
            egui::Slider::new(&mut display.exposure, -10.0..=10.0).text("exposure (EV)"),
        );
        ui.checkbox(auto_exposure, "auto EV")
            .on_hover_text("Set the exposure from the image: its mean luminance shown as mid-grey (L2 alone is dark)");
    });
    egui::ComboBox::from_label("tonemap")
        .selected_text(display.tonemap.label())
        .show_ui(ui, |ui| {
            for tonemap in Tonemap::iter() {
                ui.selectable_value(&mut display.tonemap, tonemap, tonemap.label());
            }
        });
}

/// The display mode (image or a noise view), whose samples, the scale, the probe tool.
fn noise_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    let has_reference = app.reference.is_some();
    let noise = &mut app.state.noise;
    ui.horizontal(|ui| {
        egui::ComboBox::from_label("mode")
            .selected_text(noise.mode.title())
            .show_ui(ui, |ui| {
                for mode in noise_view::available_modes(has_reference) {
                    ui.selectable_value(&mut noise.mode, mode, mode.title());
                }
            })
            .response
            .on_hover_text(
                "V: the image, or the noise of each pixel's luminance in false colour\n\
                 (standard error, relative error, samples per pixel; image − reference with a reference)",
            );
        ui.add_enabled_ui(noise_view::has_source(noise.mode), |ui| {
            egui::ComboBox::from_label("of")
                .selected_text(noise.source.label())
                .show_ui(ui, |ui| {
                    for source in NoiseSource::ALL {
                        ui.selectable_value(&mut noise.source, source, source.label());
                    }
                })
                .response
                .on_hover_text(
                    "One term, or the visible terms summed (their errors add in quadrature)",
                );
        });
    });
    ui.horizontal(|ui| {
        let can_log = matches!(
            noise.mode,
            DisplayMode::StandardError | DisplayMode::RelativeError
        );
        let mut log = noise.scale == Scale::Log;
        if ui
            .add_enabled(can_log, egui::Checkbox::new(&mut log, "log scale"))
            .on_hover_text("Colours by orders of magnitude, from the 1st to the 99th percentile")
            .changed()
        {
            noise.scale = if log { Scale::Log } else { Scale::Linear };
        }
        ui.toggle_value(&mut app.probe_tool, "Probe").on_hover_text(
            "P: a click on the image probes the pixel instead of selecting an object (Ctrl+click always probes)",
        );
        if app.probe.pixel.is_some() && ui.button("Clear probe").clicked() {
            app.probe.close();
        }
    });
    if let Some(problem) = &app.noise_view.problem {
        ui.colored_label(ui.visuals().warn_fg_color, problem);
    }
}

/// What a button of the Render group asks the app to do.
enum RenderAction {
    SaveScreenshot,
    SaveAsShown,
    ResetToDefaults,
}

/// Pause, the exports, the stop, the film's size, bounces and seed, where
/// files go; a button's action for the app.
fn render_ui(ui: &mut egui::Ui, state: &mut Persisted, paused: &mut bool) -> Option<RenderAction> {
    let mut action = None;
    egui::CollapsingHeader::new("Render")
        .default_open(true)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                let text = if *paused { "Resume" } else { "Pause" };
                if ui.button(text).on_hover_text("Space").clicked() {
                    *paused = !*paused;
                }
                if ui
                    .button("Save screenshot")
                    .on_hover_text("Ctrl+S: PNG as displayed, EXR, settings")
                    .clicked()
                {
                    action = Some(RenderAction::SaveScreenshot);
                }
            });
            if shown_size_ui(ui, &mut state.shown_size) {
                action = Some(RenderAction::SaveAsShown);
            }
            if ui
                .button("Reset to defaults")
                .on_hover_text(
                    "Every setting back to lumiere's defaults, the scene reloaded without its edits \
                     (settings are kept between runs otherwise)",
                )
                .clicked()
            {
                action = Some(RenderAction::ResetToDefaults);
            }
            ui.horizontal(|ui| {
                let mut stop = state.stop_at_spp.is_some();
                let label = ui.checkbox(&mut stop, "stop at");
                let mut spp = state.stop_at_spp.unwrap_or(256);
                ui.add_enabled(
                    stop,
                    egui::DragValue::new(&mut spp)
                        .range(1..=1_000_000)
                        .suffix(" spp"),
                )
                .labelled_by(label.id);
                state.stop_at_spp = stop.then_some(spp);
            });
            let settings = &mut state.settings;
            ui.horizontal(|ui| {
                let width = ui.label("width");
                ui.add(egui::DragValue::new(&mut settings.width).range(16..=4096))
                    .labelled_by(width.id);
                let height = ui.label("height");
                ui.add(egui::DragValue::new(&mut settings.height).range(16..=4096))
                    .labelled_by(height.id);
            });
            ui.add(
                egui::DragValue::new(&mut settings.max_bounces)
                    .range(1..=1000)
                    .prefix("max bounces "),
            );
            ui.add(egui::DragValue::new(&mut settings.seed).prefix("seed "));
            ui.checkbox(&mut state.per_term_exr, "also one EXR per term");
            if super::files::READS_PATHS {
                ui.horizontal(|ui| {
                    let label = ui.label("save to");
                    ui.text_edit_singleline(&mut state.export_dir)
                        .labelled_by(label.id);
                });
            } else {
                ui.label("saved files go to the browser's downloads");
            }
        });
    action
}

/// "Save as shown" and the size of its picture: true when clicked.
fn shown_size_ui(ui: &mut egui::Ui, shown_size: &mut (u32, u32)) -> bool {
    use crate::tools::slides::shown::{MAX_SIDE, MIN_SIDE};
    ui.horizontal(|ui| {
        let clicked = ui
            .button("Save as shown")
            .on_hover_text(
                "One PNG of the picture as shown — the image, or a noise view with its colour bar, \
                 A | B, the four-up, the probe's rays, a lesson step's title, formula and caption \
                 laid out as its slide — at this size, with the settings (JSON)",
            )
            .clicked();
        let (width, height) = shown_size;
        let sides = MIN_SIDE..=MAX_SIDE;
        ui.add(egui::DragValue::new(width).range(sides.clone()))
            .on_hover_text("The picture's width, in pixels");
        ui.label("×");
        ui.add(egui::DragValue::new(height).range(sides))
            .on_hover_text("The picture's height, in pixels");
        clicked
    })
    .inner
}

#[cfg(test)]
mod tests {
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;

    use super::*;

    /// The Terms group edits the terms it is given, with no app around it,
    /// and never lets the last visible term go.
    #[test]
    fn the_terms_group_toggles_the_terms_it_is_given() {
        let mut harness = Harness::new_ui_state(
            |ui, terms: &mut TermSet| terms_ui(ui, terms),
            TermSet::only(Term::L1),
        );
        harness.get_by_label("L2").click();
        harness.run();
        assert_eq!(
            *harness.state(),
            TermSet::only(Term::L1).with(Term::L2, true)
        );
        harness.get_by_label("L2").click();
        harness.run();
        harness.get_by_label("L1").click();
        harness.run();
        assert_eq!(
            *harness.state(),
            TermSet::only(Term::L1),
            "one term stays on"
        );
    }

    /// The Render group's buttons come back as actions for the app.
    #[test]
    fn the_render_group_returns_its_buttons_actions() {
        let mut harness = Harness::new_ui_state(
            |ui, (state, paused, asked): &mut (Persisted, bool, Vec<&'static str>)| match render_ui(
                ui, state, paused,
            ) {
                Some(RenderAction::SaveScreenshot) => asked.push("screenshot"),
                Some(RenderAction::SaveAsShown) => asked.push("as shown"),
                Some(RenderAction::ResetToDefaults) => asked.push("defaults"),
                None => {}
            },
            (Persisted::default(), false, Vec::new()),
        );
        for button in [
            "Pause",
            "Save screenshot",
            "Save as shown",
            "Reset to defaults",
        ] {
            harness.get_by_label(button).click();
            harness.run();
        }
        let (_, paused, asked) = harness.state();
        assert!(*paused);
        assert_eq!(asked, &["screenshot", "as shown", "defaults"]);
    }
}
