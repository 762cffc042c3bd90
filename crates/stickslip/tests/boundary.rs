//! `stickslip boundary`: the critical speed of the rigid drive bracketed and bisected, checked
//! against runs on both sides of it; bad calls exit 2 naming what is wrong.

use crate::common::{run, scene, texts};

const SETS: [&str; 8] = [
    "--set",
    "contact.nodes=50",
    "--set",
    "time.max_events=6",
    "--set",
    "time.max_open_event=2e-5",
    "--set",
    "temperature.A0=1e6",
];

fn boundary(extra: &[&str]) -> std::process::Output {
    let rigid = scene("rigid");
    let mut args = vec!["boundary", rigid.to_str().unwrap()];
    args.extend(SETS);
    args.extend(extra);
    run(&args)
}

/// The regime `stickslip run` reports at drive.velocity = v (run.json's summary).
fn regime_at(v: f64) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let rigid = scene("rigid");
    let set = format!("drive.velocity={v:e}");
    let mut args = vec![
        "run",
        rigid.to_str().unwrap(),
        "--out",
        tmp.path().to_str().unwrap(),
        "--quiet",
        "--set",
        &set,
    ];
    args.extend(SETS);
    let out = run(&args);
    assert!(out.status.success(), "{}", texts(&out).1);
    let info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("run.json")).unwrap())
            .unwrap();
    info["summary"]["regime"].as_str().unwrap().to_string()
}

#[test]
fn the_critical_speed_is_bracketed_to_the_tolerance_in_few_runs() {
    let out = boundary(&[
        "--key",
        "drive.velocity",
        "--from",
        "0.01",
        "--to",
        "3",
        "--quiet",
    ]);
    let (stdout, stderr) = texts(&out);
    assert!(out.status.success(), "{stderr}");
    // drive.velocity = 2.32605e-1 (bracket a … b, rtol 0.001)
    let first = stdout.lines().next().unwrap();
    let num = |s: &str| s.trim().parse::<f64>().unwrap();
    let value = num(first.split('=').nth(1).unwrap().split('(').next().unwrap());
    let bracket = first
        .split("bracket ")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap();
    let (lo, hi) = bracket.split_once('…').unwrap();
    let (lo, hi) = (num(lo), num(hi));
    assert!(
        lo < value && value < hi && (hi - lo) <= 1e-3 * hi * 1.0001,
        "{first}"
    );
    let runs: usize = stdout
        .split(" runs")
        .next()
        .unwrap()
        .rsplit(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(runs <= 20, "{runs} runs: {stdout}");
    assert!(
        stdout.contains("below: stick_slip") && stdout.contains("above: partial"),
        "{stdout}"
    );
    // Independently: plain runs a little either side give the two regimes.
    assert_eq!(regime_at(value * 0.99), "stick_slip");
    assert_eq!(regime_at(value * 1.01), "partial");
}

#[test]
fn bad_calls_exit_2_and_say_why() {
    let cases: [(&[&str], &str); 5] = [
        (
            &["--key", "drive.velocity", "--from", "0.01", "--to", "0.02"],
            "both give the regime stick_slip",
        ),
        (
            &["--key", "drive.speed", "--from", "0.01", "--to", "3"],
            "no such scene key",
        ),
        (
            &["--key", "contact.nodes", "--from", "10", "--to", "30"],
            "does not take a real number",
        ),
        (
            &[
                "--key",
                "drive.velocity",
                "--from",
                "0.01",
                "--to",
                "3",
                "--rtol",
                "0",
            ],
            "--rtol = 0",
        ),
        (
            &["--key", "contact.radius", "--from", "-1", "--to", "2e-5"],
            "contact.radius = -1",
        ),
    ];
    for (args, needle) in cases {
        let out = boundary(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", texts(&out).1);
        assert!(
            texts(&out).1.contains(needle),
            "{args:?}: {}",
            texts(&out).1
        );
    }
}

#[test]
fn a_run_that_fails_numerically_exits_3_naming_the_value() {
    // A runaway limit just above τmax: at fig2's temperature the first end's run fails at its
    // first stress peak.
    let rigid = scene("rigid");
    let out = run(&[
        "boundary",
        rigid.to_str().unwrap(),
        "--set",
        "contact.nodes=50",
        "--set",
        "numerics.runaway_stress_factor=1.0001",
        "--key",
        "drive.velocity",
        "--from",
        "0.01",
        "--to",
        "3",
        "--quiet",
    ]);
    let (_, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("drive.velocity = 0.01: the run failed"),
        "{stderr}"
    );
    assert!(stderr.contains("runaway_stress_factor"), "{stderr}");
}
