//! Value parsers of the options clap cannot check alone: numbers within a
//! range, `--indirect-samples`, `--probe`, `--shown-size` and PNG paths.

use std::ops::{Bound, RangeBounds};
use std::str::FromStr;

use lumiere::course::{MAX_SAMPLES_PER_VERTEX, SourceQuality};

/// Parses a finite number within `range`; `what` names the value (and its
/// unit) in the messages, e.g. "exposure in stops must be within -64..=64, not 99".
/// A number too large for `T` parses as infinite and is refused as not finite.
pub fn parse_in_range<T>(s: &str, range: impl RangeBounds<f64>, what: &str) -> Result<T, String>
where
    T: FromStr + Into<f64> + Copy,
{
    let value: T = s
        .parse()
        .map_err(|_| format!("{what} must be a number, not '{s}'"))?;
    let wide: f64 = value.into();
    if !wide.is_finite() {
        Err(format!(
            "{what} must be a finite number {}, not {s}",
            describe(&range)
        ))
    } else if !range.contains(&wide) {
        Err(format!("{what} must be {}, not {s}", describe(&range)))
    } else {
        Ok(value)
    }
}

/// A range in words: "within 0..=1e6", "greater than 0", "greater than 0 and at most 1".
fn describe(range: &impl RangeBounds<f64>) -> String {
    if let (Bound::Included(&low), Bound::Included(&high)) =
        (range.start_bound(), range.end_bound())
    {
        return format!("within {}..={}", number(low), number(high));
    }
    let low = match range.start_bound() {
        Bound::Included(&v) => Some(format!("at least {}", number(v))),
        Bound::Excluded(&v) => Some(format!("greater than {}", number(v))),
        Bound::Unbounded => None,
    };
    let high = match range.end_bound() {
        Bound::Included(&v) => Some(format!("at most {}", number(v))),
        Bound::Excluded(&v) => Some(format!("less than {}", number(v))),
        Bound::Unbounded => None,
    };
    match (low, high) {
        (Some(low), Some(high)) => format!("{low} and {high}"),
        (Some(bound), None) | (None, Some(bound)) => bound,
        (None, None) => "of any size".to_string(),
    }
}

/// A bound as written in the help: 64, 0.5, 1e6.
fn number(v: f64) -> String {
    if v.abs() >= 1e5 {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// `--light-radius`: metres, positive.
pub fn parse_light_radius(s: &str) -> Result<f32, String> {
    parse_in_range(
        s,
        (Bound::Excluded(0.0), Bound::Unbounded),
        "light radius in metres",
    )
}

/// `--phong-exponent`: within 0..=1e6.
pub fn parse_phong_exponent(s: &str) -> Result<f32, String> {
    parse_in_range(s, 0.0..=1e6, "Phong exponent")
}

/// `--ior`: an index of refraction, within 1..=MAX_IOR.
pub fn parse_ior(s: &str) -> Result<f32, String> {
    parse_in_range(
        s,
        1.0..=f64::from(lumiere::course::MAX_IOR),
        "index of refraction",
    )
    .map_err(|e| format!("{e} (glass: 1.5, water: 1.33, diamond: 2.42)"))
}

/// `--adaptive`: a fraction of the pixel's value, within (0, 1].
pub fn parse_adaptive_threshold(s: &str) -> Result<f32, String> {
    parse_in_range(
        s,
        (Bound::Excluded(0.0), Bound::Included(1.0)),
        "adaptive threshold",
    )
    .map_err(|e| format!("{e} (a fraction: 0.01 stops at 1% standard error)"))
}

/// `--exposure`: stops, within -64..=64.
pub fn parse_exposure(s: &str) -> Result<f32, String> {
    parse_in_range(s, -64.0..=64.0, "exposure in stops")
}

/// `--time`: seconds, positive and at most 1e7.
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    parse_in_range(
        s,
        (Bound::Excluded(0.0), Bound::Included(1e7)),
        "render time in seconds",
    )
}

/// `--indirect-samples`: a count, or `auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IndirectSamples {
    /// This many continuations per first hit.
    Count(u32),
    /// The count a pilot render finds best.
    Auto,
}

/// `--indirect-samples`: `auto` or a count within 1..=MAX_SAMPLES_PER_VERTEX.
pub fn parse_indirect_samples(s: &str) -> Result<IndirectSamples, String> {
    if s.eq_ignore_ascii_case("auto") {
        return Ok(IndirectSamples::Auto);
    }
    match s.parse::<u32>() {
        Ok(m) if (1..=MAX_SAMPLES_PER_VERTEX).contains(&m) => Ok(IndirectSamples::Count(m)),
        _ => Err(format!(
            "expected `auto` or a count within 1..={MAX_SAMPLES_PER_VERTEX}"
        )),
    }
}

/// `--probe`: a pixel `X,Y` from the top left.
pub fn parse_pixel(s: &str) -> Result<(u32, u32), String> {
    let parsed = s
        .split_once(',')
        .and_then(|(x, y)| Some((x.trim().parse().ok()?, y.trim().parse().ok()?)));
    parsed.ok_or_else(|| format!("'{s}' is not a pixel X,Y"))
}

/// `--shown-size`: `WIDTHxHEIGHT` (or `×`), each side within 16..=16384 pixels.
pub fn parse_shown_size(s: &str) -> Result<(u32, u32), String> {
    let parsed = s
        .split_once(['x', 'X', '×'])
        .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)));
    let (width, height) =
        parsed.ok_or_else(|| format!("'{s}' is not a size WIDTHxHEIGHT, e.g. 1920x1080"))?;
    lumiere::tools::slides::shown::check_size(width, height)?;
    Ok((width, height))
}

/// A path that ends in `.png`.
pub fn parse_png_path(s: &str) -> Result<std::path::PathBuf, String> {
    let path = std::path::PathBuf::from(s);
    let png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    png.then_some(path)
        .ok_or_else(|| format!("'{s}': the picture is a PNG, its name must end in .png"))
}

/// `--source NAME=N` (N light samples of its own) or `NAME=off`.
pub fn parse_source_quality(s: &str) -> Result<SourceQuality, String> {
    let Some((name, value)) = s.rsplit_once('=') else {
        return Err(format!(
            "'{s}' must be NAME=N (light samples of the source) or NAME=off"
        ));
    };
    if name.is_empty() {
        return Err(format!("'{s}' names no source"));
    }
    match value {
        "off" => Ok(SourceQuality::off(name)),
        _ => {
            let what = format!("light samples of source '{name}'");
            let n: u32 = parse_in_range(value, 1.0..=MAX_SAMPLES_PER_VERTEX as f64, &what)?;
            Ok(SourceQuality::samples(name, n))
        }
    }
}
