//! The film's viscosity (`lubricant.viscosity`, docs/model.md#viscosity): η = 0 is the paper's
//! film byte for byte; a liquid film's viscous force against exact answers — the Couette force,
//! the one-node contact on a spring (rigid substrate: a damped driven oscillator; elastic
//! substrate: a 3×3 linear system, its matrix exponential), the stiff viscous coupling — each
//! at the scheme's order, the observed order printed (`-- --nocapture`).

use crate::common;

use std::f64::consts::PI;
use stickslip_run::driver::{Control, Driver, Limit, NullSink};
use stickslip_run::outcome::StopReason;
use stickslip_run::{DirOptions, ResolvedScene, Scene, run_to_dir};

const RADIUS_M: f64 = 2e-5;
const H0_M: f64 = 1e-7;
const G_EFF_PA: f64 = 1e9;

/// A liquid film (A < 0, no noise: φ = 0 at every node for good) of viscosity `eta`, with the
/// contact and drive lines given, fixed steps of `dt` to `end`.
fn liquid(eta: f64, contact: &str, drive: &str, end: f64, dt: f64) -> ResolvedScene {
    liquid_stepped(
        eta,
        contact,
        drive,
        &format!("end = {end:e}\ndt = {dt:e}\nstepping = \"fixed\""),
    )
}

/// [`liquid`] with the `[time]` lines given (the scheme is the accurate one).
fn liquid_stepped(eta: f64, contact: &str, drive: &str, time: &str) -> ResolvedScene {
    let text = format!(
        "name = \"viscous\"\n\
         [lubricant]\ntau_max = 1e6\neps_max = 1.0\na = 1e6\ngamma = 10.0\nviscosity = {eta:e}\n\
         [lubricant.noise]\nkind = \"off\"\n\
         [temperature]\nA0 = -1e5\n\
         [contact]\nradius = {RADIUS_M:e}\nfilm_thickness = {H0_M:e}\ng_eff = {G_EFF_PA:e}\n{contact}\n\
         [drive]\n{drive}\n\
         [time]\n{time}\nscheme = \"accurate\"\n\
         [output]\nprofile_times = []\n"
    );
    Scene::from_toml_str(&text, &[] as &[&str]).unwrap()
}

/// Runs `scene` to its end; returns (t, X, V, F, u3D at the axis).
fn run(scene: &ResolvedScene) -> (f64, f64, f64, f64, f64) {
    let mut driver = Driver::start(scene, &mut NullSink).unwrap();
    let stop = driver
        .advance(&mut NullSink, &mut Control::default(), Limit::None)
        .unwrap();
    assert!(
        matches!(stop, None | Some(StopReason::End)),
        "{}: {stop:?}",
        scene.name
    );
    let st = &driver.simulation().state().physical;
    (
        st.drive.t_s,
        st.drive.x_m,
        st.drive.v_m_per_s,
        st.force_n,
        st.u3d_m[0],
    )
}

/// e^M for a small dense matrix: scaling and squaring with a Taylor series (to rounding for
/// the norms here).
fn expm(m: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = m.len();
    let norm = m
        .iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let squarings = (norm / 0.25).log2().ceil().max(0.0) as i32;
    let scale = 0.5f64.powi(squarings);
    let a: Vec<Vec<f64>> = m
        .iter()
        .map(|r| r.iter().map(|v| v * scale).collect())
        .collect();
    let mul = |x: &[Vec<f64>], y: &[Vec<f64>]| -> Vec<Vec<f64>> {
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| (0..n).map(|k| x[i][k] * y[k][j]).sum())
                    .collect()
            })
            .collect()
    };
    let mut sum: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
        .collect();
    let mut term = sum.clone();
    for k in 1..30 {
        term = mul(&term, &a);
        for row in &mut term {
            for v in row.iter_mut() {
                *v /= k as f64;
            }
        }
        for i in 0..n {
            for j in 0..n {
                sum[i][j] += term[i][j];
            }
        }
    }
    for _ in 0..squarings {
        sum = mul(&sum, &sum);
    }
    sum
}

/// The one-node liquid contact on the spring, exactly (docs/model.md#viscosity): in
/// y = X − V0·t, w = V − V0 and u = u3D,
///   ẏ = w,  m·ẇ = −K·y − c_d·w − F,  u̇ = (w + V0) − u/t_v,
/// with F = A·u/C (u = C·τ, C = πa0/(2G*) the flat punch's compliance per stress, A = πa0²,
/// t_v = C·η/h0) on the elastic substrate, and F = c_v·(w + V0), c_v = η·A/h0, u ≡ 0 on the
/// rigid one. An affine linear system from rest (y = 0, w = −V0, u = 0), solved by the
/// exponential of its 4×4 augmented matrix. Returns (X, V, F) at t.
fn one_node_exact(eta: f64, k: f64, m: f64, cd: f64, v0: f64, elastic: bool, t: f64) -> [f64; 3] {
    let area = PI * RADIUS_M * RADIUS_M;
    let compliance = PI * RADIUS_M / (2.0 * G_EFF_PA);
    let t_v = compliance * eta / H0_M;
    let cv = eta * area / H0_M;
    // Rows: y, w, u, 1.
    let mat = if elastic {
        vec![
            vec![0.0, 1.0, 0.0, 0.0],
            vec![-k / m, -cd / m, -area / (compliance * m), 0.0],
            vec![0.0, 1.0, -1.0 / t_v, v0],
            vec![0.0; 4],
        ]
    } else {
        vec![
            vec![0.0, 1.0, 0.0, 0.0],
            vec![-k / m, -(cd + cv) / m, 0.0, -cv * v0 / m],
            vec![0.0; 4],
            vec![0.0; 4],
        ]
    };
    let scaled: Vec<Vec<f64>> = mat
        .iter()
        .map(|r| r.iter().map(|v| v * t).collect())
        .collect();
    let e = expm(&scaled);
    let q0 = [0.0, -v0, 0.0, 1.0];
    let q: Vec<f64> = (0..4)
        .map(|i| (0..4).map(|j| e[i][j] * q0[j]).sum())
        .collect();
    let (x, v) = (q[0] + v0 * t, q[1] + v0);
    let f = if elastic {
        area * q[2] / compliance
    } else {
        cv * v
    };
    [x, v, f]
}

fn order(e_coarse: f64, e_fine: f64) -> f64 {
    (e_coarse / e_fine).log2()
}

#[test]
fn couette_force_on_a_rigid_substrate_is_exact_at_every_step() {
    // τ = η·V0/h0 at every node, F = η·V0·πa0²/h0, whatever the step: the rates are exact.
    let (eta, v0) = (2.5, 1e-3);
    let couette = eta * v0 * PI * RADIUS_M * RADIUS_M / H0_M;
    for contact in [
        "nodes = 40\nmodel = \"radial\"\nsubstrate = \"rigid\"",
        "nodes = 40\nmodel = \"homogeneous\"\nsubstrate = \"rigid\"",
    ] {
        for dt in [1e-7, 1e-5] {
            let s = liquid(
                eta,
                contact,
                &format!("kind = \"rigid\"\nvelocity = {v0:e}"),
                1e-4,
                dt,
            );
            let (_, _, _, f, _) = run(&s);
            let rel = (f - couette) / couette;
            eprintln!(
                "Couette, rigid substrate, {contact:?}, dt {dt:e}: F relative error {rel:.2e}"
            );
            assert!(rel.abs() < 1e-13, "{contact}: {f} vs {couette}");
        }
    }
}

#[test]
fn couette_force_on_an_elastic_substrate_one_node_transient_second_order() {
    // One node under the rigid drive: t_v·u̇ = t_v·V0 − u, so
    // F = (η·V0·πa0²/h0)·(1 − e^(−t/t_v)) exactly; BDF2 (backward Euler on the first step
    // only) is second order in Δt.
    let (eta, v0) = (30.0, 1e-3);
    let compliance = PI * RADIUS_M / (2.0 * G_EFF_PA);
    let t_v = compliance * eta / H0_M;
    let couette = eta * v0 * PI * RADIUS_M * RADIUS_M / H0_M;
    let end = 2.0 * t_v;
    let mut errors = Vec::new();
    for n in [25, 50, 100, 200, 400] {
        let s = liquid(
            eta,
            "nodes = 1\nmodel = \"homogeneous\"\nsubstrate = \"elastic\"",
            &format!("kind = \"rigid\"\nvelocity = {v0:e}"),
            end,
            end / f64::from(n),
        );
        let (t, _, _, f, _) = run(&s);
        let exact = couette * -(-t / t_v).exp_m1();
        errors.push(((f - exact) / couette).abs());
    }
    let orders: Vec<f64> = errors.windows(2).map(|e| order(e[0], e[1])).collect();
    eprintln!("one-node Couette transient: errors {errors:.3?}, observed orders {orders:.3?}");
    for p in &orders {
        assert!((p - 2.0).abs() < 0.1, "order {p} (errors {errors:?})");
    }
    assert!(errors[4] < 1e-6, "{errors:?}");
    // Long after t_v the steady Couette force, whatever the step (also Δt ≫ t_v).
    for dt in [t_v / 10.0, 30.0 * t_v] {
        let s = liquid(
            eta,
            "nodes = 1\nmodel = \"homogeneous\"\nsubstrate = \"elastic\"",
            &format!("kind = \"rigid\"\nvelocity = {v0:e}"),
            60.0 * t_v * 30.0,
            dt,
        );
        let (_, _, _, f, _) = run(&s);
        assert!(
            ((f - couette) / couette).abs() < 1e-12,
            "dt {dt:e}: {f} vs {couette}"
        );
    }
}

#[test]
fn couette_force_on_an_elastic_radial_substrate_at_steady_state() {
    // The radial substrate relaxes on a spread of time scales up to about η·a0/(h0·G*); long
    // after, u̇3D = 0 and F = η·V0·πa0²/h0 (to the force quadrature's rounding). Steps far
    // longer than the shortest scales: the implicit coupling stays stable.
    let (eta, v0) = (30.0, 1e-3);
    let t_scale = eta * RADIUS_M / (H0_M * G_EFF_PA);
    let couette = eta * v0 * PI * RADIUS_M * RADIUS_M / H0_M;
    for (n, dt) in [(40, t_scale / 5.0), (100, t_scale)] {
        let s = liquid(
            eta,
            &format!("nodes = {n}\nmodel = \"radial\"\nsubstrate = \"elastic\""),
            &format!("kind = \"rigid\"\nvelocity = {v0:e}"),
            200.0 * t_scale,
            dt,
        );
        // What check prints: the drag c_v and the viscous time.
        let driver = Driver::start(&s, &mut NullSink).unwrap();
        let v = driver.preflight().viscous.expect("viscous scales");
        assert!((v.drag_n_s_per_m / (couette / v0) - 1.0).abs() < 1e-15);
        assert!((v.time_s / t_scale - 1.0).abs() < 1e-15);
        let (_, _, _, f, u) = run(&s);
        let rel = (f - couette) / couette;
        eprintln!("radial Couette N = {n}: steady F relative error {rel:.2e}, u3D(0) = {u:.3e} m");
        assert!(rel.abs() < 1e-9, "N {n}: {f} vs {couette}");
        assert!(u > 0.0);
    }
}

#[test]
fn one_node_liquid_contact_on_a_spring_rigid_substrate() {
    // m·Ẍ = K(V0·t − X) + c_d·(V0 − Ẋ) − c_v·Ẋ: the split integrator takes the drag into the
    // spring's exact flow, so its error is rounding for any c_v·Δt/m; Verlet is second order,
    // RK4 fourth (at moderate steps).
    let (k, m, v0) = (500.0, 0.1, 1.0);
    let contact = "nodes = 1\nmodel = \"homogeneous\"\nsubstrate = \"rigid\"";
    let end = 2e-2;
    for (eta, cd) in [(1e3, 0.0), (1e3, 3.0), (1e5, 0.0)] {
        let cv = eta * PI * RADIUS_M * RADIUS_M / H0_M;
        let [x_ex, v_ex, _] = one_node_exact(eta, k, m, cd, v0, false, end);
        let drive = |integrator: &str| {
            format!(
                "kind = \"spring\"\nstiffness = {k:e}\nmass = {m:e}\ndamping = {cd:e}\n\
                 velocity = {v0:e}\nintegrator = \"{integrator}\""
            )
        };
        // Split: exact, from Δt = end/4 (c_v·Δt/m up to 630) down.
        for n in [4, 64, 1024] {
            let s = liquid(eta, contact, &drive("split"), end, end / f64::from(n));
            let (_, x, v, f, _) = run(&s);
            let (ex, ev) = ((x - x_ex) / x_ex, (v - v_ex) / v_ex.abs().max(1e-3 * v0));
            eprintln!(
                "spring, rigid substrate, eta {eta:e}, c_d {cd}, split, {n} steps (c_v dt/m = \
                 {:.2e}): X error {ex:.2e}, V error {ev:.2e}",
                cv * end / f64::from(n) / m
            );
            assert!(ex.abs() < 1e-11 && ev.abs() < 1e-11, "{ex:e} {ev:e}");
            assert!(f > 0.0);
        }
        if eta > 1e4 {
            // Stiff drag (c_v·Δt/m = 63 at 4 steps): Verlet's damping is the trapezoidal rule,
            // stable though not accurate there; RK4 is only stable below c_v·Δt/m ≈ 2.8, and
            // its adaptive steps stay within that (the error estimate takes RK4's error on
            // the drag's decay).
            for n in [4, 64] {
                let s = liquid(eta, contact, &drive("verlet"), end, end / f64::from(n));
                let (_, x, v, _, _) = run(&s);
                let ex = (x - x_ex) / x_ex;
                eprintln!(
                    "spring, rigid substrate, eta {eta:e}, verlet, {n} steps: X error {ex:.2e}"
                );
                assert!(ex.abs() < 2e-2 && v.is_finite(), "verlet {n}: {ex:e}");
            }
            let s = liquid_stepped(
                eta,
                contact,
                &drive("rk4"),
                &format!("end = {end:e}\ndt = 1e-6\nstepping = \"adaptive\"\ntolerance = 1e-6"),
            );
            let mut driver = Driver::start(&s, &mut NullSink).unwrap();
            driver
                .advance(&mut NullSink, &mut Control::default(), Limit::None)
                .unwrap();
            let sim = driver.simulation();
            let st = &sim.state().physical;
            let ex = (st.drive.x_m - x_ex) / x_ex;
            let steps = sim.state().counters.accepted_steps;
            eprintln!(
                "spring, rigid substrate, eta {eta:e}, rk4 adaptive: X error {ex:.2e} in {steps} \
                 steps (stability needs at least {:.0})",
                cv * end / (2.79 * m)
            );
            assert!(ex.abs() < 1e-4, "rk4 adaptive: {ex:e}");
            continue;
        }
        for (integrator, expected, ns) in [
            ("verlet", 2.0, [400, 800, 1600]),
            ("rk4", 4.0, [25, 50, 100]),
        ] {
            let mut errors = Vec::new();
            for n in ns {
                let s = liquid(eta, contact, &drive(integrator), end, end / f64::from(n));
                let (_, x, _, _, _) = run(&s);
                errors.push(((x - x_ex) / x_ex).abs());
            }
            let p = order(errors[1], errors[2]);
            eprintln!(
                "spring, rigid substrate, eta {eta:e}, c_d {cd}, {integrator}: X errors \
                 {errors:.3?}, observed order {p:.3}"
            );
            assert!(
                (p - expected).abs() < 0.15,
                "{integrator}: order {p} ({errors:?})"
            );
        }
    }
}

#[test]
fn one_node_liquid_contact_on_a_spring_elastic_substrate() {
    // The 3×3 system (stamp, spring, the substrate's first-order lag through the viscous film)
    // against its matrix exponential: BDF2 in the coupling keeps the whole step second order;
    // the split integrator kicks only the substrate's rate −(η/h0)·∫u̇3D dA.
    let (k, m, v0, cd) = (500.0, 0.1, 1.0, 0.0);
    let contact = "nodes = 1\nmodel = \"homogeneous\"\nsubstrate = \"elastic\"";
    let compliance = PI * RADIUS_M / (2.0 * G_EFF_PA);
    for eta in [30.0, 1e4] {
        let t_v = compliance * eta / H0_M;
        let end = 5e-4;
        let [x_ex, _, f_ex] = one_node_exact(eta, k, m, cd, v0, true, end);
        for integrator in ["split", "verlet"] {
            let mut errors = Vec::new();
            for n in [200, 400, 800, 1600] {
                let s = liquid(
                    eta,
                    contact,
                    &format!(
                        "kind = \"spring\"\nstiffness = {k:e}\nmass = {m:e}\nvelocity = {v0:e}\n\
                         integrator = \"{integrator}\""
                    ),
                    end,
                    end / f64::from(n),
                );
                let (_, x, _, f, _) = run(&s);
                errors.push(((x - x_ex) / x_ex).abs().max(((f - f_ex) / f_ex).abs()));
            }
            let orders: Vec<f64> = errors.windows(2).map(|e| order(e[0], e[1])).collect();
            eprintln!(
                "spring, elastic one node, eta {eta:e} (t_v = {t_v:.2e} s), {integrator}: \
                 errors {errors:.3?}, observed orders {orders:.3?}"
            );
            let p = orders[2];
            assert!(
                (p - 2.0).abs() < 0.15,
                "{integrator}: order {p} ({errors:?})"
            );
            assert!(errors[3] < 1e-5, "{errors:?}");
        }
    }
}

#[test]
fn a_rigid_film_on_an_elastic_substrate_under_a_stiff_drag() {
    // η = 1e6 Pa·s: t_v = 0.31 s ≫ Δt, so the film barely shears and the stamp and substrate
    // move together, while c_v·Δt/m reaches 12.6. A flow that took all of c_v would hold the
    // stamp back while the kicks gave the substrate's rate back (87 % off at 5 steps when it
    // did); the flow takes c_v·(1 − J), J the substrate's share of the stamp's rate, and the
    // step stays accurate and second order (docs/model.md#viscosity).
    let (k, m, v0, eta) = (500.0, 0.1, 1.0, 1e6);
    let contact = "nodes = 1\nmodel = \"homogeneous\"\nsubstrate = \"elastic\"";
    let cv = eta * PI * RADIUS_M * RADIUS_M / H0_M;
    let end = 5e-4;
    let [x_ex, _, f_ex] = one_node_exact(eta, k, m, 0.0, v0, true, end);
    let drive = format!(
        "kind = \"spring\"\nstiffness = {k:e}\nmass = {m:e}\nvelocity = {v0:e}\nintegrator = \"split\""
    );
    let error = |x: f64, f: f64| ((x - x_ex) / x_ex).abs().max(((f - f_ex) / f_ex).abs());
    let mut errors = Vec::new();
    for n in [5, 20, 200, 400] {
        let s = liquid(eta, contact, &drive, end, end / f64::from(n));
        let (_, x, _, f, _) = run(&s);
        let e = error(x, f);
        eprintln!(
            "rigid film, stiff drag, {n} steps (c_v dt/m = {:.2}): error {e:.3e}",
            cv * end / f64::from(n) / m
        );
        errors.push(e);
    }
    assert!(errors[0] < 1e-3, "{errors:?}");
    let p = order(errors[2], errors[3]);
    assert!((p - 2.0).abs() < 0.15, "order {p} ({errors:?})");
    let s = liquid_stepped(
        eta,
        contact,
        &drive,
        &format!("end = {end:e}\ndt = 1e-8\nstepping = \"adaptive\""),
    );
    let mut driver = Driver::start(&s, &mut NullSink).unwrap();
    driver
        .advance(&mut NullSink, &mut Control::default(), Limit::None)
        .unwrap();
    let sim = driver.simulation();
    let st = &sim.state().physical;
    let e = error(st.drive.x_m, st.force_n);
    eprintln!(
        "rigid film, stiff drag, adaptive (tolerance 5e-5): error {e:.3e} in {} steps",
        sim.state().counters.accepted_steps
    );
    assert!(e < 1e-4, "{e:e}");
}

#[test]
fn stiff_viscous_coupling_stays_stable_and_accurate() {
    // t_v = η·C/h0 ≈ 3e-9 s against steps of 0.25 to 4 µs (Δt/t_v = 80 to 1300), one node
    // and radial: the implicit (L-stable) coupling takes the quasi-static limit, stable and
    // second order (backward Euler's first step aside, whose error decays at once).
    let (k, m, v0) = (500.0, 0.1, 1.0);
    let eta = 1e-2;
    let compliance = PI * RADIUS_M / (2.0 * G_EFF_PA);
    let t_v = compliance * eta / H0_M;
    let end = 1e-3;
    let drive = format!(
        "kind = \"spring\"\nstiffness = {k:e}\nmass = {m:e}\nvelocity = {v0:e}\nintegrator = \"split\""
    );
    let [x_ex, v_ex, f_ex] = one_node_exact(eta, k, m, 0.0, v0, true, end);
    let mut errors = Vec::new();
    for n in [250, 1000, 4000] {
        let dt = end / f64::from(n);
        let s = liquid(
            eta,
            "nodes = 1\nmodel = \"homogeneous\"\nsubstrate = \"elastic\"",
            &drive,
            end,
            dt,
        );
        let (_, x, v, f, _) = run(&s);
        let e = ((x - x_ex) / x_ex)
            .abs()
            .max(((v - v_ex) / v_ex).abs())
            .max(((f - f_ex) / f_ex).abs());
        eprintln!(
            "stiff viscous coupling, one node, dt/t_v = {:.0}: relative error {e:.2e}",
            dt / t_v
        );
        errors.push(e);
    }
    let p = order(errors[0], errors[1]) / 2.0;
    eprintln!("stiff viscous coupling, one node: observed order {p:.3}");
    assert!((p - 2.0).abs() < 0.15 && errors[0] < 5e-5, "{errors:?}");
    // Radial, N = 100, against the rigid substrate's answer (the substrate's share is t_v-small).
    let radial = |substrate: &str| {
        let s = liquid(
            eta,
            &format!("nodes = 100\nmodel = \"radial\"\nsubstrate = \"{substrate}\""),
            &drive,
            end,
            4e-6,
        );
        run(&s)
    };
    let (_, x_e, _, f_e, _) = radial("elastic");
    let (_, x_r, _, f_r, _) = radial("rigid");
    let (ex, ef) = ((x_e - x_r) / x_r, (f_e - f_r) / f_r);
    eprintln!(
        "stiff viscous coupling, radial N = 100: elastic against rigid X {ex:.2e}, F {ef:.2e}"
    );
    assert!(ex.abs() < 1e-4 && ef.abs() < 1e-3, "{ex:e} {ef:e}");
}

#[test]
fn adaptive_steps_follow_the_tolerance_with_the_viscous_coupling() {
    // The step error's strain part includes the viscous coupling's local error in u3D: the
    // one-node elastic contact on the spring, t_v ≈ 9 µs, against its exact answer. A
    // second-order step (local error ∝ h³) under the controller of order 3 gives a global
    // error ∝ tolerance^(2/3); the observed exponent is printed and asserted.
    let (k, m, v0, eta) = (500.0, 0.1, 1.0, 30.0);
    let end = 5e-4;
    let [x_ex, _, f_ex] = one_node_exact(eta, k, m, 0.0, v0, true, end);
    let drive = format!(
        "kind = \"spring\"\nstiffness = {k:e}\nmass = {m:e}\nvelocity = {v0:e}\nintegrator = \"split\""
    );
    let mut errors = Vec::new();
    let tolerances = [1e-3, 1e-4, 1e-5, 1e-6];
    for tol in tolerances {
        let s = liquid_stepped(
            eta,
            "nodes = 1\nmodel = \"homogeneous\"\nsubstrate = \"elastic\"",
            &drive,
            &format!("end = {end:e}\ndt = 1e-9\nstepping = \"adaptive\"\ntolerance = {tol:e}"),
        );
        let mut driver = Driver::start(&s, &mut NullSink).unwrap();
        driver
            .advance(&mut NullSink, &mut Control::default(), Limit::None)
            .unwrap();
        let sim = driver.simulation();
        let st = &sim.state().physical;
        let e = ((st.drive.x_m - x_ex) / x_ex)
            .abs()
            .max(((st.force_n - f_ex) / f_ex).abs());
        let c = &sim.state().counters;
        eprintln!(
            "adaptive, tolerance {tol:e}: error {e:.3e} (X {:.3e}, F {:.3e}) in {} steps ({} \
             rejected)",
            (st.drive.x_m - x_ex) / x_ex,
            (st.force_n - f_ex) / f_ex,
            c.accepted_steps,
            c.rejected_steps
        );
        errors.push(e);
    }
    let slopes: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log10()).collect();
    eprintln!("adaptive, viscous coupling: error ∝ tolerance^p, observed p {slopes:.3?}");
    for p in &slopes {
        assert!((0.5..=0.95).contains(p), "{slopes:?} ({errors:?})");
    }
    assert!(errors[3] < 1e-4, "{errors:?}");
}

#[test]
fn the_films_kinetics_see_only_the_elastic_strain() {
    // Rigid drive on a rigid substrate: u3D ≡ 0, so the solid film's strain and kinetics do
    // not depend on η at all (φ, ε, every event bit for bit), while F gains the Couette force
    // η·V0·πa0²/h0 at every row (to the rounding of ΔX/Δt).
    let tmp = tempfile::tempdir().unwrap();
    let eta = 0.3;
    let mut series = Vec::new();
    for (i, set) in ["lubricant.viscosity=0", "lubricant.viscosity=0.3"]
        .iter()
        .enumerate()
    {
        let s = Scene::from_path(
            &common::scene("rigid"),
            &[
                "contact.nodes=40",
                "contact.substrate=rigid",
                "time.end=4e-4",
                "output.profile_times=[4e-4]",
                "output.series_interval=1e-6",
                set,
            ],
        )
        .unwrap();
        let dir = tmp.path().join(format!("run{i}"));
        let options = DirOptions {
            force: false,
            checkpoint_every_s: 0.0,
        };
        run_to_dir(&s, &dir, &options, &mut Control::default()).unwrap();
        series.push((
            std::fs::read_to_string(dir.join("series.csv")).unwrap(),
            std::fs::read_to_string(dir.join("events.csv")).unwrap(),
        ));
    }
    let rows = |text: &str| -> Vec<Vec<String>> {
        text.lines()
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect()
    };
    // Every event column but the forces and the energy the viscous stress moves (the drive's
    // work, the viscous sink, the total dissipated and the residual), bit for bit (as text):
    // the film's own books (Landau, resets, stored) are the same.
    let moved = [
        "drive_work",
        "viscous_energy",
        "dissipated_energy",
        "energy_residual",
    ];
    let (events, events_viscous) = (rows(&series[0].1), rows(&series[1].1));
    assert!(events.len() > 2, "no events");
    assert_eq!(events.len(), events_viscous.len());
    for (a, b) in events.iter().zip(&events_viscous) {
        for (j, name) in events[0].iter().enumerate() {
            if !name.starts_with("f_") && !moved.contains(&name.as_str()) {
                assert_eq!(a[j], b[j], "events.csv {name}");
            }
        }
    }
    let (plain, viscous) = (rows(&series[0].0), rows(&series[1].0));
    let header = &plain[0];
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    assert_eq!(plain.len(), viscous.len());
    let couette = eta * 1e-3 * PI * RADIUS_M * RADIUS_M / H0_M;
    let mut worst = 0.0_f64;
    for (a, b) in plain.iter().zip(&viscous).skip(2) {
        for name in ["t", "X", "phi_mean", "eps_mean", "melted_fraction"] {
            assert_eq!(a[col(name)], b[col(name)], "{name} at t = {}", a[0]);
        }
        let f = |r: &Vec<String>| r[col("F")].parse::<f64>().unwrap();
        worst = worst.max(((f(b) - f(a)) / couette - 1.0).abs());
    }
    eprintln!(
        "rigid drive and substrate: F − F(η = 0) against the Couette force, worst {worst:.2e}"
    );
    assert!(worst < 1e-9, "{worst:e}");
}

#[test]
fn zero_viscosity_is_the_papers_film_byte_for_byte() {
    // Through the first event and into the second stick phase: each integrator (adaptive
    // accurate steps), the literal scheme, the one-node contact and the rigid drive.
    let variants: &[&[&str]] = &[
        &["drive.integrator=split"],
        &["drive.integrator=verlet"],
        &["drive.integrator=rk4"],
        &[
            "time.scheme=literal",
            "time.stepping=fixed",
            "time.end=3e-4",
        ],
        &["contact.model=homogeneous"],
        &["contact.substrate=rigid"],
    ];
    for variant in variants {
        let mut base = vec![
            "contact.nodes=40",
            "time.end=7e-4",
            "output.profile_times=[2e-4]",
        ];
        base.extend_from_slice(variant);
        let tmp = tempfile::tempdir().unwrap();
        let mut runs = Vec::new();
        for extra in [
            None,
            Some("lubricant.viscosity=0"),
            Some("lubricant.viscosity=-0.0"),
        ] {
            let mut sets = base.clone();
            sets.extend(extra);
            let s = Scene::from_path(&common::scene("fig2"), &sets).unwrap();
            assert_eq!(s.config.lubricant.viscosity_pa_s.to_bits(), 0);
            let dir = tmp.path().join(format!("run{}", runs.len()));
            let options = DirOptions {
                force: false,
                checkpoint_every_s: 0.0,
            };
            run_to_dir(&s, &dir, &options, &mut Control::default()).unwrap();
            runs.push((s, common::outputs(&dir)));
        }
        let (plain, files) = &runs[0];
        assert!(files.iter().any(|(n, _)| n == "events.csv"));
        for (s, other) in &runs[1..] {
            assert_eq!(s.config, plain.config);
            assert_eq!(s.resolved, plain.resolved);
            assert_eq!(other.len(), files.len());
            for ((name, a), (_, b)) in files.iter().zip(other) {
                assert!(a == b, "{variant:?}: {name} differs with viscosity = 0");
            }
        }
    }
}
