//! Screenshots: the image as displayed (PNG), its radiance (EXR), one EXR
//! per term on request, and the JSON sidecar that reproduces it.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use eframe::egui;
use glam::Vec3;

use crate::render::export::save_image;
use crate::render::film::Film;
use crate::render::progressive::Snapshot;
use crate::render::settings::{Term, TermSet};
use crate::render::sidecar::Sidecar;

/// One screenshot to write, off the UI thread.
pub struct ScreenshotJob {
    pub folder: PathBuf,
    pub snapshot: Arc<Snapshot>,
    /// What the viewport shows when it is not `snapshot` alone (A | B):
    /// the PNG is that image.
    pub shown: Option<Arc<Snapshot>>,
    pub film: Option<Arc<Mutex<Film>>>,
    pub per_term_exr: bool,
    pub sidecar: Sidecar,
}

impl ScreenshotJob {
    /// Writes the files; returns a line saying where.
    pub fn run(mut self) -> Result<String, String> {
        std::fs::create_dir_all(&self.folder)
            .map_err(|e| format!("{}: {e}", self.folder.display()))?;
        let stem = self.free_stem();
        let snapshot = &self.snapshot;
        let display = self.sidecar.display;
        let path = |suffix: &str| self.folder.join(format!("{stem}{suffix}"));
        let shown = self.shown.as_ref().unwrap_or(snapshot);
        save_image(
            &path(".png"),
            shown.width,
            shown.height,
            &linear(shown),
            display,
        )
        .map_err(|e| e.to_string())?;
        save_image(
            &path(".exr"),
            snapshot.width,
            snapshot.height,
            &linear(snapshot),
            display,
        )
        .map_err(|e| e.to_string())?;
        if self.per_term_exr
            && let Some(film) = &self.film
        {
            let film = film.lock().unwrap_or_else(|p| p.into_inner());
            for term in Term::ALL.into_iter().filter(|&t| film.samples(t) > 0) {
                let label = term.label().replace('+', "plus");
                let pixels = film.radiance(TermSet::only(term));
                save_image(
                    &path(&format!("-{label}.exr")),
                    film.width,
                    film.height,
                    &pixels,
                    display,
                )
                .map_err(|e| e.to_string())?;
            }
        }
        self.sidecar.samples_per_pixel = snapshot.samples_per_pixel();
        self.sidecar
            .save(&path(".json"))
            .map_err(|e| e.to_string())?;
        Ok(format!("saved {}", path(".png").display()))
    }

    /// `lumiere-N` with the first N not used in the folder.
    fn free_stem(&self) -> String {
        (1..)
            .map(|n| format!("lumiere-{n:03}"))
            .find(|stem| !self.folder.join(format!("{stem}.png")).exists())
            .expect("some number is free")
    }
}

/// A snapshot's radiance as linear RGB.
fn linear(snapshot: &Snapshot) -> Vec<Vec3> {
    snapshot
        .radiance
        .iter()
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect()
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
