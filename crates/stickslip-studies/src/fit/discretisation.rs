//! The fit's discretisation error: how far each fitted parameter would move if the model were
//! computed finer. A fit at the N it can afford carries the model's spatial and time-stepping
//! error into its parameters, and the statistical interval does not contain it (data made at
//! N = 200 and fitted at N = 50 put τmax 15 % low, 2700 standard errors from the truth).
//!
//! At the optimum z* the model is run once more at twice the nodes (radial contacts of at most
//! [`MAX_NODES`] / 2 nodes) and a tenth of the fit's tolerance (half its step with fixed
//! steps). The refined residuals differ from the fit's by δr; the Gauss–Newton step of the
//! refined model from z*, δz = −J⁺·δr with the pseudo-inverse of the Jacobian J at the optimum
//! (directions the data do not determine left out, as the intervals leave them out), is the
//! shift each parameter would take. Its size, in the parameter's unit, is reported beside the
//! standard error as the discretisation error, and a warning is given where it is larger.

use super::forward::{Forward, Run};
use super::linalg::{Svd, dot};
use super::misfit::Target;
use super::params::Param;
use super::problem::Eval;
use std::sync::atomic::AtomicBool;

/// Most nodes a refined run may have (the key's upper bound).
pub const MAX_NODES: usize = 20_000;

/// Singular values below this fraction of the largest are directions left out of the shift
/// (as [`super::uncertainty`] leaves them out of the intervals).
const SINGULAR_CUTOFF: f64 = 1e-12;

/// What the refined run gave.
#[derive(Debug, Clone, PartialEq)]
pub struct Discretisation {
    /// The refinement, as --set text (e.g. `contact.nodes=200`, `time.tolerance=5e-7`).
    pub settings: Vec<String>,
    /// Per parameter, the shift's size in its unit (the time shift of the trace misfit
    /// included).
    pub shifts: Vec<f64>,
}

/// The refined model's settings for `forward` at tolerance `level`.
fn refinement(forward: &Forward, level: u32) -> Vec<String> {
    let c = &forward.base.config;
    let mut out = Vec::new();
    let radial = c.contact.model == stickslip_core::config::ContactModel::Radial;
    if radial && 2 * c.contact.nodes <= MAX_NODES {
        out.push(
            stickslip_run::keys::contact::NODES
                .set(2 * c.contact.nodes as i64)
                .to_string(),
        );
    }
    out.push(match forward.tolerance_at(level) {
        Some(tol) => stickslip_run::keys::time::TOLERANCE
            .set(tol / 10.0)
            .to_string(),
        None => stickslip_run::keys::time::DT
            .set(c.time.dt_s / 2.0)
            .to_string(),
    });
    out
}

/// Runs the refined model at `best` and returns each parameter's shift; `None` when the run
/// fails or is interrupted, or the scene refuses the refinement.
#[must_use]
pub fn estimate(
    forward: &Forward,
    (params, target): (&[Param], &Target),
    (best, level): (&Eval, u32),
    d: &Svd,
    interrupt: Option<&AtomicBool>,
) -> Option<Discretisation> {
    let settings = refinement(forward, level);
    let mut overrides = forward.overrides_at(params, &best.z, level);
    overrides.extend(settings.iter().cloned());
    let scene = forward.base.with_overrides(&overrides).ok()?;
    let curve = match super::forward::run_resolved(&scene, interrupt) {
        Run::Done(curve) => curve,
        Run::Failed(_) | Run::Interrupted => return None,
    };
    let shift_s = params
        .iter()
        .zip(&best.z)
        .find(|(p, _)| !p.scene_key)
        .map_or(0.0, |(p, &z)| p.value(z));
    let refined = target.compare(&curve, shift_s).residuals;
    if refined.len() != best.residuals.len() {
        return None;
    }
    let dr: Vec<f64> = refined
        .iter()
        .zip(&best.residuals)
        .map(|(a, b)| a - b)
        .collect();
    let dz = pseudo_solve(d, &dr);
    let shifts = params
        .iter()
        .zip(&best.z)
        .zip(&dz)
        .map(|((p, &z), &dz)| {
            // The shift in the parameter's unit, exactly along its box map (not linearised: a
            // log box's shift is asymmetric, and the larger side counts).
            let to = (z - dz).clamp(0.0, 1.0);
            (p.value(to) - p.value(z)).abs()
        })
        .collect();
    Some(Discretisation { settings, shifts })
}

/// δz = J⁺·δr from the SVD of J (columns: the free box coordinates): Σ v_k·(u_k·δr)/s_k over
/// the determined directions.
fn pseudo_solve(d: &Svd, dr: &[f64]) -> Vec<f64> {
    let p = d.v.first().map_or(0, Vec::len);
    let smax = d.s.first().copied().unwrap_or(0.0);
    let mut dz = vec![0.0; p];
    for (k, &s) in d.s.iter().enumerate() {
        if !(s > SINGULAR_CUTOFF * smax && s > 0.0) {
            continue;
        }
        let c = dot(&d.u[k], dr) / s;
        for (i, x) in dz.iter_mut().enumerate() {
            *x += c * d.v[k][i];
        }
    }
    dz
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pseudo_inverse_solves_a_determined_least_squares_problem() {
        // J = [[1, 0], [0, 2], [1, 1]]; δr = J·[0.3, −0.2] is solved exactly.
        let cols = vec![vec![1.0, 0.0, 1.0], vec![0.0, 2.0, 1.0]];
        let d = super::super::linalg::svd(&cols).unwrap();
        let dr: Vec<f64> = (0..3)
            .map(|i| 0.3 * cols[0][i] - 0.2 * cols[1][i])
            .collect();
        let dz = pseudo_solve(&d, &dr);
        assert!(
            (dz[0] - 0.3).abs() < 1e-12 && (dz[1] + 0.2).abs() < 1e-12,
            "{dz:?}"
        );
    }

    #[test]
    fn an_undetermined_direction_is_left_out() {
        // Two equal columns: only their sum is determined; the shift splits it evenly.
        let cols = vec![vec![1.0, 2.0], vec![1.0, 2.0]];
        let d = super::super::linalg::svd(&cols).unwrap();
        let dz = pseudo_solve(&d, &[1.0, 2.0]);
        assert!(
            (dz[0] - 0.5).abs() < 1e-12 && (dz[1] - 0.5).abs() < 1e-12,
            "{dz:?}"
        );
    }
}
