//! Landau kinetics against exact answers: derived parameters, the closed-form frozen-strain
//! solution, observed orders of the three φ steppers, stiff and degenerate cases.

use stickslip_core::landau::{
    LandauParams, PhiStepper, Temperature, critical_strain, equilibrium_phi, exact_phi, rhs, stress,
};

use crate::models::landau::{Case, FrozenStrain, fig2_film as fig2};
use crate::models::{Convergent, assert_order};

fn rel_err(x: f64, reference: f64) -> f64 {
    (x - reference).abs() / reference.abs()
}

#[test]
fn derived_parameters_match_the_paper() {
    let p = fig2();
    assert_eq!(p.b_pa(), 2e6);
    assert_eq!(p.a_coeff_default_pa(), 1.5e6);
    let a_coeff = p.a_coeff_default_pa();
    assert!(rel_err(p.critical_strain(a_coeff), 3f64.sqrt()) <= 2e-16);
    assert!(rel_err(p.equilibrium_phi(0.0, a_coeff), 1.5f64.sqrt()) <= 2e-16);
    // φ0 vanishes at and beyond εc, and the stationary stress peaks at εmax with τmax
    // (Eq. 5, 6: τ = aε(A/a − aε²/b) is maximal at ε = εc/√3 = εmax).
    assert_eq!(p.equilibrium_phi(2.0, a_coeff), 0.0);
    let phi = p.equilibrium_phi(1.0, a_coeff);
    assert!(rel_err(stress(phi, 1.0, p.a_pa), p.tau_max_pa) <= 1e-15);
    // Equilibria are fixed points of Eq. 8.
    assert!(rhs(phi, 1.0, a_coeff, &p).abs() <= 1e-9);
}

#[test]
fn validation_names_field_value_and_range() {
    let err = LandauParams::new(1e6, 1.0, -2.0, 10.0).unwrap_err();
    assert_eq!(err.field, "a_pa");
    assert_eq!(err.value, -2.0);
    let msg = err.to_string();
    assert!(
        msg.contains("a_pa") && msg.contains("-2") && msg.contains("> 0"),
        "{msg}"
    );
    let err = LandauParams::new(1e6, 1.0, 1e6, f64::NAN).unwrap_err();
    assert_eq!(err.field, "gamma_per_pa_s");
    assert_eq!(
        LandauParams::new(0.0, 1.0, 1e6, 10.0).unwrap_err().field,
        "tau_max_pa"
    );
    assert_eq!(
        LandauParams::new(1e6, f64::INFINITY, 1e6, 10.0)
            .unwrap_err()
            .field,
        "eps_max"
    );
    let bad = Temperature::Relaxation {
        a0_pa: 1.5e6,
        t_relax_s: 0.0,
    };
    assert_eq!(bad.validate().unwrap_err().field, "t_relax_s");
}

#[test]
fn temperature_laws() {
    let c = Temperature::Constant { a_coeff_pa: 1.5e6 };
    assert_eq!(c.a_coeff_pa(0.0), 1.5e6);
    assert_eq!(c.a_coeff_pa(1.0), 1.5e6);
    let r = Temperature::Relaxation {
        a0_pa: 1.5e6,
        t_relax_s: 1e-3,
    };
    assert_eq!(r.a_coeff_pa(0.0), 1.5e6);
    assert!(rel_err(r.a_coeff_pa(1e-3), 1.5e6 / std::f64::consts::E) <= 1e-15);
    assert!(rel_err(r.a_coeff_pa(2.5e-3), 1.5e6 * (-2.5f64).exp()) <= 1e-15);
}

#[test]
fn a_non_positive_gives_zero_without_nan() {
    let p = fig2();
    for a_coeff in [0.0, -1.0, -1.5e6] {
        assert_eq!(critical_strain(a_coeff, p.a_pa, p.b_pa()), 0.0);
        for eps in [0.0, 0.5, 3.0] {
            assert_eq!(equilibrium_phi(eps, a_coeff, p.a_pa, p.b_pa()), 0.0);
        }
        // The film melts: φ decays to 0 monotonically, never NaN, for every stepper.
        for stepper in [PhiStepper::Exact, PhiStepper::ImplicitEuler] {
            let mut phi = 1.0f64;
            for _ in 0..200 {
                let next = stepper.step(phi, 0.0, a_coeff, &p, 1e-6);
                assert!(
                    next.is_finite() && next >= 0.0 && next <= phi,
                    "{stepper:?}"
                );
                phi = next;
            }
            assert!(phi < 0.05, "{stepper:?} {a_coeff}: {phi}");
        }
        let phi = exact_phi(1.0, 0.0, a_coeff, &p, 1e3);
        assert!(phi.is_finite() && phi < 1e-3, "{phi}");
    }
}

/// Melting (ε = 2 > εc, c = 1e6 Pa) from the solid equilibrium, and growth (ε = 1 < εc,
/// c = −2e6 Pa) from φ = 0.1: both over ≈ 4 relaxation times 1/(2γ|c|).
const CASES: [(f64, f64, f64); 2] = [(1.224_744_871_391_589, 2.0, 2e-7), (0.1, 1.0, 1e-7)];

#[test]
fn first_order_steppers_converge_at_order_one() {
    let p = fig2();
    for stepper in [PhiStepper::ExplicitEuler, PhiStepper::ImplicitEuler] {
        for (phi0, eps, t_end) in CASES {
            let model = FrozenStrain {
                params: p,
                phi0,
                eps,
                t_end_s: t_end,
            };
            let errors = assert_order(&Case(stepper, model, 5..=12), 1.0, 0.05);
            assert!(errors.iter().all(|e| e.is_finite()));
            assert!(errors[errors.len() - 1] < 2e-3, "{stepper:?}: {errors:?}");
        }
    }
}

#[test]
fn exact_stepper_is_exact_for_every_step() {
    let p = fig2();
    for (phi0, eps, t_end) in CASES {
        let case = Case(
            PhiStepper::Exact,
            FrozenStrain {
                params: p,
                phi0,
                eps,
                t_end_s: t_end,
            },
            0..=12,
        );
        for k in 0..=12 {
            let e = case.error(k);
            assert!(e <= 1e-13, "2^{k} steps: {e}");
        }
    }
}

#[test]
fn stiff_step_explicit_euler_blows_up_exact_does_not() {
    let p = fig2();
    let a_coeff = p.a_coeff_default_pa();
    // |∂rhs/∂φ| at φ0 = √(A/a), ε = 0 is 2γ·A·b/a = 6e7 /s; Δt = 1e-6 s gives 60 ≫ 2.
    let stiffness = 2.0 * p.gamma_per_pa_s * a_coeff * p.b_pa() / p.a_pa;
    let dt = 1e-6;
    assert!(dt * stiffness > 50.0);
    let phi_eq = p.equilibrium_phi(0.0, a_coeff);
    let phi0 = 0.99 * phi_eq;

    let mut phi = phi0;
    let mut blew_up = false;
    for _ in 0..100 {
        phi = PhiStepper::ExplicitEuler.step(phi, 0.0, a_coeff, &p, dt);
        // Non-finite, negative or huge: `contains` is false for NaN and ±∞.
        if !(0.0..=1e3).contains(&phi) {
            blew_up = true;
            break;
        }
    }
    assert!(blew_up, "explicit Euler stayed bounded: {phi}");

    let mut phi = phi0;
    for n in 1..=100 {
        phi = PhiStepper::Exact.step(phi, 0.0, a_coeff, &p, dt);
        let reference = exact_phi(phi0, 0.0, a_coeff, &p, f64::from(n) * dt);
        assert!(rel_err(phi, reference) <= 1e-14);
        assert!(rel_err(phi, phi_eq) <= 1e-14);
    }
    // Implicit Euler is stable as well and lands on the equilibrium.
    let phi = PhiStepper::ImplicitEuler.step(phi0, 0.0, a_coeff, &p, dt);
    assert!(rel_err(phi, phi_eq) <= 1e-3);
}

#[test]
fn huge_steps_reach_equilibrium_without_overflow() {
    let p = fig2();
    let a_coeff = p.a_coeff_default_pa();
    // Growth (c < 0): e^(2γ|c|Δt) = e^(6e10) would overflow a naive evaluation.
    for (phi0, eps) in [(1e-3, 0.0), (0.01, 1.0), (1e-150, 0.5), (5.0, 1.0)] {
        let expected = p.equilibrium_phi(eps, a_coeff);
        for stepper in [PhiStepper::Exact, PhiStepper::ImplicitEuler] {
            let phi = stepper.step(phi0, eps, a_coeff, &p, 1e3);
            let tol = if stepper == PhiStepper::Exact {
                1e-15
            } else {
                1e-6
            };
            assert!(
                rel_err(phi, expected) <= tol,
                "{stepper:?} {phi0} {eps}: {phi}"
            );
        }
    }
    // Melting (c > 0): exact φ → 0 (to underflow); backward Euler only algebraically,
    // y1 ≤ y0/(1 + 2γΔt·c).
    let phi = PhiStepper::Exact.step(1.2, 2.0, a_coeff, &p, 1e3);
    assert_eq!(phi, 0.0);
    let phi = PhiStepper::ImplicitEuler.step(1.2, 2.0, a_coeff, &p, 1e3);
    let c = p.bernoulli_c_pa(2.0, a_coeff);
    let bound = (1.44 / (1.0 + 2.0 * p.gamma_per_pa_s * 1e3 * c)).sqrt();
    assert!(
        phi.is_finite() && phi > 0.0 && phi <= bound,
        "{phi} {bound}"
    );
    // φ = 0 is a fixed point.
    for stepper in [PhiStepper::Exact, PhiStepper::ImplicitEuler] {
        assert_eq!(stepper.step(0.0, 0.0, a_coeff, &p, 1e3), 0.0);
        assert_eq!(stepper.step(0.0, 0.0, a_coeff, &p, 1e-9), 0.0);
    }
    // Zero step is the identity; the sign of φ is irrelevant.
    assert_eq!(exact_phi(0.7, 1.0, a_coeff, &p, 0.0), 0.7);
    assert_eq!(
        exact_phi(-0.7, 1.0, a_coeff, &p, 1e-8),
        exact_phi(0.7, 1.0, a_coeff, &p, 1e-8)
    );
}

#[test]
fn c_zero_branch_and_its_neighbourhood() {
    let p = fig2();
    // ε = 1, A = a²/b = 5e5 Pa ⇒ c = a·ε² − A·b/a = 1e6 − 1e6 = 0 exactly.
    let a_coeff = p.a_pa * p.a_pa / p.b_pa();
    assert_eq!(p.bernoulli_c_pa(1.0, a_coeff), 0.0);
    let (phi0, t) = (1.3, 3e-7);
    let y0: f64 = phi0 * phi0;
    let expected = (y0 / (1.0 + 2.0 * p.gamma_per_pa_s * p.b_pa() * y0 * t)).sqrt();
    let phi = exact_phi(phi0, 1.0, a_coeff, &p, t);
    assert!(rel_err(phi, expected) <= 1e-15, "{phi} {expected}");
    // Continuity: c = ±(tiny) differs from c = 0 by O(c) only.
    for factor in [1.0 + 1e-12, 1.0 - 1e-12] {
        let near = exact_phi(phi0, 1.0, a_coeff * factor, &p, t);
        assert!(rel_err(near, expected) <= 1e-11, "{near} {expected}");
    }
    // The closed form composes: two half steps equal one full step.
    let half = exact_phi(phi0, 1.0, a_coeff, &p, t / 2.0);
    let two_halves = exact_phi(half, 1.0, a_coeff, &p, t / 2.0);
    assert!(rel_err(two_halves, expected) <= 1e-15);
}

#[test]
fn exact_solution_satisfies_the_ode() {
    // Central difference of the closed form against the right-hand side of Eq. 8.
    let p = fig2();
    let a_coeff = p.a_coeff_default_pa();
    for (phi0, eps) in [(1.2, 2.0), (0.1, 1.0), (0.5, 1.7), (1.0, 0.0)] {
        for t in [1e-9, 3e-8, 1e-7] {
            let h = 1e-12;
            let phi = exact_phi(phi0, eps, a_coeff, &p, t);
            let dphi = (exact_phi(phi0, eps, a_coeff, &p, t + h)
                - exact_phi(phi0, eps, a_coeff, &p, t - h))
                / (2.0 * h);
            let f = rhs(phi, eps, a_coeff, &p);
            assert!(
                (dphi - f).abs() <= 1e-5 * (f.abs() + 1e3),
                "{phi0} {eps} {t}: {dphi} {f}"
            );
        }
    }
}
