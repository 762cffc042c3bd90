//! stickslip-convergence: observed orders of accuracy from error sequences (Celik et al. 2008).
//!
//! Invariant: this crate only calls `stickslip-core`'s public API.

/// Observed orders p_k = ln(e_k / e_{k+1}) / ln(h_k / h_{k+1}) for errors `errors`
/// measured at resolutions `spacings` (any decreasing sequence of step sizes).
///
/// # Panics
/// If the two slices have different lengths.
#[track_caller]
pub fn observed_orders(spacings: &[f64], errors: &[f64]) -> Vec<f64> {
    assert_eq!(spacings.len(), errors.len(), "one error per spacing");
    spacings
        .windows(2)
        .zip(errors.windows(2))
        .map(|(h, e)| (e[0] / e[1]).ln() / (h[0] / h[1]).ln())
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
}
