//! `stickslip.verify`: the run library's refinements of a scene (`stickslip_run::verify`)
//! with the GIL released; the report as the dict verify.json holds.

use crate::scene::PyScene;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use stickslip_run::verify::{VerifyError, verify as run_verify};

/// Runs ``scene`` at its own settings and refined in space and time, ``jobs`` runs at a
/// time, and returns verify.json's content: ``quantities`` (each ``name``, ``unit``,
/// ``value``, ``text``, ``extrapolated``, ``uncertainty``, ``space``, ``time``,
/// ``asymptotic``, ``changed``, ``verdict``), ``levels``, ``rtol`` and ``scene``. Internal:
/// use ``stickslip.verify``.
#[pyfunction]
#[pyo3(signature = (scene, rtol = 1e-3, jobs = 2))]
pub fn verify<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    rtol: f64,
    jobs: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = std::sync::Arc::clone(&scene.get().inner);
    let report = py.detach(|| run_verify(&scene, rtol, jobs.max(1)));
    match report {
        Ok(r) => {
            let json = serde_json::to_value(&r)
                .map_err(|e| PyRuntimeError::new_err(format!("cannot encode the report: {e}")))?;
            crate::json::json_to_py(py, &json)
        }
        Err(e @ VerifyError::Option { .. }) => Err(PyValueError::new_err(e.to_string())),
        Err(VerifyError::Scene { error, .. }) => Err(crate::errors::scene(&error)),
        Err(e @ VerifyError::Start { .. }) => Err(PyRuntimeError::new_err(e.to_string())),
    }
}
