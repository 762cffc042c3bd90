//! `--set section.key=value` overrides, applied to the parsed TOML before it is deserialized.
//!
//! The value is parsed as a TOML value (`2e-8`, `200`, `"literal"`, `[1e-3, 2e-3]`, `nan`);
//! text that is not a TOML value is taken as a string, so `time.scheme=literal` works without
//! quotes. Missing intermediate tables are created (`lubricant.noise.kind=gaussian` works on a
//! scene without `[lubricant.noise]`).

use super::error::SceneError;

/// Deepest key path accepted (the scene has at most three levels).
const MAX_DEPTH: usize = 8;

/// Applies one `section.key=value` override to `root`.
///
/// # Errors
/// [`SceneError::Override`] when the argument has no `=`, an empty or malformed key path, an
/// empty value, or a path through a key that is not a table.
pub fn apply_override(root: &mut toml::Table, arg: &str) -> Result<(), SceneError> {
    let bad = |problem: &str| SceneError::Override {
        arg: super::error::shorten(arg),
        problem: problem.to_string(),
    };
    let (lhs, rhs) = arg
        .split_once('=')
        .ok_or_else(|| bad("no `=` between the key and the value"))?;
    let lhs = lhs.trim();
    let rhs = rhs.trim();
    if lhs.is_empty() {
        return Err(bad("empty key"));
    }
    let keys: Vec<&str> = lhs.split('.').map(str::trim).collect();
    if keys.len() > MAX_DEPTH {
        return Err(bad("key path too deep"));
    }
    if let Some(k) = keys.iter().find(|k| {
        k.is_empty()
            || !k
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    }) {
        return Err(bad(&format!(
            "key part {k:?} is not a bare key (letters, digits, `_`, `-`)"
        )));
    }
    if rhs.is_empty() {
        return Err(bad("empty value"));
    }
    let value = rhs
        .parse::<toml::Value>()
        .unwrap_or_else(|_| toml::Value::String(rhs.to_string()));
    let Some((last, parents)) = keys.split_last() else {
        return Err(bad("empty key"));
    };
    let mut table = root;
    for (depth, k) in parents.iter().enumerate() {
        let entry = table
            .entry(k.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        match entry {
            toml::Value::Table(t) => table = t,
            other => {
                return Err(bad(&format!(
                    "`{}` is {}, not a table",
                    keys[..=depth].join("."),
                    super::error::show_value(other)
                )));
            }
        }
    }
    table.insert(last.to_string(), value);
    Ok(())
}

/// The value `settings` (`--set` texts, as a record keeps them) give the key at `path`
/// (`section.key`), read by this parser: the last one that sets it; `None` when none does or
/// the text does not parse.
#[must_use]
pub fn value_in(path: &str, settings: &[String]) -> Option<toml::Value> {
    let mut root = toml::Table::new();
    for text in settings {
        let _ = apply_override(&mut root, text);
    }
    let mut parts = path.split('.');
    let section = root.get(parts.next()?)?.as_table()?;
    section.get(parts.next()?).cloned()
}
