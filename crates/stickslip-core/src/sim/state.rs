//! The simulation's state, apart from its stepper: what the film, the substrate and the stamp
//! are ([`PhysicalState`]), what the stepper remembers of earlier steps ([`StepperMemory`]),
//! what the step-size controller remembers ([`ControllerMemory`]), how many steps of each kind
//! were taken ([`StepCounters`]) and the melting events so far ([`EventBook`]).
//!
//! [`SimState`] is the aggregate a checkpoint saves and restores; it is not a file format
//! (the run library's checkpoint module maps it to and from its own versioned type). Every
//! part clones field by field so that `clone_from` reuses every buffer: adaptive stepping saves
//! and restores the state on every attempt, and a derived `clone_from` would allocate each
//! vector anew (the exhaustive patterns make a new field a compile error until it is handled).

use super::events::EventTracker;
pub use super::step_control::ControllerMemory;
use crate::drive::DriveState;
use crate::noise::NoiseState;

/// Everything that evolves, in five parts.
#[derive(Debug, PartialEq)]
pub struct SimState {
    /// Film, substrate, stamp and the noise generators' positions.
    pub physical: PhysicalState,
    /// What the stepper remembers of earlier steps.
    pub stepper: StepperMemory,
    /// Adaptive stepping: what the step-size controller remembers.
    pub controller: ControllerMemory,
    /// Steps, attempts and solver iterations so far.
    pub counters: StepCounters,
    /// Melting events and the per-node record they are detected from.
    pub events: EventBook,
}

/// The physical state at the current time.
#[derive(Debug, PartialEq)]
pub struct PhysicalState {
    /// Stamp kinematics (and the time).
    pub drive: DriveState,
    /// Order parameter φ per node.
    pub phi: Vec<f64>,
    /// Stamp-surface displacement since the node last re-solidified, m.
    pub u0_m: Vec<f64>,
    /// Substrate displacement, m.
    pub u3d_m: Vec<f64>,
    /// Elastic strain ε = (u0 − u3D)/h0 as used for τ.
    pub eps: Vec<f64>,
    /// Shear stress τ = aφ²ε, Pa.
    pub tau_pa: Vec<f64>,
    /// Friction force F = 2π∫τ r dr, N.
    pub force_n: f64,
    /// Noise generators' positions (a resumed run draws the same numbers).
    pub noise: NoiseState,
}

/// What the stepper remembers of earlier steps: the substrate's history, which gives the
/// coupling solve its first guess and the film its predicted strain, and the stamp's last
/// change of acceleration, which the velocity's error estimate extrapolates.
#[derive(Debug, PartialEq)]
pub struct StepperMemory {
    /// Substrate displacement one step earlier, m: the coupling solve starts from the
    /// extrapolation of u3D, which cuts the solver's iterations in the stick phase.
    pub u3d_prev_m: Vec<f64>,
    /// Substrate displacement two steps earlier, m (empty before the second step): with
    /// `u3d_prev_m` and the current u3D it gives the coupling solve a quadratic first guess.
    pub u3d_prev2_m: Vec<f64>,
    /// Length of the last step taken, s (0 before the first, and after a step that ended on a
    /// melting onset): scales the extrapolation of u3D.
    pub last_dt_s: f64,
    /// Length of the step before the last one, s (0 before the second step).
    pub prev_dt_s: f64,
    /// Change of the stamp's acceleration over the last step, m/s² (for the velocity's error
    /// estimate; 0 before the first step).
    pub accel_change_prev_m_per_s2: f64,
    /// The stamp's mean velocity over the last step, ΔX/Δt, m/s (0 before the first step and
    /// without viscosity; docs/model.md#viscosity): with the last step's length, the stamp's
    /// history for the viscous stress's second-order rate.
    pub mean_v_m_per_s: f64,
    /// The Ẋ of the film's viscous stress at the state's time, m/s, which the drive's kicks
    /// leave to the spring's flow (0 before the first step and without viscosity).
    pub viscous_v_m_per_s: f64,
    /// The film's shear rate r = Ẋ − u̇3D per node one step earlier, m/s (empty without
    /// viscosity): for the viscous coupling's error estimate.
    pub viscous_rate_prev_m_per_s: Vec<f64>,
}

/// Steps, attempts and solver iterations so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StepCounters {
    /// Steps taken.
    pub step: u64,
    /// Adaptive stepping: accepted steps.
    pub accepted_steps: u64,
    /// Adaptive stepping: rejected attempts (error above tolerance, or a failed sub-step).
    pub rejected_steps: u64,
    /// Adaptive stepping: steps accepted at `time.dt_min` although their error exceeded the
    /// tolerance.
    pub forced_steps: u64,
    /// Adaptive stepping: accepted attempts that brought a melting onset and were taken again
    /// ending at the located melting time (each one more evaluation of the step).
    pub onset_retakes: u64,
    /// Coupling-solver iterations summed over all steps (accurate scheme).
    pub coupling_iterations: u64,
}

/// Melting events so far and the per-node record the steps leave for their detection.
#[derive(Debug, PartialEq)]
pub struct EventBook {
    /// Melting events so far.
    pub tracker: EventTracker,
    /// Nodes that melted during the last step, whatever their φ at its end: the accurate
    /// scheme's melting is instantaneous, so these count as melted for events and observables.
    pub melted_in_step: Vec<bool>,
    /// When each node last melted (went from solid to below the threshold), s; −1 before its
    /// first melting. The accurate scheme's melting is instantaneous (φ touches the threshold
    /// and recovers within the step), so sampled φ rarely shows it; this does, located in time.
    pub last_melt_s: Vec<f64>,
    /// Nodes that melted at least once during the open event (cleared while none is open).
    pub swept: Vec<bool>,
}

impl Clone for SimState {
    fn clone(&self) -> Self {
        let Self {
            physical,
            stepper,
            controller,
            counters,
            events,
        } = self;
        Self {
            physical: physical.clone(),
            stepper: stepper.clone(),
            controller: *controller,
            counters: *counters,
            events: events.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        let Self {
            physical,
            stepper,
            controller,
            counters,
            events,
        } = source;
        self.physical.clone_from(physical);
        self.stepper.clone_from(stepper);
        self.controller = *controller;
        self.counters = *counters;
        self.events.clone_from(events);
    }
}

impl Clone for PhysicalState {
    fn clone(&self) -> Self {
        let Self {
            drive,
            phi,
            u0_m,
            u3d_m,
            eps,
            tau_pa,
            force_n,
            noise,
        } = self;
        Self {
            drive: *drive,
            phi: phi.clone(),
            u0_m: u0_m.clone(),
            u3d_m: u3d_m.clone(),
            eps: eps.clone(),
            tau_pa: tau_pa.clone(),
            force_n: *force_n,
            noise: noise.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        let Self {
            drive,
            phi,
            u0_m,
            u3d_m,
            eps,
            tau_pa,
            force_n,
            noise,
        } = source;
        self.drive = *drive;
        self.phi.clone_from(phi);
        self.u0_m.clone_from(u0_m);
        self.u3d_m.clone_from(u3d_m);
        self.eps.clone_from(eps);
        self.tau_pa.clone_from(tau_pa);
        self.force_n = *force_n;
        self.noise.clone_from(noise);
    }
}

impl Clone for StepperMemory {
    fn clone(&self) -> Self {
        let Self {
            u3d_prev_m,
            u3d_prev2_m,
            last_dt_s,
            prev_dt_s,
            accel_change_prev_m_per_s2,
            mean_v_m_per_s,
            viscous_v_m_per_s,
            viscous_rate_prev_m_per_s,
        } = self;
        Self {
            u3d_prev_m: u3d_prev_m.clone(),
            u3d_prev2_m: u3d_prev2_m.clone(),
            last_dt_s: *last_dt_s,
            prev_dt_s: *prev_dt_s,
            accel_change_prev_m_per_s2: *accel_change_prev_m_per_s2,
            mean_v_m_per_s: *mean_v_m_per_s,
            viscous_v_m_per_s: *viscous_v_m_per_s,
            viscous_rate_prev_m_per_s: viscous_rate_prev_m_per_s.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        let Self {
            u3d_prev_m,
            u3d_prev2_m,
            last_dt_s,
            prev_dt_s,
            accel_change_prev_m_per_s2,
            mean_v_m_per_s,
            viscous_v_m_per_s,
            viscous_rate_prev_m_per_s,
        } = source;
        self.u3d_prev_m.clone_from(u3d_prev_m);
        self.u3d_prev2_m.clone_from(u3d_prev2_m);
        self.last_dt_s = *last_dt_s;
        self.prev_dt_s = *prev_dt_s;
        self.accel_change_prev_m_per_s2 = *accel_change_prev_m_per_s2;
        self.mean_v_m_per_s = *mean_v_m_per_s;
        self.viscous_v_m_per_s = *viscous_v_m_per_s;
        self.viscous_rate_prev_m_per_s
            .clone_from(viscous_rate_prev_m_per_s);
    }
}

impl Clone for EventBook {
    fn clone(&self) -> Self {
        let Self {
            tracker,
            melted_in_step,
            last_melt_s,
            swept,
        } = self;
        Self {
            tracker: tracker.clone(),
            melted_in_step: melted_in_step.clone(),
            last_melt_s: last_melt_s.clone(),
            swept: swept.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        let Self {
            tracker,
            melted_in_step,
            last_melt_s,
            swept,
        } = source;
        self.tracker.clone_from(tracker);
        self.melted_in_step.clone_from(melted_in_step);
        self.last_melt_s.clone_from(last_melt_s);
        self.swept.clone_from(swept);
    }
}

impl SimState {
    /// Checks that every per-node vector has `nodes` entries (the substrate's history from two
    /// steps back may also be empty, before the second step), so a restored state cannot
    /// index out of range.
    ///
    /// # Errors
    /// The first vector of another length.
    pub(super) fn check_nodes(&self, nodes: usize) -> Result<(), StateMismatch> {
        let p = &self.physical;
        let s = &self.stepper;
        let e = &self.events;
        let lengths = [
            ("phi", p.phi.len()),
            ("u0", p.u0_m.len()),
            ("u3d", p.u3d_m.len()),
            ("eps", p.eps.len()),
            ("tau", p.tau_pa.len()),
            ("u3d_prev", s.u3d_prev_m.len()),
            ("melted_in_step", e.melted_in_step.len()),
            ("last_melt", e.last_melt_s.len()),
            ("swept", e.swept.len()),
        ];
        // Empty or one value per node.
        let optional = [
            ("u3d_prev2", s.u3d_prev2_m.len()),
            ("viscous_rate_prev", s.viscous_rate_prev_m_per_s.len()),
        ];
        let wrong = lengths
            .into_iter()
            .find(|&(_, len)| len != nodes)
            .or_else(|| {
                optional
                    .into_iter()
                    .find(|&(_, len)| len != 0 && len != nodes)
            });
        match wrong {
            Some((name, len)) => Err(StateMismatch::Nodes { name, len, nodes }),
            None => Ok(()),
        }
    }
}

/// A saved state that does not fit the simulation it is restored into.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StateMismatch {
    /// A per-node vector of another length than the scene's nodes.
    #[error("checkpoint has {len} values of {name}, the scene {nodes} nodes")]
    Nodes {
        /// The vector's name (`phi`, `u3d_prev`, …).
        name: &'static str,
        /// Its length in the state.
        len: usize,
        /// The scene's nodes.
        nodes: usize,
    },
    /// The noise generators' state belongs to another source.
    #[error(transparent)]
    Noise(#[from] crate::noise::NoiseError),
}
