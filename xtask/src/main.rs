//! `cargo xtask …`: the project's automation entry point (validate, convergence, bench).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

const HELP: &str = "\
cargo xtask <command>

Commands:
  validate      simulate the paper's scenes, check claims C1–C10, write reports/
                (index.md, summary.json, SVG figures); exits 1 if a claim fails
      --check   rerun and compare verdicts, event counts and the reduced block with the
                committed reports/summary.json, writing nothing; exits 1 on a mismatch
      --jobs N  scene runs in parallel (default 2)
  convergence   run the full convergence study (crate stickslip-convergence, release build)
                and write reports/convergence.{md,json} and reports/convergence_*.svg;
                options are passed on (`cargo xtask convergence --help`)
  bench         run the headline performance comparisons (not built yet)
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
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--check" => opts.check = true,
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
    match stickslip_validation::validate::validate(&opts) {
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
        Ok(s) if s.success() => ExitCode::SUCCESS,
        Ok(s) => ExitCode::from(u8::try_from(s.code().unwrap_or(1)).unwrap_or(1)),
        Err(e) => {
            eprintln!("convergence: cannot run cargo: {e}");
            ExitCode::from(2)
        }
    }
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
        Some(other) => {
            eprintln!("unknown xtask command `{other}`\n\n{HELP}");
            ExitCode::from(2)
        }
    }
}
