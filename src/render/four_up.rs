//! The four-up layout: L0 | L1 | L2 | their sum, side by side, so that the
//! terms of the rendering equation are seen at once and the sum is seen to
//! be made of them.
//!
//! The tiles come from one render: the worker's film keeps one accumulator
//! per term, and a snapshot asked for it carries each visible term's image
//! beside their sum (`progressive::Snapshot::term_images`). The four are
//! composed into one image of radiance, so that exposure and tonemap apply
//! to every tile alike, at display. A term switched off has an empty tile;
//! the sum tile is the sum of the visible terms, L3+ included when it is on
//! (its label then names it).
//!
//! ```text
//! grid (2 × 2)      row (1 × 4)
//! L0 | L1           L0 | L1 | L2 | sum
//! L2 | sum
//! ```

use crate::course::{Term, TermSet};
use crate::render::progressive::Snapshot;
use crate::render::settings_override::terms_phrase;

/// One tile of the four-up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tile {
    Term(Term),
    /// The sum of the visible terms.
    Sum,
}

/// The tiles, in reading order.
pub const TILES: [Tile; 4] = [
    Tile::Term(Term::L0),
    Tile::Term(Term::L1),
    Tile::Term(Term::L2),
    Tile::Sum,
];

impl Tile {
    /// Its label, for the visible `terms`: "L0 emission", "L1 direct",
    /// "L2 indirect (one bounce)", and the sum's terms ("L0+L1+L2").
    pub fn label(self, terms: TermSet) -> String {
        match self {
            Tile::Term(Term::L0) => "L0 emission".into(),
            Tile::Term(Term::L1) => "L1 direct".into(),
            Tile::Term(Term::L2) => "L2 indirect (one bounce)".into(),
            Tile::Term(Term::L3Plus) => "L3+ (three bounces or more)".into(),
            Tile::Sum => terms_phrase(terms),
        }
    }

    /// Its label for a narrower tile: "L2 indirect" without the
    /// parenthesis, the others as [`Tile::label`].
    pub fn compact_label(self, terms: TermSet) -> String {
        match self {
            Tile::Term(Term::L2) => "L2 indirect".into(),
            tile => tile.label(terms),
        }
    }

    /// Its label in few characters: "L0", "L1", "L2", "sum".
    pub fn short_label(self) -> &'static str {
        match self {
            Tile::Term(t) => t.label(),
            Tile::Sum => "sum",
        }
    }

    /// Whether the tile is empty: its term is switched off.
    pub fn is_off(self, terms: TermSet) -> bool {
        matches!(self, Tile::Term(t) if !terms.contains(t))
    }

    /// Its pixels in `snapshot` (`None` when off, or while the snapshot
    /// has no image of its term yet).
    pub fn pixels(self, snapshot: &Snapshot) -> Option<&[[f32; 4]]> {
        if self.is_off(snapshot.terms) {
            return None;
        }
        match self {
            Tile::Term(t) => snapshot.term_images[t.index()].as_deref(),
            Tile::Sum => Some(&snapshot.radiance),
        }
    }
}

/// How the four tiles are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arrangement {
    /// Two by two.
    Grid,
    /// Four in a row.
    Row,
}

impl Arrangement {
    pub fn columns(self) -> u32 {
        match self {
            Arrangement::Grid => 2,
            Arrangement::Row => 4,
        }
    }

    pub fn rows(self) -> u32 {
        4 / self.columns()
    }

    /// Column and row of the tile `index` (reading order).
    pub fn cell(self, index: usize) -> (u32, u32) {
        let columns = self.columns() as usize;
        ((index % columns) as u32, (index / columns) as u32)
    }

    /// The arrangement whose tiles, `tile_width` × `tile_height` each, are
    /// shown largest in `width` × `height`: the row on a wide viewport,
    /// the grid otherwise (and on a tie).
    pub fn fitting(tile_width: f32, tile_height: f32, width: f32, height: f32) -> Self {
        let scale = |a: Arrangement| {
            (width / (a.columns() as f32 * tile_width))
                .min(height / (a.rows() as f32 * tile_height))
        };
        if scale(Arrangement::Row) > scale(Arrangement::Grid) {
            Arrangement::Row
        } else {
            Arrangement::Grid
        }
    }
}

/// The four tiles of `snapshot`, each `snapshot.width` × `snapshot.height`,
/// in one image of radiance (rows from the top); empty tiles are black.
pub fn compose(snapshot: &Snapshot, arrangement: Arrangement) -> Vec<[f32; 4]> {
    let (width, height) = (snapshot.width as usize, snapshot.height as usize);
    let columns = arrangement.columns() as usize;
    let full_width = columns * width;
    let mut image = vec![[0.0, 0.0, 0.0, 1.0]; full_width * arrangement.rows() as usize * height];
    for (index, tile) in TILES.into_iter().enumerate() {
        let Some(pixels) = tile.pixels(snapshot).filter(|p| p.len() == width * height) else {
            continue;
        };
        let (column, row) = arrangement.cell(index);
        for y in 0..height {
            let start = (row as usize * height + y) * full_width + column as usize * width;
            image[start..start + width].copy_from_slice(&pixels[y * width..(y + 1) * width]);
        }
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3×2 snapshot of L0 and L2 (L1 off), each pixel valued by its term.
    fn snapshot() -> Snapshot {
        let terms = TermSet::only(Term::L0).with(Term::L2, true);
        let image = |v: f32| vec![[v, v, v, 1.0]; 6];
        let mut term_images: [Option<Vec<[f32; 4]>>; Term::COUNT] = Default::default();
        term_images[Term::L0.index()] = Some(image(1.0));
        term_images[Term::L2.index()] = Some(image(2.0));
        Snapshot {
            width: 3,
            height: 2,
            terms,
            radiance: image(3.0),
            term_images,
            ..Snapshot::default()
        }
    }

    #[test]
    fn tiles_are_placed_in_reading_order_and_an_off_term_is_black() {
        let snapshot = snapshot();
        let grid = compose(&snapshot, Arrangement::Grid);
        assert_eq!(grid.len(), 6 * 4);
        let at = |image: &[[f32; 4]], x: usize, y: usize, width: usize| image[y * width + x][0];
        // L0 top left, L1 (off) top right, L2 bottom left, the sum bottom right
        assert_eq!(at(&grid, 0, 0, 6), 1.0);
        assert_eq!(at(&grid, 2, 1, 6), 1.0);
        assert_eq!(at(&grid, 3, 0, 6), 0.0);
        assert_eq!(at(&grid, 0, 2, 6), 2.0);
        assert_eq!(at(&grid, 5, 3, 6), 3.0);
        let row = compose(&snapshot, Arrangement::Row);
        let values: Vec<f32> = (0..12).map(|x| at(&row, x, 1, 12)).collect();
        assert_eq!(
            values,
            [1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0]
        );
        assert!(Tile::Term(Term::L1).is_off(snapshot.terms));
        assert!(!Tile::Sum.is_off(snapshot.terms));
        assert_eq!(Tile::Sum.label(snapshot.terms), "L0+L2");
        assert_eq!(Tile::Sum.label(TermSet::ALL), "L0+L1+L2+L3+");
        assert_eq!(
            Tile::Term(Term::L2).label(TermSet::ALL),
            "L2 indirect (one bounce)"
        );
    }

    #[test]
    fn a_wide_viewport_takes_the_row() {
        // 4:3 tiles: the row is as large as the grid when the viewport is 8:3
        assert_eq!(
            Arrangement::fitting(4.0, 3.0, 1000.0, 800.0),
            Arrangement::Grid
        );
        assert_eq!(
            Arrangement::fitting(4.0, 3.0, 1600.0, 450.0),
            Arrangement::Row
        );
        assert_eq!(
            Arrangement::fitting(4.0, 3.0, 1600.0, 600.0),
            Arrangement::Grid
        );
        assert_eq!(Arrangement::Row.cell(3), (3, 0));
        assert_eq!(Arrangement::Grid.cell(3), (1, 1));
    }
}
