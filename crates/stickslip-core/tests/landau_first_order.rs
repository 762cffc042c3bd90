//! The first-order film (docs/model.md#the-first-order-film): its thresholds derived here
//! again from the free energy, and the exact frozen-strain step against an independent
//! reference (the path time by quadrature in a variable that keeps the integrand smooth, and
//! RK4), in every regime of its evaluation: stick phase, c ≈ 0, the hysteresis, the fold from
//! both sides, melting, b₃ → 0.

use stickslip_core::landau::first_order::{self, Branches, branches};
use stickslip_core::landau::{LandauParams, PhiStepper, rhs, stress};

const GAMMA: f64 = 10.0;
const B: f64 = 2e6;

/// fig2's lubricant with the cubic coefficient `b3`.
fn film(b3: f64) -> LandauParams {
    LandauParams::new(1e6, 1.0, 1e6, GAMMA)
        .unwrap()
        .with_cubic(b3)
        .unwrap()
}

fn rel(x: f64, r: f64) -> f64 {
    (x - r).abs() / r.abs()
}

/// b₃ of fig2_first_order: ε₊ = 1.3·εc at A = 1.5e6 Pa.
fn b3_fig2() -> f64 {
    film(1.0)
        .cubic_for_melting_strain(1.3 * 3f64.sqrt(), 1.5e6)
        .unwrap()
}

#[test]
fn thresholds_follow_from_the_free_energy() {
    let b3 = b3_fig2();
    let p = film(b3);
    let (a, b) = (p.a_pa, p.b_pa());
    for a_coeff in [1.5e6, 4e5, 1e3] {
        let ap = a_coeff * b / a;
        // Solid branch and barrier: the roots of bφ² − b₃φ + c, stationary states of Eq. 8.
        for eps in [0.0, 0.5, 1.0, 1.5] {
            let (plus, minus) = (p.solid_phi(eps, a_coeff), p.barrier_phi(eps, a_coeff));
            if plus > 0.0 {
                assert!(rhs(plus, eps, a_coeff, &p).abs() <= 1e-8 * GAMMA * b * plus.powi(3));
                let c = p.bernoulli_c_pa(eps, a_coeff);
                let by_hand = (b3 + (b3 * b3 - 4.0 * b * c).sqrt()) / (2.0 * b);
                assert!(rel(plus, by_hand) <= 1e-14, "{plus} vs {by_hand}");
                assert!(minus < plus);
                assert!(
                    rhs(minus, eps, a_coeff, &p).abs() <= 1e-6 * GAMMA * b * plus.powi(3),
                    "barrier"
                );
            }
        }
        // Melting where the solid branch ends: ε₊² = (A' + b₃²/(4b))/a, φ₊ = b₃/(2b) there.
        let eps_plus = p.melting_strain(a_coeff);
        assert!(rel(eps_plus * eps_plus, (ap + b3 * b3 / (4.0 * b)) / a) <= 1e-14);
        let below = p.solid_phi(eps_plus * (1.0 - 1e-9), a_coeff);
        assert!(rel(below, b3 / (2.0 * b)) <= 1e-3, "{below}");
        assert_eq!(p.solid_phi(eps_plus * (1.0 + 1e-9), a_coeff), 0.0);
        // Solidification where φ = 0 loses stability: ∂rhs/∂φ at 0 = −γc changes sign at
        // εc = √(A'/a); the solid branch there is b₃/b.
        let eps_minus = p.solidification_strain(a_coeff);
        assert!(rel(eps_minus * eps_minus, ap / a) <= 1e-14);
        assert!(p.bernoulli_c_pa(eps_minus * (1.0 - 1e-9), a_coeff) < 0.0);
        assert!(p.bernoulli_c_pa(eps_minus * (1.0 + 1e-9), a_coeff) > 0.0);
        assert!(rel(p.solid_phi(eps_minus, a_coeff), b3 / b) <= 1e-8);
        // The hysteresis has the same width at every temperature.
        let width = eps_plus * eps_plus - eps_minus * eps_minus;
        assert!(rel(width, b3 * b3 / (4.0 * a * b)) <= 1e-12, "{width}");
        assert!(rel(p.hysteresis_width(), width) <= 1e-12);
        // The initial state φ₊(0) and τ at ε₊.
        let phi0 = (b3 + (b3 * b3 + 4.0 * b * ap).sqrt()) / (2.0 * b);
        assert!(rel(p.solid_phi(0.0, a_coeff), phi0) <= 1e-15);
        let tau = stress(b3 / (2.0 * b), eps_plus, a);
        assert!(rel(p.melting_stress_pa(a_coeff), tau) <= 1e-15);
        // ε₊ given instead of b₃ (lubricant.eps_melt) comes back.
        let back = film(1.0)
            .cubic_for_melting_strain(eps_plus, a_coeff)
            .unwrap();
        assert!(rel(back, b3) <= 1e-12, "{back} vs {b3}");
    }
    // fig2_first_order's numbers.
    assert!(rel(p.melting_strain(1.5e6), 1.3 * 3f64.sqrt()) <= 1e-14);
    eprintln!(
        "b3 = {b3:e} Pa: phi+(0) = {}, eps+ = {}, eps- = {}, width = {}, tau(eps+) = {:e} Pa",
        p.solid_phi(0.0, 1.5e6),
        p.melting_strain(1.5e6),
        p.solidification_strain(1.5e6),
        p.hysteresis_width(),
        p.melting_stress_pa(1.5e6)
    );
}

#[test]
fn above_the_melting_temperature_a_metastable_solid_exists_while_b3_squared_exceeds_minus_4_b_a() {
    let b3 = b3_fig2();
    let p = film(b3);
    let (a, b) = (p.a_pa, p.b_pa());
    // b₃² ≥ −4b·A' ⇔ A ≥ −a·b₃²/(4b²).
    let a_limit = -a * b3 * b3 / (4.0 * b * b);
    for (a_coeff, solid) in [
        (0.0, true),
        (0.5 * a_limit, true),
        (a_limit * (1.0 - 1e-9), true),
        (a_limit * (1.0 + 1e-9), false),
        (2.0 * a_limit, false),
    ] {
        assert_eq!(p.starts_solid(a_coeff), solid, "A = {a_coeff:e}");
        assert_eq!(p.solid_phi(0.0, a_coeff) > 0.0, solid, "A = {a_coeff:e}");
        // The liquid is stable at every strain: c = aε² − A' > 0.
        assert!(p.bernoulli_c_pa(0.0, a_coeff) >= 0.0);
        assert_eq!(p.solidification_strain(a_coeff), 0.0);
    }
    // The second-order film has none.
    assert!(!film(0.0).starts_solid(0.0));
    assert_eq!(film(0.0).solid_phi(0.0, -1.0), 0.0);
}

/// The path time from `phi0` to `phi1` under frozen c, by quadrature in u with
/// |φ − r| = |φ0 − r|·e^(−u), r the state approached: the integrand (φ − r)/(γ·φ·Q(φ)) is
/// smooth up to r (φ itself is taken from whichever end is nearer, as the solver does).
/// Adaptive Gauss–Legendre (8 points per cell, a cell split until its two
/// halves agree with it to 1e-15 of the whole), Q in the factored form near roots.
fn path_time(phi0: f64, phi1: f64, c: f64, b3: f64) -> f64 {
    let (target, q): (f64, Box<dyn Fn(f64) -> f64>) = match branches(c, B, b3) {
        Branches::Real { minus, plus } => (
            if phi0 > minus { plus } else { 0.0 },
            Box::new(move |phi: f64| B * (phi - plus) * (phi - minus)),
        ),
        Branches::Fold { at } => (
            if phi0 > at { at } else { 0.0 },
            Box::new(move |phi: f64| B * (phi - at) * (phi - at)),
        ),
        Branches::Liquid => (0.0, Box::new(move |phi: f64| B * phi * phi - b3 * phi + c)),
    };
    // ln((φ0 − r)/(φ1 − r)), accurate also when φ1 is near φ0.
    let u_end = if (phi1 - target).abs() < 0.5 * (phi0 - target).abs() {
        ((phi0 - target) / (phi1 - target)).ln()
    } else {
        -((phi1 - phi0) / (phi0 - target)).ln_1p()
    };
    // dφ = −(φ − r)·du and dt = dφ/(−γφQ): dt = (φ − r)/(γφQ)·du.
    let f = |u: f64| {
        let d = (phi0 - target) * (-u).exp();
        // φ from whichever end is nearer, without cancellation.
        let phi = if d.abs() < 0.5 * phi0 {
            target + d
        } else {
            phi0 + (phi0 - target) * (-u).exp_m1()
        };
        d / (GAMMA * phi * q(phi))
    };
    const X: [f64; 4] = [
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_3,
    ];
    const W: [f64; 4] = [
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    let gl = |a: f64, b: f64| {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        half * X
            .iter()
            .zip(W)
            .map(|(x, w)| w * (f(mid - half * x) + f(mid + half * x)))
            .sum::<f64>()
    };
    let cells = 64;
    let h = u_end / f64::from(cells);
    let coarse: f64 = (0..cells)
        .map(|i| gl(f64::from(i) * h, f64::from(i + 1) * h))
        .sum();
    let mut total = 0.0;
    let mut stack: Vec<(f64, f64, f64, u32)> = (0..cells)
        .map(|i| {
            let (a, b) = (f64::from(i) * h, f64::from(i + 1) * h);
            (a, b, gl(a, b), 0)
        })
        .collect();
    while let Some((a, b, whole, depth)) = stack.pop() {
        let m = 0.5 * (a + b);
        let (left, right) = (gl(a, m), gl(m, b));
        let diff = (left + right - whole).abs();
        if diff <= 1e-15 * coarse.abs() || diff <= 1e-14 * (left + right).abs() || depth > 30 {
            total += left + right;
        } else {
            stack.push((a, m, left, depth + 1));
            stack.push((m, b, right, depth + 1));
        }
    }
    total
}

/// Every regime of the evaluation (module docs of `first_order`): (b₃, c) pairs.
fn regimes() -> Vec<(&'static str, f64, f64)> {
    let b3 = b3_fig2();
    let fold = b3 * b3 / (4.0 * B);
    let tiny = 1e-9 * B * 1.5f64.sqrt();
    vec![
        ("stick phase, eps = 0", b3, -3e6),
        ("stick phase, eps = eps_c/2", b3, -2.25e6),
        ("c = 0 (eps = eps_c)", b3, 0.0),
        ("c slightly below 0", b3, -1e-3 * fold),
        ("c slightly above 0", b3, 1e-3 * fold),
        ("hysteresis, separated roots", b3, 0.1 * fold),
        ("hysteresis, near the switch", b3, 0.13 * fold),
        ("hysteresis, past the switch", b3, 0.6 * fold),
        ("just before the fold", b3, (1.0 - 1e-6) * fold),
        ("exactly at the fold", b3, fold),
        ("just past the fold", b3, (1.0 + 1e-6) * fold),
        ("melting", b3, 2.0 * fold),
        ("melting fast", b3, 50.0 * fold),
        ("small b3, stick", 1e5, -3e6),
        ("small b3, near c = 0", 1e5, 1e3),
        ("small b3, past the fold", 1e5, 1e5),
        ("b3 -> 0, stick", tiny, -3e6),
        ("b3 -> 0, c = 0", tiny, 0.0),
        ("b3 -> 0, melting", tiny, 1e4),
    ]
}

#[test]
fn exact_step_meets_the_path_time_by_quadrature_in_every_regime() {
    let mut worst = 0.0_f64;
    let mut worst_case = String::new();
    let mut checked = 0;
    for (name, b3, c) in regimes() {
        for phi0 in [1e-4, 0.01, 0.3, 1.0, 2.0, 5.0] {
            for dt in [1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5] {
                let phi1 = first_order::exact_phi(phi0, c, B, b3, GAMMA, dt);
                assert!(phi1.is_finite() && phi1 >= 0.0, "{name}: {phi1}");
                // Monotone towards the state approached, never across a stationary state.
                let dir = first_order::rhs(phi0, c, B, b3, GAMMA).signum();
                assert!((phi1 - phi0) * dir >= 0.0, "{name}: moved the wrong way");
                if phi1 == phi0 || phi1 == 0.0 {
                    continue;
                }
                // Where φ1 sits within rounding of the state approached, the time is not
                // resolved by φ1 any more: skip (the stiff-limit test covers it).
                let at_state = match branches(c, B, b3) {
                    Branches::Real { plus, .. } => rel(phi1, plus) < 1e-12,
                    Branches::Fold { at } => rel(phi1, at) < 1e-12,
                    Branches::Liquid => false,
                } || phi1 < 1e-280;
                if at_state {
                    continue;
                }
                let t = path_time(phi0, phi1, c, b3);
                // dT/dφ·φ: the time error that a relative error of φ1 of 1 would make.
                let sens = (phi1 / (GAMMA * phi1 * (B * phi1 * phi1 - b3 * phi1 + c))).abs();
                let err = (t - dt).abs() / sens.max(1e-300);
                if err > worst {
                    worst_case = format!("{name}, phi0 {phi0}, dt {dt:e}");
                }
                worst = worst.max(err);
                checked += 1;
                assert!(
                    err <= 1e-11 || (t / dt - 1.0).abs() <= 1e-10,
                    "{name}: phi0 {phi0} dt {dt:e}: phi1 {phi1:e}, quadrature time {t:e} \
                     (relative phi error {err:e})"
                );
            }
        }
    }
    eprintln!(
        "{checked} steps: worst relative error of phi1 (from the time) {worst:e} ({worst_case})"
    );
    assert!(checked > 300);
}

#[test]
fn exact_step_agrees_with_rk4() {
    let b3 = b3_fig2();
    let fold = b3 * b3 / (4.0 * B);
    for (c, phi0, t) in [
        (-3e6, 0.01, 2e-7),
        (-3e6, 4.0, 2e-8),
        (0.5 * fold, 1.5, 1e-7),
        (1.5 * fold, 1.2, 2e-7),
        ((1.0 + 1e-4) * fold, 1.2, 1e-6),
    ] {
        let n = 200_000;
        let h = t / f64::from(n);
        let f = |phi: f64| first_order::rhs(phi, c, B, b3, GAMMA);
        let mut phi = phi0;
        for _ in 0..n {
            let k1 = f(phi);
            let k2 = f(phi + 0.5 * h * k1);
            let k3 = f(phi + 0.5 * h * k2);
            let k4 = f(phi + h * k3);
            phi += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        let exact = first_order::exact_phi(phi0, c, B, b3, GAMMA, t);
        eprintln!("c {c:e} phi0 {phi0} t {t:e}: exact {exact:e}, RK4 {phi:e}");
        assert!(rel(exact, phi) <= 1e-9, "{exact} vs {phi}");
    }
}

#[test]
fn steps_compose_and_stationary_states_stay_exact() {
    for (name, b3, c) in regimes() {
        let Some(stationary) = (match branches(c, B, b3) {
            Branches::Real { minus, plus } => Some([plus, minus]),
            Branches::Fold { at } => Some([at, at]),
            Branches::Liquid => None,
        }) else {
            continue;
        };
        for s in stationary.into_iter().filter(|&s| s > 0.0) {
            for dt in [1e-12, 1e-6, 1e3] {
                assert_eq!(
                    first_order::exact_phi(s, c, B, b3, GAMMA, dt),
                    s,
                    "{name}: stationary {s}"
                );
            }
        }
        assert_eq!(first_order::exact_phi(0.0, c, B, b3, GAMMA, 1.0), 0.0);
        for phi0 in [0.01, 0.7, 3.0] {
            for (t1, t2) in [(1e-9, 3e-9), (2e-8, 5e-8), (1e-7, 1e-6)] {
                let whole = first_order::exact_phi(phi0, c, B, b3, GAMMA, t1 + t2);
                let half = first_order::exact_phi(phi0, c, B, b3, GAMMA, t1);
                let two = first_order::exact_phi(half, c, B, b3, GAMMA, t2);
                if whole < 1e-250 {
                    continue;
                }
                assert!(
                    rel(two, whole) <= 1e-11,
                    "{name}: phi0 {phi0}, {t1:e} + {t2:e}: {two:e} vs {whole:e}"
                );
            }
        }
    }
}

#[test]
fn a_huge_step_lands_on_the_stationary_state_exactly() {
    let b3 = b3_fig2();
    let p = film(b3);
    for eps in [0.0, 1.0, 2.0, 2.2] {
        let plus = p.solid_phi(eps, 1.5e6);
        assert!(plus > 0.0);
        let c = p.bernoulli_c_pa(eps, 1.5e6);
        let minus = p.barrier_phi(eps, 1.5e6);
        let lo = minus.max(0.0);
        for phi0 in [
            lo + 1e-3 * (plus - lo),
            0.5 * (lo + plus),
            plus * 1.0001,
            10.0,
        ] {
            for dt in [1e-3, 1.0, 1e6] {
                assert_eq!(
                    first_order::exact_phi(phi0, c, B, b3, GAMMA, dt),
                    plus,
                    "eps {eps} phi0 {phi0} dt {dt}"
                );
                assert_eq!(
                    PhiStepper::Exact.step(phi0, eps, 1.5e6, &p, dt),
                    plus,
                    "through PhiStepper"
                );
            }
        }
        if minus > 0.0 {
            // Below the barrier the film melts.
            let phi = first_order::exact_phi(0.5 * minus, c, B, b3, GAMMA, 1.0);
            assert!(phi < 1e-100, "{phi}");
        }
    }
    // Beyond ε₊ every film melts, for any step.
    let eps = 1.01 * p.melting_strain(1.5e6);
    for dt in [1e-6, 1.0] {
        let phi = PhiStepper::Exact.step(3.0, eps, 1.5e6, &p, dt);
        assert!((0.0..1e-3).contains(&phi), "{phi}");
    }
}

#[test]
fn time_to_a_level_is_where_the_step_arrives() {
    for (name, b3, c) in regimes() {
        for phi0 in [0.005, 0.02, 1.0, 3.0] {
            for level in [0.01, 0.02, 0.5, 2.0] {
                let Some(t) = first_order::time_to(phi0, level, c, B, b3, GAMMA) else {
                    continue;
                };
                if t > 1.0 {
                    continue;
                }
                let phi = first_order::exact_phi(phi0, c, B, b3, GAMMA, t);
                assert!(
                    rel(phi, level) <= 1e-9,
                    "{name}: phi0 {phi0} to {level}: t {t:e} gives {phi}"
                );
            }
        }
    }
    // Not on the path: none.
    assert!(first_order::time_to(1.0, 5.0, -3e6, B, 1e6, GAMMA).is_none());
}

#[test]
fn vanishing_b3_approaches_the_second_order_film() {
    let tiny = 1e-9 * B * 1.5f64.sqrt();
    let (p0, p1) = (film(0.0), film(tiny));
    let a_coeff = 1.5e6;
    let eps_c = p0.critical_strain(a_coeff);
    let mut worst = 0.0_f64;
    for eps in [
        0.0,
        0.5 * eps_c,
        0.999 * eps_c,
        eps_c,
        1.001 * eps_c,
        1.5 * eps_c,
    ] {
        for phi0 in [0.01, 0.5, 1.2, 3.0] {
            for dt in [1e-9, 1e-7, 1e-5] {
                let second = PhiStepper::Exact.step(phi0, eps, a_coeff, &p0, dt);
                let first = PhiStepper::Exact.step(phi0, eps, a_coeff, &p1, dt);
                if second < 1e-200 {
                    assert!(first < 1e-100);
                    continue;
                }
                worst = worst.max(rel(first, second));
            }
        }
        assert!(
            rel(
                p1.solid_phi(eps, a_coeff).max(1e-300),
                p0.solid_phi(eps, a_coeff).max(1e-300)
            ) <= 1e-6
                || p0.solid_phi(eps, a_coeff) < 1e-4
        );
    }
    eprintln!("b3 = {tiny:e} Pa against b3 = 0: largest relative difference of a step {worst:e}");
    assert!(worst <= 1e-6, "{worst}");
    assert!(rel(p1.melting_strain(a_coeff), eps_c) <= 1e-12);
}

#[test]
fn implicit_euler_is_first_order_and_stays_between_stationary_states() {
    let b3 = b3_fig2();
    let p = film(b3);
    let (phi0, eps, t) = (0.05, 0.8, 1e-7);
    let reference = PhiStepper::Exact.step(phi0, eps, 1.5e6, &p, t);
    let errors: Vec<f64> = (4..10)
        .map(|k| {
            let n = 1u32 << k;
            let mut phi = phi0;
            for _ in 0..n {
                phi = PhiStepper::ImplicitEuler.step(phi, eps, 1.5e6, &p, t / f64::from(n));
            }
            rel(phi, reference)
        })
        .collect();
    let order = (errors[errors.len() - 2] / errors[errors.len() - 1]).log2();
    eprintln!("implicit Euler errors {errors:?}, order {order:.3}");
    assert!((0.9..1.1).contains(&order), "{order}");
    let plus = p.solid_phi(eps, 1.5e6);
    for dt in [1e-6, 1.0] {
        let phi = PhiStepper::ImplicitEuler.step(phi0, eps, 1.5e6, &p, dt);
        assert!(phi > phi0 && phi <= plus, "{phi}");
    }
}
