//! The CSV dialect of the output files: a header row, then comma-separated numbers written
//! with Rust's `{:e}` formatting, the shortest text that parses back to the same f64 (`1e-8`,
//! `1.2540123e-3`, `0e0`, `-0e0`), so identical runs give identical bytes and a file read back
//! gives the same bits. An empty cell is "no value" (read as NaN).

use super::SchemaError;
use std::io::{self, Write};

/// Writes `x` in shortest round-trip scientific notation (`{:e}`).
///
/// # Errors
/// Those of the writer.
pub fn write_num(w: &mut impl Write, x: f64) -> io::Result<()> {
    write!(w, "{x:e}")
}

/// Comma-separated numbers without the newline.
///
/// # Errors
/// Those of the writer.
pub fn write_cells(w: &mut impl Write, values: &[f64]) -> io::Result<()> {
    for (i, &v) in values.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        write_num(w, v)?;
    }
    Ok(())
}

/// Comma-separated numbers and a newline.
///
/// # Errors
/// Those of the writer.
pub fn write_row(w: &mut impl Write, values: &[f64]) -> io::Result<()> {
    write_cells(w, values)?;
    w.write_all(b"\n")
}

/// `,` then the value, or only `,` for none.
///
/// # Errors
/// Those of the writer.
pub fn write_opt(w: &mut impl Write, v: Option<f64>) -> io::Result<()> {
    w.write_all(b",")?;
    match v {
        Some(x) => write_num(w, x),
        None => Ok(()),
    }
}

/// A parsed numeric CSV file: header names and rows (empty cells as NaN).
#[derive(Debug, Clone, PartialEq)]
pub struct NumericCsv {
    /// Column names.
    pub header: Vec<String>,
    /// Rows, each as long as the header.
    pub rows: Vec<Vec<f64>>,
}

impl NumericCsv {
    /// Parses `text` (the contents of `file`, named in errors).
    ///
    /// # Errors
    /// [`SchemaError`] naming the file, line and cell of the first problem.
    pub fn parse(text: &str, file: &str) -> Result<Self, SchemaError> {
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .ok_or_else(|| SchemaError::new(file, None, "empty file (no header)"))?
            .split(',')
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for (i, line) in lines.enumerate() {
            let lineno = i + 2;
            let cells: Vec<&str> = line.split(',').collect();
            if cells.len() != header.len() {
                return Err(SchemaError::new(
                    file,
                    Some(lineno),
                    format!("{} cells, the header has {}", cells.len(), header.len()),
                ));
            }
            let row = cells
                .iter()
                .map(|c| {
                    if c.is_empty() {
                        Ok(f64::NAN)
                    } else {
                        c.parse::<f64>().map_err(|_| {
                            SchemaError::new(file, Some(lineno), format!("{c:?} is not a number"))
                        })
                    }
                })
                .collect::<Result<Vec<f64>, _>>()?;
            rows.push(row);
        }
        Ok(Self { header, rows })
    }

    /// Index of the column called `name`.
    ///
    /// # Errors
    /// [`SchemaError`] naming the file and the missing column.
    pub fn index(&self, name: &str, file: &str) -> Result<usize, SchemaError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| SchemaError::new(file, Some(1), format!("no column {name:?}")))
    }

    /// The column called `name`.
    ///
    /// # Errors
    /// As [`NumericCsv::index`].
    pub fn column(&self, name: &str, file: &str) -> Result<Vec<f64>, SchemaError> {
        let i = self.index(name, file)?;
        Ok(self.rows.iter().map(|r| r[i]).collect())
    }

    /// Checks that the header starts with `expected`.
    ///
    /// # Errors
    /// [`SchemaError`] showing both headers.
    pub fn expect_header(&self, expected: &[&str], file: &str) -> Result<(), SchemaError> {
        let ok = self.header.len() >= expected.len()
            && self.header.iter().zip(expected).all(|(h, e)| h == e);
        if ok {
            Ok(())
        } else {
            Err(SchemaError::new(
                file,
                Some(1),
                format!(
                    "header {:?}, expected it to start with {expected:?}",
                    self.header
                ),
            ))
        }
    }
}

/// An optional cell: NaN (empty) is none.
#[must_use]
pub fn opt(v: f64) -> Option<f64> {
    (!v.is_nan()).then_some(v)
}
