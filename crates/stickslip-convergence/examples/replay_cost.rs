//! What a replayed Jacobian column costs against a run (docs/fit.md, "Replayed Jacobians"):
//! the fit study's first-slip case (the SFA contact at N = 100 with h0 = 1.2 nm and G* =
//! 1.3 GPa, τmax = 1.15 MPa, γ = 8, to 0.1522 s at the fit's tolerance, the scene's / 100)
//! run with its steps recorded, then replayed with γ moved by 1e-6 of itself; medians of
//! three of each.
//!
//! `cargo run --release -p stickslip-convergence --example replay_cost`

use std::path::PathBuf;
use std::time::Instant;
use stickslip_run::keys::{contact, lubricant, output, time};
use stickslip_run::{Control, NullSink, ResolvedScene, Scene, StepPlan};

fn scene(gamma: f64) -> ResolvedScene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../validation/scenes/sfa.toml");
    let sets = [
        contact::NODES.set(100).to_string(),
        contact::FILM_THICKNESS.set(1.2e-9).to_string(),
        contact::G_EFF.set(1.3e9).to_string(),
        lubricant::TAU_MAX.set(1.15e6).to_string(),
        lubricant::GAMMA.set(gamma).to_string(),
        time::END.set(0.1522).to_string(),
        time::TOLERANCE.set(5e-7).to_string(),
        output::PROFILE_TIMES.set(Vec::new()).to_string(),
    ];
    Scene::from_path(&path, &sets).expect("the first-slip scene")
}

/// Wall time of a run of `scene` with `plan`, s.
fn timed(scene: &ResolvedScene, plan: Option<StepPlan<'_>>) -> f64 {
    let started = Instant::now();
    let mut control = Control {
        plan,
        ..Control::default()
    };
    stickslip_run::run(scene, &mut NullSink, &mut control).expect("the run");
    started.elapsed().as_secs_f64()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let base = scene(8.0);
    let moved = scene(8.0 * (1.0 + 1e-6));
    let mut plan = Vec::new();
    timed(&base, Some(StepPlan::Record(&mut plan)));
    let run_s = median((0..3).map(|_| timed(&base, None)).collect());
    let replay_s = median(
        (0..3)
            .map(|_| {
                timed(
                    &moved,
                    Some(StepPlan::Replay {
                        steps: &plan,
                        next: 0,
                    }),
                )
            })
            .collect(),
    );
    let ratio = replay_s / run_s;
    println!(
        "the first slip at N = 100: a run {run_s:.3} s ({} accepted steps), a replay at γ·(1 + \
         1e-6) {replay_s:.3} s: {ratio:.2} of a run; a Jacobian of p columns costs p·{ratio:.2} \
         runs (4 parameters: {:.2})",
        plan.len(),
        4.0 * ratio
    );
}
