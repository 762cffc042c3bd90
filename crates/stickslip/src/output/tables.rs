//! The CSV tables of a run: series.csv, events.csv, profiles.csv and probes.csv (columns as in
//! INTERFACE.md, plus additions at the end of a row).

use super::{AtomicFile, StreamPosition, write_num};
use std::io::{self, Write};
use std::path::Path;
use stickslip_core::sim::events::MeltingEvent;
use stickslip_core::sim::{Observables, SimState};

/// Header of series.csv: the INTERFACE.md columns, F_1d last.
pub const SERIES_HEADER: &str = "t,X,V,F,phi_mean,eps_mean,melted_fraction,F_1d";
/// Header of events.csv: the INTERFACE.md columns, then r_min, t_center, t_end,
/// max_melted_fraction (t_center and t_end empty when they did not happen).
pub const EVENTS_HEADER: &str =
    "k,t_onset,r_first,x_onset,f_peak,r_min,t_center,t_end,max_melted_fraction";
/// Header of profiles.csv.
pub const PROFILES_HEADER: &str = "t,r,phi,eps,tau,u0,u3d";

/// Comma-separated numbers and a newline.
fn write_row(w: &mut impl Write, values: &[f64]) -> io::Result<()> {
    write_row_open(w, values)?;
    w.write_all(b"\n")
}

/// series.csv, streamed row by row.
#[derive(Debug)]
pub struct SeriesWriter {
    file: AtomicFile,
    rows: u64,
}

impl SeriesWriter {
    /// Creates the file in `dir` and writes the header.
    ///
    /// # Errors
    /// If the file cannot be created or written.
    pub fn create(dir: &Path) -> io::Result<Self> {
        let mut file = AtomicFile::create(dir, "series.csv")?;
        writeln!(file, "{SERIES_HEADER}")?;
        Ok(Self { file, rows: 0 })
    }

    /// Continues the file of an interrupted run at `at`, after `rows` rows (see
    /// [`AtomicFile::reopen`]).
    ///
    /// # Errors
    /// Those of [`AtomicFile::reopen`].
    pub fn reopen(dir: &Path, at: StreamPosition, rows: u64) -> io::Result<Self> {
        Ok(Self {
            file: AtomicFile::reopen(dir, "series.csv", at)?,
            rows,
        })
    }

    /// Flushes and syncs the file; how far it has got (see [`AtomicFile::sync_position`]).
    ///
    /// # Errors
    /// Those of the file.
    pub fn sync_position(&mut self) -> io::Result<StreamPosition> {
        self.file.sync_position()
    }

    /// One row: t (s), X (m), V (m/s), F (N), φ mean, ε mean, melted fraction, F_1d (N).
    ///
    /// # Errors
    /// Those of the file.
    pub fn row(&mut self, o: &Observables) -> io::Result<()> {
        self.rows += 1;
        write_row(
            &mut self.file,
            &[
                o.t_s,
                o.x_m,
                o.v_m_per_s,
                o.f_n,
                o.phi_mean,
                o.eps_mean,
                o.melted_fraction,
                o.f_1d_n,
            ],
        )
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Renames the file into place.
    ///
    /// # Errors
    /// Those of [`AtomicFile::commit`].
    pub fn commit(self) -> io::Result<()> {
        self.file.commit()
    }
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

/// probes.csv, streamed row by row: `t`, then `phi@<radius>` per probe (interpolated between
/// nodes), then `t_melt@<radius>` per probe: when the probe's nearest node last melted, s (−1
/// before its first melting). The accurate scheme's melting is instantaneous — φ touches the
/// threshold and recovers within a step — so sampled φ rarely shows it; `t_melt` dates it.
#[derive(Debug)]
pub struct ProbeWriter {
    file: AtomicFile,
    probes: Vec<ProbePoint>,
    row: Vec<f64>,
}

impl ProbeWriter {
    /// Creates the file and writes the header `t,phi@<r1>,…,t_melt@<r1>,…` (radii in `{:e}`).
    ///
    /// # Errors
    /// If the file cannot be created or written.
    pub fn create(dir: &Path, probe_radii_m: &[f64], node_radii_m: &[f64]) -> io::Result<Self> {
        let mut file = AtomicFile::create(dir, "probes.csv")?;
        write!(file, "t")?;
        for r in probe_radii_m {
            write!(file, ",phi@{r:e}")?;
        }
        for r in probe_radii_m {
            write!(file, ",t_melt@{r:e}")?;
        }
        writeln!(file)?;
        Ok(Self::with_file(file, probe_radii_m, node_radii_m))
    }

    /// Continues the file of an interrupted run at `at` (see [`AtomicFile::reopen`]).
    ///
    /// # Errors
    /// Those of [`AtomicFile::reopen`].
    pub fn reopen(
        dir: &Path,
        at: StreamPosition,
        probe_radii_m: &[f64],
        node_radii_m: &[f64],
    ) -> io::Result<Self> {
        let file = AtomicFile::reopen(dir, "probes.csv", at)?;
        Ok(Self::with_file(file, probe_radii_m, node_radii_m))
    }

    fn with_file(file: AtomicFile, probe_radii_m: &[f64], node_radii_m: &[f64]) -> Self {
        Self {
            file,
            probes: probe_radii_m
                .iter()
                .map(|&r| ProbePoint::new(r, node_radii_m))
                .collect(),
            row: Vec::with_capacity(2 * probe_radii_m.len() + 1),
        }
    }

    /// Flushes and syncs the file; how far it has got (see [`AtomicFile::sync_position`]).
    ///
    /// # Errors
    /// Those of the file.
    pub fn sync_position(&mut self) -> io::Result<StreamPosition> {
        self.file.sync_position()
    }

    /// One row at time `t_s` from the node values `phi` and last melting times `last_melt_s`.
    ///
    /// # Errors
    /// Those of the file.
    pub fn row(&mut self, t_s: f64, phi: &[f64], last_melt_s: &[f64]) -> io::Result<()> {
        self.row.clear();
        self.row.push(t_s);
        self.row.extend(self.probes.iter().map(|p| p.value(phi)));
        self.row.extend(
            self.probes
                .iter()
                .map(|p| last_melt_s.get(p.nearest()).copied().unwrap_or(-1.0)),
        );
        write_row(&mut self.file, &self.row)
    }

    /// Renames the file into place.
    ///
    /// # Errors
    /// Those of [`AtomicFile::commit`].
    pub fn commit(self) -> io::Result<()> {
        self.file.commit()
    }
}

/// profiles.csv, one block of rows per recorded profile.
#[derive(Debug)]
pub struct ProfileWriter {
    file: AtomicFile,
}

impl ProfileWriter {
    /// Creates the file and writes the header.
    ///
    /// # Errors
    /// If the file cannot be created or written.
    pub fn create(dir: &Path) -> io::Result<Self> {
        let mut file = AtomicFile::create(dir, "profiles.csv")?;
        writeln!(file, "{PROFILES_HEADER}")?;
        Ok(Self { file })
    }

    /// Continues the file of an interrupted run at `at` (see [`AtomicFile::reopen`]).
    ///
    /// # Errors
    /// Those of [`AtomicFile::reopen`].
    pub fn reopen(dir: &Path, at: StreamPosition) -> io::Result<Self> {
        Ok(Self {
            file: AtomicFile::reopen(dir, "profiles.csv", at)?,
        })
    }

    /// Flushes and syncs the file; how far it has got (see [`AtomicFile::sync_position`]).
    ///
    /// # Errors
    /// Those of the file.
    pub fn sync_position(&mut self) -> io::Result<StreamPosition> {
        self.file.sync_position()
    }

    /// One row per node: t (s), r (m), φ, ε, τ (Pa), u0 (m), u3D (m).
    ///
    /// # Errors
    /// Those of the file.
    pub fn profile(&mut self, t_s: f64, radii_m: &[f64], s: &SimState) -> io::Result<()> {
        for (i, &r) in radii_m.iter().enumerate() {
            let at = |v: &[f64]| v.get(i).copied().unwrap_or(f64::NAN);
            write_row(
                &mut self.file,
                &[
                    t_s,
                    r,
                    at(&s.phi),
                    at(&s.eps),
                    at(&s.tau_pa),
                    at(&s.u0_m),
                    at(&s.u3d_m),
                ],
            )?;
        }
        Ok(())
    }

    /// Renames the file into place.
    ///
    /// # Errors
    /// Those of [`AtomicFile::commit`].
    pub fn commit(self) -> io::Result<()> {
        self.file.commit()
    }
}

/// Writes events.csv (atomically) from the merged melting events.
///
/// # Errors
/// If the file cannot be written.
pub fn write_events(dir: &Path, events: &[MeltingEvent]) -> io::Result<()> {
    let mut f = AtomicFile::create(dir, "events.csv")?;
    writeln!(f, "{EVENTS_HEADER}")?;
    for e in events {
        write!(f, "{},", e.k)?;
        write_row_open(
            &mut f,
            &[e.t_onset_s, e.r_first_m, e.x_onset_m, e.f_peak_n, e.r_min_m],
        )?;
        for opt in [e.t_center_s, e.t_end_s] {
            f.write_all(b",")?;
            if let Some(v) = opt {
                write_num(&mut f, v)?;
            }
        }
        f.write_all(b",")?;
        write_num(&mut f, e.max_melted_fraction)?;
        f.write_all(b"\n")?;
    }
    f.commit()
}

/// Comma-separated numbers without the newline.
fn write_row_open(w: &mut impl Write, values: &[f64]) -> io::Result<()> {
    for (i, &v) in values.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        write_num(w, v)?;
    }
    Ok(())
}
