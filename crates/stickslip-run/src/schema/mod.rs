//! The output files of a run, one Rust type per file with its writer and its reader (the CSV
//! files through one trait, [`Table`]):
//! [`series::Series`] (series.csv), [`events::Events`] (events.csv), [`profiles::Profiles`]
//! (profiles.csv), [`probes::Probes`] (probes.csv) and [`run_info::RunInfo`] (run.json).
//! [`RunOutput`] holds all five, read from a directory or collected in memory.
//!
//! Every column has a [`Column`] spec with its unit; run.json's `columns` and the generated
//! reference are built from these specs. Written and read back, every number keeps its bits
//! (tested in `tests/schema.rs`).

pub mod csv;
pub mod events;
pub mod probes;
pub mod profiles;
pub mod run_info;
pub mod series;
pub mod slips;
pub mod table;

pub use table::Table;

use std::collections::BTreeMap;
use std::path::Path;
use thiserror::Error;

/// One column of an output table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Column {
    /// Name in the header.
    pub name: &'static str,
    /// SI unit (`–` for dimensionless).
    pub unit: &'static str,
    /// What it holds.
    pub meaning: &'static str,
}

/// An output file that does not read as its schema says.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}{}: {message}", line.map(|l| format!(", line {l}")).unwrap_or_default())]
pub struct SchemaError {
    /// The file (path or name).
    pub file: String,
    /// Line, from 1, if the problem has one.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl SchemaError {
    /// A new error.
    pub fn new(file: &str, line: Option<usize>, message: impl Into<String>) -> Self {
        Self {
            file: file.to_string(),
            line,
            message: message.into(),
        }
    }

    /// An error reading `path`.
    pub fn io(path: &Path, e: &std::io::Error) -> Self {
        Self::new(&path.display().to_string(), None, e.to_string())
    }
}

/// Reads `dir/name` as text.
///
/// # Errors
/// [`SchemaError`] naming the path.
pub fn read_text(dir: &Path, name: &str) -> Result<String, SchemaError> {
    let path = dir.join(name);
    std::fs::read_to_string(&path).map_err(|e| SchemaError::io(&path, &e))
}

/// Everything one run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    /// series.csv.
    pub series: series::Series,
    /// events.csv.
    pub events: events::Events,
    /// slips.csv (none in a directory written before slips existed).
    pub slips: slips::Slips,
    /// profiles.csv.
    pub profiles: profiles::Profiles,
    /// probes.csv.
    pub probes: probes::Probes,
    /// run.json.
    pub info: run_info::RunInfo,
}

impl RunOutput {
    /// Reads the five files of a finished, failed or interrupted run in `dir` (a killed run
    /// has only temporary files: [`crate::sink::read::read_run`] reads any state).
    ///
    /// # Errors
    /// The first file that is missing or does not match its schema.
    pub fn read(dir: &Path) -> Result<Self, SchemaError> {
        let info = run_info::RunInfo::read(dir)?;
        let series = series::Series::read(dir)?;
        let no_probes = info
            .scene
            .output
            .as_ref()
            .and_then(|o| o.probe_radii.as_ref())
            .is_none_or(Vec::is_empty);
        // A scene without probes writes no probes.csv: its table is the series' times alone,
        // as the file held before it was left out.
        let probes = if no_probes && !dir.join(probes::FILE).is_file() {
            let mut p = probes::Probes::new(&[]);
            p.t_s.clone_from(&series.t_s);
            p
        } else {
            probes::Probes::read(dir)?
        };
        Ok(Self {
            series,
            events: events::Events::read(dir)?,
            slips: slips::Slips::read(dir)?,
            profiles: profiles::Profiles::read(dir)?,
            probes,
            info,
        })
    }
}

/// The output files as a Markdown section: every column with its unit and meaning.
#[must_use]
pub fn markdown() -> String {
    let mut out = String::from(
        "## Output files\n\nNumbers are written in shortest round-trip `{:e}` form (read \
         back, they keep their bits); an empty cell means no value. Columns may be added at \
         the end of a row, never renamed or dropped.\n\n\
         A scene without probes (`output.probe_radii = []`) writes no probes.csv. \
         While a run goes on, run.json says `running` and series.csv, probes.csv and \
         profiles.csv grow under temporary names (`.series.csv.tmp`, …); they are renamed into \
         place, with events.csv and slips.csv written, when the run ends (`ok` or `failed`). An interrupted \
         run (SIGINT/SIGTERM; Ctrl-C in Python's `stickslip.run(…, out=DIR)`) writes \
         checkpoint.cbor and publishes what it \
         wrote so far under the documented names: every row up to the interruption, and \
         events.csv with the events so far (the last one may still be open, `t_end` empty), so \
         the usual tools read them; the temporary files stay, and `stickslip resume DIR` \
         finishes the run and replaces these files with those of the whole run, bit-identical \
         to an uninterrupted one. After a hard kill (SIGKILL, power loss) run.json still says \
         `running` and only the temporary files and the last checkpoint are there: `stickslip \
         resume DIR` finishes the run, and Python's `stickslip.load(DIR)` reads it as of its \
         last checkpoint. A checkpoint is bound to the build of the numerics that wrote it \
         (the checkpoint carries the build identity): `stickslip resume` refuses another \
         build's checkpoint (exit 2, naming both builds), since its numbers would differ, \
         unless `--allow-other-build` is given, and then run.json records the crossing in \
         `resumed_across_builds`. One process writes a run directory at a time: `run` and \
         `resume` hold a lock on its `.stickslip.lock` (released when the process ends, \
         however it ends), and a second writer is refused with exit 2 before it touches \
         anything. `run` refuses a directory that holds another command's results (verify, \
         fit, sweep), even with `--force`.\n",
    );
    let probe = [probes::TIME, probes::PHI, probes::T_MELT];
    for (file, cols) in [
        (series::FILE, &series::COLUMNS[..]),
        (events::FILE, &events::COLUMNS[..]),
        (slips::FILE, &slips::COLUMNS[..]),
        (profiles::FILE, &profiles::COLUMNS[..]),
        (probes::FILE, &probe[..]),
    ] {
        out.push_str(&format!(
            "\n### `{file}`\n\n| column | unit | meaning |\n|---|---|---|\n"
        ));
        for c in cols {
            out.push_str(&format!("| `{}` | {} | {} |\n", c.name, c.unit, c.meaning));
        }
    }
    out.push_str(
        "\n### `run.json`\n\n`name`, `status` (`running` | `interrupted` | `ok` | `failed`), \
         `failure` (null, or `{time_s, step, node, r_m, quantity, value, reason, message}`), \
         `stop` (`end` | `max_events` | `open_event` | `periodic` | `failure` | `refused` | \
         `interrupted` | `io`: an I/O error, such as a full disk, ended the run; status \
         `failed`, the failure's quantity `io`), `version`, `scene` (as \
         resolved), `derived` (b, A, eps_c, phi0, omega, g_eff, nodes, steps_planned, \
         lagged_sweep_contraction, melting_force, critical_displacement, spring_period, \
         euler_number, first_onset_estimate, onset_displacement (m, the stamp advance to the \
         contact's quasi-static melting; absent when nothing can melt); for a first-order film also cubic, eps_melt, \
         eps_solidify, hysteresis_width, tau_melt and, when A <= 0, metastable_solid), \
         `warnings`, `steps`, `accepted_steps`, \
         `rejected_steps`, `forced_steps`, `onset_retakes`, `t_final`, `wall_seconds`, \
         `coupling_iterations`, \
         `seed`, `events`, `series_rows`, `columns` (file → column → unit), `summary` (n_events, \
         t_first_onset, period_last, x_period_last, f_peak_first, f_peak_last, f_mean, recovery, \
         melted_time_fraction, regime, steady, n_slips, stamp_regime, and `cycles`: \
         `settled_from`, `slip_drop` and, for `meltings` and for `slips`, `count` and \
         `interval`, `peak`, `drop`, `advance` (each `{n, median, mean, min, max, cv}` or \
         null) and `f_mean`; `energy_per_cycle`: the energy dissipated over the last complete \
         cycle, J; `energy`: the energy books of the whole run, J: `flows` (`drive_work_j`, \
         `temperature_work_j`, `noise_work_j`, and the sinks `landau_j`, `reset_j`, \
         `sliding_j`, `viscous_j`, `dashpot_j`), `stored_change_j` (spring, stamp, film and \
         substrate) and `residual_j` (in − sinks − stored change; docs/model.md#the-energy-books)) \
         and, only for a run resumed from another build's \
         checkpoint, `resumed_across_builds` (`[{checkpoint_build, build}, …]`, one per such \
         resume).\n",
    );
    out
}

/// Units of every column of every table, as in run.json's `columns`: file name → column
/// name → unit. Probe columns depend on the probe radii (m).
#[must_use]
pub fn column_units(probe_radii_m: &[f64]) -> BTreeMap<String, BTreeMap<String, String>> {
    let table = |cols: &[Column]| {
        cols.iter()
            .map(|c| (c.name.to_string(), c.unit.to_string()))
            .collect::<BTreeMap<_, _>>()
    };
    let mut out = BTreeMap::new();
    out.insert(series::FILE.to_string(), table(&series::COLUMNS));
    out.insert(events::FILE.to_string(), table(&events::COLUMNS));
    out.insert(slips::FILE.to_string(), table(&slips::COLUMNS));
    out.insert(profiles::FILE.to_string(), table(&profiles::COLUMNS));
    out.insert(
        probes::FILE.to_string(),
        probes::header(probe_radii_m)
            .into_iter()
            .map(|(name, col)| (name, col.unit.to_string()))
            .collect(),
    );
    out
}
