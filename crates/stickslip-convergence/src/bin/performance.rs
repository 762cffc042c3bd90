//! `performance`: the headline benchmarks of `cargo xtask bench` (P1–P8 and T3–T4, reports/performance.*).
//!
//! Options: see [`HELP`].

use std::path::PathBuf;
use std::process::ExitCode;
use stickslip_convergence::performance::{BenchSettings, measure, write_report};

/// The options.
const HELP: &str = "\
cargo xtask bench [options]

Runs the headline performance targets P1-P8 (and T3-T4) on the release stickslip binary (every run a
subprocess, read back through run.json and events.csv; the step trace of one SFA melting
in-process) and writes reports/performance.md, performance.json, performance_cost.svg,
performance_work_precision.svg and performance_steptrace.svg. P4 (a fresh
clone's build and test times) is read from reports/build-timing.json, which
`cargo xtask build-timing` writes.

Options:
  --quick          a smoke run of about a minute (few, short runs; not for the report)
  --repeats N      timed runs per configuration, median reported (default 5)
  --max-nodes N    largest N of the cost-per-step sweep (default 8000)
  --out DIR        output directory (default: the workspace's reports/)
  --binary PATH    the stickslip binary (default: target/release/stickslip)
  -h, --help       this text
";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut settings = BenchSettings {
        binary: root.join("target/release/stickslip"),
        scene: root.join("validation/scenes/fig2.toml"),
        work_dir: root.join("target/bench-runs"),
        repeats: 5,
        sweep_nodes: vec![125, 250, 500, 1000, 2000, 4000, 8000],
        sweep_steps: 200,
        full_run_limit_s: 60.0,
        reference_dts_s: [1e-8, 5e-9, 2.5e-9],
        quick: false,
        reports_dir: root.join("reports"),
    };
    let mut out = root.join("reports");
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| format!("{name} needs a value"))
        };
        let parsed: Result<(), String> = match a.as_str() {
            "-h" | "--help" => {
                print!("{HELP}");
                return ExitCode::SUCCESS;
            }
            "--quick" => {
                settings.quick = true;
                settings.repeats = 1;
                settings.sweep_nodes = vec![125, 250, 500];
                settings.sweep_steps = 50;
                settings.reference_dts_s = [4e-8, 2e-8, 1e-8];
                Ok(())
            }
            "--repeats" => value("--repeats").and_then(|v| {
                settings.repeats = v
                    .parse()
                    .map_err(|_| format!("--repeats {v}: allowed: an integer >= 1"))?;
                Ok(())
            }),
            "--max-nodes" => value("--max-nodes").and_then(|v| {
                let n: usize = v
                    .parse()
                    .map_err(|_| format!("--max-nodes {v}: allowed: an integer >= 125"))?;
                settings.sweep_nodes.retain(|&k| k <= n);
                Ok(())
            }),
            "--out" => value("--out").map(|v| out = PathBuf::from(v)),
            "--binary" => value("--binary").map(|v| settings.binary = PathBuf::from(v)),
            other => Err(format!("unknown option {other}\n\n{HELP}")),
        };
        if let Err(e) = parsed {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    }
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
