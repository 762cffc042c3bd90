//! The accurate step's passes over every node after the film's step, before the few nodes
//! that melt, regrow or recover are taken one by one: the error estimate's pieces each node
//! carries unless it melts within the step, the Landau dissipation along its frozen-strain
//! path ([`EndPass`]), and the step's end of every node that stays on its side of the melt
//! threshold ([`StayPass`]). Branch-free (selects only) and compiled once per instruction set
//! (pulp's run-time dispatch), so that they vectorise; `Accurate::node_ends` then keeps these
//! for the nodes that stay and replaces them for the others. The arithmetic per node is that
//! of a node-by-node loop, bit for bit. Beside them, the film passes' helpers: θ's weight, the
//! stiff-step test and the error norm's least φ² scale.
//!
//! Divisions are few: a vectorised division costs many multiplications, and before they were
//! hoisted into reciprocals (1/h0 once per pass, one 1/z per node for both weights, constant
//! reciprocals for series coefficients, one division where a select of two quotients took
//! two) they were most of a node's arithmetic: the same step of fig2 on a rigid substrate at
//! N = 2000 went from 57.3 µs to 42.6 µs in `cargo xtask bench`'s roofline row (whose report
//! gives today's figure).

use super::error_estimate;
use super::problem::Problem;
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
    /// 1 for a node that [`NodeScratch::stay_ends`] left to the node-by-node loop, else 0.
    pub special: Vec<f64>,
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
            special: vec![0.0; n],
        }
    }

    /// [`StayPass`] over every node: the step's end of each node that stays on its side of
    /// the melt threshold and does not cross the recovery level (φ, u0 and the held advance
    /// written); the others are flagged in `special` and left as they were. Returns how many
    /// were flagged, and the staying nodes' Landau sink Σ w·h0·(f's drop), J (`weights`: the
    /// energy weights, m²; `h0_m`: the film's thickness).
    pub fn stay_ends(
        &mut self,
        (phi, u0): (&mut [f64], &mut [f64]),
        (threshold, recovery_phi, dx_m): (f64, f64, f64),
        (weights, h0_m): (&[f64], f64),
    ) -> (usize, f64) {
        Arch::new().dispatch(StayPass {
            phi,
            u0,
            phi1: &self.phi1,
            held: &mut self.book_slide,
            special: &mut self.special,
            levels: (threshold, recovery_phi),
            dx_m,
        });
        let landau_j = crate::sums::sum_cols(
            [weights, &self.landau_pa, &self.special],
            |[w, landau, special]| {
                if special == 0.0 {
                    w * h0_m * landau
                } else {
                    0.0
                }
            },
        );
        (self.special.iter().filter(|&&s| s != 0.0).count(), landau_j)
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
        let inv_h0 = 1.0 / c.h0_m;
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
            let eps1 = eps0 + (du0 - du3d[i]) * inv_h0;
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

/// The step's end of the nodes that stay on their side of the melt threshold `levels.0` and
/// do not rise through the recovery level `levels.1`: a solid node's φ1 with u0 advanced by
/// the stamp's dx, a melted node's φ1 with u0 held at 0 (the advance held), φ kept above
/// the smallest representable value. Branch-free, so that it vectorises; the others (a node
/// that melts, regrows through the threshold or crosses the recovery level) are flagged for
/// `Accurate::node_ends`'s loop, which alone locates crossings.
struct StayPass<'a> {
    phi: &'a mut [f64],
    u0: &'a mut [f64],
    phi1: &'a [f64],
    held: &'a mut [f64],
    special: &'a mut [f64],
    levels: (f64, f64),
    dx_m: f64,
}

impl WithSimd for StayPass<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        let n = self.phi.len();
        let (phi, u0, phi1) = (&mut self.phi[..n], &mut self.u0[..n], &self.phi1[..n]);
        let (held, special) = (&mut self.held[..n], &mut self.special[..n]);
        let (thr, recovery) = self.levels;
        for i in 0..n {
            let (phi0, phi_end) = (phi[i], phi1[i]);
            let solid = phi0 >= thr;
            let stays = (solid == (phi_end >= thr)) & !((phi0 < recovery) & (phi_end >= recovery));
            special[i] = if stays { 0.0 } else { 1.0 };
            // From φ > 0 Eq. 8 never reaches 0, but a long decay underflows φ² to 0, where
            // φ = 0 is a fixed point and the node could never re-solidify.
            let floored = if phi0 > 0.0 {
                phi_end.max(super::PHI_REPRESENTABLE_MIN)
            } else {
                phi_end
            };
            phi[i] = if stays { floored } else { phi0 };
            u0[i] = match (stays, solid) {
                (true, true) => u0[i] + self.dx_m,
                (true, false) => 0.0,
                (false, _) => u0[i],
            };
            held[i] = if stays && !solid { self.dx_m } else { 0.0 };
        }
    }
}

/// The error norm's least y = φ² scale at the step's end (φ_s: the solid film's φ at zero
/// strain then): φ itself, but not below the melt threshold nor below
/// `numerics.phi_error_floor`·φ_s (squared: the norm divides y = φ²'s error); in a step that
/// starts while a melting event is `open`, not below `numerics.event_phi_error_floor`·φ_s
/// either (the tracker holds the step's start).
pub(super) fn y_scale_min(problem: &Problem, open: bool, solid_phi_end: f64) -> f64 {
    let numerics = &problem.config.numerics;
    let floor = if open {
        numerics.phi_error_floor.max(numerics.event_phi_error_floor)
    } else {
        numerics.phi_error_floor
    };
    let phi_scale = problem.config.melt_threshold.max(floor * solid_phi_end);
    phi_scale * phi_scale
}

/// Above this λΔt, e^(−λΔt) < 3.2e-17, below 2^(−54) (half an ulp of 1) by a margin larger
/// than the exponential's rounding: 1 − e rounds to 1 exactly.
pub(super) const THETA_STIFF_Z: f64 = 38.0;

/// Whether every element is below `bound` (false for a NaN), as one vectorisable fold.
#[inline(always)]
pub(super) fn all_below(values: &[f64], bound: f64) -> bool {
    values.iter().fold(true, |all, &v| all & (v < bound))
}

/// Weight θ(z) = 1/(1 − e^(−z)) − 1/z with z = λ·Δt: y' = −λ(y − g(t)) with g linear over
/// the step is solved exactly by freezing g at g(t0) + θ·(g(t1) − g(t0)).
/// θ → ½ + z/12 for z → 0, → 1 for z → +∞, → 0 for z → −∞.
pub(super) fn linear_forcing_weight(z: f64) -> f64 {
    linear_forcing_weight_from(z, crate::vexp::exp(-z))
}

/// [`linear_forcing_weight`] given e^(−z).
#[inline(always)]
pub(super) fn linear_forcing_weight_from(z: f64, e: f64) -> f64 {
    // Both forms, then a select: no branch, so loops over nodes vectorise.
    let series = 0.5 + z * (1.0 / 12.0);
    let closed = 1.0 / (1.0 - e) - 1.0 / z;
    if z.abs() < 1e-4 { series } else { closed }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_nodes_that_stay_on_their_side_are_ended_here() {
        // Threshold 0.1, recovery level 0.5, the stamp advances 1e-9 m. Nodes: solid and
        // staying; melted and staying; melting; regrowing through the threshold; solid but
        // rising through the recovery level; melted and decaying to 0 from φ > 0.
        let (thr, recovery, dx) = (0.1, 0.5, 1e-9);
        let phi0 = [0.9, 0.05, 0.3, 0.05, 0.4, 1e-3];
        let phi1 = [0.8, 0.04, 0.08, 0.2, 0.6, 0.0];
        let mut scratch = NodeScratch::new(phi0.len());
        scratch.phi1.copy_from_slice(&phi1);
        scratch
            .landau_pa
            .copy_from_slice(&[1.0, 2.0, 4.0, 8.0, 16.0, 32.0]);
        let (mut phi, mut u0) = (phi0.to_vec(), vec![5e-9; phi0.len()]);
        let (special, landau_j) =
            scratch.stay_ends((&mut phi, &mut u0), (thr, recovery, dx), (&[1.0; 6], 0.5));
        assert_eq!(scratch.special, [0.0, 0.0, 1.0, 1.0, 1.0, 0.0]);
        assert_eq!(special, 3);
        // The staying nodes' sink alone: 0.5·(1 + 2 + 32).
        assert_eq!(landau_j, 17.5);
        // Ended: φ1 (above the smallest representable φ for a node that had some), u0
        // advanced on a solid node, held at 0 (the advance held) on a melted one.
        assert_eq!(phi[..2], [0.8, 0.04]);
        assert_eq!(phi[5], crate::sim::PHI_REPRESENTABLE_MIN);
        assert_eq!([u0[0], u0[1], u0[5]], [5e-9 + dx, 0.0, 0.0]);
        assert_eq!([scratch.book_slide[0], scratch.book_slide[1]], [0.0, dx]);
        // Flagged: untouched, for the node-by-node loop.
        assert_eq!(phi[2..5], phi0[2..5]);
        assert_eq!(u0[2..5], [5e-9; 3]);
    }
}
