//! Entry-wise access to the triangular MDR operators: what the hierarchical build
//! ([`super::hodlr`]) reads instead of a stored dense matrix.
//!
//! The product and literal sources ([`super::product::ForwardEntries`], …) compute an
//! entry from the grid on demand, bit-identical to the dense builders, so an operator of
//! size N can be compressed with O(N) memory; [`TriangularOperator`] is a source too
//! (its stored entries).

use super::{Triangle, TriangularOperator};

/// An N×N triangular operator whose entries can be computed one by one.
pub trait OperatorEntries {
    /// Matrix size N.
    fn size(&self) -> usize;

    /// The non-zero triangle.
    fn triangle(&self) -> Triangle;

    /// Entry (i, k), zero outside the triangle (operator units).
    fn entry(&self, i: usize, k: usize) -> f64;

    /// `out[c] = entry(i, cols[c])` for increasing `cols`. Sources override it to share
    /// work between neighbouring columns (the product weights of adjacent columns use
    /// the same cell integrals).
    ///
    /// # Panics
    /// If `out` is shorter than `cols`.
    fn row_into(&self, i: usize, cols: &[usize], out: &mut [f64]) {
        for (o, &k) in out[..cols.len()].iter_mut().zip(cols) {
            *o = self.entry(i, k);
        }
    }

    /// As [`Self::row_into`], for the build's samples of the off-diagonal blocks: a
    /// source may compute these entries more accurately than its dense builder (the
    /// rounding noise of a cancelling closed form is no smooth function of the indices,
    /// so sampling cannot reproduce it, and at large N it would swamp the low ranks).
    /// The default is [`Self::row_into`].
    ///
    /// # Panics
    /// If `out` is shorter than `cols`.
    fn row_into_accurate(&self, i: usize, cols: &[usize], out: &mut [f64]) {
        self.row_into(i, cols, out);
    }

    /// A cheap lower bound ν₀ ≤ ‖A‖₂ (operator units), the scale of the build's
    /// sampling thresholds: the closer to ‖A‖₂, the fewer entries the build reads;
    /// too small costs time, never accuracy. The default is the largest Euclidean norm
    /// of a few whole rows and columns, O(N) entries.
    fn norm_lower_bound(&self) -> f64 {
        probe_norm_lower_bound(self)
    }
}

/// Largest norm of the rows and columns at 0, N/4, N/2, 3N/4 and N−1: every row or
/// column of A has norm ≤ ‖A‖₂.
pub fn probe_norm_lower_bound<E: OperatorEntries + ?Sized>(a: &E) -> f64 {
    let n = a.size();
    if n == 0 {
        return 0.0;
    }
    let all: Vec<usize> = (0..n).collect();
    let mut buf = vec![0.0; n];
    let mut best = 0.0_f64;
    for q in 0..5 {
        let p = (n - 1) * q / 4;
        a.row_into(p, &all, &mut buf);
        best = best.max(buf.iter().map(|v| v * v).sum::<f64>().sqrt());
        let col: f64 = (0..n).map(|i| a.entry(i, p).powi(2)).sum();
        best = best.max(col.sqrt());
    }
    best
}

impl OperatorEntries for TriangularOperator {
    fn size(&self) -> usize {
        TriangularOperator::size(self)
    }

    fn triangle(&self) -> Triangle {
        TriangularOperator::triangle(self)
    }

    fn entry(&self, i: usize, k: usize) -> f64 {
        self.get(i, k)
    }

    /// Power iteration on AᵀA from the all-ones vector (4 steps, each two O(N²)
    /// mat-vecs): the operator is stored anyway, and a tight ν₀ saves sampled entries.
    fn norm_lower_bound(&self) -> f64 {
        let n = self.size();
        if n == 0 {
            return 0.0;
        }
        let mut v = vec![1.0 / (n as f64).sqrt(); n];
        let mut av = vec![0.0; n];
        let mut estimate = 0.0_f64;
        for _ in 0..4 {
            self.apply(&v, &mut av);
            let norm_av = av.iter().map(|a| a * a).sum::<f64>().sqrt();
            estimate = estimate.max(norm_av);
            if norm_av == 0.0 {
                break;
            }
            // v ← Aᵀ(Av)/‖Aᵀ(Av)‖, reading A row by row.
            v.fill(0.0);
            for (i, &ai) in av.iter().enumerate() {
                let cols = match self.triangle() {
                    Triangle::Lower => 0..i + 1,
                    Triangle::Upper => i..n,
                };
                for k in cols {
                    v[k] += self.get(i, k) * ai;
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
}
