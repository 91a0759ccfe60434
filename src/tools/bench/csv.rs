//! The error-curve CSV: one row per (renderer, estimator, sample count).
//!
//! `renderer,estimator,spp,seconds,rmse,relmse` — the same columns whoever
//! wrote the file, so a peer renderer's rows (Mitsuba's, from
//! `tests/reference/mitsuba_bench.py`) merge with lumiere's. `seconds` is the
//! wall time of the render up to that sample count; the errors are against
//! one shared reference.

use std::path::Path;

use super::BenchError;

/// The header of an error CSV, in order.
pub const ERROR_COLUMNS: [&str; 6] = ["renderer", "estimator", "spp", "seconds", "rmse", "relmse"];

/// One measured point of an error curve.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorRow {
    pub renderer: String,
    pub estimator: String,
    pub spp: u32,
    pub seconds: f64,
    pub rmse: f64,
    pub relmse: f64,
}

/// The CSV text of `rows`, header first.
pub fn error_csv(rows: &[ErrorRow]) -> String {
    let mut text = ERROR_COLUMNS.join(",") + "\n";
    for r in rows {
        text += &format!(
            "{},{},{},{:.6},{:.6e},{:.6e}\n",
            r.renderer, r.estimator, r.spp, r.seconds, r.rmse, r.relmse
        );
    }
    text
}

/// Parses an error CSV (`path` only names it in errors): the header must be
/// exactly [`ERROR_COLUMNS`]; every row needs six fields, a positive spp,
/// finite non-negative seconds and errors.
pub fn parse_error_csv(text: &str, path: &Path) -> Result<Vec<ErrorRow>, BenchError> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let header = lines
        .next()
        .ok_or_else(|| BenchError::file(path, "empty file (expected a CSV header)"))?;
    let names: Vec<&str> = header.1.split(',').map(str::trim).collect();
    if names != ERROR_COLUMNS {
        return Err(BenchError::file(
            path,
            format!(
                "line 1: header '{}', expected '{}'",
                header.1.trim(),
                ERROR_COLUMNS.join(",")
            ),
        ));
    }
    lines
        .map(|(index, line)| {
            parse_row(line)
                .map_err(|problem| BenchError::file(path, format!("line {}: {problem}", index + 1)))
        })
        .collect()
}

fn parse_row(line: &str) -> Result<ErrorRow, String> {
    let fields: Vec<&str> = line.split(',').map(str::trim).collect();
    if fields.len() != ERROR_COLUMNS.len() {
        return Err(format!(
            "{} fields, expected {} ({})",
            fields.len(),
            ERROR_COLUMNS.len(),
            ERROR_COLUMNS.join(",")
        ));
    }
    let number = |column: usize| -> Result<f64, String> {
        fields[column]
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v >= 0.0)
            .ok_or_else(|| {
                format!(
                    "{} '{}' is not a finite non-negative number",
                    ERROR_COLUMNS[column], fields[column]
                )
            })
    };
    let spp = fields[2]
        .parse::<u32>()
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| format!("spp '{}' is not a positive integer", fields[2]))?;
    if fields[0].is_empty() {
        return Err("empty renderer name".into());
    }
    Ok(ErrorRow {
        renderer: fields[0].to_string(),
        estimator: fields[1].to_string(),
        spp,
        seconds: number(3)?,
        rmse: number(4)?,
        relmse: number(5)?,
    })
}

/// Reads a peer's error CSV.
pub fn read_error_csv(path: &Path) -> Result<Vec<ErrorRow>, BenchError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| BenchError::file(path, format!("cannot read: {e}")))?;
    parse_error_csv(&text, path)
}

/// Writes `text` to `path`.
pub fn write_text(path: &Path, text: &str) -> Result<(), BenchError> {
    std::fs::write(path, text).map_err(|e| BenchError::file(path, format!("cannot write: {e}")))
}
