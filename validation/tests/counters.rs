//! Snapshots of the work runs do: steps accepted, rejected, forced and retaken, step
//! evaluations and coupling iterations, for fig2 (N = 200) and the h0 = 1 nm contact of
//! `scenes/sfa.toml` (N = 100), each at two tolerances. Every performance change moves these
//! counters, so a change shows in review as a changed snapshot; the test command runs with
//! `INSTA_UPDATE=no`, which fails on any difference and writes nothing.

use std::path::Path;
use stickslip_run::{Control, RunStatus, Scene, run_in_memory};

/// The counters of `scene` (a file under `scenes/`) with `overrides`, as a JSON object.
fn counters(scene: &str, overrides: &[String]) -> serde_json::Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(scene);
    let scene = Scene::from_path(&path, overrides).expect("the scene resolves");
    let (outcome, _) = run_in_memory(&scene, &mut Control::default()).expect("the run starts");
    assert_eq!(outcome.status(), RunStatus::Ok, "{:?}", outcome.failure);
    let c = outcome.counts;
    serde_json::json!({
        "accepted": c.accepted_steps,
        "rejected": c.rejected_steps,
        "forced": c.forced_steps,
        "onset_retakes": c.onset_retakes,
        "evaluations": c.accepted_steps + c.rejected_steps + c.onset_retakes,
        "coupling_iterations": c.coupling_iterations,
        "events": outcome.events.len(),
    })
}

/// The counters at each tolerance, keyed by it.
fn at_tolerances(scene: &str, common: &[&str], tolerances: &[&str]) -> serde_json::Value {
    let mut out = serde_json::Map::new();
    for tol in tolerances {
        let mut overrides: Vec<String> = common.iter().map(|s| (*s).to_string()).collect();
        overrides.push(format!("time.tolerance={tol}"));
        out.insert(format!("tolerance {tol}"), counters(scene, &overrides));
    }
    serde_json::Value::Object(out)
}

#[test]
fn fig2_counters_snapshot() {
    // fig2 at N = 200 (the paper's time window, 0 → 1.3 ms), at the default tolerance and a
    // tenth of it.
    let counts = at_tolerances("fig2.toml", &["contact.nodes=200"], &["5e-5", "5e-6"]);
    insta::assert_json_snapshot!("counters_fig2_n200", counts);
}

#[test]
fn sfa_counters_snapshot() {
    // The h0 = 1 nm contact at N = 100, 0 → 0.11 s (its first melting), at the default
    // tolerance and a tenth of it.
    let counts = at_tolerances("sfa.toml", &["contact.nodes=100"], &["5e-5", "5e-6"]);
    insta::assert_json_snapshot!("counters_sfa_n100", counts);
}
