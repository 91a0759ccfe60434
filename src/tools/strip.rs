//! Convergence strips: one progressive render per row, a snapshot of its film
//! at each listed sample count, tiled side by side and labelled.
//!
//! A row renders passes 0, 1, 2, … into one film, as `render::render` does, and
//! copies the film's image when it holds N₁ < N₂ < … samples per pixel: the
//! tile at N spp is the same image as a render of N spp with the same seed,
//! and the row shows one sequence converging (noise falling as 1/√N).
//!
//! Layout, with n counts, R rows, tiles of w × h pixels and glyph scale s
//! (8 × 8 font, s ≥ 2):
//!
//! ```text
//! band b = 14·s           label band below each tile (8·s glyphs, 3·s margins)
//! left L = 0              without row labels,
//!        = 8·s·k + 6·s    with them (k: characters of the longest row label)
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
use std::time::Instant;

use image::{ImageBuffer, Rgb};

use crate::render::context::RenderContext;
use crate::render::export::{ExportError, to_srgb8};
use crate::render::film::Film;
use crate::render::settings::Choice;
use crate::render::settings::{
    BrdfOverride, DisplaySettings, IndirectSampling, LightMode, LightSampling, LightSelection,
    MAX_SAMPLES_PER_VERTEX, MisHeuristic, RenderSettings, Sampler, TermSet,
};
use crate::render::{PassBuffer, RenderStats, render_pass};
use crate::scene::Scene;
use crate::transport::splitting::choose_continuations;

/// Largest strip side in pixels: a PNG a slide can hold, a buffer memory can.
pub const MAX_STRIP_SIDE: u64 = 16384;
/// Largest sample count of a tile.
pub const MAX_SAMPLE_COUNT: u32 = 100_000_000;
/// Glyph cell of the font, in font pixels.
const GLYPH: u32 = 8;
/// Magnifications tried for the labels, largest first: at least 2 so that
/// labels read on slides.
const SCALES: [u32; 3] = [4, 3, 2];
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
    /// Glyph magnification (2 to 4).
    pub scale: u32,
}

impl StripLayout {
    /// The layout of `column_labels.len()` tiles of `tile_width × tile_height`
    /// per row; glyphs as large as the column labels allow within a tile
    /// (at most 4×, at least 2×: narrower tiles clip their labels).
    pub fn new(
        tile_width: u32,
        tile_height: u32,
        column_labels: Vec<String>,
        row_labels: Vec<String>,
    ) -> Self {
        let longest = column_labels.iter().map(|l| l.len()).max().unwrap_or(0) as u32;
        let scale = SCALES
            .into_iter()
            .find(|s| (longest * GLYPH + 6) * s <= tile_width)
            .unwrap_or(2);
        Self {
            tile_width,
            tile_height,
            column_labels,
            row_labels,
            scale,
        }
    }

    pub fn columns(&self) -> u32 {
        self.column_labels.len() as u32
    }

    pub fn rows(&self) -> u32 {
        self.row_labels.len().max(1) as u32
    }

    /// Height of the label band below each tile.
    pub fn band_height(&self) -> u32 {
        14 * self.scale
    }

    /// Width of the row label column (0 without row labels).
    pub fn label_column_width(&self) -> u32 {
        let longest = self.row_labels.iter().map(|l| l.len()).max();
        longest.map_or(0, |k| (GLYPH * k as u32 + 6) * self.scale)
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
        let (band, scale) = (layout.band_height(), layout.scale);
        let left = layout.label_column_width();
        for row in 0..layout.rows() {
            let (_, top) = layout.tile_origin(row, 0);
            if left > 0 {
                let column = Rect::new(0, top, left, layout.tile_height + band);
                image.fill(column, BAND_COLOR);
                let label = &layout.row_labels[row as usize];
                image.draw_text(column, label, scale);
            }
            for (c, label) in layout.column_labels.iter().enumerate() {
                let (x, y) = layout.tile_origin(row, c as u32);
                let rect = Rect::new(x, y + layout.tile_height, layout.tile_width, band);
                image.fill(rect, BAND_COLOR);
                image.draw_text(rect, label, scale);
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
        let image: ImageBuffer<Rgb<u8>, _> =
            ImageBuffer::from_raw(self.width(), self.height(), self.pixels.as_slice())
                .expect("the buffer matches the layout");
        image.save(path).map_err(|e| ExportError {
            path: path.to_path_buf(),
            problem: e.to_string(),
        })
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

    /// Draws `text` centred in `rect`, glyphs magnified `scale` times and
    /// clipped to `rect`; characters outside ASCII print as '?'.
    fn draw_text(&mut self, rect: Rect, text: &str, scale: u32) {
        let cell = GLYPH * scale;
        let text_width = text.chars().count() as i64 * cell as i64;
        let x0 = rect.x as i64 + (rect.width as i64 - text_width) / 2;
        let y0 = rect.y as i64 + (rect.height as i64 - cell as i64) / 2;
        for (i, c) in text.chars().enumerate() {
            let c = if c.is_ascii() { c } else { '?' };
            let glyph = font8x8::legacy::BASIC_LEGACY[c as usize];
            for (gy, bits) in glyph.into_iter().enumerate() {
                for gx in 0..GLYPH {
                    // bit 0 is the leftmost pixel of a glyph row
                    if bits >> gx & 1 == 0 {
                        continue;
                    }
                    for dy in 0..scale as i64 {
                        for dx in 0..scale as i64 {
                            let x = x0 + i as i64 * cell as i64 + (gx * scale) as i64 + dx;
                            let y = y0 + (gy as u32 * scale) as i64 + dy;
                            if rect.contains(x, y) {
                                self.set(x as u32, y as u32, TEXT_COLOR);
                            }
                        }
                    }
                }
            }
        }
    }
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
mod tests {
    use super::*;

    fn counts(s: &str) -> SampleCounts {
        s.parse().unwrap()
    }

    #[test]
    fn sample_counts_parse_increasing_lists_only() {
        assert_eq!(counts("1, 4,16").as_slice(), &[1, 4, 16]);
        assert_eq!(counts("1,4,16").labels(), ["1 spp", "4 spp", "16 spp"]);
        for (bad, says) in [
            ("0", "at least 1"),
            ("4,2", "increase"),
            ("4,4", "increase"),
            ("abc", "'abc' is not a sample count"),
            ("", "not a sample count"),
            ("1,,4", "not a sample count"),
            ("-1", "not a sample count"),
            ("200000000", "limit"),
        ] {
            let error = bad.parse::<SampleCounts>().unwrap_err();
            assert!(error.contains(says), "{bad:?}: {error}");
        }
    }

    #[test]
    fn row_sweeps_parse_and_apply() {
        let sweep: RowSweep = "light-sampling=area,solid-angle,MIS".parse().unwrap();
        assert_eq!(sweep.option, RowOption::LightSampling);
        let rows = sweep.rows(&RenderSettings::default());
        let labels: Vec<_> = rows.iter().map(|r| r.label.clone().unwrap()).collect();
        assert_eq!(labels, ["area", "solid-angle", "mis"]);
        assert_eq!(rows[1].settings.light_sampling, LightSampling::SolidAngle);

        let terms: RowSweep = "terms=L1,L1+L2,L3+,all".parse().unwrap();
        let sets: Vec<_> = terms
            .rows(&RenderSettings::default())
            .iter()
            .map(|r| (r.settings.terms, r.label.clone().unwrap()))
            .collect();
        assert_eq!(sets[1].0, "L1,L2".parse().unwrap());
        assert_eq!(sets[1].1, "L1+L2");
        assert_eq!(sets[2].0, TermSet::only(crate::Term::L3Plus));
        assert_eq!(sets[3].0, TermSet::ALL);

        let samples: RowSweep = "light-samples=1,16".parse().unwrap();
        assert_eq!(
            samples.rows(&RenderSettings::default())[1]
                .settings
                .light_samples,
            16
        );
        for option in RowOption::ALL {
            let text = format!("{option}=x");
            let error = text.parse::<RowSweep>().unwrap_err();
            assert!(error.starts_with(option.label()), "{error}");
        }
        for (bad, says) in [
            ("light-sampling", "OPTION=V1,V2"),
            ("colour=red", "unknown option 'colour'"),
            ("light-sampling=area,lasers", "unknown value 'lasers'"),
            ("light-samples=0", "within 1..=256"),
            ("terms=L7", "unknown term"),
            ("brdf=", "unknown value ''"),
        ] {
            let error = bad.parse::<RowSweep>().unwrap_err();
            assert!(error.contains(says), "{bad:?}: {error}");
        }
    }

    fn labels(texts: &[&str]) -> Vec<String> {
        texts.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn layout_sizes_and_tile_places() {
        let plain = StripLayout::new(160, 120, labels(&["1 spp", "4 spp", "256 spp"]), vec![]);
        // "256 spp" at 3×: (7·8 + 6)·3 = 186 > 160, at 2×: 124 ≤ 160
        assert_eq!(plain.scale, 2);
        assert_eq!(plain.band_height(), 28);
        assert_eq!((plain.width(), plain.height()), (3 * 160, 120 + 28));
        assert_eq!(plain.tile_origin(0, 2), (320, 0));

        let rows = StripLayout::new(
            640,
            480,
            labels(&["1 spp", "16 spp"]),
            labels(&["area", "mis"]),
        );
        assert_eq!(rows.scale, 4);
        let left = (4 * 8 + 6) * 4;
        assert_eq!(rows.label_column_width(), left);
        assert_eq!(rows.width(), left as u64 + 2 * 640);
        assert_eq!(rows.height(), 2 * (480 + 56));
        assert_eq!(rows.tile_origin(1, 1), (left + 640, 480 + 56));
        assert!(rows.check_size().is_ok());

        let huge = StripLayout::new(4000, 3000, labels(&["1 spp"; 5]), vec![]);
        let error = huge.check_size().unwrap_err();
        assert!(error.contains("20000×3056"), "{error}");
    }

    #[test]
    fn tiles_land_in_place_and_labels_are_drawn_on_dark_bands() {
        let layout = StripLayout::new(48, 20, labels(&["1 spp", "8 spp"]), labels(&["ab", "c"]));
        let mut image = StripImage::new(layout.clone());
        let (w, h) = (layout.tile_width, layout.tile_height);
        for row in 0..2 {
            for column in 0..2 {
                let value = (10 + 40 * row + 80 * column) as u8;
                image.put_tile(row, column, &vec![value; (w * h * 3) as usize]);
            }
        }
        let band = layout.band_height();
        for row in 0..2u32 {
            for column in 0..2u32 {
                let value = (10 + 40 * row + 80 * column) as u8;
                let (x0, y0) = layout.tile_origin(row, column);
                // the tile covers its rectangle exactly
                for (x, y) in [(x0, y0), (x0 + w - 1, y0 + h - 1)] {
                    assert_eq!(image.pixel(x, y), [value; 3], "tile ({row}, {column})");
                }
                // its band is dark with light glyph pixels, none outside the band
                let band_pixels: Vec<[u8; 3]> = (y0 + h..y0 + h + band)
                    .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
                    .map(|(x, y)| image.pixel(x, y))
                    .collect();
                let text = band_pixels.iter().filter(|p| **p == TEXT_COLOR).count();
                let dark = band_pixels.iter().filter(|p| **p == BAND_COLOR).count();
                assert!(text > 20, "band ({row}, {column}) has {text} text pixels");
                assert_eq!(text + dark, band_pixels.len());
            }
            // the row label column holds text too
            let (_, y0) = layout.tile_origin(row, 0);
            let text = (y0..y0 + h + band)
                .flat_map(|y| (0..layout.label_column_width()).map(move |x| (x, y)))
                .filter(|&(x, y)| image.pixel(x, y) == TEXT_COLOR)
                .count();
            assert!(text > 10, "row {row} label has {text} text pixels");
        }
        // lit pixels are the font's, magnified scale × scale
        let lit = |text: &str| {
            let layout = StripLayout::new(200, 4, labels(&[text]), vec![]);
            let image = StripImage::new(layout);
            let count = (0..image.height())
                .flat_map(|y| (0..200).map(move |x| (x, y)))
                .filter(|&(x, y)| image.pixel(x, y) == TEXT_COLOR)
                .count();
            (count, image.layout.scale as usize)
        };
        assert_eq!(lit("").0, 0);
        assert!(lit("1 spp").0 > lit("1").0);
        // '1' is 0x0C, 0x0E, 0x0C, 0x0C, 0x0C, 0x0C, 0x3F, 0x00: 19 font pixels
        let (count, scale) = lit("1");
        assert_eq!(count, 19 * scale * scale);
    }
}
