//! The contact as a linear spring, whose stiffness the split integrator's flow carries (the
//! stamp's oscillation on the contact followed exactly) and from which the preflight estimates
//! the first onset (`check`): the film linearised at its secant stiffness at melting
//! (τ = a·φs²·ε with a·φs²·ε_m = the peak stress, so a node at the melting strain ε_m carries
//! exactly the peak stress), in series with the substrate's static response. A unit stamp displacement X = 1 gives, from (I + K)·u3D = K·1 with
//! K = κ·C·diag(φs²) (the coupling the accurate scheme solves each step), the strain at every
//! node, (1 − u3D)/h0, and the force. The first node reaches ε_m at X_m = ε_m / max strain;
//! the force then is F_m = X_m · (force per unit X); the contact's stiffness is F_m / X_m.
//!
//! On a stiff film over a soft substrate (an h0 = 1 nm film under a 20 µm stamp) the edge
//! carries the load, and F_m is well below the peak stress times the area: the film melts at
//! the edge first. On a compliant film (fig2's 100 nm) the strain is nearly uniform and F_m
//! is close to the peak stress times the area.

use super::coupling::{CouplingSolver, CouplingTolerance};
use super::problem::{Contact, Problem};
use crate::config::{ContactModel, SimConfig, Substrate};
use crate::preflight::ContactSpring;

impl Problem {
    /// The contact as a linear spring at t = 0 (see the module docs); none when the film
    /// starts molten or nothing can melt (no melting strain). It depends on the configuration
    /// and the operators alone: [`Problem::new`] computes it once.
    pub(super) fn linear_contact_spring(&self) -> Option<ContactSpring> {
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
        let n = self.nodes();
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
            Contact::Radial(ops) => {
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
                            deepen_near_misses: false,
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

    /// The contact's spring for the first-onset estimate: [`Problem::contact_spring`] with
    /// its melting point moved to the quasi-static fold of the radial contact on an elastic
    /// substrate, where the film is not linear. Each node's film follows its equilibrium branch
    /// φ_eq(ε), whose stress a·φ_eq²·ε peaks below the melting strain; the substrate spreads
    /// the load of the softening edge inward, and the coupled static problem loses its
    /// solution (the fold) at a stamp displacement X_f above the linear X_m when the film is
    /// thin. On the resolved grid the linear estimate is 12 % early for the 1 nm SFA contact
    /// (tests/onset_estimate.rs). X_f is bracketed by bisection on X, each X solved by the
    /// fixed point φ² ← φ_eq(ε(φ²))² from the unloaded film, which descends monotonically to
    /// the stable branch while it exists and loses a node to φ = 0 past the fold.
    pub(super) fn onset_spring(&self) -> Option<ContactSpring> {
        let linear = self.contact_spring()?;
        let c = &self.config;
        let l = c.lubricant;
        let a_coeff = c.temperature.a_coeff_pa(0.0);
        let h0 = c.contact.film_thickness_m;
        let melted_sq = c.melt_threshold * c.melt_threshold;
        if c.contact.substrate == Substrate::Rigid {
            return Some(linear);
        }
        let Contact::Radial(ops) = &self.contact else {
            return Some(linear);
        };
        if let Some(fold) = self.coarse_fold {
            return fold.or(Some(linear));
        }
        let n = self.nodes();
        let phi0_sq = l.solid_phi(0.0, a_coeff).powi(2);
        let kappa = self.kappa;
        let rho0 = self.rho0;
        let own_phi0_sq = self.phi0_sq().max(f64::MIN_POSITIVE);
        let mut solver = CouplingSolver::new(n);
        // The static state at stamp displacement x from the film's φ² and the substrate's
        // displacement `start` of a stable state at a smaller x (φ² falls with x, so the sweeps
        // still descend from above): its force and state when the stable branch exists.
        let mut force_at = |x: f64, start: &StaticState| -> Option<(f64, StaticState)> {
            let (mut sq, mut u) = start.clone();
            let u0 = vec![x; n];
            for _ in 0..FOLD_ITERATIONS {
                let report = solver.solve(
                    ops,
                    &sq,
                    kappa,
                    &u0,
                    &mut u,
                    CouplingTolerance {
                        rel_tol: 1e-3 * FOLD_SETTLED,
                        abs_rms_m: 0.0,
                        spectral_bound: rho0 * phi0_sq / own_phi0_sq,
                        deepen_near_misses: false,
                    },
                );
                if !report.converged {
                    return None;
                }
                let mut change = 0.0_f64;
                for (q, ui) in sq.iter_mut().zip(&u) {
                    let next = l.solid_phi((x - ui) / h0, a_coeff).powi(2);
                    if next < melted_sq {
                        return None;
                    }
                    change = change.max((next - *q).abs());
                    *q = next;
                }
                let settled = FOLD_SETTLED * phi0_sq;
                if change <= settled {
                    let tau: Vec<f64> = sq
                        .iter()
                        .zip(&u)
                        .map(|(q, ui)| l.a_pa * q * (x - ui) / h0)
                        .collect();
                    return Some((ops.force_3d_n(&tau), (sq, u)));
                }
            }
            None
        };
        // The fold lies above the linear melting point's stable state (the secant film is the
        // softest): bracket it from there.
        let unloaded = (vec![phi0_sq; n], vec![0.0; n]);
        let mut lo = 0.5 * linear.x_melt_m;
        let (mut f_lo, mut state) = force_at(lo, &unloaded)?;
        let mut hi = linear.x_melt_m;
        let mut grown = 0;
        while let Some((f, next)) = force_at(hi, &state) {
            (lo, f_lo, state) = (hi, f, next);
            hi *= 2.0;
            grown += 1;
            if grown > 20 {
                return Some(linear);
            }
        }
        while hi - lo > FOLD_RTOL * hi {
            let mid = 0.5 * (lo + hi);
            match force_at(mid, &state) {
                Some((f, next)) => (lo, f_lo, state) = (mid, f, next),
                None => hi = mid,
            }
        }
        Some(ContactSpring {
            x_melt_m: lo,
            f_melt_n: f_lo,
        })
    }

    /// Whether the fold estimate of `config`'s contact is solved on its coarse copy
    /// ([`Self::coarse_fold`]): an elastic radial contact of more than [`FOLD_NODES`] nodes.
    pub(super) fn solves_coarse_fold(config: &SimConfig) -> bool {
        config.contact.model == ContactModel::Radial
            && config.contact.substrate == Substrate::Elastic
            && config.simulated_nodes() > FOLD_NODES
    }

    /// The fold estimate of `config`'s contact on a coarse copy: the fold's sweeps on a fine grid
    /// would cost a run's start-up several times over, and the same contact on the accurate
    /// scheme's graded grid of [`FOLD_NODES`] nodes, whose first onset is within 1e-3 of converged
    /// for thin films (docs/model.md, "The radial grid"), gives it well within the estimate's
    /// accuracy. `None` where the copy has no fold estimate (the caller falls back on the linear
    /// spring).
    pub(super) fn coarse_fold(config: &SimConfig) -> Option<ContactSpring> {
        let mut coarse = config.clone();
        coarse.contact.nodes = FOLD_NODES;
        coarse.contact.grid = crate::grid::Grading::Edge { power: 3.0 };
        coarse.time.scheme = crate::config::Scheme::Accurate;
        coarse.numerics.operator = None;
        Self::new(coarse).ok().and_then(|p| p.onset_spring())
    }

    /// φ² at t = 0, against which ρ0 was computed.
    fn phi0_sq(&self) -> f64 {
        self.phi_init * self.phi_init
    }
}

/// A static state of the contact: each node's φ² and the substrate's displacement u3D, m.
type StaticState = (Vec<f64>, Vec<f64>);

/// Above this many nodes the fold is found on a graded copy of the contact with this many.
const FOLD_NODES: usize = 200;
/// The fold's stamp displacement is bracketed to this relative width.
const FOLD_RTOL: f64 = 1e-3;
/// A stamp displacement's sweeps have settled when no node's φ² changes by more than this
/// fraction of the unloaded film's (an estimate's accuracy: the fold moves by less than 1e-3).
const FOLD_SETTLED: f64 = 1e-6;
/// Fixed-point sweeps per stamp displacement; one that has not settled counts as past the
/// fold (the sweeps slow down as the fold nears, so this brackets it from below).
const FOLD_ITERATIONS: usize = 60;
