//! Running a sweep: the points of a shard in-process on `jobs` threads, each point one run of
//! the driver reduced to its record; resumable (points whose record is this sweep's and this
//! build's are skipped, those of another build or damaged ones run again, a record of another
//! sweep is refused), interruptible (a point stopped mid-run leaves no record and reruns next
//! time). A shard that ran all its points writes its table for the merge
//! ([`super::merge::write_table`]).
//!
//! Nothing is listed per point up front: the shard's points are counted off by number, the
//! existing records are found with one listing of `points/`, and each record is read and
//! checked when its point comes up, so a sweep of a million points starts at once.

use super::Sweep;
use super::map::MapRow;
use super::record::{Found, PointRecord, PointStatus, listed};
use super::refine::{self, Refine};
use std::collections::BTreeMap;
use std::io;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use stickslip_run::driver::{Control, NullSink};
use stickslip_run::outcome::StopReason;
use stickslip_run::sink::dir::{DirOptions, DirSink};

use super::lock::io_err;
pub use super::lock::{
    LockWatch, Prepared, SWEEP_FILE, SweepLock, SweepRunError, load_lock, prepare,
};
pub use super::merge::{MapRead, Merge, MergeCost, after_shard, merge, merge_wait, read_map};

/// How to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepOptions {
    /// Points run in parallel (≥ 1).
    pub jobs: usize,
    /// Shard index I of N: the points with index mod N = I.
    pub shard: (usize, usize),
    /// Keep every point's full output in `DIR/runs/<point>/` (else only its record).
    pub keep_all: bool,
    /// Start afresh: remove the directory's earlier results (of this sweep or another) before
    /// running ([`prepare`]).
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

/// Progress of a shard.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepProgress {
    /// Points of the shard finished by this process.
    pub done: usize,
    /// Points of the shard to run in this process (those found finished so far left out).
    pub total: usize,
    /// Points of the shard found finished so far (their records are this sweep's and this
    /// build's).
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
    /// Points skipped (already finished by this build).
    pub skipped: usize,
    /// Points that failed numerically.
    pub failed: usize,
    /// Points refused.
    pub refused: usize,
    /// Of the points run, those that had a record computed by another build: that build's
    /// identity → count.
    pub recomputed: BTreeMap<String, usize>,
    /// Of the points run, those whose record was damaged (cut short or emptied).
    pub damaged: usize,
    /// Interrupted before every point of the shard had run.
    pub interrupted: bool,
    /// Wall-clock seconds of the shard.
    pub wall_s: f64,
    /// Sum over the points run of their own wall-clock seconds.
    pub points_wall_s: f64,
    /// Sum over the points run of the seconds spent in the driver (simulation proper).
    pub points_run_s: f64,
    /// A refined sweep: the levels this shard reached (its part of each ran).
    pub levels: usize,
    /// A refined sweep: the level at which the shard stopped because other shards' points
    /// of it are missing (their results decide the next level's points); `None` when it ran
    /// every level (or the sweep is not refined).
    pub waiting: Option<Waiting>,
    /// A refined sweep whose levels this shard found complete: the map it wrote.
    pub map: Option<Merge>,
}

/// A shard of a refined sweep waiting for others ([`ShardReport::waiting`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Waiting {
    /// The level (0: the base grid) whose points other shards have not finished.
    pub level: usize,
    /// How many of its points have no current record yet.
    pub missing: usize,
}

impl ShardReport {
    /// Why points ran again, in words (`""` when none did): "3 points recomputed: computed by
    /// build 1a2b…, this is build 3c4d…; 1 damaged record".
    #[must_use]
    pub fn recomputed_text(&self) -> String {
        let mut parts: Vec<String> = self
            .recomputed
            .iter()
            .map(|(build, n)| {
                format!(
                    "{n} point{} recomputed: computed by build {build}, this is build {}",
                    if *n == 1 { "" } else { "s" },
                    stickslip_run::build_id::BUILD_ID
                )
            })
            .collect();
        if self.damaged > 0 {
            parts.push(format!(
                "{} point{} rerun: damaged record",
                self.damaged,
                if self.damaged == 1 { "" } else { "s" }
            ));
        }
        parts.join("; ")
    }
}

/// Why a point ran although its record file existed.
#[derive(Debug, Clone)]
enum Again {
    Build(String),
    Damaged,
}

/// What became of one point.
enum Done {
    Ran(Box<PointRecord>, f64, Option<Again>),
    Skipped(Box<PointRecord>),
    Interrupted,
}

/// What the workers share.
struct Shard<'a> {
    sweep: &'a Sweep,
    dir: &'a Path,
    fingerprint: String,
    keep_all: bool,
    interrupt: Option<&'a AtomicBool>,
    watch: LockWatch,
    /// Point numbers with a record file when the shard started.
    listed: Vec<usize>,
}

impl Shard<'_> {
    /// Runs point `p` unless its record is current.
    fn point(&self, p: usize) -> Result<Done, SweepRunError> {
        let values = self.sweep.values(p);
        let mut again = None;
        if self.listed.binary_search(&p).is_ok() {
            match PointRecord::find(self.dir, p, &values, &self.fingerprint)
                .map_err(io_err(self.dir))?
            {
                Found::Current(r) => return Ok(Done::Skipped(r)),
                Found::OtherBuild { build } => again = Some(Again::Build(build)),
                Found::Damaged => again = Some(Again::Damaged),
                Found::Missing => {}
                Found::OtherSweep { why } => {
                    return Err(SweepRunError::Foreign {
                        path: PointRecord::path(self.dir, p),
                        why,
                    });
                }
            }
        }
        Ok(match self.run(p, values)? {
            Some((record, run_s)) => Done::Ran(Box::new(record), run_s, again),
            None => Done::Interrupted,
        })
    }

    /// Runs point `p` and writes its record; `None` when interrupted (no record written).
    fn run(
        &self,
        p: usize,
        values: Vec<toml::Value>,
    ) -> Result<Option<(PointRecord, f64)>, SweepRunError> {
        let start = Instant::now();
        let fail = |e: String| io_err(self.dir)(io::Error::other(format!("point {p}: {e}")));
        let mut record = match self.sweep.scene(p) {
            // Beyond MAX_POINTS a point's scene is first resolved here: a combination of
            // values the scene refuses is a refused point, as a refused configuration is.
            Err(e) => PointRecord::refused(p, values, &e.to_string(), 0.0),
            Ok(scene) => {
                let mut control = Control {
                    interrupt: self.interrupt,
                    thresholds: self.sweep.thresholds,
                    ..Control::default()
                };
                let run_start = Instant::now();
                let outcome = if self.keep_all {
                    let run_dir = self.dir.join("runs").join(format!("{p:07}"));
                    let options = DirOptions {
                        force: true,
                        checkpoint_every_s: 0.0,
                    };
                    let mut sink =
                        DirSink::create(&run_dir, &options).map_err(|e| fail(e.to_string()))?;
                    stickslip_run::driver::run(&scene, &mut sink, &mut control)
                        .map_err(|e| fail(e.to_string()))?
                } else {
                    stickslip_run::driver::run(&scene, &mut NullSink, &mut control)
                        .map_err(|e| fail(e.to_string()))?
                };
                let run_s = run_start.elapsed().as_secs_f64();
                if outcome.stop == StopReason::Interrupted {
                    return Ok(None);
                }
                PointRecord::of(p, values, &outcome, 0.0, run_s)
            }
        };
        record.fingerprint.clone_from(&self.fingerprint);
        record.level = self.sweep.level(p);
        // The directory must still be this sweep's: one metadata look-up per record.
        self.watch.check()?;
        // The point's wall time is measured just before its record is written; the write's own
        // cost (an unsynced write and a rename) is the part left out, and the sweep's overhead
        // in `cargo xtask bench` (P5) counts it.
        record.wall_s = start.elapsed().as_secs_f64();
        if let Err(e) = record.write(self.dir) {
            // A --force of another sweep removes points/ after sweep.json: a write that fails
            // in that instant is the takeover, not an I/O error of this sweep.
            self.watch.check()?;
            return Err(fail(format!("cannot write its record: {e}")));
        }
        let run_s = record.run_s;
        Ok(Some((record, run_s)))
    }
}

/// Runs the points of `options.shard` whose record is not current, `options.jobs` at a time;
/// `progress` is called about five times a second. A shard that ran to its end writes its
/// table (`DIR/shards/`) for the merge.
///
/// A refined sweep ([`Sweep::refine`]) runs level by level: the shard's part of a level is
/// every N-th of the level's points in point order, starting at its index I; the next level's
/// points are computed from every shard's results of this one ([`super::refine::next_points`]).
/// When other shards' points of a level are missing, the shard stops there
/// ([`ShardReport::waiting`]): a rerun once they finished skips what is done and goes on. The
/// shard that finds every level complete writes the map itself ([`ShardReport::map`]; it read
/// every point's record on the way) and no shard table: a refined shard reads the records of
/// every level it passes, so an array of N tasks reads about N·P records in all.
///
/// # Errors
/// [`SweepRunError::Foreign`] for a record of another sweep, [`SweepRunError::TakenOver`]
/// when the directory changes sweep meanwhile, I/O errors (a record that cannot be written or
/// read).
pub fn run_shard(
    sweep: &Sweep,
    dir: &Path,
    options: &SweepOptions,
    interrupt: Option<&AtomicBool>,
    progress: &mut dyn FnMut(&SweepProgress),
) -> Result<ShardReport, SweepRunError> {
    let started = Instant::now();
    let (index, count) = options.shard;
    let fingerprint = sweep.fingerprint();
    let shard = Shard {
        sweep,
        dir,
        keep_all: options.keep_all,
        interrupt,
        watch: LockWatch::new(dir, &fingerprint),
        listed: listed(dir).map_err(io_err(dir))?,
        fingerprint,
    };
    shard.watch.check()?;
    let mut run = Runner {
        shard: &shard,
        jobs: options.jobs.max(1),
        started,
        report: ShardReport::default(),
        offered: 0,
        progress,
    };
    if let Some(refine) = &sweep.refine {
        run_refined(&mut run, refine, options.shard)?;
    } else {
        let len = sweep.shard_len(index, count);
        let rows = run.points(len, &|k| index + k * count)?;
        match rows {
            Some(rows) if !run.report.interrupted => {
                shard.watch.check()?;
                super::merge::write_table(dir, sweep, &shard.fingerprint, options.shard, &rows)?;
            }
            _ => run.report.interrupted = true,
        }
    }
    let mut report = run.report;
    report.wall_s = started.elapsed().as_secs_f64();
    Ok(report)
}

/// The levels of a refined sweep for one shard (see [`run_shard`]).
fn run_refined(
    run: &mut Runner<'_, '_>,
    refine: &Refine,
    (index, count): (usize, usize),
) -> Result<(), SweepRunError> {
    let shard = run.shard;
    let (sweep, dir) = (shard.sweep, shard.dir);
    let mut known: BTreeMap<usize, MapRow> = BTreeMap::new();
    let mut set = refine::base_points(sweep, refine);
    let mut level = 0;
    // Records of other shards read.
    let mut read = 0;
    loop {
        let part: Vec<usize> = set.iter().copied().skip(index).step_by(count).collect();
        let Some(rows) = run.points(part.len(), &|k| part[k])? else {
            run.report.interrupted = true;
            return Ok(());
        };
        if run.report.interrupted {
            return Ok(());
        }
        for r in &rows {
            known.insert(r.point, MapRow::of(r));
        }
        // The other shards' points of this level.
        let mut missing = 0;
        read += set.len() - part.len();
        for (k, &p) in set.iter().enumerate() {
            if k % count == index {
                continue;
            }
            match PointRecord::find(dir, p, &sweep.values(p), &shard.fingerprint)
                .map_err(io_err(dir))?
            {
                Found::Current(r) => {
                    known.insert(p, MapRow::of(&r));
                }
                Found::OtherSweep { why } => {
                    return Err(SweepRunError::Foreign {
                        path: PointRecord::path(dir, p),
                        why,
                    });
                }
                Found::Missing | Found::Damaged | Found::OtherBuild { .. } => missing += 1,
            }
        }
        run.report.levels = level + 1;
        if missing > 0 {
            run.report.waiting = Some(Waiting { level, missing });
            return Ok(());
        }
        level += 1;
        set = refine::next_points(sweep, refine, level, &known);
        if set.is_empty() {
            break;
        }
    }
    // Every level is complete, and this shard read every point's current record: it writes
    // the map (several shards finishing together write the same one, atomically).
    shard.watch.check()?;
    let merge = super::merge::write_map(
        dir,
        sweep,
        known.into_values().collect(),
        MergeCost {
            records_read: read,
            ..MergeCost::default()
        },
        Instant::now(),
    )?;
    run.report.map = Some(merge);
    Ok(())
}

/// Runs lists of points on `jobs` threads, gathering the report.
struct Runner<'a, 'p> {
    shard: &'a Shard<'a>,
    jobs: usize,
    started: Instant,
    report: ShardReport,
    /// Points offered to run so far (earlier levels included), for the progress.
    offered: usize,
    progress: &'p mut dyn FnMut(&SweepProgress),
}

impl Runner<'_, '_> {
    /// Runs the `len` points `at(0)`, …, `at(len − 1)` (skipping current records): their
    /// records in that order, or `None` when interrupted before all of them finished.
    fn points(
        &mut self,
        len: usize,
        at: &(dyn Fn(usize) -> usize + Sync),
    ) -> Result<Option<Vec<PointRecord>>, SweepRunError> {
        let shard = self.shard;
        let interrupt = shard.interrupt;
        let next = AtomicUsize::new(0);
        let stop = AtomicBool::new(false);
        let stopped =
            || stop.load(Ordering::Relaxed) || interrupt.is_some_and(|f| f.load(Ordering::Relaxed));
        let offered = self.offered;
        self.offered += len;
        let report = &mut self.report;
        let progress = &mut *self.progress;
        let started = self.started;
        let mut rows: Vec<Option<PointRecord>> = Vec::new();
        rows.resize_with(len, || None);
        let mut first_error: Option<SweepRunError> = None;
        std::thread::scope(|s| {
            let (tx, rx) = mpsc::channel();
            for _ in 0..self.jobs {
                let tx = tx.clone();
                let (next, stopped) = (&next, &stopped);
                s.spawn(move || {
                    loop {
                        if stopped() {
                            break;
                        }
                        let k = next.fetch_add(1, Ordering::Relaxed);
                        if k >= len {
                            break;
                        }
                        let result = shard.point(at(k));
                        if tx.send((k, result)).is_err() {
                            break;
                        }
                    }
                });
            }
            drop(tx);
            let tick = Duration::from_millis(200);
            loop {
                match rx.recv_timeout(tick) {
                    Ok((k, Ok(Done::Ran(record, run_s, again)))) => {
                        report.ran += 1;
                        report.points_wall_s += record.wall_s;
                        report.points_run_s += run_s;
                        match record.status {
                            PointStatus::Failed => report.failed += 1,
                            PointStatus::Refused => report.refused += 1,
                            PointStatus::Ok => {}
                        }
                        match again {
                            Some(Again::Build(b)) => {
                                *report.recomputed.entry(b).or_insert(0) += 1;
                            }
                            Some(Again::Damaged) => report.damaged += 1,
                            None => {}
                        }
                        rows[k] = Some(*record);
                    }
                    Ok((k, Ok(Done::Skipped(record)))) => {
                        report.skipped += 1;
                        rows[k] = Some(*record);
                    }
                    Ok((_, Ok(Done::Interrupted))) => report.interrupted = true,
                    Ok((_, Err(e))) => {
                        first_error.get_or_insert(e);
                        stop.store(true, Ordering::Relaxed);
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    Err(mpsc::RecvTimeoutError::Disconnected) => break,
                }
                progress(&SweepProgress {
                    done: report.ran,
                    total: offered + len - report.skipped,
                    skipped: report.skipped,
                    failed: report.failed + report.refused,
                    elapsed_s: started.elapsed().as_secs_f64(),
                });
            }
        });
        if let Some(e) = first_error {
            return Err(e);
        }
        Ok(rows.into_iter().collect())
    }
}
