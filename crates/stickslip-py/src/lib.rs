//! stickslip-py: the Python bindings of stickslip (PyO3 + rust-numpy), built by maturin into
//! the `stickslip._native` extension module of the `stickslip` Python package
//! (`python/stickslip/`).
//!
//! A thin layer: scenes, runs and sweeps are the run library's (`stickslip-run`), the MDR
//! transforms the core's (`stickslip-core`); neither contains any Python. What lives here:
//! - [`scene`]: `Scene`, an immutable resolved scene (load, from a dict, overrides, to a dict
//!   or TOML);
//! - [`run`]: one run in memory with the GIL released and Ctrl-C honoured, its columns handed
//!   to NumPy without a copy;
//! - [`sweep`]: a friction map through the sweep executor, map.csv as arrays;
//! - [`mdr`]: the forward, back and compliance transforms on NumPy arrays;
//! - [`convert`] and [`errors`]: Python ⇄ TOML/JSON values, errors as the package's
//!   exception classes (`stickslip._errors`).
//!
//! The numbers are the command line's, bit for bit: both go through
//! `stickslip_run::driver::run`, only the sink differs (memory here, files there).

use pyo3::prelude::*;

pub mod convert;
pub mod errors;
pub mod mdr;
pub mod run;
pub mod scene;
pub mod sweep;

/// The native part of the ``stickslip`` package; use ``stickslip`` itself.
#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::forward, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::back, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::compliance, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::force, m)?)?;
    m.add_function(wrap_pyfunction!(mdr::radii, m)?)?;
    Ok(())
}
