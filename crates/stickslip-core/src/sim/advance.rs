//! One step of any scheme with what every step shares: the stepper's step, the step counted,
//! the noise generators' positions kept in the state (so that a checkpoint resumes the same
//! random numbers), the state checked, and the events observed ([`super::watch`]).

use super::books;
use super::problem::Problem;
use super::stepper::{StepReport, Stepper};
use super::{NumericalFailure, SimState, watch};
use crate::noise::NoiseSource;

/// The parts of a simulation a step uses besides its state.
pub(super) struct Engine {
    pub problem: Problem,
    pub stepper: Box<dyn Stepper>,
    pub noise: NoiseSource,
}

impl Engine {
    /// Advances `state` by `dt_s`.
    ///
    /// # Errors
    /// [`NumericalFailure`] from the stepper or the state check.
    pub fn step(
        &mut self,
        state: &mut SimState,
        dt_s: f64,
    ) -> Result<StepReport, NumericalFailure> {
        let start = books::StepStart::of(&self.problem, &state.physical);
        let report = self
            .stepper
            .step(&self.problem, state, &mut self.noise, dt_s)?;
        state.counters.step += 1;
        // Gaussian noise only; the other kinds draw nothing.
        if !state.physical.noise.word_pos.is_empty() {
            self.noise.write_state(&mut state.physical.noise);
        }
        watch::check_state(&self.problem, state)?;
        let books = (
            books::step_flows(&self.problem, &start, &state.physical, &report.sinks),
            books::stored(&self.problem, &state.physical),
        );
        watch::observe_events(&self.problem, state, &report, books);
        Ok(report)
    }
}
