//! The first onset's error over a set of contacts rather than one scene: the h0 = 1 nm contact
//! (`validation/scenes/sfa.toml` on the uniform grid) at K = 500 N/m and N = 50, 100, 150, 200,
//! 300, and at K = 300 and 1000 N/m with N = 100 and 200. Each is run to its first melting with
//! any `section.key=value` settings given as arguments, and against the same contact at
//! `time.tolerance` = 5e-8 at the same N, so each error is the time stepping's alone (N's own
//! error is `stickslip verify`'s space direction); the example prints each error, their
//! geometric mean and the
//! evaluations (docs/model.md, "An onset after a long stick": a single contact's onset error is
//! one draw from a wide spread, so settings are compared over the set), e.g.
//!
//! `cargo run --release -p stickslip-convergence --example onset_spread -- time.tolerance=5e-6`

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use stickslip_run::keys::words::GridChoice;
use stickslip_run::keys::{contact, drive, output, time};
use stickslip_run::{ResolvedScene, RunOutcome, Scene};

/// (K in N/m, N) of the set.
const CONTACTS: [(f64, usize); 9] = [
    (500.0, 50),
    (500.0, 100),
    (500.0, 150),
    (500.0, 200),
    (500.0, 300),
    (300.0, 100),
    (300.0, 200),
    (1000.0, 100),
    (1000.0, 200),
];

/// The reference's `time.tolerance`.
const REFERENCE_TOLERANCE: f64 = 5e-8;

/// `time.end`, s: past every contact's first melting (the latest, K = 300 N/m, at 1.64 s).
const END_S: f64 = 3.0;

/// The contact (K, N) resolved with `extra` settings, to its first melting.
fn contact_scene(
    scene: &Path,
    (k, n): (f64, usize),
    extra: &[String],
) -> Result<ResolvedScene, String> {
    let mut sets = vec![
        drive::STIFFNESS.set(k).to_string(),
        contact::NODES.set(n as i64).to_string(),
        contact::GRID.set(GridChoice::Uniform).to_string(),
        time::END.set(END_S).to_string(),
        time::MAX_EVENTS.set(1).to_string(),
        output::PROFILE_TIMES.set(Vec::new()).to_string(),
        output::SERIES_INTERVAL.set(1e-3).to_string(),
    ];
    sets.extend_from_slice(extra);
    Scene::from_path(scene, &sets).map_err(|e| e.to_string())
}

/// The run of `scene` (contact `(k, n)`) and its first melting's onset, s.
fn first_onset(scene: &ResolvedScene, (k, n): (f64, usize)) -> Result<(RunOutcome, f64), String> {
    let outcome = stickslip_run::run(
        scene,
        &mut stickslip_run::driver::NullSink,
        &mut stickslip_run::driver::Control::default(),
    )
    .map_err(|e| e.to_string())?;
    match outcome.events.first().map(|e| e.t_onset_s) {
        Some(t) => Ok((outcome, t)),
        None => Err(format!(
            "K = {k} N/m, N = {n}: no melting by time.end = {END_S} s"
        )),
    }
}

fn main() -> ExitCode {
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../validation/scenes/sfa.toml");
    let extra: Vec<String> = std::env::args().skip(1).collect();
    let reference_sets = vec![time::TOLERANCE.set(REFERENCE_TOLERANCE).to_string()];
    // Every scene resolved before any run: a bad setting is refused before the computing.
    let scenes: Result<Vec<_>, String> = CONTACTS
        .iter()
        .map(|&c| {
            Ok((
                c,
                contact_scene(&scene, c, &extra)?,
                contact_scene(&scene, c, &reference_sets)?,
            ))
        })
        .collect();
    let scenes = match scenes {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!(
        "The first onset with [{}] against time.tolerance = {REFERENCE_TOLERANCE} at the same N \
         (the time stepping's error alone; N's own is `stickslip verify`'s space direction):\n",
        extra.join(", ")
    );
    println!("| K, N/m | N | reference onset, s | error, µs | evaluations |");
    println!("|---|---|---|---|---|");
    let (mut log_sum, mut evaluations) = (0.0, 0_u64);
    for (contact, run_scene, reference_scene) in &scenes {
        let pair = first_onset(run_scene, *contact)
            .and_then(|run| Ok((run, first_onset(reference_scene, *contact)?)));
        let ((run, t_run), (_, t_ref)) = match pair {
            Ok(pair) => pair,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
        };
        let error_us = (t_run - t_ref).abs() * 1e6;
        let c = &run.counts;
        let n_eval = c.accepted_steps + c.rejected_steps + c.onset_retakes;
        log_sum += error_us.max(1e-6).ln();
        evaluations += n_eval;
        println!(
            "| {} | {} | {t_ref:.9} | {error_us:.2} | {n_eval} |",
            contact.0, contact.1
        );
    }
    let mean = (log_sum / CONTACTS.len() as f64).exp();
    println!("\ngeometric mean of the errors {mean:.1} µs; {evaluations} evaluations in all");
    ExitCode::SUCCESS
}
