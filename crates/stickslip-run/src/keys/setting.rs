//! Typed overrides: a key set from code through the registry ([`super::Key::set`]), applied
//! to a scene's table without going through text, or written as the `--set` argument that
//! sets the same value on the command line.

/// One key set to one value (see [`super::Key::set`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// The key's path, `section.key`.
    pub path: &'static str,
    /// The value as a scene holds it.
    pub value: toml::Value,
}

impl Setting {
    pub(super) fn new(path: &'static str, value: toml::Value) -> Self {
        Self { path, value }
    }

    /// Sets the key in `root`, creating its sections; a section that is not a table is
    /// replaced (scene resolution reports sections of the wrong type before this matters for
    /// text overrides, and code builds its tables itself).
    pub fn apply(&self, root: &mut toml::Table) {
        let mut parts: Vec<&str> = self.path.split('.').collect();
        let Some(last) = parts.pop() else { return };
        let mut table = root;
        for part in parts {
            let entry = table
                .entry(part.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if !entry.is_table() {
                *entry = toml::Value::Table(toml::Table::new());
            }
            match entry {
                toml::Value::Table(t) => table = t,
                _ => return,
            }
        }
        table.insert(last.to_string(), self.value.clone());
    }
}

/// `section.key=value`, as `--set` takes it: numbers in shortest round-trip form, words bare.
impl std::fmt::Display for Setting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}=", self.path)?;
        write_value(f, &self.value)
    }
}

fn write_value(f: &mut std::fmt::Formatter<'_>, v: &toml::Value) -> std::fmt::Result {
    match v {
        toml::Value::Float(x) if x.is_finite() => write!(f, "{x:e}"),
        toml::Value::Float(x) if x.is_nan() => write!(f, "nan"),
        toml::Value::Float(x) => write!(f, "{}", if *x > 0.0 { "inf" } else { "-inf" }),
        toml::Value::Integer(i) => write!(f, "{i}"),
        toml::Value::String(s) => write!(f, "{s}"),
        toml::Value::Array(items) => {
            write!(f, "[")?;
            for (i, item) in items.iter().enumerate() {
                if i > 0 {
                    write!(f, ",")?;
                }
                write_value(f, item)?;
            }
            write!(f, "]")
        }
        other => write!(f, "{other}"),
    }
}

#[cfg(test)]
mod tests {
    use crate::keys::{contact, noise, output, time, words::Scheme};

    #[test]
    fn a_setting_is_the_text_override_that_sets_the_same_value() {
        let cases = [
            (time::TOLERANCE.set(1e-4), "time.tolerance=1e-4"),
            (time::SCHEME.set(Scheme::Literal), "time.scheme=literal"),
            (contact::NODES.set(200), "contact.nodes=200"),
            (
                output::PROFILE_TIMES.set(vec![1e-3, 2.5e-3]),
                "output.profile_times=[1e-3,2.5e-3]",
            ),
            (noise::SEED.set(7), "lubricant.noise.seed=7"),
        ];
        for (setting, text) in cases {
            assert_eq!(setting.to_string(), text);
            let mut typed = toml::Table::new();
            setting.apply(&mut typed);
            let mut parsed = toml::Table::new();
            crate::scene::overrides::apply_override(&mut parsed, text).unwrap();
            assert_eq!(typed, parsed, "{text}");
        }
    }
}
