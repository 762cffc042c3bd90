//! `stickslip.keys()`: the scene-key registry as Python data, one dict per key, in the
//! reference's order (the view `stickslip keys` prints and docs/reference.md holds).

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use stickslip_run::keys::{KEYS, ValueType};

/// Every scene key as a dict: ``path``, ``type`` (``"real"``, ``"integer"``, ``"text"``,
/// ``"choice"`` or ``"real list"``), ``words`` (a choice key's words, else ``None``),
/// ``unit`` (SI; ``"–"`` for dimensionless), ``default`` (in words: a value, ``"required"``,
/// or how it derives from other keys), ``allowed`` (the range and the rules between keys, in
/// words), ``usual`` (``(lo, hi)`` of the absolute value outside which ``check`` warns, else
/// ``None``), ``meaning`` and ``since`` (the version that added the key).
#[pyfunction]
pub fn keys(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for key in KEYS.iter() {
        let d = PyDict::new(py);
        let (kind, words) = match key.value {
            ValueType::Real => ("real", None),
            ValueType::Integer => ("integer", None),
            ValueType::Text => ("text", None),
            ValueType::Choice(w) => ("choice", Some(w.to_vec())),
            ValueType::RealList => ("real list", None),
        };
        d.set_item("path", key.path)?;
        d.set_item("type", kind)?;
        d.set_item("words", words)?;
        d.set_item("unit", key.unit)?;
        d.set_item("default", key.default.describe())?;
        d.set_item("allowed", key.allowed())?;
        d.set_item("usual", key.usual)?;
        d.set_item("meaning", key.meaning)?;
        d.set_item("since", key.since)?;
        list.append(d)?;
    }
    Ok(list)
}
