//! Adaptive stepping over any stepper: one step per attempt, its error estimated by the
//! stepper ([`super::stepper::StepReport`]), the next step from a PI controller
//! ([`super::step_control`]), and the step that brings a melting onset ended at the located
//! melting time.

use super::advance::Engine;
use super::plan::{PlannedStep, cuts_to_onset, onset_retake_s};
use super::step_control::StepController;
use super::stepper::StepReport;
use super::{NumericalFailure, SimState};
use crate::config::AdaptiveConfig;

/// Order of the accurate step's local error (second-order scheme: h³).
pub const LOCAL_ERROR_ORDER: f64 = 3.0;

/// One error-controlled step (scene `time.stepping = "adaptive"`), ending at most at
/// `t_stop_s`; returns the length of the accepted step, s.
///
/// Each attempt is one accurate step; its local error is estimated from the step's own
/// values (the defect of the film's exact path against the solved strain, Verlet's
/// remainder for the stamp). An attempt within `time.tolerance` is kept, otherwise the
/// state is rolled back and the step shrinks; a sub-step that fails numerically counts as
/// a rejection too, until h reaches `dt_min`. The next h comes from the PI controller of
/// order 3. An attempt that brings the first melting of an event (no event open before
/// it) is retaken ending at the located melting time, so the step boundary sits on the
/// kink of the substrate's displacement and the onset is not smeared over a long step;
/// the next step then predicts the substrate without extrapolating across the kink.
///
/// `dt_s` is the first step's length (`time.dt`), and `saved_slot` the loop's memory of the
/// state before an attempt (kept between calls so that it is allocated once). Returns the
/// accepted step's length, its report and the step as a plan a replay takes again
/// ([`super::replay`]).
///
/// # Errors
/// [`NumericalFailure`] from a step at `dt_min`.
pub(super) fn step(
    engine: &mut Engine,
    state: &mut SimState,
    saved_slot: &mut Option<Box<SimState>>,
    (ctl, dt_s): (AdaptiveConfig, f64),
    t_stop_s: f64,
) -> Result<(f64, StepReport, PlannedStep), NumericalFailure> {
    let controller = StepController::of_order(LOCAL_ERROR_ORDER);
    let mut saved = saved_slot.take().unwrap_or_else(|| Box::new(state.clone()));
    let mut h_try = if state.controller.next_dt_s > 0.0 {
        state.controller.next_dt_s
    } else {
        dt_s
    };
    let mut cut_to_onset = false;
    // The attempt whose located onset the retake ends at, and the retake's length, s.
    let (mut cut_from_s, mut retake_s) = (0.0, 0.0);
    let result = loop {
        let remaining = t_stop_s - state.physical.drive.t_s;
        let mut h = h_try.min(ctl.dt_max_s);
        // Land on t_stop without leaving a sliver: stretch by up to 10 %, or split evenly.
        if h >= remaining / 1.1 {
            h = remaining;
        } else if h > 0.5 * remaining {
            h = 0.5 * remaining;
        }
        let landing = h == remaining;
        let at_floor = h <= ctl.dt_min_s;
        saved.as_mut().clone_from(state);
        let was_open = state.events.tracker.is_open();
        // A cascade's steps to the looser tolerance (numerics.event_tolerance_factor).
        let tolerance = if was_open {
            ctl.tolerance * engine.problem.config.numerics.event_tolerance_factor
        } else {
            ctl.tolerance
        };
        let (err, report) = match engine.step(state, h) {
            Ok(report) => (report.error.max() / tolerance, report),
            Err(failure) if at_floor => break Err(failure),
            Err(_) => (f64::INFINITY, StepReport::default()),
        };
        if err <= 1.0 || at_floor {
            let theta = report.first_melt_fraction;
            if !cut_to_onset && cuts_to_onset(was_open, theta, h, ctl.dt_min_s) {
                // Retake the step to end just after the located onset.
                state.clone_from(&saved);
                state.counters.onset_retakes += 1;
                cut_to_onset = true;
                cut_from_s = h;
                retake_s = onset_retake_s(theta, h);
                h_try = retake_s;
                continue;
            }
            if err > 1.0 {
                state.counters.forced_steps += 1;
            }
            state.counters.accepted_steps += 1;
            if landing {
                state.physical.drive.t_s = t_stop_s;
            }
            let h_next = controller.accepted(h, err, &mut state.controller);
            // A step shortened to land on t_stop or on an onset says nothing about the
            // next one: the controller's step stands.
            let h_ctl = if landing || cut_to_onset {
                h_next.max(saved.controller.next_dt_s.min(ctl.dt_max_s))
            } else {
                h_next
            };
            state.controller.next_dt_s = h_ctl.max(ctl.dt_min_s);
            if cut_to_onset {
                // The step ended on the kink: no extrapolation of u3D across it.
                state.stepper.last_dt_s = 0.0;
                state.stepper.prev_dt_s = 0.0;
            }
            let planned = if !cut_to_onset {
                PlannedStep::free(h, landing)
            } else if h == retake_s && !landing {
                PlannedStep::onset(cut_from_s)
            } else {
                // Shortened after the retake's own rejection, or stretched to land.
                PlannedStep::held(h, landing)
            };
            break Ok((h, report, planned));
        }
        state.clone_from(&saved);
        state.counters.rejected_steps += 1;
        h_try = controller
            .rejected(h, err, &mut state.controller)
            .max(ctl.dt_min_s);
    };
    *saved_slot = Some(saved);
    result
}
