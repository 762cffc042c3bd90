//! `stickslip.boundary`: the run library's scan and bisection of every regime change along one
//! key, with the GIL released and Ctrl-C seen while runs go on.

use crate::errors;
use crate::progress::{Bridge, Report};
use crate::scene::PyScene;
use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;
use stickslip_run::summary::RegimeThresholds;
use stickslip_studies::boundary::scan::{Change, ScanOptions, scan as scan_key};
use stickslip_studies::boundary::{BoundaryError, Probe};
use stickslip_studies::options;

fn probe_dict<'py>(py: Python<'py>, p: &Probe) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("value", p.value)?;
    d.set_item("regime", p.regime.name())?;
    d.set_item("stage", p.stage.name())?;
    Ok(d)
}

fn change_dict<'py>(py: Python<'py>, c: &Change) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("value", c.value)?;
    d.set_item("below", c.below.regime.name())?;
    d.set_item("above", c.above.regime.name())?;
    d.set_item("lo", c.below.value)?;
    d.set_item("hi", c.above.value)?;
    d.set_item("error", c.error)?;
    d.set_item("bracket", c.bracket)?;
    let shifts = PyDict::new(py);
    for s in &c.shifts {
        shifts.set_item(s.stage.name(), s.moved)?;
    }
    d.set_item("moves", shifts)?;
    d.set_item("third", c.third.map(|r| r.name()))?;
    d.set_item("runs", c.runs)?;
    Ok(d)
}

/// Scans ``scene`` along ``key`` from ``lo`` to ``hi`` (``scan`` points), bisects every
/// change to ``rtol`` and gives each an error; returns the first change's ``{"value",
/// "below", "above", "lo", "hi", "error"}`` with ``"changes"`` (each change so), ``"runs"``,
/// ``"probes"`` (every run as ``{"value", "regime", "stage"}``), ``"scan"`` (the scan's
/// points) and ``"warnings"``. Internal: use ``stickslip.boundary``.
#[pyfunction]
#[pyo3(signature = (scene, key, lo, hi, rtol = options::BOUNDARY_RTOL, scan = options::BOUNDARY_SCAN, jobs = options::JOBS, scale = options::BOUNDARY_SCALE))]
#[allow(clippy::too_many_arguments)]
pub fn boundary<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    key: &str,
    lo: f64,
    hi: f64,
    rtol: f64,
    scan: usize,
    jobs: usize,
    scale: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let scale = stickslip_studies::boundary::Scale::from_name(scale).ok_or_else(|| {
        pyo3::exceptions::PyValueError::new_err(format!(
            "scale = {scale:?} is invalid; allowed: \"film\" or \"stamp\""
        ))
    })?;
    let scene = std::sync::Arc::clone(&scene.get().inner);
    let stop = AtomicBool::new(false);
    let mut bridge = Bridge::new(None);
    let probes: Mutex<Vec<Probe>> = Mutex::new(Vec::new());
    let result = py.detach(|| {
        let seen = |p: &Probe| {
            if let Ok(mut v) = probes.lock() {
                v.push(*p);
            }
        };
        let mut tick = || {
            let done = probes.lock().map_or(0, |v| v.len());
            bridge.tick(&stop, || Report::Sweep {
                done,
                total: 0,
                skipped: 0,
                failed: 0,
                stop: None,
            });
        };
        scan_key(
            &scene,
            key,
            (lo, hi),
            rtol,
            ScanOptions {
                points: scan,
                jobs,
                scale,
                cache: None,
            },
            RegimeThresholds::default(),
            Some(&stop),
            &seen,
            &mut tick,
        )
    });
    match result {
        Ok(s) => {
            let d = change_dict(py, &s.changes[0])?;
            d.set_item("key", &s.key)?;
            d.set_item("runs", s.runs)?;
            d.set_item("rtol", s.rtol)?;
            let changes = s
                .changes
                .iter()
                .map(|c| change_dict(py, c))
                .collect::<PyResult<Vec<_>>>()?;
            d.set_item("changes", changes)?;
            let all = probes.into_inner().unwrap_or_default();
            let list = all
                .iter()
                .map(|p| probe_dict(py, p))
                .collect::<PyResult<Vec<_>>>()?;
            d.set_item("probes", list)?;
            let points = s
                .points
                .iter()
                .map(|p| probe_dict(py, p))
                .collect::<PyResult<Vec<_>>>()?;
            d.set_item("scan", points)?;
            let undecided = s
                .undecided
                .iter()
                .map(|u| {
                    let e = PyDict::new(py);
                    e.set_item("below", probe_dict(py, &u.below)?)?;
                    e.set_item("above", probe_dict(py, &u.above)?)?;
                    e.set_item("undecided", &u.undecided)?;
                    Ok(e)
                })
                .collect::<PyResult<Vec<_>>>()?;
            d.set_item("undecided", undecided)?;
            d.set_item("warnings", &s.warnings)?;
            Ok(d)
        }
        Err(BoundaryError::Interrupted { .. }) if bridge.error.is_some() => Err(bridge
            .error
            .take()
            .unwrap_or_else(|| PyKeyboardInterrupt::new_err(""))),
        Err(e @ BoundaryError::ScanInterrupted { .. }) => {
            Err(PyKeyboardInterrupt::new_err(e.to_string()))
        }
        Err(BoundaryError::Interrupted { runs, lo, hi }) => {
            Err(PyKeyboardInterrupt::new_err(format!(
                "interrupted after {runs} runs; the boundary lies between {} and {}",
                stickslip_run::keys::human(lo),
                stickslip_run::keys::human(hi)
            )))
        }
        Err(BoundaryError::Scene(e)) => Err(errors::scene(&e)),
        Err(BoundaryError::Start(e)) => Err(errors::start(&e)),
        Err(e @ BoundaryError::Failed { .. }) => {
            Err(pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))
        }
        Err(e) => Err(PyValueError::new_err(e.to_string())),
    }
}
