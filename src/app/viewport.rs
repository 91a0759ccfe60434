//! The central panel: the image fitted to the free space (or zoomed), the
//! mouse on it, and what is drawn over it — the noise legend, the probe,
//! the split's divider and labels, the four-up's labels.

use std::sync::Arc;

use eframe::egui;

use super::four_up_view;
use super::noise_view::{self, LEGEND_HEIGHT};
use super::probe_view::{self, ImageMapping};
use super::{LumiereApp, display, interact, lesson_view, split};
use crate::render::four_up::{Arrangement, TILES};
use crate::render::progressive::Snapshot;

/// How the image is scaled in the viewport.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Zoom {
    /// Screen pixels per film pixel; `None` fits the image to the window.
    pub scale: Option<u32>,
    /// Offset of the zoomed image from the centre, in points.
    pub pan: egui::Vec2,
}

impl Zoom {
    /// The zoom buttons: fit, 1:1, 2×, 4×, 8× (a new scale recentres).
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label("zoom");
            for (scale, text) in [
                (None, "Fit"),
                (Some(1), "1:1"),
                (Some(2), "2×"),
                (Some(4), "4×"),
                (Some(8), "8×"),
            ] {
                if ui.selectable_label(self.scale == scale, text).clicked() {
                    *self = Self {
                        scale,
                        pan: egui::Vec2::ZERO,
                    };
                }
            }
        })
        .response
        .on_hover_text("Screen pixels per film pixel (nearest neighbour); Shift+drag pans");
    }
}

/// The image, fitted to the free space, keeping the render's aspect; returns where.
pub fn viewport(app: &mut LumiereApp, ui: &mut egui::Ui, snapshot: &Arc<Snapshot>) -> egui::Rect {
    egui::CentralPanel::default()
        .frame(egui::Frame::new().fill(four_up_view::BACKGROUND))
        .show(ui, |ui| {
            let mut available = ui.available_rect_before_wrap();
            let noise = app.noise_view.image(app.state.noise);
            let legend = noise.as_ref().map(|_| {
                let (rest, strip) =
                    available.split_top_bottom_at_y(available.bottom() - LEGEND_HEIGHT);
                available = rest;
                strip
            });
            // a lesson's texts above and below the image, never over it
            let lesson_bands = lesson_view::bands(app, ui.ctx(), available);
            if let Some(bands) = &lesson_bands {
                available = bands.image_area(available);
            }
            app.windows_area = Some(available);
            let settings = &app.state.settings;
            let (width, height) = (settings.width, settings.height);
            let four_up = four_up_view::active(app).then(|| {
                Arrangement::fitting(
                    width as f32,
                    height as f32,
                    available.width(),
                    available.height(),
                )
            });
            // the film's pixels on screen: one image, or four tiles of it
            let (columns, rows) = four_up.map_or((1, 1), |a| (a.columns(), a.rows()));
            let ppp = ui.ctx().pixels_per_point();
            let film = egui::vec2((columns * width) as f32, (rows * height) as f32);
            let (size, centre) = match app.zoom.scale {
                // nearest neighbour: each film pixel is a square of `scale` screen pixels
                Some(scale) => (film * scale as f32 / ppp, available.center() + app.zoom.pan),
                None => {
                    let aspect = film.x / film.y;
                    let size = if available.width() / available.height() > aspect {
                        egui::vec2(available.height() * aspect, available.height())
                    } else {
                        egui::vec2(available.width(), available.width() / aspect)
                    };
                    (size, available.center())
                }
            };
            // whole physical pixels, so each film pixel maps to a fixed block of them
            let centred = egui::Rect::from_center_size(centre, size);
            let rect = egui::Rect::from_min_max(
                ((centred.min.to_vec2() * ppp).round() / ppp).to_pos2(),
                ((centred.max.to_vec2() * ppp).round() / ppp).to_pos2(),
            );
            // each tile's place; the image's when there is one
            let tiles: Vec<egui::Rect> = match four_up {
                Some(arrangement) => (0..TILES.len())
                    .map(|index| {
                        let (column, row) = arrangement.cell(index);
                        let tile = rect.size() / egui::vec2(columns as f32, rows as f32);
                        egui::Rect::from_min_size(
                            rect.min + tile * egui::vec2(column as f32, row as f32),
                            tile,
                        )
                    })
                    .collect(),
                None => vec![rect],
            };
            let mapping = |rect: egui::Rect| ImageMapping {
                rect,
                width,
                height,
            };
            let response = ui.allocate_rect(available, egui::Sense::click_and_drag());
            // the mouse works on the tile under it (any tile: they show one view)
            let pointer = response.interact_pointer_pos().or(response.hover_pos());
            let under = pointer
                .and_then(|p| tiles.iter().find(|t| t.contains(p)))
                .or(tiles.last())
                .copied()
                .unwrap_or(rect);
            interact::viewport_input(app, &response, &mapping(under));
            let source = match (&noise, four_up) {
                (Some((serial, image)), _) => Some(display::ImageSource::FalseColour {
                    serial: *serial,
                    image: Arc::clone(image),
                }),
                (None, _) if snapshot.radiance.is_empty() => None,
                (None, Some(arrangement)) => Some(display::ImageSource::Radiance(
                    four_up_view::shown(app, snapshot, arrangement),
                )),
                (None, None) => Some(display::ImageSource::Radiance(Arc::clone(snapshot))),
            };
            if let Some(source) = source {
                display::paint_image(ui, rect, source, app.state.display);
            }
            for &tile in &tiles {
                // a probe's path may run off the image, not onto another tile
                let clip = match four_up {
                    Some(_) => tile.intersect(available),
                    None => available,
                };
                probe_view::paint_overlay(&ui.painter_at(clip), &mapping(tile), &app.probe);
            }
            if let (Some(strip), Some((_, image))) = (legend, &noise) {
                noise_view::legend_ui(
                    ui,
                    strip,
                    image,
                    app.sent.settings.terms,
                    app.reference.as_deref(),
                );
            }
            if four_up.is_some() {
                four_up_view::overlay_ui(app, ui, &tiles, snapshot);
            } else {
                app.four_up.tiles.clear();
            }
            split::overlay_ui(app, ui, rect);
            if let Some(bands) = &lesson_bands {
                bands.paint(ui.painter());
            }
            rect
        })
        .inner
}
