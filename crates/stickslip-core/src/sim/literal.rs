//! The paper's literal step: explicit Euler for φ, u0 reset once per step, one lagged sweep
//! of the elastic coupling, plain sums.

use super::drive_step;
use super::energy::StepSinks;
use super::problem::{Contact, Problem};
use super::stepper::{StepReport, Stepper};
use super::{NumericalFailure, SimState};
use crate::config::Substrate;
use crate::landau::{first_order, second_order_rhs};
use crate::noise::NoiseSource;

/// The paper's literal scheme, with its scratch: the stresses' transform for the lagged sweep,
/// and φ at the step's start for the energy books.
pub(super) struct Literal {
    q: Vec<f64>,
    phi0: Vec<f64>,
}

impl Literal {
    pub fn new(problem: &Problem) -> Self {
        Self {
            q: vec![0.0; problem.nodes()],
            phi0: vec![0.0; problem.nodes()],
        }
    }
}

impl Stepper for Literal {
    fn step(
        &mut self,
        problem: &Problem,
        state: &mut SimState,
        noise: &mut NoiseSource,
        dt_s: f64,
    ) -> Result<StepReport, NumericalFailure> {
        let t0 = state.physical.drive.t_s;
        let a_coeff = problem.config.temperature.a_coeff_pa(t0);
        let params = problem.config.lubricant;
        let thr = problem.config.melt_threshold;
        self.phi0.clone_from(&state.physical.phi);
        for (was_solid, &phi) in state
            .events
            .melted_in_step
            .iter_mut()
            .zip(&state.physical.phi)
        {
            *was_solid = phi >= thr;
        }
        // Eq. 8 keeps φ ≥ 0 exactly; a negative φ is explicit Euler overshooting its
        // stability limit. Caught here, before noise or a floor could hide it; the first such
        // node and its φ before the step are kept for the diagnosis. The film's right-hand
        // side is chosen once per step: the second-order film's as it always was, or the
        // first-order one's (b₃ > 0).
        let overshoot = if params.cubic_pa == 0.0 {
            euler_phi(state, dt_s, |phi, eps| {
                second_order_rhs(phi, eps, a_coeff, &params)
            })
        } else {
            let (b, b3, g) = (params.b_pa(), params.cubic_pa, params.gamma_per_pa_s);
            euler_phi(state, dt_s, |phi, eps| {
                first_order::rhs(phi, params.bernoulli_c_pa(eps, a_coeff), b, b3, g)
            })
        };
        if let Some((node, phi_before)) = overshoot {
            let b = params.b_pa();
            // |∂rhs/∂φ| = γ·|a·ε² + 3b·φ² − 2b₃·φ − A·b/a| at the node's state before the step
            // (which noise may have pushed far from equilibrium).
            let eps = state.physical.eps[node];
            let stiffness = params.gamma_per_pa_s
                * (params.a_pa * eps * eps + 3.0 * b * phi_before * phi_before
                    - 2.0 * params.cubic_pa * phi_before
                    - a_coeff * b / params.a_pa)
                    .abs();
            let formula = if params.cubic_pa == 0.0 {
                "gamma*|a*eps^2 + 3*b*phi^2 - A*b/a|"
            } else {
                "gamma*|a*eps^2 + 3*b*phi^2 - 2*b3*phi - A*b/a|"
            };
            let noisy = if matches!(
                problem.config.noise,
                crate::noise::NoiseKind::Gaussian { .. }
            ) {
                " (phi before the step came from the noise kick of the step before; reduce \
                 lubricant.noise.sigma or time.dt)"
            } else {
                ""
            };
            return Err(NumericalFailure {
                t_s: t0 + dt_s,
                step: state.counters.step + 1,
                node,
                r_m: problem.radii_m[node],
                quantity: "phi",
                value: state.physical.phi[node],
                diagnosis: format!(
                    "explicit Euler overshot below 0 (Eq. 8 keeps phi >= 0): phi before the \
                     step = {phi_before:e}{noisy}; dt x stiffness = {:.3} with stiffness \
                     {formula} = {stiffness:e} 1/s there; explicit \
                     Euler needs it well below 1 (oscillates above 1, unstable above 2). \
                     Reduce time.dt or use time.scheme = \"accurate\".",
                    dt_s * stiffness
                ),
            });
        }
        noise.apply(&mut state.physical.phi, dt_s);
        let landau_j = self.landau_j(problem, state, a_coeff);
        let (dx, anchor) = drive_step::open(
            problem,
            &mut state.physical.drive,
            state.physical.force_n,
            None,
            dt_s,
        );
        let reset_j = reset_u0(problem, state, dx, t0 + dt_s);
        let sinks = StepSinks {
            landau_j,
            reset_j,
            ..StepSinks::default()
        };
        problem.update_strain_and_stress(&mut state.physical);
        // One lagged sweep: the substrate answers the stress just computed, for the next step.
        let p = &mut state.physical;
        match &problem.contact {
            Contact::Radial(ops) => {
                if problem.config.contact.substrate == Substrate::Elastic {
                    ops.compliance(&p.tau_pa, &mut self.q, &mut p.u3d_m);
                    let inv_g = 1.0 / problem.config.contact.g_eff_pa;
                    p.u3d_m.iter_mut().for_each(|u| *u *= inv_g);
                }
            }
            Contact::Homogeneous {
                compliance_m_per_pa,
                ..
            } => {
                p.u3d_m[0] = compliance_m_per_pa * p.tau_pa[0];
            }
        }
        p.force_n = problem.force_3d_n(&p.tau_pa);
        drive_step::close(problem, &mut p.drive, p.force_n, None, (dt_s, &anchor));
        Ok(StepReport {
            sinks,
            ..StepReport::default()
        })
    }
}

impl Literal {
    /// The books' Landau sink, J: f's drop over the step at the step's strain (the Euler
    /// step's own form; the noise and the floor, applied before, at the same strain).
    fn landau_j(&self, problem: &Problem, state: &SimState, a_coeff: f64) -> f64 {
        let params = problem.config.lubricant;
        let h0 = problem.config.contact.film_thickness_m;
        let p = &state.physical;
        let f = |phi: f64, eps: f64| params.free_energy_pa(phi, eps, a_coeff);
        let mut sum = 0.0;
        for (i, &w) in problem.energy_weights_m2.iter().enumerate() {
            sum += w * (f(self.phi0[i], p.eps[i]) - f(p.phi[i], p.eps[i]));
        }
        h0 * sum
    }
}

/// u0 after the stamp's advance `dx_m`: grown where the film is solid, reset to 0 where it has
/// melted (once per step), with the melting recorded at `t_end_s`; the energy the resets
/// removed, J: the elastic energy u0 + ΔX would have carried less that at u0 = 0 (the held
/// advance is in it).
fn reset_u0(problem: &Problem, state: &mut SimState, dx_m: f64, t_end_s: f64) -> f64 {
    let thr = problem.config.melt_threshold;
    let h0 = problem.config.contact.film_thickness_m;
    let a = problem.config.lubricant.a_pa;
    let mut reset_j = 0.0;
    for i in 0..state.physical.phi.len() {
        let melted = state.physical.phi[i] < thr;
        let newly = melted && state.events.melted_in_step[i];
        state.events.melted_in_step[i] = newly;
        if newly {
            state.events.last_melt_s[i] = t_end_s;
        }
        let p = &mut state.physical;
        if melted {
            let (u3d, y) = (p.u3d_m[i], p.phi[i] * p.phi[i]);
            let (kept, reset) = ((p.u0_m[i] + dx_m - u3d) / h0, -u3d / h0);
            reset_j +=
                problem.energy_weights_m2[i] * h0 * 0.5 * a * y * (kept * kept - reset * reset);
        }
        p.u0_m[i] = if melted { 0.0 } else { p.u0_m[i] + dx_m };
    }
    reset_j
}

/// φ ← φ + Δt·rhs(φ, ε) at every node (explicit Euler); the first node where φ turned
/// negative or NaN, with its φ before the step.
fn euler_phi(
    state: &mut SimState,
    dt_s: f64,
    rhs: impl Fn(f64, f64) -> f64,
) -> Option<(usize, f64)> {
    let mut overshoot: Option<(usize, f64)> = None;
    let p = &mut state.physical;
    for (i, (phi, &eps)) in p.phi.iter_mut().zip(&p.eps).enumerate() {
        let before = *phi;
        *phi += dt_s * rhs(before, eps);
        if overshoot.is_none() && (phi.is_nan() || *phi < 0.0) {
            overshoot = Some((i, before));
        }
    }
    overshoot
}
