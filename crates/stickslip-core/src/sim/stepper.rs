//! The stepper: one step of a scheme, chosen once when the simulation is built.
//!
//! A stepper reads the [`Problem`], advances the [`SimState`] by one step, owns its scratch,
//! and says what the step found in a [`StepReport`]; what every scheme shares around the step
//! (counting, the noise generators' positions, the state check, events) is `advance`'s, and
//! the error-controlled loop is `adaptive`'s, over any stepper. A new way of stepping — a
//! scheme, or a film's kinetics inside the accurate scheme — is a new implementation of
//! [`Stepper`] and one arm in `stepper_for` (`sim/mod.rs`); the implementations (`literal`, `accurate`)
//! do not refer to each other.

use super::energy::StepSinks;
use super::problem::Problem;
use super::{NumericalFailure, SimState};
use crate::noise::NoiseSource;
use serde::Serialize;

/// One step of a scheme.
pub(super) trait Stepper: Send + Sync {
    /// Advances film, substrate and stamp in `state` by `dt_s` (drawing the film's noise from
    /// `noise`).
    ///
    /// # Errors
    /// [`NumericalFailure`] when the step cannot be taken (an explicit step's overshoot, a
    /// coupling solve that does not converge); the state is then partly advanced.
    fn step(
        &mut self,
        problem: &Problem,
        state: &mut SimState,
        noise: &mut NoiseSource,
        dt_s: f64,
    ) -> Result<StepReport, NumericalFailure>;
}

/// What a step found, besides the state it advanced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    /// The step's estimated local error (zero for a scheme without an estimate).
    pub error: StepError,
    /// Fraction of the step at which the first node melted (1 = none melted before its end).
    pub first_melt_fraction: f64,
    /// Latest time within the step at which a node rose through the recovery level, located
    /// on its exact path, s; −∞ when none did or the scheme does not locate it.
    pub recovered_at_s: f64,
    /// The coupling solve's residual, root mean square over the nodes, m (0 without a solve).
    pub coupling_rms_m: f64,
    /// The energy books' sinks the stepper computed from its own film step.
    pub sinks: StepSinks,
}

impl Default for StepReport {
    fn default() -> Self {
        Self {
            error: StepError::default(),
            first_melt_fraction: 1.0,
            recovered_at_s: f64::NEG_INFINITY,
            coupling_rms_m: 0.0,
            sinks: StepSinks::default(),
        }
    }
}

/// The estimated local error of a step, each part in units of its own scale (see
/// [`super::Simulation::last_step_error`]); a step is accepted when the largest part is within
/// `time.tolerance`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct StepError {
    /// Film: the largest |Δφ| / max(φ, melt threshold, `numerics.phi_error_floor`·φ_s) over
    /// the nodes (φ_s: the solid film's φ at zero strain; in a step that starts while an event
    /// is open, the floor is the larger of it and `numerics.event_phi_error_floor`).
    pub phi: f64,
    /// Strain: the stamp's position error over h0·εc(t) (the strain it shifts).
    pub eps: f64,
    /// Stamp position: |ΔX| / max(|X|, 1e-3·h0).
    pub x: f64,
    /// Stamp velocity: |ΔV| / max(|V|, 0.1·ω·h0·εc), ω = √(K/m) the drive spring's.
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
