//! A parameter pinned by the first onset (the profile strategy's first step,
//! docs/fit.md#the-profile-strategy): at every point the optimiser asks for, that parameter
//! is solved first so that the model's first onset falls on the data's, by a safeguarded
//! secant on runs stopped after their first melting ([`Forward::onset_run`]), and the point
//! is then run whole there.
//!
//! Why: the first onset of a long stick fixes one combination of the parameters (the SFA
//! contact's τmax, h0 and G*: the stress at the contact's edge reaching the film's peak) to a
//! few parts in 10⁷, while everything after it varies on the scale of percent. The misfit is
//! then a narrow, curved needle along which no finite-difference step is both above the
//! solver's noise and inside the linear range. Solved out, the first onset's residual is
//! held near zero and the misfit of the others is smooth: the needle is gone.

use super::forward::{Forward, Run, RunFailure};
use super::misfit::{Compared, Target};
use super::params::Param;
use std::sync::atomic::AtomicBool;

/// The first onset's residual (σ units) within which the pinned parameter counts as solved.
/// Not smaller: the solver's own error in the first onset is of this order at the fit's
/// tolerance (the SFA contact's first onset after a 0.13 s stick is timed by the data to
/// about 4 ns, and a run at tolerance 1e-6 places it within about 10 ns; the residual then
/// jumps by a few σ between points 1e-8 of the box apart), and a secant below that noise
/// only spends runs.
pub const ONSET_TOLERANCE: f64 = 5.0;
/// Onset runs at most per solve; the best of them is taken when the secant has not
/// converged by then.
pub const MAX_ONSET_RUNS: usize = 10;
/// Two residuals within this fraction of each other are one plateau ([`next_trial`]).
pub const PLATEAU: f64 = 1e-6;
/// Bracketed trials after which a solve whose best residual has not halved stops
/// ([`stalled`]).
pub const STALL_TRIALS: usize = 3;

/// The pinned parameter and what the secant starts from.
#[derive(Debug, Clone, PartialEq)]
pub struct Pin {
    /// Its index among the fit's parameters.
    pub k: usize,
    /// The first onset's residual per unit of its box coordinate, σ per box (measured where
    /// the pin was chosen, then near the solutions found; the secant's first step).
    pub slope: f64,
    /// The first onset's residual per unit of each box coordinate where the pin was chosen
    /// (σ per box): the needle's direction, along which the first trial moves.
    pub gradient: Vec<f64>,
    /// A point run (the best of the last batch): the first trial at another point moves
    /// from it along the needle.
    pub anchor: Vec<f64>,
    /// The first onset's residual there (σ).
    pub anchor_residual: f64,
    /// The first onset's residual within which the pin counts as solved (σ): at least
    /// [`ONSET_TOLERANCE`], and far from the optimum a tenth of the residuals' typical size
    /// (the search does not need the first onset closer than the misfit it is reducing).
    pub tolerance: f64,
}

impl Pin {
    /// The first trial of the pinned coordinate at `z`: the anchor's, moved along the needle
    /// (the first onset brought to the data's to first order) by `z`'s distance from the
    /// anchor; inside the box.
    #[must_use]
    pub fn predict(&self, z: &[f64]) -> f64 {
        let gk = self.gradient[self.k];
        let moved: f64 = (0..z.len())
            .filter(|&j| j != self.k)
            .map(|j| self.gradient[j] * (z[j] - self.anchor[j]))
            .sum();
        let t = self.anchor[self.k] - (self.anchor_residual + moved) / gk;
        if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            z[self.k]
        }
    }
}

/// One point solved: the box coordinates with the pinned one solved, the whole run's
/// comparison there, and the onset runs spent.
pub struct Solved {
    /// The point, the pinned coordinate solved.
    pub z: Vec<f64>,
    /// The whole run at `z`; `None` when interrupted.
    pub compared: Option<Result<Compared, RunFailure>>,
    /// Onset runs made.
    pub onset_runs: usize,
    /// The first onset's slope along the pinned coordinate near the solution (the secant
    /// of the last two trials, when of the expected sign), σ per box.
    pub slope: Option<f64>,
}

/// The first onset's residual of the model at `z` from a run stopped after its first
/// melting; `Err` for a failed run, `None` when interrupted.
fn onset_residual(
    (forward, params, target): (&Forward, &[Param], &Target),
    (interrupt, level): (Option<&AtomicBool>, u32),
    z: &[f64],
) -> Option<Result<f64, RunFailure>> {
    match forward.onset_run(params, z, level, interrupt) {
        Run::Done(curve) => Some(Ok(target.compare(&curve, 0.0).residuals[0])),
        Run::Failed(why) => Some(Err(why)),
        Run::Interrupted => None,
    }
}

/// The next trial of the pinned coordinate from the points tried so far, `(z, g)` with `g`
/// the first onset's residual: Newton with `slope` from the first point, a secant from the
/// last two, and once the residual has changed sign, inverse quadratic interpolation or
/// regula falsi (Illinois) inside the bracket; always inside the box [0, 1]. A step that leaves the box stops at its face.
#[must_use]
pub fn next_trial(tried: &[(f64, f64)], slope: f64) -> f64 {
    let &(z1, g1) = tried.last().unwrap_or(&(0.5, 0.0));
    // The tightest bracket: the last point and the latest point of the other sign.
    if let Some(&(z0, g0)) = tried.iter().rev().find(|(_, g)| g.signum() != g1.signum()) {
        let (lo, hi) = (z0.min(z1), z0.max(z1));
        // Inverse quadratic interpolation through the last three trials, where it falls
        // inside the bracket: the first onset is curved over the bracket's first widths, where
        // regula falsi creeps from one side.
        if let [.., (a, fa), (b, fb), (c, fc)] = *tried
            && fa != fb
            && fb != fc
            && fa != fc
        {
            let z = a * fb * fc / ((fa - fb) * (fa - fc))
                + b * fa * fc / ((fb - fa) * (fb - fc))
                + c * fa * fb / ((fc - fa) * (fc - fb));
            if z > lo && z < hi {
                return z;
            }
        }
        // Illinois: a side kept twice in a row has its residual halved.
        let kept_twice = tried.len() >= 3 && {
            let n = tried.len();
            tried[n - 2].1.signum() == g1.signum() && tried[n - 3].1.signum() == g1.signum()
        };
        let g0 = if kept_twice { g0 / 2.0 } else { g0 };
        let z = z1 - g1 * (z1 - z0) / (g1 - g0);
        return if z > lo && z < hi { z } else { 0.5 * (z0 + z1) };
    }
    // On a plateau (the model's first onset beyond the trace's end, or before its start: the
    // residual saturated, the same at the last two trials) the slope says nothing of the way
    // out: the last move is doubled, so a plateau of any width is crossed in a few runs
    // instead of at the slope's pace (measured on the SFA contact's first slip: up to ten
    // runs at 0.015 of the box each, the solve then given up on the plateau).
    if let [.., (za, ga), (zb, gb)] = *tried
        && zb != za
        && (gb - ga).abs() <= PLATEAU * gb.abs()
    {
        return (zb + 2.0 * (zb - za)).clamp(0.0, 1.0);
    }
    let s = match tried {
        [.., (za, ga), (zb, gb)] if zb != za && gb != ga => (gb - ga) / (zb - za),
        _ => slope,
    };
    // A secant of the wrong sign (the residual saturated, or noise): the measured slope.
    let s = if s.signum() == slope.signum() && s.is_finite() && s != 0.0 {
        s
    } else {
        slope
    };
    (z1 - g1 / s).clamp(0.0, 1.0)
}

/// Solves the pinned coordinate of `z` (the other coordinates held), then runs the point
/// whole with `whole` (the fit's own run and comparison). A failed onset run is the point's
/// failure; the best trial is taken when the secant has not reached the pin's tolerance
/// within [`MAX_ONSET_RUNS`] runs, or stalls at a face of the box.
pub fn solve(
    model: (&Forward, &[Param], &Target),
    (interrupt, level): (Option<&AtomicBool>, u32),
    z: &[f64],
    pin: &Pin,
    whole: impl Fn(&[f64]) -> Option<Result<Compared, RunFailure>>,
) -> Solved {
    let mut z = z.to_vec();
    z[pin.k] = pin.predict(&z);
    let mut tried: Vec<(f64, f64)> = Vec::new();
    while tried.len() < MAX_ONSET_RUNS {
        let ended = |compared| Solved {
            z: z.clone(),
            compared,
            onset_runs: tried.len() + 1,
            slope: None,
        };
        let g = match onset_residual(model, (interrupt, level), &z) {
            Some(Ok(g)) => g,
            // A failed onset run is the point's failure.
            Some(Err(why)) => return ended(Some(Err(why))),
            None => return ended(None),
        };
        tried.push((z[pin.k], g));
        if g.abs() <= pin.tolerance.max(ONSET_TOLERANCE) {
            break;
        }
        let next = next_trial(&tried, pin.slope);
        // Stalled at a face of the box, or no longer moving, or inside a bracket that no
        // longer closes on a root: stop there.
        if tried.iter().any(|&(t, _)| t == next) || stalled(&tried) {
            break;
        }
        z[pin.k] = next;
    }
    if let Some(&(best, _)) = tried.iter().min_by(|a, b| a.1.abs().total_cmp(&b.1.abs())) {
        z[pin.k] = best;
    }
    Solved {
        compared: whole(&z),
        z,
        onset_runs: tried.len(),
        slope: slope_near(&tried, pin.slope),
    }
}

/// Whether a bracketed solve has stopped closing on a root: over its last
/// [`STALL_TRIALS`] trials, all inside a bracket (the residual changed sign before them),
/// the least residual has not halved. Where the first onset jumps (the model's first event
/// changes, a melting that appears or goes with the parameter) there is no root to close
/// on, and a secant inside the bracket creeps towards the jump a few per cent a run
/// (measured: ±1e5 σ on both sides of a jump 0.005 of the box wide, still ±4e4 after ten
/// runs); the best trial is as good then as it will get.
#[must_use]
pub fn stalled(tried: &[(f64, f64)]) -> bool {
    let Some(first_bracketed) = tried
        .windows(2)
        .position(|w| w[0].1.signum() != w[1].1.signum())
        .map(|i| i + 1)
    else {
        return false;
    };
    let n = tried.len();
    if n < first_bracketed + 1 + STALL_TRIALS {
        return false;
    }
    let least = |t: &[(f64, f64)]| t.iter().map(|x| x.1.abs()).fold(f64::INFINITY, f64::min);
    let before = least(&tried[..n - STALL_TRIALS]);
    let after = least(&tried[n - STALL_TRIALS..]);
    after > 0.5 * before
}

/// Trials this far off (σ) or farther measure the slope above the solver's noise.
pub const SLOPE_SPAN: f64 = 20.0 * ONSET_TOLERANCE;

/// The pin's tolerance for a best misfit `chi2` over `m` residuals: a tenth of the
/// residuals' typical size, at least [`ONSET_TOLERANCE`].
#[must_use]
pub fn tolerance_for(chi2: f64, m: usize) -> f64 {
    let typical = (chi2 / m.max(1) as f64).sqrt();
    if typical.is_finite() {
        (0.1 * typical).max(ONSET_TOLERANCE)
    } else {
        ONSET_TOLERANCE
    }
}

/// The first onset's slope near the solution from `tried`: the secant from the nearest
/// trial at least [`SLOPE_SPAN`] off to the best one (a secant between two trials within
/// the noise is the noise's); none when there is no such trial or its sign is not
/// `expected`'s.
#[must_use]
pub fn slope_near(tried: &[(f64, f64)], expected: f64) -> Option<f64> {
    let &(zb, gb) = tried
        .iter()
        .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    let &(za, ga) = tried
        .iter()
        .filter(|t| t.1.abs() >= SLOPE_SPAN)
        .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    let s = (gb - ga) / (zb - za);
    (s.is_finite() && s.signum() == expected.signum()).then_some(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Solves g(z) = 0 with [`next_trial`] alone; the trials made.
    fn trials(g: impl Fn(f64) -> f64, z0: f64, slope: f64) -> Vec<(f64, f64)> {
        let mut tried = vec![(z0, g(z0))];
        while tried.len() < 30 && tried.last().is_some_and(|t| t.1.abs() > 1e-9) {
            let z = next_trial(&tried, slope);
            tried.push((z, g(z)));
        }
        tried
    }

    #[test]
    fn the_slope_near_the_solution_comes_from_a_trial_above_the_noise() {
        // The last two trials sit within the noise (their secant 1e9); the slope comes from
        // the nearest trial 100 σ or more off.
        let tried = [
            (0.5, -1.5e6),
            (0.84, -3e3),
            (0.8491, -3.0),
            (0.84910001, 7.0),
        ];
        // From (0.84, −3000) to the best trial (0.8491, −3).
        let s = slope_near(&tried, 4e6).unwrap();
        let expected = (-3.0 + 3e3) / (0.8491 - 0.84);
        assert!((s / expected - 1.0).abs() < 1e-9, "{s}");
        assert!(slope_near(&tried[2..], 4e6).is_none());
        assert!(slope_near(&tried, -4e6).is_none());
    }

    #[test]
    fn a_linear_onset_is_solved_in_one_step_from_its_slope() {
        let t = trials(|z| 4e4 * (z - 0.37), 0.5, 4e4);
        assert_eq!(t.len(), 2, "{t:?}");
        assert!((t[1].0 - 0.37).abs() < 1e-12);
    }

    #[test]
    fn a_curved_onset_with_a_poor_slope_converges_inside_its_bracket() {
        // A wrong first slope (ten times too steep) and curvature: the secant, then the
        // bracket, converge within a few trials and never leave the box.
        let g = |z: f64| 3e3 * ((z - 0.2) + 2.0 * (z - 0.2).powi(2));
        let t = trials(g, 0.9, 3e4);
        assert!(t.len() <= 12, "{} trials: {t:?}", t.len());
        assert!(t.iter().all(|(z, _)| (0.0..=1.0).contains(z)));
        assert!((t.last().unwrap().0 - 0.2).abs() < 1e-8);
    }

    #[test]
    fn a_wide_plateau_is_crossed_by_doubling_moves() {
        // The residual saturated over most of the box, and a slope twenty times too steep
        // for a way out: the moves double, so the root is found within the runs allowed.
        let g = |z: f64| if z > 0.2 { 2.4e5 } else { 1.2e6 * (z - 0.1) };
        let t = trials(g, 0.72, 1.5e7);
        assert!(t.len() <= MAX_ONSET_RUNS, "{} trials: {t:?}", t.len());
        assert!((t.last().unwrap().0 - 0.1).abs() < 1e-8, "{t:?}");
    }

    #[test]
    fn a_solve_stops_at_a_jump_once_the_bracket_stops_closing() {
        // A jump of the residual from −7e4 to +4e4 at 0.92 and no root: the solve stops
        // within a few bracketed trials instead of spending all its runs.
        let g = |z: f64| {
            if z < 0.92 {
                -7e4 + 5e6 * (z - 0.92)
            } else {
                4e4 + 5e6 * (z - 0.92)
            }
        };
        let mut tried = vec![(0.90, g(0.90))];
        while !stalled(&tried) && tried.len() < 30 {
            let z = next_trial(&tried, 5e6);
            tried.push((z, g(z)));
        }
        assert!(stalled(&tried), "{tried:?}");
        assert!(tried.len() <= 8, "{} trials: {tried:?}", tried.len());
        // Converging solves never count as stalled.
        let t = trials(|z| 3e3 * ((z - 0.2) + 2.0 * (z - 0.2).powi(2)), 0.9, 3e4);
        assert!((1..=t.len()).all(|n| !stalled(&t[..n])), "{t:?}");
    }

    #[test]
    fn a_saturated_residual_steps_with_the_measured_slope_and_stops_at_the_face() {
        // No onset in the trace (the residual stuck at the trace's end) until z < 0.3; the
        // root at 0.1. A flat secant does not stall the search.
        let g = |z: f64| if z > 0.3 { 500.0 } else { 1e3 * (z - 0.1) };
        let t = trials(g, 0.8, 1e3);
        assert!((t.last().unwrap().0 - 0.1).abs() < 1e-8, "{t:?}");
        // A root beyond the box: the trial stops at its face.
        let t = trials(|z| 1e3 * (z + 0.5), 0.5, 1e3);
        assert_eq!(t[1].0, 0.0);
    }
}
