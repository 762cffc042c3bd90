//! Replayed Jacobians (docs/fit.md#replayed-jacobians): the derivative of the discrete
//! solution, by forward differences whose moved runs take the steps the run at the point
//! itself took (the run library's step plans), so that a difference measures the model's
//! change and not the step-size controller's jitter. One run per free parameter (at about
//! 0.8 of a run's cost: no rejected attempts), against 2–8 for central differences grown out
//! of the solver's noise; and no noise band, so the step is small and the derivative local.
//!
//! It applies where the fit's runs are adaptive (with fixed steps the fit keeps its
//! differences, and fit.json's `jacobian` says which was used). Under the profile strategy's
//! pin (a parameter solved at every point so that the first onset matches) the pinned
//! parameter's column is replayed too, and each other column follows the pin by the implicit
//! function: the derivative along the surface where the first onset stays put, which the
//! pinned model's differences approximate by re-solving the pin at every moved point.

use super::forward::JacobianKind;
use super::problem::{Eval, Problem};

/// The difference's step in box coordinates: a relative change of 1.4e-6–2.3e-6 in a
/// parameter searched over a factor 4–10 (log space). The replayed difference of the fit
/// study's set A is its derivative to 5e-5 over steps of 1e-7–1e-5 of the value; wider ones
/// span melting times that cross step boundaries, narrower ones see the rounding
/// (crates/stickslip-run/tests/replay.rs).
pub const STEP_Z: f64 = 1e-6;

/// Why a replayed Jacobian does not apply to `problem` (none when it does).
#[must_use]
pub fn not_applicable(problem: &Problem<'_, '_>) -> Option<&'static str> {
    if problem.jacobian != JacobianKind::Replay {
        Some("not asked for")
    } else if problem.forward.tolerance.is_none() {
        Some("fixed steps")
    } else {
        None
    }
}

/// The replayed Jacobian at `at` in the columns `free`: `Some(None)` where it does not apply
/// (the reason kept in the problem's `jacobian_fallback`: the caller takes differences),
/// `None` when interrupted.
pub fn columns(
    problem: &mut Problem<'_, '_>,
    at: &Eval,
    free: &[usize],
) -> Option<Option<Vec<Vec<f64>>>> {
    if not_applicable(problem).is_some() {
        return Some(None);
    }
    let made = replayed(problem, at, free)?;
    if let Err(why) = &made {
        problem.jacobian_fallback = Some(why);
    }
    Some(made.ok())
}

/// [`columns`] where it applies: `Err` says why it was not made.
fn replayed(
    problem: &mut Problem<'_, '_>,
    at: &Eval,
    free: &[usize],
) -> Option<Result<Vec<Vec<f64>>, &'static str>> {
    if at.failed.is_some() {
        return Some(Err("the point's run failed"));
    }
    // The run at `at` and its steps: kept from the batch that ran it, or run again at the
    // present level (the run is deterministic: the same residuals at the same level).
    let kept = problem
        .plan_at(&at.z)
        .filter(|_| at.level == problem.level)
        .map(|plan| (plan, at.residuals.clone()));
    let (plan, base) = match kept {
        Some(kept) => kept,
        None => {
            // As it is: with the pin off, a pinned coordinate keeps its solved value.
            let pin = problem.pin.take();
            let again = problem.evaluate_all(std::slice::from_ref(&at.z), false);
            problem.pin = pin;
            let again = again?;
            match (problem.plan_at(&at.z), again.first()) {
                (Some(plan), Some(e)) if e.failed.is_none() => (plan, e.residuals.clone()),
                _ => return Some(Err("the point's run failed")),
            }
        }
    };
    // With the profile strategy's pin, the pinned coordinate k follows the others so that
    // the first onset (residual 0) stays where it is: its column too, then each other
    // column plus k's times dz_k/dz_j = −(∂r0/∂z_j)/(∂r0/∂z_k) (the implicit function).
    let pinned = problem.pin.as_ref().map(|p| p.k);
    if pinned.is_some_and(|k| free.contains(&k)) {
        return Some(Err("the pinned parameter among the columns"));
    }
    let moved_coords: Vec<usize> = free.iter().copied().chain(pinned).collect();
    // Towards the inside of the box.
    let steps: Vec<f64> = moved_coords
        .iter()
        .map(|&j| {
            if at.z[j] + STEP_Z <= 1.0 {
                STEP_Z
            } else {
                -STEP_Z
            }
        })
        .collect();
    let zs: Vec<Vec<f64>> = moved_coords
        .iter()
        .zip(&steps)
        .map(|(&j, &h)| {
            let mut z = at.z.clone();
            z[j] += h;
            z
        })
        .collect();
    let pin = problem.pin.take();
    let moved = problem.evaluate_replayed(&zs, &plan);
    problem.pin = pin;
    let moved = moved?;
    if moved.iter().any(|e| e.failed.is_some()) {
        return Some(Err("a replayed run failed"));
    }
    let mut columns: Vec<Vec<f64>> = moved
        .iter()
        .zip(&steps)
        .map(|(e, &h)| {
            e.residuals
                .iter()
                .zip(&base)
                .map(|(a, b)| (a - b) / h)
                .collect()
        })
        .collect();
    if pinned.is_some() {
        let k_column = columns.pop()?;
        let onset_slope = k_column[0];
        if onset_slope == 0.0 || !onset_slope.is_finite() {
            return Some(Err(
                "the first onset does not move with the pinned parameter",
            ));
        }
        for column in &mut columns {
            let follow = -column[0] / onset_slope;
            for (c, k) in column.iter_mut().zip(&k_column) {
                *c += follow * k;
            }
        }
    }
    Some(Ok(columns))
}

/// fit.json's `jacobian`: `differences`, `replay`, or both with their counts and why replay
/// did not apply.
#[must_use]
pub fn words(problem: &Problem<'_, '_>) -> String {
    if problem.jacobian == JacobianKind::Differences {
        return JacobianKind::Differences.name().into();
    }
    match (problem.jacobians_made, not_applicable(problem)) {
        ((_, 0), _) => JacobianKind::Replay.name().into(),
        ((0, _), why) => format!(
            "differences (replay asked for; it does not apply: {})",
            why.or(problem.jacobian_fallback)
                .unwrap_or("the points' runs failed")
        ),
        ((r, d), _) => format!(
            "replay ({r}) and differences ({d}; the last because {})",
            problem.jacobian_fallback.unwrap_or("replay did not apply")
        ),
    }
}
