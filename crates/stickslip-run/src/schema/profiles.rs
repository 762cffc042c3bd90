//! profiles.csv: one block of rows (one per node) per recorded profile time.

use super::Column;
use super::csv::write_row;
use std::io::{self, Write};
use stickslip_core::sim::SimState;

/// File name.
pub const FILE: &str = "profiles.csv";

/// Columns in file order.
pub const COLUMNS: [Column; 7] = [
    Column {
        name: "t",
        unit: "s",
        meaning: "time of the profile",
    },
    Column {
        name: "r",
        unit: "m",
        meaning: "node radius r_i = i·a0/N",
    },
    Column {
        name: "phi",
        unit: "–",
        meaning: "order parameter φ",
    },
    Column {
        name: "eps",
        unit: "–",
        meaning: "elastic strain ε = (u0 − u3D)/h0",
    },
    Column {
        name: "tau",
        unit: "Pa",
        meaning: "shear stress τ = aφ²ε",
    },
    Column {
        name: "u0",
        unit: "m",
        meaning: "stamp-surface displacement since the node last re-solidified",
    },
    Column {
        name: "u3d",
        unit: "m",
        meaning: "substrate displacement",
    },
];

/// profiles.csv as columns (profiles one after another).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Profiles {
    /// Time of the profile, s.
    pub t_s: Vec<f64>,
    /// Node radius, m.
    pub r_m: Vec<f64>,
    /// φ.
    pub phi: Vec<f64>,
    /// ε.
    pub eps: Vec<f64>,
    /// τ, Pa.
    pub tau_pa: Vec<f64>,
    /// u0, m.
    pub u0_m: Vec<f64>,
    /// u3D, m.
    pub u3d_m: Vec<f64>,
}

/// One profile: every node at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfileView<'a> {
    /// Time of the profile, s.
    pub t_s: f64,
    /// Node radii, m.
    pub r_m: &'a [f64],
    /// φ.
    pub phi: &'a [f64],
    /// ε.
    pub eps: &'a [f64],
    /// τ, Pa.
    pub tau_pa: &'a [f64],
    /// u0, m.
    pub u0_m: &'a [f64],
    /// u3D, m.
    pub u3d_m: &'a [f64],
}

/// The rows of one profile: r, φ, ε, τ, u0, u3D for every node at time `t_s`.
fn rows<'a>(t_s: f64, radii_m: &'a [f64], s: &'a SimState) -> impl Iterator<Item = [f64; 7]> + 'a {
    radii_m.iter().enumerate().map(move |(i, &r)| {
        let at = |v: &[f64]| v.get(i).copied().unwrap_or(f64::NAN);
        [
            t_s,
            r,
            at(&s.physical.phi),
            at(&s.physical.eps),
            at(&s.physical.tau_pa),
            at(&s.physical.u0_m),
            at(&s.physical.u3d_m),
        ]
    })
}

impl Profiles {
    fn columns_mut(&mut self) -> [&mut Vec<f64>; 7] {
        [
            &mut self.t_s,
            &mut self.r_m,
            &mut self.phi,
            &mut self.eps,
            &mut self.tau_pa,
            &mut self.u0_m,
            &mut self.u3d_m,
        ]
    }

    /// The columns in file order, by name.
    #[must_use]
    pub fn columns(&self) -> [(&'static str, &[f64]); 7] {
        [
            (COLUMNS[0].name, &self.t_s),
            (COLUMNS[1].name, &self.r_m),
            (COLUMNS[2].name, &self.phi),
            (COLUMNS[3].name, &self.eps),
            (COLUMNS[4].name, &self.tau_pa),
            (COLUMNS[5].name, &self.u0_m),
            (COLUMNS[6].name, &self.u3d_m),
        ]
    }

    /// The columns in file order, by name, moved out (no copy).
    #[must_use]
    pub fn into_columns(self) -> Vec<(&'static str, Vec<f64>)> {
        let Self {
            t_s,
            r_m,
            phi,
            eps,
            tau_pa,
            u0_m,
            u3d_m,
        } = self;
        COLUMNS
            .iter()
            .map(|c| c.name)
            .zip([t_s, r_m, phi, eps, tau_pa, u0_m, u3d_m])
            .collect()
    }

    /// Appends the profile of `state` at `t_s`.
    pub fn push(&mut self, t_s: f64, radii_m: &[f64], state: &SimState) {
        for row in rows(t_s, radii_m, state) {
            for (col, v) in self.columns_mut().into_iter().zip(row) {
                col.push(v);
            }
        }
    }

    /// Rows (nodes × profiles).
    #[must_use]
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// No rows.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// The distinct profile times, s, in order.
    #[must_use]
    pub fn times_s(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        for &t in &self.t_s {
            if out.last() != Some(&t) {
                out.push(t);
            }
        }
        out
    }

    /// Row range of the profile at time `t_s` (exact), empty if there is none.
    #[must_use]
    pub fn rows_at(&self, t_s: f64) -> std::ops::Range<usize> {
        let a = self
            .t_s
            .iter()
            .position(|&t| t == t_s)
            .unwrap_or(self.len());
        let b = self.t_s[a..]
            .iter()
            .position(|&t| t != t_s)
            .map_or(self.len(), |p| a + p);
        a..b
    }

    /// The profiles one by one, in file order.
    #[must_use]
    pub fn blocks(&self) -> Vec<ProfileView<'_>> {
        let mut out = Vec::new();
        let mut a = 0;
        while a < self.len() {
            let t = self.t_s[a];
            let b = self.t_s[a..]
                .iter()
                .position(|&x| x != t)
                .map_or(self.len(), |p| a + p);
            out.push(ProfileView {
                t_s: t,
                r_m: &self.r_m[a..b],
                phi: &self.phi[a..b],
                eps: &self.eps[a..b],
                tau_pa: &self.tau_pa[a..b],
                u0_m: &self.u0_m[a..b],
                u3d_m: &self.u3d_m[a..b],
            });
            a = b;
        }
        out
    }

    /// The profile recorded nearest to `t_s`, if any.
    #[must_use]
    pub fn nearest(&self, t_s: f64) -> Option<ProfileView<'_>> {
        self.blocks()
            .into_iter()
            .min_by(|a, b| (a.t_s - t_s).abs().total_cmp(&(b.t_s - t_s).abs()))
    }

    /// Writes the header line.
    ///
    /// # Errors
    /// Those of the writer.
    pub fn write_header(w: &mut impl Write) -> io::Result<()> {
        let names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
        writeln!(w, "{}", names.join(","))
    }

    /// Writes the rows of one profile.
    ///
    /// # Errors
    /// Those of the writer.
    pub fn write_profile(
        w: &mut impl Write,
        t_s: f64,
        radii_m: &[f64],
        state: &SimState,
    ) -> io::Result<()> {
        for row in rows(t_s, radii_m, state) {
            write_row(w, &row)?;
        }
        Ok(())
    }
}

super::table::columnar_table!(Profiles);
