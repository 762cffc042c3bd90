//! `map.csv` and `map.json`: the table of a sweep, one row per point in point order, with its
//! writer and its reader.
//!
//! Columns: `point`, one column per axis key (named by the key), `status`, `regime`,
//! `n_events`, `t_first_onset`, `period_last`, `x_period_last`, `f_peak_first`,
//! `f_peak_last`, `f_mean`, `recovery`, `melted_time_fraction`, `wall_s`, `message` (quoted),
//! `steady`, `level`, `stamp_regime`, `n_slips`, `slip_interval_median`,
//! `melting_interval_median`, `energy_per_cycle` (the columns after `message` appended later,
//! in this order: files without them still read).
//! Numbers in shortest round-trip `{:e}` form; an empty cell is "no value".

use super::record::{PointRecord, PointStatus};
use super::{Sweep, value_text};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use stickslip_run::cycles::StampRegime;
use stickslip_run::schema::{Column, SchemaError};
use stickslip_run::summary::{Regime, RegimeThresholds, RunSummary};

pub use stickslip_run::layout::sweep::{CSV_FILE, JSON_FILE};

/// The last column of map.csv (after `message`): whether the point's last cycles repeat
/// (`true`/`false`, run.json's `summary.steady`).
pub const STEADY_COLUMN: &str = "steady";

/// The column after `steady`: the point's level in a refined sweep (0: the base grid, and
/// every point of a sweep without `[refine]`).
pub const LEVEL_COLUMN: &str = "level";

/// The stamp's scale, after `level` (docs/model.md#two-scales-meltings-and-slips): the
/// stamp-scale regime, the slips, and the median intervals of slips and of meltings over the
/// settled part.
pub const STAMP_COLUMNS: [Column; 4] = [
    Column {
        name: "stamp_regime",
        unit: "–",
        meaning: "stamp-scale regime: stick_slip, steady_sliding, creep or transient",
    },
    Column {
        name: "n_slips",
        unit: "–",
        meaning: "slips of the stamp that ended within the run",
    },
    Column {
        name: "slip_interval_median",
        unit: "s",
        meaning: "median time between slips over the settled part",
    },
    Column {
        name: "melting_interval_median",
        unit: "s",
        meaning: "median time between meltings over the settled part",
    },
];

/// The last column, after the stamp's scale: the energy dissipated over the last complete
/// cycle (run.json's `summary.energy_per_cycle`).
pub const ENERGY_COLUMN: Column = Column {
    name: "energy_per_cycle",
    unit: "J",
    meaning: "energy dissipated over the last complete cycle (every sink of the energy books)",
};

/// The summary columns after the axes and status, in order.
pub const SUMMARY_COLUMNS: [Column; 11] = [
    Column {
        name: "regime",
        unit: "–",
        meaning: "regime, by the rules under Regimes below",
    },
    Column {
        name: "n_events",
        unit: "–",
        meaning: "melting events",
    },
    Column {
        name: "t_first_onset",
        unit: "s",
        meaning: "onset of the first event",
    },
    Column {
        name: "period_last",
        unit: "s",
        meaning: "time between the last two onsets",
    },
    Column {
        name: "x_period_last",
        unit: "m",
        meaning: "stamp advance between the last two onsets",
    },
    Column {
        name: "f_peak_first",
        unit: "N",
        meaning: "peak force before the first event",
    },
    Column {
        name: "f_peak_last",
        unit: "N",
        meaning: "peak force before the last event",
    },
    Column {
        name: "f_mean",
        unit: "N",
        meaning: "time-mean force over the last complete cycle",
    },
    Column {
        name: "recovery",
        unit: "–",
        meaning: "largest ⟨φ⟩/√(A/a) over the last complete cycle",
    },
    Column {
        name: "melted_time_fraction",
        unit: "–",
        meaning: "share of the time after the first onset with no solid node",
    },
    Column {
        name: "wall_s",
        unit: "s",
        meaning: "wall-clock seconds of the point",
    },
];

/// One row of map.csv.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapRow {
    /// Point number.
    pub point: usize,
    /// Axis values as written (numbers in `{:e}`, words as they are).
    pub values: Vec<String>,
    /// `ok`, `failed` or `refused`.
    pub status: PointStatus,
    /// The summary (regime and numbers).
    pub summary: RunSummary,
    /// Wall-clock seconds.
    pub wall_s: f64,
    /// The failure or refusal (empty when ok).
    pub message: String,
    /// Level in a refined sweep (0: the base grid).
    #[serde(default)]
    pub level: usize,
    /// Median time between slips over the settled part, s (map.csv keeps only the medians of
    /// the summary's cycle statistics).
    #[serde(default)]
    pub slip_interval_median: Option<f64>,
    /// Median time between meltings over the settled part, s.
    #[serde(default)]
    pub melting_interval_median: Option<f64>,
}

impl MapRow {
    /// The row of a record.
    #[must_use]
    pub fn of(r: &PointRecord) -> Self {
        Self {
            point: r.point,
            values: r.values.iter().map(value_text).collect(),
            status: r.status,
            summary: r.summary.clone(),
            wall_s: r.wall_s,
            message: r.message.clone(),
            level: r.level,
            slip_interval_median: median_interval(r.summary.cycles.as_ref().map(|c| &c.slips)),
            melting_interval_median: median_interval(
                r.summary.cycles.as_ref().map(|c| &c.meltings),
            ),
        }
    }

    /// A summary value by column name (NaN for none or an unknown name).
    #[must_use]
    pub fn number(&self, column: &str) -> f64 {
        let s = &self.summary;
        let v = match column {
            "n_events" => Some(s.n_events as f64),
            "t_first_onset" => s.t_first_onset,
            "period_last" => s.period_last,
            "x_period_last" => s.x_period_last,
            "f_peak_first" => s.f_peak_first,
            "f_peak_last" => s.f_peak_last,
            "f_mean" => s.f_mean,
            "recovery" => s.recovery,
            "melted_time_fraction" => s.melted_time_fraction,
            "wall_s" => Some(self.wall_s),
            "n_slips" => Some(s.n_slips as f64),
            "slip_interval_median" => self.slip_interval_median,
            "melting_interval_median" => self.melting_interval_median,
            "energy_per_cycle" => s.energy_per_cycle,
            _ => None,
        };
        v.unwrap_or(f64::NAN)
    }
}

/// The median interval of one scale's statistics.
fn median_interval(stats: Option<&stickslip_run::cycles::CycleStats>) -> Option<f64> {
    stats.and_then(|c| c.interval_s.map(|i| i.median))
}

/// The table of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapTable {
    /// Axis keys, in column order.
    pub axes: Vec<String>,
    /// Rows in point order.
    pub rows: Vec<MapRow>,
}

fn num(v: Option<f64>) -> String {
    v.map_or_else(String::new, |x| format!("{x:e}"))
}

/// A CSV cell quoted when it holds a comma, quote or newline.
fn quote(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Splits one CSV line into cells, honouring quotes.
fn cells(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cur)),
            (c, _) => cur.push(c),
        }
    }
    out.push(cur);
    out
}

impl MapTable {
    /// The header names.
    #[must_use]
    pub fn header(&self) -> Vec<String> {
        let mut h = vec!["point".to_string()];
        h.extend(self.axes.iter().cloned());
        h.push("status".into());
        h.extend(SUMMARY_COLUMNS.iter().map(|c| c.name.to_string()));
        h.push("message".into());
        h.push(STEADY_COLUMN.into());
        h.push(LEVEL_COLUMN.into());
        h.extend(STAMP_COLUMNS.iter().map(|c| c.name.to_string()));
        h.push(ENERGY_COLUMN.name.into());
        h
    }

    /// The CSV text.
    #[must_use]
    pub fn to_csv(&self) -> String {
        let mut out = self.header().join(",");
        out.push('\n');
        for r in &self.rows {
            let s = &r.summary;
            let mut cells = vec![r.point.to_string()];
            cells.extend(r.values.iter().map(|v| quote(v)));
            cells.push(r.status.name().into());
            cells.push(s.regime.name().into());
            cells.push(s.n_events.to_string());
            for v in [
                s.t_first_onset,
                s.period_last,
                s.x_period_last,
                s.f_peak_first,
                s.f_peak_last,
                s.f_mean,
                s.recovery,
                s.melted_time_fraction,
                Some(r.wall_s),
            ] {
                cells.push(num(v));
            }
            cells.push(quote(&r.message));
            cells.push(s.steady.to_string());
            cells.push(r.level.to_string());
            cells.push(s.stamp_regime.map_or("", StampRegime::name).into());
            cells.push(s.n_slips.to_string());
            cells.push(num(r.slip_interval_median));
            cells.push(num(r.melting_interval_median));
            cells.push(num(s.energy_per_cycle));
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        out
    }

    /// Parses map.csv.
    ///
    /// # Errors
    /// [`SchemaError`] naming the line and what does not fit.
    pub fn parse(text: &str) -> Result<Self, SchemaError> {
        let bad = |line: usize, m: String| SchemaError::new(CSV_FILE, Some(line), m);
        let mut lines = text.lines();
        let header = cells(lines.next().ok_or_else(|| bad(1, "empty file".into()))?);
        // Columns appended after `message`, in this order: `steady`, `level`, the stamp's
        // scale, the energy per cycle. A map.csv written before them reads as not steady, at
        // level 0, without a stamp-scale regime, with no slips and no energy.
        let appended: Vec<&str> = [STEADY_COLUMN, LEVEL_COLUMN]
            .into_iter()
            .chain(STAMP_COLUMNS.iter().map(|c| c.name))
            .chain([ENERGY_COLUMN.name])
            .collect();
        let n_appended = (0..=appended.len())
            .rev()
            .find(|&k| header.len() >= k && header[header.len() - k..] == appended[..k])
            .unwrap_or(0);
        let has_steady = n_appended >= 1;
        let has_level = n_appended >= 2;
        let has_stamp = n_appended >= 2 + STAMP_COLUMNS.len();
        let has_energy = n_appended == appended.len();
        let fixed = 1 + 1 + SUMMARY_COLUMNS.len() + 1 + n_appended;
        if header.len() < fixed || header[0] != "point" {
            return Err(bad(1, format!("header {header:?}")));
        }
        let n_axes = header.len() - fixed;
        let axes = header[1..=n_axes].to_vec();
        let mut rows = Vec::new();
        for (i, line) in lines.enumerate() {
            let lineno = i + 2;
            let c = cells(line);
            if c.len() != header.len() {
                return Err(bad(
                    lineno,
                    format!("{} cells, header has {}", c.len(), header.len()),
                ));
            }
            let f = |j: usize| -> Result<Option<f64>, SchemaError> {
                if c[j].is_empty() {
                    Ok(None)
                } else {
                    c[j].parse::<f64>()
                        .map(Some)
                        .map_err(|_| bad(lineno, format!("{:?} is not a number", c[j])))
                }
            };
            let base = 1 + n_axes;
            let status = PointStatus::from_name(&c[base])
                .ok_or_else(|| bad(lineno, format!("status {:?}", c[base])))?;
            let regime = Regime::from_name(&c[base + 1])
                .ok_or_else(|| bad(lineno, format!("regime {:?}", c[base + 1])))?;
            let n_events = c[base + 2]
                .parse::<usize>()
                .map_err(|_| bad(lineno, format!("n_events {:?}", c[base + 2])))?;
            rows.push(MapRow {
                point: c[0]
                    .parse()
                    .map_err(|_| bad(lineno, format!("point {:?}", c[0])))?,
                values: c[1..=n_axes].to_vec(),
                status,
                summary: RunSummary {
                    n_events,
                    t_first_onset: f(base + 3)?,
                    period_last: f(base + 4)?,
                    x_period_last: f(base + 5)?,
                    f_peak_first: f(base + 6)?,
                    f_peak_last: f(base + 7)?,
                    f_mean: f(base + 8)?,
                    recovery: f(base + 9)?,
                    melted_time_fraction: f(base + 10)?,
                    regime,
                    steady: has_steady && c[base + 13] == "true",
                    n_slips: if has_stamp {
                        c[base + 16]
                            .parse::<usize>()
                            .map_err(|_| bad(lineno, format!("n_slips {:?}", c[base + 16])))?
                    } else {
                        0
                    },
                    stamp_regime: match (has_stamp, c.get(base + 15).map(String::as_str)) {
                        (true, Some(name)) if !name.is_empty() => Some(
                            StampRegime::from_name(name)
                                .ok_or_else(|| bad(lineno, format!("stamp_regime {name:?}")))?,
                        ),
                        _ => None,
                    },
                    cycles: None,
                    energy_per_cycle: if has_energy { f(base + 19)? } else { None },
                    energy: None,
                },
                wall_s: f(base + 11)?.unwrap_or(f64::NAN),
                message: c[base + 12].clone(),
                level: if has_level {
                    let j = base + 13 + usize::from(has_steady);
                    c[j].parse()
                        .map_err(|_| bad(lineno, format!("level {:?}", c[j])))?
                } else {
                    0
                },
                slip_interval_median: if has_stamp { f(base + 17)? } else { None },
                melting_interval_median: if has_stamp { f(base + 18)? } else { None },
            });
        }
        Ok(Self { axes, rows })
    }

    /// Reads `dir/map.csv`.
    ///
    /// # Errors
    /// As [`MapTable::parse`], or if it cannot be read.
    pub fn read(dir: &Path) -> Result<Self, SchemaError> {
        Self::parse(&stickslip_run::schema::read_text(dir, CSV_FILE)?)
    }

    /// Counts of each regime among the rows with status ok.
    #[must_use]
    pub fn regime_counts(&self) -> BTreeMap<Regime, usize> {
        let mut out = BTreeMap::new();
        for r in self.rows.iter().filter(|r| r.status == PointStatus::Ok) {
            *out.entry(r.summary.regime).or_insert(0) += 1;
        }
        out
    }
}

/// map.json: the sweep as resolved, the regime thresholds, the program version, the unit of
/// every column and the table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapJson {
    /// The sweep as resolved.
    pub sweep: Sweep,
    /// Regime thresholds.
    pub thresholds: RegimeThresholds,
    /// Program version.
    pub version: String,
    /// Column → unit.
    pub columns: BTreeMap<String, String>,
    /// The table.
    pub table: MapTable,
    /// What the spot checks found (`[verify]`), once they ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spot_checks: Option<super::checks::SpotReport>,
}

impl MapJson {
    /// The map.json of `sweep` with `table`.
    #[must_use]
    pub fn new(sweep: &Sweep, table: MapTable) -> Self {
        let mut columns = BTreeMap::new();
        columns.insert("point".to_string(), "–".to_string());
        for a in &sweep.axes {
            columns.insert(a.key.clone(), a.unit().to_string());
        }
        columns.insert("status".into(), "–".into());
        for c in SUMMARY_COLUMNS {
            columns.insert(c.name.into(), c.unit.into());
        }
        columns.insert("message".into(), "–".into());
        columns.insert(STEADY_COLUMN.into(), "–".into());
        columns.insert(LEVEL_COLUMN.into(), "–".into());
        Self {
            thresholds: sweep.thresholds,
            sweep: sweep.clone(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            columns,
            table,
            spot_checks: None,
        }
    }

    /// Reads `dir/map.json`.
    ///
    /// # Errors
    /// [`SchemaError`] if it cannot be read or parsed.
    pub fn read(dir: &Path) -> Result<Self, SchemaError> {
        let text = stickslip_run::schema::read_text(dir, JSON_FILE)?;
        serde_json::from_str(&text)
            .map_err(|e| SchemaError::new(JSON_FILE, Some(e.line()), e.to_string()))
    }
}
