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
    /// CPU seconds of the process, user + system over all its threads (from the kernel's
    /// accounting when it is reaped; none where that is not available).
    pub cpu_s: Option<f64>,
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
    let started = Solo::start();
    let cpu_before = children_cpu_s();
    let start = Instant::now();
    let out = Command::new(bin)
        .args(args)
        .envs(envs.iter().copied())
        .output()
        .map_err(|e| format!("cannot run {}: {e}", bin.display()))?;
    let wall_s = start.elapsed().as_secs_f64();
    let cpu_s = match (started.alone(), cpu_before, children_cpu_s()) {
        (true, Some(a), Some(b)) => Some(b - a),
        _ => None,
    };
    Ok(Invocation {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        wall_s,
        cpu_s,
    })
}

/// CPU seconds (user + system) of every child this process has reaped so far.
fn children_cpu_s() -> Option<f64> {
    use nix::sys::resource::{UsageWho, getrusage};
    let u = getrusage(UsageWho::RUSAGE_CHILDREN).ok()?;
    let s = |t: nix::sys::time::TimeVal| t.tv_sec() as f64 + 1e-6 * t.tv_usec() as f64;
    Some(s(u.user_time()) + s(u.system_time()))
}

/// Invocations in flight, and invocations started: an invocation's CPU time is the change of
/// [`children_cpu_s`] over its life, which is its own only when no other invocation ran
/// meanwhile (the bench runs one at a time; validation's parallel runs get none).
static ACTIVE: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
static STARTED: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// One invocation's place among the others.
struct Solo {
    number: u64,
    others_active: usize,
}

impl Solo {
    fn start() -> Self {
        use std::sync::atomic::Ordering::SeqCst;
        let number = STARTED.fetch_add(1, SeqCst) + 1;
        let others_active = ACTIVE.fetch_add(1, SeqCst);
        Self {
            number,
            others_active,
        }
    }

    /// Whether no other invocation overlapped it so far.
    fn alone(&self) -> bool {
        self.others_active == 0 && STARTED.load(std::sync::atomic::Ordering::SeqCst) == self.number
    }
}

impl Drop for Solo {
    fn drop(&mut self) {
        ACTIVE.fetch_sub(1, std::sync::atomic::Ordering::SeqCst);
    }
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
