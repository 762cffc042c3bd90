//! The paper's fig2 as the tests' configuration, read from `validation/scenes/fig2.toml`
//! through the run library's scene reader: the tests start from the scene a user runs, so a
//! default that moves in the scene moves here too (no fixture restating it).

use stickslip_core::config::{Scheme, SimConfig};

/// fig2's scene file, as users run it.
const FIG2_TOML: &str = include_str!("../../../validation/scenes/fig2.toml");

/// fig2 (N = 2000, Δt = 10 ns, 1.3 ms, the default floor noise) with `scheme` and its
/// default grid: the edge-graded grid for the accurate scheme, the uniform one for the
/// literal scheme.
#[must_use]
pub fn fig2(scheme: Scheme) -> SimConfig {
    let scheme = match scheme {
        Scheme::Accurate => "time.scheme=accurate",
        Scheme::Literal => "time.scheme=literal",
    };
    stickslip_run::scene::Scene::from_toml_str(FIG2_TOML, &[scheme])
        .expect("validation/scenes/fig2.toml resolves")
        .config
}
