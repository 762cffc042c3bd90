//! series.csv: one row per recorded time (the columns of docs/reference.md, section
//! series.csv).

use super::Column;
use super::csv::write_row;
use std::io::{self, Write};
use stickslip_core::sim::Observables;

/// File name.
pub const FILE: &str = "series.csv";

/// Columns in file order.
pub const COLUMNS: [Column; 8] = [
    Column {
        name: "t",
        unit: "s",
        meaning: "time",
    },
    Column {
        name: "X",
        unit: "m",
        meaning: "stamp position",
    },
    Column {
        name: "V",
        unit: "m/s",
        meaning: "stamp velocity",
    },
    Column {
        name: "F",
        unit: "N",
        meaning: "friction force 2π∫τ r dr (Eq. 16)",
    },
    Column {
        name: "phi_mean",
        unit: "–",
        meaning: "area-weighted mean order parameter",
    },
    Column {
        name: "eps_mean",
        unit: "–",
        meaning: "area-weighted mean elastic strain",
    },
    Column {
        name: "melted_fraction",
        unit: "–",
        meaning: "area fraction with φ below the melting threshold now (the accurate scheme melts and regrows a node at once, so it stays near 0 there; events.csv has the extent of each melting)",
    },
    Column {
        name: "F_1d",
        unit: "N",
        meaning: "friction force from 2∫q dx (Eq. 16, the MDR check)",
    },
];

/// series.csv as columns.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series {
    /// Time, s.
    pub t_s: Vec<f64>,
    /// Stamp position, m.
    pub x_m: Vec<f64>,
    /// Stamp velocity, m/s.
    pub v_m_per_s: Vec<f64>,
    /// Friction force 2π∫τ r dr, N.
    pub f_n: Vec<f64>,
    /// Area-weighted mean φ.
    pub phi_mean: Vec<f64>,
    /// Area-weighted mean ε.
    pub eps_mean: Vec<f64>,
    /// Melted area fraction.
    pub melted_fraction: Vec<f64>,
    /// Friction force 2∫q dx, N.
    pub f_1d_n: Vec<f64>,
}

/// One row in file order.
fn row(o: &Observables) -> [f64; 8] {
    [
        o.t_s,
        o.x_m,
        o.v_m_per_s,
        o.f_n,
        o.phi_mean,
        o.eps_mean,
        o.melted_fraction,
        o.f_1d_n,
    ]
}

impl Series {
    /// Appends one row.
    pub fn push(&mut self, o: &Observables) {
        for (col, v) in self.columns_mut().into_iter().zip(row(o)) {
            col.push(v);
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

    fn columns_mut(&mut self) -> [&mut Vec<f64>; 8] {
        [
            &mut self.t_s,
            &mut self.x_m,
            &mut self.v_m_per_s,
            &mut self.f_n,
            &mut self.phi_mean,
            &mut self.eps_mean,
            &mut self.melted_fraction,
            &mut self.f_1d_n,
        ]
    }

    /// The columns in file order, by name.
    #[must_use]
    pub fn columns(&self) -> [(&'static str, &[f64]); 8] {
        [
            (COLUMNS[0].name, &self.t_s),
            (COLUMNS[1].name, &self.x_m),
            (COLUMNS[2].name, &self.v_m_per_s),
            (COLUMNS[3].name, &self.f_n),
            (COLUMNS[4].name, &self.phi_mean),
            (COLUMNS[5].name, &self.eps_mean),
            (COLUMNS[6].name, &self.melted_fraction),
            (COLUMNS[7].name, &self.f_1d_n),
        ]
    }

    /// The columns in file order, by name, moved out (no copy).
    #[must_use]
    pub fn into_columns(self) -> Vec<(&'static str, Vec<f64>)> {
        let Self {
            t_s,
            x_m,
            v_m_per_s,
            f_n,
            phi_mean,
            eps_mean,
            melted_fraction,
            f_1d_n,
        } = self;
        COLUMNS
            .iter()
            .map(|c| c.name)
            .zip([
                t_s,
                x_m,
                v_m_per_s,
                f_n,
                phi_mean,
                eps_mean,
                melted_fraction,
                f_1d_n,
            ])
            .collect()
    }

    /// The column called `name`.
    #[must_use]
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns()
            .into_iter()
            .find(|(n, _)| *n == name)
            .map(|(_, c)| c)
    }

    /// Writes the header line.
    ///
    /// # Errors
    /// Those of the writer.
    pub fn write_header(w: &mut impl Write) -> io::Result<()> {
        let names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
        writeln!(w, "{}", names.join(","))
    }

    /// Writes one row of observables.
    ///
    /// # Errors
    /// Those of the writer.
    pub fn write_observables(w: &mut impl Write, o: &Observables) -> io::Result<()> {
        write_row(w, &row(o))
    }

    /// Index range of the rows with t in [t0, t1].
    #[must_use]
    pub fn window(&self, t0: f64, t1: f64) -> std::ops::Range<usize> {
        let a = self.t_s.partition_point(|&t| t < t0);
        let b = self.t_s.partition_point(|&t| t <= t1);
        a..b.max(a)
    }
}

super::table::columnar_table!(Series);
