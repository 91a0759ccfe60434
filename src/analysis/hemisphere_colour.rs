//! The map of the hemisphere as a picture: one factor of the integrand in
//! false colour (the noise views' sequential map), on a linear or a log
//! scale, with the range its colour bar states. Outside the disk, where
//! there is no direction, the picture is transparent.

use super::hemisphere::{Factor, IntegrandMap};
use super::noise::{ColourMap, Scale};

/// Decades a log scale shows below the largest value.
pub const LOG_DECADES: f32 = 4.0;

/// One factor of a map, coloured.
#[derive(Clone, Debug)]
pub struct ColouredMap {
    pub size: u32,
    /// sRGBA bytes, rows from the top.
    pub srgba: Vec<u8>,
    /// The values at the two ends of the colour bar (in the factor's unit).
    pub range: (f32, f32),
    pub scale: Scale,
    /// The values coloured, per pixel.
    pub values: Vec<f32>,
}

impl ColouredMap {
    /// The value at `position` ∈ [0, 1] along the bar.
    pub fn value_at(&self, position: f32) -> f32 {
        let (low, high) = self.range;
        match self.scale {
            Scale::Linear => low + position * (high - low),
            Scale::Log => low * (high / low).powf(position),
        }
    }

    /// The position along the bar of `value` (clamped to [0, 1]).
    pub fn position_of(&self, value: f32) -> f32 {
        let (low, high) = self.range;
        let t = match self.scale {
            Scale::Linear if high > low => (value - low) / (high - low),
            Scale::Linear => 0.0,
            Scale::Log if value > 0.0 => (value / low).log10() / (high / low).log10(),
            Scale::Log => 0.0,
        };
        t.clamp(0.0, 1.0)
    }
}

/// `factor` of `map` in false colour: see [`colour_values`].
pub fn colour_map(map: &IntegrandMap, factor: Factor, scale: Scale) -> ColouredMap {
    colour_values(map.layer(factor), map.size, scale)
}

/// The `values` of a `size`×`size` map of the disk in false colour: from 0
/// to the largest value (linear), or over [`LOG_DECADES`] decades below it
/// (log; zero shows as the bottom colour).
pub fn colour_values(values: Vec<f32>, size: u32, scale: Scale) -> ColouredMap {
    colour_values_up_to(values, size, scale, None)
}

/// [`colour_values`] with the top of the bar at `top` if given (two maps
/// compared on one bar), else at the largest value.
pub fn colour_values_up_to(
    values: Vec<f32>,
    size: u32,
    scale: Scale,
    top: Option<f32>,
) -> ColouredMap {
    let inside: Vec<bool> = (0..size * size)
        .map(|i| {
            let centre = IntegrandMap::disk_point(size, i % size, i / size, glam::Vec2::splat(0.5));
            centre.length() <= 1.0
        })
        .collect();
    let high = values
        .iter()
        .zip(&inside)
        .filter(|(_, inside)| **inside)
        .map(|(v, _)| *v)
        .fold(0.0f32, f32::max);
    let high = top.unwrap_or(high);
    let high = if high > 0.0 { high } else { 1.0 };
    let range = match scale {
        Scale::Linear => (0.0, high),
        Scale::Log => (high * 10f32.powf(-LOG_DECADES), high),
    };
    let mut coloured = ColouredMap {
        size,
        srgba: Vec::with_capacity(values.len() * 4),
        range,
        scale,
        values: Vec::new(),
    };
    for (value, inside) in values.iter().zip(&inside) {
        if !inside {
            coloured.srgba.extend([0, 0, 0, 0]);
            continue;
        }
        let [r, g, b] = ColourMap::Sequential.srgb(coloured.position_of(*value));
        let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
        coloured.srgba.extend([byte(r), byte(g), byte(b), 255]);
    }
    coloured.values = values;
    coloured
}
