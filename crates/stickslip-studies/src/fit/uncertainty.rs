//! Uncertainty at the optimum (docs/fit.md#uncertainty): the covariance of the box
//! coordinates C = s²·(JᵀJ)⁻¹ = s²·V·diag(1/σ²)·Vᵀ from the Jacobian's SVD, scaled by the
//! residual variance s² = χ²/(m − p) when it exceeds 1 (a model that cannot follow the data,
//! or noise larger than assumed, widens the intervals; a misfit below the noise, which with a
//! few residuals happens by chance, does not narrow them below what the noise alone gives); 95 % intervals z ± 1.96·√Cᵢᵢ mapped to values (asymmetric for a logarithmic
//! parameter); the standard error in the value's unit by the map's slope; correlations of the
//! coordinates; and the directions the data cannot determine, named in words.
//!
//! A direction vᵢ of the SVD is *unidentified* when its 95 % half-width 1.96·s/σᵢ exceeds
//! half the box (the data cannot place it within the bounds given), or when σᵢ is below
//! 1e-12 of the largest. It is named by the parameters with a weight of at least
//! [`NAMED_WEIGHT`] in it: one alone is "not determined by the data"; two or more "trade
//! off".

use super::linalg::Svd;
use super::params::Param;

/// Normal quantile of a two-sided 95 % interval.
pub const Z95: f64 = 1.959_963_984_540_054;
/// A parameter is named in an unidentified direction when its weight there is at least this.
pub const NAMED_WEIGHT: f64 = 0.3;
/// Pairs more correlated than this are also named as trading off.
pub const CORRELATED: f64 = 0.99;

/// One parameter's uncertainty.
#[derive(Debug, Clone, PartialEq)]
pub struct Interval {
    /// Standard error, in the parameter's unit (infinite: not determined).
    pub stderr: f64,
    /// Lower end of the 95 % interval.
    pub lo95: f64,
    /// Upper end of the 95 % interval.
    pub hi95: f64,
}

/// The uncertainty of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Uncertainty {
    /// Per parameter.
    pub intervals: Vec<Interval>,
    /// Correlations of the box coordinates (NaN where a variance is infinite).
    pub correlation: Vec<Vec<f64>>,
    /// The Jacobian's singular values (box units), decreasing.
    pub singular_values: Vec<f64>,
    /// The residual standard deviation s = √(χ²/(m − p)), at least 1: the covariance's scale.
    pub residual_sigma: f64,
    /// The unidentified combinations, in words.
    pub unidentified: Vec<String>,
}

/// The uncertainty of `params` at `z` from the Jacobian's SVD `d` (columns in the order of
/// `params`) and the misfit `chi2` of `m` residuals.
#[must_use]
pub fn uncertainty(params: &[Param], z: &[f64], d: &Svd, chi2: f64, m: usize) -> Uncertainty {
    let p = params.len();
    let dof = m.saturating_sub(p).max(1);
    let s2 = (chi2 / dof as f64).max(1.0);
    let s = s2.sqrt();
    let smax = d.s.first().copied().unwrap_or(0.0);
    let singular = |si: f64| si > 1e-12 * smax && si > 0.0;
    let mut cov = vec![vec![0.0; p]; p];
    for (v, &si) in d.v.iter().zip(&d.s) {
        for (row, &va) in cov.iter_mut().zip(v) {
            for (c, &vb) in row.iter_mut().zip(v) {
                *c += if singular(si) {
                    va * vb / (si * si)
                } else if va != 0.0 && vb != 0.0 {
                    f64::INFINITY
                } else {
                    0.0
                };
            }
        }
    }
    cov.iter_mut().flatten().for_each(|c| *c *= s2);
    let intervals = (0..p)
        .map(|k| {
            let sz = cov[k][k].max(0.0).sqrt();
            let par = &params[k];
            Interval {
                stderr: par.slope(z[k]) * sz,
                lo95: par.value(z[k] - Z95 * sz),
                hi95: par.value(z[k] + Z95 * sz),
            }
        })
        .collect();
    let correlation: Vec<Vec<f64>> = (0..p)
        .map(|a| {
            (0..p)
                .map(|b| {
                    if a == b {
                        1.0
                    } else {
                        cov[a][b] / (cov[a][a] * cov[b][b]).sqrt()
                    }
                })
                .collect()
        })
        .collect();
    let mut unidentified = Vec::new();
    for (i, &si) in d.s.iter().enumerate() {
        let half = if singular(si) {
            Z95 * s / si
        } else {
            f64::INFINITY
        };
        if half <= 0.5 {
            continue;
        }
        let named: Vec<(usize, f64)> = (0..p)
            .filter(|&k| d.v[i][k].abs() >= NAMED_WEIGHT)
            .map(|k| (k, d.v[i][k]))
            .collect();
        unidentified.push(describe(params, &named, half));
    }
    for a in 0..p {
        for b in a + 1..p {
            let r = correlation[a][b];
            if r.abs() > CORRELATED
                && !unidentified
                    .iter()
                    .any(|u| u.contains(&params[a].key) && u.contains(&params[b].key))
            {
                unidentified.push(format!(
                    "{} and {} trade off (correlation {r:.3}): the data fix mainly their {}",
                    params[a].key,
                    params[b].key,
                    combination(&params[a], &params[b], r > 0.0)
                ));
            }
        }
    }
    Uncertainty {
        intervals,
        correlation,
        singular_values: d.s.clone(),
        residual_sigma: s,
        unidentified,
    }
}

/// What a pair fixes when its coordinates move together (`together`) or against each other.
fn combination(a: &Param, b: &Param, together: bool) -> &'static str {
    match (a.log && b.log, together) {
        (true, true) => "product",
        (true, false) => "ratio",
        (false, true) => "sum",
        (false, false) => "difference",
    }
}

/// One unidentified direction in words.
fn describe(params: &[Param], named: &[(usize, f64)], half: f64) -> String {
    let width = if half.is_finite() {
        format!("its 95 % half-width is {half:.2} of the bounds' range")
    } else {
        "the misfit does not change along it".to_string()
    };
    match named {
        [] => format!("a combination of every parameter is not determined by the data ({width})"),
        [(k, _)] => format!("{} is not determined by the data ({width})", params[*k].key),
        [(a, va), (b, vb)] => format!(
            "{} and {} trade off: raising one and {} the other leaves the misfit unchanged, \
             the data fix mainly their {} ({width})",
            params[*a].key,
            params[*b].key,
            if va * vb > 0.0 { "raising" } else { "lowering" },
            // Moving together along v leaves the misfit: what is fixed is the other
            // combination.
            combination(&params[*a], &params[*b], va * vb < 0.0),
        ),
        many => format!(
            "{} trade off together ({width})",
            many.iter()
                .map(|(k, _)| params[*k].key.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::linalg::svd;
    use crate::fit::params::parse;

    #[test]
    fn a_well_determined_fit_has_narrow_intervals_and_a_degenerate_one_is_named() {
        let params = vec![
            parse("lubricant.tau_max=1e5:1e7", None).unwrap(),
            parse("contact.radius=1e-6:1e-4", None).unwrap(),
        ];
        let z = [0.5, 0.5];
        // Two independent, sharp directions: residuals r = 100·(z − z*) plus noise of 1.
        let good = svd(&[vec![100.0, 0.0, 0.0, 0.0], vec![0.0, 100.0, 0.0, 0.0]]).unwrap();
        let u = uncertainty(&params, &z, &good, 2.0, 4);
        assert!(u.unidentified.is_empty(), "{:?}", u.unidentified);
        let tau = &u.intervals[0];
        assert!(
            tau.lo95 < 1e6 && tau.hi95 > 1e6 && tau.hi95 / tau.lo95 < 1.2,
            "{tau:?}"
        );
        assert!(u.correlation[0][1].abs() < 1e-12);
        // Only the sum of the two coordinates (the product of the values) is seen.
        let bad = svd(&[vec![100.0, 100.0, 0.0, 0.0], vec![100.0, 100.0, 0.0, 0.0]]).unwrap();
        let u = uncertainty(&params, &z, &bad, 2.0, 4);
        assert_eq!(u.unidentified.len(), 1, "{:?}", u.unidentified);
        let text = &u.unidentified[0];
        assert!(
            text.contains("lubricant.tau_max and contact.radius trade off"),
            "{text}"
        );
        assert!(text.contains("product"), "{text}");
        assert!(u.intervals[0].stderr.is_infinite());
    }
}
