//! The convergence plot: error against samples per pixel and against
//! seconds, on log-log axes, one curve per estimator tried (see
//! `crate::analysis::convergence`). egui_plot has no log axes: the plot holds log10
//! values and the ticks are labelled 10^k. A dashed line of the slope an
//! unbiased estimator must follow (-1/2 for RMSE, -1 for relMSE) goes through
//! the first point of the current estimator's curve.

use std::ops::RangeInclusive;

use eframe::egui;
use egui_plot::{GridInput, GridMark, Legend, Line, LineStyle, Plot, PlotPoints, Points};

use super::LumiereApp;
use super::reference::reference_matches_view;
use crate::analysis::convergence::{Curve, ErrorPoint, EstimatorKey};

/// The convergence window, while `show_plot` is on.
pub fn plot_window(app: &mut LumiereApp, ctx: &egui::Context) {
    let mut open = app.errors.show_plot;
    egui::Window::new("Convergence")
        .open(&mut open)
        .default_size([620.0, 480.0])
        .default_pos([440.0, 300.0])
        .show(ctx, |ui| plot_ui(app, ui));
    app.errors.show_plot = open;
}

fn plot_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    if app.reference.is_none() {
        ui.label("Capture a reference or load one (Error group) to measure the error.");
        return;
    }
    if !reference_matches_view(app) {
        ui.colored_label(
            ui.visuals().warn_fg_color,
            "reference is for other settings",
        );
        return;
    }
    let errors = &mut app.errors;
    ui.horizontal(|ui| {
        ui.selectable_value(&mut errors.plot_relmse, false, "RMSE");
        ui.selectable_value(&mut errors.plot_relmse, true, "relMSE");
        if ui.button("Clear curves").clicked() {
            errors.curves.clear();
        }
    });
    let relmse = errors.plot_relmse;
    let current = EstimatorKey::of(&app.state.settings);
    let curves: Vec<&Curve> = errors.curves.iter().collect();
    let width = (ui.available_width() - 8.0) / 2.0;
    ui.horizontal(|ui| {
        for (axis, x_of) in [
            (
                "spp",
                (|p: &ErrorPoint| p.samples_per_pixel as f64) as fn(&ErrorPoint) -> f64,
            ),
            ("seconds", |p: &ErrorPoint| p.seconds),
        ] {
            ui.vertical(|ui| {
                ui.set_width(width);
                log_log_plot(ui, axis, &curves, current, relmse, x_of);
            });
        }
    });
    table_ui(ui, &curves);
}

fn log_log_plot(
    ui: &mut egui::Ui,
    axis: &str,
    curves: &[&Curve],
    current: EstimatorKey,
    relmse: bool,
    x_of: fn(&ErrorPoint) -> f64,
) {
    let y_of = |p: &ErrorPoint| if relmse { p.error.relmse } else { p.error.rmse };
    let log_point = |p: &ErrorPoint| {
        let (x, y) = (x_of(p), y_of(p));
        (x > 0.0 && y > 0.0).then(|| [x.log10(), y.log10()])
    };
    let metric = if relmse { "relMSE" } else { "RMSE" };
    Plot::new(format!("convergence vs {axis}"))
        .height(240.0)
        .legend(Legend::default())
        .x_axis_label(format!("{axis} (log)"))
        .y_axis_label(format!("{metric} (log)"))
        .x_grid_spacer(decade_marks)
        .y_grid_spacer(decade_marks)
        .x_axis_formatter(decade_label)
        .y_axis_formatter(decade_label)
        .label_formatter(move |hover| {
            let position = match hover {
                egui_plot::HoverPosition::NearDataPoint { position, .. }
                | egui_plot::HoverPosition::Elsewhere { position } => position,
            };
            Some(format!(
                "{} {axis}, {metric} {:.3e}",
                format_value(10f64.powf(position.x)),
                10f64.powf(position.y)
            ))
        })
        .show(ui, |plot| {
            let mut x_max = f64::MIN;
            for curve in curves {
                let points: Vec<[f64; 2]> = curve.points().filter_map(log_point).collect();
                x_max = points.iter().map(|p| p[0]).fold(x_max, f64::max);
                let name = curve.key.label();
                plot.add(Points::new(name.clone(), PlotPoints::new(points.clone())).radius(2.5));
                plot.line(Line::new(name, PlotPoints::new(points)));
            }
            let first = curves
                .iter()
                .find(|c| c.key == current)
                .and_then(|c| c.points().find_map(log_point));
            if let Some([x0, y0]) = first {
                let slope = if relmse { -1.0 } else { -0.5 };
                let x1 = x_max.max(x0 + 1.0);
                let name = if relmse { "slope -1" } else { "slope -1/2" };
                plot.line(
                    Line::new(
                        name,
                        PlotPoints::new(vec![[x0, y0], [x1, y0 + slope * (x1 - x0)]]),
                    )
                    .color(egui::Color32::GRAY)
                    .style(LineStyle::Dashed { length: 6.0 }),
                );
            }
        });
}

/// Grid lines at every decade, and at 2…9 × 10^k when few decades are shown.
fn decade_marks(input: GridInput) -> Vec<GridMark> {
    let (low, high) = input.bounds;
    if !(low.is_finite() && high.is_finite()) || high <= low {
        return Vec::new();
    }
    let step = ((high - low) / 12.0).ceil().max(1.0);
    let minor = high - low < 4.0;
    let mut marks = Vec::new();
    let mut k = (low / step).floor() * step;
    while k <= high {
        if k >= low {
            marks.push(GridMark {
                value: k,
                step_size: step,
            });
        }
        if minor {
            for m in 2..10 {
                let value = k + (m as f64).log10();
                if (low..=high).contains(&value) {
                    marks.push(GridMark {
                        value,
                        step_size: 0.1,
                    });
                }
            }
        }
        k += step;
    }
    marks
}

/// "10^3" at decades, nothing in between (the default font has no superscript minus).
fn decade_label(mark: GridMark, _range: &RangeInclusive<f64>) -> String {
    let k = mark.value.round();
    if (mark.value - k).abs() > 1e-6 {
        return String::new();
    }
    format!("10^{}", k as i64)
}

fn format_value(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.3}")
    }
}

/// The latest point of each curve and its efficiency 1/(relMSE × seconds).
fn table_ui(ui: &mut egui::Ui, curves: &[&Curve]) {
    egui::Grid::new("convergence table")
        .striped(true)
        .num_columns(6)
        .show(ui, |ui| {
            for heading in ["estimator", "spp", "time", "RMSE", "relMSE", "efficiency"] {
                ui.strong(heading);
            }
            ui.end_row();
            for curve in curves {
                let Some(point) = curve.latest() else {
                    continue;
                };
                ui.label(curve.key.label());
                ui.label(point.samples_per_pixel.to_string());
                ui.label(format!("{:.2} s", point.seconds));
                ui.label(format!("{:.3e}", point.error.rmse));
                ui.label(format!("{:.3e}", point.error.relmse));
                ui.label(
                    point
                        .efficiency()
                        .map_or("–".into(), |e| format!("{e:.3e}")),
                )
                .on_hover_text("1 / (relMSE × seconds): higher is better");
                ui.end_row();
            }
        });
    ui.label(
        egui::RichText::new(
            "efficiency = 1 / (relMSE × seconds); each curve is the latest run of its estimator",
        )
        .weak()
        .small(),
    );
}
