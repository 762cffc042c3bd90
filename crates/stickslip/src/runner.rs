//! Runs a resolved scene: the fixed-step time loop, recording of series, probes and profiles,
//! the progress bar, and the output files (written also when the numerics fail).
//!
//! Steps: n = ⌈end/dt − 1e-9⌉, all of length dt except the last, which is end − t and so lands
//! exactly on end. Series and probe rows: at t = 0, at the first step at or after each multiple
//! of `output.series_interval` (with a tolerance of 1e-6·dt for rounding of the summed time),
//! and at the end. Profiles: at the step nearest to each requested time, i.e. at the first
//! recorded time t (t = 0 included) with t ≥ profile_time − h/2, h the length of the step that
//! follows (dt, the shorter last step, or 0 at the end, where all remaining times are
//! recorded); times that fall on the same step give one profile.
//!
//! Checkpoints (see [`crate::checkpoint`]): the loop hands each completed iteration to a
//! [`Checkpointer`], which saves state and recorder position every few seconds of wall time;
//! [`resume`] rebuilds both from the checkpoint and carries on the same loop.

use crate::checkpoint::{self, CheckpointError, Checkpointer, RecorderState};
use crate::output::report::{DerivedReport, RunReport, seed_of, write_report};
use crate::output::tables::{ProbeWriter, ProfileWriter, SeriesWriter, write_events};
use crate::scene::{ResolvedScene, Scene};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use stickslip_core::config::{ConfigError, Scheme};
use stickslip_core::sim::events::MeltingEvent;
use stickslip_core::sim::{NumericalFailure, Simulation};
use thiserror::Error;

/// Steps between progress-bar updates.
const PROGRESS_EVERY: u64 = 1024;
/// Runs shorter than this show no progress bar.
const PROGRESS_DELAY: Duration = Duration::from_secs(1);

/// How to run, besides the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOptions {
    /// No progress bar.
    pub quiet: bool,
    /// Wall-clock interval between checkpoints, s; 0 = no checkpoints.
    pub checkpoint_every_s: f64,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            quiet: false,
            checkpoint_every_s: checkpoint::DEFAULT_EVERY_S,
        }
    }
}

/// What a finished run reports.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// Steps taken.
    pub steps: u64,
    /// Time reached, s.
    pub t_final_s: f64,
    /// Melting events.
    pub events: Vec<MeltingEvent>,
    /// Wall-clock time of the time loop, s (summed over the processes of a resumed run).
    pub wall_seconds: f64,
    /// Rows written to series.csv.
    pub series_rows: u64,
    /// Coupling-solver iterations (accurate scheme).
    pub coupling_iterations: u64,
}

/// Why a run did not finish.
#[derive(Debug, Error)]
pub enum RunError {
    /// The configuration was rejected by the engine (exit 2).
    #[error(transparent)]
    Config(#[from] ConfigError),
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
    /// The numerics failed; everything recorded up to then has been written (exit 3).
    #[error("{failure} (output up to the failure written to {dir})")]
    Numerical {
        /// The failure, naming time, step and node.
        failure: NumericalFailure,
        /// The output directory.
        dir: PathBuf,
    },
    /// A directory that cannot be resumed (see [`CheckpointError::exit_code`]).
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
}

impl RunError {
    /// Exit status of the command line: 2 bad scene or output directory, 3 numerical failure,
    /// 1 an I/O error during the run.
    pub fn exit_code(&self) -> i32 {
        match self {
            Self::Config(_) | Self::OutDir { .. } => 2,
            Self::Io { .. } => 1,
            Self::Numerical { .. } => 3,
            Self::Checkpoint(e) => e.exit_code(),
        }
    }
}

/// The scene's profile times, s, sorted and deduplicated.
fn sorted_profile_times(scene: &ResolvedScene) -> Vec<f64> {
    let mut times_s = scene.output.profile_times_s.clone();
    times_s.sort_by(f64::total_cmp);
    times_s.dedup();
    times_s
}

/// The output files being written and what is still to be recorded.
pub(crate) struct Recorder {
    series: SeriesWriter,
    probes: ProbeWriter,
    profiles: ProfileWriter,
    /// Requested profile times, sorted, deduplicated.
    profile_times_s: Vec<f64>,
    next_profile: usize,
    series_interval_s: f64,
    /// Index k of the next multiple k·interval to record at.
    next_mark: f64,
    last_series_t_s: Option<f64>,
    tol_s: f64,
}

impl Recorder {
    fn create(dir: &Path, scene: &ResolvedScene, radii_m: &[f64]) -> io::Result<Self> {
        let profile_times_s = sorted_profile_times(scene);
        let dt_s = scene.config.time.dt_s;
        Ok(Self {
            series: SeriesWriter::create(dir)?,
            probes: ProbeWriter::create(dir, &scene.output.probe_radii_m, radii_m)?,
            profiles: ProfileWriter::create(dir)?,
            profile_times_s,
            next_profile: 0,
            series_interval_s: scene.output.series_interval_s,
            next_mark: 0.0,
            last_series_t_s: None,
            tol_s: 1e-6 * dt_s,
        })
    }

    /// Continues recording where a checkpoint left it: the streamed files are cut back to
    /// the recorded lengths (see [`crate::output::AtomicFile::reopen`]).
    fn reopen(
        dir: &Path,
        scene: &ResolvedScene,
        radii_m: &[f64],
        at: &RecorderState,
    ) -> io::Result<Self> {
        Ok(Self {
            series: SeriesWriter::reopen(dir, at.series, at.series_rows)?,
            probes: ProbeWriter::reopen(dir, at.probes, &scene.output.probe_radii_m, radii_m)?,
            profiles: ProfileWriter::reopen(dir, at.profiles)?,
            profile_times_s: sorted_profile_times(scene),
            next_profile: at.next_profile,
            series_interval_s: scene.output.series_interval_s,
            next_mark: at.next_mark,
            last_series_t_s: at.last_series_t_s,
            tol_s: 1e-6 * scene.config.time.dt_s,
        })
    }

    /// Where recording stands, every streamed file flushed and synced first (for a
    /// checkpoint).
    pub(crate) fn snapshot(&mut self) -> io::Result<RecorderState> {
        Ok(RecorderState {
            next_profile: self.next_profile,
            next_mark: self.next_mark,
            last_series_t_s: self.last_series_t_s,
            series_rows: self.series.rows(),
            series: self.series.sync_position()?,
            probes: self.probes.sync_position()?,
            profiles: self.profiles.sync_position()?,
        })
    }

    /// The first requested profile time still to record that lies after `t_s`.
    fn next_profile_time_after(&self, t_s: f64) -> Option<f64> {
        self.profile_times_s[self.next_profile.min(self.profile_times_s.len())..]
            .iter()
            .copied()
            .find(|&p| p > t_s)
    }

    fn series_row(&mut self, sim: &mut Simulation) -> io::Result<()> {
        let o = sim.observables();
        self.series.row(&o)?;
        self.probes
            .row(o.t_s, &sim.state().phi, &sim.state().last_melt_s)?;
        self.last_series_t_s = Some(o.t_s);
        self.next_mark = ((o.t_s + self.tol_s) / self.series_interval_s).floor() + 1.0;
        Ok(())
    }

    /// Records whatever is due at the current time of `sim`; `h_next_s` is the length of the
    /// step that follows (0 at the end).
    fn observe(&mut self, sim: &mut Simulation, h_next_s: f64) -> io::Result<()> {
        let t = sim.time_s();
        if t + self.tol_s >= self.next_mark * self.series_interval_s {
            self.series_row(sim)?;
        }
        let mut wrote = false;
        while self
            .profile_times_s
            .get(self.next_profile)
            .is_some_and(|&p| t >= p - 0.5 * h_next_s)
        {
            if !wrote {
                self.profiles.profile(t, sim.radii_m(), sim.state())?;
                wrote = true;
            }
            self.next_profile += 1;
        }
        Ok(())
    }

    /// Records the final row (if not yet recorded) and commits all streamed files.
    fn finish(mut self, sim: &mut Simulation, record_end: bool) -> io::Result<u64> {
        if record_end && self.last_series_t_s != Some(sim.time_s()) {
            self.series_row(sim)?;
        }
        let rows = self.series.rows();
        self.series.commit()?;
        self.probes.commit()?;
        self.profiles.commit()?;
        Ok(rows)
    }
}

fn progress_bar(steps: u64) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(Some(steps), ProgressDrawTarget::hidden());
    if let Ok(style) = ProgressStyle::with_template(
        "{elapsed_precise} [{wide_bar}] {pos}/{len} steps, t = {msg} s, eta {eta}",
    ) {
        pb.set_style(style);
    }
    pb
}

/// The literal scheme's lagged sweep u3D ← K·(u0 − u3D) diverges when ρ(K) ≥ 1; refuse to
/// run it rather than hand back an oscillating, meaningless history.
fn literal_sweep_diverges(scene: &ResolvedScene, rho: f64) -> Option<NumericalFailure> {
    (scene.config.time.scheme == Scheme::Literal && rho >= 1.0).then(|| NumericalFailure {
        t_s: 0.0,
        step: 0,
        node: 0,
        r_m: 0.0,
        quantity: "lagged-sweep contraction factor",
        value: rho,
        diagnosis: format!(
            "the literal scheme takes u3D from the previous step, a fixed-point sweep that \
             diverges when its contraction factor rho((a*phi0^2/h0)*C/G*) = {rho:.3} is >= 1 \
             (softer substrate or thinner film than the scheme can follow); use \
             time.scheme = \"accurate\", which solves the coupling each step"
        ),
    })
}

/// Runs `scene`, writing series.csv, events.csv, profiles.csv, probes.csv and run.json into
/// `out_dir` (created if needed), and a checkpoint every `options.checkpoint_every_s` of wall
/// time (removed at the end). Without `options.quiet`, a progress bar appears on stderr after
/// about a second when stderr is a terminal.
///
/// # Errors
/// [`RunError`]; on a numerical failure everything recorded so far is written first, with
/// run.json `status = "failed"`.
pub fn run(
    scene: &ResolvedScene,
    out_dir: &Path,
    options: &RunOptions,
) -> Result<RunSummary, RunError> {
    execute(scene, out_dir, options, None)
}

/// Finishes the interrupted run in `out_dir` from its checkpoint, with output bit-identical to
/// an uninterrupted run (run.json's `wall_seconds` aside). `checkpoint_every_s` overrides the
/// run's checkpoint interval. Returns the scene as resolved from the checkpoint, and the
/// summary of the whole run.
///
/// # Errors
/// [`RunError::Checkpoint`] when there is nothing to resume or the checkpoint (or the partial
/// output it refers to) is unusable; otherwise as [`run`].
pub fn resume(
    out_dir: &Path,
    quiet: bool,
    checkpoint_every_s: Option<f64>,
) -> Result<(ResolvedScene, RunSummary), RunError> {
    let checkpoint = checkpoint::load(out_dir)?;
    let scene = Scene::from_toml_str(&checkpoint.scene_toml, &[] as &[&str]).map_err(|e| {
        CheckpointError::corrupt(out_dir, format!("its scene does not resolve: {e}"))
    })?;
    let options = RunOptions {
        quiet,
        checkpoint_every_s: checkpoint_every_s.unwrap_or(checkpoint.checkpoint_every_s),
    };
    let summary = execute(&scene, out_dir, &options, Some(checkpoint))?;
    Ok((scene, summary))
}

/// The run proper: from the start, or from `resumed`.
fn execute(
    scene: &ResolvedScene,
    out_dir: &Path,
    options: &RunOptions,
    resumed: Option<checkpoint::Checkpoint<'static>>,
) -> Result<RunSummary, RunError> {
    let quiet = options.quiet;
    let mut sim = Simulation::new(scene.config.clone(), scene.output.event_merge_gap_s)?;
    let out_dir_err = |source| RunError::OutDir {
        path: out_dir.to_path_buf(),
        source,
    };
    let io_err = |source| RunError::Io {
        path: out_dir.to_path_buf(),
        source,
    };
    let radii = sim.radii_m().to_vec();
    let steps = scene.steps;
    let end = scene.config.time.end_s;
    let dt = scene.config.time.dt_s;
    // Length of step i (from 1): dt, except the last, which lands on end.
    let step_length = |i: u64, t: f64| {
        if i > steps {
            0.0
        } else if i == steps {
            (end - t).max(0.0)
        } else {
            dt
        }
    };
    let (rho, mut rec, done, wall_before_s) = match resumed {
        None => {
            let rho = sim.lagged_sweep_contraction();
            std::fs::create_dir_all(out_dir).map_err(out_dir_err)?;
            // A checkpoint of an earlier run here must not be resumed over this run's files.
            checkpoint::remove(out_dir).map_err(out_dir_err)?;
            let mut rec = Recorder::create(out_dir, scene, &radii).map_err(out_dir_err)?;
            rec.observe(&mut sim, step_length(1, 0.0)).map_err(io_err)?;
            (rho, rec, 0, 0.0)
        }
        Some(c) => {
            let corrupt = |reason: String| CheckpointError::corrupt(out_dir, reason);
            sim.restore(c.sim.into_owned())
                .map_err(|e| corrupt(format!("its state does not fit its scene: {e}")))?;
            let rec = Recorder::reopen(out_dir, scene, &radii, &c.recorder)
                .map_err(|e| corrupt(format!("its partial output cannot be continued: {e}")))?;
            (
                c.lagged_sweep_contraction,
                rec,
                c.loop_index,
                c.wall_seconds,
            )
        }
    };
    let mut ckpt = Checkpointer::new(
        out_dir,
        options.checkpoint_every_s,
        scene.resolved.to_toml_string(),
        rho,
        wall_before_s,
    );
    let pb = progress_bar(steps);
    pb.set_position(done);
    let mut shown = false;
    let start = Instant::now();
    let mut failure = literal_sweep_diverges(scene, rho);
    let adaptive = scene.config.time.adaptive.is_some();
    let mut i = done;
    while failure.is_none() {
        i += 1;
        let stepped = if adaptive {
            let t = sim.time_s();
            if t >= end {
                break;
            }
            // Land exactly on profile times and on the end; series rows come at the first
            // step at or after each mark.
            let stop = rec.next_profile_time_after(t).unwrap_or(end).min(end);
            sim.step_adaptive(stop).map(|_| ())
        } else {
            let h = step_length(i, sim.time_s());
            if i > steps || h <= 0.0 {
                break;
            }
            sim.step(h)
        };
        if let Err(f) = stepped {
            failure = Some(f);
            break;
        }
        let t = sim.time_s();
        let h_next = if adaptive { 0.0 } else { step_length(i + 1, t) };
        rec.observe(&mut sim, h_next).map_err(io_err)?;
        ckpt.tick(i, &sim, &mut rec).map_err(io_err)?;
        if i % PROGRESS_EVERY == 0 || adaptive {
            let position = if adaptive {
                (t / end * steps as f64) as u64
            } else {
                i
            };
            pb.set_position(position);
            pb.set_message(format!("{t:.4e}"));
            if !shown && !quiet && start.elapsed() >= PROGRESS_DELAY {
                pb.set_draw_target(ProgressDrawTarget::stderr());
                shown = true;
            }
        }
    }
    let wall_seconds = ckpt.wall_seconds();
    pb.finish_and_clear();

    let series_rows = rec.finish(&mut sim, failure.is_none()).map_err(io_err)?;
    let events = sim.events().to_vec();
    write_events(out_dir, &events).map_err(io_err)?;
    let state = sim.state();
    let report = RunReport {
        name: &scene.name,
        status: if failure.is_some() { "failed" } else { "ok" },
        failure: failure.as_ref().map(ToString::to_string),
        version: env!("CARGO_PKG_VERSION"),
        scene: &scene.resolved,
        derived: DerivedReport::of(scene, rho),
        steps: state.step,
        accepted_steps: state.accepted_steps,
        rejected_steps: state.rejected_steps,
        forced_steps: state.forced_steps,
        t_final: sim.time_s(),
        wall_seconds,
        coupling_iterations: state.coupling_iterations,
        seed: seed_of(scene),
        events: events.len(),
        series_rows,
    };
    write_report(out_dir, &report).map_err(io_err)?;
    // The run has ended and its output is complete: nothing is left to resume.
    checkpoint::remove(out_dir).map_err(io_err)?;
    if let Some(failure) = failure {
        return Err(RunError::Numerical {
            failure,
            dir: out_dir.to_path_buf(),
        });
    }
    Ok(RunSummary {
        steps: state.step,
        t_final_s: sim.time_s(),
        events,
        wall_seconds,
        series_rows,
        coupling_iterations: state.coupling_iterations,
    })
}
