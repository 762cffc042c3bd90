//! Arguments of the native functions checked by type and range, with messages in the API's
//! words (`name = value (type) is invalid; allowed: …`).

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt};
use std::path::PathBuf;

/// The name of `value`'s type.
pub fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string())
}

/// `value` as written in a message (its repr, shortened).
pub fn shown(value: &Bound<'_, PyAny>) -> String {
    let text = value
        .repr()
        .map_or_else(|_| "?".to_string(), |r| r.to_string());
    if text.chars().count() > 60 {
        format!("{}…", text.chars().take(60).collect::<String>())
    } else {
        text
    }
}

/// A flag argument: a bool, nothing else; `None` gives `default`.
pub fn flag(value: Option<&Bound<'_, PyAny>>, name: &str, default: bool) -> PyResult<bool> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(default);
    };
    value.cast::<PyBool>().map(|b| b.is_true()).map_err(|_| {
        PyTypeError::new_err(format!(
            "{name} = {} ({}) is invalid; allowed: True or False",
            shown(value),
            type_name(value)
        ))
    })
}

/// A path argument (str or os.PathLike), or none.
pub fn path(value: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<PathBuf>> {
    match value.filter(|v| !v.is_none()) {
        None => Ok(None),
        Some(v) => v.extract().map(Some).map_err(|_| {
            PyTypeError::new_err(format!(
                "{name} = {} is invalid; allowed: a path (str or os.PathLike) or None",
                shown(v)
            ))
        }),
    }
}

/// A required path argument (str or os.PathLike).
pub fn required_path(value: &Bound<'_, PyAny>, name: &str) -> PyResult<PathBuf> {
    let invalid = || {
        PyTypeError::new_err(format!(
            "{name} = {} ({}) is invalid; allowed: a path (str or os.PathLike)",
            shown(value),
            type_name(value)
        ))
    };
    if value.is_none() {
        return Err(invalid());
    }
    value.extract().map_err(|_| invalid())
}

/// A number of seconds, finite and >= 0 (an int or a float, not a bool); `None` gives none.
pub fn seconds(value: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<f64>> {
    let Some(v) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    let number = v.cast::<PyBool>().is_err()
        && (v.cast::<PyFloat>().is_ok() || v.cast::<PyInt>().is_ok() || v.hasattr("__float__")?);
    let x: Option<f64> = if number { v.extract().ok() } else { None };
    match x {
        Some(s) if s.is_finite() && s >= 0.0 => Ok(Some(s)),
        Some(_) => Err(PyValueError::new_err(format!(
            "{name} = {} s is invalid; allowed: a finite number of seconds >= 0 (0 = none)",
            shown(v)
        ))),
        None => Err(PyTypeError::new_err(format!(
            "{name} = {} ({}) is invalid; allowed: a number of seconds >= 0",
            shown(v),
            type_name(v)
        ))),
    }
}

/// A progress callback: a callable receiving a dict, or none.
pub fn callback(value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Py<PyAny>>> {
    match value.filter(|v| !v.is_none()) {
        None => Ok(None),
        Some(v) if v.is_callable() => Ok(Some(v.clone().unbind())),
        Some(v) => Err(PyTypeError::new_err(format!(
            "progress = {} ({}) is invalid; allowed: None, True, False or a callable receiving \
             a dict",
            shown(v),
            type_name(v)
        ))),
    }
}

/// `jobs` as a count of threads: None for the available cores, else an int ≥ 1.
pub fn jobs(jobs: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
    let Some(jobs) = jobs.filter(|j| !j.is_none()) else {
        return Ok(std::thread::available_parallelism().map_or(1, std::num::NonZero::get));
    };
    if jobs.cast::<PyBool>().is_ok() || jobs.cast::<PyInt>().is_err() {
        return Err(PyTypeError::new_err(format!(
            "jobs = {jobs} ({}) is invalid; allowed: an int >= 1, or None for the available \
             cores",
            type_name(jobs)
        )));
    }
    match jobs.extract::<i64>() {
        Ok(j) if j >= 1 => Ok(usize::try_from(j).unwrap_or(usize::MAX)),
        _ => Err(PyValueError::new_err(format!(
            "jobs = {jobs} is invalid; allowed: an int >= 1, or None for the available cores"
        ))),
    }
}
