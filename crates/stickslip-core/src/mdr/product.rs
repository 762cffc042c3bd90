//! Product integration of Eq. 13, 15, 16: the kernel integrated exactly on each cell.
//!
//! Data are piecewise linear between nodes, on cells of any width (the uniform grid's or
//! the edge-graded one's, [`crate::grid::Grading`]; h below is the cell's own width). The
//! grid has no node at the contact edge
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

/// Gauss–Legendre rules on [−1, 1] as (node t, weight·(1 − t), weight·(1 + t)): the two
/// hat functions of a cell are (1 ∓ t)/2 in the rule's variable.
macro_rules! gauss_rule {
    ($(($t:expr, $w:expr)),* $(,)?) => {
        [$(($t, $w * (1.0 - $t), $w * (1.0 + $t))),*]
    };
}
const GAUSS_2: [(f64, f64, f64); 2] =
    gauss_rule![(-0.5773502691896258, 1.0), (0.5773502691896258, 1.0),];
const GAUSS_3: [(f64, f64, f64); 3] = gauss_rule![
    (-0.7745966692414834, 0.5555555555555556),
    (0.0, 0.8888888888888888),
    (0.7745966692414834, 0.5555555555555556),
];
const GAUSS_4: [(f64, f64, f64); 4] = gauss_rule![
    (-0.8611363115940526, 0.34785484513745385),
    (-0.33998104358485626, 0.6521451548625461),
    (0.33998104358485626, 0.6521451548625461),
    (0.8611363115940526, 0.34785484513745385),
];
const GAUSS_5: [(f64, f64, f64); 5] = gauss_rule![
    (-0.906179845938664, 0.23692688505618908),
    (-0.5384693101056831, 0.47862867049936647),
    (0.0, 0.5688888888888889),
    (0.5384693101056831, 0.47862867049936647),
    (0.906179845938664, 0.23692688505618908),
];
const GAUSS_6: [(f64, f64, f64); 6] = gauss_rule![
    (-0.932469514203152, 0.17132449237917036),
    (-0.6612093864662645, 0.3607615730481386),
    (-0.2386191860831969, 0.46791393457269104),
    (0.2386191860831969, 0.46791393457269104),
    (0.6612093864662645, 0.3607615730481386),
    (0.932469514203152, 0.17132449237917036),
];
const GAUSS_8: [(f64, f64, f64); 8] = gauss_rule![
    (-0.9602898564975363, 0.10122853629037626),
    (-0.7966664774136267, 0.22238103445337448),
    (-0.525532409916329, 0.31370664587788727),
    (-0.1834346424956498, 0.362683783378362),
    (0.1834346424956498, 0.362683783378362),
    (0.525532409916329, 0.31370664587788727),
    (0.7966664774136267, 0.22238103445337448),
    (0.9602898564975363, 0.10122853629037626),
];

/// Applies the shortest Gauss rule that integrates the cell integrands below to about
/// 1e-15 relative when their singular point lies `distance` from an interval of
/// half-length `half`; `None` when it is too close for an 8-point rule. The integrands
/// carry a quadratic factor, so the error falls like (half/distance)^(2P−2), not like the
/// Bernstein-ellipse rate of an analytic factor alone: the thresholds are about twice the
/// largest distance at which a sweep of both integrands (forward and back, rows 0–30000,
/// cells next to the singular point up to 30000 away, against 30-digit adaptive
/// quadrature) still showed an error above 1e-15: 16600, 760, 77, 23, 12 and 3
/// half-lengths for 2, 3, 4, 5, 6 and 8 points.
macro_rules! with_gauss_rule {
    ($distance:expr, $half:expr, $rule:ident => $body:expr) => {{
        let (d, half) = ($distance, $half);
        if d >= 40000.0 * half {
            let $rule = &GAUSS_2;
            Some($body)
        } else if d >= 1600.0 * half {
            let $rule = &GAUSS_3;
            Some($body)
        } else if d >= 160.0 * half {
            let $rule = &GAUSS_4;
            Some($body)
        } else if d >= 48.0 * half {
            let $rule = &GAUSS_5;
            Some($body)
        } else if d >= 24.0 * half {
            let $rule = &GAUSS_6;
            Some($body)
        } else if d >= 6.0 * half {
            let $rule = &GAUSS_8;
            Some($body)
        } else {
            None
        }
    }};
}

/// Hat weights (left node a, right node b) of the forward transform on the cell [a, b]
/// at x ≤ a, i.e. 2(b·I0 − I1)/h and 2(I1 − a·I0)/h, without the closed form's
/// cancellation (its relative rounding grows like (a/h)², about 1e-8 at a/h = 8000).
///
/// With s = √(r² − x²) (r dr/√(r² − x²) = ds) the weights are (2/h)∫(b − r) ds and
/// (2/h)∫(r − a) ds over [s_a, s_b], and b − r = (s_b − s)(s_b + s)/(b + r),
/// r − a = (s − s_a)(s + s_a)/(r + a) have no cancellation; r(s) = √(s² + x²) is analytic
/// but at s = ±ix, at distance a from the interval, so a short Gauss rule is exact to
/// about 1e-15. Cells too close to that point (a ≲ 18h, where the closed form loses at
/// most ~300 ulps) use the closed form.
///
/// `sa`, `sb` are √(a² − x²), √(b² − x²) (shared with the neighbouring cells).
fn forward_cell_weights(a: f64, b: f64, sa: f64, sb: f64, x: f64, h: f64) -> (f64, f64) {
    let half = 0.5 * (b - a) * (b + a) / (sa + sb);
    with_gauss_rule!(a, half, rule => forward_gauss(rule, sa, sb, half, a, b, x, h)).unwrap_or_else(
        || {
            let (i0, i1) = forward_moments(a, b, x);
            (2.0 * (b * i0 - i1) / h, 2.0 * (i1 - a * i0) / h)
        },
    )
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn forward_gauss<const P: usize>(
    rule: &[(f64, f64, f64); P],
    sa: f64,
    sb: f64,
    half: f64,
    a: f64,
    b: f64,
    x: f64,
    h: f64,
) -> (f64, f64) {
    let mid = sa + half;
    let (mut left, mut right) = (0.0, 0.0);
    for &(t, w_minus, w_plus) in rule {
        let s = mid + half * t;
        let r = (s * s + x * x).sqrt();
        // One division for both weights.
        let (to_b, to_a) = (b + r, r + a);
        let inv = 1.0 / (to_b * to_a);
        left += w_minus * (sb + s) * to_a * inv;
        right += w_plus * (s + sa) * to_b * inv;
    }
    let scale = 2.0 / h * half * half;
    (scale * left, scale * right)
}

/// Hat weights (left node a, right node b) of the back transform on the cell [a, b] at
/// r ≥ b, i.e. (2/π)(b·J0 − J1)/h and (2/π)(J1 − a·J0)/h, without the closed form's
/// cancellation (relative rounding growing like (r/h)²).
///
/// With c = √(r² − x²) (dx/√(r² − x²) = −dc/x) the weights are (2/π)(1/h)∫(b − x)/x dc
/// and (2/π)(1/h)∫(x − a)/x dc over [c_b, c_a], with b − x = (c − c_b)(c + c_b)/(b + x),
/// x − a = (c_a − c)(c_a + c)/(x + a) and x = √((r − c)(r + c)), r − c = a²/(r + c_a) +
/// (c_a − c); the only singularity is x = 0 at c = r, a²/(r + c_a) beyond the interval.
/// Closer cells (near the axis or next to r, where the closed form's rounding is small)
/// use the closed form.
///
/// `ca`, `cb` are √(r² − a²), √(r² − b²) (shared with the neighbouring cells).
fn back_cell_weights(a: f64, b: f64, ca: f64, cb: f64, r: f64, h: f64) -> (f64, f64) {
    let half = 0.5 * (b - a) * (b + a) / (ca + cb);
    let gap = a * a / (r + ca);
    with_gauss_rule!(gap, half, rule => back_gauss(rule, ca, cb, half, gap, a, b, r, h))
        .unwrap_or_else(|| {
            let (j0, j1) = back_moments(a, b, r);
            (2.0 / PI * (b * j0 - j1) / h, 2.0 / PI * (j1 - a * j0) / h)
        })
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn back_gauss<const P: usize>(
    rule: &[(f64, f64, f64); P],
    ca: f64,
    cb: f64,
    half: f64,
    gap: f64,
    a: f64,
    b: f64,
    r: f64,
    h: f64,
) -> (f64, f64) {
    let mid = cb + half;
    let (mut left, mut right) = (0.0, 0.0);
    for &(t, w_minus, w_plus) in rule {
        let c = mid + half * t;
        let x = ((gap + half * (1.0 - t)) * (r + c)).sqrt();
        let (to_b, to_a) = (b + x, x + a);
        let inv = 1.0 / (to_b * to_a * x);
        left += w_plus * (c + cb) * to_a * inv;
        right += w_minus * (ca + c) * to_b * inv;
    }
    let scale = 2.0 / PI / h * half * half;
    (scale * left, scale * right)
}

/// Forward transform q = W τ by product integration.
pub fn forward(grid: &Grid) -> TriangularOperator {
    let n = grid.nodes();
    if !grid.grading().is_uniform() {
        return from_rows(&ForwardEntries::new(*grid));
    }
    let mut w = TriangularOperator::zeros(n, Triangle::Upper);
    for j in 0..n {
        let x = grid.node_radius_m(j);
        for k in j..n {
            let a = grid.node_radius_m(k);
            let b = grid.node_radius_m(k + 1);
            let h = grid.cell_width_m(k);
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
    if !grid.grading().is_uniform() {
        return from_rows(&BackEntries::new(*grid));
    }
    let mut b_op = TriangularOperator::zeros(n, Triangle::Lower);
    b_op.add(0, 0, 1.0);
    for i in 1..n {
        let r = grid.node_radius_m(i);
        for k in 0..i {
            let a = grid.node_radius_m(k);
            let b = grid.node_radius_m(k + 1);
            let h = grid.cell_width_m(k);
            let (j0, j1) = back_moments(a, b, r);
            b_op.add(i, k, 2.0 / PI * (b * j0 - j1) / h);
            b_op.add(i, k + 1, 2.0 / PI * (j1 - a * j0) / h);
        }
    }
    b_op
}

/// The packed operator of a graded grid, row by row from the cancellation-free cell weights.
///
/// On a graded grid the closed-form moments cancel: a cell's hat weights are differences of
/// moments equal to a relative (r/h)², and the edge cells are a0·N^(−p) wide, so the closed
/// form would lose up to 2p·log10(N) digits (all of them at p = 3, N = 2000). The uniform
/// grid keeps its closed form (at most N² relative, the paper grid's bits unchanged).
fn from_rows(entries: &impl OperatorEntries) -> TriangularOperator {
    let n = entries.size();
    let triangle = entries.triangle();
    let mut op = TriangularOperator::zeros(n, triangle);
    let mut cols = Vec::with_capacity(n);
    let mut row = vec![0.0; n];
    for i in 0..n {
        cols.clear();
        match triangle {
            Triangle::Upper => cols.extend(i..n),
            Triangle::Lower => cols.extend(0..=i),
        }
        entries.row_into_accurate(i, &cols, &mut row);
        for (&k, &v) in cols.iter().zip(&row) {
            op.add(i, k, v);
        }
    }
    op
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

/// r_0 … r_N of `grid` (r_N = a0), m: [`Grid::node_radius_m`] once each.
fn node_radii(grid: &Grid) -> Vec<f64> {
    (0..=grid.nodes()).map(|i| grid.node_radius_m(i)).collect()
}

/// [`Grid::cell_width_m`] from the radii `node_radii` gave: the same value, no power.
#[inline]
fn cell_width(grid: &Grid, radii: &[f64], k: usize) -> f64 {
    if grid.grading().is_uniform() {
        grid.spacing_m()
    } else {
        radii[k + 1] - radii[k]
    }
}

/// The entries of [`forward`] on demand (N/m per Pa), for the hierarchical build.
#[derive(Debug, Clone)]
pub struct ForwardEntries {
    grid: Grid,
    /// r_0 … r_N (r_N = a0), m: computed once, since a graded grid's radius costs a power and
    /// the hierarchical build asks for each many times.
    radii: Vec<f64>,
}

impl ForwardEntries {
    /// The forward operator of `grid`, stored nowhere.
    pub fn new(grid: Grid) -> Self {
        Self {
            radii: node_radii(&grid),
            grid,
        }
    }
}

/// What entry m of an operator's row holds, in terms of the row's cells (hat functions:
/// node m's hat spans cells m − 1 and m).
#[derive(Debug, Clone, Copy)]
enum RowEntry {
    /// Outside the operator's triangle.
    Zero,
    /// The back transform's centre row: u3D(0) = u1D(0).
    One,
    /// Cell m − 1's right weight (when `right`), then cell m's left weight (when `left`),
    /// added to 0 in that order, the dense builder's.
    Cells { right: bool, left: bool },
}

/// Entry (j, m) of the forward operator on `n` nodes: cells from the row's node outward.
fn forward_row_entry(j: usize, n: usize, m: usize) -> RowEntry {
    if m < j || m >= n {
        RowEntry::Zero
    } else {
        RowEntry::Cells {
            right: m > j,
            left: true,
        }
    }
}

/// Entry (i, m) of the back operator: cells from the centre to the row's node.
fn back_row_entry(i: usize, m: usize) -> RowEntry {
    if m > i {
        RowEntry::Zero
    } else if i == 0 {
        RowEntry::One
    } else {
        RowEntry::Cells {
            right: m >= 1,
            left: m < i,
        }
    }
}

/// Fills `out` with a row's entries at `cols` from its cells' (left, right) hat weights,
/// `cell(k)`: one assembly for both operators, closed form or Gauss rules. Each cell's
/// weights are computed once for consecutive columns (which share a cell), in column order.
fn assemble_row(
    cols: &[usize],
    out: &mut [f64],
    entry: impl Fn(usize) -> RowEntry,
    mut cell: impl FnMut(usize) -> (f64, f64),
) {
    let mut cached: Option<(usize, f64, f64)> = None;
    let mut weights = |k: usize| -> (f64, f64) {
        match cached {
            Some((c, left, right)) if c == k => (left, right),
            _ => {
                let (left, right) = cell(k);
                cached = Some((k, left, right));
                (left, right)
            }
        }
    };
    for (o, &m) in out[..cols.len()].iter_mut().zip(cols) {
        let mut w = 0.0;
        match entry(m) {
            RowEntry::Zero => {}
            RowEntry::One => w += 1.0,
            RowEntry::Cells { right, left } => {
                if right {
                    w += weights(m - 1).1;
                }
                if left {
                    w += weights(m).0;
                }
            }
        }
        *o = w;
    }
}

impl OperatorEntries for ForwardEntries {
    fn size(&self) -> usize {
        self.grid.nodes()
    }

    fn triangle(&self) -> Triangle {
        Triangle::Upper
    }

    fn entry(&self, i: usize, k: usize) -> f64 {
        let mut row = [0.0];
        self.row_into(i, &[k], &mut row);
        row[0]
    }

    /// Row j: entry (j, m) sums cell m − 1's right weight and cell m's left weight, in
    /// the dense builder's order; consecutive columns share a cell's moments.
    fn row_into(&self, j: usize, cols: &[usize], out: &mut [f64]) {
        let (grid, radii) = (&self.grid, &self.radii);
        if !grid.grading().is_uniform() {
            return self.row_into_accurate(j, cols, out);
        }
        let n = grid.nodes();
        let x = radii[j];
        let cell = |k: usize| {
            let (i0, i1) = forward_moments(radii[k], radii[k + 1], x);
            if k + 1 < n {
                let (a, b) = (radii[k], radii[k + 1]);
                let h = cell_width(grid, radii, k);
                (2.0 * (b * i0 - i1) / h, 2.0 * (i1 - a * i0) / h)
            } else {
                // Constant data on the last cell; no cell to its right takes its right weight.
                (2.0 * i0, 0.0)
            }
        };
        assemble_row(cols, out, |m| forward_row_entry(j, n, m), cell);
    }

    /// Row j with the cell weights of `forward_cell_weights` (Gauss rules): the same entries to
    /// about 1e-15 relative, without the closed form's rounding noise.
    fn row_into_accurate(&self, j: usize, cols: &[usize], out: &mut [f64]) {
        let (grid, radii) = (&self.grid, &self.radii);
        let n = grid.nodes();
        let x = radii[j];
        // √(r_k² − x²) at the right end of the last cell, the next one's left end.
        let mut end: Option<(usize, f64)> = None;
        let cell = |k: usize| {
            let (a, b) = (radii[k], radii[k + 1]);
            let sa = match end {
                Some((e, s)) if e == k => s,
                _ => sqrt_diff_sq(a, x),
            };
            let sb = sqrt_diff_sq(b, x);
            end = Some((k + 1, sb));
            if k + 1 < n {
                forward_cell_weights(a, b, sa, sb, x, cell_width(grid, radii, k))
            } else {
                // Constant data on the last cell: 2·I0, free of cancellation.
                (2.0 * forward_moments(a, b, x).0, 0.0)
            }
        };
        assemble_row(cols, out, |m| forward_row_entry(j, n, m), cell);
    }

    /// ‖W·1‖₂/√N with W·1 = 2√(a0² − x_j²) exactly (product integration reproduces
    /// uniform stress, see the module docs): a lower bound of ‖W‖₂ from O(N) square roots,
    /// within a few per cent of it (the leading singular vector is smooth).
    fn norm_lower_bound(&self) -> f64 {
        let a0 = self.grid.radius_m();
        let n = self.grid.nodes();
        let sum: f64 = (0..n)
            .map(|j| 4.0 * sqrt_diff_sq(a0, self.radii[j]).powi(2))
            .sum();
        (sum / n as f64).sqrt()
    }
}

/// The entries of [`back`] on demand (m per m), for the hierarchical build.
#[derive(Debug, Clone)]
pub struct BackEntries {
    grid: Grid,
    /// r_0 … r_N (r_N = a0), m: computed once, since a graded grid's radius costs a power and
    /// the hierarchical build asks for each many times.
    radii: Vec<f64>,
}

impl BackEntries {
    /// The back operator of `grid`, stored nowhere.
    pub fn new(grid: Grid) -> Self {
        Self {
            radii: node_radii(&grid),
            grid,
        }
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
        let mut row = [0.0];
        self.row_into(i, &[k], &mut row);
        row[0]
    }

    /// Row i: entry (i, m) sums cell m − 1's right weight and cell m's left weight, in
    /// the dense builder's order; consecutive columns share a cell's moments.
    fn row_into(&self, i: usize, cols: &[usize], out: &mut [f64]) {
        let (grid, radii) = (&self.grid, &self.radii);
        if !grid.grading().is_uniform() {
            return self.row_into_accurate(i, cols, out);
        }
        let r = radii[i];
        let cell = |k: usize| {
            let (a, b) = (radii[k], radii[k + 1]);
            let (j0, j1) = back_moments(a, b, r);
            let h = cell_width(grid, radii, k);
            (2.0 / PI * (b * j0 - j1) / h, 2.0 / PI * (j1 - a * j0) / h)
        };
        assemble_row(cols, out, |m| back_row_entry(i, m), cell);
    }

    /// Row i with the cell weights of `back_cell_weights` (Gauss rules): the same entries to about
    /// 1e-15 relative, without the closed form's rounding noise.
    fn row_into_accurate(&self, i: usize, cols: &[usize], out: &mut [f64]) {
        let (grid, radii) = (&self.grid, &self.radii);
        let r = radii[i];
        // √(r² − x_k²) at the right end of the last cell, the next one's left end.
        let mut end: Option<(usize, f64)> = None;
        let cell = |k: usize| {
            let (a, b) = (radii[k], radii[k + 1]);
            let ca = match end {
                Some((e, c)) if e == k => c,
                _ => sqrt_diff_sq(r, a),
            };
            let cb = sqrt_diff_sq(r, b);
            end = Some((k + 1, cb));
            back_cell_weights(a, b, ca, cb, r, cell_width(grid, radii, k))
        };
        assemble_row(cols, out, |m| back_row_entry(i, m), cell);
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
    let mut w = vec![0.0; n];
    for k in 0..n {
        let a = grid.node_radius_m(k);
        let h = grid.cell_width_m(k);
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
    if !grid.grading().is_uniform() {
        return force_1d_weights_graded(grid);
    }
    let n = grid.nodes();
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
        let h = grid.cell_width_m(k);
        if k + 1 < n {
            c[k] += 2.0 * (b * m0 - m1) / h / edge(a);
            c[k + 1] += 2.0 * (m1 - a * m0) / h / edge(b);
        } else {
            c[k] += 2.0 * m0 / edge(a);
        }
    }
    c
}

/// [`force_1d_weights`] on a graded grid: the hat moments ∫(b − x)·√(a0² − x²) dx and
/// ∫(x − a)·√(a0² − x²) dx of each cell by an 8-point Gauss rule in w = √(a0 − x).
///
/// The closed form's antiderivatives are a0²·asin(x/a0)/2 plus terms of the same size that
/// cancel near the edge, and its hat weights are differences of moments equal to (a0/h)²;
/// with edge cells a0·N^(−p) wide nothing would be left. In w the integrand is
/// 2w²·(w² − (a0 − b))·√(2a0 − w²) (and its mirror), a polynomial times a square root whose
/// branch point w = √(2a0) lies at least 0.4·√a0 from any cell: the rule is exact to
/// rounding on every cell.
fn force_1d_weights_graded(grid: &Grid) -> Vec<f64> {
    let n = grid.nodes();
    let a0 = grid.radius_m();
    let edge = |x: f64| sqrt_diff_sq(a0, x);
    let mut c = vec![0.0; n];
    for k in 0..n {
        let a = grid.node_radius_m(k);
        let b = grid.node_radius_m(k + 1);
        let h = grid.cell_width_m(k);
        // w from √(a0 − b) (0 on the last cell) to √(a0 − a); a0 − x = w².
        let (da, db) = (a0 - a, a0 - b);
        let (wa, wb) = (da.sqrt(), db.max(0.0).sqrt());
        let (mid, half) = (0.5 * (wa + wb), 0.5 * (wa - wb));
        let (mut to_b, mut from_a) = (0.0, 0.0);
        for &(t, w_minus, w_plus) in &GAUSS_8 {
            // The rule's hat factors are not needed: recover its plain weight.
            let weight = 0.5 * (w_minus + w_plus);
            let w = mid + half * t;
            let w2 = w * w;
            let root = 2.0 * w * w.mul_add(-w, 2.0 * a0).sqrt() * w * weight;
            // b − x = w² − (a0 − b), x − a = (a0 − a) − w².
            to_b += (w2 - db) * root;
            from_a += (da - w2) * root;
        }
        let (to_b, from_a) = (to_b * half, from_a * half);
        if k + 1 < n {
            c[k] += 2.0 * to_b / h / edge(a);
            c[k + 1] += 2.0 * from_a / h / edge(b);
        } else {
            // Constant g on the last cell: 2∫√(a0² − x²) dx = 2(to_b + from_a)/h.
            c[k] += 2.0 * (to_b + from_a) / h / edge(a);
        }
    }
    c
}
