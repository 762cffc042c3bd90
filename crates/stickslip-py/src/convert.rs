//! Conversions between Python values and TOML / JSON values.
//!
//! Python → TOML: `bool`, `int` (or anything with `__index__`, e.g. `numpy.int64`), `float`
//! (or anything with `__float__`), `str`, mappings (tables), lists and tuples (arrays), NumPy
//! arrays (through `tolist()`). `None` means "no value": the key is left out (or, in
//! `Scene.with_overrides`, removed, so that its default applies).
//!
//! TOML / JSON → Python: the obvious types; TOML datetimes as `str`, JSON null as `None`.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyMapping, PyString, PyTuple};
use stickslip_run::SceneError;

/// Deepest key path accepted in a scene dict (the scene has at most three levels).
const MAX_DEPTH: usize = 8;

/// Key and value of one item of a mapping.
pub type Item<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>);

/// The items of a mapping (a `dict` or anything registered as `collections.abc.Mapping`).
pub fn mapping_items<'py>(value: &Bound<'py, PyAny>) -> PyResult<Option<Vec<Item<'py>>>> {
    let items = if let Ok(d) = value.cast::<PyDict>() {
        d.items()
    } else if let Ok(m) = value.cast::<PyMapping>() {
        m.items()?
    } else {
        return Ok(None);
    };
    items
        .iter()
        .map(|item| {
            let pair = item.cast_into::<PyTuple>()?;
            Ok((pair.get_item(0)?, pair.get_item(1)?))
        })
        .collect::<PyResult<Vec<_>>>()
        .map(Some)
}

/// A mapping key as a string.
fn key_str(key: &Bound<'_, PyAny>, at: &str) -> PyResult<String> {
    key.cast::<PyString>().map(|s| s.to_string()).map_err(|_| {
        PyTypeError::new_err(format!(
            "keys must be strings; got {} at {}",
            key.repr()
                .map_or_else(|_| "?".to_string(), |r| r.to_string()),
            if at.is_empty() { "the top level" } else { at }
        ))
    })
}

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

/// Deepest nesting of tables and arrays accepted in a value: far beyond any scene or sweep,
/// and a bound on the recursion (a dict or list that contains itself would otherwise
/// overflow the stack).
const MAX_NESTING: usize = 32;

/// A Python value as a TOML value; `None` for Python's `None`. `at` names the key in errors.
/// `split_dotted`: keys of nested mappings are split at dots (scene dicts); otherwise kept
/// whole (the `[set]` table of a sweep, whose keys are dotted scene keys).
pub fn to_toml(
    value: &Bound<'_, PyAny>,
    at: &str,
    split_dotted: bool,
) -> PyResult<Option<toml::Value>> {
    nested(value, at, split_dotted, 0)
}

fn nested(
    value: &Bound<'_, PyAny>,
    at: &str,
    split_dotted: bool,
    depth: usize,
) -> PyResult<Option<toml::Value>> {
    if depth > MAX_NESTING {
        return Err(PyValueError::new_err(format!(
            "{at}: nested more than {MAX_NESTING} levels deep (a dict or list that contains \
             itself?); allowed: the tables and arrays of a scene or sweep file"
        )));
    }
    if value.is_none() {
        return Ok(None);
    }
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(Some(toml::Value::Boolean(b.is_true())));
    }
    if value.cast::<PyInt>().is_ok() {
        let i: i64 = value.extract().map_err(|_| {
            PyTypeError::new_err(format!("{at}: the integer {value} does not fit in 64 bits"))
        })?;
        return Ok(Some(toml::Value::Integer(i)));
    }
    if let Ok(f) = value.cast::<PyFloat>() {
        return Ok(Some(toml::Value::Float(f.value())));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(Some(toml::Value::String(s.to_string())));
    }
    if let Some(items) = mapping_items(value)? {
        let mut table = toml::Table::new();
        for (k, v) in items {
            let key = key_str(&k, at)?;
            let path = join(at, &key);
            if let Some(v) = nested(&v, &path, split_dotted, depth + 1)? {
                if split_dotted {
                    insert_dotted(&mut table, &key, v).map_err(|e| crate::errors::scene(&e))?;
                } else {
                    table.insert(key, v);
                }
            }
        }
        return Ok(Some(toml::Value::Table(table)));
    }
    if value.cast::<PyList>().is_ok() || value.cast::<PyTuple>().is_ok() {
        let mut out = Vec::new();
        for (i, item) in value.try_iter()?.enumerate() {
            let item = item?;
            let path = format!("{at}[{i}]");
            match nested(&item, &path, split_dotted, depth + 1)? {
                Some(v) => out.push(v),
                None => {
                    return Err(PyTypeError::new_err(format!(
                        "{path}: None inside an array; allowed: numbers, strings, tables"
                    )));
                }
            }
        }
        return Ok(Some(toml::Value::Array(out)));
    }
    if value.hasattr("tolist")? {
        // NumPy arrays and scalars.
        let plain = value.call_method0("tolist")?;
        if !plain.is(value) {
            return nested(&plain, at, split_dotted, depth + 1);
        }
    }
    if let Ok(i) = value.extract::<i64>() {
        return Ok(Some(toml::Value::Integer(i)));
    }
    if let Ok(f) = value.extract::<f64>() {
        return Ok(Some(toml::Value::Float(f)));
    }
    Err(PyTypeError::new_err(format!(
        "{at} = {}: not a scene value; allowed: bool, int, float, str, list, dict (or None to \
         leave the key out)",
        value
            .repr()
            .map_or_else(|_| "?".to_string(), |r| r.to_string())
    )))
}

/// The key parts of a dotted path, checked as `--set` checks them.
pub fn key_parts(path: &str) -> Result<Vec<&str>, SceneError> {
    let bad = |problem: String| SceneError::Override {
        arg: path.to_string(),
        problem,
    };
    let parts: Vec<&str> = path.split('.').map(str::trim).collect();
    if parts.len() > MAX_DEPTH {
        return Err(bad("key path too deep".into()));
    }
    if let Some(k) = parts.iter().find(|k| {
        k.is_empty()
            || !k
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    }) {
        return Err(bad(format!(
            "key part {k:?} is not a bare key (letters, digits, `_`, `-`)"
        )));
    }
    Ok(parts)
}

/// The table at `parents` inside `root`, created on the way; an error names a path through a
/// value that is not a table.
fn table_at<'t>(
    root: &'t mut toml::Table,
    path: &str,
    parents: &[&str],
) -> Result<&'t mut toml::Table, SceneError> {
    let mut table = root;
    for (depth, k) in parents.iter().enumerate() {
        let entry = table
            .entry((*k).to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        match entry {
            toml::Value::Table(t) => table = t,
            other => {
                return Err(SceneError::Override {
                    arg: path.to_string(),
                    problem: format!("`{}` is {other}, not a table", parents[..=depth].join(".")),
                });
            }
        }
    }
    Ok(table)
}

/// Inserts `value` at the dotted `path` of `root` (tables are merged with what is there).
pub fn insert_dotted(
    root: &mut toml::Table,
    path: &str,
    value: toml::Value,
) -> Result<(), SceneError> {
    let parts = key_parts(path)?;
    let Some((last, parents)) = parts.split_last() else {
        return Ok(());
    };
    let table = table_at(root, path, parents)?;
    match (table.get_mut(*last), value) {
        (Some(toml::Value::Table(old)), toml::Value::Table(new)) => {
            for (k, v) in new {
                insert_dotted(old, &k, v)?;
            }
        }
        (_, value) => {
            table.insert((*last).to_string(), value);
        }
    }
    Ok(())
}

/// Removes the key at the dotted `path` of `root`, if it is there.
pub fn remove_dotted(root: &mut toml::Table, path: &str) -> Result<(), SceneError> {
    let parts = key_parts(path)?;
    let Some((last, parents)) = parts.split_last() else {
        return Ok(());
    };
    let mut table = root;
    for k in parents {
        match table.get_mut(*k) {
            Some(toml::Value::Table(t)) => table = t,
            _ => return Ok(()),
        }
    }
    table.remove(*last);
    Ok(())
}

/// A scene dict (nested like the TOML, dotted keys allowed at any level) as a TOML table.
pub fn scene_table(d: &Bound<'_, PyAny>) -> PyResult<toml::Table> {
    match to_toml(d, "", true)? {
        Some(toml::Value::Table(t)) => Ok(t),
        _ => Err(PyTypeError::new_err(format!(
            "a scene must be a dict (nested like the TOML file, or with dotted keys such as \
             \"contact.nodes\"); got {}",
            d.get_type().name()?
        ))),
    }
}

/// A TOML value as a Python object.
pub fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => PyList::new(
            py,
            a.iter()
                .map(|x| toml_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?,
        )?
        .into_any(),
        toml::Value::Table(t) => table_to_py(py, t)?.into_any(),
    })
}

/// A TOML table as a Python dict (keys in the table's order).
pub fn table_to_py<'py>(py: Python<'py>, t: &toml::Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in t {
        d.set_item(k, toml_to_py(py, v)?)?;
    }
    Ok(d)
}
