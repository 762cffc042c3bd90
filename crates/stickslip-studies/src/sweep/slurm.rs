//! The Slurm job-array script of a sweep: task i of N runs `stickslip sweep run SWEEP --out
//! DIR --shard i/N` with every option the sweep was prepared with (`--allow-large`, `--keep`),
//! reading its index from `SLURM_ARRAY_TASK_ID`. Sites cap array sizes, so the number of tasks
//! is a setting, not the number of points; a failed task reruns by index (`sbatch --array=4,8
//! DIR/sweep.sbatch`) and skips the points it had finished. The tasks run at the same time on
//! one directory; each writes its shard's table, and the last to finish merges them into the
//! map (`super::merge`): one merge of O(P) for the array.
//!
//! A refined sweep (`[refine]`, levels L) is submitted as L + 1 arrays of this one script,
//! each after the previous one ended well (`--dependency=afterok:ID`): the tasks of array k
//! skip the levels done, compute level k's points from the records and run their part, and a
//! task whose level is still missing other tasks' points exits 0 (the next array goes on).
//! After array k every point of level k is done, whatever the order of its tasks; tasks of the
//! last array finishing together may each see the others' points missing, so a merge job
//! ([`merge_command`]) follows the last array. No task waits on another inside an array, so
//! a site running fewer tasks at once than the array has cannot deadlock.

use std::path::Path;

/// File name of the script in the sweep directory.
pub const SCRIPT: &str = "sweep.sbatch";

/// The text of the job-array script.
///
/// `binary`, `sweep_file` and `dir` should be absolute (the job runs wherever Slurm starts
/// it); `extra` are additional `#SBATCH` lines' arguments (`--partition=short`, …);
/// `run_args` are options of `sweep run` every task passes (`--allow-large`, `--keep all`).
/// `levels`: a refined sweep's levels, said in a comment (the script is submitted once per
/// level and once for the base grid).
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn script(
    name: &str,
    binary: &Path,
    sweep_file: &Path,
    dir: &Path,
    tasks: usize,
    extra: &[String],
    run_args: &[String],
    levels: Option<u32>,
) -> String {
    let q = |p: &Path| shell_quote(&p.display().to_string());
    let mut out = String::from("#!/bin/bash\n");
    out.push_str(&format!(
        "#SBATCH --job-name={}\n",
        shell_quote(&format!("stickslip-{name}"))
    ));
    out.push_str(&format!("#SBATCH --array=0-{}\n", tasks.saturating_sub(1)));
    out.push_str(&format!(
        "#SBATCH --output={}\n",
        q(&dir.join("slurm").join("%A_%a.out"))
    ));
    for arg in extra {
        out.push_str(&format!("#SBATCH {}\n", sbatch_quote(arg)));
    }
    out.push_str(&format!(
        "# {tasks} tasks; task i runs the points with index mod {tasks} = i. Rerun failed tasks \
         by index: sbatch --array=4,8 {}\n",
        q(&dir.join(SCRIPT))
    ));
    if let Some(levels) = levels.filter(|&l| l > 0) {
        out.push_str(&format!(
            "# A refined sweep of {levels} levels: submit this script {} times, each after the \
             previous array ended well (sbatch --dependency=afterok:ID); each array's tasks run \
             their part of the next level; then `stickslip sweep merge` after the last one \
             (`stickslip sweep slurm --submit` does this).\n",
            levels + 1
        ));
    }
    out.push_str("set -uo pipefail\n");
    let options: String = run_args
        .iter()
        .map(|a| format!(" {}", shell_quote(a)))
        .collect();
    out.push_str(&format!(
        "{} sweep run {} --out {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{tasks}\" --jobs \
         \"${{SLURM_CPUS_PER_TASK:-1}}\"{options} --quiet\n",
        q(binary),
        q(sweep_file),
        q(dir)
    ));
    // Exit 4 (the map is complete but has failed points) is a result, not a failed task.
    out.push_str("status=$?\nif [ \"$status\" -eq 4 ]; then exit 0; fi\nexit \"$status\"\n");
    out
}

/// The shell command of the merge job after a refined sweep's last array: `sweep merge DIR`,
/// exit 4 (a complete map with failed points) counted as success, as the tasks do.
#[must_use]
pub fn merge_command(binary: &Path, dir: &Path) -> String {
    format!(
        "{} sweep merge {}; status=$?; if [ \"$status\" -eq 4 ]; then exit 0; fi; exit \"$status\"",
        shell_quote(&binary.display().to_string()),
        shell_quote(&dir.display().to_string())
    )
}

/// Checks the arguments of extra `#SBATCH` lines: one line each, so no control character (a
/// newline would start a line of its own, which every task would run), and no `"` or `\\`,
/// which sbatch's quoting cannot carry.
///
/// # Errors
/// The first bad argument, escaped, with what is allowed.
pub fn check_extra(extra: &[String]) -> Result<(), BadSbatchArg> {
    match extra
        .iter()
        .find(|a| a.is_empty() || a.chars().any(|c| c.is_control() || c == '"' || c == '\\'))
    {
        None => Ok(()),
        Some(bad) => Err(BadSbatchArg(bad.clone())),
    }
}

/// An extra `#SBATCH` argument that one script line cannot carry (see [`check_extra`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "--sbatch-arg {0:?} is invalid; allowed: one non-empty #SBATCH argument on one line, \
     without control characters (newlines, tabs, …), `\"` or `\\`"
)]
pub struct BadSbatchArg(pub String);

/// An `#SBATCH` argument as written in the script: plain when it is one word of safe
/// characters, else in double quotes (sbatch splits its lines at spaces outside them).
fn sbatch_quote(arg: &str) -> String {
    if arg
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || "/._-+%=:,@".contains(c))
    {
        arg.to_string()
    } else {
        format!("\"{arg}\"")
    }
}

/// `s` in single quotes for the shell (plain when it needs none).
#[must_use]
pub fn shell_quote(s: &str) -> String {
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-+%=:".contains(c))
    {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}
