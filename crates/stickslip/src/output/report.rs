//! run.json: the resolved scene, derived parameters, step counts, timing, version, seed and
//! status of one run.

use crate::scene::{ResolvedScene, Scene};
use serde::Serialize;
use std::io;
use std::path::Path;
use stickslip_core::noise::NoiseKind;

/// Derived parameters as written to run.json (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DerivedReport {
    /// b = 2a²εmax³/τmax, Pa.
    pub b: f64,
    /// A at t = 0, Pa.
    #[serde(rename = "A")]
    pub a: f64,
    /// εc = √(A·b)/a at t = 0.
    pub eps_c: f64,
    /// φ0 = √(A/a).
    pub phi0: f64,
    /// ω = √(K/m), rad/s (0 for the rigid drive).
    pub omega: f64,
    /// G*, Pa (given or from Eq. 9).
    pub g_eff: f64,
    /// Nodes simulated (1 for the homogeneous model).
    pub nodes: usize,
    /// Steps the scene asks for.
    pub steps_planned: u64,
    /// Contraction factor ρ((a·φ0²/h0)·C/G*) of the paper's lagged elastic sweep at t = 0,
    /// for this scheme's compliance C: the literal scheme only converges for ρ < 1.
    pub lagged_sweep_contraction: f64,
}

impl DerivedReport {
    /// The derived parameters of `scene`.
    pub fn of(scene: &ResolvedScene, lagged_sweep_contraction: f64) -> Self {
        let d = &scene.derived;
        Self {
            b: d.b_pa,
            a: d.a_coeff_pa,
            eps_c: d.eps_c,
            phi0: d.phi0,
            omega: d.omega_rad_per_s,
            g_eff: scene.config.contact.g_eff_pa,
            nodes: scene.config.simulated_nodes(),
            steps_planned: scene.steps,
            lagged_sweep_contraction,
        }
    }
}

/// Contents of run.json.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunReport<'a> {
    /// Scene name.
    pub name: &'a str,
    /// `"ok"` or `"failed"`.
    pub status: &'static str,
    /// The failure message when `status` is `"failed"`, else null.
    pub failure: Option<String>,
    /// Program version (Cargo package version).
    pub version: &'static str,
    /// The scene as resolved (defaults filled in).
    pub scene: &'a Scene,
    /// Derived parameters.
    pub derived: DerivedReport,
    /// Steps taken (with adaptive stepping: the half steps kept, two per accepted step).
    pub steps: u64,
    /// Adaptive stepping: accepted steps (0 with fixed steps).
    pub accepted_steps: u64,
    /// Adaptive stepping: rejected attempts (0 with fixed steps).
    pub rejected_steps: u64,
    /// Adaptive stepping: steps accepted at time.dt_min above the tolerance.
    pub forced_steps: u64,
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
}

/// The noise seed of `scene`, if its noise draws random numbers.
pub fn seed_of(scene: &ResolvedScene) -> Option<u64> {
    match scene.config.noise {
        NoiseKind::Gaussian { seed, .. } => Some(seed),
        NoiseKind::Off | NoiseKind::Floor { .. } => None,
    }
}

/// Writes `report` as pretty JSON to `dir/run.json` (atomically).
///
/// # Errors
/// If the file cannot be written.
pub fn write_report(dir: &Path, report: &RunReport<'_>) -> io::Result<()> {
    let mut text = serde_json::to_string_pretty(report).map_err(io::Error::other)?;
    text.push('\n');
    super::write_atomic(dir, "run.json", text.as_bytes())
}
