//! A step's render on its slide: the progressive render, what the image
//! region shows (the image, or a noise view with its colour bar), the
//! probed pixel's rays, the frames of the convergence animation and the GIF
//! they are written to.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};

use super::canvas::{self, Canvas, Rect, Rgb8};
use super::overlays::{draw_colour_bar, draw_paths, false_colour_srgb8};
use super::shown::{ShownImage, ShownPicture, ShownTile, SrgbImage, compose_shown};
use super::{Slide, SlideLayout, TEXT_COLOR};
use crate::analysis::noise::{DisplayMode, NoiseView, false_colour};
use crate::analysis::path_view::{PathLine, path_lines};
use crate::course::{RenderSettings, TermSet};
use crate::lesson::StepView;
use crate::render::display::Layout;
use crate::render::export::{ExportError, to_srgb8};
use crate::render::film::Film;
use crate::render::four_up::{TILES, Tile};
use crate::render::settings_override::side_labels;
use crate::render::{RenderStats, sample_stream};
use crate::scene::Scene;
use crate::tools::strip::{SampleCounts, render_row};
use crate::transport::context::RenderContext;
use crate::transport::counts::RayCounts;
use crate::transport::path_log::PathLog;
use crate::transport::sample_pixel_logged;
use crate::transport::splitting::choose_continuations;

/// Time a GIF frame is shown, in milliseconds…
const FRAME_MS: u32 = 700;
/// …and the last one, the converged image.
const LAST_FRAME_MS: u32 = 2100;
/// NeuQuant's sampling factor for the GIF's palettes (1: best, 30: fastest).
const GIF_SPEED: i32 = 10;
/// Colour of the "N spp" label's box.
const LABEL_BOX: Rgb8 = [0, 0, 0];

/// The samples per pixel of the frames of a step of `spp` samples:
/// 1, 2, 4, 8, … below `spp`, then `spp`.
pub fn frame_counts(spp: u32) -> Vec<u32> {
    SampleCounts::doubling_to(spp).as_slice().to_vec()
}

/// A step's finished slide and what its render did.
#[derive(Clone, Debug)]
pub struct SlideRender {
    pub slide: Canvas,
    pub stats: RenderStats,
}

/// Renders `view` (on a film of the slide's image size) for `view.spp`
/// samples per pixel, passes 0, 1, … as `lumiere render` does, and returns
/// the slide with its image. With `animate`, `frame(n, slide)` receives the
/// slide at each of [`frame_counts`] with its "N spp" label; `progress`
/// follows each pass.
pub fn render_slide(
    scene: Arc<Scene>,
    view: &StepView,
    slide: &Slide,
    animate: bool,
    progress: impl FnMut(&RenderStats),
    mut frame: impl FnMut(u32, &Canvas),
) -> SlideRender {
    let layout = &slide.layout;
    assert_eq!(
        (view.settings.width, view.settings.height),
        (layout.image.width, layout.image.height),
        "the step's film is the slide's image"
    );
    // a split step: B's images at each count, rendered first, for the same samples
    let b_images = match view.split_settings() {
        Some(mut b) => {
            b.seed += 1; // independent noise, as in the viewer
            let mut context = RenderContext::new(Arc::clone(&scene), b);
            choose_continuations(&mut context);
            let counts = frame_counts_for(view.spp, animate);
            let mut images = Vec::new();
            render_row(
                &context,
                &counts,
                |_| {},
                |_, film| {
                    images.push(to_srgb8(
                        &film.radiance(context.settings.terms),
                        view.display,
                    ));
                },
            );
            Some((context.settings.clone(), images))
        }
        None => None,
    };
    let mut context = RenderContext::new(scene, view.settings.clone());
    choose_continuations(&mut context);
    let paths = view
        .probe
        .map(|pixel| probe_lines(&context, pixel))
        .unwrap_or_default();
    let counts = frame_counts_for(view.spp, animate);
    let mut last = None;
    let stats = render_row(&context, &counts, progress, |i, film| {
        let count = counts.as_slice()[i];
        let b = b_images
            .as_ref()
            .map(|(settings, images)| (settings, images[i].as_slice()));
        let picture = picture(slide, view, film, b, &paths);
        if animate {
            let mut labelled = picture.clone();
            draw_label(&mut labelled, layout, &format!("{count} spp"));
            frame(count, &labelled);
        }
        if count == view.spp {
            last = Some(picture);
        }
    });
    SlideRender {
        slide: last.expect("the last count is the step's"),
        stats,
    }
}

/// The sample counts a slide's render stops at: the step's, and with an
/// animation every doubling before it.
fn frame_counts_for(spp: u32, animate: bool) -> SampleCounts {
    if animate {
        SampleCounts::doubling_to(spp)
    } else {
        SampleCounts::only(spp)
    }
}

/// The slide with the image region of `film`, its colour bar and the
/// probe's rays; for a split step A | B with B's settings and image `b`,
/// for the four-up the four tiles of `film`, as the viewer shows them.
fn picture(
    slide: &Slide,
    view: &StepView,
    film: &Film,
    b: Option<(&RenderSettings, &[u8])>,
    paths: &[PathLine],
) -> Canvas {
    let (width, height) = (film.width, film.height);
    let shown = match b {
        Some((b_settings, b_srgb)) => {
            let a_srgb = to_srgb8(&film.radiance(view.settings.terms), view.display);
            let divider = width / 2;
            let row = width as usize * 3;
            let mut image = a_srgb;
            for (a_row, b_row) in image.chunks_mut(row).zip(b_srgb.chunks(row)) {
                a_row[divider as usize * 3..].copy_from_slice(&b_row[divider as usize * 3..]);
            }
            let (a_label, b_label) = side_labels(&view.settings, b_settings);
            Some(ShownImage::Split {
                image: SrgbImage::new(width, height, image),
                divider,
                labels: [format!("A: {a_label}"), format!("B: {b_label}")],
            })
        }
        None if view.display.layout == Layout::FourUp => {
            let terms = view.settings.terms;
            let tiles = TILES.map(|tile| {
                let shown = match tile {
                    Tile::Term(term) => TermSet::only(term),
                    Tile::Sum => terms,
                };
                ShownTile {
                    image: (!tile.is_off(terms)).then(|| {
                        let srgb = to_srgb8(&film.radiance(shown), view.display);
                        SrgbImage::new(width, height, srgb)
                    }),
                    label: tile.label(terms),
                    off: tile.is_off(terms),
                }
            });
            Some(ShownImage::FourUp {
                tile_size: (width, height),
                tiles: tiles.to_vec(),
            })
        }
        None => None,
    };
    if let Some(image) = shown {
        let picture = ShownPicture {
            image,
            paths: paths.to_vec(),
            film: (width, height),
            texts: Some(slide.texts.clone()),
        };
        let layout = &slide.layout;
        return compose_shown(&picture, layout.width, layout.height)
            .expect("a slide's layout holds its picture");
    }
    let terms = view.settings.terms;
    let noise = (view.display_mode != DisplayMode::Image)
        .then(|| {
            let noise_view = NoiseView {
                mode: view.display_mode,
                ..NoiseView::default()
            };
            false_colour(film, terms, noise_view, None).ok()
        })
        .flatten();
    let srgb = match &noise {
        Some(noise) => false_colour_srgb8(noise),
        None => to_srgb8(&film.radiance(terms), view.display),
    };
    let mut canvas = slide.with_image(&srgb);
    let layout = &slide.layout;
    if let Some(noise) = &noise {
        let sizes = (layout.caption_size, layout.side_margin);
        draw_colour_bar(&mut canvas, layout.right_margin(), sizes, noise);
    }
    let film_size = (layout.image.width, layout.image.height);
    draw_paths(&mut canvas, layout.image, film_size, paths);
    canvas
}

// ───────────────────────── the probe's rays ─────────────────────────

/// The rays of the first sample of `pixel`, as lines on the film (the
/// viewer's path view shows the same sample first).
fn probe_lines(context: &RenderContext, (x, y): (u32, u32)) -> Vec<PathLine> {
    let index = y as u64 * context.settings.width as u64 + x as u64;
    let stream = sample_stream(&context.settings, index, 0);
    let mut log = PathLog::default();
    sample_pixel_logged(context, x, y, &stream, &mut RayCounts::default(), &mut log);
    path_lines(&log, &context.camera, context.settings.terms)
}

// ───────────────────────── labels ─────────────────────────

/// Draws `text` on a dark box in the lower right corner of the image.
fn draw_label(canvas: &mut Canvas, layout: &SlideLayout, text: &str) {
    let size = layout.caption_size;
    let pad = (0.3 * size).round();
    let width = canvas::text_width(text, size).ceil() + 2.0 * pad;
    let height = (canvas::ascent(size) + canvas::descent(size)).ceil() + 2.0 * pad;
    let image = layout.image;
    let (w, h) = (
        (width as u32).min(image.width),
        (height as u32).min(image.height),
    );
    let inset = (0.4 * size).round() as u32;
    let x = image.right().saturating_sub(w + inset).max(image.x);
    let y = image.bottom().saturating_sub(h + inset).max(image.y);
    let rect = Rect::new(x, y, w, h);
    canvas.fill(rect, LABEL_BOX);
    let baseline = y as f32 + pad + canvas::ascent(size);
    canvas.draw_text(text, size, (x as f32 + pad, baseline), TEXT_COLOR, rect);
}

// ───────────────────────── GIF ─────────────────────────

/// A convergence animation being written: frames at half the slide's size,
/// looping.
pub struct GifWriter {
    path: PathBuf,
    encoder: GifEncoder<BufWriter<File>>,
}

impl GifWriter {
    /// Creates the GIF file at `path`.
    pub fn create(path: &Path) -> Result<Self, ExportError> {
        let fail = |e: &dyn std::fmt::Display| ExportError {
            path: path.to_path_buf(),
            problem: e.to_string(),
        };
        let file = File::create(path).map_err(|e| fail(&e))?;
        let mut encoder = GifEncoder::new_with_speed(BufWriter::new(file), GIF_SPEED);
        encoder.set_repeat(Repeat::Infinite).map_err(|e| fail(&e))?;
        Ok(Self {
            path: path.to_path_buf(),
            encoder,
        })
    }

    /// Appends `slide` at half its size, shown 0.7 s (2.1 s if it is the `last`).
    pub fn push(&mut self, slide: &Canvas, last: bool) -> Result<(), ExportError> {
        let half = slide.half().to_rgb_image();
        let rgba = RgbaImage::from_fn(half.width(), half.height(), |x, y| {
            let [r, g, b] = half.get_pixel(x, y).0;
            image::Rgba([r, g, b, 255])
        });
        let ms = if last { LAST_FRAME_MS } else { FRAME_MS };
        let frame = Frame::from_parts(rgba, 0, 0, Delay::from_numer_denom_ms(ms, 1));
        self.encoder.encode_frame(frame).map_err(|e| ExportError {
            path: self.path.clone(),
            problem: e.to_string(),
        })
    }
}
