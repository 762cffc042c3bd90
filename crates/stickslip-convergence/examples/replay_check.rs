//! The replayed derivative against tight central differences on every free parameter of the
//! fit study's cases (docs/fit.md, "Replayed Jacobians"): fig2's set A (τmax, γ) and the h0 =
//! 1 nm contact up to its second melting (τmax, γ, h0, G* at the first-slip case's truth, N =
//! 30). F at the samples, per column: central differences at tolerances 5e-11 and 5e-12 with
//! steps 3e-6 to 1e-4 of the value, and where those four agree within 1e-6 of the column's
//! norm, the largest distance of the replayed forward difference (step 1e-6) at tolerances
//! 5e-7 (the fit's, the scenes' / 100) down to 5e-10, relative to the column's norm. `ONLY=KEY`
//! checks the keys containing KEY alone.
//!
//! `cargo run --release -p stickslip-convergence --example replay_check`

use std::path::PathBuf;
use stickslip_core::sim::Simulation;
use stickslip_run::keys::{Key, contact, lubricant, output, time};
use stickslip_run::{Control, NullSink, ResolvedScene, Scene, StepPlan};
use stickslip_studies::fit::misfit::ModelCurve;

/// One case: its scene file, fixed settings, window end and sample spacing, s, and its free
/// keys at their values.
struct Case {
    scene: &'static str,
    settings: Vec<String>,
    end_s: f64,
    spacing_s: f64,
    keys: Vec<(Key<f64>, f64)>,
}

/// Set A and the thin film's first meltings, at the fit study's truths.
fn cases() -> [Case; 2] {
    let tau_gamma = [(lubricant::TAU_MAX, 1.15e6), (lubricant::GAMMA, 8.0)];
    let set = |keys: &[(Key<f64>, f64)]| -> Vec<String> {
        keys.iter().map(|(k, v)| k.set(*v).to_string()).collect()
    };
    let mut sfa_keys = tau_gamma.to_vec();
    sfa_keys.extend([(contact::FILM_THICKNESS, 1.2e-9), (contact::G_EFF, 1.3e9)]);
    let mut sfa_settings = set(&sfa_keys);
    sfa_settings.push(contact::NODES.set(30).to_string());
    let mut fig2_settings = set(&tau_gamma);
    fig2_settings.push(contact::NODES.set(100).to_string());
    [
        Case {
            scene: "fig2.toml",
            settings: fig2_settings,
            end_s: 1.3e-3,
            spacing_s: 2e-6,
            keys: tau_gamma.to_vec(),
        },
        Case {
            scene: "sfa.toml",
            settings: sfa_settings,
            end_s: 0.16,
            spacing_s: 1e-6,
            keys: sfa_keys,
        },
    ]
}

/// F per step of a run of `scene`, stepping as `plan` says.
fn trace(scene: &ResolvedScene, plan: Option<StepPlan<'_>>) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (mut t, mut f) = (vec![0.0], vec![0.0]);
    let mut observe = |sim: &Simulation| {
        t.push(sim.time_s());
        f.push(sim.state().physical.force_n);
    };
    let mut control = Control {
        observer: Some(&mut observe),
        plan,
        ..Control::default()
    };
    let out = stickslip_run::run(scene, &mut NullSink, &mut control).expect("the run");
    let onsets = out.events.iter().map(|e| e.t_onset_s).collect();
    (t, f, onsets)
}

/// F at `times` from the steps `t`, `f`, as the fit takes it (`ModelCurve::at`).
fn at(t: &[f64], f: &[f64], times: &[f64]) -> Vec<f64> {
    let curve = ModelCurve {
        t_s: t.to_vec(),
        f_n: f.to_vec(),
        x_m: Vec::new(),
    };
    times.iter().map(|&x| curve.at(x)).collect()
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|a| a * a).sum::<f64>().sqrt()
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../validation/scenes");
    for case in &cases() {
        let scene = |extra: &[String]| {
            let mut sets = case.settings.clone();
            sets.push(output::PROFILE_TIMES.set(Vec::new()).to_string());
            sets.extend_from_slice(extra);
            Scene::from_path(&root.join(case.scene), &sets).expect("the scene")
        };
        // The window: to the case's end, or 1 ms after the second onset.
        let (_, _, onsets) = trace(
            &scene(&[
                time::END.set(case.end_s).to_string(),
                time::MAX_EVENTS.set(2).to_string(),
            ]),
            None,
        );
        let end_s = onsets
            .get(1)
            .map_or(case.end_s, |o| (o + 1e-3).min(case.end_s));
        let times: Vec<f64> = (1..)
            .map(|k| f64::from(k) * case.spacing_s)
            .take_while(|&x| x < end_s)
            .collect();
        println!(
            "{}: {} samples to {end_s:.6} s, onsets {onsets:?}",
            case.scene,
            times.len()
        );
        let only = std::env::var("ONLY").unwrap_or_default();
        for &(key, value) in case
            .keys
            .iter()
            .filter(|(k, _)| k.path.contains(only.as_str()))
        {
            let at_value = |v: f64, tol: f64| {
                scene(&[
                    time::END.set(end_s).to_string(),
                    time::TOLERANCE.set(tol).to_string(),
                    key.set(v).to_string(),
                ])
            };
            let central = |tol: f64, d: f64| -> Vec<f64> {
                let (tp, fp, _) = trace(&at_value(value * (1.0 + d), tol), None);
                let (tm, fm, _) = trace(&at_value(value * (1.0 - d), tol), None);
                at(&tp, &fp, &times)
                    .iter()
                    .zip(at(&tm, &fm, &times))
                    .map(|(a, b)| (a - b) / (2.0 * d))
                    .collect()
            };
            let replayed = |tol: f64, d: f64| -> Vec<f64> {
                let mut plan = Vec::new();
                let (t0, f0, _) = trace(&at_value(value, tol), Some(StepPlan::Record(&mut plan)));
                let (t1, f1, _) = trace(
                    &at_value(value * (1.0 + d), tol),
                    Some(StepPlan::Replay {
                        steps: &plan,
                        next: 0,
                    }),
                );
                at(&t1, &f1, &times)
                    .iter()
                    .zip(at(&t0, &f0, &times))
                    .map(|(a, b)| (a - b) / d)
                    .collect()
            };
            let refs = [
                central(5e-12, 1e-5),
                central(5e-12, 3e-6),
                central(5e-11, 1e-5),
                central(5e-12, 1e-4),
            ];
            let scale = norm(&refs[0]);
            let compare = |j: &[f64]| {
                let (mut n, mut worst, mut where_s) = (0, 0.0_f64, 0.0);
                for (k, x) in j.iter().enumerate() {
                    let (lo, hi) = refs
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
                            (l.min(r[k]), h.max(r[k]))
                        });
                    let off = (x - 0.5 * (lo + hi)).abs() / scale;
                    if hi - lo <= 1e-6 * scale && off > worst {
                        (worst, where_s) = (off, times[k]);
                    }
                    n += usize::from(hi - lo <= 1e-6 * scale);
                }
                (n, worst, where_s)
            };
            let mut line = String::new();
            let mut agree = 0;
            for tol in [5e-7, 5e-8, 5e-9, 5e-10] {
                let (n, worst, at_s) = compare(&replayed(tol, 1e-6));
                agree = n;
                line += &format!(" {worst:.2e} at tolerance {tol:e} (worst at t = {at_s:.7} s);");
            }
            println!(
                "  {}: {agree} of {} samples where the references agree; replayed within{line}",
                key.path,
                times.len()
            );
        }
    }
}
