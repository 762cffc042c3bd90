//! Hierarchical low-rank form of the packed triangular MDR operators: memory and apply
//! O(N·r) (r the rank, growing like log N), built from and checked against the dense ones.
//!
//! Why: the dense mat-vec of [`TriangularOperator`] streams N²/2 entries per apply
//! (16 MB, about 330 µs at N = 2000), while the Abel kernel 1/√(r² − x²) is smooth away
//! from r = x, so every off-diagonal block is numerically of low rank (10–17 at
//! `rel_tol` 1e-10 for N ≤ 2000, growing like log N).
//!
//! # Form
//! The index range 0..N is halved recursively down to leaves of at most
//! [`LEAF_MAX_ROWS`] rows; each leaf keeps its diagonal triangle densely. Every node τ
//! with index set I = [lo, hi) has an orthonormal **row basis** U_τ spanning its whole
//! off-diagonal block row (lower: A[I, 0..lo]; upper: A[I, hi..N]) and an orthonormal
//! **column basis** V_τ spanning its off-diagonal block column (lower: A[hi..N, I];
//! upper: A[0..lo, I]). The bases are *nested* — a parent's basis is its children's
//! bases times a small transfer matrix (the HSS form of a HODLR matrix) — so the one
//! non-zero sibling block of every parent (lower: A[I₂, I₁]; upper: A[I₁, I₂]) is
//! U·B·Vᵀ with B only rank × rank. Independent U·Vᵀ factors per block (plain HODLR) would
//! store N·(leaf/2 + Σ_levels r) values, ≈ 200 000 at N = 2000 and `rel_tol` 1e-10 with
//! block ranks measured by full SVDs, against 128 000 for the nested form; and the
//! nested form's cost per row grows only with the ranks, not with the number of levels.
//!
//! # Accuracy
//! Ranks are chosen by truncated SVD (faer, sequential, so the build does not depend on
//! the thread count): a singular value σ is kept if σ ≥ t = `rel_tol`·ν, where ν ≤ ‖A‖₂
//! is a power-iteration estimate of the spectral norm (a lower bound, so t never exceeds
//! `rel_tol`·‖A‖₂). The largest dropped σ of every truncation is recorded and gives an
//! a posteriori bound (see [`HodlrOperator::error_bound`]):
//!
//! ‖A x − Ã x‖₂ ≤ C·`rel_tol`·‖A‖₂·‖x‖₂,  C = [`HodlrOperator::error_bound_factor`]
//!
//! plus rounding. C is 2–4 at N = 125, about 25 at N = 2000 and 45–70 at N = 8000 (the
//! nested truncation errors may add up over the subtree of a node), while the errors
//! measured against the dense operators stay below 0.1·`rel_tol`·‖A‖₂·‖x‖₂.
//!
//! The same threshold at every node (rather than smaller ones for small nodes, which
//! would give C ≈ 10 independent of N) keeps the leaves above the rounding floor below.
//!
//! # Rounding floor of the product operators
//! The product-integration weights are differences of moments that cancel by a factor
//! of order N, so their entries carry rounding noise. Its singular values, seen as the
//! ranks jumping towards full once the threshold reaches them, lie near 1e-12·‖A‖₂ at
//! N = 2000 and approach 1e-10·‖A‖₂ at N = 8000 (column blocks of the forward operator:
//! ranks 21–24 there against 11–19 for its row blocks and for the back operator); the
//! literal operators have no such floor. Thresholds near or below the floor compress
//! noise: at `rel_tol` 1e-12 and N = 2000 the product forward operator stores almost
//! twice as much as the dense one. The error bound still holds; only speed and memory
//! are lost. Hence `rel_tol` 1e-10 (N ≤ 4000) to 1e-8 — both far below the O(h²)
//! discretisation error of the schemes.
//!
//! # Build
//! Reads every entry twice through [`TriangularOperator::get`] (once for row bases, once
//! for column bases), O(N²) time; the SVDs of the leaf block rows (leaf × N) dominate,
//! O(N²·leaf): about 0.1 s at N = 2000 and 1.8 s at N = 8000 (release, one thread).
//! The temporary memory is O(N·r·log N).
//!
//! # Apply
//! [`HodlrOperator::apply`]: leaves (x̂ = Vᵀx) → up the tree (x̂_τ = Fᵀ[x̂₁; x̂₂]) → down
//! (ŷ = E ŷ_parent + B x̂_sibling) → leaves (y = D x + U ŷ). Every small matrix is stored
//! in row panels of 8/4/2/1 rows, column after column, all in one Vec in the order the
//! apply reads them, so one apply streams through memory once; each output row has its
//! own accumulator (even and odd columns, then added), so the sums have a fixed order.
//! The kernel is dispatched at run time to AVX2 where the CPU has it (pulp, re-exported
//! by faer); it uses no fused multiply-add, so the result is bit-identical on every
//! instruction set and every call ([`HodlrOperator::apply_portable`] checks this).
//! Single-threaded and allocation-free: intermediate coefficients live in a
//! caller-owned [`HodlrScratch`], so the operator stays immutable and shareable.

use super::triangular::dot_fixed_order;
use super::{Triangle, TriangularOperator};
use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::svd::{ComputeSvdVectors, SvdParams, svd, svd_scratch};
use faer::traits::pulp::{Arch, Simd, WithSimd};
use faer::{Accum, Mat, MatRef, Par, Spec};

/// Largest leaf (rows of a dense diagonal block). Leaf triangles cost about leaf/2 per
/// row, transfers about 5r²/leaf: measured against 16 and 64, 32 is the fastest at
/// N = 2000 and as fast at N = 8000.
pub const LEAF_MAX_ROWS: usize = 32;

/// Power-iteration steps of the norm estimate ν (each is one A and one Aᵀ apply).
const NORM_ITERATIONS: usize = 4;

/// Ranks of one level of the tree, for reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RankLevel {
    /// Depth below the root (the root, 0, has no off-diagonal blocks).
    pub depth: usize,
    /// Number of nodes at this depth.
    pub nodes: usize,
    /// Largest node size (rows) at this depth.
    pub max_node_rows: usize,
    /// Largest row-basis rank at this depth.
    pub max_row_rank: usize,
    /// Largest column-basis rank at this depth.
    pub max_col_rank: usize,
}

/// Caller-owned work space of [`HodlrOperator::apply`] (basis coefficients per node).
///
/// Kept outside the operator so that `apply` takes `&self` and needs no lock.
#[derive(Debug, Clone)]
pub struct HodlrScratch {
    x_coeff: Vec<f64>,
    y_coeff: Vec<f64>,
}

/// A packed triangular MDR operator in hierarchical low-rank (nested-basis) form.
///
/// Same units as the [`TriangularOperator`] it was compressed from.
#[derive(Debug, Clone)]
pub struct HodlrOperator {
    n: usize,
    triangle: Triangle,
    rel_tol: f64,
    norm_estimate: f64,
    /// A posteriori bound B of ‖A − Ã‖₂ (operator units).
    error_bound: f64,
    /// Every small matrix of the apply, in the panel layout of [`gemv`].
    data: Vec<f64>,
    /// N ≤ [`LEAF_MAX_ROWS`]: `data` holds the packed rows, applied like the dense operator.
    single_leaf: bool,
    /// x̂_leaf = Vᵀ·x[I] (input x, output x̂).
    leaf_in: Vec<Gemv>,
    /// x̂_τ = Fᵀ·[x̂₁; x̂₂], children before parents (input and output x̂).
    up: Vec<Gemv>,
    /// Per internal node, parents first: [ŷ₁; ŷ₂] = E·ŷ_τ (input and output ŷ), then
    /// ŷ_target += B·x̂_source (input x̂, output ŷ).
    down: Vec<(Gemv, Gemv)>,
    /// y[I] = D·x[I] + U·ŷ_leaf.
    leaf_out: Vec<LeafOut>,
    x_coeff_len: usize,
    y_coeff_len: usize,
    profile: Vec<RankLevel>,
}

/// out[output..output + rows] (=|+=) M·v[input..input + cols], M at `data` in panel layout.
#[derive(Debug, Clone, Copy)]
struct Gemv {
    data: usize,
    rows: usize,
    cols: usize,
    input: usize,
    output: usize,
}

#[derive(Debug, Clone, Copy)]
struct LeafOut {
    lo: usize,
    hi: usize,
    data: usize,
    row_rank: usize,
    y_off: usize,
}

/// Which off-diagonal range a basis spans: columns left of the node or right of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Left,
    Right,
}

#[derive(Debug, Clone)]
struct TreeNode {
    lo: usize,
    hi: usize,
    depth: usize,
    children: Option<(usize, usize)>,
}

fn build_tree(n: usize) -> Vec<TreeNode> {
    fn push(nodes: &mut Vec<TreeNode>, lo: usize, hi: usize, depth: usize) -> usize {
        let id = nodes.len();
        nodes.push(TreeNode {
            lo,
            hi,
            depth,
            children: None,
        });
        if hi - lo > LEAF_MAX_ROWS {
            let mid = lo + (hi - lo) / 2;
            let a = push(nodes, lo, mid, depth + 1);
            let b = push(nodes, mid, hi, depth + 1);
            nodes[id].children = Some((a, b));
        }
        id
    }
    let mut nodes = Vec::new();
    push(&mut nodes, 0, n, 0);
    nodes
}

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
struct Projected {
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
struct BasisPass<'a> {
    tree: &'a [TreeNode],
    n: usize,
    side: Side,
    entry: &'a dyn Fn(usize, usize) -> f64,
    threshold: f64,
    rank: Vec<usize>,
    /// Largest singular value discarded at each node (0 if none).
    dropped: Vec<f64>,
    /// Leaf: its basis (size × k); internal: the stacked transfer [E₁; E₂].
    factor: Vec<Mat<f64>>,
    /// Explicit bases (size × k), kept only for the column pass (needed by couplings).
    expanded: Option<Vec<Mat<f64>>>,
    /// Couplings, computed in the row pass from the column pass's explicit bases.
    couple: Option<Coupler<'a>>,
}

struct Coupler<'a> {
    source_basis: &'a [Mat<f64>],
    target_is_second: bool,
    blocks: Vec<Mat<f64>>,
}

impl BasisPass<'_> {
    fn range(&self, id: usize) -> (usize, usize) {
        let node = &self.tree[id];
        match self.side {
            Side::Left => (0, node.lo),
            Side::Right => (node.hi, self.n),
        }
    }

    fn visit(&mut self, id: usize) -> Projected {
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
fn norm_lower_bound(op: &TriangularOperator) -> f64 {
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

impl HodlrOperator {
    /// Compresses `op` (keeping singular values ≥ `rel_tol`·ν, ν ≤ ‖A‖₂) so that
    /// ‖A x − Ã x‖₂ ≤ C·`rel_tol`·‖A‖₂·‖x‖₂ with C = [`Self::error_bound_factor`]
    /// (plus rounding); `rel_tol` = 0 keeps every non-zero singular value. O(N²) time.
    ///
    /// # Panics
    /// If `rel_tol` is negative or not finite, or if an SVD fails to converge.
    pub fn compress(op: &TriangularOperator, rel_tol: f64) -> Self {
        assert!(
            rel_tol.is_finite() && rel_tol >= 0.0,
            "rel_tol = {rel_tol} must be finite and >= 0"
        );
        let n = op.size();
        let triangle = op.triangle();
        let tree = build_tree(n);
        let norm_estimate = if n == 0 { 0.0 } else { norm_lower_bound(op) };
        let threshold = rel_tol * norm_estimate;
        let (row_side, col_side, target_is_second) = match triangle {
            Triangle::Lower => (Side::Left, Side::Right, true),
            Triangle::Upper => (Side::Right, Side::Left, false),
        };

        let nodes = tree.len();
        let col_entry = |i: usize, k: usize| op.get(k, i);
        let mut cols = BasisPass {
            tree: &tree,
            n,
            side: col_side,
            entry: &col_entry,
            threshold,
            rank: vec![0; nodes],
            dropped: vec![0.0; nodes],
            factor: vec![Mat::zeros(0, 0); nodes],
            expanded: Some(vec![Mat::zeros(0, 0); nodes]),
            couple: None,
        };
        cols.visit(0);
        let col_expanded = cols.expanded.take().unwrap_or_default();
        let row_entry = |i: usize, k: usize| op.get(i, k);
        let mut rows = BasisPass {
            tree: &tree,
            n,
            side: row_side,
            entry: &row_entry,
            threshold,
            rank: vec![0; nodes],
            dropped: vec![0.0; nodes],
            factor: vec![Mat::zeros(0, 0); nodes],
            expanded: None,
            couple: Some(Coupler {
                source_basis: &col_expanded,
                target_is_second,
                blocks: vec![Mat::zeros(0, 0); nodes],
            }),
        };
        rows.visit(0);
        let couplings = rows.couple.take().map(|c| c.blocks).unwrap_or_default();

        let bound = error_bound(&tree, &rows.dropped, &cols.dropped, target_is_second);
        let mut out = Self {
            n,
            triangle,
            rel_tol,
            norm_estimate,
            error_bound: bound,
            data: Vec::new(),
            single_leaf: false,
            leaf_in: Vec::new(),
            up: Vec::new(),
            down: Vec::new(),
            leaf_out: Vec::new(),
            x_coeff_len: 0,
            y_coeff_len: 0,
            profile: Vec::new(),
        };
        out.pack(op, &tree, &rows, &cols, &couplings);
        out
    }

    /// Lays the factors out for the apply: one contiguous Vec in panel layout, scratch
    /// offsets such that siblings' coefficients are adjacent and follow their parent's.
    fn pack(
        &mut self,
        op: &TriangularOperator,
        tree: &[TreeNode],
        rows: &BasisPass<'_>,
        cols: &BasisPass<'_>,
        couplings: &[Mat<f64>],
    ) {
        let n = self.n;
        if n <= LEAF_MAX_ROWS {
            self.single_leaf = true;
            for i in 0..n {
                let span = match self.triangle {
                    Triangle::Lower => 0..i + 1,
                    Triangle::Upper => i..n,
                };
                self.data.extend(span.map(|k| op.get(i, k)));
            }
        }
        let mut x_off = vec![0; tree.len()];
        let mut y_off = vec![0; tree.len()];
        let (mut x_cursor, mut y_cursor) = (0, 0);
        // Pre-order: a parent's offsets are known before its children are placed.
        for node in tree {
            let Some((a, b)) = node.children else {
                continue;
            };
            x_off[a] = x_cursor;
            x_off[b] = x_cursor + cols.rank[a];
            x_cursor += cols.rank[a] + cols.rank[b];
            y_off[a] = y_cursor;
            y_off[b] = y_cursor + rows.rank[a];
            y_cursor += rows.rank[a] + rows.rank[b];
        }
        self.x_coeff_len = x_cursor;
        self.y_coeff_len = y_cursor;
        if self.single_leaf {
            return self.set_profile(tree, rows, cols);
        }

        // `data` is laid out in the order the apply reads it, so one apply streams
        // through memory once, front to back.
        let leaves: Vec<usize> = (0..tree.len())
            .filter(|&id| tree[id].children.is_none())
            .collect();
        let internals: Vec<usize> = (0..tree.len())
            .filter(|&id| tree[id].children.is_some())
            .collect();
        for &id in &leaves {
            let v = &cols.factor[id];
            self.leaf_in.push(Gemv {
                data: push_panels(&mut self.data, v.ncols(), v.nrows(), |i, c| v[(c, i)]),
                rows: v.ncols(),
                cols: v.nrows(),
                input: tree[id].lo,
                output: x_off[id],
            });
        }
        for &id in internals.iter().rev() {
            let (a, _) = tree[id].children.expect("internal node");
            let f = &cols.factor[id];
            self.up.push(Gemv {
                data: push_panels(&mut self.data, f.ncols(), f.nrows(), |i, c| f[(c, i)]),
                rows: f.ncols(),
                cols: f.nrows(),
                input: x_off[a],
                output: x_off[id],
            });
        }
        for &id in &internals {
            let (a, b) = tree[id].children.expect("internal node");
            let (target, source) = match self.triangle {
                Triangle::Lower => (b, a),
                Triangle::Upper => (a, b),
            };
            let e = &rows.factor[id];
            let down = Gemv {
                data: push_panels(&mut self.data, e.nrows(), e.ncols(), |i, c| e[(i, c)]),
                rows: e.nrows(),
                cols: e.ncols(),
                input: y_off[id],
                output: y_off[a],
            };
            let blk = &couplings[id];
            let couple = Gemv {
                data: push_panels(&mut self.data, blk.nrows(), blk.ncols(), |i, c| blk[(i, c)]),
                rows: blk.nrows(),
                cols: blk.ncols(),
                input: x_off[source],
                output: y_off[target],
            };
            self.down.push((down, couple));
        }
        for &id in &leaves {
            let (lo, hi) = (tree[id].lo, tree[id].hi);
            let u = &rows.factor[id];
            let data = self.data.len();
            for (r0, height) in panel_schedule(hi - lo) {
                let (c0, c1) = leaf_panel_cols(self.triangle, hi - lo, r0, height);
                for c in c0..c1 {
                    self.data
                        .extend((0..height).map(|l| op.get(lo + r0 + l, lo + c)));
                }
                for c in 0..u.ncols() {
                    self.data.extend((0..height).map(|l| u[(r0 + l, c)]));
                }
            }
            self.leaf_out.push(LeafOut {
                lo,
                hi,
                data,
                row_rank: u.ncols(),
                y_off: y_off[id],
            });
        }
        self.set_profile(tree, rows, cols);
    }

    fn set_profile(&mut self, tree: &[TreeNode], rows: &BasisPass<'_>, cols: &BasisPass<'_>) {
        let depth = tree.iter().map(|t| t.depth).max().unwrap_or(0);
        self.profile = (0..=depth)
            .map(|d| {
                let at = || tree.iter().enumerate().filter(move |(_, t)| t.depth == d);
                RankLevel {
                    depth: d,
                    nodes: at().count(),
                    max_node_rows: at().map(|(_, t)| t.hi - t.lo).max().unwrap_or(0),
                    max_row_rank: at().map(|(i, _)| rows.rank[i]).max().unwrap_or(0),
                    max_col_rank: at().map(|(i, _)| cols.rank[i]).max().unwrap_or(0),
                }
            })
            .collect();
    }

    /// Matrix size N.
    pub fn size(&self) -> usize {
        self.n
    }

    /// The triangle of the operator it was compressed from.
    pub fn triangle(&self) -> Triangle {
        self.triangle
    }

    /// The relative tolerance it was compressed with.
    pub fn rel_tol(&self) -> f64 {
        self.rel_tol
    }

    /// ν, the power-iteration lower bound of ‖A‖₂ the thresholds were scaled by
    /// (units of the operator: N/m per Pa for the forward, m/m for the back operator).
    pub fn norm_estimate(&self) -> f64 {
        self.norm_estimate
    }

    /// B in ‖A x − Ã x‖₂ ≤ B·‖x‖₂ (rounding aside), computed after the build from the
    /// singular values that were dropped (operator units).
    pub fn error_bound(&self) -> f64 {
        self.error_bound
    }

    /// C = B/(`rel_tol`·ν) in ‖A x − Ã x‖₂ ≤ C·`rel_tol`·‖A‖₂·‖x‖₂; 0 when nothing
    /// was dropped. A priori (every dropped σ at the threshold) C is the sum over
    /// depths of √(nodes under the target child) + √(nodes under the source child),
    /// 45 at N = 2000 and 100 at N = 8000; the recorded values give about half that.
    pub fn error_bound_factor(&self) -> f64 {
        let scale = self.rel_tol * self.norm_estimate;
        if scale > 0.0 {
            self.error_bound / scale
        } else {
            0.0
        }
    }

    /// Ranks per tree level (depth 0 is the root).
    pub fn rank_profile(&self) -> &[RankLevel] {
        &self.profile
    }

    /// Largest rank of any basis.
    pub fn max_rank(&self) -> usize {
        self.profile
            .iter()
            .map(|l| l.max_row_rank.max(l.max_col_rank))
            .max()
            .unwrap_or(0)
    }

    /// Stored f64 values (memory = 8 bytes each; includes the zeros on the far side of
    /// the diagonal inside the leaves' 8-row panels); also the multiply-adds per apply.
    /// The packed dense operator stores N(N+1)/2.
    pub fn stored_entries(&self) -> usize {
        self.data.len()
    }

    /// Work space sized for this operator.
    pub fn scratch(&self) -> HodlrScratch {
        HodlrScratch {
            x_coeff: vec![0.0; self.x_coeff_len],
            y_coeff: vec![0.0; self.y_coeff_len],
        }
    }

    /// y ≈ A·x. Single-threaded, no allocation, fixed summation order: the same bits on
    /// every call, whatever the thread count or instruction set (no fused multiply-add).
    /// For N ≤ [`LEAF_MAX_ROWS`] the operator is one dense leaf applied exactly like
    /// [`TriangularOperator::apply`], so the bits equal the dense apply's.
    ///
    /// # Panics
    /// If `x.len()` or `y.len()` differs from N, or `scratch` is too small (made for
    /// another operator).
    #[track_caller]
    pub fn apply(&self, x: &[f64], y: &mut [f64], scratch: &mut HodlrScratch) {
        self.apply_with(Arch::new(), x, y, scratch);
    }

    /// [`Self::apply`] restricted to the baseline instruction set (no run-time dispatch):
    /// slower, same bits. Exists so that tests can check that the dispatched kernel
    /// does not change the result.
    ///
    /// # Panics
    /// As [`Self::apply`].
    #[track_caller]
    pub fn apply_portable(&self, x: &[f64], y: &mut [f64], scratch: &mut HodlrScratch) {
        self.apply_with(Arch::Scalar, x, y, scratch);
    }

    #[track_caller]
    fn apply_with(&self, arch: Arch, x: &[f64], y: &mut [f64], scratch: &mut HodlrScratch) {
        assert_eq!(x.len(), self.n, "input length must equal the node count");
        assert_eq!(y.len(), self.n, "output length must equal the node count");
        assert!(
            scratch.x_coeff.len() >= self.x_coeff_len && scratch.y_coeff.len() >= self.y_coeff_len,
            "scratch was made for another operator"
        );
        if self.single_leaf {
            let mut off = 0;
            for (i, yi) in y.iter_mut().enumerate() {
                let (c0, len) = match self.triangle {
                    Triangle::Lower => (0, i + 1),
                    Triangle::Upper => (i, self.n - i),
                };
                *yi = dot_fixed_order(&self.data[off..off + len], &x[c0..c0 + len]);
                off += len;
            }
            return;
        }
        arch.dispatch(ApplyKernel {
            op: self,
            x,
            y,
            scratch,
        });
    }

    /// The hierarchical apply; inlined into [`ApplyKernel`] so that it is compiled once
    /// per instruction set.
    #[inline(always)]
    fn apply_hierarchical(&self, x: &[f64], y: &mut [f64], scratch: &mut HodlrScratch) {
        let xc = &mut scratch.x_coeff[..];
        let yc = &mut scratch.y_coeff[..];
        let data = &self.data[..];

        // 1. Leaves: x̂ = Vᵀ x[I].
        for g in &self.leaf_in {
            gemv(data, g, &x[g.input..], &mut xc[g.output..], false);
        }
        // 2. Up, children first; a parent's slot lies before its children's.
        for g in &self.up {
            let (head, tail) = xc.split_at_mut(g.input);
            gemv(data, g, tail, &mut head[g.output..], false);
        }
        // 3. Down, parents first: children's ŷ set from the parent's, then the coupling.
        for (e, b) in &self.down {
            let (head, tail) = yc.split_at_mut(e.output);
            gemv(data, e, &head[e.input..], tail, false);
            gemv(data, b, &xc[b.input..], &mut yc[b.output..], true);
        }
        // 4. Leaves: y[I] = D x[I] + U ŷ.
        for leaf in &self.leaf_out {
            let size = leaf.hi - leaf.lo;
            let k = leaf.row_rank;
            let xs = &x[leaf.lo..leaf.hi];
            let ys = &yc[leaf.y_off..leaf.y_off + k];
            let out = &mut y[leaf.lo..leaf.hi];
            let mut off = leaf.data;
            for (r0, height) in panel_schedule(size) {
                let (c0, c1) = leaf_panel_cols(self.triangle, size, r0, height);
                let dense_len = height * (c1 - c0);
                let low_len = height * k;
                let dense = &data[off..off + dense_len];
                let low = &data[off + dense_len..off + dense_len + low_len];
                off += dense_len + low_len;
                let dst = &mut out[r0..r0 + height];
                match height {
                    8 => leaf_panel::<8>(dense, &xs[c0..c1], low, ys, dst),
                    4 => leaf_panel::<4>(dense, &xs[c0..c1], low, ys, dst),
                    2 => leaf_panel::<2>(dense, &xs[c0..c1], low, ys, dst),
                    _ => leaf_panel::<1>(dense, &xs[c0..c1], low, ys, dst),
                }
            }
        }
    }
}

/// Runs [`HodlrOperator::apply_hierarchical`] under the best instruction set the CPU
/// has (pulp's runtime dispatch: AVX2 where available, else the x86-64 baseline). The
/// kernels are plain Rust with one accumulator per output row and no fused
/// multiply-add, so wider vectors change the speed, never the bits.
struct ApplyKernel<'a> {
    op: &'a HodlrOperator,
    x: &'a [f64],
    y: &'a mut [f64],
    scratch: &'a mut HodlrScratch,
}

impl WithSimd for ApplyKernel<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        self.op.apply_hierarchical(self.x, self.y, self.scratch);
    }
}

/// Row panels (first row, height) covering `rows` rows exactly: panels of 8, then at
/// most one each of 4, 2, 1. Exact heights mean no padding and fixed-size stores.
fn panel_schedule(rows: usize) -> impl Iterator<Item = (usize, usize)> {
    let mut r0 = 0;
    std::iter::from_fn(move || {
        let left = rows - r0;
        let height = match left {
            0 => return None,
            8.. => 8,
            4..=7 => 4,
            2..=3 => 2,
            _ => 1,
        };
        let item = (r0, height);
        r0 += height;
        Some(item)
    })
}

/// Local columns of a leaf's triangle that a row panel [r0, r0 + height) touches.
fn leaf_panel_cols(triangle: Triangle, size: usize, r0: usize, height: usize) -> (usize, usize) {
    match triangle {
        Triangle::Lower => (0, r0 + height),
        Triangle::Upper => (r0, size),
    }
}

/// Appends an m × n matrix in panel layout (per row panel, column after column, each
/// column `height` contiguous values); returns its offset.
fn push_panels(
    data: &mut Vec<f64>,
    m: usize,
    n: usize,
    entry: impl Fn(usize, usize) -> f64,
) -> usize {
    let start = data.len();
    for (r0, height) in panel_schedule(m) {
        for c in 0..n {
            data.extend((0..height).map(|l| entry(r0 + l, c)));
        }
    }
    start
}

/// acc[l] += Σ_c panel[c][l]·v[c] with even and odd columns summed separately (two
/// independent chains hide the add latency) and then added: each row's sum has a fixed
/// order whatever the vector width, and the accumulators stay in registers.
#[inline(always)]
fn panel_accumulate<const H: usize>(acc: &mut [f64; H], panel: &[f64], v: &[f64]) {
    let mut odd = [0.0; H];
    let mut pairs = panel.chunks_exact(2 * H);
    let mut vs = v.chunks_exact(2);
    for (cols, vv) in (&mut pairs).zip(&mut vs) {
        let (v0, v1) = (vv[0], vv[1]);
        for l in 0..H {
            acc[l] += cols[l] * v0;
            odd[l] += cols[H + l] * v1;
        }
    }
    if let (Some(&vc), Some(col)) = (vs.remainder().first(), pairs.remainder().get(..H)) {
        for l in 0..H {
            acc[l] += col[l] * vc;
        }
    }
    for l in 0..H {
        acc[l] += odd[l];
    }
}

/// One row panel of a leaf: dst = D·x (triangle part) + U·ŷ.
#[inline(always)]
fn leaf_panel<const H: usize>(dense: &[f64], xs: &[f64], low: &[f64], ys: &[f64], dst: &mut [f64]) {
    let mut acc = [0.0; H];
    panel_accumulate(&mut acc, dense, xs);
    panel_accumulate(&mut acc, low, ys);
    let dst: &mut [f64; H] = dst.try_into().expect("panel height");
    *dst = acc;
}

/// One row panel of a small matrix: dst (=|+=) M·v.
#[inline(always)]
fn gemv_panel<const H: usize>(panel: &[f64], v: &[f64], dst: &mut [f64], accumulate: bool) {
    let mut acc = [0.0; H];
    panel_accumulate(&mut acc, panel, v);
    let dst: &mut [f64; H] = dst.try_into().expect("panel height");
    if accumulate {
        for l in 0..H {
            dst[l] += acc[l];
        }
    } else {
        *dst = acc;
    }
}

/// out[..rows] = M·v (or += when `accumulate`), M in the panel layout of [`push_panels`].
#[inline(always)]
fn gemv(data: &[f64], g: &Gemv, v: &[f64], out: &mut [f64], accumulate: bool) {
    let v = &v[..g.cols];
    let mut off = g.data;
    for (r0, height) in panel_schedule(g.rows) {
        let len = height * g.cols;
        let panel = &data[off..off + len];
        off += len;
        let dst = &mut out[r0..r0 + height];
        match height {
            8 => gemv_panel::<8>(panel, v, dst, accumulate),
            4 => gemv_panel::<4>(panel, v, dst, accumulate),
            2 => gemv_panel::<2>(panel, v, dst, accumulate),
            _ => gemv_panel::<1>(panel, v, dst, accumulate),
        }
    }
}

/// A posteriori bound B of ‖A − Ã‖₂ from the singular values each truncation dropped.
///
/// A node's basis error e (spectral norm of the part of its off-diagonal block outside
/// the basis) obeys e_τ² ≤ e₁² + e₂² + δ_τ², δ_τ its own largest dropped σ (the children's
/// errors and the parent's truncation lie in orthogonal subspaces); a sibling block's
/// error is ≤ e_row(target) + e_col(source); blocks at one depth occupy disjoint rows and
/// columns, so their errors combine as a maximum, and depths add up.
fn error_bound(
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
