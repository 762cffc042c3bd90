//! The `stickslip` command line: `run`, `check` and `resume` (see INTERFACE.md).
//!
//! Exit status: 0 success, 2 bad scene or arguments (clap usage errors included), 3 numerical
//! failure, 1 an I/O error while writing output. Messages go to stderr, prefixed `error: `.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use stickslip::output::report::DerivedReport;
use stickslip::scene::{ResolvedScene, Scene};
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
    },
    /// Validate a scene and print its resolved and derived parameters.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Override a scene value (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
    },
    /// Finish an interrupted run from its checkpoint.
    Resume {
        /// Output directory of the interrupted run.
        dir: PathBuf,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run {
            scene,
            out,
            set,
            quiet,
        } => {
            let resolved = match Scene::from_path(&scene, &set) {
                Ok(r) => r,
                Err(e) => return fail(e, 2),
            };
            match stickslip::run(&resolved, &out, quiet) {
                Ok(summary) => {
                    println!(
                        "{}: {} steps to t = {:e} s, {} melting events, {:.2} s wall; output in {}",
                        resolved.name,
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
        Command::Check { scene, set } => match Scene::from_path(&scene, &set) {
            Ok(r) => {
                print_check(&r);
                ExitCode::SUCCESS
            }
            Err(e) => fail(e, 2),
        },
        Command::Resume { dir, quiet: _ } => fail(
            format!(
                "no checkpoint in {} (allowed: the output directory of an interrupted run)",
                dir.display()
            ),
            2,
        ),
    }
}
