//! Noisy fixed-step runs: the weak error of fig2's first onset with gaussian noise.
//!
//! With `lubricant.noise.kind = "gaussian"` the accurate scheme takes fixed steps (adaptive
//! steps are refused: a retried step would redraw the noise); each step adds ξ ~ N(0, σ²Δt) per
//! node after the exact Landau step. Every seed is a different path, so the study measures
//! statistics over seeds: the mean first onset and its spread (standard deviation) at each Δt,
//! against the same statistics at a fine Δt. Their differences are the weak errors, with
//! standard errors from the seeds (the levels' paths are independent: a seed's draws mean
//! different increments at different Δt).
//!
//! The observed weak order is read two ways: the log–log slope of |error| against Δt over the
//! levels whose error exceeds twice its standard error, and a weighted fit of
//! m(Δt) = m0 + C·Δt^p over all levels including the finest (which does not assume the
//! finest level is exact).

use crate::fig2::{RunRecord, RunSpec, run};
use serde::{Deserialize, Serialize};
use stickslip_core::config::Scheme;
use stickslip_report::stats::{log_log_slope, mean};

/// Levels of the noise study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoiseSettings {
    /// Nodes N.
    pub nodes: usize,
    /// Fixed steps, coarse to fine, s.
    pub dts_s: Vec<f64>,
    /// The fine step of the reference statistics, s.
    pub reference_dt_s: f64,
    /// Seeds 1 … `seeds` at every level.
    pub seeds: u64,
    /// Noise amplitude σ (`lubricant.noise.sigma`).
    pub sigma: f64,
    /// End of each run (just past the first onset), s.
    pub end_s: f64,
}

impl NoiseSettings {
    /// The full study: N = 50, 64 seeds, Δt = 6.4e-7 … 2e-8 s, reference 5e-9 s (the
    /// coarse levels are where a bias outgrows the seeds' standard error of about 3 ns).
    #[must_use]
    pub fn full() -> Self {
        Self {
            nodes: 50,
            dts_s: vec![6.4e-7, 3.2e-7, 1.6e-7, 8e-8, 4e-8, 2e-8],
            reference_dt_s: 5e-9,
            seeds: 64,
            sigma: 1.0,
            end_s: 6.0e-4,
        }
    }

    /// The smoke study: N = 25, 4 seeds, Δt = 6.4e-7 … 1.6e-7 s, reference 4e-8 s.
    #[must_use]
    pub fn quick() -> Self {
        Self {
            nodes: 25,
            dts_s: vec![6.4e-7, 3.2e-7, 1.6e-7],
            reference_dt_s: 4e-8,
            seeds: 4,
            sigma: 1.0,
            end_s: 6.0e-4,
        }
    }
}

/// The first onsets of all seeds at one Δt and their statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoiseLevel {
    /// Step, s.
    pub dt_s: f64,
    /// First onset per seed (None: no event before the end, or a failed run), s.
    pub first_onsets_s: Vec<Option<f64>>,
    /// Mean over the seeds with an onset, s.
    pub mean_s: f64,
    /// Standard deviation over them (n − 1), s.
    pub std_s: f64,
    /// Standard error of the mean, s.
    pub se_mean_s: f64,
    /// Standard error of the standard deviation, std/√(2(n − 1)), s.
    pub se_std_s: f64,
    /// Share of first onsets that fall on a step end (to 1e-6 of the step).
    pub at_step_end: f64,
    /// Wall seconds of all its runs.
    pub wall_s: f64,
    /// The first onset of the same run without gaussian noise (the scene's floor), s: the
    /// deterministic scheme's own Δt error, for comparison.
    pub deterministic_onset_s: Option<f64>,
}

impl NoiseLevel {
    /// Statistics of `onsets` (per seed) at `dt_s`.
    #[must_use]
    pub fn of(dt_s: f64, onsets: Vec<Option<f64>>, wall_s: f64) -> Self {
        let v: Vec<f64> = onsets.iter().flatten().copied().collect();
        let n = v.len() as f64;
        let m = mean(&v);
        let std = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let on_end = v
            .iter()
            .filter(|&&t| {
                let k = (t / dt_s).round();
                (t - k * dt_s).abs() <= 1e-6 * dt_s
            })
            .count();
        Self {
            dt_s,
            first_onsets_s: onsets,
            mean_s: m,
            std_s: std,
            se_mean_s: std / n.sqrt(),
            se_std_s: std / (2.0 * (n - 1.0)).sqrt(),
            at_step_end: on_end as f64 / n,
            wall_s,
            deterministic_onset_s: None,
        }
    }

    /// Seeds without an onset.
    #[must_use]
    pub fn missing(&self) -> usize {
        self.first_onsets_s.iter().filter(|o| o.is_none()).count()
    }
}

/// A weak error with its standard error, s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WeakError {
    /// Step, s.
    pub dt_s: f64,
    /// Statistic at Δt minus the reference's, s.
    pub error_s: f64,
    /// Its standard error (both levels' combined), s.
    pub se_s: f64,
    /// The same difference without noise (the deterministic scheme's first onset; only for
    /// the mean), s.
    pub deterministic_s: Option<f64>,
}

/// The observed weak order of one statistic.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WeakOrder {
    /// Weak errors per level (coarse to fine).
    pub errors: Vec<WeakError>,
    /// Slope of log |error| against log Δt over the levels with |error| > 2·se.
    pub slope: Option<f64>,
    /// Levels in that slope.
    pub slope_points: usize,
    /// p of the weighted fit m(Δt) = m0 + C·Δt^p over every level and the reference.
    pub fit_p: Option<f64>,
    /// m0 of that fit (the statistic's Δt → 0 limit), s.
    pub fit_limit_s: Option<f64>,
}

/// Weighted least squares of y = m0 + C·x^p over p in [0.1, 3] (step 0.005): (p, m0, C).
#[must_use]
pub fn fit_power(points: &[(f64, f64, f64)]) -> Option<(f64, f64, f64)> {
    if points.len() < 3 {
        return None;
    }
    let mut best: Option<(f64, f64, f64, f64)> = None;
    for i in 0..=580 {
        let p = 0.1 + 0.005 * f64::from(i);
        // Weighted normal equations for (m0, C) with basis (1, x^p).
        let (mut s1, mut sx, mut sxx, mut sy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for &(x, y, se) in points {
            let w = 1.0 / (se * se).max(f64::MIN_POSITIVE);
            let u = x.powf(p);
            s1 += w;
            sx += w * u;
            sxx += w * u * u;
            sy += w * y;
            sxy += w * u * y;
        }
        let det = s1 * sxx - sx * sx;
        if det.abs() < f64::MIN_POSITIVE {
            continue;
        }
        let c = (s1 * sxy - sx * sy) / det;
        let m0 = (sy - c * sx) / s1;
        let chi2: f64 = points
            .iter()
            .map(|&(x, y, se)| ((y - m0 - c * x.powf(p)) / se).powi(2))
            .sum();
        if best.is_none_or(|b| chi2 < b.3) {
            best = Some((p, m0, c, chi2));
        }
    }
    best.map(|(p, m0, c, _)| (p, m0, c))
}

fn weak_order(
    levels: &[NoiseLevel],
    reference: &NoiseLevel,
    stat: fn(&NoiseLevel) -> (f64, f64),
    deterministic: bool,
) -> WeakOrder {
    let (r, r_se) = stat(reference);
    let errors: Vec<WeakError> = levels
        .iter()
        .map(|l| {
            let (v, se) = stat(l);
            WeakError {
                dt_s: l.dt_s,
                error_s: v - r,
                se_s: se.hypot(r_se),
                deterministic_s: match (l.deterministic_onset_s, reference.deterministic_onset_s) {
                    (Some(a), Some(b)) if deterministic => Some(a - b),
                    _ => None,
                },
            }
        })
        .collect();
    let sig: Vec<(f64, f64)> = errors
        .iter()
        .filter(|e| e.error_s.abs() > 2.0 * e.se_s)
        .map(|e| (e.dt_s, e.error_s.abs()))
        .collect();
    let slope = (sig.len() >= 2).then(|| log_log_slope(&sig));
    let pts: Vec<(f64, f64, f64)> = levels
        .iter()
        .chain(std::iter::once(reference))
        .map(|l| {
            let (v, se) = stat(l);
            (l.dt_s, v, se)
        })
        .collect();
    let fit = fit_power(&pts);
    WeakOrder {
        errors,
        slope,
        slope_points: sig.len(),
        fit_p: fit.map(|f| f.0),
        fit_limit_s: fit.map(|f| f.1),
    }
}

/// The whole noise study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoiseStudy {
    /// Levels.
    pub settings: NoiseSettings,
    /// One level per Δt (coarse to fine).
    pub levels: Vec<NoiseLevel>,
    /// The reference level.
    pub reference: NoiseLevel,
    /// Weak error and order of the mean first onset.
    pub mean: WeakOrder,
    /// Weak error and order of its spread (standard deviation).
    pub spread: WeakOrder,
}

/// Runs the study.
pub fn study(s: &NoiseSettings, progress: &mut dyn FnMut(&RunRecord)) -> NoiseStudy {
    let level = |dt: f64, progress: &mut dyn FnMut(&RunRecord)| {
        let mut wall = 0.0;
        let onsets = (1..=s.seeds)
            .map(|seed| {
                let mut spec = RunSpec::fig2(Scheme::Accurate, s.nodes, dt);
                spec.end_s = s.end_s;
                spec.noise = Some((s.sigma, seed));
                let r = run(&spec);
                progress(&r);
                wall += r.wall_s;
                r.events
                    .first()
                    .filter(|_| r.failure.is_none())
                    .map(|e| e.onset_s)
            })
            .collect();
        let mut spec = RunSpec::fig2(Scheme::Accurate, s.nodes, dt);
        spec.end_s = s.end_s;
        let r = run(&spec);
        progress(&r);
        let mut l = NoiseLevel::of(dt, onsets, wall);
        l.deterministic_onset_s = r.events.first().map(|e| e.onset_s);
        l
    };
    let levels: Vec<NoiseLevel> = s.dts_s.iter().map(|&dt| level(dt, progress)).collect();
    let reference = level(s.reference_dt_s, progress);
    let mean = weak_order(&levels, &reference, |l| (l.mean_s, l.se_mean_s), true);
    let spread = weak_order(&levels, &reference, |l| (l.std_s, l.se_std_s), false);
    NoiseStudy {
        settings: s.clone(),
        levels,
        reference,
        mean,
        spread,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_power_fit_finds_a_known_order() {
        // m = 5 + 2·h^0.5 with small, equal errors.
        let pts: Vec<(f64, f64, f64)> = [8.0, 4.0, 2.0, 1.0, 0.5, 0.25]
            .iter()
            .map(|&h: &f64| (h, 5.0 + 2.0 * h.sqrt(), 1e-3))
            .collect();
        let (p, m0, c) = fit_power(&pts).unwrap();
        assert!((p - 0.5).abs() < 0.01, "{p}");
        assert!(
            (m0 - 5.0).abs() < 0.02 && (c - 2.0).abs() < 0.02,
            "{m0} {c}"
        );
    }

    #[test]
    fn level_statistics() {
        let l = NoiseLevel::of(1.0, vec![Some(1.0), Some(3.5), None], 0.0);
        assert_eq!(l.missing(), 1);
        assert!((l.mean_s - 2.25).abs() < 1e-15);
        assert!((l.std_s - 2.5 / 2f64.sqrt()).abs() < 1e-12);
        assert!((l.at_step_end - 0.5).abs() < 1e-15);
    }
}
