//! The accurate step's substrate at the step's end: the guess of u3D from its history, then
//! the coupling (I + K)·u3D = K·u0 with K = κ·C·diag(φ²) solved to a tolerance (see
//! [`super::coupling`]); with the film's viscous stress, the same solve with φ² → w and
//! u0 → s (see [`super::viscous`]). The one-node contact solves it in closed form; a rigid
//! substrate has nothing to solve.

use super::coupling::{CouplingReport, CouplingSolver};
use super::problem::{Contact, Problem};
use super::viscous::Viscous;
use super::{NumericalFailure, SimState};
use crate::config::SimConfig;

/// The accurate step's coupling solver and its scratch (φ² per node).
pub(super) struct SubstrateSolver {
    /// The radial elastic contact's solver; `None` on a rigid substrate or the one-node
    /// contact.
    solver: Option<CouplingSolver>,
    phi_sq: Vec<f64>,
}

impl SubstrateSolver {
    pub fn new(problem: &Problem) -> Self {
        Self {
            solver: problem.coupling_solver(),
            phi_sq: vec![0.0; problem.nodes()],
        }
    }

    /// Solves u3D at `t_s`, the end of a step of `dt_s` in which the stamp advanced `dx_m`
    /// (which only the viscous stress uses): the residual's root mean square over the nodes,
    /// m (0 without a solve).
    ///
    /// # Errors
    /// [`NumericalFailure`] when the solve does not reach its tolerance.
    pub fn solve(
        &mut self,
        problem: &Problem,
        state: &mut SimState,
        viscous: Option<&mut Viscous>,
        (t_s, dt_s, dx_m): (f64, f64, f64),
    ) -> Result<f64, NumericalFailure> {
        if self.solver.is_some() {
            extrapolate_u3d(state, dt_s);
        }
        if let Some(v) = viscous {
            return self.solve_viscous(problem, state, v, (t_s, dt_s, dx_m));
        }
        match (&problem.contact, self.solver.as_mut()) {
            (Contact::Radial(ops), Some(solver)) => {
                for (p2, &p) in self.phi_sq.iter_mut().zip(&state.physical.phi) {
                    *p2 = p * p;
                }
                let report = solver.solve(
                    ops,
                    &self.phi_sq,
                    problem.kappa,
                    &state.physical.u0_m,
                    &mut state.physical.u3d_m,
                    problem.coupling_tolerance(t_s, problem.rho0),
                );
                checked(&problem.config, state, t_s, report, "")
            }
            (Contact::Radial(_), None) => Ok(0.0),
            (
                Contact::Homogeneous {
                    compliance_m_per_pa,
                    ..
                },
                _,
            ) => {
                let phi = state.physical.phi[0];
                let k = *compliance_m_per_pa * problem.config.lubricant.a_pa * phi * phi
                    / problem.config.contact.film_thickness_m;
                // Kept for the next step's strain prediction, as in the radial solve.
                state.stepper.u3d_prev_m[0] = state.physical.u3d_m[0];
                state.physical.u3d_m[0] = k * state.physical.u0_m[0] / (1.0 + k);
                Ok(0.0)
            }
        }
    }

    /// [`solve`](Self::solve) with the viscous stress (after the guess is in place):
    /// (I + κ·C·diag(w))·u3D = κ·C·diag(w)·s (see [`super::viscous`]), the same solve and the
    /// same one-node formula with φ² → w and u0 → s.
    fn solve_viscous(
        &mut self,
        problem: &Problem,
        state: &mut SimState,
        v: &mut Viscous,
        (t_s, dt_s, dx_m): (f64, f64, f64),
    ) -> Result<f64, NumericalFailure> {
        let memory = &mut state.stepper;
        if matches!(problem.contact, Contact::Homogeneous { .. }) {
            // Kept for the next step's strain prediction and the viscous rates' history, as in
            // the radial solve (whose guess has already shifted u3D's history).
            memory.u3d_prev2_m.clone_from(&memory.u3d_prev_m);
            memory.u3d_prev_m[0] = state.physical.u3d_m[0];
        }
        let p = &mut state.physical;
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
            problem.config.lubricant.a_pa,
            dt_s,
            dx_m,
            (&p.phi, &p.u0_m, &memory.u3d_prev_m),
            history,
        );
        match (&problem.contact, self.solver.as_mut()) {
            (Contact::Radial(ops), Some(solver)) => {
                let report = solver.solve(
                    ops,
                    v.w(),
                    problem.kappa,
                    v.s(),
                    &mut p.u3d_m,
                    problem.coupling_tolerance(t_s, bound),
                );
                checked(
                    &problem.config,
                    state,
                    t_s,
                    report,
                    " with the viscous stress",
                )
            }
            (Contact::Radial(_), None) => Ok(0.0),
            (
                Contact::Homogeneous {
                    compliance_m_per_pa,
                    ..
                },
                _,
            ) => {
                let k = *compliance_m_per_pa * problem.config.lubricant.a_pa * v.w()[0]
                    / problem.config.contact.film_thickness_m;
                p.u3d_m[0] = k * v.s()[0] / (1.0 + k);
                Ok(0.0)
            }
        }
    }
}

/// The solve's iterations counted and its residual returned, or the failure of a solve that
/// did not converge (`what`: the solve's qualifier in the diagnosis).
fn checked(
    config: &SimConfig,
    state: &mut SimState,
    t_s: f64,
    report: CouplingReport,
    what: &str,
) -> Result<f64, NumericalFailure> {
    state.counters.coupling_iterations += report.iterations as u64;
    if report.converged {
        return Ok(report.rms_residual_m);
    }
    Err(NumericalFailure {
        t_s,
        step: state.counters.step + 1,
        node: 0,
        r_m: 0.0,
        quantity: "coupling residual",
        value: report.rel_residual,
        diagnosis: format!(
            "the elastic coupling solve{what} did not reach numerics.coupling_tol = {:e} in {} \
             iterations{}",
            config.numerics.coupling_tol,
            report.iterations,
            non_finite_inputs(config, report.rel_residual)
        ),
    })
}

/// First guess of u3D at the end of a step of `dt_s`, written into `u3d_m` while the
/// history shifts (u3d_prev2 ← u3d_prev ← u3d): the quadratic through the last three
/// values when there are three (an error of O(Δt³), which in the stick phase already meets
/// the coupling tolerance, so the solve only checks it), else the linear one.
fn extrapolate_u3d(state: &mut SimState, dt_s: f64) {
    let (p, s) = (&mut state.physical, &mut state.stepper);
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
    // The slices cut to n: no bounds checks, so the loop vectorises.
    let (u3d, prev_m, prev2_m) = (
        &mut p.u3d_m[..n],
        &mut s.u3d_prev_m[..n],
        &mut s.u3d_prev2_m[..n],
    );
    for i in 0..n {
        let (u, prev, prev2) = (u3d[i], prev_m[i], prev2_m[i]);
        u3d[i] = w0 * u + w1 * prev + w2 * prev2;
        prev2_m[i] = prev;
        prev_m[i] = u;
    }
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

/// The quadratic prediction of u3D is used only where its bend is at least this many times
/// the coupling solve's absolute residual floor (`Problem::coupling_abs_rms_m`): u3D is
/// solved only to that floor, and the quadratic through three such values amplifies their
/// noise about fourfold. Measured with the ramp step: the SFA contact (sfa.toml, 0 → 0.11 s,
/// its long stick on the h0 = 1 nm film) in 6646 + 1266 rejected steps against 18 056 + 2989
/// without this condition and 7267 + 720 with the linear prediction alone; fig2 (N = 2000) in
/// 1486 + 168 against 2948 + 58 with the linear one alone.
pub(super) const BEND_NOISE_FACTOR: f64 = 3.0;

/// The substrate's displacement change over the coming step, per node, from its last values:
/// the quadratic through the last three (u3D's error O(Δt³), so the strain the film steps
/// under is off by O(Δt³) and the error estimate's end-strain part is that small where u3D
/// is smooth), or the linear one through the last two where the quadratic's bend is more
/// than half the linear change — in a melting cascade, where u3D's history has kinks the
/// quadratic would throw forward — or below [`BEND_NOISE_FACTOR`] times the coupling's
/// residual floor (noise), and where there is no history yet. Fixed steps keep the
/// linear one: no error estimate rejects a step whose quadratic overshoots a kink there (the
/// hard case of fig2 at Δt = 1 µs had its onsets 5.55 µs off the reference with it, beyond
/// the case's 5·Δt), and their runs stay bit for bit what they were.
pub(super) struct SubstratePredictor {
    /// The linear extrapolation's factor Δt/Δt_last on u − u_prev (0 without a last step).
    ratio: f64,
    /// Lagrange weights of the quadratic's change (u, u_prev, u_prev2), when three values
    /// exist.
    quadratic: Option<(f64, f64, f64)>,
    /// The smallest bend of the quadratic that is taken as signal, m.
    noise_m: f64,
}

impl SubstratePredictor {
    pub(super) fn new(
        memory: &super::state::StepperMemory,
        dt_s: f64,
        adaptive: bool,
        noise_m: f64,
    ) -> Self {
        let (h_last, h_prev) = (memory.last_dt_s, memory.prev_dt_s);
        let ratio = if h_last > 0.0 { dt_s / h_last } else { 0.0 };
        let has_three = adaptive
            && h_last > 0.0
            && h_prev > 0.0
            && memory.u3d_prev2_m.len() == memory.u3d_prev_m.len();
        // Lagrange weights at t_n + x from t_n, t_n − a, t_n − b, less 1 on u: the change.
        let (x, a, b) = (dt_s, h_last, h_last + h_prev);
        let quadratic = has_three.then(|| {
            (
                (x + a) * (x + b) / (a * b) - 1.0,
                -x * (x + b) / (a * (b - a)),
                x * (x + a) / (b * (b - a)),
            )
        });
        Self {
            ratio,
            quadratic,
            noise_m,
        }
    }

    /// [`SubstratePredictor::du3d`] at every node into `out`, with selects in place of
    /// branches (bit for bit the same values), so that the loop vectorises where it is
    /// compiled for the CPU's instruction set; `prev2` is empty when no third value exists.
    #[inline(always)]
    pub(super) fn du3d_all(&self, (u, prev, prev2): (&[f64], &[f64], &[f64]), out: &mut [f64]) {
        let n = out.len();
        let (u, prev) = (&u[..n], &prev[..n]);
        // The quadratic exists only with three values of every node (`new`); otherwise the
        // last values stand in for the third and are never selected.
        let (w0, w1, w2) = self.quadratic.unwrap_or((0.0, 0.0, 0.0));
        let quadratic_ok = self.quadratic.is_some() && prev2.len() == n;
        let prev2 = if prev2.len() == n { prev2 } else { prev };
        for i in 0..n {
            let linear = self.ratio * (u[i] - prev[i]);
            let quadratic = w0 * u[i] + w1 * prev[i] + w2 * prev2[i];
            let bend = (quadratic - linear).abs();
            let take = quadratic_ok & (bend <= 0.5 * linear.abs()) & (bend >= self.noise_m);
            out[i] = if take { quadratic } else { linear };
        }
    }

    /// One node's prediction with branches: the reference [`SubstratePredictor::du3d_all`] is
    /// tested against.
    #[cfg(test)]
    fn du3d(&self, u: f64, prev: f64, prev2: Option<f64>) -> f64 {
        let linear = self.ratio * (u - prev);
        match (self.quadratic, prev2) {
            (Some((w0, w1, w2)), Some(prev2)) => {
                let quadratic = w0 * u + w1 * prev + w2 * prev2;
                let bend = (quadratic - linear).abs();
                if bend <= 0.5 * linear.abs() && bend >= self.noise_m {
                    quadratic
                } else {
                    linear
                }
            }
            _ => linear,
        }
    }
}

#[cfg(test)]
mod prediction_tests {
    use super::SubstratePredictor;

    #[test]
    fn the_select_prediction_is_the_branch_prediction_bit_for_bit() {
        // Linear and quadratic predictors, with and without a third value, bends either side
        // of both limits.
        let n = 4000;
        let wave = |k: usize, f: f64| 1e-9 * ((k as f64 * f).sin() + 0.3 * (k as f64 * 0.37).cos());
        let u: Vec<f64> = (0..n).map(|k| wave(k, 0.011)).collect();
        let prev: Vec<f64> = (0..n).map(|k| wave(k, 0.0109)).collect();
        let prev2: Vec<f64> = (0..n)
            .map(|k| wave(k, 0.0107) * (1.0 + 1e-3 * (k % 7) as f64))
            .collect();
        for quadratic in [None, Some((1.7, -0.9, 0.2)), Some((2.5, -2.0, 0.5))] {
            for noise_m in [0.0, 1e-13, 1e-11] {
                let p = SubstratePredictor {
                    ratio: 1.3,
                    quadratic,
                    noise_m,
                };
                for third in [&prev2[..], &[][..]] {
                    let mut out = vec![0.0; n];
                    p.du3d_all((&u, &prev, third), &mut out);
                    for k in 0..n {
                        let want = p.du3d(u[k], prev[k], third.get(k).copied());
                        assert_eq!(want.to_bits(), out[k].to_bits(), "node {k}, {quadratic:?}");
                    }
                }
            }
        }
    }
}
