//! P5: the cost of a friction map. A 32 × 32 sweep of the rigid drive (speed × temperature,
//! as `maps/rigid.toml`, at N = 50) run by `stickslip sweep run` with 1 and with 2 jobs.
//!
//! Per job count: the process wall time, and from the point records (read through the run
//! library's `PointRecord`) the seconds each point spent in its run (`run_s`: building and
//! stepping the simulation) and in all (`wall_s`). Overhead per point beyond the simulation:
//! (jobs·wall − Σ run_s)/Σ run_s, i.e. everything the sweep adds (process start, resolving and
//! validating every point, records, merge, idle workers at the end). Parallel efficiency:
//! wall(1 job) / (2·wall(2 jobs)).

use super::BenchSettings;
use serde::Serialize;
use std::path::Path;
use stickslip_report::binary;
use stickslip_report::fmt::first_line;
use stickslip_studies::sweep::map::MapTable;
use stickslip_studies::sweep::record::{PointRecord, PointStatus};

/// P5 goal: overhead per point beyond the simulation.
pub const OVERHEAD_GOAL: f64 = 0.05;
/// P5 goal: parallel efficiency on 2 cores.
pub const EFFICIENCY_GOAL: f64 = 0.85;

/// One `stickslip sweep run`.
#[derive(Debug, Clone, Serialize)]
pub struct SweepRun {
    /// `--jobs`.
    pub jobs: usize,
    /// Wall time of the whole process, s.
    pub wall_s: f64,
    /// Σ over points of the run's own seconds.
    pub sum_run_s: f64,
    /// Σ over points of the point's seconds (resolution, run, record).
    pub sum_point_wall_s: f64,
    /// Points that did not end `ok`.
    pub not_ok: usize,
}

impl SweepRun {
    /// (jobs·wall − Σ run_s) / Σ run_s.
    #[must_use]
    pub fn overhead(&self) -> f64 {
        (self.jobs as f64 * self.wall_s - self.sum_run_s) / self.sum_run_s
    }
}

/// P5 as measured.
#[derive(Debug, Clone, Serialize)]
pub struct SweepBench {
    /// The sweep file run (TOML, written into the work directory).
    pub sweep_toml: String,
    /// Points of the map.
    pub points: usize,
    /// Nodes per point.
    pub nodes: usize,
    /// Runs with 1 and 2 jobs.
    pub runs: Vec<SweepRun>,
    /// Regimes of the map (name, count), to show what was computed.
    pub regimes: Vec<(String, usize)>,
}

impl SweepBench {
    /// The run with `jobs` jobs.
    #[must_use]
    pub fn run(&self, jobs: usize) -> Option<&SweepRun> {
        self.runs.iter().find(|r| r.jobs == jobs)
    }

    /// wall(1 job) / (2·wall(2 jobs)).
    #[must_use]
    pub fn efficiency(&self) -> f64 {
        match (self.run(1), self.run(2)) {
            (Some(one), Some(two)) => one.wall_s / (2.0 * two.wall_s),
            _ => f64::NAN,
        }
    }

    /// Wall seconds per point with 2 jobs on this machine.
    #[must_use]
    pub fn cost_per_point_s(&self) -> f64 {
        self.run(2)
            .or_else(|| self.runs.last())
            .map_or(f64::NAN, |r| r.wall_s / self.points as f64)
    }

    /// Core-seconds per point (Σ point wall / points, one job).
    #[must_use]
    pub fn core_s_per_point(&self) -> f64 {
        self.run(1)
            .or_else(|| self.runs.first())
            .map_or(f64::NAN, |r| r.sum_point_wall_s / self.points as f64)
    }
}

/// The sweep file: `side` × `side` points over V0 (log) × A0 (linear) of the rigid drive (P5's,
/// and V2's with its `[verify]` table appended).
pub(super) fn sweep_toml(scene: &Path, side: usize, nodes: usize) -> String {
    format!(
        "# P5 of cargo xtask bench: maps/rigid.toml's axes at {side} x {side} points.\n\
         name = \"bench-sweep\"\n\
         scene = \"{}\"\n\n\
         [set]\n\
         \"contact.nodes\" = {nodes}\n\
         \"time.end\" = 2e-3\n\
         \"time.max_events\" = 6\n\
         \"time.max_open_event\" = 2e-5\n\
         \"output.profile_times\" = [2e-3]\n\n\
         [[axis]]\n\
         key = \"drive.velocity\"\n\
         range = {{ from = 1e-3, to = 3.0, count = {side}, scale = \"log\" }}\n\n\
         [[axis]]\n\
         key = \"temperature.A0\"\n\
         range = {{ from = -3e5, to = 1.5e6, count = {side}, scale = \"linear\" }}\n",
        scene.display()
    )
}

/// `stickslip sweep run FILE --out OUT --jobs J --force` afresh (OUT removed first), as a user
/// runs it; an error unless it exits 0.
///
/// # Errors
/// The process could not start or failed.
pub(super) fn run_sweep(
    s: &BenchSettings,
    file: &Path,
    out: &Path,
    jobs: usize,
) -> Result<binary::Invocation, String> {
    let args: Vec<String> = vec![
        "sweep".into(),
        "run".into(),
        file.display().to_string(),
        "--out".into(),
        out.display().to_string(),
        "--jobs".into(),
        jobs.to_string(),
        "--force".into(),
    ];
    let _ = std::fs::remove_dir_all(out);
    let inv = binary::invoke(&s.binary, &args, &[])?;
    if !inv.ok() {
        return Err(format!(
            "stickslip sweep run {} --jobs {jobs} failed (exit {:?}): {}",
            file.display(),
            inv.code,
            first_line(&inv.stderr)
        ));
    }
    Ok(inv)
}

/// Runs the sweep with 1 and 2 jobs.
///
/// # Errors
/// The sweep could not run or its records do not read.
pub fn measure(s: &BenchSettings, rigid_scene: &Path) -> Result<SweepBench, String> {
    let (side, nodes) = if s.quick { (6, 20) } else { (32, 50) };
    let points = side * side;
    let dir = s.work_dir.join("sweep");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let file = dir.join("bench-sweep.toml");
    let text = sweep_toml(rigid_scene, side, nodes);
    std::fs::write(&file, &text).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut runs = Vec::new();
    let mut regimes = Vec::new();
    for jobs in [1_usize, 2] {
        let out = dir.join(format!("jobs{jobs}"));
        let inv = run_sweep(s, &file, &out, jobs)?;
        let (mut sum_run_s, mut sum_point_wall_s, mut not_ok) = (0.0, 0.0, 0);
        for p in 0..points {
            let r = PointRecord::read(&out, p)
                .map_err(|e| format!("point {p}: {e}"))?
                .ok_or_else(|| format!("point {p} has no record in {}", out.display()))?;
            sum_run_s += r.run_s;
            sum_point_wall_s += r.wall_s;
            if r.status != PointStatus::Ok {
                not_ok += 1;
            }
        }
        if regimes.is_empty() {
            let table = MapTable::read(&out).map_err(|e| format!("{}: {e}", out.display()))?;
            regimes = table
                .regime_counts()
                .into_iter()
                .map(|(r, n)| (r.name().to_string(), n))
                .collect();
        }
        runs.push(SweepRun {
            jobs,
            wall_s: inv.wall_s,
            sum_run_s,
            sum_point_wall_s,
            not_ok,
        });
    }
    Ok(SweepBench {
        sweep_toml: text,
        points,
        nodes,
        runs,
        regimes,
    })
}
