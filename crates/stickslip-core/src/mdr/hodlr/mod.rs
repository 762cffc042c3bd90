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

mod apply;
mod compress;

use super::{Triangle, TriangularOperator};
use apply::{Gemv, LeafOut};
use compress::{BasisPass, Coupler, error_bound, norm_lower_bound};
use faer::Mat;
use faer::traits::pulp::Arch;

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
    /// Every small matrix of the apply, in the panel layout of `apply::gemv`.
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
}
