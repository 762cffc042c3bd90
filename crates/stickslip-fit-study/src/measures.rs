//! The study's numbers from its record: coverage per parameter, interval width against the
//! number of samples and its log–log slope, the Jacobians' agreement, costs, and what the fits
//! find identifiable — each with its target and verdict. Pure functions of the record, so that
//! the report's every number is computed from the data it describes.

use crate::record::{FitSummary, JacobianCheck};
use stickslip_report::stats::{log_log_slope, median};

/// The intervals' nominal coverage.
pub const COVERAGE_NOMINAL: f64 = 0.95;
/// The coverage band's two-sided probability: a count outside it has less than this chance
/// under the nominal coverage.
pub const COVERAGE_BAND_ALPHA: f64 = 0.05;
/// The pulls' standard deviation passes within [lo, hi]: 1 when the standard errors are right;
/// below 0.7 the intervals are more than 1.4× too wide, above 1.3 too narrow.
pub const PULL_SD_BAND: (f64, f64) = (0.7, 1.3);
/// Fewest judged fits (not at a bound, identified) for a coverage verdict.
pub const MIN_JUDGED: usize = 5;
/// The expected log–log slope of an interval's width against the number of samples.
pub const SLOPE_EXPECTED: f64 = -0.5;
/// The band around it that passes.
pub const SLOPE_BAND: f64 = 0.1;
/// The Jacobian's columns agree with central differences within this relative difference.
pub const JACOBIAN_RTOL: f64 = 0.05;
/// Target: a two-parameter event fit of fig2 at N = 100, s.
pub const FIG2_FIT_TARGET_S: f64 = 30.0;
/// Target: a four-parameter fit of the SFA contact's first slip at N = 100, s.
pub const FIRST_SLIP_TARGET_S: f64 = 300.0;
/// A parameter is identified when its 95 % half-width is within this much of its box (the
/// fit's own rule for an undetermined direction).
pub const BOX_HALF: f64 = 0.5;

/// "pass" or "fail".
#[must_use]
pub fn verdict(pass: bool) -> &'static str {
    if pass { "pass" } else { "fail" }
}

/// Why a fit's parameter is left out of its coverage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Excluded {
    /// The fitted value sits at a bound of the box: a Gaussian interval there proves nothing.
    AtBound,
    /// The fit calls it (or a combination with it) undetermined, gives it no interval, or its
    /// interval reaches outside the box.
    Unidentified,
}

/// Whether `key` of `fit` is left out of coverage, and why.
#[must_use]
pub fn excluded(fit: &FitSummary, key: &str) -> Option<Excluded> {
    let p = fit.param(key)?;
    if p.at_bound() {
        return Some(Excluded::AtBound);
    }
    let beyond = match (p.lo95, p.hi95) {
        (Some(a), Some(b)) => a < p.lo || b > p.hi,
        _ => true,
    };
    (fit.unidentified.iter().any(|u| u.contains(key)) || p.stderr.is_none() || beyond)
        .then_some(Excluded::Unidentified)
}

/// The counts k of n fits that a coverage of `nominal` gives with probability at least
/// 1 − `alpha`, two-sided: [k_lo, k_hi] with P(X < k_lo) ≤ α/2 and P(X > k_hi) ≤ α/2.
#[must_use]
pub fn binomial_band(n: usize, nominal: f64, alpha: f64) -> (usize, usize) {
    let pmf: Vec<f64> = (0..=n)
        .map(|k| {
            let mut c = 1.0f64;
            for j in 0..k {
                c *= (n - j) as f64 / (j + 1) as f64;
            }
            c * nominal.powi(k as i32) * (1.0 - nominal).powi((n - k) as i32)
        })
        .collect();
    let mut lo = 0;
    let mut below = 0.0;
    while lo < n && below + pmf[lo] <= alpha / 2.0 {
        below += pmf[lo];
        lo += 1;
    }
    let mut hi = n;
    let mut above = 0.0;
    while hi > lo && above + pmf[hi] <= alpha / 2.0 {
        above += pmf[hi];
        hi -= 1;
    }
    (lo, hi)
}

/// One parameter's coverage over a set's fits.
#[derive(Debug, Clone, PartialEq)]
pub struct Coverage {
    /// The parameter.
    pub key: String,
    /// Fits.
    pub fits: usize,
    /// Fits judged: not at a bound and identified.
    pub judged: usize,
    /// Judged fits whose 95 % interval holds the truth.
    pub covered: usize,
    /// Fits left out: at a bound.
    pub at_bound: usize,
    /// Fits left out: unidentified (no interval, called undetermined, or an interval outside
    /// the box).
    pub undetermined: usize,
    /// The counts of `judged` that the nominal coverage gives (two-sided binomial band).
    pub band: (usize, usize),
    /// covered / judged.
    pub share: f64,
    /// Median relative 95 % half-width (judged fits).
    pub median_rel_half_width: f64,
    /// Mean of (value − truth)/stderr (judged fits).
    pub pull_mean: f64,
    /// Standard deviation of those pulls (1 when the standard errors are right).
    pub pull_sd: f64,
    /// The judged fits' pulls, ascending (for the Q–Q plot).
    pub pulls: Vec<f64>,
    /// Covered within the band, the pulls' SD within [`PULL_SD_BAND`], and at least
    /// [`MIN_JUDGED`] judged fits.
    pub pass: bool,
}

/// The coverage of `key` over `fits`: two-sided, the count within the binomial band of the
/// nominal 95 % and the pulls' SD within [`PULL_SD_BAND`]; fits at a bound or unidentified
/// are counted apart and left out.
#[must_use]
pub fn coverage(fits: &[FitSummary], key: &str) -> Coverage {
    let with: Vec<&FitSummary> = fits.iter().filter(|f| f.param(key).is_some()).collect();
    let at_bound = with
        .iter()
        .filter(|f| excluded(f, key) == Some(Excluded::AtBound))
        .count();
    let undetermined = with
        .iter()
        .filter(|f| excluded(f, key) == Some(Excluded::Unidentified))
        .count();
    let ps: Vec<_> = with
        .iter()
        .filter(|f| excluded(f, key).is_none())
        .filter_map(|f| f.param(key))
        .collect();
    let covered = ps.iter().filter(|p| p.covers() == Some(true)).count();
    let share = if ps.is_empty() {
        f64::NAN
    } else {
        covered as f64 / ps.len() as f64
    };
    let rel: Vec<f64> = ps.iter().map(|p| p.relative_half_width()).collect();
    let mut pulls: Vec<f64> = ps.iter().filter_map(|p| p.pull()).collect();
    pulls.sort_by(f64::total_cmp);
    let n = pulls.len() as f64;
    let mean = pulls.iter().sum::<f64>() / n;
    let sd = (pulls.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let band = binomial_band(ps.len(), COVERAGE_NOMINAL, COVERAGE_BAND_ALPHA);
    Coverage {
        key: key.to_string(),
        fits: with.len(),
        judged: ps.len(),
        covered,
        at_bound,
        undetermined,
        band,
        share,
        median_rel_half_width: median(&rel),
        pull_mean: mean,
        pull_sd: sd,
        pulls,
        pass: ps.len() >= MIN_JUDGED
            && (band.0..=band.1).contains(&covered)
            && (PULL_SD_BAND.0..=PULL_SD_BAND.1).contains(&sd),
    }
}

/// One parameter's interval width against the number of samples, for one misfit.
#[derive(Debug, Clone, PartialEq)]
pub struct Scaling {
    /// The parameter.
    pub key: String,
    /// (samples, median relative 95 % half-width over the level's seeds).
    pub points: Vec<(f64, f64)>,
    /// The least-squares log–log slope.
    pub slope: f64,
    /// Whether it is within [`SLOPE_BAND`] of [`SLOPE_EXPECTED`].
    pub pass: bool,
}

/// The widths of `key` in `fits` at each of `levels` samples, and their slope.
#[must_use]
pub fn scaling(fits: &[FitSummary], key: &str, levels: &[usize]) -> Scaling {
    let points: Vec<(f64, f64)> = levels
        .iter()
        .map(|&n| {
            let w: Vec<f64> = fits
                .iter()
                .filter(|f| f.samples == n)
                .filter_map(|f| f.param(key))
                .map(|p| p.relative_half_width())
                .collect();
            (n as f64, median(&w))
        })
        .collect();
    let slope = log_log_slope(&points);
    Scaling {
        key: key.to_string(),
        points,
        slope,
        pass: (slope - SLOPE_EXPECTED).abs() <= SLOPE_BAND,
    }
}

/// The largest relative difference of a check's columns, at either step.
#[must_use]
pub fn jacobian_worst(c: &JacobianCheck) -> f64 {
    c.columns
        .iter()
        .flat_map(|k| [k.rel_diff_wide, k.rel_diff_narrow])
        .fold(0.0, f64::max)
}

/// Whether every column of `c` agrees within [`JACOBIAN_RTOL`] at both steps.
#[must_use]
pub fn jacobian_pass(c: &JacobianCheck) -> bool {
    jacobian_worst(c) <= JACOBIAN_RTOL
}

/// Wall times of `fits`: (median, largest, how many over `target_s`).
#[must_use]
pub fn wall_times(fits: &[FitSummary], target_s: f64) -> (f64, f64, usize) {
    let w: Vec<f64> = fits.iter().map(|f| f.wall_s).collect();
    (
        median(&w),
        w.iter().copied().fold(0.0, f64::max),
        w.iter().filter(|&&x| x > target_s).count(),
    )
}

/// What a set of fits of one case finds about one parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Identity {
    /// The parameter.
    pub key: String,
    /// Fits.
    pub fits: usize,
    /// Fits that name it in an undetermined combination.
    pub named: usize,
    /// Median 95 % half-width in box units (1 = the bounds' range).
    pub median_box_half_width: f64,
    /// Median relative 95 % half-width.
    pub median_rel_half_width: f64,
    /// Identified: named by fewer than half the fits, and the median box half-width within
    /// [`BOX_HALF`].
    pub identified: bool,
}

/// Whether statement `u` (one of a fit's unidentified combinations) names `key`.
#[must_use]
pub fn names(u: &str, key: &str) -> bool {
    u.split(|c: char| c.is_whitespace() || c == ',' || c == ':')
        .any(|w| w == key)
}

/// Per parameter (the time shift aside) what `fits` find.
#[must_use]
pub fn identifiability(fits: &[FitSummary]) -> Vec<Identity> {
    let Some(first) = fits.first() else {
        return Vec::new();
    };
    first
        .params
        .iter()
        .filter(|p| p.key != "time_shift")
        .map(|p| {
            let own: Vec<_> = fits.iter().filter_map(|f| f.param(&p.key)).collect();
            let named = fits
                .iter()
                .filter(|f| f.unidentified.iter().any(|u| names(u, &p.key)))
                .count();
            let boxes: Vec<f64> = own.iter().map(|q| q.box_half_width()).collect();
            let rel: Vec<f64> = own.iter().map(|q| q.relative_half_width()).collect();
            let b = median(&boxes);
            Identity {
                key: p.key.clone(),
                fits: fits.len(),
                named,
                median_box_half_width: b,
                median_rel_half_width: median(&rel),
                identified: 2 * named < fits.len() && b <= BOX_HALF,
            }
        })
        .collect()
}

/// The (fit, parameter) pairs of `fits` whose 95 % half-width exceeds half the box but which
/// the fit does not name as undetermined: a silent gap in its words.
#[must_use]
pub fn silent(fits: &[FitSummary]) -> Vec<(String, u64, String)> {
    let mut out = Vec::new();
    for f in fits {
        for p in f.params.iter().filter(|p| p.key != "time_shift") {
            if p.box_half_width() > BOX_HALF && !f.unidentified.iter().any(|u| names(u, &p.key)) {
                out.push((f.case.clone(), f.seed, p.key.clone()));
            }
        }
    }
    out
}

/// The fit's statement without its numbers in brackets (so that statements of several fits
/// about the same combination read alike).
#[must_use]
pub fn statement_kind(u: &str) -> String {
    let mut out = String::new();
    let mut depth = 0;
    for c in u.chars() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// How many of `fits` end at a χ² no larger than the true model's on the same data (a
/// hair's tolerance, 1e-9 of it, for the rounding of the true values into the box).
#[must_use]
pub fn reached(fits: &[FitSummary]) -> usize {
    fits.iter()
        .filter(|f| f.chi2_truth.is_some_and(|t| f.chi2 <= t * (1.0 + 1e-9)))
        .count()
}

/// σmax/σmin of a fit's Jacobian (infinite for a zero singular value).
#[must_use]
pub fn condition(f: &FitSummary) -> f64 {
    match (f.singular_values.first(), f.singular_values.last()) {
        (Some(a), Some(b)) if *b > 0.0 => a / b,
        _ => f64::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::ParamResult;

    fn fit(seed: u64, samples: usize, lo: f64, hi: f64, unidentified: &[&str]) -> FitSummary {
        let p = ParamResult {
            key: "lubricant.gamma".into(),
            unit: "1/(Pa·s)".into(),
            truth: 8.0,
            value: 0.5 * (lo + hi),
            stderr: Some((hi - lo) / 3.92),
            lo95: Some(lo),
            hi95: Some(hi),
            lo: 3.0,
            hi: 30.0,
            log: true,
            initial: Some(10.0),
        };
        FitSummary {
            case: "A".into(),
            seed,
            samples,
            misfit_kind: "events".into(),
            params: vec![p],
            singular_values: vec![10.0, 2.0],
            unidentified: unidentified.iter().map(|s| (*s).to_string()).collect(),
            correlation: vec![],
            chi2: 1.0,
            residuals: 10,
            residual_sigma: Some(1.0),
            noise_n: 1.0,
            data_events: 3,
            model_events: 3,
            evaluations: 10,
            failed_runs: 0,
            iterations: 1,
            converged: true,
            solver_noise: None,
            fd_steps: vec![1e-3],
            wall_s: f64::from(u32::try_from(seed).unwrap()),
            cpu_s: None,
            chi2_truth: None,
        }
    }

    #[test]
    fn coverage_is_two_sided_in_count_and_in_the_pulls_spread() {
        // The band of 20 fits at 95 %: 17 … 20 (P(X ≤ 16) = 0.016).
        assert_eq!(binomial_band(20, 0.95, 0.05), (17, 20));
        assert_eq!(binomial_band(100, 0.95, 0.05), (90, 99));
        // Pulls spread like a standard normal's: the errors' quantiles at stderr 0.1.
        let errs = [
            -1.87, -1.40, -1.13, -0.92, -0.75, -0.59, -0.45, -0.32, -0.19, -0.06, 0.06, 0.19, 0.32,
            0.45, 0.59, 0.75, 0.92, 1.13, 1.40, 1.87,
        ];
        let fits: Vec<FitSummary> = errs
            .iter()
            .enumerate()
            .map(|(s, e)| {
                let v = 8.0 + 0.1 * e;
                fit(s as u64, 10, v - 0.196, v + 0.196, &[])
            })
            .collect();
        let c = coverage(&fits, "lubricant.gamma");
        assert_eq!(
            (c.fits, c.judged, c.covered, c.undetermined),
            (20, 20, 20, 0)
        );
        assert!((c.pull_sd - 1.0).abs() < 0.05 && c.pass, "{c:?}");
        // The same values with intervals three times too wide: every interval holds the
        // truth, but the pulls' SD is a third: fails.
        let wide: Vec<FitSummary> = errs
            .iter()
            .enumerate()
            .map(|(s, e)| {
                let v = 8.0 + 0.1 * e;
                fit(s as u64, 10, v - 0.588, v + 0.588, &[])
            })
            .collect();
        let c = coverage(&wide, "lubricant.gamma");
        assert_eq!(c.covered, 20);
        assert!(c.pull_sd < 0.7 && !c.pass, "{c:?}");
        // A fit at a bound and one the fit calls undetermined are counted apart.
        let mut some = fits.clone();
        some[0].params[0].value = 30.0;
        some[1].unidentified = vec!["lubricant.gamma".into()];
        let c = coverage(&some, "lubricant.gamma");
        assert_eq!((c.judged, c.at_bound, c.undetermined), (18, 1, 1));
        assert!((c.median_rel_half_width - 0.196 / 8.0).abs() < 0.01);
    }

    #[test]
    fn the_slope_of_widths_halving_per_fourfold_samples_is_minus_a_half() {
        let fits: Vec<FitSummary> = [100usize, 200, 400, 800]
            .iter()
            .map(|&n| {
                let w = 0.8 / (n as f64).sqrt();
                fit(1, n, 8.0 - w, 8.0 + w, &[])
            })
            .collect();
        let s = scaling(&fits, "lubricant.gamma", &[100, 200, 400, 800]);
        assert!((s.slope + 0.5).abs() < 1e-9 && s.pass, "{s:?}");
        let flat: Vec<FitSummary> = [100usize, 200]
            .iter()
            .map(|&n| fit(1, n, 7.9, 8.1, &[]))
            .collect();
        let s = scaling(&flat, "lubricant.gamma", &[100, 200]);
        assert!(s.slope.abs() < 1e-9 && !s.pass);
    }

    #[test]
    fn identifiability_follows_the_fits_words_and_widths() {
        let named = "lubricant.gamma and lubricant.a trade off: raising one … (its 95 % \
                     half-width is 0.73 of the bounds' range)";
        assert!(names(named, "lubricant.gamma") && !names(named, "lubricant.tau_max"));
        assert_eq!(
            statement_kind(named),
            "lubricant.gamma and lubricant.a trade off: raising one …"
        );
        let good: Vec<FitSummary> = (0..3).map(|s| fit(s, 10, 7.9, 8.1, &[])).collect();
        let id = identifiability(&good);
        assert!(id[0].identified && id[0].named == 0, "{id:?}");
        let bad: Vec<FitSummary> = (0..3).map(|s| fit(s, 10, 1.0, 60.0, &[named])).collect();
        let id = identifiability(&bad);
        assert!(!id[0].identified && id[0].named == 3, "{id:?}");
        assert!(silent(&bad).is_empty());
        let quiet: Vec<FitSummary> = (0..1).map(|s| fit(s, 10, 1.0, 60.0, &[])).collect();
        assert_eq!(silent(&quiet).len(), 1);
        assert_eq!(wall_times(&good, 1.5), (1.0, 2.0, 1));
    }
}
