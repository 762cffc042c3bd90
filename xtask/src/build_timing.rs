//! `cargo xtask build-timing`: what the README's two commands cost on a fresh clone (P4 of
//! reports/performance.md), written to `reports/build-timing.json`.
//!
//! Clones HEAD into `target/build-timing/clone` (a clean checkout with its own empty
//! `target/`, as CI has), then runs there, timed: `cargo xtask validate` and `cargo xtask
//! test`, which records its own stages (compile, Rust tests, Python, Slurm) through
//! [`StageTimes`]. The cargo registry (downloaded sources) is the machine's, as stated in the
//! file. Takes as long as a fresh clone does (several minutes on 2 cores).

use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::Instant;
use stickslip_report::build_timing::{BuildTiming, STAGE_TIMES_ENV, StageTimes};

fn git(dir: &Path, args: &[&str]) -> Result<String, String> {
    let out = Command::new("git")
        .current_dir(dir)
        .args(args)
        .output()
        .map_err(|e| format!("cannot run git: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "git {} failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Runs `cargo xtask ARGS` in `dir` with a clean cargo environment; (seconds, exit 0).
fn xtask(dir: &Path, args: &[&str], envs: &[(&str, &Path)]) -> Result<(f64, bool), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let mut cmd = Command::new(&cargo);
    cmd.current_dir(dir).arg("xtask").args(args);
    // The clone builds into its own target/, whatever this process was started with.
    for var in ["CARGO_TARGET_DIR", "CARGO_BUILD_TARGET_DIR", "RUSTFLAGS"] {
        cmd.env_remove(var);
    }
    for (k, v) in envs {
        cmd.env(k, v);
    }
    eprintln!(
        "build-timing: cargo xtask {} (in {})",
        args.join(" "),
        dir.display()
    );
    let start = Instant::now();
    let status = cmd
        .status()
        .map_err(|e| format!("cannot run {cargo}: {e}"))?;
    Ok((start.elapsed().as_secs_f64(), status.success()))
}

fn measure(root: &Path) -> Result<BuildTiming, String> {
    let work = root.join("target").join("build-timing");
    let clone = work.join("clone");
    if clone.exists() {
        std::fs::remove_dir_all(&clone).map_err(|e| format!("{}: {e}", clone.display()))?;
    }
    std::fs::create_dir_all(&work).map_err(|e| format!("{}: {e}", work.display()))?;
    let source = root.to_string_lossy().to_string();
    let target = clone.to_string_lossy().to_string();
    git(
        &work,
        &["clone", "--quiet", "--no-hardlinks", &source, &target],
    )?;
    let commit = git(&clone, &["rev-parse", "HEAD"])?;
    let home = std::env::var_os("CARGO_HOME")
        .map(std::path::PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cargo")));
    let registry_warm = home.is_some_and(|h| h.join("registry").join("src").is_dir());
    let (validate_s, validate_ok) = xtask(&clone, &["validate"], &[])?;
    let stages_file = work.join("test-stages.json");
    let _ = std::fs::remove_file(&stages_file);
    let (test_s, test_ok) = xtask(&clone, &["test"], &[(STAGE_TIMES_ENV, &stages_file)])?;
    let stages = StageTimes::read(&stages_file)?.ok_or_else(|| {
        format!(
            "cargo xtask test wrote no stage times to {}",
            stages_file.display()
        )
    })?;
    Ok(BuildTiming {
        commit,
        cpus: std::thread::available_parallelism().map_or(0, usize::from),
        validate_s,
        validate_ok,
        test_s,
        test_ok,
        test_stages: stages.stages,
        registry_warm,
    })
}

/// `cargo xtask build-timing`.
pub fn main(root: &Path) -> ExitCode {
    match measure(root) {
        Ok(t) => {
            let reports = root.join("reports");
            if let Err(e) = t.write(&reports) {
                eprintln!("build-timing: {e}");
                return ExitCode::FAILURE;
            }
            eprintln!(
                "build-timing: fresh clone of {}: validate {:.0} s ({}), test {:.0} s ({}) = {:.2}× \
                 validate; stages: {}; wrote {}",
                &t.commit[..t.commit.len().min(10)],
                t.validate_s,
                if t.validate_ok { "ok" } else { "FAILED" },
                t.test_s,
                if t.test_ok { "ok" } else { "FAILED" },
                t.test_s / t.validate_s,
                t.test_stages
                    .iter()
                    .map(|s| format!("{} {:.0} s", s.name, s.seconds))
                    .collect::<Vec<_>>()
                    .join(", "),
                BuildTiming::path(&reports).display()
            );
            if t.validate_ok && t.test_ok {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            }
        }
        Err(e) => {
            eprintln!("build-timing: {e}");
            ExitCode::FAILURE
        }
    }
}
