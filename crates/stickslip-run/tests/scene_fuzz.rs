//! Property tests of the scene parser: arbitrary bytes (also as a file, so invalid UTF-8 reaches
//! the reader), TOML documents built from the real section and key names with values of every
//! TOML type (NaN, ±inf, huge, negative, strings, arrays, tables, booleans, datetimes), the same
//! values given as `--set` overrides, and valid scenes with one key mutated. The parser must
//! never panic, and every error must be non-empty and name its key (a key error), the line and
//! column (a syntax error), the argument (a bad `--set`) or the file (an unreadable scene).
//!
//! `scene_resolution.rs` already feeds 3000 TOML-ish ASCII strings and single-byte mutations;
//! this adds arbitrary bytes, typed values at real keys and checks of the messages.

use crate::common;

use proptest::prelude::*;
use proptest::test_runner::Config;
use std::collections::BTreeSet;
use std::io::Write;
use std::sync::OnceLock;
use stickslip_run::scene::{Scene, SceneError};
use toml::Value;

const NONE: &[&str] = &[];

/// Overrides that make fig2 resolve with every optional key filled in, in several variants, so
/// their key paths can be collected.
const VARIANTS: &[&[&str]] = &[
    &[],
    &["lubricant.noise.kind=gaussian"],
    &["lubricant.noise.kind=off"],
    &[
        "temperature.law=relaxation",
        "temperature.A0=1.5e6",
        "temperature.t_relax=1e-3",
    ],
];

/// Scene keys (docs/reference.md) that a resolved scene may leave out (e.g. Eq. 9's moduli).
const EXTRA_KEYS: &[&str] = &[
    "contact.g1",
    "contact.nu1",
    "contact.g2",
    "contact.nu2",
    "lubricant.noise.floor",
    "lubricant.noise.sigma",
    "lubricant.noise.seed",
    "temperature.t_relax",
    "drive.stiffness",
    "drive.mass",
];

/// Strings the scene's choice keys accept, so random documents reach the resolution stage.
const WORDS: &[&str] = &[
    "gaussian",
    "floor",
    "off",
    "constant",
    "relaxation",
    "radial",
    "homogeneous",
    "elastic",
    "rigid",
    "spring",
    "verlet",
    "rk4",
    "literal",
    "accurate",
    "adaptive",
    "fixed",
    "",
];

fn fig2_text() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| std::fs::read_to_string(common::scene("fig2")).unwrap())
}

/// The fig2 scene resolved (every default filled in), as a TOML table.
fn resolved_table(overrides: &[&str]) -> Option<toml::Table> {
    let r = Scene::from_toml_str(fig2_text(), overrides).ok()?;
    toml::Table::try_from(&r.resolved).ok()
}

fn leaf_paths(t: &toml::Table, prefix: &str, out: &mut BTreeSet<String>) {
    walk(t, prefix, &mut |path, v| {
        if !v.is_table() {
            out.insert(path.to_string());
        }
    });
}

/// Calls `f` with the dotted path and value of every entry of `t`, tables included.
fn walk(t: &toml::Table, prefix: &str, f: &mut impl FnMut(&str, &Value)) {
    for (k, v) in t {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        f(&path, v);
        if let Value::Table(sub) = v {
            walk(sub, &path, f);
        }
    }
}

/// Paths of the sections (tables) and of the keys that take arrays, from resolved scenes.
fn tables_and_arrays() -> &'static (BTreeSet<String>, BTreeSet<String>) {
    static SETS: OnceLock<(BTreeSet<String>, BTreeSet<String>)> = OnceLock::new();
    SETS.get_or_init(|| {
        let (mut tables, mut arrays) = (BTreeSet::new(), BTreeSet::new());
        for v in VARIANTS {
            if let Some(t) = resolved_table(v) {
                walk(&t, "", &mut |path, v| {
                    match v {
                        Value::Table(_) => tables.insert(path.to_string()),
                        Value::Array(_) => arrays.insert(path.to_string()),
                        _ => false,
                    };
                });
            }
        }
        assert!(tables.contains("lubricant.noise") && arrays.contains("output.probe_radii"));
        (tables, arrays)
    })
}

/// Every key path the scene knows: the leaves of resolved variants of fig2 (so keys added to
/// the scene later are covered without editing this list) and [`EXTRA_KEYS`].
fn known_keys() -> &'static [String] {
    static KEYS: OnceLock<Vec<String>> = OnceLock::new();
    KEYS.get_or_init(collect_keys)
}

fn collect_keys() -> Vec<String> {
    let mut keys: BTreeSet<String> = EXTRA_KEYS.iter().map(|k| (*k).to_string()).collect();
    for v in VARIANTS {
        if let Some(t) = resolved_table(v) {
            leaf_paths(&t, "", &mut keys);
        }
    }
    assert!(keys.len() > 30, "too few keys found: {keys:?}");
    keys.into_iter().collect()
}

fn float() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(f64::MAX),
        Just(-f64::MAX),
        Just(1e300),
        Just(5e-324),
        Just(0.0),
        Just(-0.0),
        any::<f64>(),
        -1e3..1e3f64,
        1e-12..1e-3f64,
    ]
}

fn string() -> impl Strategy<Value = String> {
    prop_oneof![
        proptest::sample::select(WORDS).prop_map(str::to_string),
        ".{0,24}",
        "[a-z_.=\\[\\]\"' ]{0,16}",
    ]
}

fn scalar() -> impl Strategy<Value = Value> {
    prop_oneof![
        any::<i64>().prop_map(Value::Integer),
        prop_oneof![
            Just(0i64),
            Just(-1),
            Just(1),
            Just(i64::MAX),
            Just(i64::MIN),
            2..5000i64
        ]
        .prop_map(Value::Integer),
        float().prop_map(Value::Float),
        any::<bool>().prop_map(Value::Boolean),
        string().prop_map(Value::String),
        Just(Value::Datetime(
            "1979-05-27T07:32:00Z".parse().expect("a TOML datetime")
        )),
    ]
}

/// Any TOML value: scalars, and arrays and tables of them, nested up to three deep.
fn value() -> impl Strategy<Value = Value> {
    scalar().prop_recursive(3, 24, 5, |inner| {
        prop_oneof![
            proptest::collection::vec(inner.clone(), 0..5).prop_map(Value::Array),
            proptest::collection::btree_map("[a-z_]{1,8}", inner, 0..4)
                .prop_map(|m| Value::Table(m.into_iter().collect())),
        ]
    })
}

/// Inserts `v` at the dotted `path` of `t`, making the tables on the way (and replacing
/// whatever non-table is in their place).
fn insert(t: &mut toml::Table, path: &str, v: Value) {
    let mut keys: Vec<&str> = path.split('.').collect();
    let last = keys.pop().unwrap_or_default();
    let mut table = t;
    for k in keys {
        let entry = table
            .entry(k.to_string())
            .or_insert_with(|| Value::Table(toml::Table::new()));
        if !entry.is_table() {
            *entry = Value::Table(toml::Table::new());
        }
        let Value::Table(sub) = entry else {
            unreachable!("made a table just above")
        };
        table = sub;
    }
    table.insert(last.to_string(), v);
}

/// Top-level names of the scene: `name` and the section names.
fn sections(keys: &[String]) -> BTreeSet<String> {
    keys.iter()
        .filter_map(|k| k.split('.').next())
        .map(str::to_string)
        .collect()
}

/// The checks every error must pass: a message, and in it what the error is about.
fn check_error(e: &SceneError) -> Result<(), TestCaseError> {
    let msg = e.to_string();
    prop_assert!(!msg.trim().is_empty(), "empty message for {e:?}");
    match e {
        SceneError::Syntax { line, column, .. } => {
            prop_assert!(*line >= 1 && *column >= 1, "{msg}");
            prop_assert!(
                msg.contains(&format!("line {line}, column {column}")),
                "{msg}"
            );
        }
        SceneError::Read { path, .. } => {
            prop_assert!(!path.is_empty() && msg.contains(path.as_str()), "{msg}")
        }
        SceneError::Override { arg, .. } => {
            prop_assert!(msg.contains(&format!("{arg:?}")), "{msg}")
        }
        _ => {
            let key = e.key().unwrap_or_default();
            prop_assert!(!key.is_empty(), "no key in {e:?}");
            prop_assert!(msg.contains(key), "key {key:?} not in: {msg}");
        }
    }
    Ok(())
}

/// A key error must be about a key of the scene or one the document has (unknown keys are
/// named as written; `(top level)` stands for the document itself), and a wrong type must be
/// corrected by the key's own type: a table for a section, an array only where arrays go.
fn check_key_error(
    e: &SceneError,
    known: &BTreeSet<String>,
    doc: &toml::Table,
) -> Result<(), TestCaseError> {
    let Some(key) = e.key() else {
        return Ok(());
    };
    let mut present = BTreeSet::new();
    leaf_paths(doc, "", &mut present);
    let in_doc = present
        .iter()
        .any(|p| p == key || p.starts_with(&format!("{key}.")))
        || doc.contains_key(key);
    prop_assert!(
        key == "(top level)" || known.contains(key.split('.').next().unwrap_or("")) || in_doc,
        "{key:?} is neither a scene key nor in the document: {e}"
    );
    if let SceneError::WrongType { allowed, .. } = e {
        let (tables, arrays) = tables_and_arrays();
        if tables.contains(key) {
            prop_assert!(allowed.starts_with("a table"), "{e}");
        }
        if allowed.contains("array") {
            prop_assert!(arrays.contains(key), "{e}");
        }
    }
    Ok(())
}

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config(256))]

    /// (a) Arbitrary bytes, as text and as a file (invalid UTF-8 is a read error naming the
    /// file), alone and spliced into a valid scene.
    #[test]
    fn arbitrary_bytes_never_panic(
        bytes in proptest::collection::vec(any::<u8>(), 0..400),
        splice_at in any::<proptest::sample::Index>(),
    ) {
        let base = fig2_text().as_bytes();
        let at = splice_at.index(base.len() + 1);
        let spliced = [&base[..at], &bytes[..], &base[at..]].concat();
        let dir = tempfile::tempdir().unwrap();
        for (i, b) in [&bytes, &spliced].into_iter().enumerate() {
            if let Err(e) = Scene::from_toml_str(&String::from_utf8_lossy(b), NONE) {
                check_error(&e)?;
            }
            let path = dir.path().join(format!("scene{i}.toml"));
            std::fs::File::create(&path).unwrap().write_all(b).unwrap();
            match Scene::from_path(&path, NONE) {
                Err(e @ SceneError::Read { .. }) => {
                    prop_assert!(std::str::from_utf8(b).is_err(), "{e}");
                    check_error(&e)?;
                }
                Err(e) => check_error(&e)?,
                Ok(_) => {}
            }
        }
    }
}

proptest! {
    #![proptest_config(config(512))]

    /// (b) Documents of real section and key names (and a few unknown ones) with values of
    /// random types, parsed as text and given as `--set` overrides.
    #[test]
    fn random_documents_of_real_keys_never_panic(
        entries in proptest::collection::vec(
            (any::<proptest::sample::Index>(), value(), 0u8..10), 0..24),
    ) {
        let keys = known_keys();
        let known: BTreeSet<String> = sections(keys);
        let mut doc = toml::Table::new();
        let mut sets = Vec::new();
        for (index, v, kind) in entries {
            let key = index.get(keys).clone();
            // Mostly real keys; sometimes an unknown key in a real section, or a whole
            // section replaced by the value.
            let key = match kind {
                0 => format!("{key}x"),
                1 => key.split('.').next().unwrap_or("name").to_string(),
                _ => key,
            };
            sets.push(format!("{key}={v}"));
            insert(&mut doc, &key, v);
        }
        let Ok(text) = toml::to_string(&doc) else {
            return Ok(());
        };
        if let Err(e) = Scene::from_toml_str(&text, NONE) {
            check_error(&e)?;
            let reparsed: toml::Table = text.parse().unwrap();
            check_key_error(&e, &known, &reparsed)?;
        }
        let base = fig2_text();
        for set in &sets {
            if let Err(e) = Scene::from_toml_str(base, &[set.as_str()]) {
                check_error(&e)?;
            }
        }
        if let Err(e) = Scene::from_toml_str(base, &sets) {
            check_error(&e)?;
        }
    }

    /// (c) A valid, fully resolved scene with one key replaced by a random value, removed or
    /// misspelt: a rejection must name that key (directly, or as what another key contradicts
    /// or is bounded by).
    #[test]
    fn one_mutated_key_is_named(
        variant in any::<proptest::sample::Index>(),
        index in any::<proptest::sample::Index>(),
        v in value(),
        how in 0u8..4,
    ) {
        let overrides = variant.get(VARIANTS);
        let Some(mut doc) = resolved_table(overrides) else {
            return Ok(());
        };
        let mut present = BTreeSet::new();
        leaf_paths(&doc, "", &mut present);
        let present: Vec<String> = present.into_iter().collect();
        let key = index.get(&present).clone();
        let named = match how {
            0 => {
                remove_and_get(&mut doc, &key);
                key.clone()
            }
            1 => {
                let Some(v) = remove_and_get(&mut doc, &key) else {
                    return Ok(());
                };
                let typo = format!("{key}_");
                insert(&mut doc, &typo, v);
                typo
            }
            _ => {
                insert(&mut doc, &key, v);
                key.clone()
            }
        };
        let Ok(text) = toml::to_string(&doc) else {
            return Ok(());
        };
        if let Err(e) = Scene::from_toml_str(&text, NONE) {
            check_error(&e)?;
            let reparsed: toml::Table = text.parse().unwrap();
            check_key_error(&e, &sections(known_keys()), &reparsed)?;
            let msg = e.to_string();
            // Removing a key may surface as the required key it was (named), or as a key that
            // needed it; misspelling one names the misspelt key.
            let names_it = msg.contains(&named)
                || (how == 0 && e.key().is_some());
            prop_assert!(names_it, "mutated {named:?} ({how}), message: {msg}");
        }
    }
}

/// Removes the value at the dotted `path` of `t` and returns it.
fn remove_and_get(t: &mut toml::Table, path: &str) -> Option<Value> {
    let mut keys: Vec<&str> = path.split('.').collect();
    let last = keys.pop()?;
    let mut table = t;
    for k in keys {
        match table.get_mut(k) {
            Some(Value::Table(sub)) => table = sub,
            _ => return None,
        }
    }
    table.remove(last)
}

#[test]
fn sections_must_be_tables() {
    // serde would read `numerics = [1e-10, 10.0]` field by field into the section.
    for set in [
        "numerics=[1e-10, 10.0]",
        "lubricant.noise=[\"off\"]",
        "time=[1e-3]",
    ] {
        let e = Scene::from_toml_str(fig2_text(), &[set]).unwrap_err();
        let section = set.split('=').next().unwrap();
        assert_eq!(e.key(), Some(section), "{e}");
        assert!(e.to_string().contains("allowed: a table"), "{e}");
    }
    let e = Scene::from_toml_str(fig2_text(), &["time.end=[1e-3]"]).unwrap_err();
    assert!(
        e.to_string()
            .ends_with("allowed: a number (float or integer)"),
        "{e}"
    );
}
