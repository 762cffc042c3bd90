//! The contact as a linear spring, for `check`'s first-onset estimate: the film linearised at
//! its secant stiffness at melting (τ = a·φs²·ε with a·φs²·ε_m = the peak stress, so a node at
//! the melting strain ε_m carries exactly the peak stress), in series with the substrate's
//! static response. A unit stamp displacement X = 1 gives, from (I + K)·u3D = K·1 with
//! K = κ·C·diag(φs²) (the coupling the accurate scheme solves each step), the strain at every
//! node, (1 − u3D)/h0, and the force. The first node reaches ε_m at X_m = ε_m / max strain;
//! the force then is F_m = X_m · (force per unit X); the contact's stiffness is F_m / X_m.
//!
//! On a stiff film over a soft substrate (an h0 = 1 nm film under a 20 µm stamp) the edge
//! carries the load, and F_m is well below the peak stress times the area: the film melts at
//! the edge first. On a compliant film (fig2's 100 nm) the strain is nearly uniform and F_m
//! is close to the peak stress times the area.

use super::coupling::{CouplingSolver, CouplingTolerance};
use super::{Contact, Simulation};
use crate::config::Substrate;
use crate::preflight::ContactSpring;

impl Simulation {
    /// The contact as a linear spring at t = 0 (see the module docs); none when the film
    /// starts molten or nothing can melt (no melting strain).
    pub fn contact_spring(&mut self) -> Option<ContactSpring> {
        let c = &self.config;
        let l = &c.lubricant;
        let a_coeff = c.temperature.a_coeff_pa(0.0);
        if !l.starts_solid(a_coeff) {
            return None;
        }
        let eps_m = l.melting_strain(a_coeff);
        let peak = l.peak_stress_pa(a_coeff);
        if !(eps_m > 0.0 && peak > 0.0 && eps_m.is_finite()) {
            return None;
        }
        let h0 = c.contact.film_thickness_m;
        // a·φs²: the secant stiffness of the film's stress-strain curve at melting.
        let secant_pa = peak / eps_m;
        let phi_sq = secant_pa / l.a_pa;
        let rigid = c.contact.substrate == Substrate::Rigid;
        let n = self.state.physical.phi.len();
        // Strain per unit stamp displacement at each node, and the force per unit X.
        let (max_strain, force) = match &self.contact {
            Contact::Homogeneous {
                area_m2,
                compliance_m_per_pa,
            } => {
                let k_film = secant_pa / h0;
                let compliance = if rigid { 0.0 } else { *compliance_m_per_pa };
                let tau = k_film / (1.0 + compliance * k_film);
                (tau / secant_pa, tau * area_m2)
            }
            Contact::Radial { ops, .. } => {
                let mut u = vec![0.0; n];
                if !rigid {
                    let sq = vec![phi_sq; n];
                    let ones = vec![1.0; n];
                    let mut solver = CouplingSolver::new(n);
                    let report = solver.solve(
                        ops,
                        &sq,
                        self.kappa,
                        &ones,
                        &mut u,
                        CouplingTolerance {
                            rel_tol: 1e-10,
                            abs_rms_m: 0.0,
                            spectral_bound: self.rho0 * phi_sq
                                / self.phi0_sq().max(f64::MIN_POSITIVE),
                        },
                    );
                    if !report.converged {
                        return None;
                    }
                }
                let tau: Vec<f64> = u.iter().map(|ui| secant_pa * (1.0 - ui) / h0).collect();
                let max_strain = u.iter().map(|ui| (1.0 - ui) / h0).fold(0.0_f64, f64::max);
                (max_strain, ops.force_3d_n(&tau))
            }
        };
        if !(max_strain > 0.0 && force > 0.0) {
            return None;
        }
        let x_melt_m = eps_m / max_strain;
        Some(ContactSpring {
            x_melt_m,
            f_melt_n: force * x_melt_m,
        })
    }

    /// φ² at t = 0 (the first node's), against which ρ0 was computed.
    fn phi0_sq(&self) -> f64 {
        self.state.physical.phi.first().map_or(0.0, |p| p * p)
    }
}
