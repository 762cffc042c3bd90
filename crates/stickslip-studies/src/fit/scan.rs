//! The profile strategy (docs/fit.md#the-profile-strategy), a global search for a fit with
//! three or more parameters whose data begin with a long stick (`FitOptions::strategy`;
//! not yet `stickslip fit`'s: it does not meet its target, see the docs):
//!
//! 1. **The needle removed.** The Jacobian at the start; the parameter with the largest
//!    share of its leading right singular vector (the combination the data fix most
//!    sharply: the first onset's) is pinned: at every later point it is solved so that the
//!    first onset matches ([`super::pin`]).
//! 2. **The first meltings first.** The search runs on the data's first [`WINDOW_EVENTS`]
//!    meltings ([`profile_fit`]), then the local stage on the whole trace from what it found.
//! 3. **The weakest direction scanned.** Of the unpinned parameters, the one with the widest
//!    marginal interval once the pinned one is solved out (the SFA contact's γ) is held at
//!    [`SCAN_POINTS`] values, the centres of equal strata of its box. A stratified sample of
//!    the unpinned parameters, [`SAMPLE_PER_PARAM`] points per parameter, gives each value
//!    its stratum's best point as the start of a few local iterations over the rest: a
//!    profile likelihood, used as the global search.
//! 4. **The final fit** goes on from the profile's best point with every parameter but the
//!    pinned one free (the pin still on), to convergence; the caller then takes the
//!    uncertainty with every parameter free.

use super::forward::Forward;
use super::linalg::{Svd, svd};
use super::misfit::{MisfitKind, Target};
use super::optimise::{self, Damping, Local, SolverNoise};
use super::pin::Pin;
use super::problem::{Eval, Problem};
use super::report::FitScan;

/// Values of the scanned parameter.
pub const SCAN_POINTS: usize = 6;
/// Points of the stratified sample per parameter left once the pin is solved.
pub const SAMPLE_PER_PARAM: usize = 8;
/// Local iterations at each scanned value: the profile needs each value's optimum to well
/// within the differences between values, not to convergence.
pub const SCAN_ITERATIONS: usize = 3;

/// Meltings of the data in the first stage's window ([`profile_fit`]). Not fewer: on the
/// SFA contact's first slip (12 meltings) the first four left several minima along the
/// valley of τmax, h0 and γ at χ² 10³–10⁴ (γ from 3.6 to 25; the truth's 8), from which the
/// whole trace's local stage did not come back; on the first eight the scan's best value
/// led the local stage into the truth's valley (docs/fit.md, "The profile strategy").
pub const WINDOW_EVENTS: usize = 8;

/// The data's first `count` meltings alone: the trace cut half-way between the onsets of its
/// meltings `count` and `count + 1`, with the whole trace's σF. `None` when the data hold
/// fewer than `count + 2` meltings (the window would be most of the trace).
#[must_use]
pub fn first_meltings(target: &Target, count: usize) -> Option<Target> {
    let ev = &target.events;
    if count == 0 || ev.len() < count + 2 {
        return None;
    }
    let t_cut = 0.5 * (ev[count - 1].t_onset_s + ev[count].t_onset_s);
    let t = &target.trace.t_s;
    let n = t.partition_point(|&x| x <= t_cut);
    let trace = super::data::Trace::new(
        t[..n].to_vec(),
        target.trace.f_n[..n].to_vec(),
        target.trace.x_m.as_ref().map(|x| x[..n].to_vec()),
    )
    .ok()?;
    let short = Target::new(trace, MisfitKind::Events, Some(target.sigma_f_n)).ok()?;
    (short.events.len() == count).then_some(short)
}

/// The profile strategy from the box point `z0`: the search ([`profile_search`]) on the
/// data's first [`WINDOW_EVENTS`] meltings, then the local stage on the whole trace from
/// what it found (the pin on). The late intervals of a long slip are the most sensitive
/// residuals and the least linear far from the truth; the first meltings leave a wide,
/// smooth basin, and their optimum lies well inside the whole trace's. Where the data hold
/// too few meltings for a shorter window, the search runs on the whole trace. `None` as
/// [`profile_search`].
pub fn profile_fit(
    problem: &mut Problem<'_, '_>,
    z0: Vec<f64>,
    steps: &mut [f64],
    noise: &mut Option<SolverNoise>,
) -> Option<(Local, FitScan)> {
    let whole = |problem: &mut Problem<'_, '_>, z: Vec<f64>| {
        problem
            .evaluate_all(&[z], false)
            .and_then(|mut e| e.pop())
            .filter(|e| e.failed.is_none())
    };
    let Some(short) = first_meltings(problem.target, WINDOW_EVENTS) else {
        let first = whole(problem, z0)?;
        return profile_search(problem, &first, steps, noise);
    };
    let end_s = *short.trace.t_s.last()?;
    let forward = Forward::new(&problem.forward.base, end_s).ok()?;
    let mut sp = Problem::new(&forward, problem.params, &short, problem.jobs);
    sp.jacobian = problem.jacobian;
    sp.max_level = 0;
    sp.interrupt = problem.interrupt;
    sp.progress = problem.progress.take();
    (sp.evaluations, sp.failed_runs, sp.onset_runs) =
        (problem.evaluations, problem.failed_runs, problem.onset_runs);
    let mut short_noise = None;
    let found = whole(&mut sp, z0)
        .and_then(|first| profile_search(&mut sp, &first, steps, &mut short_noise));
    problem.progress = sp.progress.take();
    (problem.evaluations, problem.failed_runs, problem.onset_runs) =
        (sp.evaluations, sp.failed_runs, sp.onset_runs);
    problem.jacobians_made.0 += sp.jacobians_made.0;
    problem.jacobians_made.1 += sp.jacobians_made.1;
    problem.jacobian_fallback = problem.jacobian_fallback.or(sp.jacobian_fallback);
    if problem.first_failure.is_none() {
        problem.first_failure = sp.first_failure.take();
    }
    if sp.interrupted() {
        problem.stop();
        return None;
    }
    let (l, mut scan) = found?;
    scan.window_events = Some(WINDOW_EVENTS);
    problem.pin = sp.pin.take();
    problem.stage = "local";
    let first = whole(problem, l.best.z)?;
    let mut n = optimise::measure(problem, &first)?;
    let k = problem.pin.as_ref()?.k;
    let free: Vec<usize> = (0..problem.params.len()).filter(|&j| j != k).collect();
    problem.stage = "local";
    let mut local = optimise::levenberg_marquardt_damped(
        problem,
        first,
        &free,
        (steps, &mut n),
        optimise::MAX_ITERATIONS,
        Damping::Weak,
    );
    local.iterations += l.iterations;
    *noise = Some(n);
    Some((local, scan))
}

/// The pinned and the scanned parameter (indices among the fit's parameters) from the
/// Jacobian's columns `columns` over all parameters, and the first onset's slope along the
/// pinned one; `None` when fewer than three parameters, or the first onset does not move.
#[must_use]
pub fn choose(columns: &[Vec<f64>], d: &Svd) -> Option<(usize, usize, f64)> {
    let p = columns.len();
    if p < 3 {
        return None;
    }
    let lead = &d.v[0];
    let k = (0..p).max_by(|&a, &b| lead[a].abs().total_cmp(&lead[b].abs()))?;
    let slope = columns[k][0];
    if !(slope.is_finite() && slope != 0.0) {
        return None;
    }
    // The others with the pinned one solved out along the first onset: moving z_j by δ
    // moves z_k by −(∂r0/∂z_j)/(∂r0/∂z_k)·δ.
    let rest: Vec<usize> = (0..p).filter(|&j| j != k).collect();
    let reduced: Vec<Vec<f64>> = rest
        .iter()
        .map(|&j| {
            let ratio = columns[j][0] / slope;
            columns[j]
                .iter()
                .zip(&columns[k])
                .map(|(a, b)| a - ratio * b)
                .collect()
        })
        .collect();
    let r = svd(&reduced)?;
    // Marginal variance of each (box units²): Σᵢ (vᵢⱼ/sᵢ)²; a null direction is infinite.
    let variance = |c: usize| -> f64 {
        r.s.iter()
            .zip(&r.v)
            .map(|(s, v)| {
                if *s > 0.0 {
                    (v[c] / s).powi(2)
                } else {
                    f64::INFINITY
                }
            })
            .sum()
    };
    let widest = (0..rest.len()).max_by(|&a, &b| variance(a).total_cmp(&variance(b)))?;
    Some((k, rest[widest], slope))
}

/// The scanned values in box coordinates: the centres of [`SCAN_POINTS`] equal strata.
#[must_use]
pub fn scan_values() -> Vec<f64> {
    (0..SCAN_POINTS)
        .map(|i| (i as f64 + 0.5) / SCAN_POINTS as f64)
        .collect()
}

/// The profile strategy's global search and local stage from `start` (a successful
/// evaluation with the pin off). Sets `problem.pin`. Returns the local stage's answer and
/// the scan for fit.json; `None` when the strategy does not apply (fewer than three
/// parameters, a first onset that does not move) or the fit was interrupted before the scan
/// ended (then `problem.best` holds the best so far).
pub fn profile_search(
    problem: &mut Problem<'_, '_>,
    start: &Eval,
    steps: &mut [f64],
    noise: &mut Option<SolverNoise>,
) -> Option<(Local, FitScan)> {
    let p = problem.params.len();
    let all: Vec<usize> = (0..p).collect();
    problem.stage = "scan";
    let columns = optimise::jacobian(problem, start, &all, steps, 0.0, false)?;
    let d = svd(&columns)?;
    let (k, s, slope) = choose(&columns, &d)?;
    problem.pin = Some(Pin {
        k,
        slope,
        gradient: columns.iter().map(|c| c[0]).collect(),
        anchor: start.z.clone(),
        anchor_residual: start.residuals[0],
        tolerance: super::pin::tolerance_for(start.chi2, start.residuals.len()),
    });
    let rest: Vec<usize> = (0..p).filter(|&j| j != k && j != s).collect();
    let values = scan_values();
    // A stratified sample of the space left once the pin is solved (every parameter but the
    // pinned one), as many points in each of the scanned parameter's strata: each scanned
    // value starts from its stratum's best point. Warm starts from the scene's values alone
    // leave the other parameters too far off: at the SFA contact's start (h0 and G* an
    // eighth of their boxes off), χ² is 10⁸ times the truth's and the local stage barely
    // moves them.
    let free_rest: Vec<usize> = (0..p).filter(|&j| j != k).collect();
    let per_stratum = (SAMPLE_PER_PARAM * free_rest.len()).div_ceil(SCAN_POINTS);
    let sample =
        optimise::latin_hypercube(per_stratum * SCAN_POINTS, free_rest.len(), optimise::SEED);
    let points: Vec<Vec<f64>> = sample
        .iter()
        .map(|u| {
            let mut z = start.z.clone();
            for (c, &j) in free_rest.iter().enumerate() {
                z[j] = u[c];
            }
            z
        })
        .collect();
    let sampled = problem.evaluate_all(&points, false)?;
    let stratum = |z: f64| ((z * SCAN_POINTS as f64) as usize).min(SCAN_POINTS - 1);
    let mut n = match *noise {
        Some(n) => n,
        None => {
            let best = sampled
                .iter()
                .filter(|e| e.failed.is_none())
                .min_by(|a, b| a.chi2.total_cmp(&b.chi2))
                .unwrap_or(start);
            optimise::measure(problem, best)?
        }
    };
    let max_level = std::mem::replace(&mut problem.max_level, problem.level);
    let mut optima: Vec<Eval> = Vec::with_capacity(values.len());
    for (i, &v) in values.iter().enumerate() {
        let from = sampled
            .iter()
            .filter(|e| e.failed.is_none() && stratum(e.z[s]) == i)
            .min_by(|a, b| a.chi2.total_cmp(&b.chi2))
            .or_else(|| optima.iter().min_by(|a, b| a.chi2.total_cmp(&b.chi2)))
            .map_or_else(|| start.z.clone(), |e| e.z.clone());
        let mut z = from;
        z[s] = v;
        problem.stage = "scan";
        let first = problem.evaluate_all(&[z], false)?.pop()?;
        let local = optimise::levenberg_marquardt_damped(
            problem,
            first,
            &rest,
            (steps, &mut n),
            SCAN_ITERATIONS,
            Damping::Weak,
        );
        if problem.interrupted() {
            *noise = Some(n);
            return None;
        }
        optima.push(local.best);
    }
    *noise = Some(n);
    problem.max_level = max_level;
    let found = optima;
    let best = found
        .iter()
        .filter(|e| e.failed.is_none())
        .min_by(|a, b| a.chi2.total_cmp(&b.chi2))?
        .clone();
    let scan = FitScan {
        pinned: problem.params[k].key.clone(),
        key: problem.params[s].key.clone(),
        values: found
            .iter()
            .map(|e| problem.params[s].value(e.z[s]))
            .collect(),
        chi2: found.iter().map(|e| e.chi2).collect(),
        start: problem.params[s].value(best.z[s]),
        window_events: None,
    };
    // The final fit: every parameter but the pinned one, from the profile's best point.
    problem.stage = "local";
    let mut n = noise.unwrap_or(SolverNoise {
        value: 0.0,
        at_chi2: best.chi2,
    });
    let local = optimise::levenberg_marquardt_damped(
        problem,
        best,
        &free_rest,
        (steps, &mut n),
        optimise::MAX_ITERATIONS,
        Damping::Weak,
    );
    *noise = Some(n);
    Some((local, scan))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sharpest_parameter_is_pinned_and_the_widest_of_the_rest_scanned() {
        // Residual 0 (the first onset) moves 1e4 per box unit of parameter 0 and 2e3 of
        // parameter 2; the other residuals see parameter 1 weakly (its interval widest),
        // parameter 2 strongly.
        let columns = vec![
            vec![1e4, 1.0, 0.5, 0.0],
            vec![1.0, 0.1, -0.05, 0.02],
            vec![2e3, 3.0, 1.0, 2.0],
        ];
        let d = svd(&columns).unwrap();
        let (k, s, slope) = choose(&columns, &d).unwrap();
        assert_eq!((k, s), (0, 1));
        assert_eq!(slope, 1e4);
        // Two parameters: nothing to scan besides the pinned one.
        assert!(choose(&columns[..2], &svd(&columns[..2]).unwrap()).is_none());
    }

    #[test]
    fn the_scan_spreads_over_the_box() {
        let v = scan_values();
        assert_eq!(v.len(), SCAN_POINTS);
        assert!(v[0] > 0.0 && v[SCAN_POINTS - 1] < 1.0);
        assert!(
            v.windows(2)
                .all(|w| (w[1] - w[0] - 1.0 / SCAN_POINTS as f64).abs() < 1e-12)
        );
    }
}
