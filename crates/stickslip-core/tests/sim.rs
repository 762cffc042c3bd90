//! The time loop on small scenes: complete melting, free spring, force consistency, resume.

use stickslip_core::config::{ContactModel, Scheme, SimConfig, Substrate};
use stickslip_core::drive::{Drive, free_spring_exact};
use stickslip_core::landau::Temperature;
use stickslip_core::sim::Simulation;

fn small_fig2(scheme: Scheme, nodes: usize) -> SimConfig {
    let mut c = SimConfig::fig2(scheme);
    c.contact.nodes = nodes;
    c.time.dt_s = 2e-8;
    c
}

fn run_until(sim: &mut Simulation, end_s: f64, dt_s: f64) {
    while sim.time_s() < end_s - 0.5 * dt_s {
        sim.step(dt_s).expect("step");
    }
}

#[test]
fn complete_melting_gives_zero_force_and_free_spring_motion() {
    // A ≤ 0 (SPEC §1): the film melts completely, F = 0, and the stamp follows the free
    // spring X = V0 t − (V0/ω) sin ωt to Verlet's second-order accuracy.
    for scheme in [Scheme::Literal, Scheme::Accurate] {
        let mut c = small_fig2(scheme, 20);
        c.temperature = Temperature::Constant { a_coeff_pa: -1e5 };
        c.time.end_s = 2e-4;
        let dt = c.time.dt_s;
        let Drive::Spring(spring) = c.drive else {
            unreachable!()
        };
        let mut sim = Simulation::new(c, 1e-5).unwrap();
        run_until(&mut sim, 2e-4, dt);
        let s = sim.state();
        assert!(
            s.phi.iter().all(|&p| p.is_finite() && p < 1e-3),
            "{scheme:?}: film not melted"
        );
        assert_eq!(s.force_n, 0.0, "{scheme:?}");
        let (x, _) = free_spring_exact(&spring, sim.time_s());
        assert!(
            (s.drive.x_m - x).abs() <= 1e-6 * x.abs() + 1e-15,
            "{scheme:?}: X = {} vs {x}",
            s.drive.x_m
        );
        assert_eq!(
            sim.events().len(),
            1,
            "{scheme:?}: one event, the initial melting"
        );
    }
}

#[test]
fn accurate_forces_from_both_forms_of_eq16_agree() {
    let mut sim = Simulation::new(small_fig2(Scheme::Accurate, 60), 1e-5).unwrap();
    run_until(&mut sim, 4e-4, 2e-8);
    let o = sim.observables();
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
    let mut sim = Simulation::new(small_fig2(Scheme::Literal, 60), 1e-5).unwrap();
    run_until(&mut sim, 4e-4, 2e-8);
    let o = sim.observables();
    let gap = ((o.f_1d_n - o.f_n) / o.f_n).abs();
    assert!(gap > 1e-2, "gap {gap}");
}

#[test]
fn first_melting_accurate_at_edge_literal_at_axis() {
    // The literal back sum skips its singular term, which at r = 0 leaves an empty sum:
    // u3D(0) = 0, so the axis feels the full stamp displacement and melts first. Product
    // integration gives u3D(0) = u1D(0) and the edge, where the stress concentrates, melts first.
    let first = |scheme| {
        let mut sim = Simulation::new(small_fig2(scheme, 40), 1e-5).unwrap();
        while sim.events().is_empty() {
            sim.step(2e-8).unwrap();
            assert!(sim.time_s() < 1e-3, "no melting before 1 ms");
        }
        sim.events()[0].r_first_m
    };
    let a0 = 2e-5;
    assert!(first(Scheme::Accurate) >= 0.95 * a0);
    assert_eq!(first(Scheme::Literal), 0.0);
}

#[test]
fn homogeneous_and_rigid_variants_run() {
    for (model, substrate) in [
        (ContactModel::Homogeneous, Substrate::Elastic),
        (ContactModel::Homogeneous, Substrate::Rigid),
        (ContactModel::Radial, Substrate::Rigid),
    ] {
        for scheme in [Scheme::Literal, Scheme::Accurate] {
            let mut c = small_fig2(scheme, 30);
            c.contact.model = model;
            c.contact.substrate = substrate;
            let mut sim = Simulation::new(c, 1e-5).unwrap();
            run_until(&mut sim, 8e-4, 2e-8);
            assert!(
                !sim.events().is_empty(),
                "{model:?} {substrate:?} {scheme:?}: no event"
            );
            let f = sim.events()[0].f_peak_n;
            assert!(
                (1.0e-3..1.6e-3).contains(&f),
                "{model:?} {substrate:?} {scheme:?}: f_peak {f}"
            );
        }
    }
}

#[test]
fn restoring_a_state_continues_bit_identically() {
    let c = small_fig2(Scheme::Accurate, 30);
    let mut a = Simulation::new(c.clone(), 1e-5).unwrap();
    run_until(&mut a, 1e-4, 2e-8);
    let saved = a.state().clone();
    for _ in 0..500 {
        a.step(2e-8).unwrap();
    }
    let mut b = Simulation::new(c, 1e-5).unwrap();
    b.restore(saved).unwrap();
    for _ in 0..500 {
        b.step(2e-8).unwrap();
    }
    assert_eq!(a.state(), b.state());
}

#[test]
fn lagged_sweep_contraction_scales_with_substrate_softness() {
    // ρ ∝ 1/G*: fig2 (G* = 1e9 Pa) contracts, a ten times softer substrate does not (SPEC §2).
    let rho = |g: f64, scheme| {
        let mut c = small_fig2(scheme, 200);
        c.contact.g_eff_pa = g;
        Simulation::new(c, 1e-5).unwrap().lagged_sweep_contraction()
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
    assert_eq!(
        Simulation::new(c, 1e-5).unwrap().lagged_sweep_contraction(),
        0.0
    );
}

#[test]
fn literal_euler_overshoot_is_caught_even_under_a_floor() {
    // γ raised 10⁴×: Δt·2γAb/a = 6000 ≫ 2. The floor φ ≥ 1e-6 would clip the negative
    // overshoot into a "melted" film; the step must fail instead, naming φ.
    let mut c = small_fig2(Scheme::Literal, 20);
    c.lubricant.gamma_per_pa_s = 1e5;
    c.time.dt_s = 1e-8;
    let mut sim = Simulation::new(c, 1e-5).unwrap();
    let err = (0..1000)
        .find_map(|_| sim.step(1e-8).err())
        .expect("explicit Euler must fail");
    assert_eq!(err.quantity, "phi");
    assert!(
        err.diagnosis.contains("explicit Euler"),
        "{}",
        err.diagnosis
    );
    // The accurate scheme at the same Δt stays bounded.
    let mut c = small_fig2(Scheme::Accurate, 20);
    c.lubricant.gamma_per_pa_s = 1e5;
    let mut sim = Simulation::new(c, 1e-5).unwrap();
    run_until(&mut sim, 2e-5, 1e-8);
    assert!(
        sim.state()
            .phi
            .iter()
            .all(|p| p.is_finite() && *p >= 0.0 && *p < 1.3)
    );
}

fn first_onset_adaptive(tol: f64) -> (f64, u64, u64) {
    let mut c = small_fig2(Scheme::Accurate, 30);
    c.time.end_s = 6.5e-4;
    c.time.adaptive = Some(stickslip_core::config::AdaptiveConfig {
        tolerance: tol,
        dt_max_s: 1e-6,
        dt_min_s: 1e-14,
    });
    let mut sim = Simulation::new(c, 1e-5).unwrap();
    while sim.time_s() < 6.5e-4 {
        sim.step_adaptive(6.5e-4).unwrap();
    }
    let st = sim.state();
    (
        sim.events()[0].t_onset_s,
        st.accepted_steps,
        st.rejected_steps,
    )
}

#[test]
fn adaptive_steps_converge_to_the_fine_fixed_step_onset_with_far_fewer_steps() {
    let mut fine = Simulation::new(small_fig2(Scheme::Accurate, 30), 1e-5).unwrap();
    run_until(&mut fine, 6.5e-4, 2.5e-9);
    let reference = fine.events()[0].t_onset_s;
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
    let mut sim = Simulation::new(small_fig2(Scheme::Accurate, 30), 1e-5).unwrap();
    run_until(&mut sim, 6.5e-4, 4e-8);
    let onset = sim.events()[0].t_onset_s;
    let steps = onset / 4e-8;
    assert!(
        (steps - steps.round()).abs() > 1e-6,
        "onset {onset:e} on a step end"
    );
    assert!(sim.state().last_melt_s.iter().any(|&t| t > 0.0));
}
