//! Observed orders and the three-grid procedure of Celik et al. 2008 (J. Fluids Eng. 130, 078001).
//!
//! Notation of the paper: grids 1 (fine), 2 (medium), 3 (coarse) with representative spacings
//! h1 < h2 < h3, refinement ratios r21 = h2/h1, r32 = h3/h2 (both should exceed 1.3), values
//! φ1, φ2, φ3 and differences ε21 = φ2 − φ1, ε32 = φ3 − φ2. The apparent order p solves
//!
//! p = |ln|ε32/ε21| + q(p)| / ln r21,  q(p) = ln((r21^p − s)/(r32^p − s)),  s = sign(ε32/ε21),
//!
//! by fixed-point iteration from q = 0 (q ≡ 0 when r21 = r32). Then
//!
//! - extrapolated value φext = (r21^p·φ1 − φ2)/(r21^p − 1),
//! - approximate relative error e_a = |(φ1 − φ2)/φ1|,
//! - extrapolated relative error e_ext = |(φext − φ1)/φext|,
//! - fine-grid convergence index GCI_fine = 1.25·e_a/(r21^p − 1).
//!
//! s < 0 is oscillatory convergence: p is still reported (the paper takes absolute values), but
//! the extrapolated value and the GCI are then not error bounds, and [`Celik::oscillatory`] says
//! so.

use serde::{Deserialize, Serialize};

/// Observed orders p_k = ln(e_k / e_{k+1}) / ln(h_k / h_{k+1}) for errors `errors`
/// measured at resolutions `spacings` (any decreasing sequence of step sizes).
///
/// # Panics
/// If the two slices have different lengths.
///
/// # Example
/// ```
/// use stickslip_studies::verify::celik::observed_orders;
/// let p = observed_orders(&[0.1, 0.05], &[3e-2, 7.5e-3]);
/// assert!((p[0] - 2.0).abs() < 1e-12);
/// ```
#[track_caller]
pub fn observed_orders(spacings: &[f64], errors: &[f64]) -> Vec<f64> {
    assert_eq!(spacings.len(), errors.len(), "one error per spacing");
    spacings
        .windows(2)
        .zip(errors.windows(2))
        .map(|(h, e)| (e[0] / e[1]).ln() / (h[0] / h[1]).ln())
        .collect()
}

/// Smallest refinement ratio Celik et al. recommend between successive grids.
pub const MIN_RATIO: f64 = 1.3;

/// Why the three-grid procedure gave no answer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CelikFailure {
    /// A refinement ratio is ≤ [`MIN_RATIO`] (or the spacings are not fine < medium < coarse).
    RatioTooSmall,
    /// ε21 or ε32 is zero: the value does not change with the grid (exact, or below rounding).
    NoChange,
    /// A value or spacing is not finite.
    NonFinite,
    /// The fixed-point iteration for p did not settle (or p collapsed to 0).
    NoOrder,
}

impl std::fmt::Display for CelikFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::RatioTooSmall => "refinement ratio <= 1.3",
            Self::NoChange => "no change between grids",
            Self::NonFinite => "non-finite value",
            Self::NoOrder => "apparent order did not converge",
        })
    }
}

/// The result of the three-grid procedure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Celik {
    /// Refinement ratio r21 = h2/h1.
    pub r21: f64,
    /// Refinement ratio r32 = h3/h2.
    pub r32: f64,
    /// Apparent order p.
    pub p: f64,
    /// Extrapolated value φext21.
    pub phi_ext: f64,
    /// Approximate relative error e_a21 = |(φ1 − φ2)/φ1|.
    pub e_a: f64,
    /// Extrapolated relative error e_ext21 = |(φext − φ1)/φext|.
    pub e_ext: f64,
    /// GCI_fine21 = 1.25·e_a21/(r21^p − 1), relative.
    pub gci_fine: f64,
    /// The same index in the units of φ: 1.25·|φ1 − φ2|/(r21^p − 1).
    pub gci_fine_abs: f64,
    /// ε32/ε21 < 0: oscillatory convergence (φext and GCI are not bounds then).
    pub oscillatory: bool,
    /// Fixed-point iterations used for p (0 when r21 = r32 needs none).
    pub iterations: usize,
}

/// Celik et al.'s three-grid procedure for spacings `h = [h1, h2, h3]` (fine, medium, coarse)
/// and values `phi = [φ1, φ2, φ3]` on them. See the module documentation for the formulas.
///
/// # Errors
/// [`CelikFailure`] when the ratios are ≤ 1.3, a difference is zero, a value is not finite or
/// the iteration for p does not converge.
///
/// # Example
/// ```
/// use stickslip_studies::verify::celik::three_grid;
/// // f(h) = 1 + 3·h^1.7 on non-uniformly refined grids: p = 1.7 and φext = 1 are recovered.
/// let h = [0.04, 0.07, 0.1];
/// let phi = h.map(|h: f64| 1.0 + 3.0 * h.powf(1.7));
/// let c = three_grid(h, phi).unwrap();
/// assert!((c.p - 1.7).abs() < 1e-9 && (c.phi_ext - 1.0).abs() < 1e-9);
/// ```
pub fn three_grid(h: [f64; 3], phi: [f64; 3]) -> Result<Celik, CelikFailure> {
    if h.iter().chain(&phi).any(|v| !v.is_finite()) {
        return Err(CelikFailure::NonFinite);
    }
    let r21 = h[1] / h[0];
    let r32 = h[2] / h[1];
    if !(r21 > MIN_RATIO && r32 > MIN_RATIO) || h[0] <= 0.0 {
        return Err(CelikFailure::RatioTooSmall);
    }
    let e21 = phi[1] - phi[0];
    let e32 = phi[2] - phi[1];
    if e21 == 0.0 || e32 == 0.0 {
        return Err(CelikFailure::NoChange);
    }
    let ratio = e32 / e21;
    let s = ratio.signum();
    let ln_ratio = ratio.abs().ln();
    let ln_r21 = r21.ln();
    let mut p = (ln_ratio / ln_r21).abs();
    let mut iterations = 0;
    if (r21 - r32).abs() > 1e-12 * r21 {
        let mut settled = false;
        for _ in 0..500 {
            iterations += 1;
            let num = r21.powf(p) - s;
            let den = r32.powf(p) - s;
            if !(num > 0.0 && den > 0.0) {
                return Err(CelikFailure::NoOrder);
            }
            let next = ((ln_ratio + (num / den).ln()) / ln_r21).abs();
            if !next.is_finite() {
                return Err(CelikFailure::NoOrder);
            }
            let done = (next - p).abs() <= 1e-13 * next.max(1.0);
            p = next;
            if done {
                settled = true;
                break;
            }
        }
        if !settled {
            return Err(CelikFailure::NoOrder);
        }
    }
    let rp = r21.powf(p);
    if rp.is_nan() || rp - 1.0 <= 1e-12 {
        return Err(CelikFailure::NoOrder);
    }
    let phi_ext = (rp * phi[0] - phi[1]) / (rp - 1.0);
    let e_a = (e21 / phi[0]).abs();
    let e_ext = ((phi_ext - phi[0]) / phi_ext).abs();
    Ok(Celik {
        r21,
        r32,
        p,
        phi_ext,
        e_a,
        e_ext,
        gci_fine: 1.25 * e_a / (rp - 1.0),
        gci_fine_abs: 1.25 * e21.abs() / (rp - 1.0),
        oscillatory: s < 0.0,
        iterations,
    })
}

/// Apparent orders along a refinement sequence without a known answer: for every three
/// consecutive levels (coarse to fine in the slices' order), the order p of [`three_grid`]
/// (`None` where it fails). `spacings` must decrease along the sequence.
///
/// # Panics
/// If the slices have different lengths.
#[track_caller]
pub fn apparent_orders(spacings: &[f64], values: &[f64]) -> Vec<Option<f64>> {
    assert_eq!(spacings.len(), values.len(), "one value per spacing");
    (0..spacings.len().saturating_sub(2))
        .map(|k| {
            let h = [spacings[k + 2], spacings[k + 1], spacings[k]];
            let v = [values[k + 2], values[k + 1], values[k]];
            three_grid(h, v).ok().map(|c| c.p)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn second_order_sequence_gives_two() {
        let h = [0.1, 0.05, 0.025];
        let e: Vec<f64> = h.iter().map(|x| 3.0 * x * x).collect();
        for p in observed_orders(&h, &e) {
            assert!((p - 2.0).abs() < 1e-12, "p = {p}");
        }
    }

    /// f(h) = φ0 + c·h^p on three grids.
    fn manufactured(h: [f64; 3], phi0: f64, c: f64, p: f64) -> [f64; 3] {
        h.map(|h| phi0 + c * h.powf(p))
    }

    #[test]
    fn recovers_order_and_limit_for_uniform_ratio() {
        for (p, c) in [(0.5, 2.0), (1.0, -0.7), (1.7, 3.0), (2.0, 1.0), (4.0, 50.0)] {
            let h = [0.025, 0.05, 0.1];
            let r = three_grid(h, manufactured(h, 1.0, c, p)).unwrap();
            assert!((r.p - p).abs() < 1e-9, "p = {} vs {p}", r.p);
            assert!((r.phi_ext - 1.0).abs() < 1e-9, "{}", r.phi_ext);
            assert_eq!(r.iterations, 0);
            assert!(!r.oscillatory);
            // The GCI with the exact p is 1.25 × the true relative error of φ1.
            let phi1 = manufactured(h, 1.0, c, p)[0];
            let true_rel = ((phi1 - 1.0) / phi1).abs();
            assert!(
                (r.gci_fine / true_rel - 1.25).abs() < 1e-6,
                "{} {true_rel}",
                r.gci_fine
            );
            // φext = 1, so e_ext = |φ1 − 1|.
            assert!((r.e_ext - (phi1 - 1.0).abs()).abs() < 1e-9);
        }
    }

    #[test]
    fn recovers_order_for_non_uniform_ratios_by_fixed_point() {
        // r21 = 1.75, r32 ≈ 1.43: q(p) ≠ 0, the iteration must run.
        let h = [0.04, 0.07, 0.1];
        let r = three_grid(h, manufactured(h, 1.0, 3.0, 1.7)).unwrap();
        assert!((r.p - 1.7).abs() < 1e-9, "{}", r.p);
        assert!((r.phi_ext - 1.0).abs() < 1e-9);
        assert!(r.iterations > 1);
        assert!((r.r21 - 1.75).abs() < 1e-12);
        // Same with a decreasing error towards the fine grid and a negative coefficient.
        let h = [1.0e-3, 1.5e-3, 2.6e-3];
        let r = three_grid(h, manufactured(h, -2.0, -40.0, 0.8)).unwrap();
        assert!((r.p - 0.8).abs() < 1e-9, "{}", r.p);
        assert!((r.phi_ext + 2.0).abs() < 1e-9);
    }

    #[test]
    fn oscillatory_convergence_is_flagged() {
        // φ_k = 1 + (−1)^k·c·h_k^p: the differences alternate in sign.
        let h: [f64; 3] = [0.025, 0.05, 0.1];
        let phi = [
            1.0 + 2.0 * h[0].powi(2),
            1.0 - 2.0 * h[1].powi(2),
            1.0 + 2.0 * h[2].powi(2),
        ];
        let r = three_grid(h, phi).unwrap();
        assert!(r.oscillatory);
        assert!((r.p - 2.0).abs() < 1e-9, "{}", r.p);
    }

    #[test]
    fn refuses_small_ratios_and_flat_data() {
        let h = [0.1, 0.12, 0.2];
        assert_eq!(
            three_grid(h, [1.0, 1.1, 1.3]).unwrap_err(),
            CelikFailure::RatioTooSmall
        );
        let h = [0.1, 0.2, 0.4];
        assert_eq!(
            three_grid(h, [1.0, 1.0, 1.3]).unwrap_err(),
            CelikFailure::NoChange
        );
        assert_eq!(
            three_grid(h, [1.0, f64::NAN, 1.3]).unwrap_err(),
            CelikFailure::NonFinite
        );
    }

    #[test]
    fn apparent_orders_along_a_sequence() {
        let h = [0.16, 0.08, 0.04, 0.02, 0.01];
        let v: Vec<f64> = h.iter().map(|&h: &f64| 5.0 + h * h.sqrt()).collect();
        let p = apparent_orders(&h, &v);
        assert_eq!(p.len(), 3);
        for p in p {
            assert!((p.unwrap() - 1.5).abs() < 1e-9);
        }
    }
}
