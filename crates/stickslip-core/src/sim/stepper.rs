//! The stepper: one step of a scheme, chosen once when the simulation is built.
//!
//! [`Simulation::step`] hands the step to its stepper and then does what every scheme shares
//! (counting, the noise generators' positions, the state check, events). A new way of
//! stepping — a scheme, or a film's kinetics inside the accurate scheme — is a new
//! implementation of [`Stepper`] and one line in [`for_config`], not a branch inside the
//! step. The steps themselves are written in their own modules (`literal`, `accurate`), which
//! do not refer to this one.

use super::film::{Film, FirstOrder, SecondOrder, SecondOrderRamp};
use super::{NumericalFailure, Simulation};
use crate::config::{FilmStep, Scheme, SimConfig};
use std::sync::Arc;

/// One step of a scheme.
pub(super) trait Stepper: Send + Sync {
    /// Advances film, substrate and stamp of `sim` by `dt_s`; the shared bookkeeping
    /// (counters, noise positions, the state check, events) is [`Simulation::step`]'s.
    fn step(&self, sim: &mut Simulation, dt_s: f64) -> Result<(), NumericalFailure>;
}

/// The paper's literal scheme (explicit Euler, one lagged sweep).
#[derive(Debug, Clone, Copy)]
struct Literal;

impl Stepper for Literal {
    fn step(&self, sim: &mut Simulation, dt_s: f64) -> Result<(), NumericalFailure> {
        sim.step_literal(dt_s)
    }
}

/// The accurate scheme with the film's kinetics `F`.
#[derive(Debug, Clone, Copy)]
struct Accurate<F> {
    film: F,
}

impl<F: Film + Send + Sync> Stepper for Accurate<F> {
    fn step(&self, sim: &mut Simulation, dt_s: f64) -> Result<(), NumericalFailure> {
        sim.step_accurate_with(&self.film, dt_s)
    }
}

/// The stepper of `config`: the literal scheme, or the accurate scheme with the film's
/// kinetics of the second-order film (b₃ = 0; its step ramp-corrected, or frozen as before)
/// or of the first-order one.
///
/// Shared (`Arc`) so that a step can hold the stepper while it borrows the simulation
/// mutably: taking a handle is a counter increment, no allocation in the step loop.
pub(super) fn for_config(config: &SimConfig) -> Arc<dyn Stepper> {
    let params = config.lubricant;
    match config.time.scheme {
        Scheme::Literal => Arc::new(Literal),
        Scheme::Accurate if params.cubic_pa == 0.0 => match config.numerics.film_step {
            FilmStep::Ramp => Arc::new(Accurate {
                film: SecondOrderRamp(SecondOrder::new(params)),
            }),
            FilmStep::Frozen => Arc::new(Accurate {
                film: SecondOrder::new(params),
            }),
        },
        Scheme::Accurate => Arc::new(Accurate {
            film: FirstOrder::new(params),
        }),
    }
}
