//! The `stickslip` command line: `run`, `check`, `resume`, `sweep`, `boundary`, `verify`, `fit`
//! and `keys` (see
//! `docs/reference.md`).
//!
//! This crate holds arguments, progress, signals, printing and exit codes only; scenes, the
//! time loop and the output files are the run library's (`stickslip-run`). The program is this
//! library's [`main_from`]: the `stickslip` binary (`bin/stickslip.rs`) calls it with its
//! arguments, and so does the Python package's `stickslip` command (`pip install
//! ./crates/stickslip-py`), in the interpreter's process.
//!
//! Exit status: 0 success, 1 an I/O error while writing output, 2 bad scene or arguments
//! (clap usage errors included), an output directory holding an earlier run without
//! `--force`, or a checkpoint `resume` cannot continue (none, damaged, of an older format, or
//! of another build without `--allow-other-build`), 3 numerical failure (or a refused configuration), 4 a sweep whose map has
//! failed or refused points, 5 `sweep merge` with points missing, 130 interrupted (SIGINT/SIGTERM; a checkpoint is written, `resume` finishes the run).
//! Messages go to stderr, prefixed `error: `.

/// `println!` that ignores a closed stdout (e.g. `stickslip check … | head`) instead of
/// panicking: output nobody reads is not an error of the run.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}

/// `print!` that ignores a closed stdout (see `say!`).
macro_rules! say_raw {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout().lock(), $($arg)*);
    }};
}

mod boundary;
mod check;
mod fit;
mod out_dir;
mod progress;
mod reference;
mod spot;
mod sweep;
mod verify;

use clap::{Parser, Subcommand};
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use stickslip_core::preflight::{Finding, Severity};
use stickslip_run::checkpoint::CheckpointError;
use stickslip_run::cycles::StampRegime;
use stickslip_run::exit::Exit;
use stickslip_run::{DirOptions, ResumeOptions, RunError, RunOutcome, Scene, StopReason};
use stickslip_studies::options;

/// Stick–slip friction of a lubricant film under a flat stamp.
#[derive(Debug, Parser)]
#[command(name = "stickslip", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a scene and write series.csv, events.csv, profiles.csv, probes.csv and run.json.
    Run {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output directory (created if needed; refused if it holds an earlier run's results,
        /// unless --force).
        #[arg(long)]
        out: PathBuf,
        /// Override a scene value, e.g. `--set contact.nodes=200` (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// Remove a key the scene file sets before the --set values apply, e.g. `--unset
        /// drive.stiffness` (repeatable): its default applies, or a --set value.
        #[arg(long = "unset", value_name = "SECTION.KEY")]
        unset: Vec<String>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Replace the results of an earlier run in the output directory.
        #[arg(long)]
        force: bool,
        /// Wall-clock seconds between checkpoints in DIR, from which `resume` finishes a killed
        /// run; 0 = none (Ctrl-C still writes one).
        #[arg(long, value_name = "SECONDS", default_value_t = options::CHECKPOINT_EVERY_S, value_parser = parse_interval)]
        checkpoint_every: f64,
    },
    /// Validate a scene and print its resolved, derived and stability numbers, estimates of
    /// the first melting and the cost, and warnings.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Override a scene value (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// Remove a key the scene file sets before the --set values apply, e.g. `--unset
        /// drive.stiffness` (repeatable): its default applies, or a --set value.
        #[arg(long = "unset", value_name = "SECTION.KEY")]
        unset: Vec<String>,
    },
    /// Find where the regime changes along one key: a first scan of --scan points over the
    /// range (log-spaced when both ends are > 0), then every change between neighbouring
    /// points is bisected until its bracket is within --rtol and rerun at 2N and at a tenth of
    /// the tolerance; prints each change with its error (the bracket plus how far the change
    /// moves at the finer resolution) and warnings about changes the scan may have missed.
    /// The first two lines give the lowest change (value, bracket, regimes, runs). Exit 2
    /// when every scan point has the same regime, 3 when a run fails numerically.
    Boundary {
        /// Scene file (TOML).
        scene: PathBuf,
        /// The scene key to vary (a number, in its unit: see `stickslip keys`).
        #[arg(long, value_name = "SECTION.KEY")]
        key: String,
        /// One end of the range.
        #[arg(long = "from", value_name = "LO", allow_hyphen_values = true)]
        from: f64,
        /// The other end.
        #[arg(long = "to", value_name = "HI", allow_hyphen_values = true)]
        to: f64,
        /// Relative width of the final bracket: (hi − lo) ≤ rtol·max(|lo|, |hi|).
        #[arg(long, default_value_t = options::BOUNDARY_RTOL)]
        rtol: f64,
        /// Points of the first scan, the range's ends included (2: the ends only).
        #[arg(long, value_name = "N", default_value_t = options::BOUNDARY_SCAN)]
        scan: usize,
        /// Runs at a time.
        #[arg(long, default_value_t = options::JOBS)]
        jobs: usize,
        /// Which regime to follow: the film's (`regime`) or the stamp's (`stamp_regime`:
        /// where slips of the stamp stop recurring).
        #[arg(long, value_name = "SCALE", default_value = options::BOUNDARY_SCALE, value_parser = ["film", "stamp"])]
        scale: String,
        /// Override a scene value (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// Remove a key the scene file sets before the --set values apply, e.g. `--unset
        /// drive.stiffness` (repeatable): its default applies, or a --set value.
        #[arg(long = "unset", value_name = "SECTION.KEY")]
        unset: Vec<String>,
        /// No line per run on stderr.
        #[arg(long)]
        quiet: bool,
        /// Keep every run's regime in DIR/probes.jsonl as it ends: the same command with the
        /// same --out after an interrupt makes only the runs not kept yet.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// The error of every summary number of a scene: it runs at its own settings and refined
    /// in space (N, 2N, 4N) and in time (tolerance /10, /100; or Δt /2, /4) apart, and prints
    /// per quantity the value, its uncertainty (Celik's GCI, safety 1.25 in the asymptotic
    /// range, 3 outside), the extrapolated value, observed against theoretical orders and a
    /// verdict; writes DIR/verify.json. Exit 0 when every quantity is within --rtol, 4 when
    /// one is not (or not converged, or a discrete quantity changed), 2 for bad input.
    Verify {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Relative accuracy each quantity's uncertainty must be within.
        #[arg(long, default_value_t = options::VERIFY_RTOL)]
        rtol: f64,
        /// Instead of checking the scene's own resolution, search the cheapest N and
        /// time.tolerance whose estimated error of the first onset and of its peak force is
        /// within this relative error (runs to the first event: N doubling from 25, then the
        /// tolerance falling tenfold); prints the pair and its cost and writes
        /// DIR/resolution.toml (the pair as a scene's sections) and DIR/target.json. Exit 0
        /// when a pair is found, 4 when the node limit or the smallest tolerance comes first.
        #[arg(long, value_name = "REL")]
        target: Option<f64>,
        /// Directory of verify.json [default: a fresh verify-NAME]; checked before any run,
        /// refused when it holds files unless --force.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write over the files of an earlier result in --out.
        #[arg(long)]
        force: bool,
        /// Runs at a time.
        #[arg(long, default_value_t = options::JOBS)]
        jobs: usize,
        /// Override a scene value (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// Remove a key the scene file sets before the --set values apply, e.g. `--unset
        /// drive.stiffness` (repeatable): its default applies, or a --set value.
        #[arg(long = "unset", value_name = "SECTION.KEY")]
        unset: Vec<String>,
    },
    /// Fit scene parameters to a measured friction trace (docs/fit.md): a space-filling
    /// sample of the bounds, then bounded Levenberg–Marquardt with finite-difference
    /// Jacobians above the solver's noise (the fit's runs use time.tolerance/100, tightened
    /// tenfold at a time while that noise is large against the residuals); prints the
    /// values with standard errors, 95 % intervals, correlations and the combinations the data
    /// cannot determine; writes DIR/fit.json, DIR/fit.svg and DIR/fitted.toml (the scene with
    /// the fitted values: `stickslip run` reproduces the fitted model). Exit 2 for bad input
    /// (naming the field), 3 when no run of the optimiser succeeded, 130 when interrupted (the
    /// best fit so far written, status "interrupted").
    Fit {
        /// Scene file (TOML): the known parameters (K, m, V0, a0, …) and starting values.
        scene: PathBuf,
        /// The measured trace: CSV with a header line, columns t (s) and F (N), optionally X
        /// (m).
        #[arg(long, value_name = "TRACE.csv")]
        data: PathBuf,
        /// A free parameter: a scene key taking a number, with bounds (default: the key's
        /// usual range; searched in log space when both bounds are > 0). Repeatable.
        #[arg(long = "param", value_name = "KEY[=LO:HI]", required = true)]
        param: Vec<String>,
        /// What is compared: `events` (onsets, intervals, peak forces and drops, matched
        /// event by event) or `trace` (F at the data's times, with a fitted time shift).
        #[arg(long, value_name = "MISFIT", default_value = options::FIT_MISFIT, value_parser = ["events", "trace"])]
        misfit: String,
        /// Column names of the trace when not t, F and X, e.g. `t=time,F=force`.
        #[arg(long, value_name = "t=NAME,F=NAME")]
        columns: Option<String>,
        /// Standard deviation of the noise of F, N [default: estimated from the data].
        #[arg(long, value_name = "N", allow_hyphen_values = true)]
        noise: Option<f64>,
        /// Runs at a time.
        #[arg(long, default_value_t = options::JOBS)]
        jobs: usize,
        /// Also compute the profile likelihood of this parameter (one of --param's keys).
        #[arg(long, value_name = "KEY")]
        profile: Option<String>,
        /// How the Jacobians are made: `differences` (central, grown out of the solver's
        /// noise) or `replay` (forward differences of runs that take the point's own run's
        /// steps again: the derivative of the discrete solution, one run per parameter;
        /// adaptive steps).
        #[arg(long, value_name = "HOW", default_value = "differences", value_parser = ["differences", "replay"])]
        jacobian: String,
        /// Output directory [default: a fresh fit-NAME]; checked before any run, refused when
        /// it holds files unless --force.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write over the files of an earlier result in --out.
        #[arg(long)]
        force: bool,
        /// Override a scene value (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// Remove a key the scene file sets before the --set values apply, e.g. `--unset
        /// drive.stiffness` (repeatable): its default applies, or a --set value.
        #[arg(long = "unset", value_name = "SECTION.KEY")]
        unset: Vec<String>,
        /// No progress lines on stderr.
        #[arg(long)]
        quiet: bool,
    },
    /// Finish an interrupted run from its checkpoint; the output is bit-identical to that of
    /// an uninterrupted run (run.json's wall_seconds aside). The checkpoint must come from
    /// this build of the numerics: another build's is refused (exit 2), as its numbers would
    /// differ.
    Resume {
        /// Output directory of the interrupted run.
        dir: PathBuf,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Wall-clock seconds between checkpoints from here on; 0 = none [default: the run's].
        #[arg(long, value_name = "SECONDS", value_parser = parse_interval)]
        checkpoint_every: Option<f64>,
        /// Continue a checkpoint written by another build anyway (the numbers after the resume
        /// come from this build; run.json records it in resumed_across_builds).
        #[arg(long)]
        allow_other_build: bool,
    },
    /// Friction maps: parameter sweeps with regime classification.
    #[command(subcommand)]
    Sweep(sweep::SweepCommand),
    /// Every scene key with its unit, default, allowed range and meaning.
    Keys {
        /// Print the reference as Markdown (docs/reference.md is generated from it).
        #[arg(long)]
        markdown: bool,
    },
}

/// `--checkpoint-every`: seconds, finite and >= 0.
fn parse_interval(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!(
            "{s:?} is not a valid interval; allowed: a finite number of seconds >= 0 \
             (0 = no checkpoints)"
        )),
    }
}

/// Prints `message` as an error and returns the status of `exit`.
pub fn fail(message: impl std::fmt::Display, exit: Exit) -> ExitCode {
    eprintln!("error: {message}");
    code(exit)
}

/// The process's exit status for `exit`.
#[must_use]
pub fn code(exit: Exit) -> ExitCode {
    ExitCode::from(exit.code())
}

/// A flag set by SIGINT and SIGTERM.
///
/// # Errors
/// If the handlers cannot be installed.
pub fn interrupt_flag() -> std::io::Result<Arc<AtomicBool>> {
    let flag = Arc::new(AtomicBool::new(false));
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(signal, Arc::clone(&flag))?;
    }
    Ok(flag)
}

/// Prints findings of at least warning severity (and notes when `notes`) to stderr.
pub fn print_findings(findings: &[Finding], notes: bool) {
    for f in findings {
        match f.severity {
            Severity::Warning => eprintln!("warning: {}", f.message),
            Severity::Note if notes => eprintln!("note: {}", f.message),
            _ => {}
        }
    }
}

/// Reports the end of a run; the exit status.
fn report(name: &str, dir: &Path, outcome: &RunOutcome) -> ExitCode {
    match outcome.stop {
        StopReason::Interrupted => {
            eprintln!(
                "interrupted at t = {:e} s (step {}, {} events so far); the data so far is in \
                 {} (series.csv, events.csv, … as a finished run's), the checkpoint in {}\n\
                 resume with: stickslip resume {}",
                outcome.t_final_s,
                outcome.counts.steps,
                outcome.events.len(),
                dir.display(),
                stickslip_run::checkpoint::path(dir).display(),
                dir.display()
            );
            code(Exit::Interrupted)
        }
        StopReason::Failure | StopReason::Refused => {
            let failure = outcome
                .failure
                .as_ref()
                .map_or_else(String::new, ToString::to_string);
            fail(
                format!(
                    "{failure} (output up to the failure written to {})",
                    dir.display()
                ),
                Exit::Numerical,
            )
        }
        StopReason::End | StopReason::MaxEvents | StopReason::OpenEvent | StopReason::Periodic => {
            say!(
                "{name}: {} steps to t = {:e} s, {} melting events, {:.2} s wall; output in {}",
                outcome.counts.steps,
                outcome.t_final_s,
                outcome.events.len(),
                outcome.wall_seconds,
                dir.display()
            );
            say!("summary: {}", outcome.summary_line());
            ExitCode::SUCCESS
        }
    }
}

fn run_error(e: &RunError) -> ExitCode {
    fail(e, e.exit())
}

fn run(
    scene: &Path,
    out: &Path,
    (unset, set): (&[String], &[String]),
    quiet: bool,
    options: &DirOptions,
) -> ExitCode {
    let resolved = match Scene::from_path_unsetting(scene, unset, set) {
        Ok(r) => r,
        Err(e) => return fail(e, Exit::BadInput),
    };
    let flag = match interrupt_flag() {
        Ok(f) => f,
        Err(e) => return fail(format!("cannot install signal handlers: {e}"), Exit::Io),
    };
    let mut bar = progress::Bar::new(quiet);
    let mut poll = |p: &stickslip_run::driver::Progress| bar.update(p);
    let mut control = stickslip_run::Control {
        interrupt: Some(&flag),
        poll: Some(&mut poll),
        ..Default::default()
    };
    let mut warn = |findings: &[Finding]| print_findings(findings, false);
    control.on_start = Some(&mut warn);
    let result = stickslip_run::run_to_dir(&resolved, out, options, &mut control);
    bar.finish();
    match result {
        Ok(outcome) => {
            let code = report(&resolved.name, out, &outcome);
            // Asked to stop once the cycles repeat, and they did not: say why.
            if resolved.steady.stop
                && outcome.stop == StopReason::End
                && let Some(why) = resolved.steady.why_not(&outcome.events)
            {
                // The stamp's scale: slips that do not repeat either, or none to repeat.
                let s = &outcome.summary;
                let stamp = match s.stamp_regime {
                    Some(StampRegime::SteadySliding) => format!(
                        "; on the stamp's scale it slides steadily (stamp regime steady_sliding \
                         after {} slips): no slips to repeat",
                        s.n_slips
                    ),
                    Some(regime) => format!(
                        "; nor do the stamp's slips repeat ({} slip{}, stamp regime {})",
                        s.n_slips,
                        if s.n_slips == 1 { "" } else { "s" },
                        regime.name()
                    ),
                    None => String::new(),
                };
                eprintln!(
                    "note: time.until = \"periodic\", but the run did not settle by time.end: \
                     {why}{stamp}"
                );
            }
            code
        }
        Err(e) => run_error(&e),
    }
}

fn resume(dir: &Path, quiet: bool, options: &ResumeOptions) -> ExitCode {
    let flag = match interrupt_flag() {
        Ok(f) => f,
        Err(e) => return fail(format!("cannot install signal handlers: {e}"), Exit::Io),
    };
    let mut bar = progress::Bar::new(quiet);
    let mut poll = |p: &stickslip_run::driver::Progress| bar.update(p);
    let mut control = stickslip_run::Control {
        interrupt: Some(&flag),
        poll: Some(&mut poll),
        ..Default::default()
    };
    let result = stickslip_run::resume(dir, options, &mut control);
    bar.finish();
    match result {
        Ok((scene, outcome)) => report(&scene.name, dir, &outcome),
        Err(RunError::Checkpoint(e @ CheckpointError::Finished { .. }))
            if e.exit() == Exit::Success =>
        {
            say!("{e}");
            ExitCode::SUCCESS
        }
        Err(e) => run_error(&e),
    }
}

/// The command that starts this program again, for `sweep slurm`'s job script (see
/// [`set_program`]).
static PROGRAM: Mutex<Option<PathBuf>> = Mutex::new(None);

/// Sets the command that starts this program again (written into `sweep slurm`'s job script):
/// the Python package's `stickslip` script, whose process is the interpreter's. Without it,
/// the running executable.
pub fn set_program(path: PathBuf) {
    if let Ok(mut p) = PROGRAM.lock() {
        *p = Some(path);
    }
}

/// The command that starts this program again: [`set_program`]'s, else the running executable,
/// else `stickslip` (found on `PATH`).
#[must_use]
pub fn program() -> PathBuf {
    PROGRAM
        .lock()
        .ok()
        .and_then(|p| p.clone())
        .or_else(|| std::env::current_exe().ok())
        .unwrap_or_else(|| PathBuf::from("stickslip"))
}

/// The number behind an [`ExitCode`] (which has no accessor; `ExitCode::from` is one-to-one
/// on `u8`).
fn status(code: ExitCode) -> u8 {
    (0..=u8::MAX)
        .find(|&c| ExitCode::from(c) == code)
        .unwrap_or(1)
}

/// The `stickslip` program: parses `args` (the first is the program's name, as `argv[0]`),
/// runs the command, and returns the exit status (see the crate's documentation). Help,
/// `--version` and usage errors are printed as clap's `exit` prints them (status 0 or 2) but
/// return instead of ending the process; stdout is flushed before returning.
pub fn main_from<I, T>(args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let code = match Cli::try_parse_from(args) {
        Ok(cli) => status(dispatch(cli)),
        Err(e) => {
            let _ = e.print();
            u8::try_from(e.exit_code()).unwrap_or(2)
        }
    };
    {
        use std::io::Write as _;
        let _ = std::io::stdout().flush();
        let _ = std::io::stderr().flush();
    }
    code
}

/// Runs the parsed command; its exit status.
fn dispatch(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Run {
            scene,
            out,
            set,
            unset,
            quiet,
            force,
            checkpoint_every,
        } => run(
            &scene,
            &out,
            (&unset, &set),
            quiet,
            &DirOptions {
                force,
                checkpoint_every_s: checkpoint_every,
            },
        ),
        Command::Check { scene, set, unset } => {
            match Scene::from_path_unsetting(&scene, &unset, &set) {
                Ok(r) => check::print(&r),
                Err(e) => fail(e, Exit::BadInput),
            }
        }
        Command::Boundary {
            scene,
            key,
            from,
            to,
            rtol,
            scan,
            jobs,
            scale,
            set,
            unset,
            quiet,
            out,
        } => boundary::main(&boundary::Args {
            out: out.as_deref(),
            scale: stickslip_studies::boundary::Scale::from_name(&scale).unwrap_or_default(),
            scene: &scene,
            set: &set,
            unset: &unset,
            key: &key,
            from,
            to,
            rtol,
            scan,
            jobs,
            quiet,
        }),
        Command::Verify {
            scene,
            rtol,
            target,
            out,
            force,
            jobs,
            set,
            unset,
        } => verify::main(&verify::Args {
            scene: &scene,
            set: &set,
            unset: &unset,
            rtol,
            target,
            out: out.as_deref(),
            force,
            jobs,
        }),
        Command::Fit {
            scene,
            data,
            param,
            misfit,
            columns,
            noise,
            jobs,
            profile,
            jacobian,
            out,
            force,
            set,
            unset,
            quiet,
        } => fit::main(&fit::Args {
            scene: &scene,
            set: &set,
            unset: &unset,
            data: &data,
            params: &param,
            misfit: &misfit,
            columns: columns.as_deref(),
            noise,
            jobs,
            profile: profile.as_deref(),
            jacobian: &jacobian,
            out: out.as_deref(),
            force,
            quiet,
        }),
        Command::Resume {
            dir,
            quiet,
            checkpoint_every,
            allow_other_build,
        } => resume(
            &dir,
            quiet,
            &ResumeOptions {
                checkpoint_every_s: checkpoint_every,
                allow_other_build,
            },
        ),
        Command::Sweep(cmd) => sweep::main(cmd),
        Command::Keys { markdown } => {
            if markdown {
                say_raw!("{}", reference::markdown());
            } else {
                say_raw!("{}", stickslip_run::keys::table_text());
            }
            ExitCode::SUCCESS
        }
    }
}
