//! run.json: the resolved scene, derived and stability numbers, status and failure, step
//! counts, timing, version, seed, the unit of every output column and the run's summary.
//!
//! `status` is there from the start: `running` while the run goes on (written before the
//! first step), then `ok`, `failed` (with `failure`) or `interrupted` (a checkpoint is in the
//! directory; `stickslip resume DIR` finishes it). `resumed_across_builds` is there only when
//! the run was resumed from another build's checkpoint (`--allow-other-build`).

use super::SchemaError;
use crate::outcome::RunOutcome;
pub use crate::outcome::{RunStatus, StepCounts};
use crate::scene::{ResolvedScene, Scene};
use crate::summary::RunSummary;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use stickslip_core::noise::NoiseKind;
use stickslip_core::preflight::{Finding, Preflight};
use stickslip_core::sim::NumericalFailure;

/// File name.
pub const FILE: &str = "run.json";

/// A numerical failure (or refusal) as written to run.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FailureRecord {
    /// Time at the end of the failing step, s (0 for a refusal).
    pub time_s: f64,
    /// Number of the failing step, from 1 (0 for a refusal).
    pub step: u64,
    /// Node where the bad value appeared first.
    pub node: usize,
    /// Radius of that node, m.
    pub r_m: f64,
    /// The quantity (`phi`, `tau`, `coupling residual`, `lagged-sweep contraction factor`, …).
    pub quantity: String,
    /// Its value (a string when it is not finite, as JSON has no NaN).
    pub value: serde_json::Value,
    /// What it means and what to do.
    pub reason: String,
    /// The whole message, as printed.
    pub message: String,
}

impl From<&NumericalFailure> for FailureRecord {
    fn from(f: &NumericalFailure) -> Self {
        Self {
            time_s: f.t_s,
            step: f.step,
            node: f.node,
            r_m: f.r_m,
            quantity: f.quantity.to_string(),
            value: serde_json::Number::from_f64(f.value).map_or_else(
                || serde_json::Value::String(format!("{}", f.value)),
                Into::into,
            ),
            reason: f.diagnosis.clone(),
            message: f.to_string(),
        }
    }
}

/// A resume from a checkpoint that another build of the numerics wrote (`stickslip resume
/// --allow-other-build`): the run's numbers before and after it come from different builds.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct BuildCrossing {
    /// The build that wrote the checkpoint.
    pub checkpoint_build: String,
    /// The build that resumed it.
    pub build: String,
}

/// Derived parameters as written to run.json (SI).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DerivedReport {
    /// b = 2a²εmax³/τmax, Pa.
    pub b: f64,
    /// A at t = 0, Pa.
    #[serde(rename = "A")]
    pub a: f64,
    /// εc = √(A·b)/a at t = 0 (the first-order film re-solidifies there, ε₋ = εc).
    pub eps_c: f64,
    /// φ0 = √(A/a), the initial state (the first-order film's φ₊(0)).
    pub phi0: f64,
    /// ω = √(K/m), rad/s (0 for the rigid drive).
    pub omega: f64,
    /// G*, Pa (given or from Eq. 9).
    pub g_eff: f64,
    /// Nodes simulated (1 for the homogeneous model).
    pub nodes: usize,
    /// Steps the scene asks for (fixed stepping; a scale with adaptive steps).
    pub steps_planned: u64,
    /// Contraction factor ρ((a·φ0²/h0)·C/G*) of the paper's lagged elastic sweep at t = 0,
    /// for this scheme's compliance C: the literal scheme only converges for ρ < 1.
    pub lagged_sweep_contraction: f64,
    /// Largest friction force τmax·π·a0², N.
    pub melting_force: f64,
    /// Melting strain times h0, m: εc·h0 (ε₊·h0 for the first-order film).
    pub critical_displacement: f64,
    /// 2π/ω, s (null for the rigid drive).
    pub spring_period: Option<f64>,
    /// Δt·2γAb/a, literal scheme only (stable below 2).
    pub euler_number: Option<f64>,
    /// Estimate of the first onset, s, whatever time.end (null: the drive never reaches the
    /// melting strain).
    pub first_onset_estimate: Option<f64>,
    /// Stamp advance at which the contact first melts under quasi-static loading, m: the
    /// melting point of the contact as a spring (the target of `first_onset_estimate`; on an
    /// elastic radial contact the static problem's fold, which holds the substrate's share
    /// and the film's softening; εc·h0 on a rigid one). Absent when nothing can melt, and in
    /// run.json files written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub onset_displacement: Option<f64>,
    /// First-order film only (absent for b₃ = 0): b₃, Pa.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cubic: Option<f64>,
    /// First-order film only: ε₊, where the solid branch ends and the film melts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eps_melt: Option<f64>,
    /// First-order film only: ε₋ = εc, where a liquid film re-solidifies.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eps_solidify: Option<f64>,
    /// First-order film only: ε₊² − ε₋², the hysteresis width (b₃²/(4ab) while A > 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hysteresis_width: Option<f64>,
    /// First-order film only: τ on the solid branch at ε₊, Pa.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tau_melt: Option<f64>,
    /// First-order film with A ≤ 0 only: whether it starts as a metastable solid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub metastable_solid: Option<bool>,
    /// Viscous film only (absent for η = 0): c_v = η·π·a0²/h0, N·s/m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscous_drag: Option<f64>,
    /// Viscous film only: η·a0/(h0·G*), s (0 on a rigid substrate).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscous_time: Option<f64>,
}

impl DerivedReport {
    /// The derived parameters of `scene` with its preflight.
    #[must_use]
    pub fn of(scene: &ResolvedScene, preflight: &Preflight) -> Self {
        let d = &preflight.derived;
        Self {
            b: d.b_pa,
            a: d.a_coeff_pa,
            eps_c: d.eps_c,
            phi0: d.phi0,
            omega: d.omega_rad_per_s,
            g_eff: scene.config.contact.g_eff_pa,
            nodes: scene.config.simulated_nodes(),
            steps_planned: scene.steps,
            lagged_sweep_contraction: preflight.lagged_sweep_contraction,
            melting_force: preflight.melting_force_n,
            critical_displacement: preflight.critical_displacement_m,
            spring_period: preflight.spring_period_s,
            euler_number: preflight.euler_number,
            first_onset_estimate: preflight.first_onset_estimate_s,
            onset_displacement: preflight.contact_spring.map(|c| c.x_melt_m),
            cubic: preflight.first_order.map(|f| f.cubic_pa),
            eps_melt: preflight.first_order.map(|f| f.eps_melt),
            eps_solidify: preflight.first_order.map(|f| f.eps_solidify),
            hysteresis_width: preflight.first_order.map(|f| f.hysteresis_width),
            tau_melt: preflight.first_order.map(|f| f.tau_melt_pa),
            metastable_solid: preflight.first_order.and_then(|f| f.metastable_solid),
            viscous_drag: preflight.viscous.map(|v| v.drag_n_s_per_m),
            viscous_time: preflight.viscous.map(|v| v.time_s),
        }
    }
}

/// Contents of run.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunInfo {
    /// Scene name.
    pub name: String,
    /// Where the run stands.
    pub status: RunStatus,
    /// Why it failed (null unless `status` is `failed`).
    pub failure: Option<FailureRecord>,
    /// Why it stopped: `end` (time.end), `max_events`, `open_event` (time.max_open_event),
    /// `failure`, `refused`, `interrupted`, `io` (an I/O error ended it; null while running).
    pub stop: Option<String>,
    /// Program version (Cargo package version).
    pub version: String,
    /// The scene as resolved (defaults filled in).
    pub scene: Scene,
    /// Derived parameters.
    pub derived: DerivedReport,
    /// Notes and warnings of the preflight and of unusual values (likely unit slips).
    pub warnings: Vec<Finding>,
    /// Steps taken.
    pub steps: u64,
    /// Adaptive stepping: accepted steps (0 with fixed steps).
    pub accepted_steps: u64,
    /// Adaptive stepping: rejected attempts (0 with fixed steps).
    pub rejected_steps: u64,
    /// Adaptive stepping: steps accepted at time.dt_min above the tolerance.
    pub forced_steps: u64,
    /// Adaptive stepping: accepted attempts that brought a melting onset and were taken again
    /// ending at the located melting time; step evaluations = accepted + rejected + these.
    #[serde(default)]
    pub onset_retakes: u64,
    /// Time reached, s.
    pub t_final: f64,
    /// Wall-clock time of the time loop, s; for a resumed run, summed over its processes (each
    /// up to its last checkpoint, the last one to the end). The one field in which a resumed
    /// run's run.json differs from an uninterrupted one's.
    pub wall_seconds: f64,
    /// Coupling-solver iterations summed over all steps (accurate scheme).
    pub coupling_iterations: u64,
    /// Noise seed (null unless the noise is gaussian).
    pub seed: Option<u64>,
    /// Number of melting events.
    pub events: usize,
    /// Rows in series.csv (and probes.csv).
    pub series_rows: u64,
    /// Unit of every output column: file → column → unit.
    pub columns: BTreeMap<String, BTreeMap<String, String>>,
    /// The run's summary and regime (docs/model.md#regimes-and-friction-maps; null while running).
    pub summary: Option<RunSummary>,
    /// Resumes from a checkpoint of another build, in order (absent when there were none,
    /// so a run within one build writes the same run.json as before the field existed, and
    /// run.json files without it read as none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub resumed_across_builds: Vec<BuildCrossing>,
}

/// The noise seed of `scene`, if its noise draws random numbers.
#[must_use]
pub fn seed_of(scene: &ResolvedScene) -> Option<u64> {
    match scene.config.noise {
        NoiseKind::Gaussian { seed, .. } => Some(seed),
        NoiseKind::Off | NoiseKind::Floor { .. } => None,
    }
}

impl RunInfo {
    /// The run.json of a run of `scene` that has not taken a step yet (`status: running`).
    #[must_use]
    pub fn starting(scene: &ResolvedScene, preflight: &Preflight, warnings: Vec<Finding>) -> Self {
        Self {
            name: scene.name.clone(),
            status: RunStatus::Running,
            failure: None,
            stop: None,
            version: env!("CARGO_PKG_VERSION").to_string(),
            scene: scene.resolved.clone(),
            derived: DerivedReport::of(scene, preflight),
            warnings,
            steps: 0,
            accepted_steps: 0,
            rejected_steps: 0,
            forced_steps: 0,
            onset_retakes: 0,
            t_final: 0.0,
            wall_seconds: 0.0,
            coupling_iterations: 0,
            seed: seed_of(scene),
            events: 0,
            series_rows: 0,
            columns: super::column_units(&scene.output.probe_radii_m),
            summary: None,
            resumed_across_builds: Vec::new(),
        }
    }

    /// Sets the step counters.
    pub fn set_counts(&mut self, c: &StepCounts) {
        self.steps = c.steps;
        self.accepted_steps = c.accepted_steps;
        self.rejected_steps = c.rejected_steps;
        self.forced_steps = c.forced_steps;
        self.onset_retakes = c.onset_retakes;
        self.coupling_iterations = c.coupling_iterations;
    }

    /// Fills in what the run ended with: status, failure, stop reason, counters, time, wall
    /// seconds, events, rows and summary.
    pub fn finish(&mut self, outcome: &RunOutcome) {
        self.status = outcome.status();
        self.failure = outcome.failure.as_ref().map(FailureRecord::from);
        self.stop = Some(outcome.stop.name().to_string());
        self.set_counts(&outcome.counts);
        self.t_final = outcome.t_final_s;
        self.wall_seconds = outcome.wall_seconds;
        self.events = outcome.events.len();
        self.series_rows = outcome.series_rows;
        self.summary = Some(outcome.summary.clone());
    }

    /// Pretty JSON and a newline.
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text
    }

    /// Parses run.json.
    ///
    /// # Errors
    /// [`SchemaError`] naming what does not fit.
    pub fn parse(text: &str) -> Result<Self, SchemaError> {
        serde_json::from_str(text)
            .map_err(|e| SchemaError::new(FILE, Some(e.line()), e.to_string()))
    }

    /// Reads `dir/run.json`.
    ///
    /// # Errors
    /// As [`RunInfo::parse`], or if the file cannot be read.
    pub fn read(dir: &Path) -> Result<Self, SchemaError> {
        Self::parse(&super::read_text(dir, FILE)?)
    }

    /// Writes `dir/run.json` atomically.
    ///
    /// # Errors
    /// If it cannot be written.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        crate::atomic::write_atomic(dir, FILE, self.to_json().as_bytes())
    }

    /// End time of the scene, s.
    #[must_use]
    pub fn end_s(&self) -> f64 {
        self.scene
            .time
            .as_ref()
            .and_then(|t| t.end)
            .unwrap_or(f64::NAN)
    }
}
