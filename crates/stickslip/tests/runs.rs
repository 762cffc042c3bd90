//! Runs of the shipped scenes through the binary: fig2 events and forces, both schemes, exit 3
//! on a numerical failure with partial output, determinism (also across thread counts), the
//! step and recording schedule, and `check`.

use crate::common;

use common::{Csv, bin, run, scene, texts};
use std::path::{Path, PathBuf};
use stickslip_run::schema::run_info::{RunInfo, RunStatus};

/// fig2 shortened: N = 50, 1 ms, Δt = 2e-8 s (four events).
const FIG2_SHORT: &[&str] = &[
    "--set",
    "contact.nodes=50",
    "--set",
    "time.end=1.0e-3",
    "--set",
    "time.dt=2e-8",
    "--set",
    "output.profile_times=[0.0, 1e-3]",
    "--quiet",
];

fn run_scene(name: &str, out: &Path, extra: &[&str]) -> std::process::Output {
    let scene = scene(name).display().to_string();
    let out = out.display().to_string();
    let mut args = vec!["run", scene.as_str(), "--out", out.as_str()];
    args.extend_from_slice(extra);
    run(&args)
}

fn assert_ok(out: &std::process::Output) {
    assert_eq!(out.status.code(), Some(0), "stderr: {}", texts(out).1);
}

#[test]
fn fig2_short_run_shows_shrinking_intervals_edge_onset_and_consistent_forces() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("fig2");
    assert_ok(&run_scene("fig2", &dir, FIG2_SHORT));

    let events = Csv::read(&dir.join("events.csv"));
    assert_eq!(
        &events.header[..5],
        &["k", "t_onset", "r_first", "x_onset", "f_peak"]
    );
    let onsets = events.col("t_onset");
    assert!(onsets.len() >= 3, "only {} events", onsets.len());
    let intervals: Vec<f64> = onsets.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(
        intervals.windows(2).all(|w| w[1] < w[0]),
        "intervals do not shrink: {intervals:?}"
    );
    let a0 = 2e-5;
    let r_first = events.col("r_first")[0];
    assert!(r_first >= 0.95 * a0, "first melting at r = {r_first:e} m");
    for f in events.col("f_peak") {
        assert!((1.15e-3..=1.35e-3).contains(&f), "f_peak = {f:e} N");
    }

    let series = Csv::read(&dir.join("series.csv"));
    for c in [
        "t",
        "X",
        "V",
        "F",
        "phi_mean",
        "eps_mean",
        "melted_fraction",
        "F_1d",
    ] {
        assert!(series.header.iter().any(|h| h == c), "series.csv lacks {c}");
    }
    let t = series.col("t");
    assert_eq!(t[0], 0.0);
    assert_eq!(*t.last().unwrap(), 1e-3, "the run ends exactly on time.end");
    assert!(t.windows(2).all(|w| w[1] > w[0]));
    let (f, f1d) = (series.col("F"), series.col("F_1d"));
    let mut compared = 0;
    for (a, b) in f.iter().zip(&f1d) {
        if a.abs() > 1e-4 {
            compared += 1;
            assert!(((a - b) / a).abs() < 1e-3, "F = {a:e}, F_1d = {b:e}");
        }
    }
    assert!(compared > 100);

    let profiles = Csv::read(&dir.join("profiles.csv"));
    assert_eq!(
        profiles.header,
        ["t", "r", "phi", "eps", "tau", "u0", "u3d"]
    );
    assert_eq!(profiles.rows.len(), 2 * 50, "profiles at t = 0 and 1e-3");
    let probes = Csv::read(&dir.join("probes.csv"));
    assert_eq!(probes.header[0], "t");
    assert_eq!(probes.header[1], "phi@2e-6");
    assert_eq!(probes.header.len(), 19, "t, 9 × phi@r, 9 × t_melt@r");
    assert_eq!(probes.header[10], "t_melt@2e-6");
    assert_eq!(probes.rows.len(), series.rows.len());

    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    assert_eq!(report["status"], "ok");
    // Adaptive by default: one step per accepted step (the error is estimated from the step
    // itself), far fewer than end/dt.
    assert_eq!(report["scene"]["time"]["stepping"], "adaptive");
    let accepted = report["accepted_steps"].as_u64().unwrap();
    assert_eq!(report["steps"].as_u64().unwrap(), accepted);
    assert!(
        (100..10_000).contains(&accepted),
        "{accepted} accepted steps"
    );
    assert!(report["rejected_steps"].as_u64().unwrap() < accepted);
    assert_eq!(report["forced_steps"], 0);
    assert_eq!(report["seed"], serde_json::Value::Null);
    assert_eq!(report["scene"]["contact"]["nodes"], 50);
    assert_eq!(report["scene"]["lubricant"]["noise"]["kind"], "floor");
    assert!((report["derived"]["eps_c"].as_f64().unwrap() - 3f64.sqrt()).abs() < 1e-12);
    // No temporary files left behind.
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name();
        assert!(!name.to_string_lossy().ends_with(".tmp"), "{name:?} left");
    }
}

#[test]
fn literal_scheme_runs_too() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("literal");
    let mut args = FIG2_SHORT.to_vec();
    args.extend_from_slice(&["--set", "time.scheme=literal"]);
    assert_ok(&run_scene("fig2", &dir, &args));
    for f in [
        "series.csv",
        "events.csv",
        "profiles.csv",
        "probes.csv",
        "run.json",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    assert!(!Csv::read(&dir.join("events.csv")).rows.is_empty());
    assert!(Csv::read(&dir.join("series.csv")).rows.len() > 1000);
}

#[test]
fn explicit_euler_beyond_its_limit_exits_3_with_partial_output() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("blowup");
    let out = run_scene(
        "fig2",
        &dir,
        &[
            "--set",
            "contact.nodes=40",
            "--set",
            "time.scheme=literal",
            "--set",
            "lubricant.gamma=1e5",
            "--set",
            "lubricant.noise.kind=off",
            "--set",
            "time.end=1e-4",
            "--set",
            "output.profile_times=[0.0]",
            "--quiet",
        ],
    );
    let (_, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(3), "stderr: {stderr}");
    // Warned before the run (Δt·2γAb/a = 600 > 2), then the failure itself.
    assert!(
        stderr.starts_with("warning: time.dt x 2*gamma*A*b/a"),
        "{stderr}"
    );
    assert!(stderr.lines().any(|l| l.starts_with("error: ")), "{stderr}");
    for word in ["t = ", "step ", "node "] {
        assert!(stderr.contains(word), "message lacks {word:?}: {stderr}");
    }
    let series = Csv::read(&dir.join("series.csv"));
    assert_eq!(series.header[0], "t");
    assert!(!series.rows.is_empty(), "the row at t = 0 is kept");
    assert_eq!(Csv::read(&dir.join("profiles.csv")).rows.len(), 40);
    let report = RunInfo::read(&dir).unwrap();
    assert_eq!(report.status, RunStatus::Failed);
    let failure = report.failure.expect("a failure record");
    assert!(failure.message.contains("numerical failure"));
    assert_eq!(failure.quantity, "phi");
    assert!(failure.step >= 1 && failure.time_s > 0.0);
}

const OUTPUTS: [&str; 4] = ["series.csv", "events.csv", "profiles.csv", "probes.csv"];

fn assert_identical(a: &Path, b: &Path) {
    for f in OUTPUTS {
        let (x, y) = (
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
        );
        assert!(
            x == y,
            "{f} differs between {} and {}",
            a.display(),
            b.display()
        );
    }
}

#[test]
fn runs_are_bit_reproducible() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    assert_ok(&run_scene("fig2", &a, FIG2_SHORT));
    assert_ok(&run_scene("fig2", &b, FIG2_SHORT));
    assert_identical(&a, &b);
}

/// `scene` run with `sets` on 1 and on 2 threads (`RAYON_NUM_THREADS`): the two output
/// directories, inside `tmp`.
fn on_one_and_two_threads(tmp: &Path, scene_name: &str, sets: &[&str]) -> Vec<PathBuf> {
    let scene = scene(scene_name).display().to_string();
    let mut dirs = Vec::new();
    for threads in ["1", "2"] {
        let dir = tmp.join(format!("threads{threads}"));
        let mut args = vec!["run", &scene, "--out"];
        let dir_text = dir.display().to_string();
        args.push(&dir_text);
        for set in sets {
            args.extend(["--set", set]);
        }
        args.push("--quiet");
        let out = bin()
            .env("RAYON_NUM_THREADS", threads)
            .args(&args)
            .output()
            .unwrap();
        assert_ok(&out);
        dirs.push(dir);
    }
    dirs
}

#[test]
fn runs_do_not_depend_on_the_thread_count() {
    // N = 600 takes the engine's row-parallel operator path (N >= 512); rigid_fast melts
    // three times in 1 µs.
    let tmp = tempfile::tempdir().unwrap();
    let sets = [
        "contact.nodes=600",
        "time.end=1e-6",
        "output.profile_times=[5e-7, 1e-6]",
    ];
    let dirs = on_one_and_two_threads(tmp.path(), "rigid_fast", &sets);
    assert!(Csv::read(&dirs[0].join("events.csv")).rows.len() >= 2);
    assert_identical(&dirs[0], &dirs[1]);
}

#[test]
fn the_compliance_on_two_threads_gives_the_one_thread_bits() {
    // fig2 at N = 1200: the fast operators, whose compliance takes a helper thread from
    // 1000 nodes when the run has two threads; adaptive, through the first melting (181
    // steps, 135 coupling iterations).
    let tmp = tempfile::tempdir().unwrap();
    let sets = [
        "contact.nodes=1200",
        "time.end=6.5e-4",
        "output.profile_times=[6.5e-4]",
    ];
    let dirs = on_one_and_two_threads(tmp.path(), "fig2", &sets);
    assert_eq!(Csv::read(&dirs[0].join("events.csv")).rows.len(), 1);
    assert_identical(&dirs[0], &dirs[1]);
}

#[test]
fn steps_land_on_end_and_rows_follow_the_series_interval() {
    // dt = 3e-8 does not divide end = 1e-6: 34 steps, the last one shorter.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sched");
    assert_ok(&run_scene(
        "homogeneous",
        &dir,
        &[
            "--set",
            "time.end=1e-6",
            "--set",
            "time.dt=3e-8",
            "--set",
            "time.stepping=fixed",
            "--set",
            "output.series_interval=1e-7",
            "--set",
            "output.profile_times=[0.0, 5e-7, 5.1e-7, 1e-6]",
            "--set",
            "output.probe_radii=[0.0, 1e-5]",
            "--quiet",
        ],
    ));
    let t = Csv::read(&dir.join("series.csv")).col("t");
    // t = 0, then the first step at or after each multiple of 1e-7 (steps are 3e-8 long).
    assert_eq!(t.len(), 11, "{t:?}");
    assert_eq!(t[0], 0.0);
    for (k, &tk) in t.iter().enumerate().skip(1) {
        let mark = k as f64 * 1e-7;
        assert!(tk >= mark - 1e-15 && tk < mark + 3e-8, "row {k} at {tk:e}");
    }
    assert_eq!(*t.last().unwrap(), 1e-6);
    let profile_t = Csv::read(&dir.join("profiles.csv")).col("t");
    // 5e-7 and 5.1e-7 fall on the same step; one node (homogeneous).
    assert_eq!(profile_t.len(), 3, "{profile_t:?}");
    assert_eq!(profile_t[0], 0.0);
    assert!((profile_t[1] - 5.1e-7).abs() < 1.5e-8);
    assert_eq!(profile_t[2], 1e-6);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    assert_eq!(report["steps"], 34);
    assert_eq!(report["t_final"], 1e-6);
}

#[test]
fn complete_melting_has_zero_force() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("melt");
    assert_ok(&run_scene(
        "melt",
        &dir,
        &[
            "--set",
            "contact.nodes=40",
            "--set",
            "time.end=2e-5",
            "--set",
            "output.profile_times=[0.0]",
            "--quiet",
        ],
    ));
    let series = Csv::read(&dir.join("series.csv"));
    assert!(series.col("F").iter().all(|&f| f == 0.0));
    assert!(series.col("melted_fraction").iter().all(|&m| m > 0.999));
    let events = Csv::read(&dir.join("events.csv"));
    assert_eq!(events.rows.len(), 1);
    assert_eq!(events.col("t_onset")[0], 0.0);
}

#[test]
fn all_shipped_scenes_check() {
    for name in [
        "fig2",
        "fig3",
        "fig4",
        "rigid",
        "rigid_fast",
        "melt",
        "homogeneous",
        "fig2_first_order",
    ] {
        let out = run(&["check", &scene(name).display().to_string()]);
        assert_ok(&out);
    }
}

#[test]
fn check_prints_derived_parameters() {
    let out = run(&["check", &scene("fig2").display().to_string()]);
    assert_ok(&out);
    let (stdout, _) = texts(&out);
    for line in [
        "eps_c = 1.732",
        "b = 2e6 Pa",
        "A = 1.5e6 Pa",
        "phi0 = 1.2247",
        "omega = 70.71",
        "nodes = 2000",
        "steps = 130000",
    ] {
        assert!(
            stdout.contains(line),
            "check output lacks {line:?}:\n{stdout}"
        );
    }
}

#[test]
fn check_prints_the_viscous_films_scales() {
    let fig2 = scene("fig2").display().to_string();
    let out = run(&["check", &fig2]);
    assert_ok(&out);
    assert!(!texts(&out).0.contains("viscous_"));
    // c_v = η·π·a0²/h0 = 2·π·4e-10/1e-7 = 8π·1e-3 N·s/m; η·a0/(h0·G*) = 2·2e-5/(1e-7·1e9) s.
    let out = run(&["check", &fig2, "--set", "lubricant.viscosity=2"]);
    assert_ok(&out);
    let (stdout, _) = texts(&out);
    // To rounding: the last digits depend on the order of the products.
    assert!(
        stdout.contains("viscous_drag = 2.51327412287183"),
        "{stdout}"
    );
    assert!(
        stdout.contains("viscous_time = 4.0000000000000"),
        "{stdout}"
    );
}

#[test]
fn check_prints_the_drives_damping_ratio() {
    let fig2 = scene("fig2").display().to_string();
    let out = run(&["check", &fig2]);
    assert_ok(&out);
    assert!(texts(&out).0.contains("damping_ratio = 0 ("));
    // c_d = 2·√(K·m) = 2·√50 N·s/m: critical, ζ = 1.
    let out = run(&["check", &fig2, "--set", "drive.damping=14.142135623730951"]);
    assert_ok(&out);
    let (stdout, _) = texts(&out);
    assert!(stdout.contains("damping_ratio = 1 ("), "{stdout}");
    let out = run(&["check", &scene("rigid").display().to_string()]);
    assert_ok(&out);
    let (rigid, _) = texts(&out);
    assert!(!rigid.contains("damping_ratio"), "{rigid}");
}

#[test]
fn check_prints_the_first_order_films_thresholds() {
    let out = run(&["check", &scene("fig2_first_order").display().to_string()]);
    assert_ok(&out);
    let (stdout, _) = texts(&out);
    for line in [
        "cubic = 4.0693979898",
        "eps_melt = 2.2516660498",
        "eps_solidify = 1.7320508075",
        "hysteresis_width = 2.0699999999",
        "tau_melt = 2.33047436",
        "phi0 = 2.6095178302",
        "critical_displacement = 2.2516660498",
    ] {
        assert!(
            stdout.contains(line),
            "check output lacks {line:?}:\n{stdout}"
        );
    }
    assert!(!stdout.contains("metastable_solid"), "{stdout}");
    // Above the melting temperature: whether a metastable solid can start.
    for (a0, verdict) in [
        ("-1e5", "metastable_solid = true"),
        ("-3e6", "metastable_solid = false"),
    ] {
        let out = run(&[
            "check",
            &scene("fig2").display().to_string(),
            "--set",
            "lubricant.cubic=4.07e6",
            "--set",
            &format!("temperature.A0={a0}"),
        ]);
        assert_ok(&out);
        let (stdout, _) = texts(&out);
        assert!(stdout.contains(verdict), "A0 = {a0}:\n{stdout}");
    }
}

#[test]
fn literal_scheme_beyond_eulers_limit_is_warned_about() {
    let tmp = tempfile::tempdir().unwrap();
    let args = |dt: &'static str| {
        vec![
            "--set",
            "contact.nodes=20",
            "--set",
            "time.scheme=literal",
            "--set",
            dt,
            "--set",
            "time.end=1e-6",
            "--set",
            "output.profile_times=[1e-6]",
            "--quiet",
        ]
    };
    let beyond = run_scene("fig2", &tmp.path().join("a"), &args("time.dt=4e-8"));
    assert_ok(&beyond);
    assert!(
        texts(&beyond)
            .1
            .contains("warning: time.dt x 2*gamma*A*b/a = 2.400 > 2"),
        "{}",
        texts(&beyond).1
    );
    let within = run_scene("fig2", &tmp.path().join("b"), &args("time.dt=1e-8"));
    assert_ok(&within);
    let stderr = texts(&within).1;
    assert!(!stderr.contains("2*gamma*A*b/a"), "{stderr}");
    // 1 µs of fig2 cannot reach the first melting (≈ 0.6 ms): the preflight says so.
    assert!(
        stderr.contains("warning: nothing melts within time.end"),
        "{stderr}"
    );
}

#[test]
fn a_runaway_stress_at_a_high_strain_rate_names_the_knob_not_the_step() {
    // A 1 nm film sheared at 3 m/s: 3e9 1/s against the film's 3e7 1/s. The stress overshoot
    // is the film's lag, which error-controlled steps cannot remove.
    let tmp = tempfile::tempdir().unwrap();
    let out = run_scene(
        "rigid",
        tmp.path(),
        &[
            "--set",
            "contact.film_thickness=1e-9",
            "--set",
            "drive.velocity=3",
            "--set",
            "contact.nodes=50",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("raise numerics.runaway_stress_factor (now 10)")
            && stderr.contains("strain rate |V0|/h0 = 3.000e9 1/s")
            && !stderr.contains("Reduce time.dt"),
        "{stderr}"
    );
}

#[test]
fn a_scene_without_probes_writes_no_probes_csv_and_reads_back() {
    let tmp = tempfile::tempdir().unwrap();
    let out = run_scene(
        "rigid",
        tmp.path(),
        &[
            "--set",
            "contact.nodes=50",
            "--set",
            "output.probe_radii=[]",
            "--quiet",
        ],
    );
    assert_ok(&out);
    assert!(!tmp.path().join("probes.csv").exists());
    assert!(!tmp.path().join(".probes.csv.tmp").exists());
    let read = stickslip_run::schema::RunOutput::read(tmp.path()).unwrap();
    assert!(read.probes.radii_m.is_empty());
    assert_eq!(read.probes.t_s, read.series.t_s);
    assert!(read.series.t_s.len() > 10);
    // With probes the file is there.
    let with = tempfile::tempdir().unwrap();
    assert_ok(&run_scene(
        "rigid",
        with.path(),
        &["--set", "contact.nodes=50", "--quiet"],
    ));
    assert!(with.path().join("probes.csv").is_file());
}

#[test]
fn unset_turns_a_spring_scene_rigid_and_a_wrong_name_exits_2() {
    let tmp = tempfile::tempdir().unwrap();
    let out = run_scene(
        "fig2",
        tmp.path(),
        &[
            "--unset",
            "drive.stiffness",
            "--unset",
            "drive.mass",
            "--unset",
            "drive.integrator",
            "--set",
            "drive.kind=rigid",
            "--set",
            "contact.nodes=50",
            "--set",
            "time.end=2e-4",
            "--set",
            "output.profile_times=[2e-4]",
            "--quiet",
        ],
    );
    assert_ok(&out);
    let info = RunInfo::read(tmp.path()).unwrap();
    assert!(
        info.scene
            .drive
            .as_ref()
            .and_then(|d| d.kind)
            .is_some_and(|k| format!("{k:?}").to_lowercase() == "rigid"),
        "{:?}",
        info.scene.drive
    );
    let bad = run(&[
        "check",
        scene("fig2").to_str().unwrap(),
        "--unset",
        "drive.speed",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        texts(&bad)
            .1
            .contains("--unset \"drive.speed\": no such scene key")
    );
}

#[test]
fn a_periodic_run_that_does_not_settle_says_why() {
    // The h0 = 1 nm contact's meltings come ever faster within its first slip: no repeat.
    let tmp = tempfile::tempdir().unwrap();
    let out = run_scene(
        "sfa",
        tmp.path(),
        &[
            "--set",
            "time.until=periodic",
            "--set",
            "time.end=0.115",
            "--set",
            "output.profile_times=[]",
            "--quiet",
        ],
    );
    assert_ok(&out);
    let stderr = texts(&out).1;
    assert!(
        stderr.contains("did not settle by time.end: the last 3 cycles differ")
            && stderr.contains("in period")
            && stderr.contains("nor do the stamp's slips repeat (1 slip, stamp regime transient)"),
        "{stderr}"
    );
}

#[test]
fn check_names_the_inputs_when_a_derived_number_overflows() {
    // A dashpot at the edge of the doubles: the free stamp's travel overflows; check says
    // which inputs did it instead of printing NaN.
    let out = run(&[
        "check",
        &scene("fig2").display().to_string(),
        "--set",
        "drive.damping=1e308",
    ]);
    let (stdout, stderr) = texts(&out);
    assert!(
        !stdout.contains("NaN") && !stdout.contains("= nan"),
        "{stdout}"
    );
    assert!(
        stdout.contains("stamp_travel: not computable") && stdout.contains("drive.damping = 1e308"),
        "{stdout}{stderr}"
    );
}

#[test]
fn a_coupling_that_overflows_names_the_inputs_that_can_do_it() {
    let tmp = tempfile::tempdir().unwrap();
    let out = run(&[
        "run",
        &scene("fig2").display().to_string(),
        "--set",
        "contact.nodes=20",
        "--set",
        "time.end=1e-5",
        "--set",
        "output.profile_times=[]",
        "--set",
        "drive.damping=1e308",
        "--out",
        tmp.path().join("r").to_str().unwrap(),
        "--quiet",
    ]);
    let (_, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("coupling residual") && stderr.contains("drive.damping = 1e308"),
        "{stderr}"
    );
}
