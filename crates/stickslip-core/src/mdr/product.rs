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

use super::{OperatorEntries, Triangle, TriangularOperator};
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

/// One entry (j, m) of [`forward`], computed on demand: bit-identical to the dense builder,
/// which adds cell m − 1's right weight, then cell m's left weight, to a zero.
pub fn forward_entry(grid: &Grid, j: usize, m: usize) -> f64 {
    let mut row = [0.0];
    ForwardEntries::new(*grid).row_into(j, &[m], &mut row);
    row[0]
}

/// One entry (i, m) of [`back`], computed on demand: bit-identical to the dense builder.
pub fn back_entry(grid: &Grid, i: usize, m: usize) -> f64 {
    let mut row = [0.0];
    BackEntries::new(*grid).row_into(i, &[m], &mut row);
    row[0]
}

/// The entries of [`forward`] on demand (N/m per Pa), for the hierarchical build.
#[derive(Debug, Clone, Copy)]
pub struct ForwardEntries {
    grid: Grid,
}

impl ForwardEntries {
    /// The forward operator of `grid`, stored nowhere.
    pub fn new(grid: Grid) -> Self {
        Self { grid }
    }
}

/// Cell moments cached along one row: (cell index, first moment, second moment).
type CellMoments = Option<(usize, f64, f64)>;

impl OperatorEntries for ForwardEntries {
    fn size(&self) -> usize {
        self.grid.nodes()
    }

    fn triangle(&self) -> Triangle {
        Triangle::Upper
    }

    fn entry(&self, i: usize, k: usize) -> f64 {
        forward_entry(&self.grid, i, k)
    }

    /// Row j: entry (j, m) sums cell m − 1's right weight and cell m's left weight, in
    /// the dense builder's order; consecutive columns share a cell's moments.
    fn row_into(&self, j: usize, cols: &[usize], out: &mut [f64]) {
        let grid = &self.grid;
        let n = grid.nodes();
        let h = grid.spacing_m();
        let x = grid.node_radius_m(j);
        let mut cached: CellMoments = None;
        let mut moments = |k: usize| -> (f64, f64) {
            match cached {
                Some((c, i0, i1)) if c == k => (i0, i1),
                _ => {
                    let (i0, i1) =
                        forward_moments(grid.node_radius_m(k), grid.node_radius_m(k + 1), x);
                    cached = Some((k, i0, i1));
                    (i0, i1)
                }
            }
        };
        for (o, &m) in out[..cols.len()].iter_mut().zip(cols) {
            let mut w = 0.0;
            if m < j || m >= n {
                *o = w;
                continue;
            }
            if m > j {
                let (i0, i1) = moments(m - 1);
                let a = grid.node_radius_m(m - 1);
                w += 2.0 * (i1 - a * i0) / h;
            }
            let (i0, i1) = moments(m);
            if m + 1 < n {
                let b = grid.node_radius_m(m + 1);
                w += 2.0 * (b * i0 - i1) / h;
            } else {
                w += 2.0 * i0;
            }
            *o = w;
        }
    }

    /// ‖W·1‖₂/√N with W·1 = 2√(a0² − x_j²) exactly (product integration reproduces
    /// uniform stress, see the module docs): a lower bound of ‖W‖₂ from O(N) square roots,
    /// within a few per cent of it (the leading singular vector is smooth).
    fn norm_lower_bound(&self) -> f64 {
        let a0 = self.grid.radius_m();
        let n = self.grid.nodes();
        let sum: f64 = (0..n)
            .map(|j| 4.0 * sqrt_diff_sq(a0, self.grid.node_radius_m(j)).powi(2))
            .sum();
        (sum / n as f64).sqrt()
    }
}

/// The entries of [`back`] on demand (m per m), for the hierarchical build.
#[derive(Debug, Clone, Copy)]
pub struct BackEntries {
    grid: Grid,
}

impl BackEntries {
    /// The back operator of `grid`, stored nowhere.
    pub fn new(grid: Grid) -> Self {
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
        back_entry(&self.grid, i, k)
    }

    /// Row i: entry (i, m) sums cell m − 1's right weight and cell m's left weight, in
    /// the dense builder's order; consecutive columns share a cell's moments.
    fn row_into(&self, i: usize, cols: &[usize], out: &mut [f64]) {
        let grid = &self.grid;
        let h = grid.spacing_m();
        let r = grid.node_radius_m(i);
        let mut cached: CellMoments = None;
        let mut moments = |k: usize| -> (f64, f64) {
            match cached {
                Some((c, j0, j1)) if c == k => (j0, j1),
                _ => {
                    let (j0, j1) =
                        back_moments(grid.node_radius_m(k), grid.node_radius_m(k + 1), r);
                    cached = Some((k, j0, j1));
                    (j0, j1)
                }
            }
        };
        for (o, &m) in out[..cols.len()].iter_mut().zip(cols) {
            let mut w = 0.0;
            if m > i {
                *o = w;
                continue;
            }
            if i == 0 {
                // The transform's limit u3D(0) = u1D(0).
                w += 1.0;
                *o = w;
                continue;
            }
            if m >= 1 {
                let (j0, j1) = moments(m - 1);
                let a = grid.node_radius_m(m - 1);
                w += 2.0 / PI * (j1 - a * j0) / h;
            }
            if m < i {
                let (j0, j1) = moments(m);
                let b = grid.node_radius_m(m + 1);
                w += 2.0 / PI * (b * j0 - j1) / h;
            }
            *o = w;
        }
    }

    /// ‖B·1‖₂/√N = 1: product integration maps a constant u1D to the same constant
    /// (the flat punch, exact to rounding), so ‖B‖₂ ≥ 1.
    fn norm_lower_bound(&self) -> f64 {
        1.0
    }
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
