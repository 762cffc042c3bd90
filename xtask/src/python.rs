//! `cargo xtask python-test`: the Python package's tests in a virtual environment of their own.
//!
//! 1. creates `target/python-venv` with `python3 -m venv` (reused when present; `--fresh`
//!    recreates it) and installs maturin, numpy, pytest, pandas and matplotlib into it once;
//! 2. builds the release `stickslip` binary (the tests compare the package's numbers with it,
//!    found through `STICKSLIP_BIN`);
//! 3. `pip install ./crates/stickslip-py`: maturin builds the extension into the workspace's
//!    `target/` (release profile), so Rust dependencies already built there are reused
//!    (`--no-build-isolation` with the venv's maturin: no download per install);
//! 4. runs pytest on `crates/stickslip-py/tests` (arguments after `--` are passed on).
//!
//! Prints the time of each stage; exits non-zero when a stage or a test fails. The Python
//! interpreter is `$STICKSLIP_PYTHON`, else `python3` (3.9 or newer).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

const USAGE: &str = "\
cargo xtask python-test [--fresh] [-- PYTEST_ARGS...]

  --fresh   recreate the virtual environment target/python-venv
  PYTEST_ARGS are passed to pytest (e.g. -- -k mdr -x)
Environment: STICKSLIP_PYTHON (the interpreter for the venv, default python3).";

/// Test dependencies installed into the venv once (scipy runs the independent implementation
/// of validation/independent; pandas and matplotlib exercise
/// `RunResult.to_pandas` and the example's plots, tqdm the progress bar, nbclient and
/// ipykernel execute the notebooks of examples/). A venv made with another list is brought
/// up to this one.
const TEST_DEPS: [&str; 9] = [
    "maturin>=1.5,<2",
    "numpy",
    "scipy",
    "pytest",
    "pandas",
    "matplotlib",
    "tqdm",
    "nbclient",
    "ipykernel",
];

fn status(what: &str, cmd: &mut Command) -> Result<(), String> {
    match cmd.status() {
        Ok(s) if s.success() => Ok(()),
        Ok(s) => Err(format!("{what} failed ({s})")),
        Err(e) => Err(format!("{what}: cannot start {:?}: {e}", cmd.get_program())),
    }
}

/// The venv's interpreter, after creating the venv and its test dependencies if needed.
pub(crate) fn venv(root: &Path, fresh: bool) -> Result<(PathBuf, &'static str), String> {
    let dir = root.join("target").join("python-venv");
    let python = dir.join("bin").join("python");
    if fresh && dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(|e| format!("removing {}: {e}", dir.display()))?;
    }
    let ready = dir.join(".stickslip-test-deps");
    let listed = std::fs::read_to_string(&ready).unwrap_or_default();
    if python.is_file() && listed == TEST_DEPS.join("\n") {
        return Ok((python, "reused"));
    }
    let base = std::env::var("STICKSLIP_PYTHON").unwrap_or_else(|_| "python3".to_string());
    status(
        "the Python version check (3.9 or newer needed)",
        Command::new(&base).args([
            "-c",
            "import sys; sys.exit(0 if sys.version_info >= (3, 9) else 1)",
        ]),
    )?;
    if !python.is_file() {
        status(
            "creating the virtual environment",
            Command::new(&base).args(["-m", "venv"]).arg(&dir),
        )?;
    }
    status(
        "installing the test dependencies",
        Command::new(&python)
            .args(["-m", "pip", "install", "-q", "--disable-pip-version-check"])
            .args(TEST_DEPS),
    )?;
    std::fs::write(&ready, TEST_DEPS.join("\n"))
        .map_err(|e| format!("writing {}: {e}", ready.display()))?;
    Ok((python, "created"))
}

/// `PATH` with the venv's `bin` first (maturin is called by name under
/// `--no-build-isolation`).
fn path_with(bin: &Path) -> std::ffi::OsString {
    let mut paths = vec![bin.to_path_buf()];
    if let Some(old) = std::env::var_os("PATH") {
        paths.extend(std::env::split_paths(&old));
    }
    std::env::join_paths(paths).unwrap_or_default()
}

/// Creates the venv and its test dependencies if needed (downloads and unpacking: little CPU,
/// so `cargo xtask test` does it while the Rust tests compile).
///
/// # Errors
/// No suitable Python, or pip failed.
pub fn prepare_venv(root: &Path) -> Result<(), String> {
    venv(root, false).map(|_| ())
}

/// Runs the stages; the first error ends it.
pub fn stages(root: &Path, fresh: bool, pytest_args: &[String]) -> Result<(), String> {
    let mut times: Vec<(String, f64)> = Vec::new();
    let t = Instant::now();
    let (python, how) = venv(root, fresh)?;
    times.push((format!("venv ({how})"), t.elapsed().as_secs_f64()));
    let bin_dir = python.parent().unwrap_or(Path::new(".")).to_path_buf();

    let t = Instant::now();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    status(
        "building the release stickslip binary",
        Command::new(&cargo).current_dir(root).args([
            "build",
            "--release",
            "-q",
            "-p",
            "stickslip",
        ]),
    )?;
    times.push(("stickslip binary".into(), t.elapsed().as_secs_f64()));

    let t = Instant::now();
    eprintln!("python-test: pip install ./crates/stickslip-py (maturin, release profile)");
    status(
        "pip install ./crates/stickslip-py",
        Command::new(&python)
            .current_dir(root)
            .env("PATH", path_with(&bin_dir))
            .args([
                "-m",
                "pip",
                "install",
                "--disable-pip-version-check",
                "--no-build-isolation",
                "--force-reinstall",
                "--no-deps",
                "./crates/stickslip-py",
            ]),
    )?;
    times.push(("install".into(), t.elapsed().as_secs_f64()));

    let t = Instant::now();
    let tests = status(
        "pytest",
        Command::new(&python)
            .current_dir(root.join("crates").join("stickslip-py"))
            .env(
                "STICKSLIP_BIN",
                root.join("target").join("release").join("stickslip"),
            )
            .env("PATH", path_with(&bin_dir))
            .args(["-m", "pytest", "tests"])
            .args(pytest_args),
    );
    times.push(("tests".into(), t.elapsed().as_secs_f64()));
    let line: Vec<String> = times
        .iter()
        .map(|(what, s)| format!("{what} {s:.1} s"))
        .collect();
    eprintln!("python-test: {}", line.join(", "));
    tests
}

/// `cargo xtask python-test [--fresh] [-- PYTEST_ARGS...]`.
pub fn main(args: &[String], root: PathBuf) -> ExitCode {
    let mut fresh = false;
    let mut pytest_args = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--fresh" => fresh = true,
            "--" => pytest_args.extend(it.by_ref().cloned()),
            "-h" | "--help" => {
                println!("{USAGE}");
                return ExitCode::SUCCESS;
            }
            other => {
                eprintln!("unknown option `{other}` for python-test\n\n{USAGE}");
                return ExitCode::from(2);
            }
        }
    }
    match stages(&root, fresh, &pytest_args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("python-test: {e}");
            ExitCode::FAILURE
        }
    }
}
