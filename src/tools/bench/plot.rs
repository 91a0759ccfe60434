//! The bench's figures, drawn with plotters into an RGB buffer and saved as PNG.
//!
//! Text uses the Hack font embedded in the binary ([`crate::tools::font`]),
//! registered with plotters' ab_glyph renderer: no system font or
//! fontconfig is needed.

use std::path::Path;
use std::sync::Once;

use plotters::backend::BitMapBackend;
use plotters::prelude::*;

#[cfg(not(target_arch = "wasm32"))]
use crate::tools::font::HACK_REGULAR;

use super::BenchError;
use super::csv::ErrorRow;
use super::error_curve::{RELMSE_THRESHOLDS, curves};
use super::scaling::{Axis, ScalingRow};

const FAMILY: &str = "sans-serif";
const SIZE: (u32, u32) = (900, 600);

fn register_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // the embedded font is valid: a failure would only leave labels out
        // (the bench does not run in the browser, where plotters has no fonts)
        #[cfg(not(target_arch = "wasm32"))]
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, HACK_REGULAR);
    });
}

fn color(index: usize) -> RGBColor {
    const COLORS: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
    ];
    COLORS[index % COLORS.len()]
}

/// A range of positive values widened to whole decades, for log axes.
fn decades(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        return 0.1..10.0;
    }
    10f64.powf(lo.log10().floor())..10f64.powf(hi.log10().ceil().max(lo.log10().floor() + 1.0))
}

/// Draws into a buffer and saves it as `path` (PNG).
fn save(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<BitMapBackend, plotters::coord::Shift>) -> Result<(), String>,
) -> Result<(), BenchError> {
    register_font();
    let mut pixels = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, SIZE).into_drawing_area();
        draw(&root).map_err(|e| BenchError::file(path, format!("cannot draw the plot: {e}")))?;
        root.present()
            .map_err(|e| BenchError::file(path, format!("cannot draw the plot: {e}")))?;
    }
    image::RgbImage::from_raw(SIZE.0, SIZE.1, pixels)
        .ok_or_else(|| BenchError::file(path, "plot buffer size mismatch"))?
        .save(path)
        .map_err(|e| BenchError::file(path, format!("cannot write: {e}")))
}

/// relMSE against seconds, log-log, one line per (renderer, estimator), with the thresholds dashed.
pub fn error_plot(rows: &[ErrorRow], path: &Path) -> Result<(), BenchError> {
    let x_range = decades(rows.iter().map(|r| r.seconds));
    // half the lowest threshold, so that its line is not the frame's edge
    let y_range = decades(
        rows.iter()
            .map(|r| r.relmse)
            .chain(RELMSE_THRESHOLDS.map(|t| t * 0.5)),
    );
    save(path, |root| {
        let e = |e: &dyn std::fmt::Display| e.to_string();
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let mut chart = ChartBuilder::on(root)
            .caption("relMSE against render time", (FAMILY, 22))
            .margin(12)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(x_range.clone().log_scale(), y_range.log_scale())
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_desc("seconds")
            .y_desc("relMSE")
            .label_style((FAMILY, 14))
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .draw()
            .map_err(|x| e(&x))?;
        for threshold in RELMSE_THRESHOLDS {
            let line = [(x_range.start, threshold), (x_range.end, threshold)];
            chart
                .draw_series(DashedLineSeries::new(line, 6, 4, BLACK.mix(0.5).into()))
                .map_err(|x| e(&x))?;
        }
        for (i, (renderer, estimator, points)) in curves(rows).into_iter().enumerate() {
            let c = color(i);
            let xy: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.seconds > 0.0 && p.relmse > 0.0)
                .map(|p| (p.seconds, p.relmse))
                .collect();
            chart
                .draw_series(xy.iter().map(|&p| Circle::new(p, 3, c.filled())))
                .map_err(|x| e(&x))?;
            chart
                .draw_series(LineSeries::new(xy, c.stroke_width(2)))
                .map_err(|x| e(&x))?
                .label(format!("{renderer} {estimator}"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c.stroke_width(2)));
        }
        if rows.is_empty() {
            return Ok(()); // no curve: the frame alone, without an empty legend
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FAMILY, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|x| e(&x))
    })
}

/// Load + build seconds and Mrays/s against triangles, side by side.
pub fn scaling_plot(rows: &[ScalingRow], path: &Path) -> Result<(), BenchError> {
    let triangle_rows: Vec<&ScalingRow> = rows
        .iter()
        .filter(|r| matches!(r.axis, Axis::Triangles | Axis::GltfTriangles))
        .collect();
    let x_range = decades(triangle_rows.iter().map(|r| r.triangles as f64));
    let seconds = |r: &ScalingRow| r.load_seconds + r.build_seconds;
    let seconds_range = decades(triangle_rows.iter().map(|r| seconds(r)));
    let mrays_max = triangle_rows
        .iter()
        .map(|r| r.mrays_per_second())
        .fold(1.0, f64::max)
        * 1.15;
    save(path, |root| {
        let e = |e: &dyn std::fmt::Display| e.to_string();
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let panels = root.split_evenly((1, 2));
        let series = |axis: Axis, value: &dyn Fn(&ScalingRow) -> f64| -> Vec<(f64, f64)> {
            triangle_rows
                .iter()
                .filter(|r| r.axis == axis)
                .map(|r| (r.triangles as f64, value(r)))
                .collect()
        };
        let axes = [
            (Axis::Triangles, "procedural", color(0)),
            (Axis::GltfTriangles, "glTF file", color(1)),
        ];
        // left: seconds to load and build
        let mut left = ChartBuilder::on(&panels[0])
            .caption("load + build seconds", (FAMILY, 20))
            .margin(12)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(60)
            .build_cartesian_2d(x_range.clone().log_scale(), seconds_range.log_scale())
            .map_err(|x| e(&x))?;
        left.configure_mesh()
            .x_desc("triangles")
            .label_style((FAMILY, 13))
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .draw()
            .map_err(|x| e(&x))?;
        for (axis, name, c) in axes {
            let xy = series(axis, &seconds);
            left.draw_series(xy.iter().map(|&p| Circle::new(p, 4, c.filled())))
                .map_err(|x| e(&x))?;
            left.draw_series(LineSeries::new(xy, c.stroke_width(2)))
                .map_err(|x| e(&x))?
                .label(name)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c.stroke_width(2)));
        }
        left.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font((FAMILY, 13))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|x| e(&x))?;
        // right: rays per second
        let mut right = ChartBuilder::on(&panels[1])
            .caption("Mrays/s", (FAMILY, 20))
            .margin(12)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(50)
            .build_cartesian_2d(x_range.clone().log_scale(), 0.0..mrays_max)
            .map_err(|x| e(&x))?;
        right
            .configure_mesh()
            .x_desc("triangles")
            .label_style((FAMILY, 13))
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .draw()
            .map_err(|x| e(&x))?;
        for (axis, _, c) in axes {
            let xy = series(axis, &|r: &ScalingRow| r.mrays_per_second());
            right
                .draw_series(xy.iter().map(|&p| Circle::new(p, 4, c.filled())))
                .map_err(|x| e(&x))?;
            right
                .draw_series(LineSeries::new(xy, c.stroke_width(2)))
                .map_err(|x| e(&x))?;
        }
        Ok(())
    })
}

/// A compact tick label: plain decimals from 10⁻³ to 10⁵ ("0.01", "250"),
/// powers of ten outside ("1e6"), never a trailing ".0".
fn tick_label(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || (1e-3..1e5).contains(&magnitude) {
        // round away the binary noise of log-scale ticks
        format!("{}", (value * 1e6).round() / 1e6)
    } else {
        format!("{value:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::tick_label;

    #[test]
    fn tick_labels_are_compact() {
        assert_eq!(tick_label(0.0), "0");
        assert_eq!(tick_label(0.001), "0.001");
        assert_eq!(tick_label(1.0), "1");
        assert_eq!(tick_label(2.5), "2.5");
        assert_eq!(tick_label(10000.000000001), "10000");
        assert_eq!(tick_label(1e6), "1e6");
        assert_eq!(tick_label(1e-4), "1e-4");
    }
}
