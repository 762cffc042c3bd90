//! The outputs of one `stickslip run`, parsed: series.csv, events.csv, probes.csv, profiles.csv
//! and run.json (formats of INTERFACE.md). The claims work on these structures only.

use serde_json::Value;
use std::fmt;
use std::path::Path;

/// A problem reading or parsing an output file.
#[derive(Debug, Clone, PartialEq)]
pub struct DataError(pub String);

impl fmt::Display for DataError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for DataError {}

fn err(msg: impl Into<String>) -> DataError {
    DataError(msg.into())
}

/// A numeric CSV table stored by column. Empty cells (and `nan`) parse as NaN.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Column names from the header row.
    pub header: Vec<String>,
    /// One vector per column, all of the same length.
    pub columns: Vec<Vec<f64>>,
}

impl Table {
    /// Parses `text` (header row, then rows of numbers); `what` names the file in errors.
    ///
    /// # Errors
    /// A missing header, a row of the wrong width or a cell that is not a number.
    pub fn parse(text: &str, what: &str) -> Result<Self, DataError> {
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header: Vec<String> = lines
            .next()
            .ok_or_else(|| err(format!("{what}: empty file")))?
            .split(',')
            .map(|s| s.trim().to_string())
            .collect();
        let mut columns = vec![Vec::new(); header.len()];
        for (row, line) in lines.enumerate() {
            let cells: Vec<&str> = line.split(',').collect();
            if cells.len() != header.len() {
                return Err(err(format!(
                    "{what}: row {} has {} cells, the header {}",
                    row + 1,
                    cells.len(),
                    header.len()
                )));
            }
            for (col, cell) in columns.iter_mut().zip(cells) {
                let cell = cell.trim();
                let v = if cell.is_empty() {
                    f64::NAN
                } else {
                    cell.parse::<f64>().map_err(|_| {
                        err(format!("{what}: row {}: `{cell}` is not a number", row + 1))
                    })?
                };
                col.push(v);
            }
        }
        Ok(Self { header, columns })
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// The column called `name`, if present.
    pub fn get(&self, name: &str) -> Option<&[f64]> {
        self.header
            .iter()
            .position(|h| h == name)
            .map(|i| self.columns[i].as_slice())
    }

    /// The column called `name`.
    ///
    /// # Errors
    /// If there is no such column; `what` names the file.
    pub fn column(&self, name: &str, what: &str) -> Result<Vec<f64>, DataError> {
        self.get(name)
            .map(<[f64]>::to_vec)
            .ok_or_else(|| err(format!("{what}: no column `{name}`")))
    }
}

/// series.csv: scalar observables against time.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series {
    /// Time, s.
    pub t_s: Vec<f64>,
    /// Stamp position X, m.
    pub x_m: Vec<f64>,
    /// Stamp velocity V, m/s.
    pub v_m_per_s: Vec<f64>,
    /// Friction force from 2π∫τr dr, N.
    pub f_n: Vec<f64>,
    /// Friction force from 2∫q dx, N (empty when the file lacks the column).
    pub f_1d_n: Vec<f64>,
    /// Area-weighted mean order parameter ⟨φ⟩.
    pub phi_mean: Vec<f64>,
    /// Area-weighted mean strain ⟨ε⟩.
    pub eps_mean: Vec<f64>,
    /// Melted area fraction.
    pub melted_fraction: Vec<f64>,
}

impl Series {
    /// Parses series.csv text.
    ///
    /// # Errors
    /// A required column is missing or a cell is not a number.
    pub fn parse(text: &str) -> Result<Self, DataError> {
        let w = "series.csv";
        let t = Table::parse(text, w)?;
        Ok(Self {
            t_s: t.column("t", w)?,
            x_m: t.column("X", w)?,
            v_m_per_s: t.column("V", w)?,
            f_n: t.column("F", w)?,
            f_1d_n: t.get("F_1d").map(<[f64]>::to_vec).unwrap_or_default(),
            phi_mean: t.column("phi_mean", w)?,
            eps_mean: t.column("eps_mean", w)?,
            melted_fraction: t.column("melted_fraction", w)?,
        })
    }

    /// Number of recorded times.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// Index range of the rows with `t0 <= t <= t1`.
    pub fn window(&self, t0: f64, t1: f64) -> std::ops::Range<usize> {
        let a = self.t_s.partition_point(|&t| t < t0);
        let b = self.t_s.partition_point(|&t| t <= t1);
        a..b.max(a)
    }

    /// Linear interpolation of column `y` at time `t` (clamped to the ends).
    pub fn interp(&self, y: &[f64], t: f64) -> f64 {
        interp(&self.t_s, y, t)
    }
}

/// Linear interpolation of `y(x)` at `x0`, `x` ascending; clamped outside.
pub fn interp(x: &[f64], y: &[f64], x0: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let i = x.partition_point(|&v| v <= x0);
    if i == 0 {
        return y[0];
    }
    if i >= x.len() {
        return y[x.len() - 1];
    }
    let (x_a, x_b) = (x[i - 1], x[i]);
    if x_b == x_a {
        return y[i];
    }
    y[i - 1] + (y[i] - y[i - 1]) * (x0 - x_a) / (x_b - x_a)
}

/// One row of events.csv.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    /// Event number, from 1.
    pub k: usize,
    /// Onset time, s.
    pub t_onset_s: f64,
    /// Radius of the outermost node melted at the onset, m.
    pub r_first_m: f64,
    /// Stamp position at the onset, m.
    pub x_onset_m: f64,
    /// Largest F since the previous event began, N.
    pub f_peak_n: f64,
    /// Innermost radius the front reached, m (extra column).
    pub r_min_m: Option<f64>,
    /// First time the axis node melted in this event, s (extra column).
    pub t_center_s: Option<f64>,
    /// Last return of the contact to fully solid in this event, s (extra column).
    pub t_end_s: Option<f64>,
    /// Largest melted area fraction during the event (extra column).
    pub max_melted_fraction: Option<f64>,
}

/// events.csv.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Events {
    /// The events in order.
    pub events: Vec<Event>,
    /// Whether the file has the extra front columns `r_min, t_center, t_end,
    /// max_melted_fraction`.
    pub has_front_columns: bool,
}

impl Events {
    /// The front columns beyond INTERFACE.md's minimum.
    pub const FRONT_COLUMNS: [&'static str; 4] =
        ["r_min", "t_center", "t_end", "max_melted_fraction"];

    /// Parses events.csv text.
    ///
    /// # Errors
    /// A required column is missing or a cell is not a number.
    pub fn parse(text: &str) -> Result<Self, DataError> {
        let w = "events.csv";
        let t = Table::parse(text, w)?;
        let k = t.column("k", w)?;
        let onset = t.column("t_onset", w)?;
        let r_first = t.column("r_first", w)?;
        let x_onset = t.column("x_onset", w)?;
        let f_peak = t.column("f_peak", w)?;
        let opt = |name: &str, i: usize| t.get(name).map(|c| c[i]).filter(|v| v.is_finite());
        let has_front_columns = Self::FRONT_COLUMNS.iter().all(|c| t.get(c).is_some());
        let events = (0..t.rows())
            .map(|i| Event {
                k: k[i] as usize,
                t_onset_s: onset[i],
                r_first_m: r_first[i],
                x_onset_m: x_onset[i],
                f_peak_n: f_peak[i],
                r_min_m: opt("r_min", i),
                t_center_s: opt("t_center", i),
                t_end_s: opt("t_end", i),
                max_melted_fraction: opt("max_melted_fraction", i),
            })
            .collect();
        Ok(Self {
            events,
            has_front_columns,
        })
    }

    /// Onset times, s.
    pub fn onsets_s(&self) -> Vec<f64> {
        self.events.iter().map(|e| e.t_onset_s).collect()
    }

    /// Number of events.
    pub fn len(&self) -> usize {
        self.events.len()
    }

    /// Whether there was no event.
    pub fn is_empty(&self) -> bool {
        self.events.is_empty()
    }
}

/// probes.csv: φ(t) at fixed radii.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Probes {
    /// Probe radii, m, in column order.
    pub radii_m: Vec<f64>,
    /// Time, s.
    pub t_s: Vec<f64>,
    /// φ per probe (outer index as `radii_m`).
    pub phi: Vec<Vec<f64>>,
    /// Per probe, the time its node last melted (`t_melt@<radius>` columns, −1 = never), s;
    /// empty when the file has no such columns.
    pub t_melt_s: Vec<Vec<f64>>,
}

impl Probes {
    /// Parses probes.csv text (`t`, then `phi@<radius>` columns).
    ///
    /// # Errors
    /// A missing `t` column, a column name that is not `phi@<number>`, or a bad cell.
    pub fn parse(text: &str) -> Result<Self, DataError> {
        let w = "probes.csv";
        let t = Table::parse(text, w)?;
        let t_s = t.column("t", w)?;
        let mut radii_m = Vec::new();
        let mut phi = Vec::new();
        let mut t_melt_s = Vec::new();
        for (name, col) in t.header.iter().zip(&t.columns) {
            if name == "t" {
                continue;
            }
            if name.starts_with("t_melt@") {
                t_melt_s.push(col.clone());
                continue;
            }
            let r = name
                .strip_prefix("phi@")
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| err(format!("{w}: column `{name}` is not `phi@<radius>`")))?;
            radii_m.push(r);
            phi.push(col.clone());
        }
        if !t_melt_s.is_empty() && t_melt_s.len() != phi.len() {
            return Err(err(format!(
                "{w}: {} t_melt@ columns for {} phi@ columns",
                t_melt_s.len(),
                phi.len()
            )));
        }
        Ok(Self {
            radii_m,
            t_s,
            phi,
            t_melt_s,
        })
    }
}

/// One block of profiles.csv: profiles against r at one time.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Profile {
    /// Time of the profile, s.
    pub t_s: f64,
    /// Node radii, m.
    pub r_m: Vec<f64>,
    /// Order parameter φ.
    pub phi: Vec<f64>,
    /// Strain ε.
    pub eps: Vec<f64>,
    /// Stress τ, Pa.
    pub tau_pa: Vec<f64>,
    /// Stamp-surface displacement u0, m.
    pub u0_m: Vec<f64>,
    /// Substrate displacement u3D, m.
    pub u3d_m: Vec<f64>,
}

/// Parses profiles.csv into one [`Profile`] per distinct time (rows grouped in file order).
///
/// # Errors
/// A missing column or a bad cell.
pub fn parse_profiles(text: &str) -> Result<Vec<Profile>, DataError> {
    let w = "profiles.csv";
    let t = Table::parse(text, w)?;
    let cols: Vec<Vec<f64>> = ["t", "r", "phi", "eps", "tau", "u0", "u3d"]
        .iter()
        .map(|c| t.column(c, w))
        .collect::<Result<_, _>>()?;
    let mut out: Vec<Profile> = Vec::new();
    let [t_col, r, phi, eps, tau, u0, u3d] = cols.as_slice() else {
        return Err(err(format!("{w}: internal column count")));
    };
    for (i, &ti) in t_col.iter().enumerate() {
        if out.last().is_none_or(|p| p.t_s != ti) {
            out.push(Profile {
                t_s: ti,
                ..Profile::default()
            });
        }
        let p = out.last_mut().expect("pushed above");
        p.r_m.push(r[i]);
        p.phi.push(phi[i]);
        p.eps.push(eps[i]);
        p.tau_pa.push(tau[i]);
        p.u0_m.push(u0[i]);
        p.u3d_m.push(u3d[i]);
    }
    Ok(out)
}

/// What the claims need from run.json (the resolved scene and the run's counters).
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// Contact radius a0, m.
    pub radius_m: f64,
    /// Melting threshold of φ.
    pub melt_threshold: f64,
    /// Drive velocity V0, m/s.
    pub velocity_m_per_s: f64,
    /// Spring stiffness K, N/m (None for a rigid drive).
    pub stiffness_n_per_m: Option<f64>,
    /// Stamp mass m, kg (None for a rigid drive).
    pub mass_kg: Option<f64>,
    /// Maximum shear stress τmax, Pa.
    pub tau_max_pa: f64,
    /// Nodes simulated (1 for the homogeneous model).
    pub nodes: usize,
    /// `"accurate"` or `"literal"`.
    pub scheme: String,
    /// Time step, s.
    pub dt_s: f64,
    /// End time, s.
    pub end_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// Wall seconds of the time loop as the run measured it.
    pub wall_seconds: f64,
    /// `"ok"` or `"failed"`.
    pub status: String,
}

fn num(v: &Value, path: &str) -> Option<f64> {
    v.pointer(path).and_then(Value::as_f64)
}

fn text(v: &Value, path: &str) -> Option<String> {
    v.pointer(path).and_then(Value::as_str).map(str::to_string)
}

impl RunInfo {
    /// Reads the fields from run.json's JSON value.
    ///
    /// # Errors
    /// If a required field is missing.
    pub fn from_json(v: &Value) -> Result<Self, DataError> {
        let need = |path: &str| num(v, path).ok_or_else(|| err(format!("run.json: no {path}")));
        Ok(Self {
            radius_m: need("/scene/contact/radius")?,
            melt_threshold: num(v, "/scene/lubricant/melt_threshold").unwrap_or(0.01),
            velocity_m_per_s: need("/scene/drive/velocity")?,
            stiffness_n_per_m: num(v, "/scene/drive/stiffness"),
            mass_kg: num(v, "/scene/drive/mass"),
            tau_max_pa: need("/scene/lubricant/tau_max")?,
            nodes: num(v, "/derived/nodes")
                .or_else(|| num(v, "/scene/contact/nodes"))
                .unwrap_or(0.0) as usize,
            scheme: text(v, "/scene/time/scheme").unwrap_or_else(|| "accurate".into()),
            dt_s: need("/scene/time/dt")?,
            end_s: need("/scene/time/end")?,
            steps: num(v, "/steps").unwrap_or(0.0) as u64,
            wall_seconds: num(v, "/wall_seconds").unwrap_or(f64::NAN),
            status: text(v, "/status").unwrap_or_else(|| "ok".into()),
        })
    }

    /// ω = √(K/m) of the spring drive, rad/s.
    pub fn omega_rad_per_s(&self) -> Option<f64> {
        Some((self.stiffness_n_per_m? / self.mass_kg?).sqrt())
    }
}

/// Everything one run wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    /// Name of the run (the output directory's name).
    pub name: String,
    /// series.csv.
    pub series: Series,
    /// events.csv.
    pub events: Events,
    /// probes.csv (None when the scene has no probes).
    pub probes: Option<Probes>,
    /// profiles.csv blocks.
    pub profiles: Vec<Profile>,
    /// run.json fields.
    pub info: RunInfo,
}

impl RunOutput {
    /// Reads all output files of a run from `dir`.
    ///
    /// # Errors
    /// A missing required file or a parse error.
    pub fn read(dir: &Path, name: &str) -> Result<Self, DataError> {
        let read = |f: &str| {
            std::fs::read_to_string(dir.join(f))
                .map_err(|e| err(format!("{}: {e}", dir.join(f).display())))
        };
        let run_json: Value =
            serde_json::from_str(&read("run.json")?).map_err(|e| err(format!("run.json: {e}")))?;
        let probes = match read("probes.csv") {
            Ok(text) => {
                let p = Probes::parse(&text)?;
                (!p.radii_m.is_empty()).then_some(p)
            }
            Err(_) => None,
        };
        let profiles = match read("profiles.csv") {
            Ok(text) => parse_profiles(&text)?,
            Err(_) => Vec::new(),
        };
        Ok(Self {
            name: name.to_string(),
            series: Series::parse(&read("series.csv")?)?,
            events: Events::parse(&read("events.csv")?)?,
            probes,
            profiles,
            info: RunInfo::from_json(&run_json)?,
        })
    }

    /// The profile recorded nearest to `t_s`, if any.
    pub fn profile_near(&self, t_s: f64) -> Option<&Profile> {
        self.profiles
            .iter()
            .min_by(|a, b| (a.t_s - t_s).abs().total_cmp(&(b.t_s - t_s).abs()))
    }
}
