//! How many continuations each first hit of a pixel takes: one count for
//! the image, or the splitting pilot's count region by region
//! (`transport::splitting` chooses them).

use std::sync::Arc;

/// Continuations per first hit, pixel by pixel: one count everywhere, or
/// the pilot's count for each region of the image.
#[derive(Clone, Debug, PartialEq)]
pub struct Continuations {
    /// The count everywhere, or with a map the one the whole image would
    /// take (the formula applied to the sums over every region).
    pub count: u32,
    pub map: Option<Arc<SplitMap>>,
}

impl Default for Continuations {
    fn default() -> Self {
        Self::uniform(1)
    }
}

impl Continuations {
    /// `count` continuations at every pixel.
    pub fn uniform(count: u32) -> Self {
        Self {
            count: count.max(1),
            map: None,
        }
    }

    /// The continuations of pixel (`x`, `y`).
    #[inline(always)]
    pub fn at(&self, x: u32, y: u32) -> u32 {
        match &self.map {
            None => self.count,
            Some(map) => map.at(x, y),
        }
    }

    /// The fewest and the most continuations a pixel takes.
    pub fn range(&self) -> (u32, u32) {
        match &self.map {
            None => (self.count, self.count),
            Some(map) => map.range(),
        }
    }

    /// Continuations per sample, averaged over the image.
    pub fn mean(&self) -> f64 {
        self.map.as_ref().map_or(self.count as f64, |m| m.mean())
    }

    /// `4`, or with a map that varies `1–16`.
    pub fn label(&self) -> String {
        match self.range() {
            (lo, hi) if lo == hi => lo.to_string(),
            (lo, hi) => format!("{lo}–{hi}"),
        }
    }
}

/// Continuations per first hit for each of `columns` × `rows` regions
/// tiling a `width` × `height` image (region (i, j) holds the pixels x
/// with ⌊x·columns/width⌋ = i, and likewise for y).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMap {
    pub width: u32,
    pub height: u32,
    pub columns: u32,
    pub rows: u32,
    /// Row by row, `columns` per row.
    pub counts: Vec<u32>,
}

impl SplitMap {
    /// The region of pixel (`x`, `y`): its column and row.
    #[inline(always)]
    pub fn region_of(&self, x: u32, y: u32) -> (u32, u32) {
        let column = (x as u64 * self.columns as u64 / self.width.max(1) as u64) as u32;
        let row = (y as u64 * self.rows as u64 / self.height.max(1) as u64) as u32;
        (column.min(self.columns - 1), row.min(self.rows - 1))
    }

    #[inline(always)]
    pub fn at(&self, x: u32, y: u32) -> u32 {
        let (column, row) = self.region_of(x, y);
        self.counts[(row * self.columns + column) as usize]
    }

    pub fn range(&self) -> (u32, u32) {
        let lo = self.counts.iter().copied().min().unwrap_or(1);
        let hi = self.counts.iter().copied().max().unwrap_or(1);
        (lo, hi)
    }

    /// The count averaged over the image's pixels.
    pub fn mean(&self) -> f64 {
        let span = |i: u32, n: u32, size: u32| {
            let start = (i as u64 * size as u64).div_ceil(n as u64);
            let end = ((i + 1) as u64 * size as u64).div_ceil(n as u64);
            (end - start) as f64
        };
        let mut sum = 0.0;
        for row in 0..self.rows {
            for column in 0..self.columns {
                let area =
                    span(column, self.columns, self.width) * span(row, self.rows, self.height);
                sum += area * self.counts[(row * self.columns + column) as usize] as f64;
            }
        }
        sum / (self.width as f64 * self.height as f64).max(1.0)
    }
}
