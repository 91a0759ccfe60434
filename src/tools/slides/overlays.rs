//! What is drawn over a slide's image, on the exported slides and on the
//! viewer's picture as shown alike: the probe's rays, the noise view's
//! colour bar, a false-colour image in sRGB.

use glam::Vec2;

use super::TEXT_COLOR;
use super::canvas::{self, Canvas, Rect, Rgb8};
use crate::analysis::noise::{FalseColour, format_tick};
use crate::analysis::path_view::{PathLine, RayRole, outline_rgb, role_rgb};
use crate::course::color::linear_to_srgb;

/// The 8-bit sRGB pixels of a false-colour image.
pub fn false_colour_srgb8(noise: &FalseColour) -> Vec<u8> {
    noise
        .rgba
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]])
        .map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8)
        .collect()
}

// ───────────────────────── the probe's rays ─────────────────────────

/// Draws `lines` (pixels of a film of `film` size) over the image at
/// `image` (the film scaled to it), clipped to it, as the viewer's path
/// view does: solid lines over a dark outline, dashed ones for rays that
/// added nothing, a ring where the camera ray lands.
pub fn draw_paths(canvas: &mut Canvas, image: Rect, film: (u32, u32), lines: &[PathLine]) {
    let s = (image.height as f32 / 480.0).max(1.0);
    let offset = Vec2::new(image.x as f32, image.y as f32);
    let scale = Vec2::new(
        image.width as f32 / film.0.max(1) as f32,
        image.height as f32 / film.1.max(1) as f32,
    );
    let outline: Rgb8 = [12, 12, 12];
    for line in lines {
        let (from, to) = (line.from * scale + offset, line.to * scale + offset);
        let colour = role_rgb(line.role);
        if line.role == RayRole::Camera {
            canvas.draw_disc(to, 5.0 * s, Some(3.5 * s), outline, image);
            canvas.draw_disc(to, 5.0 * s, Some(2.0 * s), colour, image);
            continue;
        }
        let width = s * if matches!(line.role, RayRole::GatherMissed { .. }) {
            1.0
        } else {
            2.0
        };
        if line.role.is_dashed() {
            canvas.draw_segment((from, to), width, colour, Some((6.0 * s, 4.0 * s)), image);
        } else {
            let edge = outline_rgb(line.role);
            canvas.draw_segment((from, to), width + 1.5 * s, edge, None, image);
            canvas.draw_segment((from, to), width, colour, None, image);
        }
        if line.ends_on_film && !matches!(line.role, RayRole::GatherMissed { .. }) {
            canvas.draw_disc(to, 3.0 * s, None, colour, image);
        }
    }
}

// ───────────────────────── the colour bar ─────────────────────────

/// The width a colour bar of `noise` needs right of the image, with the
/// slide's caption size and side margin `sizes`.
pub fn colour_bar_width(noise: &FalseColour, (caption_size, side_margin): (f32, f32)) -> f32 {
    let size = 0.75 * caption_size;
    let widest = [1.0f32, 0.5, 0.0]
        .map(|t| canvas::text_width(&format_tick(noise.value_at(t), noise.unit), size))
        .into_iter()
        .fold(0.0, f32::max);
    0.6 * size + 0.8 * size + 0.6 * size + widest + side_margin
}

/// The width the colour bar of `noise` needs with its title (the mode and
/// unit) at full size, with the slide's caption size and side margin `sizes`.
pub fn colour_bar_room(noise: &FalseColour, sizes: (f32, f32)) -> f32 {
    let size = 0.75 * sizes.0;
    let title = [noise.view.mode.title(), noise.unit.symbol()]
        .map(|text| canvas::text_width(text, size))
        .into_iter()
        .fold(0.0, f32::max);
    colour_bar_width(noise, sizes).max(0.6 * size + title + sizes.1)
}

/// Draws the colour bar of `noise` in `margin`, the margin right of the
/// image, with the slide's caption size and side margin `sizes`: the mode
/// and unit above it, the values of its ends and middle beside it.
/// Nothing if the margin is too narrow.
pub fn draw_colour_bar(
    canvas: &mut Canvas,
    margin: Rect,
    (caption_size, side_margin): (f32, f32),
    noise: &FalseColour,
) {
    let size = 0.75 * caption_size;
    let (gap, bar_width) = (0.6 * size, 0.8 * size);
    let ticks = [1.0f32, 0.5, 0.0].map(|t| (t, format_tick(noise.value_at(t), noise.unit)));
    if (margin.width as f32) < colour_bar_width(noise, (caption_size, side_margin)) {
        return;
    }
    // the title: the mode, then the unit, on two lines
    let left = margin.x as f32 + gap;
    let room = margin.width as f32 - gap - side_margin;
    let line = canvas::ascent(size) + canvas::descent(size);
    let title = [noise.view.mode.title(), noise.unit.symbol()];
    for (k, text) in title.iter().enumerate() {
        let (text, fitted) = canvas::fit_line(text, size, 0.6 * size, room);
        let baseline = margin.y as f32 + canvas::ascent(size) + k as f32 * line;
        canvas.draw_text(&text, fitted, (left, baseline), TEXT_COLOR, margin);
    }
    // the bar, top (the range's end) to bottom (its start), in the map's sRGB colours
    let top = margin.y + (2.5 * line).ceil() as u32;
    let bottom = margin.bottom().saturating_sub((0.5 * line).ceil() as u32);
    if bottom <= top + 2 {
        return;
    }
    let x = left.round() as u32;
    let span = (bottom - top - 1) as f32;
    for y in top..bottom {
        let position = 1.0 - (y - top) as f32 / span;
        let colour = noise
            .map
            .srgb(position)
            .map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8);
        canvas.fill(Rect::new(x, y, bar_width.round() as u32, 1), colour);
    }
    let label_left = x as f32 + bar_width + gap;
    for (t, label) in ticks {
        let y = bottom as f32 - t * span;
        let baseline = y + 0.35 * size;
        canvas.draw_text(&label, size, (label_left, baseline), TEXT_COLOR, margin);
    }
}
