//! Drive integrators against exact answers (the spring models of `models::spring`): observed
//! orders of velocity Verlet and RK4 on the friction-free spring, of the split integrator under
//! a prescribed friction force (and its exactness without one), of the shipped default, the
//! loaded split, on the loaded spring; long-run energy behaviour, split Verlet, and the exact
//! rigid drive.

use stickslip_core::drive::{
    Drive, DriveState, Integrator, RigidDrive, SpringDrive, comoving_energy_j, free_spring_exact,
};

use crate::models::assert_order;
use crate::models::spring::fig2_drive as fig2;
use crate::models::spring::{Case, SpringMethod, SpringModel, damped_drive as damped, damped_free};

#[test]
fn verlet_is_second_order() {
    assert_order(&Case(SpringMethod::Verlet, SpringModel::free()), 2.0, 0.2);
}

#[test]
fn rk4_is_fourth_order() {
    assert_order(&Case(SpringMethod::Rk4, SpringModel::free()), 4.0, 0.3);
}

#[test]
fn split_is_exact_without_friction_and_second_order_with_it() {
    // F = 0: the spring's own flow, exact whatever the step (ωΔt up to 7).
    let free = SpringModel::free();
    for k in 0..=6 {
        let e = free.error(&SpringMethod::Split.run(&free, 1 << k));
        assert!(e <= 1e-12, "2^{k} steps: {e:e}");
    }
    assert_order(
        &Case(SpringMethod::Split, SpringModel::forced(0.0)),
        2.0,
        0.1,
    );
}

#[test]
fn the_loaded_split_is_second_order_and_exact_on_the_contact_alone() {
    for zeta in [0.0, 0.3] {
        let model = SpringModel::loaded(zeta);
        let k_c = model.contact_n_per_m;
        // The shipped default, its flow loaded with the contact's stiffness.
        assert_order(
            &Case(
                SpringMethod::LoadedSplit {
                    stiffness_n_per_m: k_c,
                },
                model,
            ),
            2.0,
            0.1,
        );
        // With a stiffness that is only an estimate of the contact's (the contact spring is
        // computed at t = 0; the film's stiffness changes), still second order.
        for k in [0.5 * k_c, 0.0] {
            assert_order(
                &Case(
                    SpringMethod::LoadedSplit {
                        stiffness_n_per_m: k,
                    },
                    model,
                ),
                2.0,
                0.1,
            );
        }
        // Without forcing, F is the contact alone, which the flow carries exactly: exact
        // whatever the step (ω'Δt up to 61).
        let contact = SpringModel {
            forcing_n: 0.0,
            ..model
        };
        for k in 0..=8 {
            let state = SpringMethod::LoadedSplit {
                stiffness_n_per_m: k_c,
            }
            .run(&contact, 1 << k);
            let e = contact.error(&state);
            assert!(e <= 1e-11, "zeta {zeta}, 2^{k} steps: {e:e}");
        }
    }
}

#[test]
fn split_verlet_equals_verlet_step_and_step() {
    let d = fig2();
    let (mut a, mut b, mut c) = (
        DriveState::at_rest(),
        DriveState::at_rest(),
        DriveState::at_rest(),
    );
    for i in 0..100 {
        let f0 = 1e-3 * f64::from(i);
        let f1 = 1e-3 * f64::from(i + 1);
        d.half_kick(&mut a, f0, 1e-4);
        d.drift(&mut a, 1e-4);
        d.half_kick(&mut a, f1, 1e-4);
        d.verlet_step(&mut b, 1e-4, f0, f1);
        d.step(Integrator::Verlet, &mut c, 1e-4, f0);
    }
    assert_eq!(a, b);
    assert_ne!(a, c);
    // A constant friction force F shifts the comoving equilibrium by −F/K: starting there at
    // V = V0 the stamp moves at exactly V0.
    let f = 0.2;
    for integrator in [Integrator::Verlet, Integrator::Rk4] {
        let mut s = DriveState {
            t_s: 0.0,
            x_m: -f / d.stiffness_n_per_m,
            v_m_per_s: 1.0,
        };
        for _ in 0..1000 {
            d.step(integrator, &mut s, 1e-4, f);
        }
        assert!((s.v_m_per_s - 1.0).abs() <= 1e-12, "{integrator:?} {s:?}");
        assert!(
            (s.x_m - (s.t_s - f / d.stiffness_n_per_m)).abs() <= 1e-12,
            "{integrator:?}"
        );
    }
}

/// Relative co-moving energy error, sampled once per period, over `periods` periods.
fn energy_history(integrator: Integrator, omega_dt: f64, periods: usize) -> Vec<f64> {
    // ω = 1 rad/s, V0 = 1 m/s: amplitude 1 m, E0 = ½·m·V0² = 0.5 J.
    let d = SpringDrive::new(1.0, 1.0, 1.0).unwrap();
    let steps_per_period = (std::f64::consts::TAU / omega_dt).round() as usize;
    let dt = std::f64::consts::TAU / steps_per_period as f64;
    let mut s = DriveState::at_rest();
    let e0 = comoving_energy_j(&d, &s);
    let mut out = Vec::with_capacity(periods);
    for _ in 0..periods {
        for _ in 0..steps_per_period {
            d.step(integrator, &mut s, dt, 0.0);
        }
        out.push((comoving_energy_j(&d, &s) - e0) / e0);
    }
    out
}

#[test]
fn verlet_energy_bounded_rk4_energy_drifts() {
    // 1e5 periods at ωΔt ≈ 0.15 (42 steps per period).
    let periods = 100_000;
    let tenth = periods / 10;
    let max_abs = |s: &[f64]| s.iter().fold(0.0f64, |m, e| m.max(e.abs()));

    let verlet = energy_history(Integrator::Verlet, 0.15, periods);
    let (first, last) = (
        max_abs(&verlet[..tenth]),
        max_abs(&verlet[periods - tenth..]),
    );
    eprintln!("Verlet: max |ΔE/E| first tenth {first:.3e}, last tenth {last:.3e}");
    assert!(last <= 1.5 * first, "{first} {last}");
    // Modified energy: the error oscillates with amplitude ≈ (ωΔt)²/4 ≈ 5.6e-3.
    assert!(last <= 0.3 * 0.15 * 0.15, "{last}");

    let rk4 = energy_history(Integrator::Rk4, 0.15, periods);
    eprintln!(
        "RK4: ΔE/E after 1 period {:.3e}, first tenth {:.3e}, end {:.3e}",
        rk4[0],
        rk4[tenth - 1],
        rk4[periods - 1]
    );
    // Monotone loss of energy: |R(iωΔt)| < 1 every step.
    assert!(rk4[0] < 0.0);
    assert!(rk4.windows(2).all(|w| w[1] < w[0]));
    // The loss keeps growing: ≈ 7.6× from the first tenth to the end (a loss 1 − (1 − δ)^n is
    // concave in n, so 10× is out of reach), ≈ 7e4× from the first period to the end.
    assert!(rk4[periods - 1].abs() >= 5.0 * rk4[tenth - 1].abs());
    assert!(rk4[periods - 1].abs() >= 1e4 * rk4[0].abs());
    // Verlet beats RK4 at the end of the run despite RK4's higher order.
    assert!(last < rk4[periods - 1].abs());
}

#[test]
fn free_spring_exact_is_consistent() {
    let d = fig2();
    let w = d.omega_rad_per_s();
    assert!((w - 5000f64.sqrt()).abs() <= 1e-13);
    // Small t: X ≈ V0·ω²t³/6 with full relative accuracy (no cancellation).
    for t in [1e-9, 1e-6, 1e-4] {
        let (x, v) = free_spring_exact(&d, t);
        let theta: f64 = w * t;
        let series = (theta.powi(3) / 6.0 - theta.powi(5) / 120.0 + theta.powi(7) / 5040.0) / w;
        assert!((x - series).abs() <= 1e-14 * series, "{t}: {x} {series}");
        let v_series = theta * theta / 2.0 * (1.0 - theta * theta / 12.0);
        assert!((v - v_series).abs() <= 1e-10 * v, "{t}: {v} {v_series}");
    }
    // Large t: the textbook formula.
    for t in [0.05, 1.0, 13.7] {
        let (x, v) = free_spring_exact(&d, t);
        assert!((x - (t - (w * t).sin() / w)).abs() <= 1e-14 * x.max(1.0));
        assert!((v - (1.0 - (w * t).cos())).abs() <= 1e-14);
        let e = comoving_energy_j(
            &d,
            &DriveState {
                t_s: t,
                x_m: x,
                v_m_per_s: v,
            },
        );
        assert!((e - 0.05).abs() <= 1e-12, "{e}");
    }
}

#[test]
fn rigid_drive_is_exact() {
    let r = RigidDrive::new(1e-3).unwrap();
    let drive = Drive::Rigid(r);
    let mut s = DriveState::at_rest();
    for n in 1..=1000 {
        drive.step(Integrator::Rk4, &mut s, 1e-8, 123.0);
        let t = f64::from(n) * 1e-8;
        assert!((s.t_s - t).abs() <= 1e-13 * t);
        assert_eq!(s.x_m, 1e-3 * s.t_s);
        assert_eq!(s.v_m_per_s, 1e-3);
    }
    assert_eq!(
        r.state_at(2.0),
        DriveState {
            t_s: 2.0,
            x_m: 2e-3,
            v_m_per_s: 1e-3
        }
    );
    assert_eq!(drive.velocity_m_per_s(), 1e-3);
}

#[test]
fn validation_names_field_value_and_range() {
    let e = SpringDrive::new(500.0, 0.0, 1.0).unwrap_err();
    assert_eq!((e.field, e.value), ("mass_kg", 0.0));
    assert!(e.to_string().contains("mass_kg") && e.to_string().contains("> 0"));
    assert_eq!(
        SpringDrive::new(-1.0, 0.1, 1.0).unwrap_err().field,
        "stiffness_n_per_m"
    );
    assert_eq!(
        SpringDrive::new(500.0, 0.1, f64::NAN).unwrap_err().field,
        "velocity_m_per_s"
    );
    assert_eq!(
        RigidDrive::new(f64::INFINITY).unwrap_err().field,
        "velocity_m_per_s"
    );
    assert!(Drive::Spring(fig2()).validate().is_ok());
}

/// Phase-space distance of the stamp's co-moving state (Y = X − V0·t, Ẏ/ω) from the exact
/// (y, ẏ), relative to the exact state's own size — a relative error that never divides by a
/// zero of Y or Ẏ alone.
fn relative_phase_error(d: &SpringDrive, s: &DriveState, (y, yv): (f64, f64)) -> f64 {
    let w = d.omega_rad_per_s();
    let v0 = d.velocity_m_per_s;
    let (ys, yvs) = (s.x_m - v0 * s.t_s, s.v_m_per_s - v0);
    (ys - y).hypot((yvs - yv) / w) / y.hypot(yv / w)
}

/// The co-moving frame itself: the drive with V0 = 0 started at X = 0, V = −V0 moves as the
/// co-moving coordinate Y of the drive from rest, without the rounding of X = V0·t + Y, which
/// limits a relative error of Y to about ε·V0·t/|Y| once Y has decayed.
fn comoving(d: &SpringDrive) -> (SpringDrive, DriveState) {
    let frame = SpringDrive {
        velocity_m_per_s: 0.0,
        ..*d
    };
    let start = DriveState {
        t_s: 0.0,
        x_m: 0.0,
        v_m_per_s: -d.velocity_m_per_s,
    };
    (frame, start)
}

#[test]
fn damped_free_oscillator_split_flow_is_exact_whatever_the_step() {
    // 20 undamped periods (ωT ≈ 126), from rest: Y = 0, Ẏ = −V0.
    let t_end = 20.0 * std::f64::consts::TAU / fig2().omega_rad_per_s();
    for zeta in [0.05, 0.5, 1.0, 2.0] {
        let d = damped(zeta);
        assert!((d.damping_ratio() - zeta).abs() <= 1e-15 * zeta);
        let w = d.omega_rad_per_s();
        let v0 = d.velocity_m_per_s;
        let (frame, start) = comoving(&d);
        let (mut worst_rel, mut worst_abs) = (0.0_f64, 0.0_f64);
        for k in [0u32, 1, 3, 6, 9, 12] {
            let n = 1u32 << k;
            let dt = t_end / f64::from(n);
            let (mut s, mut c) = (DriveState::at_rest(), start);
            for i in 1..=n {
                d.split_step(&mut s, dt, 0.0, 0.0);
                frame.split_step(&mut c, dt, 0.0, 0.0);
                // At the flow's own elapsed time i·Δt (t_s sums the steps, with rounding).
                let exact = damped_free(w, zeta, 0.0, -v0, f64::from(i) * dt);
                // In the co-moving frame: relative to the state's own size, at every step; the
                // bound is the flow's rounding, composed up to 4096 times.
                let rel = relative_phase_error(&frame, &c, exact);
                assert!(rel <= 1e-12, "zeta {zeta}, 2^{k} steps, step {i}: {rel:e}");
                // The stamp's X and V from rest: relative to the amplitude V0/ω, V0.
                let (y, yv) = (s.x_m - v0 * s.t_s, s.v_m_per_s - v0);
                let abs = ((y - exact.0) * w / v0).hypot((yv - exact.1) / v0);
                assert!(abs <= 1e-12, "zeta {zeta}, 2^{k} steps, step {i}: {abs:e}");
                worst_rel = worst_rel.max(rel);
                worst_abs = worst_abs.max(abs);
            }
            assert!((s.t_s - t_end).abs() <= 1e-12 * t_end);
        }
        eprintln!(
            "damped split flow, zeta = {zeta}: 20 periods in 1 … 4096 steps (omega*dt {:.3} … \
             {:.2e}): largest relative error of the co-moving state {worst_rel:.2e}, of the \
             stamp's (X, V) from rest over the amplitude {worst_abs:.2e}",
            w * t_end,
            w * t_end / 4096.0
        );
    }
}

#[test]
fn damped_flow_is_continuous_through_critical_damping() {
    // ζ = 1 ± δ against the critical solution: the flows differ by O(δ·(ωT)²) (sin x/x and
    // expm1 x/x keep their accuracy as ω_d, μ → 0; the textbook forms would lose it all).
    let t_end = 2.0 * std::f64::consts::TAU / fig2().omega_rad_per_s();
    for delta in [1e-15, 1e-12, 1e-9, 1e-6] {
        for zeta in [1.0 - delta, 1.0 + delta] {
            let d = damped(zeta);
            let (frame, start) = comoving(&d);
            let w = d.omega_rad_per_s();
            for k in [0u32, 4, 10] {
                let n = 1u32 << k;
                let mut c = start;
                let dt = t_end / f64::from(n);
                for _ in 0..n {
                    frame.split_step(&mut c, dt, 0.0, 0.0);
                }
                let exact = damped_free(w, 1.0, 0.0, -d.velocity_m_per_s, f64::from(n) * dt);
                let e = relative_phase_error(&frame, &c, exact);
                // |∂ln Ẏ/∂ζ| ≈ (ωT)² ≈ 158 at the end, plus rounding.
                assert!(
                    e <= 200.0 * delta + 1e-12,
                    "zeta = 1 + {:e}, 2^{k} steps: {e:e}",
                    zeta - 1.0
                );
            }
        }
    }
}

#[test]
fn damped_split_is_second_order_in_the_friction_force() {
    for zeta in [0.05, 0.5, 2.0] {
        // F = 0: exact (the flow alone), a few steps over 0.1 s.
        let free = SpringModel::damped(zeta);
        for k in 0..=4 {
            let e = free.error(&SpringMethod::Split.run(&free, 1 << k));
            assert!(e <= 1e-12, "zeta {zeta}, 2^{k} steps: {e:e}");
        }
        assert_order(
            &Case(SpringMethod::Split, SpringModel::forced(zeta)),
            2.0,
            0.1,
        );
    }
}

#[test]
fn damped_verlet_is_second_order_and_rk4_fourth() {
    assert_order(
        &Case(SpringMethod::Verlet, SpringModel::forced(0.5)),
        2.0,
        0.1,
    );
    // RK4 holds F over the step, so its order shows on the free damped spring.
    assert_order(&Case(SpringMethod::Rk4, SpringModel::damped(0.5)), 4.0, 0.3);
}

#[test]
fn damping_is_checked_and_zero_damping_is_the_undamped_spring() {
    let d = fig2();
    for bad in [-1e-300, -1.0, f64::NAN, f64::INFINITY] {
        let e = d.with_damping(bad).unwrap_err();
        assert_eq!(e.field, "damping_n_s_per_m");
        assert!(e.to_string().contains(">= 0"), "{e}");
    }
    // c_d = 0: the same arithmetic as without a dashpot, bit for bit, for every integrator.
    let zero = d.with_damping(0.0).unwrap();
    assert_eq!(zero, d);
    for integrator in [Integrator::Split, Integrator::Verlet, Integrator::Rk4] {
        let (mut a, mut b) = (DriveState::at_rest(), DriveState::at_rest());
        for i in 0..1000 {
            let f = 1e-3 * f64::from(i % 7);
            d.step(integrator, &mut a, 1e-4, f);
            zero.step(integrator, &mut b, 1e-4, f);
        }
        assert_eq!(a, b);
    }
    // The friction-free motion from rest: the flow's own, against the textbook.
    let half = damped(0.5);
    let (x, v) = free_spring_exact(&half, 0.05);
    let (y, yv) = damped_free(half.omega_rad_per_s(), 0.5, 0.0, -1.0, 0.05);
    assert!((x - (0.05 + y)).abs() <= 1e-15 && (v - (1.0 + yv)).abs() <= 1e-14);
}

/// RK4 with `n` steps of m·Ẍ = K·(V0·t − X) + c_d·(V0 − Ẋ) − c_v·Ẋ − k·X from `s` over `t`:
/// the reference for the loaded flow, independent of its closed form.
fn loaded_rk4(
    d: &SpringDrive,
    (k, c_v, p): (f64, f64, f64),
    s: DriveState,
    t: f64,
    n: u32,
) -> DriveState {
    let acc = |t: f64, x: f64, v: f64| {
        (d.stiffness_n_per_m * (d.velocity_m_per_s * t - x)
            + d.damping_n_s_per_m * (d.velocity_m_per_s - v)
            - c_v * v
            - k * x
            + p)
            / d.mass_kg
    };
    let h = t / f64::from(n);
    let (mut t, mut x, mut v) = (s.t_s, s.x_m, s.v_m_per_s);
    for _ in 0..n {
        let (k1x, k1v) = (v, acc(t, x, v));
        let (k2x, k2v) = (
            v + 0.5 * h * k1v,
            acc(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v),
        );
        let (k3x, k3v) = (
            v + 0.5 * h * k2v,
            acc(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v),
        );
        let (k4x, k4v) = (v + h * k3v, acc(t + h, x + h * k3x, v + h * k3v));
        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        t += h;
    }
    DriveState {
        t_s: t,
        x_m: x,
        v_m_per_s: v,
    }
}

#[test]
fn the_loaded_flow_solves_the_spring_with_the_contact_stiffness_and_drag_exactly() {
    // The SFA contact's numbers: K = 500 N/m, m = 0.1 kg, V0 = 1 µm/s, the contact as a spring
    // of 3.7e4 N/m (74 K); from a state off the rest point, over 3 periods of the loaded spring,
    // in one step and in 64.
    let base = SpringDrive::new(500.0, 0.1, 1e-6).unwrap();
    let start = DriveState {
        t_s: 0.25,
        x_m: 3e-9,
        v_m_per_s: 2e-8,
    };
    for zeta_d in [0.0, 0.3] {
        let d = base
            .with_damping(2.0 * zeta_d * (base.stiffness_n_per_m * base.mass_kg).sqrt())
            .unwrap();
        for (k, c_v, p) in [
            (3.7e4, 0.0, 0.0),
            (3.7e4, 20.0, 1e-4),
            (0.0, 5.0, 0.0),
            (3.7e4, 400.0, -2e-4),
        ] {
            let period = std::f64::consts::TAU / ((d.stiffness_n_per_m + k) / d.mass_kg).sqrt();
            let t = 3.0 * period;
            let reference = loaded_rk4(&d, (k, c_v, p), start, t, 1 << 16);
            let scale_x = reference.x_m.abs().max(1e-12);
            let scale_v = reference.v_m_per_s.abs().max(1e-12 / period);
            for steps in [1u32, 64] {
                let mut s = start;
                for _ in 0..steps {
                    d.loaded_flow(&mut s, t / f64::from(steps), k, c_v, p);
                }
                let ex = (s.x_m - reference.x_m).abs() / scale_x;
                let ev = (s.v_m_per_s - reference.v_m_per_s).abs() / scale_v;
                assert!(
                    ex <= 1e-9 && ev <= 1e-9,
                    "zeta_d {zeta_d}, k {k}, c_v {c_v}, p {p}, {steps} steps: X {:e} vs {:e} ({ex:e}), \
                     V {:e} vs {:e} ({ev:e})",
                    s.x_m,
                    reference.x_m,
                    s.v_m_per_s,
                    reference.v_m_per_s
                );
            }
        }
    }
}

#[test]
fn the_loaded_flow_without_load_is_the_springs_own_flow() {
    let base = SpringDrive::new(500.0, 0.1, 1e-6).unwrap();
    let start = DriveState {
        t_s: 0.25,
        x_m: 3e-9,
        v_m_per_s: 2e-8,
    };
    for zeta_d in [0.0, 0.3, 2.0] {
        let d = base
            .with_damping(2.0 * zeta_d * (base.stiffness_n_per_m * base.mass_kg).sqrt())
            .unwrap();
        for h in [1e-6, 1e-3, 0.05] {
            let (mut a, mut b) = (start, start);
            d.loaded_flow(&mut a, h, 0.0, 0.0, 0.0);
            d.spring_flow(&mut b, h);
            assert_eq!(a.t_s, b.t_s);
            assert!(
                (a.x_m - b.x_m).abs() <= 1e-14 * b.x_m.abs()
                    && (a.v_m_per_s - b.v_m_per_s).abs() <= 1e-13 * b.v_m_per_s.abs().max(1e-9),
                "zeta_d {zeta_d}, h {h}: {a:?} vs {b:?}"
            );
            let (mut a, mut b) = (start, start);
            d.loaded_flow(&mut a, h, 0.0, 7.0, 0.0);
            d.spring_flow_with_drag(&mut b, h, 7.0);
            assert!(
                (a.x_m - b.x_m).abs() <= 1e-12 * b.x_m.abs()
                    && (a.v_m_per_s - b.v_m_per_s).abs() <= 1e-10 * b.v_m_per_s.abs().max(1e-9),
                "drag, zeta_d {zeta_d}, h {h}: {a:?} vs {b:?}"
            );
        }
    }
}
