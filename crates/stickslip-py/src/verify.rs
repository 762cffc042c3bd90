//! `stickslip.verify`: the run library's refinements of a scene (`stickslip_studies::verify`)
//! with the GIL released; the report as the dict verify.json holds.

use crate::scene::PyScene;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use stickslip_studies::options;
use stickslip_studies::verify::{VerifyError, target, verify as run_verify};

/// Runs ``scene`` at its own settings and refined in space and time, ``jobs`` runs at a
/// time, and returns verify.json's content: ``quantities`` (each ``name``, ``unit``,
/// ``value``, ``text``, ``extrapolated``, ``uncertainty``, ``space``, ``time``,
/// ``asymptotic``, ``changed``, ``verdict``), ``levels``, ``rtol`` and ``scene``. Internal:
/// use ``stickslip.verify``.
#[pyfunction]
#[pyo3(signature = (scene, rtol = options::VERIFY_RTOL, jobs = options::JOBS))]
pub fn verify<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    rtol: f64,
    jobs: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = std::sync::Arc::clone(&scene.get().inner);
    let report = py.detach(|| run_verify(&scene, rtol, jobs.max(1)));
    to_py(py, report.map(|r| serde_json::to_value(&r)))
}

/// Searches the cheapest ``contact.nodes`` and ``time.tolerance`` of ``scene`` whose
/// estimated relative error of the first onset and of its peak force is within ``target``
/// (``stickslip verify --target``) and returns target.json's content: ``choice`` (``nodes``,
/// ``tolerance``, ``grid``, ``space_error``, ``time_error``, ``wall_s``, …, or None),
/// ``probes``, ``target``, ``scene``, ``note``. Internal: use ``stickslip.verify``.
#[pyfunction]
#[pyo3(signature = (scene, target_rel))]
pub fn verify_target<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    target_rel: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = std::sync::Arc::clone(&scene.get().inner);
    let report = py.detach(|| target::search(&scene, target_rel, &mut |_| {}));
    to_py(py, report.map(|r| serde_json::to_value(&r)))
}

/// A report as the dict its JSON file holds, or the error as Python's exception.
fn to_py<'py>(
    py: Python<'py>,
    report: Result<serde_json::Result<serde_json::Value>, VerifyError>,
) -> PyResult<Bound<'py, PyAny>> {
    match report {
        Ok(r) => {
            let json =
                r.map_err(|e| PyRuntimeError::new_err(format!("cannot encode the report: {e}")))?;
            crate::json::json_to_py(py, &json)
        }
        Err(e @ VerifyError::Option { .. }) => Err(PyValueError::new_err(e.to_string())),
        Err(VerifyError::Scene { error, .. }) => Err(crate::errors::scene(&error)),
        Err(e @ (VerifyError::Start { .. } | VerifyError::Failed { .. })) => {
            Err(PyRuntimeError::new_err(e.to_string()))
        }
        Err(e @ VerifyError::Interrupted { .. }) => Err(
            pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string()),
        ),
    }
}
