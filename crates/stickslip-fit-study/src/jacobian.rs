//! Item 3: the fit's Jacobian at its optimum against central differences at two other steps.
//! The fit's Jacobian — the one its uncertainty comes from — is recomputed at the optimum as
//! the fit computes it (`optimise::jacobian`: central differences at the fit's final steps,
//! grown until the residuals move by 100 times the solver's noise), then each column is
//! compared with central differences at twice and at half that step (a factor 4 apart): the
//! first shows the truncation error of the fit's step, the second the solver's noise.

use crate::prepared::Prepared;
use crate::record::{JacobianCheck, JacobianColumn};
use stickslip_studies::fit::forward::Forward;
use stickslip_studies::fit::misfit::Target;
use stickslip_studies::fit::params::Param;
use stickslip_studies::fit::problem::{Eval, Problem};
use stickslip_studies::fit::{FitOutcome, MisfitKind, optimise, parameters};

/// The step factors of the two central differences.
pub const FACTORS: [f64; 2] = [2.0, 0.5];

/// ‖a − b‖/‖a‖ (infinite for a zero column).
#[must_use]
pub fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let n: f64 = a.iter().map(|x| x * x).sum();
    if n > 0.0 {
        (d / n).sqrt()
    } else {
        f64::INFINITY
    }
}

/// What a fit of `p`'s trace compared with, rebuilt from its outcome: the target (the same
/// σF), the free parameters and the forward runs.
struct Rebuilt {
    target: Target,
    params: Vec<Param>,
    forward: Forward,
}

fn rebuild(p: &Prepared, out: &FitOutcome) -> Result<Rebuilt, String> {
    let r = &out.report;
    let kind = MisfitKind::from_name(&r.misfit_kind).map_err(|e| e.to_string())?;
    let target =
        Target::new(out.trace.clone(), kind, Some(r.noise_n)).map_err(|e| e.to_string())?;
    let params =
        parameters(&p.scene, &p.case.params, kind, &target.trace).map_err(|e| e.to_string())?;
    let shift_max = params.iter().find(|q| !q.scene_key).map_or(0.0, |q| q.hi);
    let t_end = target.trace.t_s.last().copied().unwrap_or(0.0);
    let forward = Forward::new(&p.scene, t_end + shift_max).map_err(|e| e.to_string())?;
    Ok(Rebuilt {
        target,
        params,
        forward,
    })
}

/// The misfit χ² of the true model (the time shift, if any, at 0) against the data of `out`:
/// a fit whose χ² is above it has missed the misfit's least value.
///
/// # Errors
/// As [`check`].
pub fn chi2_at_truth(p: &Prepared, out: &FitOutcome, jobs: usize) -> Result<f64, String> {
    let b = rebuild(p, out)?;
    let mut problem = Problem::new(&b.forward, &b.params, &b.target, jobs);
    let z: Vec<f64> = b
        .params
        .iter()
        .map(|q| q.z(p.case.true_value(&q.key).unwrap_or(0.0)))
        .collect();
    let e = problem
        .evaluate_all(std::slice::from_ref(&z), false)
        .ok_or("interrupted")?;
    Ok(e[0].chi2)
}

/// The check at the optimum of `out`, a fit of `p`'s trace with `seed`.
///
/// # Errors
/// The fit's inputs do not rebuild, or a run was interrupted.
pub fn check(
    p: &Prepared,
    out: &FitOutcome,
    seed: u64,
    jobs: usize,
) -> Result<JacobianCheck, String> {
    let r = &out.report;
    let b = rebuild(p, out)?;
    let params = &b.params;
    let mut problem = Problem::new(&b.forward, params, &b.target, jobs);
    problem.level = b.forward.level_of(r.time_tolerance);
    let z: Vec<f64> = params
        .iter()
        .zip(&r.parameters)
        .map(|(q, fp)| q.z(fp.value))
        .collect();
    let interrupted = || "interrupted".to_string();
    let at: Eval = problem
        .evaluate_all(std::slice::from_ref(&z), false)
        .ok_or_else(interrupted)?
        .remove(0);
    let noise = optimise::noise(&mut problem, &at).ok_or_else(interrupted)?;
    let mut steps = r.fd_steps.clone();
    let free: Vec<usize> = (0..params.len()).collect();
    let j = optimise::jacobian(&mut problem, &at, &free, &mut steps, noise, true)
        .ok_or_else(interrupted)?;
    let mut columns = Vec::new();
    for (k, column) in j.iter().enumerate() {
        let mut diffs = Vec::new();
        for f in FACTORS {
            let h = f * steps[k];
            let (a, b) = ((z[k] - h).max(0.0), (z[k] + h).min(1.0));
            let points: Vec<Vec<f64>> = [a, b]
                .iter()
                .map(|&v| {
                    let mut q = z.clone();
                    q[k] = v;
                    q
                })
                .collect();
            let e = problem
                .evaluate_all(&points, false)
                .ok_or_else(interrupted)?;
            let central: Vec<f64> = e[1]
                .residuals
                .iter()
                .zip(&e[0].residuals)
                .map(|(y, x)| (y - x) / (b - a))
                .collect();
            diffs.push(rel_diff(column, &central));
        }
        columns.push(JacobianColumn {
            key: params[k].key.clone(),
            step: steps[k],
            norm: column.iter().map(|x| x * x).sum::<f64>().sqrt(),
            rel_diff_wide: diffs[0],
            rel_diff_narrow: diffs[1],
        });
    }
    Ok(JacobianCheck {
        case: p.case.id.clone(),
        seed,
        misfit_kind: r.misfit_kind.clone(),
        solver_noise: noise,
        columns,
        evaluations: problem.evaluations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_relative_difference_is_in_units_of_the_first_column() {
        assert_eq!(rel_diff(&[3.0, 4.0], &[3.0, 4.0]), 0.0);
        assert!((rel_diff(&[3.0, 4.0], &[3.0, 3.5]) - 0.1).abs() < 1e-15);
        assert!(rel_diff(&[0.0], &[1.0]).is_infinite());
    }
}
