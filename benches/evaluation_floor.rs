//! The floor of one coupled evaluation at N nodes on this machine: what the accurate step's
//! evaluation cannot be cheaper than, shared by the criterion bench (`benches/roofline.rs`)
//! and `cargo xtask bench`'s roofline target.
//!
//! - the node pass: one fused pass over the nodes with one exponential per node (vectorised,
//!   `vexp::exp_expm1_all`), the film's exact frozen-strain step of u = 1/φ² from it, the
//!   stress, a relative error norm and the force sum: the least per-node work of an
//!   evaluation, without temporaries beyond the exponentials' two arrays;
//! - the two applies: the forward and back MDR transforms of fig2's default operators
//!   (product integration on the edge-graded grid, hierarchical form), which every coupled
//!   evaluation applies at least once each.

use faer::traits::pulp::{Arch, Simd, WithSimd};
use stickslip_core::grid::{Grading, Grid};
use stickslip_core::mdr::{MdrOperators, OperatorForm, Quadrature};
use stickslip_core::vexp;

/// Accumulators per reduction (N must be a multiple): one AVX-512 vector of f64.
const LANES: usize = 8;

/// fig2's film: τmax = a = 1e6 Pa, εmax = 1, γ = 10 1/(Pa·s); b = 2a²εmax³/τmax.
const A_PA: f64 = 1e6;
const B_PA: f64 = 2.0 * A_PA * A_PA / 1e6;
const TWO_GAMMA: f64 = 20.0;
/// The step, s.
const H_S: f64 = 2e-8;

/// The nodes' state: φ² and the strains at the step's ends, spread over solid, near-melting
/// and molten values so that no branch is always taken.
struct Nodes {
    phi_sq: Vec<f64>,
    eps0: Vec<f64>,
    eps1: Vec<f64>,
    weights_m2: Vec<f64>,
    exponent: Vec<f64>,
    e: Vec<f64>,
    em1: Vec<f64>,
}

impl Nodes {
    fn new(radii_m: &[f64]) -> Self {
        let n = radii_m.len();
        let s = |i: usize| i as f64 / n as f64;
        Self {
            phi_sq: (0..n).map(|i| 0.01 + 0.99 * (1.0 - s(i))).collect(),
            eps0: (0..n).map(|i| 1.8 * s(i)).collect(),
            eps1: (0..n).map(|i| 1.8 * s(i) + 1e-6).collect(),
            weights_m2: radii_m
                .iter()
                .map(|r| 2.0 * std::f64::consts::PI * r * 2e-8)
                .collect(),
            exponent: vec![0.0; n],
            e: vec![0.0; n],
            em1: vec![0.0; n],
        }
    }

    /// One fused pass: the exponentials, then the step, stress, error and force per node.
    /// Returns (force, N; largest relative change of φ²). Its loops run under the CPU's best
    /// instruction set (pulp's run-time dispatch), as the stepper's passes do: a floor
    /// compiled for a narrower one would not be the machine's.
    fn pass(&mut self, a_coeff_pa: f64) -> (f64, f64) {
        Arch::new().dispatch(FusedPass {
            nodes: self,
            a_coeff_pa,
        })
    }
}

/// [`Nodes::pass`]'s body, compiled once per instruction set.
struct FusedPass<'a> {
    nodes: &'a mut Nodes,
    a_coeff_pa: f64,
}

impl WithSimd for FusedPass<'_> {
    type Output = (f64, f64);

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) -> (f64, f64) {
        let nodes = self.nodes;
        let c0 = self.a_coeff_pa * B_PA / A_PA;
        for (x, (&e0, &e1)) in nodes
            .exponent
            .iter_mut()
            .zip(nodes.eps0.iter().zip(&nodes.eps1))
        {
            let eps = 0.5 * (e0 + e1);
            *x = -TWO_GAMMA * (A_PA * eps * eps - c0) * H_S;
        }
        vexp::exp_expm1_all(&nodes.exponent, &mut nodes.e, &mut nodes.em1);
        // Independent accumulators per reduction, so that the loop vectorises (a single
        // floating-point sum is sequential).
        let mut force = [0.0; LANES];
        let mut error = [0.0_f64; LANES];
        let chunks = nodes.phi_sq.len() / LANES;
        for c in 0..chunks {
            for l in 0..LANES {
                let i = c * LANES + l;
                let eps = 0.5 * (nodes.eps0[i] + nodes.eps1[i]);
                let rate = TWO_GAMMA * (A_PA * eps * eps - c0);
                let u0 = 1.0 / nodes.phi_sq[i];
                // u(h) = u0·e^(Lh) + (g/L)·(e^(Lh) − 1), g = 2γb; e^(Lh) = 1/e^(−Lh).
                let grow = 1.0 / nodes.e[i];
                let u1 = u0 * grow + TWO_GAMMA * B_PA / rate * (grow - 1.0);
                let phi_sq1 = 1.0 / u1;
                let tau = A_PA * phi_sq1 * nodes.eps1[i];
                force[l] += nodes.weights_m2[i] * tau;
                error[l] = error[l].max((phi_sq1 - nodes.phi_sq[i]).abs() / phi_sq1.max(1e-2));
            }
        }
        (force.iter().sum(), error.iter().fold(0.0, |m, &e| m.max(e)))
    }
}

/// The roofline's two parts on fig2's contact at `n` nodes.
pub struct Floor {
    nodes: Nodes,
    ops: MdrOperators,
    tau: Vec<f64>,
    q: Vec<f64>,
    u: Vec<f64>,
}

impl Floor {
    /// fig2's contact (a0 = 20 µm, the edge-graded grid of power 3) at `n` nodes, a multiple
    /// of 8.
    ///
    /// # Panics
    /// If `n` is not a positive multiple of 8.
    #[must_use]
    pub fn fig2(n: usize) -> Self {
        assert!(
            n > 0 && n.is_multiple_of(LANES),
            "n = {n}: a positive multiple of {LANES}"
        );
        let grid = Grid::graded(2e-5, n, Grading::Edge { power: 3.0 }).expect("valid grid");
        let ops = MdrOperators::with_form(grid, Quadrature::Product, OperatorForm::Fast);
        Self {
            nodes: Nodes::new(&grid.radii_m()),
            ops,
            tau: (0..n).map(|i| 1e6 * (1.0 - i as f64 / n as f64)).collect(),
            q: vec![0.0; n],
            u: vec![0.0; n],
        }
    }

    /// The fused node pass at A = `a_coeff_pa`: (force, N; largest relative change of φ²).
    pub fn node_pass(&mut self, a_coeff_pa: f64) -> (f64, f64) {
        self.nodes.pass(a_coeff_pa)
    }

    /// The forward and back transforms once each; returns u3D at the axis (to be used).
    pub fn two_applies(&mut self) -> f64 {
        self.ops.forward(&self.tau, &mut self.q);
        self.ops.back(&self.q, &mut self.u);
        self.u[0]
    }

    /// Both, as one evaluation runs them.
    pub fn evaluation(&mut self, a_coeff_pa: f64) -> (f64, f64) {
        let out = self.node_pass(a_coeff_pa);
        let axis = self.two_applies();
        (out.0 + axis, out.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_floor_computes_what_an_evaluation_computes() {
        // The node pass steps every node to a finite, positive φ² and sums a positive force;
        // the applies give a finite displacement: the floor does the work it stands for.
        let mut floor = Floor::fig2(200);
        let (force, change) = floor.node_pass(1.5e6);
        assert!(force.is_finite() && force > 0.0, "{force}");
        assert!(change.is_finite() && change > 0.0, "{change}");
        let axis = floor.two_applies();
        assert!(axis.is_finite() && axis > 0.0, "{axis}");
    }

    #[test]
    #[should_panic(expected = "multiple of 8")]
    fn a_node_count_off_the_lanes_is_refused() {
        let _ = Floor::fig2(201);
    }
}
