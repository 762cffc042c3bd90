//! A sweep's spot checks (`[verify]`): the checked points are rerun at 2N and at a tenth of
//! the tolerance once the map is complete, each record equal to a plain run of that point at
//! that resolution; map.json says what changed; a rerun finds them done; adding `[verify]` to
//! a finished sweep runs only the checks.

use crate::common::{run, scene, texts};
use std::path::Path;
use stickslip_studies::sweep::map::MapJson;

/// 4 speeds × 3 values of A0 on the rigid drive at N = 20: regimes of three kinds.
fn sweep_text(verify: &str) -> String {
    format!(
        r#"name = "spot"
scene = "{}"
[set]
"contact.nodes" = 20
"time.max_events" = 6
"time.max_open_event" = 2e-5
"time.end" = 1e-3
[[axis]]
key = "drive.velocity"
range = {{ from = 0.01, to = 3.0, count = 4, scale = "log" }}
[[axis]]
key = "temperature.A0"
values = [-1e5, 5e5, 1.5e6]
{verify}"#,
        scene("rigid").display()
    )
}

fn sweep_run(file: &Path, dir: &Path) -> (String, String) {
    let out = run(&[
        "sweep",
        "run",
        file.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--quiet",
        "--jobs",
        "2",
    ]);
    let (stdout, stderr) = texts(&out);
    assert!(out.status.success(), "{stderr}");
    (stdout, stderr)
}

/// run.json's summary of the rigid scene with the sweep's settings, the point's values and
/// `extra`.
fn plain_summary(values: &[toml::Value], extra: &str) -> serde_json::Value {
    let tmp = tempfile::tempdir().unwrap();
    let rigid = scene("rigid");
    let sets = [
        "contact.nodes=20".to_string(),
        "time.max_events=6".into(),
        "time.max_open_event=2e-5".into(),
        "time.end=1e-3".into(),
        format!("drive.velocity={}", values[0]),
        format!("temperature.A0={}", values[1]),
        extra.into(),
    ];
    let mut args = vec![
        "run",
        rigid.to_str().unwrap(),
        "--out",
        tmp.path().to_str().unwrap(),
        "--quiet",
    ];
    for s in &sets {
        args.extend(["--set", s.as_str()]);
    }
    let out = run(&args);
    assert!(out.status.success(), "{}", texts(&out).1);
    let info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("run.json")).unwrap())
            .unwrap();
    info["summary"].clone()
}

#[test]
fn spot_checks_rerun_the_sample_and_the_boundaries_at_a_finer_resolution() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("spot.toml");
    std::fs::write(&file, sweep_text("[verify]\npoints = 3\n")).unwrap();
    let dir = tmp.path().join("out");
    let (stdout, _) = sweep_run(&file, &dir);
    assert!(stdout.contains("spot checks: "), "{stdout}");
    let map = MapJson::read(&dir).unwrap();
    let spot = map.spot_checks.as_ref().expect("map.json has spot_checks");
    assert!(spot.sampled >= 3 && spot.at_boundaries >= 2, "{spot:?}");
    assert_eq!(spot.checked, spot.checks.len());
    assert_eq!(
        spot.changed,
        spot.checks.iter().filter(|c| c.changed).count()
    );
    for c in &spot.checks {
        assert_eq!(c.runs.len(), 2, "2N and tolerance/10: {c:?}");
        let row = map.table.rows.iter().find(|r| r.point == c.point).unwrap();
        assert_eq!(c.regime, row.summary.regime.name());
        let changed = c.runs.iter().any(|r| r.summary.regime.name() != c.regime);
        assert_eq!(c.changed, changed, "{c:?}");
        assert!(
            dir.join("checks")
                .join(format!("{:07}.json", c.point))
                .is_file()
        );
    }
    // A check is the point's own run at that resolution, bit for bit.
    let c = &spot.checks[0];
    let two_n = plain_summary(&c.values, "contact.nodes=40");
    assert_eq!(
        two_n["t_first_onset"].as_f64(),
        c.runs[0].summary.t_first_onset,
        "{c:?}"
    );
    assert_eq!(
        two_n["regime"].as_str(),
        Some(c.runs[0].summary.regime.name())
    );
    let tol = plain_summary(&c.values, "time.tolerance=5e-6");
    assert_eq!(tol["f_mean"].as_f64(), c.runs[1].summary.f_mean, "{c:?}");
    // A rerun finds every check done; plot still draws the map.
    let (again, _) = sweep_run(&file, &dir);
    assert!(
        again.contains(&format!("{} found done", spot.checked)),
        "{again}"
    );
    let plot = run(&["sweep", "plot", dir.to_str().unwrap()]);
    assert!(plot.status.success(), "{}", texts(&plot).1);
}

#[test]
fn adding_verify_to_a_finished_sweep_runs_only_the_checks() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("spot.toml");
    std::fs::write(&file, sweep_text("")).unwrap();
    let dir = tmp.path().join("out");
    let (first, _) = sweep_run(&file, &dir);
    assert!(!first.contains("spot checks"), "{first}");
    assert!(MapJson::read(&dir).unwrap().spot_checks.is_none());
    std::fs::write(
        &file,
        sweep_text("[verify]\nsample = 0.25\nboundaries = false\n"),
    )
    .unwrap();
    let (second, _) = sweep_run(&file, &dir);
    assert!(second.contains("0 points run"), "{second}");
    let spot = MapJson::read(&dir).unwrap().spot_checks.unwrap();
    assert_eq!((spot.checked, spot.at_boundaries), (3, 0), "{spot:?}");
}
