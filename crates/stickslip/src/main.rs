//! The `stickslip` command line: `run`, `check` and `resume` (see INTERFACE.md).
//!
//! Exit status: 0 success, 2 bad scene or arguments (clap usage errors included), 3 numerical
//! failure, 1 an I/O error while writing output. Messages go to stderr, prefixed `error: `.
//!
//! `resume DIR`: 2 when DIR has no checkpoint or an unusable one; for a run that has already
//! ended, a note and the status that run had (0 finished, 3 failed numerically).

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use stickslip::checkpoint::{CheckpointError, DEFAULT_EVERY_S};
use stickslip::output::report::DerivedReport;
use stickslip::scene::{ResolvedScene, Scene};
use stickslip::{RunError, RunOptions, RunSummary};
use stickslip_core::config::Scheme;
use stickslip_core::sim::Simulation;

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
        /// Output directory (created if needed).
        #[arg(long)]
        out: PathBuf,
        /// Override a scene value, e.g. `--set contact.nodes=200` (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Wall-clock seconds between checkpoints in DIR, from which `resume` finishes a killed
        /// run; 0 = none.
        #[arg(long, value_name = "SECONDS", default_value_t = DEFAULT_EVERY_S, value_parser = parse_interval)]
        checkpoint_every: f64,
    },
    /// Validate a scene and print its resolved and derived parameters.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Override a scene value (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
    },
    /// Finish an interrupted run from its checkpoint; the output is bit-identical to that of
    /// an uninterrupted run (run.json's wall_seconds aside).
    Resume {
        /// Output directory of the interrupted run.
        dir: PathBuf,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Wall-clock seconds between checkpoints from here on; 0 = none [default: the run's].
        #[arg(long, value_name = "SECONDS", value_parser = parse_interval)]
        checkpoint_every: Option<f64>,
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

/// Prints the one-line summary of a run, or its error; the exit status.
fn report(name: &str, out: &std::path::Path, result: Result<RunSummary, RunError>) -> ExitCode {
    match result {
        Ok(summary) => {
            println!(
                "{name}: {} steps to t = {:e} s, {} melting events, {:.2} s wall; output in {}",
                summary.steps,
                summary.t_final_s,
                summary.events.len(),
                summary.wall_seconds,
                out.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            let code = u8::try_from(e.exit_code()).unwrap_or(1);
            fail(e, code)
        }
    }
}

fn fail(message: impl std::fmt::Display, code: u8) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(code)
}

fn print_check(scene: &ResolvedScene) {
    println!("# resolved scene (defaults filled in)");
    print!("{}", scene.resolved.to_toml_string());
    let rho = Simulation::new(scene.config.clone(), scene.output.event_merge_gap_s)
        .map(|mut sim| sim.lagged_sweep_contraction())
        .unwrap_or(f64::NAN);
    let d = DerivedReport::of(scene, rho);
    let c = &scene.config;
    println!();
    println!("# derived parameters");
    println!("b = {:e} Pa", d.b);
    println!("A = {:e} Pa", d.a);
    println!("eps_c = {}", d.eps_c);
    println!("phi0 = {}", d.phi0);
    println!("omega = {} rad/s", d.omega);
    println!("g_eff = {:e} Pa", d.g_eff);
    println!("nodes = {}", d.nodes);
    println!("steps = {}", d.steps_planned);
    println!(
        "lagged_sweep_contraction = {:.4} (rho of the paper's lagged elastic sweep at t = 0; \
         the literal scheme needs < 1)",
        d.lagged_sweep_contraction
    );
    if c.time.scheme == Scheme::Literal {
        // Explicit Euler on Eq. 8 at the solid equilibrium (ε = 0): |∂rhs/∂φ| = 2γ·A·b/a.
        let stiffness = 2.0 * c.lubricant.gamma_per_pa_s * d.a.max(0.0) * d.b / c.lubricant.a_pa;
        println!(
            "euler_number = {} (literal scheme: gamma*dt*2*A*b/a, stable below 2)",
            stiffness * c.time.dt_s
        );
    }
}

/// The literal scheme's explicit Euler is unstable for Δt·2γAb/a > 2 at the solid equilibrium;
/// just beyond that a run can finish with plausible-looking but wrong numbers (the convergence
/// report measured f_peak 40 % off at 2.4), so say so before running.
fn warn_unstable_euler(scene: &ResolvedScene) {
    let c = &scene.config;
    if c.time.scheme != Scheme::Literal {
        return;
    }
    let a_coeff = scene.derived.a_coeff_pa.max(0.0);
    let number = c.time.dt_s * 2.0 * c.lubricant.gamma_per_pa_s * a_coeff * scene.derived.b_pa
        / c.lubricant.a_pa;
    if number > 2.0 {
        eprintln!(
            "warning: time.dt x 2*gamma*A*b/a = {number:.3} > 2: the literal scheme's explicit \
             Euler is beyond its stability limit; the run may fail (exit 3) or finish with wrong \
             numbers. Use time.dt < {:e} s or time.scheme = \"accurate\".",
            2.0 * c.time.dt_s / number
        );
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run {
            scene,
            out,
            set,
            quiet,
            checkpoint_every,
        } => {
            let resolved = match Scene::from_path(&scene, &set) {
                Ok(r) => r,
                Err(e) => return fail(e, 2),
            };
            let options = RunOptions {
                quiet,
                checkpoint_every_s: checkpoint_every,
            };
            warn_unstable_euler(&resolved);
            report(
                &resolved.name,
                &out,
                stickslip::run(&resolved, &out, &options),
            )
        }
        Command::Check { scene, set } => match Scene::from_path(&scene, &set) {
            Ok(r) => {
                print_check(&r);
                ExitCode::SUCCESS
            }
            Err(e) => fail(e, 2),
        },
        Command::Resume {
            dir,
            quiet,
            checkpoint_every,
        } => match stickslip::resume(&dir, quiet, checkpoint_every) {
            Ok((scene, summary)) => report(&scene.name, &dir, Ok(summary)),
            Err(RunError::Checkpoint(e @ CheckpointError::Finished { .. }))
                if e.exit_code() == 0 =>
            {
                println!("{e}");
                ExitCode::SUCCESS
            }
            Err(e) => report("", &dir, Err(e)),
        },
    }
}
