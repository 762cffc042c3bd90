//! The sweep file (SWEEP.toml) as written, and the errors of a bad one (each naming the key,
//! its line, the value and what is allowed).
//!
//! [`parse`] reads the text into a [`SweepFile`]; a value of the wrong type or a key where
//! none belongs is reported with its full key path (`axis[0].range.count`,
//! `regime.stick_slip`), the value as written and its line. Errors found later, when the sweep
//! is resolved, get their line from [`SweepError::located`].

use serde::Deserialize;
use stickslip_run::scene::SceneError;
use stickslip_run::summary::RegimeThresholds;
use thiserror::Error;

/// SWEEP.toml as written (docs/reference.md, "Sweeps"): every field optional here, checked
/// on resolution.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// Name of the sweep.
    pub name: Option<String>,
    /// Base scene, relative to the sweep file.
    pub scene: Option<String>,
    /// Values applied to every point, like `--set`.
    #[serde(default)]
    pub set: toml::Table,
    /// The axes; points are their cartesian product, the last axis fastest.
    #[serde(default)]
    pub axis: Vec<AxisFile>,
    /// Regime thresholds (docs/reference.md, section Regimes).
    pub regime: Option<RegimeThresholds>,
    /// Adaptive refinement of the map (docs/reference.md, section Refinement).
    pub refine: Option<RefineFile>,
    /// Spot checks of the finished map at a refined resolution (docs/reference.md, section
    /// Spot checks).
    pub verify: Option<VerifyFile>,
}

/// `[verify]`: which points of the finished map are rerun at 2N and at a tenth of the
/// tolerance.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VerifyFile {
    /// A share of the map's points, 0 < sample ≤ 1.
    pub sample: Option<f64>,
    /// Or a number of points.
    pub points: Option<i64>,
    /// Also every point next to a regime boundary (default true).
    pub boundaries: Option<bool>,
}

/// `[refine]`: split the cells whose corner points differ, `levels` times.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefineFile {
    /// Levels of refinement (an integer ≥ 0; 0 = none).
    pub levels: Option<i64>,
    /// `"regime"` (default) or a numeric column of map.csv.
    pub on: Option<String>,
    /// With `on` a column: the relative jump that splits a cell.
    pub threshold: Option<f64>,
}

/// One `[[axis]]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisFile {
    /// A scene key.
    pub key: Option<String>,
    /// Explicit values (numbers, or words for a choice key).
    pub values: Option<Vec<toml::Value>>,
    /// Or a range.
    pub range: Option<RangeFile>,
}

/// `range = { from, to, count, scale }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RangeFile {
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Number of values (≥ 1).
    pub count: i64,
    /// `"linear"` (default) or `"log"`.
    pub scale: Option<String>,
}

/// " (line N)" when the line is known.
fn at(line: Option<usize>) -> String {
    line.map_or_else(String::new, |n| format!(" (line {n})"))
}

/// A bad sweep (exit status 2): nothing is written.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SweepError {
    /// The file cannot be read or parsed.
    #[error("cannot read sweep file {path}: {message}")]
    Read {
        /// The path.
        path: String,
        /// What went wrong (with the line, for a syntax error).
        message: String,
    },
    /// A value of the sweep file itself.
    #[error("sweep {key} = {value}{} is invalid; allowed: {allowed}", at(*.line))]
    Invalid {
        /// The sweep file's key (`axis[1].range.count`, `scene`, …).
        key: String,
        /// The value.
        value: String,
        /// What is allowed.
        allowed: String,
        /// Its line in the sweep file, when it is there.
        line: Option<usize>,
    },
    /// A point whose scene does not resolve.
    #[error("sweep point {point} ({values}){}: {error}", at(*.line))]
    Point {
        /// The point number.
        point: usize,
        /// Its axis values, `key = value, …`.
        values: String,
        /// The scene's error (names the key).
        error: Box<SceneError>,
        /// The line of the sweep file that sets the key (an axis or `[set]`), when known.
        line: Option<usize>,
    },
    /// The base scene (with `[set]`) does not resolve.
    #[error("sweep base scene {path} (with [set]){}: {error}", at(*.line))]
    Base {
        /// The scene path.
        path: String,
        /// The scene's error.
        error: Box<SceneError>,
        /// The line of the sweep file that sets the key (`[set]`, or `scene`), when known.
        line: Option<usize>,
    },
}

impl SweepError {
    /// The key the error is about.
    #[must_use]
    pub fn key(&self) -> Option<&str> {
        match self {
            Self::Invalid { key, .. } => Some(key),
            Self::Point { error, .. } | Self::Base { error, .. } => error.key(),
            Self::Read { .. } => None,
        }
    }

    /// The line of the sweep file the error is about, when known.
    #[must_use]
    pub fn line(&self) -> Option<usize> {
        match self {
            Self::Invalid { line, .. } | Self::Point { line, .. } | Self::Base { line, .. } => {
                *line
            }
            Self::Read { .. } => None,
        }
    }

    /// A [`SweepError::Invalid`] (its line found later by [`SweepError::located`]).
    pub fn invalid(key: impl Into<String>, value: impl std::fmt::Display, allowed: &str) -> Self {
        Self::Invalid {
            key: key.into(),
            value: value.to_string(),
            allowed: allowed.to_string(),
            line: None,
        }
    }

    /// The error with the line of its key in the sweep file `text` (kept when already known).
    #[must_use]
    pub fn located(mut self, text: &str) -> Self {
        let entries = match toml::de::DeTable::parse(text) {
            Ok(doc) => flatten(doc.get_ref()),
            Err(_) => return self,
        };
        let found = match &self {
            Self::Invalid { key, .. } => line_of_sweep_key(text, &entries, key),
            Self::Point { error, .. } | Self::Base { error, .. } => error
                .key()
                .and_then(|k| line_of_scene_key(text, &entries, k)),
            Self::Read { .. } => None,
        };
        if let Self::Invalid { line, .. } | Self::Point { line, .. } | Self::Base { line, .. } =
            &mut self
        {
            *line = line.or(found);
        }
        self
    }
}

/// One step of a key path in the sweep file.
#[derive(Debug, Clone, PartialEq)]
enum Seg {
    Key(String),
    Index(usize),
}

/// A key path as written in messages: `axis[0].range.count`, `set."contact.nodes"`.
fn show_path(path: &[Seg]) -> String {
    let mut out = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => {
                if !out.is_empty() {
                    out.push('.');
                }
                if k.contains('.') || k.is_empty() {
                    out.push_str(&format!("{k:?}"));
                } else {
                    out.push_str(k);
                }
            }
            Seg::Index(i) => out.push_str(&format!("[{i}]")),
        }
    }
    out
}

/// One key or array element of the document: its path and where its key and value are.
#[derive(Debug, Clone)]
struct Entry {
    path: Vec<Seg>,
    key: std::ops::Range<usize>,
    value: std::ops::Range<usize>,
}

fn flatten(doc: &toml::de::DeTable<'_>) -> Vec<Entry> {
    fn walk(
        value: &toml::de::DeValue<'_>,
        path: &mut Vec<Seg>,
        key: std::ops::Range<usize>,
        out: &mut Vec<Entry>,
    ) {
        match value {
            toml::de::DeValue::Table(t) => {
                for (k, v) in t.iter() {
                    path.push(Seg::Key(k.get_ref().to_string()));
                    out.push(Entry {
                        path: path.clone(),
                        key: k.span(),
                        value: v.span(),
                    });
                    walk(v.get_ref(), path, k.span(), out);
                    path.pop();
                }
            }
            toml::de::DeValue::Array(a) => {
                for (i, e) in a.iter().enumerate() {
                    path.push(Seg::Index(i));
                    out.push(Entry {
                        path: path.clone(),
                        key: key.clone(),
                        value: e.span(),
                    });
                    walk(e.get_ref(), path, e.span(), out);
                    path.pop();
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    let root = toml::de::DeValue::Table(doc.clone());
    walk(&root, &mut Vec::new(), 0..0, &mut out);
    out
}

/// The 1-based line of byte `offset` of `text`.
fn line_at(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The line of the sweep-file key `key` as messages write it (`axis[1].range.count`, `axis[0]
/// (drive.velocity)`, `regime.stick_slip_recovery`, `set."contact.nodez"`); for a key that is
/// not written, the line of the nearest enclosing one that is.
fn line_of_sweep_key(text: &str, entries: &[Entry], key: &str) -> Option<usize> {
    let key = key.split(" (").next().unwrap_or(key);
    let mut best: Option<&Entry> = None;
    for e in entries {
        let shown = show_path(&e.path);
        let prefix = key == shown
            || key.starts_with(&format!("{shown}."))
            || key.starts_with(&format!("{shown}["));
        if prefix && best.is_none_or(|b| b.path.len() < e.path.len()) {
            best = Some(e);
        }
    }
    best.map(|e| line_at(text, e.key.start))
}

/// The line that sets the scene key `key`: an axis sweeping it, a `[set]` entry, or else the
/// `scene` line (the base scene file's own value).
fn line_of_scene_key(text: &str, entries: &[Entry], key: &str) -> Option<usize> {
    let quoted = format!("{key:?}");
    for e in entries {
        if let [Seg::Key(a), Seg::Index(i), Seg::Key(k)] = e.path.as_slice()
            && a == "axis"
            && k == "key"
            && text
                .get(e.value.clone())
                .is_some_and(|v| v.trim() == quoted)
        {
            let values = entries.iter().find(|v| {
                matches!(v.path.as_slice(), [Seg::Key(a2), Seg::Index(i2), Seg::Key(f)]
                    if a2 == "axis" && i2 == i && (f == "values" || f == "range"))
            });
            return Some(line_at(text, values.unwrap_or(e).key.start));
        }
    }
    let dotted: Vec<&str> = key.split('.').collect();
    for e in entries {
        let in_set = match e.path.as_slice() {
            [Seg::Key(s), rest @ ..] if s == "set" => {
                let keys: Vec<&str> = rest
                    .iter()
                    .flat_map(|seg| match seg {
                        Seg::Key(k) => k.split('.').collect::<Vec<_>>(),
                        Seg::Index(_) => vec!["[]"],
                    })
                    .collect();
                keys == dotted
            }
            _ => false,
        };
        if in_set {
            return Some(line_at(text, e.key.start));
        }
    }
    entries
        .iter()
        .find(|e| e.path == [Seg::Key("scene".into())])
        .map(|e| line_at(text, e.key.start))
}

/// The line of the first `[[section]]` or `section =` in `text`.
fn entries_line(text: &str, section: &str) -> Option<usize> {
    text.lines()
        .position(|l| {
            let l = l.trim_start();
            l.starts_with(&format!("[[{section}]]"))
                || l.starts_with(&format!("[{section}]"))
                || l.strip_prefix(section)
                    .is_some_and(|r| r.trim_start().starts_with('='))
        })
        .map(|i| i + 1)
}

/// What a serde "expected …" means, in the words of the messages.
fn expected_words(expected: &str) -> String {
    match expected {
        "i64" | "u64" | "usize" => "an integer".to_string(),
        "f64" => "a number (float or integer)".to_string(),
        "a string" => "a string".to_string(),
        "a sequence" => "an array".to_string(),
        "a map" => "a table".to_string(),
        e if e.starts_with("struct ") => "a table".to_string(),
        e => e.replace('`', ""),
    }
}

/// The value at `range` of `text`, on one line and shortened.
fn value_text(text: &str, range: &std::ops::Range<usize>) -> String {
    let v = text.get(range.clone()).unwrap_or("?").trim();
    let v: String = v.split_whitespace().collect::<Vec<_>>().join(" ");
    if v.chars().count() > 60 {
        format!("{}…", v.chars().take(60).collect::<String>())
    } else {
        v
    }
}

/// Parses a sweep file's `text`; `path` names it in messages, and `lines` says whether its
/// lines mean anything to the user (false for text made from a Python dict).
///
/// # Errors
/// A syntax error ([`SweepError::Read`], with its line), or a value of the wrong type or an
/// unknown key ([`SweepError::Invalid`] with the full key path, the value and its line).
pub fn parse(text: &str, path: &str, lines: bool) -> Result<SweepFile, SweepError> {
    let doc = toml::de::DeTable::parse(text).map_err(|e| {
        let line = e.span().map(|s| line_at(text, s.start));
        SweepError::Read {
            path: path.to_string(),
            message: match line.filter(|_| lines) {
                Some(n) => format!("line {n}: {}", e.message().trim()),
                None => e.message().trim().to_string(),
            },
        }
    })?;
    let e = match toml::from_str::<SweepFile>(text) {
        Ok(file) => {
            // serde reads a TOML date as a string; a name is text.
            if let Ok(table) = text.parse::<toml::Table>()
                && let Some(v) = table.get("name")
                && !v.is_str()
            {
                return Err(SweepError::invalid(
                    "name",
                    stickslip_run::scene::error::show_value(v),
                    "a string (name = \"...\")",
                ));
            }
            return Ok(file);
        }
        Err(e) => e,
    };
    // A table written as an array of tables ([[verify]] for [verify]): say so, rather than
    // what serde expected of the array's first element.
    if let Ok(table) = text.parse::<toml::Table>() {
        for section in ["verify", "set", "regime"] {
            if let Some(toml::Value::Array(items)) = table.get(section) {
                let double = items.iter().all(toml::Value::is_table);
                let at = entries_line(text, section).filter(|_| lines);
                return Err(SweepError::Invalid {
                    key: section.to_string(),
                    value: if double {
                        format!("[[{section}]] (an array of tables)")
                    } else {
                        "an array".to_string()
                    },
                    allowed: format!(
                        "one [{section}] table, in single brackets (docs/reference.md, \"Sweep \
                         file\"); [[axis]] is the only section written twice"
                    ),
                    line: at,
                });
            }
        }
    }
    let entries = flatten(doc.get_ref());
    let message = e.message().trim().to_string();
    let span = e.span().unwrap_or(0..0);
    let line = |r: &std::ops::Range<usize>| lines.then(|| line_at(text, r.start));
    // An unknown key: the entry of that name nearest to the reported place.
    if let Some(rest) = message.strip_prefix("unknown field `")
        && let Some((field, expected)) = rest.split_once('`')
    {
        let entry = entries
            .iter()
            .filter(|e| e.path.last() == Some(&Seg::Key(field.to_string())))
            .min_by_key(|e| e.key.start.abs_diff(span.start));
        let allowed = expected
            .trim_start_matches(", ")
            .trim_start_matches("expected one of ")
            .trim_start_matches("expected ")
            .replace('`', "");
        let (key, value, line) = match entry {
            Some(e) => (show_path(&e.path), value_text(text, &e.value), line(&e.key)),
            None => (field.to_string(), "(present)".to_string(), None),
        };
        let section = key
            .rsplit_once('.')
            .map_or_else(|| "the top level".to_string(), |(s, _)| format!("[{s}]"));
        return Err(SweepError::Invalid {
            key,
            value,
            allowed: format!("a key of {section}: {allowed} (docs/reference.md, \"Sweep file\")"),
            line,
        });
    }
    // Otherwise the innermost entry whose value holds the reported place.
    let entry = entries
        .iter()
        .filter(|e| e.value.start <= span.start && span.start < e.value.end.max(e.value.start + 1))
        .max_by_key(|e| e.path.len());
    let allowed = if let Some(rest) = message.strip_prefix("invalid type: ")
        && let Some((_, expected)) = rest.rsplit_once(", expected ")
    {
        expected_words(expected)
    } else if let Some(rest) = message.strip_prefix("missing field `") {
        let field = rest.split('`').next().unwrap_or(rest);
        let key = entry.map_or_else(
            || field.to_string(),
            |e| format!("{}.{field}", show_path(&e.path)),
        );
        return Err(SweepError::Invalid {
            key,
            value: "none".into(),
            allowed: "a value: it is required here".into(),
            line: entry.and_then(|e| line(&e.key)),
        });
    } else {
        message.clone()
    };
    Err(match entry {
        Some(e) => SweepError::Invalid {
            key: show_path(&e.path),
            value: value_text(text, &e.value),
            allowed,
            line: line(&e.key),
        },
        None => SweepError::Read {
            path: path.to_string(),
            message,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "name = \"x\"\nscene = \"s.toml\"\n[set]\n\"contact.nodes\" = 20\n\
                        [set.drive]\nvelocity = 2.0\n[[axis]]\nkey = \"time.dt\"\n\
                        range = { from = 1, to = 2, count = 4 }\n[[axis]]\n\
                        key = \"temperature.A0\"\nvalues = [1, 2]\n[regime]\n\
                        smooth_recovery = 0.2\n";

    fn err(text: &str) -> SweepError {
        parse(text, "s.toml", true).unwrap_err()
    }

    #[test]
    fn wrong_types_and_misplaced_keys_name_the_key_path_value_and_line() {
        assert!(parse(GOOD, "s.toml", true).is_ok());
        let e = err(&GOOD.replace("count = 4", "count = 4.0"));
        assert_eq!(e.key(), Some("axis[0].range.count"));
        assert_eq!(e.line(), Some(9));
        let text = e.to_string();
        assert!(
            text.contains("= 4.0 (line 9)") && text.contains("an integer"),
            "{text}"
        );
        let e = err(&GOOD.replace("smooth_recovery", "stick_slip"));
        assert_eq!(e.key(), Some("regime.stick_slip"));
        assert_eq!(e.line(), Some(14));
        let text = e.to_string();
        assert!(
            text.contains("= 0.2 (line 14)")
                && text.contains("[regime]")
                && text.contains("stick_slip_recovery"),
            "{text}"
        );
        let e = err(&GOOD.replace("[[axis]]\nkey = \"time.dt\"", "[[axis]]\nkye = \"time.dt\""));
        assert_eq!(e.key(), Some("axis[0].kye"));
        assert_eq!(e.line(), Some(8));
        let e = err(&GOOD.replace("name = \"x\"", "name = 3"));
        assert_eq!(e.key(), Some("name"));
        assert_eq!(e.line(), Some(1));
        let e = err(&GOOD.replace("from = 1, ", ""));
        assert_eq!(e.key(), Some("axis[0].range.from"), "{e}");
        assert_eq!(e.line(), Some(9));
        let e = err("name = \"x\"\nscene = [\n");
        assert!(
            e.to_string().contains("line 2") || e.to_string().contains("line 3"),
            "{e}"
        );
        // Text made from a dict: the key path, no line.
        let e = parse(&GOOD.replace("count = 4", "count = 4.0"), "(dict)", false).unwrap_err();
        assert_eq!((e.key(), e.line()), (Some("axis[0].range.count"), None));
    }

    #[test]
    fn errors_of_resolution_find_their_line() {
        let e = SweepError::invalid("axis[1].values", "[]", "x").located(GOOD);
        assert_eq!(e.line(), Some(12));
        let e = SweepError::invalid("axis[0] (time.dt)", "values and range", "x").located(GOOD);
        assert_eq!(e.line(), Some(7));
        let e = SweepError::invalid("regime.smooth_recovery", "1.5", "x").located(GOOD);
        assert_eq!(e.line(), Some(14));
        let e = SweepError::invalid("set.\"contact.nodes\"", "20", "x").located(GOOD);
        assert_eq!(e.line(), Some(4));
        let e = SweepError::invalid("name", "none", "x").located("scene = \"s\"\n");
        assert_eq!(e.line(), None);
        let scene = |key: &str| SweepError::Point {
            point: 0,
            values: String::new(),
            error: Box::new(SceneError::missing(key, "x")),
            line: None,
        };
        assert_eq!(scene("temperature.A0").located(GOOD).line(), Some(12));
        assert_eq!(scene("contact.nodes").located(GOOD).line(), Some(4));
        assert_eq!(scene("drive.velocity").located(GOOD).line(), Some(6));
        assert_eq!(scene("contact.radius").located(GOOD).line(), Some(2));
    }
}
