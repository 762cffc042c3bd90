//! The paper's plain sums for Eq. 13, 15, 16: weight h per node, singular term skipped.
//!
//! This is the baseline every other scheme is compared against; it is kept exactly as
//! the paper describes it, weaknesses included:
//! - forward  q_j = 2h Σ_{k>j} r_k τ_k / √(r_k² − x_j²)   (the k = j term is singular, skipped);
//! - back     u_i = (2/π) h Σ_{k<i} u_k / √(r_i² − x_k²)  (k = i skipped, so u3D(0) = 0);
//! - forces   F = 2π h Σ τ_k r_k  and  F = 2h Σ q_k  (no node at r = a0).
//!
//! Skipping the singular term drops ∫_{x}^{x+h} r/√(r² − x²) dr ≈ √(2xh): the sums
//! converge at order ½ in the interior.

use super::{OperatorEntries, Triangle, TriangularOperator};
use crate::grid::Grid;
use std::f64::consts::PI;

/// The paper's sums weigh every node by the uniform spacing: on another grid they would be
/// a different (wrong) quadrature, so the configuration refuses that pairing before here.
#[track_caller]
fn assert_uniform(grid: &Grid) {
    assert!(
        grid.grading().is_uniform(),
        "the literal sums are defined on the uniform grid only"
    );
}

/// Forward transform q = W τ with the paper's sum.
pub fn forward(grid: &Grid) -> TriangularOperator {
    assert_uniform(grid);
    let n = grid.nodes();
    let h = grid.spacing_m();
    let mut w = TriangularOperator::zeros(n, Triangle::Upper);
    for j in 0..n {
        let x = grid.node_radius_m(j);
        for k in j + 1..n {
            let r = grid.node_radius_m(k);
            w.add(j, k, 2.0 * h * r / ((r - x) * (r + x)).sqrt());
        }
    }
    w
}

/// Back transform u3D = B u1D with the paper's sum.
pub fn back(grid: &Grid) -> TriangularOperator {
    assert_uniform(grid);
    let n = grid.nodes();
    let h = grid.spacing_m();
    let mut b = TriangularOperator::zeros(n, Triangle::Lower);
    for i in 0..n {
        let r = grid.node_radius_m(i);
        for k in 0..i {
            let x = grid.node_radius_m(k);
            b.add(i, k, 2.0 / PI * h / ((r - x) * (r + x)).sqrt());
        }
    }
    b
}

/// The entries of [`forward`] on demand (N/m per Pa), bit-identical to the dense builder.
#[derive(Debug, Clone, Copy)]
pub struct ForwardEntries {
    grid: Grid,
}

impl ForwardEntries {
    /// The forward operator of `grid`, stored nowhere.
    pub fn new(grid: Grid) -> Self {
        assert_uniform(&grid);
        Self { grid }
    }
}

impl OperatorEntries for ForwardEntries {
    fn size(&self) -> usize {
        self.grid.nodes()
    }

    fn triangle(&self) -> Triangle {
        Triangle::Upper
    }

    fn entry(&self, j: usize, k: usize) -> f64 {
        let mut w = 0.0;
        if k > j && k < self.grid.nodes() {
            let h = self.grid.spacing_m();
            let x = self.grid.node_radius_m(j);
            let r = self.grid.node_radius_m(k);
            w += 2.0 * h * r / ((r - x) * (r + x)).sqrt();
        }
        w
    }
}

/// The entries of [`back`] on demand (m per m), bit-identical to the dense builder.
#[derive(Debug, Clone, Copy)]
pub struct BackEntries {
    grid: Grid,
}

impl BackEntries {
    /// The back operator of `grid`, stored nowhere.
    pub fn new(grid: Grid) -> Self {
        assert_uniform(&grid);
        Self { grid }
    }
}

impl OperatorEntries for BackEntries {
    fn size(&self) -> usize {
        self.grid.nodes()
    }

    fn triangle(&self) -> Triangle {
        Triangle::Lower
    }

    fn entry(&self, i: usize, k: usize) -> f64 {
        let mut w = 0.0;
        if k < i && i < self.grid.nodes() {
            let h = self.grid.spacing_m();
            let r = self.grid.node_radius_m(i);
            let x = self.grid.node_radius_m(k);
            w += 2.0 / PI * h / ((r - x) * (r + x)).sqrt();
        }
        w
    }
}

/// F = 2π h Σ τ_k r_k: weights 2π h r_k (m²).
pub fn force_3d_weights(grid: &Grid) -> Vec<f64> {
    assert_uniform(grid);
    let h = grid.spacing_m();
    (0..grid.nodes())
        .map(|k| 2.0 * PI * h * grid.node_radius_m(k))
        .collect()
}

/// F = 2h Σ q_k: weights 2h (m).
pub fn force_1d_weights(grid: &Grid) -> Vec<f64> {
    assert_uniform(grid);
    vec![2.0 * grid.spacing_m(); grid.nodes()]
}
