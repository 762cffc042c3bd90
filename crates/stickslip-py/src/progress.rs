//! The bridge between Rust work running detached from the interpreter and Python: signals
//! (Ctrl-C) and progress callbacks, at a bounded rate.
//!
//! A run or a sweep steps without the GIL. About every [`CALL_EVERY`] the [`Bridge`]
//! re-attaches: it runs Python's signal handlers (`Python::check_signals`, so SIGINT raises
//! KeyboardInterrupt there) and then calls the progress callback, if any, with a dict. An
//! exception from either sets the stop flag the driver reads before each step and is kept,
//! to be raised once the run has stopped with its output so far.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How often detached work re-attaches to Python (signals, progress): at most 10 times a
/// second, so neither costs the run anything measurable.
pub const CALL_EVERY: Duration = Duration::from_millis(100);

/// Signals and progress for one run or sweep (see the module docs).
pub struct Bridge {
    callback: Option<Py<PyAny>>,
    started: Instant,
    last: Instant,
    /// Fraction done and seconds elapsed at the first report (a resumed run starts
    /// part-way): the rate for the remaining time is measured from there.
    first: Option<(f64, f64)>,
    /// The exception a signal handler or the callback raised.
    pub error: Option<PyErr>,
}

/// What a report says; turned into the callback's dict.
pub enum Report<'a> {
    /// A run: time reached, end time, simulation steps, events, why it stopped (none yet).
    Run {
        /// Time reached, s.
        t_s: f64,
        /// `time.end`, s.
        end_s: f64,
        /// Simulation steps so far.
        steps: u64,
        /// Melting events so far.
        events: usize,
        /// Why the run stopped, once it has.
        stop: Option<&'a str>,
    },
    /// A fit: its stage, forward runs so far, of which failed, the least misfit so far.
    Fit {
        /// `global`, `noise`, `local`, `uncertainty` or `profile`.
        stage: &'a str,
        /// Forward runs so far.
        evaluations: usize,
        /// Of which failed.
        failed: usize,
        /// The least χ² so far (infinite before the first run).
        best_chi2: f64,
        /// The runs' `time.tolerance` (tightened as the fit nears its optimum; none with
        /// fixed steps).
        tolerance: Option<f64>,
        /// Runs of the present batch not ended yet, and their remaining wall time, s.
        batch: (usize, Option<f64>),
        /// Why the fit stopped, once it has.
        stop: Option<&'a str>,
    },
    /// A sweep: points done of those to run, points found finished, points failed.
    Sweep {
        /// Points run so far by this call.
        done: usize,
        /// Points this call runs (those found finished left out).
        total: usize,
        /// Points found finished (skipped).
        skipped: usize,
        /// Points failed or refused so far.
        failed: usize,
        /// Why the sweep stopped, once it has.
        stop: Option<&'a str>,
    },
}

impl Bridge {
    /// A bridge calling `callback` (a Python callable taking one dict), or none.
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        let now = Instant::now();
        Self {
            callback,
            started: now,
            last: now,
            first: None,
            error: None,
        }
    }

    /// From detached code: when [`CALL_EVERY`] has passed, re-attaches, checks signals and
    /// reports `report()`; an exception sets `stop`. Cheap otherwise (a clock read).
    pub fn tick<'a>(&mut self, stop: &AtomicBool, report: impl FnOnce() -> Report<'a>) {
        if self.error.is_some() || self.last.elapsed() < CALL_EVERY {
            return;
        }
        self.last = Instant::now();
        let result = Python::attach(|py| {
            py.check_signals()?;
            self.call(py, &report())
        });
        if let Err(e) = result {
            self.error = Some(e);
            stop.store(true, Ordering::Relaxed);
        }
    }

    /// The last report, with the GIL held, whatever the rate (a bar then shows where the work
    /// ended); nothing after an error.
    pub fn finish(&mut self, py: Python<'_>, report: &Report<'_>) {
        if self.error.is_none()
            && let Err(e) = self.call(py, report)
        {
            self.error = Some(e);
        }
    }

    /// Calls the callback with the dict of `report`.
    fn call(&mut self, py: Python<'_>, report: &Report<'_>) -> PyResult<()> {
        let Some(callback) = &self.callback else {
            return Ok(());
        };
        let elapsed_s = self.started.elapsed().as_secs_f64();
        let d = PyDict::new(py);
        let (fraction, stop) = match *report {
            Report::Run {
                t_s,
                end_s,
                steps,
                events,
                stop,
            } => {
                d.set_item("t_s", t_s)?;
                d.set_item("end_s", end_s)?;
                d.set_item("steps", steps)?;
                d.set_item("events", events)?;
                let f = if end_s > 0.0 {
                    (t_s / end_s).clamp(0.0, 1.0)
                } else {
                    1.0
                };
                (f, stop)
            }
            Report::Sweep {
                done,
                total,
                skipped,
                failed,
                stop,
            } => {
                d.set_item("done", done)?;
                d.set_item("total", total)?;
                d.set_item("skipped", skipped)?;
                d.set_item("failed", failed)?;
                let f = if total > 0 {
                    done as f64 / total as f64
                } else {
                    1.0
                };
                (f, stop)
            }
            Report::Fit {
                stage,
                evaluations,
                failed,
                best_chi2,
                tolerance,
                batch,
                stop,
            } => {
                d.set_item("stage", stage)?;
                d.set_item("evaluations", evaluations)?;
                d.set_item("failed_runs", failed)?;
                d.set_item("best_chi2", best_chi2)?;
                d.set_item("tolerance", tolerance)?;
                d.set_item("batch_left", batch.0)?;
                d.set_item("batch_eta_s", batch.1)?;
                // A fit's length is not known ahead: no fraction until it ends.
                (if stop.is_some() { 1.0 } else { 0.0 }, stop)
            }
        };
        let (f0, e0) = *self.first.get_or_insert((fraction, elapsed_s));
        // Remaining time at the rate since the first report.
        let eta_s = (fraction > f0 && stop.is_none())
            .then(|| (elapsed_s - e0) * (1.0 - fraction) / (fraction - f0));
        d.set_item("fraction", fraction)?;
        d.set_item("elapsed_s", elapsed_s)?;
        d.set_item("eta_s", if stop.is_some() { Some(0.0) } else { eta_s })?;
        d.set_item("stop", stop)?;
        callback.bind(py).call1((d,))?;
        Ok(())
    }
}
