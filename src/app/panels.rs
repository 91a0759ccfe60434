//! The viewer's widgets: side panel groups, status bar, shortcuts.
//! Each function edits the app's plain state; `LumiereApp::sync_renderer`
//! then tells the worker what changed.

use eframe::egui;
use strum::IntoEnumIterator;

use super::noise_view;
use super::{LumiereApp, interact, reference, split};
use crate::analysis::noise::{DisplayMode, NoiseSource, Scale};
use crate::course::Choice;
use crate::course::{
    Adaptive, BrdfOverride, IndirectSampling, Integrator, LightMode, LightSampling, LightSelection,
    MAX_IOR, MAX_SAMPLES_PER_VERTEX, MisHeuristic, RenderSettings, Sampler, Term,
};
use crate::render::display::Tonemap;
use crate::render::progressive::Snapshot;

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
            toggle_term(app, term);
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
fn toggle_term(app: &mut LumiereApp, term: Term) {
    let terms = app.state.settings.terms;
    let toggled = terms.with(term, !terms.contains(term));
    if !toggled.is_empty() {
        app.state.settings.terms = toggled;
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
                super::lesson_view::lesson_ui(app, ui);
                terms_ui(app, ui);
                lights_ui(app, ui);
                materials_ui(app, ui);
                sampling_ui(app, ui);
                interact::selection_ui(app, ui);
                camera_ui(app, ui);
                display_ui(app, ui);
                render_ui(app, ui);
                super::scene_panel::scene_ui(app, ui);
                reference::error_ui(app, ui);
                split::compare_ui(app, ui);
            });
        });
}

fn terms_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Terms")
        .default_open(true)
        .show(ui, |ui| {
            for term in Term::ALL {
                let mut on = app.state.settings.terms.contains(term);
                ui.horizontal(|ui| {
                    let response = ui
                        .checkbox(&mut on, term.label())
                        .on_hover_text(term_tooltip(term));
                    ui.label(egui::RichText::new(term.description()).weak().small())
                        .on_hover_text(term_tooltip(term));
                    if response.changed() {
                        toggle_term(app, term);
                    }
                });
            }
        });
}

fn lights_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Lights").default_open(true).show(ui, |ui| {
        let settings = &mut app.state.settings;
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
        let diagonal = app.scene.bounds().diagonal().max(1e-3);
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
        interact::light_power_ui(app, ui);
        super::source_quality::source_quality_ui(app, ui);
    });
}

fn materials_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Materials")
        .default_open(true)
        .show(ui, |ui| {
            let settings = &mut app.state.settings;
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

/// The estimators: how direct lighting, the next reflection and the random
/// numbers are drawn. Every choice is unbiased; only the noise differs.
fn sampling_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Sampling")
        .default_open(true)
        .show(ui, |ui| {
            let settings = &mut app.state.settings;
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

fn brdf_text(brdf: BrdfOverride) -> &'static str {
    match brdf {
        BrdfOverride::Authored => "As authored",
        BrdfOverride::Lambert => "Lambert",
        BrdfOverride::Phong => "Phong",
        BrdfOverride::Mirror => "Mirror",
        BrdfOverride::Glass => "Glass",
    }
}

fn camera_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Camera")
        .default_open(false)
        .show(ui, |ui| {
            let cameras = app.scene.cameras.clone();
            egui::ComboBox::from_label("view")
                .selected_text(app.camera.name.clone())
                .show_ui(ui, |ui| {
                    for camera in cameras {
                        let name = camera.name.clone();
                        if ui.selectable_value(&mut app.camera, camera, name).clicked() {
                            app.orbit = interact::Orbit::default();
                        }
                    }
                });
            if ui
                .button("Reset")
                .on_hover_text("Back to the scene's first camera")
                .clicked()
            {
                app.camera = app.scene.default_camera();
                app.orbit = interact::Orbit::default();
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

fn display_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Display")
        .default_open(true)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.label("zoom");
                for (zoom, text) in [
                    (None, "Fit"),
                    (Some(1), "1:1"),
                    (Some(2), "2×"),
                    (Some(4), "4×"),
                    (Some(8), "8×"),
                ] {
                    if ui.selectable_label(app.zoom == zoom, text).clicked() {
                        app.zoom = zoom;
                        app.pan = egui::Vec2::ZERO;
                    }
                }
            })
            .response
            .on_hover_text("Screen pixels per film pixel (nearest neighbour); Shift+drag pans");
            let auto = app.state.auto_exposure;
            let display = &mut app.state.display;
            ui.horizontal(|ui| {
                ui.add_enabled(
                    !auto,
                    egui::Slider::new(&mut display.exposure, -10.0..=10.0).text("exposure (EV)"),
                );
                ui.checkbox(&mut app.state.auto_exposure, "auto EV")
                    .on_hover_text("Set the exposure from the image: its mean luminance shown as mid-grey (L2 alone is dark)");
            });
            egui::ComboBox::from_label("tonemap")
                .selected_text(display.tonemap.label())
                .show_ui(ui, |ui| {
                    for tonemap in Tonemap::iter() {
                        ui.selectable_value(&mut display.tonemap, tonemap, tonemap.label());
                    }
                });
            noise_ui(app, ui);
            super::four_up_view::layout_ui(app, ui);
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

fn render_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Render")
        .default_open(true)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                let text = if app.paused { "Resume" } else { "Pause" };
                if ui.button(text).on_hover_text("Space").clicked() {
                    app.paused = !app.paused;
                }
                if ui
                    .button("Save screenshot")
                    .on_hover_text("Ctrl+S: PNG as displayed, EXR, settings")
                    .clicked()
                {
                    app.save_screenshot();
                }
            });
            shown_size_ui(app, ui);
            if ui
                .button("Reset to defaults")
                .on_hover_text(
                    "Every setting back to lumiere's defaults, the scene reloaded without its edits \
                     (settings are kept between runs otherwise)",
                )
                .clicked()
            {
                app.reset_to_defaults();
            }
            ui.horizontal(|ui| {
                let mut stop = app.state.stop_at_spp.is_some();
                let label = ui.checkbox(&mut stop, "stop at");
                let mut spp = app.state.stop_at_spp.unwrap_or(256);
                ui.add_enabled(
                    stop,
                    egui::DragValue::new(&mut spp)
                        .range(1..=1_000_000)
                        .suffix(" spp"),
                )
                .labelled_by(label.id);
                app.state.stop_at_spp = stop.then_some(spp);
            });
            let settings = &mut app.state.settings;
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
            ui.checkbox(&mut app.state.per_term_exr, "also one EXR per term");
            if super::files::READS_PATHS {
                ui.horizontal(|ui| {
                    let label = ui.label("save to");
                    ui.text_edit_singleline(&mut app.state.export_dir)
                        .labelled_by(label.id);
                });
            } else {
                ui.label("saved files go to the browser's downloads");
            }
        });
}

/// "Save as shown" and the size of its picture.
fn shown_size_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    use crate::tools::slides::shown::{MAX_SIDE, MIN_SIDE};
    ui.horizontal(|ui| {
        if ui
            .button("Save as shown")
            .on_hover_text(
                "One PNG of the picture as shown — the image, or a noise view with its colour bar, \
                 A | B, the four-up, the probe's rays, a lesson step's title, formula and caption \
                 laid out as its slide — at this size, with the settings (JSON)",
            )
            .clicked()
        {
            app.save_as_shown();
        }
        let (width, height) = &mut app.state.shown_size;
        let sides = MIN_SIDE..=MAX_SIDE;
        ui.add(egui::DragValue::new(width).range(sides.clone()))
            .on_hover_text("The picture's width, in pixels");
        ui.label("×");
        ui.add(egui::DragValue::new(height).range(sides))
            .on_hover_text("The picture's height, in pixels");
    });
}
