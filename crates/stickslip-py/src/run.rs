//! `stickslip._native.run`: one run in memory, the GIL released, Ctrl-C honoured.

use crate::errors;
use crate::scene::PyScene;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use stickslip_run::driver::Control;
use stickslip_run::schema::RunOutput;

/// How often a run (or a sweep) re-attaches to Python to let it handle signals.
pub const SIGNAL_CHECK_EVERY: Duration = Duration::from_millis(100);

/// Watches Python's signals from a thread that runs Rust code detached from the interpreter:
/// [`SignalWatch::check`] re-attaches about every [`SIGNAL_CHECK_EVERY`] and runs
/// `Python::check_signals` (the Python-level handlers, e.g. SIGINT's KeyboardInterrupt); an
/// exception from a handler sets the stop flag and is kept to be raised later.
pub struct SignalWatch {
    last: Instant,
    /// The exception a handler raised.
    pub error: Option<PyErr>,
}

impl Default for SignalWatch {
    fn default() -> Self {
        Self::new()
    }
}

impl SignalWatch {
    /// A watch that checks first after [`SIGNAL_CHECK_EVERY`].
    pub fn new() -> Self {
        Self {
            last: Instant::now(),
            error: None,
        }
    }

    /// Checks Python's signals if [`SIGNAL_CHECK_EVERY`] has passed; sets `stop` once a
    /// handler has raised.
    pub fn check(&mut self, stop: &AtomicBool) {
        if self.error.is_none() && self.last.elapsed() >= SIGNAL_CHECK_EVERY {
            self.last = Instant::now();
            if let Err(e) = Python::attach(|py| py.check_signals()) {
                self.error = Some(e);
                stop.store(true, Ordering::Relaxed);
            }
        }
    }
}

/// Columns as a dict of NumPy arrays, each Vec handed over without a copy.
fn columns<'py, S: AsRef<str>>(
    py: Python<'py>,
    cols: Vec<(S, Vec<f64>)>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, col) in cols {
        d.set_item(name.as_ref(), col.into_pyarray(py))?;
    }
    Ok(d)
}

/// The run's output as the dict the Python layer wraps in a `RunResult`.
fn output_dict<'py>(
    py: Python<'py>,
    stop: &str,
    output: RunOutput,
) -> PyResult<Bound<'py, PyDict>> {
    let RunOutput {
        series,
        events,
        profiles,
        probes,
        info,
    } = output;
    let d = PyDict::new(py);
    d.set_item("series", columns(py, series.into_columns())?)?;
    let ev = PyDict::new(py);
    let k: Vec<i64> = events
        .events()
        .iter()
        .map(|e| i64::try_from(e.k).unwrap_or(i64::MAX))
        .collect();
    ev.set_item("k", PyArray1::from_vec(py, k))?;
    for (name, col) in events.columns().into_iter().skip(1) {
        ev.set_item(name, col.into_pyarray(py))?;
    }
    d.set_item("events", ev)?;
    d.set_item("profiles", columns(py, profiles.into_columns())?)?;
    d.set_item("probes", columns(py, probes.into_columns())?)?;
    // run.json's text through Python's json module: the keys keep run.json's order and every
    // number its bits (shortest round-trip text both ways).
    let info = py
        .import("json")?
        .call_method1("loads", (info.to_json(),))?
        .cast_into::<PyDict>()?;
    let summary = info.get_item("summary")?;
    info.del_item("summary")?;
    d.set_item("summary", summary)?;
    d.set_item("run_info", info)?;
    d.set_item("stop", stop)?;
    Ok(d)
}

/// Runs ``scene`` in memory and returns its output as a dict (``series``, ``events``,
/// ``profiles``, ``probes``: dicts of NumPy arrays named as the CSV columns; ``summary``;
/// ``run_info``: the rest of run.json; ``stop``). Internal: use ``stickslip.run``, which
/// wraps it in a ``RunResult`` and raises ``NumericalFailure``.
///
/// The GIL is released while the run steps; Ctrl-C (any exception raised by a signal
/// handler) stops it within about 0.1 s and is raised here.
#[pyfunction]
pub fn run<'py>(py: Python<'py>, scene: &Bound<'py, PyScene>) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.get().inner.clone();
    let mut watch = SignalWatch::new();
    let stop = AtomicBool::new(false);
    let result = py.detach(|| {
        // The driver reads `interrupt` before every step and calls the observer after every
        // step (a clock read; Python only every 0.1 s), so a run stops within about 0.1 s plus
        // one step whatever its stepping (`Control::poll` comes only every 1024 fixed steps).
        let mut observer = |_: &stickslip_core::sim::Simulation| watch.check(&stop);
        let mut control = Control {
            interrupt: Some(&stop),
            observer: Some(&mut observer),
            ..Control::default()
        };
        stickslip_run::run_in_memory(&scene, &mut control)
    });
    if let Some(e) = watch.error.take() {
        return Err(e);
    }
    let (outcome, output) = result.map_err(|e| errors::start(&e))?;
    output_dict(py, outcome.stop.name(), output)
}
