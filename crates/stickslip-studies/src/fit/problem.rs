//! One fit's evaluations: the model at box coordinates z run and compared with the data,
//! `jobs` runs at a time on the run library's pool, with the counts fit.json reports
//! (evaluations, failed runs — a failed run is a penalty, the misfit of a model without any
//! of the data, not an error), the best model so far, progress, and Ctrl-C: an interrupted
//! batch returns nothing and every later one is skipped, so the optimiser stops with the best
//! model it has.

use super::forward::{Forward, JacobianKind, Run, RunFailure, Stepping};
use super::misfit::{Compared, Target};
use super::params::{Param, TIME_SHIFT};
use super::pin::{self, Pin};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use stickslip_core::sim::PlannedStep;

/// The recorded step plans a fit keeps (its most recent runs'): the local stage's next
/// Jacobian is taken at a point it has just run.
const PLANS_KEPT: usize = 16;

/// A recorded run's steps, shared by the replays of a Jacobian.
pub type Plan = Arc<Vec<PlannedStep>>;

/// How a batch's runs step.
#[derive(Debug, Clone, Copy)]
enum Mode<'a> {
    /// As the scene says (`finer`: at a tenth of the tolerance).
    Own { finer: bool },
    /// Replaying a recorded run's steps.
    Replay(&'a [PlannedStep]),
}

/// One evaluated model.
#[derive(Debug, Clone, PartialEq)]
pub struct Eval {
    /// Box coordinates of the parameters.
    pub z: Vec<f64>,
    /// Its residuals.
    pub residuals: Vec<f64>,
    /// The misfit χ² = Σ r².
    pub chi2: f64,
    /// Why its run failed, if it did (the residuals are then the penalty).
    pub failed: Option<String>,
    /// The tolerance level it was run at.
    pub level: u32,
}

/// Where a fit is, for a progress display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// The stage: `global`, `local`, `valley`, `noise`, `uncertainty` or `profile`.
    pub stage: &'static str,
    /// Forward runs so far.
    pub evaluations: usize,
    /// Of which failed.
    pub failed_runs: usize,
    /// The least misfit χ² so far (infinite before the first run).
    pub best_chi2: f64,
    /// The runs' tolerance level: their tolerance is the fit's first one / 10^level.
    pub level: u32,
    /// The runs' `time.tolerance` at that level (none with fixed steps).
    pub tolerance: Option<f64>,
    /// Runs of the present batch (a global sample, a Jacobian, a line search's points, the
    /// noise runs) not ended yet.
    pub batch_left: usize,
    /// The batch's remaining wall time, s, from the mean wall time of the runs at this
    /// tolerance so far (none before the first such run ends).
    pub batch_eta_s: Option<f64>,
}

/// A progress callback; returning true stops the fit as Ctrl-C does.
pub type OnProgress<'a> = dyn FnMut(&Progress) -> bool + 'a;

/// The fit's evaluations (see the module's docs); `'a` the data's lifetime, `'p` the
/// caller's interrupt flag and progress callback's.
pub struct Problem<'a, 'p> {
    /// The forward runs.
    pub forward: &'a Forward,
    /// The free parameters.
    pub params: &'a [Param],
    /// The data.
    pub target: &'a Target,
    /// Runs at a time.
    pub jobs: usize,
    /// Set by Ctrl-C.
    pub interrupt: Option<&'p AtomicBool>,
    /// Progress, called on the calling thread a few times a second.
    pub progress: Option<&'p mut OnProgress<'p>>,
    /// The stage, for progress.
    pub stage: &'static str,
    /// Forward runs so far (noise runs included).
    pub evaluations: usize,
    /// Of which failed.
    pub failed_runs: usize,
    /// The first failure, in words.
    pub first_failure: Option<String>,
    /// The best model so far (at the present `level`).
    pub best: Option<Eval>,
    /// The runs' tolerance level ([`Forward::run_at`]); raised by the optimiser when the
    /// solver's noise is too large for the data ([`super::optimise::settle`]).
    pub level: u32,
    /// The last Jacobian made (by the local stage or for the intervals): an interrupted fit
    /// takes its provisional intervals from it.
    pub last_jacobian: Option<LastJacobian>,
    /// The highest tolerance level the optimiser may raise `level` to
    /// ([`super::forward::MAX_LEVEL`]; the profile strategy's search holds it at 0: a global
    /// search needs the misfit's shape, not its last digits, and a finer run costs twice).
    pub max_level: u32,
    /// The parameter solved at every point so that the first onset matches (the profile
    /// strategy, [`super::pin`]); none in the direct strategy.
    pub pin: Option<Pin>,
    /// Runs stopped after their first melting, made to solve the pinned parameter (not
    /// counted in `evaluations`).
    pub onset_runs: usize,
    /// Wall time and count of the runs so far, per (level, finer): the mean estimates a
    /// batch's remaining time (a finer run costs more than a run at the fit's tolerance).
    run_times: std::collections::HashMap<(u32, bool), (f64, usize)>,
    stopped: bool,
    /// How the Jacobians are made (`--jacobian`).
    pub jacobian: JacobianKind,
    /// Jacobians made so far: replayed, and by differences.
    pub jacobians_made: (usize, usize),
    /// Why the last Jacobian asked to be replayed was made by differences.
    pub jacobian_fallback: Option<&'static str>,
    /// With replayed Jacobians, the step plans of the most recent runs: (z, level, plan).
    plans: Vec<(Vec<f64>, u32, Plan)>,
}

/// A Jacobian of the residuals in box coordinates, and where it was made.
#[derive(Debug, Clone, PartialEq)]
pub struct LastJacobian {
    /// The point, box coordinates.
    pub z: Vec<f64>,
    /// The parameters it differentiates (indices).
    pub free: Vec<usize>,
    /// Its columns, one per free parameter.
    pub columns: Vec<Vec<f64>>,
}

impl<'a, 'p> Problem<'a, 'p> {
    /// A fit's evaluations, none made yet.
    pub fn new(forward: &'a Forward, params: &'a [Param], target: &'a Target, jobs: usize) -> Self {
        Self {
            forward,
            params,
            target,
            jobs: jobs.max(1),
            interrupt: None,
            progress: None,
            stage: "global",
            last_jacobian: None,
            evaluations: 0,
            failed_runs: 0,
            first_failure: None,
            best: None,
            level: 0,
            max_level: super::forward::MAX_LEVEL,
            pin: None,
            onset_runs: 0,
            run_times: std::collections::HashMap::new(),
            stopped: false,
            jacobian: JacobianKind::default(),
            jacobians_made: (0, 0),
            jacobian_fallback: None,
            plans: Vec::new(),
        }
    }

    /// The recorded steps of the run at `z` at the present level, if it is one of the most
    /// recent runs of a fit with replayed Jacobians.
    #[must_use]
    pub fn plan_at(&self, z: &[f64]) -> Option<Plan> {
        self.plans
            .iter()
            .rev()
            .find(|(at, level, _)| *level == self.level && at.as_slice() == z)
            .map(|(_, _, p)| Arc::clone(p))
    }

    /// Evaluates every `zs` replaying `plan` (not counted as the best: a replay is the model
    /// at z stepped as another point's run, for a difference with that run); `None` when
    /// interrupted.
    pub fn evaluate_replayed(
        &mut self,
        zs: &[Vec<f64>],
        plan: &[PlannedStep],
    ) -> Option<Vec<Eval>> {
        self.evaluate_with(zs, Mode::Replay(plan))
    }

    /// Whether the fit was interrupted (Ctrl-C, or the progress callback asked to stop).
    #[must_use]
    pub fn interrupted(&self) -> bool {
        self.stopped || self.interrupt.is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// Stops the fit as Ctrl-C does (a stage run on another problem was stopped).
    pub fn stop(&mut self) {
        self.stopped = true;
    }

    /// The time shift at `z` (0 without one), s.
    #[must_use]
    pub fn shift_s(&self, z: &[f64]) -> f64 {
        shift_s(self.params, z)
    }

    /// One run's comparison with the data (`finer`: at a tenth of the tolerance).
    fn run(&self, z: &[f64], finer: bool) -> Option<Result<Compared, RunFailure>> {
        run_one(
            (self.forward, self.params, self.target),
            (self.interrupt, self.level),
            z,
            finer,
        )
    }

    /// The comparison of the model at `z` with the data, for the outputs (counted as a run).
    pub fn compare(&mut self, z: &[f64]) -> Option<Compared> {
        self.evaluations += 1;
        match self.run(z, false)? {
            Ok(c) => Some(c),
            Err(_) => Some(Compared {
                residuals: self.target.failed(),
                ..Compared::default()
            }),
        }
    }

    /// Evaluates every `zs` (`finer`: at a tenth of the tolerance, not counted as the best);
    /// `None` when interrupted.
    pub fn evaluate_all(&mut self, zs: &[Vec<f64>], finer: bool) -> Option<Vec<Eval>> {
        self.evaluate_with(zs, Mode::Own { finer })
    }

    /// [`Problem::evaluate_all`] and [`Problem::evaluate_replayed`].
    fn evaluate_with(&mut self, zs: &[Vec<f64>], mode: Mode<'_>) -> Option<Vec<Eval>> {
        // A finer run measures the solver's noise; a replay is a Jacobian's: neither is the
        // best model.
        let finer = matches!(mode, Mode::Own { finer: true });
        let counts_as_best = matches!(mode, Mode::Own { finer: false });
        // Runs of the fit's own stepping keep their steps for a replayed Jacobian.
        let record = counts_as_best
            && self.jacobian == JacobianKind::Replay
            && self.forward.tolerance.is_some();
        if self.interrupted() {
            self.stopped = true;
            return None;
        }
        let model = (self.forward, self.params, self.target);
        let how = (self.interrupt, self.level);
        // Runs ended in this batch and their summed wall time, µs, for the progress's ETA.
        let ended = AtomicUsize::new(0);
        let onset_runs = AtomicUsize::new(0);
        let spent_us = std::sync::atomic::AtomicU64::new(0);
        let pinned = self.pin.clone();
        let slopes = std::sync::Mutex::new(Vec::new());
        let work = |i: usize| {
            let t0 = std::time::Instant::now();
            // A finer run measures the solver's noise at the point itself: the pin held.
            let r = match pinned.as_ref().filter(|_| counts_as_best) {
                Some(p) => {
                    // The whole run at the solved point keeps its steps.
                    let plan = std::cell::RefCell::new(Vec::new());
                    let solved = pin::solve(model, how, &zs[i], p, |z| {
                        let mut steps = plan.borrow_mut();
                        let stepping = if record {
                            Stepping::Record(&mut steps)
                        } else {
                            Stepping::Own
                        };
                        run_stepping(model, how, z, (false, stepping))
                    });
                    onset_runs.fetch_add(solved.onset_runs, Ordering::Relaxed);
                    if let Some(s) = solved.slope {
                        slopes.lock().map(|mut v| v.push(s)).ok();
                    }
                    let plan = record.then(|| Arc::new(plan.into_inner()));
                    solved.compared.map(|c| (solved.z, c, plan))
                }
                None => {
                    let mut plan = Vec::new();
                    let stepping = match mode {
                        Mode::Replay(steps) => Stepping::Replay(steps),
                        Mode::Own { .. } if record => Stepping::Record(&mut plan),
                        Mode::Own { .. } => Stepping::Own,
                    };
                    run_stepping(model, how, &zs[i], (finer, stepping))
                        .map(|c| (zs[i].clone(), c, record.then(|| Arc::new(plan))))
                }
            };
            let us = u64::try_from(t0.elapsed().as_micros()).unwrap_or(u64::MAX);
            spent_us.fetch_add(us, Ordering::Relaxed);
            ended.fetch_add(1, Ordering::Relaxed);
            r
        };
        let level = self.level;
        let tolerance = self.forward.tolerance_at(level);
        let (before_s, before_n) = self
            .run_times
            .get(&(level, finer))
            .copied()
            .unwrap_or((0.0, 0));
        let jobs = self.jobs;
        let (stage, evaluations, failed, best) = (
            self.stage,
            self.evaluations,
            self.failed_runs,
            self.best.as_ref().map_or(f64::INFINITY, |b| b.chi2),
        );
        let mut stop = false;
        let progress = &mut self.progress;
        let mut tick = || {
            if let Some(p) = progress.as_mut() {
                let done = ended.load(Ordering::Relaxed);
                let spent = spent_us.load(Ordering::Relaxed) as f64 * 1e-6;
                let (total_s, runs) = (before_s + spent, before_n + done);
                let left = zs.len().saturating_sub(done);
                stop |= p(&Progress {
                    stage,
                    evaluations: evaluations + done,
                    failed_runs: failed,
                    best_chi2: best,
                    level,
                    tolerance,
                    batch_left: left,
                    batch_eta_s: (runs > 0)
                        .then(|| total_s / runs as f64 * left.div_ceil(jobs) as f64),
                });
            }
        };
        let results = crate::pool::map(zs.len(), self.jobs, &work, &mut tick);
        let entry = self.run_times.entry((level, finer)).or_insert((0.0, 0));
        entry.0 += spent_us.load(Ordering::Relaxed) as f64 * 1e-6;
        entry.1 += ended.load(Ordering::Relaxed);
        self.evaluations += zs.len();
        self.onset_runs += onset_runs.load(Ordering::Relaxed);
        // The pin's next secants start from the slope found near this batch's solutions (the
        // first onset is far from linear over the box: its slope near the needle differs
        // several times from the start's).
        if let (Some(p), Ok(mut v)) = (self.pin.as_mut(), slopes.into_inner())
            && !v.is_empty()
        {
            v.sort_by(f64::total_cmp);
            p.slope = v[v.len() / 2];
        }
        let mut out = Vec::with_capacity(zs.len());
        for r in results {
            let Some((z, r, plan)) = r else {
                self.stopped = true;
                continue;
            };
            if let Some(plan) = plan.filter(|_| r.is_ok()) {
                if self.plans.len() >= PLANS_KEPT {
                    self.plans.remove(0);
                }
                self.plans.push((z.clone(), self.level, plan));
            }
            let (residuals, failed) = match r {
                Ok(c) => (c.residuals, None),
                Err(failure) => {
                    let why = failure.to_string();
                    self.failed_runs += 1;
                    self.first_failure.get_or_insert_with(|| why.clone());
                    (self.target.failed(), Some(why))
                }
            };
            let chi2 = residuals.iter().map(|r| r * r).sum();
            out.push(Eval {
                z,
                residuals,
                chi2,
                failed,
                level: self.level,
            });
        }
        // The runs that ended count for the best model even when the batch was interrupted.
        // The pin's next first trials move from this batch's best point.
        if let Some(p) = self.pin.as_mut()
            && let Some(e) = out
                .iter()
                .filter(|e| e.failed.is_none())
                .min_by(|a, b| a.chi2.total_cmp(&b.chi2))
        {
            p.anchor.clone_from(&e.z);
            p.anchor_residual = e.residuals[0];
        }
        if counts_as_best {
            for e in &out {
                if e.failed.is_none() && self.best.as_ref().is_none_or(|b| e.chi2 < b.chi2) {
                    self.best = Some(e.clone());
                }
            }
        }
        if let (Some(p), Some(b)) = (self.pin.as_mut(), self.best.as_ref()) {
            p.tolerance = pin::tolerance_for(b.chi2, self.target.len());
        }
        if stop {
            self.stopped = true;
        }
        (!self.stopped).then_some(out)
    }
}

/// The time shift of `params` at `z` (0 without one), s.
fn shift_s(params: &[Param], z: &[f64]) -> f64 {
    params
        .iter()
        .zip(z)
        .find(|(p, _)| p.key == TIME_SHIFT)
        .map_or(0.0, |(p, &z)| p.value(z))
}

/// One run of the model at `z` at tolerance `level` compared with the data (`finer`: at a
/// tenth of that tolerance); `None` when interrupted.
fn run_one(
    model: (&Forward, &[Param], &Target),
    how: (Option<&AtomicBool>, u32),
    z: &[f64],
    finer: bool,
) -> Option<Result<Compared, RunFailure>> {
    run_stepping(model, how, z, (finer, Stepping::Own))
}

/// [`run_one`], stepping as `stepping` says (a finer run steps on its own).
fn run_stepping(
    (forward, params, target): (&Forward, &[Param], &Target),
    (interrupt, level): (Option<&AtomicBool>, u32),
    z: &[f64],
    (finer, stepping): (bool, Stepping<'_>),
) -> Option<Result<Compared, RunFailure>> {
    let run = if finer {
        forward.noise_run(params, z, level, interrupt)
    } else {
        forward.run_stepping(params, z, level, stepping, interrupt)
    };
    match run {
        Run::Done(curve) => Some(Ok(target.compare(&curve, shift_s(params, z)))),
        Run::Failed(why) => Some(Err(why)),
        Run::Interrupted => None,
    }
}
