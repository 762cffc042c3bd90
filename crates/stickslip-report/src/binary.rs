//! Runs scenes through the `stickslip` binary, exactly as a user would, and reads what each
//! run wrote through the run library's schema types (never its stderr for data).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use stickslip_run::RunOutput;
use stickslip_run::schema::SchemaError;

/// Builds the release binary of the workspace at `root` (`cargo build --release -p
/// stickslip`) and returns its path.
///
/// # Errors
/// If cargo cannot be run or the build fails.
pub fn build(root: &Path) -> Result<PathBuf, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let status = Command::new(cargo)
        .current_dir(root)
        .args(["build", "--release", "--quiet", "-p", "stickslip"])
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err(format!("cargo build failed ({status})"));
    }
    let exe = root
        .join("target")
        .join("release")
        .join(format!("stickslip{}", std::env::consts::EXE_SUFFIX));
    if exe.exists() {
        Ok(exe)
    } else {
        Err(format!("{} was not built", exe.display()))
    }
}

/// One invocation of the binary.
#[derive(Debug, Clone)]
pub struct Invocation {
    /// Exit status (None: killed by a signal).
    pub code: Option<i32>,
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
    /// Wall-clock seconds of the whole process.
    pub wall_s: f64,
}

impl Invocation {
    /// Exit status 0.
    #[must_use]
    pub fn ok(&self) -> bool {
        self.code == Some(0)
    }
}

/// Runs `bin` with `args`.
///
/// # Errors
/// If the process cannot be started.
pub fn invoke(bin: &Path, args: &[String], envs: &[(&str, &str)]) -> Result<Invocation, String> {
    let start = Instant::now();
    let out = Command::new(bin)
        .args(args)
        .envs(envs.iter().copied())
        .output()
        .map_err(|e| format!("cannot run {}: {e}", bin.display()))?;
    Ok(Invocation {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        wall_s: start.elapsed().as_secs_f64(),
    })
}

/// A `stickslip run` and what it wrote.
#[derive(Debug, Clone)]
pub struct CliRun {
    /// The process.
    pub process: Invocation,
    /// The output directory.
    pub dir: PathBuf,
    /// Its files read through the schema (an error when the run wrote none or bad ones).
    pub output: Result<RunOutput, SchemaError>,
}

/// `stickslip run SCENE --out DIR --quiet --force --set …` and reads DIR.
///
/// # Errors
/// If the process cannot be started.
pub fn run_scene(
    bin: &Path,
    scene: &Path,
    out: &Path,
    sets: &[String],
    envs: &[(&str, &str)],
) -> Result<CliRun, String> {
    let mut args = vec![
        "run".to_string(),
        scene.display().to_string(),
        "--out".into(),
        out.display().to_string(),
        "--quiet".into(),
        "--force".into(),
    ];
    for s in sets {
        args.push("--set".into());
        args.push(s.clone());
    }
    let process = invoke(bin, &args, envs)?;
    Ok(CliRun {
        process,
        dir: out.to_path_buf(),
        output: RunOutput::read(out),
    })
}
