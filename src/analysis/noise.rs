//! Noise views: per-pixel statistics of the film as false colour.
//!
//! Every value is about the **luminance** Y of a pixel's samples. For one
//! term t with N samples, the film's Welford statistics give the mean and
//! M2 = Σ (Y − Ȳ)², and
//!
//! ```text
//! standard error   se_t = √(M2 / (N − 1) / N)                 (W·m⁻²·sr⁻¹)
//! visible sum      se   = √(Σ_t se_t²)       (the terms' samples taken as independent)
//! relative error   se / Ȳ × 100                               (%; none where Ȳ = 0)
//! sample count     N  (per term; the fewest among the visible terms for the sum)
//! difference       Y(image) − Y(reference)                    (signed, W·m⁻²·sr⁻¹)
//! ```
//!
//! The colour scale is robust: magnitudes run from 0 to their 99th
//! percentile (log scale: from the 1st to the 99th percentile of the
//! positive values), the difference from −p to +p with p the 99th percentile
//! of |difference|; values beyond the range take the end colours. Magnitudes
//! use a viridis-like map (luminance rising with the value), signed values a
//! blue–white–red map (white at zero).

use std::fmt;
use std::str::FromStr;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::analysis::metrics::ReferenceImage;
use crate::course::color::{luminance, srgb_to_linear};
use crate::course::{Term, TermSet};
use crate::render::film::Film;

/// What the viewer shows in place of the image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum DisplayMode {
    /// The radiance, exposed and tonemapped.
    #[default]
    Image,
    StandardError,
    RelativeError,
    SampleCount,
    /// Image − reference (only with a reference image).
    Difference,
}

impl DisplayMode {
    pub const ALL: [DisplayMode; 5] = [
        DisplayMode::Image,
        DisplayMode::StandardError,
        DisplayMode::RelativeError,
        DisplayMode::SampleCount,
        DisplayMode::Difference,
    ];

    /// Command-line name.
    pub fn label(self) -> &'static str {
        match self {
            DisplayMode::Image => "image",
            DisplayMode::StandardError => "standard-error",
            DisplayMode::RelativeError => "relative-error",
            DisplayMode::SampleCount => "sample-count",
            DisplayMode::Difference => "difference",
        }
    }

    /// Name for people.
    pub fn title(self) -> &'static str {
        match self {
            DisplayMode::Image => "Image",
            DisplayMode::StandardError => "Standard error",
            DisplayMode::RelativeError => "Relative error",
            DisplayMode::SampleCount => "Sample count",
            DisplayMode::Difference => "Difference",
        }
    }

    /// The unit of its values (none for the image).
    pub fn unit(self) -> Option<Unit> {
        match self {
            DisplayMode::Image => None,
            DisplayMode::StandardError | DisplayMode::Difference => Some(Unit::Radiance),
            DisplayMode::RelativeError => Some(Unit::Percent),
            DisplayMode::SampleCount => Some(Unit::Samples),
        }
    }

    pub fn colour_map(self) -> ColourMap {
        match self {
            DisplayMode::Difference => ColourMap::Diverging,
            _ => ColourMap::Sequential,
        }
    }
}

impl fmt::Display for DisplayMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

impl FromStr for DisplayMode {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|m| m.label().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|m| m.label()).collect();
                format!(
                    "unknown display mode '{s}' (expected one of: {})",
                    names.join(", ")
                )
            })
    }
}

/// Whose samples a noise view describes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum NoiseSource {
    /// The sum of the visible terms.
    #[default]
    Visible,
    Term(Term),
}

impl NoiseSource {
    pub const ALL: [NoiseSource; 5] = [
        NoiseSource::Visible,
        NoiseSource::Term(Term::L0),
        NoiseSource::Term(Term::L1),
        NoiseSource::Term(Term::L2),
        NoiseSource::Term(Term::L3Plus),
    ];

    pub fn label(self) -> &'static str {
        match self {
            NoiseSource::Visible => "visible sum",
            NoiseSource::Term(t) => t.label(),
        }
    }

    /// The terms it sums, given the visible ones.
    pub fn terms(self, visible: TermSet) -> TermSet {
        match self {
            NoiseSource::Visible => visible,
            NoiseSource::Term(t) => TermSet::only(t),
        }
    }
}

/// How values map to the colour bar.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Scale {
    #[default]
    Linear,
    /// Logarithmic, for errors spanning decades (magnitudes only).
    Log,
}

/// Unit of the values of a noise view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    Radiance,
    Percent,
    Samples,
}

/// A tick label: few digits, an exponent for tiny values, whole sample counts.
pub fn format_tick(value: f32, unit: Unit) -> String {
    let magnitude = value.abs();
    if unit == Unit::Samples || (unit == Unit::Percent && magnitude >= 10.0) {
        format!("{value:.0}")
    } else if magnitude == 0.0 {
        "0".into()
    } else if magnitude >= 100.0 {
        format!("{value:.0}")
    } else if magnitude >= 1.0 {
        format!("{value:.2}")
    } else if magnitude >= 0.01 {
        format!("{value:.3}")
    } else {
        format!("{value:.1e}")
    }
}

impl Unit {
    pub fn symbol(self) -> &'static str {
        match self {
            // "W·m⁻²·sr⁻¹" written without superscript minus signs, which some UI fonts lack
            Unit::Radiance => "W/(m²·sr)",
            Unit::Percent => "%",
            Unit::Samples => "spp",
        }
    }
}

/// What to show: the mode, whose samples, on which scale.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(default)]
pub struct NoiseView {
    pub mode: DisplayMode,
    pub source: NoiseSource,
    pub scale: Scale,
}

/// A colour map: a position in [0, 1] along the bar → a colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourMap {
    /// Viridis-like: dark blue-violet → green → yellow, luminance rising.
    Sequential,
    /// Blue → white (0.5) → red.
    Diverging,
}

/// Colour of pixels that have no value (relative error where the mean is 0), sRGB.
pub const NO_VALUE_SRGB: [f32; 3] = [0.42, 0.42, 0.42];

/// Entries of a colour table.
pub const TABLE_SIZE: usize = 256;

impl ColourMap {
    /// The sRGB colour (components in [0, 1]) at `position` (clamped to [0, 1]).
    pub fn srgb(self, position: f32) -> [f32; 3] {
        let t = position.clamp(0.0, 1.0);
        match self {
            ColourMap::Sequential => viridis(t),
            ColourMap::Diverging => {
                let linear = diverging_linear(t);
                linear.map(crate::course::color::linear_to_srgb)
            }
        }
    }

    /// The linear-RGB colour at `position`.
    pub fn linear(self, position: f32) -> [f32; 3] {
        match self {
            ColourMap::Diverging => diverging_linear(position.clamp(0.0, 1.0)),
            ColourMap::Sequential => self.srgb(position).map(srgb_to_linear),
        }
    }

    /// [`TABLE_SIZE`] linear-RGB colours, entry i at position i / (size − 1).
    pub fn linear_table(self) -> Vec<[f32; 3]> {
        (0..TABLE_SIZE)
            .map(|i| self.linear(i as f32 / (TABLE_SIZE - 1) as f32))
            .collect()
    }
}

/// Viridis (matplotlib) as a degree-6 polynomial fit in sRGB.
fn viridis(t: f32) -> [f32; 3] {
    const C: [[f32; 3]; 7] = [
        [0.277_727_33, 0.005_407_344_5, 0.334_099_8],
        [0.105_093_04, 1.404_613_5, 1.384_590_1],
        [-0.330_861_83, 0.214_847_56, 0.095_095_16],
        [-4.634_230_5, -5.799_101, -19.332_441],
        [6.228_27, 14.179_933, 56.690_55],
        [4.776_385, -13.745_145, -65.353_03],
        [-5.435_456, 4.645_852_6, 26.312_435],
    ];
    std::array::from_fn(|c| {
        C.iter()
            .rev()
            .fold(0.0, |acc, coefficients| acc * t + coefficients[c])
            .clamp(0.0, 1.0)
    })
}

/// Blue → white → red, interpolated in linear RGB (so luminance is linear on each side).
fn diverging_linear(t: f32) -> [f32; 3] {
    // Moreland's cool-warm end colours, sRGB (59, 76, 192) and (180, 4, 38)
    let blue = Vec3::new(59.0, 76.0, 192.0) / 255.0;
    let red = Vec3::new(180.0, 4.0, 38.0) / 255.0;
    let (blue, red) = (blue.map(srgb_to_linear), red.map(srgb_to_linear));
    let colour = if t < 0.5 {
        blue.lerp(Vec3::ONE, t * 2.0)
    } else {
        Vec3::ONE.lerp(red, t * 2.0 - 1.0)
    };
    colour.to_array()
}

/// A noise view of the film: one value per pixel, the range of the colour
/// bar, and the colours.
#[derive(Clone, Debug)]
pub struct FalseColour {
    pub view: NoiseView,
    pub width: u32,
    pub height: u32,
    /// Per pixel, row-major from the top, in `unit`; NaN where there is no value.
    pub values: Vec<f32>,
    /// The values at the two ends of the colour bar.
    pub range: (f32, f32),
    /// The scale actually used (log falls back to linear for signed values).
    pub scale: Scale,
    pub unit: Unit,
    pub map: ColourMap,
    /// Linear RGBA (A = 1) of each pixel.
    pub rgba: Vec<[f32; 4]>,
}

impl FalseColour {
    /// Position of `value` along the colour bar, in [0, 1].
    pub fn position(&self, value: f32) -> f32 {
        bar_position(value, self.range, self.scale)
    }

    /// The value at `position` ∈ [0, 1] along the bar (for tick labels).
    pub fn value_at(&self, position: f32) -> f32 {
        let (lo, hi) = self.range;
        match self.scale {
            Scale::Linear => lo + (hi - lo) * position,
            Scale::Log => lo * (hi / lo).powf(position),
        }
    }

    /// Whether some pixels have no value (shown in [`NO_VALUE_SRGB`]).
    pub fn has_missing_values(&self) -> bool {
        self.values.iter().any(|v| v.is_nan())
    }
}

fn bar_position(value: f32, (lo, hi): (f32, f32), scale: Scale) -> f32 {
    if hi.is_nan() || lo.is_nan() || hi <= lo {
        // a constant image: magnitudes at the bottom, differences in the middle (white)
        return if lo < 0.0 { 0.5 } else { 0.0 };
    }
    let t = match scale {
        Scale::Linear => (value - lo) / (hi - lo),
        Scale::Log if value > 0.0 => (value / lo).ln() / (hi / lo).ln(),
        Scale::Log => 0.0,
    };
    t.clamp(0.0, 1.0)
}

/// Why a noise view cannot be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NoiseViewError {
    /// The image mode is not a noise view.
    NotANoiseView,
    NoReference,
    /// The reference's size differs from the film's.
    ReferenceSize {
        reference: (u32, u32),
        film: (u32, u32),
    },
}

impl fmt::Display for NoiseViewError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NoiseViewError::NotANoiseView => f.write_str("the image is not a noise view"),
            NoiseViewError::NoReference => f.write_str("no reference image"),
            NoiseViewError::ReferenceSize { reference, film } => write!(
                f,
                "the reference is {}×{}, the image {}×{}",
                reference.0, reference.1, film.0, film.1
            ),
        }
    }
}

impl std::error::Error for NoiseViewError {}

/// The per-pixel values of `view` over `film`, whose visible terms are
/// `visible` (see the module's table; NaN where there is no value).
pub fn noise_values(
    film: &Film,
    visible: TermSet,
    view: NoiseView,
    reference: Option<&ReferenceImage>,
) -> Result<Vec<f32>, NoiseViewError> {
    let pixels = film.pixel_count();
    let buffers: Vec<_> = view
        .source
        .terms(visible)
        .iter()
        .filter_map(|t| film.term(t))
        .collect();
    let values = match view.mode {
        DisplayMode::Image => return Err(NoiseViewError::NotANoiseView),
        DisplayMode::StandardError => (0..pixels)
            .map(|i| {
                let variance: f64 = buffers.iter().map(|b| b.standard_error(i).powi(2)).sum();
                variance.sqrt() as f32
            })
            .collect(),
        DisplayMode::RelativeError => (0..pixels)
            .map(|i| {
                let variance: f64 = buffers.iter().map(|b| b.standard_error(i).powi(2)).sum();
                let mean: f64 = buffers
                    .iter()
                    .filter(|b| b.samples > 0)
                    .map(|b| b.luminance[i].mean)
                    .sum();
                if mean > 0.0 {
                    (100.0 * variance.sqrt() / mean) as f32
                } else {
                    f32::NAN
                }
            })
            .collect(),
        DisplayMode::SampleCount => {
            // per pixel, the fewest samples of a shown term (a term switched on
            // later has fewer); with adaptive sampling, where terms stop at
            // different counts, the most: how often the pixel was traced
            let terms = view.source.terms(visible);
            let adaptive = terms
                .iter()
                .any(|t| film.term(t).is_some_and(|b| b.is_adaptive()));
            (0..pixels)
                .map(|i| {
                    let counts = terms
                        .iter()
                        .map(|t| film.term(t).map_or(0, |b| b.pixel_samples(i)));
                    let spp = if adaptive { counts.max() } else { counts.min() };
                    spp.unwrap_or(0) as f32
                })
                .collect()
        }
        DisplayMode::Difference => {
            let reference = reference.ok_or(NoiseViewError::NoReference)?;
            if (reference.width, reference.height) != (film.width, film.height)
                || reference.radiance.len() != pixels
            {
                return Err(NoiseViewError::ReferenceSize {
                    reference: (reference.width, reference.height),
                    film: (film.width, film.height),
                });
            }
            film.radiance(view.source.terms(visible))
                .iter()
                .zip(&reference.radiance)
                .map(|(&x, &r)| luminance(x) - luminance(r))
                .collect()
        }
    };
    Ok(values)
}

/// The `p`-th percentile (p ∈ [0, 100], nearest rank) of the finite `values`
/// that pass `keep`; `None` if there are none.
pub fn percentile(values: &[f32], p: f32, keep: impl Fn(f32) -> bool) -> Option<f32> {
    let mut kept: Vec<f32> = values
        .iter()
        .copied()
        .filter(|v| v.is_finite() && keep(*v))
        .collect();
    if kept.is_empty() {
        return None;
    }
    let rank = ((p / 100.0 * kept.len() as f32).ceil() as usize).clamp(1, kept.len()) - 1;
    let (_, value, _) = kept.select_nth_unstable_by(rank, f32::total_cmp);
    Some(*value)
}

/// The colour bar's range for `values` (see the module header), and the scale used.
pub fn robust_range(values: &[f32], map: ColourMap, scale: Scale) -> ((f32, f32), Scale) {
    match (map, scale) {
        (ColourMap::Diverging, _) => {
            let magnitudes: Vec<f32> = values.iter().map(|v| v.abs()).collect();
            let p = percentile(&magnitudes, 99.0, |_| true).unwrap_or(0.0);
            ((-p, p), Scale::Linear)
        }
        (ColourMap::Sequential, Scale::Log) => {
            let positive = |v: f32| v > 0.0;
            match (
                percentile(values, 1.0, positive),
                percentile(values, 99.0, positive),
            ) {
                (Some(lo), Some(hi)) if hi > lo => ((lo, hi), Scale::Log),
                _ => robust_range(values, map, Scale::Linear),
            }
        }
        (ColourMap::Sequential, Scale::Linear) => {
            let hi = percentile(values, 99.0, |_| true).unwrap_or(0.0);
            ((0.0, hi.max(0.0)), Scale::Linear)
        }
    }
}

/// The noise view `view` of `film` (visible terms `visible`), coloured.
pub fn false_colour(
    film: &Film,
    visible: TermSet,
    view: NoiseView,
    reference: Option<&ReferenceImage>,
) -> Result<FalseColour, NoiseViewError> {
    let values = noise_values(film, visible, view, reference)?;
    Ok(colour_values(film.width, film.height, view, values))
}

/// Colours per-pixel `values` of `view` (see [`noise_values`]).
pub fn colour_values(width: u32, height: u32, view: NoiseView, values: Vec<f32>) -> FalseColour {
    let map = view.mode.colour_map();
    let (range, scale) = match view.mode {
        // counts are exact: the bar runs from 0 to the largest
        DisplayMode::SampleCount => {
            let max = values.iter().copied().fold(0.0f32, f32::max);
            ((0.0, max), Scale::Linear)
        }
        _ => robust_range(&values, map, view.scale),
    };
    let table = map.linear_table();
    let missing = NO_VALUE_SRGB.map(srgb_to_linear);
    let last = (TABLE_SIZE - 1) as f32;
    let rgba = values
        .iter()
        .map(|&v| {
            let [r, g, b] = if v.is_nan() {
                missing
            } else {
                table[(bar_position(v, range, scale) * last).round() as usize]
            };
            [r, g, b, 1.0]
        })
        .collect();
    FalseColour {
        view,
        width,
        height,
        values,
        range,
        scale,
        unit: view.mode.unit().unwrap_or(Unit::Radiance),
        map,
        rgba,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn srgb_luminance(c: [f32; 3]) -> f32 {
        luminance(Vec3::from_array(c.map(srgb_to_linear)))
    }

    /// The map's ends are matplotlib's viridis ends, to the fit's error: the
    /// degree-6 polynomial departs from matplotlib's 256 viridis entries by
    /// at most 0.01264 (the blue of the last entry), and its f32 evaluation
    /// by Horner's rule (a product and a sum per degree, 12 roundings) adds at
    /// most 12 · 2⁻²⁴ · Σ|cₖ| ≤ 1.3·10⁻⁴ (Σ|cₖ| ≤ 170 at t ≤ 1).
    #[test]
    fn sequential_map_is_viridis_with_rising_luminance() {
        const FIT_ERROR: f32 = 0.01264 + 1.3e-4;
        let ends = [
            ColourMap::Sequential.srgb(0.0),
            ColourMap::Sequential.srgb(1.0),
        ];
        // matplotlib's first and last viridis entries (#440154 and #fde725)
        let expected = [
            [0.267004, 0.004874, 0.329415],
            [0.993248, 0.906157, 0.143936],
        ];
        for (end, want) in ends.iter().zip(expected) {
            for c in 0..3 {
                assert!((end[c] - want[c]).abs() <= FIT_ERROR, "{end:?} vs {want:?}");
            }
        }
        let table: Vec<f32> = (0..TABLE_SIZE)
            .map(|i| srgb_luminance(ColourMap::Sequential.srgb(i as f32 / 255.0)))
            .collect();
        for pair in table.windows(2) {
            assert!(pair[1] > pair[0], "luminance must rise: {pair:?}");
        }
    }

    #[test]
    fn diverging_map_is_white_at_zero_and_darker_towards_both_ends() {
        let map = ColourMap::Diverging;
        assert_eq!(map.linear(0.5), [1.0, 1.0, 1.0]);
        let [r, _, b] = map.srgb(0.0);
        assert!(b > r, "negative end is blue");
        let [r, _, b] = map.srgb(1.0);
        assert!(r > b, "positive end is red");
        let y = |t: f32| luminance(Vec3::from_array(map.linear(t)));
        for i in 0..127 {
            let t = i as f32 / 255.0;
            assert!(y(t + 1.0 / 255.0) > y(t), "rises to the centre at {t}");
            assert!(
                y(1.0 - t - 1.0 / 255.0) > y(1.0 - t),
                "falls from the centre"
            );
        }
    }

    #[test]
    fn percentile_takes_the_nearest_rank_and_ignores_non_finite_values() {
        let mut values: Vec<f32> = (1..=100).map(|v| v as f32).collect();
        values.extend([f32::NAN, f32::INFINITY]);
        assert_eq!(percentile(&values, 99.0, |_| true), Some(99.0));
        assert_eq!(percentile(&values, 100.0, |_| true), Some(100.0));
        assert_eq!(percentile(&values, 1.0, |v| v > 50.0), Some(51.0));
        assert_eq!(percentile(&[f32::NAN], 50.0, |_| true), None);
    }

    /// Nearest-rank percentiles of known values, exactly: of 1000 values the
    /// 99th percentile is the 990th smallest; of the 999 positive ones the
    /// 1st is the 10th smallest and the 99th the 990th (ranks ⌈p·n/100⌉).
    #[test]
    fn robust_range_ignores_the_top_percent() {
        // 995 values i/995 in [0, 1) and five fireflies (0.5 %) of 1000
        let mut values: Vec<f32> = (0..995).map(|i| i as f32 / 995.0).collect();
        values.extend([1000.0; 5]);
        let ((lo, hi), scale) = robust_range(&values, ColourMap::Sequential, Scale::Linear);
        assert_eq!((lo, hi, scale), (0.0, 989.0 / 995.0, Scale::Linear));
        let signed: Vec<f32> = values.iter().map(|v| -v).collect();
        let ((lo, hi), _) = robust_range(&signed, ColourMap::Diverging, Scale::Linear);
        assert_eq!(
            (lo, hi),
            (-989.0 / 995.0, 989.0 / 995.0),
            "symmetric ±p99 of |d|"
        );
        // the log scale ranges over the positive values: 0 is left out
        let ((lo, hi), scale) = robust_range(&values, ColourMap::Sequential, Scale::Log);
        assert_eq!((lo, hi, scale), (10.0 / 995.0, 990.0 / 995.0, Scale::Log));
    }

    #[test]
    fn values_match_the_film_statistics() {
        // two pixels, L1 and L2, four samples each
        let mut film = Film::new(2, 1);
        let l1 = [[1.0, 0.0], [3.0, 0.0], [2.0, 0.0], [6.0, 0.0]];
        let l2 = [[0.5, 0.0], [0.5, 0.0], [1.5, 0.0], [1.5, 0.0]];
        for pass in 0..4 {
            let sample = |p: usize| {
                [
                    Vec3::ZERO,
                    Vec3::splat(l1[pass][p]),
                    Vec3::splat(l2[pass][p]),
                    Vec3::ZERO,
                ]
            };
            film.add_pass(TermSet::COURSE, pass as u32, &[sample(0), sample(1)]);
        }
        let visible = TermSet::COURSE;
        let view = |mode, source| NoiseView {
            mode,
            source,
            scale: Scale::Linear,
        };
        // sample standard deviations: L1 {1,3,2,6}: var = 14/3; L2 {.5,.5,1.5,1.5}: var = 1/3
        let se_l1 = (14.0f64 / 3.0 / 4.0).sqrt();
        let se_l2 = (1.0f64 / 3.0 / 4.0).sqrt();
        let se = noise_values(
            &film,
            visible,
            view(DisplayMode::StandardError, NoiseSource::Term(Term::L1)),
            None,
        )
        .unwrap();
        assert!((se[0] as f64 - se_l1).abs() < 1e-6 && se[1] == 0.0);
        let se = noise_values(
            &film,
            visible,
            view(DisplayMode::StandardError, NoiseSource::Visible),
            None,
        )
        .unwrap();
        assert!((se[0] as f64 - (se_l1 * se_l1 + se_l2 * se_l2).sqrt()).abs() < 1e-6);
        let relative = noise_values(
            &film,
            visible,
            view(DisplayMode::RelativeError, NoiseSource::Visible),
            None,
        )
        .unwrap();
        let mean = 3.0 + 1.0;
        assert!((relative[0] - se[0] / mean * 100.0).abs() < 1e-4);
        assert!(relative[1].is_nan(), "mean 0 has no relative error");
        let count = noise_values(
            &film,
            visible,
            view(DisplayMode::SampleCount, NoiseSource::Visible),
            None,
        )
        .unwrap();
        assert_eq!(count, [4.0, 4.0]);

        let reference = ReferenceImage {
            width: 2,
            height: 1,
            radiance: vec![Vec3::splat(5.0), Vec3::splat(1.0)],
            label: "test".into(),
        };
        let difference = noise_values(
            &film,
            visible,
            view(DisplayMode::Difference, NoiseSource::Visible),
            Some(&reference),
        )
        .unwrap();
        assert!((difference[0] - (4.0 - 5.0)).abs() < 1e-5);
        assert!((difference[1] - (0.0 - 1.0)).abs() < 1e-5);
        let coloured = colour_values(
            2,
            1,
            view(DisplayMode::Difference, NoiseSource::Visible),
            difference,
        );
        assert_eq!(coloured.range, (-1.0, 1.0));
        assert_eq!(coloured.rgba[0][..3], ColourMap::Diverging.linear(0.0));
        let small = ReferenceImage {
            width: 1,
            ..reference
        };
        assert!(matches!(
            noise_values(
                &film,
                visible,
                view(DisplayMode::Difference, NoiseSource::Visible),
                Some(&small)
            ),
            Err(NoiseViewError::ReferenceSize { .. })
        ));
    }

    #[test]
    fn display_mode_names_round_trip() {
        for mode in DisplayMode::ALL {
            assert_eq!(mode.label().parse::<DisplayMode>().unwrap(), mode);
        }
        assert!("noise".parse::<DisplayMode>().is_err());
    }
}
