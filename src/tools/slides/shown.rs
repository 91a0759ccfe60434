//! "Save as shown": the picture the viewer shows, composed at a chosen size
//! the way the slides are, from plain data (the viewer gathers it; nothing
//! here knows the window).
//!
//! ```text
//! without a lesson                         a lesson's step: the slide's layout
//! ┌───────────────────────────────────┐    ┌───────────────────────────────────┐
//! │       ┌───────────────────┐       │    │ 4. title                          │
//! │       │ the image, its    │ colour│    │ formula                           │
//! │ dark  │ aspect kept, as   │ bar   │    │        ┌─────────────┐            │
//! │ margin│ large as the size │(noise │    │ margin │ the image   │ colour bar │
//! │       │ allows            │ views)│    │        └─────────────┘            │
//! │       └───────────────────┘       │    │ caption, up to three lines        │
//! └───────────────────────────────────┘    └───────────────────────────────────┘
//! ```
//!
//! * The image region shows what the viewport shows: the image as
//!   displayed (exposure, tonemap, sRGB); a noise view's false colours,
//!   with the colour bar, its mode, unit and range right of the image (as
//!   on a slide; without a lesson the image makes room for it); A | B with
//!   the divider and each half's label at the top; the four-up's tiles,
//!   each labelled at its top left, an empty tile saying "off", arranged
//!   two by two or in a row, whichever shows them larger in the region;
//!   the probe's rays over the image, or over every tile.
//! * With a lesson's step, the step's title, formula and caption are laid
//!   out exactly as on its slide (`lumiere lesson --export`, [`Slide`]),
//!   and the image is fitted into the slide's image region. Without, there
//!   are no text bands and the image fills the picture, its aspect kept.
//! * Scaling ([`Canvas::put_scaled`]): each pixel is the mean, in linear
//!   light, of the film pixels its footprint covers, weighted by how much
//!   of it each covers. Enlarged by a whole factor, each film pixel becomes
//!   a block of its value (nearest neighbour, as the viewer draws it); by a
//!   fraction, the pixels on a block's edge mix its two film pixels;
//!   reduced, a box filter.
//! * Text sizes follow the picture's height as on a slide (u = H / 1080):
//!   the colour bar's are the slide's; a split label is 1/36 of the image's
//!   height, a tile's label 1/18 of the tile's (at least 9 px), on a
//!   translucent dark box, as in the viewer.

use std::sync::Arc;

use super::canvas::{self, Canvas, Rect, Rgb8};
use super::overlays::{colour_bar_room, draw_colour_bar, draw_paths, false_colour_srgb8};
use super::{BACKGROUND, MAX_SLIDE_SIDE, Slide, SlideLayout, SlideTexts, TEXT_COLOR};
use crate::analysis::noise::FalseColour;
use crate::analysis::path_view::PathLine;
use crate::render::display::DisplaySettings;
use crate::render::export::to_srgb8;
use crate::render::four_up::Arrangement;

/// The smallest side of a picture, in pixels.
pub const MIN_SIDE: u32 = 16;
/// The largest side of a picture, in pixels.
pub const MAX_SIDE: u32 = MAX_SLIDE_SIDE;
/// The size offered first: full HD.
pub const DEFAULT_SIZE: (u32, u32) = (1920, 1080);

/// The labels' box, blended over the image by [`LABEL_ALPHA`].
const LABEL_BOX: Rgb8 = [0, 0, 0];
const LABEL_ALPHA: f32 = 170.0 / 255.0;
/// The split's divider.
const DIVIDER: Rgb8 = [225, 225, 225];
/// The "off" of an empty tile.
const OFF_COLOR: Rgb8 = [160, 160, 160];
/// The smallest label, in pixels (font size).
const MIN_LABEL_SIZE: f32 = 9.0;

/// Refuses a size with a side outside [`MIN_SIDE`]..=[`MAX_SIDE`], saying so.
pub fn check_size(width: u32, height: u32) -> Result<(), String> {
    let sides = MIN_SIDE..=MAX_SIDE;
    if sides.contains(&width) && sides.contains(&height) {
        Ok(())
    } else {
        Err(format!(
            "a picture of {width}×{height} px: each side must be within {MIN_SIDE}..={MAX_SIDE} px"
        ))
    }
}

/// An 8-bit sRGB image, RGB, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct SrgbImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

impl SrgbImage {
    pub fn new(width: u32, height: u32, pixels: Vec<u8>) -> Self {
        assert_eq!(
            pixels.len(),
            width as usize * height as usize * 3,
            "image size"
        );
        Self {
            width,
            height,
            pixels,
        }
    }

    /// Linear RGBA radiance as displayed with `display` (exposure, tonemap,
    /// sRGB: the PNG export's [`to_srgb8`]).
    pub fn from_radiance(
        width: u32,
        height: u32,
        rgba: &[[f32; 4]],
        display: DisplaySettings,
    ) -> Self {
        let rgb: Vec<glam::Vec3> = rgba
            .iter()
            .map(|p| glam::Vec3::new(p[0], p[1], p[2]))
            .collect();
        Self::new(width, height, to_srgb8(&rgb, display))
    }

    /// Draws the image into `rect`, scaled to it.
    fn draw(&self, canvas: &mut Canvas, rect: Rect) {
        canvas.put_scaled(rect, (self.width, self.height), &self.pixels);
    }
}

/// A tile of the four-up.
#[derive(Clone, Debug, PartialEq)]
pub struct ShownTile {
    /// Its pixels; `None` while its term has no image yet (an empty tile).
    pub image: Option<SrgbImage>,
    pub label: String,
    /// Its term is switched off: the tile is empty and says "off".
    pub off: bool,
}

/// What the image region shows.
#[derive(Clone, Debug)]
pub enum ShownImage {
    /// The image as displayed.
    Image(SrgbImage),
    /// A noise view: its false colours, with their colour bar.
    Noise(Arc<FalseColour>),
    /// A | B: A's columns left of `divider`, B's from it on, and each half's label.
    Split {
        image: SrgbImage,
        divider: u32,
        labels: [String; 2],
    },
    /// The four tiles in reading order (L0, L1, L2, their sum), each of `tile_size`.
    FourUp {
        tile_size: (u32, u32),
        tiles: Vec<ShownTile>,
    },
}

/// Everything a picture shows.
#[derive(Clone, Debug)]
pub struct ShownPicture {
    pub image: ShownImage,
    /// The probe's rays, in pixels of a film of `film` size, drawn over the
    /// image or over every tile.
    pub paths: Vec<PathLine>,
    pub film: (u32, u32),
    /// A lesson step's texts: the picture is then laid out as its slide.
    pub texts: Option<SlideTexts>,
}

/// Where the parts of a picture go.
#[derive(Clone, Debug, PartialEq)]
pub struct ShownLayout {
    pub width: u32,
    pub height: u32,
    /// The slide's layout, with a lesson's texts.
    pub slide: Option<SlideLayout>,
    /// The image (the four tiles together, in the four-up).
    pub image: Rect,
    /// The four-up's arrangement and tiles, in reading order (none otherwise).
    pub arrangement: Option<Arrangement>,
    pub tiles: Vec<Rect>,
    /// The slide's caption size and side margin at this height (the colour bar's sizes).
    pub caption_size: f32,
    pub side_margin: f32,
}

impl ShownLayout {
    /// The layout of `picture` at `width` × `height`, or why there is none
    /// (a side out of range, or too small a slide for its texts).
    pub fn new(picture: &ShownPicture, width: u32, height: u32) -> Result<Self, String> {
        check_size(width, height)?;
        let slide = SlideLayout::new(width, height);
        let (caption_size, side_margin) = (slide.caption_size, slide.side_margin);
        let (area, slide) = match picture.texts {
            Some(_) => {
                slide.check()?;
                (slide.image, Some(slide))
            }
            None => (Rect::new(0, 0, width, height), None),
        };
        let (content, arrangement) = match &picture.image {
            ShownImage::Image(image) | ShownImage::Split { image, .. } => {
                ((image.width, image.height), None)
            }
            ShownImage::Noise(noise) => ((noise.width, noise.height), None),
            ShownImage::FourUp {
                tile_size: (w, h), ..
            } => {
                let (aw, ah) = (area.width as f32, area.height as f32);
                let arrangement = Arrangement::fitting(*w as f32, *h as f32, aw, ah);
                let size = (arrangement.columns() * w, arrangement.rows() * h);
                (size, Some(arrangement))
            }
        };
        let mut image = fit(content, area);
        // without a lesson, the image makes room for a colour bar and its title on its right
        if let (ShownImage::Noise(noise), None) = (&picture.image, &slide) {
            let needed = colour_bar_room(noise, (caption_size, side_margin)).ceil() as u32;
            if width - image.right() < needed && width >= needed + MIN_SIDE {
                image = fit(content, Rect::new(0, 0, width - needed, height));
            }
        }
        let tiles = arrangement.map_or_else(Vec::new, |arrangement| {
            let (columns, rows) = (arrangement.columns(), arrangement.rows());
            let edge = |start: u32, length: u32, k: u32, n: u32| {
                start + (length as u64 * k as u64 / n as u64) as u32
            };
            (0..4)
                .map(|index| {
                    let (column, row) = arrangement.cell(index);
                    let x0 = edge(image.x, image.width, column, columns);
                    let x1 = edge(image.x, image.width, column + 1, columns);
                    let y0 = edge(image.y, image.height, row, rows);
                    let y1 = edge(image.y, image.height, row + 1, rows);
                    Rect::new(x0, y0, x1 - x0, y1 - y0)
                })
                .collect()
        });
        Ok(Self {
            width,
            height,
            slide,
            image,
            arrangement,
            tiles,
            caption_size,
            side_margin,
        })
    }

    /// The margin right of the image, where a colour bar goes.
    pub fn colour_bar(&self) -> Rect {
        let image = self.image;
        Rect::new(
            image.right(),
            image.y,
            self.width - image.right(),
            image.height,
        )
    }
}

/// The largest rectangle of `content`'s aspect in `area`, centred in it.
fn fit((width, height): (u32, u32), area: Rect) -> Rect {
    let (cw, ch) = (width.max(1) as u64, height.max(1) as u64);
    let (aw, ah) = (area.width.max(1) as u64, area.height.max(1) as u64);
    let (w, h) = if aw * ch >= ah * cw {
        (((ah * cw + ch / 2) / ch).clamp(1, aw), ah)
    } else {
        (aw, ((aw * ch + cw / 2) / cw).clamp(1, ah))
    };
    let (w, h) = (w as u32, h as u32);
    Rect::new(
        area.x + area.width.saturating_sub(w) / 2,
        area.y + area.height.saturating_sub(h) / 2,
        w,
        h,
    )
}

/// `picture` at `width` × `height` (see the module's header), or why not.
pub fn compose_shown(picture: &ShownPicture, width: u32, height: u32) -> Result<Canvas, String> {
    let layout = ShownLayout::new(picture, width, height)?;
    let mut canvas = match (&picture.texts, &layout.slide) {
        (Some(texts), Some(slide)) => Slide::new(slide.clone(), texts).canvas(),
        _ => Canvas::new(width, height, BACKGROUND),
    };
    let image = layout.image;
    match &picture.image {
        ShownImage::Image(srgb) | ShownImage::Split { image: srgb, .. } => {
            srgb.draw(&mut canvas, image)
        }
        ShownImage::Noise(noise) => {
            let srgb = false_colour_srgb8(noise);
            canvas.put_scaled(image, (noise.width, noise.height), &srgb);
            let sizes = (layout.caption_size, layout.side_margin);
            draw_colour_bar(&mut canvas, layout.colour_bar(), sizes, noise);
        }
        ShownImage::FourUp { tiles, .. } => {
            for (&rect, tile) in layout.tiles.iter().zip(tiles) {
                match &tile.image {
                    Some(srgb) if !tile.off => srgb.draw(&mut canvas, rect),
                    _ => canvas.fill(rect, BACKGROUND),
                }
                if tile.off {
                    draw_centred(&mut canvas, "off", rect, OFF_COLOR);
                }
            }
        }
    }
    // the probe's rays, then what the viewer draws over them
    let regions = match layout.tiles.is_empty() {
        true => std::slice::from_ref(&image),
        false => &layout.tiles[..],
    };
    for &region in regions {
        draw_paths(&mut canvas, region, picture.film, &picture.paths);
    }
    match &picture.image {
        ShownImage::Split {
            image: srgb,
            divider,
            labels,
        } => draw_split(&mut canvas, image, srgb.width, *divider, labels),
        ShownImage::FourUp { tiles, .. } => draw_tile_labels(&mut canvas, &layout, tiles),
        ShownImage::Image(_) | ShownImage::Noise(_) => {}
    }
    Ok(canvas)
}

/// The divider at column `divider` of an image `source_width` wide drawn
/// at `image`, and A's label at the top left of its half, B's at the top
/// right of its.
fn draw_split(
    canvas: &mut Canvas,
    image: Rect,
    source_width: u32,
    divider: u32,
    labels: &[String; 2],
) {
    let offset = divider as u64 * image.width as u64 / source_width.max(1) as u64;
    let x = image.x + (offset as u32).min(image.width);
    let line = (image.height as f32 / 360.0).max(2.0);
    let (top, bottom) = (image.y as f32, image.bottom() as f32);
    let segment = (
        glam::Vec2::new(x as f32, top),
        glam::Vec2::new(x as f32, bottom),
    );
    canvas.draw_segment(segment, line, DIVIDER, None, image);
    let size = (image.height as f32 / 36.0).max(MIN_LABEL_SIZE);
    let inset = (0.4 * size).round() as u32;
    let height = image.height.saturating_sub(2 * inset);
    let (left, right) = (image.x + inset, x + inset);
    let a = Rect::new(
        left,
        image.y + inset,
        x.saturating_sub(inset + left),
        height,
    );
    let b_width = image.right().saturating_sub(inset + right);
    let b = Rect::new(right, image.y + inset, b_width, height);
    draw_label(canvas, &labels[0], size, a, false);
    draw_label(canvas, &labels[1], size, b, true);
}

/// The seams between the tiles and each tile's label at its top left.
fn draw_tile_labels(canvas: &mut Canvas, layout: &ShownLayout, tiles: &[ShownTile]) {
    let image = layout.image;
    let seam = (image.height as f32 / 360.0).max(1.0);
    for rect in &layout.tiles {
        let (x, y) = (rect.x as f32, rect.y as f32);
        let (right, bottom) = (rect.right() as f32, rect.bottom() as f32);
        if rect.x > image.x {
            let line = (glam::Vec2::new(x, y), glam::Vec2::new(x, bottom));
            canvas.draw_segment(line, seam, BACKGROUND, None, image);
        }
        if rect.y > image.y {
            let line = (glam::Vec2::new(x, y), glam::Vec2::new(right, y));
            canvas.draw_segment(line, seam, BACKGROUND, None, image);
        }
    }
    for (rect, tile) in layout.tiles.iter().zip(tiles) {
        let size = (rect.height as f32 / 18.0).max(MIN_LABEL_SIZE);
        let inset = (0.25 * size).round() as u32;
        let area = Rect::new(
            rect.x + inset,
            rect.y + inset,
            rect.width.saturating_sub(2 * inset),
            rect.height.saturating_sub(2 * inset),
        );
        draw_label(canvas, &tile.label, size, area, false);
    }
}

/// Draws `text` at font size `size` (smaller, then cut with "…", if it is
/// too wide) on a translucent dark box at the top left of `area` (top right
/// with `right`); nothing if `area` is too narrow for a word.
fn draw_label(canvas: &mut Canvas, text: &str, size: f32, area: Rect, right: bool) {
    if area.width < 20 || area.height < 8 {
        return;
    }
    let pad = (0.3 * size).round();
    let room = area.width as f32 - 2.0 * pad;
    let (line, fitted) = canvas::fit_line(text, size, 0.6 * size, room);
    let width = canvas::text_width(&line, fitted).ceil() + 2.0 * pad;
    let height = (canvas::ascent(fitted) + canvas::descent(fitted)).ceil() + 2.0 * pad;
    let (width, height) = (
        (width as u32).min(area.width),
        (height as u32).min(area.height),
    );
    let x = if right { area.right() - width } else { area.x };
    let rect = Rect::new(x, area.y, width, height);
    canvas.shade(rect, LABEL_BOX, LABEL_ALPHA);
    let baseline = area.y as f32 + pad + canvas::ascent(fitted);
    canvas.draw_text(&line, fitted, (x as f32 + pad, baseline), TEXT_COLOR, rect);
}

/// Draws `text` in the middle of `rect`, at 1/8 of its height.
fn draw_centred(canvas: &mut Canvas, text: &str, rect: Rect, colour: Rgb8) {
    let size = (rect.height as f32 / 8.0).max(MIN_LABEL_SIZE);
    let width = canvas::text_width(text, size);
    let left = rect.x as f32 + (rect.width as f32 - width) / 2.0;
    let middle = rect.y as f32 + rect.height as f32 / 2.0;
    let baseline = middle + (canvas::ascent(size) - canvas::descent(size)) / 2.0;
    canvas.draw_text(text, size, (left, baseline), colour, rect);
}
