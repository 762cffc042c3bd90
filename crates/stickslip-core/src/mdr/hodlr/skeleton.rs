//! First stage of the build: nested interpolative decompositions (skeletons) of the
//! off-diagonal block rows and columns, from sampled entries (see "Build" in the module
//! docs).
//!
//! For every node τ (children first) the candidate rows are the node's indices (leaf) or
//! the union of its children's skeleton rows; their entries are read only at sampled
//! columns S_τ of the node's off-diagonal range, and a pivoted QR picks skeleton rows J_τ
//! with M[C_τ, ·] ≈ T_τ·M[J_τ, ·]. The interpolation matrices T are nested by construction
//! (a parent interpolates from its children's skeletons), so they are the leaf bases and
//! transfers of an HSS form whose sibling couplings are plain entries A[J_target, J_source].

use super::dense::pivoted_qr;
use super::{Side, TreeNode};
use crate::mdr::OperatorEntries;
use faer::Mat;

/// Distances from a node's boundary (in nodes) up to which every index of the range is
/// sampled: the kernel 1/√(r² − x²) is singular at the boundary, so entries there are no
/// smooth function of the index.
pub(super) const NEAR_ALL: usize = 16;

/// Sampled indices per octave of distance beyond [`NEAR_ALL`] (Chebyshev points of the
/// octave [L, 2L], both ends included). Seen from the boundary the kernel is analytic on
/// an octave with its singularity one octave length away, so the octave's columns are
/// close to polynomials of low degree in the index (interpolation error ≈ 5.8^−p of the
/// octave's entries), and the block row's range, of rank ~20 over all octaves together,
/// is caught long before that bound: measured against the dense operators for
/// N ≤ 4000, 10 points give ‖A − Ã‖₂ within 2–4·`rel_tol`·ν, 14 points 1.5–2, 6 points
/// 2.5–5, at 10–30 % more or less build time.
pub(super) const SAMPLES_PER_OCTAVE: usize = 10;

/// Sampled indices of a node's off-diagonal range, increasing: every index within
/// [`NEAR_ALL`] of the boundary, Chebyshev points of each further octave of distance, and
/// the far end of the range (the first or last node, whose weights follow special rules).
pub(super) fn samples(side: Side, boundary: usize, n: usize) -> Vec<usize> {
    let len = match side {
        Side::Left => boundary,
        Side::Right => n - boundary,
    };
    if len == 0 {
        return Vec::new();
    }
    // Distances d = 1..=len from the boundary.
    let mut dist: Vec<usize> = (1..=NEAR_ALL.min(len)).collect();
    let mut lower = NEAR_ALL;
    while lower < len {
        let upper = (2 * lower).min(len);
        let width = (upper - lower) as f64;
        for q in 0..SAMPLES_PER_OCTAVE {
            let angle = std::f64::consts::PI * q as f64 / (SAMPLES_PER_OCTAVE - 1) as f64;
            let d = lower as f64 + width * 0.5 * (1.0 - angle.cos());
            dist.push(d.round() as usize);
        }
        lower = upper;
    }
    dist.push(len);
    let mut idx: Vec<usize> = dist
        .into_iter()
        .map(|d| match side {
            Side::Left => boundary - d,
            Side::Right => boundary + d - 1,
        })
        .collect();
    idx.sort_unstable();
    idx.dedup();
    idx
}

/// The nested skeletons of one side (rows of M = A, or of M = Aᵀ for columns).
#[derive(Debug)]
pub(super) struct Skeleton {
    /// k_τ, the number of skeleton indices.
    pub rank: Vec<usize>,
    /// Leaf: T (size × k); internal: the transfer T ((k₁ + k₂) × k) from the children's
    /// skeletons; the root and nodes with an empty range have k = 0.
    pub factor: Vec<Mat<f64>>,
    /// J_τ, increasing.
    pub index: Vec<Vec<usize>>,
    /// ‖M[C, S] − T·M[J, S]‖_F on the samples S.
    pub residual: Vec<f64>,
}

/// One bottom-up pass over the tree.
pub(super) struct SkeletonPass<'a, E: ?Sized> {
    pub entries: &'a E,
    pub tree: &'a [TreeNode],
    pub side: Side,
    /// M = Aᵀ (column skeletons) rather than M = A.
    pub transposed: bool,
    /// Frobenius threshold of every interpolative decomposition (operator units).
    pub threshold: f64,
    pub out: Skeleton,
}

/// M[J_τ, S_τ], the sampled rows of a node's skeleton, handed to the parent, which has
/// the same samples when it shares the child's boundary.
struct Kept {
    values: Mat<f64>,
}

impl<E: OperatorEntries + ?Sized> SkeletonPass<'_, E> {
    pub fn new<'a>(
        entries: &'a E,
        tree: &'a [TreeNode],
        side: Side,
        transposed: bool,
        threshold: f64,
    ) -> SkeletonPass<'a, E> {
        let nodes = tree.len();
        SkeletonPass {
            entries,
            tree,
            side,
            transposed,
            threshold,
            out: Skeleton {
                rank: vec![0; nodes],
                factor: vec![Mat::zeros(0, 0); nodes],
                index: vec![Vec::new(); nodes],
                residual: vec![0.0; nodes],
            },
        }
    }

    pub fn run(mut self) -> Skeleton {
        if !self.tree.is_empty() {
            self.visit(0);
        }
        self.out
    }

    fn boundary(&self, id: usize) -> usize {
        match self.side {
            Side::Left => self.tree[id].lo,
            Side::Right => self.tree[id].hi,
        }
    }

    /// G[s, c] = M(rows[c], cols[s]) into columns `c0..` of `g` (G = M[rows, cols]ᵀ, so a
    /// candidate's samples are one contiguous column).
    fn fetch(&self, rows: &[usize], cols: &[usize], g: &mut Mat<f64>, c0: usize) {
        if self.transposed {
            // M(r, s) = A(s, r): one row of A per sample, over the candidates.
            let mut buf = vec![0.0; rows.len()];
            for (s, &col) in cols.iter().enumerate() {
                self.entries.row_into_accurate(col, rows, &mut buf);
                for (c, &v) in buf.iter().enumerate() {
                    g[(s, c0 + c)] = v;
                }
            }
        } else {
            for (c, &row) in rows.iter().enumerate() {
                self.entries
                    .row_into_accurate(row, cols, g.col_as_slice_mut(c0 + c));
            }
        }
    }

    fn visit(&mut self, id: usize) -> Kept {
        let node = &self.tree[id];
        let (lo, hi) = (node.lo, node.hi);
        let n = self.entries.size();
        let cols = samples(self.side, self.boundary(id), n);
        let (cand, g) = match node.children {
            None => {
                let cand: Vec<usize> = (lo..hi).collect();
                let mut g = Mat::<f64>::zeros(cols.len(), cand.len());
                self.fetch(&cand, &cols, &mut g, 0);
                (cand, g)
            }
            Some((a, b)) => {
                let kept_a = self.visit(a);
                let kept_b = self.visit(b);
                let (ka, kb) = (self.out.rank[a], self.out.rank[b]);
                let mut cand = self.out.index[a].clone();
                cand.extend_from_slice(&self.out.index[b]);
                let mut g = Mat::<f64>::zeros(cols.len(), ka + kb);
                // The child on the parent's boundary was sampled at the same indices.
                let (shared, shared_off, other, other_off) = match self.side {
                    Side::Left => (kept_a, 0, b, ka),
                    Side::Right => (kept_b, ka, a, 0),
                };
                debug_assert_eq!(shared.values.nrows(), cols.len());
                for c in 0..shared.values.ncols() {
                    g.col_as_slice_mut(shared_off + c)
                        .copy_from_slice(shared.values.col_as_slice(c));
                }
                let other_rows = self.out.index[other].clone();
                self.fetch(&other_rows, &cols, &mut g, other_off);
                (cand, g)
            }
        };
        let m = cand.len();
        if cols.is_empty() || m == 0 {
            self.out.factor[id] = Mat::zeros(m, 0);
            return Kept {
                values: Mat::zeros(cols.len(), 0),
            };
        }
        let qr = pivoted_qr(g.clone(), self.threshold);
        let k = qr.rank;
        // Skeleton positions in increasing order (so J_τ stays sorted), and where each
        // pivot column lands among them.
        let mut chosen: Vec<usize> = qr.perm[..k].to_vec();
        chosen.sort_unstable();
        let slot = |pos: usize| chosen.binary_search(&pos).expect("a chosen column");
        let mut t = Mat::<f64>::zeros(m, k);
        for &pos in &chosen {
            t[(pos, slot(pos))] = 1.0;
        }
        for q in 0..m - k {
            let pos = qr.perm[k + q];
            for i in 0..k {
                t[(pos, slot(qr.perm[i]))] = qr.x[(i, q)];
            }
        }
        let values = Mat::from_fn(cols.len(), k, |s, c| g[(s, chosen[c])]);
        self.out.rank[id] = k;
        self.out.index[id] = chosen.iter().map(|&p| cand[p]).collect();
        self.out.residual[id] = qr.residual;
        self.out.factor[id] = t;
        Kept { values }
    }
}
