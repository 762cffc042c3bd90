//! The committed `reports/summary.json` against the code, at reduced size: fig2 at N = 30,
//! fixed Δt = 2e-8 s, end = 1 ms — `validation/scenes/fig2.toml` with
//! `reduced::cli_overrides()` — run here in-process with the run library's one driver loop
//! (`stickslip_run::run_in_memory`), while `cargo xtask validate` ran the same through the
//! `stickslip` binary; both go through the same `reduced::features`. So this test fails when
//! the reports are stale, and also when the command line stops recording what the run library
//! computes. Plus an insta snapshot of the same qualitative features (event count, onsets to
//! 0.1 µs, first radii, step count, verdicts).

use std::path::Path;
use std::sync::OnceLock;
use stickslip_run::{Control, RunStatus, Scene, run_in_memory};
use stickslip_validation::reduced::{Features, cli_overrides, features};

fn fresh() -> &'static Features {
    static FEATURES: OnceLock<Features> = OnceLock::new();
    FEATURES.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/fig2.toml");
        let scene = Scene::from_path(&path, &cli_overrides()).expect("the reduced scene resolves");
        let (outcome, output) =
            run_in_memory(&scene, &mut Control::default()).expect("the reduced run starts");
        assert_eq!(outcome.status(), RunStatus::Ok, "{:?}", outcome.failure);
        features(&output)
    })
}

#[test]
fn committed_summary_matches_the_code_at_reduced_size() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../reports/summary.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; the reports are generated: run `cargo xtask validate`",
            path.display()
        )
    });
    let summary: serde_json::Value = serde_json::from_str(&text).expect("summary.json is JSON");
    let committed: Features = serde_json::from_value(summary["reduced"].clone())
        .expect("summary.json has a `reduced` block: run `cargo xtask validate`");
    assert_eq!(
        fresh(),
        &committed,
        "reports/summary.json is stale: the run library now gives different reduced-size \
         results than the committed reports (or the CLI recorded something else than the run \
         library computes). Run `cargo xtask validate` and commit reports/."
    );
}

#[test]
fn reduced_fig2_features_snapshot() {
    insta::assert_json_snapshot!("reduced_fig2", fresh());
}
