//! The one time loop of the project: every run, whoever asks for it (the command line, a
//! sweep, Python, validation, convergence studies, benches, tests), steps its simulation here.
//!
//! **Steps.** Fixed: n = ⌈end/dt − 1e-9⌉ steps, all of length dt except the last, which is
//! end − t and so lands exactly on end. Adaptive: error-controlled steps
//! ([`Simulation::step_adaptive`]) that land exactly on every profile time and on end.
//!
//! **Stops.** At `time.end`; once `time.max_events` events have ended; at a numerical
//! failure (or before the first step, when the preflight refuses the configuration); when
//! interrupted ([`Control::interrupt`] or [`Control::poll`]).
//!
//! **Recording.** Series and probe rows: at t = 0, at the first step at or after each
//! multiple of `output.series_interval` (with a tolerance of 1e-6·dt for rounding of the
//! summed time), and at the end. Profiles: at the step nearest to each requested time, i.e. at
//! the first recorded time t (t = 0 included) with t ≥ profile_time − h/2, h the length of the
//! step that follows (dt, the shorter last step, or 0 at the end or with adaptive steps, which
//! land on the profile times); times that fall on the same step give one profile. Rows go to
//! a [`Sink`]: memory, an output directory, or nowhere.
//!
//! **State.** Whatever evolves lives in the core's `SimState` or in [`DriverState`] (both saved
//! by the checkpoint module), and the loop is keyed on them, not on the wall clock: a run
//! restored from a [`Snapshot`] goes on bit-identically.

use crate::cycles::summarize_stamp;
use crate::outcome::{RunOutcome, StepCounts, StopReason};
use crate::scene::{ResolvedScene, step_count};
use crate::schema::probes::ProbeRow;
use crate::slips::{Moment, SlipTracker};
use crate::summary::{RegimeThresholds, SummaryInput, summarize};
use serde::{Deserialize, Serialize};
use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use stickslip_core::config::ConfigError;
use stickslip_core::drive::Drive;
use stickslip_core::preflight::{Finding, Preflight, Severity};
use stickslip_core::sim::{NumericalFailure, Observables, PlannedStep, SimState, Simulation};

/// Where rows go. Every method but [`Sink::end`] may be called many times.
pub trait Sink {
    /// A fresh run is about to take its first step (not called when a run is resumed).
    ///
    /// # Errors
    /// I/O errors of the sink.
    fn begin(&mut self, start: &RunStart<'_>) -> io::Result<()>;
    /// One series row and its probe row (t, φ per probe, t_melt per probe).
    ///
    /// # Errors
    /// I/O errors of the sink.
    fn series_row(&mut self, observables: &Observables, probes: &[f64]) -> io::Result<()>;
    /// One profile of the state at `t_s`.
    ///
    /// # Errors
    /// I/O errors of the sink.
    fn profile(&mut self, t_s: f64, radii_m: &[f64], state: &SimState) -> io::Result<()>;
    /// Called after every loop iteration; a sink that keeps checkpoints writes one when due.
    ///
    /// # Errors
    /// I/O errors of the sink.
    fn after_iteration(&mut self, _snapshot: &Snapshot<'_>) -> io::Result<()> {
        Ok(())
    }
    /// The run has stopped (for any reason); `snapshot` is its final state.
    ///
    /// # Errors
    /// I/O errors of the sink.
    fn end(&mut self, outcome: &RunOutcome, snapshot: &Snapshot<'_>) -> io::Result<()>;
}

/// A sink that keeps nothing (sweeps keep only the outcome's summary).
#[derive(Debug, Clone, Copy, Default)]
pub struct NullSink;

impl Sink for NullSink {
    fn begin(&mut self, _start: &RunStart<'_>) -> io::Result<()> {
        Ok(())
    }
    fn series_row(&mut self, _o: &Observables, _probes: &[f64]) -> io::Result<()> {
        Ok(())
    }
    fn profile(&mut self, _t_s: f64, _r: &[f64], _s: &SimState) -> io::Result<()> {
        Ok(())
    }
    fn end(&mut self, _o: &RunOutcome, _s: &Snapshot<'_>) -> io::Result<()> {
        Ok(())
    }
}

/// What a sink learns before the first step.
#[derive(Debug, Clone, Copy)]
pub struct RunStart<'a> {
    /// The scene.
    pub scene: &'a ResolvedScene,
    /// Its preflight.
    pub preflight: &'a Preflight,
    /// Notes and warnings (preflight and unusual values).
    pub warnings: &'a [Finding],
    /// Node radii, m.
    pub radii_m: &'a [f64],
}

/// Where recording stands.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecorderState {
    /// Index into the sorted, deduplicated profile times of the next profile to write.
    pub next_profile: usize,
    /// k of the next multiple k·series_interval at which a series row is due.
    pub next_mark: f64,
    /// Time of the last series row, s (none before the first).
    pub last_series_t_s: Option<f64>,
    /// Rows recorded so far.
    pub series_rows: u64,
}

/// Fixed steps from loop index `first_index` on: `steps` steps of `dt_s`, the last one landing
/// on end.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FixedSchedule {
    /// Step length, s.
    pub dt_s: f64,
    /// Loop index after which this schedule began.
    pub first_index: u64,
    /// Number of steps in it.
    pub steps: u64,
}

/// The driver's own evolving state (besides the simulation's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DriverState {
    /// Index of the last loop iteration completed.
    pub loop_index: u64,
    /// Recording.
    pub recorder: RecorderState,
    /// Fixed stepping schedule (unused with adaptive steps).
    pub schedule: FixedSchedule,
    /// Wall-clock time spent in the loop by earlier processes of this run, s.
    pub wall_before_s: f64,
    /// The stamp's slips, followed step by step.
    pub slips: SlipTracker,
}

/// Everything needed to carry a run on, borrowed from the driver.
#[derive(Debug, Clone, Copy)]
pub struct Snapshot<'a> {
    /// The scene.
    pub scene: &'a ResolvedScene,
    /// The preflight at t = 0.
    pub preflight: &'a Preflight,
    /// The simulation's state.
    pub sim: &'a SimState,
    /// The driver's state.
    pub driver: &'a DriverState,
    /// Wall-clock time of the loop so far, s (all processes).
    pub wall_seconds: f64,
}

impl Snapshot<'_> {
    /// The outcome of the run had it stopped in this state for `stop` (with `failure` and the
    /// run's `warnings`): what [`Driver::outcome`] returns, and what a reader of a saved state
    /// (a checkpoint) learns without building the simulation.
    #[must_use]
    pub fn outcome(
        &self,
        stop: StopReason,
        failure: Option<NumericalFailure>,
        warnings: Vec<Finding>,
        thresholds: &RegimeThresholds,
    ) -> RunOutcome {
        let state = self.sim;
        let events = state.events.tracker.events().to_vec();
        let t_final_s = state.physical.drive.t_s;
        let mut summary = summarize(
            &SummaryInput {
                events: &events,
                no_solid_time_s: state.events.tracker.no_solid_time_s(),
                t_final_s,
                starts_liquid: !self
                    .scene
                    .config
                    .lubricant
                    .starts_solid(self.preflight.derived.a_coeff_pa),
                books: state.events.tracker.books(),
            },
            thresholds,
        );
        let tracker = &self.driver.slips;
        let v0 = self.scene.config.drive.velocity_m_per_s();
        let stamp = summarize_stamp(tracker, &events, t_final_s, v0);
        summary.steady = self.scene.steady.is_steady(&events)
            || self.scene.steady.is_steady_slips(&tracker.slips);
        summary.n_slips = stamp.n_slips;
        summary.stamp_regime = Some(stamp.stamp_regime);
        summary.cycles = Some(stamp.cycles);
        let slips = tracker.all_slips(&events);
        RunOutcome {
            stop,
            failure,
            events,
            slips,
            summary,
            counts: StepCounts {
                steps: state.counters.step,
                accepted_steps: state.counters.accepted_steps,
                rejected_steps: state.counters.rejected_steps,
                forced_steps: state.counters.forced_steps,
                onset_retakes: state.counters.onset_retakes,
                coupling_iterations: state.counters.coupling_iterations,
            },
            t_final_s,
            wall_seconds: self.wall_seconds,
            series_rows: self.driver.recorder.series_rows,
            preflight: self.preflight.clone(),
            warnings,
        }
    }
}

/// Progress of a run, for progress bars.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Time reached, s.
    pub t_s: f64,
    /// End time, s.
    pub end_s: f64,
    /// Loop iterations so far.
    pub loop_index: u64,
    /// Events so far.
    pub events: usize,
}

/// A callback that receives a run's notes and warnings before its first step.
pub type OnStart = dyn FnMut(&[Finding]);

/// How the caller steers a run.
#[derive(Default)]
pub struct Control<'a> {
    /// Set (e.g. by a signal handler) to stop the run at the next iteration.
    pub interrupt: Option<&'a AtomicBool>,
    /// Called with the progress every 1024 fixed steps or every adaptive step; returns true
    /// to stop the run (e.g. Python's Ctrl-C check).
    pub poll: Option<&'a mut dyn FnMut(&Progress) -> bool>,
    /// Called after every step with the simulation (studies that need more than the rows).
    pub observer: Option<&'a mut dyn FnMut(&Simulation)>,
    /// Called once before the first step of a fresh run with its notes and warnings.
    pub on_start: Option<&'a mut OnStart>,
    /// Regime thresholds of the summary.
    pub thresholds: RegimeThresholds,
    /// Adaptive steps: record the accepted steps, or take a recorded run's steps again
    /// ([`StepPlan`]); none steps as the scene says.
    pub plan: Option<StepPlan<'a>>,
}

/// An adaptive run's steps, recorded or taken again ([`Simulation::step_planned`]): a run of a
/// scene with one parameter moved by a small step that replays the plan of the scene's own
/// run follows the same discrete map, so their difference is the derivative of the discrete
/// solution, without the step-size controller's jitter. Fixed steps ignore it. A plan is not
/// part of a checkpoint.
#[derive(Debug)]
pub enum StepPlan<'a> {
    /// Appends every accepted step.
    Record(&'a mut Vec<PlannedStep>),
    /// Takes these steps from `next` on, one per iteration; past their end the run goes on
    /// with error-controlled steps.
    Replay {
        /// The recorded steps.
        steps: &'a [PlannedStep],
        /// The next one to take.
        next: usize,
    },
}

impl std::fmt::Debug for Control<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Control")
            .field("interrupt", &self.interrupt)
            .field("poll", &self.poll.is_some())
            .field("observer", &self.observer.is_some())
            .field("on_start", &self.on_start.is_some())
            .field("thresholds", &self.thresholds)
            .field("plan", &self.plan)
            .finish()
    }
}

/// Fixed steps between calls of [`Control::poll`].
const POLL_EVERY: u64 = 1024;

/// How far [`Driver::advance`] may go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Limit {
    /// To the run's own end (time.end, max_events, failure, interrupt).
    None,
    /// At most this many more loop iterations.
    Steps(u64),
    /// Until the time reaches at least this, s.
    Time(f64),
}

/// A run in progress.
pub struct Driver {
    scene: ResolvedScene,
    sim: Simulation,
    preflight: Preflight,
    warnings: Vec<Finding>,
    state: DriverState,
    probes: ProbeRow,
    profile_times_s: Vec<f64>,
    tol_s: f64,
    started: Instant,
    failure: Option<NumericalFailure>,
}

impl std::fmt::Debug for Driver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Driver")
            .field("scene", &self.scene.name)
            .field("state", &self.state)
            .finish_non_exhaustive()
    }
}

/// The notes and warnings of a run: the preflight's, then unusual values (likely unit slips).
#[must_use]
pub fn warnings_of(scene: &ResolvedScene, preflight: &Preflight) -> Vec<Finding> {
    let mut out: Vec<Finding> = preflight.findings.clone();
    out.extend(
        scene
            .unusual_values()
            .into_iter()
            .map(|(key, message)| Finding {
                severity: Severity::Warning,
                key,
                message,
            }),
    );
    out
}

impl Driver {
    /// Builds the simulation of `scene`, its preflight, and records the state at t = 0 into
    /// `sink` (after [`Sink::begin`]).
    ///
    /// # Errors
    /// The engine's rejection of the configuration, or the sink's I/O error.
    ///
    /// # Example
    /// ```
    /// use stickslip_run::{Control, Driver, MemorySink, Scene, StopReason};
    /// const SCENE: &str = r#"
    /// name = "example"
    /// [lubricant]
    /// tau_max = 1e6
    /// eps_max = 1
    /// a = 1e6
    /// gamma = 10
    /// [contact]
    /// radius = 2e-5
    /// film_thickness = 1e-7
    /// g_eff = 1e9
    /// nodes = 20
    /// [drive]
    /// stiffness = 500
    /// mass = 0.1
    /// velocity = 1
    /// [time]
    /// end = 2e-4
    /// [output]
    /// profile_times = []
    /// "#;
    /// let scene = Scene::from_toml_str(SCENE, &[] as &[&str]).unwrap();
    /// let mut sink = MemorySink::new();
    /// let driver = Driver::start(&scene, &mut sink).unwrap();
    /// // The preflight is known before the first step.
    /// assert!(driver.preflight().refusal().is_none());
    /// let outcome = driver.run_to_end(&mut sink, &mut Control::default()).unwrap();
    /// assert_eq!(outcome.stop, StopReason::End);
    /// ```
    pub fn start(scene: &ResolvedScene, sink: &mut dyn Sink) -> Result<Self, StartError> {
        let sim = Simulation::new(scene.config.clone())?;
        let preflight = sim.preflight();
        let warnings = warnings_of(scene, &preflight);
        let failure = preflight.refusal();
        let schedule = FixedSchedule {
            dt_s: scene.config.time.dt_s,
            first_index: 0,
            steps: scene.steps,
        };
        let mut driver = Self::assemble(
            scene,
            sim,
            preflight,
            warnings,
            DriverState {
                loop_index: 0,
                recorder: RecorderState {
                    next_profile: 0,
                    next_mark: 0.0,
                    last_series_t_s: None,
                    series_rows: 0,
                },
                schedule,
                wall_before_s: 0.0,
                slips: SlipTracker::new(
                    scene.output.slip_drop_n(&scene.config),
                    scene.config.time.end_s,
                ),
            },
        );
        driver.observe_slips();
        driver.failure = failure;
        sink.begin(&RunStart {
            scene: &driver.scene,
            preflight: &driver.preflight,
            warnings: &driver.warnings,
            radii_m: driver.sim.radii_m(),
        })?;
        let h = driver.step_length(1, 0.0);
        driver.record(sink, h)?;
        Ok(driver)
    }

    /// A driver carrying on from a snapshot's parts (see [`Snapshot`]).
    ///
    /// # Errors
    /// The engine's rejection of the configuration, or a state that does not fit it.
    pub fn restore(
        scene: &ResolvedScene,
        preflight: Preflight,
        sim_state: SimState,
        state: DriverState,
    ) -> Result<Self, StartError> {
        let mut sim = Simulation::new(scene.config.clone())?;
        sim.restore(sim_state)?;
        let warnings = warnings_of(scene, &preflight);
        Ok(Self::assemble(scene, sim, preflight, warnings, state))
    }

    fn assemble(
        scene: &ResolvedScene,
        sim: Simulation,
        preflight: Preflight,
        warnings: Vec<Finding>,
        state: DriverState,
    ) -> Self {
        let probes = ProbeRow::new(&scene.output.probe_radii_m, sim.radii_m());
        Self {
            profile_times_s: scene.output.sorted_profile_times_s(),
            tol_s: 1e-6 * scene.config.time.dt_s,
            scene: scene.clone(),
            sim,
            preflight,
            warnings,
            state,
            probes,
            started: Instant::now(),
            failure: None,
        }
    }

    /// The simulation.
    #[must_use]
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// Scalar observables now (F from both forms of Eq. 16, means, melted fraction).
    pub fn observables(&mut self) -> Observables {
        self.sim.observables()
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &ResolvedScene {
        &self.scene
    }

    /// The preflight at t = 0.
    #[must_use]
    pub fn preflight(&self) -> &Preflight {
        &self.preflight
    }

    /// Notes and warnings of the run (preflight and unusual values).
    #[must_use]
    pub fn warnings(&self) -> &[Finding] {
        &self.warnings
    }

    /// Wall-clock seconds of the loop so far (all processes of the run).
    #[must_use]
    pub fn wall_seconds(&self) -> f64 {
        self.state.wall_before_s + self.started.elapsed().as_secs_f64()
    }

    /// The run's state as a snapshot.
    #[must_use]
    pub fn snapshot(&self) -> Snapshot<'_> {
        Snapshot {
            scene: &self.scene,
            preflight: &self.preflight,
            sim: self.sim.state(),
            driver: &self.state,
            wall_seconds: self.wall_seconds(),
        }
    }

    /// Puts the run back to an earlier snapshot's states in place (the operators are kept):
    /// a benchmark repeating a window of steps.
    ///
    /// # Errors
    /// A state that does not fit this simulation.
    pub fn rewind(
        &mut self,
        sim_state: SimState,
        state: DriverState,
    ) -> Result<(), stickslip_core::sim::StateMismatch> {
        self.sim.restore(sim_state)?;
        self.state = state;
        self.failure = None;
        Ok(())
    }

    /// From now on, fixed steps of `dt_s` to the end (a study's change of step).
    pub fn set_fixed_dt(&mut self, dt_s: f64) {
        self.state.schedule = FixedSchedule {
            dt_s,
            first_index: self.state.loop_index,
            steps: step_count(self.scene.config.time.end_s - self.sim.time_s(), dt_s),
        };
    }

    /// Length of loop iteration `i` (from 1) starting at time `t_s` with fixed steps: dt,
    /// except the schedule's last step, which lands on end; 0 beyond it.
    fn step_length(&self, i: u64, t_s: f64) -> f64 {
        let s = &self.state.schedule;
        let j = i.saturating_sub(s.first_index);
        if j > s.steps {
            0.0
        } else if j == s.steps {
            (self.scene.config.time.end_s - t_s).max(0.0)
        } else {
            s.dt_s
        }
    }

    /// Hands the state after a step (or at t = 0) to the slip tracker: the drive force is the
    /// spring's K·(V0·t − X), or F under the rigid drive.
    fn observe_slips(&mut self) {
        let s = &self.sim.state().physical;
        let f_drive = match &self.scene.config.drive {
            Drive::Spring(sp) => sp.spring_force_n(s.drive.t_s, s.drive.x_m),
            Drive::Rigid(_) => s.force_n,
        };
        let dissipated_j = self
            .sim
            .state()
            .events
            .tracker
            .books()
            .map_or(f64::NAN, |b| b.flows.dissipated_j());
        let now = Moment {
            t_s: s.drive.t_s,
            f_n: f_drive,
            x_m: s.drive.x_m,
            dissipated_j,
        };
        self.state.slips.observe(now, s.force_n, self.sim.events());
    }

    fn adaptive(&self) -> bool {
        self.scene.config.time.adaptive.is_some()
    }

    fn series_row(&mut self, sink: &mut dyn Sink) -> io::Result<()> {
        let o = self.sim.observables();
        let state = self.sim.state();
        let probes = self
            .probes
            .values(o.t_s, &state.physical.phi, &state.events.last_melt_s);
        sink.series_row(&o, probes)?;
        let r = &mut self.state.recorder;
        r.series_rows += 1;
        r.last_series_t_s = Some(o.t_s);
        r.next_mark = ((o.t_s + self.tol_s) / self.scene.output.series_interval_s).floor() + 1.0;
        Ok(())
    }

    /// Records whatever is due at the current time; `h_next_s` is the length of the step that
    /// follows (0 at the end and with adaptive steps).
    fn record(&mut self, sink: &mut dyn Sink, h_next_s: f64) -> io::Result<()> {
        let t = self.sim.time_s();
        let interval = self.scene.output.series_interval_s;
        if t + self.tol_s >= self.state.recorder.next_mark * interval {
            self.series_row(sink)?;
        }
        let mut wrote = false;
        while self
            .profile_times_s
            .get(self.state.recorder.next_profile)
            .is_some_and(|&p| t >= p - 0.5 * h_next_s)
        {
            if !wrote {
                sink.profile(t, self.sim.radii_m(), self.sim.state())?;
                wrote = true;
            }
            self.state.recorder.next_profile += 1;
        }
        Ok(())
    }

    /// One adaptive step to at most `stop_s`: the plan's next when replaying one, else
    /// error-controlled (and recorded when recording).
    fn adaptive_step(
        &mut self,
        plan: Option<&mut StepPlan<'_>>,
        stop_s: f64,
    ) -> Result<(), NumericalFailure> {
        match plan {
            Some(StepPlan::Replay { steps, next }) if *next < steps.len() => {
                let planned = steps[*next];
                *next += 1;
                self.sim.step_planned(planned, stop_s).map(|_| ())
            }
            plan => {
                self.sim.step_adaptive(stop_s)?;
                if let (Some(StepPlan::Record(out)), Some(planned)) =
                    (plan, self.sim.last_planned_step())
                {
                    out.push(planned);
                }
                Ok(())
            }
        }
    }

    /// The first requested profile time still to record that lies after `t_s`.
    fn next_profile_time_after(&self, t_s: f64) -> Option<f64> {
        let from = self
            .state
            .recorder
            .next_profile
            .min(self.profile_times_s.len());
        self.profile_times_s[from..]
            .iter()
            .copied()
            .find(|&p| p > t_s)
    }

    /// Steps until the run stops or `limit` is reached; `Some(reason)` when the run has
    /// stopped (call [`Driver::finish`] then), `None` when only the limit was reached.
    ///
    /// # Errors
    /// The sink's I/O errors.
    pub fn advance(
        &mut self,
        sink: &mut dyn Sink,
        control: &mut Control<'_>,
        limit: Limit,
    ) -> io::Result<Option<StopReason>> {
        if self.failure.is_some() {
            // Only a refusal is set before the loop runs; a failure ends it.
            return Ok(Some(if self.state.loop_index == 0 {
                StopReason::Refused
            } else {
                StopReason::Failure
            }));
        }
        let end = self.scene.config.time.end_s;
        let adaptive = self.adaptive();
        let first = self.state.loop_index;
        loop {
            match limit {
                Limit::Steps(n) if self.state.loop_index - first >= n => return Ok(None),
                Limit::Time(t) if self.sim.time_s() >= t => return Ok(None),
                _ => {}
            }
            if control
                .interrupt
                .is_some_and(|flag| flag.load(Ordering::Relaxed))
            {
                return Ok(Some(StopReason::Interrupted));
            }
            let i = self.state.loop_index + 1;
            let t = self.sim.time_s();
            let ended_before = self.sim.state().events.tracker.ended();
            let slips_before = self.state.slips.slips.len();
            let stepped = if adaptive {
                if t >= end {
                    return Ok(Some(StopReason::End));
                }
                // Land exactly on profile times and on the end; series rows come at the
                // first step at or after each mark.
                let stop = self.next_profile_time_after(t).unwrap_or(end).min(end);
                self.adaptive_step(control.plan.as_mut(), stop)
            } else {
                let h = self.step_length(i, t);
                if h <= 0.0 {
                    return Ok(Some(StopReason::End));
                }
                self.sim.step(h)
            };
            self.state.loop_index = i;
            if let Err(f) = stepped {
                self.failure = Some(f);
                return Ok(Some(StopReason::Failure));
            }
            self.observe_slips();
            if let Some(observe) = control.observer.as_mut() {
                observe(&self.sim);
            }
            let h_next = if adaptive {
                0.0
            } else {
                self.step_length(i + 1, self.sim.time_s())
            };
            self.record(sink, h_next)?;
            let ended = self.sim.state().events.tracker.ended();
            if self.scene.max_events.is_some_and(|m| ended as u64 >= m) {
                return Ok(Some(StopReason::MaxEvents));
            }
            // Periodic: checked when an event or a slip has just ended, so the last cycle is
            // whole; on the film's scale (meltings repeat) or on the stamp's (slips repeat).
            let slips = &self.state.slips.slips;
            if self.scene.steady.stop
                && ((ended > ended_before && self.scene.steady.is_steady(self.sim.events()))
                    || (slips.len() > slips_before && self.scene.steady.is_steady_slips(slips)))
            {
                return Ok(Some(StopReason::Periodic));
            }
            if let (Some(limit), Some(last)) =
                (self.scene.max_open_event_s, self.sim.events().last())
                && last.t_end_s.is_none()
                && self.sim.time_s() - last.t_onset_s >= limit
            {
                return Ok(Some(StopReason::OpenEvent));
            }
            // After the stop checks: a checkpoint is only ever taken of a state from which the
            // run goes on, so a run resumed from it takes the same next step.
            sink.after_iteration(&self.snapshot())?;
            if (adaptive || i.is_multiple_of(POLL_EVERY))
                && let Some(poll) = control.poll.as_mut()
            {
                let progress = Progress {
                    t_s: self.sim.time_s(),
                    end_s: end,
                    loop_index: i,
                    events: self.sim.events().len(),
                };
                if poll(&progress) {
                    return Ok(Some(StopReason::Interrupted));
                }
            }
        }
    }

    /// Ends the run stopped for `stop`: records the final row (unless it failed or was
    /// interrupted), builds the outcome and hands it to [`Sink::end`].
    ///
    /// # Errors
    /// The sink's I/O errors.
    pub fn finish(
        mut self,
        sink: &mut dyn Sink,
        stop: StopReason,
        thresholds: &RegimeThresholds,
    ) -> io::Result<RunOutcome> {
        if matches!(
            stop,
            StopReason::End | StopReason::MaxEvents | StopReason::OpenEvent | StopReason::Periodic
        ) && self.state.recorder.last_series_t_s != Some(self.sim.time_s())
        {
            self.series_row(sink)?;
        }
        let outcome = self.outcome(stop, thresholds);
        sink.end(&outcome, &self.snapshot())?;
        Ok(outcome)
    }

    /// The outcome if the run stopped now for `stop`.
    #[must_use]
    pub fn outcome(&self, stop: StopReason, thresholds: &RegimeThresholds) -> RunOutcome {
        self.snapshot().outcome(
            stop,
            self.failure.clone(),
            self.warnings.clone(),
            thresholds,
        )
    }

    /// Runs to the end: [`Driver::advance`] then [`Driver::finish`].
    ///
    /// # Errors
    /// The sink's I/O errors.
    pub fn run_to_end(
        mut self,
        sink: &mut dyn Sink,
        control: &mut Control<'_>,
    ) -> io::Result<RunOutcome> {
        let stop = self
            .advance(sink, control, Limit::None)?
            .unwrap_or(StopReason::End);
        let thresholds = control.thresholds;
        self.finish(sink, stop, &thresholds)
    }
}

/// Why a run could not start.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// The engine rejected the configuration.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A restored state that does not fit the scene.
    #[error("the saved state does not fit its scene: {0}")]
    State(#[from] stickslip_core::sim::StateMismatch),
    /// The sink ended without the run's output (a run that never began).
    #[error("the run never began")]
    NeverBegan,
    /// The sink could not begin.
    #[error(transparent)]
    Io(#[from] io::Error),
}

/// Runs `scene` into `sink` from the start to its end.
///
/// # Errors
/// [`StartError`] if the run cannot start, or the sink's I/O error.
pub fn run(
    scene: &ResolvedScene,
    sink: &mut dyn Sink,
    control: &mut Control<'_>,
) -> Result<RunOutcome, StartError> {
    let driver = Driver::start(scene, sink)?;
    if let Some(on_start) = control.on_start.as_mut() {
        on_start(driver.warnings());
    }
    Ok(driver.run_to_end(sink, control)?)
}
