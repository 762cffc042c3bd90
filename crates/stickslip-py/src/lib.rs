//! stickslip-py: the Python bindings of stickslip (PyO3 + rust-numpy), built by maturin into
//! the `stickslip._native` extension module of the `stickslip` Python package
//! (`python/stickslip/`).
//!
//! A thin layer: scenes, runs and sweeps are the run library's (`stickslip-run`), the MDR
//! transforms the core's (`stickslip-core`); neither contains any Python. What lives here:
//! - [`scene`]: `Scene`, an immutable resolved scene (load, from a dict, overrides, to a dict
//!   or TOML, `check`);
//! - [`run`]: one run in memory or into an output directory (the command line's files and
//!   checkpoints), `resume` and `load` of a run directory; columns handed to NumPy without a
//!   copy;
//! - [`sweep`]: a friction map through the sweep executor, map.csv as arrays, and
//!   `load_sweep` of a sweep directory, complete or partial;
//! - [`progress`]: the GIL released while runs and sweeps work, taken back at most ten times
//!   a second for Ctrl-C and progress callbacks;
//! - [`boundary`]: the critical value of one key (the run library's bisection);
//! - [`keys`]: the scene-key registry as Python data;
//! - [`cli`]: the command line itself (the `stickslip` crate's library), for the package's
//!   `stickslip` command;
//! - [`verify`]: the error of every summary number of a scene;
//! - [`fit`]: scene parameters fitted to a measured trace (the studies crate's fit);
//! - [`mdr`]: the forward, back and compliance transforms on NumPy arrays, their inputs
//!   checked (shape, type, finite values, sizes whose operators would not fit);
//! - [`args`], [`convert`] and [`errors`]: arguments checked in the API's words, Python ⇄
//!   TOML/JSON values, errors as the package's exception classes (`stickslip._errors`) and
//!   the `OSError` family.
//!
//! The numbers are the command line's, bit for bit: both go through
//! `stickslip_run::driver::run`, only the sink differs (memory here, files there, the same
//! files with `out=`).

use pyo3::prelude::*;

pub mod args;
pub mod boundary;
pub mod cli;
pub mod convert;
pub mod errors;
pub mod fit;
pub mod json;
pub mod keys;
pub mod mdr;
pub mod progress;
pub mod run;
pub mod scene;
pub mod sweep;
pub mod verify;

/// The native part of the ``stickslip`` package; use ``stickslip`` itself.
#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(run::resume, m)?)?;
    m.add_function(wrap_pyfunction!(run::load, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(boundary::boundary, m)?)?;
    m.add_function(wrap_pyfunction!(keys::keys, m)?)?;
    m.add_function(wrap_pyfunction!(verify::verify, m)?)?;
    m.add_function(wrap_pyfunction!(verify::verify_target, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::load_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::forward, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::back, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::compliance, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::force, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::radii, m)?)?;
    m.add_function(wrap_pyfunction!(cli::cli, m)?)?;
    m.add_function(wrap_pyfunction!(option_defaults, m)?)?;
    Ok(())
}

/// The defaults of the commands' options as ``{"command.option": value}``: the command line's
/// and the Python functions' (one definition, the run library's ``options``).
#[pyfunction]
fn option_defaults(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    use stickslip_studies::options::OptionDefault;
    let out = pyo3::types::PyDict::new(py);
    for (name, value) in stickslip_studies::options::all() {
        match value {
            OptionDefault::Count(n) => out.set_item(name, n)?,
            OptionDefault::Number(x) => out.set_item(name, x)?,
            OptionDefault::Word(w) => out.set_item(name, w)?,
        }
    }
    Ok(out)
}
