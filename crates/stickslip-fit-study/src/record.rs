//! `reports/fit.json`: everything the study measured, one type written and read back here, so
//! that `--render-only` redraws the report from it and every number of the report comes from
//! it.

use crate::cases::{Case, Sizes};
use serde::{Deserialize, Serialize};
use stickslip_studies::fit::report::FitReport;

/// The file's name.
pub const FILE: &str = "fit.json";

/// One fitted parameter against its truth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParamResult {
    /// The scene key, or `time_shift`.
    pub key: String,
    /// Its unit.
    pub unit: String,
    /// The true value (0 for the trace misfit's time shift: the model is not shifted).
    pub truth: f64,
    /// The fitted value.
    pub value: f64,
    /// Standard error (none: not determined).
    pub stderr: Option<f64>,
    /// The 95 % interval (none: not determined).
    pub lo95: Option<f64>,
    /// Its upper end.
    pub hi95: Option<f64>,
    /// The bounds searched.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Searched in log space.
    pub log: bool,
    /// The scene's own value, where the search also starts (none for the time shift).
    #[serde(default)]
    pub initial: Option<f64>,
}

impl ParamResult {
    /// Whether the 95 % interval holds the truth (none when the interval is not determined).
    #[must_use]
    pub fn covers(&self) -> Option<bool> {
        Some(self.lo95? <= self.truth && self.truth <= self.hi95?)
    }

    /// The 95 % interval's half-width in box units (the bounds' range is 1; log space for a
    /// log parameter); infinite when not determined.
    #[must_use]
    pub fn box_half_width(&self) -> f64 {
        match (self.lo95, self.hi95) {
            (Some(a), Some(b)) if self.log && a > 0.0 => {
                0.5 * (b / a).ln() / (self.hi / self.lo).ln()
            }
            (Some(a), Some(b)) => 0.5 * (b - a) / (self.hi - self.lo),
            _ => f64::INFINITY,
        }
    }

    /// The interval's half-width relative to the fitted value (for the time shift, relative
    /// to the bounds' half range); infinite when not determined.
    #[must_use]
    pub fn relative_half_width(&self) -> f64 {
        match (self.lo95, self.hi95) {
            (Some(a), Some(b)) if self.value != 0.0 && self.key != "time_shift" => {
                0.5 * (b - a) / self.value.abs()
            }
            (Some(a), Some(b)) => (b - a) / (self.hi - self.lo),
            _ => f64::INFINITY,
        }
    }

    /// Whether the fitted value sits at a bound of the box (within 1e-6 of its range, in log
    /// space for a log parameter).
    #[must_use]
    pub fn at_bound(&self) -> bool {
        let (v, lo, hi) = if self.log && self.value > 0.0 && self.lo > 0.0 {
            (self.value.ln(), self.lo.ln(), self.hi.ln())
        } else {
            (self.value, self.lo, self.hi)
        };
        let tol = 1e-6 * (hi - lo).abs();
        (v - lo).abs() <= tol || (hi - v).abs() <= tol
    }

    /// (value − truth)/stderr: the error in units of the fit's own standard error (none when
    /// that is not determined).
    #[must_use]
    pub fn pull(&self) -> Option<f64> {
        self.stderr
            .filter(|s| *s > 0.0)
            .map(|s| (self.value - self.truth) / s)
    }
}

/// One fit's results, against the truth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitSummary {
    /// The case's id.
    pub case: String,
    /// The noise seed.
    pub seed: u64,
    /// Samples of the trace.
    pub samples: usize,
    /// `events` or `trace`.
    pub misfit_kind: String,
    /// The parameters.
    pub params: Vec<ParamResult>,
    /// The Jacobian's singular values (box units), decreasing.
    pub singular_values: Vec<f64>,
    /// The combinations the fit names as not determined.
    pub unidentified: Vec<String>,
    /// Correlations of the box coordinates.
    pub correlation: Vec<Vec<Option<f64>>>,
    /// χ².
    pub chi2: f64,
    /// Residuals.
    pub residuals: usize,
    /// s (at least 1).
    pub residual_sigma: Option<f64>,
    /// σF used, N.
    pub noise_n: f64,
    /// The data's events.
    pub data_events: usize,
    /// The fitted model's events.
    pub model_events: usize,
    /// Forward runs.
    pub evaluations: usize,
    /// Of which failed.
    pub failed_runs: usize,
    /// Local iterations.
    pub iterations: usize,
    /// Whether the local stage converged.
    pub converged: bool,
    /// The solver's noise, residual units.
    pub solver_noise: Option<f64>,
    /// The final difference steps, box units.
    pub fd_steps: Vec<f64>,
    /// Wall time of the fit, s.
    pub wall_s: f64,
    /// CPU time the study's process spent during the fit, s (all its threads; none where
    /// unreadable): over the wall time, the cores the fit had.
    #[serde(default)]
    pub cpu_s: Option<f64>,
    /// χ² of the true model against the same data (one more run): a fit above it missed the
    /// misfit's least value.
    #[serde(default)]
    pub chi2_truth: Option<f64>,
}

impl FitSummary {
    /// The summary of `report`, a fit of `case`'s trace with `seed` and `samples`.
    #[must_use]
    pub fn new(case: &Case, seed: u64, samples: usize, report: &FitReport) -> Self {
        Self {
            case: case.id.clone(),
            seed,
            samples,
            misfit_kind: report.misfit_kind.clone(),
            params: report
                .parameters
                .iter()
                .map(|p| ParamResult {
                    key: p.key.clone(),
                    unit: p.unit.clone(),
                    truth: case.true_value(&p.key).unwrap_or(0.0),
                    value: p.value,
                    stderr: p.stderr,
                    lo95: p.lo95,
                    hi95: p.hi95,
                    lo: p.lo,
                    hi: p.hi,
                    log: p.log,
                    initial: p.initial,
                })
                .collect(),
            singular_values: report.singular_values.clone(),
            unidentified: report.unidentified.clone(),
            correlation: report.correlation.clone(),
            chi2: report.misfit,
            residuals: report.residuals,
            residual_sigma: report.residual_sigma,
            noise_n: report.noise_n,
            data_events: report.data_events.len(),
            model_events: report.model_events.len(),
            evaluations: report.evaluations,
            failed_runs: report.failed_runs,
            iterations: report.iterations,
            converged: report.converged,
            solver_noise: report.solver_noise,
            fd_steps: report.fd_steps.clone(),
            wall_s: report.wall_s,
            cpu_s: None,
            chi2_truth: None,
        }
    }

    /// The parameter `key`.
    #[must_use]
    pub fn param(&self, key: &str) -> Option<&ParamResult> {
        self.params.iter().find(|p| p.key == key)
    }
}

/// The coverage of one parameter set: its fits over the noise seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoverageRun {
    /// The set.
    pub case: Case,
    /// One fit per seed.
    pub fits: Vec<FitSummary>,
}

/// The interval widths against the number of samples: the same trace (set A's scene and
/// truth) sampled at `levels` samples, fitted with both misfits.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WidthRun {
    /// The case at its first level.
    pub case: Case,
    /// Samples per level.
    pub levels: Vec<usize>,
    /// The events misfit's fits (every level and seed).
    pub events: Vec<FitSummary>,
    /// The trace misfit's fits.
    pub trace: Vec<FitSummary>,
}

/// One Jacobian column against central differences.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JacobianColumn {
    /// The parameter.
    pub key: String,
    /// The fit's step, box units.
    pub step: f64,
    /// ‖column‖ of the fit's Jacobian (residual units per box unit).
    pub norm: f64,
    /// ‖fit's − central difference at 2·step‖/‖fit's‖.
    pub rel_diff_wide: f64,
    /// ‖fit's − central difference at step/2‖/‖fit's‖.
    pub rel_diff_narrow: f64,
}

/// The Jacobian at one fit's optimum against central differences at two steps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JacobianCheck {
    /// The case.
    pub case: String,
    /// The seed of its trace.
    pub seed: u64,
    /// `events` or `trace`.
    pub misfit_kind: String,
    /// The solver's noise at the optimum, residual units.
    pub solver_noise: f64,
    /// Per parameter.
    pub columns: Vec<JacobianColumn>,
    /// Forward runs of the check.
    pub evaluations: usize,
}

/// A figure's curves, thinned for the record: the data and the fitted model at the same
/// sample times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Curves {
    /// Times, s.
    pub t_s: Vec<f64>,
    /// The data's F, N.
    pub data_f_n: Vec<f64>,
    /// The fitted model's F, N.
    pub model_f_n: Vec<f64>,
}

/// One fit of its own (the cost target, the damped viscous contact), with its fit.json and
/// its curves for the figure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SingleFit {
    /// The case.
    pub case: Case,
    /// The results against the truth.
    pub summary: FitSummary,
    /// A staged fit's first stage (some of the parameters, from the scene's values), whose
    /// values the fit of `summary` started from.
    #[serde(default)]
    pub first_stage: Option<FitSummary>,
    /// fit.json of the fit.
    pub report: FitReport,
    /// The curves, thinned.
    pub curves: Curves,
}

/// The host while the study ran.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Host {
    /// Cores available.
    pub cores: usize,
    /// Runs at a time of every fit.
    pub jobs: usize,
    /// The 1-minute load average at the start and at the end (none where unreadable).
    pub load_start: Option<f64>,
    /// At the end.
    pub load_end: Option<f64>,
}

/// One section's wall time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SectionTime {
    /// The section (`coverage-A`, `width`, …).
    pub name: String,
    /// Its wall time, s (its fits and its Jacobian checks).
    pub wall_s: f64,
}

/// The whole study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Study {
    /// The commit the study ran at (absent in studies made before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub commit: Option<stickslip_report::provenance::Commit>,
    /// Its sizes.
    pub sizes: Sizes,
    /// The host.
    pub host: Host,
    /// Wall time of the whole study, s: the sum of its sections'.
    pub wall_s: f64,
    /// Each section's wall time.
    pub sections: Vec<SectionTime>,
    /// Item 1: coverage of sets A and B.
    pub coverage: Vec<CoverageRun>,
    /// Item 2: widths against samples.
    pub width: WidthRun,
    /// Item 3: Jacobians at optima.
    pub jacobians: Vec<JacobianCheck>,
    /// The events misfit's σ against the residuals' scatter at the truth, per coverage set.
    #[serde(default)]
    pub sigmas: Vec<crate::sigmas::SigmaCheck>,
    /// Item 4: the four-parameter fit of the SFA contact's first slip.
    pub first_slip: SingleFit,
    /// The same, staged: τmax and γ first, then all four from there.
    #[serde(default)]
    pub first_slip_staged: Option<SingleFit>,
    /// Item 5: the damped, viscous SFA contact.
    pub viscous: SingleFit,
}

impl Study {
    /// The record as JSON text.
    ///
    /// # Panics
    /// Never: every field serialises.
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("the study serialises") + "\n"
    }

    /// Reads a record.
    ///
    /// # Errors
    /// Text that is not a study, in words.
    pub fn parse(text: &str) -> Result<Self, String> {
        serde_json::from_str(text).map_err(|e| e.to_string())
    }
}
