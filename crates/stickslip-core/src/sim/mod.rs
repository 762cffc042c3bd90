//! The time loop: one [`Simulation`] advances film, substrate and stamp by one step at a time.
//!
//! Effects are composed from [`SimConfig`]: what a scene leaves off is not computed at all
//! (no operator for a rigid substrate, no random numbers for floor/off noise, one node for the
//! homogeneous model). Two schemes:
//!
//! **literal** (the paper's): φ by explicit Euler with ε of the previous step; u0 grows by the
//! stamp's advance and is reset to 0 where φ < threshold, once per step; ε = (u0 − u3D_prev)/h0
//! with the substrate displacement of the previous step (one lagged sweep of the coupling);
//! plain sums for Eq. 13–16.
//!
//! **accurate**: per node, the exact Landau step with ε frozen at its mid-step value; u0 reset
//! where the deterministic path crosses the threshold, re-solidifying nodes accumulate u0 only
//! from the located crossing time on; the coupling (I + K)·u3D = K·u0 solved to a tolerance
//! (see [`coupling`]); product integration for Eq. 13–16.
//!
//! The stamp is advanced by the split integrator (the exact flow of the spring with the friction
//! force linearised at the step's start, film update, a half kick with F's departure from that
//! linearisation; see [`drive_step`]), velocity Verlet (half kick with F_n, drift, film update,
//! half kick with F_{n+1}) or RK4 with F frozen over the step; the rigid drive sets X = V0·t.
//!
//! A simulation is three things. The problem (`problem`): the resolved configuration, grid,
//! operators and what follows from them, fixed once built. The state ([`state`]): the
//! physical state apart from what the stepper and the step-size controller remember, the
//! counters and the events. The stepper (`stepper`): one scheme's step, chosen once in
//! [`Simulation::new`], owning its scratch and returning a report of what the step found.
//! A step goes `advance` (any scheme's bookkeeping) → the stepper (`literal`, `accurate`,
//! which uses `drive_step`, `substrate`, `viscous`, `film`, `ramp` and `error_estimate`) →
//! back to `advance`, which checks and observes the result (`watch`); with adaptive steps
//! `adaptive`'s loop drives `advance` over any stepper.

mod accurate;
mod adaptive;
mod advance;
mod books;
mod contact_spring;
pub mod coupling;
mod drive_step;
pub mod energy;
pub mod error_estimate;
pub mod events;
mod film;
mod literal;
mod node_pass;
mod plan;
mod problem;
mod ramp;
mod replay;
pub mod state;
pub mod step_control;
mod stepper;
mod substrate;
mod viscous;
mod watch;

pub use crate::failure::NumericalFailure;
pub use adaptive::LOCAL_ERROR_ORDER;
pub use plan::{PlannedStep, StepKind};
pub use problem::COUPLING_STRAIN_SHARE;
pub use state::{
    ControllerMemory, EventBook, PhysicalState, SimState, StateMismatch, StepCounters,
    StepperMemory,
};
pub use stepper::{StepError, StepReport};

use crate::config::SimConfig;
use crate::drive::DriveState;
use crate::noise::NoiseSource;
use crate::preflight::ContactSpring;
use advance::Engine;
use events::{EventTracker, MeltingEvent};
use problem::{Contact, Problem};
use serde::Serialize;
use stepper::Stepper;

/// Smallest φ the accurate scheme keeps from a positive start: φ² = 1e-300 is still a normal
/// f64, so a molten node stays able to regrow (Eq. 8 never takes φ > 0 to 0 in finite time).
pub const PHI_REPRESENTABLE_MIN: f64 = 1e-150;

/// Floor of the velocity's error scale, ω·(this)·h0·εc with ω = √(K/m) the drive spring's
/// angular frequency. V's scale is its own size, not V0, since a spring-driven stamp creeps at
/// V ≪ V0 before its first slip; but an error δV moves the stamp by at most δV/ω within the
/// spring's period, so this floor is the speed whose error moves it by a tenth of the melting
/// displacement h0·εc (a tenth of what the strain part allows). Relative to |V| alone the
/// stamp's ringing in a stick, whose velocity passes through zero every period, limited the
/// steps around each zero: on the h0 = 1 nm contact (K = 500 N/m, N = 200, uniform grid) the
/// floor 1e-6·V0 took 17 914 evaluations to the first onset, this one 7 393, and over
/// N = 50–300 the onset's error is unchanged on average (docs/model.md, "The velocity's
/// floor").
const V_FLOOR_MELT_FRACTION: f64 = 0.1;
/// Floor of the position's error scale, as a fraction of the film thickness h0.
const X_FLOOR: f64 = 1e-3;

/// Scalar observables at the current time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Observables {
    /// Time, s.
    pub t_s: f64,
    /// Stamp position X, m.
    pub x_m: f64,
    /// Stamp velocity V, m/s.
    pub v_m_per_s: f64,
    /// Friction force from 2π∫τ r dr, N.
    pub f_n: f64,
    /// Friction force from 2∫q dx, N.
    pub f_1d_n: f64,
    /// Area-weighted mean of φ.
    pub phi_mean: f64,
    /// Area-weighted mean of ε.
    pub eps_mean: f64,
    /// Melted area fraction (φ < threshold).
    pub melted_fraction: f64,
}

/// One simulation: its problem, its stepper, its state and the last step's report.
///
/// # Example
/// ```
/// use stickslip_core::sim::Simulation;
///
/// // A configuration comes from a scene (the run library reads and checks it): here the
/// // paper's fig2 at 20 nodes.
/// let fig2 = include_str!("../../../../validation/scenes/fig2.toml");
/// let config = stickslip_run::scene::Scene::from_toml_str(fig2, &["contact.nodes=20"])
///     .unwrap()
///     .config;
/// let mut sim = Simulation::new(config).unwrap();
/// for _ in 0..10 {
///     sim.step(1e-6).unwrap();
/// }
/// assert_eq!(sim.state().counters.step, 10);
/// assert!((sim.time_s() - 1e-5).abs() < 1e-12);
/// ```
pub struct Simulation {
    /// The problem, the scheme's stepper (chosen once from the configuration,
    /// [`stepper_for`]) and the noise: what a step uses besides the state.
    engine: Engine,
    state: SimState,
    /// What the last step found.
    report: StepReport,
    /// Adaptive stepping: the state before the attempted step (allocated once).
    saved: Option<Box<SimState>>,
    /// Adaptive stepping: the last accepted step as a replay takes it again.
    planned: Option<PlannedStep>,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("config", &self.engine.problem.config)
            .field("step", &self.state.counters.step)
            .finish_non_exhaustive()
    }
}

impl Simulation {
    /// Builds operators and the initial state (X = Ẋ = 0, u0 = u3D = 0, φ = √(A/a), or the
    /// first-order film's solid branch φ₊(0)).
    ///
    /// # Errors
    /// The first invalid configuration value.
    pub fn new(config: SimConfig) -> Result<Self, crate::config::ConfigError> {
        let problem = Problem::new(config)?;
        let n = problem.nodes();
        let noise = NoiseSource::new(problem.config.noise, n)
            .map_err(|e| crate::config::ConfigError::new("lubricant.noise", "-", &e.to_string()))?;
        let state = SimState {
            physical: PhysicalState {
                drive: DriveState::at_rest(),
                phi: vec![problem.phi_init; n],
                u0_m: vec![0.0; n],
                u3d_m: vec![0.0; n],
                eps: vec![0.0; n],
                tau_pa: vec![0.0; n],
                force_n: 0.0,
                noise: noise.state(),
            },
            stepper: StepperMemory {
                u3d_prev_m: vec![0.0; n],
                u3d_prev2_m: Vec::new(),
                last_dt_s: 0.0,
                prev_dt_s: 0.0,
                accel_change_prev_m_per_s2: 0.0,
                mean_v_m_per_s: 0.0,
                viscous_v_m_per_s: 0.0,
                viscous_rate_prev_m_per_s: Vec::new(),
            },
            controller: ControllerMemory::default(),
            counters: StepCounters::default(),
            events: EventBook {
                tracker: EventTracker::new(problem.config.events),
                melted_in_step: vec![false; n],
                last_melt_s: vec![-1.0; n],
                swept: vec![false; n],
            },
        };
        let mut sim = Self {
            engine: Engine {
                stepper: stepper_for(&problem),
                problem,
                noise,
            },
            state,
            report: StepReport::default(),
            saved: None,
            planned: None,
        };
        let stored = books::stored(&sim.engine.problem, &sim.state.physical);
        watch::observe_events(
            &sim.engine.problem,
            &mut sim.state,
            &sim.report,
            (energy::EnergyFlows::default(), stored),
        );
        Ok(sim)
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.engine.problem.config
    }

    /// The state (for checkpoints and profiles).
    pub fn state(&self) -> &SimState {
        &self.state
    }

    /// Replaces the state with a checkpointed one of the same configuration.
    ///
    /// # Errors
    /// If a per-node vector's length or the noise state does not fit.
    pub fn restore(&mut self, state: SimState) -> Result<(), StateMismatch> {
        state.check_nodes(self.engine.problem.nodes())?;
        self.engine.noise.restore(&state.physical.noise)?;
        self.state = state;
        Ok(())
    }

    /// Node radii, m.
    pub fn radii_m(&self) -> &[f64] {
        &self.engine.problem.radii_m
    }

    /// Current time, s.
    pub fn time_s(&self) -> f64 {
        self.state.physical.drive.t_s
    }

    /// Melting events so far.
    pub fn events(&self) -> &[MeltingEvent] {
        self.state.events.tracker.events()
    }

    /// Advances by `dt_s` (normally `config.time.dt_s`).
    ///
    /// # Errors
    /// [`NumericalFailure`] when a value turns non-finite or runs away (|τ| beyond
    /// `numerics.runaway_stress_factor`·τmax, or the coupling solve fails).
    pub fn step(&mut self, dt_s: f64) -> Result<(), NumericalFailure> {
        self.planned = None;
        self.report = self.engine.step(&mut self.state, dt_s)?;
        Ok(())
    }

    /// One error-controlled step (scene `time.stepping = "adaptive"`), ending at most at
    /// `t_stop_s`; returns the length of the accepted step, s. See the `adaptive` module for
    /// the loop: attempts within `time.tolerance` are kept, others retaken shorter, and the
    /// step bringing a melting onset ends at the located onset.
    ///
    /// # Errors
    /// [`NumericalFailure`] from a step at `dt_min`.
    ///
    /// # Panics
    /// If the configuration is not adaptive.
    pub fn step_adaptive(&mut self, t_stop_s: f64) -> Result<f64, NumericalFailure> {
        let time = self.engine.problem.config.time;
        let ctl = time.adaptive.expect("step_adaptive needs time.adaptive");
        let (h, report, planned) = adaptive::step(
            &mut self.engine,
            &mut self.state,
            &mut self.saved,
            (ctl, time.dt_s),
            t_stop_s,
        )?;
        self.report = report;
        self.planned = Some(planned);
        Ok(h)
    }

    /// The last step [`Simulation::step_adaptive`] accepted, as [`Simulation::step_planned`]
    /// takes it again (none before the first, and after any other kind of step).
    pub fn last_planned_step(&self) -> Option<PlannedStep> {
        self.planned
    }

    /// Takes a step recorded from an adaptive run ([`Simulation::last_planned_step`]) again,
    /// without error control, ending at most at `t_stop_s`; returns its length, s. A step
    /// that brings a first melting ends at it, as the adaptive step's does (see
    /// the `replay` module): a run of a slightly different scene that replays another's steps follows
    /// the same discrete map, and differences between the two are smooth in the difference
    /// of the scenes.
    ///
    /// # Errors
    /// [`NumericalFailure`] from the step.
    ///
    /// # Panics
    /// If the configuration is not adaptive.
    pub fn step_planned(
        &mut self,
        planned: PlannedStep,
        t_stop_s: f64,
    ) -> Result<f64, NumericalFailure> {
        let ctl = self
            .engine
            .problem
            .config
            .time
            .adaptive
            .expect("step_planned needs time.adaptive");
        let (h, report) = replay::step(
            &mut self.engine,
            &mut self.state,
            &mut self.saved,
            (planned, ctl.dt_min_s),
            t_stop_s,
        )?;
        self.report = report;
        self.planned = None;
        Ok(h)
    }

    /// The last step's estimated local error (accurate scheme; zero for the literal one).
    pub fn last_step_error(&self) -> StepError {
        self.report.error
    }

    /// Contraction factor ρ(K) of the paper's lagged elastic sweep u3D ← K·(u0 − u3D) for
    /// the current φ, with K = (a/(h0·G*))·C·diag(φ²) and C this scheme's compliance.
    ///
    /// The sweep converges only when ρ < 1; the accurate scheme's solve does not need it.
    /// K has non-negative entries, so power iteration from a positive vector converges to ρ
    /// (Perron–Frobenius); 0 for a rigid substrate.
    pub fn lagged_sweep_contraction(&self) -> f64 {
        let phi_sq: Vec<f64> = self.state.physical.phi.iter().map(|p| p * p).collect();
        self.engine.problem.contraction_with(&phi_sq)
    }

    /// The contact as a linear spring at t = 0 (see the `contact_spring` module); none when
    /// the film starts molten or nothing can melt (no melting strain).
    pub fn contact_spring(&self) -> Option<ContactSpring> {
        self.engine.problem.contact_spring()
    }

    /// The contact's spring for the first-onset estimate: [`Simulation::contact_spring`] with
    /// its melting point moved to the quasi-static fold of the radial contact on an elastic
    /// substrate (see the `contact_spring` module).
    pub fn onset_spring(&self) -> Option<ContactSpring> {
        self.engine.problem.onset_spring()
    }

    /// The physics of this configuration before it runs (derived and stability numbers,
    /// estimates, the verdict); computes the lagged-sweep contraction factor from the state now.
    pub fn preflight(&self) -> crate::preflight::Preflight {
        let rho = if self.state.counters.step == 0 {
            self.engine.problem.rho0
        } else {
            self.lagged_sweep_contraction()
        };
        crate::preflight::Preflight::with_contact(
            &self.engine.problem.config,
            rho,
            self.onset_spring(),
        )
    }

    /// Threads the elastic coupling's compliance runs on: 2 once it has taken the helper of
    /// [`crate::mdr::MdrOperators::compliance_threads`], else 1 (the same bits either way).
    pub fn compliance_threads(&self) -> usize {
        match &self.engine.problem.contact {
            Contact::Radial(ops) => ops.compliance_threads(),
            Contact::Homogeneous { .. } => 1,
        }
    }

    /// Scalar observables now (F from 2∫q dx through the forward transform's weights,
    /// [`crate::mdr::MdrOperators::force_1d_from_tau_n`]).
    pub fn observables(&mut self) -> Observables {
        let f_1d_n = match &self.engine.problem.contact {
            Contact::Radial(ops) => ops.force_1d_from_tau_n(&self.state.physical.tau_pa),
            Contact::Homogeneous { area_m2, .. } => area_m2 * self.state.physical.tau_pa[0],
        };
        let w = &self.engine.problem.area_weights[..];
        let n = w.len();
        let thr = self.engine.problem.config.melt_threshold;
        let (phi_mean, (melted, melted_count)) =
            watch::film_means(w, &self.state.physical.phi, thr);
        let eps_mean = crate::sums::dot(w, &self.state.physical.eps);
        let melted = watch::whole_area(melted, melted_count, n);
        Observables {
            t_s: self.state.physical.drive.t_s,
            x_m: self.state.physical.drive.x_m,
            v_m_per_s: self.state.physical.drive.v_m_per_s,
            f_n: self.state.physical.force_n,
            f_1d_n,
            phi_mean,
            eps_mean,
            melted_fraction: melted,
        }
    }
}

/// The stepper of `problem`: the literal scheme, or the accurate scheme with the film's
/// kinetics of the second-order film (b₃ = 0; its step ramp-corrected, or frozen as before)
/// or of the first-order one. A new scheme or film step is one more arm here.
fn stepper_for(problem: &Problem) -> Box<dyn Stepper> {
    use crate::config::{FilmStep, Scheme};
    use film::{FirstOrder, SecondOrder, SecondOrderRamp};
    let params = problem.config.lubricant;
    match problem.config.time.scheme {
        Scheme::Literal => Box::new(literal::Literal::new(problem)),
        Scheme::Accurate if params.cubic_pa == 0.0 => match problem.config.numerics.film_step {
            FilmStep::Ramp => Box::new(accurate::Accurate::new(
                problem,
                SecondOrderRamp(SecondOrder::new(params)),
            )),
            FilmStep::Frozen => {
                Box::new(accurate::Accurate::new(problem, SecondOrder::new(params)))
            }
        },
        Scheme::Accurate => Box::new(accurate::Accurate::new(problem, FirstOrder::new(params))),
    }
}
