//! `stickslip boundary`: the critical speed of the rigid drive scanned, bracketed and bisected,
//! checked against runs on both sides of it; every change of a line with several found, each
//! with an error; bad calls exit 2 naming what is wrong.

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

/// A number printed by `boundary`.
fn num(s: &str) -> f64 {
    s.trim()
        .parse::<f64>()
        .unwrap_or_else(|e| panic!("{s:?}: {e}"))
}

#[test]
fn the_critical_speed_is_bracketed_to_the_tolerance_and_given_an_error() {
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
    // drive.velocity = 2.32605e-1 ± 1.2e-4 (bracket a … b, rtol 0.001)
    let first = stdout.lines().next().unwrap();
    let after = first.split('=').nth(1).unwrap();
    let (value, rest) = after.split_once('±').unwrap();
    let value = num(value);
    let error = num(rest.split('(').next().unwrap());
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
    // The error counts at least the bracket, and here the change stays near it at 2N and at
    // a tenth of the tolerance.
    assert!(
        error >= 0.5 * (hi - lo) * 0.999 && error < 0.05 * value,
        "{first}"
    );
    assert!(
        stdout.contains("below: stick_slip") && stdout.contains("above: partial"),
        "{stdout}"
    );
    assert!(
        stdout.contains("2N:") && stdout.contains("tolerance/10:"),
        "{stdout}"
    );
    // Independently: plain runs a little either side give the two regimes.
    assert_eq!(regime_at(value * 0.99), "stick_slip");
    assert_eq!(regime_at(value * 1.01), "partial");
    // The scan also finds where partial recovery gives way to smooth sliding, which a
    // bisection of the ends alone cannot see.
    assert!(stdout.contains("2 changes (value ± error"), "{stdout}");
    let second = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("2. "))
        .unwrap();
    assert!(second.contains("partial → smooth"), "{second}");
    let v2 = num(second
        .split_once(". ")
        .unwrap()
        .1
        .split('±')
        .next()
        .unwrap());
    assert_eq!(regime_at(v2 * 0.99), "partial");
    assert_eq!(regime_at(v2 * 1.01), "smooth");
}

#[test]
fn a_line_with_several_changes_reports_each_with_its_error() {
    // Temperature through A0 at 0.1 m/s: sliding (A0 <= 0), then partial recovery and stick–
    // slip as the film grows stiffer: two changes, where a bisection of the ends finds one.
    let out = boundary(&[
        "--key",
        "temperature.A0",
        "--from",
        "-3e5",
        "--to",
        "1.5e6",
        "--scan",
        "7",
        "--rtol",
        "1e-2",
        "--set",
        "drive.velocity=0.5",
        "--quiet",
    ]);
    let (stdout, stderr) = texts(&out);
    assert!(out.status.success(), "{stderr}");
    let changes: Vec<&str> = stdout
        .lines()
        .filter(|l| l.trim_start().starts_with(|c: char| c.is_ascii_digit()) && l.contains(" → "))
        .collect();
    assert!(changes.len() >= 2, "{stdout}");
    assert!(stdout.contains("scan of 7 points (step"), "{stdout}");
    for line in &changes {
        let after = line.split_once(". ").unwrap().1;
        let (value, rest) = after.split_once('±').unwrap();
        let error = num(rest.trim_start().split(' ').next().unwrap());
        assert!(num(value).is_finite() && error > 0.0, "{line}");
    }
}

#[test]
fn bad_calls_exit_2_and_say_why() {
    let cases: [(&[&str], &str); 7] = [
        (
            &["--key", "drive.velocity", "--from", "0.01", "--to", "0.02"],
            "both give the regime stick_slip (as do the 7 scan points between them)",
        ),
        (
            &[
                "--key",
                "drive.velocity",
                "--from",
                "0.01",
                "--to",
                "3",
                "--scan",
                "1",
            ],
            "--scan = 1",
        ),
        (
            &[
                "--key",
                "drive.velocity",
                "--from",
                "0.01",
                "--to",
                "3",
                "--jobs",
                "0",
            ],
            "--jobs 0",
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

#[test]
fn the_stamp_scale_finds_where_the_stamp_stops_slipping() {
    // The h0 = 1 nm contact on its spring: a weak film (small A0) melts and re-freezes while
    // the stamp slides steadily; a strong one makes the stamp slip. `--scale stamp` follows
    // the stamp-scale regime, and each side agrees with a run there.
    let sfa = scene("sfa");
    let base = [
        "--set",
        "contact.nodes=50",
        "--set",
        "time.end=0.25",
        "--set",
        "output.profile_times=[]",
    ];
    let mut args = vec![
        "boundary",
        sfa.to_str().unwrap(),
        "--key",
        "temperature.A0",
        "--from",
        "-2e5",
        "--to",
        "1e6",
        "--scan",
        "3",
        "--rtol",
        "0.2",
        "--scale",
        "stamp",
        "--quiet",
    ];
    args.extend(base);
    let out = run(&args);
    let (stdout, stderr) = texts(&out);
    assert!(out.status.success(), "{stderr}");
    let first: Vec<&str> = stdout.lines().take(2).collect();
    assert!(first[1].starts_with("below: steady_sliding"), "{stdout}");
    let value = num(first[0].split(' ').nth(2).unwrap());
    // Each side's stamp regime, as `stickslip run` reports it: at the scene's window, and
    // while that says "transient" (undecided) over windows doubled up to 8 times, as boundary
    // does.
    let stamp_regime_at = |a0: f64| {
        let mut regime = String::new();
        for factor in [1.0, 2.0, 4.0, 8.0] {
            let tmp = tempfile::tempdir().unwrap();
            let set = format!("temperature.A0={a0:e}");
            let end = format!("time.end={:e}", 0.25 * factor);
            let mut args = vec![
                "run",
                sfa.to_str().unwrap(),
                "--out",
                tmp.path().to_str().unwrap(),
                "--quiet",
                "--set",
                &set,
            ];
            args.extend(base);
            args.extend(["--set", &end]);
            let out = run(&args);
            assert!(out.status.success(), "{}", texts(&out).1);
            let info: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(tmp.path().join("run.json")).unwrap(),
            )
            .unwrap();
            regime = info["summary"]["stamp_regime"]
                .as_str()
                .unwrap()
                .to_string();
            if regime != "transient" {
                break;
            }
        }
        regime
    };
    // The bracket's ends, where boundary ran: a run there reports the same regime. (Points
    // farther out need not: at N = 20 the stamp regime changes back and forth below 5e5 Pa,
    // where single slips come and go — the scan of 3 points sees one change.)
    // "below: REGIME (at VALUE); above: REGIME (at VALUE); …"
    let side = |name: &str| {
        let text = first[1]
            .split(';')
            .find(|part| part.trim_start().starts_with(name))
            .unwrap()
            .trim_start()
            .trim_start_matches(name)
            .trim_start_matches(':')
            .trim();
        let (regime, at) = text.split_once(" (at ").unwrap();
        (regime.to_string(), num(at.trim_end_matches(')')))
    };
    let ((regime_below, below), (regime_above, above)) = (side("below"), side("above"));
    assert!(below < value && value < above, "{stdout}");
    assert_eq!(regime_below, "steady_sliding", "{stdout}");
    assert_ne!(regime_above, "steady_sliding", "{stdout}");
    assert_eq!(stamp_regime_at(below), regime_below);
    assert_eq!(stamp_regime_at(above), regime_above);
    // An unknown scale exits 2 naming the allowed ones.
    let bad = run(&[
        "boundary",
        sfa.to_str().unwrap(),
        "--key",
        "temperature.A0",
        "--from",
        "-2e5",
        "--to",
        "1e6",
        "--scale",
        "slips",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(texts(&bad).1.contains("film") && texts(&bad).1.contains("stamp"));
}

#[test]
fn an_interrupted_scan_prints_its_brackets_and_the_same_command_finishes_it_from_its_runs() {
    // The several-changes line above with --out: SIGINT once some runs are kept; the scan
    // says what it had found (exit 130), and the same command makes only the missing runs and
    // prints what an uninterrupted search prints.
    let tmp = tempfile::tempdir().unwrap();
    let out_dir = tmp.path().join("b");
    let rigid = scene("rigid");
    let mut args: Vec<String> = vec!["boundary".into(), rigid.display().to_string()];
    args.extend(SETS.iter().map(|s| (*s).to_string()));
    for a in [
        "--key",
        "temperature.A0",
        "--from",
        "-3e5",
        "--to",
        "1.5e6",
        "--scan",
        "7",
        "--rtol",
        "1e-2",
        "--set",
        "drive.velocity=0.5",
        "--jobs",
        "1",
        "--quiet",
        "--out",
    ] {
        args.push(a.into());
    }
    args.push(out_dir.display().to_string());
    let probes = out_dir.join("probes.jsonl");
    let lines = || {
        std::fs::read_to_string(&probes)
            .map(|t| t.lines().count())
            .unwrap_or(0)
    };
    let cut = crate::common::run_signalled(
        &args,
        "INT",
        || lines() >= 9,
        std::time::Duration::from_secs(120),
    );
    let (stdout, stderr) = texts(&cut);
    assert_eq!(cut.status.code(), Some(130), "{stdout}{stderr}");
    assert!(
        stderr.contains("the changes above are as far as the scan got"),
        "{stderr}"
    );
    assert!(stderr.contains("--out"), "{stderr}");
    let kept = lines();
    assert!(kept >= 9, "{kept}");
    // The same command: the kept runs are found again, and the answer is a whole search's.
    let again = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let (stdout, stderr) = texts(&again);
    assert!(again.status.success(), "{stderr}");
    assert!(stderr.contains(&format!("{kept} runs kept")), "{stderr}");
    let fresh_dir = tmp.path().join("fresh");
    let mut fresh_args = args.clone();
    *fresh_args.last_mut().unwrap() = fresh_dir.display().to_string();
    let fresh = run(&fresh_args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(texts(&fresh).0, stdout);
}
