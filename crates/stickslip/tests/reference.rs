//! The repository's reference (`docs/reference.md`) is the output of `stickslip keys
//! --markdown`, generated from the argument definitions, the key table and the output schema.

use crate::common;

use common::{run, texts};

#[test]
fn docs_reference_is_current() {
    let out = run(&["keys", "--markdown"]);
    assert!(out.status.success());
    let generated = texts(&out).0;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/reference.md");
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "docs/reference.md is stale: run `cargo run --release -- keys --markdown > docs/reference.md`"
    );
    for key in stickslip_run::keys::KEYS.iter() {
        assert!(
            generated.contains(&format!("`{}`", key.path)),
            "{}",
            key.path
        );
    }
    for command in ["run", "check", "resume", "keys"] {
        assert!(
            generated.contains(&format!("### `stickslip {command}`")),
            "{command}"
        );
    }
}

#[test]
fn keys_lists_every_key_with_unit_default_and_range() {
    let out = run(&["keys"]);
    assert!(out.status.success());
    let text = texts(&out).0;
    assert!(
        text.contains("contact.radius  [m]  default: required"),
        "{text}"
    );
    assert!(text.contains("time.max_events"), "{text}");
    assert!(
        text.contains("output.event_recovery  [–]  default: 2"),
        "{text}"
    );
}

#[test]
fn check_reports_plausibility_and_warns_about_unit_slips() {
    let scene = common::scene("fig2");
    let out = run(&[
        "check",
        scene.to_str().unwrap(),
        "--set",
        "contact.radius=20",
        "--set",
        "contact.nodes=50",
    ]);
    let (stdout, stderr) = texts(&out);
    assert!(out.status.success(), "{stderr}");
    for needle in [
        "melting_force = ",
        "critical_displacement = ",
        "spring_period = ",
        "first_onset_estimate = ",
        "seconds_estimate = ",
    ] {
        assert!(stdout.contains(needle), "{needle}: {stdout}");
    }
    // Each warning once, in the report on stdout.
    let warning = "warning: contact.radius = 20 m is outside the usual range";
    assert_eq!(stdout.matches(warning).count(), 1, "{stdout}");
    assert!(!stderr.contains(warning), "{stderr}");
    let short = run(&[
        "check",
        scene.to_str().unwrap(),
        "--set",
        "time.end=1e-4",
        "--set",
        "output.profile_times=[1e-4]",
        "--set",
        "contact.nodes=50",
    ]);
    assert!(
        texts(&short).0.contains(
            "warning: nothing melts within time.end = 1e-4 s: the first melting comes at about"
        ),
        "{}",
        texts(&short).0
    );
    let literal = run(&[
        "check",
        scene.to_str().unwrap(),
        "--set",
        "time.scheme=literal",
        "--set",
        "time.dt=4e-8",
        "--set",
        "contact.nodes=50",
    ]);
    let (stdout, _) = texts(&literal);
    assert!(stdout.contains("euler_number = 2.4"), "{stdout}");
    assert!(
        stdout.contains("warning: time.dt x 2*gamma*A*b/a = 2.400 > 2"),
        "{stdout}"
    );
}

#[test]
fn check_warns_when_the_outermost_node_misses_the_edge_layer() {
    // The 1 nm SFA contact: on the uniform grid at N = 200 the outermost node is 100 nm from
    // the edge, 89 widths of the 1.1 nm edge layer; the graded grid's (the default) is
    // 2.5 pm away.
    let scene = common::scene("sfa");
    let uniform = run(&[
        "check",
        scene.to_str().unwrap(),
        "--set",
        "contact.grid=uniform",
    ]);
    let (stdout, stderr) = texts(&uniform);
    assert!(uniform.status.success(), "{stderr}");
    assert!(stdout.contains("# edge layer"), "{stdout}");
    let warning = "warning: contact.nodes = 200 leaves the outermost node 1.000e-7 m";
    assert_eq!(stdout.matches(warning).count(), 1, "{stdout}");
    assert!(stdout.contains("This grid needs N >= 1777"), "{stdout}");
    assert!(
        stdout.contains("contact.grid = \"graded\" N >= 13"),
        "{stdout}"
    );
    let graded = run(&["check", scene.to_str().unwrap()]);
    let (stdout, _) = texts(&graded);
    assert!(stdout.contains("# edge layer"), "{stdout}");
    assert!(!stdout.contains("leaves the outermost node"), "{stdout}");
}

#[test]
fn check_warns_loudly_about_a_run_of_years_naming_the_mistyped_key() {
    // A speed of 3 µm/s typed as 3 (m/s): the stamp travels 3 m in a second.
    let scene = common::scene("sfa");
    let speed = run(&[
        "check",
        scene.to_str().unwrap(),
        "--set",
        "drive.velocity=3",
        "--set",
        "time.end=1",
    ]);
    let (stdout, _) = texts(&speed);
    assert!(
        stdout.contains("warning: THIS RUN WOULD TAKE ABOUT")
            && stdout.contains("(drive.velocity)"),
        "{stdout}"
    );
    let viscous = run(&[
        "check",
        scene.to_str().unwrap(),
        "--set",
        "lubricant.viscosity=1e30",
    ]);
    let (stdout, _) = texts(&viscous);
    assert!(stdout.contains("(lubricant.viscosity)"), "{stdout}");
    let shipped = run(&["check", scene.to_str().unwrap()]);
    assert!(!texts(&shipped).0.contains("THIS RUN WOULD TAKE"));
}
