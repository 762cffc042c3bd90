//! The fit's one piece of linear algebra: the thin singular value decomposition of a
//! Jacobian (faer), from which both the Levenberg–Marquardt step and the covariance follow.

use faer::Mat;

/// J = U·diag(s)·Vᵀ of an m × p matrix (m ≥ 1, p ≥ 1), singular values decreasing.
#[derive(Debug, Clone, PartialEq)]
pub struct Svd {
    /// Singular values, decreasing.
    pub s: Vec<f64>,
    /// Left singular vectors, one per singular value (m entries each).
    pub u: Vec<Vec<f64>>,
    /// Right singular vectors, one per singular value (p entries each).
    pub v: Vec<Vec<f64>>,
}

/// The SVD of the matrix whose columns are `columns` (all of one length); `None` when faer's
/// iteration does not converge (a matrix with non-finite entries).
#[must_use]
pub fn svd(columns: &[Vec<f64>]) -> Option<Svd> {
    let p = columns.len();
    let m = columns.first().map_or(0, Vec::len);
    if p == 0 || m == 0 || columns.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    let j = Mat::from_fn(m, p, |i, k| columns[k][i]);
    let d = j.thin_svd().ok()?;
    let (u, s, v) = (d.U(), d.S().column_vector(), d.V());
    let k = s.nrows();
    Some(Svd {
        s: (0..k).map(|i| s[i]).collect(),
        u: (0..k)
            .map(|c| (0..m).map(|i| u[(i, c)]).collect())
            .collect(),
        v: (0..k)
            .map(|c| (0..p).map(|i| v[(i, c)]).collect())
            .collect(),
    })
}

/// uᵀ·r.
#[must_use]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_decomposition_rebuilds_the_matrix() {
        let cols = vec![vec![1.0, 2.0, 3.0], vec![0.5, -1.0, 4.0]];
        let d = svd(&cols).unwrap();
        assert!(d.s[0] >= d.s[1] && d.s[1] > 0.0);
        for (c, col) in cols.iter().enumerate() {
            for (i, &x) in col.iter().enumerate() {
                let back: f64 = (0..2).map(|k| d.u[k][i] * d.s[k] * d.v[k][c]).sum();
                assert!((back - x).abs() < 1e-12, "{back} {x}");
            }
        }
        assert!(svd(&[vec![f64::NAN]]).is_none());
    }
}
