//! Second stage of the build: the skeleton HSS form made orthonormal, its norm estimated,
//! and its bases truncated to the tolerance with the largest dropped singular value of
//! every truncation recorded (see "Build" and "Accuracy" in the module docs).
//!
//! All of it works on the small factors (ranks × ranks), O(N·r²) in all.

use super::TreeNode;
use super::dense::{left_svd, matmul, r_factor, thin_qr};
use faer::Mat;

/// Nested bases of one side: leaf bases (size × k) and transfers ((k₁ + k₂) × k).
#[derive(Debug)]
pub(super) struct Bases {
    pub rank: Vec<usize>,
    pub factor: Vec<Mat<f64>>,
}

/// An HSS form Ã = D + Σ U_t·B·V_sᵀ over the tree: leaf diagonal blocks, row bases U,
/// column bases V, one coupling B per internal node (target ← source).
pub(super) struct Hss<'a> {
    pub tree: &'a [TreeNode],
    /// Dense diagonal block of each leaf (empty for internal nodes).
    pub diagonal: &'a [Mat<f64>],
    pub rows: &'a Bases,
    pub cols: &'a Bases,
    pub couplings: &'a [Mat<f64>],
    /// Lower triangle: the second child is the target of its parent's coupling.
    pub target_is_second: bool,
}

/// (child, row offset in the parent's transfer) of both children of `node`.
fn children(node: &TreeNode, rank: &[usize]) -> [(usize, usize); 2] {
    let (a, b) = node.children.expect("internal node");
    [(a, 0), (b, rank[a])]
}

/// Makes nested bases orthonormal, children first: a leaf T = Q·R; a parent's stacked
/// [R₁·T₁; R₂·T₂] = Q·R. Returns the R of every node: old basis = new basis·R.
pub(super) fn orthonormalize(tree: &[TreeNode], bases: &mut Bases) -> Vec<Mat<f64>> {
    let mut r_of: Vec<Mat<f64>> = vec![Mat::zeros(0, 0); tree.len()];
    // Pre-order puts children after their parent: a reverse sweep sees children first.
    for id in (0..tree.len()).rev() {
        let k = bases.rank[id];
        let stacked = match tree[id].children {
            None => bases.factor[id].clone(),
            Some(_) => {
                let t = &bases.factor[id];
                let mut s = Mat::<f64>::zeros(t.nrows(), k);
                for (child, off) in children(&tree[id], &bases.rank) {
                    let kc = bases.rank[child];
                    let part = matmul(r_of[child].as_ref(), t.subrows(off, kc));
                    for c in 0..k {
                        for i in 0..kc {
                            s[(off + i, c)] = part[(i, c)];
                        }
                    }
                }
                s
            }
        };
        let (q, r) = thin_qr(&stacked);
        bases.factor[id] = q;
        r_of[id] = r;
    }
    r_of
}

impl Hss<'_> {
    /// y = Ã·x (or Ãᵀ·x), unpacked: for the norm estimate of the build only.
    pub fn apply(&self, x: &[f64], y: &mut [f64], transpose: bool) {
        let tree = self.tree;
        // Ãᵀ swaps the bases, transposes blocks and turns sources into targets.
        let (inb, outb) = if transpose {
            (self.rows, self.cols)
        } else {
            (self.cols, self.rows)
        };
        let out_is_second = self.target_is_second != transpose;
        let mut xh: Vec<Vec<f64>> = vec![Vec::new(); tree.len()];
        for id in (0..tree.len()).rev() {
            let f = &inb.factor[id];
            let input: Vec<f64> = match tree[id].children {
                None => x[tree[id].lo..tree[id].hi].to_vec(),
                Some((a, b)) => [xh[a].as_slice(), xh[b].as_slice()].concat(),
            };
            xh[id] = (0..f.ncols())
                .map(|c| (0..f.nrows()).map(|i| f[(i, c)] * input[i]).sum())
                .collect();
        }
        let mut yh: Vec<Vec<f64>> = vec![Vec::new(); tree.len()];
        yh[0] = vec![0.0; outb.rank[0]];
        for (id, node) in tree.iter().enumerate() {
            let Some((a, b)) = node.children else {
                continue;
            };
            let e = &outb.factor[id];
            for (child, off) in children(node, &outb.rank) {
                let kc = outb.rank[child];
                let mut v: Vec<f64> = (0..kc)
                    .map(|i| (0..e.ncols()).map(|c| e[(off + i, c)] * yh[id][c]).sum())
                    .collect();
                let is_second = child == b;
                if is_second == out_is_second {
                    let src = if is_second { a } else { b };
                    let blk = &self.couplings[id];
                    for (i, vi) in v.iter_mut().enumerate() {
                        *vi += if transpose {
                            (0..blk.nrows())
                                .map(|c| blk[(c, i)] * xh[src][c])
                                .sum::<f64>()
                        } else {
                            (0..blk.ncols())
                                .map(|c| blk[(i, c)] * xh[src][c])
                                .sum::<f64>()
                        };
                    }
                }
                yh[child] = v;
            }
        }
        for (id, node) in tree.iter().enumerate() {
            if node.children.is_some() {
                continue;
            }
            let (lo, hi) = (node.lo, node.hi);
            let d = &self.diagonal[id];
            let u = &outb.factor[id];
            for i in 0..hi - lo {
                let dense: f64 = if transpose {
                    (0..hi - lo).map(|c| d[(c, i)] * x[lo + c]).sum()
                } else {
                    (0..hi - lo).map(|c| d[(i, c)] * x[lo + c]).sum()
                };
                let low: f64 = (0..u.ncols()).map(|c| u[(i, c)] * yh[id][c]).sum();
                y[lo + i] = dense + low;
            }
        }
    }

    /// Lower bound ν ≤ ‖Ã‖₂ by `iterations` steps of power iteration on ÃᵀÃ from the
    /// all-ones vector.
    pub fn norm_estimate(&self, n: usize, iterations: usize) -> f64 {
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        let mut v = vec![1.0 / (n as f64).sqrt(); n];
        let mut av = vec![0.0; n];
        let mut estimate = 0.0_f64;
        for _ in 0..iterations {
            self.apply(&v, &mut av, false);
            let norm_av = norm(&av);
            estimate = estimate.max(norm_av);
            if norm_av == 0.0 {
                break;
            }
            self.apply(&av, &mut v, true);
            let norm_v = norm(&v);
            if norm_v == 0.0 {
                break;
            }
            v.iter_mut().for_each(|a| *a /= norm_v);
        }
        estimate
    }
}

/// Factors W_τ of the Gram matrix of each node's block row in its (orthonormal) basis
/// coordinates, parents first: the block row of τ is U_τ·G_τ with G_τ·G_τᵀ = W_τ·W_τᵀ,
/// G_τ = [E_τ·G_parent, B] (the coupling only where τ is the target; the other side's
/// basis is orthonormal, so B contributes B·Bᵀ). W is kept at most k_τ wide by a QR.
pub(super) fn weights(
    tree: &[TreeNode],
    bases: &Bases,
    couplings: &[Mat<f64>],
    target_is_second: bool,
    transpose: bool,
) -> Vec<Mat<f64>> {
    let mut w: Vec<Mat<f64>> = vec![Mat::zeros(0, 0); tree.len()];
    w[0] = Mat::zeros(bases.rank[0], 0);
    let out_is_second = target_is_second != transpose;
    for (id, node) in tree.iter().enumerate() {
        let Some((_, b)) = node.children else {
            continue;
        };
        let e = &bases.factor[id];
        for (child, off) in children(node, &bases.rank) {
            let kc = bases.rank[child];
            let inherited = matmul(e.subrows(off, kc), w[id].as_ref());
            let own = if (child == b) == out_is_second {
                if transpose {
                    couplings[id].transpose().to_owned()
                } else {
                    couplings[id].clone()
                }
            } else {
                Mat::zeros(kc, 0)
            };
            let width = inherited.ncols() + own.ncols();
            let y = Mat::from_fn(kc, width, |i, c| {
                if c < inherited.ncols() {
                    inherited[(i, c)]
                } else {
                    own[(i, c - inherited.ncols())]
                }
            });
            w[child] = if width > kc {
                // Y·Yᵀ = Rᵀ·R with R from a QR of Yᵀ: W = Rᵀ, k × k.
                r_factor(&y.transpose().to_owned()).transpose().to_owned()
            } else {
                y
            };
        }
    }
    w
}

/// Result of truncating one side: the new bases, P_τ = U_τᵀ·U'_τ (old → new coordinates)
/// and the largest dropped singular value of every node.
pub(super) struct Truncated {
    pub bases: Bases,
    pub projection: Vec<Mat<f64>>,
    pub dropped: Vec<f64>,
}

/// Truncates orthonormal nested bases, children first: the node's weighted block row
/// projected on its children's new bases, [P₁ᵀ·E₁; P₂ᵀ·E₂]·W_τ (leaf: W_τ), keeps the
/// singular vectors with σ ≥ `threshold` as the new transfer (leaf: basis U_τ·X). Consumes
/// the old bases and weights node by node, so that old and new factors are not all held
/// at once.
pub(super) fn truncate(
    tree: &[TreeNode],
    mut bases: Bases,
    mut weight: Vec<Mat<f64>>,
    threshold: f64,
) -> Truncated {
    let nodes = tree.len();
    let mut out = Truncated {
        bases: Bases {
            rank: vec![0; nodes],
            factor: vec![Mat::zeros(0, 0); nodes],
        },
        projection: vec![Mat::zeros(0, 0); nodes],
        dropped: vec![0.0; nodes],
    };
    for id in (0..nodes).rev() {
        let k = bases.rank[id];
        // X0: the node's old basis in its children's new coordinates (leaf: identity).
        let x0 = match tree[id].children {
            None => None,
            Some(_) => {
                let e = &bases.factor[id];
                let parts: Vec<(usize, Mat<f64>)> = children(&tree[id], &bases.rank)
                    .into_iter()
                    .map(|(child, off)| {
                        let p = &out.projection[child];
                        (
                            child,
                            matmul(p.transpose(), e.subrows(off, bases.rank[child])),
                        )
                    })
                    .collect();
                let rows: usize = parts.iter().map(|(_, m)| m.nrows()).sum();
                let mut x0 = Mat::<f64>::zeros(rows, k);
                let mut r0 = 0;
                for (_, m) in &parts {
                    for c in 0..k {
                        for i in 0..m.nrows() {
                            x0[(r0 + i, c)] = m[(i, c)];
                        }
                    }
                    r0 += m.nrows();
                }
                Some(x0)
            }
        };
        let w = std::mem::replace(&mut weight[id], Mat::zeros(0, 0));
        let z = match &x0 {
            None => w,
            Some(x0) => matmul(x0.as_ref(), w.as_ref()),
        };
        let (u, sigma) = left_svd(z.as_ref());
        let keep = sigma
            .iter()
            .take_while(|&&s| s > 0.0 && s >= threshold)
            .count();
        out.dropped[id] = sigma.get(keep).copied().unwrap_or(0.0);
        let new_coords = u.subcols(0, keep).to_owned();
        out.bases.rank[id] = keep;
        let old = std::mem::replace(&mut bases.factor[id], Mat::zeros(0, 0));
        match x0 {
            None => {
                out.bases.factor[id] = matmul(old.as_ref(), new_coords.as_ref());
                out.projection[id] = new_coords;
            }
            Some(x0) => {
                out.projection[id] = matmul(x0.transpose(), new_coords.as_ref());
                out.bases.factor[id] = new_coords;
            }
        }
    }
    out
}

/// Bound of ‖Ã − Ã'‖₂ from per-node errors δ (largest dropped singular values, or
/// residuals for an estimate).
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
