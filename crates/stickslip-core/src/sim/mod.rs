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
//! Each scheme is an implementation of the `stepper` module's trait, chosen once in
//! [`Simulation::new`]; the state it advances is [`state`]'s: the physical state apart from
//! what the stepper and the step-size controller remember, the counters and the events.

mod accurate;
mod adaptive;
mod contact_spring;
pub mod coupling;
mod drive_step;
pub mod error_estimate;
pub mod events;
mod film;
mod literal;
mod ramp;
pub mod state;
pub mod step_control;
mod stepper;
mod viscous;

pub use crate::failure::NumericalFailure;
pub use adaptive::StepError;
pub use state::{
    ControllerMemory, EventBook, PhysicalState, SimState, StateMismatch, StepCounters,
    StepperMemory,
};

use crate::config::{ContactModel, Scheme, SimConfig, Substrate};
use crate::drive::{Drive, DriveState, Integrator};
use crate::grid::Grid;
use crate::mdr::{MdrOperators, Quadrature};
use crate::noise::NoiseSource;
use coupling::{CouplingSolver, CouplingTolerance};
use events::{EventTracker, MeltingEvent, StepSample};
use serde::Serialize;
use std::f64::consts::PI;
use std::sync::Arc;
use stepper::Stepper;

/// Smallest φ the accurate scheme keeps from a positive start: φ² = 1e-300 is still a normal
/// f64, so a molten node stays able to regrow (Eq. 8 never takes φ > 0 to 0 in finite time).
pub const PHI_REPRESENTABLE_MIN: f64 = 1e-150;

/// Floor of the velocity's error scale, as a fraction of the drive velocity V0.
const V_FLOOR: f64 = 1e-6;
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

enum Contact {
    Radial {
        ops: Box<MdrOperators>,
        solver: Option<Box<CouplingSolver>>,
    },
    Homogeneous {
        area_m2: f64,
        /// u3D per unit τ, m/Pa (0 for a rigid substrate).
        compliance_m_per_pa: f64,
    },
}

/// One simulation: configuration, operators, stepper, state and scratch.
pub struct Simulation {
    config: SimConfig,
    contact: Contact,
    /// The scheme's step, chosen once from the configuration ([`stepper::for_config`]).
    stepper: Arc<dyn Stepper>,
    noise: NoiseSource,
    state: SimState,
    radii_m: Vec<f64>,
    area_weights: Vec<f64>,
    kappa: f64,
    scratch_q: Vec<f64>,
    phi_sq: Vec<f64>,
    /// Per node, from the φ-step for the error estimate after the coupling solve (see
    /// [`error_estimate`]): the start's defect term h·w0·D(0) (or a melting node's whole
    /// estimate), the end's gain h·w1·(−2γ·a·y1), the effective strain, and 1/(2·max(y1, thr²)).
    est_base: Vec<f64>,
    est_gain: Vec<f64>,
    est_eps_eff: Vec<f64>,
    est_norm: Vec<f64>,
    /// Per node, scratch of the accurate step, which takes the exponentials of all nodes in
    /// vectorised loops ([`crate::vexp::exp_expm1_all`]): their arguments, e^x, e^x − 1, and
    /// the film's φ at the step's end.
    node_arg: Vec<f64>,
    node_exp: Vec<f64>,
    node_expm1: Vec<f64>,
    node_phi1: Vec<f64>,
    /// The accurate step's predicted u3D change per node over the step, m.
    node_du3d: Vec<f64>,
    /// The frozen strain's place θ on the step's strain ramp, per node.
    node_theta: Vec<f64>,
    /// The last step's estimated local error, in units of the error scales.
    last_error: StepError,
    /// Adaptive stepping: the state before the attempted step.
    saved: Option<Box<SimState>>,
    /// Fraction of the last step at which the first node melted (1 = at its end).
    first_melt_fraction: f64,
    /// Latest time within the last step at which a node rose through the recovery level,
    /// located on its exact path (accurate scheme), s; −∞ when none did or not located.
    recovered_at_s: f64,
    /// Contraction factor ρ of the lagged sweep at t = 0 (see
    /// [`Simulation::lagged_sweep_contraction`]): bounds K's spectrum for the coupling solve's
    /// relaxation of accepted guesses.
    rho0: f64,
    /// The film's viscous stress (`lubricant.viscosity` > 0, accurate scheme); `None` for η = 0,
    /// which then costs nothing and changes no bit.
    viscous: Option<viscous::Viscous>,
    /// The contact's linear stiffness k with which the split integrator's exact flow carries
    /// the friction force linearised at each step's start, N/m (see
    /// [`crate::drive::SpringDrive::loaded_flow`]): the contact as a spring at t = 0
    /// ([`Simulation::contact_spring`]); 0 for the other integrators, the rigid drive and the
    /// literal scheme, whose flow is the spring's alone.
    flow_stiffness_n_per_m: f64,
    /// Where the split flow linearised the kick force in the step being taken (with
    /// `flow_stiffness_n_per_m` > 0).
    flow_anchor: crate::drive::FlowAnchor,
    /// [`Simulation::contact_spring`] once computed (the outer `None`: not yet).
    contact_spring_at_start: Option<Option<crate::preflight::ContactSpring>>,
    /// The last coupling solve's residual, root mean square over the nodes, m: its strain
    /// enters the step's error estimate (0 without a solve).
    last_coupling_rms_m: f64,
}

/// The share of the step's strain tolerance a coupling residual may take (see
/// [`Simulation::coupling_abs_rms_m`]).
pub const COUPLING_STRAIN_SHARE: f64 = 0.1;

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("config", &self.config)
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
        config.validate()?;
        let n = config.simulated_nodes();
        let c = config.contact;
        let grading = match c.model {
            ContactModel::Radial => c.grid,
            ContactModel::Homogeneous => crate::grid::Grading::Uniform,
        };
        let grid = Grid::graded(c.radius_m, n, grading).map_err(|e| match e {
            crate::grid::GridError::OutOfRange {
                field,
                value,
                allowed,
            } => crate::config::ConfigError::new(field, value, allowed),
        })?;
        let elastic = c.substrate == Substrate::Elastic;
        let contact = match c.model {
            ContactModel::Radial => {
                let quadrature = match config.time.scheme {
                    Scheme::Literal => Quadrature::Literal,
                    Scheme::Accurate => Quadrature::Product,
                };
                let solver = (elastic && config.time.scheme == Scheme::Accurate)
                    .then(|| Box::new(CouplingSolver::new(n)));
                Contact::Radial {
                    ops: Box::new(MdrOperators::with_form(
                        grid,
                        quadrature,
                        config.operator_form(),
                    )),
                    solver,
                }
            }
            ContactModel::Homogeneous => Contact::Homogeneous {
                area_m2: PI * c.radius_m * c.radius_m,
                compliance_m_per_pa: if elastic {
                    PI * c.radius_m / (2.0 * c.g_eff_pa)
                } else {
                    0.0
                },
            },
        };
        let noise = NoiseSource::new(config.noise, n)
            .map_err(|e| crate::config::ConfigError::new("lubricant.noise", "-", &e.to_string()))?;
        let a0 = config.temperature.a_coeff_pa(0.0);
        // The unstrained solid film: √(A/a), or φ₊(0) of the first-order film (which also
        // starts solid, as a metastable solid, for A ≤ 0 while b₃² ≥ −4b·A·b/a).
        let phi_init = config.lubricant.solid_phi(0.0, a0);
        let (radii_m, area_weights) = match c.model {
            ContactModel::Radial => (grid.radii_m(), grid.area_weights()),
            ContactModel::Homogeneous => (vec![0.0], vec![1.0]),
        };
        let kappa = config.lubricant.a_pa / (c.film_thickness_m * c.g_eff_pa);
        let state = SimState {
            physical: PhysicalState {
                drive: DriveState::at_rest(),
                phi: vec![phi_init; n],
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
                tracker: EventTracker::new(config.events),
                melted_in_step: vec![false; n],
                last_melt_s: vec![-1.0; n],
                swept: vec![false; n],
            },
        };
        let mut sim = Self {
            stepper: stepper::for_config(&config),
            config,
            contact,
            noise,
            state,
            radii_m,
            area_weights,
            kappa,
            scratch_q: vec![0.0; n],
            phi_sq: vec![0.0; n],
            est_base: vec![0.0; n],
            est_gain: vec![0.0; n],
            est_eps_eff: vec![0.0; n],
            est_norm: vec![0.0; n],
            node_arg: vec![0.0; n],
            node_exp: vec![0.0; n],
            node_expm1: vec![0.0; n],
            node_phi1: vec![0.0; n],
            node_du3d: vec![0.0; n],
            node_theta: vec![0.0; n],
            last_error: StepError::default(),
            saved: None,
            first_melt_fraction: 1.0,
            recovered_at_s: f64::NEG_INFINITY,
            rho0: 0.0,
            viscous: None,
            flow_stiffness_n_per_m: 0.0,
            flow_anchor: crate::drive::FlowAnchor::default(),
            contact_spring_at_start: None,
            last_coupling_rms_m: 0.0,
        };
        sim.rho0 = sim.lagged_sweep_contraction();
        if matches!(sim.config.drive, Drive::Spring(_))
            && sim.config.integrator == Integrator::Split
            && sim.config.time.scheme == Scheme::Accurate
            && let Some(k) = sim.contact_spring()
        {
            sim.flow_stiffness_n_per_m = k.stiffness_n_per_m();
        }
        let eta = sim.config.lubricant.viscosity_pa_s;
        if eta > 0.0 {
            // The contact's area as the force quadrature integrates a uniform stress (πa0² up
            // to rounding), and κ·C's spectral radius at unit film stiffness.
            let (area_m2, unit) = match &sim.contact {
                Contact::Radial { ops, solver } => {
                    let area = ops.force_3d_n(&vec![1.0; n]);
                    let unit = if solver.is_some() {
                        sim.contraction_with(&vec![1.0; n])
                    } else {
                        0.0
                    };
                    (area, unit)
                }
                Contact::Homogeneous { area_m2, .. } => (*area_m2, 0.0),
            };
            let drag = eta * area_m2 / c.film_thickness_m;
            let relaxation = if elastic {
                eta * PI * c.radius_m / (2.0 * c.g_eff_pa * c.film_thickness_m)
            } else {
                0.0
            };
            sim.viscous = Some(viscous::Viscous::new(eta, (drag, relaxation), unit, n));
        }
        sim.observe_events();
        Ok(sim)
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.config
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
        state.check_nodes(self.radii_m.len())?;
        self.noise.restore(&state.physical.noise)?;
        self.state = state;
        Ok(())
    }

    /// Node radii, m.
    pub fn radii_m(&self) -> &[f64] {
        &self.radii_m
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
        let stepper = Arc::clone(&self.stepper);
        stepper.step(self, dt_s)?;
        self.state.counters.step += 1;
        // The state carries the generators' positions so that a checkpoint resumes the same
        // random numbers (gaussian noise only; the other kinds draw nothing).
        if !self.state.physical.noise.word_pos.is_empty() {
            self.noise.write_state(&mut self.state.physical.noise);
        }
        self.check_state()?;
        self.observe_events();
        Ok(())
    }

    /// ε = (u0 − u3D)/h0 (Eq. 11) and τ = aφ²ε (Eq. 12) from the current φ, u0 and u3D.
    fn update_strain_and_stress(&mut self) {
        let h0 = self.config.contact.film_thickness_m;
        let a = self.config.lubricant.a_pa;
        let s = &mut self.state.physical;
        for i in 0..s.phi.len() {
            let eps = (s.u0_m[i] - s.u3d_m[i]) / h0;
            s.eps[i] = eps;
            s.tau_pa[i] = a * s.phi[i] * s.phi[i] * eps;
        }
    }

    /// First guess of u3D at the end of a step of `dt_s`, written into `u3d_m` while the
    /// history shifts (u3d_prev2 ← u3d_prev ← u3d): the quadratic through the last three
    /// values when there are three (an error of O(Δt³), which in the stick phase already meets
    /// the coupling tolerance, so the solve only checks it), else the linear one.
    /// The coupling solve's absolute floor at `t_s` with adaptive steps: a residual of RMS
    /// [`COUPLING_STRAIN_SHARE`]·`time.tolerance`·εc(t)·h0 over the nodes, m (εc: the melting
    /// strain, as in the error estimate's strain scale; εmax when nothing melts). Its
    /// displacement shifts the strain by that share of what the step's error estimate accepts
    /// (the stamp's position error is measured against the same h0·εc), so solving further is
    /// work the step cannot use; `numerics.coupling_tol`'s relative bound still applies where it
    /// is looser. 0 with fixed steps, which keep `numerics.coupling_tol` alone.
    fn coupling_abs_rms_m(&self, t_s: f64) -> f64 {
        let Some(adaptive) = self.config.time.adaptive else {
            return 0.0;
        };
        let a = self.config.temperature.a_coeff_pa(t_s);
        let eps_c = self.config.lubricant.melting_strain(a);
        let scale = if eps_c > 0.0 {
            eps_c
        } else {
            self.config.lubricant.eps_max
        };
        COUPLING_STRAIN_SHARE * adaptive.tolerance * scale * self.config.contact.film_thickness_m
    }

    fn extrapolate_u3d(&mut self, dt_s: f64) {
        let (p, s) = (&mut self.state.physical, &mut self.state.stepper);
        let n = p.u3d_m.len();
        let (h_last, h_prev) = (s.last_dt_s, s.prev_dt_s);
        if s.u3d_prev2_m.len() != n {
            s.u3d_prev2_m = s.u3d_prev_m.clone();
        }
        let quadratic = h_last > 0.0 && h_prev > 0.0;
        // Lagrange weights at t_n + x from t_n, t_n − a, t_n − b.
        let (x, a, b) = (dt_s, h_last, h_last + h_prev);
        let (w0, w1, w2) = if quadratic {
            (
                (x + a) * (x + b) / (a * b),
                -x * (x + b) / (a * (b - a)),
                x * (x + a) / (b * (b - a)),
            )
        } else if h_last > 0.0 {
            (1.0 + x / a, -x / a, 0.0)
        } else {
            (1.0, 0.0, 0.0)
        };
        for i in 0..n {
            let (u, prev, prev2) = (p.u3d_m[i], s.u3d_prev_m[i], s.u3d_prev2_m[i]);
            p.u3d_m[i] = w0 * u + w1 * prev + w2 * prev2;
            s.u3d_prev2_m[i] = prev;
            s.u3d_prev_m[i] = u;
        }
    }

    /// The coupling solve at the end of a step of `dt_s` in which the stamp advanced `dx_m`
    /// (which only the viscous stress uses).
    fn solve_coupling(
        &mut self,
        step: u64,
        t_s: f64,
        dt_s: f64,
        dx_m: f64,
    ) -> Result<(), NumericalFailure> {
        let coupling_abs_rms_m = self.coupling_abs_rms_m(t_s);
        self.last_coupling_rms_m = 0.0;
        if matches!(
            self.contact,
            Contact::Radial {
                solver: Some(_),
                ..
            }
        ) {
            self.extrapolate_u3d(dt_s);
        }
        if self.viscous.is_some() {
            return self.solve_viscous_coupling(step, t_s, dt_s, dx_m);
        }
        match &mut self.contact {
            Contact::Radial {
                ops,
                solver: Some(solver),
            } => {
                for (p2, &p) in self.phi_sq.iter_mut().zip(&self.state.physical.phi) {
                    *p2 = p * p;
                }
                let report = solver.solve(
                    ops,
                    &self.phi_sq,
                    self.kappa,
                    &self.state.physical.u0_m,
                    &mut self.state.physical.u3d_m,
                    CouplingTolerance {
                        rel_tol: self.config.numerics.coupling_tol,
                        abs_rms_m: coupling_abs_rms_m,
                        spectral_bound: self.rho0,
                    },
                );
                self.state.counters.coupling_iterations += report.iterations as u64;
                self.last_coupling_rms_m = report.rms_residual_m;
                if !report.converged {
                    return Err(NumericalFailure {
                        t_s,
                        step,
                        node: 0,
                        r_m: 0.0,
                        quantity: "coupling residual",
                        value: report.rel_residual,
                        diagnosis: format!(
                            "the elastic coupling solve did not reach numerics.coupling_tol = {:e} \
                             in {} iterations{}",
                            self.config.numerics.coupling_tol,
                            report.iterations,
                            non_finite_inputs(&self.config, report.rel_residual)
                        ),
                    });
                }
            }
            Contact::Radial { solver: None, .. } => {}
            Contact::Homogeneous {
                compliance_m_per_pa,
                ..
            } => {
                let phi = self.state.physical.phi[0];
                let k = *compliance_m_per_pa * self.config.lubricant.a_pa * phi * phi
                    / self.config.contact.film_thickness_m;
                // Kept for the next step's strain prediction, as in the radial solve.
                self.state.stepper.u3d_prev_m[0] = self.state.physical.u3d_m[0];
                self.state.physical.u3d_m[0] = k * self.state.physical.u0_m[0] / (1.0 + k);
            }
        }
        Ok(())
    }

    /// [`solve_coupling`](Self::solve_coupling) with the viscous stress (after the guess is in
    /// place): (I + κ·C·diag(w))·u3D = κ·C·diag(w)·s (see [`viscous`]), the same solve and
    /// the same one-node formula with φ² → w and u0 → s.
    fn solve_viscous_coupling(
        &mut self,
        step: u64,
        t_s: f64,
        dt_s: f64,
        dx_m: f64,
    ) -> Result<(), NumericalFailure> {
        let coupling_abs_rms_m = self.coupling_abs_rms_m(t_s);
        let memory = &mut self.state.stepper;
        if matches!(self.contact, Contact::Homogeneous { .. }) {
            // Kept for the next step's strain prediction and the viscous rates' history, as in
            // the radial solve (whose guess has already shifted u3D's history).
            memory.u3d_prev2_m.clone_from(&memory.u3d_prev_m);
            memory.u3d_prev_m[0] = self.state.physical.u3d_m[0];
        }
        let Some(v) = self.viscous.as_mut() else {
            return Ok(());
        };
        let p = &mut self.state.physical;
        let n = p.phi.len();
        // u3D one step before this one's start (zeros on a rigid substrate, as u3D itself).
        let before = if memory.u3d_prev2_m.len() == n {
            &memory.u3d_prev2_m
        } else {
            &memory.u3d_prev_m
        };
        let history = (memory.last_dt_s > 0.0).then_some((
            memory.last_dt_s,
            memory.mean_v_m_per_s * memory.last_dt_s,
            before.as_slice(),
        ));
        let bound = v.prepare(
            self.config.lubricant.a_pa,
            dt_s,
            dx_m,
            (&p.phi, &p.u0_m, &memory.u3d_prev_m),
            history,
        );
        match &mut self.contact {
            Contact::Radial {
                ops,
                solver: Some(solver),
            } => {
                let report = solver.solve(
                    ops,
                    v.w(),
                    self.kappa,
                    v.s(),
                    &mut p.u3d_m,
                    CouplingTolerance {
                        rel_tol: self.config.numerics.coupling_tol,
                        abs_rms_m: coupling_abs_rms_m,
                        spectral_bound: bound,
                    },
                );
                self.state.counters.coupling_iterations += report.iterations as u64;
                self.last_coupling_rms_m = report.rms_residual_m;
                if !report.converged {
                    return Err(NumericalFailure {
                        t_s,
                        step,
                        node: 0,
                        r_m: 0.0,
                        quantity: "coupling residual",
                        value: report.rel_residual,
                        diagnosis: format!(
                            "the elastic coupling solve with the viscous stress did not reach \
                             numerics.coupling_tol = {:e} in {} iterations{}",
                            self.config.numerics.coupling_tol,
                            report.iterations,
                            non_finite_inputs(&self.config, report.rel_residual)
                        ),
                    });
                }
            }
            Contact::Radial { solver: None, .. } => {}
            Contact::Homogeneous {
                compliance_m_per_pa,
                ..
            } => {
                let k = *compliance_m_per_pa * self.config.lubricant.a_pa * v.w()[0]
                    / self.config.contact.film_thickness_m;
                p.u3d_m[0] = k * v.s()[0] / (1.0 + k);
            }
        }
        Ok(())
    }

    fn force_3d(&self) -> f64 {
        match &self.contact {
            Contact::Radial { ops, .. } => ops.force_3d_n(&self.state.physical.tau_pa),
            Contact::Homogeneous { area_m2, .. } => area_m2 * self.state.physical.tau_pa[0],
        }
    }

    /// Contraction factor ρ(K) of the paper's lagged elastic sweep u3D ← K·(u0 − u3D) for
    /// the current φ, with K = (a/(h0·G*))·C·diag(φ²) and C this scheme's compliance.
    ///
    /// The sweep converges only when ρ < 1; the accurate scheme's solve does not need it.
    /// K has non-negative entries, so power iteration from a positive vector converges to ρ
    /// (Perron–Frobenius); 0 for a rigid substrate.
    pub fn lagged_sweep_contraction(&mut self) -> f64 {
        let phi_sq: Vec<f64> = self.state.physical.phi.iter().map(|p| p * p).collect();
        self.contraction_with(&phi_sq)
    }

    /// ρ(κ·C·diag(`phi_sq`)) by power iteration (see
    /// [`lagged_sweep_contraction`](Self::lagged_sweep_contraction)); 0 for a rigid substrate.
    fn contraction_with(&mut self, phi_sq: &[f64]) -> f64 {
        let n = phi_sq.len();
        match &self.contact {
            _ if self.config.contact.substrate == Substrate::Rigid => 0.0,
            Contact::Homogeneous {
                compliance_m_per_pa,
                ..
            } => {
                compliance_m_per_pa * self.config.lubricant.a_pa * phi_sq[0]
                    / self.config.contact.film_thickness_m
            }
            Contact::Radial { ops, .. } => {
                let mut x = vec![1.0 / (n as f64).sqrt(); n];
                let mut dx = vec![0.0; n];
                let mut y = vec![0.0; n];
                let mut rho = 0.0;
                for _ in 0..500 {
                    for i in 0..n {
                        dx[i] = self.kappa * phi_sq[i] * x[i];
                    }
                    ops.compliance(&dx, &mut self.scratch_q, &mut y);
                    let norm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
                    if norm == 0.0 {
                        return 0.0;
                    }
                    let converged = (norm - rho).abs() <= 1e-10 * norm;
                    rho = norm;
                    for i in 0..n {
                        x[i] = y[i] / norm;
                    }
                    if converged {
                        break;
                    }
                }
                rho
            }
        }
    }

    /// The physics of this configuration before it runs (derived and stability numbers,
    /// estimates, the verdict); computes the lagged-sweep contraction factor from the state now.
    pub fn preflight(&mut self) -> crate::preflight::Preflight {
        let rho = if self.state.counters.step == 0 {
            self.rho0
        } else {
            self.lagged_sweep_contraction()
        };
        let contact = self.onset_spring();
        crate::preflight::Preflight::with_contact(&self.config, rho, contact)
    }

    /// Scalar observables now (computes F from 2∫q dx with one forward transform).
    pub fn observables(&mut self) -> Observables {
        let f_1d_n = match &self.contact {
            Contact::Radial { ops, .. } => {
                ops.forward(&self.state.physical.tau_pa, &mut self.scratch_q);
                ops.force_1d_n(&self.scratch_q)
            }
            Contact::Homogeneous { area_m2, .. } => area_m2 * self.state.physical.tau_pa[0],
        };
        let mut phi_mean = 0.0;
        let mut eps_mean = 0.0;
        let mut melted = 0.0;
        let mut melted_count = 0;
        for i in 0..self.state.physical.phi.len() {
            let w = self.area_weights[i];
            phi_mean += w * self.state.physical.phi[i];
            eps_mean += w * self.state.physical.eps[i];
            if self.state.physical.phi[i] < self.config.melt_threshold {
                melted += w;
                melted_count += 1;
            }
        }
        let melted = whole_area(melted, melted_count, self.area_weights.len());
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

    /// Node `i` is below the threshold now or melted during the last step.
    fn is_melted(&self, i: usize) -> bool {
        self.state.physical.phi[i] < self.config.melt_threshold
            || self
                .state
                .events
                .melted_in_step
                .get(i)
                .copied()
                .unwrap_or(false)
    }

    fn observe_events(&mut self) {
        let thr = self.config.melt_threshold;
        let a_coeff = self
            .config
            .temperature
            .a_coeff_pa(self.state.physical.drive.t_s);
        let phi_eq = self.config.lubricant.solid_phi(0.0, a_coeff);
        let recovery_phi = self.config.events.recovery_phi(thr, phi_eq);
        let mut melted_nodes = 0;
        let mut unrecovered_nodes = 0;
        let mut solid_nodes = 0;
        let mut outer = 0.0_f64;
        let mut inner = f64::INFINITY;
        let mut fraction = 0.0;
        let mut fraction_count = 0;
        let mut swept = 0.0;
        let mut swept_count = 0;
        let mut phi_mean = 0.0;
        let open = self.state.events.tracker.is_open();
        for i in 0..self.state.physical.phi.len() {
            let phi = self.state.physical.phi[i];
            phi_mean += self.area_weights[i] * phi;
            if phi < thr {
                fraction += self.area_weights[i];
                fraction_count += 1;
            }
            if !open {
                self.state.events.swept[i] = false;
            }
            if self.is_melted(i) {
                melted_nodes += 1;
                // A node that melted inside the step and regrew past φ_rec before its end has
                // recovered by the rule (its crossing is located in `recovered_at_s`); counting
                // it unrecovered would hold the event open to the next step's end.
                if phi < recovery_phi {
                    unrecovered_nodes += 1;
                }
                outer = outer.max(self.radii_m[i]);
                inner = inner.min(self.radii_m[i]);
                self.state.events.swept[i] = true;
            } else {
                solid_nodes += 1;
                if phi < recovery_phi {
                    unrecovered_nodes += 1;
                }
            }
            if self.state.events.swept[i] {
                swept += self.area_weights[i];
                swept_count += 1;
            }
        }
        let n = self.area_weights.len();
        let fraction = whole_area(fraction, fraction_count, n);
        let swept = whole_area(swept, swept_count, n);
        let t_s = self.state.physical.drive.t_s;
        // Located times where the scheme knows them (the accurate scheme's melting of the
        // axis node and recovery crossings), else the step's end.
        let center_melt_s = if self
            .state
            .events
            .melted_in_step
            .first()
            .copied()
            .unwrap_or(false)
            && self.state.events.last_melt_s[0] >= 0.0
        {
            self.state.events.last_melt_s[0].min(t_s)
        } else {
            t_s
        };
        let recovered_s = if self.recovered_at_s.is_finite() {
            self.recovered_at_s.min(t_s)
        } else {
            t_s
        };
        let sample = StepSample {
            t_s: self.state.physical.drive.t_s,
            first_melt_s: self.state.physical.drive.t_s
                - (1.0 - self.first_melt_fraction) * self.state.stepper.last_dt_s,
            v_m_per_s: self.state.physical.drive.v_m_per_s,
            x_m: self.state.physical.drive.x_m,
            f_n: self.state.physical.force_n,
            melted_nodes,
            unrecovered_nodes,
            solid_nodes,
            outermost_melted_m: outer,
            innermost_melted_m: inner,
            center_melted: self.is_melted(0),
            center_melt_s,
            recovered_s,
            melted_fraction: fraction,
            swept_fraction: swept,
            phi_mean,
            phi_eq,
        };
        self.state.events.tracker.observe(&sample);
    }

    fn check_state(&self) -> Result<(), NumericalFailure> {
        let s = &self.state.physical;
        let fail = |node: usize, quantity: &'static str, value: f64, diagnosis: String| {
            Err(NumericalFailure {
                t_s: s.drive.t_s,
                step: self.state.counters.step,
                node,
                r_m: self.radii_m.get(node).copied().unwrap_or(0.0),
                quantity,
                value,
                diagnosis,
            })
        };
        let d = &s.drive;
        if !(d.x_m.is_finite() && d.v_m_per_s.is_finite() && s.force_n.is_finite()) {
            return fail(
                0,
                "X, V or F",
                d.x_m + d.v_m_per_s + s.force_n,
                non_finite_advice(&self.config),
            );
        }
        let l = &self.config.lubricant;
        // τmax; the first-order film's stationary curve peaks higher (at A(0), its largest).
        let scale = if l.cubic_pa == 0.0 {
            l.tau_max_pa
        } else {
            l.tau_max_pa
                .max(l.peak_stress_pa(self.config.temperature.a_coeff_pa(0.0)))
        };
        let limit = self.config.numerics.runaway_stress_factor * scale;
        // A node whose order a noise kick raised above the solid's φ0 carries proportionally
        // more: a·φ²·ε at the same strain. Its limit grows with (φ/φ0)², so that only a stress
        // beyond what its own order can hold counts as running away (hard case 7: σ = 1e6
        // kicks φ to ~300, and the graded grid's edge node then holds 15·τmax legitimately).
        let phi0 = l.solid_phi(0.0, self.config.temperature.a_coeff_pa(0.0));
        let order_factor = |phi: f64| {
            if phi0 > 0.0 {
                (phi * phi / (phi0 * phi0)).max(1.0)
            } else {
                1.0
            }
        };
        let mut worst = (0usize, 0.0_f64);
        let mut sum = 0.0;
        for (i, (&tau, &phi)) in s.tau_pa.iter().zip(&s.phi).enumerate() {
            sum += tau + phi + s.u3d_m[i];
            // The film's elastic stress runs away, not the viscous one, which is the drive's
            // rate: with viscosity the limit applies to a·φ²·ε alone.
            let tau_film = if self.viscous.is_some() {
                l.a_pa * phi * phi * s.eps[i]
            } else {
                tau
            };
            // Measured in units of the node's own limit.
            let excess = tau_film.abs() / order_factor(phi);
            if excess > worst.1 {
                worst = (i, excess);
            }
        }
        if !sum.is_finite() {
            for (i, ((&tau, &phi), &u)) in s.tau_pa.iter().zip(&s.phi).zip(&s.u3d_m).enumerate() {
                for (q, v) in [("phi", phi), ("tau", tau), ("u3d", u)] {
                    if !v.is_finite() {
                        return fail(i, q, v, non_finite_advice(&self.config));
                    }
                }
            }
        }
        if worst.1 > limit {
            return fail(
                worst.0,
                "tau",
                s.tau_pa[worst.0],
                format!(
                    "|tau| exceeds numerics.runaway_stress_factor x {} = {limit:e} Pa{}: the \
                     solution is running away. {}",
                    if l.cubic_pa == 0.0 {
                        "tau_max"
                    } else {
                        "the stationary curve's peak"
                    },
                    if order_factor(s.phi[worst.0]) > 1.0 {
                        format!(" x (phi/phi0)^2 = {:e}", order_factor(s.phi[worst.0]))
                    } else {
                        String::new()
                    },
                    runaway_advice(&self.config)
                ),
            );
        }
        Ok(())
    }
}

/// Advice on a stress beyond the runaway limit: with error-controlled steps a smaller step
/// changes nothing; the overshoot is the film lagging behind its equilibrium when sheared
/// faster than it relaxes, which the drive's strain rate against the film's rate says.
fn runaway_advice(config: &SimConfig) -> String {
    if config.time.scheme == Scheme::Literal || config.time.adaptive.is_none() {
        return non_finite_advice(config);
    }
    let l = &config.lubricant;
    let v0 = match config.drive {
        crate::drive::Drive::Spring(s) => s.velocity_m_per_s,
        crate::drive::Drive::Rigid(r) => r.velocity_m_per_s,
    };
    let strain_rate = v0.abs() / config.contact.film_thickness_m;
    let a = config.temperature.a_coeff_pa(0.0).abs();
    let relaxation = l.gamma_per_pa_s * a * crate::config::Derived::of(config).b_pa / l.a_pa;
    format!(
        "The steps are error-controlled, so a smaller time.dt changes nothing. A stress above \
         tau_max is the film lagging behind its equilibrium when it is sheared faster than it \
         relaxes: here the drive's strain rate |V0|/h0 = {strain_rate:.3e} 1/s against the \
         film's relaxation rate gamma*|A|*b/a = {relaxation:.3e} 1/s. If that overshoot is the \
         physics you want, raise numerics.runaway_stress_factor (now {}); otherwise check the \
         scene's parameters.",
        config.numerics.runaway_stress_factor
    )
}

/// For a coupling residual that is not a number: the state entering the solve had already
/// overflowed, and the inputs that can do that are named with their values (empty for a
/// finite residual, which is a slow solve, not an overflow).
fn non_finite_inputs(config: &SimConfig, residual: f64) -> String {
    if residual.is_finite() {
        return String::new();
    }
    let damping = match &config.drive {
        crate::drive::Drive::Spring(s) => s.damping_n_s_per_m,
        crate::drive::Drive::Rigid(_) => 0.0,
    };
    format!(
        ": the residual is {} because the state entering the solve had overflowed; the inputs \
         that can do that: drive.damping = {} N·s/m, lubricant.viscosity = {} Pa·s, \
         drive.velocity = {} m/s (check their units)",
        crate::config::bounds::human(residual),
        crate::config::bounds::human(damping),
        crate::config::bounds::human(config.lubricant.viscosity_pa_s),
        crate::config::bounds::human(config.drive.velocity_m_per_s())
    )
}

fn non_finite_advice(config: &SimConfig) -> String {
    match config.time.scheme {
        Scheme::Literal => "The literal scheme is unstable here (explicit Euler beyond its \
                            stability limit, or a lagged elastic sweep with contraction factor \
                            >= 1): reduce time.dt or use time.scheme = \"accurate\"."
            .to_string(),
        Scheme::Accurate => "Reduce time.dt or check the scene's parameters.".to_string(),
    }
}

/// An area fraction summed from `count` of the `n` nodes' weights: exactly 1 when every node
/// counts (the midpoint weights sum to 1 only to rounding on the graded grid, and "the whole
/// contact melted" must read as 1).
fn whole_area(sum: f64, count: usize, n: usize) -> f64 {
    if count == n { 1.0 } else { sum }
}
