//! Convergence strips: one progressive render per row, a snapshot of its film
//! at each listed sample count, tiled side by side and labelled.
//!
//! A row renders passes 0, 1, 2, … into one film, as `render::render` does, and
//! copies the film's image when it holds N₁ < N₂ < … samples per pixel: the
//! tile at N spp is the same image as a render of N spp with the same seed,
//! and the row shows one sequence converging (noise falling as 1/√N).
//!
//! Labels are set in the Hack font ([`crate::tools::font`]), rasterized by
//! ab_glyph and blended over the dark bands by their coverage (antialiased).
//! Their size t is the height from the font's ascent to its descent, in
//! pixels: the smaller of w/8 and h/6 for tiles of w × h pixels (32 px for
//! 256 × 192), within 14..=64 px, and smaller if the longest column label
//! would not fit a tile with its margins (down to 14 px: narrower tiles clip
//! their labels).
//!
//! Layout, with n counts, R rows, tiles of w × h pixels, text size t and
//! margin m = ⌈t/3⌉:
//!
//! ```text
//! band b = t + 2·m        label band below each tile, the text centred in it
//! left L = 0              without row labels,
//!        = ⌈W⌉ + 2·m      with them (W: width of the longest row label)
//! width  = L + n·w
//! height = R·(h + b)
//! tile (r, c) at (L + c·w, r·(h + b)); its band at (L + c·w, r·(h + b) + h)
//! ```
//!
//! The image is display-referred (the PNG export's exposure, tonemap, sRGB):
//! labels are pixels, so a strip is written as PNG only.

use std::fmt;
use std::path::Path;
use std::str::FromStr;
use std::sync::Arc;

use ab_glyph::{Font, GlyphId, PxScale, ScaleFont, point};

use crate::course::Choice;
use crate::course::{
    BrdfOverride, IndirectSampling, LightMode, LightSampling, LightSelection,
    MAX_SAMPLES_PER_VERTEX, MisHeuristic, RenderSettings, Sampler, TermSet,
};
use crate::platform::time::Instant;
use crate::render::display::DisplaySettings;
use crate::render::export::{ExportError, to_srgb8};
use crate::render::film::Film;
use crate::render::{PassBuffer, RenderStats, render_pass};
use crate::scene::Scene;
use crate::tools::font::{self, hack_regular};
use crate::transport::context::RenderContext;
use crate::transport::splitting::choose_continuations;

/// Largest strip side in pixels: a PNG a slide can hold, a buffer memory can.
pub const MAX_STRIP_SIDE: u64 = 16384;
/// Largest sample count of a tile.
pub const MAX_SAMPLE_COUNT: u32 = 100_000_000;
/// Label text size (ascent to descent, in pixels) per pixel of tile width…
const TEXT_PER_TILE_WIDTH: f32 = 1.0 / 8.0;
/// …and at most this per pixel of tile height (equal for 4:3 tiles).
const TEXT_PER_TILE_HEIGHT: f32 = 1.0 / 6.0;
/// Smallest label text: still legible on a slide.
pub const MIN_TEXT_SIZE: u32 = 14;
/// Largest label text.
pub const MAX_TEXT_SIZE: u32 = 64;
/// Background of the label bands and column.
pub const BAND_COLOR: [u8; 3] = [24, 24, 24];
/// Colour of the label glyphs.
pub const TEXT_COLOR: [u8; 3] = [240, 240, 240];

// ───────────────────────── sample counts ─────────────────────────

/// The sample counts of a strip's tiles, strictly increasing (each ≥ 1).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SampleCounts(Vec<u32>);

impl SampleCounts {
    pub fn as_slice(&self) -> &[u32] {
        &self.0
    }

    /// The last and largest count: the passes a row renders.
    pub fn max(&self) -> u32 {
        *self.0.last().expect("at least one count")
    }

    /// 1, 2, 4, 8, … below `max`, then `max` (at least 1): the frames of a
    /// convergence animation.
    pub fn doubling_to(max: u32) -> Self {
        let max = max.max(1);
        let mut counts: Vec<u32> = std::iter::successors(Some(1u32), |n| n.checked_mul(2))
            .take_while(|&n| n < max)
            .collect();
        counts.push(max);
        Self(counts)
    }

    /// One count, `count` (at least 1).
    pub fn only(count: u32) -> Self {
        Self(vec![count.max(1)])
    }

    /// "1 spp", "4 spp", …
    pub fn labels(&self) -> Vec<String> {
        self.0.iter().map(|n| format!("{n} spp")).collect()
    }
}

impl FromStr for SampleCounts {
    type Err = String;

    /// `1,4,16,64`: positive integers, strictly increasing (the order of the
    /// tiles is the order of the render, so an unsorted list is refused
    /// rather than silently reordered).
    fn from_str(s: &str) -> Result<Self, String> {
        let mut counts: Vec<u32> = Vec::new();
        for word in s.split(',').map(str::trim) {
            let n: u32 = word.parse().map_err(|_| {
                format!("'{word}' is not a sample count (expected positive integers separated by commas, e.g. 1,4,16)")
            })?;
            if n == 0 {
                return Err("a sample count must be at least 1".into());
            }
            if n > MAX_SAMPLE_COUNT {
                return Err(format!(
                    "sample count {n} is above the limit {MAX_SAMPLE_COUNT}"
                ));
            }
            if let Some(&previous) = counts.last()
                && n <= previous
            {
                return Err(format!(
                    "sample counts must increase from left to right, but {previous} is followed by {n}"
                ));
            }
            counts.push(n);
        }
        Ok(Self(counts))
    }
}

// ───────────────────────── rows ─────────────────────────

/// An estimator option a strip can vary from row to row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowOption {
    LightSampling,
    IndirectSampling,
    Sampler,
    LightSamples,
    IndirectSamples,
    LightSelection,
    MisHeuristic,
    Lights,
    Brdf,
    Terms,
}

impl RowOption {
    pub const ALL: [RowOption; 10] = [
        RowOption::LightSampling,
        RowOption::IndirectSampling,
        RowOption::Sampler,
        RowOption::LightSamples,
        RowOption::IndirectSamples,
        RowOption::LightSelection,
        RowOption::MisHeuristic,
        RowOption::Lights,
        RowOption::Brdf,
        RowOption::Terms,
    ];

    /// The command-line flag's name, without `--`.
    pub fn label(self) -> &'static str {
        match self {
            RowOption::LightSampling => "light-sampling",
            RowOption::IndirectSampling => "indirect-sampling",
            RowOption::Sampler => "sampler",
            RowOption::LightSamples => "light-samples",
            RowOption::IndirectSamples => "indirect-samples",
            RowOption::LightSelection => "light-selection",
            RowOption::MisHeuristic => "mis-heuristic",
            RowOption::Lights => "lights",
            RowOption::Brdf => "brdf",
            RowOption::Terms => "terms",
        }
    }

    /// Parses one value of this option.
    pub fn parse_value(self, s: &str) -> Result<RowValue, String> {
        Ok(match self {
            RowOption::LightSampling => RowValue::LightSampling(s.parse()?),
            RowOption::IndirectSampling => RowValue::IndirectSampling(s.parse()?),
            RowOption::Sampler => RowValue::Sampler(s.parse()?),
            RowOption::LightSamples => RowValue::LightSamples(parse_per_vertex(s)?),
            RowOption::IndirectSamples => RowValue::IndirectSamples(parse_per_vertex(s)?),
            RowOption::LightSelection => RowValue::LightSelection(s.parse()?),
            RowOption::MisHeuristic => RowValue::MisHeuristic(s.parse()?),
            RowOption::Lights => RowValue::Lights(s.parse()?),
            RowOption::Brdf => RowValue::Brdf(s.parse()?),
            // terms are joined by '+' (',' separates the rows): L1+L2, L3+, all
            RowOption::Terms => {
                let words: Vec<&str> = s.split('+').filter(|w| !w.trim().is_empty()).collect();
                RowValue::Terms(words.join(",").parse()?)
            }
        })
    }
}

impl fmt::Display for RowOption {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

fn parse_per_vertex(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(n) if (1..=MAX_SAMPLES_PER_VERTEX).contains(&n) => Ok(n),
        _ => Err(format!(
            "'{s}' is not a sample count within 1..={MAX_SAMPLES_PER_VERTEX}"
        )),
    }
}

/// One row's value of a [`RowOption`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RowValue {
    LightSampling(LightSampling),
    IndirectSampling(IndirectSampling),
    Sampler(Sampler),
    LightSamples(u32),
    IndirectSamples(u32),
    LightSelection(LightSelection),
    MisHeuristic(MisHeuristic),
    Lights(LightMode),
    Brdf(BrdfOverride),
    Terms(TermSet),
}

impl RowValue {
    /// `settings` with this value in place of the option's.
    pub fn apply(self, settings: &RenderSettings) -> RenderSettings {
        let mut settings = settings.clone();
        match self {
            RowValue::LightSampling(v) => settings.light_sampling = v,
            RowValue::IndirectSampling(v) => settings.indirect_sampling = v,
            RowValue::Sampler(v) => settings.sampler = v,
            RowValue::LightSamples(v) => settings.light_samples = v,
            RowValue::IndirectSamples(v) => settings.indirect_samples = v,
            RowValue::LightSelection(v) => settings.light_selection = v,
            RowValue::MisHeuristic(v) => settings.mis_heuristic = v,
            RowValue::Lights(v) => settings.light_mode = v,
            RowValue::Brdf(v) => settings.brdf = v,
            RowValue::Terms(v) => settings.terms = v,
        }
        settings
    }

    /// The row's label in the image: the value, with what it counts for the
    /// two sample counts.
    pub fn label(self) -> String {
        match self {
            RowValue::LightSampling(v) => v.label().into(),
            RowValue::IndirectSampling(v) => v.label().into(),
            RowValue::Sampler(v) => v.label().into(),
            RowValue::LightSamples(n) => format!("light x{n}"),
            RowValue::IndirectSamples(n) => format!("indirect x{n}"),
            RowValue::LightSelection(v) => v.label().into(),
            RowValue::MisHeuristic(v) => v.label().into(),
            RowValue::Lights(v) => v.label().into(),
            RowValue::Brdf(v) => v.label().into(),
            RowValue::Terms(v) => v.to_string().replace(',', "+"),
        }
    }
}

/// `--rows OPTION=V1,V2,…`: one row per value of one option.
#[derive(Clone, Debug, PartialEq)]
pub struct RowSweep {
    pub option: RowOption,
    pub values: Vec<RowValue>,
}

impl RowSweep {
    /// One row per value: its label and its settings (`base` with the value).
    pub fn rows(&self, base: &RenderSettings) -> Vec<StripRow> {
        self.values
            .iter()
            .map(|v| StripRow {
                label: Some(v.label()),
                settings: v.apply(base),
            })
            .collect()
    }
}

impl FromStr for RowSweep {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let names: Vec<&str> = RowOption::ALL.iter().map(|o| o.label()).collect();
        let Some((name, values)) = s.split_once('=') else {
            return Err(format!(
                "'{s}' is not OPTION=V1,V2,… (e.g. light-sampling=area,mis); OPTION is one of: {}",
                names.join(", ")
            ));
        };
        let name = name.trim().trim_start_matches("--");
        let option = RowOption::ALL
            .into_iter()
            .find(|o| o.label().eq_ignore_ascii_case(name))
            .ok_or_else(|| {
                format!(
                    "unknown option '{name}' (expected one of: {})",
                    names.join(", ")
                )
            })?;
        let values = values
            .split(',')
            .map(|v| {
                option
                    .parse_value(v.trim())
                    .map_err(|e| format!("{option}: {e}"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { option, values })
    }
}

/// One row of a strip: its settings and, with `--rows`, its label.
#[derive(Clone, Debug, PartialEq)]
pub struct StripRow {
    pub label: Option<String>,
    pub settings: RenderSettings,
}

// ───────────────────────── layout ─────────────────────────

/// Where tiles and labels go.
#[derive(Clone, Debug, PartialEq)]
pub struct StripLayout {
    pub tile_width: u32,
    pub tile_height: u32,
    /// One per column, drawn in the band below each tile.
    pub column_labels: Vec<String>,
    /// One per row, drawn left of the row; empty: one row, no label column.
    pub row_labels: Vec<String>,
    /// Height of the label text from the font's ascent to its descent, in
    /// pixels ([`MIN_TEXT_SIZE`] to [`MAX_TEXT_SIZE`]).
    pub text_size: u32,
}

impl StripLayout {
    /// The layout of `column_labels.len()` tiles of `tile_width × tile_height`
    /// per row; text of tile_width/8 pixels (tile_height/6 if smaller),
    /// smaller still if a column label would not fit a tile with its
    /// margins, but at least [`MIN_TEXT_SIZE`] (narrower tiles clip their
    /// labels).
    pub fn new(
        tile_width: u32,
        tile_height: u32,
        column_labels: Vec<String>,
        row_labels: Vec<String>,
    ) -> Self {
        let size = (tile_width as f32 * TEXT_PER_TILE_WIDTH)
            .min(tile_height as f32 * TEXT_PER_TILE_HEIGHT);
        let mut text_size = (size.round() as u32).clamp(MIN_TEXT_SIZE, MAX_TEXT_SIZE);
        let fits = |size: u32| {
            column_labels
                .iter()
                .all(|l| text_width(l, size).ceil() as u32 + 2 * margin(size) <= tile_width)
        };
        while text_size > MIN_TEXT_SIZE && !fits(text_size) {
            text_size -= 1;
        }
        Self {
            tile_width,
            tile_height,
            column_labels,
            row_labels,
            text_size,
        }
    }

    pub fn columns(&self) -> u32 {
        self.column_labels.len() as u32
    }

    pub fn rows(&self) -> u32 {
        self.row_labels.len().max(1) as u32
    }

    /// Space between a label and the edges of its band or column.
    pub fn margin(&self) -> u32 {
        margin(self.text_size)
    }

    /// Height of the label band below each tile.
    pub fn band_height(&self) -> u32 {
        self.text_size + 2 * self.margin()
    }

    /// Width of the row label column (0 without row labels).
    pub fn label_column_width(&self) -> u32 {
        let widest = self
            .row_labels
            .iter()
            .map(|l| text_width(l, self.text_size))
            .max_by(f32::total_cmp);
        widest.map_or(0, |w| w.ceil() as u32 + 2 * self.margin())
    }

    /// Strip width in pixels (u64: checked against [`MAX_STRIP_SIDE`] before use).
    pub fn width(&self) -> u64 {
        self.label_column_width() as u64 + self.columns() as u64 * self.tile_width as u64
    }

    pub fn height(&self) -> u64 {
        self.rows() as u64 * (self.tile_height as u64 + self.band_height() as u64)
    }

    /// Top-left pixel of tile (`row`, `column`).
    pub fn tile_origin(&self, row: u32, column: u32) -> (u32, u32) {
        (
            self.label_column_width() + column * self.tile_width,
            row * (self.tile_height + self.band_height()),
        )
    }

    /// Refuses strips too large to write, saying how large this one is.
    pub fn check_size(&self) -> Result<(), String> {
        let (w, h) = (self.width(), self.height());
        if w > MAX_STRIP_SIDE || h > MAX_STRIP_SIDE {
            return Err(format!(
                "a strip of {} × {} tiles of {}×{} px with labels is {w}×{h} px ({:.1} MiB); the limit is {MAX_STRIP_SIDE} px a side (make the tiles smaller with --width/--height)",
                self.columns(),
                self.rows(),
                self.tile_width,
                self.tile_height,
                (w * h * 3) as f64 / (1u64 << 20) as f64
            ));
        }
        Ok(())
    }
}

// ───────────────────────── image ─────────────────────────

/// A strip being composed: 8-bit sRGB, row-major from the top.
#[derive(Clone, Debug)]
pub struct StripImage {
    pub layout: StripLayout,
    pixels: Vec<u8>,
}

impl StripImage {
    /// Dark bands and label column with their labels; tiles black until placed.
    /// The layout must pass [`StripLayout::check_size`].
    pub fn new(layout: StripLayout) -> Self {
        let (width, height) = (layout.width() as u32, layout.height() as u32);
        let mut image = Self {
            pixels: vec![0; width as usize * height as usize * 3],
            layout,
        };
        let layout = image.layout.clone();
        let (band, size) = (layout.band_height(), layout.text_size);
        let left = layout.label_column_width();
        for row in 0..layout.rows() {
            let (_, top) = layout.tile_origin(row, 0);
            if left > 0 {
                let column = Rect::new(0, top, left, layout.tile_height + band);
                image.fill(column, BAND_COLOR);
                let label = &layout.row_labels[row as usize];
                image.draw_text(column, label, size);
            }
            for (c, label) in layout.column_labels.iter().enumerate() {
                let (x, y) = layout.tile_origin(row, c as u32);
                let rect = Rect::new(x, y + layout.tile_height, layout.tile_width, band);
                image.fill(rect, BAND_COLOR);
                image.draw_text(rect, label, size);
            }
        }
        image
    }

    pub fn width(&self) -> u32 {
        self.layout.width() as u32
    }

    pub fn height(&self) -> u32 {
        self.layout.height() as u32
    }

    /// Places tile (`row`, `column`): `srgb` holds tile_width × tile_height
    /// RGB8 pixels, row-major from the top.
    pub fn put_tile(&mut self, row: u32, column: u32, srgb: &[u8]) {
        let (tw, th) = (
            self.layout.tile_width as usize,
            self.layout.tile_height as usize,
        );
        assert_eq!(
            srgb.len(),
            tw * th * 3,
            "tile size differs from the layout's"
        );
        let (x0, y0) = self.layout.tile_origin(row, column);
        let stride = self.width() as usize * 3;
        for (y, line) in srgb.chunks_exact(tw * 3).enumerate() {
            let start = (y0 as usize + y) * stride + x0 as usize * 3;
            self.pixels[start..start + tw * 3].copy_from_slice(line);
        }
    }

    /// The RGB8 pixel at (`x`, `y`).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = (y as usize * self.width() as usize + x as usize) * 3;
        [self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]]
    }

    pub fn save_png(&self, path: &Path) -> Result<(), ExportError> {
        std::fs::write(path, self.png_bytes()).map_err(|e| ExportError {
            path: path.to_path_buf(),
            problem: format!("cannot write: {e}"),
        })
    }

    /// The PNG file's bytes.
    pub fn png_bytes(&self) -> Vec<u8> {
        crate::render::export::encode_png(self.width(), self.height(), &self.pixels)
            .expect("the buffer matches the layout")
    }

    fn fill(&mut self, rect: Rect, color: [u8; 3]) {
        for y in rect.y..rect.y + rect.height {
            for x in rect.x..rect.x + rect.width {
                self.set(x, y, color);
            }
        }
    }

    fn set(&mut self, x: u32, y: u32, color: [u8; 3]) {
        let i = (y as usize * self.width() as usize + x as usize) * 3;
        self.pixels[i..i + 3].copy_from_slice(&color);
    }

    /// Blends `color` over pixel (`x`, `y`) by `coverage` (0 to 1).
    fn blend(&mut self, x: u32, y: u32, color: [u8; 3], coverage: f32) {
        let a = coverage.clamp(0.0, 1.0);
        let i = (y as usize * self.width() as usize + x as usize) * 3;
        for (under, over) in self.pixels[i..i + 3].iter_mut().zip(color) {
            let under_f = *under as f32;
            *under = (under_f + (over as f32 - under_f) * a).round() as u8;
        }
    }

    /// Draws `text` of `size` pixels (ascent to descent) centred in `rect`,
    /// antialiased and clipped to `rect`; characters the font lacks print
    /// as '?'.
    fn draw_text(&mut self, rect: Rect, text: &str, size: u32) {
        let font = hack_regular();
        let scale = PxScale::from(size as f32);
        let (glyphs, width) = set_text(text, size);
        // whole pixels for the pen's start and the baseline: the same label
        // is drawn alike in every band
        let left = (rect.x as f32 + (rect.width as f32 - width) / 2.0).round();
        let top = rect.y as f32 + (rect.height as f32 - size as f32) / 2.0;
        let baseline = (top + font.as_scaled(scale).ascent()).round();
        for (id, x) in glyphs {
            let glyph = id.with_scale_and_position(scale, point(left + x, baseline));
            let Some(outline) = font.outline_glyph(glyph) else {
                continue; // a space
            };
            let bounds = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                let x = bounds.min.x as i64 + gx as i64;
                let y = bounds.min.y as i64 + gy as i64;
                if rect.contains(x, y) {
                    self.blend(x as u32, y as u32, TEXT_COLOR, coverage);
                }
            });
        }
    }
}

/// The glyphs of `text` at `size` pixels, with their pen positions, and its width.
fn set_text(text: &str, size: u32) -> (Vec<(GlyphId, f32)>, f32) {
    font::set_text(hack_regular(), text, PxScale::from(size as f32))
}

/// Width of `text` at `size` pixels.
fn text_width(text: &str, size: u32) -> f32 {
    set_text(text, size).1
}

/// Whether `label` fits a tile `tile_width` pixels wide, with its margins,
/// at the smallest text size (else it is clipped).
pub fn label_fits(label: &str, tile_width: u32) -> bool {
    text_width(label, MIN_TEXT_SIZE).ceil() as u32 + 2 * margin(MIN_TEXT_SIZE) <= tile_width
}

/// Space around labels of `size` pixels.
fn margin(size: u32) -> u32 {
    size.div_ceil(3)
}

#[derive(Clone, Copy, Debug)]
struct Rect {
    x: u32,
    y: u32,
    width: u32,
    height: u32,
}

impl Rect {
    fn new(x: u32, y: u32, width: u32, height: u32) -> Self {
        Self {
            x,
            y,
            width,
            height,
        }
    }

    fn contains(&self, x: i64, y: i64) -> bool {
        (self.x as i64..(self.x + self.width) as i64).contains(&x)
            && (self.y as i64..(self.y + self.height) as i64).contains(&y)
    }
}

// ───────────────────────── rendering ─────────────────────────

/// Renders one row: passes 0, 1, … of `context` into a fresh film until it
/// holds `counts.max()` samples per pixel, calling `tile(i, &film)` when it
/// holds `counts[i]` and `progress` after every pass.
pub fn render_row(
    context: &RenderContext,
    counts: &SampleCounts,
    mut progress: impl FnMut(&RenderStats),
    mut tile: impl FnMut(usize, &Film),
) -> RenderStats {
    let start = Instant::now();
    let settings = &context.settings;
    let mut film = Film::new(settings.width, settings.height);
    let mut buffer = PassBuffer::default();
    let mut stats = RenderStats::default();
    let mut next = 0;
    // pass s is sample s of every pixel, as in render::render on a new film
    for pass in 0..counts.max() {
        let rays = render_pass(context, &mut film, pass, &mut buffer);
        stats.rays.add(&rays);
        stats.samples_per_pixel = pass + 1;
        stats.elapsed = start.elapsed();
        if counts.as_slice()[next] == pass + 1 {
            tile(next, &film);
            next += 1;
        }
        progress(&stats);
    }
    stats
}

/// Renders every row of a strip into `image`, one progressive render per
/// row. `progress(row, stats)` follows each pass, `row_done(row, stats)`
/// each row.
pub fn render_strip(
    scene: Arc<Scene>,
    rows: &[StripRow],
    counts: &SampleCounts,
    display: DisplaySettings,
    image: &mut StripImage,
    mut progress: impl FnMut(usize, &RenderStats),
    mut row_done: impl FnMut(usize, &RenderStats),
) {
    for (r, row) in rows.iter().enumerate() {
        let mut context = RenderContext::new(scene.clone(), row.settings.clone());
        choose_continuations(&mut context);
        let stats = render_row(
            &context,
            counts,
            |stats| progress(r, stats),
            |column, film| {
                let srgb = to_srgb8(&film.radiance(row.settings.terms), display);
                image.put_tile(r as u32, column as u32, &srgb);
            },
        );
        row_done(r, &stats);
    }
}

#[cfg(test)]
mod tests;
