//! TOML text of scenes: the printed form (numbers in shortest round-trip `{:e}` form, so a
//! printed scene parses back to the same values), syntax errors with line and column, and the
//! check that no number anywhere is non-finite.

use super::error::{self, SceneError};

/// `table` as TOML text: plain keys first, then one `[section]` per sub-table, in order.
#[must_use]
pub fn to_toml_string(table: &toml::Table) -> String {
    let mut out = String::new();
    emit_table(&mut out, &mut Vec::new(), table);
    out
}

fn emit_key(out: &mut String, k: &str) {
    if !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        out.push_str(k);
    } else {
        out.push_str(&toml::Value::String(k.to_string()).to_string());
    }
}

fn emit_value(out: &mut String, v: &toml::Value) {
    match v {
        toml::Value::Float(f) => out.push_str(&error::format_float(*f)),
        toml::Value::Array(a) => {
            out.push('[');
            for (i, x) in a.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                emit_value(out, x);
            }
            out.push(']');
        }
        toml::Value::Table(t) => {
            out.push('{');
            for (i, (k, x)) in t.iter().enumerate() {
                out.push_str(if i > 0 { ", " } else { " " });
                emit_key(out, k);
                out.push_str(" = ");
                emit_value(out, x);
            }
            out.push_str(" }");
        }
        other => out.push_str(&other.to_string()),
    }
}

fn emit_table(out: &mut String, path: &mut Vec<String>, t: &toml::Table) {
    for (k, v) in t.iter().filter(|(_, v)| !v.is_table()) {
        emit_key(out, k);
        out.push_str(" = ");
        emit_value(out, v);
        out.push('\n');
    }
    for (k, v) in t {
        if let toml::Value::Table(sub) = v {
            path.push(k.clone());
            out.push_str("\n[");
            for (i, p) in path.iter().enumerate() {
                if i > 0 {
                    out.push('.');
                }
                emit_key(out, p);
            }
            out.push_str("]\n");
            emit_table(out, path, sub);
            path.pop();
        }
    }
}

/// A [`SceneError::Syntax`] for the parse error `e` of `text`.
pub(crate) fn syntax_error(text: &str, e: &toml::de::Error) -> SceneError {
    let start = e.span().map_or(0, |s| s.start).min(text.len());
    let before = &text.as_bytes()[..start];
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    let rest = &text.as_bytes()[line_start..];
    let line_end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
    let excerpt = String::from_utf8_lossy(&rest[..line_end]);
    SceneError::Syntax {
        line,
        column,
        message: error::shorten(e.message().trim()),
        excerpt: error::shorten(excerpt.trim()),
    }
}

/// Rejects NaN and infinities anywhere in the table (after the specific checks, so a value that
/// has its own range gets that range in the message).
pub(crate) fn check_finite(v: &toml::Table, path: &mut Vec<String>) -> Result<(), SceneError> {
    for (k, x) in v {
        path.push(k.clone());
        check_finite_value(x, path)?;
        path.pop();
    }
    Ok(())
}

fn check_finite_value(x: &toml::Value, path: &mut Vec<String>) -> Result<(), SceneError> {
    match x {
        toml::Value::Float(f) if !f.is_finite() => Err(SceneError::invalid(
            &path.join("."),
            error::human(*f),
            "a finite number",
        )),
        toml::Value::Table(t) => check_finite(t, path),
        toml::Value::Array(a) => a.iter().try_for_each(|y| check_finite_value(y, path)),
        _ => Ok(()),
    }
}
