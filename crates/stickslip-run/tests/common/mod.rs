//! Helpers shared by the run library's integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// Path of a scene in validation/scenes.
pub fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../validation/scenes")
        .join(format!("{name}.toml"))
}

/// Every output file of a run written to `dir` (run.json without its wall time).
pub fn outputs(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            let mut bytes = std::fs::read(&path).unwrap();
            if name == "run.json" {
                let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
                v.as_object_mut().unwrap().remove("wall_seconds");
                bytes = serde_json::to_vec_pretty(&v).unwrap();
            }
            (name, bytes)
        })
        .collect();
    files.sort();
    files
}

/// The h0 = 1 nm contact's first slip (sfa.toml at N = 100, h0 = 1.2 nm, G* = 1.3 GPa, 11
/// meltings to 0.16 s; the fit study's first-slip case) with `extra` settings, in memory.
pub fn sfa_first_slip(extra: &[&str]) -> stickslip_run::RunOutcome {
    let mut sets = vec![
        "contact.nodes=100",
        "contact.film_thickness=1.2e-9",
        "contact.g_eff=1.3e9",
        "time.end=0.16",
        "output.profile_times=[]",
        "output.series_interval=1e-3",
    ];
    sets.extend_from_slice(extra);
    let scene = stickslip_run::Scene::from_path(&scene("sfa"), &sets).unwrap();
    stickslip_run::run(
        &scene,
        &mut stickslip_run::driver::NullSink,
        &mut stickslip_run::driver::Control::default(),
    )
    .unwrap()
}

/// Asserts that two runs of the same scene melt the same nodes in every event (as many events,
/// each with the same largest melted fraction, a sum of the melted nodes' areas that is equal
/// to the bit when the same nodes melt) and returns the largest |onset shift| between them, s.
pub fn same_meltings_largest_onset_shift(
    a: &stickslip_run::RunOutcome,
    b: &stickslip_run::RunOutcome,
) -> f64 {
    assert_eq!(a.events.len(), b.events.len());
    let mut largest_shift = 0.0_f64;
    for (x, y) in a.events.iter().zip(&b.events) {
        assert_eq!(
            x.max_melted_fraction, y.max_melted_fraction,
            "event {}",
            x.k
        );
        largest_shift = largest_shift.max((x.t_onset_s - y.t_onset_s).abs());
    }
    largest_shift
}

/// Checks a key of the adaptive step only on sfa.toml: `key=value` with fixed steps is refused
/// naming the key and adaptive steps, and `key=bad` is refused naming the key as given;
/// returns the second error, for the caller's checks of the range it states.
pub fn refused_adaptive_only_key(key: &str, value: &str, bad: &str) -> String {
    let fixed = format!("{key}={value}");
    let err = stickslip_run::Scene::from_path(&scene("sfa"), &["time.stepping=fixed", &fixed])
        .unwrap_err()
        .to_string();
    assert!(err.contains(key), "{err}");
    assert!(err.contains("adaptive"), "{err}");
    let out_of_range = format!("{key}={bad}");
    let err = stickslip_run::Scene::from_path(&scene("sfa"), &[out_of_range.as_str()])
        .unwrap_err()
        .to_string();
    assert!(err.contains(&format!("{key} = {bad}")), "{err}");
    err
}

/// A run's step attempts: accepted, rejected and retaken at an onset.
pub fn attempts(o: &stickslip_run::RunOutcome) -> u64 {
    o.counts.accepted_steps + o.counts.rejected_steps + o.counts.onset_retakes
}
