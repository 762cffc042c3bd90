//! Small dense linear algebra of the build: Householder QR (plain and column-pivoted with a
//! residual threshold), thin SVD, products. Sequential loops in a fixed order, so the
//! build does not depend on the thread count.

use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::svd::{ComputeSvdVectors, SvdParams, svd, svd_scratch};
use faer::{Accum, Mat, MatRef, Par, Spec};

/// C = A·B, sequential.
pub(super) fn matmul(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut c = Mat::<f64>::zeros(a.nrows(), b.ncols());
    if a.ncols() > 0 {
        faer::linalg::matmul::matmul(c.as_mut(), Accum::Replace, a, b, 1.0, Par::Seq);
    }
    c
}

/// Left singular vectors (thin) and singular values of `m`, computed sequentially so that
/// the build does not depend on threads; the right vectors are not formed.
///
/// # Panics
/// If the SVD does not converge.
pub(super) fn left_svd(m: MatRef<'_, f64>) -> (Mat<f64>, Vec<f64>) {
    let (rows, cols) = m.shape();
    let size = rows.min(cols);
    let mut u = Mat::<f64>::zeros(rows, size);
    if size == 0 {
        return (u, Vec::new());
    }
    let mut s = Diag::<f64>::zeros(size);
    let params: Spec<SvdParams, f64> = Default::default();
    let mut buf = MemBuffer::new(svd_scratch::<f64>(
        rows,
        cols,
        ComputeSvdVectors::Thin,
        ComputeSvdVectors::No,
        Par::Seq,
        params,
    ));
    svd(
        m,
        s.as_mut(),
        Some(u.as_mut()),
        None,
        Par::Seq,
        MemStack::new(&mut buf),
        params,
    )
    .expect("SVD of a small factor did not converge");
    let sigma = (0..size).map(|i| s.column_vector()[i]).collect();
    (u, sigma)
}

/// The Householder reflector H = I − τ·v·vᵀ (v₀ = 1) with H·x = β·e₁, applied in place:
/// `x` becomes [β, v₁, v₂, …]; returns τ (0 when x is already zero below and at the top).
fn make_reflector(x: &mut [f64]) -> f64 {
    let alpha = x[0];
    let tail = dot(&x[1..], &x[1..]);
    if tail == 0.0 {
        return 0.0;
    }
    let norm = (alpha * alpha + tail).sqrt();
    let beta = if alpha >= 0.0 { -norm } else { norm };
    let scale = 1.0 / (alpha - beta);
    x[1..].iter_mut().for_each(|a| *a *= scale);
    x[0] = beta;
    (beta - alpha) / beta
}

/// Σ a_i·b_i with four interleaved partial sums (independent add chains; the order is
/// fixed by the length alone).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0_f64; 4];
    let mut ca = a.chunks_exact(4);
    let mut cb = b.chunks_exact(4);
    for (x, y) in (&mut ca).zip(&mut cb) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// y ← (I − τ·v·vᵀ)·y with v = [1, v_tail].
fn apply_reflector(v_tail: &[f64], tau: f64, y: &mut [f64]) {
    if tau == 0.0 {
        return;
    }
    let (y0, y_tail) = y.split_first_mut().expect("reflector of length >= 1");
    let w = *y0 + dot(v_tail, y_tail);
    let tw = tau * w;
    *y0 -= tw;
    y_tail
        .iter_mut()
        .zip(v_tail)
        .for_each(|(b, a)| *b -= tw * a);
}

/// Householder QR of `m` (rows ≥ cols): the thin Q (rows × cols, orthonormal columns)
/// and R (cols × cols, upper triangular).
pub(super) fn thin_qr(m: &Mat<f64>) -> (Mat<f64>, Mat<f64>) {
    let (rows, cols) = (m.nrows(), m.ncols());
    debug_assert!(rows >= cols);
    let mut a = m.clone();
    let mut taus = vec![0.0; cols];
    let mut buf = Vec::with_capacity(rows);
    for (j, tau) in taus.iter_mut().enumerate() {
        householder_step(&mut a, j, j, tau, &mut buf);
    }
    let r = Mat::from_fn(cols, cols, |i, j| if i <= j { a[(i, j)] } else { 0.0 });
    let mut q = Mat::<f64>::zeros(rows, cols);
    for j in 0..cols {
        q[(j, j)] = 1.0;
    }
    for j in (0..cols).rev() {
        let v_tail: Vec<f64> = a.col_as_slice(j)[j + 1..].to_vec();
        for c in j..cols {
            apply_reflector(&v_tail, taus[j], &mut q.col_as_slice_mut(c)[j..]);
        }
    }
    (q, r)
}

/// The R factor (min(rows, cols) × cols, upper trapezoidal) of a Householder QR of `m`.
pub(super) fn r_factor(m: &Mat<f64>) -> Mat<f64> {
    let (rows, cols) = (m.nrows(), m.ncols());
    let steps = rows.min(cols);
    let mut a = m.clone();
    let (mut tau, mut buf) = (0.0, Vec::with_capacity(rows));
    for j in 0..steps {
        householder_step(&mut a, j, j, &mut tau, &mut buf);
    }
    Mat::from_fn(steps, cols, |i, j| if i <= j { a[(i, j)] } else { 0.0 })
}

/// Reflects column `col` of `a` from row `row` down onto e₁ and applies the reflector to
/// the columns after it; the reflector's tail stays below the diagonal.
fn householder_step(
    a: &mut Mat<f64>,
    row: usize,
    col: usize,
    tau: &mut f64,
    v_tail: &mut Vec<f64>,
) {
    *tau = make_reflector(&mut a.col_as_slice_mut(col)[row..]);
    if *tau == 0.0 {
        return;
    }
    // A copy of the reflector, so that the other columns can be updated in place.
    v_tail.clear();
    v_tail.extend_from_slice(&a.col_as_slice(col)[row + 1..]);
    for c in col + 1..a.ncols() {
        apply_reflector(v_tail, *tau, &mut a.col_as_slice_mut(c)[row..]);
    }
}

/// A column-pivoted QR of G (s × c) stopped at the first rank k whose remainder has
/// Frobenius norm ≤ the threshold: G·P ≈ Q₁·[R₁₁ R₁₂], so that the columns not chosen are
/// G[:, rest] ≈ G[:, chosen]·X with X = R₁₁⁻¹R₁₂.
pub(super) struct PivotedQr {
    /// Column order: the first `rank` are the chosen (skeleton) columns.
    pub perm: Vec<usize>,
    /// Number of chosen columns.
    pub rank: usize,
    /// X = R₁₁⁻¹R₁₂ (rank × (c − rank)), column q for column `perm[rank + q]`.
    pub x: Mat<f64>,
    /// ‖R₂₂‖_F, the Frobenius norm of G[:, rest] − G[:, chosen]·X.
    pub residual: f64,
}

/// Column-pivoted Householder QR of `g`, stopped when the remainder's Frobenius norm is
/// ≤ `threshold` (so `threshold` = 0 continues while anything non-zero is left). Column
/// norms are recomputed at every step rather than downdated: exact, and cheap at the
/// sizes of the build. Ties go to the first column, so the choice is deterministic.
pub(super) fn pivoted_qr(mut g: Mat<f64>, threshold: f64) -> PivotedQr {
    let (rows, cols) = (g.nrows(), g.ncols());
    let mut perm: Vec<usize> = (0..cols).collect();
    let mut norms_sq: Vec<f64> = (0..cols)
        .map(|j| {
            let c = g.col_as_slice(j);
            dot(c, c)
        })
        .collect();
    let mut rank = 0;
    let mut residual = norms_sq.iter().sum::<f64>().sqrt();
    let mut tau = 0.0;
    let mut v_tail = Vec::with_capacity(rows);
    while rank < rows.min(cols) && residual > threshold {
        let mut best = rank;
        for j in rank + 1..cols {
            if norms_sq[j] > norms_sq[best] {
                best = j;
            }
        }
        if norms_sq[best] == 0.0 {
            break;
        }
        if best != rank {
            perm.swap(rank, best);
            norms_sq.swap(rank, best);
            for i in 0..rows {
                let t = g[(i, rank)];
                g[(i, rank)] = g[(i, best)];
                g[(i, best)] = t;
            }
        }
        householder_step(&mut g, rank, rank, &mut tau, &mut v_tail);
        rank += 1;
        for (j, n2) in norms_sq.iter_mut().enumerate().skip(rank) {
            let c = &g.col_as_slice(j)[rank..];
            *n2 = dot(c, c);
        }
        residual = norms_sq[rank..].iter().sum::<f64>().sqrt();
    }
    if rank == rows.min(cols) {
        // Nothing is left below the last row of R: the factorisation is exact.
        residual = 0.0;
    }
    // X = R₁₁⁻¹R₁₂ by back substitution, one column of R₁₂ at a time.
    let rest = cols - rank;
    let mut x = Mat::<f64>::zeros(rank, rest);
    for q in 0..rest {
        let rhs = g.col_as_slice(rank + q);
        let out = x.col_as_slice_mut(q);
        for i in (0..rank).rev() {
            let mut s = rhs[i];
            for l in i + 1..rank {
                s -= g[(i, l)] * out[l];
            }
            out[i] = s / g[(i, i)];
        }
    }
    PivotedQr {
        perm,
        rank,
        x,
        residual,
    }
}
