//! The apply cut at the root into its two halves, for two threads: each half's leaves, up
//! and down passes touch only that half's rows and coefficients, and the root's one sibling
//! block is the only thing that crosses (the source child's r coefficients, copied).
//!
//! Why: at N = 2000 the two transforms' factors are about 2.4 MB, more than one core's
//! 2 MB L2, so a whole apply streams them from L3; each half's are about 1.2 MB and stay in
//! their core's L2. Every output element is summed by the same panels in the same order as
//! the whole apply, so the bits are the same (checked by the tests).

use super::{HodlrOperator, HodlrScratch, TreeNode, Triangle};
use faer::traits::pulp::Arch;

/// Which half of the root's index range, [0, mid) or [mid, N).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Half {
    /// Rows [0, mid): the root's first child.
    First,
    /// Rows [mid, N): the root's second child.
    Second,
}

impl Half {
    fn index(self) -> usize {
        match self {
            Half::First => 0,
            Half::Second => 1,
        }
    }
}

/// Where the packed lists divide between the halves (set by `pack`).
#[derive(Debug, Clone)]
pub(super) struct Split {
    /// The first row of the second half.
    pub mid: usize,
    /// `leaf_in` and `leaf_out`: the first half's leaves are [0, first_leaves).
    pub first_leaves: usize,
    /// `up` (children before parents, i.e. reversed pre-order): the second half's
    /// internal nodes are [0, up_second), the first half's [up_second, up_first_end), and
    /// the root last.
    pub up_second: usize,
    pub up_first_end: usize,
    /// `down` (parents first, pre-order): the root at 0, the first half's internal nodes
    /// [1, down_first_end), the second half's after.
    pub down_first_end: usize,
    /// Each child's x̂ (offset, rank) in the coefficient scratch.
    pub child_x: [(usize, usize); 2],
    /// Each child's ŷ (offset, rank).
    pub child_y: [(usize, usize); 2],
    /// The child the root's sibling block writes to (the other is its source).
    pub target: Half,
}

impl Split {
    /// The cut of a packed operator, if its root has two children and no basis of its own
    /// (an operator's root has no off-diagonal block: its bases are empty).
    pub fn of(
        tree: &[TreeNode],
        triangle: Triangle,
        (x_off, y_off): (&[usize], &[usize]),
        (row_rank, col_rank): (&[usize], &[usize]),
    ) -> Option<Self> {
        let (a, b) = tree.first()?.children?;
        if row_rank[0] != 0 || col_rank[0] != 0 {
            return None;
        }
        let mid = tree[a].hi;
        let in_first = |t: &TreeNode| t.hi <= mid;
        let leaves = || tree.iter().filter(|t| t.children.is_none());
        let internals = || tree.iter().skip(1).filter(|t| t.children.is_some());
        Some(Self {
            mid,
            first_leaves: leaves().filter(|t| in_first(t)).count(),
            up_second: internals().filter(|t| !in_first(t)).count(),
            up_first_end: internals().count(),
            down_first_end: 1 + internals().filter(|t| in_first(t)).count(),
            child_x: [(x_off[a], col_rank[a]), (x_off[b], col_rank[b])],
            child_y: [(y_off[a], row_rank[a]), (y_off[b], row_rank[b])],
            target: match triangle {
                Triangle::Upper => Half::First,
                Triangle::Lower => Half::Second,
            },
        })
    }
}

/// A part of the apply that one thread runs.
#[derive(Debug, Clone, Copy)]
pub(super) enum Part {
    /// The half's leaves and up pass: its child's x̂.
    Up(Half),
    /// The half's down pass and leaves, after its child's ŷ is set: zero, plus the root's
    /// sibling block when this half is its target (the source's x̂ in place by then).
    Down(Half),
}

impl HodlrOperator {
    /// The row where the apply splits, if it can ([`Self::apply_up`] and
    /// [`Self::apply_down`]); `None` for an operator of one leaf.
    pub fn split_row(&self) -> Option<usize> {
        self.split.as_ref().map(|s| s.mid)
    }

    /// The half that the root's sibling block writes to; the other half's x̂ must be copied
    /// into its scratch ([`Self::child_coefficients`]) between [`Self::apply_up`] and
    /// [`Self::apply_down`].
    ///
    /// # Panics
    /// If the operator does not split ([`Self::split_row`] is `None`).
    pub fn split_target(&self) -> Half {
        self.split.as_ref().expect("a split operator").target
    }

    /// The x̂ coefficients of `half`'s child in a scratch (what the other half needs).
    ///
    /// # Panics
    /// If the operator does not split.
    pub fn child_coefficients<'s>(&self, half: Half, scratch: &'s HodlrScratch) -> &'s [f64] {
        let (off, len) = self.split.as_ref().expect("a split operator").child_x[half.index()];
        &scratch.x_coeff[off..off + len]
    }

    /// Writable x̂ coefficients of `half`'s child (where the other half copies them).
    ///
    /// # Panics
    /// If the operator does not split.
    pub fn child_coefficients_mut<'s>(
        &self,
        half: Half,
        scratch: &'s mut HodlrScratch,
    ) -> &'s mut [f64] {
        let (off, len) = self.split.as_ref().expect("a split operator").child_x[half.index()];
        &mut scratch.x_coeff[off..off + len]
    }

    /// The first part of a split apply: reads x on `half`'s rows only and sets that half's
    /// coefficients in `scratch`.
    ///
    /// # Panics
    /// If the operator does not split, or on wrong lengths as [`Self::apply`].
    #[track_caller]
    pub fn apply_up(&self, half: Half, x: &[f64], scratch: &mut HodlrScratch) {
        self.apply_part(Part::Up(half), x, &mut [], scratch);
    }

    /// The second part of a split apply: writes y on `half`'s rows only (x is read on them
    /// too). The target half needs the source's x̂ in its scratch first.
    ///
    /// # Panics
    /// As [`Self::apply_up`].
    #[track_caller]
    pub fn apply_down(&self, half: Half, x: &[f64], y: &mut [f64], scratch: &mut HodlrScratch) {
        self.apply_part(Part::Down(half), x, y, scratch);
    }

    #[track_caller]
    fn apply_part(&self, part: Part, x: &[f64], y: &mut [f64], scratch: &mut HodlrScratch) {
        assert!(self.split.is_some(), "this operator does not split");
        assert_eq!(x.len(), self.n, "input length must equal the node count");
        if matches!(part, Part::Down(_)) {
            assert_eq!(y.len(), self.n, "output length must equal the node count");
        }
        assert!(
            scratch.x_coeff.len() >= self.x_coeff_len && scratch.y_coeff.len() >= self.y_coeff_len,
            "scratch was made for another operator"
        );
        self.dispatch(Arch::new(), Some(part), x, y, scratch);
    }

    /// The part's passes (see [`Part`]); inlined into the dispatched kernel.
    #[inline(always)]
    pub(super) fn apply_split_part(
        &self,
        part: Part,
        x: &[f64],
        y: &mut [f64],
        scratch: &mut HodlrScratch,
    ) {
        let s = self.split.as_ref().expect("a split operator");
        let xc = &mut scratch.x_coeff[..];
        let yc = &mut scratch.y_coeff[..];
        match part {
            Part::Up(half) => {
                let (leaves, up) = match half {
                    Half::First => (0..s.first_leaves, s.up_second..s.up_first_end),
                    Half::Second => (s.first_leaves..self.leaf_in.len(), 0..s.up_second),
                };
                self.leaves_in(&self.leaf_in[leaves], x, xc);
                self.up_pass(&self.up[up], xc);
            }
            Part::Down(half) => {
                let (off, len) = s.child_y[half.index()];
                yc[off..off + len].fill(0.0);
                if half == s.target {
                    let (_, couple) = &self.down[0];
                    self.couple(couple, xc, yc);
                }
                let (down, leaves) = match half {
                    Half::First => (1..s.down_first_end, 0..s.first_leaves),
                    Half::Second => (
                        s.down_first_end..self.down.len(),
                        s.first_leaves..self.leaf_out.len(),
                    ),
                };
                self.down_pass(&self.down[down], xc, yc);
                self.leaves_out(&self.leaf_out[leaves], x, yc, y);
            }
        }
    }
}
