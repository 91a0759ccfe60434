//! The bench's CSV files, written and read with the `csv` crate (quoting,
//! trimming, line numbers) and serde for their rows.
//!
//! The error-curve CSV has one row per (renderer, estimator, sample count):
//! `renderer,estimator,spp,seconds,rmse,relmse` — the same columns whoever
//! wrote the file, so a peer renderer's rows (Mitsuba's, from
//! `tests/reference/mitsuba_bench.py`) merge with lumiere's. `seconds` is the
//! wall time of the render up to that sample count; the errors are against
//! one shared reference. The throughput and scaling tables are written with
//! [`csv_text`] by their own modules.

use std::path::Path;

use ::csv::{ErrorKind, Position, ReaderBuilder, StringRecord, Trim, WriterBuilder};
use serde::{Deserialize, Serialize, Serializer};

use super::BenchError;

/// The header of an error CSV, in order.
pub const ERROR_COLUMNS: [&str; 6] = ["renderer", "estimator", "spp", "seconds", "rmse", "relmse"];

/// One measured point of an error curve; its fields are the CSV's columns.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorRow {
    pub renderer: String,
    pub estimator: String,
    pub spp: u32,
    #[serde(serialize_with = "six_decimals")]
    pub seconds: f64,
    #[serde(serialize_with = "six_digit_exponent")]
    pub rmse: f64,
    #[serde(serialize_with = "six_digit_exponent")]
    pub relmse: f64,
}

/// A number written with `DIGITS` decimals: `Decimals::<3>(2.0)` is `2.000`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decimals<const DIGITS: usize>(pub f64);

impl<const DIGITS: usize> Serialize for Decimals<DIGITS> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(&format_args!("{:.*}", DIGITS, self.0))
    }
}

/// A number in scientific notation with `DIGITS` decimals:
/// `Exponent::<2>(0.0125)` is `1.25e-2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exponent<const DIGITS: usize>(pub f64);

impl<const DIGITS: usize> Serialize for Exponent<DIGITS> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(&format_args!("{:.*e}", DIGITS, self.0))
    }
}

fn six_decimals<S: Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
    Decimals::<6>(*value).serialize(serializer)
}

fn six_digit_exponent<S: Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
    Exponent::<6>(*value).serialize(serializer)
}

/// CSV text: the header `columns`, then one record per row, its fields in
/// the order of the columns (the header is written even without rows).
pub fn csv_text<R: Serialize>(columns: &[&str], rows: impl IntoIterator<Item = R>) -> String {
    let mut writer = WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    writer
        .write_record(columns)
        .expect("a header writes to memory");
    for row in rows {
        writer
            .serialize(row)
            .expect("a row of numbers and strings is one CSV record");
    }
    let bytes = writer.into_inner().expect("a CSV writes to memory");
    String::from_utf8(bytes).expect("CSV of UTF-8 fields is UTF-8")
}

/// The CSV text of `rows`, header first.
pub fn error_csv(rows: &[ErrorRow]) -> String {
    csv_text(&ERROR_COLUMNS, rows)
}

/// Parses an error CSV (`path` only names it in errors): the header must be
/// exactly [`ERROR_COLUMNS`]; every row needs six fields, a positive spp,
/// finite non-negative seconds and errors. Fields are trimmed; blank lines
/// are skipped.
pub fn parse_error_csv(text: &str, path: &Path) -> Result<Vec<ErrorRow>, BenchError> {
    let at = |position: Option<&Position>, problem: &dyn std::fmt::Display| {
        let line = line_at(text, position);
        BenchError::file(path, format!("line {line}: {problem}"))
    };
    let mut reader = ReaderBuilder::new()
        .trim(Trim::All)
        .flexible(true)
        .from_reader(text.as_bytes());
    let header = reader.headers().map_err(|e| at(e.position(), &e))?.clone();
    if header.is_empty() {
        return Err(BenchError::file(path, "empty file (expected a CSV header)"));
    }
    if header.iter().ne(ERROR_COLUMNS) {
        let problem = format!(
            "header '{}', expected '{}'",
            header.iter().collect::<Vec<_>>().join(","),
            ERROR_COLUMNS.join(",")
        );
        return Err(at(header.position(), &problem));
    }
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| at(e.position(), &e))?;
        rows.push(parse_row(&record).map_err(|problem| at(record.position(), &problem))?);
    }
    Ok(rows)
}

/// The line of `text`, from 1, where the record read at `position` starts.
/// (`Position::line` gives a record after blank lines the line of the
/// first blank one, and `position` is where the reader stood before the
/// record: at the blank lines, which are skipped here.)
fn line_at(text: &str, position: Option<&Position>) -> usize {
    let bytes = text.as_bytes();
    let mut start = position.map_or(0, |p| p.byte() as usize).min(bytes.len());
    while matches!(bytes.get(start), Some(b'\n' | b'\r')) {
        start += 1;
    }
    1 + bytes[..start].iter().filter(|&&b| b == b'\n').count()
}

fn parse_row(record: &StringRecord) -> Result<ErrorRow, String> {
    if record.len() != ERROR_COLUMNS.len() {
        return Err(format!(
            "{} fields, expected {} ({})",
            record.len(),
            ERROR_COLUMNS.len(),
            ERROR_COLUMNS.join(",")
        ));
    }
    let invalid = |column: usize| {
        let (name, value) = (ERROR_COLUMNS[column], &record[column]);
        if name == "spp" {
            format!("spp '{value}' is not a positive integer")
        } else {
            format!("{name} '{value}' is not a finite non-negative number")
        }
    };
    let row: ErrorRow = record.deserialize(None).map_err(|e| {
        let column = match e.kind() {
            ErrorKind::Deserialize { err, .. } => err.field(),
            _ => None,
        };
        column.map_or_else(|| e.to_string(), |c| invalid(c as usize))
    })?;
    if row.renderer.is_empty() {
        return Err("empty renderer name".into());
    }
    if row.spp == 0 {
        return Err(invalid(2));
    }
    let numbers = [row.seconds, row.rmse, row.relmse];
    if let Some(k) = numbers.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(invalid(3 + k));
    }
    Ok(row)
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

/// The header serde gives `row`'s fields, for checking a row type against
/// its file's columns.
#[cfg(test)]
pub(crate) fn field_names<R: Serialize>(row: R) -> String {
    let mut writer = WriterBuilder::new().from_writer(Vec::new());
    writer.serialize(row).unwrap();
    let text = String::from_utf8(writer.into_inner().unwrap()).unwrap();
    text.lines().next().unwrap().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(renderer: &str, estimator: &str) -> ErrorRow {
        ErrorRow {
            renderer: renderer.into(),
            estimator: estimator.into(),
            spp: 16,
            seconds: 0.0123456789,
            rmse: 0.31415926,
            relmse: 1.5e-7,
        }
    }

    #[test]
    fn error_rows_are_written_under_their_columns() {
        assert_eq!(field_names(row("a", "b")), ERROR_COLUMNS.join(","));
        assert_eq!(
            error_csv(&[row("lumiere", "mis/independent")]),
            "renderer,estimator,spp,seconds,rmse,relmse\n\
             lumiere,mis/independent,16,0.012346,3.141593e-1,1.500000e-7\n"
        );
        assert_eq!(
            error_csv(&[]),
            "renderer,estimator,spp,seconds,rmse,relmse\n"
        );
    }

    #[test]
    fn error_rows_read_back_with_quoted_fields() {
        let rows = [row("peer, patched", "say \"mis\""), row("lumiere", "area")];
        let text = error_csv(&rows);
        assert!(
            text.contains("\"peer, patched\",\"say \"\"mis\"\"\""),
            "{text}"
        );
        let read = parse_error_csv(&text, Path::new("e.csv")).unwrap();
        assert_eq!(read.len(), 2);
        assert_eq!(read[0].renderer, "peer, patched");
        assert_eq!(read[0].estimator, "say \"mis\"");
        assert_eq!(read[1].seconds, 0.012346);
        assert_eq!(read[1].relmse, 1.5e-7);
    }

    #[test]
    fn bad_error_rows_name_their_line_and_field() {
        let path = Path::new("peer.csv");
        let error = |text: &str| parse_error_csv(text, path).unwrap_err().to_string();
        let header = "renderer,estimator,spp,seconds,rmse,relmse\n";
        for (rows, says) in [
            ("a,b,0,1,1,1\n", "line 2: spp '0' is not a positive integer"),
            (
                "a,b,1.5,1,1,1\n",
                "line 2: spp '1.5' is not a positive integer",
            ),
            (
                "a,b,1,1,1,1\n\na,b,1,1,-1,1\n",
                "line 4: rmse '-1' is not a finite",
            ),
            ("\n\r\n\na,b,1,1,1,1,1\n", "line 5: 7 fields, expected 6"),
            (
                "a,b,1,1,1,1\r\n\r\na,b,x,1,1,1\r\n",
                "line 4: spp 'x' is not",
            ),
            ("a,b,1,1,1,inf\n", "line 2: relmse 'inf' is not a finite"),
            ("a,b,1,NaN,1,1\n", "line 2: seconds 'NaN' is not a finite"),
            (",b,1,1,1,1\n", "line 2: empty renderer name"),
            ("a,b,1,1,1,1,1\n", "line 2: 7 fields, expected 6"),
        ] {
            let message = error(&format!("{header}{rows}"));
            assert!(message.contains(says), "{rows:?}: {message}");
            assert!(message.starts_with("peer.csv"), "{message}");
        }
        let header = error("\n\nrenderer,spp\n");
        assert!(
            header.contains("line 3: header 'renderer,spp', expected"),
            "{header}"
        );
        // spaces around fields and blank lines are allowed
        let rows = parse_error_csv(
            "\n renderer , estimator,spp,seconds,rmse,relmse\n\n a , b , 2 , 1.5 , 0 , 0 \n",
            path,
        )
        .unwrap();
        assert_eq!((rows[0].renderer.as_str(), rows[0].spp), ("a", 2));
    }
}
