//! Whole simulations on small scenes, through the driver: complete melting, free spring, force
//! consistency, where melting starts, variants, restoring a snapshot, stability guards,
//! adaptive steps and located melting.

use crate::common;

use stickslip_core::drive::{Drive, free_spring_exact};
use stickslip_run::driver::{Control, Driver, Limit, NullSink};
use stickslip_run::{ResolvedScene, Scene, StopReason};

/// fig2 at `nodes` nodes with fixed steps of 20 ns, plus `extra` overrides.
fn small_fig2(scheme: &str, nodes: usize, extra: &[&str]) -> ResolvedScene {
    let mut sets = vec![
        format!("time.scheme={scheme}"),
        format!("contact.nodes={nodes}"),
        "time.dt=2e-8".to_string(),
        "time.stepping=fixed".to_string(),
    ];
    sets.extend(extra.iter().map(|s| (*s).to_string()));
    Scene::from_path(&common::scene("fig2"), &sets).unwrap()
}

/// A driver for `scene` advanced to time `t_s`.
fn run_until(scene: &ResolvedScene, t_s: f64) -> Driver {
    let mut driver = Driver::start(scene, &mut NullSink).unwrap();
    let stop = driver
        .advance(&mut NullSink, &mut Control::default(), Limit::Time(t_s))
        .unwrap();
    assert_eq!(stop, None, "stopped before {t_s:e} s");
    driver
}

#[test]
fn complete_melting_gives_zero_force_and_free_spring_motion() {
    // A ≤ 0 (docs/model.md#the-lubricant-film): the film melts completely, F = 0, and the stamp
    // follows the free spring X = V0 t − (V0/ω) sin ωt to Verlet's second-order accuracy.
    for scheme in ["literal", "accurate"] {
        let scene = small_fig2(scheme, 20, &["temperature.A0=-1e5"]);
        let Drive::Spring(spring) = scene.config.drive else {
            unreachable!()
        };
        let driver = run_until(&scene, 2e-4 - 1e-9);
        let sim = driver.simulation();
        let s = &sim.state().physical;
        assert!(
            s.phi.iter().all(|&p| p.is_finite() && p < 1e-3),
            "{scheme}: film not melted"
        );
        assert_eq!(s.force_n, 0.0, "{scheme}");
        let (x, _) = free_spring_exact(&spring, sim.time_s());
        assert!(
            (s.drive.x_m - x).abs() <= 1e-6 * x.abs() + 1e-15,
            "{scheme}: X = {} vs {x}",
            s.drive.x_m
        );
        assert_eq!(
            sim.events().len(),
            1,
            "{scheme}: one event, the initial melting"
        );
        let outcome = driver.outcome(StopReason::End, &Default::default());
        assert_eq!(outcome.summary.regime.name(), "sliding", "{scheme}");
    }
}

#[test]
fn accurate_forces_from_both_forms_of_eq16_agree() {
    let mut driver = run_until(&small_fig2("accurate", 60, &[]), 4e-4);
    let o = driver.observables();
    assert!(o.f_n > 1e-4, "force should have built up: {}", o.f_n);
    assert!(
        ((o.f_1d_n - o.f_n) / o.f_n).abs() < 1e-3,
        "F = {} vs F_1d = {}",
        o.f_n,
        o.f_1d_n
    );
}

#[test]
fn literal_sums_leave_the_two_force_integrals_percent_apart() {
    let mut driver = run_until(&small_fig2("literal", 60, &[]), 4e-4);
    let o = driver.observables();
    let gap = ((o.f_1d_n - o.f_n) / o.f_n).abs();
    assert!(gap > 1e-2, "gap {gap}");
}

#[test]
fn first_melting_accurate_at_edge_literal_at_axis() {
    // The literal back sum skips its singular term, which at r = 0 leaves an empty sum:
    // u3D(0) = 0, so the axis feels the full stamp displacement and melts first. Product
    // integration gives u3D(0) = u1D(0) and the edge, where the stress concentrates, melts first.
    let first = |scheme| {
        let scene = small_fig2(scheme, 40, &["time.max_events=1"]);
        let (outcome, _) = stickslip_run::run_in_memory(&scene, &mut Control::default()).unwrap();
        assert_eq!(outcome.stop, StopReason::MaxEvents, "{scheme}: no melting");
        outcome.events[0].r_first_m
    };
    let a0 = 2e-5;
    assert!(first("accurate") >= 0.95 * a0);
    assert_eq!(first("literal"), 0.0);
}

#[test]
fn homogeneous_and_rigid_variants_run() {
    for (model, substrate) in [
        ("homogeneous", "elastic"),
        ("homogeneous", "rigid"),
        ("radial", "rigid"),
    ] {
        for scheme in ["literal", "accurate"] {
            let scene = small_fig2(
                scheme,
                30,
                &[
                    &format!("contact.model={model}"),
                    &format!("contact.substrate={substrate}"),
                ],
            );
            let driver = run_until(&scene, 8e-4);
            let events = driver.simulation().events();
            assert!(!events.is_empty(), "{model} {substrate} {scheme}: no event");
            let f = events[0].f_peak_n;
            assert!(
                (1.0e-3..1.6e-3).contains(&f),
                "{model} {substrate} {scheme}: f_peak {f}"
            );
        }
    }
}

#[test]
fn restoring_a_snapshot_continues_bit_identically() {
    let scene = small_fig2("accurate", 30, &[]);
    let mut a = run_until(&scene, 1e-4);
    let snap = a.snapshot();
    let mut b = Driver::restore(
        &scene,
        snap.preflight.clone(),
        snap.sim.clone(),
        snap.driver.clone(),
    )
    .unwrap();
    let mut control = Control::default();
    for d in [&mut a, &mut b] {
        d.advance(&mut NullSink, &mut control, Limit::Steps(500))
            .unwrap();
    }
    assert_eq!(a.simulation().state(), b.simulation().state());
}

#[test]
fn literal_euler_overshoot_is_caught_even_under_a_floor() {
    // γ raised 10⁴×: Δt·2γAb/a = 6000 ≫ 2. The floor φ ≥ 1e-6 would clip the negative
    // overshoot into a "melted" film; the step must fail instead, naming φ.
    let scene = small_fig2("literal", 20, &["lubricant.gamma=1e5", "time.dt=1e-8"]);
    let (outcome, _) = stickslip_run::run_in_memory(&scene, &mut Control::default()).unwrap();
    assert_eq!(outcome.stop, StopReason::Failure);
    let err = outcome.failure.expect("explicit Euler must fail");
    assert_eq!(err.quantity, "phi");
    assert!(
        err.diagnosis.contains("explicit Euler"),
        "{}",
        err.diagnosis
    );
    // The accurate scheme at the same Δt stays bounded.
    let scene = small_fig2("accurate", 20, &["lubricant.gamma=1e5", "time.dt=1e-8"]);
    let driver = run_until(&scene, 2e-5);
    assert!(
        driver
            .simulation()
            .state()
            .physical
            .phi
            .iter()
            .all(|p| p.is_finite() && *p >= 0.0 && *p < 1.3)
    );
}

fn first_onset_adaptive(tol: f64) -> (f64, u64, u64) {
    let scene = Scene::from_path(
        &common::scene("fig2"),
        &[
            "contact.nodes=30",
            "time.end=6.5e-4",
            "output.profile_times=[6.5e-4]",
            &format!("time.tolerance={tol:e}"),
            "time.dt_max=1e-6",
            "time.dt_min=1e-14",
        ],
    )
    .unwrap();
    let (outcome, _) = stickslip_run::run_in_memory(&scene, &mut Control::default()).unwrap();
    (
        outcome.events[0].t_onset_s,
        outcome.counts.accepted_steps,
        outcome.counts.rejected_steps,
    )
}

#[test]
fn adaptive_steps_converge_to_the_fine_fixed_step_onset_with_far_fewer_steps() {
    let fine = run_until(
        &small_fig2(
            "accurate",
            30,
            &[
                "time.dt=2.5e-9",
                "time.end=6.5e-4",
                "output.profile_times=[6.5e-4]",
            ],
        ),
        6.5e-4 - 1e-12,
    );
    let reference = fine.simulation().events()[0].t_onset_s;
    let (loose, acc_loose, _) = first_onset_adaptive(1e-3);
    let (tight, acc_tight, rej_tight) = first_onset_adaptive(1e-5);
    let (e_loose, e_tight) = ((loose - reference).abs(), (tight - reference).abs());
    eprintln!(
        "onset error {e_loose:e} s at tol 1e-3 ({acc_loose} steps), {e_tight:e} s at 1e-5 \
         ({acc_tight} steps, {rej_tight} rejected)"
    );
    // The fixed reference took 260 000 steps; its own error is ~1e-9 s.
    assert!(e_tight < 5e-9, "tight tolerance: {e_tight:e} s");
    assert!(e_loose < 1e-7, "loose tolerance: {e_loose:e} s");
    assert!(acc_tight < 10_000 && acc_loose < acc_tight);
}

#[test]
fn melting_is_located_inside_the_step() {
    // With steps of 40 ns the onset still falls between step ends, not on them.
    let driver = run_until(&small_fig2("accurate", 30, &["time.dt=4e-8"]), 6.5e-4);
    let onset = driver.simulation().events()[0].t_onset_s;
    let steps = onset / 4e-8;
    assert!(
        (steps - steps.round()).abs() > 1e-6,
        "onset {onset:e} on a step end"
    );
    assert!(
        driver
            .simulation()
            .state()
            .events
            .last_melt_s
            .iter()
            .any(|&t| t > 0.0)
    );
}
