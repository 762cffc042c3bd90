//! The fit's forward runs: the scene with the parameters' values applied as `--set` overrides
//! (exactly as the command line's `--set`, so the fitted scene is the scene a user would run),
//! run by the driver with a null sink while an observer records the friction force and the
//! stamp's position at every step (the model's F and X at the data's times are interpolated
//! from those).
//!
//! Every run of a fit also carries the fit's settings: `time.end` at the trace's end (plus the
//! largest time shift), no profile times, and with adaptive steps a tolerance tightened by
//! [`TOLERANCE_FACTOR`], so that the solver's noise — the run-to-run jitter of the adaptive
//! step sequence, measured as `verify` measures an error, against a run at a tenth of the
//! tolerance ([`Forward::noise_run`]) — stays far below the differences the Jacobian takes.
//! Where that is not tight enough (a slow loading to a sharp onset: the SFA contact's onsets
//! at the tolerance / 100 are tens of their own σ off), the optimiser tightens it tenfold at a
//! time: the run's `level` ([`MAX_LEVEL`] at most), the tolerance / (100·10^level).

use super::error::FitError;
use super::misfit::ModelCurve;
use super::params::Param;
use std::sync::atomic::AtomicBool;
use stickslip_core::sim::PlannedStep;
use stickslip_run::driver::{Control, NullSink, StepPlan};
use stickslip_run::keys::{output, time};
use stickslip_run::outcome::StopReason;
use stickslip_run::scene::{ResolvedScene, SceneError};

/// The fit's runs use the scene's `time.tolerance` divided by this.
pub const TOLERANCE_FACTOR: f64 = 100.0;
/// The most tenfold tightenings beyond [`TOLERANCE_FACTOR`] (the tolerance / 10⁵ at most).
pub const MAX_LEVEL: u32 = 3;

/// How one forward run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Run {
    /// It ran to the trace's end: the force over time.
    Done(ModelCurve),
    /// It failed numerically, was refused, or the scene did not resolve.
    Failed(RunFailure),
    /// Interrupted.
    Interrupted,
}

/// Why a forward run produced no curve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunFailure {
    /// The parameters' overrides did not make a valid scene.
    #[error(transparent)]
    Scene(#[from] stickslip_run::scene::SceneError),
    /// The run could not start (its message: a start error holds an I/O error, which is not
    /// `Clone`).
    #[error("{0}")]
    Start(String),
    /// The run stopped on a numerical failure, or its preflight refused it.
    #[error(transparent)]
    Numerical(#[from] stickslip_core::sim::NumericalFailure),
    /// It stopped as failed or refused without a recorded failure.
    #[error("the run failed")]
    Unrecorded,
}

/// How a fit makes its Jacobians (`--jacobian`; [`super::replayed`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JacobianKind {
    /// Central differences grown out of the solver's noise (and, for the intervals, into the
    /// misfit's linear range).
    #[default]
    Differences,
    /// Forward differences of replayed runs, where they apply; differences elsewhere.
    Replay,
}

impl JacobianKind {
    /// The name (`--jacobian`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Differences => "differences",
            Self::Replay => "replay",
        }
    }

    /// The kind named `name`.
    ///
    /// # Errors
    /// [`FitError::Input`] for another name.
    pub fn from_name(name: &str) -> Result<Self, FitError> {
        match name {
            "differences" => Ok(Self::Differences),
            "replay" => Ok(Self::Replay),
            _ => Err(FitError::input("--jacobian", name, "differences or replay")),
        }
    }
}

/// How a forward run steps: as its scene says, recording its accepted steps, or taking a
/// recorded run's steps again (the replayed Jacobian, docs/fit.md#replayed-jacobians).
#[derive(Debug)]
pub enum Stepping<'a> {
    /// Error-controlled (or fixed) steps, as the scene says.
    Own,
    /// Its own steps, appended to the vector.
    Record(&'a mut Vec<PlannedStep>),
    /// The recorded steps (error-controlled past their end).
    Replay(&'a [PlannedStep]),
}

/// The scene and settings every forward run of a fit starts from.
#[derive(Debug, Clone)]
pub struct Forward {
    /// The scene as given (with the command line's --set).
    pub base: ResolvedScene,
    /// The fit's settings, as --set text, applied before the parameters' values.
    pub settings: Vec<String>,
    /// The tolerance of the fit's runs at level 0 (none with fixed steps).
    pub tolerance: Option<f64>,
}

impl Forward {
    /// The forward runs of `base` up to `end_s`.
    ///
    /// # Errors
    /// The scene with the fit's settings does not resolve.
    pub fn new(base: &ResolvedScene, end_s: f64) -> Result<Self, Box<SceneError>> {
        let tolerance = base
            .config
            .time
            .adaptive
            .map(|a| a.tolerance / TOLERANCE_FACTOR);
        let mut settings = vec![
            time::END.set(end_s).to_string(),
            output::PROFILE_TIMES.set(Vec::new()).to_string(),
        ];
        if let Some(tol) = tolerance {
            settings.push(time::TOLERANCE.set(tol).to_string());
        }
        let forward = Self {
            base: base.clone(),
            settings,
            tolerance,
        };
        forward.scene(&[], &[])?;
        Ok(forward)
    }

    /// The tolerance of the runs at `level` (none with fixed steps).
    #[must_use]
    pub fn tolerance_at(&self, level: u32) -> Option<f64> {
        self.tolerance
            .map(|t| t / 10f64.powi(level.min(MAX_LEVEL) as i32))
    }

    /// The level whose tolerance is `tolerance` (a fit.json's `time_tolerance`; 0 for none).
    #[must_use]
    pub fn level_of(&self, tolerance: Option<f64>) -> u32 {
        match (self.tolerance, tolerance) {
            (Some(t0), Some(t)) if t > 0.0 => {
                ((t0 / t).log10().round().max(0.0) as u32).min(MAX_LEVEL)
            }
            _ => 0,
        }
    }

    /// The overrides of the model at `z`: the fit's settings, then each scene parameter's
    /// `KEY=VALUE`.
    #[must_use]
    pub fn overrides(&self, params: &[Param], z: &[f64]) -> Vec<String> {
        self.overrides_at(params, z, 0)
    }

    /// [`Forward::overrides`] with the tolerance at `level`.
    #[must_use]
    pub fn overrides_at(&self, params: &[Param], z: &[f64], level: u32) -> Vec<String> {
        let mut out = self.settings.clone();
        if level > 0
            && let Some(tol) = self.tolerance_at(level)
        {
            out.push(time::TOLERANCE.set(tol).to_string());
        }
        out.extend(
            params
                .iter()
                .zip(z)
                .filter(|(p, _)| p.scene_key)
                .map(|(p, &z)| p.setting(z)),
        );
        out
    }

    /// The scene of the model at `z`.
    ///
    /// # Errors
    /// A value the scene refuses.
    pub fn scene(&self, params: &[Param], z: &[f64]) -> Result<ResolvedScene, Box<SceneError>> {
        self.base
            .with_overrides(&self.overrides(params, z))
            .map_err(Box::new)
    }

    /// Runs the model at `z`.
    #[must_use]
    pub fn run(&self, params: &[Param], z: &[f64], interrupt: Option<&AtomicBool>) -> Run {
        self.run_at(params, z, 0, interrupt)
    }

    /// Runs the model at `z` with the tolerance at `level`.
    #[must_use]
    pub fn run_at(
        &self,
        params: &[Param],
        z: &[f64],
        level: u32,
        interrupt: Option<&AtomicBool>,
    ) -> Run {
        self.run_overrides(&self.overrides_at(params, z, level), interrupt)
    }

    /// Runs the model at `z` with the tolerance at `level`, stepping as `stepping` says.
    #[must_use]
    pub fn run_stepping(
        &self,
        params: &[Param],
        z: &[f64],
        level: u32,
        stepping: Stepping<'_>,
        interrupt: Option<&AtomicBool>,
    ) -> Run {
        match self
            .base
            .with_overrides(&self.overrides_at(params, z, level))
        {
            Ok(scene) => run_scene(&scene, stepping, interrupt),
            Err(e) => Run::Failed(e.into()),
        }
    }

    /// Runs the base scene with `overrides`.
    fn run_overrides(&self, overrides: &[String], interrupt: Option<&AtomicBool>) -> Run {
        match self.base.with_overrides(overrides) {
            Ok(scene) => run_scene(&scene, Stepping::Own, interrupt),
            Err(e) => Run::Failed(e.into()),
        }
    }

    /// The model at `z` run only until its first melting event has ended (`time.max_events
    /// = 1`), at tolerance `level`: the first onset alone, at about a third of a first slip's
    /// cost (its stick phase is cheap, its meltings are not). The steps up to that event are
    /// the full run's, so its curve is the full run's up to there.
    #[must_use]
    pub fn onset_run(
        &self,
        params: &[Param],
        z: &[f64],
        level: u32,
        interrupt: Option<&AtomicBool>,
    ) -> Run {
        let mut overrides = self.overrides_at(params, z, level);
        overrides.push(time::MAX_EVENTS.set(1).to_string());
        self.run_overrides(&overrides, interrupt)
    }

    /// Runs the model at `z` at a tenth of the tolerance of `level` (the solver's noise is
    /// the difference to [`Forward::run_at`]'s; with fixed steps, at half the step).
    #[must_use]
    pub fn noise_run(
        &self,
        params: &[Param],
        z: &[f64],
        level: u32,
        interrupt: Option<&AtomicBool>,
    ) -> Run {
        let finer = match self.tolerance_at(level) {
            Some(tol) => time::TOLERANCE.set(tol / 10.0),
            None => time::DT.set(self.base.config.time.dt_s / 2.0),
        };
        let mut overrides = self.overrides_at(params, z, level);
        overrides.push(finer.to_string());
        self.run_overrides(&overrides, interrupt)
    }
}

/// Runs a resolved scene as a forward run does (the discretisation check's refined model).
#[must_use]
pub fn run_resolved(scene: &ResolvedScene, interrupt: Option<&AtomicBool>) -> Run {
    run_scene(scene, Stepping::Own, interrupt)
}

/// Runs `scene` with a null sink, stepping as `stepping` says, recording F at every step.
fn run_scene(scene: &ResolvedScene, stepping: Stepping<'_>, interrupt: Option<&AtomicBool>) -> Run {
    let mut curve = ModelCurve::default();
    let mut observe = |sim: &stickslip_core::sim::Simulation| {
        let p = &sim.state().physical;
        curve.t_s.push(p.drive.t_s);
        curve.f_n.push(p.force_n);
        curve.x_m.push(p.drive.x_m);
    };
    let plan = match stepping {
        Stepping::Own => None,
        Stepping::Record(steps) => Some(StepPlan::Record(steps)),
        Stepping::Replay(steps) => Some(StepPlan::Replay { steps, next: 0 }),
    };
    let mut control = Control {
        interrupt,
        observer: Some(&mut observe),
        plan,
        ..Control::default()
    };
    let outcome = match stickslip_run::driver::run(scene, &mut NullSink, &mut control) {
        Ok(o) => o,
        Err(e) => return Run::Failed(RunFailure::Start(e.to_string())),
    };
    match outcome.stop {
        StopReason::Interrupted => Run::Interrupted,
        StopReason::Failure | StopReason::Refused => {
            Run::Failed(outcome.failure.map_or(RunFailure::Unrecorded, Into::into))
        }
        _ => Run::Done(curve),
    }
}
