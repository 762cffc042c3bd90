//! `stickslip sweep run | merge | slurm | plot`: friction maps (docs/reference.md, "Sweeps").
//!
//! Exit status: 0 done (a shard whose map is not complete yet also exits 0: it did its part,
//! and so does one whose closing merge met an I/O error: `sweep merge` finishes it); 2 a bad
//! sweep file or arguments, an output directory that cannot be written, a directory holding
//! another sweep without `--force`, a record of another sweep in it, or a directory another
//! sweep took over while this one ran; 4 the map is complete but some points failed
//! numerically or were refused (their rows say so; the other points are valid results); 5
//! `merge` of an incomplete sweep; 130 interrupted (finished points are kept, a rerun skips
//! them); 1 an I/O error.

use clap::{Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::sync::atomic::Ordering;
use stickslip_run::exit::Exit;
use stickslip_studies::sweep::exec::{
    self, Merge, MergeCost, Prepared, SweepOptions, SweepProgress, SweepRunError,
};
use stickslip_studies::sweep::map::MapJson;
use stickslip_studies::sweep::{Sweep, slurm};

/// What to keep of each point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Keep {
    /// Only the point's record (summary and regime).
    Summary,
    /// Also its full output (series.csv, events.csv, … in DIR/runs/<point>/).
    All,
}

/// The sweep subcommands.
#[derive(Debug, Subcommand)]
pub enum SweepCommand {
    /// Run the points of a sweep in-process (skipping finished ones) and merge when complete.
    Run {
        /// Sweep file (TOML).
        sweep: PathBuf,
        /// Sweep directory (points/, map.csv, map.json).
        #[arg(long)]
        out: PathBuf,
        /// Points run in parallel [default: the available cores].
        #[arg(long, value_name = "J", value_parser = clap::value_parser!(u64).range(1..))]
        jobs: Option<u64>,
        /// Run only the points with index mod N = I.
        #[arg(long, value_name = "I/N", value_parser = parse_shard)]
        shard: Option<(usize, usize)>,
        /// What to keep of each point.
        #[arg(long, value_enum, default_value_t = Keep::Summary)]
        keep: Keep,
        /// Start afresh: remove the directory's earlier results (of another sweep, or of this
        /// one) first.
        #[arg(long)]
        force: bool,
        /// Allow more than 100000 points (at most 10000000).
        #[arg(long)]
        allow_large: bool,
        /// No progress display.
        #[arg(long)]
        quiet: bool,
    },
    /// Merge the point records of DIR (shards run elsewhere) into map.csv and map.json.
    Merge {
        /// Sweep directory.
        dir: PathBuf,
        /// Wait up to SECONDS for the sweep to appear and its points to be complete, then merge
        /// (a merge started with the shards, or a dependent job).
        #[arg(long, value_name = "SECONDS", value_parser = parse_wait)]
        wait: Option<f64>,
    },
    /// Write DIR/sweep.sbatch, a Slurm job array of N tasks (task i runs shard i/N).
    Slurm {
        /// Sweep file (TOML).
        sweep: PathBuf,
        /// Sweep directory.
        #[arg(long)]
        out: PathBuf,
        /// Number of array tasks.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
        tasks: u64,
        /// Submit with sbatch and print the job id and the merge command.
        #[arg(long)]
        submit: bool,
        /// An extra #SBATCH argument, e.g. --sbatch-arg=--partition=short (repeatable).
        #[arg(long = "sbatch-arg", value_name = "ARG", allow_hyphen_values = true)]
        sbatch_arg: Vec<String>,
        /// Start afresh: remove the directory's earlier results (of another sweep, or of this
        /// one) now, when the directory is prepared; the tasks do not repeat it.
        #[arg(long)]
        force: bool,
        /// Allow more than 100000 points (at most 10000000); the tasks run with it too.
        #[arg(long)]
        allow_large: bool,
        /// What the tasks keep of each point.
        #[arg(long, value_enum, default_value_t = Keep::Summary)]
        keep: Keep,
    },
    /// Render the map of DIR as SVG: regimes as colours and one quantity with a colour bar.
    Plot {
        /// Sweep directory: finished (map.json), or unfinished (its point records so far; the
        /// missing points are drawn as not run yet).
        dir: PathBuf,
        /// The quantity of the second panel: any numeric column of map.csv (n_events,
        /// t_first_onset, period_last, x_period_last, f_peak_first, f_peak_last, f_mean,
        /// recovery, melted_time_fraction, wall_s, n_slips, slip_interval_median,
        /// melting_interval_median, energy_per_cycle) or a numeric axis key.
        #[arg(long, default_value = "recovery")]
        quantity: String,
        /// Output file [default: DIR/map_<quantity>.svg].
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("{s:?} is not a shard; allowed: I/N with 0 <= I < N, e.g. 0/4");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

fn parse_wait(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && (0.0..=1e7).contains(&x) => Ok(x),
        _ => Err(format!(
            "{s:?} is not a waiting time; allowed: seconds from 0 to 1e7, e.g. 3600"
        )),
    }
}

fn sweep_error(e: &SweepRunError) -> ExitCode {
    crate::fail(e, e.exit())
}

/// "from 4 shard tables", "from 12 records", … of a merge.
fn cost_text(cost: &MergeCost) -> String {
    let source = match (cost.tables_read, cost.records_read) {
        (0, 0) => "nothing read".to_string(),
        (t, 0) => format!("from {t} shard tables"),
        (0, r) => format!("from {r} records"),
        (t, r) => format!("{t} shard tables and {r} records read"),
    };
    format!("{source}, {:.3} s", cost.seconds)
}

/// What `prepare` found, said.
fn report_prepared(dir: &Path, prepared: &Prepared) {
    if let Some(build) = &prepared.previous_build {
        say!(
            "{} holds this sweep computed by build {build}; this is build {}: its points are \
             recomputed",
            dir.display(),
            stickslip_run::build_id::BUILD_ID
        );
    }
    if let Some(why) = &prepared.repaired {
        say!(
            "{}: its sweep.json could not be read ({why}); rewritten for this sweep (each point \
             record is still checked against it)",
            dir.display()
        );
    }
    if prepared.started_afresh {
        say!("--force: earlier results in {} removed", dir.display());
    }
}

/// Prints the merge's outcome; the exit status.
fn report_merge(dir: &Path, merge: &Merge, after_shard: bool) -> ExitCode {
    match merge {
        Merge::Complete {
            table,
            statuses,
            regimes,
            cost,
        } => {
            let regimes: Vec<String> = regimes
                .iter()
                .map(|(r, n)| format!("{} {n}", r.name()))
                .collect();
            let statuses: Vec<String> = statuses.iter().map(|(s, n)| format!("{s} {n}")).collect();
            say!(
                "map: {} points ({}); regimes: {}; written {} and {} ({})",
                table.rows.len(),
                statuses.join(", "),
                regimes.join(", "),
                dir.join("map.csv").display(),
                dir.join("map.json").display(),
                cost_text(cost)
            );
            let bad = table
                .rows
                .iter()
                .filter(|r| r.status.name() != "ok")
                .count();
            if bad > 0 {
                eprintln!(
                    "warning: {bad} points failed or were refused: their rows in map.csv give \
                     the status and the message (exit {})",
                    Exit::FailedPoints.code()
                );
                return crate::code(Exit::FailedPoints);
            }
            ExitCode::SUCCESS
        }
        Merge::Incomplete {
            missing,
            points,
            other_build,
            ..
        } => {
            if after_shard {
                say!(
                    "{missing} of {points} points in shards that have not finished yet; the \
                     last shard to finish merges (or: stickslip sweep merge {})",
                    dir.display()
                );
                ExitCode::SUCCESS
            } else {
                let stale = if *other_build > 0 {
                    format!(
                        " ({other_build} of them computed by another build, which is recomputed \
                         when they run again)"
                    )
                } else {
                    String::new()
                };
                crate::fail(
                    format!(
                        "{missing} of {points} points of {} have no record of this build yet{stale}: \
                         run the missing shards (finished points are skipped), then merge again",
                        dir.display()
                    ),
                    Exit::Incomplete,
                )
            }
        }
    }
}

/// Progress display: a bar on a terminal, else a line every ten seconds.
struct Display {
    bar: Option<ProgressBar>,
    quiet: bool,
    last_line_s: f64,
}

impl Display {
    fn new(quiet: bool) -> Self {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template(
                "{elapsed_precise} [{wide_bar}] {pos}/{len} points, {msg}",
            ) {
                bar.set_style(style);
            }
            bar
        });
        Self {
            bar,
            quiet,
            last_line_s: 0.0,
        }
    }

    fn update(&mut self, p: &SweepProgress) {
        if let Some(bar) = &self.bar {
            bar.set_length(p.total as u64);
            bar.set_position(p.done as u64);
            // The rate of the points run by this invocation (skipped ones cost nothing).
            let run = p.done.saturating_sub(p.skipped) as f64;
            let to_run = p.total.saturating_sub(p.skipped) as f64;
            let eta = crate::progress::eta_text(p.elapsed_s, run / to_run.max(1.0));
            bar.set_message(format!(
                "{} failed, {} skipped, eta {eta}",
                p.failed, p.skipped
            ));
        } else if !self.quiet && p.elapsed_s - self.last_line_s >= 10.0 {
            self.last_line_s = p.elapsed_s;
            eprintln!(
                "sweep: {}/{} points, {} failed, {:.0} s",
                p.done, p.total, p.failed, p.elapsed_s
            );
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn run(
    path: &Path,
    dir: &Path,
    jobs: Option<u64>,
    shard: Option<(usize, usize)>,
    keep: Keep,
    force: bool,
    allow_large: bool,
    quiet: bool,
) -> ExitCode {
    let sweep = match Sweep::load(path, allow_large) {
        Ok(s) => s,
        Err(e) => return crate::fail(e, Exit::BadInput),
    };
    match exec::prepare(&sweep, dir, force) {
        Ok(prepared) => report_prepared(dir, &prepared),
        Err(e) => return sweep_error(&e),
    }
    let flag = match crate::interrupt_flag() {
        Ok(f) => f,
        Err(e) => return crate::fail(format!("cannot install signal handlers: {e}"), Exit::Io),
    };
    let jobs = jobs.map_or_else(
        || std::thread::available_parallelism().map_or(1, usize::from),
        |j| usize::try_from(j).unwrap_or(1),
    );
    let options = SweepOptions {
        jobs,
        shard: shard.unwrap_or((0, 1)),
        keep_all: keep == Keep::All,
        force,
    };
    let mut display = Display::new(quiet);
    let report = exec::run_shard(&sweep, dir, &options, Some(&flag), &mut |p| {
        display.update(p)
    });
    if let Some(bar) = &display.bar {
        bar.finish_and_clear();
    }
    let report = match report {
        Ok(r) => r,
        Err(e) => return sweep_error(&e),
    };
    let (i, n) = options.shard;
    say!(
        "sweep {}: shard {i}/{n}: {} points run ({} failed, {} refused), {} already done, {:.2} s \
         on {jobs} jobs",
        sweep.name,
        report.ran,
        report.failed,
        report.refused,
        report.skipped,
        report.wall_s
    );
    let again = report.recomputed_text();
    if !again.is_empty() {
        say!("{again}");
    }
    if report.interrupted || flag.load(Ordering::Relaxed) {
        eprintln!("interrupted: finished points are kept; rerun the same command to run the rest");
        return crate::code(Exit::Interrupted);
    }
    if let Some(w) = report.waiting {
        // A refined sweep's next level is decided by every shard's results of this one.
        say!(
            "shard {i}/{n} waits at level {}: {} of its points in other shards are not \
             finished; rerun this shard once they are (it skips what is done and goes on with \
             level {}); `sweep slurm --submit` submits one dependent array per level",
            w.level,
            w.missing,
            w.level + 1
        );
        return ExitCode::SUCCESS;
    }
    let then_checks = |m: &Merge, code: ExitCode| {
        if matches!(m, Merge::Complete { .. }) {
            crate::spot::after_map(&sweep, dir, jobs, &flag, quiet, code)
        } else {
            code
        }
    };
    if let Some(m) = &report.map {
        // A refined sweep: the shard that found every level complete wrote the map.
        return then_checks(m, report_merge(dir, m, true));
    }
    match exec::after_shard(dir, &sweep.fingerprint(), options.shard) {
        Ok(m) => then_checks(&m, report_merge(dir, &m, true)),
        // The shard's points are done and recorded: a merge that cannot write is not a
        // failed shard; `sweep merge` finishes it.
        Err(e @ SweepRunError::Io { .. }) => {
            eprintln!(
                "warning: the shard's points are done, but its closing merge failed: {e}; \
                 merge with: stickslip sweep merge {}",
                dir.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => sweep_error(&e),
    }
}

#[allow(clippy::too_many_arguments)]
fn submit_slurm(
    path: &Path,
    dir: &Path,
    tasks: u64,
    submit: bool,
    extra: &[String],
    force: bool,
    allow_large: bool,
    keep: Keep,
) -> ExitCode {
    if let Err(e) = slurm::check_extra(extra) {
        return crate::fail(e, Exit::BadInput);
    }
    let sweep = match Sweep::load(path, allow_large) {
        Ok(s) => s,
        Err(e) => return crate::fail(e, Exit::BadInput),
    };
    match exec::prepare(&sweep, dir, force) {
        Ok(prepared) => report_prepared(dir, &prepared),
        Err(e) => return sweep_error(&e),
    }
    // Every option the sweep runs with goes to the tasks (but --force, applied just now: a
    // task repeating it would remove the points of the others).
    let mut run_args = Vec::new();
    if allow_large {
        run_args.push("--allow-large".to_string());
    }
    if keep == Keep::All {
        run_args.extend(["--keep".to_string(), "all".to_string()]);
    }
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let binary = crate::program();
    let tasks = usize::try_from(tasks).unwrap_or(1);
    let text = slurm::script(
        &sweep.name,
        &binary,
        &abs(path),
        &abs(dir),
        tasks,
        extra,
        &run_args,
        sweep.refine.as_ref().map(|r| r.levels),
    );
    let script = dir.join(slurm::SCRIPT);
    if let Err(e) = std::fs::create_dir_all(dir.join("slurm"))
        .and_then(|()| stickslip_run::atomic::write_atomic(dir, slurm::SCRIPT, text.as_bytes()))
    {
        return crate::fail(format!("cannot write {}: {e}", script.display()), Exit::Io);
    }
    match &sweep.refine {
        None => say!(
            "wrote {} ({} points in {tasks} tasks)",
            script.display(),
            sweep.points
        ),
        Some(r) => say!(
            "wrote {} (a refined sweep: {} base points, then {} levels, in {tasks} tasks; one \
             array per level)",
            script.display(),
            r.base.iter().product::<usize>(),
            r.levels
        ),
    }
    if !submit {
        let levels = sweep.refine.as_ref().map_or(0, |r| r.levels);
        if levels == 0 {
            say!("submit with: sbatch {}", script.display());
        } else {
            say!(
                "submit with --submit, or by hand one array per level, each after the one \
                 before: ID=$(sbatch --parsable {0}), then {levels} times ID=$(sbatch \
                 --parsable --dependency=afterok:$ID {0}), then sbatch \
                 --dependency=afterok:$ID --wrap \"stickslip sweep merge {1}\"",
                script.display(),
                dir.display()
            );
        }
        return ExitCode::SUCCESS;
    }
    // A refined sweep: one array per level, each after the previous one ended well (its
    // tasks' results decide the next level's points).
    let waves = sweep.refine.as_ref().map_or(1, |r| r.levels as usize + 1);
    let mut previous: Option<String> = None;
    for wave in 0..waves {
        let mut cmd = Command::new("sbatch");
        cmd.arg("--parsable");
        if let Some(id) = &previous {
            cmd.arg(format!("--dependency=afterok:{id}"));
        }
        match cmd.arg(&script).output() {
            Ok(out) if out.status.success() => {
                let text = String::from_utf8_lossy(&out.stdout);
                // --parsable prints `ID` or `ID;CLUSTER`.
                let id = text.trim().split(';').next().unwrap_or("").to_string();
                if waves > 1 {
                    say!(
                        "submitted job {id} (level {wave} of {}{})",
                        waves - 1,
                        previous
                            .as_ref()
                            .map_or_else(String::new, |p| format!(", after job {p}"))
                    );
                } else {
                    say!("submitted job {id}");
                }
                previous = Some(id);
            }
            Ok(out) => {
                return crate::fail(
                    format!(
                        "sbatch failed ({}): {}",
                        out.status,
                        String::from_utf8_lossy(&out.stderr).trim()
                    ),
                    Exit::Io,
                );
            }
            Err(e) => return crate::fail(format!("cannot run sbatch: {e}"), Exit::Io),
        }
    }
    if waves > 1 {
        // Tasks of the last array finishing together may each see the others' points
        // missing: a merge after the last array writes the map whatever the order.
        let mut cmd = Command::new("sbatch");
        cmd.args([
            "--parsable".to_string(),
            format!("--dependency=afterok:{}", previous.unwrap_or_default()),
            format!("--job-name=stickslip-{}", sweep.name),
            format!(
                "--output={}",
                abs(dir).join("slurm").join("merge-%j.out").display()
            ),
        ]);
        for arg in extra {
            cmd.arg(arg);
        }
        cmd.arg(format!(
            "--wrap={}",
            slurm::merge_command(&binary, &abs(dir))
        ));
        match cmd.output() {
            Ok(out) if out.status.success() => {
                let text = String::from_utf8_lossy(&out.stdout);
                let id = text.trim().split(';').next().unwrap_or("");
                say!("submitted job {id} (the merge, after the last level)");
            }
            Ok(out) => {
                return crate::fail(
                    format!(
                        "sbatch of the merge failed ({}): {}; merge by hand once the arrays \
                         ended: stickslip sweep merge {}",
                        out.status,
                        String::from_utf8_lossy(&out.stderr).trim(),
                        dir.display()
                    ),
                    Exit::Io,
                );
            }
            Err(e) => return crate::fail(format!("cannot run sbatch: {e}"), Exit::Io),
        }
        say!("to merge by hand: stickslip sweep merge {}", dir.display());
        return ExitCode::SUCCESS;
    }
    say!(
        "the last task to finish writes the map; to merge by hand: stickslip sweep merge {}",
        dir.display()
    );
    ExitCode::SUCCESS
}

fn plot(dir: &Path, quantity: &str, out: Option<PathBuf>) -> ExitCode {
    // A finished sweep has map.json; an unfinished one (running, interrupted, shards
    // elsewhere) is drawn from the point records there are, its missing points marked.
    let json = match MapJson::read(dir) {
        Ok(j) => j,
        Err(e) => match stickslip_studies::sweep::merge::read_map(dir) {
            Ok(read) => {
                if !read.complete {
                    say!(
                        "sweep {}: {} of {} points so far; the missing ones are drawn as \
                         not run yet",
                        read.sweep.name,
                        read.table.rows.len(),
                        read.points
                    );
                }
                MapJson::new(&read.sweep, read.table)
            }
            Err(partial) => {
                // A damaged map.json is the news; else why the directory holds no sweep.
                let why = if dir.join(stickslip_studies::sweep::map::JSON_FILE).exists() {
                    e.to_string()
                } else {
                    partial.to_string()
                };
                return crate::fail(why, Exit::BadInput);
            }
        },
    };
    let panels = match stickslip_report::map::panels(&json, quantity) {
        Ok(p) => p,
        Err(e) => return crate::fail(e, Exit::BadInput),
    };
    let svg = match stickslip_report::plot::render_svg(
        &panels,
        2,
        stickslip_report::map::PANEL_PX.0,
        stickslip_report::map::PANEL_PX.1,
    ) {
        Ok(s) => s,
        Err(e) => return crate::fail(format!("cannot draw the map: {e}"), Exit::Io),
    };
    let path = out.unwrap_or_else(|| dir.join(format!("map_{quantity}.svg")));
    match stickslip_report::write_atomic(&path, svg.as_bytes()) {
        Ok(()) => {
            say!("wrote {}", path.display());
            ExitCode::SUCCESS
        }
        Err(e) => crate::fail(format!("cannot write {}: {e}", path.display()), Exit::Io),
    }
}

/// Runs a sweep subcommand.
pub fn main(cmd: SweepCommand) -> ExitCode {
    match cmd {
        SweepCommand::Run {
            sweep,
            out,
            jobs,
            shard,
            keep,
            force,
            allow_large,
            quiet,
        } => run(&sweep, &out, jobs, shard, keep, force, allow_large, quiet),
        SweepCommand::Merge { dir, wait } => {
            let merged = match wait {
                Some(s) => exec::merge_wait(&dir, std::time::Duration::from_secs_f64(s)),
                None => exec::merge(&dir),
            };
            match merged {
                Ok(m) => {
                    let built = exec::load_lock(&dir).map(|l| l.build).unwrap_or_default();
                    let now = stickslip_run::build_id::BUILD_ID;
                    if matches!(m, Merge::Complete { .. }) && built != now {
                        say!(
                            "note: the points were computed by build {}, this binary is build \
                             {now}; `stickslip sweep run` with this binary recomputes them",
                            if built.is_empty() {
                                "of an earlier version"
                            } else {
                                &built
                            }
                        );
                    }
                    let code = report_merge(&dir, &m, false);
                    match (&m, exec::load_lock(&dir)) {
                        (Merge::Complete { .. }, Ok(lock)) if lock.sweep.verify.is_some() => {
                            let flag = match crate::interrupt_flag() {
                                Ok(f) => f,
                                Err(e) => {
                                    return crate::fail(
                                        format!("cannot install signal handlers: {e}"),
                                        Exit::Io,
                                    );
                                }
                            };
                            let jobs = std::thread::available_parallelism().map_or(1, usize::from);
                            crate::spot::after_map(&lock.sweep, &dir, jobs, &flag, false, code)
                        }
                        _ => code,
                    }
                }
                Err(e) => sweep_error(&e),
            }
        }
        SweepCommand::Slurm {
            sweep,
            out,
            tasks,
            submit,
            sbatch_arg,
            force,
            allow_large,
            keep,
        } => submit_slurm(
            &sweep,
            &out,
            tasks,
            submit,
            &sbatch_arg,
            force,
            allow_large,
            keep,
        ),
        SweepCommand::Plot { dir, quantity, out } => plot(&dir, &quantity, out),
    }
}
