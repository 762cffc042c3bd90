//! An adaptive run's step sequence taken again: the steps of a run recorded as a plan, and a
//! step of that plan taken without error control. A run of a slightly different scene (a
//! parameter moved by a finite-difference step) that replays the plan of the run it is
//! compared with follows the same discrete map, so the difference of the two measures the
//! derivative of the discrete solution, free of the jitter of the step-size controller's
//! decisions (internal numerical differentiation, after Bock). Melting onsets stay where the
//! replaying run's own film puts them: a step that brings a first melting is cut there, as
//! [`super::adaptive::step`] cuts it, so an onset that moves with the parameter moves the
//! step boundary with it.

use super::advance::Engine;
use super::plan::{PlannedStep, StepKind, cuts_to_onset, onset_retake_s};
use super::stepper::StepReport;
use super::{NumericalFailure, SimState};

/// Takes `planned` from `state`, ending at most at `t_stop_s`; returns the step's length and
/// report. No error control: the step is accepted whatever its error (a replay follows the
/// recorded run's decisions). `dt_min_s` is the scene's shortest step (an onset is cut only
/// where the adaptive loop would cut it).
///
/// # Errors
/// [`NumericalFailure`] from the step (a replay does not retry).
pub(super) fn step(
    engine: &mut Engine,
    state: &mut SimState,
    saved_slot: &mut Option<Box<SimState>>,
    (planned, dt_min_s): (PlannedStep, f64),
    t_stop_s: f64,
) -> Result<(f64, StepReport), NumericalFailure> {
    let remaining = t_stop_s - state.physical.drive.t_s;
    // A step that overshoots its stop (the replaying run's onsets moved the times a little)
    // lands there.
    let h = if planned.landed || planned.h_s >= remaining {
        remaining
    } else {
        planned.h_s
    };
    let was_open = state.events.tracker.is_open();
    let mut saved = saved_slot.take().unwrap_or_else(|| Box::new(state.clone()));
    let may_cut = planned.kind != StepKind::Held;
    if may_cut {
        saved.as_mut().clone_from(state);
    }
    let result = (|| {
        let report = engine.step(state, h)?;
        let theta = report.first_melt_fraction;
        if may_cut && cuts_to_onset(was_open, theta, h, dt_min_s) {
            state.clone_from(&saved);
            state.counters.onset_retakes += 1;
            let cut = onset_retake_s(theta, h);
            let report = engine.step(state, cut)?;
            state.stepper.last_dt_s = 0.0;
            state.stepper.prev_dt_s = 0.0;
            return Ok((cut, report));
        }
        if h == remaining {
            state.physical.drive.t_s = t_stop_s;
        }
        if planned.kind == StepKind::Held {
            // Taken after an onset's cut: as the adaptive loop does, no extrapolation of u3D
            // across the onset's kink.
            state.stepper.last_dt_s = 0.0;
            state.stepper.prev_dt_s = 0.0;
        }
        Ok((h, report))
    })();
    *saved_slot = Some(saved);
    if result.is_ok() {
        state.counters.accepted_steps += 1;
    }
    result
}
