//! Packed triangular matrices and their mat-vec, the storage of the MDR operators.

use faer::Mat;

/// Which triangle of the N×N matrix is stored (diagonal included).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Triangle {
    /// Entries (j, k) with k ≥ j: the forward transform integrates outward from x_j.
    Upper,
    /// Entries (i, k) with k ≤ i: the back transform integrates inward to r_i.
    Lower,
}

/// An N×N triangular matrix stored row by row, each row contiguous.
///
/// Row i holds columns `i..N` (upper) or `0..=i` (lower). The mat-vec computes each
/// output entry as one dot product in a fixed order, so results do not depend on how
/// rows are shared among threads.
#[derive(Debug, Clone)]
pub struct TriangularOperator {
    n: usize,
    triangle: Triangle,
    row_offset: Vec<usize>,
    data: Vec<f64>,
}

impl TriangularOperator {
    /// An all-zero operator of size `n`.
    pub fn zeros(n: usize, triangle: Triangle) -> Self {
        let mut row_offset = Vec::with_capacity(n + 1);
        let mut acc = 0;
        for i in 0..n {
            row_offset.push(acc);
            acc += Self::row_len_of(n, triangle, i);
        }
        row_offset.push(acc);
        Self {
            n,
            triangle,
            row_offset,
            data: vec![0.0; acc],
        }
    }

    fn row_len_of(n: usize, triangle: Triangle, i: usize) -> usize {
        match triangle {
            Triangle::Upper => n - i,
            Triangle::Lower => i + 1,
        }
    }

    fn first_col(&self, i: usize) -> usize {
        match self.triangle {
            Triangle::Upper => i,
            Triangle::Lower => 0,
        }
    }

    /// Matrix size N.
    pub fn size(&self) -> usize {
        self.n
    }

    /// The stored triangle.
    pub fn triangle(&self) -> Triangle {
        self.triangle
    }

    /// Adds `value` to entry (i, k).
    ///
    /// # Panics
    /// If (i, k) lies outside the stored triangle.
    #[track_caller]
    pub fn add(&mut self, i: usize, k: usize, value: f64) {
        let first = self.first_col(i);
        let len = self.row_offset[i + 1] - self.row_offset[i];
        assert!(
            k >= first && k < first + len,
            "entry ({i}, {k}) outside the {:?} triangle",
            self.triangle
        );
        self.data[self.row_offset[i] + k - first] += value;
    }

    /// Entry (i, k) (zero outside the triangle).
    pub fn get(&self, i: usize, k: usize) -> f64 {
        let first = self.first_col(i);
        let len = self.row_offset[i + 1] - self.row_offset[i];
        if k >= first && k < first + len {
            self.data[self.row_offset[i] + k - first]
        } else {
            0.0
        }
    }

    /// y = A·x.
    ///
    /// # Panics
    /// If `x.len()` or `y.len()` differs from N.
    #[track_caller]
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.n, "input length must equal the node count");
        assert_eq!(y.len(), self.n, "output length must equal the node count");
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = self.row_dot(i, x);
        }
    }

    /// y = A·x with rows shared among rayon threads; bit-identical to [`Self::apply`].
    ///
    /// # Panics
    /// If `x.len()` or `y.len()` differs from N.
    #[track_caller]
    pub fn apply_par(&self, x: &[f64], y: &mut [f64]) {
        use rayon::prelude::*;
        assert_eq!(x.len(), self.n, "input length must equal the node count");
        assert_eq!(y.len(), self.n, "output length must equal the node count");
        y.par_iter_mut()
            .with_min_len(64)
            .enumerate()
            .for_each(|(i, yi)| *yi = self.row_dot(i, x));
    }

    #[inline]
    fn row_dot(&self, i: usize, x: &[f64]) -> f64 {
        let row = &self.data[self.row_offset[i]..self.row_offset[i + 1]];
        let first = self.first_col(i);
        dot_fixed_order(row, &x[first..first + row.len()])
    }

    /// y = Aᵀ·x, row by row of A (each y[k] accumulates in row order). For one-off uses
    /// (weights derived from the operator), not the step loop.
    ///
    /// # Panics
    /// If `x.len()` or `y.len()` differs from N.
    #[track_caller]
    pub fn apply_transpose(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.n, "input length must equal the node count");
        assert_eq!(y.len(), self.n, "output length must equal the node count");
        y.fill(0.0);
        for (i, &xi) in x.iter().enumerate() {
            let row = &self.data[self.row_offset[i]..self.row_offset[i + 1]];
            let first = self.first_col(i);
            for (yk, &a) in y[first..first + row.len()].iter_mut().zip(row) {
                *yk += a * xi;
            }
        }
    }

    /// The matrix as a dense faer matrix.
    pub fn to_dense(&self) -> Mat<f64> {
        Mat::from_fn(self.n, self.n, |i, k| self.get(i, k))
    }
}

/// Dot product with eight interleaved partial sums (vectorisable; order fixed by length only).
#[inline]
pub(super) fn dot_fixed_order(a: &[f64], b: &[f64]) -> f64 {
    const LANES: usize = 8;
    let mut acc = [0.0_f64; LANES];
    let chunks = a.len() / LANES;
    for c in 0..chunks {
        let aa = &a[c * LANES..(c + 1) * LANES];
        let bb = &b[c * LANES..(c + 1) * LANES];
        for l in 0..LANES {
            acc[l] += aa[l] * bb[l];
        }
    }
    let mut tail = 0.0;
    for k in chunks * LANES..a.len() {
        tail += a[k] * b[k];
    }
    let pair = [
        acc[0] + acc[4],
        acc[1] + acc[5],
        acc[2] + acc[6],
        acc[3] + acc[7],
    ];
    (pair[0] + pair[2]) + (pair[1] + pair[3]) + tail
}
