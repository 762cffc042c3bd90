//! Fits of synthetic traces: fig2's scene at N = 30 over 1 ms (four meltings), the trace made
//! by the forward model itself from known parameters plus a known noise; the fit must find
//! them within its 95 % intervals (also the trace misfit with the stamp's position X), its
//! Jacobian must agree with central differences at two step sizes, and fitted.toml must be
//! the fitted model.

use stickslip_run::Scene;
use stickslip_run::scene::ResolvedScene;
use stickslip_studies::fit::forward::{Forward, Run};
use stickslip_studies::fit::misfit::Target;
use stickslip_studies::fit::problem::Problem;
use stickslip_studies::fit::{FitOptions, JacobianKind, MisfitKind, Trace, optimise, parameters};

const TAU_MAX: f64 = 1.15e6;
const GAMMA: f64 = 8.0;
/// σF of the added noise, N (about 1 % of the peak force).
const NOISE: f64 = 1e-5;

fn scene() -> ResolvedScene {
    Scene::from_path(
        &crate::common::scene("fig2"),
        &[
            "contact.nodes=30",
            "time.end=1e-3",
            "output.profile_times=[]",
        ],
    )
    .unwrap()
}

fn params() -> Vec<String> {
    vec![
        "lubricant.tau_max=5e5:2e6".to_string(),
        "lubricant.gamma=3:30".to_string(),
    ]
}

/// The model's trace at the true values, sampled every µs, with deterministic noise of
/// standard deviation NOISE (uniform, from a fixed linear congruential sequence).
fn synthetic(scene: &ResolvedScene) -> Trace {
    let forward = Forward::new(scene, 1e-3).unwrap();
    let truth = scene
        .with_overrides(&[
            format!("lubricant.tau_max={TAU_MAX:e}"),
            format!("lubricant.gamma={GAMMA:e}"),
        ])
        .unwrap();
    let forward = Forward {
        base: truth,
        ..forward
    };
    let Run::Done(curve) = forward.run(&[], &[], None) else {
        panic!("the true model failed")
    };
    let mut state = 12345u64;
    let t: Vec<f64> = (0..1000).map(|i| i as f64 * 1e-6).collect();
    let f = t
        .iter()
        .map(|&t| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            curve.at(t) + (2.0 * u - 1.0) * 3f64.sqrt() * NOISE
        })
        .collect();
    Trace::new(t, f, None).unwrap()
}

#[test]
fn an_event_fit_recovers_known_parameters_within_its_intervals() {
    let scene = scene();
    let trace = synthetic(&scene);
    let out = stickslip_studies::fit::fit(
        &scene,
        trace,
        &params(),
        FitOptions {
            jobs: 2,
            ..FitOptions::default()
        },
    )
    .unwrap();
    let r = &out.report;
    assert_eq!(r.status, "ok");
    assert!(r.data_events.len() >= 3, "{:?}", r.data_events);
    assert_eq!(r.model_events.len(), r.data_events.len());
    for (key, truth) in [("lubricant.tau_max", TAU_MAX), ("lubricant.gamma", GAMMA)] {
        let p = r.parameter(key).unwrap();
        let (lo, hi) = (p.lo95.unwrap(), p.hi95.unwrap());
        assert!(
            lo <= truth && truth <= hi,
            "{key}: {truth} not in [{lo}, {hi}] ({p:?})"
        );
        // An interval that says something: narrower than a factor 1.5 either way.
        assert!(hi / lo < 2.25, "{key}: [{lo}, {hi}]");
    }
    assert!(r.misfit.is_finite() && r.evaluations > 16 && r.failed_runs == 0);
    assert_eq!(r.correlation.len(), 2);
    assert_eq!(r.singular_values.len(), 2);
    // The noise estimated from the data is the noise added.
    assert!((r.noise_n / NOISE - 1.0).abs() < 0.2, "{}", r.noise_n);
    // fit.json reads back through its type, every number with its bits.
    let back = stickslip_studies::fit::report::FitReport::parse(&r.to_json()).unwrap();
    assert_eq!(&back, r);
    // fitted.toml is the scene with the fitted values and the fit's settings.
    let fitted = Scene::from_toml_str(&out.fitted_toml, &[] as &[&str]).unwrap();
    let expected = scene.with_overrides(&r.settings).unwrap();
    assert_eq!(fitted.config, expected.config);
    let tau = r.parameter("lubricant.tau_max").unwrap().value;
    assert_eq!(fitted.config.lubricant.tau_max_pa.to_bits(), tau.to_bits());
    // …and running it gives the fitted model's events.
    let (_, output) =
        stickslip_run::run_in_memory(&fitted, &mut stickslip_run::Control::default()).unwrap();
    assert_eq!(output.events.onsets_s().len(), r.model_events.len());
}

#[test]
fn a_trace_fit_with_the_stamps_position_fits_it_too() {
    // The synthetic trace with the true model's X and noise of 1e-9 m added.
    let scene = scene();
    let trace = synthetic(&scene);
    let forward = Forward::new(&scene, 1e-3).unwrap();
    let truth = scene
        .with_overrides(&[
            format!("lubricant.tau_max={TAU_MAX:e}"),
            format!("lubricant.gamma={GAMMA:e}"),
        ])
        .unwrap();
    let Run::Done(curve) = (Forward {
        base: truth,
        ..forward
    })
    .run(&[], &[], None) else {
        panic!("the true model failed")
    };
    let x: Vec<f64> = trace
        .t_s
        .iter()
        .enumerate()
        .map(|(i, &t)| curve.x_at(t) + if i % 2 == 0 { 1e-9 } else { -1e-9 })
        .collect();
    let n = trace.t_s.len();
    let with_x = Trace::new(trace.t_s, trace.f_n, Some(x)).unwrap();
    let out = stickslip_studies::fit::fit(
        &scene,
        with_x,
        &["lubricant.tau_max=5e5:2e6".to_string()],
        FitOptions {
            misfit: MisfitKind::Trace,
            jobs: 2,
            ..FitOptions::default()
        },
    )
    .unwrap();
    let r = &out.report;
    // One residual per sample for F and one for X; σX estimated near the noise added.
    assert_eq!(r.residuals, 2 * n);
    let sx = r.noise_x_m.unwrap();
    assert!(sx > 3e-10 && sx < 3e-9, "{sx}");
    let p = r.parameter("lubricant.tau_max").unwrap();
    let (lo, hi) = (p.lo95.unwrap(), p.hi95.unwrap());
    assert!(
        lo <= TAU_MAX && TAU_MAX <= hi,
        "{TAU_MAX} not in [{lo}, {hi}]"
    );
}

#[test]
fn the_jacobian_agrees_with_central_differences_at_two_step_sizes() {
    // On the uniform grid: there the events misfit is nearly linear in γ over the step the
    // noise band picks (z ± 0.008). On the default graded grid at N = 30 it is not: central
    // differences at z ± 3e-3 … 3e-4 agree with each other but differ by 6 % from the column
    // at ± 0.008, a truncation error of the noise-driven step that the Jacobians of the
    // discrete solution (internal numerical differentiation) are to remove.
    let scene = scene()
        .with_overrides(&["contact.grid=uniform".to_string()])
        .unwrap();
    let trace = synthetic(&scene);
    let target = Target::new(trace, MisfitKind::Events, None).unwrap();
    let params = parameters(&scene, &params(), MisfitKind::Events, &target.trace).unwrap();
    let forward = Forward::new(&scene, 1e-3).unwrap();
    let mut problem = Problem::new(&forward, &params, &target, 2);
    let z: Vec<f64> = params
        .iter()
        .zip([TAU_MAX, GAMMA])
        .map(|(p, v)| p.z(v))
        .collect();
    let at = problem
        .evaluate_all(std::slice::from_ref(&z), false)
        .unwrap()
        .remove(0);
    let noise = optimise::noise(&mut problem, &at).unwrap();
    let mut steps = vec![optimise::FD_STEP_START; 2];
    let j = optimise::jacobian(&mut problem, &at, &[0, 1], &mut steps, noise, true).unwrap();
    for (k, column) in j.iter().enumerate() {
        let norm = column.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(norm > 0.0, "column {k}");
        for h in [3e-3, 1e-3] {
            let mut pts = vec![z.clone(), z.clone()];
            pts[0][k] -= h;
            pts[1][k] += h;
            let e = problem.evaluate_all(&pts, false).unwrap();
            let central: Vec<f64> = e[1]
                .residuals
                .iter()
                .zip(&e[0].residuals)
                .map(|(b, a)| (b - a) / (2.0 * h))
                .collect();
            let diff = column
                .iter()
                .zip(&central)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(
                diff < 0.05 * norm,
                "column {k}, h = {h}: {diff} against {norm}"
            );
        }
    }
}

#[test]
fn a_scene_that_cuts_the_model_short_is_refused_before_any_run() {
    for (set, key) in [
        ("time.max_events=1", "time.max_events"),
        ("time.max_open_event=1e-4", "time.max_open_event"),
        ("time.until=periodic", "time.until"),
    ] {
        let scene = scene().with_overrides(&[set.to_string()]).unwrap();
        let e = stickslip_studies::fit::refuse_cut_short(&scene).unwrap_err();
        assert!(e.to_string().contains(key), "{set}: {e}");
    }
    assert!(stickslip_studies::fit::refuse_cut_short(&scene()).is_ok());
}

#[test]
fn an_interrupted_fit_keeps_provisional_intervals_from_its_last_jacobian() {
    // Stopped as the final Jacobian at the optimum begins: the local stage's last Jacobian
    // gives the intervals, marked provisional; they are finite and bracket the value.
    let scene = scene();
    let trace = synthetic(&scene);
    let mut stop = |p: &stickslip_studies::fit::Progress| p.stage == "uncertainty";
    let out = stickslip_studies::fit::fit(
        &scene,
        trace,
        &params(),
        FitOptions {
            jobs: 2,
            progress: Some(&mut stop),
            ..FitOptions::default()
        },
    )
    .unwrap();
    let r = &out.report;
    assert_eq!(r.status, "interrupted");
    assert!(r.provisional_intervals);
    for p in &r.parameters {
        let (lo, hi) = (p.lo95.unwrap(), p.hi95.unwrap());
        assert!(lo < p.value && p.value < hi, "{p:?}");
    }
    let back = stickslip_studies::fit::report::FitReport::parse(&r.to_json()).unwrap();
    assert_eq!(&back, r);
}

#[test]
fn a_coarse_fit_states_its_discretisation_error_and_warns_when_it_exceeds_the_statistical() {
    // The h0 = 1 nm contact to just past its first melting, on the paper's uniform grid, whose
    // outermost node makes the first onset converge slowly in N: data from N = 80, fitted for
    // τmax at N = 10. The fitted value is biased by the model's spatial error, which the
    // statistical interval does not hold; the refined run at 2N must report a move of the
    // same order as that bias, and warn.
    let uniform = |nodes: usize| {
        Scene::from_path(
            &crate::common::scene("sfa"),
            &[
                format!("contact.nodes={nodes}"),
                "contact.grid=uniform".to_string(),
                "time.end=0.115".to_string(),
                "output.profile_times=[]".to_string(),
            ],
        )
        .unwrap()
    };
    let truth = uniform(80);
    let forward = Forward::new(&truth, 0.115).unwrap();
    let Run::Done(curve) = forward.run(&[], &[], None) else {
        panic!("the true model failed")
    };
    // Every 20 µs, with a small deterministic noise (1e-7 N, 0.02 % of the peak).
    let t: Vec<f64> = (0..5750).map(|i| i as f64 * 2e-5).collect();
    let f: Vec<f64> = t
        .iter()
        .enumerate()
        .map(|(i, &t)| curve.at(t) + if i % 2 == 0 { 1e-7 } else { -1e-7 })
        .collect();
    let trace = Trace::new(t, f, None).unwrap();
    let tau_true = truth.config.lubricant.tau_max_pa;
    let r = stickslip_studies::fit::fit(
        &uniform(10),
        trace,
        &["lubricant.tau_max=5e5:2e6".to_string()],
        FitOptions {
            jobs: 2,
            ..FitOptions::default()
        },
    )
    .unwrap()
    .report;
    assert_eq!(
        r.discretisation_settings.first().map(String::as_str),
        Some("contact.nodes=20")
    );
    let p = r.parameter("lubricant.tau_max").unwrap();
    let (shift, se) = (p.discretisation.unwrap(), p.stderr.unwrap());
    let bias = (p.value - tau_true).abs();
    println!(
        "N = 10 against data from N = 80: tau_max {} (truth {tau_true}), standard error {se}, \
         discretisation error {shift}",
        p.value
    );
    assert!(
        bias > 3.0 * se,
        "bias {bias} against se {se}: not a biased fit"
    );
    assert!(shift > se, "shift {shift} against se {se}");
    // The move to 2N is part of the way to the converged model: of the bias's order.
    assert!(
        shift > bias / 10.0 && shift < bias * 3.0,
        "shift {shift} against bias {bias}"
    );
    assert!(
        r.warnings
            .iter()
            .any(|w| w.starts_with("lubricant.tau_max: the discretisation error")),
        "{:?}",
        r.warnings
    );
}

#[test]
fn the_profile_strategy_pins_the_first_onset_and_finds_three_known_parameters() {
    // τmax, γ and εmax free: the first onset fixes τmax and εmax together (the film melts
    // where the stress reaches τmax at εmax), the profile strategy solves one of them at
    // every point and scans the widest of the rest; with either kind of Jacobian (the
    // replayed one follows the pin by the implicit function, and needs fewer onset runs to
    // solve the pin: measured 142 against 204).
    let [differences, replayed] =
        [JacobianKind::Differences, JacobianKind::Replay].map(|jacobian| {
            let r = profile_fit(jacobian);
            assert_eq!(r.jacobian, jacobian.name());
            r
        });
    assert!(
        replayed.onset_runs < differences.onset_runs,
        "onset runs {} against {}",
        replayed.onset_runs,
        differences.onset_runs
    );
}

/// The profile strategy's fit of τmax, γ and εmax with `jacobian`, checked.
fn profile_fit(jacobian: JacobianKind) -> stickslip_studies::fit::report::FitReport {
    let scene = scene();
    let trace = synthetic(&scene);
    let mut specs = params();
    specs.push("lubricant.eps_max=0.5:2".into());
    let out = stickslip_studies::fit::fit(
        &scene,
        trace,
        &specs,
        FitOptions {
            jobs: 2,
            strategy: stickslip_studies::fit::Strategy::Profile,
            jacobian,
            ..FitOptions::default()
        },
    )
    .unwrap();
    let r = &out.report;
    eprintln!(
        "profile fit, {} Jacobians: χ² {:.4} in {} runs and {} onset runs",
        r.jacobian, r.misfit, r.evaluations, r.onset_runs
    );
    assert_eq!((r.status.as_str(), r.strategy.as_str()), ("ok", "profile"));
    let scan = r.scan.as_ref().unwrap();
    assert_eq!(scan.values.len(), stickslip_studies::fit::scan::SCAN_POINTS);
    assert!(scan.chi2.iter().all(|c| c.is_finite() && *c >= r.misfit));
    assert!(specs.iter().any(|s| s.starts_with(&scan.pinned)) && scan.key != scan.pinned);
    assert!(r.onset_runs > 0, "no onset runs: the pin was never solved");
    for (key, truth) in [
        ("lubricant.tau_max", TAU_MAX),
        ("lubricant.gamma", GAMMA),
        ("lubricant.eps_max", 1.0),
    ] {
        let p = r.parameter(key).unwrap();
        let (lo, hi) = (p.lo95.unwrap(), p.hi95.unwrap());
        assert!(
            lo <= truth && truth <= hi,
            "{key}: {truth} not in [{lo}, {hi}] ({p:?})"
        );
    }
    let back = stickslip_studies::fit::report::FitReport::parse(&r.to_json()).unwrap();
    assert_eq!(&back, r);
    out.report
}

#[test]
fn the_profile_strategy_is_refused_where_it_does_not_apply() {
    // Two parameters (nothing left to scan once one is pinned), and the trace misfit.
    let scene = scene();
    let trace = synthetic(&scene);
    for (specs, misfit) in [
        (params(), MisfitKind::Events),
        (
            {
                let mut p = params();
                p.push("lubricant.eps_max=0.5:2".into());
                p
            },
            MisfitKind::Trace,
        ),
    ] {
        let err = stickslip_studies::fit::fit(
            &scene,
            trace.clone(),
            &specs,
            FitOptions {
                misfit,
                strategy: stickslip_studies::fit::Strategy::Profile,
                ..FitOptions::default()
            },
        )
        .unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("--strategy") && text.contains("three or more parameters"),
            "{text}"
        );
    }
    assert!(stickslip_studies::fit::Strategy::from_name("scan").is_err());
}

#[test]
fn replayed_jacobians_recover_the_parameters_as_differences_do() {
    // Both misfits, each fitted with both kinds of Jacobian: every interval holds the truth,
    // the two fits' values agree to a tenth of their intervals, fit.json says which Jacobian
    // was made, and the replayed fit takes fewer runs (measured: 114 against 159 for the
    // events misfit, 144 against 221 for the trace's).
    let scene = scene();
    let trace = synthetic(&scene);
    for misfit in [MisfitKind::Events, MisfitKind::Trace] {
        let reports: Vec<_> = [JacobianKind::Differences, JacobianKind::Replay]
            .into_iter()
            .map(|jacobian| {
                let out = stickslip_studies::fit::fit(
                    &scene,
                    trace.clone(),
                    &params(),
                    FitOptions {
                        jobs: 2,
                        misfit,
                        jacobian,
                        ..FitOptions::default()
                    },
                )
                .unwrap();
                let r = out.report;
                assert_eq!(r.status, "ok");
                assert_eq!(r.jacobian, jacobian.name());
                r
            })
            .collect();
        for (key, truth) in [("lubricant.tau_max", TAU_MAX), ("lubricant.gamma", GAMMA)] {
            let [d, r] = [&reports[0], &reports[1]].map(|x| x.parameter(key).unwrap());
            for p in [d, r] {
                let (lo, hi) = (p.lo95.unwrap(), p.hi95.unwrap());
                assert!(
                    lo <= truth && truth <= hi,
                    "{misfit:?}: {key}: {truth} not in [{lo}, {hi}]"
                );
            }
            let half = 0.5 * (d.hi95.unwrap() - d.lo95.unwrap());
            assert!(
                (r.value - d.value).abs() < 0.1 * half,
                "{misfit:?}: {key}: {} against {} (±{half})",
                r.value,
                d.value
            );
        }
        let runs = [reports[0].evaluations, reports[1].evaluations];
        assert!(runs[1] < runs[0], "{misfit:?}: runs {runs:?}");
    }
}

#[test]
fn a_fit_says_why_replayed_jacobians_do_not_apply() {
    // Fixed steps: nothing to replay; the fit makes differences and says why.
    let scene = scene()
        .with_overrides(&["time.stepping=fixed", "time.dt=2e-7"])
        .unwrap();
    let trace = synthetic(&scene);
    let out = stickslip_studies::fit::fit(
        &scene,
        trace,
        &params(),
        FitOptions {
            jobs: 2,
            jacobian: JacobianKind::Replay,
            ..FitOptions::default()
        },
    )
    .unwrap();
    assert_eq!(
        out.report.jacobian,
        "differences (replay asked for; it does not apply: fixed steps)"
    );
    assert!(
        JacobianKind::from_name("adjoint")
            .unwrap_err()
            .to_string()
            .contains("--jacobian")
    );
}
