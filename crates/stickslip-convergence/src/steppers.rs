//! Time-stepper convergence against closed forms: the Landau φ-steppers against
//! [`exact_phi`] with the strain frozen, and the drive integrators against the friction-free
//! spring [`free_spring_exact`].

use crate::study::{Refined, Study};
use stickslip_core::drive::{DriveState, Integrator, SpringDrive, free_spring_exact};
use stickslip_core::landau::{LandauParams, PhiStepper, exact_phi};

/// The paper's lubricant (fig2): τmax = 1e6 Pa, εmax = 1, a = 1e6 Pa, γ = 10 /(Pa·s).
pub fn fig2_lubricant() -> LandauParams {
    LandauParams::new(1e6, 1.0, 1e6, 10.0).expect("valid fig2 lubricant")
}

/// The paper's spring (fig2): K = 500 N/m, m = 0.1 kg, V0 = 1 m/s.
pub fn fig2_spring() -> SpringDrive {
    SpringDrive::new(500.0, 0.1, 1.0).expect("valid fig2 spring")
}

/// A frozen-strain Landau problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LandauCase {
    /// Name in tables.
    pub name: &'static str,
    /// Initial φ.
    pub phi0: f64,
    /// Frozen strain ε.
    pub eps: f64,
    /// Length of the interval, s.
    pub t_end_s: f64,
}

/// The three cases: melting from the solid equilibrium (ε = 2 > εc = √3), growth at ε = 1
/// from φ = 0.1, and re-solidification from the floor φ = 1e-6 at ε = 0 (what every melted
/// node of fig2 does).
pub const LANDAU_CASES: [LandauCase; 3] = [
    LandauCase {
        name: "melting (phi0 = sqrt(1.5), eps = 2)",
        phi0: 1.224_744_871_391_589,
        eps: 2.0,
        t_end_s: 3.2e-7,
    },
    LandauCase {
        name: "growth (phi0 = 0.1, eps = 1)",
        phi0: 0.1,
        eps: 1.0,
        t_end_s: 3.2e-7,
    },
    LandauCase {
        name: "re-solidification (phi0 = 1e-6, eps = 0)",
        phi0: 1e-6,
        eps: 0.0,
        t_end_s: 6.4e-7,
    },
];

/// The default Δt levels of the Landau study, s (the simulation's range and below).
pub const LANDAU_DT_S: [f64; 7] = [4e-8, 2e-8, 1e-8, 5e-9, 2.5e-9, 1.25e-9, 6.25e-10];

/// Name of a φ-stepper in tables.
pub fn stepper_name(s: PhiStepper) -> &'static str {
    match s {
        PhiStepper::ExplicitEuler => "explicit_euler",
        PhiStepper::Exact => "exact",
        PhiStepper::ImplicitEuler => "implicit_euler",
    }
}

/// max over steps of |φ_n − φ(t_n)| / φ_scale, φ_scale = max(φ0, φ(T)), for `stepper` with Δt.
/// Non-finite (blown up) trajectories give +∞.
pub fn landau_error(stepper: PhiStepper, case: &LandauCase, dt_s: f64) -> f64 {
    let p = fig2_lubricant();
    let a_coeff = p.a_coeff_default_pa();
    let n = (case.t_end_s / dt_s).round() as u64;
    let scale = case
        .phi0
        .max(exact_phi(case.phi0, case.eps, a_coeff, &p, case.t_end_s));
    let mut phi = case.phi0;
    let mut worst = 0.0_f64;
    for k in 1..=n {
        phi = stepper.step(phi, case.eps, a_coeff, &p, dt_s);
        let exact = exact_phi(case.phi0, case.eps, a_coeff, &p, k as f64 * dt_s);
        let e = (phi - exact).abs() / scale;
        if !e.is_finite() {
            return f64::INFINITY;
        }
        worst = worst.max(e);
    }
    worst
}

/// Phase-space error of the friction-free spring after `t_end_s` with Δt = `dt_s`:
/// hypot((X − X_exact)/(V0/ω), (V − V_exact)/V0).
pub fn drive_error(integrator: Integrator, t_end_s: f64, dt_s: f64) -> f64 {
    let d = fig2_spring();
    let n = (t_end_s / dt_s).round() as u64;
    let mut s = DriveState::at_rest();
    for _ in 0..n {
        d.step(integrator, &mut s, dt_s, 0.0);
    }
    let (x, v) = free_spring_exact(&d, s.t_s);
    let v0 = d.velocity_m_per_s;
    ((s.x_m - x) / (v0 / d.omega_rad_per_s())).hypot((s.v_m_per_s - v) / v0)
}

/// Relative error of X of the free spring after `end_s` with steps of `dt_s` (fig2's horizon
/// and the paper's step: how much the drive integrator contributes to fig2's error).
pub fn drive_error_at(integrator: Integrator, end_s: f64, dt_s: f64) -> f64 {
    let d = fig2_spring();
    let n = (end_s / dt_s).round() as u64;
    let mut s = DriveState::at_rest();
    for _ in 0..n {
        d.step(integrator, &mut s, dt_s, 0.0);
    }
    let (x, _) = free_spring_exact(&d, s.t_s);
    ((s.x_m - x) / x).abs()
}

/// ωT of the friction-free spring over `t_s`.
pub fn omega_t(t_s: f64) -> f64 {
    fig2_spring().omega_rad_per_s() * t_s
}

/// Relaxation time 1/(2γ|c|) of a frozen-strain Landau case, s (c the Bernoulli coefficient
/// a·ε² − A·b/a of [`LandauParams::bernoulli_c_pa`]).
pub fn relaxation_time_s(case: &LandauCase) -> f64 {
    let p = fig2_lubricant();
    let c = p.bernoulli_c_pa(case.eps, p.a_coeff_default_pa());
    1.0 / (2.0 * p.gamma_per_pa_s * c.abs())
}

/// Horizon of the drive study: ωT ≈ 7 (a little more than one period), s.
pub const DRIVE_T_END_S: f64 = 0.1;

/// Default Δt levels of the drive study, s: T/2^k, k = 5 … 12.
pub fn drive_dts(ks: std::ops::RangeInclusive<u32>) -> Vec<f64> {
    ks.map(|k| DRIVE_T_END_S / f64::from(1u32 << k)).collect()
}

/// Theoretical order of a φ-stepper.
pub fn landau_theory(s: PhiStepper) -> (Option<f64>, &'static str) {
    match s {
        PhiStepper::ExplicitEuler | PhiStepper::ImplicitEuler => (Some(1.0), "1"),
        PhiStepper::Exact => (None, "exact"),
    }
}

/// The Landau stepper studies for Δt levels `dts` (coarse to fine).
pub fn landau_study(dts: &[f64]) -> Vec<Study> {
    let mut out = Vec::new();
    for case in LANDAU_CASES {
        for stepper in [
            PhiStepper::ExplicitEuler,
            PhiStepper::ImplicitEuler,
            PhiStepper::Exact,
        ] {
            let errors: Vec<f64> = dts
                .iter()
                .map(|&dt| landau_error(stepper, &case, dt))
                .collect();
            let mut s = Study::exact(
                "stepper",
                "phi",
                stepper_name(stepper),
                Refined::Dt,
                dts.to_vec(),
                &format!("case = {}, T = {:e} s", case.name, case.t_end_s),
                "relative (max over steps / max(phi0, phi(T)))",
                errors.clone(),
                landau_theory(stepper),
            );
            let unstable: Vec<String> = dts
                .iter()
                .zip(&errors)
                .filter(|(_, e)| !e.is_finite() || **e > 1.0)
                .map(|(dt, _)| format!("{dt:e}"))
                .collect();
            if !unstable.is_empty() {
                s = s.with_note(&format!(
                    "unstable or O(1) error at dt = {}",
                    unstable.join(", ")
                ));
            }
            out.push(s);
        }
    }
    out
}

/// The drive integrator studies for Δt levels `dts` over [`DRIVE_T_END_S`].
pub fn drive_study(dts: &[f64]) -> Vec<Study> {
    [
        (Integrator::Verlet, "verlet", 2.0),
        (Integrator::Rk4, "rk4", 4.0),
    ]
    .into_iter()
    .map(|(integrator, name, p)| {
        let errors = dts
            .iter()
            .map(|&dt| drive_error(integrator, DRIVE_T_END_S, dt))
            .collect();
        Study::exact(
            "stepper",
            "spring_phase_space",
            name,
            Refined::Dt,
            dts.to_vec(),
            &format!(
                "free spring from rest, T = {DRIVE_T_END_S} s (omega T = {:.2})",
                omega_t(DRIVE_T_END_S)
            ),
            "relative (phase space, by V0/omega and V0)",
            errors,
            (Some(p), if p == 2.0 { "2" } else { "4" }),
        )
    })
    .collect()
}
