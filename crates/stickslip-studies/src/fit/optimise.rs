//! The optimiser (docs/fit.md#optimiser), in the unit box of the parameters' coordinates:
//!
//! 1. **Global stage**: a scrambled Latin hypercube sample of the box (each parameter's range
//!    cut into n strata, one point in each, strata paired at random; a fixed seed, so a fit is
//!    reproducible) plus the scene's own values, run `jobs` at a time. The misfit is
//!    multimodal — an event more or less is a cliff, and a sharply determined parameter
//!    makes a narrow valley the sample rarely falls into — so the local stage starts from the
//!    best [`STARTS`] distinct points of the sample, each for [`SCREEN_ITERATIONS`]
//!    iterations, and goes on to convergence from the best of those.
//! 2. **Local stage**: Levenberg–Marquardt bounded by projection onto the box, its step from
//!    the Jacobian's SVD, δ = −Σ σᵢ/(σᵢ² + λ)·(uᵢ·r)·vᵢ; each iteration tries `jobs` damping
//!    values at once (λ, 16λ, …) and keeps the best that lowers χ²; a small gain from a
//!    step the damping held back is tried once more from λ = σ²min ([`after_step`]) before
//!    it counts as convergence. Jacobians are central
//!    differences (one-sided at a bound) whose step per parameter grows from 1e-3 of the box
//!    until the residuals move by at least [`NOISE_RATIO`] times the solver's noise, so the
//!    derivative's error from that noise is below 1/[`NOISE_RATIO`] of it.

use super::linalg::{dot, svd};
use super::problem::{Eval, Problem};

/// Points of the global sample per free parameter.
pub const GLOBAL_PER_PARAM: usize = 8;
/// Fewest points of the global sample.
pub const GLOBAL_MIN: usize = 16;
/// The seed of the global sample.
pub const SEED: u64 = 0x5ee5_f17e_d00d_1e55;
/// First finite-difference step, in box units.
pub const FD_STEP_START: f64 = 1e-3;
/// Largest finite-difference step, in box units.
pub const FD_STEP_MAX: f64 = 0.05;
/// A difference must exceed the solver's noise this many times...
pub const NOISE_RATIO: f64 = 100.0;
/// ...unless that takes it beyond the linear range ([`LINEAR_MAX`]); then this many times.
pub const NOISE_RATIO_LEAST: f64 = 10.0;
/// A difference (‖r(z + h) − r(z − h)‖) larger than this many times the residuals' typical
/// size, max(1, √(χ²/m)), leaves the range where the misfit is linear near its optimum: the
/// step shrinks. A parameter the data fix to a millionth (the SFA contact's τmax, by its first
/// onset) moved 1e-3 of its box shifts the residuals by thousands of σ, and the uncertainty
/// from that secant is not the curvature's.
pub const LINEAR_MAX: f64 = 10.0;
/// Smallest finite-difference step, in box units.
pub const FD_STEP_MIN: f64 = 1e-8;

/// The band (lower, upper) a column's difference is steered into: above [`NOISE_RATIO`]
/// times the solver's `noise` where that stays below a quarter of [`LINEAR_MAX`], at least
/// [`NOISE_RATIO_LEAST`] times it; below [`LINEAR_MAX`] times the residuals' typical size
/// (and at least four times the lower end, so that a fourfold step change cannot skip it).
#[must_use]
pub fn difference_band(noise: f64, chi2: f64, m: usize) -> (f64, f64) {
    let scale = (chi2 / m.max(1) as f64).sqrt().max(1.0);
    let linear = LINEAR_MAX * scale;
    let lower = (NOISE_RATIO * noise)
        .min(linear / 4.0)
        .max(NOISE_RATIO_LEAST * noise);
    (lower, linear.max(4.0 * lower))
}
/// Most Levenberg–Marquardt iterations.
pub const MAX_ITERATIONS: usize = 40;
/// Starts of the local stage (the best distinct points of the global sample).
pub const STARTS: usize = 3;
/// Iterations from each start before the best goes on.
pub const SCREEN_ITERATIONS: usize = 4;
/// Two starts are distinct when they differ by more than this in some box coordinate.
pub const DISTINCT: f64 = 0.1;

/// The best `STARTS` successful evaluations of `sorted` (by χ²) that are [`DISTINCT`].
#[must_use]
pub fn starts(sorted: &[Eval]) -> Vec<Eval> {
    let mut out: Vec<Eval> = Vec::new();
    for e in sorted.iter().filter(|e| e.failed.is_none()) {
        let far = out
            .iter()
            .all(|o| o.z.iter().zip(&e.z).any(|(a, b)| (a - b).abs() > DISTINCT));
        if far {
            out.push(e.clone());
        }
        if out.len() == STARTS {
            break;
        }
    }
    out
}
/// Distances along the weakest direction, in box units, at which [`valley`] looks for a
/// lower point (each way).
pub const VALLEY_STEPS: [f64; 4] = [0.03, 0.07, 0.15, 0.3];
/// Most walks along the valley after the local stage.
pub const VALLEY_WALKS: usize = 2;

/// Points along the misfit's valley through `at`: moved along the Jacobian's weakest
/// direction by [`VALLEY_STEPS`] each way (to the box's edge), each brought back to the
/// valley's floor by one Gauss–Newton step in the other directions (with `at`'s Jacobian `d`).
/// A parameter the data fix sharply (the SFA contact's τmax, to a millionth) makes a valley
/// far narrower than any global sample's spacing, and further minima along it — seen from one
/// of them, the others are no lower in any local direction. `None` when interrupted.
pub fn valley(
    problem: &mut Problem<'_, '_>,
    at: &Eval,
    free: &[usize],
    d: &super::linalg::Svd,
) -> Option<Vec<Eval>> {
    let p = d.s.len();
    if p < 2 {
        return Some(Vec::new());
    }
    let weak = &d.v[p - 1];
    let moved: Vec<Vec<f64>> = VALLEY_STEPS
        .iter()
        .flat_map(|&t| [t, -t])
        .map(|t| {
            let mut z = at.z.clone();
            for (k, &j) in free.iter().enumerate() {
                z[j] = (z[j] + t * weak[k]).clamp(0.0, 1.0);
            }
            z
        })
        .collect();
    let first = problem.evaluate_all(&moved, false)?;
    let corrected: Vec<Vec<f64>> = first
        .iter()
        .map(|e| {
            let mut z = e.z.clone();
            if e.failed.is_none() {
                for i in 0..p - 1 {
                    let c = -dot(&d.u[i], &e.residuals) / d.s[i];
                    for (k, &j) in free.iter().enumerate() {
                        z[j] += c * d.v[i][k];
                    }
                }
                z.iter_mut().for_each(|x| *x = x.clamp(0.0, 1.0));
            }
            z
        })
        .collect();
    let mut out = problem.evaluate_all(&corrected, false)?;
    out.extend(first);
    Some(out)
}

/// Stop when an accepted step lowers χ² by less than this fraction...
pub const RTOL_CHI2: f64 = 1e-6;
/// ...or by less than this (σ² units): the parameters are then within a tenth of their
/// standard errors of where the step came from, and gains below it are the solver's noise
/// more than the misfit's slope. On the SFA contact's first slip, started at the truth, the
/// local stage spent about 100 runs at the runs' tightest tolerances on gains from 0.14 to
/// 0.01.
pub const CHI2_GAIN_MIN: f64 = 1e-2;

/// A small deterministic generator (SplitMix64) for the sample: the fit must not depend on
/// the host.
struct Mix(u64);

impl Mix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A scrambled Latin hypercube of `n` points in the unit box of `p` dimensions.
#[must_use]
pub fn latin_hypercube(n: usize, p: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = Mix(seed);
    let mut out = vec![vec![0.0; p]; n];
    for j in 0..p {
        let mut strata: Vec<usize> = (0..n).collect();
        // Fisher–Yates.
        for i in (1..n).rev() {
            let k = (rng.next() % (i as u64 + 1)) as usize;
            strata.swap(i, k);
        }
        for (i, point) in out.iter_mut().enumerate() {
            point[j] = (strata[i] as f64 + rng.uniform()) / n as f64;
        }
    }
    out
}

/// The global stage: the sample and `start` (the scene's own values, when inside the box),
/// evaluated; sorted by χ², failed runs last. `None` when interrupted.
pub fn global(problem: &mut Problem<'_, '_>, start: Option<Vec<f64>>) -> Option<Vec<Eval>> {
    problem.stage = "global";
    let p = problem.params.len();
    let n = (GLOBAL_PER_PARAM * p).max(GLOBAL_MIN);
    let mut zs = latin_hypercube(n, p, SEED);
    zs.extend(start);
    let mut evals = problem.evaluate_all(&zs, false)?;
    evals.sort_by(|a, b| {
        (a.failed.is_some(), a.chi2)
            .partial_cmp(&(b.failed.is_some(), b.chi2))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    Some(evals)
}

/// The solver's noise as last measured, and the misfit where it was measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverNoise {
    /// ‖r(tolerance) − r(tolerance/10)‖, residual units.
    pub value: f64,
    /// χ² of the model it was measured at.
    pub at_chi2: f64,
}

/// The noise is measured again once χ² has fallen this many times below where it was
/// measured. It scales with the residuals (the solver's relative error times their size): a
/// value from far off the optimum makes the difference steps grow far beyond what the
/// optimum needs, and a Jacobian from steps of a twentieth of the box is a secant, not a
/// derivative.
pub const REMEASURE_FALL: f64 = 100.0;

impl SolverNoise {
    /// Whether a model of misfit `chi2` should have the noise measured again.
    #[must_use]
    pub fn stale(&self, chi2: f64) -> bool {
        chi2 * REMEASURE_FALL < self.at_chi2
    }
}

/// The solver's noise at `at` (see [`noise`]), as a [`SolverNoise`]. `None` when interrupted.
pub fn measure(problem: &mut Problem<'_, '_>, at: &Eval) -> Option<SolverNoise> {
    noise(problem, at).map(|value| SolverNoise {
        value,
        at_chi2: at.chi2,
    })
}

/// The solver's noise may be at most this many times the residuals' typical size,
/// max(1, √(χ²/m)), before the runs' tolerance is tightened tenfold: a deterministic error δr
/// of the residuals moves a parameter by at most ‖δr‖ of its standard error, and far from the
/// optimum the residuals — and with them the noise — are larger.
pub const NOISE_MAX: f64 = 0.3;
/// A tightening that does not cut the noise by this factor is the last (the noise is then
/// not the step sequence's).
pub const TIGHTENING_GAIN: f64 = 2.0;

/// Whether `noise` is too large for residuals of misfit `chi2` over `m` residuals.
#[must_use]
pub fn too_noisy(noise: f64, chi2: f64, m: usize) -> bool {
    noise > NOISE_MAX * (chi2 / m.max(1) as f64).sqrt().max(1.0)
}

/// Brings `at` and the `noise` up to date: `at` run again when it was run at an older level;
/// the noise measured again when it is stale; and while it is [`too_noisy`], the runs'
/// tolerance tightened tenfold (to `problem.max_level` at most), `at` run again
/// and the noise measured anew. The difference steps start again from [`FD_STEP_START`]
/// whenever the noise is measured. `None` when interrupted, else whether the level rose.
pub fn settle(
    problem: &mut Problem<'_, '_>,
    noise: &mut SolverNoise,
    at: &mut Eval,
    steps: &mut [f64],
) -> Option<bool> {
    let start = problem.level;
    if at.level != problem.level {
        *at = rerun(problem, at)?;
        *noise = measure(problem, at)?;
        steps.iter_mut().for_each(|h| *h = FD_STEP_START);
    } else if noise.stale(at.chi2) {
        *noise = measure(problem, at)?;
        steps.iter_mut().for_each(|h| *h = FD_STEP_START);
    }
    let m = problem.target.len();
    while problem.forward.tolerance.is_some()
        && problem.level < problem.max_level
        && too_noisy(noise.value, at.chi2, m)
    {
        problem.level += 1;
        *at = rerun(problem, at)?;
        // The best so far was run at the old tolerance: the point it came from, run again.
        problem.best = (at.failed.is_none()).then(|| at.clone());
        let before = noise.value;
        *noise = measure(problem, at)?;
        steps.iter_mut().for_each(|h| *h = FD_STEP_START);
        if noise.value * TIGHTENING_GAIN > before {
            break;
        }
    }
    Some(problem.level > start)
}

/// `at` run again at the present level.
fn rerun(problem: &mut Problem<'_, '_>, at: &Eval) -> Option<Eval> {
    let mut e = problem.evaluate_all(std::slice::from_ref(&at.z), false)?;
    e.pop()
}

/// The solver's noise at `z`: ‖r(tolerance) − r(tolerance/10)‖, in residual units (as
/// `verify` bounds a run's error by its distance to a refined run). `None` when interrupted.
pub fn noise(problem: &mut Problem<'_, '_>, at: &Eval) -> Option<f64> {
    problem.stage = "noise";
    let fine = problem.evaluate_all(std::slice::from_ref(&at.z), true)?;
    let d: f64 = fine[0]
        .residuals
        .iter()
        .zip(&at.residuals)
        .map(|(a, b)| (a - b).powi(2))
        .sum();
    Some(if fine[0].failed.is_some() {
        0.0
    } else {
        d.sqrt()
    })
}

/// The Jacobian at `at` in the columns `free` (box units): replayed where the fit asks for it
/// and it applies ([`super::replayed`]), else by central differences (one-sided
/// at a bound) with per-parameter `steps` grown until each column's difference exceeds
/// [`NOISE_RATIO`]·`noise`; with `linear` (the uncertainty's Jacobian) steered into
/// [`difference_band`] instead, shrinking a step whose difference leaves the linear range,
/// then grown until twice the step agrees ([`settle_scale`]).
/// The local stage's steps only grow: a secant over the misfit's small-scale roughness leads
/// the search better than its local slope. `None` when interrupted.
pub fn jacobian(
    problem: &mut Problem<'_, '_>,
    at: &Eval,
    free: &[usize],
    steps: &mut [f64],
    noise: f64,
    linear: bool,
) -> Option<Vec<Vec<f64>>> {
    let mut columns = match super::replayed::columns(problem, at, free)? {
        Some(columns) => {
            problem.jacobians_made.0 += 1;
            columns
        }
        None => {
            problem.jacobians_made.1 += 1;
            differences(problem, at, (free, steps), noise, linear)?
        }
    };
    hold_pinned_row(&mut columns, problem.pin.as_ref(), free);
    problem.last_jacobian = Some(super::problem::LastJacobian {
        z: at.z.clone(),
        free: free.to_vec(),
        columns: columns.clone(),
    });
    Some(columns)
}

/// Under a pin (the profile strategy's), the first onset's row of `columns` (over `free`) set
/// to zero: the pin holds that onset at the data's at every point run, so its derivative
/// along the free parameters is zero. What differences measure there is the pin's own
/// scatter within its tolerance (up to a tenth of the typical residual far from the
/// optimum): on the SFA contact's first slip that row reached 3·10⁶ per box, the leading
/// singular value, against 10⁵ for the intervals, and steered the steps. Without a pin, or
/// with the pinned parameter among the columns, nothing changes.
pub fn hold_pinned_row(columns: &mut [Vec<f64>], pin: Option<&super::pin::Pin>, free: &[usize]) {
    if pin.is_some_and(|pin| !free.contains(&pin.k)) {
        for c in columns {
            if let Some(r0) = c.first_mut() {
                *r0 = 0.0;
            }
        }
    }
}

/// [`jacobian`] by central differences (see there); `None` when interrupted.
fn differences(
    problem: &mut Problem<'_, '_>,
    at: &Eval,
    (free, steps): (&[usize], &mut [f64]),
    noise: f64,
    linear: bool,
) -> Option<Vec<Vec<f64>>> {
    let m = at.residuals.len();
    let (lower, upper) = if linear {
        difference_band(noise, at.chi2, m)
    } else {
        (NOISE_RATIO * noise, f64::INFINITY)
    };
    if linear {
        predict_steps(problem.last_jacobian.as_ref(), free, (lower, upper), steps);
    }
    let mut columns = vec![vec![0.0; m]; free.len()];
    let mut todo: Vec<usize> = (0..free.len()).collect();
    // Per column: +1 once its step grew, −1 once it shrank (it never turns back).
    let mut moved = vec![0i8; free.len()];
    while !todo.is_empty() {
        // Per column: its two points (a, b), each the point at `at` itself when at a bound.
        let ends: Vec<(f64, f64)> = todo
            .iter()
            .map(|&c| {
                let (z, h) = (at.z[free[c]], steps[free[c]]);
                ((z - h).max(0.0), (z + h).min(1.0))
            })
            .collect();
        let mut zs = Vec::new();
        for (&c, &(a, b)) in todo.iter().zip(&ends) {
            for v in [a, b] {
                if v != at.z[free[c]] {
                    let mut z = at.z.clone();
                    z[free[c]] = v;
                    zs.push(z);
                }
            }
        }
        let evals = problem.evaluate_all(&zs, false)?;
        let mut next = 0;
        let mut again = Vec::new();
        for (&c, &(a, b)) in todo.iter().zip(&ends) {
            let j = free[c];
            let mut take = |v: f64| -> Option<&Eval> {
                if v == at.z[j] {
                    Some(at)
                } else {
                    next += 1;
                    let e = &evals[next - 1];
                    e.failed.is_none().then_some(e)
                }
            };
            let (ra, rb) = (take(a), take(b));
            let (ra, rb, width) = match (ra, rb) {
                (Some(x), Some(y)) => (x, y, b - a),
                // A failed side: the other one against the point itself.
                (Some(x), None) => (x, at, at.z[j] - a),
                (None, Some(y)) => (at, y, b - at.z[j]),
                (None, None) => (at, at, 1.0),
            };
            let diff: Vec<f64> = rb
                .residuals
                .iter()
                .zip(&ra.residuals)
                .map(|(y, x)| y - x)
                .collect();
            let size = dot(&diff, &diff).sqrt();
            if size < lower && steps[j] < FD_STEP_MAX && moved[c] >= 0 {
                steps[j] = (steps[j] * 4.0).min(FD_STEP_MAX);
                moved[c] = 1;
                again.push(c);
            } else if size > upper && steps[j] > FD_STEP_MIN && moved[c] <= 0 {
                steps[j] = (steps[j] / 4.0).max(FD_STEP_MIN);
                moved[c] = -1;
                again.push(c);
            }
            columns[c] = if width > 0.0 {
                diff.iter().map(|d| d / width).collect()
            } else {
                vec![0.0; m]
            };
        }
        todo = again;
    }
    if linear {
        settle_scale(problem, at, free, steps, &mut columns)?;
    }
    Some(columns)
}

/// The steps of a Jacobian steered into the band (`lower`, `upper`) (the uncertainty's),
/// predicted from the `last` Jacobian's columns: each parameter's step set so that its central
/// difference, 2·h·‖column‖, lands at half the band's top, max(`upper`/2, `lower`) (within
/// [`FD_STEP_MIN`], [`FD_STEP_MAX`]), the middle of where shrinking by 4 from above lands. A
/// parameter without a column there keeps its step. Why: the steps start again from
/// [`FD_STEP_START`] whenever the noise is measured, and a parameter the data fix to a
/// millionth then shrinks by 4 a round, two runs each, into the band, at the runs' tightest
/// tolerances (on the SFA contact's first slip 2–5 s a run).
pub fn predict_steps(
    last: Option<&super::problem::LastJacobian>,
    free: &[usize],
    (lower, upper): (f64, f64),
    steps: &mut [f64],
) {
    let Some(last) = last else { return };
    let aim = (0.5 * upper).max(lower);
    if !(aim.is_finite() && aim > 0.0 && lower > 0.0) {
        return;
    }
    for &j in free {
        let Some(c) = last.free.iter().position(|&k| k == j) else {
            continue;
        };
        let norm = dot(&last.columns[c], &last.columns[c]).sqrt();
        if norm > 0.0 && norm.is_finite() {
            steps[j] = (aim / (2.0 * norm)).clamp(FD_STEP_MIN, FD_STEP_MAX);
        }
    }
}

/// Two columns agree when they differ by at most this fraction of the first's norm.
pub const SCALE_AGREEMENT: f64 = 0.1;

/// Grows each column's step (doubling, to [`FD_STEP_MAX`]) until its central difference at
/// twice the step agrees with it ([`SCALE_AGREEMENT`]). The events misfit is rough on a small
/// scale — an onset or a window placed between samples moves in jumps of a fraction of a σ
/// — and a derivative over that scale is the roughness's, not the misfit's: the SFA contact's
/// γ, whose χ² is flat within 1 over ±5 %, had 95 % intervals of ±1.6 % from it. `None` when
/// interrupted.
fn settle_scale(
    problem: &mut Problem<'_, '_>,
    at: &Eval,
    free: &[usize],
    steps: &mut [f64],
    columns: &mut [Vec<f64>],
) -> Option<()> {
    for (c, &j) in free.iter().enumerate() {
        while steps[j] < FD_STEP_MAX {
            let h = (2.0 * steps[j]).min(FD_STEP_MAX);
            let (a, b) = ((at.z[j] - h).max(0.0), (at.z[j] + h).min(1.0));
            let points: Vec<Vec<f64>> = [a, b]
                .iter()
                .map(|&v| {
                    let mut z = at.z.clone();
                    z[j] = v;
                    z
                })
                .collect();
            let e = problem.evaluate_all(&points, false)?;
            if e.iter().any(|e| e.failed.is_some()) || b <= a {
                break;
            }
            let wider: Vec<f64> = e[1]
                .residuals
                .iter()
                .zip(&e[0].residuals)
                .map(|(y, x)| (y - x) / (b - a))
                .collect();
            let diff: Vec<f64> = wider.iter().zip(&columns[c]).map(|(w, x)| w - x).collect();
            let agree =
                dot(&diff, &diff).sqrt() <= SCALE_AGREEMENT * dot(&columns[c], &columns[c]).sqrt();
            steps[j] = h;
            columns[c] = wider;
            if agree {
                break;
            }
        }
    }
    Some(())
}

/// The local stage's answer.
#[derive(Debug, Clone)]
pub struct Local {
    /// The best model.
    pub best: Eval,
    /// Iterations taken.
    pub iterations: usize,
    /// Whether it stopped because χ² no longer fell (not because of the iteration limit or an
    /// interrupt).
    pub converged: bool,
}

/// What the local stage does after an accepted step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AfterStep {
    /// Go on as usual (λ eased by 8).
    Go,
    /// One more iteration from λ = σ²min: the small gain came from a step the damping held
    /// back.
    Undamped,
    /// Converged: χ² no longer falls.
    Converged,
}

/// The local stage's decision after a step accepted with damping `lambda`, its gain `small`
/// (below [`RTOL_CHI2`] of χ²) or not, `weakest` the least σ² of the Jacobian, and `retried`
/// whether this step was already the one more try after a stall.
///
/// A small gain from a step the damping held back (λ above σ²min, so the weakest direction
/// barely moved) is no sign of convergence: in a long, narrow valley — one parameter fixed a
/// thousand times more sharply than another — the damping the steep direction needs stops
/// the step along the valley, and each step gains little. Once per stall the next iteration
/// therefore starts at λ = σ²min, where the weakest direction takes about half its
/// Gauss–Newton step; a small gain then, or from an undamped step, is convergence.
#[must_use]
pub fn after_step(small: bool, lambda: f64, weakest: f64, retried: bool) -> AfterStep {
    match (small, lambda > weakest && !retried) {
        (false, _) => AfterStep::Go,
        (true, true) => AfterStep::Undamped,
        (true, false) => AfterStep::Converged,
    }
}

/// Levenberg–Marquardt from `start` over the parameters `free` (the others held), bounded to
/// the unit box, for at most `max_iterations`; stops early (unconverged) when interrupted.
/// The solver's `noise` is measured again as χ² falls, and the runs' tolerance tightened
/// while it is too large ([`settle`]).
pub fn levenberg_marquardt(
    problem: &mut Problem<'_, '_>,
    start: Eval,
    free: &[usize],
    steps: &mut [f64],
    noise: &mut SolverNoise,
    max_iterations: usize,
) -> Local {
    levenberg_marquardt_damped(
        problem,
        start,
        free,
        (steps, noise),
        max_iterations,
        Damping::Steep,
    )
}

/// The first iteration's damping of [`levenberg_marquardt_damped`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Damping {
    /// λ = 1e-2·σ²max: the step follows the sharpest directions first (the direct search's).
    Steep,
    /// λ = σ²min: about half the Gauss–Newton step in the weakest direction too (the profile
    /// strategy's, whose misfit, the needle solved out, is nearly linear over a large part
    /// of the box; with λ from σ²max the weakest direction moved 10⁻⁴ of its Gauss–Newton
    /// step per iteration there).
    Weak,
}

/// [`levenberg_marquardt`] with the first iteration's damping `damping`.
pub fn levenberg_marquardt_damped(
    problem: &mut Problem<'_, '_>,
    start: Eval,
    free: &[usize],
    (steps, noise): (&mut [f64], &mut SolverNoise),
    max_iterations: usize,
    damping: Damping,
) -> Local {
    let mut cur = start;
    let mut lambda: Option<f64> = None;
    // Whether the last iteration was the one more, undamped, try after a stall (below).
    let mut retried = false;
    let tries = problem.jobs.clamp(2, 4);
    for iteration in 0..max_iterations {
        if settle(problem, noise, &mut cur, steps).is_none() {
            return Local {
                best: cur,
                iterations: iteration,
                converged: false,
            };
        }
        let Some(j) = jacobian(problem, &cur, free, steps, noise.value, false) else {
            return Local {
                best: cur,
                iterations: iteration,
                converged: false,
            };
        };
        let Some(d) = svd(&j) else {
            return Local {
                best: cur,
                iterations: iteration,
                converged: true,
            };
        };
        let g: Vec<f64> = d.u.iter().map(|u| dot(u, &cur.residuals)).collect();
        let first = match damping {
            Damping::Steep => 1e-2 * d.s[0] * d.s[0],
            Damping::Weak => d.s.last().map_or(0.0, |s| s * s),
        };
        let mut lam = lambda.unwrap_or(first).max(1e-12 * d.s[0] * d.s[0]);
        let mut accepted = None;
        for _ in 0..6 {
            let lambdas: Vec<f64> = (0..tries).map(|k| lam * 16f64.powi(k as i32)).collect();
            let zs: Vec<Vec<f64>> = lambdas
                .iter()
                .map(|&l| {
                    let mut z = cur.z.clone();
                    for (i, s) in d.s.iter().enumerate() {
                        let c = -s / (s * s + l) * g[i];
                        for (k, &j) in free.iter().enumerate() {
                            z[j] += c * d.v[i][k];
                        }
                    }
                    z.iter_mut().for_each(|x| *x = x.clamp(0.0, 1.0));
                    z
                })
                .collect();
            let Some(evals) = problem.evaluate_all(&zs, false) else {
                return Local {
                    best: cur,
                    iterations: iteration,
                    converged: false,
                };
            };
            let best = evals
                .into_iter()
                .zip(&lambdas)
                .filter(|(e, _)| e.failed.is_none() && e.chi2 < cur.chi2)
                .min_by(|a, b| a.0.chi2.total_cmp(&b.0.chi2));
            if let Some((e, &l)) = best {
                accepted = Some((e, l));
                lam = l / 8.0;
                break;
            }
            lam *= 16f64.powi(tries as i32);
        }
        lambda = Some(lam);
        let Some((next, used)) = accepted else {
            return Local {
                best: cur,
                iterations: iteration + 1,
                converged: true,
            };
        };
        let gain = cur.chi2 - next.chi2;
        let moved = next
            .z
            .iter()
            .zip(&cur.z)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let small = gain <= (RTOL_CHI2 * cur.chi2).max(CHI2_GAIN_MIN) || moved < 1e-7;
        cur = next;
        let weakest = d.s.last().map_or(0.0, |s| s * s);
        match after_step(small, used, weakest, retried) {
            AfterStep::Go => retried = false,
            AfterStep::Undamped => {
                retried = true;
                lambda = Some(weakest.min(lam));
            }
            AfterStep::Converged => {
                return Local {
                    best: cur,
                    iterations: iteration + 1,
                    converged: true,
                };
            }
        }
    }
    Local {
        best: cur,
        iterations: max_iterations,
        converged: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uncertainty_steps_are_predicted_from_the_last_jacobian() {
        let last = super::super::problem::LastJacobian {
            z: vec![0.5; 3],
            free: vec![0, 2],
            // Norms 1e4 (a sharp parameter) and 1e-3 (a flat one).
            columns: vec![vec![6e3, 8e3], vec![0.0, 1e-3]],
        };
        let mut steps = vec![FD_STEP_START; 3];
        predict_steps(Some(&last), &[0, 1, 2], (10.0, 1000.0), &mut steps);
        // Half the band's top, 500, over twice the norm; the flat one at the largest step;
        // the parameter without a column keeps its own.
        assert!((steps[0] - 2.5e-2).abs() < 1e-15, "{steps:?}");
        assert_eq!(steps[1], FD_STEP_START);
        assert_eq!(steps[2], FD_STEP_MAX);
        // No Jacobian yet, or an empty band: nothing changes.
        let mut fresh = vec![FD_STEP_START; 3];
        predict_steps(None, &[0, 1, 2], (10.0, 1000.0), &mut fresh);
        predict_steps(Some(&last), &[0, 1, 2], (0.0, 1000.0), &mut fresh);
        assert_eq!(fresh, vec![FD_STEP_START; 3]);
    }

    #[test]
    fn a_pinned_onsets_row_is_held_at_zero_only_under_the_pin() {
        let pin = super::super::pin::Pin {
            k: 2,
            slope: 1e6,
            gradient: vec![1.0, 2.0, 1e6],
            anchor: vec![0.5; 3],
            anchor_residual: 0.0,
            tolerance: 5.0,
        };
        let columns = vec![vec![3e6, 1.0, 2.0], vec![-2e6, 3.0, 4.0]];
        let mut held = columns.clone();
        hold_pinned_row(&mut held, Some(&pin), &[0, 1]);
        assert_eq!(held, vec![vec![0.0, 1.0, 2.0], vec![0.0, 3.0, 4.0]]);
        // No pin, or the pinned parameter among the columns: the row is measured.
        for (p, free) in [(None, [0, 1]), (Some(&pin), [0, 2])] {
            let mut kept = columns.clone();
            hold_pinned_row(&mut kept, p, &free);
            assert_eq!(kept, columns);
        }
    }

    #[test]
    fn the_noise_is_too_large_against_the_residuals_typical_size() {
        // Near the optimum (χ²/m ≤ 1) against 1 σ; far off against √(χ²/m).
        assert!(!too_noisy(0.29, 10.0, 13));
        assert!(too_noisy(0.31, 10.0, 13));
        assert!(!too_noisy(2.9, 1300.0, 13));
        assert!(too_noisy(3.1, 1300.0, 13));
    }

    #[test]
    fn the_difference_band_keeps_above_the_noise_and_within_the_linear_range() {
        // A quiet solver: a hundred times the noise, below the linear range's end.
        let (lo, hi) = difference_band(0.01, 13.0, 13);
        assert!((lo - 1.0).abs() < 1e-12 && (hi - LINEAR_MAX).abs() < 1e-12);
        // A noisier one: the lower end held to a quarter of the linear range, but never
        // under ten times the noise.
        let (lo, hi) = difference_band(0.2, 13.0, 13);
        assert!((lo - LINEAR_MAX / 4.0).abs() < 1e-12 && (hi - LINEAR_MAX).abs() < 1e-12);
        let (lo, hi) = difference_band(2.0, 13.0, 13);
        assert!((lo - 20.0).abs() < 1e-12 && (hi - 80.0).abs() < 1e-12);
        // Far from the optimum the range scales with the residuals.
        let (_, hi) = difference_band(0.0, 1300.0, 13);
        assert!((hi - 10.0 * LINEAR_MAX).abs() < 1e-9);
    }

    #[test]
    fn the_noise_is_stale_once_the_misfit_has_fallen_a_hundredfold() {
        let n = SolverNoise {
            value: 50.0,
            at_chi2: 1e10,
        };
        assert!(!n.stale(1e10) && !n.stale(2e8) && !n.stale(1e8));
        assert!(n.stale(0.99e8) && n.stale(30.0));
    }

    #[test]
    fn a_small_gain_of_a_damped_step_is_tried_once_more_undamped() {
        // A large gain goes on, whatever the damping.
        assert_eq!(after_step(false, 1e6, 1.0, false), AfterStep::Go);
        assert_eq!(after_step(false, 1e-6, 1.0, true), AfterStep::Go);
        // A small gain with λ far above σ²min: the valley's direction was held back.
        assert_eq!(after_step(true, 1e6, 1.0, false), AfterStep::Undamped);
        // …but only once in a row, and not when the step was already undamped.
        assert_eq!(after_step(true, 1e6, 1.0, true), AfterStep::Converged);
        assert_eq!(after_step(true, 0.5, 1.0, false), AfterStep::Converged);
    }

    #[test]
    fn the_sample_has_one_point_in_each_stratum_of_each_parameter() {
        let s = latin_hypercube(10, 3, SEED);
        for j in 0..3 {
            let mut strata: Vec<usize> = s.iter().map(|p| (p[j] * 10.0).floor() as usize).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..10).collect::<Vec<_>>());
        }
        assert_eq!(s, latin_hypercube(10, 3, SEED));
    }
}
