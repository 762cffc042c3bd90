//! `stickslip fit` through the binary: a synthetic trace (fig2 at N = 30 by `stickslip run`,
//! its columns renamed, a known noise added) fitted with its fit.json, fit.svg and fitted.toml;
//! every bad input exits 2 naming the field; a fit none of whose runs succeed exits 3; Ctrl-C
//! keeps the best fit so far.

use crate::common::{bin, run, scene, texts};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::Stdio;
use stickslip_run::schema::Table;

const TAU_MAX: f64 = 1.15e6;

/// Writes `DIR/trace.csv` from a run of fig2 at N = `nodes` up to `end_s` with τmax = TAU_MAX
/// (columns `time`, `force`, `position`; deterministic noise of 1e-5 N added to F).
fn synthetic(dir: &Path, nodes: u32, end_s: f64) -> PathBuf {
    let out = dir.join("truth");
    let status = run(&[
        "run",
        &scene("fig2").display().to_string(),
        "--out",
        &out.display().to_string(),
        "--quiet",
        "--set",
        &format!("contact.nodes={nodes}"),
        "--set",
        &format!("time.end={end_s:e}"),
        "--set",
        "output.profile_times=[]",
        "--set",
        "output.series_interval=2e-6",
        "--set",
        "time.tolerance=5e-7",
        "--set",
        &format!("lubricant.tau_max={TAU_MAX:e}"),
    ]);
    assert_eq!(status.status.code(), Some(0), "{:?}", texts(&status));
    let series = crate::common::Csv::read(&out.join("series.csv"));
    let (t, f, x) = (series.col("t"), series.col("F"), series.col("X"));
    let mut state = 99u64;
    let mut text = String::from("time,force,position\n");
    for i in 0..t.len() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let u = (state >> 11) as f64 / (1u64 << 53) as f64;
        let noisy = f[i] + (2.0 * u - 1.0) * 3f64.sqrt() * 1e-5;
        text.push_str(&format!("{:e},{noisy:e},{:e}\n", t[i], x[i]));
    }
    let path = dir.join("trace.csv");
    std::fs::write(&path, text).unwrap();
    path
}

fn fit_args(trace: &Path, out: &Path, extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = [
        "fit",
        &scene("fig2").display().to_string(),
        "--data",
        &trace.display().to_string(),
        "--set",
        "contact.nodes=30",
        "--out",
        &out.display().to_string(),
    ]
    .iter()
    .map(|s| (*s).to_string())
    .collect();
    args.extend(extra.iter().map(|s| (*s).to_string()));
    args
}

fn run_strings(args: &[String]) -> std::process::Output {
    run(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

#[test]
fn a_fit_writes_its_report_figure_and_fitted_scene_which_reproduces_it() {
    let tmp = tempfile::tempdir().unwrap();
    let trace = synthetic(tmp.path(), 30, 1e-3);
    let out = tmp.path().join("fit");
    let done = run_strings(&fit_args(
        &trace,
        &out,
        &[
            "--columns",
            "t=time,F=force,X=position",
            "--param",
            "lubricant.tau_max=5e5:2e6",
            "--profile",
            "lubricant.tau_max",
        ],
    ));
    let (stdout, stderr) = texts(&done);
    assert_eq!(done.status.code(), Some(0), "{stdout}{stderr}");
    assert!(stdout.contains("lubricant.tau_max"), "{stdout}");
    assert!(stderr.contains("fit: local stage"), "{stderr}");
    // Each progress line names the runs' tolerance (the fit tightens it near the optimum).
    assert!(
        stderr
            .lines()
            .filter(|l| l.starts_with("fit: "))
            .all(|l| l.contains(", runs at time.tolerance ")),
        "{stderr}"
    );
    let report = stickslip_studies::fit::report::FitReport::read(&out).unwrap();
    assert_eq!(report.status, "ok");
    let p = report.parameter("lubricant.tau_max").unwrap();
    let (lo, hi) = (p.lo95.unwrap(), p.hi95.unwrap());
    assert!(lo <= TAU_MAX && TAU_MAX <= hi, "{p:?}");
    let profile = report.profile.as_ref().unwrap();
    assert_eq!(profile.values.len(), 9);
    assert!(profile.delta.iter().all(|d| *d >= 0.0), "{profile:?}");
    // The profile's interval holds the truth too, and is about the covariance's.
    let (plo, phi) = (profile.lo95.unwrap(), profile.hi95.unwrap());
    assert!(plo <= TAU_MAX && TAU_MAX <= phi, "{profile:?}");
    assert!(
        (phi - plo) / (hi - lo) > 0.5 && (phi - plo) / (hi - lo) < 2.0,
        "{profile:?}"
    );
    let svg = std::fs::read_to_string(out.join("fit.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("residual"),
        "{}",
        &svg[..100]
    );
    // `stickslip run fitted.toml` is the fitted model: its τmax bit for bit, and the events
    // the fit found in it.
    let rerun = tmp.path().join("rerun");
    let ran = run(&[
        "run",
        &out.join("fitted.toml").display().to_string(),
        "--out",
        &rerun.display().to_string(),
        "--quiet",
    ]);
    assert_eq!(ran.status.code(), Some(0), "{:?}", texts(&ran));
    let info = stickslip_run::schema::run_info::RunInfo::read(&rerun).unwrap();
    let tau = info
        .scene
        .lubricant
        .as_ref()
        .and_then(|l| l.tau_max)
        .unwrap();
    assert_eq!(tau.to_bits(), p.value.to_bits());
    let events = stickslip_run::schema::events::Events::read(&rerun).unwrap();
    assert_eq!(events.onsets_s().len(), report.model_events.len());
}

#[test]
fn bad_input_exits_2_naming_the_field() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let ramp: String = (0..40).map(|i| format!("{}e-6,{}e-6\n", i, i)).collect();
    let saw: String = (0..40)
        .map(|i| format!("{}e-6,{}e-4\n", i, i % 10))
        .collect();
    let good = write("good.csv", &format!("t,F\n{saw}"));
    let cases: Vec<(PathBuf, Vec<&str>, &str)> = vec![
        (
            good.clone(),
            vec!["--param", "lubricant.nope"],
            "--param = lubricant.nope",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max=-1:1e6"],
            "lower bound within",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max=2e6:1e6"],
            "LO < HI",
        ),
        (
            good.clone(),
            vec!["--param", "contact.nodes=10:20"],
            "takes a real number",
        ),
        (
            write("back.csv", &format!("t,F\n{saw}1e-6,0\n")),
            vec!["--param", "lubricant.tau_max"],
            "trace t at sample 41",
        ),
        (
            write(
                "nan.csv",
                &format!("t,F\n{}", saw.replace("3e-6,3e-4", "3e-6,NaN")),
            ),
            vec!["--param", "lubricant.tau_max"],
            "trace F at line 5 = NaN",
        ),
        (
            write("short.csv", "t,F\n0,0\n1e-6,1e-4\n"),
            vec!["--param", "lubricant.tau_max"],
            "trace samples = 2",
        ),
        (
            write("ramp.csv", &format!("t,F\n{ramp}")),
            vec!["--param", "lubricant.tau_max"],
            "trace events = none",
        ),
        (
            write("names.csv", &format!("time,F\n{saw}")),
            vec!["--param", "lubricant.tau_max"],
            "trace column t = t",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max", "--columns", "q=x"],
            "--columns = q=x",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max", "--noise", "-1"],
            "--noise = -1",
        ),
        (
            good.clone(),
            vec![
                "--param",
                "lubricant.tau_max",
                "--profile",
                "lubricant.gamma",
            ],
            "--profile = lubricant.gamma",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max", "--jobs", "0"],
            "--jobs = 0",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max", "--misfit", "x"],
            "--misfit",
        ),
        (good.clone(), vec![], "--param"),
        // The second campaign's classes: ambiguous columns, a constant trace, absurd units,
        // a noise larger than the signal, a key the scene does not take, a huge cell echoed.
        (
            write(
                "twice.csv",
                &format!("t,F,F\n{}", saw.replace('\n', ",0\n")),
            ),
            vec!["--param", "lubricant.tau_max"],
            "appears 2 times",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max", "--columns", "F=t"],
            "a different column for each of t, F and X",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max", "--columns", "X=pos"],
            "--columns X = pos",
        ),
        (
            write(
                "flat.csv",
                &format!(
                    "t,F\n{}",
                    (0..40)
                        .map(|i| format!("{i}e-6,1e-4\n"))
                        .collect::<String>()
                ),
            ),
            vec!["--param", "lubricant.tau_max"],
            "trace F = 1e-4 N at every sample",
        ),
        (
            write(
                "huge.csv",
                &format!("t,F\n{}", saw.replace("e-4\n", "e302\n")),
            ),
            vec!["--param", "lubricant.tau_max"],
            "trace F = up to 9e302 N",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.tau_max", "--noise", "1e308"],
            "--noise = 1e308",
        ),
        (
            good.clone(),
            vec!["--param", "lubricant.noise.sigma=1e-3:1"],
            "a key this scene takes over the whole box",
        ),
        (
            // A trace long after the drive's start: the cost of that is said before any run
            // (the unknown key then stops the fit).
            write(
                "late.csv",
                &format!(
                    "t,F\n{}",
                    (0..40)
                        .map(|i| format!("{:e},{}e-4\n", 0.5 + i as f64 * 1e-6, i % 10))
                        .collect::<String>()
                ),
            ),
            vec!["--param", "lubricant.nope"],
            "the trace starts at t = 0.5 s",
        ),
        (
            write(
                "long.csv",
                &format!("t,F\n{}{}\n", saw, "x".repeat(1 << 20)),
            ),
            vec!["--param", "lubricant.tau_max"],
            "bytes in all",
        ),
    ];
    for (trace, extra, expected) in cases {
        let args = fit_args(&trace, &dir.join("out"), &extra);
        let done = run_strings(&args);
        let (_, stderr) = texts(&done);
        assert_eq!(done.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(expected), "{extra:?}: {stderr}");
        // Short messages: no echo of a long line, no 300-digit number.
        assert!(stderr.len() < 2000, "{extra:?}: {} bytes", stderr.len());
        assert!(!dir.join("out").join("fit.json").exists(), "{extra:?}");
    }
}

#[test]
fn a_fit_whose_runs_all_fail_exits_3() {
    let tmp = tempfile::tempdir().unwrap();
    let saw: String = (0..40)
        .map(|i| format!("{}e-6,{}e-4\n", i, i % 10))
        .collect();
    let trace = tmp.path().join("saw.csv");
    std::fs::write(
        &trace,
        format!("time,force,position\n{}", saw.replace('\n', ",0\n")),
    )
    .unwrap();
    // A runaway limit just above τmax: every run fails at its first stress peak, within the
    // trace's 1 ms. (A key the scene refuses over the box is bad input, refused before any
    // run: the battery above.)
    let long: String = (0..40)
        .map(|i| format!("{}e-6,{}e-4,0\n", 25 * i, i % 10))
        .collect();
    std::fs::write(&trace, format!("time,force,position\n{long}")).unwrap();
    let done = run_strings(&fit_args(
        &trace,
        &tmp.path().join("out"),
        &[
            "--columns",
            "t=time,F=force,X=position",
            "--set",
            "numerics.runaway_stress_factor=1.0001",
            "--param",
            "lubricant.gamma=3:30",
            "--quiet",
        ],
    ));
    let (_, stderr) = texts(&done);
    assert_eq!(done.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("no run of the optimiser succeeded"),
        "{stderr}"
    );
}

#[test]
fn ctrl_c_keeps_the_best_fit_so_far() {
    let tmp = tempfile::tempdir().unwrap();
    let trace = synthetic(tmp.path(), 30, 1e-3);
    let out = tmp.path().join("fit");
    let args = fit_args(
        &trace,
        &out,
        &[
            "--columns",
            "t=time,F=force,X=position",
            "--param",
            "lubricant.tau_max=5e5:2e6",
            "--param",
            "lubricant.gamma=3:30",
            "--param",
            "lubricant.a=5e5:2e6",
            "--jobs",
            "1",
        ],
    );
    let mut child = bin()
        .args(&args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // SIGINT once the local stage has begun (a best model exists then).
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let mut seen = String::new();
    for line in lines.by_ref() {
        let line = line.unwrap();
        seen.push_str(&line);
        seen.push('\n');
        if line.contains("local stage") {
            crate::common::signal(&child, "INT");
            break;
        }
    }
    for line in lines {
        seen.push_str(&line.unwrap());
        seen.push('\n');
    }
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{seen}");
    let report = stickslip_studies::fit::report::FitReport::read(&out).unwrap();
    assert_eq!(report.status, "interrupted");
    assert!(report.misfit.is_finite() && report.parameters.len() == 3);
    assert!(out.join("fitted.toml").is_file() && out.join("fit.svg").is_file());
}

#[test]
fn fit_and_verify_check_their_output_directory_before_any_run() {
    // An --out holding an earlier result is refused at once (exit 2) unless --force; a file
    // in its place too; bad input after the check leaves no empty directory behind.
    let tmp = tempfile::tempdir().unwrap();
    let used = tmp.path().join("used");
    std::fs::create_dir(&used).unwrap();
    std::fs::write(used.join("fit.json"), b"{}").unwrap();
    let saw: String = (0..40)
        .map(|i| format!("{}e-6,{}e-4\n", i, i % 10))
        .collect();
    let trace = tmp.path().join("saw.csv");
    std::fs::write(&trace, format!("t,F\n{saw}")).unwrap();
    let o = run_strings(&fit_args(&trace, &used, &["--param", "lubricant.tau_max"]));
    let (stdout, stderr) = texts(&o);
    assert_eq!(o.status.code(), Some(2), "{stdout}{stderr}");
    assert!(
        stderr.contains("already holds files") && stderr.contains("--force"),
        "{stderr}"
    );
    assert!(!stderr.contains("evaluations"), "it ran: {stderr}");
    assert_eq!(std::fs::read(used.join("fit.json")).unwrap(), b"{}");
    let o = run(&[
        "verify",
        scene("fig2").to_str().unwrap(),
        "--out",
        used.to_str().unwrap(),
    ]);
    let (_, stderr) = texts(&o);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--force") && !stderr.contains("runs ("),
        "{stderr}"
    );
    // A file where the directory should be.
    let file = tmp.path().join("file");
    std::fs::write(&file, b"").unwrap();
    let o = run(&[
        "verify",
        scene("fig2").to_str().unwrap(),
        "--force",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(texts(&o).1.contains("is a file"));
    // Bad input found after the check: the directory it made is gone again.
    let fresh = tmp.path().join("fresh");
    let o = run(&[
        "verify",
        scene("fig2").to_str().unwrap(),
        "--target",
        "2",
        "--out",
        fresh.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!fresh.exists());
}
