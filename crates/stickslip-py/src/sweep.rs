//! `stickslip.sweep`: a friction map, every point run in-process on `jobs` threads (the run
//! library's sweep executor, as `stickslip sweep run`), the table returned as NumPy arrays.

use crate::convert;
use crate::errors;
use crate::run::SignalWatch;
use crate::scene::PyScene;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{
    PyKeyboardInterrupt, PyOSError, PyRuntimeWarning, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyInt, PyString};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use stickslip_run::scene::toml_text;
use stickslip_run::sweep::exec::{self, Merge, SweepOptions, SweepProgress, SweepRunError};
use stickslip_run::sweep::map::MapTable;
use stickslip_run::sweep::{Sweep, SweepError, file, value_number};

/// Resolves a sweep given as a dict; `scratch` receives the scene file of a `Scene` object.
fn from_dict(d: &Bound<'_, PyAny>, scratch: &Path, allow_large: bool) -> PyResult<Sweep> {
    let Some(items) = convert::mapping_items(d)? else {
        return Err(PyTypeError::new_err("a sweep is a path or a dict"));
    };
    let mut table = toml::Table::new();
    for (k, v) in items {
        let key: String = k
            .extract()
            .map_err(|_| PyTypeError::new_err("sweep keys must be strings"))?;
        if key == "scene"
            && let Ok(scene) = v.cast::<PyScene>()
        {
            let path = scratch.join("scene.toml");
            std::fs::write(&path, toml_text::to_toml_string(&scene.get().inner.source))
                .map_err(|e| PyOSError::new_err(format!("{}: {e}", path.display())))?;
            table.insert(key, toml::Value::String(path.display().to_string()));
            continue;
        }
        if key == "scene"
            && let Ok(path) = v.extract::<PathBuf>()
        {
            table.insert(key, toml::Value::String(path.display().to_string()));
            continue;
        }
        if let Some(value) = convert::to_toml(&v, &key, false)? {
            table.insert(key, value);
        }
    }
    // As the text of a sweep file, so a dict's errors name the key path as a file's do (its
    // lines mean nothing here and are left out).
    let text = toml::to_string(&table).map_err(|e| {
        errors::sweep(&SweepError::Read {
            path: "(dict)".to_string(),
            message: e.to_string(),
        })
    })?;
    let file = file::parse(&text, "(dict)", false).map_err(|e| errors::sweep(&e))?;
    // The scene path of a dict is relative to the current directory.
    let here = std::env::current_dir()
        .map_err(|e| PyOSError::new_err(format!("current directory: {e}")))?
        .join("(sweep dict)");
    Sweep::resolve(&file, &here, allow_large).map_err(|e| errors::sweep(&e))
}

/// A column of numbers (NaN for none).
fn floats<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyAny> {
    v.into_pyarray(py).into_any()
}

/// A column of words, as a NumPy array of Python strings (dtype object).
fn words<'py>(py: Python<'py>, v: impl Iterator<Item = String>) -> Bound<'py, PyAny> {
    let objs: Vec<Py<PyAny>> = v
        .map(|s| PyString::new(py, &s).into_any().unbind())
        .collect();
    PyArray1::from_vec(py, objs).into_any()
}

/// map.csv as a dict of arrays, in its column order.
fn table_dict<'py>(
    py: Python<'py>,
    sweep: &Sweep,
    table: &MapTable,
) -> PyResult<Bound<'py, PyDict>> {
    let rows = &table.rows;
    let d = PyDict::new(py);
    let point: Vec<i64> = rows
        .iter()
        .map(|r| i64::try_from(r.point).unwrap_or(i64::MAX))
        .collect();
    d.set_item("point", PyArray1::from_vec(py, point))?;
    for (j, axis) in sweep.axes.iter().enumerate() {
        let values: Vec<toml::Value> = rows
            .iter()
            .map(|r| sweep.values(r.point)[j].clone())
            .collect();
        let col = if values
            .iter()
            .all(|v| matches!(v, toml::Value::Float(_) | toml::Value::Integer(_)))
        {
            floats(py, values.iter().map(value_number).collect())
        } else {
            words(py, rows.iter().map(|r| r.values[j].clone()))
        };
        d.set_item(&axis.key, col)?;
    }
    d.set_item(
        "status",
        words(py, rows.iter().map(|r| r.status.name().to_string())),
    )?;
    d.set_item(
        "regime",
        words(py, rows.iter().map(|r| r.summary.regime.name().to_string())),
    )?;
    let n_events: Vec<i64> = rows
        .iter()
        .map(|r| i64::try_from(r.summary.n_events).unwrap_or(i64::MAX))
        .collect();
    d.set_item("n_events", PyArray1::from_vec(py, n_events))?;
    for name in [
        "t_first_onset",
        "period_last",
        "x_period_last",
        "f_peak_first",
        "f_peak_last",
        "f_mean",
        "recovery",
        "melted_time_fraction",
        "wall_s",
    ] {
        d.set_item(
            name,
            floats(py, rows.iter().map(|r| r.number(name)).collect()),
        )?;
    }
    d.set_item("message", words(py, rows.iter().map(|r| r.message.clone())))?;
    Ok(d)
}

/// `jobs` as a count of threads: None for the available cores, else an int ≥ 1.
fn jobs_count(jobs: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
    let Some(jobs) = jobs.filter(|j| !j.is_none()) else {
        return Ok(std::thread::available_parallelism().map_or(1, std::num::NonZero::get));
    };
    let kind = jobs
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    if jobs.cast::<PyBool>().is_ok() || jobs.cast::<PyInt>().is_err() {
        return Err(PyTypeError::new_err(format!(
            "jobs = {jobs} ({kind}) is invalid; allowed: an int >= 1, or None for the \
             available cores"
        )));
    }
    match jobs.extract::<i64>() {
        Ok(j) if j >= 1 => Ok(usize::try_from(j).unwrap_or(usize::MAX)),
        _ => Err(PyValueError::new_err(format!(
            "jobs = {jobs} is invalid; allowed: an int >= 1, or None for the available cores"
        ))),
    }
}

/// A flag argument: a bool, nothing else.
fn flag(value: &Bound<'_, PyAny>, name: &str) -> PyResult<bool> {
    value.cast::<PyBool>().map(|b| b.is_true()).map_err(|_| {
        let kind = value
            .get_type()
            .name()
            .map_or_else(|_| "?".to_string(), |n| n.to_string());
        PyTypeError::new_err(format!(
            "{name} = {value} ({kind}) is invalid; allowed: True or False"
        ))
    })
}

/// Runs a sweep (a friction map) and returns map.csv as a dict of NumPy arrays. Internal: see
/// ``stickslip.sweep``.
#[pyfunction]
#[pyo3(signature = (sweep, jobs = None, *, out = None, force = None, allow_large = None))]
pub fn sweep<'py>(
    py: Python<'py>,
    sweep: &Bound<'py, PyAny>,
    jobs: Option<&Bound<'py, PyAny>>,
    out: Option<&Bound<'py, PyAny>>,
    force: Option<&Bound<'py, PyAny>>,
    allow_large: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let jobs = jobs_count(jobs)?;
    let force = force.map_or(Ok(false), |f| flag(f, "force"))?;
    let allow_large = allow_large.map_or(Ok(false), |f| flag(f, "allow_large"))?;
    let out: Option<PathBuf> = match out.filter(|o| !o.is_none()) {
        None => None,
        Some(o) => Some(o.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "out = {o} is invalid; allowed: a path (str or os.PathLike) or None"
            ))
        })?),
    };
    let scratch = tempfile::Builder::new()
        .prefix("stickslip-sweep-")
        .tempdir()
        .map_err(|e| PyOSError::new_err(format!("cannot create a temporary directory: {e}")))?;
    let resolved = if mapping_like(sweep)? {
        from_dict(sweep, scratch.path(), allow_large)?
    } else {
        let path: PathBuf = sweep.extract().map_err(|_| {
            PyTypeError::new_err("a sweep is a path to a sweep file (TOML) or a dict like one")
        })?;
        Sweep::load(&path, allow_large).map_err(|e| errors::sweep(&e))?
    };
    let dir = out.unwrap_or_else(|| scratch.path().join("sweep"));
    let options = SweepOptions {
        jobs,
        shard: (0, 1),
        keep_all: false,
        force,
    };
    let mut watch = SignalWatch::new();
    let stop = AtomicBool::new(false);
    let result = py.detach(|| {
        exec::prepare(&resolved, &dir, force)?;
        let mut progress = |_: &SweepProgress| watch.check(&stop);
        let report = exec::run_shard(&resolved, &dir, &options, Some(&stop), &mut progress)?;
        let merged = if report.interrupted {
            exec::merge(&dir)
        } else {
            exec::after_shard(&dir, &resolved.fingerprint(), options.shard)
        };
        merged.map(|m| (m, report.recomputed_text()))
    });
    if let Some(e) = watch.error.take() {
        return Err(e);
    }
    match result {
        Ok((Merge::Complete { table, .. }, again)) => {
            if !again.is_empty() {
                PyErr::warn(
                    py,
                    &py.get_type::<PyRuntimeWarning>(),
                    &std::ffi::CString::new(format!("stickslip.sweep: {again}"))
                        .unwrap_or_default(),
                    1,
                )?;
            }
            table_dict(py, &resolved, &table)
        }
        Ok((
            Merge::Incomplete {
                missing, points, ..
            },
            _,
        )) => Err(PyKeyboardInterrupt::new_err(format!(
            "sweep interrupted: {missing} of {points} points not run"
        ))),
        Err(SweepRunError::Other { dir }) => Err(PyOSError::new_err(format!(
            "{dir} holds the results of another sweep (its sweep.json differs); allowed: the \
             directory of this sweep, a new one, or force=True to replace them"
        ))),
        Err(e @ SweepRunError::Foreign { .. }) => Err(PyOSError::new_err(
            e.to_string().replace("--force", "force=True"),
        )),
        Err(e) => Err(PyOSError::new_err(e.to_string())),
    }
}

fn mapping_like(v: &Bound<'_, PyAny>) -> PyResult<bool> {
    Ok(v.cast::<PyDict>().is_ok() || v.cast::<pyo3::types::PyMapping>().is_ok())
}
