//! Adaptive stepping: one accurate step per attempt, its error estimated from what the step
//! computed ([`super::error_estimate`]), the next step from a PI controller
//! ([`super::step_control`]), and the step that brings a melting onset ended at the located
//! melting time.

use super::step_control::StepController;
use super::{NumericalFailure, Simulation};
use serde::Serialize;

/// The estimated local error of the last step, each part in units of its own scale (see
/// [`Simulation::last_step_error`]); a step is accepted when the largest part is within
/// `time.tolerance`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct StepError {
    /// Film: the largest |Δφ| / max(φ, melt threshold, `numerics.phi_error_floor`·φ_s) over
    /// the nodes (φ_s: the solid film's φ at zero strain).
    pub phi: f64,
    /// Strain: the stamp's position error over h0·εc(t) (the strain it shifts).
    pub eps: f64,
    /// Stamp position: |ΔX| / max(|X|, 1e-3·h0).
    pub x: f64,
    /// Stamp velocity: |ΔV| / max(|V|, 1e-6·V0).
    pub v: f64,
}

impl StepError {
    /// The largest part.
    #[must_use]
    pub fn max(&self) -> f64 {
        let m = self.phi.max(self.eps).max(self.x).max(self.v);
        if m.is_nan() { f64::INFINITY } else { m }
    }
}

/// Order of the accurate step's local error (second-order scheme: h³).
pub const LOCAL_ERROR_ORDER: f64 = 3.0;

/// An onset located closer than this fraction of the step to its start is taken as is
/// (cutting the step there would leave a sliver).
const MIN_CUT_FRACTION: f64 = 1e-3;

impl Simulation {
    /// The last step's estimated local error (accurate scheme; zero for the literal one).
    pub fn last_step_error(&self) -> StepError {
        self.last_error
    }

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
    /// # Errors
    /// [`NumericalFailure`] from a step at `dt_min`.
    ///
    /// # Panics
    /// If the configuration is not adaptive.
    pub fn step_adaptive(&mut self, t_stop_s: f64) -> Result<f64, NumericalFailure> {
        let ctl = self
            .config
            .time
            .adaptive
            .expect("step_adaptive needs time.adaptive");
        let controller = StepController::of_order(LOCAL_ERROR_ORDER);
        let mut saved = self
            .saved
            .take()
            .unwrap_or_else(|| Box::new(self.state.clone()));
        let mut h_try = if self.state.controller.next_dt_s > 0.0 {
            self.state.controller.next_dt_s
        } else {
            self.config.time.dt_s
        };
        let mut cut_to_onset = false;
        let result = loop {
            let remaining = t_stop_s - self.state.physical.drive.t_s;
            let mut h = h_try.min(ctl.dt_max_s);
            // Land on t_stop without leaving a sliver: stretch by up to 10 %, or split evenly.
            if h >= remaining / 1.1 {
                h = remaining;
            } else if h > 0.5 * remaining {
                h = 0.5 * remaining;
            }
            let landing = h == remaining;
            let at_floor = h <= ctl.dt_min_s;
            saved.as_mut().clone_from(&self.state);
            let was_open = self.state.events.tracker.is_open();
            let err = match self.step(h) {
                Ok(()) => self.last_error.max() / ctl.tolerance,
                Err(failure) if at_floor => break Err(failure),
                Err(_) => f64::INFINITY,
            };
            if err <= 1.0 || at_floor {
                let theta = self.first_melt_fraction;
                if !was_open
                    && !cut_to_onset
                    && theta < 1.0
                    && theta > MIN_CUT_FRACTION
                    && theta * h > ctl.dt_min_s
                {
                    // Retake the step to end just after the located onset (the margin keeps
                    // the crossing inside it despite rounding).
                    self.state.clone_from(&saved);
                    self.state.counters.onset_retakes += 1;
                    cut_to_onset = true;
                    h_try = theta * h * (1.0 + 1e-9);
                    continue;
                }
                if err > 1.0 {
                    self.state.counters.forced_steps += 1;
                }
                self.state.counters.accepted_steps += 1;
                if landing {
                    self.state.physical.drive.t_s = t_stop_s;
                }
                let h_next = controller.accepted(h, err, &mut self.state.controller);
                // A step shortened to land on t_stop or on an onset says nothing about the
                // next one: the controller's step stands.
                let h_ctl = if landing || cut_to_onset {
                    h_next.max(saved.controller.next_dt_s.min(ctl.dt_max_s))
                } else {
                    h_next
                };
                self.state.controller.next_dt_s = h_ctl.max(ctl.dt_min_s);
                if cut_to_onset {
                    // The step ended on the kink: no extrapolation of u3D across it.
                    self.state.stepper.last_dt_s = 0.0;
                    self.state.stepper.prev_dt_s = 0.0;
                }
                break Ok(h);
            }
            self.state.clone_from(&saved);
            self.state.counters.rejected_steps += 1;
            h_try = controller
                .rejected(h, err, &mut self.state.controller)
                .max(ctl.dt_min_s);
        };
        self.saved = Some(saved);
        result
    }
}
