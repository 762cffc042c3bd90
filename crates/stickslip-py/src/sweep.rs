//! `stickslip.sweep`: a friction map, every point run in-process on `jobs` threads (the run
//! library's sweep executor, as `stickslip sweep run`), the table returned as NumPy arrays.

use crate::args;
use crate::convert;
use crate::errors;
use crate::progress::{Bridge, Report};
use crate::scene::PyScene;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyOSError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use stickslip_run::scene::toml_text;
use stickslip_studies::sweep::exec::{self, MapRead, SweepOptions, SweepProgress, SweepRunError};
use stickslip_studies::sweep::map::{MapJson, MapTable};
use stickslip_studies::sweep::spot;
use stickslip_studies::sweep::{Sweep, SweepError, file, value_number};

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
    let steady: Vec<bool> = rows.iter().map(|r| r.summary.steady).collect();
    d.set_item(
        stickslip_studies::sweep::map::STEADY_COLUMN,
        PyArray1::from_vec(py, steady),
    )?;
    let level: Vec<i64> = rows
        .iter()
        .map(|r| i64::try_from(r.level).unwrap_or(i64::MAX))
        .collect();
    d.set_item(
        stickslip_studies::sweep::map::LEVEL_COLUMN,
        PyArray1::from_vec(py, level),
    )?;
    d.set_item(
        "stamp_regime",
        words(
            py,
            rows.iter().map(|r| {
                r.summary
                    .stamp_regime
                    .map_or("", stickslip_run::cycles::StampRegime::name)
                    .to_string()
            }),
        ),
    )?;
    let n_slips: Vec<i64> = rows
        .iter()
        .map(|r| i64::try_from(r.summary.n_slips).unwrap_or(i64::MAX))
        .collect();
    d.set_item("n_slips", PyArray1::from_vec(py, n_slips))?;
    for name in [
        "slip_interval_median",
        "melting_interval_median",
        stickslip_studies::sweep::map::ENERGY_COLUMN.name,
    ] {
        d.set_item(
            name,
            floats(py, rows.iter().map(|r| r.number(name)).collect()),
        )?;
    }
    Ok(d)
}

/// The sweep's table as the dict the Python layer wraps in a `MapTable`: `table` (map.csv's
/// columns), `points` (of the sweep), `complete`.
fn map_dict<'py>(py: Python<'py>, read: &MapRead) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("table", table_dict(py, &read.sweep, &read.table)?)?;
    d.set_item("points", read.points)?;
    d.set_item("complete", read.complete)?;
    Ok(d)
}

/// Runs a sweep (a friction map) and returns its table as a dict: `table` (map.csv's columns
/// as NumPy arrays), `points`, `complete`, `error` (the exception that stopped it: Ctrl-C or
/// one the progress callback raised; then the table holds the points finished so far) and
/// `warning` (points recomputed, or ""). Internal: see ``stickslip.sweep``.
#[pyfunction]
#[pyo3(signature = (sweep, jobs = None, *, out = None, force = None, allow_large = None, progress = None))]
pub fn sweep<'py>(
    py: Python<'py>,
    sweep: &Bound<'py, PyAny>,
    jobs: Option<&Bound<'py, PyAny>>,
    out: Option<&Bound<'py, PyAny>>,
    force: Option<&Bound<'py, PyAny>>,
    allow_large: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let jobs = args::jobs(jobs)?;
    let force = args::flag(force, "force", false)?;
    let allow_large = args::flag(allow_large, "allow_large", false)?;
    let out = args::path(out, "out")?;
    let mut bridge = Bridge::new(args::callback(progress)?);
    let scratch = tempfile::Builder::new()
        .prefix("stickslip-sweep-")
        .tempdir()
        .map_err(|e| PyOSError::new_err(format!("cannot create a temporary directory: {e}")))?;
    let resolved = if mapping_like(sweep)? {
        from_dict(sweep, scratch.path(), allow_large)?
    } else {
        let path: PathBuf = sweep.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "sweep = {} ({}) is invalid; allowed: a path to a sweep file (TOML) or a dict \
                 like one",
                args::shown(sweep),
                args::type_name(sweep)
            ))
        })?;
        Sweep::load(&path, allow_large).map_err(|e| errors::sweep(&e))?
    };
    let dir = out.unwrap_or_else(|| scratch.path().join("sweep"));
    let options = SweepOptions {
        // Threads beyond the points would have nothing to do.
        jobs: jobs.min(resolved.points.max(1)),
        shard: (0, 1),
        keep_all: false,
        force,
    };
    let stop = AtomicBool::new(false);
    let mut last = SweepProgress {
        done: 0,
        total: 0,
        skipped: 0,
        failed: 0,
        elapsed_s: 0.0,
    };
    let result = py.detach(|| {
        exec::prepare(&resolved, &dir, force)?;
        let mut progress = |p: &SweepProgress| {
            last = *p;
            bridge.tick(&stop, || Report::Sweep {
                done: p.done,
                total: p.total,
                skipped: p.skipped,
                failed: p.failed,
                stop: None,
            });
        };
        let mut report = exec::run_shard(&resolved, &dir, &options, Some(&stop), &mut progress)?;
        let merged = if report.interrupted {
            // Writes the map only if every point has its row after all.
            exec::merge(&dir)?
        } else {
            exec::after_shard(&dir, &resolved.fingerprint(), options.shard)?
        };
        // Spot checks once the map is complete (`[verify]`).
        if let (Some(spot), exec::Merge::Complete { .. }) = (&resolved.verify, &merged)
            && !report.interrupted
        {
            let mut checked = |done: usize, total: usize| {
                bridge.tick(&stop, || Report::Sweep {
                    done,
                    total,
                    skipped: 0,
                    failed: 0,
                    stop: None,
                });
            };
            let found = spot::run_checks(&resolved, spot, &dir, jobs, Some(&stop), &mut checked)?;
            report.interrupted |= found.is_none();
        }
        Ok((exec::read_map(&dir)?, report))
    });
    let (read, report) = result.map_err(|e| sweep_run_error(&e))?;
    bridge.finish(
        py,
        &Report::Sweep {
            done: report.ran,
            total: last.total.max(report.ran),
            skipped: report.skipped,
            failed: report.failed + report.refused,
            stop: Some(if report.interrupted {
                "interrupted"
            } else {
                "end"
            }),
        },
    );
    let d = map_dict(py, &read)?;
    spot_checks(py, &d, &dir)?;
    d.set_item("error", bridge.error.take().map(|e| e.into_value(py)))?;
    d.set_item("warning", report.recomputed_text())?;
    Ok(d)
}

/// Reads the table of the sweep in ``dir``, complete or partial, as ``sweep`` returns it.
/// Internal: see ``stickslip.load_sweep``.
#[pyfunction]
pub fn load_sweep<'py>(py: Python<'py>, dir: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let dir = args::required_path(dir, "dir")?;
    let read = py
        .detach(|| exec::read_map(&dir))
        .map_err(|e| sweep_run_error(&e))?;
    let d = map_dict(py, &read)?;
    spot_checks(py, &d, &dir)?;
    Ok(d)
}

/// Sets `d["spot_checks"]`: map.json's spot checks as a dict, or None (no `[verify]`, or the
/// checks not made yet).
fn spot_checks(py: Python<'_>, d: &Bound<'_, PyDict>, dir: &Path) -> PyResult<()> {
    let report = MapJson::read(dir).ok().and_then(|m| m.spot_checks);
    let value = match report {
        Some(r) => {
            let v = serde_json::to_value(&r).map_err(|e| PyValueError::new_err(e.to_string()))?;
            Some(crate::json::json_to_py(py, &v)?)
        }
        None => None,
    };
    d.set_item("spot_checks", value)
}

/// A sweep that could not run or be read, as a Python exception.
fn sweep_run_error(e: &SweepRunError) -> PyErr {
    match e {
        SweepRunError::Other { dir } => PyFileExistsError::new_err(format!(
            "{dir} holds the results of another sweep (its sweep.json differs); allowed: the \
             directory of this sweep, a new one, or force=True to replace them"
        )),
        // A sweep.json that does not parse is there but damaged.
        SweepRunError::Missing { dir, .. } if Path::new(dir).join(exec::SWEEP_FILE).is_file() => {
            PyValueError::new_err(e.to_string())
        }
        SweepRunError::Missing { .. } => PyFileNotFoundError::new_err(e.to_string()),
        SweepRunError::Foreign { .. } => {
            PyOSError::new_err(e.to_string().replace("--force", "force=True"))
        }
        SweepRunError::OutDir { source, .. } | SweepRunError::Io { source, .. } => {
            errors::os(source.kind(), e.to_string())
        }
        SweepRunError::TakenOver { .. } => PyOSError::new_err(e.to_string()),
    }
}

fn mapping_like(v: &Bound<'_, PyAny>) -> PyResult<bool> {
    Ok(v.cast::<PyDict>().is_ok() || v.cast::<pyo3::types::PyMapping>().is_ok())
}
