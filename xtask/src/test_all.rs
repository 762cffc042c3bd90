//! `cargo xtask test`: every test of the project, the command CI runs (`.ci/run`).
//!
//! Stages, each timed and all run even when one fails (the summary names every failure):
//! 1. **rust build**: `cargo test --release --workspace --exclude stickslip-benches --no-run`,
//!    in the release profile that `cargo xtask validate` has already built, so after the main
//!    job only the test targets compile (the criterion benches are `cargo xtask bench`'s and
//!    clippy's business, not the test command's);
//! 2. **rust tests**: the same command running the tests;
//! 3. **python**: `cargo xtask python-test` (venv, `pip install ./crates/stickslip-py`, pytest);
//!    the venv and its test dependencies are prepared in a thread from the start, overlapping
//!    the Rust build (pip's downloads and unpacking barely compete with the compiler);
//! 4. **wheel**: `cargo xtask wheel --check` (the abi3 wheel into dist/, installed into a
//!    fresh venv without cargo on PATH, running the README's example);
//! 5. **slurm**: `cargo xtask slurm-check` (a one-node Slurm runs a sweep as a job array).
//!
//! Exits 0 when every stage passed, 1 otherwise.

use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::Instant;
use stickslip_report::build_timing::{STAGE_TIMES_ENV, StageTime, StageTimes};

const USAGE: &str = "\
cargo xtask test [--no-python] [--no-slurm]

  every test: Rust (cargo test --release --workspace), Python (python-test), Slurm (slurm-check)
  --no-python   skip the Python package's tests
  --no-slurm    skip the Slurm check";

/// The cargo arguments of the Rust stages (before `--no-run`).
const CARGO_TEST: [&str; 5] = [
    "test",
    "--release",
    "--workspace",
    "--exclude",
    "stickslip-benches",
];

fn cargo(root: &Path, extra: &[&str]) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let mut cmd = Command::new(&cargo);
    // A snapshot that differs fails, and nothing is written beside it: a change in the work a
    // run does (the step counters' snapshots) is accepted only by committing the new snapshot.
    cmd.current_dir(root)
        .args(CARGO_TEST)
        .args(extra)
        .env("INSTA_UPDATE", "no");
    match cmd.status() {
        Ok(s) if s.success() => Ok(()),
        Ok(s) => Err(format!("`cargo {}` failed ({s})", CARGO_TEST.join(" "))),
        Err(e) => Err(format!("cannot start {cargo}: {e}")),
    }
}

/// `cargo xtask test [--no-python] [--no-slurm]`.
pub fn main(args: &[String], root: &Path) -> ExitCode {
    let (mut python, mut slurm) = (true, true);
    for a in args {
        match a.as_str() {
            "--no-python" => python = false,
            "--no-slurm" => slurm = false,
            "-h" | "--help" => {
                println!("{USAGE}");
                return ExitCode::SUCCESS;
            }
            other => {
                eprintln!("unknown option `{other}` for test\n\n{USAGE}");
                return ExitCode::from(2);
            }
        }
    }
    // The venv's downloads and unpacking overlap the Rust build (which is CPU-bound); the
    // Python stage waits for them.
    let venv_prep = python.then(|| {
        let root = root.to_path_buf();
        std::sync::Mutex::new(Some(std::thread::spawn(move || {
            let t = Instant::now();
            crate::python::prepare_venv(&root).map(|()| t.elapsed().as_secs_f64())
        })))
    });
    let wait_for_venv = || -> Result<(), String> {
        let handle = venv_prep
            .as_ref()
            .and_then(|m| m.lock().ok().and_then(|mut h| h.take()));
        match handle.map(std::thread::JoinHandle::join) {
            Some(Ok(Ok(secs))) => {
                eprintln!("xtask test: the Python venv was ready after {secs:.1} s (overlapped)");
                Ok(())
            }
            Some(Ok(Err(e))) => Err(e),
            Some(Err(_)) => Err("preparing the Python venv panicked".into()),
            None => Ok(()),
        }
    };
    type Stage<'a> = (&'static str, Box<dyn Fn() -> Result<(), String> + 'a>);
    let mut stages: Vec<Stage> = vec![
        ("rust build", Box::new(|| cargo(root, &["--no-run"]))),
        ("rust tests", Box::new(|| cargo(root, &[]))),
    ];
    if python {
        stages.push((
            "python",
            Box::new(|| {
                wait_for_venv()?;
                crate::python::stages(root, false, &[])
            }),
        ));
        stages.push(("wheel", Box::new(|| crate::wheel::stage(root))));
    }
    if slurm {
        stages.push(("slurm", Box::new(|| crate::slurm::check_all(root))));
    }
    let start = Instant::now();
    let mut lines = Vec::new();
    let mut failed = Vec::new();
    let mut times = StageTimes { stages: Vec::new() };
    for (name, stage) in &stages {
        eprintln!("xtask test: {name} …");
        let t = Instant::now();
        let result = stage();
        let secs = t.elapsed().as_secs_f64();
        times.stages.push(StageTime {
            name: (*name).to_string(),
            seconds: secs,
            ok: result.is_ok(),
        });
        match result {
            Ok(()) => lines.push(format!("  {name:<11} ok      {secs:7.1} s")),
            Err(e) => {
                lines.push(format!("  {name:<11} FAILED  {secs:7.1} s  {e}"));
                failed.push(*name);
            }
        }
    }
    eprintln!("\nxtask test: summary");
    for l in &lines {
        eprintln!("{l}");
    }
    eprintln!(
        "  {:<11} {}  {:7.1} s",
        "total",
        if failed.is_empty() {
            "ok    "
        } else {
            "FAILED"
        },
        start.elapsed().as_secs_f64()
    );
    // `cargo xtask build-timing` asks for the stage times as data.
    if let Some(path) = std::env::var_os(STAGE_TIMES_ENV)
        && let Err(e) = times.write(Path::new(&path))
    {
        eprintln!("xtask test: cannot record the stage times: {e}");
        return ExitCode::FAILURE;
    }
    if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        eprintln!("xtask test: failed: {}", failed.join(", "));
        ExitCode::FAILURE
    }
}
