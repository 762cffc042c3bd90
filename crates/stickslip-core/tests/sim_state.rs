//! The simulation's state without a time loop: the lagged-sweep contraction factor from the
//! operators, and one step advancing the noise generators held in the state.

use stickslip_core::config::{Scheme, SimConfig, Substrate};
use stickslip_core::noise::NoiseKind;
use stickslip_core::sim::Simulation;

fn small_fig2(scheme: Scheme, nodes: usize) -> SimConfig {
    let mut c = crate::scenes::fig2(scheme);
    c.contact.nodes = nodes;
    c.time.dt_s = 2e-8;
    c
}

#[test]
fn lagged_sweep_contraction_scales_with_substrate_softness() {
    // ρ ∝ 1/G*: fig2 (G* = 1e9 Pa) contracts, a ten times softer substrate does not
    // (docs/model.md#the-literal-scheme).
    let rho = |g: f64, scheme| {
        let mut c = small_fig2(scheme, 200);
        c.contact.g_eff_pa = g;
        Simulation::new(c).unwrap().lagged_sweep_contraction()
    };
    for scheme in [Scheme::Literal, Scheme::Accurate] {
        let stiff = rho(1e9, scheme);
        let soft = rho(1e8, scheme);
        eprintln!("{scheme:?}: rho(1e9) = {stiff:.4}, rho(1e8) = {soft:.4}");
        assert!(stiff > 0.1 && stiff < 1.0, "{scheme:?}: rho = {stiff}");
        assert!(soft > 1.0, "{scheme:?}: rho = {soft}");
        assert!(
            (soft / stiff - 10.0).abs() < 1e-6,
            "{scheme:?}: {soft} / {stiff}"
        );
    }
    let mut c = small_fig2(Scheme::Accurate, 50);
    c.contact.substrate = Substrate::Rigid;
    assert_eq!(Simulation::new(c).unwrap().lagged_sweep_contraction(), 0.0);
}

#[test]
fn one_step_advances_the_noise_generators_in_the_state() {
    // The precondition of resuming gaussian runs: the state a checkpoint saves must follow the
    // noise generators, or a resumed run replays the noise from its start.
    let mut c = small_fig2(Scheme::Accurate, 10);
    // Gaussian noise is drawn per step: fixed steps (the scene's default is adaptive).
    c.time.adaptive = None;
    c.noise = NoiseKind::Gaussian {
        sigma_per_sqrt_s: 1.0,
        seed: 1,
    };
    let mut sim = Simulation::new(c).unwrap();
    let before = sim.state().physical.noise.clone();
    sim.step(1e-8).unwrap();
    assert_ne!(sim.state().physical.noise, before);
}
