//! Rust errors as Python exceptions: the classes of `stickslip._errors` (`SceneError`,
//! `SweepError`; `NumericalFailure` and `Interrupted` are raised by the Python layer, which
//! attaches the partial result) and the built-in `OSError` family for directories and files.

use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyNotADirectoryError, PyOSError, PyPermissionError,
    PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use stickslip_run::SceneError;
use stickslip_studies::sweep::SweepError;

/// An instance of `stickslip._errors.<class>(message, **kwargs)` as a `PyErr`.
fn make(class: &str, message: String, kwargs: &[(&str, serde_json::Value)]) -> PyErr {
    Python::attach(|py| {
        let build = || -> PyResult<PyErr> {
            let cls = py.import("stickslip._errors")?.getattr(class)?;
            let kw = PyDict::new(py);
            for (k, v) in kwargs {
                kw.set_item(k, crate::json::json_to_py(py, v)?)?;
            }
            let value = cls.call((message.clone(),), Some(&kw))?;
            Ok(PyErr::from_value(value))
        };
        build().unwrap_or_else(|e| e)
    })
}

/// Key, value and allowed range of a scene error, where it has them.
fn parts(e: &SceneError) -> [(&'static str, serde_json::Value); 3] {
    let (value, allowed) = match e {
        SceneError::UnknownKey { value, allowed, .. }
        | SceneError::WrongType { value, allowed, .. }
        | SceneError::Invalid { value, allowed, .. }
        | SceneError::Contradictory { value, allowed, .. } => {
            (Some(value.clone()), Some(allowed.clone()))
        }
        SceneError::MissingKey { allowed, .. } => (None, Some(allowed.clone())),
        SceneError::Override { arg, .. } => (Some(arg.clone()), None),
        SceneError::Unset { key, .. } => (Some(key.clone()), None),
        SceneError::Read { .. } | SceneError::Syntax { .. } => (None, None),
    };
    [
        ("key", e.key().into()),
        ("value", value.into()),
        ("allowed", allowed.into()),
    ]
}

/// `stickslip.SceneError` for a bad scene.
pub fn scene(e: &SceneError) -> PyErr {
    make("SceneError", e.to_string(), &parts(e))
}

/// `stickslip.SweepError` for a bad sweep.
pub fn sweep(e: &SweepError) -> PyErr {
    let (value, allowed) = match e {
        SweepError::Invalid { value, allowed, .. } => {
            (value.as_str().into(), allowed.as_str().into())
        }
        SweepError::Point { error, .. } | SweepError::Base { error, .. } => {
            let [_, (_, v), (_, a)] = parts(error);
            (v, a)
        }
        SweepError::Read { .. } => (serde_json::Value::Null, serde_json::Value::Null),
    };
    let point = match e {
        SweepError::Point { point, .. } => (*point).into(),
        _ => serde_json::Value::Null,
    };
    make(
        "SweepError",
        e.to_string(),
        &[
            ("key", e.key().into()),
            ("value", value),
            ("allowed", allowed),
            ("point", point),
            ("line", e.line().into()),
        ],
    )
}

/// A run that could not start.
pub fn start(e: &stickslip_run::driver::StartError) -> PyErr {
    use stickslip_run::driver::StartError;
    match e {
        StartError::Config(c) => scene(&SceneError::from(c.clone())),
        StartError::Io(io) => PyOSError::new_err(io.to_string()),
        StartError::State(_) | StartError::NeverBegan => PyRuntimeError::new_err(e.to_string()),
    }
}

/// An `OSError` of the subclass that fits `kind` (`FileNotFoundError`, `PermissionError`,
/// `FileExistsError`), with `message`.
pub fn os(kind: std::io::ErrorKind, message: String) -> PyErr {
    use std::io::ErrorKind;
    match kind {
        ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
        ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
        ErrorKind::AlreadyExists => PyFileExistsError::new_err(message),
        _ => PyOSError::new_err(message),
    }
}

/// A run into a directory (or its resume) that did not happen: `SceneError` for the scene,
/// `FileExistsError` for an earlier run's directory, `FileNotFoundError` for nothing to
/// resume, `ValueError` for a checkpoint that cannot be resumed (damaged, of an older format,
/// or of another build without `allow_other_build=True`), `OSError` for the rest.
pub fn run(e: &stickslip_run::RunError) -> PyErr {
    use stickslip_run::RunError;
    use stickslip_run::checkpoint::CheckpointError;
    let text = || {
        e.to_string()
            .replace("--force", "force=True")
            .replace("--allow-other-build", "allow_other_build=True")
    };
    match e {
        RunError::Config(c) => scene(&SceneError::from(c.clone())),
        RunError::Existing { dir, files } => PyFileExistsError::new_err(format!(
            "{dir} holds the results of an earlier run ({files}); allowed: an empty or new \
             directory, force=True to replace them, or stickslip.resume('{dir}') to finish an \
             interrupted run"
        )),
        RunError::OutDir { source, .. } | RunError::Io { source, .. } => os(source.kind(), text()),
        RunError::Busy { .. } => PyRuntimeError::new_err(text()),
        RunError::Foreign { .. } => PyFileExistsError::new_err(text()),
        RunError::Checkpoint(CheckpointError::Missing { .. }) => {
            PyFileNotFoundError::new_err(text())
        }
        RunError::Checkpoint(
            CheckpointError::Corrupt { .. }
            | CheckpointError::Format { .. }
            | CheckpointError::OtherBuild { .. },
        ) => PyValueError::new_err(text()),
        RunError::Checkpoint(CheckpointError::Finished { .. }) => PyRuntimeError::new_err(text()),
    }
}

/// A run directory that cannot be read: `FileNotFoundError` when there is no run,
/// `ValueError` for a file that does not parse.
pub fn read(e: &stickslip_run::sink::read::ReadError) -> PyErr {
    use stickslip_run::sink::read::ReadError;
    match e {
        ReadError::Missing { dir, .. } if dir.exists() && !dir.is_dir() => {
            PyNotADirectoryError::new_err(e.to_string())
        }
        ReadError::Missing { .. } => PyFileNotFoundError::new_err(e.to_string()),
        ReadError::Schema(_) => PyValueError::new_err(e.to_string()),
    }
}
