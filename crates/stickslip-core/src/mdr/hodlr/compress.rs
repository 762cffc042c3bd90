//! The compression of a dense packed operator: nested row and column bases by truncated
//! SVDs of whole off-diagonal block rows (see the "Build" section of the module docs).

use super::{NORM_ITERATIONS, Side, TreeNode};
use crate::mdr::{Triangle, TriangularOperator};
use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::svd::{ComputeSvdVectors, SvdParams, svd, svd_scratch};
use faer::{Accum, Mat, MatRef, Par, Spec};

/// Thin SVD (U, σ, V) computed sequentially, so the build does not depend on threads.
fn thin_svd(m: MatRef<'_, f64>) -> (Mat<f64>, Vec<f64>, Mat<f64>) {
    let (rows, cols) = m.shape();
    let size = rows.min(cols);
    let mut u = Mat::<f64>::zeros(rows, size);
    let mut v = Mat::<f64>::zeros(cols, size);
    let mut s = Diag::<f64>::zeros(size);
    let params: Spec<SvdParams, f64> = Default::default();
    let mut buf = MemBuffer::new(svd_scratch::<f64>(
        rows,
        cols,
        ComputeSvdVectors::Thin,
        ComputeSvdVectors::Thin,
        Par::Seq,
        params,
    ));
    svd(
        m,
        s.as_mut(),
        Some(u.as_mut()),
        Some(v.as_mut()),
        Par::Seq,
        MemStack::new(&mut buf),
        params,
    )
    .expect("SVD of an off-diagonal block did not converge");
    let sigma = (0..size).map(|i| s.column_vector()[i]).collect();
    (u, sigma, v)
}

fn matmul(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut c = Mat::<f64>::zeros(a.nrows(), b.ncols());
    faer::linalg::matmul::matmul(c.as_mut(), Accum::Replace, a, b, 1.0, Par::Seq);
    c
}

/// Truncated factors of an SVD: the first k columns of U, Z = diag(σ₁..σ_k)·V_kᵀ and the
/// largest discarded σ (the spectral norm of what is dropped), k = #{σ ≥ threshold, σ > 0}.
fn truncate(m: MatRef<'_, f64>, threshold: f64) -> (Mat<f64>, Mat<f64>, f64) {
    if m.nrows() == 0 || m.ncols() == 0 {
        return (Mat::zeros(m.nrows(), 0), Mat::zeros(0, m.ncols()), 0.0);
    }
    let (u, sigma, v) = thin_svd(m);
    let k = sigma
        .iter()
        .take_while(|&&s| s > 0.0 && s >= threshold)
        .count();
    let dropped = sigma.get(k).copied().unwrap_or(0.0);
    let basis = u.subcols(0, k).to_owned();
    let z = Mat::from_fn(k, m.ncols(), |i, c| sigma[i] * v[(c, i)]);
    (basis, z, dropped)
}

/// Projection Z = Uᵀ·R of a node's off-diagonal range onto its basis, columns
/// `col0..col0 + z.ncols()` of the oriented matrix.
pub(super) struct Projected {
    z: Mat<f64>,
    col0: usize,
}

impl Projected {
    fn cols(&self, c0: usize, c1: usize) -> MatRef<'_, f64> {
        debug_assert!(c0 >= self.col0 && c1 <= self.col0 + self.z.ncols());
        self.z.subcols(c0 - self.col0, c1 - c0)
    }
}

/// One bottom-up pass building the nested bases of the rows of an oriented matrix M
/// (M = A for row bases, M = Aᵀ for column bases).
pub(super) struct BasisPass<'a> {
    pub(super) tree: &'a [TreeNode],
    pub(super) n: usize,
    pub(super) side: Side,
    pub(super) entry: &'a dyn Fn(usize, usize) -> f64,
    pub(super) threshold: f64,
    pub(super) rank: Vec<usize>,
    /// Largest singular value discarded at each node (0 if none).
    pub(super) dropped: Vec<f64>,
    /// Leaf: its basis (size × k); internal: the stacked transfer [E₁; E₂].
    pub(super) factor: Vec<Mat<f64>>,
    /// Explicit bases (size × k), kept only for the column pass (needed by couplings).
    pub(super) expanded: Option<Vec<Mat<f64>>>,
    /// Couplings, computed in the row pass from the column pass's explicit bases.
    pub(super) couple: Option<Coupler<'a>>,
}

pub(super) struct Coupler<'a> {
    pub(super) source_basis: &'a [Mat<f64>],
    pub(super) target_is_second: bool,
    pub(super) blocks: Vec<Mat<f64>>,
}

impl BasisPass<'_> {
    fn range(&self, id: usize) -> (usize, usize) {
        let node = &self.tree[id];
        match self.side {
            Side::Left => (0, node.lo),
            Side::Right => (node.hi, self.n),
        }
    }

    pub(super) fn visit(&mut self, id: usize) -> Projected {
        let (c0, c1) = self.range(id);
        let node = &self.tree[id];
        let (lo, hi) = (node.lo, node.hi);
        match node.children {
            None => {
                let entry = self.entry;
                let m = Mat::from_fn(hi - lo, c1 - c0, |i, c| entry(lo + i, c0 + c));
                let (basis, z, dropped) = truncate(m.as_ref(), self.threshold);
                self.rank[id] = basis.ncols();
                self.dropped[id] = dropped;
                if let Some(expanded) = &mut self.expanded {
                    expanded[id] = basis.clone();
                }
                self.factor[id] = basis;
                Projected { z, col0: c0 }
            }
            Some((a, b)) => {
                let pa = self.visit(a);
                let pb = self.visit(b);
                if let Some(couple) = &mut self.couple {
                    let (target, source, pt) = if couple.target_is_second {
                        (b, a, &pb)
                    } else {
                        (a, b, &pa)
                    };
                    let src = &self.tree[source];
                    let block = pt.cols(src.lo, src.hi);
                    couple.blocks[id] = matmul(block, couple.source_basis[source].as_ref());
                    debug_assert_eq!(couple.blocks[id].nrows(), self.rank[target]);
                }
                let (ka, kb) = (self.rank[a], self.rank[b]);
                let stacked = Mat::from_fn(ka + kb, c1 - c0, |i, c| {
                    if i < ka {
                        pa.z[(i, c0 + c - pa.col0)]
                    } else {
                        pb.z[(i - ka, c0 + c - pb.col0)]
                    }
                });
                let (transfer, z, dropped) = truncate(stacked.as_ref(), self.threshold);
                self.rank[id] = transfer.ncols();
                self.dropped[id] = dropped;
                if let Some(expanded) = &mut self.expanded {
                    let top = matmul(expanded[a].as_ref(), transfer.subrows(0, ka));
                    let bottom = matmul(expanded[b].as_ref(), transfer.subrows(ka, kb));
                    let (ra, k) = (top.nrows(), transfer.ncols());
                    expanded[id] = Mat::from_fn(ra + bottom.nrows(), k, |i, c| {
                        if i < ra {
                            top[(i, c)]
                        } else {
                            bottom[(i - ra, c)]
                        }
                    });
                }
                self.factor[id] = transfer;
                Projected { z, col0: c0 }
            }
        }
    }
}

/// Lower bound ν ≤ ‖A‖₂ by power iteration on AᵀA from the all-ones vector.
pub(super) fn norm_lower_bound(op: &TriangularOperator) -> f64 {
    let n = op.size();
    let mut v = vec![1.0 / (n as f64).sqrt(); n];
    let mut av = vec![0.0; n];
    let mut estimate = 0.0_f64;
    for _ in 0..NORM_ITERATIONS {
        op.apply(&v, &mut av);
        let norm_av = av.iter().map(|a| a * a).sum::<f64>().sqrt();
        estimate = estimate.max(norm_av);
        if norm_av == 0.0 {
            break;
        }
        // v ← Aᵀ(Av)/‖Aᵀ(Av)‖, reading A row by row.
        v.fill(0.0);
        for (i, &ai) in av.iter().enumerate() {
            let cols = match op.triangle() {
                Triangle::Lower => 0..i + 1,
                Triangle::Upper => i..n,
            };
            for k in cols {
                v[k] += op.get(i, k) * ai;
            }
        }
        let norm_v = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        if norm_v == 0.0 {
            break;
        }
        v.iter_mut().for_each(|a| *a /= norm_v);
    }
    estimate
}

/// A posteriori bound B of ‖A − Ã‖₂ from the singular values each truncation dropped.
///
/// A node's basis error e (spectral norm of the part of its off-diagonal block outside
/// the basis) obeys e_τ² ≤ e₁² + e₂² + δ_τ², δ_τ its own largest dropped σ (the children's
/// errors and the parent's truncation lie in orthogonal subspaces); a sibling block's
/// error is ≤ e_row(target) + e_col(source); blocks at one depth occupy disjoint rows and
/// columns, so their errors combine as a maximum, and depths add up.
pub(super) fn error_bound(
    tree: &[TreeNode],
    row_dropped: &[f64],
    col_dropped: &[f64],
    target_is_second: bool,
) -> f64 {
    let mut row_sq: Vec<f64> = row_dropped.iter().map(|d| d * d).collect();
    let mut col_sq: Vec<f64> = col_dropped.iter().map(|d| d * d).collect();
    // Children come after their parent in pre-order: a reverse sweep sums subtrees.
    for id in (0..tree.len()).rev() {
        if let Some((a, b)) = tree[id].children {
            row_sq[id] += row_sq[a] + row_sq[b];
            col_sq[id] += col_sq[a] + col_sq[b];
        }
    }
    let depth = tree.iter().map(|t| t.depth).max().unwrap_or(0);
    let mut per_depth = vec![0.0_f64; depth + 1];
    for node in tree {
        if let Some((a, b)) = node.children {
            let (target, source) = if target_is_second { (b, a) } else { (a, b) };
            let e = row_sq[target].sqrt() + col_sq[source].sqrt();
            per_depth[node.depth] = per_depth[node.depth].max(e);
        }
    }
    per_depth.iter().sum()
}
