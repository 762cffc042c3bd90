//! The sizes of the validation's runs, shared by the run list ([`crate::runner`]), the claims
//! and the reduced-size check ([`crate::reduced`]): N of every radial scene, and the reduced
//! fig2 run's N, step, end and overrides. A module that imports none of the others, so that
//! the run list, the claims and the reduced check need not import each other in a circle.

/// Nodes used for every radial scene (the paper used N = 2000). The evidence that this
/// suffices is measured on every validation: the `fig2_n50` and `fig2_n100` runs against
/// `fig2` (the report's Resolution section); the cost per N is in reports/performance.md.
pub const NODES: usize = 200;

/// Nodes of the reduced run.
pub const REDUCED_NODES: usize = 30;
/// Time step of the reduced run, s.
pub const REDUCED_DT_S: f64 = 2e-8;
/// End time of the reduced run, s.
pub const REDUCED_END_S: f64 = 1.0e-3;

/// The `--set` overrides that turn `validation/scenes/fig2.toml` into the reduced run: the
/// paper's fig2 (accurate scheme, floor noise 1e-6, default event settings) at N =
/// [`REDUCED_NODES`], fixed steps Δt = [`REDUCED_DT_S`], end = [`REDUCED_END_S`], rows every
/// 1e-7 s.
pub fn reduced_overrides() -> Vec<String> {
    use stickslip_run::keys::words::{NoiseKindName, Scheme, Stepping};
    use stickslip_run::keys::{contact, noise, output, time};
    [
        contact::NODES.set(REDUCED_NODES as i64),
        time::DT.set(REDUCED_DT_S),
        time::END.set(REDUCED_END_S),
        time::SCHEME.set(Scheme::Accurate),
        time::STEPPING.set(Stepping::Fixed),
        noise::KIND.set(NoiseKindName::Floor),
        noise::FLOOR.set(1e-6),
        output::PROFILE_TIMES.set(vec![REDUCED_END_S]),
        output::SERIES_INTERVAL.set(1e-7),
    ]
    .iter()
    .map(ToString::to_string)
    .collect()
}

/// The temperatures of claim C11's `hysteresis` runs, A0 in Pa: fig2's 1.5e6 Pa and a third
/// below and above it (εc from 1.41 to 2; the first-order film's ε₊ from 2.02 to 2.46).
pub const HYSTERESIS_A0_PA: [f64; 3] = [1.0e6, 1.5e6, 2.0e6];

/// The run name of the `hysteresis` scene at temperature `a0_pa` (`hysteresis_A1.5e6`).
pub fn hysteresis_run(a0_pa: f64) -> String {
    format!("hysteresis_A{a0_pa:e}")
}
