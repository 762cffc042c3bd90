//! The validation's runs and their scheduling: which scenes run with which overrides (the run
//! list of `cargo xtask validate`), and a [`Runner`] that runs one scene through the
//! `stickslip` binary as a user would, a few at a time. Building and invoking the binary go
//! through `stickslip_report::binary`; what a run wrote is read through the run library's
//! schema (a failure from run.json's typed `failure` record, never from stderr). The hard
//! cases ([`crate::hard::Bench`]) use the same [`Runner`]. Work other than a `stickslip run`
//! (the `stickslip verify` runs of [`crate::verify_check`]) joins the same pool as a [`Task`].

use std::collections::{BTreeMap, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use stickslip_report::binary::{Invocation, run_scene};
use stickslip_run::keys::{contact, output, temperature, time, words::Scheme};
use stickslip_run::schema::SchemaError;
use stickslip_run::schema::run_info::FailureRecord;
use stickslip_run::{ResolvedScene, RunOutput, RunStatus, Scene, SceneError};

pub use crate::sizes::NODES;

/// The old default of `output.event_merge_gap`, s: the event-rule comparison runs every paper
/// scene with it beside the default settings.
pub const OLD_MERGE_GAP_S: f64 = 1e-5;

/// [`OLD_MERGE_GAP_S`] as the `--set` argument.
pub fn old_merge_gap() -> String {
    output::EVENT_MERGE_GAP.set(OLD_MERGE_GAP_S).to_string()
}

/// Suffix of the runs with [`OLD_MERGE_GAP_S`].
pub const OLD_GAP_SUFFIX: &str = "_gap1e-5";

/// Runs scenes with one `stickslip` binary, outputs under one directory.
#[derive(Debug, Clone)]
pub struct Runner {
    bin: PathBuf,
    root: PathBuf,
    out_root: PathBuf,
}

/// One `stickslip run` and what it left behind (also when it failed).
#[derive(Debug, Clone)]
pub struct Attempt {
    /// Run label (output directory name under the runner's output root).
    pub label: String,
    /// The command line, relative to the workspace root, to reproduce the run.
    pub command: String,
    /// The same scene and overrides resolved in-process (the typed scene, or the typed error
    /// the command line reports with exit status 2).
    pub scene: Result<ResolvedScene, SceneError>,
    /// The process (exit status, wall time), or why it could not be started.
    pub process: Result<Invocation, String>,
    /// The output files read through the schema (also after a numerical failure).
    pub output: Result<RunOutput, SchemaError>,
}

impl Runner {
    /// A runner of `bin` for the workspace at `root`, outputs under `out_root`.
    pub fn new(bin: PathBuf, root: PathBuf, out_root: PathBuf) -> Self {
        Self {
            bin,
            root,
            out_root,
        }
    }

    /// The binary.
    pub fn bin(&self) -> &Path {
        &self.bin
    }

    /// The directory the runs write under.
    pub fn out_root(&self) -> &Path {
        &self.out_root
    }

    /// The workspace root.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// `path` relative to the workspace root, for commands a reader can paste.
    pub fn relative(&self, path: &Path) -> String {
        path.strip_prefix(&self.root)
            .map_or_else(|_| path.display().to_string(), |p| p.display().to_string())
    }

    /// `stickslip run <scene> --out <out_root>/<label> --quiet --force --set …` (after removing
    /// what an earlier run left there, so a refused run never shows stale files), then reads
    /// the outputs.
    pub fn run(&self, label: &str, scene: &Path, sets: &[String]) -> Attempt {
        let dir = self.out_root.join(label);
        let mut command = format!(
            "stickslip run {} --out {}",
            self.relative(scene),
            self.relative(&dir)
        );
        for s in sets {
            command.push_str(&format!(" --set {s}"));
        }
        if dir.exists() {
            let _ = std::fs::remove_dir_all(&dir);
        }
        let resolved = Scene::from_path(scene, sets);
        let (process, output) = match run_scene(&self.bin, scene, &dir, sets, &[]) {
            Ok(run) => (Ok(run.process), run.output),
            Err(e) => (
                Err(e.clone()),
                Err(SchemaError::new(&dir.display().to_string(), None, e)),
            ),
        };
        Attempt {
            label: label.to_string(),
            command,
            scene: resolved,
            process,
            output,
        }
    }
}

impl Attempt {
    /// Exit status (None when killed by a signal or not started).
    pub fn exit_code(&self) -> Option<i32> {
        self.process.as_ref().ok().and_then(|p| p.code)
    }

    /// Exit 0, readable outputs and run.json status `ok`.
    pub fn ok(&self) -> bool {
        self.exit_code() == Some(0) && self.out().is_some_and(|o| o.info.status == RunStatus::Ok)
    }

    /// The outputs, if readable.
    pub fn out(&self) -> Option<&RunOutput> {
        self.output.as_ref().ok()
    }

    /// The typed failure record of run.json (a numerical failure or a refusal), if any.
    pub fn failure(&self) -> Option<&FailureRecord> {
        self.out().and_then(|o| o.info.failure.as_ref())
    }

    /// Why the run has no usable outputs: the failure record's message, the typed scene error,
    /// or the exit status and why the files cannot be read.
    pub fn error(&self) -> String {
        if let Some(f) = self.failure() {
            return format!("exit {}: {}", self.exit_text(), f.message);
        }
        if let Err(e) = &self.scene {
            return format!("exit {}: {e}", self.exit_text());
        }
        match (&self.process, &self.output) {
            (Err(e), _) => e.clone(),
            (_, Err(e)) => format!("exit {}; {e}", self.exit_text()),
            (_, Ok(o)) => format!(
                "exit {}, run.json status {}",
                self.exit_text(),
                o.info.status.name()
            ),
        }
    }

    /// The exit status in words (`0`, `3`, `none`).
    pub fn exit_text(&self) -> String {
        self.exit_code()
            .map_or_else(|| "none".to_string(), |c| c.to_string())
    }

    /// The outputs of a successful run, or [`Attempt::error`].
    ///
    /// # Errors
    /// When the run did not succeed.
    pub fn result(&self) -> Result<RunOutput, String> {
        match self.out() {
            Some(o) if self.ok() => Ok(o.clone()),
            _ => Err(self.error()),
        }
    }
}

/// Extra `--set` overrides computed from the outputs of an earlier run.
pub type Derive = fn(&RunOutput) -> Vec<String>;

/// One run of a scene file with overrides.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// Run name (output directory under `target/validation/`).
    pub name: String,
    /// Scene file stem in `validation/scenes/`.
    pub scene: &'static str,
    /// `--set` overrides beyond `contact.nodes`.
    pub sets: Vec<String>,
    /// Nodes (`--set contact.nodes=…`).
    pub nodes: usize,
    /// What the run is for.
    pub purpose: String,
    /// A run that must finish first, and the extra overrides computed from its outputs.
    pub after: Option<(String, Derive)>,
}

impl RunSpec {
    /// A run of `scene` at N = [`NODES`] without other overrides.
    pub fn new(name: &str, scene: &'static str, purpose: &str) -> Self {
        Self {
            name: name.to_string(),
            scene,
            sets: Vec::new(),
            nodes: NODES,
            purpose: purpose.to_string(),
            after: None,
        }
    }

    /// The full `--set` list.
    pub fn overrides(&self) -> Vec<String> {
        let mut v = vec![contact::NODES.set(self.nodes as i64).to_string()];
        v.extend(self.sets.iter().cloned());
        v
    }

    /// The same run with the old default `output.event_merge_gap` (for the event-rule
    /// comparison).
    fn with_old_gap(&self) -> Self {
        let mut s = self.clone();
        s.name = format!("{}{OLD_GAP_SUFFIX}", self.name);
        s.sets.push(old_merge_gap());
        s.purpose = format!("event rule: `{}` with {}", self.name, old_merge_gap());
        s.after = self
            .after
            .as_ref()
            .map(|(dep, f)| (format!("{dep}{OLD_GAP_SUFFIX}"), *f));
        s
    }
}

/// fig3's overrides from fig2's outputs: probes sampled every 1e-8 s, and profiles at the end
/// plus six snapshots through the last complete melting of fig2 (1 µs before the onset, then
/// the onset and four equal steps to the film's recovery, `t_end`), so Fig. 2b,d can show the
/// front crossing the contact. fig3 is fig2 with probes: its events are fig2's.
pub fn fig3_overrides(fig2: &RunOutput) -> Vec<String> {
    let end = fig2.info.end_s();
    let mut times = vec![end];
    if let Some(e) = fig2
        .events
        .events()
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
    vec![
        output::SERIES_INTERVAL.set(1e-8).to_string(),
        output::PROFILE_TIMES.set(times).to_string(),
    ]
}

/// The runs of the event-rule comparison, with the default event settings; each has a partner
/// run with [`OLD_MERGE_GAP_S`] ([`old_gap_partner`]).
pub const EVENT_RULE_RUNS: [&str; 8] = [
    "fig2",
    "fig2_literal_default",
    "fig3",
    "fig4",
    "homogeneous",
    "melt",
    "rigid",
    "rigid_fast",
];

/// The run that repeats `name` with [`OLD_MERGE_GAP_S`]: `fig2_literal` for the literal scheme
/// (which the report uses with that gap anyway), else `<name>_gap1e-5`.
pub fn old_gap_partner(name: &str) -> String {
    if name == "fig2_literal_default" {
        "fig2_literal".into()
    } else {
        format!("{name}{OLD_GAP_SUFFIX}")
    }
}

/// Every run of `cargo xtask validate`, longest first (so two workers finish together).
pub fn specs() -> Vec<RunSpec> {
    let mut literal = RunSpec::new(
        "fig2_literal",
        "fig2",
        &format!(
            "the paper's algorithm (C4 finding), with {} so that its axis \
             precursor and the edge front that follows form one event: literal and accurate \
             onsets then compare front by front",
            old_merge_gap()
        ),
    );
    literal.sets = vec![
        time::SCHEME.set(Scheme::Literal).to_string(),
        old_merge_gap(),
    ];
    let mut literal_default = RunSpec::new(
        "fig2_literal_default",
        "fig2",
        "the paper's algorithm with the default event settings (axis precursors as events)",
    );
    literal_default
        .sets
        .push(time::SCHEME.set(Scheme::Literal).to_string());
    let mut n100 = RunSpec::new("fig2_n100", "fig2", "resolution evidence");
    n100.nodes = 100;
    let mut n50 = RunSpec::new("fig2_n50", "fig2", "resolution evidence");
    n50.nodes = 50;
    let mut reduced = RunSpec::new(
        "fig2_reduced_cli",
        "fig2",
        "the reduced block of summary.json",
    );
    reduced.nodes = crate::sizes::REDUCED_NODES;
    reduced.sets = crate::sizes::reduced_overrides()
        .into_iter()
        .filter(|s| !s.starts_with(&format!("{}=", contact::NODES.path)))
        .collect();
    let mut fig3 = RunSpec::new("fig3", "fig3", "Fig. 2b,d snapshots, Fig. 3; C4, C5");
    fig3.after = Some(("fig2".into(), fig3_overrides));
    let mut all = vec![
        literal_default,
        literal,
        RunSpec::new("fig2", "fig2", "Fig. 2, 5a; C1–C4, C6, C9, C12, C13"),
        fig3,
        RunSpec::new("fig4", "fig4", "Fig. 4, 5b; C2, C7, C9"),
        RunSpec::new("rigid", "rigid", "C10"),
        RunSpec::new("rigid_fast", "rigid_fast", "rigid drive at V0 = 1 m/s"),
        n100,
        n50,
        RunSpec::new("melt", "melt", "C8"),
        RunSpec::new("homogeneous", "homogeneous", "C6, C12"),
        RunSpec::new(
            "fig2_first_order",
            "fig2_first_order",
            "the first-order film (ε₊ = 1.3·εc); C12, C13",
        ),
        RunSpec::new("homogeneous_first_order", "homogeneous_first_order", "C12"),
        reduced,
    ];
    for a0 in crate::sizes::HYSTERESIS_A0_PA {
        let mut h = RunSpec::new(
            &crate::sizes::hysteresis_run(a0),
            "hysteresis",
            &format!("C11: the first-order film's melting strain at A0 = {a0:e} Pa"),
        );
        h.sets.push(temperature::A0.set(a0).to_string());
        all.push(h);
    }
    let partners: Vec<RunSpec> = EVENT_RULE_RUNS
        .iter()
        .filter(|name| !all.iter().any(|s| s.name == old_gap_partner(name)))
        .filter_map(|name| all.iter().find(|s| s.name == *name))
        .map(RunSpec::with_old_gap)
        .collect();
    all.extend(partners);
    all
}

/// The outcome of one validation run.
#[derive(Debug)]
pub struct RunResult {
    /// The spec (with the overrides derived from an earlier run, if any).
    pub spec: RunSpec,
    /// What the run did; None when it could not start because the run it needs failed.
    pub attempt: Option<Attempt>,
    /// Why it was not run (a run it needs failed).
    pub skipped: Option<String>,
}

impl RunResult {
    /// The outputs of a successful run, or why there are none.
    ///
    /// # Errors
    /// When the run failed or was skipped.
    pub fn output(&self) -> Result<RunOutput, String> {
        match (&self.attempt, &self.skipped) {
            (Some(a), _) => a.result(),
            (None, Some(e)) => Err(e.clone()),
            (None, None) => Err("not run".into()),
        }
    }
}

/// Work that [`run_all_with`] schedules among the runs: its name for the progress line, and a
/// closure that does it (it keeps its own results) and says in a line what it did.
pub struct Task<'a> {
    /// Name shown in the progress line.
    pub name: String,
    /// The work; returns the progress line's text.
    pub work: Box<dyn FnOnce() -> String + Send + 'a>,
}

impl std::fmt::Debug for Task<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Task").field("name", &self.name).finish()
    }
}

/// Runs all `specs` of `scenes` with `jobs` workers, printing progress; results by run name.
pub fn run_all(
    runner: &Runner,
    scenes: &Path,
    specs: Vec<RunSpec>,
    jobs: usize,
) -> BTreeMap<String, RunResult> {
    run_all_with(runner, scenes, specs, Vec::new(), jobs)
}

/// What a worker takes from the queue.
enum Job<'a> {
    Run(RunSpec),
    Task(Task<'a>),
}

/// As [`run_all`], with `tasks` in the same pool: they start right after the first run of
/// `specs` (the longest) and before the others, so that a few long tasks overlap the many
/// short runs.
pub fn run_all_with<'a>(
    runner: &Runner,
    scenes: &Path,
    specs: Vec<RunSpec>,
    tasks: Vec<Task<'a>>,
    jobs: usize,
) -> BTreeMap<String, RunResult> {
    let total = specs.len() + tasks.len();
    let mut jobs_list: Vec<Job<'a>> = specs.into_iter().map(Job::Run).collect();
    let at = jobs_list.len().min(1);
    jobs_list.splice(at..at, tasks.into_iter().map(Job::Task));
    let queue: Mutex<VecDeque<(usize, Job<'a>)>> =
        Mutex::new(jobs_list.into_iter().enumerate().collect());
    let results: Mutex<BTreeMap<String, RunResult>> = Mutex::new(BTreeMap::new());
    std::thread::scope(|scope| {
        for _ in 0..jobs.max(1) {
            scope.spawn(|| {
                loop {
                    let next = {
                        let mut q = queue.lock().expect("queue lock");
                        if q.is_empty() {
                            break;
                        }
                        let done = results.lock().expect("results lock");
                        let ready = q.iter().position(|(_, j)| match j {
                            Job::Run(s) => s
                                .after
                                .as_ref()
                                .is_none_or(|(dep, _)| done.contains_key(dep)),
                            Job::Task(_) => true,
                        });
                        ready.and_then(|p| q.remove(p)).map(|(i, job)| match job {
                            Job::Task(t) => (i, Job::Task(t), None),
                            Job::Run(mut spec) => {
                                let mut blocked = None;
                                if let Some((dep, derive)) = spec.after.clone() {
                                    match done.get(&dep).map(RunResult::output) {
                                        Some(Ok(o)) => spec.sets.extend(derive(&o)),
                                        _ => {
                                            blocked =
                                                Some(format!("needs run `{dep}`, which failed"));
                                        }
                                    }
                                }
                                (i, Job::Run(spec), blocked)
                            }
                        })
                    };
                    let Some((i, job, blocked)) = next else {
                        std::thread::sleep(std::time::Duration::from_millis(50));
                        continue;
                    };
                    let spec = match job {
                        Job::Run(spec) => spec,
                        Job::Task(task) => {
                            let line = (task.work)();
                            println!("  [{:>2}/{total}] done    {:<28} {line}", i + 1, task.name);
                            continue;
                        }
                    };
                    let result = if let Some(e) = blocked {
                        println!("  [{:>2}/{total}] SKIPPED {:<28} {e}", i + 1, spec.name);
                        RunResult {
                            spec,
                            attempt: None,
                            skipped: Some(e),
                        }
                    } else {
                        let scene = scenes.join(format!("{}.toml", spec.scene));
                        let attempt = runner.run(&spec.name, &scene, &spec.overrides());
                        match attempt.result() {
                            Ok(o) => println!(
                                "  [{:>2}/{total}] done    {:<28} {:>3} events, {:>6.2} s — {}",
                                i + 1,
                                spec.name,
                                o.events.len(),
                                attempt.process.as_ref().map_or(f64::NAN, |p| p.wall_s),
                                spec.purpose
                            ),
                            Err(e) => println!(
                                "  [{:>2}/{total}] FAILED  {:<28} {}",
                                i + 1,
                                spec.name,
                                stickslip_report::fmt::first_line(&e)
                            ),
                        }
                        RunResult {
                            spec,
                            attempt: Some(attempt),
                            skipped: None,
                        }
                    };
                    results
                        .lock()
                        .expect("results lock")
                        .insert(result.spec.name.clone(), result);
                }
            });
        }
    });
    results.into_inner().expect("results lock")
}
