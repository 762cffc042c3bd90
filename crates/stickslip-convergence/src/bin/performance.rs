//! `performance`: the headline benchmarks of `cargo xtask bench` (P1–P8 and T3–T4, reports/performance.*).

use std::path::PathBuf;
use std::process::ExitCode;
use stickslip_convergence::performance::{BenchSettings, measure, write_report};
use stickslip_report::options::{self, at_least_one};

/// Timed runs per configuration in the report.
const REPEATS: usize = 5;
/// The cost-per-step sweep's node counts.
const SWEEP_NODES: [usize; 7] = [125, 250, 500, 1000, 2000, 4000, 8000];

/// `cargo xtask bench`'s options.
#[derive(Debug, clap::Parser)]
#[command(
    name = "cargo xtask bench",
    about = "Runs the headline performance targets P1-P8 (and T3-T4)",
    long_about = "Runs the headline performance targets P1-P8 (and T3-T4) on the release \
                  stickslip binary (every run a subprocess, read back through run.json and \
                  events.csv; the step trace of one SFA melting in-process) and writes \
                  reports/performance.md, performance.json, performance_cost.svg, \
                  performance_work_precision.svg and performance_steptrace.svg. P4 (a fresh \
                  clone's build and test times) is read from reports/build-timing.json, which \
                  `cargo xtask build-timing` writes."
)]
struct Args {
    /// A smoke run of about a minute (few, short runs; not for the report).
    #[arg(long)]
    quick: bool,
    /// Timed runs per configuration, median reported (with --quick: the smoke run's unless given).
    #[arg(long, value_name = "N", default_value_t = REPEATS, value_parser = at_least_one)]
    repeats: usize,
    /// Largest N of the cost-per-step sweep (its levels are 125, 250, … 8000 up to N).
    #[arg(long, value_name = "N", default_value_t = SWEEP_NODES[SWEEP_NODES.len() - 1],
          value_parser = at_least_one)]
    max_nodes: usize,
    /// Output directory [default: the workspace's reports/].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// The stickslip binary [default: target/release/stickslip].
    #[arg(long, value_name = "PATH")]
    binary: Option<PathBuf>,
}

fn main() -> ExitCode {
    let (args, matches) =
        match options::parse::<Args>("cargo xtask bench", std::env::args().skip(1)) {
            Ok(p) => p,
            Err(code) => return code,
        };
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut settings = BenchSettings {
        binary: args
            .binary
            .clone()
            .unwrap_or_else(|| root.join("target/release/stickslip")),
        scene: root.join("validation/scenes/fig2.toml"),
        work_dir: root.join("target/bench-runs"),
        repeats: args.repeats,
        sweep_nodes: SWEEP_NODES.to_vec(),
        sweep_steps: 200,
        full_run_limit_s: 60.0,
        reference_dts_s: [1e-8, 5e-9, 2.5e-9],
        quick: false,
        reports_dir: root.join("reports"),
    };
    if args.quick {
        settings.quick = true;
        if !options::given(&matches, "repeats") {
            settings.repeats = 1;
        }
        settings.sweep_nodes = vec![125, 250, 500];
        settings.sweep_steps = 50;
        settings.reference_dts_s = [4e-8, 2e-8, 1e-8];
    }
    settings.sweep_nodes.retain(|&k| k <= args.max_nodes);
    if settings.sweep_nodes.is_empty() {
        eprintln!(
            "error: --max-nodes {}: allowed: an integer >= {} (the sweep's smallest N)",
            args.max_nodes, SWEEP_NODES[0]
        );
        return ExitCode::from(2);
    }
    let out = args.out.unwrap_or_else(|| root.join("reports"));
    match measure(&settings).and_then(|p| write_report(&p, &out)) {
        Ok(files) => {
            for f in files {
                println!("wrote {}", f.display());
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
