//! Drive integrators against exact answers: observed orders of velocity Verlet and RK4 on the
//! friction-free spring, of the split integrator under a prescribed friction force (and its
//! exactness without one), long-run energy behaviour, split Verlet, and the exact rigid drive.

use stickslip_core::drive::{
    Drive, DriveState, Integrator, RigidDrive, SpringDrive, comoving_energy_j, free_spring_exact,
};

/// The paper's spring (fig2): K = 500 N/m, m = 0.1 kg, V0 = 1 m/s, ω ≈ 70.7 rad/s.
fn fig2() -> SpringDrive {
    SpringDrive::new(500.0, 0.1, 1.0).unwrap()
}

/// Phase-space error at `t_end` after 2^k steps, normalised by the oscillation amplitude
/// (V0/ω for X, V0 for V).
fn phase_error(drive: &SpringDrive, integrator: Integrator, t_end_s: f64, k: u32) -> f64 {
    let n = 1u32 << k;
    let dt = t_end_s / f64::from(n);
    let mut state = DriveState::at_rest();
    for _ in 0..n {
        drive.step(integrator, &mut state, dt, 0.0);
    }
    let (x, v) = free_spring_exact(drive, t_end_s);
    let v0 = drive.velocity_m_per_s;
    let ex = (state.x_m - x) / (v0 / drive.omega_rad_per_s());
    let ev = (state.v_m_per_s - v) / v0;
    assert!((state.t_s - t_end_s).abs() <= 1e-12 * t_end_s);
    ex.hypot(ev)
}

fn orders(
    drive: &SpringDrive,
    integrator: Integrator,
    ks: std::ops::RangeInclusive<u32>,
) -> Vec<f64> {
    // ωT ≈ 7.07: a little more than one period.
    let t_end = 0.1;
    let errors: Vec<f64> = ks
        .clone()
        .map(|k| phase_error(drive, integrator, t_end, k))
        .collect();
    let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    eprintln!(
        "{integrator:?}, T = {t_end} s, ω = {:.3} rad/s",
        drive.omega_rad_per_s()
    );
    for (i, k) in ks.enumerate() {
        let p = if i > 0 {
            format!("{:.4}", orders[i - 1])
        } else {
            "-".into()
        };
        eprintln!(
            "  dt = T/2^{k:<2} ωΔt = {:.4}  err = {:.3e}  p = {p}",
            drive.omega_rad_per_s() * t_end / f64::from(1u32 << k),
            errors[i]
        );
    }
    orders
}

#[test]
fn verlet_is_second_order() {
    let o = orders(&fig2(), Integrator::Verlet, 5..=11);
    for &p in &o[o.len() - 4..] {
        assert!((1.8..=2.2).contains(&p), "{o:?}");
    }
}

#[test]
fn rk4_is_fourth_order() {
    let o = orders(&fig2(), Integrator::Rk4, 4..=9);
    for &p in &o[o.len() - 3..] {
        assert!((3.7..=4.3).contains(&p), "{o:?}");
    }
}

/// The split integrator under a prescribed friction force F(t) = F0·sin(Ωt), whose motion is
/// known in closed form: with Y = X − V0·t, m·Ÿ = −K·Y − F(t), from rest (Y = 0, Ẏ = −V0),
/// Y = B·sin ωt + Yp with Yp = −F0·sin(Ωt)/(m·(ω² − Ω²)) and B·ω = −V0 − Ẏp(0). Phase-space
/// error at `t_end_s` after 2^k split steps with F at each step's start and end, normalised as
/// in [`phase_error`].
fn split_forced_error(drive: &SpringDrive, f0_n: f64, t_end_s: f64, k: u32) -> f64 {
    let omega_f = 30.0;
    let force = |t: f64| f0_n * (omega_f * t).sin();
    let n = 1u32 << k;
    let dt = t_end_s / f64::from(n);
    let mut state = DriveState::at_rest();
    for i in 0..n {
        let t0 = f64::from(i) * dt;
        drive.split_step(&mut state, dt, force(t0), force(t0 + dt));
    }
    let (m, w, v0) = (
        drive.mass_kg,
        drive.omega_rad_per_s(),
        drive.velocity_m_per_s,
    );
    let c = -f0_n / (m * (w * w - omega_f * omega_f));
    let b = (-v0 - c * omega_f) / w;
    let y = b * (w * t_end_s).sin() + c * (omega_f * t_end_s).sin();
    let yv = b * w * (w * t_end_s).cos() + c * omega_f * (omega_f * t_end_s).cos();
    let (x, v) = (y + v0 * t_end_s, yv + v0);
    let ex = (state.x_m - x) / (v0 / w);
    let ev = (state.v_m_per_s - v) / v0;
    assert!((state.t_s - t_end_s).abs() <= 1e-12 * t_end_s);
    ex.hypot(ev)
}

#[test]
fn split_is_exact_without_friction_and_second_order_with_it() {
    let d = fig2();
    // F = 0: the spring's own flow, exact whatever the step (ωΔt up to 7).
    for k in 0..=6 {
        let e = split_forced_error(&d, 0.0, 0.1, k);
        assert!(e <= 1e-12, "2^{k} steps: {e:e}");
    }
    // F0 = 3 N, about half the spring's force amplitude K·V0/ω ≈ 7 N.
    let errors: Vec<f64> = (5..=11)
        .map(|k| split_forced_error(&d, 3.0, 0.1, k))
        .collect();
    let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    let shown: Vec<String> = errors.iter().map(|e| format!("{e:.3e}")).collect();
    eprintln!("split under F0·sin(Ωt): errors {shown:?}, observed orders {orders:.4?}");
    for &p in &orders[orders.len() - 4..] {
        assert!((1.9..=2.1).contains(&p), "{orders:?}");
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
