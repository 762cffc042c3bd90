//! The key table agrees with the scene file's serde structs, with the resolved defaults and
//! with the engine's own checks.

use stickslip_run::keys::{DefaultValue, KEYS, Range, ValueType};
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
model = "radial"
substrate = "elastic"
[drive]
kind = "spring"
stiffness = 1.0
mass = 1.0
velocity = 1.0
integrator = "verlet"
[time]
end = 1.0
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
series_interval = 1.0
[numerics]
coupling_tol = 1.0
runaway_stress_factor = 1.0
operator = "auto"
"#;
    full = toml::from_str(text).unwrap_or(full);
    let mut paths = Vec::new();
    leaf_paths(&full.to_table(), "", &mut paths);
    paths.sort();
    let mut table: Vec<String> = KEYS.iter().map(|k| k.path.to_string()).collect();
    table.sort();
    assert_eq!(paths, table, "scene file fields vs key table");
}

#[test]
fn documented_defaults_are_the_resolved_values() {
    let resolved = Scene::resolve_table(minimal(), &[] as &[&str])
        .unwrap()
        .to_table();
    let mut checked = 0;
    for key in KEYS {
        let DefaultValue::Value(text) = key.default else {
            continue;
        };
        let text = text.split(" (").next().unwrap();
        let Some(actual) = get(&resolved, key.path) else {
            // A default of a kind not chosen by the minimal scene (e.g. gaussian sigma).
            continue;
        };
        let expected: toml::Value = format!("v = {text}")
            .parse::<toml::Table>()
            .ok()
            .and_then(|mut t| t.remove("v"))
            .unwrap_or_else(|| toml::Value::String(text.to_string()));
        let same = match (&expected, actual) {
            (toml::Value::Integer(i), toml::Value::Float(f)) => *i as f64 == *f,
            (toml::Value::Float(e), toml::Value::Integer(i)) => *e == *i as f64,
            (e, a) => e == a,
        };
        assert!(
            same,
            "{}: documented default {expected}, resolved {actual}",
            key.path
        );
        checked += 1;
    }
    assert!(checked >= 15, "only {checked} defaults checked");
}

#[test]
fn choice_words_are_the_accepted_words() {
    for key in KEYS {
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
    for key in KEYS {
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
