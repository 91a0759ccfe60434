//! A slide being drawn: 8-bit sRGB pixels, row-major from the top, with
//! rectangles, text in DejaVu Sans and antialiased lines, and halved for the
//! GIF.
//!
//! Text sizes are font sizes: the em square in pixels, as CSS's `font-size`
//! (DejaVu Sans rises 0.93 em above its baseline and falls 0.24 em below).
//! Glyphs are rasterized by ab_glyph and blended over the pixels by their
//! coverage, as the strips' labels are. Lines are blended by their coverage
//! of each pixel: `w/2 + ½ − d` for a pixel centre at distance d from a line
//! of width w, clamped to [0, 1].

use ab_glyph::{Font, GlyphId, PxScale, ScaleFont, point};
use glam::Vec2;
use image::RgbImage;

use crate::course::color::{linear_to_srgb, srgb_to_linear};
use crate::tools::font::{self, dejavu_sans};

/// An 8-bit sRGB colour.
pub type Rgb8 = [u8; 3];

/// A rectangle of pixels: its top-left corner and size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl Rect {
    pub fn new(x: u32, y: u32, width: u32, height: u32) -> Self {
        Self {
            x,
            y,
            width,
            height,
        }
    }

    /// One past the last column.
    pub fn right(&self) -> u32 {
        self.x + self.width
    }

    /// One past the last row.
    pub fn bottom(&self) -> u32 {
        self.y + self.height
    }

    pub fn contains(&self, x: i64, y: i64) -> bool {
        (self.x as i64..self.right() as i64).contains(&x)
            && (self.y as i64..self.bottom() as i64).contains(&y)
    }
}

/// An image being composed.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    width: u32,
    height: u32,
    pixels: Vec<u8>,
}

impl Canvas {
    /// A canvas of `width` × `height` pixels of `background`.
    pub fn new(width: u32, height: u32, background: Rgb8) -> Self {
        let pixels = background
            .iter()
            .copied()
            .cycle()
            .take(width as usize * height as usize * 3)
            .collect();
        Self {
            width,
            height,
            pixels,
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// The whole canvas as a rectangle.
    pub fn bounds(&self) -> Rect {
        Rect::new(0, 0, self.width, self.height)
    }

    /// The pixel at (`x`, `y`).
    pub fn pixel(&self, x: u32, y: u32) -> Rgb8 {
        let i = self.index(x, y);
        [self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]]
    }

    fn index(&self, x: u32, y: u32) -> usize {
        (y as usize * self.width as usize + x as usize) * 3
    }

    /// Paints `rect` (within the canvas) in `colour`.
    pub fn fill(&mut self, rect: Rect, colour: Rgb8) {
        for y in rect.y..rect.bottom() {
            for x in rect.x..rect.right() {
                let i = self.index(x, y);
                self.pixels[i..i + 3].copy_from_slice(&colour);
            }
        }
    }

    /// Copies `srgb` (rect.width × rect.height RGB8 pixels, row-major from
    /// the top) into `rect`, which lies within the canvas.
    pub fn put(&mut self, rect: Rect, srgb: &[u8]) {
        let row = rect.width as usize * 3;
        assert_eq!(srgb.len(), row * rect.height as usize, "image size");
        for (y, line) in srgb.chunks_exact(row).enumerate() {
            let start = self.index(rect.x, rect.y + y as u32);
            self.pixels[start..start + row].copy_from_slice(line);
        }
    }

    /// Draws `srgb` (`width` × `height` RGB8 pixels, row-major from the top)
    /// into `rect` (within the canvas), scaled to its size: each pixel of
    /// `rect` is the mean, in linear light, of the source pixels its
    /// footprint covers, each weighted by the share it covers. Enlarged by a
    /// whole factor, a source pixel becomes a block of its own value
    /// (nearest neighbour, as the viewer draws its image); by a fraction,
    /// the pixels on a block's edge mix the two neighbours; reduced, a box
    /// filter. A pixel within one source pixel is a copy of it.
    pub fn put_scaled(&mut self, rect: Rect, (width, height): (u32, u32), srgb: &[u8]) {
        assert_eq!(
            srgb.len(),
            width as usize * height as usize * 3,
            "image size"
        );
        if (rect.width, rect.height) == (width, height) {
            return self.put(rect, srgb);
        }
        if rect.width == 0 || rect.height == 0 || width == 0 || height == 0 {
            return;
        }
        let columns = footprints(width, rect.width);
        let rows = footprints(height, rect.height);
        let to_linear: Vec<f32> = (0..=255u8)
            .map(|c| srgb_to_linear(c as f32 / 255.0))
            .collect();
        let source = |x: u32, y: u32| (y as usize * width as usize + x as usize) * 3;
        for (y, row) in rows.iter().enumerate() {
            for (x, column) in columns.iter().enumerate() {
                let i = self.index(rect.x + x as u32, rect.y + y as u32);
                if let ([(sx, _)], [(sy, _)]) = (column.as_slice(), row.as_slice()) {
                    let j = source(*sx, *sy);
                    self.pixels[i..i + 3].copy_from_slice(&srgb[j..j + 3]);
                    continue;
                }
                let mut sum = [0.0f32; 3];
                for &(sy, wy) in row {
                    for &(sx, wx) in column {
                        let j = source(sx, sy);
                        for (c, total) in sum.iter_mut().enumerate() {
                            *total += wx * wy * to_linear[srgb[j + c] as usize];
                        }
                    }
                }
                for (c, total) in sum.into_iter().enumerate() {
                    self.pixels[i + c] = (linear_to_srgb(total) * 255.0 + 0.5) as u8;
                }
            }
        }
    }

    /// Blends `colour` over every pixel of `rect` (clipped to the canvas) by `alpha`.
    pub fn shade(&mut self, rect: Rect, colour: Rgb8, alpha: f32) {
        let bounds = self.bounds();
        for y in rect.y..rect.bottom().min(self.height) {
            for x in rect.x..rect.right().min(self.width) {
                self.blend(x as i64, y as i64, colour, alpha, bounds);
            }
        }
    }

    /// Blends `colour` over pixel (`x`, `y`) by `coverage` (0 to 1), if it lies in `clip`.
    fn blend(&mut self, x: i64, y: i64, colour: Rgb8, coverage: f32, clip: Rect) {
        if coverage <= 0.0 || !clip.contains(x, y) {
            return;
        }
        let a = coverage.min(1.0);
        let i = self.index(x as u32, y as u32);
        for (under, over) in self.pixels[i..i + 3].iter_mut().zip(colour) {
            let under_f = *under as f32;
            *under = (under_f + (over as f32 - under_f) * a).round() as u8;
        }
    }

    /// Draws one line of `text` at font size `size`, its pen starting at
    /// `left` on the baseline `baseline`, clipped to `clip`; characters
    /// DejaVu Sans lacks print as '?'.
    pub fn draw_text(
        &mut self,
        text: &str,
        size: f32,
        (left, baseline): (f32, f32),
        colour: Rgb8,
        clip: Rect,
    ) {
        let font = dejavu_sans();
        let scale = px_scale(size);
        let (glyphs, _) = set_text(text, size);
        // whole pixels for the pen's start and the baseline: crisp stems
        let (left, baseline) = (left.round(), baseline.round());
        for (id, x) in glyphs {
            let glyph = id.with_scale_and_position(scale, point(left + x, baseline));
            let Some(outline) = font.outline_glyph(glyph) else {
                continue; // a space
            };
            let bounds = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                let x = bounds.min.x as i64 + gx as i64;
                let y = bounds.min.y as i64 + gy as i64;
                self.blend(x, y, colour, coverage, clip);
            });
        }
    }

    /// Draws the segment `from`–`to` (pixel coordinates, pixel centres at
    /// half-integers), `width` pixels wide, clipped to `clip`; `dash`
    /// (on, off) in pixels along the segment makes it dashed.
    pub fn draw_segment(
        &mut self,
        (from, to): (Vec2, Vec2),
        width: f32,
        colour: Rgb8,
        dash: Option<(f32, f32)>,
        clip: Rect,
    ) {
        let d = to - from;
        let length = d.length();
        let reach = width / 2.0 + 1.0;
        let lo = from.min(to) - Vec2::splat(reach);
        let hi = from.max(to) + Vec2::splat(reach);
        let (x0, y0) = (lo.x.max(clip.x as f32), lo.y.max(clip.y as f32));
        let (x1, y1) = (
            hi.x.min(clip.right() as f32),
            hi.y.min(clip.bottom() as f32),
        );
        if x0 >= x1 || y0 >= y1 {
            return;
        }
        for y in y0.floor() as i64..y1.ceil() as i64 {
            for x in x0.floor() as i64..x1.ceil() as i64 {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                // distance to the segment, and how far along it the nearest point is
                let t = if length > 0.0 {
                    ((p - from).dot(d) / (length * length)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let distance = (from + d * t).distance(p);
                if let Some((on, off)) = dash
                    && (t * length) % (on + off) > on
                {
                    continue;
                }
                let coverage = width / 2.0 + 0.5 - distance;
                self.blend(x, y, colour, coverage, clip);
            }
        }
    }

    /// Draws a disc of `radius` pixels at `centre` (`ring`: only a band of
    /// that width around the circle), clipped to `clip`.
    pub fn draw_disc(
        &mut self,
        centre: Vec2,
        radius: f32,
        ring: Option<f32>,
        colour: Rgb8,
        clip: Rect,
    ) {
        let reach = radius + ring.unwrap_or(0.0) + 1.0;
        let (lo, hi) = (centre - Vec2::splat(reach), centre + Vec2::splat(reach));
        for y in lo.y.floor() as i64..hi.y.ceil() as i64 {
            for x in lo.x.floor() as i64..hi.x.ceil() as i64 {
                let distance = centre.distance(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                let coverage = match ring {
                    Some(width) => width / 2.0 + 0.5 - (distance - radius).abs(),
                    None => radius + 0.5 - distance,
                };
                self.blend(x, y, colour, coverage, clip);
            }
        }
    }

    /// The canvas at half its size (rounded down, at least 1 pixel a side):
    /// each pixel the mean of a 2 × 2 block, in sRGB values.
    pub fn half(&self) -> Canvas {
        let (width, height) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let mut pixels = Vec::with_capacity(width as usize * height as usize * 3);
        for y in 0..height {
            for x in 0..width {
                let (xs, ys) = (2 * x, 2 * y);
                let block = [
                    (xs, ys),
                    ((xs + 1).min(self.width - 1), ys),
                    (xs, (ys + 1).min(self.height - 1)),
                    ((xs + 1).min(self.width - 1), (ys + 1).min(self.height - 1)),
                ];
                for c in 0..3 {
                    let sum: u32 = block
                        .iter()
                        .map(|&(bx, by)| self.pixels[self.index(bx, by) + c] as u32)
                        .sum();
                    pixels.push(((sum + 2) / 4) as u8);
                }
            }
        }
        Canvas {
            width,
            height,
            pixels,
        }
    }

    /// The canvas as an image of the `image` crate.
    pub fn to_rgb_image(&self) -> RgbImage {
        RgbImage::from_raw(self.width, self.height, self.pixels.clone())
            .expect("the buffer matches the size")
    }

    /// The canvas as a PNG file's bytes.
    pub fn png_bytes(&self) -> Vec<u8> {
        crate::render::export::encode_png(self.width, self.height, &self.pixels)
            .expect("the buffer matches the size")
    }
}

/// For each of `to` pixels along an axis, the pixels of `from` its
/// footprint [i·from/to, (i+1)·from/to) covers, each with the share of the
/// footprint it covers (they add up to 1).
fn footprints(from: u32, to: u32) -> Vec<Vec<(u32, f32)>> {
    let (from, to) = (from as u64, to as u64);
    (0..to)
        .map(|i| {
            // the footprint in 1/to of a source pixel
            let (start, end) = (i * from, (i + 1) * from);
            (start / to..=(end - 1) / to)
                .map(|s| {
                    let covered = end.min((s + 1) * to) - start.max(s * to);
                    (s as u32, covered as f32 / from as f32)
                })
                .collect()
        })
        .collect()
}

// ───────────────────────── text ─────────────────────────

/// ab_glyph's scale (the height from ascent to descent) of font size `size`.
fn px_scale(size: f32) -> PxScale {
    let font = dejavu_sans();
    let units_per_em = font.units_per_em().expect("the font has a unit size");
    PxScale::from(size * font.height_unscaled() / units_per_em)
}

/// Height above the baseline of the font's tallest glyphs, at font size `size`.
pub fn ascent(size: f32) -> f32 {
    dejavu_sans().as_scaled(px_scale(size)).ascent()
}

/// Depth below the baseline of the font's lowest glyphs (positive), at font size `size`.
pub fn descent(size: f32) -> f32 {
    -dejavu_sans().as_scaled(px_scale(size)).descent()
}

/// The glyphs of `text` at font size `size`, with their pen positions, and its width.
fn set_text(text: &str, size: f32) -> (Vec<(GlyphId, f32)>, f32) {
    font::set_text(dejavu_sans(), text, px_scale(size))
}

/// Width of one line of `text` at font size `size`, in pixels.
pub fn text_width(text: &str, size: f32) -> f32 {
    set_text(text, size).1
}

/// Punctuation that French sets after a space and that must not begin a
/// line: it stays with the word before it.
const NO_BREAK_BEFORE: [&str; 6] = [":", ";", "!", "?", "»", "—"];

/// `text` broken into lines no wider than `max_width` at font size `size`,
/// between words (a word wider than a line gets a line of its own).
pub fn wrap(text: &str, size: f32, max_width: f32) -> Vec<String> {
    let mut words: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match words.last_mut() {
            Some(previous) if NO_BREAK_BEFORE.contains(&word) || previous.ends_with('«') => {
                previous.push(' ');
                previous.push_str(word);
            }
            _ => words.push(word.to_string()),
        }
    }
    let mut lines: Vec<String> = Vec::new();
    for word in words {
        if let Some(line) = lines.last_mut() {
            let longer = format!("{line} {word}");
            if text_width(&longer, size) <= max_width {
                *line = longer;
                continue;
            }
        }
        lines.push(word);
    }
    lines
}

/// `text` shortened with an ellipsis to fit `max_width` at font size `size`
/// (unchanged if it fits).
pub fn ellipsize(text: &str, size: f32, max_width: f32) -> String {
    if text_width(text, size) <= max_width {
        return text.to_string();
    }
    let mut chars: Vec<char> = text.chars().collect();
    while !chars.is_empty() {
        chars.pop();
        let shorter: String = chars.iter().collect::<String>().trim_end().to_string() + "…";
        if text_width(&shorter, size) <= max_width {
            return shorter;
        }
    }
    "…".into()
}

/// One line of `text` at font size `size`, or smaller (down to `min_size`)
/// if it is wider than `max_width`, shortened with an ellipsis if it still
/// is: the line and its size.
pub fn fit_line(text: &str, size: f32, min_size: f32, max_width: f32) -> (String, f32) {
    let width = text_width(text, size);
    if width <= max_width {
        return (text.to_string(), size);
    }
    // the width is proportional to the size
    let fitted = (size * max_width / width).max(min_size);
    (ellipsize(text, fitted, max_width), fitted)
}

/// `text` wrapped onto at most `max_lines` lines of `max_width` at font size
/// `size`, or smaller (by 5% steps, down to `min_size`) if it needs more;
/// the last line ends with an ellipsis if it still does. The lines and their
/// size; `max_lines` is at least 1.
pub fn fit_paragraph(
    text: &str,
    size: f32,
    min_size: f32,
    max_width: f32,
    max_lines: usize,
) -> (Vec<String>, f32) {
    assert!(max_lines >= 1, "a paragraph needs a line");
    let mut size = size;
    loop {
        let lines = wrap(text, size, max_width);
        if lines.len() <= max_lines {
            return (lines, size);
        }
        if size * 0.95 < min_size {
            let mut lines = lines;
            let rest = lines.split_off(max_lines - 1).join(" ");
            lines.push(ellipsize(&rest, size, max_width));
            return (lines, size);
        }
        size *= 0.95;
    }
}
