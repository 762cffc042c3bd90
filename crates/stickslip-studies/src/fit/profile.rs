//! The profile likelihood of one parameter (`--profile KEY`): the parameter held at each of
//! [`POINTS`] values across its 95 % interval widened to ±3 standard errors (the whole box
//! when its error is unknown), clipped to its bounds, and the other parameters refitted by the
//! local stage from the optimum at each. Where Δ = (χ² − χ²min)/s² ≤ 3.84 (the 95 % point of
//! χ² with one degree of freedom) is the profile's 95 % interval: unlike the covariance's, it
//! follows a misfit that is not quadratic.

use super::optimise::{MAX_ITERATIONS, SolverNoise, levenberg_marquardt};
use super::problem::{Eval, Problem};
use crate::fit::report::FitProfile;

/// Values of the profiled parameter.
pub const POINTS: usize = 9;
/// Δχ²/s² at the edge of a 95 % interval of one parameter.
pub const CHI2_95: f64 = 3.841_458_820_694_124;

/// The profile of parameter `k` around `best`, whose standard error in box units is
/// `sigma_z` and residual variance `s2`. `None` when interrupted.
pub fn profile(
    problem: &mut Problem<'_, '_>,
    best: &Eval,
    k: usize,
    sigma_z: f64,
    s2: f64,
    steps: &mut [f64],
    noise: &mut SolverNoise,
) -> Option<FitProfile> {
    problem.stage = "profile";
    let p = problem.params.len();
    let z0 = best.z[k];
    let (a, b) = if sigma_z.is_finite() && sigma_z > 0.0 {
        ((z0 - 3.0 * sigma_z).max(0.0), (z0 + 3.0 * sigma_z).min(1.0))
    } else {
        (0.0, 1.0)
    };
    let grid: Vec<f64> = (0..POINTS)
        .map(|i| a + (b - a) * i as f64 / (POINTS - 1) as f64)
        .collect();
    let free: Vec<usize> = (0..p).filter(|&j| j != k).collect();
    let starts: Vec<Vec<f64>> = grid
        .iter()
        .map(|&zk| {
            let mut z = best.z.clone();
            z[k] = zk;
            z
        })
        .collect();
    let mut evals = problem.evaluate_all(&starts, false)?;
    if !free.is_empty() {
        for e in &mut evals {
            let local =
                levenberg_marquardt(problem, e.clone(), &free, steps, noise, MAX_ITERATIONS);
            if problem.interrupted() {
                return None;
            }
            *e = local.best;
        }
    }
    let chi2: Vec<f64> = evals.iter().map(|e| e.chi2).collect();
    let min = chi2.iter().copied().fold(best.chi2, f64::min);
    let delta: Vec<f64> = chi2
        .iter()
        .map(|c| (c - min) / s2.max(f64::MIN_POSITIVE))
        .collect();
    let param = &problem.params[k];
    let values: Vec<f64> = grid.iter().map(|&z| param.value(z)).collect();
    // The crossing of 3.84 on each side of the least Δ, linearly interpolated.
    let i_min = (0..POINTS)
        .min_by(|&i, &j| delta[i].total_cmp(&delta[j]))
        .unwrap_or(0);
    let cross = |i: usize, j: usize| {
        let w = (CHI2_95 - delta[i]) / (delta[j] - delta[i]);
        values[i] + w * (values[j] - values[i])
    };
    let lo95 = (1..=i_min)
        .rev()
        .find(|&i| delta[i - 1] > CHI2_95)
        .map(|i| cross(i, i - 1));
    let hi95 = (i_min..POINTS - 1)
        .find(|&i| delta[i + 1] > CHI2_95)
        .map(|i| cross(i, i + 1));
    Some(FitProfile {
        key: param.key.clone(),
        values,
        chi2,
        delta,
        lo95,
        hi95,
    })
}
