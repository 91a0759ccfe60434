//! The window's contents: the choices, the disk with its outlines, names,
//! marks and samples, the colour bar, the quadrature, and the film's
//! samples at p with their running estimate.

use eframe::egui;
use egui_plot::{HLine, Line, LineStyle, Plot, PlotPoints, Points};
use glam::Vec2;

use crate::analysis::hemisphere::{Factor, IntegrandMap, Vertex, disk_to_direction};
use crate::analysis::hemisphere_colour::ColouredMap;
use crate::analysis::noise::{ColourMap, Scale, Unit, format_tick};
use crate::analysis::strategy_samples::{DrawnSample, Strategy};
use crate::course::color::luminance;
use crate::course::{Term, TermSet};

use super::{
    Computed, HemisphereView, MAP_POINTS, MOST_DRAWN_SAMPLES, MapShows, Outcome, SecondVertex,
};

/// The colour of a strategy's samples.
pub fn strategy_colour(strategy: Strategy) -> egui::Color32 {
    match strategy {
        Strategy::Light => egui::Color32::from_rgb(255, 150, 40),
        Strategy::Directions => egui::Color32::from_rgb(80, 220, 255),
    }
}

/// The term, what the map shows and the scale.
pub(super) fn choices_ui(ui: &mut egui::Ui, view: &mut HemisphereView, visible: TermSet) {
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
            .selected_text(shows_label(view.shows))
            .show_ui(ui, |ui| {
                for factor in Factor::ALL {
                    let shows = MapShows::Factor(factor);
                    ui.selectable_value(&mut view.shows, shows, shows_label(shows));
                }
                for strategy in [Strategy::Light, Strategy::Directions] {
                    let shows = MapShows::Density(strategy);
                    ui.selectable_value(&mut view.shows, shows, shows_label(shows));
                }
            })
            .response
            .on_hover_text("The integrand, one of its factors alone, or the density of a strategy");
        ui.separator();
        ui.selectable_value(&mut view.scale, Scale::Linear, "linear");
        ui.selectable_value(&mut view.scale, Scale::Log, "log");
    });
}

fn shows_label(shows: MapShows) -> &'static str {
    match shows {
        MapShows::Factor(Factor::Integrand) => "L_i · f_r · cos θ",
        MapShows::Factor(Factor::Incident) => "L_i alone",
        MapShows::Factor(Factor::Brdf) => "f_r alone",
        MapShows::Factor(Factor::Cosine) => "cos θ alone",
        MapShows::Density(Strategy::Light) => "pdf of the light samples",
        MapShows::Density(Strategy::Directions) => "pdf of the directions",
    }
}

fn shows_unit(shows: MapShows) -> &'static str {
    match shows {
        MapShows::Factor(factor) => factor.unit(),
        MapShows::Density(_) => "1/sr",
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

/// The disk, its outlines, names, marks and samples, and the colour bar.
pub(super) fn map_ui(
    ui: &mut egui::Ui,
    view: &HemisphereView,
    texture: egui::TextureId,
    coloured: &ColouredMap,
    outcome: &Outcome,
    term: Term,
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
    for &(a, b) in &outcome.at_point.outline {
        painter.line_segment([screen(a), screen(b)], outline);
    }
    let font = egui::FontId::proportional(12.0);
    let shadowed_text = |at: egui::Pos2, align, text: &str, colour| {
        painter.text(
            at + egui::vec2(1.0, 1.0),
            align,
            text,
            font.clone(),
            egui::Color32::BLACK,
        );
        painter.text(at, align, text, font.clone(), colour);
    };
    for label in &outcome.at_point.labels {
        let at = screen(label.below) + egui::vec2(0.0, 2.0);
        let text = format!("Ω {}", label.name);
        shadowed_text(at, egui::Align2::CENTER_TOP, &text, egui::Color32::WHITE);
    }
    if term == Term::L1 {
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
            let text = format!("δ {}{hidden}", dirac.name);
            shadowed_text(
                at + egui::vec2(8.0, -8.0),
                egui::Align2::LEFT_BOTTOM,
                &text,
                colour,
            );
        }
    }
    // ωo: where the path comes from (the camera at p, p at q)
    let outgoing = screen(outcome.outgoing);
    let grey = egui::Color32::from_gray(220);
    painter.circle_stroke(outgoing, 5.0, egui::Stroke::new(1.5, grey));
    painter.circle_filled(outgoing, 1.5, grey);
    let towards = if computed_at_q(view) {
        "ωo, to p"
    } else {
        "ωo, to the eye"
    };
    shadowed_text(
        outgoing + egui::vec2(7.0, 7.0),
        egui::Align2::LEFT_TOP,
        towards,
        grey,
    );
    let drawn = &outcome.at_point.drawn;
    if view.samples_shown {
        // each sample sized by its value: the area of its dot ∝ f cos L / pdf · w
        let largest = drawn
            .first(view.samples_drawn)
            .map(|s| luminance(s.value))
            .fold(0.0f32, f32::max);
        for sample in drawn.first(view.samples_drawn) {
            let at = screen(sample.disk);
            let colour = strategy_colour(sample.strategy);
            let y = luminance(sample.value);
            if y > 0.0 && largest > 0.0 {
                let radius = 2.0 + 5.0 * (y / largest).sqrt();
                painter.circle_filled(at, radius + 1.0, egui::Color32::BLACK);
                painter.circle_filled(at, radius, colour);
            } else {
                // a sample that brought nothing: a ring
                painter.circle_stroke(at, 2.5, egui::Stroke::new(1.0, colour));
            }
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
        let nearest = view
            .samples_shown
            .then(|| nearest_sample(view, outcome, pos, &screen))
            .flatten();
        hover_ui(&response, pos, rect, coloured, view.shows, outcome, nearest);
    }
    colour_bar_ui(ui, coloured, view.shows);
}

/// Whether the map shown is at a second vertex q.
fn computed_at_q(view: &HemisphereView) -> bool {
    view.result
        .as_ref()
        .is_some_and(|r| matches!(r.vertex(), Vertex::Second { .. }))
}

/// At a second vertex q: where it is, how its integral nests in p's, and
/// the way back to p.
pub(super) fn second_vertex_ui(ui: &mut egui::Ui, view: &mut HemisphereView, q: &SecondVertex) {
    ui.horizontal(|ui| {
        if ui
            .button("← back to p")
            .on_hover_text("The integral at the pixel's first hit")
            .clicked()
        {
            view.at_q = None;
        }
        ui.label(format!(
            "q: where sample {}'s bounce from p lands",
            q.sample
        ));
    });
    ui.add(
        egui::Label::new(
            egui::RichText::new(
                "The nested integral: L1 at q, ∫ over Ωq of Le f_r(q) cos θ' dω', is L_direct(q, −ω), \
                 the L_i of L2's integrand at p along this bounce; L2 at q is the L_i of L3+ at p.",
            )
            .small(),
        )
        .wrap(),
    );
}

/// The drawn sample within a few points of `pos`, if any.
fn nearest_sample<'a>(
    view: &HemisphereView,
    outcome: &'a Outcome,
    pos: egui::Pos2,
    screen: &impl Fn(Vec2) -> egui::Pos2,
) -> Option<&'a DrawnSample> {
    outcome
        .at_point
        .drawn
        .first(view.samples_drawn)
        .map(|s| (s, screen(s.disk).distance(pos)))
        .filter(|(_, d)| *d < 6.0)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(s, _)| s)
}

/// The value under the pointer, the direction, and the sample there.
fn hover_ui(
    response: &egui::Response,
    pos: egui::Pos2,
    rect: egui::Rect,
    coloured: &ColouredMap,
    shows: MapShows,
    outcome: &Outcome,
    sample: Option<&DrawnSample>,
) {
    let uv = (pos - rect.min) / rect.size();
    let size = coloured.size;
    let (column, row) = ((uv.x * size as f32) as u32, (uv.y * size as f32) as u32);
    if column >= size || row >= size {
        return;
    }
    let centre = IntegrandMap::disk_point(size, column, row, Vec2::splat(0.5));
    let Some(w) = disk_to_direction(centre) else {
        return;
    };
    let index = (row * size + column) as usize;
    let domains = &outcome.at_point.domains;
    let source = domains.source[index]
        .map(|s| {
            let seen = if domains.visible[index] {
                ""
            } else {
                ", hidden"
            };
            format!(" · in Ω of {}{seen}", domains.names[s as usize])
        })
        .unwrap_or_default();
    let mut text = format!(
        "θ = {:.0}°{source}\n{} = {} {}",
        w.z.clamp(-1.0, 1.0).acos().to_degrees(),
        shows_label(shows),
        format_tick(coloured.values[index], Unit::Radiance),
        shows_unit(shows)
    );
    if let Some(sample) = sample {
        let strategy = match sample.strategy {
            Strategy::Light => "light sample",
            Strategy::Directions => "drawn direction",
        };
        text += &format!(
            "\nsample {}: {strategy}, value {} W/m²/sr, MIS weight {:.3}{}",
            sample.pass + 1,
            format_tick(luminance(sample.value), Unit::Radiance),
            sample.weight,
            if sample.reached_light {
                ""
            } else {
                " (no light reached)"
            }
        );
    }
    response.clone().on_hover_text(text);
}

/// The colour bar under the map, with its ticks and unit.
fn colour_bar_ui(ui: &mut egui::Ui, coloured: &ColouredMap, shows: MapShows) {
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
        format!("{} ({}), {scale}", shows_label(shows), shows_unit(shows)),
        font,
        text,
    );
}

/// The quadrature, the point lights, and how the map was made.
pub(super) fn numbers_ui(ui: &mut egui::Ui, computed: &Computed, outcome: &Outcome) {
    let map = &outcome.map;
    let term = computed.term();
    ui.label(format!(
        "∫ {} over Ω⁺ = {:.5} ± {:.5} W/m²/sr",
        term.label(),
        luminance(map.integral),
        map.integral_standard_error
    ))
    .on_hover_text("The map's quadrature (luminance), with its standard error");
    if term == Term::L1 && !map.diracs.is_empty() {
        let diracs: f32 = map.diracs.iter().map(|d| luminance(d.radiance)).sum();
        let below = match map.diracs.iter().filter(|d| d.direction.z <= 0.0).count() {
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
    ui.horizontal(|ui| {
        if !computed.is_final() {
            ui.spinner();
        }
        ui.add(
            egui::Label::new(
                egui::RichText::new(format!(
                    "{} = ({:.3}, {:.3}, {:.3}) · {} direction(s) per pixel of {}² · {:.0} ms · equal-area disk, zenith at the centre",
                    computed.vertex().name(),
                    outcome.point.x,
                    outcome.point.y,
                    outcome.point.z,
                    map.directions_per_pixel,
                    map.size,
                    computed.duration.as_secs_f64() * 1e3
                ))
                .small()
                .weak(),
            )
            .wrap(),
        );
    });
}

/// The film's samples at p: how many are drawn, their strategies and
/// weights, and their running estimate against the quadrature.
pub(super) fn samples_ui(
    ui: &mut egui::Ui,
    view: &mut HemisphereView,
    computed: &Computed,
    outcome: &Outcome,
) {
    let drawn = &outcome.at_point.drawn;
    ui.separator();
    ui.horizontal(|ui| {
        if computed.vertex() == Vertex::FirstHit {
            ui.checkbox(&mut view.samples_shown, "the film's samples")
                .on_hover_text("The directions the render's own samples of this pixel take from p, with the same random numbers");
        } else {
            ui.checkbox(&mut view.samples_shown, "the estimator's samples at q")
                .on_hover_text("Samples of the render's estimator started along the bounce p → q (the pixel's random streams): the directions each takes from q");
        }
        let mut n = view.samples_drawn;
        ui.add(
            egui::Slider::new(&mut n, 1..=MOST_DRAWN_SAMPLES)
                .logarithmic(true)
                .text("N"),
        );
        view.samples_drawn = n;
    });
    ui.horizontal_wrapped(|ui| {
        for (strategy, how) in [
            (Strategy::Light, drawn.light),
            (Strategy::Directions, drawn.directions),
        ] {
            let Some(how) = how else { continue };
            let samples: Vec<&DrawnSample> = drawn
                .first(view.samples_drawn)
                .filter(|s| s.strategy == strategy)
                .collect();
            let weights: Vec<f32> = samples
                .iter()
                .filter(|s| s.reached_light)
                .map(|s| s.weight)
                .collect();
            let mean_weight = weights.iter().sum::<f32>() / weights.len().max(1) as f32;
            let name = match strategy {
                Strategy::Light => "light samples",
                Strategy::Directions => "directions",
            };
            let mis = if drawn.light.is_some() && drawn.directions.is_some() && !weights.is_empty()
            {
                format!(", mean MIS weight {mean_weight:.2} where a light is reached")
            } else {
                String::new()
            };
            ui.label(
                egui::RichText::new(format!("● {name} ({how}): {}{mis}", samples.len()))
                    .color(strategy_colour(strategy)),
            );
        }
    });
    let estimates: Vec<_> = drawn
        .running_estimate()
        .into_iter()
        .filter(|e| e.n <= view.samples_drawn.max(1))
        .collect();
    if let Some(last) = estimates.last() {
        let quadrature = if computed.term() == Term::L1 {
            luminance(outcome.map.quadrature())
        } else {
            luminance(outcome.map.integral)
        };
        ui.label(format!(
            "estimate after {} sample(s): {:.5} ± {:.5} · the map's quadrature: {:.5} W/m²/sr",
            last.n, last.mean, last.standard_error, quadrature
        ));
        estimate_plot(ui, &estimates, quadrature as f64);
        ui.label(
            egui::RichText::new("red: the estimate after N samples, dashed: ± its standard error, yellow: the quadrature")
                .small()
                .weak(),
        );
    }
}

/// The running estimate ± its standard error against N (log), and the quadrature.
fn estimate_plot(
    ui: &mut egui::Ui,
    estimates: &[crate::analysis::strategy_samples::RunningEstimate],
    quadrature: f64,
) {
    let x = |n: u32| (n as f64).log2();
    let mean: Vec<[f64; 2]> = estimates.iter().map(|e| [x(e.n), e.mean]).collect();
    let band = |sign: f64| -> Vec<[f64; 2]> {
        estimates
            .iter()
            .map(|e| [x(e.n), e.mean + sign * e.standard_error])
            .collect()
    };
    Plot::new("hemisphere running estimate")
        .height(130.0)
        .width(MAP_POINTS)
        .x_axis_label("log₂ N")
        .y_axis_label("W/m²/sr")
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .show(ui, |plot| {
            let red = egui::Color32::from_rgb(240, 90, 80);
            plot.add(
                Points::new("estimate", PlotPoints::new(mean.clone()))
                    .radius(2.5)
                    .color(red),
            );
            plot.line(Line::new("estimate", PlotPoints::new(mean)).color(red));
            for (name, sign) in [("± standard error", 1.0), ("± standard error", -1.0)] {
                plot.line(
                    Line::new(name, PlotPoints::new(band(sign)))
                        .color(egui::Color32::GRAY)
                        .style(LineStyle::Dashed { length: 4.0 }),
                );
            }
            plot.hline(
                HLine::new("quadrature", quadrature).color(egui::Color32::from_rgb(255, 214, 153)),
            );
        });
}
