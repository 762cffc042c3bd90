//! A sweep's spot checks (`[verify]`): once the map is complete, some of its points are run
//! again at a refined resolution — twice the nodes, and a tenth of the tolerance (or half the
//! fixed step), the first refinement along each axis `verify` makes — and map.json records
//! what changed.
//!
//! The points checked are a sample spread evenly over the map in point order (`sample`, a
//! share of its points, or `points`, a count) and, with `boundaries` (the default), every
//! point whose neighbour along an axis has another regime (in a refined map the nearest point
//! that ran along that axis; a failed or refused point counts as a class of its own). Only
//! points that ran `ok` are checked.
//!
//! Each check is one record, `DIR/checks/<point>.json` ([`super::checks`]), written atomically
//! with the sweep's fingerprint: a rerun skips the checks already made by this build, and a
//! kill loses only the checks in hand. The checks do not change the sweep's definition (its points' results do
//! not depend on them): adding `[verify]` to a finished sweep reruns only the checks.

use super::Sweep;
pub use super::checks::{CheckRecord, CheckRun, Reason, SpotChecks, SpotReport};
use super::file::{SweepError, VerifyFile};
use super::lock::{CHECKS_DIR, SweepRunError, io_err};
use super::map::{JSON_FILE, MapJson, MapRow, MapTable};
use super::record::PointStatus;
use crate::verify::{Axis, refinements};
use std::collections::HashMap;
use std::io;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;
use stickslip_run::atomic::write_atomic;
use stickslip_run::driver::{Control, NullSink};
use stickslip_run::outcome::StopReason;
use stickslip_run::summary::RunSummary;

/// Resolves `[verify]`.
///
/// # Errors
/// A share outside (0, 1], a count < 1, both given, or nothing to check.
pub fn resolve(file: &VerifyFile) -> Result<SpotChecks, SweepError> {
    let boundaries = file.boundaries.unwrap_or(true);
    if let Some(f) = file.sample
        && !(f > 0.0 && f <= 1.0)
    {
        return Err(SweepError::invalid(
            "verify.sample",
            stickslip_run::keys::human(f),
            "a share of the map's points, 0 < sample <= 1",
        ));
    }
    if let Some(n) = file.points
        && n < 1
    {
        return Err(SweepError::invalid(
            "verify.points",
            n,
            "a number of points >= 1",
        ));
    }
    if file.sample.is_some() && file.points.is_some() {
        return Err(SweepError::invalid(
            "verify.points",
            file.points.unwrap_or_default(),
            "either verify.sample or verify.points, not both",
        ));
    }
    if file.sample.is_none() && file.points.is_none() && !boundaries {
        return Err(SweepError::invalid(
            "verify.boundaries",
            "false",
            "true, or a sample (verify.sample or verify.points): nothing would be checked",
        ));
    }
    Ok(SpotChecks {
        sample: file.sample,
        points: file
            .points
            .map(|n| usize::try_from(n).unwrap_or(usize::MAX)),
        boundaries,
    })
}

/// The points of `table` to check, in point order, with why.
#[must_use]
pub fn select(sweep: &Sweep, spot: &SpotChecks, table: &MapTable) -> Vec<(usize, Reason)> {
    let ok: Vec<&MapRow> = table
        .rows
        .iter()
        .filter(|r| r.status == PointStatus::Ok)
        .collect();
    let mut chosen: std::collections::BTreeMap<usize, Reason> = Default::default();
    let n = match (spot.sample, spot.points) {
        (Some(f), _) => (f * ok.len() as f64).ceil() as usize,
        (None, Some(n)) => n,
        (None, None) => 0,
    }
    .min(ok.len());
    // Evenly spread in point order: the middle of each of n equal runs of rows.
    for k in 0..n {
        let i = ((2 * k + 1) * ok.len()) / (2 * n);
        chosen.insert(ok[i.min(ok.len() - 1)].point, Reason::Sample);
    }
    if spot.boundaries {
        for p in boundary_points(sweep, table) {
            chosen
                .entry(p)
                .and_modify(|r| *r = Reason::Both)
                .or_insert(Reason::Boundary);
        }
    }
    let ok_points: std::collections::HashSet<usize> = ok.iter().map(|r| r.point).collect();
    chosen
        .into_iter()
        .filter(|(p, _)| ok_points.contains(p))
        .collect()
}

/// The points that ran `ok` whose nearest neighbour along some axis has another class (regime,
/// or status when not ok).
fn boundary_points(sweep: &Sweep, table: &MapTable) -> Vec<usize> {
    let class = |r: &MapRow| match r.status {
        PointStatus::Ok => r.summary.regime.name(),
        other => other.name(),
    };
    let at: HashMap<Vec<usize>, &'static str> = table
        .rows
        .iter()
        .map(|r| (sweep.indices(r.point), class(r)))
        .collect();
    let mut out = Vec::new();
    for r in table.rows.iter().filter(|r| r.status == PointStatus::Ok) {
        let idx = sweep.indices(r.point);
        let mine = class(r);
        let differs = (0..idx.len()).any(|d| {
            let len = sweep.axes[d].values.len();
            [-1_i64, 1].iter().any(|&dir| {
                let mut j = idx.clone();
                loop {
                    let next = j[d] as i64 + dir;
                    if next < 0 || next >= len as i64 {
                        return false;
                    }
                    j[d] = next as usize;
                    if let Some(c) = at.get(&j) {
                        return *c != mine;
                    }
                }
            })
        });
        if differs {
            out.push(r.point);
        }
    }
    out
}

/// The largest relative change between two summaries' numbers, with its column.
fn max_change(base: &RunSummary, other: &RunSummary) -> Option<(String, f64)> {
    let pairs = [
        ("t_first_onset", base.t_first_onset, other.t_first_onset),
        ("period_last", base.period_last, other.period_last),
        ("f_peak_first", base.f_peak_first, other.f_peak_first),
        ("f_peak_last", base.f_peak_last, other.f_peak_last),
        ("f_mean", base.f_mean, other.f_mean),
    ];
    pairs
        .iter()
        .filter_map(|(name, a, b)| match (a, b) {
            (Some(a), Some(b)) if *a != 0.0 => Some((name.to_string(), ((b - a) / a).abs())),
            _ => None,
        })
        .max_by(|x, y| x.1.total_cmp(&y.1))
}

/// Runs (or finds done) the spot checks of the complete map in `dir`, `jobs` at a time, and
/// rewrites map.json with them. `progress(done, total)` is called as checks end. `Ok(None)`
/// when interrupted (the checks finished are kept).
///
/// # Errors
/// The map cannot be read or written, a check's record cannot be written.
pub fn run_checks(
    sweep: &Sweep,
    spot: &SpotChecks,
    dir: &Path,
    jobs: usize,
    interrupt: Option<&AtomicBool>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Option<SpotReport>, SweepRunError> {
    let started = Instant::now();
    let mut map = MapJson::read(dir).map_err(|e| io_err(dir)(io::Error::other(e.to_string())))?;
    let chosen = select(sweep, spot, &map.table);
    std::fs::create_dir_all(dir.join(CHECKS_DIR)).map_err(io_err(dir))?;
    let fingerprint = sweep.fingerprint();
    let rows: HashMap<usize, &MapRow> = map.table.rows.iter().map(|r| (r.point, r)).collect();
    let done = AtomicUsize::new(0);
    let skipped = AtomicUsize::new(0);
    let total = chosen.len();
    let check = |k: usize| -> Result<Option<CheckRecord>, SweepRunError> {
        let (p, reason) = chosen[k];
        let values = sweep.values(p);
        if let Some(r) = CheckRecord::current(dir, p, &values, &fingerprint) {
            skipped.fetch_add(1, Ordering::Relaxed);
            done.fetch_add(1, Ordering::Relaxed);
            return Ok(Some(r));
        }
        let fail = |e: String| io_err(dir)(io::Error::other(format!("check of point {p}: {e}")));
        let scene = sweep.scene(p).map_err(|e| fail(e.to_string()))?;
        let refined = refinements(&scene).map_err(|e| fail(e.to_string()))?;
        let base = &rows[&p].summary;
        let mut runs = Vec::new();
        for (axis, s) in &refined {
            if interrupt.is_some_and(|f| f.load(Ordering::Relaxed)) {
                return Ok(None);
            }
            let start = Instant::now();
            let mut control = Control {
                interrupt,
                thresholds: sweep.thresholds,
                ..Control::default()
            };
            let outcome = stickslip_run::driver::run(s, &mut NullSink, &mut control)
                .map_err(|e| fail(e.to_string()))?;
            if outcome.stop == StopReason::Interrupted {
                return Ok(None);
            }
            let status = match outcome.stop {
                StopReason::Failure => PointStatus::Failed,
                StopReason::Refused => PointStatus::Refused,
                _ => PointStatus::Ok,
            };
            runs.push(CheckRun {
                refinement: match (axis, s.config.time.adaptive.is_some()) {
                    (Axis::Space, _) => "2N".into(),
                    (Axis::Time, true) => "tolerance/10".into(),
                    (Axis::Time, false) => "dt/2".into(),
                },
                status,
                max_change: max_change(base, &outcome.summary),
                summary: outcome.summary,
                wall_s: start.elapsed().as_secs_f64(),
            });
        }
        let changed = runs
            .iter()
            .any(|r| r.status != PointStatus::Ok || r.summary.regime != base.regime);
        let record = CheckRecord {
            point: p,
            values,
            fingerprint: fingerprint.clone(),
            reason,
            regime: base.regime.name().to_string(),
            runs,
            changed,
        };
        record
            .write(dir)
            .map_err(|e| fail(format!("cannot write its record: {e}")))?;
        done.fetch_add(1, Ordering::Relaxed);
        Ok(Some(record))
    };
    // The costliest points first (by their own run's time), so that no long check is left
    // for one worker at the end while the others idle.
    let mut order: Vec<usize> = (0..total).collect();
    order.sort_by(|&a, &b| {
        let cost = |k: usize| rows[&chosen[k].0].wall_s;
        cost(b).total_cmp(&cost(a))
    });
    let results = crate::pool::map(total, jobs, &|k| check(order[k]), &mut || {
        progress(done.load(Ordering::Relaxed), total);
    });
    let mut by_item: Vec<Option<CheckRecord>> = (0..total).map(|_| None).collect();
    for (k, r) in order.into_iter().zip(results) {
        match r? {
            Some(c) => by_item[k] = Some(c),
            None => return Ok(None),
        }
    }
    let checks: Vec<CheckRecord> = by_item.into_iter().flatten().collect();
    // Among the checks whose regime held: a changed regime changes its numbers wholesale,
    // and is counted apart.
    let max = checks
        .iter()
        .filter(|c| !c.changed)
        .flat_map(|c| {
            c.runs
                .iter()
                .filter_map(move |r| r.max_change.clone().map(|(n, v)| (n, v, c.point)))
        })
        .max_by(|x, y| x.1.total_cmp(&y.1));
    let report = SpotReport {
        config: *spot,
        checked: checks.len(),
        sampled: checks
            .iter()
            .filter(|c| c.reason != Reason::Boundary)
            .count(),
        at_boundaries: checks.iter().filter(|c| c.reason != Reason::Sample).count(),
        changed: checks.iter().filter(|c| c.changed).count(),
        max_change: max,
        skipped: skipped.load(Ordering::Relaxed),
        checks,
        wall_s: started.elapsed().as_secs_f64(),
    };
    map.spot_checks = Some(report.clone());
    let mut text =
        serde_json::to_string_pretty(&map).map_err(|e| io_err(dir)(io::Error::other(e)))?;
    text.push('\n');
    write_atomic(dir, JSON_FILE, text.as_bytes()).map_err(io_err(dir))?;
    Ok(Some(report))
}
