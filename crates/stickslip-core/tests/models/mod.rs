//! Exact models × methods: each model states its problem and its exact solution, each method
//! steps a model, and one [`assert_order`] measures any method's observed order on any model
//! (an error at successive halvings of the step, or doublings of the nodes) against the order
//! it must have. Shared by the test files through `mod models;`.

#![allow(dead_code)] // each test file uses the models it needs

pub mod landau;
pub mod spring;

/// A method applied to a model: its error at refinement level `level` (a step of T/2^level,
/// or 2^level·N0 nodes), measured against the model's exact solution.
pub trait Convergent {
    /// What is measured, for the printed table and the failure message.
    fn label(&self) -> String;
    /// The levels to measure at: the first where the method is in its asymptotic range, and
    /// enough above it for the last orders to be trusted, while the error stays far above
    /// rounding.
    fn levels(&self, order: f64) -> std::ops::RangeInclusive<u32>;
    /// The error at `level`, normalised by the solution's scale.
    fn error(&self, level: u32) -> f64;
}

/// Observed orders log2(e_k/e_{k+1}) of successive errors.
#[must_use]
pub fn observed_orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// Measures `case`'s errors over its levels, prints them with the observed orders, and asserts
/// that the last three orders are within `order ± band`. Returns the errors.
pub fn assert_order(case: &impl Convergent, order: f64, band: f64) -> Vec<f64> {
    let levels = case.levels(order);
    let errors: Vec<f64> = levels.clone().map(|k| case.error(k)).collect();
    let orders = observed_orders(&errors);
    eprintln!("{}: expected order {order} ± {band}", case.label());
    for (i, k) in levels.enumerate() {
        let p = if i > 0 {
            format!("{:.4}", orders[i - 1])
        } else {
            "-".into()
        };
        eprintln!("  level {k:<2} error {:.3e}  observed order {p}", errors[i]);
    }
    let last = &orders[orders.len().saturating_sub(3)..];
    assert!(
        last.iter()
            .all(|p| (order - band..=order + band).contains(p)),
        "{}: observed orders {orders:.4?}, expected {order} ± {band} over the last three",
        case.label()
    );
    errors
}
