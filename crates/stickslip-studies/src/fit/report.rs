//! fit.json, what `stickslip fit` found (docs/fit.md#fitjson): one type, written and read back
//! here. Numbers that can be infinite or undefined (a standard error of a parameter the data
//! do not determine, a correlation with it) are optional and written as null.

use serde::{Deserialize, Serialize};
use std::path::Path;
use stickslip_run::schema::SchemaError;

/// The file's name.
pub const FILE: &str = stickslip_run::layout::fit::REPORT_FILE;

/// One fitted parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitParameter {
    /// The scene key, or `time_shift` (the trace misfit's shift of the model's times).
    pub key: String,
    /// Its unit.
    pub unit: String,
    /// The fitted value.
    pub value: f64,
    /// Standard error (null: not determined, or not computed when interrupted).
    pub stderr: Option<f64>,
    /// Lower end of the 95 % interval.
    pub lo95: Option<f64>,
    /// Upper end of the 95 % interval.
    pub hi95: Option<f64>,
    /// Lower bound searched.
    pub lo: f64,
    /// Upper bound searched.
    pub hi: f64,
    /// Searched in log space.
    pub log: bool,
    /// The value in the scene before the fit (null for the time shift, or a key the scene
    /// leaves to a derived default it does not write out).
    pub initial: Option<f64>,
    /// The discretisation error, in the parameter's unit: how far the value moves when the
    /// model is refined (`discretisation_settings`: twice the nodes, a tenth of the
    /// tolerance), from one refined run at the optimum (null: not computed — interrupted, or
    /// the refined run failed).
    #[serde(default)]
    pub discretisation: Option<f64>,
}

/// One event of the data or of the fitted model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FitEvent {
    /// Onset (F crosses peak − h/2 on its way down), s.
    pub t_onset_s: f64,
    /// F at the peak, N.
    pub f_peak_n: f64,
    /// F's drop, N.
    pub drop_n: f64,
}

/// A profile likelihood of one parameter: the others refitted at each of its values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitProfile {
    /// The parameter.
    pub key: String,
    /// Its values.
    pub values: Vec<f64>,
    /// χ² at each, the others refitted.
    pub chi2: Vec<f64>,
    /// (χ² − χ²min)/s², which is below 3.84 inside a 95 % interval.
    pub delta: Vec<f64>,
    /// The interval where `delta` ≤ 3.84, linearly interpolated (null: it reaches the bound).
    pub lo95: Option<f64>,
    /// Its upper end.
    pub hi95: Option<f64>,
}

/// The profile strategy's scan (docs/fit.md#the-profile-strategy): the parameter pinned by
/// the first onset, the parameter scanned, and the profile's χ² at each scanned value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitScan {
    /// The parameter solved at every point so that the first onset matches.
    pub pinned: String,
    /// The parameter scanned.
    pub key: String,
    /// Its values, in the order they were fitted.
    pub values: Vec<f64>,
    /// χ² at each, the others (but the pinned one) fitted by the local stage.
    pub chi2: Vec<f64>,
    /// The value the final fit started from (the profile's least χ²).
    pub start: f64,
    /// The data's meltings the scan was made on (its first ones; none: the whole trace).
    #[serde(default)]
    pub window_events: Option<usize>,
}

/// fit.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    /// The scene's name.
    pub scene: String,
    /// `ok`, or `interrupted` (the best model found so far; its intervals, if any, are
    /// provisional: see `provisional_intervals`).
    pub status: String,
    /// The intervals are the local stage's last Jacobian's, not the final one at the optimum
    /// (an interrupted fit): an estimate, marked so wherever they are printed.
    #[serde(default)]
    pub provisional_intervals: bool,
    /// `events` or `trace`.
    pub misfit_kind: String,
    /// The fitted parameters.
    pub parameters: Vec<FitParameter>,
    /// Correlations of the parameters' box coordinates (of their logarithms for log
    /// parameters), row by row; null where undefined.
    pub correlation: Vec<Vec<Option<f64>>>,
    /// The Jacobian's singular values in box units, decreasing.
    pub singular_values: Vec<f64>,
    /// The combinations the data cannot determine, in words.
    pub unidentified: Vec<String>,
    /// The misfit χ² = Σ r² at the fit, each residual in units of its σ.
    pub misfit: f64,
    /// Residuals.
    pub residuals: usize,
    /// The residual standard deviation s = √(χ²/(residuals − parameters)), at least 1, which
    /// scales the covariance (null when interrupted).
    pub residual_sigma: Option<f64>,
    /// σF, N: the noise of F used for the weights.
    pub noise_n: f64,
    /// Whether `noise_n` was estimated from the data (else given).
    pub noise_estimated: bool,
    /// σX, m: the noise of the stamp's position, estimated from the data, when the trace has
    /// X and the trace misfit fits it (null otherwise).
    #[serde(default)]
    pub noise_x_m: Option<f64>,
    /// The events' hysteresis, N.
    pub hysteresis_n: f64,
    /// The solver's noise: ‖r(tolerance) − r(tolerance/10)‖ at the optimum (where the
    /// uncertainty's Jacobian is taken).
    pub solver_noise: Option<f64>,
    /// The finite-difference steps of the uncertainty's Jacobian, box units, per parameter.
    pub fd_steps: Vec<f64>,
    /// `time.tolerance` of the fit's runs (null with fixed steps).
    pub time_tolerance: Option<f64>,
    /// The `--set` overrides that make the scene the fitted one (fitted.toml holds them).
    pub settings: Vec<String>,
    /// The data's events.
    pub data_events: Vec<FitEvent>,
    /// The fitted model's events, at the data's times.
    pub model_events: Vec<FitEvent>,
    /// Local-stage iterations.
    pub iterations: usize,
    /// Whether the local stage converged (χ² stopped falling).
    pub converged: bool,
    /// Forward runs made.
    pub evaluations: usize,
    /// Of which failed (each counted as a penalty).
    pub failed_runs: usize,
    /// The first failure, in words.
    pub first_failure: Option<String>,
    /// The profile likelihood asked for.
    pub profile: Option<FitProfile>,
    /// How the fit searched: `direct` (global sample, then the local stage) or `profile`
    /// (a parameter pinned by the first onset, another scanned; see `scan`).
    #[serde(default)]
    pub strategy: String,
    /// How its Jacobians were made: `differences`, `replay` (forward differences of runs
    /// that replay the point's own steps), or both with the count of each and why replay
    /// did not apply (docs/fit.md#replayed-jacobians); empty in a fit.json written before.
    #[serde(default)]
    pub jacobian: String,
    /// The profile strategy's scan.
    #[serde(default)]
    pub scan: Option<FitScan>,
    /// Runs stopped after their first melting, made to solve the pinned parameter (not in
    /// `evaluations`; each costs a fraction of a whole run).
    #[serde(default)]
    pub onset_runs: usize,
    /// Wall time, s.
    pub wall_s: f64,
    /// The refinement the discretisation errors were measured with, as --set text.
    #[serde(default)]
    pub discretisation_settings: Vec<String>,
    /// What the fit warns of: a discretisation error larger than the standard error (the
    /// interval does not hold the model's own error: fit at more nodes or a finer tolerance).
    #[serde(default)]
    pub warnings: Vec<String>,
    /// A fingerprint of the fit's inputs (the resolved scene, the parameters and their boxes,
    /// the misfit, the noise option and the trace's numbers): an interrupted fit is resumed
    /// only by a fit of the same inputs.
    #[serde(default)]
    pub inputs: String,
}

impl FitReport {
    /// The report as pretty JSON.
    ///
    /// # Panics
    /// Never: the type has only JSON-representable fields (non-finite numbers are options).
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Parses fit.json's text.
    ///
    /// # Errors
    /// [`SchemaError`] when it does not match.
    pub fn parse(text: &str) -> Result<Self, SchemaError> {
        serde_json::from_str(text)
            .map_err(|e| SchemaError::new(FILE, Some(e.line()), e.to_string()))
    }

    /// Reads `dir/fit.json`.
    ///
    /// # Errors
    /// [`SchemaError`] naming the file.
    pub fn read(dir: &Path) -> Result<Self, SchemaError> {
        Self::parse(&stickslip_run::schema::read_text(dir, FILE)?)
    }

    /// Writes `dir/fit.json` atomically.
    ///
    /// # Errors
    /// If it cannot be written.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        stickslip_run::atomic::write_atomic(dir, FILE, self.to_json().as_bytes())
    }

    /// The parameter `key`.
    #[must_use]
    pub fn parameter(&self, key: &str) -> Option<&FitParameter> {
        self.parameters.iter().find(|p| p.key == key)
    }
}

/// A number for fit.json: `None` when not finite.
#[must_use]
pub fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}
