//! The reduced-size fig2 run (N = 30, fixed Δt = 2e-8 s, end = 1 ms) and the qualitative
//! features taken from it (event count, onsets to 0.1 µs, first radii, step count, verdicts of
//! the claims computable from fig2 alone).
//!
//! `cargo xtask validate` runs it through the `stickslip` binary and writes its features into
//! `reports/summary.json` (block `"reduced"`); the fast test `tests/reduced.rs` runs the same
//! scene and overrides in-process (`stickslip_run::run_in_memory`) and computes the features
//! with the same [`features`], so the committed reports go stale loudly and the command line
//! is checked against the run library on every `cargo test`.

use crate::claims::{c1_part, c2_part, c3_part, c4_events_part, c9_periodic_part};
use crate::facts::{Facts, word};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use stickslip_run::RunOutput;

/// Time step of the reduced run, s.
pub use crate::sizes::REDUCED_DT_S as DT_S;
/// End time of the reduced run, s.
pub use crate::sizes::REDUCED_END_S as END_S;
/// Nodes of the reduced run.
pub use crate::sizes::REDUCED_NODES as NODES;
/// The `--set` overrides that turn `validation/scenes/fig2.toml` into the reduced run.
pub use crate::sizes::reduced_overrides as cli_overrides;

/// Qualitative features of a reduced run: what `summary.json` commits and the test checks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Features {
    /// Scene and size, in words.
    pub setup: String,
    /// Steps taken.
    pub steps: u64,
    /// Number of melting events.
    pub events: usize,
    /// Onset times rounded to 0.1 µs.
    pub onsets_us: Vec<f64>,
    /// Outermost melted radius at each onset, rounded to 0.1 µm.
    pub r_first_um: Vec<f64>,
    /// Verdicts of the claims (parts) computable from fig2 alone.
    pub verdicts: BTreeMap<String, bool>,
}

/// Rounds to one decimal.
pub fn round1(x: f64) -> f64 {
    (x * 10.0).round() / 10.0
}

/// The features of `run` (a fig2-like run), from its outputs as the schema reads them.
pub fn features(run: &RunOutput) -> Features {
    let ev = run.events.events();
    let verdicts = [
        ("C1", c1_part(run).pass),
        ("C2_fig2", c2_part(run).pass),
        ("C3", c3_part(run).pass),
        ("C4_fig2", c4_events_part(run).pass),
        ("C9_fig2", c9_periodic_part(run).pass),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    Features {
        setup: format!(
            "{}, {} scheme, N = {}, dt = {:e} s, end = {:e} s",
            run.info.name,
            word(&run.info.scheme()),
            run.info.nodes(),
            run.info.dt_s(),
            run.info.end_s()
        ),
        steps: run.info.steps,
        events: ev.len(),
        onsets_us: ev.iter().map(|e| round1(e.t_onset_s * 1e6)).collect(),
        r_first_um: ev.iter().map(|e| round1(e.r_first_m * 1e6)).collect(),
        verdicts,
    }
}
