//! Packing of the factors into one panel-layout Vec, and the apply kernels (see the
//! "Apply" section of the module docs).

use super::recompress::Bases;
use super::split::{Part, Split};
use super::{HodlrOperator, HodlrScratch, LEAF_MAX_ROWS, RankLevel, TreeNode};
use crate::mdr::Triangle;
use crate::mdr::triangular::dot_fixed_order;
use faer::Mat;
use faer::traits::pulp::{Arch, Simd, WithSimd};

/// out[output..output + rows] (=|+=) M·v[input..input + cols], M at `data` in panel layout.
#[derive(Debug, Clone, Copy)]
pub(super) struct Gemv {
    pub data: usize,
    pub rows: usize,
    pub cols: usize,
    pub input: usize,
    pub output: usize,
}

#[derive(Debug, Clone, Copy)]
pub(super) struct LeafOut {
    pub lo: usize,
    pub hi: usize,
    pub data: usize,
    pub row_rank: usize,
    pub y_off: usize,
}

impl HodlrOperator {
    /// Lays the factors out for the apply: one contiguous Vec in panel layout, scratch
    /// offsets such that siblings' coefficients are adjacent and follow their parent's.
    pub(super) fn pack(
        &mut self,
        tree: &[TreeNode],
        diagonal: &[Mat<f64>],
        rows: &Bases,
        cols: &Bases,
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
                self.data.extend(span.map(|k| diagonal[0][(i, k)]));
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
                        .extend((0..height).map(|l| diagonal[id][(r0 + l, c)]));
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
        let (offsets, ranks) = ((&x_off[..], &y_off[..]), (&rows.rank[..], &cols.rank[..]));
        self.split = Split::of(tree, self.triangle, offsets, ranks);
        self.set_profile(tree, rows, cols);
    }

    fn set_profile(&mut self, tree: &[TreeNode], rows: &Bases, cols: &Bases) {
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

    #[track_caller]
    pub(super) fn apply_with(
        &self,
        arch: Arch,
        x: &[f64],
        y: &mut [f64],
        scratch: &mut HodlrScratch,
    ) {
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
        self.dispatch(arch, None, x, y, scratch);
    }

    /// Runs the whole apply (`part` `None`) or a part of the split one under `arch`'s
    /// instruction set ([`ApplyKernel`]); the callers check the lengths.
    pub(super) fn dispatch(
        &self,
        arch: Arch,
        part: Option<Part>,
        x: &[f64],
        y: &mut [f64],
        scratch: &mut HodlrScratch,
    ) {
        arch.dispatch(ApplyKernel {
            op: self,
            part,
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
        self.leaves_in(&self.leaf_in, x, xc);
        self.up_pass(&self.up, xc);
        self.down_pass(&self.down, xc, yc);
        self.leaves_out(&self.leaf_out, x, yc, y);
    }

    /// 1. Leaves: x̂ = Vᵀ x[I].
    #[inline(always)]
    pub(super) fn leaves_in(&self, leaves: &[Gemv], x: &[f64], xc: &mut [f64]) {
        for g in leaves {
            gemv(&self.data, g, &x[g.input..], &mut xc[g.output..], false);
        }
    }

    /// 2. Up, children first; a parent's slot lies before its children's.
    #[inline(always)]
    pub(super) fn up_pass(&self, up: &[Gemv], xc: &mut [f64]) {
        for g in up {
            let (head, tail) = xc.split_at_mut(g.input);
            gemv(&self.data, g, tail, &mut head[g.output..], false);
        }
    }

    /// 3. Down, parents first: children's ŷ set from the parent's, then the coupling.
    #[inline(always)]
    pub(super) fn down_pass(&self, down: &[(Gemv, Gemv)], xc: &[f64], yc: &mut [f64]) {
        for (e, b) in down {
            let (head, tail) = yc.split_at_mut(e.output);
            gemv(&self.data, e, &head[e.input..], tail, false);
            self.couple(b, xc, yc);
        }
    }

    /// A sibling block: ŷ_target += B·x̂_source.
    #[inline(always)]
    pub(super) fn couple(&self, b: &Gemv, xc: &[f64], yc: &mut [f64]) {
        gemv(&self.data, b, &xc[b.input..], &mut yc[b.output..], true);
    }

    /// 4. Leaves: y[I] = D x[I] + U ŷ.
    #[inline(always)]
    pub(super) fn leaves_out(&self, leaves: &[LeafOut], x: &[f64], yc: &[f64], y: &mut [f64]) {
        let data = &self.data[..];
        for leaf in leaves {
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

/// Runs [`HodlrOperator::apply_hierarchical`], or one part of the split apply
/// ([`HodlrOperator::apply_split_part`]), under the best instruction set the CPU has
/// (pulp's runtime dispatch: AVX-512 or AVX2 where available, else the x86-64 baseline).
/// The kernels are plain Rust with one accumulator per output row and no fused
/// multiply-add, so wider vectors change the speed, never the bits.
struct ApplyKernel<'a> {
    op: &'a HodlrOperator,
    part: Option<Part>,
    x: &'a [f64],
    y: &'a mut [f64],
    scratch: &'a mut HodlrScratch,
}

impl WithSimd for ApplyKernel<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        match self.part {
            None => self.op.apply_hierarchical(self.x, self.y, self.scratch),
            Some(part) => self.op.apply_split_part(part, self.x, self.y, self.scratch),
        }
    }
}

/// Row panels (first row, height) covering `rows` rows exactly: panels of 8, then at
/// most one each of 4, 2, 1. Exact heights mean no padding and fixed-size stores.
pub(super) fn panel_schedule(rows: usize) -> impl Iterator<Item = (usize, usize)> {
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
pub(super) fn leaf_panel_cols(
    triangle: Triangle,
    size: usize,
    r0: usize,
    height: usize,
) -> (usize, usize) {
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
