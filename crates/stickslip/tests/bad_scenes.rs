//! Bad scenes and bad `--set` arguments: each exits 2 with an `error: ` message naming the key,
//! the value and the allowed range, and writes nothing into the --out directory.

use crate::common;

use common::{run, texts};

/// A small valid scene (fig2 parameters, N = 40, 10 µs).
const BASE: &str = r#"
name = "base"

[lubricant]
tau_max = 1e6
eps_max = 1.0
a = 1e6
gamma = 10.0

[contact]
radius = 2e-5
film_thickness = 1e-7
g_eff = 1e9
nodes = 40

[drive]
kind = "spring"
stiffness = 500.0
mass = 0.1
velocity = 1.0

[time]
end = 1e-5
dt = 1e-8
"#;

struct Case {
    name: &'static str,
    /// (find, replace) applied to [`BASE`].
    edit: Option<(&'static str, &'static str)>,
    sets: &'static [&'static str],
    /// Substrings the message must contain (key, value, allowed range).
    expect: &'static [&'static str],
}

const fn case(
    name: &'static str,
    edit: Option<(&'static str, &'static str)>,
    sets: &'static [&'static str],
    expect: &'static [&'static str],
) -> Case {
    Case {
        name,
        edit,
        sets,
        expect,
    }
}

const CASES: &[Case] = &[
    // Unknown keys: the key, its section, the value and the keys allowed there.
    case(
        "unknown top-level key",
        Some(("name = \"base\"", "name = \"base\"\ncolour = 3")),
        &[],
        &[
            "unknown key `colour`",
            "in section (top level)",
            "3",
            "allowed keys there",
            "lubricant",
        ],
    ),
    case(
        "unknown key in section",
        None,
        &["lubricant.taumax=1e6"],
        &[
            "unknown key `lubricant.taumax`",
            "[lubricant]",
            "1e6",
            "tau_max",
        ],
    ),
    case(
        "unknown key in subsection",
        None,
        &["lubricant.noise.sigmaa=1"],
        &[
            "unknown key `lubricant.noise.sigmaa`",
            "[lubricant.noise]",
            "1",
            "sigma",
        ],
    ),
    case(
        "unknown section",
        None,
        &["solver.tol=1e-3"],
        &[
            "unknown key `solver`",
            "in section (top level)",
            "tol",
            "numerics",
        ],
    ),
    case(
        "unknown key in file",
        Some(("nodes = 40", "nodes = 40\nshape = \"round\"")),
        &[],
        &[
            "unknown key `contact.shape`",
            "[contact]",
            "\"round\"",
            "radius",
        ],
    ),
    // Missing required keys.
    case(
        "missing tau_max",
        Some(("tau_max = 1e6\n", "")),
        &[],
        &[
            "missing required key `lubricant.tau_max`",
            "none",
            "within [1e-15, 1e20] Pa",
        ],
    ),
    case(
        "missing name",
        Some(("name = \"base\"", "")),
        &[],
        &["missing required key `name`", "non-empty string"],
    ),
    case(
        "missing time.end",
        Some(("end = 1e-5\n", "")),
        &[],
        &["missing required key `time.end`", "> 0"],
    ),
    case(
        "missing velocity",
        Some(("velocity = 1.0\n", "")),
        &[],
        &["missing required key `drive.velocity`", "finite"],
    ),
    case(
        "missing contact section",
        Some(("[contact]", "[unused]")),
        &[],
        &["unknown key `unused`"],
    ),
    case(
        "missing film thickness",
        Some(("film_thickness = 1e-7\n", "")),
        &[],
        &["missing required key `contact.film_thickness`", "> 0"],
    ),
    // Wrong types.
    case(
        "string for a number",
        None,
        &["contact.radius=\"big\""],
        &["contact.radius = \"big\"", "wrong type", "a number"],
    ),
    case(
        "float for nodes",
        None,
        &["contact.nodes=2.5"],
        &["contact.nodes = 2.5", "wrong type", "an integer"],
    ),
    case(
        "whole float for nodes: shown as given, with the integer to write",
        None,
        &["contact.nodes=2e2"],
        &[
            "contact.nodes = 2e2 (a float)",
            "wrong type",
            "written without a decimal point or exponent: 200",
        ],
    ),
    case(
        "number for name",
        None,
        &["name=5"],
        &["name = 5", "wrong type", "a string"],
    ),
    case(
        "number for a section",
        None,
        &["lubricant=5"],
        &["lubricant = 5", "wrong type", "a table"],
    ),
    case(
        "string in array",
        None,
        &["output.probe_radii=[1e-6, \"x\"]"],
        &["output.probe_radii", "\"x\"", "an array of numbers"],
    ),
    // Out of range.
    case(
        "negative radius",
        None,
        &["contact.radius=-2e-5"],
        &["contact.radius = -2e-5", "finite and within [1e-15, "],
    ),
    case(
        "zero radius",
        None,
        &["contact.radius=0"],
        &["contact.radius = 0", "finite and within [1e-15, "],
    ),
    case(
        "zero film thickness",
        None,
        &["contact.film_thickness=0.0"],
        &["contact.film_thickness = 0", "finite and within [1e-15, "],
    ),
    case(
        "negative mass",
        None,
        &["drive.mass=-0.1"],
        &["drive.mass = -0.1", "finite and > 0"],
    ),
    case(
        "zero stiffness",
        None,
        &["drive.stiffness=0"],
        &["drive.stiffness = 0", "finite and > 0"],
    ),
    case(
        "negative g_eff",
        None,
        &["contact.g_eff=-1e9"],
        &["contact.g_eff = -1e9", "finite and within [1e-15, "],
    ),
    case(
        "zero nodes",
        None,
        &["contact.nodes=0"],
        &["contact.nodes = 0", "1 ..= 20000"],
    ),
    case(
        "negative nodes",
        None,
        &["contact.nodes=-5"],
        &["contact.nodes = -5", "1 ..= 20000"],
    ),
    case(
        "too many nodes",
        None,
        &["contact.nodes=100000"],
        &["contact.nodes = 100000", "1 ..= 20000"],
    ),
    case(
        "zero dt",
        None,
        &["time.dt=0.0"],
        &["time.dt = 0", "> 0 and <= time.end"],
    ),
    case(
        "negative dt",
        None,
        &["time.dt=-1e-8"],
        &["time.dt = -1e-8", "> 0"],
    ),
    case(
        "dt beyond end",
        None,
        &["time.dt=1e-3"],
        &["time.dt = 0.001", "<= time.end = 1e-5"],
    ),
    case(
        "too many steps",
        None,
        &["time.dt=1e-20"],
        &["time.dt = 1e-20", "at most 1e12 steps"],
    ),
    case(
        "zero end",
        None,
        &["time.end=0"],
        &["time.end = 0", "finite and > 0"],
    ),
    case(
        "zero melt threshold",
        None,
        &["lubricant.melt_threshold=0"],
        &["lubricant.melt_threshold = 0", "finite and > 0"],
    ),
    case(
        "zero gamma",
        None,
        &["lubricant.gamma=0"],
        &["lubricant.gamma = 0", "finite and > 0"],
    ),
    // Non-finite values.
    case(
        "nan end",
        None,
        &["time.end=nan"],
        &["time.end = nan", "finite"],
    ),
    case(
        "inf tau_max",
        None,
        &["lubricant.tau_max=inf"],
        &["lubricant.tau_max = inf", "finite"],
    ),
    case(
        "nan velocity",
        None,
        &["drive.velocity=nan"],
        &["drive.velocity = nan", "finite"],
    ),
    case(
        "nan probe radius",
        None,
        &["output.probe_radii=[nan]"],
        &["output.probe_radii = nan", "within [0, contact.radius"],
    ),
    case(
        "inf A0",
        None,
        &["temperature.A0=-inf"],
        &["temperature.A0 = -inf", "finite"],
    ),
    case(
        "nan g_eff",
        None,
        &["contact.g_eff=nan"],
        &["contact.g_eff = nan", "finite and within [1e-15, "],
    ),
    // Output times and radii.
    case(
        "profile time after end",
        None,
        &["output.profile_times=[2e-5]"],
        &[
            "output.profile_times = 2e-5",
            "within [0, time.end = 1e-5] s",
        ],
    ),
    case(
        "negative profile time",
        None,
        &["output.profile_times=[0.0, -1e-6]"],
        &["output.profile_times = -1e-6", "within [0, time.end"],
    ),
    case(
        "probe radius at the edge",
        None,
        &["output.probe_radii=[2e-5]"],
        &[
            "output.probe_radii = 2e-5",
            "within [0, contact.radius = 2e-5) m",
        ],
    ),
    case(
        "negative probe radius",
        None,
        &["output.probe_radii=[-1e-6]"],
        &["output.probe_radii = -1e-6", "within [0, contact.radius"],
    ),
    case(
        "negative merge gap",
        None,
        &["output.event_merge_gap=-1"],
        &["output.event_merge_gap = -1", ">= 0"],
    ),
    case(
        "zero series interval",
        None,
        &["output.series_interval=0"],
        &["output.series_interval = 0", "> 0"],
    ),
    // Contradictions and incomplete sets.
    case(
        "g_eff and g1",
        None,
        &["contact.g1=1e9"],
        &[
            "contact.g1 = 1e9",
            "contact.g_eff",
            "either g_eff or all of g1, nu1, g2, nu2",
        ],
    ),
    case(
        "incomplete Eq. 9 set",
        Some(("g_eff = 1e9", "g1 = 1e9\nnu1 = 0.3\ng2 = 1e9")),
        &[],
        &[
            "missing required key `contact.nu2`",
            "all of contact.g1, nu1, g2, nu2",
        ],
    ),
    case(
        "nu out of range",
        Some(("g_eff = 1e9", "g1 = 1e9\nnu1 = 0.6\ng2 = 1e9\nnu2 = 0.3")),
        &[],
        &["contact.nu1 = 0.6", "-1 < nu <= 0.5"],
    ),
    case(
        "no modulus",
        Some(("g_eff = 1e9", "")),
        &[],
        &["missing required key `contact.g_eff`", "finite and > 0 Pa"],
    ),
    case(
        "spring without mass",
        Some(("mass = 0.1\n", "")),
        &[],
        &[
            "missing required key `drive.mass`",
            "drive.mass is required when drive.kind = \"spring\"",
        ],
    ),
    case(
        "rigid with stiffness",
        None,
        &["drive.kind=rigid"],
        &[
            "drive.stiffness = 500",
            "contradictory",
            "drive.kind = \"rigid\"",
            "no stiffness, mass or damping",
        ],
    ),
    case(
        "rigid with damping",
        Some(("stiffness = 500.0\nmass = 0.1\n", "")),
        &["drive.kind=rigid", "drive.damping=0"],
        &[
            "drive.damping = 0",
            "contradictory",
            "drive.kind = \"rigid\"",
            "no stiffness, mass or damping",
        ],
    ),
    case(
        "negative damping",
        None,
        &["drive.damping=-0.5"],
        &["drive.damping = -0.5", "finite and >= 0 N·s/m"],
    ),
    case(
        "negative viscosity",
        None,
        &["lubricant.viscosity=-2"],
        &["lubricant.viscosity = -2", "finite and >= 0 Pa·s"],
    ),
    case(
        "viscosity with the literal scheme",
        None,
        &["time.scheme=literal", "lubricant.viscosity=2.5"],
        &[
            "lubricant.viscosity = 2.5",
            "0 with time.scheme = \"literal\"",
            "time.scheme = \"accurate\"",
        ],
    ),
    case(
        "infinite damping",
        None,
        &["drive.damping=inf"],
        &["drive.damping", "finite and >= 0 N·s/m"],
    ),
    case(
        "unknown scheme",
        None,
        &["time.scheme=fast"],
        &["time.scheme = \"fast\"", "\"accurate\", \"literal\""],
    ),
    case(
        "unknown noise kind",
        None,
        &["lubricant.noise.kind=pink"],
        &[
            "lubricant.noise.kind = \"pink\"",
            "\"gaussian\", \"floor\", \"off\"",
        ],
    ),
    case(
        "sigma with floor noise",
        None,
        &["lubricant.noise.sigma=1"],
        &[
            "lubricant.noise.sigma = 1",
            "lubricant.noise.kind = \"floor\"",
            "only with kind = \"gaussian\"",
        ],
    ),
    case(
        "negative seed",
        None,
        &["lubricant.noise.kind=gaussian", "lubricant.noise.seed=-1"],
        &["lubricant.noise.seed = -1", "0 ..= "],
    ),
    case(
        "relaxation without t_relax",
        None,
        &["temperature.law=relaxation", "temperature.A0=1.5e6"],
        &["missing required key `temperature.t_relax`", "> 0 s"],
    ),
    case(
        "floor above threshold",
        None,
        &["lubricant.noise.floor=0.5"],
        &[
            "lubricant.noise.floor = 0.5",
            "below lubricant.melt_threshold",
        ],
    ),
    // Keys within their ranges whose derived numbers overflow or underflow: the key that
    // moved them is named, not a default derived from it.
    case(
        "a subnormal tau_max",
        None,
        &["lubricant.tau_max=1e-320"],
        &["lubricant.tau_max = 1e-320", "within [1e-15, 1e20] Pa"],
    ),
    case(
        "eps_max making b zero",
        None,
        &["lubricant.eps_max=1e-320"],
        &["lubricant.eps_max = 1e-320", "(here b = 0)"],
    ),
    case(
        "eps_max making b infinite",
        None,
        &["lubricant.eps_max=1e308"],
        &["lubricant.eps_max = 1e308", "b = inf"],
    ),
    case(
        "a beyond the moduli's range",
        None,
        &["lubricant.a=1e308"],
        &["lubricant.a = 1e308", "within [1e-15, 1e20] Pa"],
    ),
    case(
        "a tolerance below double precision",
        None,
        &["time.tolerance=1e-300"],
        &["time.tolerance = 1e-300", "> 1e-12 and < 1"],
    ),
    case(
        "a mass making omega infinite",
        None,
        &["drive.mass=1e-320"],
        &["drive.mass = 1e-320", "omega = √(K/m)"],
    ),
    case(
        "a subnormal series interval",
        None,
        &["output.series_interval=1e-320"],
        &["output.series_interval = 1e-320", ">= time.end / 1e12"],
    ),
    case(
        "a date as the name",
        Some(("name = \"base\"", "name = 1979-05-27")),
        &[],
        &["name = 1979-05-27", "a string"],
    ),
    // The first-order film (docs/model.md#the-first-order-film).
    case(
        "negative cubic",
        None,
        &["lubricant.cubic=-1e5"],
        &["lubricant.cubic = -1e5", "within [0, 1e20] Pa"],
    ),
    case(
        "nan cubic",
        None,
        &["lubricant.cubic=nan"],
        &["lubricant.cubic = nan", "within [0, 1e20] Pa"],
    ),
    case(
        "infinite cubic",
        None,
        &["lubricant.cubic=inf"],
        &["lubricant.cubic = inf", "within [0, 1e20] Pa"],
    ),
    case(
        "cubic beyond its bound",
        None,
        &["lubricant.cubic=1e21"],
        &["lubricant.cubic = 1e21", "within [0, 1e20] Pa"],
    ),
    case(
        "eps_melt at eps_c",
        None,
        &["lubricant.eps_melt=1.7"],
        &[
            "lubricant.eps_melt = 1.7",
            "> eps_c = 1.7320508075688772",
            "temperature.A0 = 1.5e6 Pa",
        ],
    ),
    case(
        "eps_melt below eps_c at a lower temperature coefficient",
        None,
        &["temperature.A0=3e6", "lubricant.eps_melt=2"],
        &[
            "lubricant.eps_melt = 2",
            "> eps_c = 2.449",
            "temperature.A0 = 3e6 Pa",
        ],
    ),
    case(
        "negative eps_melt",
        None,
        &["lubricant.eps_melt=-2"],
        &["lubricant.eps_melt = -2", "finite and > eps_c"],
    ),
    case(
        "nan eps_melt",
        None,
        &["lubricant.eps_melt=nan"],
        &["lubricant.eps_melt = nan", "finite and > eps_c"],
    ),
    case(
        "both cubic and eps_melt",
        None,
        &["lubricant.cubic=4e6", "lubricant.eps_melt=2.25"],
        &[
            "lubricant.eps_melt = 2.25",
            "contradictory with lubricant.cubic = 4e6",
            "either lubricant.cubic (b3) or lubricant.eps_melt",
        ],
    ),
    // Bad --set syntax.
    case(
        "set without =",
        None,
        &["contact.nodes"],
        &["--set \"contact.nodes\"", "no `=`", "allowed"],
    ),
    case(
        "set with empty key",
        None,
        &["=5"],
        &["--set \"=5\"", "empty key", "allowed"],
    ),
    case(
        "set with empty key part",
        None,
        &["contact..nodes=5"],
        &["--set \"contact..nodes=5\"", "not a bare key", "allowed"],
    ),
    case(
        "set with empty value",
        None,
        &["contact.nodes="],
        &["--set \"contact.nodes=\"", "empty value"],
    ),
    case(
        "set through a value",
        None,
        &["name.first=x"],
        &["--set \"name.first=x\"", "not a table"],
    ),
    // TOML syntax.
    case(
        "syntax error",
        Some(("tau_max = 1e6", "tau_max = = 1e6")),
        &[],
        &["not valid TOML at line", "tau_max = = 1e6", "allowed"],
    ),
    case(
        "duplicate key",
        Some(("eps_max = 1.0", "eps_max = 1.0\neps_max = 2.0")),
        &[],
        &["not valid TOML at line", "eps_max = 2.0"],
    ),
];

#[test]
fn bad_scenes_exit_2_and_name_key_value_and_range() {
    assert!(CASES.len() >= 30);
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for (i, c) in CASES.iter().enumerate() {
        let text = match c.edit {
            Some((find, replace)) => {
                assert!(
                    BASE.contains(find),
                    "{}: {find:?} not in the base scene",
                    c.name
                );
                BASE.replacen(find, replace, 1)
            }
            None => BASE.to_string(),
        };
        let scene = tmp.path().join(format!("case{i}.toml"));
        std::fs::write(&scene, text).unwrap();
        let out_dir = tmp.path().join(format!("out{i}"));
        let mut args = vec![
            "run".to_string(),
            scene.display().to_string(),
            "--out".to_string(),
            out_dir.display().to_string(),
            "--quiet".to_string(),
        ];
        for s in c.sets {
            args.push("--set".to_string());
            args.push((*s).to_string());
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = run(&args);
        let (_, stderr) = texts(&out);
        let mut problems = Vec::new();
        if out.status.code() != Some(2) {
            problems.push(format!("exit status {:?}, expected 2", out.status.code()));
        }
        if !stderr.starts_with("error: ") {
            problems.push("stderr does not start with `error: `".to_string());
        }
        for e in c.expect {
            if !stderr.contains(e) {
                problems.push(format!("message lacks {e:?}"));
            }
        }
        if out_dir.exists() {
            problems.push("the --out directory was created".to_string());
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{}: {} — stderr: {stderr}",
                c.name,
                problems.join("; ")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn check_rejects_bad_scenes_too() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("s.toml");
    std::fs::write(&scene, BASE).unwrap();
    let path = scene.display().to_string();
    let out = run(&["check", &path, "--set", "contact.radius=-1"]);
    assert_eq!(out.status.code(), Some(2));
    let (_, stderr) = texts(&out);
    assert!(stderr.starts_with("error: contact.radius = -1"), "{stderr}");
    // And the base scene itself is fine.
    let out = run(&["check", &path]);
    assert_eq!(out.status.code(), Some(0), "{}", texts(&out).1);
}

#[test]
fn unreadable_scene_and_usage_errors_exit_2() {
    let out = run(&["check", "/nonexistent/scene.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(texts(&out).1.contains("cannot read scene file"));
    // clap usage errors: missing --out, unknown subcommand, unknown flag.
    for args in [
        &["run", "x.toml"][..],
        &["frobnicate"][..],
        &["check", "x.toml", "--bogus"][..],
    ] {
        let out = run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(texts(&out).1.starts_with("error: "), "{args:?}");
    }
}

#[test]
fn resume_without_checkpoint_exits_2() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().display().to_string();
    let out = run(&["resume", &dir]);
    assert_eq!(out.status.code(), Some(2));
    let (_, stderr) = texts(&out);
    assert!(stderr.starts_with("error: no checkpoint in "), "{stderr}");
}
