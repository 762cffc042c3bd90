//! Hierarchical low-rank form of the triangular MDR operators: memory and apply O(N·r)
//! (r the rank, growing like log N), built from entries computed on demand
//! ([`OperatorEntries`]) without ever forming the dense matrix.
//!
//! Why: the dense mat-vec of [`TriangularOperator`] streams N²/2 entries per apply
//! (16 MB, about 330 µs at N = 2000), while the Abel kernel 1/√(r² − x²) is smooth away
//! from r = x, so every off-diagonal block is numerically of low rank (11–17 at
//! `rel_tol` 1e-10 for N ≤ 2000, 19 at N = 8000, 21 at N = 20000: growing like log N).
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
//! # Build
//! Two stages, neither touching more than O(N·log N) entries nor holding more than the
//! factors (O(N·r) values, plus O(r·log N) per level of the recursion):
//!
//! 1. **Skeletons** (`skeleton.rs`): for every node, children first, an interpolative
//!    decomposition of its block row from *sampled* columns — every column within
//!    16 nodes of the node's boundary, then 10 Chebyshev points per octave of distance
//!    (the kernel, seen from the boundary, is smooth on each octave), and the range's far
//!    end. A pivoted QR of those samples picks skeleton rows J_τ among the node's
//!    candidates (a leaf's rows, or its children's skeletons) with
//!    A[I, ·] ≈ T·A[J_τ, ·]; the same for columns. The interpolation matrices are nested
//!    by construction, and a sibling block is coupled by the plain entries
//!    A[J_target, J_source]. About 190 sampled entries per row of the operator (both
//!    sides together) at N = 2000 and 330 at N = 20000, against N/2 for a dense row. The threshold of this stage is 0.1·`rel_tol`·ν₀
//!    (ν₀ ≤ ‖A‖₂ the source's cheap bound), so that the next stage sets the ranks.
//! 2. **Recompression** (`recompress.rs`): the skeleton form is made orthonormal (QR of
//!    the nested bases, the triangular factors moved into the couplings), ν is estimated
//!    by power iteration on it, and every basis is truncated at t = `rel_tol`·ν by SVDs of
//!    small matrices: the node's block row, known through the couplings and its
//!    ancestors' transfers (a top-down pass of Gram factors), projected on its children's
//!    truncated bases. Only r × r matrices are touched.
//!
//! The samples are read through [`OperatorEntries::row_into_accurate`]: the product
//! operators' closed-form weights cancel by a factor up to (N)², so at large N their
//! rounding noise (7e-8 of an entry at N = 20000) would dominate any sampled block and
//! no sampling can reproduce it; the accurate weights (Gauss rules where the cell is
//! away from the singular point) are exact to ~1e-15 and give ranks 19 at N = 8000, 21
//! at N = 20000 and 24 at N = 200000 (the noisy ones 70–100 already at N = 8000). The
//! leaves' dense triangles are the dense builders' bits.
//!
//! Time (forward and back, release, one thread; about half with two): 0.07 s at
//! N = 2000, 0.35 s at 8000, 1.2 s at 20000, 13 s at 200000; peak memory 52 MB at
//! N = 20000 and 0.44 GB at 200000 (of which the factors: 22 MB and 0.21 GB).
//! Deterministic: sequential loops in a fixed order; independent parts (forward and
//! back, row and column sides) may run on two threads with the same result. faer's SVD
//! and matrix products are dispatched by instruction set, so the factors (not the
//! apply's bits given the factors) may differ in the last bits between CPUs, as before.
//!
//! # Accuracy
//! [`HodlrOperator::error_bound`] B states ‖A x − Ã x‖₂ ≲ B·‖x‖₂ = C·`rel_tol`·ν·‖x‖₂
//! ([`HodlrOperator::error_bound_factor`]), the sum of two parts:
//! - the **truncation**, bounded rigorously (relative to the skeleton form) by the largest
//!   singular value dropped at every node: a node's basis error e obeys
//!   e_τ² ≤ e₁² + e₂² + δ_τ², a sibling block's error is ≤ e_row(target) + e_col(source),
//!   blocks at one depth are disjoint and depths add up;
//! - the **skeleton stage**, *estimated* by the same formula from the interpolation
//!   residuals on the sampled columns ([`HodlrOperator::skeleton_error_estimate`]): not a
//!   bound, since unsampled columns are not seen (and it ignores the norms of the
//!   interpolation matrices); it is about a tenth of the truncation part.
//!
//! C is 2–3 at N = 125, about 25 at N = 2000, 50 at N = 8000, 110 at N = 20000 and 300
//! at N = 200000 (the nested truncation errors may add up over the subtree of a node).
//! Measured against the dense operators (explicit Ã, power iteration on A − Ã)
//! ‖A − Ã‖₂ is 0.1–0.8·`rel_tol`·ν for N ≤ 125 (about half of C there) and
//! 1–4·`rel_tol`·ν for N = 1000–4000, and errors on random vectors stay below
//! 0.15·`rel_tol`·ν·‖x‖₂ (the tests check 0.5). The same threshold at every node (rather
//! than smaller ones for small nodes, which would give C ≈ 10 independent of N) keeps the
//! ranks of the many small nodes low.
//!
//! The product operators' dense builders carry rounding noise of their own,
//! ‖A_dense − A_exact‖₂ ≈ 3e-11·‖A‖₂ at N = 2000 and growing like N^1.5, which the fast
//! form does not follow (it approximates the exact weights): at `rel_tol` 1e-12 its
//! difference to the dense operator is that noise, not the compression; at
//! [`crate::mdr::FAST_REL_TOL`] and N ≤ 4000 it is negligible.
//!
//! # Apply
//! [`HodlrOperator::apply`]: leaves (x̂ = Vᵀx) → up the tree (x̂_τ = Fᵀ[x̂₁; x̂₂]) → down
//! (ŷ = E ŷ_parent + B x̂_sibling) → leaves (y = D x + U ŷ). Every small matrix is stored
//! in row panels of 8/4/2/1 rows, column after column, all in one Vec in the order the
//! apply reads them, so one apply streams through memory once; each output row has its
//! own accumulator (even and odd columns, then added), so the sums have a fixed order.
//! The kernel is dispatched at run time to AVX-512 or AVX2 where the CPU has them (pulp,
//! re-exported by faer); it uses no fused multiply-add, so the result is bit-identical on every
//! instruction set and every call ([`HodlrOperator::apply_portable`] checks this).
//! Single-threaded and allocation-free: intermediate coefficients live in a
//! caller-owned [`HodlrScratch`], so the operator stays immutable and shareable.

mod apply;
mod dense;
mod recompress;
mod skeleton;
mod split;
mod transpose;

pub use split::Half;

use super::{OperatorEntries, Triangle, TriangularOperator};
use apply::{Gemv, LeafOut};
use dense::matmul;
use faer::Mat;
use faer::traits::pulp::Arch;
use recompress::{Bases, Hss, error_bound, orthonormalize, truncate, weights};
use skeleton::SkeletonPass;

/// Largest leaf (rows of a dense diagonal block). Leaf triangles cost about leaf/2 per
/// row, transfers about 5r²/leaf: measured against 16 and 64, 32 is the fastest at
/// N = 2000 and as fast at N = 8000.
pub const LEAF_MAX_ROWS: usize = 32;

/// Power-iteration steps of the norm estimate ν (each is one Ã and one Ãᵀ apply).
const NORM_ITERATIONS: usize = 4;

/// Threshold of the skeleton stage relative to the final truncation's (`rel_tol`·ν₀, ν₀
/// the entries' cheap lower bound of ‖A‖₂): its error stays a small part of the total,
/// and the truncation, not the sampling, sets the ranks.
const SKELETON_REL_TOL: f64 = 0.1;

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

impl HodlrScratch {
    /// Length of its x̂ coefficients (every node's column-basis coefficients).
    pub fn coefficient_len(&self) -> usize {
        self.x_coeff.len()
    }
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
    /// B of ‖A − Ã‖₂ ≲ B: the truncation's bound plus the skeleton estimate (operator units).
    error_bound: f64,
    /// The skeleton stage's part of `error_bound`, estimated from sampled residuals.
    skeleton_error: f64,
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
    /// Where the apply divides between two threads ([`split`]).
    split: Option<split::Split>,
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
    /// [`Self::build`] from the stored entries of a dense packed operator (read only where
    /// the build samples). Its rounding noise is sampled too, so for the product
    /// operators below their noise floor (`rel_tol` ≲ 1e-11 at N = 2000) build from
    /// [`crate::mdr::product::ForwardEntries`] and [`crate::mdr::product::BackEntries`]
    /// instead, which sample accurate entries.
    ///
    /// # Panics
    /// As [`Self::build`].
    pub fn compress(op: &TriangularOperator, rel_tol: f64) -> Self {
        Self::build(op, rel_tol)
    }

    /// Builds the hierarchical form of the operator whose entries `entries` computes,
    /// reading O(N·log N) of them (see "Build" in the module docs), truncated at
    /// `rel_tol`·ν (ν ≤ ‖Ã‖₂ a power-iteration estimate): ‖A x − Ã x‖₂ ≲ C·`rel_tol`·ν·‖x‖₂
    /// with C = [`Self::error_bound_factor`] (see "Accuracy" for what is bounded and what
    /// is estimated). `rel_tol` = 0 keeps every non-zero singular value of what the
    /// samples see. N ≤ [`LEAF_MAX_ROWS`] gives the exact dense operator.
    ///
    /// # Panics
    /// If `rel_tol` is negative or not finite, or if an SVD fails to converge.
    pub fn build<E: OperatorEntries + Sync + ?Sized>(entries: &E, rel_tol: f64) -> Self {
        assert!(
            rel_tol.is_finite() && rel_tol >= 0.0,
            "rel_tol = {rel_tol} must be finite and >= 0"
        );
        let n = entries.size();
        let triangle = entries.triangle();
        let tree = build_tree(n);
        let nodes = tree.len();
        let (row_side, col_side, target_is_second) = match triangle {
            Triangle::Lower => (Side::Left, Side::Right, true),
            Triangle::Upper => (Side::Right, Side::Left, false),
        };
        let diagonal: Vec<Mat<f64>> = tree
            .iter()
            .map(|t| match t.children {
                Some(_) => Mat::zeros(0, 0),
                None => dense_block(entries, t.lo, t.hi),
            })
            .collect();
        let mut out = Self::unpacked(n, triangle, rel_tol);
        if n <= LEAF_MAX_ROWS {
            // One dense leaf: exact, no bases.
            let none = || Bases {
                rank: vec![0; nodes],
                factor: vec![Mat::zeros(0, 0); nodes],
            };
            let (rows, cols) = (none(), none());
            let hss = Hss {
                tree: &tree,
                diagonal: &diagonal,
                rows: &rows,
                cols: &cols,
                couplings: &[],
                target_is_second,
            };
            out.norm_estimate = hss.norm_estimate(n, NORM_ITERATIONS);
            out.pack(&tree, &diagonal, &rows, &cols, &[]);
            return out;
        }

        // 1. Skeletons from sampled entries (see `skeletons`).
        let (mut rows, mut cols, mut couplings, skeleton_error) = skeletons(
            entries,
            &tree,
            (row_side, col_side, target_is_second),
            rel_tol,
        );
        out.skeleton_error = skeleton_error;

        // 2. Orthonormal bases (couplings absorb the triangular factors), the norm, and
        //    the truncation to rel_tol·ν of the small factors.
        let (r_rows, r_cols) = rayon::join(
            || orthonormalize(&tree, &mut rows),
            || orthonormalize(&tree, &mut cols),
        );
        for (id, node) in tree.iter().enumerate() {
            if let Some((a, b)) = node.children {
                let (target, source) = if target_is_second { (b, a) } else { (a, b) };
                let left = matmul(r_rows[target].as_ref(), couplings[id].as_ref());
                couplings[id] = matmul(left.as_ref(), r_cols[source].transpose());
            }
        }
        drop((r_rows, r_cols));
        let hss = Hss {
            tree: &tree,
            diagonal: &diagonal,
            rows: &rows,
            cols: &cols,
            couplings: &couplings,
            target_is_second,
        };
        out.norm_estimate = hss.norm_estimate(n, NORM_ITERATIONS);
        let threshold = rel_tol * out.norm_estimate;
        let side = |bases: Bases, transpose: bool| {
            let w = weights(&tree, &bases, &couplings, target_is_second, transpose);
            truncate(&tree, bases, w, threshold)
        };
        let (new_rows, new_cols) = rayon::join(|| side(rows, false), || side(cols, true));
        for (id, node) in tree.iter().enumerate() {
            if let Some((a, b)) = node.children {
                let (target, source) = if target_is_second { (b, a) } else { (a, b) };
                let left = matmul(
                    new_rows.projection[target].transpose(),
                    couplings[id].as_ref(),
                );
                couplings[id] = matmul(left.as_ref(), new_cols.projection[source].as_ref());
            }
        }
        out.error_bound = out.skeleton_error
            + error_bound(
                &tree,
                &new_rows.dropped,
                &new_cols.dropped,
                target_is_second,
            );
        out.pack(
            &tree,
            &diagonal,
            &new_rows.bases,
            &new_cols.bases,
            &couplings,
        );
        out
    }

    /// An operator of size `n` with nothing packed yet (what [`Self::build`] fills).
    fn unpacked(n: usize, triangle: Triangle, rel_tol: f64) -> Self {
        Self {
            n,
            triangle,
            rel_tol,
            norm_estimate: 0.0,
            error_bound: 0.0,
            skeleton_error: 0.0,
            data: Vec::new(),
            single_leaf: false,
            leaf_in: Vec::new(),
            up: Vec::new(),
            down: Vec::new(),
            leaf_out: Vec::new(),
            x_coeff_len: 0,
            y_coeff_len: 0,
            profile: Vec::new(),
            split: None,
        }
    }

    /// Matrix size N.
    pub fn size(&self) -> usize {
        self.n
    }

    /// The triangle of the operator it was compressed from.
    pub fn triangle(&self) -> Triangle {
        self.triangle
    }

    /// The relative tolerance it was built with.
    pub fn rel_tol(&self) -> f64 {
        self.rel_tol
    }

    /// ν, the power-iteration lower bound of ‖Ã‖₂ (≈ ‖A‖₂) of the skeleton form that the
    /// truncation threshold was scaled by (units of the operator: N/m per Pa for the
    /// forward, m/m for the back operator).
    pub fn norm_estimate(&self) -> f64 {
        self.norm_estimate
    }

    /// B in ‖A x − Ã x‖₂ ≲ B·‖x‖₂ (rounding aside, operator units): the truncation's
    /// rigorous bound from the singular values that were dropped, plus
    /// [`Self::skeleton_error_estimate`] (see "Accuracy" in the module docs).
    pub fn error_bound(&self) -> f64 {
        self.error_bound
    }

    /// The skeleton stage's part of [`Self::error_bound`] (operator units): an estimate
    /// from the interpolation residuals on the sampled entries, not a bound.
    pub fn skeleton_error_estimate(&self) -> f64 {
        self.skeleton_error
    }

    /// C = B/(`rel_tol`·ν) in ‖A x − Ã x‖₂ ≲ C·`rel_tol`·ν·‖x‖₂; 0 when nothing
    /// was dropped. A priori (every dropped σ at the threshold) the truncation part is the
    /// sum over depths of √(nodes under the target child) + √(nodes under the source
    /// child), 45 at N = 2000 and 100 at N = 8000; the recorded values give about half
    /// that, plus about a tenth for the skeleton estimate.
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

/// The leaf's diagonal block A[lo..hi, lo..hi] (zeros outside the triangle), with the
/// dense builder's bits.
fn dense_block<E: OperatorEntries + ?Sized>(entries: &E, lo: usize, hi: usize) -> Mat<f64> {
    let idx: Vec<usize> = (lo..hi).collect();
    entry_block(entries, &idx, &idx, false)
}

/// A[rows, cols] for increasing index lists, from the accurate entries (off-diagonal
/// blocks) or the dense builder's.
fn entry_block<E: OperatorEntries + ?Sized>(
    entries: &E,
    rows: &[usize],
    cols: &[usize],
    accurate: bool,
) -> Mat<f64> {
    let mut block = Mat::<f64>::zeros(rows.len(), cols.len());
    let mut buf = vec![0.0; cols.len()];
    for (r, &i) in rows.iter().enumerate() {
        if accurate {
            entries.row_into_accurate(i, cols, &mut buf);
        } else {
            entries.row_into(i, cols, &mut buf);
        }
        for (c, &v) in buf.iter().enumerate() {
            block[(r, c)] = v;
        }
    }
    block
}

/// Step 1 of [`HodlrOperator::build`]: the row and column skeletons from sampled entries, at a
/// threshold well below the final one (scaled by a cheap lower bound of ‖A‖₂, so never looser
/// than intended): the interpolation bases, the couplings between skeletons, and the bound of
/// the skeletons' error.
fn skeletons<E: OperatorEntries + Sync + ?Sized>(
    entries: &E,
    tree: &[TreeNode],
    (row_side, col_side, target_is_second): (Side, Side, bool),
    rel_tol: f64,
) -> (Bases, Bases, Vec<Mat<f64>>, f64) {
    let nodes = tree.len();
    // 1. Skeletons from sampled entries, at a threshold well below the final one
    //    (scaled by a cheap lower bound of ‖A‖₂, so never looser than intended).
    let skeleton_threshold = SKELETON_REL_TOL * rel_tol * entries.norm_lower_bound();
    // Independent passes: run side by side where threads are free (same bits either way).
    let (row_skel, col_skel) = rayon::join(
        || SkeletonPass::new(entries, tree, row_side, false, skeleton_threshold).run(),
        || SkeletonPass::new(entries, tree, col_side, true, skeleton_threshold).run(),
    );
    let mut couplings = vec![Mat::zeros(0, 0); nodes];
    for (id, node) in tree.iter().enumerate() {
        if let Some((a, b)) = node.children {
            let (target, source) = if target_is_second { (b, a) } else { (a, b) };
            couplings[id] = entry_block(
                entries,
                &row_skel.index[target],
                &col_skel.index[source],
                true,
            );
        }
    }
    let skeleton_error = error_bound(
        tree,
        &row_skel.residual,
        &col_skel.residual,
        target_is_second,
    );
    // Only the interpolation matrices go on (the skeleton indices are spent).
    let rows = Bases {
        rank: row_skel.rank,
        factor: row_skel.factor,
    };
    let cols = Bases {
        rank: col_skel.rank,
        factor: col_skel.factor,
    };
    drop((row_skel.index, col_skel.index));
    (rows, cols, couplings, skeleton_error)
}
