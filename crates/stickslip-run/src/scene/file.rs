//! The scene file as written: a serde mirror of the scene TOML (docs/reference.md, section
//! Scene keys), every key optional here.
//!
//! Unknown keys are rejected (`deny_unknown_fields` on every section). Which keys are required,
//! their defaults and their allowed ranges are decided when the scene is resolved
//! ([`super::resolve`]); the resolved scene is this same structure with every default filled in,
//! so it can be written to `run.json` and read back as a scene.
//!
//! Words are serde enums (the core's where it has them), so a misspelt word is a
//! deserialization error, translated into a message naming the key and the allowed words of
//! [`crate::keys`].

use serde::{Deserialize, Serialize};
pub use stickslip_core::config::{ContactModel, Scheme, Substrate};
pub use stickslip_core::drive::Integrator;

/// `lubricant.noise.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NoiseKindName {
    /// ξ ~ N(0, σ²Δt) per node and step.
    Gaussian,
    /// Deterministic floor φ ≥ floor.
    Floor,
    /// No noise.
    Off,
}

/// `temperature.law`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TemperatureLaw {
    /// A constant.
    Constant,
    /// A(t) = A0·exp(−t/t̃).
    Relaxation,
}

/// `drive.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DriveKind {
    /// Spring of stiffness K and stamp of mass m (Eq. 10).
    Spring,
    /// X = V0·t.
    Rigid,
}

/// `time.stepping`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stepping {
    /// Error-controlled steps.
    Adaptive,
    /// Fixed steps of `time.dt`.
    Fixed,
}

/// `numerics.operator`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OperatorChoice {
    /// Fast for the accurate scheme, dense for the literal one.
    Auto,
    /// Hierarchical low-rank, O(N) per apply.
    Fast,
    /// Dense mat-vec, O(N²) per apply.
    Dense,
}

/// A whole scene file as written (keys: docs/reference.md). All quantities SI.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Name of the scene (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// `[lubricant]` (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lubricant: Option<LubricantSection>,
    /// `[temperature]` (optional).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub temperature: Option<TemperatureSection>,
    /// `[contact]` (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactSection>,
    /// `[drive]` (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive: Option<DriveSection>,
    /// `[time]` (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeSection>,
    /// `[output]` (optional).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output: Option<OutputSection>,
    /// `[numerics]` (optional).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub numerics: Option<NumericsSection>,
}

/// `[lubricant]`: the Landau film (Eq. 1–8).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LubricantSection {
    /// τmax, Pa (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tau_max: Option<f64>,
    /// εmax, dimensionless (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eps_max: Option<f64>,
    /// a, Pa (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a: Option<f64>,
    /// γ, 1/(Pa·s) (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gamma: Option<f64>,
    /// φ below which a node counts as melted (default 0.01).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub melt_threshold: Option<f64>,
    /// b₃ of the first-order film, Pa (default 0: the second-order film; as resolved, present
    /// only when > 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cubic: Option<f64>,
    /// The first-order film's melting strain ε₊ instead of `cubic` (converted to b₃ once, at
    /// the initial temperature; as resolved, given as `cubic`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eps_melt: Option<f64>,
    /// `[lubricant.noise]` (optional; default floor 1e-6).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise: Option<NoiseSection>,
}

/// `[lubricant.noise]`: thermal noise ξ(t) or its deterministic floor.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseSection {
    /// `"gaussian"`, `"floor"` (default) or `"off"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kind: Option<NoiseKindName>,
    /// σ, s^-1/2 (gaussian only; default 1.0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// φ floor, dimensionless (floor only; default 1e-6).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub floor: Option<f64>,
    /// Seed of the per-node streams (gaussian only; default 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<i64>,
}

/// `[temperature]`: the law of A(t) (Eq. 17, 18).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureSection {
    /// `"constant"` (default) or `"relaxation"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub law: Option<TemperatureLaw>,
    /// A (constant) or A0 (relaxation), Pa.
    #[serde(rename = "A0", skip_serializing_if = "Option::is_none")]
    pub a0: Option<f64>,
    /// t̃, s (relaxation only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_relax: Option<f64>,
}

/// `[contact]`: stamp geometry and elasticity (Eq. 9–16).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// a0, m (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// h0, m (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub film_thickness: Option<f64>,
    /// G*, Pa (or g1, nu1, g2, nu2).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g_eff: Option<f64>,
    /// G1, Pa.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g1: Option<f64>,
    /// ν1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nu1: Option<f64>,
    /// G2, Pa.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g2: Option<f64>,
    /// ν2.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nu2: Option<f64>,
    /// N (default 2000).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nodes: Option<i64>,
    /// `"radial"` (default) or `"homogeneous"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<ContactModel>,
    /// `"elastic"` (default) or `"rigid"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub substrate: Option<Substrate>,
}

/// `[drive]`: how the stamp is pulled (Eq. 10).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveSection {
    /// `"spring"` (default) or `"rigid"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kind: Option<DriveKind>,
    /// K, N/m (spring only, required there).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// m, kg (spring only, required there).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// V0, m/s (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub velocity: Option<f64>,
    /// `"split"` (default), `"verlet"` or `"rk4"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integrator: Option<Integrator>,
}

/// `[time]`: interval, step and scheme.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSection {
    /// End time, s (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end: Option<f64>,
    /// Step Δt, s (default 1e-8).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// `"accurate"` (default) or `"literal"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scheme: Option<Scheme>,
    /// `"adaptive"` (default for the accurate scheme without gaussian noise) or `"fixed"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stepping: Option<Stepping>,
    /// Adaptive: allowed local error per step relative to the error scales (default 1e-4).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// Adaptive: longest step, s (default time.end / 1000).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt_max: Option<f64>,
    /// Adaptive: shortest step, s, accepted whatever its error (default 1e-6·min(dt, dt_max)).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt_min: Option<f64>,
    /// Stop once this many events have ended (default: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_events: Option<i64>,
    /// Stop once an event has stayed open this long, s (default: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_open_event: Option<f64>,
    /// `"end"` (default) or `"periodic"`: stop once the last cycles repeat.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub until: Option<Until>,
    /// Cycles that must repeat (default 3).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steady_cycles: Option<i64>,
    /// Relative tolerance of the repetition (default 1e-3).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steady_rtol: Option<f64>,
}

/// `time.until`: how long a run goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Until {
    /// To `time.end` (or another stop rule).
    End,
    /// Until the last cycles repeat (see `crate::steady`), at most to `time.end`.
    Periodic,
}

/// `[output]`: what is recorded.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Times of the profiles, s (default `[time.end]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile_times: Option<Vec<f64>>,
    /// Radii of the φ(t) probes, m (default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub probe_radii: Option<Vec<f64>>,
    /// A melting this soon after the previous event ended continues it, s (default 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub event_merge_gap: Option<f64>,
    /// An event ends when every node is back above this multiple of the threshold (default 2).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub event_recovery: Option<f64>,
    /// Interval between rows of series.csv and probes.csv, s (default 1e-7; an addition).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub series_interval: Option<f64>,
}

/// `[numerics]`: numerical controls.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NumericsSection {
    /// Relative residual of the coupling solve (default 1e-10).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coupling_tol: Option<f64>,
    /// Runaway limit on |τ| in units of τmax (default 10).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub runaway_stress_factor: Option<f64>,
    /// `"auto"` (default: fast for the accurate scheme, dense for the literal one), `"fast"`
    /// (hierarchical low-rank, O(N) per apply) or `"dense"` (O(N²) mat-vec).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub operator: Option<OperatorChoice>,
}
