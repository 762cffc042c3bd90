//! `stickslip.boundary`: the run library's bisection of a regime change along one key, with
//! the GIL released and Ctrl-C seen between runs.

use crate::errors;
use crate::progress::{Bridge, Report};
use crate::scene::PyScene;
use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::AtomicBool;
use stickslip_run::boundary::{BoundaryError, Probe, find};
use stickslip_run::summary::RegimeThresholds;

fn probe_dict<'py>(py: Python<'py>, p: &Probe) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("value", p.value)?;
    d.set_item("regime", p.regime.name())?;
    Ok(d)
}

/// Brackets the regime change of ``scene`` along ``key`` between ``lo`` and ``hi`` and
/// bisects it to ``rtol``; returns ``{"value", "below", "above", "runs", "lo", "hi",
/// "probes"}`` (``below``/``above``: the regimes either side; ``lo``/``hi``: the final
/// bracket; ``probes``: every run as ``{"value", "regime"}``). Internal: use
/// ``stickslip.boundary``.
#[pyfunction]
#[pyo3(signature = (scene, key, lo, hi, rtol = 1e-3))]
pub fn boundary<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    key: &str,
    lo: f64,
    hi: f64,
    rtol: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = std::sync::Arc::clone(&scene.get().inner);
    let stop = AtomicBool::new(false);
    let mut bridge = Bridge::new(None);
    let mut runs = 0_usize;
    let result = py.detach(|| {
        let mut seen = |_: &Probe| {
            runs += 1;
            bridge.tick(&stop, || Report::Sweep {
                done: runs,
                total: 0,
                skipped: 0,
                failed: 0,
                stop: None,
            });
        };
        find(
            &scene,
            key,
            (lo, hi),
            rtol,
            RegimeThresholds::default(),
            Some(&stop),
            &mut seen,
        )
    });
    match result {
        Ok(b) => {
            let d = PyDict::new(py);
            d.set_item("key", &b.key)?;
            d.set_item("value", b.value)?;
            d.set_item("below", b.below.regime.name())?;
            d.set_item("above", b.above.regime.name())?;
            d.set_item("lo", b.below.value)?;
            d.set_item("hi", b.above.value)?;
            d.set_item("runs", b.runs)?;
            d.set_item("rtol", b.rtol)?;
            let probes = b
                .probes
                .iter()
                .map(|p| probe_dict(py, p))
                .collect::<PyResult<Vec<_>>>()?;
            d.set_item("probes", probes)?;
            Ok(d)
        }
        Err(BoundaryError::Interrupted { .. }) if bridge.error.is_some() => Err(bridge
            .error
            .take()
            .unwrap_or_else(|| PyKeyboardInterrupt::new_err(""))),
        Err(BoundaryError::Interrupted { runs, lo, hi }) => Err(PyKeyboardInterrupt::new_err(
            format!("interrupted after {runs} runs; the boundary lies between {lo} and {hi}"),
        )),
        Err(BoundaryError::Scene(e)) => Err(errors::scene(&e)),
        Err(BoundaryError::Start(e)) => Err(errors::start(&e)),
        Err(e @ BoundaryError::Failed { .. }) => {
            Err(pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))
        }
        Err(e) => Err(PyValueError::new_err(e.to_string())),
    }
}
