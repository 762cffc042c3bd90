//! The CSV output files as one trait: a [`Table`] names its file, writes its header and rows,
//! and builds itself from the file's parsed text; its CSV text, its parsing and its reading
//! from a run's directory come with the trait.

use super::SchemaError;
use super::csv::{NumericCsv, write_row};
use std::io::{self, Write};
use std::path::Path;

/// A CSV output file of a run (series, events, slips, profiles, probes).
pub trait Table: Sized + Default {
    /// The file's name in a run's directory.
    const FILE: &'static str;
    /// Whether a directory without the file reads as an empty table (a file added in a later
    /// version, absent from directories written before it).
    const OPTIONAL: bool = false;

    /// Writes the header line and every row.
    ///
    /// # Errors
    /// Those of the writer.
    fn write_to<W: Write>(&self, w: &mut W) -> io::Result<()>;

    /// The table from the file's parsed text, its header checked.
    ///
    /// # Errors
    /// [`SchemaError`] naming the file, the line and what is wrong.
    fn from_csv(csv: NumericCsv) -> Result<Self, SchemaError>;

    /// The file's text.
    #[must_use]
    fn to_csv(&self) -> String {
        let mut out = Vec::new();
        // Writing to a Vec cannot fail.
        let _ = self.write_to(&mut out);
        String::from_utf8(out).unwrap_or_default()
    }

    /// Parses the file's text.
    ///
    /// # Errors
    /// [`SchemaError`] if a column is missing or a cell is not a number.
    fn parse(text: &str) -> Result<Self, SchemaError> {
        Self::from_csv(NumericCsv::parse(text, Self::FILE)?)
    }

    /// Reads `dir/FILE` (an optional file that is absent reads as an empty table).
    ///
    /// # Errors
    /// As [`Table::parse`], or if the file cannot be read.
    fn read(dir: &Path) -> Result<Self, SchemaError> {
        if Self::OPTIONAL && !dir.join(Self::FILE).exists() {
            return Ok(Self::default());
        }
        Self::parse(&super::read_text(dir, Self::FILE)?)
    }
}

/// Writes a table held as columns of equal length: the header `names`, then one row per
/// index.
///
/// # Errors
/// Those of the writer.
pub(super) fn write_columns<W: Write, S: AsRef<str>>(
    w: &mut W,
    names: &[S],
    columns: &[&[f64]],
) -> io::Result<()> {
    let names: Vec<&str> = names.iter().map(AsRef::as_ref).collect();
    writeln!(w, "{}", names.join(","))?;
    let rows = columns.first().map_or(0, |c| c.len());
    let mut values = vec![0.0; columns.len()];
    for i in 0..rows {
        for (v, c) in values.iter_mut().zip(columns) {
            *v = c[i];
        }
        write_row(w, &values)?;
    }
    Ok(())
}

/// The columns of `csv` into `columns` in file order, after checking that its header is
/// `names` (`file` for the error).
///
/// # Errors
/// [`SchemaError`] if the header differs.
pub(super) fn read_columns(
    csv: &NumericCsv,
    names: &[&str],
    columns: &mut [&mut Vec<f64>],
    file: &str,
) -> Result<(), SchemaError> {
    csv.expect_header(names, file)?;
    for (i, col) in columns.iter_mut().enumerate() {
        **col = csv.rows.iter().map(|r| r[i]).collect();
    }
    Ok(())
}

/// The [`Table`] of a struct held as equal-length columns (series, profiles): its module's
/// `FILE` and `COLUMNS` (the header, in order), and the struct's `columns()` (name, data) and
/// `columns_mut()` in the same order. Written once here, so the columnar files cannot read
/// or write differently.
macro_rules! columnar_table {
    ($table:ty) => {
        impl $crate::schema::table::Table for $table {
            const FILE: &'static str = FILE;

            fn write_to<W: std::io::Write>(&self, w: &mut W) -> std::io::Result<()> {
                let names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
                $crate::schema::table::write_columns(w, &names, &self.columns().map(|(_, c)| c))
            }

            fn from_csv(
                csv: $crate::schema::csv::NumericCsv,
            ) -> Result<Self, $crate::schema::SchemaError> {
                let names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
                let mut table = Self::default();
                $crate::schema::table::read_columns(&csv, &names, &mut table.columns_mut(), FILE)?;
                Ok(table)
            }
        }
    };
}
pub(super) use columnar_table;
