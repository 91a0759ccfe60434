//! Screenshots: the image as displayed (PNG), its radiance (EXR), one EXR
//! per term on request, and the JSON sidecar that reproduces it.
//!
//! The PNG is what the viewport shows: the image, A | B while comparing,
//! or, in the four-up layout, the four tiles in a row, each labelled in a
//! band below (as `lumiere strip` lays its tiles out). The EXR is always
//! the image of the visible terms, which `lumiere render --settings`
//! renders again.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use eframe::egui;
use glam::Vec3;

use super::files::{Outbox, Saved};
use crate::course::{Term, TermSet};
use crate::render::display::DisplaySettings;
use crate::render::export::{ImageFormat, encode_image, to_srgb8};
use crate::render::film::Film;
use crate::render::four_up::{TILES, Tile};
use crate::render::progressive::Snapshot;
use crate::render::sidecar::Sidecar;
use crate::tools::strip::{BAND_COLOR, StripImage, StripLayout, label_fits};

/// What the viewport shows, for the PNG.
pub enum Shown {
    /// The image (`ScreenshotJob::snapshot`).
    Image,
    /// A | B, composed.
    Split(Arc<Snapshot>),
    /// The snapshot's four tiles (it holds its terms' images).
    FourUp,
}

/// One screenshot to write, off the UI thread.
pub struct ScreenshotJob {
    pub folder: PathBuf,
    pub snapshot: Arc<Snapshot>,
    pub shown: Shown,
    pub film: Option<Arc<Mutex<Film>>>,
    pub per_term_exr: bool,
    pub sidecar: Sidecar,
}

impl ScreenshotJob {
    /// Writes the files (through an [`Outbox`]); says where.
    pub fn run(mut self) -> Result<Saved, String> {
        let mut outbox = Outbox::new(&self.folder)?;
        let stem = outbox.free_stem("lumiere", ".png");
        let snapshot = &self.snapshot;
        let display = self.sidecar.display;
        let image =
            |s: &Snapshot, format| encode_image(format, s.width, s.height, &linear(s), display);
        let png = match &self.shown {
            Shown::FourUp => four_up_strip(snapshot, display)?.png_bytes(),
            Shown::Split(shown) => image(shown, ImageFormat::Png)?,
            Shown::Image => image(snapshot, ImageFormat::Png)?,
        };
        outbox.write(&format!("{stem}.png"), png)?;
        outbox.write(&format!("{stem}.exr"), image(snapshot, ImageFormat::Exr)?)?;
        if self.per_term_exr
            && let Some(film) = &self.film
        {
            let film = film.lock().unwrap_or_else(|p| p.into_inner());
            for term in Term::ALL.into_iter().filter(|&t| film.samples(t) > 0) {
                let label = term.label().replace('+', "plus");
                let pixels = film.radiance(TermSet::only(term));
                let exr =
                    encode_image(ImageFormat::Exr, film.width, film.height, &pixels, display)?;
                outbox.write(&format!("{stem}-{label}.exr"), exr)?;
            }
        }
        self.sidecar.samples_per_pixel = snapshot.samples_per_pixel();
        outbox.write(&format!("{stem}.json"), self.sidecar.to_json().into_bytes())?;
        Ok(outbox.finish(""))
    }
}

/// A snapshot's radiance as linear RGB.
fn linear(snapshot: &Snapshot) -> Vec<Vec3> {
    rgb(&snapshot.radiance)
}

fn rgb(pixels: &[[f32; 4]]) -> Vec<Vec3> {
    pixels.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect()
}

/// The four tiles of `snapshot` in a row, each exposed and tonemapped as
/// displayed and labelled below; an empty tile is the bands' colour and its
/// label says "off".
pub fn four_up_strip(snapshot: &Snapshot, display: DisplaySettings) -> Result<StripImage, String> {
    let terms = snapshot.terms;
    let off = |tile: Tile, label: String| {
        if tile.is_off(terms) {
            format!("{label}: off")
        } else {
            label
        }
    };
    // the labels, or shorter ones when a tile is too narrow: the same form for all
    let forms: [&dyn Fn(Tile) -> String; 3] = [
        &|tile| off(tile, tile.label(terms)),
        &|tile| off(tile, tile.compact_label(terms)),
        &|tile| off(tile, tile.short_label().into()),
    ];
    let labels: Vec<String> = forms
        .iter()
        .map(|form| TILES.map(form).to_vec())
        .find(|labels| labels.iter().all(|l| label_fits(l, snapshot.width)))
        .unwrap_or_else(|| TILES.map(forms[2]).to_vec());
    let layout = StripLayout::new(snapshot.width, snapshot.height, labels, Vec::new());
    layout.check_size()?;
    let mut image = StripImage::new(layout);
    let pixels = snapshot.width as usize * snapshot.height as usize;
    for (column, tile) in TILES.into_iter().enumerate() {
        let srgb = match tile.pixels(snapshot).filter(|p| p.len() == pixels) {
            Some(tile) => to_srgb8(&rgb(tile), display),
            None => BAND_COLOR.repeat(pixels),
        };
        image.put_tile(0, column as u32, &srgb);
    }
    Ok(image)
}

/// Saves egui's screenshot of the whole window as a PNG.
pub fn save_window(path: &Path, image: &egui::ColorImage) -> Result<(), String> {
    let [width, height] = image.size;
    let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
    let buffer = image::RgbaImage::from_raw(width as u32, height as u32, bytes)
        .ok_or("screenshot size mismatch")?;
    buffer
        .save(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `width`×`height` snapshot of L0 and L2 (L1 off): L0 = 0.25, L2 = 0.5.
    fn snapshot(width: u32, height: u32) -> Snapshot {
        let pixels = (width * height) as usize;
        let image = |v: f32| vec![[v, v, v, 1.0]; pixels];
        let mut term_images: [Option<Vec<[f32; 4]>>; Term::COUNT] = Default::default();
        term_images[Term::L0.index()] = Some(image(0.25));
        term_images[Term::L2.index()] = Some(image(0.5));
        Snapshot {
            width,
            height,
            terms: TermSet::only(Term::L0).with(Term::L2, true),
            radiance: image(0.75),
            term_images,
            ..Snapshot::default()
        }
    }

    #[test]
    fn the_four_up_png_is_the_tiles_in_a_row_labelled_below() {
        let strip = four_up_strip(&snapshot(160, 120), DisplaySettings::default()).unwrap();
        assert_eq!(strip.width(), 4 * 160);
        assert!(strip.height() > 120);
        assert_eq!(
            strip.layout.column_labels,
            ["L0 emission", "L1 direct: off", "L2 indirect", "L0+L2"]
        );
        let code = |v: f32| to_srgb8(&[Vec3::splat(v)], DisplaySettings::default())[0];
        for (column, value) in [(0, Some(0.25)), (1, None), (2, Some(0.5)), (3, Some(0.75))] {
            let expected = value.map_or(BAND_COLOR, |v| [code(v); 3]);
            assert_eq!(
                strip.pixel(column * 160 + 80, 60),
                expected,
                "tile {column}"
            );
        }
        let wide = four_up_strip(&snapshot(320, 240), DisplaySettings::default()).unwrap();
        assert_eq!(wide.layout.column_labels[2], "L2 indirect (one bounce)");
        // on narrow tiles, the short labels
        let narrow = four_up_strip(&snapshot(64, 48), DisplaySettings::default()).unwrap();
        assert_eq!(narrow.layout.column_labels, ["L0", "L1: off", "L2", "sum"]);
        assert_eq!(Tile::Sum.short_label(), "sum");
    }
}
