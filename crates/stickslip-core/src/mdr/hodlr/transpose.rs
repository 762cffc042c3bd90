//! Aᵀ·x of the packed hierarchical form, for weights derived once from an operator (the
//! 1D force as a function of τ, [`crate::mdr::MdrOperators::force_1d_from_tau_n`]): the
//! apply's passes read backwards, each small matrix transposed. Allocates and reads the
//! panels column-wise: not for the step loop.
//!
//! With A = D + Σ U·B·Vᵀ over the nested bases (see "Apply" in the module docs),
//! Aᵀ = Dᵀ + Σ V·Bᵀ·Uᵀ: the row bases' coefficients ẑ = Uᵀx go up the tree through the
//! transfers Eᵀ, cross the sibling blocks as Bᵀ into the column side, and come down through
//! the transfers F to the leaves' V.

use super::apply::{Gemv, leaf_panel_cols, panel_schedule};
use super::{HodlrOperator, Triangle};

/// out[c] (= or +=) Σ_r M[r, c]·v[r], M at `g` in panel layout.
fn gemv_t(data: &[f64], g: &Gemv, v: &[f64], out: &mut [f64], accumulate: bool) {
    if !accumulate {
        out[..g.cols].fill(0.0);
    }
    let mut off = g.data;
    for (r0, height) in panel_schedule(g.rows) {
        for (c, o) in out[..g.cols].iter_mut().enumerate() {
            let column = &data[off + c * height..off + (c + 1) * height];
            *o += column
                .iter()
                .zip(&v[r0..r0 + height])
                .map(|(a, b)| a * b)
                .sum::<f64>();
        }
        off += height * g.cols;
    }
}

impl HodlrOperator {
    /// y ≈ Aᵀ·x (the same approximation Ã as [`Self::apply`], transposed: ⟨y, Ã·x⟩ =
    /// ⟨Ãᵀ·y, x⟩ to rounding).
    ///
    /// # Panics
    /// If `x.len()` or `y.len()` differs from N.
    #[track_caller]
    pub fn apply_transpose(&self, x: &[f64], y: &mut [f64]) {
        let n = self.n;
        assert_eq!(x.len(), n, "input length must equal the node count");
        assert_eq!(y.len(), n, "output length must equal the node count");
        y.fill(0.0);
        let data = &self.data[..];
        if self.single_leaf {
            let mut off = 0;
            for (i, &xi) in x.iter().enumerate() {
                let (c0, len) = match self.triangle {
                    Triangle::Lower => (0, i + 1),
                    Triangle::Upper => (i, n - i),
                };
                for (yk, &a) in y[c0..c0 + len].iter_mut().zip(&data[off..off + len]) {
                    *yk += a * xi;
                }
                off += len;
            }
            return;
        }
        let mut z = vec![0.0; self.y_coeff_len];
        let mut w = vec![0.0; self.x_coeff_len];
        // Leaves: y[I] = Dᵀ·x[I], ẑ = Uᵀ·x[I].
        for leaf in &self.leaf_out {
            let size = leaf.hi - leaf.lo;
            let xs = &x[leaf.lo..leaf.hi];
            let mut off = leaf.data;
            for (r0, height) in panel_schedule(size) {
                let (c0, c1) = leaf_panel_cols(self.triangle, size, r0, height);
                let rows = &xs[r0..r0 + height];
                let column_dot = |j: usize| -> f64 {
                    let column = &data[off + j * height..off + (j + 1) * height];
                    column.iter().zip(rows).map(|(a, b)| a * b).sum()
                };
                // The panel's triangle columns c0..c1, then U's columns.
                for c in c0..c1 {
                    y[leaf.lo + c] += column_dot(c - c0);
                }
                for c in 0..leaf.row_rank {
                    z[leaf.y_off + c] += column_dot(c1 - c0 + c);
                }
                off += height * (c1 - c0 + leaf.row_rank);
            }
        }
        // Up the row side, children first: ẑ_τ = Eᵀ·[ẑ₁; ẑ₂].
        for (e, _) in self.down.iter().rev() {
            let children = z[e.output..e.output + e.rows].to_vec();
            gemv_t(data, e, &children, &mut z[e.input..], false);
        }
        // Down the column side, parents first: [ŵ₁; ŵ₂] = F·ŵ_τ, then ŵ_source += Bᵀ·ẑ_target.
        for (f, (_, b)) in self.up.iter().rev().zip(&self.down) {
            let parent = w[f.output..f.output + f.rows].to_vec();
            gemv_t(data, f, &parent, &mut w[f.input..], false);
            gemv_t(data, b, &z[b.output..], &mut w[b.input..], true);
        }
        // Leaves: y[I] += V·ŵ.
        for g in &self.leaf_in {
            gemv_t(data, g, &w[g.output..], &mut y[g.input..], true);
        }
    }
}
