//! `cargo xtask …`: the project's automation entry point (test, validate, convergence, bench,
//! fit-study, maps, slurm-check, python-test, wheel, readme).

mod build_timing;
mod maps;
mod python;
mod readme;
mod slurm;
mod test_all;
mod wheel;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

const HELP: &str = "\
cargo xtask <command>

Commands:
  test          every test, the command CI runs: cargo test --release --workspace (less the
                criterion benches), then python-test, the wheel's check and slurm-check; a
                timed summary at the end; exits 1 if any stage failed
      --no-python, --no-slurm   skip that stage (--no-python skips the wheel too)
  validate      simulate the paper's scenes, check claims C1–C13, compare with the
                independent implementation, write reports/ (index.md, summary.json,
                independent.json, SVG figures); exits 1 if a claim fails or a compared
                quantity disagrees
      --check   rerun and compare verdicts, event counts and the reduced block with the
                committed reports/summary.json, writing nothing; exits 1 on a mismatch
      --jobs N  scene runs in parallel (default 2)
      --hard-only  only rerun the hard cases (validation/hard/) and write
                reports/hard-cases.md; exits 1 if an expected outcome is not met
      --independent-only  only compare with the independent implementation
                (validation/independent/, NumPy and SciPy in target/python-venv) and write
                reports/independent.{json,svg}; exits 1 if a quantity disagrees
      --energy-only  only run the energy books' checks and write
                reports/energy.{json} and energy_books.svg (index.md's section is written by a
                full run); exits 1 if a target is not met
  convergence   run the full convergence study (crate stickslip-convergence, release build)
                and write reports/convergence.{md,json} and reports/convergence_*.svg;
                options are passed on (`cargo xtask convergence --help`)
  bench         run the headline performance targets P1–P5 (and T3–T4) on the release binary and
                write reports/performance.{md,json} and reports/performance_*.svg
      --quick   smoke run (few, short runs; not for the report)
      --repeats N, --max-nodes N, --out DIR   (see crates/stickslip-convergence/src/bin/performance.rs)
  fit-study     fit synthetic traces from known parameters through the studies crate's fit and
                write reports/fit.{md,json} and reports/fit_*.svg: coverage of the 95 %
                intervals, width against samples, Jacobians, costs (the fig2 and SFA targets),
                the damped viscous SFA contact, identifiability; exits 1 if a verdict fails
      --quick   smoke study (N = 30, few seeds) into target/fit-study/quick/report
      --resume, --work DIR, --render-only, --out DIR, --jobs J   (`cargo xtask fit-study --help`)
  maps          run the showcase friction maps (maps/*.toml) and write reports/maps.md and
                reports/maps_*.svg with their checks; exits 1 if a check fails
      --jobs J  points run in parallel (default: the available cores)
      --resume  keep the points an interrupted `cargo xtask maps` finished (default: afresh)
  slurm-check   start a one-node Slurm here (installs slurm-wlm and munge with apt-get when
                missing), run maps/slurm-check.toml as a job array, merge, compare with a
                local run, stop the daemons it started; exits 1 on a mismatch
  build-timing  clone HEAD into target/build-timing/clone and time the README's two commands
                there (validate, then test with its stages) as on a fresh machine; writes
                reports/build-timing.json, which `bench` reports as P4 (several minutes)
  readme        rewrite README.md's generated blocks (every measured number it quotes) from the
                committed reports/ and say which changed; validate, convergence, bench,
                fit-study, maps and build-timing run it at their end
      --check   write nothing; exit 1 listing the blocks that differ from the reports
  python-test   build the Python package (pip install ./crates/stickslip-py) into the venv
                target/python-venv and run its pytest suite; prints install and test times
      --fresh   recreate the venv;  -- ARGS  passed to pytest
  wheel         build the Python package's abi3 wheel into dist/ (for machines without Rust:
                pip install dist/stickslip-*.whl)
      --check   then install it into a fresh venv without cargo on PATH and run the README's
                example with it (the `wheel` stage of `test`)
";

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives one level below the workspace root")
        .to_path_buf()
}

fn validate(args: &[String]) -> ExitCode {
    let mut opts = stickslip_validation::validate::Options {
        root: workspace_root(),
        check: false,
        jobs: 2,
        hard_only: false,
        python: None,
        independent_only: false,
        energy_only: false,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--check" => opts.check = true,
            "--hard-only" => opts.hard_only = true,
            "--independent-only" => opts.independent_only = true,
            "--energy-only" => opts.energy_only = true,
            "--jobs" => match it.next().and_then(|v| v.parse::<usize>().ok()) {
                Some(n) if n > 0 => opts.jobs = n,
                _ => {
                    eprintln!("--jobs needs a positive integer\n\n{HELP}");
                    return ExitCode::from(2);
                }
            },
            other => {
                eprintln!("unknown option `{other}` for validate\n\n{HELP}");
                return ExitCode::from(2);
            }
        }
    }
    // The independent implementation needs NumPy and SciPy: the test venv has them.
    if !opts.check && !opts.hard_only {
        match python::venv(&opts.root, false) {
            Ok((python, _)) => opts.python = Some(python),
            Err(e) => {
                eprintln!("validate: the Python venv for the independent implementation: {e}");
                return ExitCode::from(2);
            }
        }
    }
    let outcome = stickslip_validation::validate::validate(&opts);
    // The reports were written (whatever the verdicts), unless --check compared only.
    if outcome.is_ok() && !opts.check {
        readme::after("validate", &opts.root);
    }
    match outcome {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!("validate: a claim failed or the committed reports are stale (see above)");
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("validate: {e}");
            ExitCode::from(2)
        }
    }
}

/// Runs the study in its own release binary, so xtask itself stays light to build.
fn convergence(args: &[String]) -> ExitCode {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let status = std::process::Command::new(cargo)
        .current_dir(workspace_root())
        .args([
            "run",
            "--release",
            "-q",
            "-p",
            "stickslip-convergence",
            "--bin",
            "convergence",
            "--",
        ])
        .args(args)
        .status();
    match status {
        Ok(s) if s.success() => {
            readme::after("convergence", &workspace_root());
            ExitCode::SUCCESS
        }
        Ok(s) => ExitCode::from(u8::try_from(s.code().unwrap_or(1)).unwrap_or(1)),
        Err(e) => {
            eprintln!("convergence: cannot run cargo: {e}");
            ExitCode::from(2)
        }
    }
}

/// Builds the release `stickslip` binary, then runs the benchmarks in their own release binary.
fn bench(args: &[String]) -> ExitCode {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let run = |extra: &[&str], rest: &[String]| {
        std::process::Command::new(&cargo)
            .current_dir(workspace_root())
            .args(extra)
            .args(rest)
            .status()
    };
    let built = run(&["build", "--release", "-q", "-p", "stickslip"], &[]);
    if !matches!(built, Ok(s) if s.success()) {
        eprintln!("bench: building the release stickslip binary failed");
        return ExitCode::from(2);
    }
    let status = run(
        &[
            "run",
            "--release",
            "-q",
            "-p",
            "stickslip-convergence",
            "--bin",
            "performance",
            "--",
        ],
        args,
    );
    match status {
        Ok(s) if s.success() => {
            readme::after("bench", &workspace_root());
            ExitCode::SUCCESS
        }
        Ok(s) => ExitCode::from(u8::try_from(s.code().unwrap_or(1)).unwrap_or(1)),
        Err(e) => {
            eprintln!("bench: cannot run cargo: {e}");
            ExitCode::from(2)
        }
    }
}

/// After a command that writes reports and exits 0 (done) or 1 (done, a verdict failed;
/// or an error after which the committed reports are unchanged): README.md's generated blocks
/// from reports/, an error there printed, not fatal. Exit 2 (bad arguments) skips it.
fn wrote_reports(command: &str, code: ExitCode) -> ExitCode {
    if code != ExitCode::from(2) {
        readme::after(command, &workspace_root());
    }
    code
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        None | Some("help" | "--help" | "-h") => {
            print!("{HELP}");
            ExitCode::SUCCESS
        }
        Some("validate") => validate(&args[1..]),
        Some("convergence") => convergence(&args[1..]),
        Some("bench") => bench(&args[1..]),
        Some("maps") => wrote_reports("maps", maps::main(&args[1..], workspace_root())),
        Some("fit-study") => wrote_reports(
            "fit-study",
            stickslip_fit_study::cli(&args[1..], workspace_root()),
        ),
        Some("slurm-check") => slurm::main(workspace_root()),
        Some("test") => test_all::main(&args[1..], &workspace_root()),
        Some("build-timing") => {
            wrote_reports("build-timing", build_timing::main(&workspace_root()))
        }
        Some("readme") => readme::main(&args[1..], &workspace_root()),
        Some("python-test") => python::main(&args[1..], workspace_root()),
        Some("wheel") => wheel::main(&args[1..], &workspace_root()),
        Some(other) => {
            eprintln!("unknown xtask command `{other}`\n\n{HELP}");
            ExitCode::from(2)
        }
    }
}
