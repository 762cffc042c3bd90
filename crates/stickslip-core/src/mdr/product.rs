//! Product integration of Eq. 13, 15, 16: the kernel integrated exactly on each cell.
//!
//! Data are piecewise linear between nodes. The grid has no node at the contact edge
//! r = a0, so the last cell [r_{N−1}, a0] needs a rule; we hold the data **constant**
//! there (τ(r) = τ_{N−1}). Linear extrapolation from the last two nodes would be one
//! order better in that cell, but it gives the node N−2 a negative weight, and then a
//! non-negative stress can produce a negative line load near the edge; the constant
//! rule keeps every weight ≥ 0 (τ ≥ 0 ⇒ q ≥ 0 ⇒ u3D ≥ 0) and costs only O(h^{3/2})
//! at the last node, O(h²) elsewhere.
//!
//! - forward: on cell [r_k, r_{k+1}] with x ≤ r_k, the moments
//!   I0 = ∫ r/√(r² − x²) dr = [√(r² − x²)] and
//!   I1 = ∫ r²/√(r² − x²) dr = ½[r√(r² − x²) + x² ln(r + √(r² − x²))]
//!   give the hat-function weights 2(r_{k+1}I0 − I1)/h and 2(I1 − r_k I0)/h.
//! - back: on cell [x_k, x_{k+1}] with x_{k+1} ≤ r, J0 = ∫ dx/√(r² − x²) = [asin(x/r)] and
//!   J1 = ∫ x dx/√(r² − x²) = [−√(r² − x²)]; weights (2/π)(x_{k+1}J0 − J1)/h and
//!   (2/π)(J1 − x_k J0)/h. At r = 0 the transform's limit u3D(0) = u1D(0) is used.
//! - 3D force: 2π∫ r τ dr exactly for piecewise-linear τ (constant on the last cell).
//! - 1D force: q vanishes like √(a0 − x) at the edge for bounded τ, so q is written as
//!   q = √(a0² − x²)·g with g piecewise linear (constant on the last cell) and
//!   2∫√(a0² − x²)·g dx integrated exactly: second order for smooth τ.

use super::{Triangle, TriangularOperator};
use crate::grid::Grid;
use std::f64::consts::PI;

/// √(a² − b²) computed as √((a − b)(a + b)) to keep precision when a ≈ b.
#[inline]
fn sqrt_diff_sq(a: f64, b: f64) -> f64 {
    ((a - b) * (a + b)).max(0.0).sqrt()
}

/// Moments (I0, I1) = (∫_a^b r/√(r² − x²) dr, ∫_a^b r²/√(r² − x²) dr) for 0 ≤ x ≤ a < b.
fn forward_moments(a: f64, b: f64, x: f64) -> (f64, f64) {
    let sa = sqrt_diff_sq(a, x);
    let sb = sqrt_diff_sq(b, x);
    let i0 = (b - a) * (b + a) / (sa + sb);
    let log_term = if x == 0.0 {
        0.0
    } else {
        x * x * ((b + sb) / (a + sa)).ln()
    };
    let i1 = 0.5 * (b * sb - a * sa + log_term);
    (i0, i1)
}

/// Moments (J0, J1) = (∫_a^b dx/√(r² − x²), ∫_a^b x dx/√(r² − x²)) for 0 ≤ a < b ≤ r.
fn back_moments(a: f64, b: f64, r: f64) -> (f64, f64) {
    let sa = sqrt_diff_sq(r, a);
    let sb = sqrt_diff_sq(r, b);
    // asin(b/r) − asin(a/r) as one atan2: no cancellation near b = r.
    let j0 = (b * sa - a * sb).atan2(sa * sb + a * b);
    let j1 = (b - a) * (b + a) / (sa + sb);
    (j0, j1)
}

/// Forward transform q = W τ by product integration.
pub fn forward(grid: &Grid) -> TriangularOperator {
    let n = grid.nodes();
    let h = grid.spacing_m();
    let mut w = TriangularOperator::zeros(n, Triangle::Upper);
    for j in 0..n {
        let x = grid.node_radius_m(j);
        for k in j..n {
            let a = grid.node_radius_m(k);
            let b = grid.node_radius_m(k + 1);
            let (i0, i1) = forward_moments(a, b, x);
            if k + 1 < n {
                w.add(j, k, 2.0 * (b * i0 - i1) / h);
                w.add(j, k + 1, 2.0 * (i1 - a * i0) / h);
            } else {
                w.add(j, k, 2.0 * i0);
            }
        }
    }
    w
}

/// Back transform u3D = B u1D by product integration.
pub fn back(grid: &Grid) -> TriangularOperator {
    let n = grid.nodes();
    let h = grid.spacing_m();
    let mut b_op = TriangularOperator::zeros(n, Triangle::Lower);
    b_op.add(0, 0, 1.0);
    for i in 1..n {
        let r = grid.node_radius_m(i);
        for k in 0..i {
            let a = grid.node_radius_m(k);
            let b = grid.node_radius_m(k + 1);
            let (j0, j1) = back_moments(a, b, r);
            b_op.add(i, k, 2.0 / PI * (b * j0 - j1) / h);
            b_op.add(i, k + 1, 2.0 / PI * (j1 - a * j0) / h);
        }
    }
    b_op
}

/// Weights of F = 2π∫_0^{a0} τ r dr for piecewise-linear τ, constant on the last cell (m²).
pub fn force_3d_weights(grid: &Grid) -> Vec<f64> {
    let n = grid.nodes();
    let h = grid.spacing_m();
    let mut w = vec![0.0; n];
    for k in 0..n {
        let a = grid.node_radius_m(k);
        if k + 1 < n {
            w[k] += 2.0 * PI * h * (a / 2.0 + h / 6.0);
            w[k + 1] += 2.0 * PI * h * (a / 2.0 + h / 3.0);
        } else {
            let b = grid.radius_m();
            w[k] += PI * (b - a) * (b + a);
        }
    }
    w
}

/// Weights of F = 2∫_0^{a0} q dx with q = √(a0² − x²)·g, g piecewise linear (m).
pub fn force_1d_weights(grid: &Grid) -> Vec<f64> {
    let n = grid.nodes();
    let h = grid.spacing_m();
    let a0 = grid.radius_m();
    let edge = |x: f64| sqrt_diff_sq(a0, x);
    // Antiderivatives of √(a0² − x²) and x·√(a0² − x²).
    let p0 = |x: f64| 0.5 * (x * edge(x) + a0 * a0 * (x / a0).clamp(-1.0, 1.0).asin());
    let p1 = |x: f64| -edge(x).powi(3) / 3.0;
    let mut c = vec![0.0; n];
    for k in 0..n {
        let a = grid.node_radius_m(k);
        let b = grid.node_radius_m(k + 1);
        let m0 = p0(b) - p0(a);
        let m1 = p1(b) - p1(a);
        if k + 1 < n {
            c[k] += 2.0 * (b * m0 - m1) / h / edge(a);
            c[k + 1] += 2.0 * (m1 - a * m0) / h / edge(b);
        } else {
            c[k] += 2.0 * m0 / edge(a);
        }
    }
    c
}
