//! The registry of scene keys: one typed entry per key, from which every other view follows.
//!
//! An entry ([`Key`]) holds the key's path, type, unit, default (a value, or for a default
//! derived from other keys the code that derives it and its wording), allowed range, rules
//! between keys in words, usual range, meaning and the version it appeared in. The entries are
//! declared in [`registry`] together with the scene file's serde sections, which the same
//! declaration generates (field names, types and docs), so a key is defined in one place:
//! - scene resolution checks single-key ranges and takes defaults from the entries, and the
//!   engine's own range checks are the same [`stickslip_core::config::bounds`] the entries use
//!   (a compile-time check keeps their paths equal);
//! - `stickslip keys`, `docs/reference.md` ([`markdown`]) and `check`'s unusual-value warnings
//!   ([`unusual_values`]) are written from the entries;
//! - code sets keys through them, typed ([`Key::set`] gives a [`Setting`]; enums as enums),
//!   while the command line's `--set` and Python's dictionaries still take text.
//!
//! Rules between keys (`time.dt <= time.end`) are checked in code; each entry's `rule` states
//! them.

pub mod registry;
mod setting;
mod values;
pub mod words;

pub use registry::*;
pub use setting::Setting;
pub use stickslip_core::config::bounds::{Range, human};
pub use values::{KeyValue, ValueType};

use stickslip_core::config::ConfigError;

/// A key's default.
#[derive(Debug, Clone, Copy)]
pub enum KeyDefault<T: 'static> {
    /// The key must be given.
    Required,
    /// This value (a reference, so that entries are constants whatever the type).
    Value(&'static T),
    /// Computed from keys resolved before it: `of` reads them from the scene as resolved so
    /// far (`None` if they are not there yet, an ordering mistake the tests would show);
    /// `doc` says it in words.
    Derived {
        /// The rule in words, for the reference.
        doc: &'static str,
        /// The rule as code.
        of: fn(&Scene) -> Option<T>,
    },
    /// No value: the feature is off unless the key is given (in words).
    Off(&'static str),
}

/// One scene key (see the [module docs](self)).
#[derive(Debug, Clone, Copy)]
pub struct Key<T: 'static> {
    /// Full path, `section.key`.
    pub path: &'static str,
    /// SI unit (`–` for dimensionless).
    pub unit: &'static str,
    /// Default.
    pub default: KeyDefault<T>,
    /// Allowed values of the key alone.
    pub range: Range,
    /// Rules between keys, in words (empty if none).
    pub rule: &'static str,
    /// Usual range (absolute value): a value outside draws a warning, not an error.
    pub usual: Option<(f64, f64)>,
    /// One line of meaning.
    pub meaning: &'static str,
    /// The version of stickslip in which the key appeared.
    pub since: &'static str,
}

/// A key that cannot be resolved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KeyError {
    /// Absent, and required.
    #[error("missing required key `{path}`; allowed: {allowed}")]
    Missing {
        /// The key.
        path: &'static str,
        /// Its allowed values.
        allowed: String,
    },
    /// Outside its range.
    #[error(transparent)]
    Invalid(#[from] ConfigError),
}

/// A key's default in words, as the reference states it.
#[derive(Debug, Clone, PartialEq)]
pub enum DefaultValue {
    /// The key must be given.
    Required,
    /// This value, as it would be written in a scene.
    Value(String),
    /// Computed from other keys, as described.
    Derived(&'static str),
    /// No value: the feature is off.
    Off(&'static str),
}

impl DefaultValue {
    /// The default in words.
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            Self::Required => "required".to_string(),
            Self::Value(v) => v.clone(),
            Self::Derived(d) | Self::Off(d) => (*d).to_string(),
        }
    }
}

/// A key without its type: what lookups by path, the reference and the tables use.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyInfo {
    /// Full path, `section.key`.
    pub path: &'static str,
    /// Type of its value.
    pub value: ValueType,
    /// SI unit (`–` for dimensionless).
    pub unit: &'static str,
    /// Default, in words.
    pub default: DefaultValue,
    /// Allowed values of the key alone.
    pub range: Range,
    /// Rules between keys, in words (empty if none).
    pub rule: &'static str,
    /// Usual range (absolute value).
    pub usual: Option<(f64, f64)>,
    /// One line of meaning.
    pub meaning: &'static str,
    /// The version in which the key appeared.
    pub since: &'static str,
}

/// Any key, whatever its type (the registry's list holds these).
pub trait AnyKey: Sync {
    /// The key without its type.
    fn info(&self) -> KeyInfo;
    /// The default the key takes in `resolved` (a scene as resolved): its value, or the
    /// derived one computed from the other keys there; `None` for required and off keys.
    fn default_in(&self, resolved: &Scene) -> Option<toml::Value>;
}

impl<T: KeyValue> Key<T> {
    /// `v` if the key's own range allows it.
    ///
    /// # Errors
    /// A [`ConfigError`] naming the key, the value and the allowed values (range and rules).
    pub fn check(&self, v: T) -> Result<T, ConfigError> {
        match v.as_number() {
            Some(x) if !self.range.contains(x) => {
                Err(ConfigError::new(self.path, v.show(), &self.allowed()))
            }
            _ => Ok(v),
        }
    }

    /// The given value checked, else the default value or the derived one (from `so_far`,
    /// the scene as resolved up to this key), checked too. `Ok(None)` for an absent key
    /// that is off by default.
    ///
    /// # Errors
    /// [`KeyError::Missing`] for an absent required key, [`KeyError::Invalid`] for a value
    /// outside the range.
    pub fn resolve(&self, given: Option<T>, so_far: &Scene) -> Result<Option<T>, KeyError> {
        let v = match (given, &self.default) {
            (Some(v), _) => v,
            (None, KeyDefault::Value(v)) => (*v).clone(),
            (None, KeyDefault::Derived { of, .. }) => {
                of(so_far).ok_or_else(|| KeyError::Missing {
                    path: self.path,
                    allowed: format!("{} (derived from keys not resolved yet)", self.allowed()),
                })?
            }
            (None, KeyDefault::Required) => {
                return Err(KeyError::Missing {
                    path: self.path,
                    allowed: self.allowed(),
                });
            }
            (None, KeyDefault::Off(_)) => return Ok(None),
        };
        Ok(Some(self.check(v)?))
    }

    /// As [`Key::resolve`], for a key that always has a value (required, or with a default).
    ///
    /// # Errors
    /// As [`Key::resolve`]; an off key that is absent counts as missing.
    pub fn value(&self, given: Option<T>, so_far: &Scene) -> Result<T, KeyError> {
        self.resolve(given, so_far)?
            .ok_or_else(|| KeyError::Missing {
                path: self.path,
                allowed: self.allowed(),
            })
    }

    /// A typed override of this key (for code; `--set` takes text).
    ///
    /// # Example
    /// ```
    /// use stickslip_run::keys::{contact, time};
    ///
    /// let nodes = contact::NODES.set(400);
    /// // The command line's text for the same value.
    /// assert_eq!(nodes.to_string(), "contact.nodes=400");
    /// assert_eq!(time::TOLERANCE.set(1e-6).to_string(), "time.tolerance=1e-6");
    /// // Applied to a scene's table without text.
    /// let mut table = toml::Table::new();
    /// nodes.apply(&mut table);
    /// assert_eq!(table["contact"]["nodes"].as_integer(), Some(400));
    /// ```
    #[must_use]
    pub fn set(&self, value: T) -> Setting {
        Setting::new(self.path, value.to_toml())
    }

    /// Allowed values in words: the range, then the rules between keys.
    #[must_use]
    pub fn allowed(&self) -> String {
        self.info().allowed()
    }
}

impl<T: KeyValue> AnyKey for Key<T> {
    fn info(&self) -> KeyInfo {
        KeyInfo {
            path: self.path,
            value: T::TYPE,
            unit: self.unit,
            default: match &self.default {
                KeyDefault::Required => DefaultValue::Required,
                KeyDefault::Value(v) => DefaultValue::Value(v.show()),
                KeyDefault::Derived { doc, .. } => DefaultValue::Derived(doc),
                KeyDefault::Off(doc) => DefaultValue::Off(doc),
            },
            range: self.range,
            rule: self.rule,
            usual: self.usual,
            meaning: self.meaning,
            since: self.since,
        }
    }

    fn default_in(&self, resolved: &Scene) -> Option<toml::Value> {
        match &self.default {
            KeyDefault::Value(v) => Some(v.to_toml()),
            KeyDefault::Derived { of, .. } => of(resolved).map(|v| v.to_toml()),
            KeyDefault::Required | KeyDefault::Off(_) => None,
        }
    }
}

impl KeyInfo {
    /// Allowed values in words: the range, then the rules between keys.
    #[must_use]
    pub fn allowed(&self) -> String {
        let base = match self.value {
            ValueType::Choice(words) => format!(
                "one of {}",
                words
                    .iter()
                    .map(|w| format!("{w:?}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            ValueType::RealList => format!("an array of numbers in {}", self.unit),
            _ => self.range.describe(self.short_name(), self.unit),
        };
        if self.rule.is_empty() {
            base
        } else if self.range == Range::ByRule {
            self.rule.to_string()
        } else {
            format!("{base}; {}", self.rule)
        }
    }

    /// The last part of the path (`nu1` of `contact.nu1`), without trailing digits.
    #[must_use]
    pub fn short_name(&self) -> &'static str {
        let last = self.path.rsplit('.').next().unwrap_or(self.path);
        last.trim_end_matches(|c: char| c.is_ascii_digit())
    }

    /// Whether `v` lies outside the usual range (a likely unit slip).
    #[must_use]
    pub fn unusual(&self, v: f64) -> bool {
        self.usual
            .is_some_and(|(lo, hi)| v != 0.0 && !(lo..=hi).contains(&v.abs()))
    }
}

/// Every key, in the order of the reference.
pub fn all() -> impl Iterator<Item = &'static dyn AnyKey> {
    registry::SECTIONS.iter().flat_map(|s| s.iter().copied())
}

/// Every key without its type, in the order of the reference.
pub static KEYS: std::sync::LazyLock<Vec<KeyInfo>> =
    std::sync::LazyLock::new(|| all().map(AnyKey::info).collect());

/// The key at `path`, if there is one.
#[must_use]
pub fn find(path: &str) -> Option<&'static KeyInfo> {
    KEYS.iter().find(|k| k.path == path)
}

/// The value at the dotted `path` of `table`, if there is one.
#[must_use]
pub fn lookup<'a>(table: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let mut parts = path.split('.');
    let mut v = table.get(parts.next()?)?;
    for k in parts {
        v = v.as_table()?.get(k)?;
    }
    Some(v)
}

/// Warnings for values outside their key's usual range (likely unit slips), from the scene
/// as resolved (`table`: the resolved scene as a TOML table).
#[must_use]
pub fn unusual_values(table: &toml::Table) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for key in KEYS.iter() {
        let Some((lo, hi)) = key.usual else { continue };
        let Some(v) = lookup(table, key.path).and_then(|v| match v {
            toml::Value::Float(f) => Some(*f),
            toml::Value::Integer(i) => Some(*i as f64),
            _ => None,
        }) else {
            continue;
        };
        if key.unusual(v) {
            out.push((
                key.path.to_string(),
                format!(
                    "{} = {} {} is outside the usual range [{lo:e}, {hi:e}] {} for this model \
                     (a unit slip?); running anyway",
                    key.path,
                    human(v),
                    key.unit,
                    key.unit
                ),
            ));
        }
    }
    out
}

/// The scene keys as a Markdown section (one table per section of the scene file).
#[must_use]
pub fn markdown() -> String {
    let mut out = String::from(
        "## Scene keys\n\nAll quantities SI. Unknown keys are an error naming the key and its \
         section. A value outside its *usual* range draws a warning (a likely unit slip), not \
         an error. *Since* is the version of stickslip that added the key.\n",
    );
    let mut section = "";
    for key in KEYS.iter() {
        let sec = key.path.rsplit_once('.').map_or("(top level)", |(s, _)| s);
        if sec != section {
            section = sec;
            out.push_str(&format!(
                "\n### `{}`\n\n| key | unit | default | allowed | usual | meaning | since |\n|---|---|---|---|---|---|---|\n",
                if sec == "(top level)" { sec.to_string() } else { format!("[{sec}]") }
            ));
        }
        let usual = key
            .usual
            .map_or_else(String::new, |(lo, hi)| format!("[{lo:e}, {hi:e}]"));
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} | {} | {} |\n",
            key.path,
            key.unit,
            key.default.describe().replace('|', "\\|"),
            key.allowed().replace('|', "\\|"),
            usual,
            key.meaning.replace('|', "\\|"),
            key.since
        ));
    }
    out
}

/// The table as aligned text (`stickslip keys`).
#[must_use]
pub fn table_text() -> String {
    let mut out = String::new();
    for key in KEYS.iter() {
        out.push_str(&format!(
            "{}  [{}]  default: {}\n    allowed: {}\n    {}\n",
            key.path,
            key.unit,
            key.default.describe(),
            key.allowed(),
            key.meaning
        ));
        if let Some((lo, hi)) = key.usual {
            out.push_str(&format!(
                "    usual: [{lo:e}, {hi:e}] {} (outside: a warning)\n",
                key.unit
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_unique() {
        let mut seen = std::collections::HashSet::new();
        for k in KEYS.iter() {
            assert!(seen.insert(k.path), "{} twice", k.path);
        }
        assert!(find("time.bogus").is_none());
    }

    #[test]
    fn ranges_say_what_they_check() {
        let e = contact::RADIUS.check(1e16).unwrap_err().to_string();
        assert!(e.contains("contact.radius = 1e16"), "{e}");
        assert!(e.contains("[1e-15, 1e15] m"), "{e}");
        let r = find("contact.radius").unwrap();
        assert!(r.unusual(20.0));
        assert!(!r.unusual(2e-5));
        assert!(time::TOLERANCE.check(1.0).is_err());
        assert!(contact::NU1.check(0.5).is_ok());
        assert!(contact::NU1.check(-1.0).is_err());
    }
}
