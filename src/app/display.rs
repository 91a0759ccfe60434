//! The image on screen: a persistent float texture and a WGSL blit on the
//! desktop (`display/blit.rs`), an egui texture in the browser
//! (`display/texture.rs`), where egui's wgpu callbacks cannot hold the
//! GPU objects of a page whose memory is shared with its workers.
//!
//! On the desktop the worker's snapshot (linear RGBA radiance) is written into an
//! `Rgba32Float` texture with `queue.write_texture` only when a new snapshot
//! arrives; every frame a tiny paint callback draws one triangle whose
//! fragment shader (`blit.wgsl`) reads the texel under it (nearest neighbour),
//! applies 2^EV, the tonemap and the sRGB curve. The image never goes through
//! egui's texture manager. A noise view (false colour, already mapped to
//! linear RGB by `crate::analysis::noise`) goes through the same texture; the shader
//! then skips exposure and tonemap.

use std::sync::Arc;

use crate::analysis::noise::FalseColour;
use crate::render::progressive::Snapshot;

#[cfg(not(target_arch = "wasm32"))]
mod blit;
#[cfg(not(target_arch = "wasm32"))]
pub use blit::{install, paint_image};
#[cfg(target_arch = "wasm32")]
mod texture;
#[cfg(target_arch = "wasm32")]
pub use texture::{install, paint_image};

/// What the texture shows: the worker's radiance or a noise view of the film.
#[derive(Clone)]
pub enum ImageSource {
    Radiance(Arc<Snapshot>),
    /// `serial` changes with every new false-colour image.
    FalseColour {
        serial: u64,
        image: Arc<FalseColour>,
    },
}

impl ImageSource {
    /// Identifies the pixels, so each image is uploaded once.
    pub(crate) fn key(&self) -> (bool, u64) {
        match self {
            ImageSource::Radiance(snapshot) => (false, snapshot.generation),
            ImageSource::FalseColour { serial, .. } => (true, *serial),
        }
    }

    pub(crate) fn pixels(&self) -> (u32, u32, &[[f32; 4]]) {
        match self {
            ImageSource::Radiance(s) => (s.width, s.height, &s.radiance),
            ImageSource::FalseColour { image, .. } => (image.width, image.height, &image.rgba),
        }
    }
}
