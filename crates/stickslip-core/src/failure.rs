//! [`NumericalFailure`]: a step that produced a non-finite or runaway value, with where and
//! when. Its own module, so that the preflight (which refuses configurations with it) and the
//! simulation need not import each other.

use thiserror::Error;

/// A step produced a non-finite or runaway value.
#[derive(Debug, Clone, PartialEq, Error)]
#[error(
    "numerical failure at t = {t_s:e} s, step {step}, node {node} (r = {r_m:e} m): \
     {quantity} = {value:e}. {diagnosis}"
)]
pub struct NumericalFailure {
    /// Time at the end of the failing step, s.
    pub t_s: f64,
    /// Number of the failing step (from 1).
    pub step: u64,
    /// Node where the bad value appeared first.
    pub node: usize,
    /// Radius of that node, m.
    pub r_m: f64,
    /// Which quantity (`phi`, `tau`, `u3d`, `X`, …).
    pub quantity: &'static str,
    /// The bad value.
    pub value: f64,
    /// What it means and what to do.
    pub diagnosis: String,
}
