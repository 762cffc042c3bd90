//! `stickslip._native.run`, `resume` and `load`: one run in memory or in an output directory
//! (the command line's files and checkpoints), the GIL released, Ctrl-C and progress through
//! the [`Bridge`]; a run directory read back in any state.

use crate::args;
use crate::errors;
use crate::progress::{Bridge, Report};
use crate::scene::PyScene;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyNotADirectoryError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use stickslip_core::sim::Simulation;
use stickslip_run::checkpoint::CheckpointError;
use stickslip_run::driver::Control;
use stickslip_run::schema::RunOutput;
use stickslip_run::sink::read::{ReadError, read_run};
use stickslip_run::{DirOptions, ResumeOptions, RunError, RunOutcome};

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

/// A run's output as the dict the Python layer wraps in a `RunResult`: the tables, `summary`,
/// `run_info` (the rest of run.json), `stop` (run.json's, or `None` while running).
fn output_dict(py: Python<'_>, output: RunOutput) -> PyResult<Bound<'_, PyDict>> {
    let RunOutput {
        series,
        events,
        slips,
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
    let sl = PyDict::new(py);
    for (name, col) in slips.columns() {
        if matches!(name, "k" | "meltings") {
            let counts: Vec<i64> = col.iter().map(|&v| v as i64).collect();
            sl.set_item(name, PyArray1::from_vec(py, counts))?;
        } else {
            sl.set_item(name, col.into_pyarray(py))?;
        }
    }
    d.set_item("slips", sl)?;
    d.set_item("profiles", columns(py, profiles.into_columns())?)?;
    d.set_item("probes", columns(py, probes.into_columns())?)?;
    d.set_item("stop", info.stop.clone())?;
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
    Ok(d)
}

/// Where a run's output goes.
enum Target {
    /// Memory.
    Memory(std::sync::Arc<stickslip_run::ResolvedScene>),
    /// A new run into a directory.
    Dir {
        scene: std::sync::Arc<stickslip_run::ResolvedScene>,
        dir: PathBuf,
        options: DirOptions,
    },
    /// The interrupted run in a directory, resumed.
    Resume {
        dir: PathBuf,
        options: ResumeOptions,
    },
}

/// Why a run gave no output.
enum Failed {
    Start(stickslip_run::driver::StartError),
    Run(RunError),
    Read(ReadError),
}

/// Runs `target` (detached from Python), reporting to `bridge`; the outcome (none for an
/// ended run resumed) and the output read back.
fn execute(
    target: &Target,
    bridge: &mut Bridge,
    stop: &AtomicBool,
) -> Result<(Option<RunOutcome>, RunOutput), Failed> {
    let mut observer = |sim: &Simulation| {
        bridge.tick(stop, || Report::Run {
            t_s: sim.time_s(),
            end_s: sim.config().time.end_s,
            steps: sim.state().counters.step,
            events: sim.events().len(),
            stop: None,
        });
    };
    // The driver reads `interrupt` before every step and calls the observer after every step
    // (a clock read; Python only every 0.1 s), so a run stops within about 0.1 s plus one
    // step whatever its stepping.
    let mut control = Control {
        interrupt: Some(stop),
        observer: Some(&mut observer),
        ..Control::default()
    };
    let read = |dir: &Path| read_run(dir).map(|r| r.output).map_err(Failed::Read);
    match target {
        Target::Memory(scene) => stickslip_run::run_in_memory(scene, &mut control)
            .map(|(outcome, output)| (Some(outcome), output))
            .map_err(Failed::Start),
        Target::Dir {
            scene,
            dir,
            options,
        } => {
            let outcome = stickslip_run::run_to_dir(scene, dir, options, &mut control)
                .map_err(Failed::Run)?;
            Ok((Some(outcome), read(dir)?))
        }
        Target::Resume { dir, options } => {
            match stickslip_run::resume(dir, options, &mut control) {
                Ok((_, outcome)) => Ok((Some(outcome), read(dir)?)),
                // Nothing to resume: the run has ended; its output as it is.
                Err(RunError::Checkpoint(CheckpointError::Finished { .. })) => {
                    Ok((None, read(dir)?))
                }
                Err(e) => Err(Failed::Run(e)),
            }
        }
    }
}

/// Runs `target` with the GIL released and returns the output dict, with `error`: the
/// exception a signal handler or the progress callback raised (the run stopped there), or
/// None.
fn drive<'py>(
    py: Python<'py>,
    target: &Target,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut bridge = Bridge::new(args::callback(progress)?);
    let stop = AtomicBool::new(false);
    let result = py.detach(|| execute(target, &mut bridge, &stop));
    let (outcome, output) = match result {
        Ok(r) => r,
        Err(Failed::Start(e)) => return Err(errors::start(&e)),
        Err(Failed::Run(e)) => return Err(errors::run(&e)),
        Err(Failed::Read(e)) => return Err(errors::read(&e)),
    };
    if let Some(o) = &outcome {
        bridge.finish(
            py,
            &Report::Run {
                t_s: o.t_final_s,
                end_s: output.info.end_s(),
                steps: o.counts.steps,
                events: o.events.len(),
                stop: Some(o.stop.name()),
            },
        );
    }
    let d = output_dict(py, output)?;
    d.set_item("error", bridge.error.take().map(|e| e.into_value(py)))?;
    d.set_item("resumed", outcome.is_some())?;
    Ok(d)
}

/// Runs ``scene`` in memory, or into the directory ``out`` as ``stickslip run --out`` does,
/// and returns its output as a dict (``series``, ``events``, ``profiles``, ``probes``: dicts
/// of NumPy arrays named as the CSV columns; ``summary``; ``run_info``: the rest of run.json;
/// ``stop``; ``error``: the exception that stopped the run, or None). Internal: use
/// ``stickslip.run``, which wraps it in a ``RunResult`` and raises.
///
/// The GIL is released while the run steps; about every 0.1 s it is taken back to run the
/// signal handlers (Ctrl-C) and ``progress(dict)``.
#[pyfunction]
#[pyo3(signature = (scene, *, progress = None, out = None, force = None, checkpoint_every = None))]
pub fn run<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    progress: Option<&Bound<'py, PyAny>>,
    out: Option<&Bound<'py, PyAny>>,
    force: Option<&Bound<'py, PyAny>>,
    checkpoint_every: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = std::sync::Arc::clone(&scene.get().inner);
    let force = args::flag(force, "force", false)?;
    let every = args::seconds(checkpoint_every, "checkpoint_every")?;
    let target = match args::path(out, "out")? {
        None => Target::Memory(scene),
        Some(dir) => Target::Dir {
            scene,
            dir,
            options: DirOptions {
                force,
                checkpoint_every_s: every
                    .unwrap_or(stickslip_run::sink::dir::DEFAULT_CHECKPOINT_EVERY_S),
            },
        },
    };
    drive(py, &target, progress)
}

/// Finishes the interrupted run in ``dir`` as ``stickslip resume DIR`` does and returns its
/// output as ``run`` does (``resumed`` False when the run had already ended); a checkpoint of
/// another build only with ``allow_other_build``. Internal: use ``stickslip.resume``.
#[pyfunction]
#[pyo3(signature = (dir, *, progress = None, checkpoint_every = None, allow_other_build = None))]
pub fn resume<'py>(
    py: Python<'py>,
    dir: &Bound<'py, PyAny>,
    progress: Option<&Bound<'py, PyAny>>,
    checkpoint_every: Option<&Bound<'py, PyAny>>,
    allow_other_build: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let dir = args::required_path(dir, "dir")?;
    if dir.exists() && !dir.is_dir() {
        return Err(PyNotADirectoryError::new_err(format!(
            "{} is not a directory; allowed: the output directory of an interrupted run",
            dir.display()
        )));
    }
    let target = Target::Resume {
        dir,
        options: ResumeOptions {
            checkpoint_every_s: args::seconds(checkpoint_every, "checkpoint_every")?,
            allow_other_build: args::flag(allow_other_build, "allow_other_build", false)?,
        },
    };
    drive(py, &target, progress)
}

/// Reads the run in ``dir`` (ended, interrupted or killed) as the dict ``run`` returns.
/// Internal: use ``stickslip.load``.
#[pyfunction]
pub fn load<'py>(py: Python<'py>, dir: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let dir = args::required_path(dir, "dir")?;
    let read = py.detach(|| read_run(&dir)).map_err(|e| errors::read(&e))?;
    let d = output_dict(py, read.output)?;
    d.set_item("error", py.None())?;
    d.set_item("resumed", false)?;
    Ok(d)
}
