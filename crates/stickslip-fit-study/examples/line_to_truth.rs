//! The first slip's misfit on the straight line (in the box) from a point to the truth, with one
//! parameter solved at each point so that the first onset matches (the profile strategy's pin):
//! whether a fit's end point and the truth share a basin, or a ridge separates them.
//!
//! `cargo run --release -p stickslip-fit-study --example line_to_truth -- SEED LEVEL STEPS
//! VALUES` with VALUES the point's τmax, γ, h0 and G* (comma-separated, SI units), LEVEL the
//! runs' tolerance level (their tolerance is the fit's first one / 10^LEVEL) and STEPS the
//! intervals of the line. The pinned parameter is h0. Prints χ² and the parameters at each
//! point.

use stickslip_fit_study::{cases, prepared::prepare};
use stickslip_studies::fit::forward::Forward;
use stickslip_studies::fit::misfit::Target;
use stickslip_studies::fit::pin::Pin;
use stickslip_studies::fit::problem::Problem;
use stickslip_studies::fit::{MisfitKind, parameters};

/// The pinned parameter's index among the case's (τmax, γ, h0, G*).
const PINNED: usize = 2;
/// The relative move of each parameter for the first onset's gradient at the truth.
const GRADIENT_STEP: f64 = 3e-3;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: line_to_truth SEED LEVEL STEPS TAU_MAX,GAMMA,H0,G_EFF";
    let [seed, level, steps, values] = args.as_slice() else {
        return Err(usage.into());
    };
    let seed: u64 = seed
        .parse()
        .map_err(|_| format!("SEED = {seed}: {usage}"))?;
    let level: u32 = level
        .parse()
        .map_err(|_| format!("LEVEL = {level}: {usage}"))?;
    let steps: usize = steps
        .parse()
        .ok()
        .filter(|&n| n >= 1)
        .ok_or(format!("STEPS = {steps}: a whole number ≥ 1"))?;
    let from: Vec<f64> = values
        .split(',')
        .map(|v| {
            v.parse()
                .map_err(|_| format!("VALUES: {v} is not a number"))
        })
        .collect::<Result<_, String>>()?;
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let p = prepare(&root, cases::first_slip(&cases::Sizes::full()))?;
    let trace = p.trace(p.case.samples, seed)?;
    let target =
        Target::new(trace, MisfitKind::Events, Some(p.case.noise_n)).map_err(|e| e.to_string())?;
    let params = parameters(&p.scene, &p.case.params, MisfitKind::Events, &target.trace)
        .map_err(|e| e.to_string())?;
    if from.len() != params.len() {
        return Err(format!(
            "VALUES: {} numbers, {} wanted",
            from.len(),
            params.len()
        ));
    }
    let t_end = *target.trace.t_s.last().ok_or("an empty trace")?;
    let forward = Forward::new(&p.scene, t_end).map_err(|e| e.to_string())?;
    let mut problem = Problem::new(&forward, &params, &target, 2);
    let truth: Vec<f64> = params
        .iter()
        .map(|q| p.case.true_value(&q.key).map(|v| q.z(v)))
        .collect::<Option<_>>()
        .ok_or("a parameter without a true value")?;
    // The first onset's gradient at the truth, for the pin's first trials.
    let mut moved = Vec::new();
    for (k, q) in params.iter().enumerate() {
        for f in [-GRADIENT_STEP, GRADIENT_STEP] {
            let mut z = truth.clone();
            z[k] = q.z(q.value(truth[k]) * (1.0 + f));
            moved.push(z);
        }
    }
    let at_moved = problem.evaluate_all(&moved, false).ok_or("interrupted")?;
    let at_truth = problem
        .evaluate_all(std::slice::from_ref(&truth), false)
        .and_then(|mut e| e.pop())
        .ok_or("interrupted")?;
    let gradient: Vec<f64> = (0..params.len())
        .map(|k| {
            (at_moved[2 * k + 1].residuals[0] - at_moved[2 * k].residuals[0])
                / (moved[2 * k + 1][k] - moved[2 * k][k])
        })
        .collect();
    problem.level = level;
    problem.pin = Some(Pin {
        k: PINNED,
        slope: gradient[PINNED],
        gradient,
        anchor: truth.clone(),
        anchor_residual: at_truth.residuals[0],
        tolerance: stickslip_studies::fit::pin::ONSET_TOLERANCE,
    });
    let a: Vec<f64> = params.iter().zip(&from).map(|(q, v)| q.z(*v)).collect();
    let line: Vec<Vec<f64>> = (0..=steps)
        .map(|i| {
            let s = i as f64 / steps as f64;
            a.iter().zip(&truth).map(|(x, y)| x + s * (y - x)).collect()
        })
        .collect();
    let evals = problem.evaluate_all(&line, false).ok_or("interrupted")?;
    println!(
        "seed {seed}, level {level}: χ² from the point (s = 0) to the truth (s = 1), h0 solved"
    );
    for (i, e) in evals.iter().enumerate() {
        let values: Vec<String> = params
            .iter()
            .zip(&e.z)
            .map(|(q, z)| format!("{} {:.5e}", q.key, q.value(*z)))
            .collect();
        println!(
            "s {:.3}: χ² {:.4e}, first onset {:+.2} σ; {}",
            i as f64 / steps as f64,
            e.chi2,
            e.residuals[0],
            values.join(", ")
        );
    }
    Ok(())
}
