//! `stickslip._native.cli`: the command line (the `stickslip` crate's library, the program of
//! the Rust binary) run in the interpreter's process, for the package's `stickslip` command
//! (`python/stickslip/_cli.py`, a console script).

use pyo3::prelude::*;
use std::ffi::OsString;
use std::path::PathBuf;

/// Runs ``stickslip ARGS...`` (``argv[0]`` is the program's name) as the Rust binary does and
/// returns its exit status; the GIL is released meanwhile. ``program``, when given, is the
/// command that starts the program again (``sweep slurm`` writes it into its job script).
/// Signals are the command line's own (SIGINT and SIGTERM write a checkpoint, status 130):
/// meant for the ``stickslip`` console script, which gives SIGINT back to the system's default
/// first (``stickslip._cli.main``), not for use inside a Python program.
#[pyfunction]
#[pyo3(signature = (argv, program = None))]
pub fn cli(py: Python<'_>, argv: Vec<OsString>, program: Option<PathBuf>) -> u8 {
    if let Some(p) = program {
        stickslip::set_program(p);
    }
    py.detach(move || {
        // A panic ends the program with Rust's status for one (101), its message printed by
        // the panic hook, as in the binary.
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| stickslip::main_from(argv)))
            .unwrap_or(101)
    })
}
