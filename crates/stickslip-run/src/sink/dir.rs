//! The output directory of a run: streamed CSV files, events.csv, run.json from the start,
//! checkpoints, and [`resume`].
//!
//! **Safe outputs.** A directory that holds an earlier run's files (run.json, a CSV, a
//! checkpoint) is refused unless `force` is set, and nothing in it is touched. With `force`,
//! the earlier files are removed before the run writes anything, so old results never sit
//! beside a newer run's partial output. run.json is written before the first step with
//! `status: running`; the CSV files grow as `.<name>.tmp` and are renamed into place when the
//! run ends; then run.json is rewritten with the final status (`ok` or `failed`).
//!
//! **Checkpoints** every `checkpoint_every_s` of wall time (see [`crate::checkpoint`]), and at
//! once when the run is interrupted: then run.json says `interrupted`, what the run wrote so
//! far is published under the final names (a copy of each stream, written atomically, and
//! events.csv with the events so far), the streams stay under their temporary names, and
//! [`resume`] finishes the run bit-identically, replacing the copies. After a hard kill only
//! the temporary files and the last checkpoint are there; [`super::read`] reads a directory in
//! any of these states.

use crate::atomic::{AtomicFile, remove_temporaries, write_atomic};
use crate::checkpoint::{self, Checkpoint, CheckpointError, StreamPositions};
use crate::driver::{Control, Driver, RunStart, Sink, Snapshot, StartError};
use crate::outcome::{RunOutcome, StopReason};
use crate::scene::ResolvedScene;
use crate::schema::Table;
use crate::schema::events::Events;
use crate::schema::probes::Probes;
use crate::schema::profiles::Profiles;
use crate::schema::run_info::RunInfo;
use crate::schema::series::Series;
use crate::schema::slips::Slips;
use crate::schema::{self};
use std::borrow::Cow;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use stickslip_core::config::ConfigError;
use stickslip_core::sim::{Observables, SimState};
use thiserror::Error;

/// Default wall-clock interval between checkpoints, s.
pub const DEFAULT_CHECKPOINT_EVERY_S: f64 = checkpoint::DEFAULT_EVERY_S;

/// Loop iterations between looks at the clock: a look costs about as much as a step of the
/// one-node model, and even slow steps keep the delay well below a second.
const CLOCK_EVERY: u64 = 8;

/// Files that belong to a run (final names; temporary ones are `.<name>.tmp`).
pub const RUN_FILES: [&str; 6] = [
    schema::run_info::FILE,
    schema::series::FILE,
    schema::events::FILE,
    schema::profiles::FILE,
    schema::probes::FILE,
    checkpoint::FILE_NAME,
];

/// How to write into the directory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirOptions {
    /// Replace an earlier run's files (otherwise such a directory is refused).
    pub force: bool,
    /// Wall-clock interval between checkpoints, s; 0 = none (an interrupt still writes one).
    pub checkpoint_every_s: f64,
}

impl Default for DirOptions {
    fn default() -> Self {
        Self {
            force: false,
            checkpoint_every_s: DEFAULT_CHECKPOINT_EVERY_S,
        }
    }
}

/// How to resume.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ResumeOptions {
    /// Wall-clock interval between checkpoints from here on, s (`None`: the run's own).
    pub checkpoint_every_s: Option<f64>,
    /// Continue a checkpoint written by another build of the numerics (recorded in run.json's
    /// `resumed_across_builds`); otherwise it is refused.
    pub allow_other_build: bool,
}

/// Why a run into a directory did not happen or did not complete.
#[derive(Debug, Error)]
pub enum RunError {
    /// The configuration was rejected by the engine (exit 2).
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The directory holds an earlier run's results (exit 2).
    #[error(
        "{dir} holds the results of an earlier run ({files}); allowed: an empty or new \
         directory, --force to replace them, or `stickslip resume {dir}` to finish an \
         interrupted run"
    )]
    Existing {
        /// The directory.
        dir: String,
        /// The files found.
        files: String,
    },
    /// The directory holds another command's results (exit 2), which a run's files would mix
    /// with; `--force` replaces only an earlier run's.
    #[error(
        "{dir} holds the results of {what} ({files}): a run's files would mix with them; \
         allowed: an empty or new directory, or one of an earlier run (--force replaces only \
         a run's files)"
    )]
    Foreign {
        /// The directory.
        dir: String,
        /// The command whose files they are.
        what: String,
        /// The files found.
        files: String,
    },
    /// Another process is writing the directory (exit 2): it holds the directory's lock
    /// ([`super::lock`]).
    #[error(
        "another stickslip process is writing {dir} (it holds {dir}/{lock}); nothing was \
         changed. Allowed: wait for it to finish (or stop it), then run or resume again",
        lock = super::lock::FILE
    )]
    Busy {
        /// The directory.
        dir: String,
    },
    /// The output directory cannot be created or written to (exit 2).
    #[error("cannot write to output directory {path}: {source}; allowed: a writable directory")]
    OutDir {
        /// The directory.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// Writing an output file failed during or after the run (exit 1).
    #[error("cannot write output in {path}: {source}")]
    Io {
        /// The directory.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// A directory that cannot be resumed (see [`CheckpointError::exit`]).
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
}

impl RunError {
    /// Exit status of the command line: 2 bad scene or output directory, 1 an I/O error
    /// during the run, the checkpoint error's own code.
    #[must_use]
    pub fn exit(&self) -> crate::exit::Exit {
        match self {
            Self::Config(_)
            | Self::OutDir { .. }
            | Self::Existing { .. }
            | Self::Busy { .. }
            | Self::Foreign { .. } => crate::exit::Exit::BadInput,
            Self::Io { .. } => crate::exit::Exit::Io,
            Self::Checkpoint(e) => e.exit(),
        }
    }
}

/// The result files of the other commands that write a directory, by command.
const OTHER_RESULTS: &[(&str, &[&str])] = &[
    (
        "`stickslip verify`",
        &[
            crate::layout::verify::VERIFY_FILE,
            crate::layout::verify::TARGET_FILE,
            crate::layout::verify::RESOLUTION_FILE,
        ],
    ),
    (
        "`stickslip fit`",
        &[
            crate::layout::fit::REPORT_FILE,
            crate::layout::fit::FITTED_SCENE,
        ],
    ),
    (
        "a sweep",
        &[
            crate::layout::sweep::SWEEP_FILE,
            crate::layout::sweep::CSV_FILE,
            crate::layout::sweep::JSON_FILE,
        ],
    ),
];

/// The first other command whose results `dir` holds, with the files found.
fn other_results(dir: &Path) -> Option<(&'static str, Vec<&'static str>)> {
    OTHER_RESULTS.iter().find_map(|(what, files)| {
        let found: Vec<&str> = files
            .iter()
            .copied()
            .filter(|f| dir.join(f).exists())
            .collect();
        (!found.is_empty()).then_some((*what, found))
    })
}

/// The files of an earlier run in `dir` (final or temporary names).
#[must_use]
pub fn earlier_run_files(dir: &Path) -> Vec<String> {
    RUN_FILES
        .iter()
        .flat_map(|f| [(*f).to_string(), format!(".{f}.tmp")])
        .filter(|f| dir.join(f).exists())
        .collect()
}

/// Removes the files of an earlier run in `dir`, and the temporary files a killed writer of
/// run.json or events.csv left (a run directory has one writer).
fn remove_earlier_run(dir: &Path) -> io::Result<()> {
    for f in earlier_run_files(dir) {
        match std::fs::remove_file(dir.join(&f)) {
            Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
            _ => {}
        }
    }
    for f in RUN_FILES {
        remove_temporaries(dir, f)?;
    }
    release_reserve(dir)
}

/// The three streamed files.
#[derive(Debug)]
struct Streams {
    series: AtomicFile,
    probes: AtomicFile,
    profiles: AtomicFile,
    /// Whether the scene has probes: without, probes.csv (its time column alone) is not
    /// published. Its stream is still written while the run goes on, so a checkpoint's stream
    /// positions stay those of every run.
    with_probes: bool,
}

impl Streams {
    fn positions(&mut self) -> io::Result<StreamPositions> {
        Ok(StreamPositions {
            series: self.series.sync_position()?,
            probes: self.probes.sync_position()?,
            profiles: self.profiles.sync_position()?,
        })
    }
}

/// run.json's `stop` after an I/O error ended the run.
pub const IO_STOP: &str = "io";
/// The space a running run keeps in its directory, removed when an I/O error ends it so that
/// run.json can still say so on a full disk (a hidden file; removed when the run ends).
const RESERVE_FILE: &str = ".run.reserve";
/// Its size, bytes: several times a run.json.
const RESERVE_BYTES: usize = 64 << 10;

/// Keeps [`RESERVE_BYTES`] of the disk for the record of an I/O failure.
fn reserve(dir: &Path) -> io::Result<()> {
    let path = dir.join(RESERVE_FILE);
    let mut f = std::fs::File::create(&path)?;
    io::Write::write_all(&mut f, &[0u8; RESERVE_BYTES])?;
    f.sync_data()
}

/// Gives the reserved space back.
fn release_reserve(dir: &Path) -> io::Result<()> {
    match std::fs::remove_file(dir.join(RESERVE_FILE)) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

/// Streams a run into a directory.
#[derive(Debug)]
pub struct DirSink {
    dir: PathBuf,
    streams: Option<Streams>,
    info: Option<RunInfo>,
    every_s: f64,
    every: Option<Duration>,
    due: Instant,
    calls: u64,
    /// Time and step of the last iteration, s: where an I/O failure is said to have happened.
    last: (f64, u64),
}

impl DirSink {
    /// A sink writing into `dir`, created if needed; refuses a directory with an earlier
    /// run's files unless `options.force` (nothing is touched then).
    ///
    /// # Errors
    /// [`RunError::Existing`] or [`RunError::OutDir`].
    pub fn create(dir: &Path, options: &DirOptions) -> Result<Self, RunError> {
        if let Some((what, files)) = other_results(dir) {
            return Err(RunError::Foreign {
                dir: dir.display().to_string(),
                what: what.to_string(),
                files: files.join(", "),
            });
        }
        let earlier = earlier_run_files(dir);
        if !earlier.is_empty() && !options.force {
            return Err(RunError::Existing {
                dir: dir.display().to_string(),
                files: earlier.join(", "),
            });
        }
        std::fs::create_dir_all(dir).map_err(|source| RunError::OutDir {
            path: dir.to_path_buf(),
            source,
        })?;
        Ok(Self::with_interval(dir, options.checkpoint_every_s))
    }

    fn with_interval(dir: &Path, every_s: f64) -> Self {
        let every = checkpoint::interval(every_s);
        let now = Instant::now();
        Self {
            dir: dir.to_path_buf(),
            streams: None,
            info: None,
            every_s,
            every,
            due: every.and_then(|d| now.checked_add(d)).unwrap_or(now),
            calls: 0,
            last: (0.0, 0),
        }
    }

    /// After an I/O error that ended the run (a full disk, a removed directory): run.json
    /// says `failed`, stop `io`, with the error as its failure record, so that no reader takes
    /// the run for one still going. Written atomically where the file system still allows it,
    /// else rewritten in place (truncating run.json first frees the space it needs).
    fn record_io_failure(&mut self, e: &io::Error) {
        // The rows so far stay in the temporary files (readable, and resumable from the last
        // checkpoint).
        if let Some(s) = self.streams.take() {
            s.series.keep_after_failure();
            s.probes.keep_after_failure();
            s.profiles.keep_after_failure();
        }
        let Some(info) = &mut self.info else { return };
        let (time_s, step) = self.last;
        info.status = crate::outcome::RunStatus::Failed;
        info.stop = Some(IO_STOP.to_string());
        let reason = "an I/O error while writing the output (a full disk, a removed or \
                      read-only directory, …); the rows written so far are in the directory's \
                      temporary files, and `stickslip resume` continues from the last \
                      checkpoint once the cause is fixed"
            .to_string();
        info.failure = Some(crate::schema::run_info::FailureRecord {
            time_s,
            step,
            node: 0,
            r_m: 0.0,
            quantity: "io".to_string(),
            value: serde_json::Value::String(format!("{:?}", e.kind())),
            message: format!("I/O error at t = {time_s:e} s, step {step}: {e}. {reason}"),
            reason,
        });
        let _ = release_reserve(&self.dir);
        if info.write(&self.dir).is_err()
            && let Ok(text) = serde_json::to_vec_pretty(&*info)
        {
            let _ = std::fs::write(self.dir.join(schema::run_info::FILE), text);
        }
    }

    /// The directory.
    #[must_use]
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn save_checkpoint(&mut self, snapshot: &Snapshot<'_>) -> io::Result<()> {
        let Some(streams) = &mut self.streams else {
            return Ok(());
        };
        // Syncs the streamed files first: the checkpoint must not refer to bytes that a crash
        // could lose.
        let positions = streams.positions()?;
        let mut driver = snapshot.driver.clone();
        driver.wall_before_s = snapshot.wall_seconds;
        let crossings = self
            .info
            .as_ref()
            .map_or(&[][..], |i| &i.resumed_across_builds[..]);
        let c = Checkpoint {
            build: Cow::Borrowed(checkpoint::BUILD_ID),
            checkpoint_every_s: self.every_s,
            scene: Cow::Borrowed(snapshot.scene),
            preflight: Cow::Borrowed(snapshot.preflight),
            driver: Cow::Owned(driver),
            sim: Cow::Borrowed(snapshot.sim),
            streams: positions,
            resumed_across_builds: Cow::Borrowed(crossings),
        };
        checkpoint::save(&self.dir, &c)
    }

    fn streams(&mut self) -> io::Result<&mut Streams> {
        self.streams
            .as_mut()
            .ok_or_else(|| io::Error::other("the run has not begun"))
    }
}

impl Sink for DirSink {
    fn begin(&mut self, start: &RunStart<'_>) -> io::Result<()> {
        remove_earlier_run(&self.dir)?;
        reserve(&self.dir)?;
        let info = RunInfo::starting(start.scene, start.preflight, start.warnings.to_vec());
        info.write(&self.dir)?;
        let mut series = AtomicFile::create_resumable(&self.dir, schema::series::FILE)?;
        Series::write_header(&mut series)?;
        let mut probes = AtomicFile::create_resumable(&self.dir, schema::probes::FILE)?;
        Probes::write_header(&mut probes, &start.scene.output.probe_radii_m)?;
        let mut profiles = AtomicFile::create_resumable(&self.dir, schema::profiles::FILE)?;
        Profiles::write_header(&mut profiles)?;
        self.streams = Some(Streams {
            series,
            probes,
            profiles,
            with_probes: !start.scene.output.probe_radii_m.is_empty(),
        });
        self.info = Some(info);
        Ok(())
    }

    fn series_row(&mut self, observables: &Observables, probes: &[f64]) -> io::Result<()> {
        let s = self.streams()?;
        Series::write_observables(&mut s.series, observables)?;
        Probes::write_values(&mut s.probes, probes)
    }

    fn profile(&mut self, t_s: f64, radii_m: &[f64], state: &SimState) -> io::Result<()> {
        Profiles::write_profile(&mut self.streams()?.profiles, t_s, radii_m, state)
    }

    fn after_iteration(&mut self, snapshot: &Snapshot<'_>) -> io::Result<()> {
        self.last = (snapshot.sim.physical.drive.t_s, snapshot.sim.counters.step);
        let Some(every) = self.every else {
            return Ok(());
        };
        self.calls += 1;
        if !self.calls.is_multiple_of(CLOCK_EVERY) || Instant::now() < self.due {
            return Ok(());
        }
        self.save_checkpoint(snapshot)?;
        let now = Instant::now();
        self.due = now.checked_add(every).unwrap_or(now);
        Ok(())
    }

    fn end(&mut self, outcome: &RunOutcome, snapshot: &Snapshot<'_>) -> io::Result<()> {
        if outcome.stop == StopReason::Interrupted {
            self.save_checkpoint(snapshot)?;
            if let Some(mut s) = self.streams.take() {
                // The data so far under the documented names, for any reader; the temporary
                // files stay for the resumed run, whose commit replaces these copies.
                s.series.publish_copy()?;
                if s.with_probes {
                    s.probes.publish_copy()?;
                }
                s.profiles.publish_copy()?;
                s.series.keep_for_resume()?;
                s.probes.keep_for_resume()?;
                s.profiles.keep_for_resume()?;
            }
        } else if let Some(s) = self.streams.take() {
            s.series.commit()?;
            if s.with_probes {
                s.probes.commit()?;
            } else {
                // Dropped: its temporary file is removed.
                drop(s.probes);
            }
            s.profiles.commit()?;
        }
        // The events so far (the last one may still be open when interrupted); an ended run's
        // events are complete.
        let mut text = Vec::new();
        Events(outcome.events.clone()).write_to(&mut text)?;
        write_atomic(&self.dir, schema::events::FILE, &text)?;
        let mut text = Vec::new();
        Slips(outcome.slips.clone()).write_to(&mut text)?;
        write_atomic(&self.dir, schema::slips::FILE, &text)?;
        if let Some(info) = &mut self.info {
            info.finish(outcome);
            info.write(&self.dir)?;
        }
        release_reserve(&self.dir)?;
        if outcome.stop != StopReason::Interrupted {
            // The run has ended and its output is complete: nothing is left to resume, and no
            // temporary file of a killed earlier process of this run is kept (nor the copy a
            // process killed while publishing an interrupted run's streams left).
            checkpoint::remove(&self.dir)?;
            for f in RUN_FILES {
                remove_temporaries(&self.dir, f)?;
            }
        }
        Ok(())
    }
}

fn start_error(dir: &Path, e: StartError) -> RunError {
    match e {
        StartError::Config(c) => RunError::Config(c),
        StartError::State(s) => RunError::Checkpoint(CheckpointError::corrupt(dir, s)),
        StartError::NeverBegan => RunError::Checkpoint(CheckpointError::corrupt(dir, e)),
        StartError::Io(source) => RunError::Io {
            path: dir.to_path_buf(),
            source,
        },
    }
}

/// Locks `dir` for this process's writing ([`super::lock`]).
fn lock_dir(dir: &Path) -> Result<super::lock::DirLock, RunError> {
    super::lock::DirLock::acquire(dir).map_err(|e| match e {
        super::lock::LockError::Busy => RunError::Busy {
            dir: dir.display().to_string(),
        },
        super::lock::LockError::Io(source) => RunError::OutDir {
            path: dir.to_path_buf(),
            source,
        },
    })
}

/// Runs `scene` into `dir` (see the module docs).
///
/// # Errors
/// [`RunError`]; a numerical failure is not an error here but the outcome's `stop`.
pub fn run_to_dir(
    scene: &ResolvedScene,
    dir: &Path,
    options: &DirOptions,
    control: &mut Control<'_>,
) -> Result<RunOutcome, RunError> {
    let mut sink = DirSink::create(dir, options)?;
    let mut lock = lock_dir(dir)?;
    let driver = Driver::start(scene, &mut sink).map_err(|e| start_error(dir, e))?;
    if let Some(on_start) = control.on_start.as_mut() {
        on_start(driver.warnings());
    }
    lock.finished();
    driver.run_to_end(&mut sink, control).map_err(|source| {
        sink.record_io_failure(&source);
        RunError::Io {
            path: dir.to_path_buf(),
            source,
        }
    })
}

/// Finishes the interrupted run in `dir` from its checkpoint, with output bit-identical to
/// an uninterrupted run (run.json's `wall_seconds` aside). A checkpoint of another build is
/// refused unless `options.allow_other_build`, and then recorded in run.json. Returns the
/// scene and the outcome of the whole run.
///
/// # Errors
/// [`RunError::Checkpoint`] when there is nothing to resume or the checkpoint (or the partial
/// output it refers to) is unusable or another build's; otherwise as [`run_to_dir`].
pub fn resume(
    dir: &Path,
    options: &ResumeOptions,
    control: &mut Control<'_>,
) -> Result<(ResolvedScene, RunOutcome), RunError> {
    // Before the checkpoint is read: a second resume of the same directory waits for nothing
    // and changes nothing.
    let mut lock = if dir.is_dir() {
        Some(lock_dir(dir)?)
    } else {
        None
    };
    let c = checkpoint::load(dir)?;
    let crossing = checkpoint::check_build(dir, &c, options.allow_other_build)?;
    let mut crossings = c.resumed_across_builds.into_owned();
    crossings.extend(crossing);
    let corrupt = |reason: String| CheckpointError::corrupt(dir, reason);
    let scene = c.scene.into_owned();
    let preflight = c.preflight.into_owned();
    let driver = Driver::restore(
        &scene,
        preflight.clone(),
        c.sim.into_owned(),
        c.driver.into_owned(),
    )
    .map_err(|e| start_error(dir, e))?;
    let cannot_continue =
        |e: io::Error| corrupt(format!("its partial output cannot be continued: {e}"));
    // Every stream checked before any is reopened (which cuts it back to the checkpoint): a
    // resume that cannot go on leaves the directory as it found it.
    for (name, at) in [
        (schema::series::FILE, c.streams.series),
        (schema::probes::FILE, c.streams.probes),
        (schema::profiles::FILE, c.streams.profiles),
    ] {
        AtomicFile::check_prefix(dir, name, at).map_err(cannot_continue)?;
    }
    let reopen = |name: &str, at| AtomicFile::reopen(dir, name, at).map_err(cannot_continue);
    let streams = Streams {
        series: reopen(schema::series::FILE, c.streams.series)?,
        probes: reopen(schema::probes::FILE, c.streams.probes)?,
        profiles: reopen(schema::profiles::FILE, c.streams.profiles)?,
        with_probes: !scene.output.probe_radii_m.is_empty(),
    };
    let mut sink = DirSink::with_interval(
        dir,
        options.checkpoint_every_s.unwrap_or(c.checkpoint_every_s),
    );
    let mut info = RunInfo::starting(
        &scene,
        &preflight,
        crate::driver::warnings_of(&scene, &preflight),
    );
    info.resumed_across_builds = crossings;
    let io_err = |source| RunError::Io {
        path: dir.to_path_buf(),
        source,
    };
    // From here on the directory is this resume's: the lock file goes with the lock.
    if let Some(l) = lock.as_mut() {
        l.finished();
    }
    reserve(dir).map_err(io_err)?;
    info.write(dir).map_err(io_err)?;
    sink.info = Some(info);
    sink.streams = Some(streams);
    let outcome = driver.run_to_end(&mut sink, control).map_err(|source| {
        sink.record_io_failure(&source);
        io_err(source)
    })?;
    Ok((scene, outcome))
}
