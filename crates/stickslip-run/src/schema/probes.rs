//! probes.csv: `t`, then `phi@<radius>` per probe (φ interpolated between nodes), then
//! `t_melt@<radius>` per probe (when the probe's nearest node last melted, s; −1 before its
//! first melting). The accurate scheme's melting is instantaneous — φ touches the threshold
//! and recovers within a step — so sampled φ rarely shows it; `t_melt` dates it.

use super::csv::{NumericCsv, write_row};
use super::table::Table;
use super::{Column, SchemaError};
use std::io::{self, Write};

/// File name.
pub const FILE: &str = "probes.csv";

/// The time column.
pub const TIME: Column = Column {
    name: "t",
    unit: "s",
    meaning: "time",
};
/// A `phi@<radius>` column.
pub const PHI: Column = Column {
    name: "phi@<r>",
    unit: "–",
    meaning: "φ at radius r (m, written as {:e}), interpolated linearly between nodes",
};
/// A `t_melt@<radius>` column.
pub const T_MELT: Column = Column {
    name: "t_melt@<r>",
    unit: "s",
    meaning: "when the node nearest to r last melted (−1 before its first melting)",
};

/// The header for `probe_radii_m`: names with their column specs.
#[must_use]
pub fn header(probe_radii_m: &[f64]) -> Vec<(String, Column)> {
    let mut out = vec![(TIME.name.to_string(), TIME)];
    out.extend(probe_radii_m.iter().map(|r| (format!("phi@{r:e}"), PHI)));
    out.extend(
        probe_radii_m
            .iter()
            .map(|r| (format!("t_melt@{r:e}"), T_MELT)),
    );
    out
}

/// φ at a probe radius, interpolated linearly between the two neighbouring nodes (exact at a
/// node; the last node's value beyond the last node; the only node's value for one node).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbePoint {
    /// Radius as given, m.
    pub radius_m: f64,
    lower: usize,
    weight_upper: f64,
}

impl ProbePoint {
    /// Locates `radius_m` on the node radii `radii_m` (ascending, non-empty).
    pub fn new(radius_m: f64, radii_m: &[f64]) -> Self {
        let last = radii_m.len().saturating_sub(1);
        let upper = radii_m.partition_point(|&r| r <= radius_m);
        if upper == 0 || upper > last {
            return Self {
                radius_m,
                lower: upper.saturating_sub(1).min(last),
                weight_upper: 0.0,
            };
        }
        let (r0, r1) = (radii_m[upper - 1], radii_m[upper]);
        Self {
            radius_m,
            lower: upper - 1,
            weight_upper: (radius_m - r0) / (r1 - r0),
        }
    }

    /// The node nearest to the probe.
    pub fn nearest(&self) -> usize {
        if self.weight_upper > 0.5 {
            self.lower + 1
        } else {
            self.lower
        }
    }

    /// φ at the probe.
    pub fn value(&self, phi: &[f64]) -> f64 {
        let p0 = phi.get(self.lower).copied().unwrap_or(f64::NAN);
        if self.weight_upper == 0.0 {
            return p0;
        }
        let p1 = phi.get(self.lower + 1).copied().unwrap_or(p0);
        p0 + self.weight_upper * (p1 - p0)
    }
}

/// probes.csv as columns.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Probes {
    /// Probe radii, m, in column order.
    pub radii_m: Vec<f64>,
    /// Time, s.
    pub t_s: Vec<f64>,
    /// φ per probe (outer index: probe).
    pub phi: Vec<Vec<f64>>,
    /// Last melting time per probe, s (−1 before the first).
    pub t_melt_s: Vec<Vec<f64>>,
}

impl Probes {
    /// An empty table for `radii_m`.
    #[must_use]
    pub fn new(radii_m: &[f64]) -> Self {
        Self {
            radii_m: radii_m.to_vec(),
            t_s: Vec::new(),
            phi: vec![Vec::new(); radii_m.len()],
            t_melt_s: vec![Vec::new(); radii_m.len()],
        }
    }

    /// Appends one row: `row` = t, φ per probe, t_melt per probe (as [`ProbeRow::values`]).
    pub fn push(&mut self, row: &[f64]) {
        let n = self.radii_m.len();
        self.t_s.push(row[0]);
        for j in 0..n {
            self.phi[j].push(row[1 + j]);
            self.t_melt_s[j].push(row[1 + n + j]);
        }
    }

    /// Rows.
    #[must_use]
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// No rows.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// The columns in file order, by header name.
    #[must_use]
    pub fn columns(&self) -> Vec<(String, &[f64])> {
        let names = header(&self.radii_m);
        let cols = std::iter::once(&self.t_s)
            .chain(&self.phi)
            .chain(&self.t_melt_s);
        names
            .into_iter()
            .zip(cols)
            .map(|((name, _), c)| (name, c.as_slice()))
            .collect()
    }

    /// The columns in file order, by header name, moved out (no copy).
    #[must_use]
    pub fn into_columns(self) -> Vec<(String, Vec<f64>)> {
        let names = header(&self.radii_m);
        let cols = std::iter::once(self.t_s)
            .chain(self.phi)
            .chain(self.t_melt_s);
        names.into_iter().map(|(n, _)| n).zip(cols).collect()
    }

    /// The φ column of the probe at radius `r_m` (exact match of the given radius).
    #[must_use]
    pub fn phi_at(&self, r_m: f64) -> Option<&[f64]> {
        let j = self.radii_m.iter().position(|&r| r == r_m)?;
        Some(&self.phi[j])
    }

    /// Writes the header line.
    ///
    /// # Errors
    /// Those of the writer.
    pub fn write_header(w: &mut impl Write, probe_radii_m: &[f64]) -> io::Result<()> {
        let names: Vec<String> = header(probe_radii_m).into_iter().map(|(n, _)| n).collect();
        writeln!(w, "{}", names.join(","))
    }

    /// Writes one row (t, φ per probe, t_melt per probe).
    ///
    /// # Errors
    /// Those of the writer.
    pub fn write_values(w: &mut impl Write, row: &[f64]) -> io::Result<()> {
        write_row(w, row)
    }
}

impl Table for Probes {
    const FILE: &'static str = FILE;

    fn write_to<W: Write>(&self, w: &mut W) -> io::Result<()> {
        Self::write_header(w, &self.radii_m)?;
        let cols = self.columns();
        for i in 0..self.len() {
            let values: Vec<f64> = cols.iter().map(|(_, c)| c[i]).collect();
            write_row(w, &values)?;
        }
        Ok(())
    }

    /// The radii from the `phi@<r>` names; the header must be `t, phi@…, t_melt@…`.
    fn from_csv(csv: NumericCsv) -> Result<Self, SchemaError> {
        csv.expect_header(&[TIME.name], FILE)?;
        let n = (csv.header.len() - 1) / 2;
        let radii_m = csv.header[1..=n]
            .iter()
            .map(|h| {
                h.strip_prefix("phi@")
                    .and_then(|r| r.parse::<f64>().ok())
                    .ok_or_else(|| {
                        SchemaError::new(FILE, Some(1), format!("{h:?} is not phi@<radius>"))
                    })
            })
            .collect::<Result<Vec<f64>, _>>()?;
        let expected: Vec<String> = header(&radii_m).into_iter().map(|(n, _)| n).collect();
        if csv.header != expected {
            return Err(SchemaError::new(
                FILE,
                Some(1),
                format!("header {:?}, expected {expected:?}", csv.header),
            ));
        }
        let mut p = Self::new(&radii_m);
        for row in &csv.rows {
            p.push(row);
        }
        Ok(p)
    }
}

/// The probes of a run located on its grid, turning a state into a row.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeRow {
    points: Vec<ProbePoint>,
    values: Vec<f64>,
}

impl ProbeRow {
    /// Probes at `probe_radii_m` on nodes `node_radii_m`.
    #[must_use]
    pub fn new(probe_radii_m: &[f64], node_radii_m: &[f64]) -> Self {
        Self {
            points: probe_radii_m
                .iter()
                .map(|&r| ProbePoint::new(r, node_radii_m))
                .collect(),
            values: Vec::with_capacity(2 * probe_radii_m.len() + 1),
        }
    }

    /// The row at time `t_s` from node values `phi` and last melting times `last_melt_s`:
    /// t, φ per probe, t_melt per probe.
    pub fn values(&mut self, t_s: f64, phi: &[f64], last_melt_s: &[f64]) -> &[f64] {
        self.values.clear();
        self.values.push(t_s);
        self.values.extend(self.points.iter().map(|p| p.value(phi)));
        self.values.extend(
            self.points
                .iter()
                .map(|p| last_melt_s.get(p.nearest()).copied().unwrap_or(-1.0)),
        );
        &self.values
    }
}
