//! `cargo xtask slurm-check`: a real one-node Slurm on this machine runs a small sweep as a
//! job array through `stickslip sweep slurm … --allow-large --keep all --submit`, its tasks
//! at the same time on one directory, and the map the last task merged must equal a local
//! run's in every column but `wall_s`.
//!
//! Steps: install Debian's `slurm-wlm` and `munge` with apt-get when missing (and say so);
//! start `munged` unless a munge daemon answers already; write a slurm.conf naming this host
//! under `target/slurm-check/`, with more CPUs than the machine has (the node takes the
//! configured count), so every task of the array runs at once; start `slurmctld` and `slurmd`
//! in the foreground as children; wait for the node; submit; wait for the array; check that
//! the script carried the options, that the tasks overlapped in time (slurmctld's log of
//! their starts and ends), that every task exited 0, and that the tasks kept each point's
//! output (`--keep all` carried through); compare the map with a local run's; check that
//! `sweep merge` agrees. Then a refined sweep (`maps/slurm-check-refine.toml`, `[refine]`):
//! `sweep slurm --submit` chains one array per level and a merge (`--dependency=afterok`),
//! every task must exit 0, and the map the last task merged must equal a local run's and hold points
//! beyond the base grid. Stop the daemons this command started, by pid (also on failure).

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};
use std::time::{Duration, Instant};
use stickslip_studies::sweep::map::MapTable;

/// The sweep the check runs.
const SWEEP: &str = "maps/slurm-check.toml";
/// Array tasks.
const TASKS: usize = 4;
/// The refined sweep the check runs, one array per level.
const REFINED: &str = "maps/slurm-check-refine.toml";
/// Array tasks of each level of the refined sweep.
const REFINED_TASKS: usize = 3;
/// CPUs the node is configured with: more task slots than tasks (one CPU each).
const NODE_CPUS: usize = 8;
/// Longest wait for the node or the jobs.
const PATIENCE: Duration = Duration::from_secs(180);

/// Daemons started here, stopped by pid when dropped.
struct Daemons(Vec<(String, Child)>);

impl Drop for Daemons {
    fn drop(&mut self) {
        for (name, child) in self.0.iter_mut().rev() {
            let pid = child.id();
            let _ = Command::new("kill")
                .args(["-TERM", &pid.to_string()])
                .status();
            let start = Instant::now();
            while start.elapsed() < Duration::from_secs(10) {
                if child.try_wait().ok().flatten().is_some() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(50));
            }
            if child.try_wait().ok().flatten().is_none() {
                let _ = child.kill();
                let _ = child.wait();
            }
            println!("slurm-check: stopped {name} (pid {pid})");
        }
    }
}

fn have(cmd: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {cmd} >/dev/null 2>&1")])
        .status()
        .is_ok_and(|s| s.success())
}

fn run(cmd: &mut Command) -> Result<String, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run {cmd:?}: {e}"))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    } else {
        Err(format!(
            "{cmd:?} failed ({}): {}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

fn install_if_missing() -> Result<(), String> {
    if ["slurmctld", "slurmd", "sbatch", "squeue", "munged"]
        .iter()
        .all(|c| have(c))
    {
        return Ok(());
    }
    println!("slurm-check: installing Debian's slurm-wlm and munge with apt-get (missing here)");
    let started = Instant::now();
    let env = [("DEBIAN_FRONTEND", "noninteractive")];
    run(Command::new("apt-get").args(["update", "-q"]).envs(env))?;
    run(Command::new("apt-get")
        .args([
            "install",
            "-y",
            "-q",
            "--no-install-recommends",
            "slurm-wlm",
            "munge",
        ])
        .envs(env))?;
    println!(
        "slurm-check: installed in {:.0} s",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

fn wait_for(what: &str, mut ready: impl FnMut() -> bool) -> Result<(), String> {
    let start = Instant::now();
    while !ready() {
        if start.elapsed() > PATIENCE {
            return Err(format!(
                "timed out after {} s waiting for {what}",
                PATIENCE.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(250));
    }
    Ok(())
}

fn spawn(name: &str, cmd: &mut Command, log: &Path, daemons: &mut Daemons) -> Result<(), String> {
    let file = std::fs::File::create(log).map_err(|e| format!("{}: {e}", log.display()))?;
    let err = file.try_clone().map_err(|e| e.to_string())?;
    let child = cmd
        .stdin(Stdio::null())
        .stdout(file)
        .stderr(err)
        .spawn()
        .map_err(|e| format!("cannot start {name}: {e}"))?;
    println!("slurm-check: started {name} (pid {})", child.id());
    daemons.0.push((name.to_string(), child));
    Ok(())
}

fn munge_answers() -> bool {
    Command::new("sh")
        .args(["-c", "munge -n 2>/dev/null | unmunge >/dev/null 2>&1"])
        .status()
        .is_ok_and(|s| s.success())
}

fn slurm_conf(dir: &Path, host: &str) -> String {
    let cpus = NODE_CPUS;
    let d = dir.display();
    format!(
        "# Written by cargo xtask slurm-check: a one-node cluster on this host.\n\
         ClusterName=stickslip-check\nSlurmctldHost={host}\nSlurmUser=root\nSlurmdUser=root\n\
         AuthType=auth/munge\nCredType=cred/munge\nProctrackType=proctrack/linuxproc\n\
         TaskPlugin=task/none\nSelectType=select/cons_tres\nSelectTypeParameters=CR_CPU\n\
         ReturnToService=2\nMpiDefault=none\nJobCompType=jobcomp/none\n\
         SlurmdParameters=config_overrides\nSlurmctldDebug=debug\n\
         AccountingStorageType=accounting_storage/none\nSchedulerType=sched/backfill\n\
         StateSaveLocation={d}/state\nSlurmdSpoolDir={d}/spool\n\
         SlurmctldPidFile={d}/slurmctld.pid\nSlurmdPidFile={d}/slurmd.pid\n\
         SlurmctldLogFile={d}/slurmctld.log\nSlurmdLogFile={d}/slurmd.log\n\
         SlurmctldPort=16817\nSlurmdPort=16818\n\
         NodeName={host} CPUs={cpus} State=UNKNOWN\n\
         PartitionName=check Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n"
    )
}

/// Runs `sweep` locally into `local` and checks that `out`'s map.csv equals it in every column
/// but wall_s; `what` names `out`'s map in the error. Returns map.csv's line count.
fn same_as_local(
    bin: &Path,
    sweep: &Path,
    out: &Path,
    local: &Path,
    what: &str,
) -> Result<usize, String> {
    let ran = run(Command::new(bin).args([
        "sweep",
        "run",
        sweep.to_str().unwrap_or(""),
        "--out",
        local.to_str().unwrap_or(""),
        "--quiet",
    ]))?;
    print!("{ran}");
    let (a, b) = (without_wall(out)?, without_wall(local)?);
    if a != b {
        return Err(format!(
            "{what} differs from the local one (beyond wall_s): {} against {} rows",
            a.len(),
            b.len()
        ));
    }
    Ok(a.len())
}

/// Map rows without the wall-clock column.
fn without_wall(dir: &Path) -> Result<Vec<String>, String> {
    let table = MapTable::read(dir).map_err(|e| e.to_string())?;
    let wall = table
        .header()
        .iter()
        .position(|h| h == "wall_s")
        .ok_or("no wall_s column")?;
    Ok(table
        .to_csv()
        .lines()
        .map(|l| {
            let mut c: Vec<&str> = l.split(',').collect();
            c.remove(wall);
            c.join(",")
        })
        .collect())
}

fn check(root: &Path, daemons: &mut Daemons) -> Result<(), String> {
    install_if_missing()?;
    let bin = stickslip_report::binary::build(root)?;
    let dir = root.join("target").join("slurm-check");
    let _ = std::fs::remove_dir_all(&dir);
    for sub in ["state", "spool", "out"] {
        std::fs::create_dir_all(dir.join(sub)).map_err(|e| e.to_string())?;
    }
    let host = run(Command::new("hostname").arg("-s"))?.trim().to_string();
    let conf = dir.join("slurm.conf");
    std::fs::write(&conf, slurm_conf(&dir, &host)).map_err(|e| e.to_string())?;
    if munge_answers() {
        println!("slurm-check: a munge daemon answers already; using it");
    } else {
        let _ = std::fs::create_dir_all("/run/munge");
        let _ = run(Command::new("chown").args(["munge:munge", "/run/munge"]));
        if !Path::new("/etc/munge/munge.key").exists() {
            run(Command::new("mungekey").arg("--create"))?;
        }
        spawn(
            "munged",
            Command::new("munged").args(["--foreground", "--force"]),
            &dir.join("munged.out"),
            daemons,
        )?;
        wait_for("munged", munge_answers)?;
    }
    let conf_arg = conf.display().to_string();
    spawn(
        "slurmctld",
        Command::new("slurmctld").args(["-D", "-f", &conf_arg]),
        &dir.join("slurmctld.out"),
        daemons,
    )?;
    spawn(
        "slurmd",
        Command::new("slurmd").args(["-D", "-f", &conf_arg]),
        &dir.join("slurmd.out"),
        daemons,
    )?;
    let slurm = |cmd: &str, args: &[&str]| {
        let mut c = Command::new(cmd);
        c.args(args).env("SLURM_CONF", &conf);
        c
    };
    wait_for("the node to be idle", || {
        run(&mut slurm("sinfo", &["-h", "-o", "%T"])).is_ok_and(|s| s.trim() == "idle")
    })?;
    let sweep = root.join(SWEEP);
    let out = dir.join("out").join("slurm");
    let submitted = run(&mut slurm(
        bin.to_str().unwrap_or("stickslip"),
        &[
            "sweep",
            "slurm",
            sweep.to_str().unwrap_or(SWEEP),
            "--out",
            out.to_str().unwrap_or(""),
            "--tasks",
            &TASKS.to_string(),
            "--allow-large",
            "--keep",
            "all",
            "--submit",
        ],
    ))?;
    print!("{submitted}");
    let started = Instant::now();
    wait_for("the job array to finish", || {
        run(&mut slurm("squeue", &["-h", "-n", "stickslip-slurm-check"]))
            .is_ok_and(|s| s.trim().is_empty())
    })?;
    println!(
        "slurm-check: the array ran in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    check_array(&dir, &out)?;
    let merged = run(&mut slurm(
        bin.to_str().unwrap_or("stickslip"),
        &["sweep", "merge", out.to_str().unwrap_or("")],
    ))?;
    print!("{merged}");
    let lines = same_as_local(
        &bin,
        &sweep,
        &out,
        &dir.join("out").join("local"),
        "the Slurm map.csv",
    )?;
    println!(
        "slurm-check: map.csv from {TASKS} concurrent Slurm tasks equals the local run's in \
         every column but wall_s ({} points)",
        lines - 1
    );
    check_refined(root, &dir, &bin, &slurm)
}

/// The refined sweep: one array per level, chained by `sweep slurm --submit`; every task exits
/// 0 and the merged map equals a local run's (see the module docs).
fn check_refined(
    root: &Path,
    dir: &Path,
    bin: &Path,
    slurm: &dyn Fn(&str, &[&str]) -> Command,
) -> Result<(), String> {
    let sweep = root.join(REFINED);
    let out = dir.join("out").join("refined");
    let program = bin.to_str().unwrap_or("stickslip");
    let submitted = run(&mut slurm(
        program,
        &[
            "sweep",
            "slurm",
            sweep.to_str().unwrap_or(REFINED),
            "--out",
            out.to_str().unwrap_or(""),
            "--tasks",
            &REFINED_TASKS.to_string(),
            "--submit",
        ],
    ))?;
    print!("{submitted}");
    let started = Instant::now();
    wait_for("the refined sweep's arrays to finish", || {
        run(&mut slurm(
            "squeue",
            &["-h", "-n", "stickslip-slurm-check-refine"],
        ))
        .is_ok_and(|s| s.trim().is_empty())
    })?;
    let lock = stickslip_studies::sweep::exec::load_lock(&out).map_err(|e| e.to_string())?;
    let levels = lock.sweep.refine.as_ref().map_or(0, |r| r.levels as usize);
    println!(
        "slurm-check: the refined sweep's {} arrays ran in {:.1} s",
        levels + 1,
        started.elapsed().as_secs_f64()
    );
    let log = std::fs::read_to_string(dir.join("slurmctld.log")).map_err(|e| e.to_string())?;
    let exits: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("_job_complete") && l.contains("WEXITSTATUS"))
        .collect();
    if let Some(bad) = exits.iter().find(|l| !l.contains("WEXITSTATUS 0")) {
        return Err(format!("a task failed: {bad}"));
    }
    // The first sweep's tasks, each level's array, and the merge after the last one.
    let expected = TASKS + REFINED_TASKS * (levels + 1) + 1;
    if exits.len() != expected {
        return Err(format!(
            "slurmctld.log shows the exit status of {} jobs, not {expected} ({TASKS} of the \
             first sweep, {REFINED_TASKS} per level of the refined one and its merge)",
            exits.len()
        ));
    }
    if !out.join("map.csv").is_file() {
        return Err(format!(
            "the refined sweep's arrays ended without a map in {}",
            out.display()
        ));
    }
    same_as_local(
        bin,
        &sweep,
        &out,
        &dir.join("out").join("refined-local"),
        "the refined sweep's Slurm map.csv",
    )?;
    let table = MapTable::read(&out).map_err(|e| e.to_string())?;
    let refined = table.rows.iter().filter(|r| r.level > 0).count();
    if refined == 0 {
        return Err("the refined sweep's map has no point beyond the base grid".into());
    }
    println!(
        "slurm-check: the refined sweep ({} levels, {} arrays of {REFINED_TASKS} tasks and a \
         merge, each after the one before, all exited 0) equals the local run's map in every column \
         but wall_s ({} points, {refined} of them refined)",
        levels,
        levels + 1,
        table.rows.len()
    );
    Ok(())
}

/// Checks what the array did in `out`: the options reached every task (the script's `sweep
/// run` line; each point's output kept), every task exited 0, and the tasks overlapped.
fn check_array(dir: &Path, out: &Path) -> Result<(), String> {
    let script = std::fs::read_to_string(out.join("sweep.sbatch")).map_err(|e| e.to_string())?;
    let line = script
        .lines()
        .find(|l| l.contains(" sweep run "))
        .ok_or("the script has no `sweep run` line")?;
    if !(line.contains("--allow-large") && line.contains("--keep all")) {
        return Err(format!(
            "the script's tasks do not carry --allow-large --keep all: {line}"
        ));
    }
    let kept = std::fs::read_dir(out.join("runs")).map_or(0, Iterator::count);
    let points = stickslip_studies::sweep::exec::load_lock(out)
        .map_err(|e| e.to_string())?
        .sweep
        .points;
    if kept != points {
        return Err(format!(
            "--keep all did not reach the tasks: {kept} of {points} points kept their output"
        ));
    }
    let log = std::fs::read_to_string(dir.join("slurmctld.log")).map_err(|e| e.to_string())?;
    let spans = task_spans(&log);
    let exits: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("_job_complete") && l.contains("WEXITSTATUS"))
        .collect();
    if let Some(bad) = exits.iter().find(|l| !l.contains("WEXITSTATUS 0")) {
        return Err(format!("a task failed: {bad}"));
    }
    if exits.len() != TASKS {
        return Err(format!(
            "slurmctld.log shows the exit status of {} tasks, not {TASKS}",
            exits.len()
        ));
    }
    let overlapping = spans
        .iter()
        .map(|&(start, _)| {
            spans
                .iter()
                .filter(|&&(s, e)| s <= start && start < e)
                .count()
        })
        .max()
        .unwrap_or(0);
    println!(
        "slurm-check: {} tasks ran, {} at once at most, all exited 0 (slurmctld.log); the \
         script carried --allow-large --keep all, and each of the {points} points kept its \
         output",
        spans.len(),
        overlapping
    );
    if spans.len() != TASKS || overlapping < 2 {
        return Err(format!(
            "expected {TASKS} tasks running at the same time, the log shows {} tasks, {} at \
             once at most",
            spans.len(),
            overlapping
        ));
    }
    Ok(())
}

/// Seconds of the day of a slurmctld log line's `[YYYY-MM-DDTHH:MM:SS.mmm]` stamp.
fn stamp_s(line: &str) -> Option<f64> {
    let t = line
        .strip_prefix('[')?
        .split(']')
        .next()?
        .split('T')
        .nth(1)?;
    let mut parts = t.split(':');
    let h: f64 = parts.next()?.parse().ok()?;
    let m: f64 = parts.next()?.parse().ok()?;
    let s: f64 = parts.next()?.parse().ok()?;
    Some(h * 3600.0 + m * 60.0 + s)
}

/// (start, end) of each array task in slurmctld's log: from `sched: Allocate JobId=A_I` to
/// `_job_complete: JobId=A_I`.
fn task_spans(log: &str) -> Vec<(f64, f64)> {
    let id = |line: &str, after: &str| {
        line.split(after)
            .nth(1)
            .and_then(|r| r.split_whitespace().next())
            .map(|s| s.split('(').next().unwrap_or(s).to_string())
    };
    let mut starts = std::collections::BTreeMap::new();
    let mut spans = Vec::new();
    for line in log.lines() {
        let Some(t) = stamp_s(line) else { continue };
        if line.contains("Allocate JobId=") {
            if let Some(job) = id(line, "Allocate JobId=") {
                starts.insert(job, t);
            }
        } else if line.contains("_job_complete: JobId=")
            && line.contains("done")
            && let Some(job) = id(line, "_job_complete: JobId=")
            && let Some(start) = starts.remove(&job)
        {
            spans.push((start, t));
        }
    }
    spans
}

/// Runs the check; exit 0 on success, 1 on a failed check or error.
pub fn main(root: PathBuf) -> ExitCode {
    match check_all(&root) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("slurm-check: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The whole check; the daemons it started are stopped before it returns, also on failure.
pub fn check_all(root: &Path) -> Result<(), String> {
    let mut daemons = Daemons(Vec::new());
    let result = check(root, &mut daemons);
    drop(daemons);
    result.map_err(|e| {
        let dir = root.join("target").join("slurm-check");
        format!("{e} (logs in {})", dir.display())
    })
}
