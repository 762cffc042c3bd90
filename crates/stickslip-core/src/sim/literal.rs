//! The paper's literal step: explicit Euler for φ, u0 reset once per step, one lagged sweep
//! of the elastic coupling, plain sums.

use super::{Contact, NumericalFailure, Simulation};
use crate::config::Substrate;
use crate::landau::{first_order, second_order_rhs};

impl Simulation {
    /// One literal step of `dt_s` (the `Literal` stepper's).
    pub(super) fn step_literal(&mut self, dt_s: f64) -> Result<(), NumericalFailure> {
        let t0 = self.state.physical.drive.t_s;
        let a_coeff = self.config.temperature.a_coeff_pa(t0);
        let params = self.config.lubricant;
        let thr = self.config.melt_threshold;
        for (was_solid, &phi) in self
            .state
            .events
            .melted_in_step
            .iter_mut()
            .zip(&self.state.physical.phi)
        {
            *was_solid = phi >= thr;
        }
        // Eq. 8 keeps φ ≥ 0 exactly; a negative φ is explicit Euler overshooting its
        // stability limit. Caught here, before noise or a floor could hide it; the first such
        // node and its φ before the step are kept for the diagnosis. The film's right-hand
        // side is chosen once per step: the second-order film's as it always was, or the
        // first-order one's (b₃ > 0).
        let overshoot = if params.cubic_pa == 0.0 {
            self.euler_phi(dt_s, |phi, eps| {
                second_order_rhs(phi, eps, a_coeff, &params)
            })
        } else {
            let (b, b3, g) = (params.b_pa(), params.cubic_pa, params.gamma_per_pa_s);
            self.euler_phi(dt_s, |phi, eps| {
                first_order::rhs(phi, params.bernoulli_c_pa(eps, a_coeff), b, b3, g)
            })
        };
        if let Some((node, phi_before)) = overshoot {
            let b = params.b_pa();
            // |∂rhs/∂φ| = γ·|a·ε² + 3b·φ² − 2b₃·φ − A·b/a| at the node's state before the step
            // (which noise may have pushed far from equilibrium).
            let eps = self.state.physical.eps[node];
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
            let noisy = if matches!(self.config.noise, crate::noise::NoiseKind::Gaussian { .. }) {
                " (phi before the step came from the noise kick of the step before; reduce \
                 lubricant.noise.sigma or time.dt)"
            } else {
                ""
            };
            return Err(NumericalFailure {
                t_s: t0 + dt_s,
                step: self.state.counters.step + 1,
                node,
                r_m: self.radii_m[node],
                quantity: "phi",
                value: self.state.physical.phi[node],
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
        self.noise.apply(&mut self.state.physical.phi, dt_s);
        self.first_melt_fraction = 1.0;
        self.recovered_at_s = f64::NEG_INFINITY;
        let dx = self.drive_first_half(dt_s);
        for i in 0..self.state.physical.phi.len() {
            let melted = self.state.physical.phi[i] < thr;
            let newly = melted && self.state.events.melted_in_step[i];
            self.state.events.melted_in_step[i] = newly;
            if newly {
                self.state.events.last_melt_s[i] = t0 + dt_s;
            }
            let u0 = &mut self.state.physical.u0_m[i];
            *u0 = if melted { 0.0 } else { *u0 + dx };
        }
        self.update_strain_and_stress();
        // One lagged sweep: the substrate answers the stress just computed, for the next step.
        match &self.contact {
            Contact::Radial { ops, .. } => {
                if self.config.contact.substrate == Substrate::Elastic {
                    ops.compliance(
                        &self.state.physical.tau_pa,
                        &mut self.scratch_q,
                        &mut self.state.physical.u3d_m,
                    );
                    let inv_g = 1.0 / self.config.contact.g_eff_pa;
                    self.state
                        .physical
                        .u3d_m
                        .iter_mut()
                        .for_each(|u| *u *= inv_g);
                }
            }
            Contact::Homogeneous {
                compliance_m_per_pa,
                ..
            } => {
                self.state.physical.u3d_m[0] = compliance_m_per_pa * self.state.physical.tau_pa[0];
            }
        }
        self.state.physical.force_n = self.force_3d();
        self.drive_second_half(dt_s);
        Ok(())
    }
}

impl Simulation {
    /// φ ← φ + Δt·rhs(φ, ε) at every node (explicit Euler); the first node where φ turned
    /// negative or NaN, with its φ before the step.
    fn euler_phi(&mut self, dt_s: f64, rhs: impl Fn(f64, f64) -> f64) -> Option<(usize, f64)> {
        let mut overshoot: Option<(usize, f64)> = None;
        for (i, (phi, &eps)) in self
            .state
            .physical
            .phi
            .iter_mut()
            .zip(&self.state.physical.eps)
            .enumerate()
        {
            let before = *phi;
            *phi += dt_s * rhs(before, eps);
            if overshoot.is_none() && (phi.is_nan() || *phi < 0.0) {
                overshoot = Some((i, before));
            }
        }
        overshoot
    }
}
