//! The film's Newtonian viscous stress η·(Ẋ − u̇3D)/h0 (`lubricant.viscosity` > 0,
//! docs/model.md#viscosity), in the accurate scheme: the rates by backward Euler over the step
//! (Ẋ ≈ ΔX/Δt, u̇3D ≈ (u3D − u3D_old)/Δt), which turns the coupling into today's solve with
//! φ² replaced by w = φ² + η/(a·Δt) and u0 by s = (φ²·u0 + (η/(a·Δt))·(ΔX + u3D_old))/w,
//! stable for any step; the stamp's drag c_v·Ẋ folded into the spring's exact flow, the kicks
//! carrying the rest; the coupling step's local error for the adaptive control.
//!
//! With η = 0 nothing here is built or called, and every step is the paper's film's
//! arithmetic unchanged.

use super::Simulation;
use crate::config::Substrate;

/// What the viscous stress needs besides the state.
#[derive(Debug)]
pub(super) struct Viscous {
    /// η, Pa·s.
    pub eta_pa_s: f64,
    /// c_v = η·A/h0, N·s/m, with A = πa0² as the force quadrature integrates a uniform stress
    /// (so that on a rigid substrate the kicks carry no part of the drag at all).
    pub drag_n_s_per_m: f64,
    /// Spectral radius of κ·C (the compliance at unit film stiffness; radial elastic contacts):
    /// κ·C·diag(w) has its spectrum within [0, this·max w], the coupling solve's bound.
    pub unit_contraction: f64,
    /// w = φ² + η/(a·Δt) per node.
    w: Vec<f64>,
    /// s per node, m: the displacement the film's total stiffness pulls u3D towards.
    s: Vec<f64>,
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
            relaxation_s,
            unit_contraction,
            w: vec![0.0; n],
            s: vec![0.0; n],
            rate_before: vec![0.0; n],
        }
    }
}

impl Viscous {
    /// The coupling's weights w and targets s for a step of `dt_s` in which the stamp advanced
    /// `dx_m`, from φ, u0 and the substrate's displacement at the step's start `u3d_old`, with
    /// the film's coefficient `a_pa`; returns the spectral bound of κ·C·diag(w).
    pub fn prepare(
        &mut self,
        a_pa: f64,
        dt_s: f64,
        dx_m: f64,
        (phi, u0, u3d_old): (&[f64], &[f64], &[f64]),
    ) -> f64 {
        let beta = self.eta_pa_s / (a_pa * dt_s);
        let mut w_max = 0.0_f64;
        for i in 0..phi.len() {
            let y = phi[i] * phi[i];
            let w = y + beta;
            self.w[i] = w;
            self.s[i] = (y * u0[i] + beta * (dx_m + u3d_old[i])) / w;
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

impl Simulation {
    /// The force the drive's kicks carry: F itself without viscosity; with it F − c_v·ΔX/Δt
    /// of the last step, the part of the film's force the spring's flow does not take
    /// (F_el − (η/h0)·∫u̇3D dA).
    pub(super) fn kick_force_n(&self) -> f64 {
        match &self.viscous {
            None => self.state.physical.force_n,
            Some(v) => {
                self.state.physical.force_n - v.drag_n_s_per_m * self.state.stepper.mean_v_m_per_s
            }
        }
    }

    /// Before the step's film update: the film's shear rate r = Ẋ − u̇3D per node at the
    /// step's start, from the viscous stress of the state, τ − a·φ²·ε = η·r/h0 (valid after
    /// any step, also one whose history the adaptive control cleared).
    pub(super) fn viscous_step_start(&mut self) {
        let Some(v) = self.viscous.as_mut() else {
            return;
        };
        let s = &self.state.physical;
        let a = self.config.lubricant.a_pa;
        let h0 = self.config.contact.film_thickness_m;
        for i in 0..s.phi.len() {
            let tau_v = s.tau_pa[i] - a * s.phi[i] * s.phi[i] * s.eps[i];
            v.rate_before[i] = h0 * tau_v / v.eta_pa_s;
        }
    }

    /// After ε and τ of the step's end (Eqs. 11–12): τ gains η·(ΔX − (u3D − u3D_old))/(Δt·h0),
    /// and the stamp's mean velocity ΔX/Δt is kept for the kicks.
    pub(super) fn add_viscous_stress(&mut self, dt_s: f64, dx_m: f64) {
        let Some(v) = self.viscous.as_ref() else {
            return;
        };
        let h0 = self.config.contact.film_thickness_m;
        let (p, memory) = (&mut self.state.physical, &mut self.state.stepper);
        let k = v.eta_pa_s / (dt_s * h0);
        let elastic = self.config.contact.substrate == Substrate::Elastic;
        for i in 0..p.phi.len() {
            let du = if elastic {
                p.u3d_m[i] - memory.u3d_prev_m[i]
            } else {
                0.0
            };
            p.tau_pa[i] += k * (dx_m - du);
        }
        memory.mean_v_m_per_s = dx_m / dt_s;
    }

    /// The local error in u3D of the step's viscous coupling, m, for the strain's part of the
    /// step error. Over the step the stamp's advance enters exactly (as ΔX) and the film's
    /// relaxation r = Ẋ − u̇3D = h0·τ_v/η implicitly, at the step's end: backward Euler's
    /// error (Δt/2)·|Δr| for a step short against the film's relaxation time t_v = η·C/h0, and
    /// the lag t_v·|Δr|/2 of the quasi-static film for a longer one (u3D ≈ t_v·r, r taken
    /// at the end instead of over the step), so (Δt/2)·|Δr|·min(1, t_v/Δt) at the worst
    /// node. 0 on a rigid substrate, where u3D ≡ 0.
    pub(super) fn viscous_error_m(&self, dt_s: f64) -> f64 {
        let Some(v) = self.viscous.as_ref() else {
            return 0.0;
        };
        if self.config.contact.substrate == Substrate::Rigid {
            return 0.0;
        }
        let (p, memory) = (&self.state.physical, &self.state.stepper);
        let mean_v = memory.mean_v_m_per_s;
        let mut worst = 0.0_f64;
        for i in 0..p.phi.len() {
            let rate = mean_v - (p.u3d_m[i] - memory.u3d_prev_m[i]) / dt_s;
            worst = worst.max((rate - v.rate_before[i]).abs());
        }
        0.5 * worst * dt_s.min(v.relaxation_s)
    }
}
