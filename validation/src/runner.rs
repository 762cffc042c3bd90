//! Runs the validation scenes with the `stickslip` binary as a subprocess, exactly as a user
//! would (`stickslip run SCENE --out DIR --quiet --set …`), a few at a time, and parses what
//! each run wrote.

use crate::data::RunOutput;
use std::collections::{BTreeMap, VecDeque};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Nodes used for every radial scene. The paper used N = 2000; the dense operators make one
/// fig2 run cost ~10 min there against ~4 s at N = 200, and the fig2 onsets at N = 50, 100 and
/// 200 agree to ~0.01 µs (measured by the `fig2_n50`/`fig2_n100` runs every time).
pub const NODES: usize = 200;

/// Extra `--set` overrides computed from the outputs of an earlier run.
pub type Derive = fn(&RunOutput) -> Vec<String>;

/// One run of a scene file with overrides.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// Run name (output directory under `target/validation/`).
    pub name: &'static str,
    /// Scene file stem in `validation/scenes/`.
    pub scene: &'static str,
    /// `--set` overrides beyond `contact.nodes`.
    pub sets: Vec<String>,
    /// Nodes (`--set contact.nodes=…`).
    pub nodes: usize,
    /// What the run is for.
    pub purpose: &'static str,
    /// A run that must finish first, and the extra overrides computed from its outputs.
    pub after: Option<(&'static str, Derive)>,
}

impl RunSpec {
    fn new(name: &'static str, scene: &'static str, purpose: &'static str) -> Self {
        Self {
            name,
            scene,
            sets: Vec::new(),
            nodes: NODES,
            purpose,
            after: None,
        }
    }

    /// The full `--set` list.
    pub fn overrides(&self) -> Vec<String> {
        let mut v = vec![format!("contact.nodes={}", self.nodes)];
        v.extend(self.sets.iter().cloned());
        v
    }
}

/// fig3's overrides from fig2's outputs: probes sampled every step (1e-8 s), and profiles at
/// 1.3 ms plus six snapshots through the last complete melting of fig2 (1 µs before the
/// onset, then the onset and four equal steps to the return to fully solid), so Fig. 2b,d can
/// show the front crossing the contact. fig3 is fig2 with probes: its events are fig2's.
pub fn fig3_overrides(fig2: &RunOutput) -> Vec<String> {
    let mut times = vec![fig2.info.end_s];
    let end = fig2.info.end_s;
    if let Some(e) = fig2
        .events
        .events
        .iter()
        .rev()
        .find(|e| e.t_end_s.is_some_and(|t| t < end))
    {
        let t_end = e.t_end_s.unwrap_or(e.t_onset_s);
        let step = (t_end - e.t_onset_s) / 4.0;
        times.push(e.t_onset_s - 1e-6);
        times.extend((0..5).map(|j| e.t_onset_s + j as f64 * step));
    }
    times.sort_by(f64::total_cmp);
    let list: Vec<String> = times.iter().map(|t| format!("{t:e}")).collect();
    vec![
        "output.series_interval=1e-8".into(),
        format!("output.profile_times=[{}]", list.join(",")),
    ]
}

/// Every run of `cargo xtask validate`, longest first (so two workers finish together).
pub fn specs() -> Vec<RunSpec> {
    let mut literal = RunSpec::new("fig2_literal", "fig2", "the paper's algorithm (C4 finding)");
    literal.sets.push("time.scheme=literal".into());
    let mut n100 = RunSpec::new("fig2_n100", "fig2", "resolution evidence");
    n100.nodes = 100;
    let mut n50 = RunSpec::new("fig2_n50", "fig2", "resolution evidence");
    n50.nodes = 50;
    let mut reduced = RunSpec::new(
        "fig2_reduced_cli",
        "fig2",
        "the reduced block of summary.json",
    );
    reduced.nodes = crate::reduced::NODES;
    reduced.sets = crate::reduced::cli_overrides()
        .into_iter()
        .filter(|s| !s.starts_with("contact.nodes="))
        .collect();
    vec![
        RunSpec::new("fig2", "fig2", "Fig. 2, 5a; C1–C4, C6, C9"),
        RunSpec {
            after: Some(("fig2", fig3_overrides)),
            ..RunSpec::new("fig3", "fig3", "Fig. 2b,d snapshots, Fig. 3; C4, C5")
        },
        RunSpec::new("fig4", "fig4", "Fig. 4, 5b; C2, C7, C9"),
        RunSpec::new("rigid", "rigid", "C10"),
        RunSpec::new("rigid_fast", "rigid_fast", "rigid drive at V0 = 1 m/s"),
        n100,
        literal,
        n50,
        RunSpec::new("melt", "melt", "C8"),
        RunSpec::new("homogeneous", "homogeneous", "C6"),
        reduced,
    ]
}

/// The outcome of one run.
#[derive(Debug)]
pub struct RunResult {
    /// The spec.
    pub spec: RunSpec,
    /// Parsed outputs, or the failure (exit status and stderr, or a parse error).
    pub output: Result<RunOutput, String>,
    /// Wall seconds of the subprocess as seen from here.
    pub wall_seconds: f64,
}

/// Builds the release binary with `cargo build --release -p stickslip` and returns its path.
///
/// # Errors
/// If cargo fails or the binary is not where it should be.
pub fn build_binary(root: &Path) -> Result<PathBuf, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(root)
        .args(["build", "--release", "-p", "stickslip"])
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err(format!(
            "cargo build --release -p stickslip failed: {status}"
        ));
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let bin = target
        .join("release")
        .join(format!("stickslip{}", std::env::consts::EXE_SUFFIX));
    if bin.is_file() {
        Ok(bin)
    } else {
        Err(format!("{} not found after the build", bin.display()))
    }
}

/// Runs one spec: `bin run <scene> --out <out_root>/<name> --quiet --set …`, then parses.
pub fn run_one(bin: &Path, scenes: &Path, out_root: &Path, spec: &RunSpec) -> RunResult {
    let dir = out_root.join(spec.name);
    let scene = scenes.join(format!("{}.toml", spec.scene));
    let start = Instant::now();
    let output = (|| {
        if !scene.is_file() {
            return Err(format!("scene file {} missing", scene.display()));
        }
        if dir.exists() {
            std::fs::remove_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let mut cmd = Command::new(bin);
        cmd.arg("run")
            .arg(&scene)
            .arg("--out")
            .arg(&dir)
            .arg("--quiet");
        for s in spec.overrides() {
            cmd.arg("--set").arg(s);
        }
        let out = cmd
            .output()
            .map_err(|e| format!("cannot start {}: {e}", bin.display()))?;
        if !out.status.success() {
            let stderr = String::from_utf8_lossy(&out.stderr);
            return Err(format!(
                "`stickslip run {}` exited with {}: {}",
                spec.scene,
                out.status,
                stderr.trim()
            ));
        }
        RunOutput::read(&dir, spec.name).map_err(|e| e.to_string())
    })();
    RunResult {
        spec: spec.clone(),
        output,
        wall_seconds: start.elapsed().as_secs_f64(),
    }
}

/// Runs all `specs` with `jobs` workers, printing progress; results by run name.
pub fn run_all(
    bin: &Path,
    scenes: &Path,
    out_root: &Path,
    specs: Vec<RunSpec>,
    jobs: usize,
) -> BTreeMap<String, RunResult> {
    let total = specs.len();
    let queue: Arc<Mutex<VecDeque<(usize, RunSpec)>>> =
        Arc::new(Mutex::new(specs.into_iter().enumerate().collect()));
    let results = Arc::new(Mutex::new(BTreeMap::new()));
    std::thread::scope(|scope| {
        for _ in 0..jobs.max(1) {
            let queue = Arc::clone(&queue);
            let results = Arc::clone(&results);
            scope.spawn(move || {
                loop {
                    let next = {
                        let mut q = queue.lock().expect("queue lock");
                        if q.is_empty() {
                            break;
                        }
                        let done = results.lock().expect("results lock");
                        let ready = q.iter().position(|(_, s): &(usize, RunSpec)| {
                            s.after.is_none_or(|(dep, _)| done.contains_key(dep))
                        });
                        ready.and_then(|p| q.remove(p)).map(|(i, mut spec)| {
                            let mut blocked = None;
                            if let Some((dep, derive)) = spec.after {
                                match &done.get(dep).map(|r: &RunResult| &r.output) {
                                    Some(Ok(o)) => spec.sets.extend(derive(o)),
                                    _ => blocked = Some(format!("needs run `{dep}`, which failed")),
                                }
                            }
                            (i, spec, blocked)
                        })
                    };
                    let Some((i, spec, blocked)) = next else {
                        std::thread::sleep(std::time::Duration::from_millis(100));
                        continue;
                    };
                    if let Some(e) = blocked {
                        println!("  [{:>2}/{total}] SKIPPED {:<17} {e}", i + 1, spec.name);
                        results.lock().expect("results lock").insert(
                            spec.name.to_string(),
                            RunResult {
                                spec,
                                output: Err(e),
                                wall_seconds: 0.0,
                            },
                        );
                        continue;
                    }
                    println!(
                        "  [{:>2}/{total}] running {:<17} ({}.toml, N = {}{}) — {}",
                        i + 1,
                        spec.name,
                        spec.scene,
                        spec.nodes,
                        if spec.sets.is_empty() {
                            String::new()
                        } else {
                            format!(", {}", spec.sets.join(", "))
                        },
                        spec.purpose
                    );
                    let r = run_one(bin, scenes, out_root, &spec);
                    match &r.output {
                        Ok(o) => println!(
                            "  [{:>2}/{total}] done    {:<17} {:>3} events, {:>6.1} s",
                            i + 1,
                            spec.name,
                            o.events.len(),
                            r.wall_seconds
                        ),
                        Err(e) => {
                            println!("  [{:>2}/{total}] FAILED  {:<17} {e}", i + 1, spec.name)
                        }
                    }
                    results
                        .lock()
                        .expect("results lock")
                        .insert(spec.name.to_string(), r);
                }
            });
        }
    });
    Arc::try_unwrap(results)
        .expect("workers joined")
        .into_inner()
        .expect("results lock")
}
