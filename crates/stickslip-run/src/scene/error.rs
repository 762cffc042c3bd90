//! [`SceneError`]: everything that can be wrong with a scene file or a `--set` override,
//! each naming the key, the value and what is allowed; plus the translation of toml/serde
//! errors into such messages.

use stickslip_core::config::ConfigError;
use thiserror::Error;

/// A bad scene (command-line exit status 2).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SceneError {
    /// The scene file could not be read (or is not UTF-8).
    #[error("cannot read scene file {path}: {message}")]
    Read {
        /// The path as given.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The text is not valid TOML.
    #[error(
        "scene is not valid TOML at line {line}, column {column}: {message} (near `{excerpt}`); \
         allowed: a TOML document with the scene keys (`stickslip keys`, docs/reference.md)"
    )]
    Syntax {
        /// Line, from 1.
        line: usize,
        /// Column, from 1.
        column: usize,
        /// The parser's message.
        message: String,
        /// The offending line, shortened.
        excerpt: String,
    },
    /// A `--unset` argument that names no scene key.
    #[error(
        "--unset {key:?}: {problem}; allowed: a scene key as section.key (`stickslip keys`), \
         e.g. drive.stiffness"
    )]
    Unset {
        /// The key as given.
        key: String,
        /// What is wrong.
        problem: String,
    },
    /// A `--set` argument that cannot be applied.
    #[error(
        "--set {arg:?}: {problem}; allowed: section.key=value with a TOML value \
         (e.g. contact.nodes=200, time.scheme=literal, output.probe_radii=[2e-6])"
    )]
    Override {
        /// The argument as given.
        arg: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A key that the section does not have.
    #[error("unknown key `{key}` = {value} in section {section}; allowed keys there: {allowed}")]
    UnknownKey {
        /// Full key path, e.g. `lubricant.taumax`.
        key: String,
        /// The section, e.g. `[lubricant]` or `(top level)`.
        section: String,
        /// The value given.
        value: String,
        /// The keys the section accepts.
        allowed: String,
    },
    /// A required key is absent (and maybe others: all are named at once).
    #[error(
        "missing required key `{key}` (value: none); allowed: {allowed}{}",
        also_missing(also)
    )]
    MissingKey {
        /// Full key path.
        key: String,
        /// The allowed range of the key.
        allowed: String,
        /// The other required keys the scene lacks too.
        also: Vec<String>,
    },
    /// A key with a value of the wrong type.
    #[error("{key} = {value} has the wrong type; allowed: {allowed}")]
    WrongType {
        /// Full key path.
        key: String,
        /// The value given.
        value: String,
        /// The expected type.
        allowed: String,
    },
    /// A value outside its allowed range (same wording as the engine's `ConfigError`).
    #[error("{key} = {value} is out of range: allowed {allowed}")]
    Invalid {
        /// Full key path.
        key: String,
        /// The value given.
        value: String,
        /// The allowed range.
        allowed: String,
    },
    /// Keys that exclude each other.
    #[error("{key} = {value} is contradictory with {other}; allowed: {allowed}")]
    Contradictory {
        /// Full key path of the key that may not be there.
        key: String,
        /// Its value.
        value: String,
        /// What it contradicts, e.g. `drive.kind = "rigid"`.
        other: String,
        /// What is allowed instead.
        allowed: String,
    },
}

impl SceneError {
    /// An [`SceneError::Invalid`] for `key` with `value` and `allowed`.
    pub fn invalid(key: &str, value: impl std::fmt::Display, allowed: impl Into<String>) -> Self {
        Self::Invalid {
            key: key.to_string(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }

    /// A [`SceneError::MissingKey`] for `key`.
    pub fn missing(key: &str, allowed: impl Into<String>) -> Self {
        Self::MissingKey {
            key: key.to_string(),
            allowed: allowed.into(),
            also: Vec::new(),
        }
    }

    /// A [`SceneError::MissingKey`] with every other required key `root` lacks named too, so
    /// that one edit adds them all; other errors unchanged.
    #[must_use]
    pub fn with_all_missing(self, root: &toml::Table) -> Self {
        match self {
            Self::MissingKey { key, allowed, .. } => {
                // g_eff is required unless the four moduli of Eq. 9 stand for it.
                use crate::keys::{contact, drive};
                let eq9 = [
                    contact::G1.path,
                    contact::NU1.path,
                    contact::G2.path,
                    contact::NU2.path,
                ]
                .iter()
                .any(|p| crate::keys::lookup(root, p).is_some());
                let also: Vec<String> = crate::keys::all()
                    .map(|k| k.info())
                    .filter(|i| {
                        i.default == crate::keys::DefaultValue::Required
                            && i.path != key
                            && !(eq9 && i.path == contact::G_EFF.path)
                            && crate::keys::lookup(root, i.path).is_none()
                    })
                    .map(|i| i.path.to_string())
                    .chain(
                        // time.end unless time.travel stands for it.
                        [crate::keys::time::END.path]
                            .into_iter()
                            .filter(|p| {
                                *p != key
                                    && crate::keys::lookup(root, p).is_none()
                                    && crate::keys::lookup(root, crate::keys::time::TRAVEL.path)
                                        .is_none()
                            })
                            .map(str::to_string),
                    )
                    .chain(
                        // A spring drive (the default) needs its stiffness and mass.
                        [drive::STIFFNESS.path, drive::MASS.path]
                            .into_iter()
                            .filter(|p| {
                                *p != key
                                    && crate::keys::lookup(root, drive::KIND.path)
                                        .is_none_or(|k| k.as_str() == Some("spring"))
                                    && crate::keys::lookup(root, p).is_none()
                            })
                            .map(str::to_string),
                    )
                    .collect();
                Self::MissingKey { key, allowed, also }
            }
            other => other,
        }
    }

    /// The key the error is about, if any.
    pub fn key(&self) -> Option<&str> {
        match self {
            Self::UnknownKey { key, .. }
            | Self::MissingKey { key, .. }
            | Self::WrongType { key, .. }
            | Self::Invalid { key, .. }
            | Self::Contradictory { key, .. } => Some(key),
            Self::Read { .. }
            | Self::Syntax { .. }
            | Self::Override { .. }
            | Self::Unset { .. } => None,
        }
    }
}

/// The other missing keys, as the message's tail.
fn also_missing(also: &[String]) -> String {
    if also.is_empty() {
        String::new()
    } else {
        format!("; also missing: {}", also.join(", "))
    }
}

impl From<crate::keys::KeyError> for SceneError {
    fn from(e: crate::keys::KeyError) -> Self {
        match e {
            crate::keys::KeyError::Missing { path, allowed } => Self::missing(path, allowed),
            crate::keys::KeyError::Invalid(e) => e.into(),
        }
    }
}

impl From<ConfigError> for SceneError {
    /// Keeps key and range; float values are re-rendered with [`human`] so all messages spell
    /// values alike (`contact.nodes` is the engine's only integer key).
    fn from(e: ConfigError) -> Self {
        let value = match e.value.parse::<f64>() {
            Ok(f) if e.key != "contact.nodes" => human(f),
            _ => e.value,
        };
        Self::Invalid {
            key: e.key,
            value,
            allowed: e.allowed,
        }
    }
}

/// A float for messages, spelled as it could be written in a scene (the engine's wording).
pub(crate) use stickslip_core::config::bounds::human;

/// Longest value text quoted in a message.
const MAX_VALUE_CHARS: usize = 80;

/// Shortens `s` to at most [`MAX_VALUE_CHARS`] characters (on a char boundary).
pub(crate) fn shorten(s: &str) -> String {
    if s.chars().count() <= MAX_VALUE_CHARS {
        s.to_string()
    } else {
        let mut out: String = s.chars().take(MAX_VALUE_CHARS).collect();
        out.push('…');
        out
    }
}

/// A TOML value as it would be written in a scene (shortened), for messages.
#[must_use]
pub fn show_value(v: &toml::Value) -> String {
    fn write(v: &toml::Value, out: &mut String, depth: usize) {
        if out.len() > 4 * MAX_VALUE_CHARS {
            return;
        }
        match v {
            toml::Value::String(s) => out.push_str(&format!("{s:?}")),
            toml::Value::Integer(i) => out.push_str(&i.to_string()),
            toml::Value::Float(f) => out.push_str(&human(*f)),
            toml::Value::Boolean(b) => out.push_str(&b.to_string()),
            toml::Value::Datetime(d) => out.push_str(&d.to_string()),
            toml::Value::Array(a) => {
                out.push('[');
                for (i, x) in a.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    if depth > 8 {
                        out.push('…');
                        break;
                    }
                    write(x, out, depth + 1);
                }
                out.push(']');
            }
            toml::Value::Table(t) => {
                out.push('{');
                for (i, (k, x)) in t.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    if depth > 8 {
                        out.push('…');
                        break;
                    }
                    out.push_str(k);
                    out.push_str(" = ");
                    write(x, out, depth + 1);
                }
                out.push('}');
            }
        }
    }
    let mut out = String::new();
    write(v, &mut out, 0);
    shorten(&out)
}

/// A float as TOML would accept it back (`nan`, `inf`, `-inf`, else shortest `{:e}`).
pub(crate) fn format_float(f: f64) -> String {
    if f.is_nan() {
        "nan".to_string()
    } else if f.is_infinite() {
        if f > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{f:e}")
    }
}

/// The value at `path` in `root`, if there is one.
pub(crate) fn lookup<'a>(root: &'a toml::Table, path: &[String]) -> Option<&'a toml::Value> {
    let (first, rest) = path.split_first()?;
    let mut v = root.get(first)?;
    for k in rest {
        v = v.as_table()?.get(k)?;
    }
    Some(v)
}

/// Key paths of the scene's sections. serde reads a struct from an array too (field by field,
/// in order), so `numerics = [1e-10, 10]` would pass as a section; scenes have tables there.
const SECTIONS: &[&str] = &[
    "lubricant",
    "lubricant.noise",
    "temperature",
    "contact",
    "drive",
    "time",
    "output",
    "numerics",
];

/// Rejects a section that is not a table (see [`SECTIONS`]).
pub(crate) fn check_sections(root: &toml::Table) -> Result<(), SceneError> {
    for section in SECTIONS {
        let keys: Vec<String> = section.split('.').map(str::to_string).collect();
        if let Some(v) = lookup(root, &keys)
            && !v.is_table()
        {
            return Err(SceneError::WrongType {
                key: (*section).to_string(),
                value: show_value(v),
                allowed: format!("a table ([{section}])"),
            });
        }
    }
    Ok(())
}

/// Whether the scene key at `path` takes an array: probed on the scene type itself, with an
/// empty array at `path` and nothing else (every key is optional there).
fn takes_array(path: &[String]) -> bool {
    let mut v = toml::Value::Array(Vec::new());
    for k in path.iter().rev() {
        let mut t = toml::Table::new();
        t.insert(k.clone(), v);
        v = toml::Value::Table(t);
    }
    match v {
        toml::Value::Table(t) => t.try_into::<super::Scene>().is_ok(),
        _ => false,
    }
}

/// Turns the error of deserializing `root` (a parsed scene) into a [`SceneError`] naming the
/// key path.
///
/// toml reports errors of deserializing from a [`toml::Value`] as the serde message followed by
/// a line ``in `a.b` `` naming the table path; the serde messages have fixed forms
/// (`unknown field`, `invalid type`, …).
pub(crate) fn from_de_error(root: &toml::Table, e: &toml::de::Error) -> SceneError {
    let text = e.to_string();
    let text = text.trim_end();
    let (message, path) = match text.rfind("\nin `") {
        Some(pos) => {
            let tail = &text[pos + "\nin `".len()..];
            let path = tail.strip_suffix('`').unwrap_or(tail);
            (&text[..pos], path.to_string())
        }
        None => (text, String::new()),
    };
    let message = message.trim();
    let path_keys: Vec<String> = if path.is_empty() {
        Vec::new()
    } else {
        path.split('.').map(str::to_string).collect()
    };
    let section = if path.is_empty() {
        "(top level)".to_string()
    } else {
        format!("[{path}]")
    };
    let join = |k: &str| {
        if path.is_empty() {
            k.to_string()
        } else {
            format!("{path}.{k}")
        }
    };
    if let Some(rest) = message.strip_prefix("unknown field `")
        && let Some((field, expected)) = rest.split_once('`')
    {
        let mut keys = path_keys.clone();
        keys.push(field.to_string());
        let value = lookup(root, &keys).map_or_else(|| "?".to_string(), show_value);
        let allowed = expected
            .trim_start_matches(", ")
            .trim_start_matches("expected one of ")
            .trim_start_matches("expected ")
            .replace('`', "");
        return SceneError::UnknownKey {
            key: shorten(&join(field)),
            section,
            value,
            allowed,
        };
    }
    if let Some(rest) = message.strip_prefix("missing field `")
        && let Some((field, _)) = rest.split_once('`')
    {
        return SceneError::missing(&join(field), "see `stickslip keys` (docs/reference.md)");
    }
    let value = lookup(root, &path_keys).map_or_else(|| "?".to_string(), show_value);
    if message.starts_with("unknown variant `") {
        // A misspelt word: the allowed words are the key registry's.
        let key = path.clone();
        let words = crate::keys::find(&key).map_or_else(|| shorten(message), |k| k.allowed());
        return SceneError::Invalid {
            key: shorten(&key),
            value,
            allowed: words,
        };
    }
    if let Some(rest) = message.strip_prefix("invalid type: ")
        && let Some((_, expected)) = rest.rsplit_once(", expected ")
    {
        // An array where a number belongs reads `invalid type: sequence, expected f64`, as does
        // a nested array in an array of numbers: the key's own type decides.
        let is_array = matches!(lookup(root, &path_keys), Some(toml::Value::Array(_)));
        let given = lookup(root, &path_keys);
        // A float where an integer belongs: 2e2 is a float in TOML (and in `--set`), and
        // showing it as "200" would hide why it is refused.
        let whole_float = match given {
            Some(toml::Value::Float(f)) if expected == "i64" && f.fract() == 0.0 => Some(*f),
            _ => None,
        };
        let value = whole_float.map_or(value, |f| format!("{f:e} (a float)"));
        let allowed = match expected {
            "f64" if is_array && takes_array(&path_keys) => "an array of numbers".to_string(),
            "f64" => "a number (float or integer)".to_string(),
            "i64" => match whole_float {
                Some(f) if f.abs() < 9e15 => {
                    format!("an integer, written without a decimal point or exponent: {f:.0}")
                }
                _ => "an integer".to_string(),
            },
            "a string" => "a string".to_string(),
            "a sequence" => "an array of numbers".to_string(),
            e if e.starts_with("struct ") => "a table".to_string(),
            e => e.to_string(),
        };
        return SceneError::WrongType {
            key: if path.is_empty() {
                "(top level)".to_string()
            } else {
                shorten(&path)
            },
            value,
            allowed,
        };
    }
    SceneError::WrongType {
        key: if path.is_empty() {
            "(top level)".to_string()
        } else {
            shorten(&path)
        },
        value,
        allowed: shorten(message),
    }
}
