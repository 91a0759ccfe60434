//! Slides of a lesson (`lumiere lesson NAME --export DIR`): each step
//! rendered and laid out as a 16:9 slide, with its title, formula and
//! caption as the viewer draws them over the image, an `index.md` listing
//! them and, with `--gif`, a convergence animation per step.
//!
//! Layout of a slide of W × H pixels (1920 × 1080 by default), every length
//! in proportion to H (u = H / 1080; sizes are font sizes in DejaVu Sans,
//! the em square in pixels):
//!
//! ```text
//! ┌──────────────────────────────────────────────────────────────┐ ─┐
//! │  4. L = L₀ + L₁ + L₂                        title   54u px   │  │ top band
//! │  Lᵣ(p, ωₒ) = Lₑ(p, ωₒ) + L_direct + …      formula 40u px   │  │ padding 24u,
//! ├─────────────────┬──────────────────────────┬─────────────────┤ ─┘ gap 10u
//! │                 │                          │  colour bar     │
//! │     margin      │  the render, 4:3, as     │  (noise views)  │    image area:
//! │                 │  tall as the space left  │                 │    what the bands
//! │                 │  between the bands       │                 │    leave
//! ├─────────────────┴──────────────────────────┴─────────────────┤ ─┐
//! │  The sum of the three terms: emission + direct lighting …    │  │ bottom band
//! │  … wrapped onto up to 3 lines              caption 34u px    │  │ padding 24u,
//! │                                            line pitch 1.25 em│  │ 3 lines
//! └──────────────────────────────────────────────────────────────┘ ─┘
//!  ↑ text starts 48u from the left edge and ends 48u from the right one
//! ```
//!
//! * The bands are the same on every slide (the caption band always holds
//!   three lines), so the image sits at the same place throughout a lesson.
//! * The render keeps the aspect of the frame lessons are written for
//!   ([`crate::lesson::PROBE_FRAME`], 640 × 480, the viewer's film): its film
//!   is as tall as the space between the bands and 4/3 as wide, centred, so
//!   a 16:9 slide has dark margins on both sides (on a narrow slide it is as
//!   wide as the text instead, and centred vertically). At 1920 × 1080 the
//!   film is 985 × 739.
//! * The title ("4. " and the step's title) and the formula take one line
//!   each: a longer one is set smaller (down to 60%), then cut with "…". The
//!   caption wraps between words (French punctuation stays with its word);
//!   if it needs more than three lines it is set smaller (down to 70%), then
//!   its third line is cut with "…".
//! * A noise view (standard error, relative error, sample count) shows its
//!   false-colour map ([`crate::analysis::noise`]) with a vertical colour bar
//!   and its range in the margin right of the image, when the margin is wide
//!   enough. A probed pixel shows the rays of its first sample, coloured by
//!   term as in the viewer's path view ([`crate::analysis::path_view`]).
//! * The image region holds the same pixels as `lumiere render` of the
//!   step's settings at the film's size, with the same seed and sample
//!   count (the PNG export's exposure, tonemap and sRGB).
//!
//! The GIF (`--gif`) shows the same render at 1, 2, 4, 8, … samples per
//! pixel up to the step's count (one progressive render, a frame copied
//! when the film reaches each count, as the strips do), each frame the
//! whole slide with an "N spp" label at the image's lower right corner, at
//! half the slide's size (960 × 540 by default: a GIF has 256 colours a
//! frame and grows with the pixels), 0.7 s a frame, the last held 2.1 s,
//! looping.

mod canvas;
mod overlays;
mod render;
pub mod shown;
#[cfg(test)]
mod shown_tests;
#[cfg(test)]
mod tests;

pub use canvas::{Canvas, Rect, Rgb8};
pub use overlays::false_colour_srgb8;
pub use render::{GifWriter, SlideRender, frame_counts, render_slide};

use crate::lesson::{Lang, Lesson, PROBE_FRAME, StepView};

/// Largest slide side in pixels.
pub const MAX_SLIDE_SIDE: u32 = 16384;
/// The reference slide height: lengths below are for it, and scale with H.
const REFERENCE_HEIGHT: f32 = 1080.0;
/// Font size of the title, per 1080 px of slide height.
const TITLE_SIZE: f32 = 54.0;
/// Font size of the formula.
const FORMULA_SIZE: f32 = 40.0;
/// Font size of the caption.
const CAPTION_SIZE: f32 = 34.0;
/// Space above and below the text of each band.
const BAND_PADDING: f32 = 24.0;
/// Space between the title and the formula.
const TITLE_GAP: f32 = 10.0;
/// Space between the slide's left and right edges and the text.
const SIDE_MARGIN: f32 = 48.0;
/// Distance between the caption's baselines, in ems.
const CAPTION_PITCH: f32 = 1.25;
/// Lines the caption band holds.
pub const CAPTION_LINES: usize = 3;
/// Smallest fraction of its size a title or formula is set at to fit its line.
const MIN_LINE_SCALE: f32 = 0.6;
/// Smallest fraction of its size the caption is set at to fit its lines.
const MIN_CAPTION_SCALE: f32 = 0.7;
/// Smallest film the image region may have.
const MIN_IMAGE: (u32, u32) = (16, 12);

/// Background of the slide, around the image.
pub const BACKGROUND: Rgb8 = [20, 20, 24];
/// Background of the title and caption bands.
pub const BAND_COLOR: Rgb8 = [20, 20, 24];
/// Colour of the title and the caption.
pub const TEXT_COLOR: Rgb8 = [242, 242, 242];
/// Colour of the formula: warm, to set it apart from the title.
pub const FORMULA_COLOR: Rgb8 = [255, 214, 140];

/// Where everything goes on a slide.
#[derive(Clone, Debug, PartialEq)]
pub struct SlideLayout {
    pub width: u32,
    pub height: u32,
    /// Font sizes (em, pixels).
    pub title_size: f32,
    pub formula_size: f32,
    pub caption_size: f32,
    /// Padding of the bands, gap under the title, side margin (pixels).
    pub padding: f32,
    pub title_gap: f32,
    pub side_margin: f32,
    /// The title and formula band, across the top.
    pub top_band: Rect,
    /// The caption band, across the bottom.
    pub bottom_band: Rect,
    /// Where the render goes: its film's size and place.
    pub image: Rect,
}

impl SlideLayout {
    /// The layout of a `width` × `height` slide (see the module's header).
    /// A slide too small for its bands has an empty image: see [`SlideLayout::check`].
    pub fn new(width: u32, height: u32) -> Self {
        let u = height as f32 / REFERENCE_HEIGHT;
        let (title_size, formula_size, caption_size) =
            (TITLE_SIZE * u, FORMULA_SIZE * u, CAPTION_SIZE * u);
        let (padding, title_gap, side_margin) = (BAND_PADDING * u, TITLE_GAP * u, SIDE_MARGIN * u);
        let line = |size: f32| canvas::ascent(size) + canvas::descent(size);
        let top = 2.0 * padding + line(title_size) + title_gap + line(formula_size);
        let bottom = 2.0 * padding
            + line(caption_size)
            + (CAPTION_LINES - 1) as f32 * CAPTION_PITCH * caption_size;
        let top = (top.ceil() as u32).min(height);
        let bottom = (bottom.ceil() as u32).min(height - top);
        let top_band = Rect::new(0, 0, width, top);
        let bottom_band = Rect::new(0, height - bottom, width, bottom);
        // the image: the frame's aspect, as tall as the space left, at most as wide as the text
        let area_height = height - top - bottom;
        let (frame_width, frame_height) = (PROBE_FRAME.0 as u64, PROBE_FRAME.1 as u64);
        let max_width = width.saturating_sub(2 * side_margin.round() as u32);
        let mut image_width = (area_height as u64 * frame_width / frame_height) as u32;
        let mut image_height = area_height;
        if image_width > max_width {
            image_width = max_width;
            image_height = (max_width as u64 * frame_height / frame_width) as u32;
        }
        let image = Rect::new(
            (width - image_width) / 2,
            top + (area_height - image_height) / 2,
            image_width,
            image_height,
        );
        Self {
            width,
            height,
            title_size,
            formula_size,
            caption_size,
            padding,
            title_gap,
            side_margin,
            top_band,
            bottom_band,
            image,
        }
    }

    /// Refuses slides too large to write or too small to hold an image
    /// between their bands, saying why.
    pub fn check(&self) -> Result<(), String> {
        let (w, h) = (self.width, self.height);
        if w == 0 || h == 0 || w > MAX_SLIDE_SIDE || h > MAX_SLIDE_SIDE {
            return Err(format!(
                "a slide of {w}×{h} px: each side must be within 1..={MAX_SLIDE_SIDE} px"
            ));
        }
        if self.image.width < MIN_IMAGE.0 || self.image.height < MIN_IMAGE.1 {
            return Err(format!(
                "a slide of {w}×{h} px leaves an image of {}×{} px between its text bands; at least {}×{} are needed (e.g. --width 320 --height 180)",
                self.image.width, self.image.height, MIN_IMAGE.0, MIN_IMAGE.1
            ));
        }
        Ok(())
    }

    /// Width available to a line of text.
    pub fn text_width(&self) -> f32 {
        self.width as f32 - 2.0 * self.side_margin
    }

    /// The rectangle the caption's text may cover (the band less its padding and margins).
    pub fn caption_rect(&self) -> Rect {
        inset(self.bottom_band, self.side_margin, self.padding)
    }

    /// The rectangle the title and the formula may cover.
    pub fn title_rect(&self) -> Rect {
        inset(self.top_band, self.side_margin, self.padding)
    }

    /// The margin right of the image, where a colour bar goes.
    pub fn right_margin(&self) -> Rect {
        Rect::new(
            self.image.right(),
            self.image.y,
            self.width - self.image.right(),
            self.image.height,
        )
    }
}

/// `rect` less `x` on the left and right and `y` above and below.
fn inset(rect: Rect, x: f32, y: f32) -> Rect {
    let (x, y) = (x.round() as u32, y.round() as u32);
    Rect::new(
        rect.x + x.min(rect.width / 2),
        rect.y + y.min(rect.height / 2),
        rect.width.saturating_sub(2 * x),
        rect.height.saturating_sub(2 * y),
    )
}

/// What a slide says: its title line, formula and caption.
#[derive(Clone, Debug, PartialEq)]
pub struct SlideTexts {
    /// "4. " and the step's title.
    pub title: String,
    pub formula: String,
    pub caption: String,
}

impl SlideTexts {
    /// The texts of step `index` (from 0) of `lesson` in `lang`.
    pub fn of(lesson: &Lesson, index: usize, lang: Lang) -> Self {
        let step = &lesson.steps[index];
        Self {
            title: format!("{}. {}", index + 1, step.title.get(lang)),
            formula: step.formula.clone(),
            caption: step.caption.get(lang).to_string(),
        }
    }
}

/// A slide without its image: the background, the bands and their text.
#[derive(Clone, Debug)]
pub struct Slide {
    pub layout: SlideLayout,
    pub texts: SlideTexts,
    base: Canvas,
}

impl Slide {
    /// Lays out `texts` on a slide of `layout` (which must pass [`SlideLayout::check`]).
    pub fn new(layout: SlideLayout, texts: &SlideTexts) -> Self {
        let mut base = Canvas::new(layout.width, layout.height, BACKGROUND);
        base.fill(layout.top_band, BAND_COLOR);
        base.fill(layout.bottom_band, BAND_COLOR);
        let (left, width) = (layout.side_margin, layout.text_width());
        // the title and the formula, one line each
        let clip = layout.top_band;
        let (title, size) = canvas::fit_line(
            &texts.title,
            layout.title_size,
            layout.title_size * MIN_LINE_SCALE,
            width,
        );
        let baseline = layout.padding + canvas::ascent(layout.title_size);
        base.draw_text(&title, size, (left, baseline), TEXT_COLOR, clip);
        let (formula, size) = canvas::fit_line(
            &texts.formula,
            layout.formula_size,
            layout.formula_size * MIN_LINE_SCALE,
            width,
        );
        let baseline = baseline
            + canvas::descent(layout.title_size)
            + layout.title_gap
            + canvas::ascent(layout.formula_size);
        base.draw_text(&formula, size, (left, baseline), FORMULA_COLOR, clip);
        // the caption, on up to three lines from the top of its band
        let (lines, size) = canvas::fit_paragraph(
            &texts.caption,
            layout.caption_size,
            layout.caption_size * MIN_CAPTION_SCALE,
            width,
            CAPTION_LINES,
        );
        let clip = layout.bottom_band;
        let first = clip.y as f32 + layout.padding + canvas::ascent(layout.caption_size);
        for (k, line) in lines.iter().enumerate() {
            let baseline = first + k as f32 * CAPTION_PITCH * size;
            base.draw_text(line, size, (left, baseline), TEXT_COLOR, clip);
        }
        Self {
            layout,
            texts: texts.clone(),
            base,
        }
    }

    /// The slide with its image region empty (the background).
    pub fn canvas(&self) -> Canvas {
        self.base.clone()
    }

    /// The slide with `srgb` (the image region's RGB8 pixels) in its image region.
    pub fn with_image(&self, srgb: &[u8]) -> Canvas {
        let mut canvas = self.base.clone();
        canvas.put(self.layout.image, srgb);
        canvas
    }
}

// ───────────────────────── files and index ─────────────────────────

/// The file name of slide `number` (from 1) of `count` without its
/// extension: the number on at least two digits, then the slug (`04-l0-l1-l2`).
pub fn file_stem(number: usize, count: usize, slug: &str) -> String {
    let digits = count.to_string().len().max(2);
    format!("{number:0digits$}-{slug}")
}

/// The step's settings in one line: its scene and terms, what it changes
/// from lumiere's defaults (in the lesson file's names), its samples per
/// pixel and seed.
pub fn settings_summary(view: &StepView) -> String {
    let defaults = StepView::new(view.settings.width, view.settings.height);
    let (s, d) = (&view.settings, &defaults.settings);
    let mut parts = vec![
        format!("scene {}", view.scene),
        format!("terms {}", s.terms),
    ];
    let mut changed = |name: &str, differs: bool, value: String| {
        if differs {
            parts.push(format!("{name} {value}"));
        }
    };
    changed(
        "lights",
        s.light_mode != d.light_mode,
        s.light_mode.to_string(),
    );
    if let Some(radius) = s.light_radius {
        changed("light_radius", true, format!("{radius} m"));
    }
    changed("brdf", s.brdf != d.brdf, s.brdf.to_string());
    changed(
        "phong_exponent",
        s.phong_exponent != d.phong_exponent,
        s.phong_exponent.to_string(),
    );
    changed(
        "phong_specular",
        s.phong_specular != d.phong_specular,
        s.phong_specular.to_string(),
    );
    changed(
        "light_sampling",
        s.light_sampling != d.light_sampling,
        s.light_sampling.to_string(),
    );
    changed(
        "mis_heuristic",
        s.mis_heuristic != d.mis_heuristic,
        s.mis_heuristic.to_string(),
    );
    changed(
        "indirect_sampling",
        s.indirect_sampling != d.indirect_sampling,
        s.indirect_sampling.to_string(),
    );
    changed(
        "light_samples",
        s.light_samples != d.light_samples,
        s.light_samples.to_string(),
    );
    changed(
        "indirect_samples",
        (s.auto_indirect_samples, s.indirect_samples)
            != (d.auto_indirect_samples, d.indirect_samples),
        if s.auto_indirect_samples {
            "auto".into()
        } else {
            s.indirect_samples.to_string()
        },
    );
    changed("sampler", s.sampler != d.sampler, s.sampler.to_string());
    changed(
        "integrator",
        s.integrator != d.integrator,
        s.integrator.to_string(),
    );
    let display = &view.display;
    changed(
        "exposure",
        display.exposure != defaults.display.exposure,
        format!("{:+} EV", display.exposure),
    );
    changed(
        "tonemap",
        display.tonemap != defaults.display.tonemap,
        display.tonemap.to_string(),
    );
    changed(
        "display",
        view.display_mode != defaults.display_mode,
        view.display_mode.to_string(),
    );
    if let Some((x, y)) = view.probe {
        changed("probe", true, format!("({x}, {y})"));
    }
    format!(
        "{} · {} spp, seed {}",
        parts.join(", "),
        view.spp,
        view.settings.seed
    )
}

/// One slide of the index.
#[derive(Clone, Debug)]
pub struct IndexEntry {
    pub texts: SlideTexts,
    /// The file name without its extension ([`file_stem`]).
    pub stem: String,
    /// The step's settings ([`settings_summary`]).
    pub settings: String,
    /// Whether a GIF goes with the PNG.
    pub gif: bool,
}

/// `index.md`: the lesson's title, how the slides were made (`command`), then
/// per slide its number and title, formula, caption, image and settings.
pub fn index_markdown(
    lesson: &Lesson,
    lang: Lang,
    layout: &SlideLayout,
    command: &str,
    entries: &[IndexEntry],
) -> String {
    let mut out = format!(
        "# {}\n\nThe {} slides of the lesson `{}`, {}×{} px (images {}×{} px), made by\n\n    {command}\n",
        escape_markdown(lesson.title.get(lang)),
        entries.len(),
        lesson.name,
        layout.width,
        layout.height,
        layout.image.width,
        layout.image.height,
    );
    for entry in entries {
        let texts = &entry.texts;
        out.push_str(&format!(
            "\n## {}\n\n`{}`\n\n{}\n\n![{}]({}.png)\n\n",
            escape_markdown(&texts.title),
            texts.formula.replace('`', "'"),
            escape_markdown(&texts.caption),
            escape_markdown(&texts.title),
            entry.stem,
        ));
        if entry.gif {
            out.push_str(&format!(
                "Convergence, from 1 spp: [{0}.gif]({0}.gif)\n\n",
                entry.stem
            ));
        }
        out.push_str(&format!("Settings: {}\n", entry.settings));
    }
    out
}

/// `text` with Markdown's markup characters escaped.
fn escape_markdown(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if matches!(
            c,
            '\\' | '`' | '*' | '_' | '[' | ']' | '<' | '>' | '#' | '|'
        ) {
            out.push('\\');
        }
        out.push(c);
    }
    out
}
