//! The accurate step's pass over every node after the film's step, before the nodes are taken
//! one by one: the error estimate's pieces each node carries unless it melts within the step,
//! and the Landau dissipation along its frozen-strain path. Branch-free (selects only) and
//! compiled once per instruction set (pulp's run-time dispatch), so that it vectorises;
//! `Accurate::node_ends` then keeps these for the nodes that do not melt and replaces them for
//! the few that do. The arithmetic per node is that of a node-by-node loop, bit for bit.

use super::error_estimate;
use crate::landau::LandauParams;
use faer::traits::pulp::{Arch, Simd, WithSimd};

/// Per node, what the accurate step's passes hand each other. The exponentials of all nodes
/// are taken in vectorised loops ([`crate::vexp::exp_expm1_all`]): their arguments, e^x and
/// e^x − 1; the film's φ at the step's end; the predicted u3D change over the step, m; the
/// frozen strain's place θ on the step's strain ramp. For the error estimate after the
/// coupling solve (see [`error_estimate`]): the start's defect term h·w0·D(0) (or a melting
/// node's whole estimate), the end's gain h·w1·(−2γ·a·y1), the effective strain, and
/// 1/(2·max(y1, thr²)).
pub(super) struct NodeScratch {
    pub arg: Vec<f64>,
    pub exp: Vec<f64>,
    pub expm1: Vec<f64>,
    pub phi1: Vec<f64>,
    pub du3d: Vec<f64>,
    pub theta: Vec<f64>,
    pub est_base: Vec<f64>,
    pub est_gain: Vec<f64>,
    pub est_eps_eff: Vec<f64>,
    pub est_norm: Vec<f64>,
    /// The energy books' per-node parts: the elastic stress a·φ²·ε at the step's start, Pa;
    /// the stamp's advance over which the node's u0 was held, m; the strain of the node's
    /// last exact path; φ before the noise.
    pub book_tau0: Vec<f64>,
    pub book_slide: Vec<f64>,
    pub book_eps_path: Vec<f64>,
    pub book_phi: Vec<f64>,
    /// f's drop along each node's path at its effective strain, J/m³ ([`EndPass`]).
    pub landau_pa: Vec<f64>,
}

impl NodeScratch {
    /// Zeroed scratch for `n` nodes.
    pub fn new(n: usize) -> Self {
        Self {
            arg: vec![0.0; n],
            exp: vec![0.0; n],
            expm1: vec![0.0; n],
            phi1: vec![0.0; n],
            du3d: vec![0.0; n],
            theta: vec![0.0; n],
            est_base: vec![0.0; n],
            est_gain: vec![0.0; n],
            est_eps_eff: vec![0.0; n],
            est_norm: vec![0.0; n],
            book_tau0: vec![0.0; n],
            book_slide: vec![0.0; n],
            book_eps_path: vec![0.0; n],
            book_phi: vec![0.0; n],
            landau_pa: vec![0.0; n],
        }
    }

    /// [`EndPass`] over every node from the state's φ and ε at the step's start.
    pub fn estimate_ends(&mut self, (phi, eps): (&[f64], &[f64]), constants: EndConstants) {
        Arch::new().dispatch(EndPass {
            phi,
            eps,
            arg: &self.arg,
            exp: &self.exp,
            expm1: &self.expm1,
            du3d: &self.du3d,
            phi1: &self.phi1,
            theta: &self.theta,
            est_eps_eff: &mut self.est_eps_eff,
            est_base: &mut self.est_base,
            est_gain: &mut self.est_gain,
            est_norm: &mut self.est_norm,
            eps_path: &mut self.book_eps_path,
            landau_pa: &mut self.landau_pa,
            constants,
        });
    }
}

/// The step's constants the pass reads.
#[derive(Debug, Clone, Copy)]
pub(super) struct EndConstants {
    pub params: LandauParams,
    /// The melt threshold φ below which a node is melted.
    pub threshold: f64,
    /// h0, m.
    pub h0_m: f64,
    /// The stamp's advance over the step, m.
    pub dx_m: f64,
    /// The step, s.
    pub dt_s: f64,
    /// A at the step's middle, Pa.
    pub a_mid_pa: f64,
    /// The error norm's least y = φ² scale.
    pub y_scale_min: f64,
    /// Whether the film's step was corrected along the strain ramp (`Film::RAMP`).
    pub ramp: bool,
}

/// The nodes' values the pass reads (at the step's start: φ, ε; the film step's scratch: the
/// clamped propagator exponent's negative, its e^(−z) and e^(−z) − 1, the predicted u3D
/// change, φ1, θ) and writes (the estimate's pieces; the path's strain; the dissipation).
struct EndPass<'a> {
    phi: &'a [f64],
    eps: &'a [f64],
    arg: &'a [f64],
    exp: &'a [f64],
    expm1: &'a [f64],
    du3d: &'a [f64],
    phi1: &'a [f64],
    theta: &'a [f64],
    /// In: the step's effective strain; out: the strain the estimate compares with the solved
    /// end strain (the ramp's end ε1 for the ramp step, else the effective strain itself).
    est_eps_eff: &'a mut [f64],
    est_base: &'a mut [f64],
    est_gain: &'a mut [f64],
    est_norm: &'a mut [f64],
    /// Out: the effective strain (the strain of the node's exact path when it does not melt).
    eps_path: &'a mut [f64],
    /// Out: f's drop along the path at the effective strain, J/m³.
    landau_pa: &'a mut [f64],
    constants: EndConstants,
}

impl WithSimd for EndPass<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        let c = self.constants;
        let p = c.params;
        let (a, two_gamma) = (p.a_pa, 2.0 * p.gamma_per_pa_s);
        let n = self.phi.len();
        let (phi, eps, arg) = (&self.phi[..n], &self.eps[..n], &self.arg[..n]);
        let (exp, expm1, du3d) = (&self.exp[..n], &self.expm1[..n], &self.du3d[..n]);
        let (phi1s, theta) = (&self.phi1[..n], &self.theta[..n]);
        let est_eps_eff = &mut self.est_eps_eff[..n];
        let (est_base, est_gain) = (&mut self.est_base[..n], &mut self.est_gain[..n]);
        let est_norm = &mut self.est_norm[..n];
        let (eps_path, landau_pa) = (&mut self.eps_path[..n], &mut self.landau_pa[..n]);
        for i in 0..n {
            let phi0 = phi[i];
            // u0 is held at 0 while melted, so only solid nodes see the stamp's advance.
            let du0 = if phi0 >= c.threshold { c.dx_m } else { 0.0 };
            let eps0 = eps[i];
            let eps1 = eps0 + (du0 - du3d[i]) / c.h0_m;
            let y0 = phi0 * phi0;
            let eps_eff = est_eps_eff[i];
            let phi1 = phi1s[i];
            // The error estimate's pieces (see `error_estimate`): the defect at the start
            // now, at the end once the coupling solve has given the end strain.
            let y1 = phi1 * phi1;
            let (w0, w1) = error_estimate::defect_weights_select(-arg[i], (exp[i], expm1[i]));
            let frozen_base =
                c.dt_s * w0 * (-two_gamma * a * y0 * (eps_eff * eps_eff - eps0 * eps0));
            est_gain[i] = c.dt_s * w1 * (-two_gamma * a * y1);
            // The ramp step's error: its second-order remainder, and the end strain's
            // prediction error (the defect at the end against ε1, the ramp's end).
            est_base[i] = if c.ramp { y1 * theta[i] } else { frozen_base };
            est_eps_eff[i] = if c.ramp { eps1 } else { eps_eff };
            est_norm[i] = 0.5 / y1.max(c.y_scale_min);
            eps_path[i] = eps_eff;
            // The drop of f along the exact path at the frozen strain: the Landau dissipation.
            landau_pa[i] = p.free_energy_pa(phi0, eps_eff, c.a_mid_pa)
                - p.free_energy_pa(phi1, eps_eff, c.a_mid_pa);
        }
    }
}
