//! The browser's display: the snapshot mapped to 8-bit sRGB on the CPU
//! (2^EV, the tonemap, the sRGB curve: `render::export::to_srgb8`, the
//! PNG export's own mapping) and drawn as an egui texture, nearest
//! neighbour. It is mapped again only when the image or the display
//! settings change.

use eframe::egui;
use eframe::egui_wgpu;
use glam::Vec3;

use super::ImageSource;
use crate::render::display::{DisplaySettings, Tonemap};
use crate::render::export::to_srgb8;

/// Nothing to set up: egui owns the texture.
pub fn install(_render_state: &egui_wgpu::RenderState) {}

/// The texture on screen and what it was made from.
#[derive(Clone)]
struct Shown {
    key: (bool, u64),
    display: DisplaySettings,
    texture: egui::TextureHandle,
}

/// Adds the image to `ui`'s painter, drawn in `rect` (points).
pub fn paint_image(ui: &egui::Ui, rect: egui::Rect, source: ImageSource, display: DisplaySettings) {
    let id = egui::Id::unique("lumiere image texture");
    let shown: Option<Shown> = ui.ctx().data(|d| d.get_temp(id));
    let (key, false_colour) = (source.key(), source.key().0);
    // a false-colour image is already in linear RGB: no exposure, no tonemap
    let display = if false_colour {
        DisplaySettings {
            exposure: 0.0,
            tonemap: Tonemap::None,
            ..display
        }
    } else {
        display
    };
    let texture = match shown {
        Some(shown) if shown.key == key && shown.display == display => shown.texture,
        _ => {
            let (width, height, rgba) = source.pixels();
            let linear: Vec<Vec3> = rgba.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect();
            let rgb = to_srgb8(&linear, display);
            let image = egui::ColorImage::from_rgb([width as usize, height as usize], &rgb);
            let texture =
                ui.ctx()
                    .load_texture("lumiere image", image, egui::TextureOptions::NEAREST);
            ui.ctx().data_mut(|d| {
                d.insert_temp(
                    id,
                    Shown {
                        key,
                        display,
                        texture: texture.clone(),
                    },
                )
            });
            texture
        }
    };
    let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
    ui.painter()
        .image(texture.id(), rect, uv, egui::Color32::WHITE);
}
