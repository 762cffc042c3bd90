//! `stickslip verify`: the refinements run, the table and verify.json say each quantity's
//! value, uncertainty, orders and verdict, the exit status follows the verdicts, and bad
//! options exit 2.

use crate::common::{run, scene, texts};

fn run_strings(args: &[String]) -> std::process::Output {
    run(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

#[test]
fn verify_writes_each_quantity_with_its_error_and_exits_by_the_verdicts() {
    let tmp = tempfile::tempdir().unwrap();
    let fig2 = scene("fig2");
    let out = tmp.path().join("v");
    let args = |rtol: &str| {
        vec![
            "verify".to_string(),
            fig2.display().to_string(),
            "--set".to_string(),
            "contact.nodes=50".to_string(),
            "--set".to_string(),
            "time.end=8e-4".to_string(),
            "--set".to_string(),
            "output.profile_times=[8e-4]".to_string(),
            "--rtol".to_string(),
            rtol.to_string(),
            "--out".to_string(),
            out.display().to_string(),
            // The second call writes over the first's result.
            "--force".to_string(),
        ]
    };
    let loose = run_strings(&args("0.5"));
    let (stdout, stderr) = texts(&loose);
    assert_eq!(loose.status.code(), Some(0), "{stdout}{stderr}");
    assert!(stderr.contains("verify: 5 runs"), "{stderr}");
    assert!(stdout.contains("t_first_onset"), "{stdout}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("verify.json")).unwrap()).unwrap();
    assert_eq!(report["levels"].as_array().unwrap().len(), 5);
    let onset = report["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["name"] == "t_first_onset")
        .unwrap();
    for field in [
        "value",
        "extrapolated",
        "uncertainty",
        "asymptotic",
        "verdict",
        "space",
        "time",
    ] {
        assert!(!onset[field].is_null(), "{field}: {onset}");
    }
    // The default grid is the edge-graded one: the onset converges at second order in N.
    assert_eq!(onset["space"]["order_theoretical"], 2.0);
    assert_eq!(onset["values"].as_array().unwrap().len(), 5);
    let svg = std::fs::read_to_string(out.join("verify_t_first_onset.svg")).unwrap();
    assert!(
        svg.contains("<svg") && svg.contains("t_first_onset against N"),
        "{svg:.200}"
    );
    assert!(!out.join("verify_regime.svg").exists());
    // An accuracy no run gives: exit 4, naming how many quantities miss it.
    let tight = run_strings(&args("1e-12"));
    let (_, stderr) = texts(&tight);
    assert_eq!(tight.status.code(), Some(4), "{stderr}");
    assert!(stderr.contains("are not within rtol 1e-12"), "{stderr}");
    // Bad options exit 2 naming them.
    for (bad, says) in [("0", "--rtol 0"), ("nan", "--rtol nan"), ("2", "--rtol 2")] {
        let o = run_strings(&args(bad));
        let (_, stderr) = texts(&o);
        assert_eq!(o.status.code(), Some(2), "{bad}: {stderr}");
        assert!(stderr.contains(says), "{stderr}");
    }
}

/// The surface-force-apparatus contact a new user built: fig2's film at h0 = 1 nm, K = 5000
/// N/m, V0 = 1 µm/s, N = 200.
const SFA: &str = r#"name = "sfa_k5000"
[lubricant]
tau_max = 1e6
eps_max = 1.0
a = 1e6
gamma = 10.0
[contact]
radius = 2e-5
film_thickness = 1e-9
g_eff = 1e9
nodes = 200
[drive]
stiffness = 5000.0
mass = 0.1
velocity = 1e-6
[time]
end = 0.2
[output]
series_interval = 1e-3
"#;

#[test]
fn check_warns_when_the_first_event_moves_with_the_resolution() {
    let tmp = tempfile::tempdir().unwrap();
    let sfa = tmp.path().join("sfa.toml");
    std::fs::write(&sfa, SFA).unwrap();
    // On the uniform grid: 0.10707 s at N = 200 against 0.10235 s at N = 400, 4.6 %.
    let out = run(&[
        "check",
        sfa.to_str().unwrap(),
        "--set",
        "contact.grid=uniform",
    ]);
    let (stdout, stderr) = texts(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stdout.contains("first event at N = 200 and 400"),
        "{stdout}"
    );
    assert!(stdout.contains("may be too coarse"), "{stdout}");
    assert!(stdout.contains("stickslip verify"), "{stdout}");
    // On the default, edge-graded grid the two agree to a few 1e-5 s: no warning.
    let out = run(&["check", sfa.to_str().unwrap()]);
    let (stdout, stderr) = texts(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stdout.contains("first event at N = 200 and 400"),
        "{stdout}"
    );
    assert!(!stdout.contains("may be too coarse"), "{stdout}");
    let fig2 = scene("fig2");
    let out = run(&[
        "check",
        fig2.to_str().unwrap(),
        "--set",
        "contact.nodes=200",
    ]);
    let (stdout, _) = texts(&out);
    assert!(
        stdout.contains("first event at N = 200 and 400"),
        "{stdout}"
    );
    assert!(!stdout.contains("may be too coarse"), "{stdout}");
}

/// The first event's onset (s) and peak force (N) of fig2 with `sets`, from a run to it.
fn first_event(tmp: &std::path::Path, tag: &str, sets: &[String]) -> (f64, f64) {
    let out = tmp.join(tag);
    let mut args = vec![
        "run".to_string(),
        scene("fig2").display().to_string(),
        "--set".into(),
        "time.max_events=1".into(),
        "--set".into(),
        "output.probe_radii=[]".into(),
        "--set".into(),
        "output.series_interval=1e-5".into(),
    ];
    for s in sets {
        args.extend(["--set".to_string(), s.clone()]);
    }
    args.extend(["--out".to_string(), out.display().to_string()]);
    let o = run_strings(&args);
    assert!(o.status.success(), "{:?}", texts(&o));
    let events = crate::common::Csv::read(&out.join("events.csv"));
    let col = |name: &str| events.header.iter().position(|h| h == name).unwrap();
    (
        events.rows[0][col("t_onset")],
        events.rows[0][col("f_peak")],
    )
}

#[test]
fn verify_target_finds_a_resolution_whose_error_is_within_the_target() {
    // fig2 on the graded grid, to a relative error of 1e-7 in the first onset (60 ps) and its
    // peak force: the search prints the pair and its cost and writes it as a scene's sections;
    // a run at the pair is within the target of a much finer run.
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("t");
    let target = 1e-7;
    let o = run_strings(&[
        "verify".into(),
        scene("fig2").display().to_string(),
        "--set".into(),
        "contact.grid=graded".into(),
        "--target".into(),
        target.to_string(),
        "--out".into(),
        out.display().to_string(),
    ]);
    let (stdout, stderr) = texts(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}{stderr}");
    assert!(
        stdout.contains("cheapest within 1e-7: contact.nodes = "),
        "{stdout}"
    );
    assert!(stderr.contains("space  N =    25"), "{stderr}");
    let text = std::fs::read_to_string(out.join("resolution.toml")).unwrap();
    let table: toml::Table = toml::from_str(&text).unwrap();
    let nodes = table["contact"]["nodes"].as_integer().unwrap();
    let tolerance = table["time"]["tolerance"].as_float().unwrap();
    assert_eq!(table["contact"]["grid"].as_str(), Some("graded"));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("target.json")).unwrap()).unwrap();
    assert_eq!(report["choice"]["nodes"], nodes);
    let sets = |n: i64, tol: f64| {
        vec![
            "contact.grid=graded".to_string(),
            format!("contact.nodes={n}"),
            format!("time.tolerance={tol:e}"),
        ]
    };
    let (onset, force) = first_event(tmp.path(), "chosen", &sets(nodes, tolerance));
    let (onset_ref, force_ref) = first_event(tmp.path(), "fine", &sets(1600, 5e-9));
    assert!(
        (onset - onset_ref).abs() <= target * onset_ref,
        "onset {onset} vs {onset_ref}"
    );
    assert!(
        (force - force_ref).abs() <= target * force_ref,
        "peak force {force} vs {force_ref}"
    );
    // The search was not trivial: the coarsest level alone is outside the target.
    let (onset_25, _) = first_event(tmp.path(), "coarse", &sets(25, tolerance));
    assert!((onset_25 - onset_ref).abs() > target * onset_ref);
}

#[test]
fn verify_target_refuses_what_it_cannot_search() {
    let fig2 = scene("fig2").display().to_string();
    for (extra, needle) in [
        (vec!["--target", "0"], "--target = 0"),
        (vec!["--target", "2"], "--target = 2"),
        (vec!["--target", "nan"], "--target = nan"),
        (
            vec!["--target", "1e-3", "--set", "time.stepping=fixed"],
            "time.stepping = \"adaptive\"",
        ),
    ] {
        let mut args = vec!["verify", fig2.as_str()];
        args.extend(extra);
        let o = run(&args);
        let (stdout, stderr) = texts(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stdout}{stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!stderr.contains("runs to the first event"), "{stderr}");
    }
}

#[test]
fn verify_of_a_scene_that_fails_numerically_is_a_numerical_failure_not_within() {
    // The paper's scheme at 100 times its Δt: explicit Euler blows up in every level. verify
    // used to print "within" for the failed runs' "no melting" and exit 0.
    let o = run(&[
        "verify",
        scene("fig2").to_str().unwrap(),
        "--set",
        "time.scheme=literal",
        "--set",
        "time.dt=1e-6",
        "--set",
        "contact.nodes=50",
        "--set",
        "time.end=1e-4",
        "--set",
        "output.profile_times=[]",
        "--out",
        tempfile::tempdir()
            .unwrap()
            .path()
            .join("v")
            .to_str()
            .unwrap(),
    ]);
    let (stdout, stderr) = texts(&o);
    assert_eq!(o.status.code(), Some(3), "{stdout}{stderr}");
    assert!(
        stderr.contains("the scene's own run failed numerically (N = 50)"),
        "{stderr}"
    );
    assert!(!stdout.contains("within"), "{stdout}");
}

#[test]
fn sigterm_keeps_the_finished_levels_and_the_same_command_runs_only_the_rest() {
    // fig2 at N = 200, one job: the scene's own level ends first; SIGTERM then stops the rest
    // (exit 130, as a run's), the level stays in levels/, and the same command reuses it.
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("v");
    let args: Vec<String> = [
        "verify",
        scene("fig2").to_str().unwrap(),
        "--set",
        "contact.nodes=200",
        "--jobs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]
    .iter()
    .map(|s| (*s).to_string())
    .collect();
    let first = out.join("levels").join("level-0.json");
    let cut = crate::common::run_signalled(
        &args,
        "TERM",
        || first.exists(),
        std::time::Duration::from_secs(120),
    );
    let (_, stderr) = texts(&cut);
    assert_eq!(cut.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("runs only the rest"), "{stderr}");
    assert!(first.exists());
    assert!(!out.join("verify.json").exists());
    // The same command, without --force: the directory holds this verify's levels only.
    let again = run_strings(&args);
    let (_, stderr) = texts(&again);
    assert!(matches!(again.status.code(), Some(0 | 4)), "{stderr}");
    assert!(stderr.contains("level 0 reused"), "{stderr}");
    assert!(out.join("verify.json").exists());
}
