//! The problem a simulation solves, fixed once it is built: the resolved configuration, the
//! grid's radii and area weights, the contact's operators, κ, the lagged sweep's contraction
//! at t = 0 and the contact as a spring. Every stepper reads it and none writes it; the state
//! it advances is [`super::state`]'s and its scratch is its own.

use super::coupling::{CouplingSolver, CouplingTolerance};
use crate::config::{ContactModel, Scheme, SimConfig, Substrate};
use crate::drive::{Drive, Integrator};
use crate::grid::Grid;
use crate::mdr::{MdrOperators, Quadrature};
use crate::preflight::ContactSpring;
use std::f64::consts::PI;

/// The share of the step's strain tolerance a coupling residual may take (see
/// [`Problem::coupling_abs_rms_m`]).
pub const COUPLING_STRAIN_SHARE: f64 = 0.1;

/// The contact's substrate response: the radial contact's operators, or the one-node
/// (homogeneous) contact's compliance.
pub(super) enum Contact {
    Radial(Box<MdrOperators>),
    Homogeneous {
        area_m2: f64,
        /// u3D per unit τ, m/Pa (0 for a rigid substrate).
        compliance_m_per_pa: f64,
    },
}

/// The immutable part of a simulation (see the module docs).
pub(super) struct Problem {
    pub config: SimConfig,
    pub contact: Contact,
    /// Node radii, m (one node at r = 0 for the homogeneous contact).
    pub radii_m: Vec<f64>,
    /// Area weights of the nodes, summing to 1.
    pub area_weights: Vec<f64>,
    /// The weights of ∫·dA over the contact for the energy books (the force's quadrature,
    /// F = Σ w_i·τ_i), m².
    pub energy_weights_m2: Vec<f64>,
    /// κ = a/(h0·G*), 1/m: the coupling's scale per unit φ².
    pub kappa: f64,
    /// The solid film's φ at t = 0 (every node's first value).
    pub phi_init: f64,
    /// Contraction factor ρ of the lagged sweep at t = 0 (see [`Problem::contraction_with`]):
    /// bounds K's spectrum for the coupling solve's relaxation of accepted guesses.
    pub rho0: f64,
    /// The contact as a linear spring at t = 0 ([`Problem::linear_contact_spring`]), computed
    /// once, when first asked for ([`Problem::contact_spring`]): at the start for the split
    /// integrator's flow, by the preflight otherwise; a simulation that asks for neither
    /// (a rigid drive stepped without a preflight) does not pay its solve.
    contact_spring: std::sync::OnceLock<Option<ContactSpring>>,
    /// The fold estimate solved on the coarse copy of a contact finer than its grid
    /// (`Problem::coarse_fold`), computed with the operators; `None` where the
    /// estimate uses the contact itself.
    pub(super) coarse_fold: Option<Option<ContactSpring>>,
    /// The contact's linear stiffness k with which the split integrator's exact flow carries
    /// the friction force linearised at each step's start, N/m (see
    /// [`crate::drive::SpringDrive::loaded_flow`]): the contact spring's; 0 for the other
    /// integrators, the rigid drive and the literal scheme, whose flow is the spring's alone.
    pub flow_stiffness_n_per_m: f64,
}

impl Problem {
    /// Builds the grid, the operators and what follows from them.
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
        let (radii_m, area_weights) = match c.model {
            ContactModel::Radial => (grid.radii_m(), grid.area_weights()),
            ContactModel::Homogeneous => (vec![0.0], vec![1.0]),
        };
        let radial = || {
            let quadrature = match config.time.scheme {
                Scheme::Literal => Quadrature::Literal,
                Scheme::Accurate => Quadrature::Product,
            };
            Contact::Radial(Box::new(MdrOperators::with_form(
                grid,
                quadrature,
                config.operator_form(),
            )))
        };
        // A contact finer than the fold estimate's grid has that estimate solved on its own
        // coarse copy, beside the operators' build (both on the thread pool): at fig2's
        // N = 2000 its sweeps took 9.5 ms of a 40 ms start-up after the build.
        let (contact, coarse_fold) = match c.model {
            ContactModel::Radial if Self::solves_coarse_fold(&config) => {
                let (contact, fold) = rayon::join(radial, || Self::coarse_fold(&config));
                (contact, Some(fold))
            }
            ContactModel::Radial => (radial(), None),
            ContactModel::Homogeneous => (
                Contact::Homogeneous {
                    area_m2: PI * c.radius_m * c.radius_m,
                    compliance_m_per_pa: if elastic {
                        PI * c.radius_m / (2.0 * c.g_eff_pa)
                    } else {
                        0.0
                    },
                },
                None,
            ),
        };
        // The unstrained solid film: √(A/a), or φ₊(0) of the first-order film (which also
        // starts solid, as a metastable solid, for A ≤ 0 while b₃² ≥ −4b·A·b/a).
        let phi_init = config
            .lubricant
            .solid_phi(0.0, config.temperature.a_coeff_pa(0.0));
        let kappa = config.lubricant.a_pa / (c.film_thickness_m * c.g_eff_pa);
        let mut problem = Self {
            config,
            contact,
            radii_m,
            area_weights,
            energy_weights_m2: Vec::new(),
            kappa,
            phi_init,
            rho0: 0.0,
            contact_spring: std::sync::OnceLock::new(),
            coarse_fold,
            flow_stiffness_n_per_m: 0.0,
        };
        problem.energy_weights_m2 = match &problem.contact {
            Contact::Radial(ops) => ops.force_3d_weights_m2().to_vec(),
            Contact::Homogeneous { area_m2, .. } => vec![*area_m2],
        };
        problem.rho0 = problem.contraction_with(&vec![phi_init * phi_init; n]);
        if matches!(problem.config.drive, Drive::Spring(_))
            && problem.config.integrator == Integrator::Split
            && problem.config.time.scheme == Scheme::Accurate
            && let Some(k) = problem.contact_spring()
        {
            problem.flow_stiffness_n_per_m = k.stiffness_n_per_m();
        }
        Ok(problem)
    }

    /// The contact as a linear spring at t = 0 (see the `contact_spring` module), solved on
    /// the first call; none when the contact has no such spring.
    pub fn contact_spring(&self) -> Option<ContactSpring> {
        *self
            .contact_spring
            .get_or_init(|| self.linear_contact_spring())
    }

    /// The nodes simulated.
    pub fn nodes(&self) -> usize {
        self.radii_m.len()
    }

    /// The coupling solve's absolute floor at `t_s` with adaptive steps: a residual of RMS
    /// [`COUPLING_STRAIN_SHARE`]·`time.tolerance`·εc(t)·h0 over the nodes, m (εc: the melting
    /// strain, as in the error estimate's strain scale; εmax when nothing melts). Its
    /// displacement shifts the strain by that share of what the step's error estimate accepts
    /// (the stamp's position error is measured against the same h0·εc), so solving further is
    /// work the step cannot use; `numerics.coupling_tol`'s relative bound still applies where it
    /// is looser. 0 with fixed steps, which keep `numerics.coupling_tol` alone.
    pub fn coupling_abs_rms_m(&self, t_s: f64) -> f64 {
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

    /// ε = (u0 − u3D)/h0 (Eq. 11) and τ = aφ²ε (Eq. 12) from the state's φ, u0 and u3D.
    pub fn update_strain_and_stress(&self, s: &mut super::PhysicalState) {
        let h0 = self.config.contact.film_thickness_m;
        let a = self.config.lubricant.a_pa;
        // The slices cut to n: no bounds checks, so the loop vectorises.
        let n = s.phi.len();
        let (phi, u0, u3d) = (&s.phi[..n], &s.u0_m[..n], &s.u3d_m[..n]);
        let (eps_out, tau) = (&mut s.eps[..n], &mut s.tau_pa[..n]);
        // A multiplication by 1/h0, not a division per node (see `sim::node_pass`).
        let inv_h0 = 1.0 / h0;
        for i in 0..n {
            let eps = (u0[i] - u3d[i]) * inv_h0;
            eps_out[i] = eps;
            tau[i] = a * phi[i] * phi[i] * eps;
        }
    }

    /// The friction force of the stresses `tau_pa`, 2π∫τ r dr, N.
    pub fn force_3d_n(&self, tau_pa: &[f64]) -> f64 {
        match &self.contact {
            Contact::Radial(ops) => ops.force_3d_n(tau_pa),
            Contact::Homogeneous { area_m2, .. } => area_m2 * tau_pa[0],
        }
    }

    /// ρ(κ·C·diag(`phi_sq`)) by power iteration: the contraction factor of the paper's lagged
    /// elastic sweep u3D ← K·(u0 − u3D) with K = (a/(h0·G*))·C·diag(φ²) and C this scheme's
    /// compliance. The sweep converges only when ρ < 1; the accurate scheme's solve does not
    /// need it. K has non-negative entries, so power iteration from a positive vector converges
    /// to ρ (Perron–Frobenius); 0 for a rigid substrate.
    pub fn contraction_with(&self, phi_sq: &[f64]) -> f64 {
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
            Contact::Radial(ops) => {
                let mut x = vec![1.0 / (n as f64).sqrt(); n];
                let mut dx = vec![0.0; n];
                let mut y = vec![0.0; n];
                let mut q = vec![0.0; n];
                let mut rho = 0.0;
                for _ in 0..500 {
                    for i in 0..n {
                        dx[i] = self.kappa * phi_sq[i] * x[i];
                    }
                    ops.compliance(&dx, &mut q, &mut y);
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

    /// A coupling solver of this problem's size when the scheme solves the coupling (the
    /// accurate scheme on an elastic radial contact); `None` otherwise.
    pub fn coupling_solver(&self) -> Option<CouplingSolver> {
        (matches!(self.contact, Contact::Radial(_))
            && self.config.contact.substrate == Substrate::Elastic
            && self.config.time.scheme == Scheme::Accurate)
            .then(|| CouplingSolver::new(self.nodes()))
    }

    /// The tolerance of the accurate step's coupling solve at `t_s` with `spectral_bound`.
    pub fn coupling_tolerance(&self, t_s: f64, spectral_bound: f64) -> CouplingTolerance {
        CouplingTolerance {
            rel_tol: self.config.numerics.coupling_tol,
            abs_rms_m: self.coupling_abs_rms_m(t_s),
            spectral_bound,
            deepen_near_misses: self.config.time.adaptive.is_none(),
        }
    }
}
