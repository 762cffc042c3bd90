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
    assert_eq!(onset["space"]["order_theoretical"], 1.0);
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
