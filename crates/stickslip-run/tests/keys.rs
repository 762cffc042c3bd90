//! The key table agrees with the scene file's serde structs, with the resolved defaults and
//! with the engine's own checks.

use stickslip_run::keys::{self, DefaultValue, KEYS, Range, ValueType};
use stickslip_run::scene::{Scene, SceneError};

fn minimal() -> toml::Table {
    r#"
name = "minimal"
[lubricant]
tau_max = 1e6
eps_max = 1.0
a = 1e6
gamma = 10.0
[contact]
radius = 2e-5
film_thickness = 1e-7
g_eff = 1e9
[drive]
stiffness = 500.0
mass = 0.1
velocity = 1.0
[time]
end = 1e-3
"#
    .parse()
    .unwrap()
}

fn insert(t: &mut toml::Table, path: &str, v: toml::Value) {
    let parts: Vec<&str> = path.split('.').collect();
    let (last, parents) = parts.split_last().unwrap();
    let mut table = t;
    for p in parents {
        table = table
            .entry((*p).to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            .as_table_mut()
            .unwrap();
    }
    table.insert((*last).to_string(), v);
}

fn get<'a>(t: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let mut v: Option<&toml::Value> = None;
    let mut table = t;
    for p in path.split('.') {
        v = table.get(p);
        if let Some(toml::Value::Table(sub)) = v {
            table = sub;
        }
    }
    v
}

fn leaf_paths(t: &toml::Table, prefix: &str, out: &mut Vec<String>) {
    for (k, v) in t {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(sub) => leaf_paths(sub, &path, out),
            _ => out.push(path),
        }
    }
}

#[test]
fn every_key_of_the_table_is_a_key_of_the_scene_file_and_back() {
    // A scene file with every field set, serialised: its leaf paths are the table's keys.
    let mut full = Scene::default();
    let text = r#"
name = "x"
[lubricant]
tau_max = 1.0
eps_max = 1.0
a = 1.0
gamma = 1.0
melt_threshold = 1.0
cubic = 1.0
eps_melt = 1.0
viscosity = 1.0
[lubricant.noise]
kind = "floor"
sigma = 1.0
floor = 1.0
seed = 1
[temperature]
law = "constant"
A0 = 1.0
t_relax = 1.0
[contact]
radius = 1.0
film_thickness = 1.0
g_eff = 1.0
g1 = 1.0
nu1 = 1.0
g2 = 1.0
nu2 = 1.0
nodes = 1
grid = "graded"
grading = 2.0
model = "radial"
substrate = "elastic"
[drive]
kind = "spring"
stiffness = 1.0
mass = 1.0
damping = 1.0
velocity = 1.0
integrator = "verlet"
[time]
end = 1.0
travel = 1.0
dt = 1.0
scheme = "accurate"
stepping = "fixed"
tolerance = 1.0
dt_max = 1.0
dt_min = 1.0
max_events = 1
max_open_event = 1.0
until = "periodic"
steady_cycles = 1
steady_rtol = 1.0
[output]
profile_times = [1.0]
probe_radii = [1.0]
event_merge_gap = 1.0
event_recovery = 1.0
slip_drop = 0.5
series_interval = 1.0
[numerics]
coupling_tol = 1.0
runaway_stress_factor = 1.0
operator = "auto"
film_step = "frozen"
phi_error_floor = 0.5
event_phi_error_floor = 0.5
event_tolerance_factor = 2.0
"#;
    full = toml::from_str(text).unwrap_or(full);
    let mut paths = Vec::new();
    leaf_paths(&full.to_table(), "", &mut paths);
    paths.sort();
    let mut table: Vec<String> = KEYS.iter().map(|k| k.path.to_string()).collect();
    table.sort();
    assert_eq!(paths, table, "scene file fields vs key table");
}

/// Scenes that between them take every default: the minimal one, and variants that switch
/// on the keys that only exist beside another choice.
fn variants() -> Vec<(&'static str, toml::Table)> {
    let with = |sets: &[(&str, toml::Value)]| {
        let mut t = minimal();
        for (path, v) in sets {
            insert(&mut t, path, v.clone());
        }
        t
    };
    vec![
        ("minimal", minimal()),
        (
            "gaussian",
            with(&[("lubricant.noise.kind", "gaussian".into())]),
        ),
        ("literal", with(&[("time.scheme", "literal".into())])),
        (
            "relaxation",
            with(&[
                ("temperature.law", "relaxation".into()),
                ("temperature.A0", 1e6.into()),
                ("temperature.t_relax", 1e-3.into()),
            ]),
        ),
        (
            "capped",
            with(&[
                ("time.end", 2e-3.into()),
                ("time.dt", 1e-6.into()),
                ("time.dt_max", 5e-7.into()),
                ("time.tolerance", 1e-3.into()),
            ]),
        ),
        ("graded", with(&[("contact.grid", "graded".into())])),
        ("travel", {
            // The window as the drive's travel: time.end derived from it.
            let mut t = with(&[("time.travel", 2e-3.into())]);
            if let Some(toml::Value::Table(time)) = t.get_mut("time") {
                time.remove("end");
            }
            t
        }),
        (
            "homogeneous",
            with(&[
                ("contact.model", "homogeneous".into()),
                ("contact.nodes", 1.into()),
            ]),
        ),
        (
            "graded_fine",
            with(&[
                ("contact.grid", "graded".into()),
                ("contact.nodes", 20_000.into()),
            ]),
        ),
    ]
}

#[test]
fn every_default_resolves_as_the_registry_states_it() {
    let mut fixed = 0;
    let mut derived = std::collections::BTreeSet::new();
    for (label, source) in variants() {
        let resolved = Scene::resolve_table(source.clone(), &[] as &[&str])
            .unwrap_or_else(|e| panic!("{label}: {e}"));
        let table = resolved.to_table();
        for key in keys::all() {
            let info = key.info();
            if get(&source, info.path).is_some() {
                continue;
            }
            let (Some(expected), Some(actual)) =
                (key.default_in(&resolved.resolved), get(&table, info.path))
            else {
                continue;
            };
            assert_eq!(
                &expected, actual,
                "{label}: {} resolved to {actual}, its registry default is {expected}",
                info.path
            );
            match info.default {
                DefaultValue::Derived(_) => {
                    derived.insert(info.path);
                }
                _ => fixed += 1,
            }
        }
    }
    assert!(fixed >= 60, "only {fixed} fixed defaults checked");
    let every_derived: std::collections::BTreeSet<_> = KEYS
        .iter()
        .filter(|k| matches!(k.default, DefaultValue::Derived(_)))
        .map(|k| k.path)
        .collect();
    assert_eq!(derived, every_derived, "derived defaults not exercised");
}

#[test]
fn derived_defaults_are_what_the_reference_says() {
    // (key, its default as the reference words it, per variant the value that wording gives,
    // computed here by hand from the variants' keys).
    type Case = (&'static str, &'static str, Vec<(&'static str, toml::Value)>);
    let cases: Vec<Case> = vec![
        (
            "temperature.A0",
            "1.5·tau_max/eps_max (law = \"constant\")",
            // tau_max = 1e6, eps_max = 1.
            vec![("minimal", toml::Value::Float(1.5e6))],
        ),
        (
            "time.stepping",
            "adaptive for the accurate scheme without gaussian noise, else fixed",
            vec![
                ("minimal", toml::Value::String("adaptive".into())),
                ("gaussian", toml::Value::String("fixed".into())),
                ("literal", toml::Value::String("fixed".into())),
            ],
        ),
        (
            "time.dt_max",
            "time.end (no cap)",
            vec![
                ("minimal", toml::Value::Float(1e-3)),
                ("relaxation", toml::Value::Float(1e-3)),
            ],
        ),
        (
            "time.dt_min",
            "1e-6·min(time.dt, time.dt_max)",
            vec![
                // dt = 1e-8 (its default) < dt_max = 1e-3.
                ("minimal", toml::Value::Float(1e-6 * 1e-8)),
                // dt = 1e-6 > dt_max = 5e-7.
                ("capped", toml::Value::Float(1e-6 * 5e-7)),
            ],
        ),
        (
            "numerics.coupling_tol",
            "time.tolerance / 100 (adaptive), 1e-10 (fixed)",
            vec![
                ("minimal", toml::Value::Float(5e-5 / 100.0)),
                ("capped", toml::Value::Float(1e-3 / 100.0)),
                ("gaussian", toml::Value::Float(1e-10)),
            ],
        ),
        (
            "contact.grid",
            "graded for the accurate scheme's radial contact of N >= 10 nodes (it verifies: reports/convergence.md, section 8); uniform for the literal scheme, the homogeneous model and fewer nodes, where a grading has nothing to spread",
            vec![
                ("minimal", toml::Value::String("graded".into())),
                ("literal", toml::Value::String("uniform".into())),
                ("homogeneous", toml::Value::String("uniform".into())),
            ],
        ),
        (
            "contact.grading",
            "3, or 11.5/log10(N) where that is smaller (N > 6800, so that N^(−p) >= 3e-12)",
            vec![
                // N = 200 (the default).
                ("graded", toml::Value::Float(3.0)),
                ("graded_fine", toml::Value::Float(11.5 / 20_000f64.log10())),
            ],
        ),
        (
            "time.end",
            "time.travel / |drive.velocity| when time.travel is given; else required",
            // V0 = 1 m/s.
            vec![("travel", toml::Value::Float(2e-3))],
        ),
        (
            "output.profile_times",
            "[time.end]",
            vec![
                (
                    "minimal",
                    toml::Value::Array(vec![toml::Value::Float(1e-3)]),
                ),
                ("capped", toml::Value::Array(vec![toml::Value::Float(2e-3)])),
            ],
        ),
    ];
    let scenes: std::collections::HashMap<_, _> = variants().into_iter().collect();
    for (path, doc, values) in &cases {
        let info = keys::find(path).unwrap();
        assert_eq!(info.default, DefaultValue::Derived(doc), "{path}'s wording");
        for (label, expected) in values {
            let resolved = Scene::resolve_table(scenes[label].clone(), &[] as &[&str])
                .unwrap()
                .to_table();
            let actual = get(&resolved, path).unwrap();
            let same = match (expected, actual) {
                (toml::Value::Float(e), toml::Value::Float(a)) => (e - a).abs() <= 1e-15 * e.abs(),
                (e, a) => e == a,
            };
            assert!(
                same,
                "{path} in {label}: {actual}, the reference says {expected}"
            );
        }
    }
    let documented = KEYS
        .iter()
        .filter(|k| matches!(k.default, DefaultValue::Derived(_)))
        .count();
    assert_eq!(
        documented,
        cases.len(),
        "a derived default without a case here"
    );
}

#[test]
fn choice_words_are_the_accepted_words() {
    for key in KEYS.iter() {
        let ValueType::Choice(words) = key.value else {
            continue;
        };
        for w in words {
            let mut t = minimal();
            insert(&mut t, key.path, toml::Value::String((*w).to_string()));
            if let Err(SceneError::Invalid { key: k, .. } | SceneError::WrongType { key: k, .. }) =
                Scene::resolve_table(t, &[] as &[&str])
            {
                assert_ne!(k, key.path, "{}: word {w:?} rejected", key.path);
            }
        }
        let mut t = minimal();
        insert(&mut t, key.path, toml::Value::String("bogus".into()));
        match Scene::resolve_table(t, &[] as &[&str]) {
            Err(SceneError::Invalid {
                key: k, allowed, ..
            }) => {
                assert_eq!(k, key.path);
                for w in words {
                    assert!(allowed.contains(&format!("{w:?}")), "{allowed}");
                }
            }
            other => panic!("{}: bogus word gave {other:?}", key.path),
        }
    }
}

#[test]
fn values_outside_a_keys_own_range_are_rejected_naming_the_key() {
    let mut checked = 0;
    for key in KEYS.iter() {
        let bad = match key.range {
            Range::Positive => Some(-1.0),
            Range::NonNegative => Some(-1.0),
            Range::Above(lo) => Some(lo),
            Range::Closed(_, hi) => Some(hi * 10.0),
            Range::Open(_, hi) => Some(hi),
            Range::OpenClosed(lo, _) => Some(lo),
            _ => None,
        };
        let Some(bad) = bad else { continue };
        let mut t = minimal();
        // Keys that only exist beside another choice.
        match key.path {
            "lubricant.noise.sigma" => {
                insert(&mut t, "lubricant.noise.kind", "gaussian".into());
            }
            "temperature.t_relax" => {
                insert(&mut t, "temperature.law", "relaxation".into());
                insert(&mut t, "temperature.A0", 1.5e6.into());
            }
            p if (p.starts_with("contact.g") || p.starts_with("contact.nu"))
                && p != "contact.g_eff" =>
            {
                t["contact"].as_table_mut().unwrap().remove("g_eff");
                for (k, v) in [("g1", 1e9), ("nu1", 0.3), ("g2", 1e9), ("nu2", 0.3)] {
                    insert(&mut t, &format!("contact.{k}"), v.into());
                }
            }
            _ => {}
        }
        let value = if key.value == ValueType::Integer {
            toml::Value::Integer(bad as i64)
        } else {
            toml::Value::Float(bad)
        };
        insert(&mut t, key.path, value);
        let err = Scene::resolve_table(t, &[] as &[&str]).expect_err(key.path);
        assert_eq!(err.key(), Some(key.path), "{}: {err}", key.path);
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} ranges checked");
}
