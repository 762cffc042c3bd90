//! The film's Newtonian viscous stress η·(Ẋ − u̇3D)/h0 (`lubricant.viscosity` > 0,
//! docs/model.md#viscosity), in the accurate scheme. The rates at the step's end are implicit:
//! the second-order backward difference (BDF2, variable steps) of the stamp's position and of
//! u3D when the last step is known and this one is at most twice as long (variable-step BDF2
//! is zero-stable below a ratio of 1 + √2), backward Euler otherwise (the first step, after
//! an onset, after a jump in the step). Either way the stress is
//! τ_v = η·α0/(Δt·h0)·(g − u3D) with g known before the solve, which turns the coupling into
//! the accurate scheme's solve with φ² replaced by w = φ² + η·α0/(a·Δt) and u0 by
//! s = (φ²·u0 + (η·α0/(a·Δt))·g)/w: stable for any step (BDF2 and backward Euler are both
//! L-stable). The stamp's drag c_v·Ẋ is folded into the spring's exact flow, the kicks carry
//! the rest; the coupling's local error goes to the adaptive control.
//!
//! With η = 0 nothing here is built or called, and every step is the paper's film's
//! arithmetic unchanged.

use super::SimState;
use super::problem::Problem;
use crate::config::Substrate;

/// What the viscous stress needs besides the state.
#[derive(Debug)]
pub(super) struct Viscous {
    /// η, Pa·s.
    pub eta_pa_s: f64,
    /// c_v = η·A/h0, N·s/m, with A = πa0² as the force quadrature integrates a uniform stress
    /// (so that on a rigid substrate the kicks carry no part of the drag at all).
    pub drag_n_s_per_m: f64,
    /// The drag this step's spring flow takes, c_v·(1 − J), N·s/m: J ≈ ∂u̇3D/∂Ẋ, the share of
    /// the stamp's velocity the substrate follows through the film (0 on a rigid substrate,
    /// → 1 for a film too viscous to shear within the step), estimated at the step's start
    /// for the one-node contact of the mean φ² (see [`Viscous::step_start`]).
    pub flow_drag_n_s_per_m: f64,
    /// Spectral radius of κ·C (the compliance at unit film stiffness; radial elastic contacts):
    /// κ·C·diag(w) has its spectrum within [0, this·max w], the coupling solve's bound.
    pub unit_contraction: f64,
    /// w = φ² + η·α0/(a·Δt) per node.
    w: Vec<f64>,
    /// s per node, m: the displacement the film's total stiffness pulls u3D towards.
    s: Vec<f64>,
    /// g per node, m: the viscous stress is η·α0/(Δt·h0)·(g − u3D).
    g: Vec<f64>,
    /// This step's rule: α0 (1 for backward Euler), and with BDF2 the ratio ω = Δt/Δt_prev
    /// and the last step's length, s.
    alpha0: f64,
    bdf2: Option<(f64, f64)>,
    /// The viscous film's relaxation time against the substrate, η·C/h0 with C = πa0/(2G*)
    /// the flat punch's compliance per stress (0 on a rigid substrate), s.
    relaxation_s: f64,
    /// r = Ẋ − u̇3D = h0·τ_v/η per node at the step's start (the last step's rates), m/s.
    rate_before: Vec<f64>,
}

impl Viscous {
    /// For `n` nodes.
    pub fn new(
        eta_pa_s: f64,
        (drag_n_s_per_m, relaxation_s): (f64, f64),
        unit_contraction: f64,
        n: usize,
    ) -> Self {
        Self {
            eta_pa_s,
            drag_n_s_per_m,
            flow_drag_n_s_per_m: drag_n_s_per_m,
            relaxation_s,
            unit_contraction,
            w: vec![0.0; n],
            s: vec![0.0; n],
            g: vec![0.0; n],
            alpha0: 1.0,
            bdf2: None,
            rate_before: vec![0.0; n],
        }
    }
}

impl Viscous {
    /// The coupling's weights w and targets s for a step of `dt_s` in which the stamp advanced
    /// `dx_m`, from φ, u0 and the substrate's displacement at the step's start `u3d_now`, with
    /// the film's coefficient `a_pa`; `history` (the last step's length, the stamp's advance
    /// over it, u3D at its start) gives BDF2 when the step is at most twice the last one.
    /// Returns the spectral bound of κ·C·diag(w).
    ///
    /// Variable-step BDF2 with ω = Δt/Δt_prev: y'(t_{n+1}) ≈ (α0·Δy − α2·Δy_prev)/Δt,
    /// α0 = (1 + 2ω)/(1 + ω), α2 = ω²/(1 + ω), so τ_v = η·α0/(Δt·h0)·(g − u3D) with
    /// g = ΔX + u3D_n − (α2/α0)·(ΔX_prev − Δu3D_prev); backward Euler is α0 = 1, g = ΔX + u3D_n.
    pub fn prepare(
        &mut self,
        a_pa: f64,
        dt_s: f64,
        dx_m: f64,
        (phi, u0, u3d_now): (&[f64], &[f64], &[f64]),
        history: Option<(f64, f64, &[f64])>,
    ) -> f64 {
        let bdf2 = history.filter(|&(h_prev, _, _)| h_prev > 0.0 && dt_s <= 2.0 * h_prev);
        let (k, dx_prev, u3d_before) = match bdf2 {
            Some((h_prev, dx_prev, u3d_before)) => {
                let omega = dt_s / h_prev;
                self.alpha0 = (1.0 + 2.0 * omega) / (1.0 + omega);
                self.bdf2 = Some((omega, h_prev));
                (omega * omega / (1.0 + 2.0 * omega), dx_prev, u3d_before)
            }
            None => {
                self.alpha0 = 1.0;
                self.bdf2 = None;
                (0.0, 0.0, u3d_now)
            }
        };
        let beta = self.eta_pa_s * self.alpha0 / (a_pa * dt_s);
        let mut w_max = 0.0_f64;
        for i in 0..phi.len() {
            let y = phi[i] * phi[i];
            let w = y + beta;
            let g = if k == 0.0 {
                dx_m + u3d_now[i]
            } else {
                dx_m + u3d_now[i] - k * (dx_prev - (u3d_now[i] - u3d_before[i]))
            };
            self.g[i] = g;
            self.w[i] = w;
            self.s[i] = (y * u0[i] + beta * g) / w;
            w_max = w_max.max(w);
        }
        self.unit_contraction * w_max
    }

    /// w per node (after [`prepare`](Self::prepare)).
    pub fn w(&self) -> &[f64] {
        &self.w
    }

    /// s per node, m (after [`prepare`](Self::prepare)).
    pub fn s(&self) -> &[f64] {
        &self.s
    }
}

impl Viscous {
    /// The force the drive's kicks carry: F itself without viscosity; with it F − c·Ẋ (the Ẋ
    /// of the viscous stress, c the step's flow drag), the part of the film's force the
    /// spring's flow does not take (on a rigid substrate c = c_v and this is F_el).
    pub(super) fn kick_force_n(&self, state: &SimState) -> f64 {
        state.physical.force_n - self.flow_drag_n_s_per_m * state.stepper.viscous_v_m_per_s
    }

    /// Before a step of `dt_s`: the film's shear rate r = Ẋ − u̇3D per node at the step's
    /// start, from the viscous stress of the state, τ − a·φ²·ε = η·r/h0 (valid after any step,
    /// also one whose history the adaptive control cleared); and the drag the spring's flow
    /// takes over the step.
    ///
    /// The flow may take any part c of the drag: the kicks carry F − c·Ẋ, and the split stays
    /// consistent and second order. The part that keeps the kicks free of stiffness is the
    /// force's own dependence on Ẋ, c_v·(1 − J) with J = ∂u̇3D/∂Ẋ: on a rigid substrate J = 0
    /// (all of c_v), for a film too viscous to shear within the step J → 1 (the stamp and the
    /// substrate move together, and a flow with all of c_v would hold the stamp back while the
    /// kicks gave the substrate's rate back). On the one-node contact of compliance C per
    /// stress, the coupling gives J = (k/(1 + k))·(β/w) with β = η·α0/(a·Δt), w = φ² + β,
    /// k = C·a·w/h0; a radial contact uses it with the mean φ² and C = πa0/(2G*).
    pub(super) fn step_start(&mut self, problem: &Problem, state: &SimState, dt_s: f64) {
        let v = self;
        let s = &state.physical;
        let a = problem.config.lubricant.a_pa;
        let h0 = problem.config.contact.film_thickness_m;
        let mut y_mean = 0.0;
        for i in 0..s.phi.len() {
            let y = s.phi[i] * s.phi[i];
            let tau_v = s.tau_pa[i] - a * y * s.eps[i];
            v.rate_before[i] = h0 * tau_v / v.eta_pa_s;
            y_mean += problem.area_weights[i] * y;
        }
        let last = state.stepper.last_dt_s;
        let alpha0 = if last > 0.0 && dt_s <= 2.0 * last {
            let omega = dt_s / last;
            (1.0 + 2.0 * omega) / (1.0 + omega)
        } else {
            1.0
        };
        let beta = v.eta_pa_s * alpha0 / (a * dt_s);
        let w = y_mean + beta;
        // k = C·a·w/h0 with C = t_v·h0/η.
        let k = v.relaxation_s * a * w / v.eta_pa_s;
        let share = k / (1.0 + k) * (beta / w);
        v.flow_drag_n_s_per_m = v.drag_n_s_per_m * (1.0 - share);
    }

    /// After ε and τ of the step's end (Eqs. 11–12): τ gains η·α0/(Δt·h0)·(g − u3D), and the
    /// stamp's history is kept (ΔX/Δt, and the Ẋ of the stress for the kicks).
    pub(super) fn add_stress(&self, problem: &Problem, state: &mut SimState, dt_s: f64, dx_m: f64) {
        let v = self;
        let h0 = problem.config.contact.film_thickness_m;
        let (p, memory) = (&mut state.physical, &mut state.stepper);
        let k = v.eta_pa_s * v.alpha0 / (dt_s * h0);
        let elastic = problem.config.contact.substrate == Substrate::Elastic;
        for i in 0..p.phi.len() {
            let u = if elastic { p.u3d_m[i] } else { 0.0 };
            p.tau_pa[i] += k * (v.g[i] - u);
        }
        // Ẋ = α0·(ΔX − (α2/α0)·ΔX_prev)/Δt: g less u3D_n and the substrate's history.
        let xdot = match v.bdf2 {
            Some((omega, h_prev)) => {
                let k = omega * omega / (1.0 + 2.0 * omega);
                v.alpha0 * (dx_m - k * memory.mean_v_m_per_s * h_prev) / dt_s
            }
            None => dx_m / dt_s,
        };
        memory.viscous_v_m_per_s = xdot;
        memory.mean_v_m_per_s = dx_m / dt_s;
    }

    /// The film's viscous dissipation over the step just taken, J: η·r²/h0 = τ_v·r per area
    /// (r = Ẋ − u̇3D = h0·τ_v/η) by the trapezoidal rule, from the start's rates and the end's
    /// viscous stress τ − a·φ²·ε (after [`add_stress`](Self::add_stress)).
    pub(super) fn loss_j(&self, problem: &Problem, state: &SimState, dt_s: f64) -> f64 {
        let a = problem.config.lubricant.a_pa;
        let h0 = problem.config.contact.film_thickness_m;
        let p = &state.physical;
        let mut sum = 0.0;
        for (i, &w) in problem.energy_weights_m2.iter().enumerate() {
            let tau_v1 = p.tau_pa[i] - a * p.phi[i] * p.phi[i] * p.eps[i];
            let r1 = h0 * tau_v1 / self.eta_pa_s;
            let r0 = self.rate_before[i];
            let tau_v0 = self.eta_pa_s * r0 / h0;
            sum += w * 0.5 * (tau_v0 * r0 + tau_v1 * r1);
        }
        sum * dt_s
    }

    /// The local error in u3D of the step's viscous coupling, m, for the strain's part of the
    /// step error; keeps this step's start rates for the next one. The stamp's advance enters
    /// exactly and the film's relaxation r = Ẋ − u̇3D = h0·τ_v/η implicitly: for a step short
    /// against the film's relaxation time t_v = η·C/h0 the implicit rule's error, backward
    /// Euler's (Δt/2)·|Δr| or BDF2's (2/9)·Δt³·|r''|; for a longer one the lag of the
    /// quasi-static film u3D ≈ t_v·r behind r's error, t_v·|Δr|/2 or t_v·Δt²·|r''|/3; the
    /// smaller of the two at the worst node (r'' from the last two steps' changes). 0 on a
    /// rigid substrate, where u3D ≡ 0.
    pub(super) fn step_end(&self, problem: &Problem, state: &mut SimState, dt_s: f64) -> f64 {
        let v = self;
        let (p, memory) = (&state.physical, &mut state.stepper);
        let elastic = problem.config.contact.substrate == Substrate::Elastic;
        let n = p.phi.len();
        let mut worst = 0.0_f64;
        if elastic {
            let k = v.alpha0 / dt_s;
            let second = match v.bdf2 {
                Some((_, h_prev)) if memory.viscous_rate_prev_m_per_s.len() == n => Some(h_prev),
                _ => None,
            };
            for i in 0..n {
                let (r0, r1) = (v.rate_before[i], k * (v.g[i] - p.u3d_m[i]));
                let e = match second {
                    None => 0.5 * (r1 - r0).abs() * dt_s.min(v.relaxation_s),
                    Some(h_prev) => {
                        let r_prev = memory.viscous_rate_prev_m_per_s[i];
                        let r2 =
                            2.0 * ((r1 - r0) / dt_s - (r0 - r_prev) / h_prev) / (dt_s + h_prev);
                        dt_s * dt_s * r2.abs() * (2.0 / 9.0 * dt_s).min(v.relaxation_s / 3.0)
                    }
                };
                worst = worst.max(e);
            }
        }
        memory.viscous_rate_prev_m_per_s.clone_from(&v.rate_before);
        worst
    }
}
