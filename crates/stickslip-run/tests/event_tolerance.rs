//! `numerics.event_tolerance_factor`: a cascade's steps (those that start while a melting
//! event is open) taken to a looser tolerance, the stick phases to the scene's. On the
//! h0 = 1 nm contact's first slip (sfa.toml at N = 100, h0 = 1.2 nm, G* = 1.3 GPa, 11
//! meltings to 0.16 s) the run takes fewer attempts, melts the same nodes in every event, and
//! its onsets move by far less than the slip's onset accuracy target (1e-4 s).

use crate::common;

use stickslip_run::Scene;

#[test]
fn a_looser_tolerance_in_cascades_saves_attempts_and_melts_the_same_nodes() {
    let tight = common::sfa_first_slip(&[]);
    let loose = common::sfa_first_slip(&["numerics.event_tolerance_factor=30"]);
    assert!(tight.events.len() >= 8, "{}", tight.events.len());
    // The same nodes melt in every event.
    let largest_shift = common::same_meltings_largest_onset_shift(&loose, &tight);
    let (n_tight, n_loose) = (common::attempts(&tight), common::attempts(&loose));
    println!("attempts {n_tight} → {n_loose}; largest onset shift {largest_shift:e} s");
    assert!(
        (n_loose as f64) < 0.7 * n_tight as f64,
        "{n_tight} → {n_loose} attempts"
    );
    // A tenth of the slip's onset accuracy target.
    assert!(largest_shift < 1e-5, "{largest_shift:e} s");
}

#[test]
fn the_default_factor_is_one_and_fixed_steps_refuse_another() {
    let scene = Scene::from_path::<&str>(&common::scene("sfa"), &[]).unwrap();
    assert_eq!(scene.config.numerics.event_tolerance_factor, 1.0);
    common::refused_adaptive_only_key("numerics.event_tolerance_factor", "10", "0.5");
}
