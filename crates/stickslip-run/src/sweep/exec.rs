//! Running a sweep: the points of a shard in-process on `jobs` threads, each point one run of
//! the driver reduced to its record; resumable (finished points are skipped), interruptible
//! (a point stopped mid-run leaves no record and reruns next time); then the merge into
//! map.csv and map.json once every point has its record.
//!
//! `DIR/sweep.json` holds the sweep as resolved; a directory holding another sweep's points
//! is refused unless `force`, which removes them first.

use super::Sweep;
use super::map::{CSV_FILE, JSON_FILE, MapJson, MapRow, MapTable};
use super::record::{PointRecord, PointStatus};
use crate::atomic::write_atomic;
use crate::driver::{Control, NullSink};
use crate::outcome::StopReason;
use crate::sink::dir::{DirOptions, DirSink};
use crate::summary::Regime;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use thiserror::Error;

/// File name of the resolved sweep in its directory.
pub const SWEEP_FILE: &str = "sweep.json";

/// How to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepOptions {
    /// Points run in parallel (≥ 1).
    pub jobs: usize,
    /// Shard index I of N: the points with index mod N = I.
    pub shard: (usize, usize),
    /// Keep every point's full output in `DIR/runs/<point>/` (else only its record).
    pub keep_all: bool,
    /// Replace another sweep's results in the directory.
    pub force: bool,
}

impl Default for SweepOptions {
    fn default() -> Self {
        Self {
            jobs: 1,
            shard: (0, 1),
            keep_all: false,
            force: false,
        }
    }
}

/// Why a sweep could not run or merge.
#[derive(Debug, Error)]
pub enum SweepRunError {
    /// The directory holds another sweep (exit 2).
    #[error(
        "{dir} holds the results of another sweep (its sweep.json differs); allowed: the \
         directory of this sweep, a new one, or --force to replace them"
    )]
    Other {
        /// The directory.
        dir: String,
    },
    /// No sweep in the directory (exit 2).
    #[error("no sweep in {dir} ({why}); allowed: a directory written by `stickslip sweep run`")]
    Missing {
        /// The directory.
        dir: String,
        /// What is missing.
        why: String,
    },
    /// An I/O error (exit 1).
    #[error("sweep directory {path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: io::Error,
    },
}

fn io_err(path: &Path) -> impl FnOnce(io::Error) -> SweepRunError + '_ {
    move |source| SweepRunError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// `DIR/sweep.json`: the resolved sweep and its fingerprint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepLock {
    /// What decides every point's outcome.
    pub fingerprint: String,
    /// The sweep.
    pub sweep: Sweep,
}

/// Readies `dir` for `sweep`: creates it and writes `sweep.json`, or checks that the one there
/// is this sweep's; with `force`, another sweep's files are removed first.
///
/// # Errors
/// [`SweepRunError::Other`] for another sweep's directory without `force`; I/O errors.
pub fn prepare(sweep: &Sweep, dir: &Path, force: bool) -> Result<(), SweepRunError> {
    let lock = SweepLock {
        fingerprint: sweep.fingerprint(),
        sweep: sweep.clone(),
    };
    let path = dir.join(SWEEP_FILE);
    if let Ok(text) = std::fs::read_to_string(&path) {
        let same = serde_json::from_str::<SweepLock>(&text)
            .is_ok_and(|old| old.fingerprint == lock.fingerprint);
        if same {
            return Ok(());
        }
        if !force {
            return Err(SweepRunError::Other {
                dir: dir.display().to_string(),
            });
        }
        for sub in ["points", "runs"] {
            match std::fs::remove_dir_all(dir.join(sub)) {
                Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(io_err(dir)(e)),
                _ => {}
            }
        }
        for f in [CSV_FILE, JSON_FILE] {
            match std::fs::remove_file(dir.join(f)) {
                Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(io_err(dir)(e)),
                _ => {}
            }
        }
    }
    std::fs::create_dir_all(dir.join("points")).map_err(io_err(dir))?;
    let text = serde_json::to_string_pretty(&lock).map_err(|e| io_err(dir)(io::Error::other(e)))?;
    write_atomic(dir, SWEEP_FILE, text.as_bytes()).map_err(io_err(dir))
}

/// Reads `DIR/sweep.json`.
///
/// # Errors
/// [`SweepRunError::Missing`] when there is none or it cannot be parsed.
pub fn load_lock(dir: &Path) -> Result<SweepLock, SweepRunError> {
    let missing = |why: String| SweepRunError::Missing {
        dir: dir.display().to_string(),
        why,
    };
    let text = std::fs::read_to_string(dir.join(SWEEP_FILE))
        .map_err(|e| missing(format!("{SWEEP_FILE}: {e}")))?;
    serde_json::from_str(&text).map_err(|e| missing(format!("{SWEEP_FILE}: {e}")))
}

/// Progress of a shard.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepProgress {
    /// Points of the shard finished by this process.
    pub done: usize,
    /// Points of the shard to run in this process (finished ones skipped).
    pub total: usize,
    /// Points of the shard that had a record already.
    pub skipped: usize,
    /// Points that failed or were refused so far.
    pub failed: usize,
    /// Seconds since the shard started.
    pub elapsed_s: f64,
}

/// What a shard did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ShardReport {
    /// Points run.
    pub ran: usize,
    /// Points skipped (already finished).
    pub skipped: usize,
    /// Points that failed numerically.
    pub failed: usize,
    /// Points refused.
    pub refused: usize,
    /// Interrupted before every point of the shard had run.
    pub interrupted: bool,
    /// Wall-clock seconds of the shard.
    pub wall_s: f64,
    /// Sum over the points run of their own wall-clock seconds.
    pub points_wall_s: f64,
    /// Sum over the points run of the seconds spent in the driver (simulation proper).
    pub points_run_s: f64,
}

/// Runs point `p`; `None` when interrupted (no record written).
fn run_point(
    sweep: &Sweep,
    dir: &Path,
    p: usize,
    keep_all: bool,
    interrupt: Option<&AtomicBool>,
) -> Result<Option<(PointRecord, f64)>, String> {
    let start = Instant::now();
    let scene = sweep.scene(p).map_err(|e| format!("point {p}: {e}"))?;
    let mut control = Control {
        interrupt,
        thresholds: sweep.thresholds,
        ..Control::default()
    };
    let run_start = Instant::now();
    let outcome = if keep_all {
        let run_dir = dir.join("runs").join(format!("{p:07}"));
        let options = DirOptions {
            force: true,
            checkpoint_every_s: 0.0,
        };
        let mut sink = DirSink::create(&run_dir, &options).map_err(|e| e.to_string())?;
        crate::driver::run(&scene, &mut sink, &mut control).map_err(|e| e.to_string())?
    } else {
        crate::driver::run(&scene, &mut NullSink, &mut control).map_err(|e| e.to_string())?
    };
    let run_s = run_start.elapsed().as_secs_f64();
    if outcome.stop == StopReason::Interrupted {
        return Ok(None);
    }
    let mut record = PointRecord::of(p, sweep.values(p), &outcome, 0.0, run_s);
    // The point's wall time is measured just before its record is written; the write's own
    // cost (an unsynced write and a rename) is the part left out, and the sweep's overhead in
    // `cargo xtask bench` (P5) counts it.
    record.wall_s = start.elapsed().as_secs_f64();
    record
        .write(dir)
        .map_err(|e| format!("point {p}: cannot write its record: {e}"))?;
    Ok(Some((record, run_s)))
}

/// Runs the points of `options.shard` that have no record yet, `options.jobs` at a time;
/// `progress` is called about five times a second.
///
/// # Errors
/// I/O errors (a record that cannot be written or read).
pub fn run_shard(
    sweep: &Sweep,
    dir: &Path,
    options: &SweepOptions,
    interrupt: Option<&AtomicBool>,
    progress: &mut dyn FnMut(&SweepProgress),
) -> Result<ShardReport, SweepRunError> {
    let started = Instant::now();
    let (index, count) = options.shard;
    let mut pending = Vec::new();
    let mut skipped = 0;
    for p in sweep.shard(index, count) {
        match PointRecord::read(dir, p).map_err(io_err(dir))? {
            Some(_) => skipped += 1,
            None => pending.push(p),
        }
    }
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let stopped =
        || stop.load(Ordering::Relaxed) || interrupt.is_some_and(|f| f.load(Ordering::Relaxed));
    let mut report = ShardReport {
        skipped,
        ..ShardReport::default()
    };
    let mut first_error: Option<String> = None;
    std::thread::scope(|s| {
        let (tx, rx) = mpsc::channel();
        for _ in 0..options.jobs.max(1) {
            let tx = tx.clone();
            let (next, pending, stopped) = (&next, &pending, &stopped);
            s.spawn(move || {
                loop {
                    if stopped() {
                        break;
                    }
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&p) = pending.get(k) else { break };
                    let result = run_point(sweep, dir, p, options.keep_all, interrupt);
                    if tx.send(result).is_err() {
                        break;
                    }
                }
            });
        }
        drop(tx);
        let tick = Duration::from_millis(200);
        loop {
            match rx.recv_timeout(tick) {
                Ok(Ok(Some((record, run_s)))) => {
                    report.ran += 1;
                    report.points_wall_s += record.wall_s;
                    report.points_run_s += run_s;
                    match record.status {
                        PointStatus::Failed => report.failed += 1,
                        PointStatus::Refused => report.refused += 1,
                        PointStatus::Ok => {}
                    }
                }
                Ok(Ok(None)) => report.interrupted = true,
                Ok(Err(e)) => {
                    first_error.get_or_insert(e);
                    stop.store(true, Ordering::Relaxed);
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            progress(&SweepProgress {
                done: report.ran,
                total: pending.len(),
                skipped,
                failed: report.failed + report.refused,
                elapsed_s: started.elapsed().as_secs_f64(),
            });
        }
    });
    if interrupt.is_some_and(|f| f.load(Ordering::Relaxed)) && report.ran < pending.len() {
        report.interrupted = true;
    }
    report.wall_s = started.elapsed().as_secs_f64();
    match first_error {
        Some(e) => Err(io_err(dir)(io::Error::other(e))),
        None => Ok(report),
    }
}

/// The result of a merge.
#[derive(Debug, Clone, PartialEq)]
pub enum Merge {
    /// Every point has its record: map.csv and map.json are written.
    Complete {
        /// The table.
        table: MapTable,
        /// Points per status.
        statuses: BTreeMap<String, usize>,
        /// Points per regime (status ok).
        regimes: BTreeMap<Regime, usize>,
    },
    /// Points without a record (shards still running or interrupted).
    Incomplete {
        /// How many.
        missing: usize,
        /// Of how many.
        points: usize,
    },
}

/// Merges the records in `dir` into map.csv and map.json when every point has one.
///
/// # Errors
/// No sweep in `dir`, or I/O errors (a damaged record counts as missing).
pub fn merge(dir: &Path) -> Result<Merge, SweepRunError> {
    let lock = load_lock(dir)?;
    let sweep = &lock.sweep;
    let mut rows = Vec::with_capacity(sweep.points);
    let mut missing = 0;
    for p in 0..sweep.points {
        match PointRecord::read(dir, p).map_err(io_err(dir))? {
            Some(r) => rows.push(MapRow::of(&r)),
            None => missing += 1,
        }
    }
    if missing > 0 {
        return Ok(Merge::Incomplete {
            missing,
            points: sweep.points,
        });
    }
    let table = MapTable {
        axes: sweep.axes.iter().map(|a| a.key.clone()).collect(),
        rows,
    };
    write_atomic(dir, CSV_FILE, table.to_csv().as_bytes()).map_err(io_err(dir))?;
    let json = MapJson::new(sweep, table.clone());
    let mut text =
        serde_json::to_string_pretty(&json).map_err(|e| io_err(dir)(io::Error::other(e)))?;
    text.push('\n');
    write_atomic(dir, JSON_FILE, text.as_bytes()).map_err(io_err(dir))?;
    let mut statuses = BTreeMap::new();
    for r in &table.rows {
        *statuses.entry(r.status.name().to_string()).or_insert(0) += 1;
    }
    Ok(Merge::Complete {
        regimes: table.regime_counts(),
        statuses,
        table,
    })
}
