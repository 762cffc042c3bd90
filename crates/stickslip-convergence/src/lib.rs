//! stickslip-convergence: how the errors of stickslip fall with N and Δt, at which order, and
//! what each digit of accuracy costs in seconds.
//!
//! Pieces:
//! - [`celik`]: observed orders and the three-grid procedure of Celik et al. 2008 (apparent
//!   order by fixed-point iteration, extrapolated value, GCI, oscillation flag);
//! - [`operators`]: the MDR operators against exact pairs (both quadratures, two norms);
//! - [`steppers`]: Landau φ-steppers and drive integrators against closed forms;
//! - [`fig2`] and [`simulation`]: whole-simulation convergence of fig2 (event onsets, peak
//!   forces, stick-phase force) refining N and Δt separately for each scheme;
//! - [`work_precision`]: error against wall seconds, against a much finer reference;
//! - [`same_n`]: same-N references (fixed steps, Richardson) and errors against them;
//! - [`tolerance`]: the default adaptive stepping per `time.tolerance` against same-N
//!   references, with the controller before the redesign as measured;
//! - [`noise`]: the weak order of fixed steps with gaussian noise (first onset over seeds);
//! - [`report`]: `reports/convergence.md`, `convergence.json`, `convergence_*.svg`, drawn and
//!   formatted with the reporting kit (`stickslip-report`);
//! - [`performance`]: `cargo xtask bench` (T1–T4), the release binary run as a user would.
//!
//! Entry point: [`run_convergence_cli`] (used by `cargo xtask convergence` and by the
//! `convergence` binary of this crate).
//!
//! Invariant: every fig2 run goes through the run library's driver (`stickslip-run`), every
//! benchmark through the `stickslip` binary; otherwise only `stickslip-core`'s public API is
//! called, and reports are made with `stickslip-report`.

/// Celik et al.'s three-grid procedure (the run library's, which `stickslip verify` uses too).
pub use stickslip_studies::verify::celik;
pub mod fig2;
pub mod grid_study;
pub mod n_reference;
pub mod noise;
pub mod operators;
pub mod performance;
pub mod report;
pub mod same_n;
pub mod simulation;
pub mod steppers;
pub mod study;
pub mod tolerance;
pub mod work_precision;

pub use celik::observed_orders;

use fig2::{EventRecord, RunRecord};
use serde::{Deserialize, Serialize};
use simulation::scheme_name;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use stickslip_core::config::Scheme;
use stickslip_core::drive::Integrator;
use study::{Refined, Study};
use work_precision::{Reference, WorkPrecision};

/// Levels and repeats of one full study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// Node counts of the operator study.
    pub operator_nodes: Vec<usize>,
    /// Δt levels of the Landau stepper study, s.
    pub landau_dts_s: Vec<f64>,
    /// Δt levels of the drive integrator study, s.
    pub drive_dts_s: Vec<f64>,
    /// Node counts of the whole-simulation N refinement.
    pub sim_nodes: Vec<usize>,
    /// Δt held fixed in the N refinement, s.
    pub sim_nodes_dt_s: f64,
    /// Δt levels of the whole-simulation Δt refinement, s.
    pub sim_dts_s: Vec<f64>,
    /// N held fixed in the Δt refinement.
    pub sim_dts_nodes: usize,
    /// (N, Δt) of the work–precision points, per method.
    pub wp_points: Vec<(usize, f64)>,
    /// Nodes of the reference.
    pub ref_nodes: usize,
    /// Δt of the three reference runs, coarse to fine, s.
    pub ref_dts_s: [f64; 3],
    /// Timing repeats per work–precision point.
    pub repeats: usize,
    /// Largest N allowed in the simulation studies.
    pub max_nodes: usize,
    /// The tolerance study (absent in studies written before it existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<tolerance::ToleranceSettings>,
    /// The noise study (absent in studies written before it existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<noise::NoiseSettings>,
    /// The spatial study at the user's scale (absent in studies written before it existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<grid_study::GridSettings>,
}

impl Settings {
    /// The full study: N = 125 … 2000 (capped by `max_nodes`), Δt = 1.6e-7 … 2.5e-9.
    pub fn full(max_nodes: usize) -> Self {
        Self {
            operator_nodes: operators::DEFAULT_NODES.to_vec(),
            landau_dts_s: steppers::LANDAU_DT_S.to_vec(),
            drive_dts_s: steppers::drive_dts(5..=12),
            sim_nodes: [125, 250, 500, 1000, 2000]
                .into_iter()
                .filter(|&n| n <= max_nodes)
                .collect(),
            sim_nodes_dt_s: 1e-8,
            sim_dts_s: vec![1.6e-7, 8e-8, 4e-8, 2e-8, 1e-8, 5e-9, 2.5e-9],
            sim_dts_nodes: 125,
            wp_points: vec![(25, 4e-8), (50, 2e-8), (100, 1e-8), (200, 5e-9)],
            ref_nodes: FULL_REF_NODES,
            ref_dts_s: [5e-9, 2.5e-9, 1.25e-9],
            repeats: FULL_REPEATS,
            max_nodes,
            tolerance: Some(tolerance::ToleranceSettings::full(max_nodes, FULL_REPEATS)),
            noise: Some(noise::NoiseSettings::full()),
            grid: Some(grid_study::GridSettings::full()),
        }
    }

    /// A smoke-test study of about a minute: small N, few levels, one repeat.
    pub fn quick() -> Self {
        Self {
            operator_nodes: vec![125, 250, 500],
            landau_dts_s: vec![2e-8, 1e-8, 5e-9, 2.5e-9],
            drive_dts_s: steppers::drive_dts(6..=9),
            sim_nodes: vec![50, 100, 200],
            sim_nodes_dt_s: 1e-8,
            sim_dts_s: vec![4e-8, 2e-8, 1e-8],
            sim_dts_nodes: 50,
            wp_points: vec![(25, 4e-8), (50, 2e-8)],
            ref_nodes: 100,
            ref_dts_s: [2e-8, 1e-8, 5e-9],
            repeats: 1,
            max_nodes: 200,
            tolerance: Some(tolerance::ToleranceSettings::quick()),
            noise: Some(noise::NoiseSettings::quick()),
            grid: Some(grid_study::GridSettings::quick()),
        }
    }
}

/// One fig2 run as written to JSON, with its errors against the reference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Which study the run belongs to (`N`, `dt`, `reference`, `work-precision`).
    pub role: String,
    /// Scheme.
    pub scheme: String,
    /// Nodes.
    pub nodes: usize,
    /// Time step, s.
    pub dt_s: f64,
    /// Wall seconds of this run (work–precision: the median of the repeats).
    pub wall_s: f64,
    /// Events.
    pub events: Vec<EventRecord>,
    /// The core's error message if a step failed.
    pub failure: Option<String>,
    /// max over events of |onset − reference|, s.
    pub onset_error_s: Option<f64>,
    /// max over events of |f_peak − reference|/reference.
    pub f_peak_error_rel: Option<f64>,
    /// Stick-phase RMS force error against the reference, relative to max F.
    pub force_error_rel: Option<f64>,
}

/// Everything the report is made of (the content of `reports/convergence.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Results {
    /// Producer and command.
    pub generated_by: String,
    /// The commit the study ran at (absent in studies made before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub commit: Option<stickslip_report::provenance::Commit>,
    /// Wall seconds of the whole study.
    pub total_wall_s: f64,
    /// Cargo profile the study ran in (`release`, or `dev` with the core at opt-level 3).
    #[serde(default = "dev_profile")]
    pub build_profile: String,
    /// The machine the study ran on (logical CPUs; absent in studies written before it was
    /// recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine: Option<String>,
    /// Levels used.
    pub settings: Settings,
    /// All studies.
    pub studies: Vec<Study>,
    /// Relative error of X at the end of fig2 of each drive integrator with the paper's Δt
    /// (free spring; the shipped scene's time.end and time.dt).
    pub drive_fig2_rel_error: Vec<(String, f64)>,
    /// Every fig2 run.
    pub runs: Vec<RunSummary>,
    /// The work–precision study.
    pub work_precision: WorkPrecision,
    /// Where the accurate scheme's Δt error of the first onset is made.
    pub localisation: simulation::Localisation,
    /// The tolerance study of the default adaptive stepping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<tolerance::ToleranceStudy>,
    /// The weak order of noisy fixed steps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<noise::NoiseStudy>,
    /// Spatial convergence at the user's scale, uniform and graded grids.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<grid_study::GridStudy>,
}

fn dev_profile() -> String {
    "dev (the core at opt-level 3)".to_string()
}

fn summary(role: &str, r: &RunRecord, reference: &Reference) -> RunSummary {
    let p = work_precision::point(r, reference, vec![r.wall_s]);
    RunSummary {
        role: role.to_string(),
        scheme: scheme_name(r.spec.scheme).to_string(),
        nodes: r.spec.nodes,
        dt_s: r.spec.dt_s,
        wall_s: r.wall_s,
        events: r.events.clone(),
        failure: r.failure.clone(),
        onset_error_s: p.onset_error_s,
        f_peak_error_rel: p.f_peak_error_rel,
        force_error_rel: p.force_error_rel,
    }
}

/// Runs every study of `settings`; `log` receives one line per finished piece.
pub fn run_all(settings: &Settings, log: &mut dyn FnMut(&str)) -> Results {
    let start = Instant::now();
    let mut studies = Vec::new();
    let stamp = |start: &Instant| format!("[{:7.1} s]", start.elapsed().as_secs_f64());

    studies.extend(operators::study(&settings.operator_nodes));
    log(&format!("{} operators done", stamp(&start)));
    studies.extend(steppers::landau_study(&settings.landau_dts_s));
    studies.extend(steppers::drive_study(&settings.drive_dts_s));
    let paper = fig2::shipped();
    let drive_fig2_rel_error = [(Integrator::Verlet, "verlet"), (Integrator::Rk4, "rk4")]
        .into_iter()
        .map(|(i, n)| {
            let t = &paper.config.time;
            (n.to_string(), steppers::drive_error_at(i, t.end_s, t.dt_s))
        })
        .collect();
    log(&format!("{} steppers done", stamp(&start)));

    let mut progress = |r: &RunRecord| {
        log(&format!(
            "{} {} N={} dt={:e}: {:.1} s, {} events{}",
            stamp(&start),
            scheme_name(r.spec.scheme),
            r.spec.nodes,
            r.spec.dt_s,
            r.wall_s,
            r.events.len(),
            r.failure
                .as_ref()
                .map(|f| format!(" FAILED: {f}"))
                .unwrap_or_default()
        ));
    };

    let (reference, ref_runs) =
        work_precision::reference(settings.ref_nodes, settings.ref_dts_s, &mut progress);
    let mut runs: Vec<RunSummary> = ref_runs
        .iter()
        .map(|r| summary("reference", r, &reference))
        .collect();

    for scheme in [Scheme::Literal, Scheme::Accurate] {
        let levels: Vec<f64> = settings.sim_nodes.iter().map(|&n| n as f64).collect();
        let recs = simulation::run_levels(
            scheme,
            Refined::Nodes,
            &levels,
            settings.sim_nodes_dt_s,
            fig2::FIG2_END_S,
            &mut progress,
        );
        studies.extend(simulation::studies(Refined::Nodes, &recs));
        runs.extend(recs.iter().map(|r| summary("N", r, &reference)));
        let recs = simulation::run_levels(
            scheme,
            Refined::Dt,
            &settings.sim_dts_s,
            settings.sim_dts_nodes as f64,
            fig2::FIG2_END_S,
            &mut progress,
        );
        studies.extend(simulation::studies(Refined::Dt, &recs));
        runs.extend(recs.iter().map(|r| summary("dt", r, &reference)));
    }

    let localisation = simulation::localise(
        Scheme::Accurate,
        settings.sim_dts_nodes,
        4e-8,
        1e-8,
        7e-6,
        &mut progress,
    );

    let mut points = Vec::new();
    for scheme in [Scheme::Literal, Scheme::Accurate] {
        let curve = work_precision::curve(
            scheme,
            &settings.wp_points,
            settings.repeats,
            &reference,
            &mut progress,
        );
        for p in &curve {
            runs.push(RunSummary {
                role: "work-precision".into(),
                scheme: p.method.clone(),
                nodes: p.nodes,
                dt_s: p.dt_s,
                wall_s: p.wall_s,
                events: p.event_records.clone(),
                failure: p.failure.clone(),
                onset_error_s: p.onset_error_s,
                f_peak_error_rel: p.f_peak_error_rel,
                force_error_rel: p.force_error_rel,
            });
        }
        points.extend(curve);
    }
    let tolerance = settings
        .tolerance
        .as_ref()
        .map(|t| tolerance::study(t, &mut progress));
    let noise = settings
        .noise
        .as_ref()
        .map(|n| noise::study(n, &mut progress));
    log(&format!(
        "{} tolerance and noise studies done",
        stamp(&start)
    ));
    let grid = settings
        .grid
        .as_ref()
        .map(|g| grid_study::study(g, &mut |line| log(line)));
    let mut results = Results {
        commit: stickslip_report::provenance::Commit::of_workspace(),
        generated_by: "cargo xtask convergence (stickslip-convergence)".into(),
        total_wall_s: start.elapsed().as_secs_f64(),
        build_profile: if cfg!(debug_assertions) {
            dev_profile()
        } else {
            "release".to_string()
        },
        machine: Some(format!(
            "{} logical CPUs",
            std::thread::available_parallelism().map_or(0, usize::from)
        )),
        settings: settings.clone(),
        studies,
        drive_fig2_rel_error,
        runs,
        work_precision: WorkPrecision {
            reference,
            points,
            repeats: settings.repeats,
        },
        localisation,
        tolerance,
        noise,
        grid,
    };
    n_reference::apply(&mut results);
    results
}

/// Re-derives the theory annotations of the studies from the current code (used when
/// re-rendering a stored study, so that corrected wording reaches the report without a re-run).
pub fn refresh_annotations(r: &mut Results) {
    for s in &mut r.studies {
        if s.study != "simulation" {
            continue;
        }
        let scheme = if s.scheme == "literal" {
            Scheme::Literal
        } else {
            Scheme::Accurate
        };
        let (order, words) = simulation::theory(scheme, s.refined, &s.observable);
        s.theory_order = order;
        s.theory = words.to_string();
    }
}

/// The workspace's `reports/` directory (next to `crates/`).
pub fn default_reports_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reports")
}

/// The full study's largest N of the whole-simulation N refinement.
pub const FULL_MAX_NODES: usize = 2000;
/// The full study's timing repeats per work-precision point.
pub const FULL_REPEATS: usize = 3;
/// The full study's nodes of the work-precision reference.
pub const FULL_REF_NODES: usize = 400;

/// `cargo xtask convergence`'s options (`--repeats` and `--ref-nodes` default to the full
/// study's, or to the smoke study's with `--quick` unless given).
#[derive(Debug, clap::Parser)]
#[command(
    name = "cargo xtask convergence",
    about = "Runs the convergence studies (operators, steppers, whole fig2 simulation, \
             work-precision) and writes reports/convergence.md, reports/convergence.json and \
             reports/convergence_*.svg"
)]
struct Args {
    /// Largest N of the whole-simulation N refinement (the levels are 125, 250, 500, 1000,
    /// 2000 up to N).
    #[arg(long, value_name = "N", default_value_t = FULL_MAX_NODES, value_parser = at_least_one)]
    max_nodes: usize,
    /// Timing repeats per work-precision point (with --quick: the smoke study's unless given).
    #[arg(long, value_name = "K", default_value_t = FULL_REPEATS, value_parser = at_least_one)]
    repeats: usize,
    /// Nodes of the work-precision reference (with --quick: the smoke study's unless given).
    #[arg(long, value_name = "N", default_value_t = FULL_REF_NODES, value_parser = at_least_one)]
    ref_nodes: usize,
    /// A smoke study of about a minute (small N, few levels).
    #[arg(long)]
    quick: bool,
    /// Re-render the .md and .svg files from the existing convergence.json.
    #[arg(long)]
    render_only: bool,
    /// Run only the spatial study at the user's scale (section 8; about 20 min, with --quick
    /// seconds) and merge it into the existing convergence.json.
    #[arg(long)]
    grid_only: bool,
    /// Run every section but 8, and keep section 8 from the existing convergence.json (its
    /// runs name their grid: no default moves them).
    #[arg(long)]
    keep_grid: bool,
    /// Output directory [default: the workspace's reports/].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

use stickslip_report::options::at_least_one;

/// `cargo xtask convergence` with `args` (the words after `convergence`).
///
/// Exit status: 0 success, 2 bad arguments, 1 an I/O or rendering error.
pub fn run_convergence_cli(args: &[String]) -> ExitCode {
    let (args, matches) = match stickslip_report::options::parse::<Args>(
        "cargo xtask convergence",
        args.iter().cloned(),
    ) {
        Ok(p) => p,
        Err(code) => return code,
    };
    let given = |id: &str| stickslip_report::options::given(&matches, id);
    let Args {
        max_nodes,
        quick,
        render_only,
        grid_only,
        keep_grid,
        ..
    } = args;
    // --quick's own repeats and reference unless given.
    let repeats = (!quick || given("repeats")).then_some(args.repeats);
    let ref_nodes = (!quick || given("ref_nodes")).then_some(args.ref_nodes);
    let out = args.out.unwrap_or_else(default_reports_dir);
    let json_path = out.join("convergence.json");
    let results = if render_only || grid_only {
        let text = match std::fs::read_to_string(&json_path) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("convergence: cannot read {}: {e}", json_path.display());
                return ExitCode::from(1);
            }
        };
        match serde_json::from_str::<Results>(&text) {
            Ok(mut r) => {
                refresh_annotations(&mut r);
                n_reference::apply(&mut r);
                if grid_only {
                    let settings = if quick {
                        grid_study::GridSettings::quick()
                    } else {
                        grid_study::GridSettings::full()
                    };
                    let study = grid_study::study(&settings, &mut |line| eprintln!("{line}"));
                    eprintln!("convergence: the spatial study took {:.0} s", study.wall_s);
                    r.settings.grid = Some(settings);
                    r.grid = Some(study);
                    r.commit = stickslip_report::provenance::Commit::of_workspace();
                }
                r
            }
            Err(e) => {
                eprintln!("convergence: {} is not a study: {e}", json_path.display());
                return ExitCode::from(1);
            }
        }
    } else {
        let mut settings = if quick {
            Settings::quick()
        } else {
            Settings::full(max_nodes)
        };
        if let Some(r) = repeats {
            settings.repeats = r;
        }
        if let Some(n) = ref_nodes {
            settings.ref_nodes = n;
        }
        if let (Some(t), Some(r)) = (settings.tolerance.as_mut(), repeats) {
            t.repeats = r;
        }
        // Section 8 from the existing JSON, read before the study so that a missing or
        // unreadable one stops it at once.
        let kept = if keep_grid {
            settings.grid = None;
            let old = std::fs::read_to_string(&json_path)
                .ok()
                .and_then(|t| serde_json::from_str::<Results>(&t).ok());
            match old {
                Some(Results {
                    grid: Some(study),
                    settings: Settings { grid: Some(g), .. },
                    ..
                }) => Some((g, study)),
                _ => {
                    eprintln!(
                        "convergence: --keep-grid: {} holds no section 8 to keep",
                        json_path.display()
                    );
                    return ExitCode::from(1);
                }
            }
        } else {
            None
        };
        eprintln!(
            "convergence: N levels {:?}, dt levels {:?}, reference N = {}; this takes a while",
            settings.sim_nodes, settings.sim_dts_s, settings.ref_nodes
        );
        let mut results = run_all(&settings, &mut |line| eprintln!("{line}"));
        if let Some((g, study)) = kept {
            results.settings.grid = Some(g);
            results.grid = Some(study);
        }
        results
    };
    match report::write_all(&results, &out) {
        Ok(files) => {
            for f in files {
                println!("wrote {}", f.display());
            }
            eprintln!("convergence: total {:.0} s", results.total_wall_s);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("convergence: {e}");
            ExitCode::from(1)
        }
    }
}

#[cfg(test)]
mod cli_tests {
    use super::{Args, FULL_MAX_NODES, FULL_REF_NODES, FULL_REPEATS};
    use clap::Parser;

    #[test]
    fn options_default_to_the_full_study_and_bad_ones_are_refused() {
        let a = Args::try_parse_from(["convergence"]).unwrap();
        assert_eq!(
            (a.max_nodes, a.repeats, a.ref_nodes),
            (FULL_MAX_NODES, FULL_REPEATS, FULL_REF_NODES)
        );
        let full = super::Settings::full(a.max_nodes);
        assert_eq!((full.repeats, full.ref_nodes), (a.repeats, a.ref_nodes));
        for bad in [&["--repeats", "0"][..], &["--max-nodes", "x"], &["--bogus"]] {
            let e = Args::try_parse_from(std::iter::once("convergence").chain(bad.iter().copied()))
                .unwrap_err();
            assert!(e.use_stderr(), "{bad:?}");
        }
    }
}
