//! `stickslip.fit`: the studies crate's fit of scene parameters to a measured trace
//! (`stickslip_studies::fit`) with the GIL released, Ctrl-C and progress through the bridge; the
//! result as fit.json's dict with the fitted scene's TOML and the curves, and with `out` the
//! command line's three files (the reporting kit's `fit::write_outputs`).

use crate::progress::{Bridge, Report};
use crate::scene::PyScene;
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use stickslip_studies::fit::{
    Columns, FitError, FitOptions, JacobianKind, MisfitKind, Progress, Trace,
};
use stickslip_studies::options;

/// Fits ``params`` (``KEY[=LO:HI]``) of ``scene`` to a trace: the CSV at ``path`` (its
/// ``columns`` as ``t=NAME,F=NAME``) or the arrays ``t`` (s), ``f`` (N) and ``x`` (m, or
/// None). Returns ``{"report": fit.json's dict, "fitted_toml": str, "t": [...], "f":
/// [...], "model_f": [...]}``; an interrupted fit returns its best model so far (report
/// status ``"interrupted"``). With ``out``, also writes fit.json, fit.svg and fitted.toml
/// there as ``stickslip fit --out`` does. Internal: use ``stickslip.fit``.
#[pyfunction]
#[pyo3(signature = (scene, params, misfit = options::FIT_MISFIT, path = None, columns = None, t = None, f = None, x = None, noise = None, jobs = options::JOBS, profile = None, progress = None, out = None, jacobian = "differences"))]
#[allow(clippy::too_many_arguments)]
pub fn fit<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    params: Vec<String>,
    misfit: &str,
    path: Option<PathBuf>,
    columns: Option<String>,
    t: Option<Vec<f64>>,
    f: Option<Vec<f64>>,
    x: Option<Vec<f64>>,
    noise: Option<f64>,
    jobs: usize,
    profile: Option<String>,
    progress: Option<Py<PyAny>>,
    out: Option<PathBuf>,
    jacobian: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let kind = MisfitKind::from_name(misfit).map_err(|e| error(&e))?;
    let jacobian = JacobianKind::from_name(jacobian).map_err(|e| error(&e))?;
    let trace = match (path, t, f) {
        (Some(p), None, None) => {
            let columns = match &columns {
                Some(c) => Columns::parse(c).map_err(|e| error(&e))?,
                None => Columns::default(),
            };
            Trace::read(&p, &columns)
        }
        (None, Some(t), Some(f)) => Trace::new(t, f, x),
        _ => {
            return Err(PyValueError::new_err(
                "data: give a trace file's path, or arrays t and F",
            ));
        }
    }
    .map_err(|e| error(&e))?;
    let scene = std::sync::Arc::clone(&scene.get().inner);
    let stop = AtomicBool::new(false);
    let mut bridge = Bridge::new(progress);
    let result = py.detach(|| {
        let mut on_progress = |p: &Progress| {
            bridge.tick(&stop, || Report::Fit {
                stage: p.stage,
                evaluations: p.evaluations,
                failed: p.failed_runs,
                best_chi2: p.best_chi2,
                tolerance: p.tolerance,
                batch: (p.batch_left, p.batch_eta_s),
                stop: None,
            });
            false
        };
        stickslip_studies::fit::fit(
            &scene,
            trace,
            &params,
            FitOptions {
                misfit: kind,
                noise_n: noise,
                jobs: jobs.max(1),
                profile,
                interrupt: Some(&stop),
                progress: Some(&mut on_progress),
                start: None,
                jacobian,
                ..FitOptions::default()
            },
        )
    });
    // An exception from the progress callback other than Ctrl-C is the caller's error.
    if let Some(e) = bridge.error.take()
        && !e.is_instance_of::<PyKeyboardInterrupt>(py)
    {
        return Err(e);
    }
    let outcome = result.map_err(|e| error(&e))?;
    if let Some(dir) = &out {
        stickslip_report::fit::write_outputs(dir, &outcome).map_err(PyOSError::new_err)?;
    }
    let json = serde_json::to_value(&outcome.report)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot encode the report: {e}")))?;
    let d = PyDict::new(py);
    d.set_item("report", crate::json::json_to_py(py, &json)?)?;
    d.set_item("fitted_toml", &outcome.fitted_toml)?;
    d.set_item("t", &outcome.trace.t_s)?;
    d.set_item("f", &outcome.trace.f_n)?;
    d.set_item("model_f", &outcome.model_f_n)?;
    Ok(d)
}

/// A fit's error as the package's exception: bad input a ValueError, an unreadable trace an
/// OSError, a bad scene value a SceneError, Ctrl-C before any run ended a
/// KeyboardInterrupt, no run succeeding a RuntimeError.
fn error(e: &FitError) -> PyErr {
    match e {
        FitError::Input { .. } => PyValueError::new_err(e.to_string()),
        FitError::Read { .. } => PyOSError::new_err(e.to_string()),
        FitError::Scene(s) => crate::errors::scene(s),
        FitError::Interrupted { .. } => PyKeyboardInterrupt::new_err(e.to_string()),
        FitError::NoRun { .. } => PyRuntimeError::new_err(e.to_string()),
    }
}
