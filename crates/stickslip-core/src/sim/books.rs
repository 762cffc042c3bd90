//! The energy books' computations (see [`super::energy`] for what they mean): the energy
//! stored in a state, a step's flows from its start and end, and the per-node sums the
//! steppers call.

use super::energy::{EnergyFlows, StepSinks, StoredEnergy};
use super::problem::Problem;
use super::state::PhysicalState;
use crate::drive::Drive;
use crate::sums;

/// What the books keep of a step's start for its flows.
#[derive(Debug, Clone, Copy)]
pub(super) struct StepStart {
    t_s: f64,
    x_m: f64,
    v_m_per_s: f64,
    force_n: f64,
    /// h0·Σ w_i·φ_i², m³ (only with a temperature law that changes A).
    film_phi_sq_m3: f64,
}

/// The drive's work over the step from `start` to `p`, J. The spring's free end moves at V0
/// against the spring's and the dashpot's tension: V0·(K·∫s dt + c_d·Δs) with the stretch
/// s = V0·t − X, ∫s dt by the trapezoidal rule with its end correction h²/12·(ṡ0 − ṡ1)
/// (ṡ = V0 − V is known at both ends), fourth order, so that the books' quadrature stays
/// below the stepping's own error even on the long steps of a stick phase. The rigid coupler:
/// F·V0 by the trapezoidal rule.
fn drive_work_j(problem: &Problem, start: &StepStart, p: &PhysicalState) -> f64 {
    let d = &p.drive;
    let h = d.t_s - start.t_s;
    match &problem.config.drive {
        Drive::Spring(sp) => {
            let v0 = sp.velocity_m_per_s;
            let (s0, s1) = (v0 * start.t_s - start.x_m, v0 * d.t_s - d.x_m);
            let integral = 0.5 * h * (s0 + s1) + h * h / 12.0 * (d.v_m_per_s - start.v_m_per_s);
            v0 * (sp.stiffness_n_per_m * integral + sp.damping_n_s_per_m * (s1 - s0))
        }
        Drive::Rigid(r) => 0.5 * (start.force_n + p.force_n) * r.velocity_m_per_s * h,
    }
}

/// The temperature law changes A: the temperature's work is then computed.
fn temperature_varies(problem: &Problem) -> bool {
    let t = problem.config.temperature;
    t.a_coeff_pa(0.0) != t.a_coeff_pa(1.0)
}

fn film_phi_sq_m3(problem: &Problem, p: &PhysicalState) -> f64 {
    if !temperature_varies(problem) {
        return 0.0;
    }
    let h0 = problem.config.contact.film_thickness_m;
    h0 * sums::sum_cols([&problem.energy_weights_m2, &p.phi], |[w, phi]| {
        w * phi * phi
    })
}

impl StepStart {
    /// The start of a step from `p`.
    pub fn of(problem: &Problem, p: &PhysicalState) -> Self {
        Self {
            t_s: p.drive.t_s,
            x_m: p.drive.x_m,
            v_m_per_s: p.drive.v_m_per_s,
            force_n: p.force_n,
            film_phi_sq_m3: film_phi_sq_m3(problem, p),
        }
    }
}

/// The energy stored in `p`, J.
pub(super) fn stored(problem: &Problem, p: &PhysicalState) -> StoredEnergy {
    let d = &p.drive;
    let (spring_j, kinetic_j) = match &problem.config.drive {
        Drive::Spring(s) => {
            let stretch = s.velocity_m_per_s * d.t_s - d.x_m;
            (
                0.5 * s.stiffness_n_per_m * stretch * stretch,
                0.5 * s.mass_kg * d.v_m_per_s * d.v_m_per_s,
            )
        }
        Drive::Rigid(_) => (0.0, 0.0),
    };
    let params = problem.config.lubricant;
    let a_coeff = problem.config.temperature.a_coeff_pa(d.t_s);
    let h0 = problem.config.contact.film_thickness_m;
    let cols: [&[f64]; 5] = [
        &problem.energy_weights_m2,
        &p.phi,
        &p.eps,
        &p.tau_pa,
        &p.u3d_m,
    ];
    let (film, substrate) = sums::sum2_cols(cols, |[w, phi, eps, tau, u]| {
        (w * params.free_energy_pa(phi, eps, a_coeff), w * tau * u)
    });
    StoredEnergy {
        spring_j,
        kinetic_j,
        film_j: h0 * film,
        substrate_j: 0.5 * substrate,
    }
}

/// The flows of the step from `start` to `p` with the stepper's `sinks`, J.
pub(super) fn step_flows(
    problem: &Problem,
    start: &StepStart,
    p: &PhysicalState,
    sinks: &StepSinks,
) -> EnergyFlows {
    let dt = p.drive.t_s - start.t_s;
    let drive_work_j = drive_work_j(problem, start, p);
    let dashpot_j = match &problem.config.drive {
        Drive::Spring(s) if s.damping_n_s_per_m > 0.0 => {
            let v0 = s.velocity_m_per_s;
            let (r0, r1) = (v0 - start.v_m_per_s, v0 - p.drive.v_m_per_s);
            0.5 * s.damping_n_s_per_m * (r0 * r0 + r1 * r1) * dt
        }
        _ => 0.0,
    };
    let temperature_work_j = if temperature_varies(problem) {
        let params = problem.config.lubricant;
        let t = problem.config.temperature;
        let da = t.a_coeff_pa(p.drive.t_s) - t.a_coeff_pa(start.t_s);
        // ∂f/∂A = −(b/(2a))·φ², φ² by the trapezoidal rule.
        let phi_sq = 0.5 * (start.film_phi_sq_m3 + film_phi_sq_m3(problem, p));
        -params.b_pa() / (2.0 * params.a_pa) * da * phi_sq
    } else {
        0.0
    };
    EnergyFlows {
        drive_work_j,
        temperature_work_j,
        noise_work_j: sinks.noise_work_j,
        landau_j: sinks.landau_j,
        reset_j: sinks.reset_j,
        sliding_j: sinks.sliding_j,
        viscous_j: sinks.viscous_j,
        dashpot_j,
    }
}

/// The free energy the noise (or the φ floor) added over a step, J: f after it less f before
/// it (`phi`: before, after), at the strain of each node's last exact path `eps_path`.
pub(super) fn noise_work_j(
    problem: &Problem,
    a_coeff: f64,
    (before, after): (&[f64], &[f64]),
    eps_path: &[f64],
) -> f64 {
    let params = problem.config.lubricant;
    let w = &problem.energy_weights_m2[..];
    // The noise changes few nodes per step (the floor only those below it): nothing to sum
    // where none changed.
    if before == after {
        return 0.0;
    }
    let sum = sums::sum_cols([w, before, after, eps_path], |[w, b, a, eps]| {
        let change =
            params.free_energy_pa(a, eps, a_coeff) - params.free_energy_pa(b, eps, a_coeff);
        if a != b { w * change } else { 0.0 }
    });
    problem.config.contact.film_thickness_m * sum
}

/// The stamp's work on nodes while their u0 was held, J: the elastic stress a·φ²·ε by the
/// trapezoidal rule (`tau0`: at the step's start, Pa; the end's from `p`) times the stamp's
/// advance the node did not follow (`held`, m).
pub(super) fn sliding_j(problem: &Problem, p: &PhysicalState, tau0: &[f64], held: &[f64]) -> f64 {
    let a = problem.config.lubricant.a_pa;
    let cols = [&problem.energy_weights_m2[..], held, tau0, &p.phi, &p.eps];
    sums::sum_cols(cols, |[w, held, tau0, phi, eps]| {
        let tau1 = a * phi * phi * eps;
        let term = w * 0.5 * (tau0 + tau1) * held;
        // A held node's term only: a node that never held adds an exact 0, whatever its τ.
        if held != 0.0 { term } else { 0.0 }
    })
}
