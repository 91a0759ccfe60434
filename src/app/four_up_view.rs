//! The four-up layout on screen: L0 | L1 | L2 | their sum as four tiles of
//! one image (`crate::render::four_up`), each labelled; a term switched off
//! leaves its tile empty, saying "off". The layout is a display setting: it
//! never restarts the render, it only asks the worker for each term's image.

use std::sync::Arc;

use eframe::egui;

use super::LumiereApp;
use crate::analysis::noise::DisplayMode;
use crate::render::display::Layout;
use crate::render::four_up::{Arrangement, TILES, Tile, compose};
use crate::render::progressive::Snapshot;

/// The colour around the image, and of an empty tile.
pub const BACKGROUND: egui::Color32 = egui::Color32::from_gray(24);

/// Composed images count their generations from here, away from the
/// workers' and the split's.
const FOUR_UP_GENERATION: u64 = 1 << 61;

/// The four-up image last composed, and where its tiles were drawn.
#[derive(Default)]
pub struct FourUpState {
    composite: Option<Composite>,
    composed: u64,
    /// Each tile as drawn last frame (empty when the layout is not shown).
    pub tiles: Vec<TileView>,
}

struct Composite {
    image: Arc<Snapshot>,
    /// The worker, its snapshot and the arrangement it was composed from.
    key: (u64, u64, Arrangement),
}

/// A tile as drawn: where, its label, and whether it is empty.
#[derive(Clone, Debug, PartialEq)]
pub struct TileView {
    pub tile: Tile,
    /// Points.
    pub rect: egui::Rect,
    pub label: String,
    /// Where the label is drawn over the tile (points).
    pub label_rect: Option<egui::Rect>,
    /// Its term is switched off: the tile is empty and says "off".
    pub off: bool,
}

/// Whether the four-up is shown: its layout is chosen, the display mode is
/// the image (a noise view shows one image), and no A/B comparison is on.
pub fn active(app: &LumiereApp) -> bool {
    app.state.display.layout == Layout::FourUp
        && app.state.noise.mode == DisplayMode::Image
        && !app.compare.enabled
}

/// `snapshot`'s four tiles in `arrangement`, as one snapshot to display.
pub fn shown(app: &mut LumiereApp, snapshot: &Snapshot, arrangement: Arrangement) -> Arc<Snapshot> {
    let key = (app.renderer_serial, snapshot.generation, arrangement);
    let state = &mut app.four_up;
    if let Some(composite) = &state.composite
        && composite.key == key
    {
        return Arc::clone(&composite.image);
    }
    state.composed += 1;
    let image = Arc::new(Snapshot {
        generation: FOUR_UP_GENERATION + state.composed,
        restarts: snapshot.restarts,
        width: arrangement.columns() * snapshot.width,
        height: arrangement.rows() * snapshot.height,
        preview: snapshot.preview,
        radiance: compose(snapshot, arrangement),
        terms: snapshot.terms,
        term_images: Default::default(),
        term_samples: snapshot.term_samples,
        elapsed: snapshot.elapsed,
        rays: snapshot.rays,
        pixel_samples: snapshot.pixel_samples,
        continuations: snapshot.continuations.clone(),
        idle: snapshot.idle,
        source: snapshot.source.clone(),
    });
    state.composite = Some(Composite {
        image: Arc::clone(&image),
        key,
    });
    image
}

/// Over the tiles (`tiles`, in reading order): empty tiles, the seams
/// between tiles, and each tile's label.
pub fn overlay_ui(
    app: &mut LumiereApp,
    ui: &mut egui::Ui,
    tiles: &[egui::Rect],
    snapshot: &Snapshot,
) {
    let terms = app.state.settings.terms;
    let image = tiles
        .iter()
        .copied()
        .reduce(|a, b| a.union(b))
        .unwrap_or(egui::Rect::NOTHING);
    let painter = ui.painter_at(image);
    let mut views = Vec::with_capacity(TILES.len());
    for (&tile, &rect) in TILES.iter().zip(tiles) {
        let off = tile.is_off(terms);
        // an empty tile: the image under it is black (or a term not yet published)
        if off || tile.pixels(snapshot).is_none() {
            painter.rect_filled(rect, 0.0, BACKGROUND);
        }
        if off {
            let size = (rect.height() / 8.0).clamp(14.0, 48.0);
            ui.put(
                rect,
                egui::Label::new(
                    egui::RichText::new("off")
                        .size(size)
                        .color(egui::Color32::from_gray(160)),
                ),
            );
        }
        views.push(TileView {
            tile,
            rect,
            label: tile.label(terms),
            label_rect: None,
            off,
        });
    }
    // seams: a thin line of the background between tiles
    let seam = egui::Stroke::new(2.0, BACKGROUND);
    for rect in tiles {
        if rect.min.x > image.min.x + 0.5 {
            painter.vline(rect.min.x, rect.y_range(), seam);
        }
        if rect.min.y > image.min.y + 0.5 {
            painter.hline(rect.x_range(), rect.min.y, seam);
        }
    }
    for view in &mut views {
        let inset = view.rect.shrink(4.0);
        if inset.width() < 20.0 || inset.height() < 10.0 {
            continue;
        }
        let size = (view.rect.height() / 18.0).clamp(12.0, 28.0);
        let response = ui.scope_builder(
            egui::UiBuilder::new()
                .max_rect(inset)
                .layout(egui::Layout::left_to_right(egui::Align::Min)),
            |ui| {
                egui::Frame::new()
                    .fill(egui::Color32::from_black_alpha(170))
                    .inner_margin(3.0)
                    .corner_radius(3.0)
                    .show(ui, |ui| {
                        ui.add(
                            egui::Label::new(
                                egui::RichText::new(&view.label)
                                    .size(size)
                                    .color(egui::Color32::WHITE),
                            )
                            .truncate(),
                        );
                    })
                    .response
            },
        );
        view.label_rect = Some(response.inner.rect);
    }
    app.four_up.tiles = views;
}

/// The layout choice of the Display group (key 4).
pub fn layout_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        ui.label("layout");
        let layout = &mut app.state.display.layout;
        ui.radio_value(layout, Layout::Single, "single")
            .on_hover_text("The sum of the visible terms");
        ui.radio_value(layout, Layout::FourUp, "four-up").on_hover_text(
            "4: L0 | L1 | L2 | their sum, from the same render, with the same exposure and tonemap \
             (2 × 2, or in a row when the window is wide)",
        );
    });
    if app.state.display.layout == Layout::FourUp && !active(app) {
        ui.label(
            egui::RichText::new("four-up: with the image mode, without Compare")
                .weak()
                .small(),
        );
    }
}

/// Key 4: the four-up on or off.
pub fn toggle(app: &mut LumiereApp) {
    let layout = &mut app.state.display.layout;
    *layout = match layout {
        Layout::Single => Layout::FourUp,
        Layout::FourUp => Layout::Single,
    };
}
