//! `cargo xtask bench`: the headline performance comparisons (issue "performance", T1–T4),
//! measured end to end on the release `stickslip` binary and written to
//! `reports/performance.{md,json}` with two SVG figures.
//!
//! Every number is a wall-clock measurement of a subprocess on this machine (medians of
//! `repeats` runs, thread count set with `RAYON_NUM_THREADS`), and every accuracy figure is a
//! difference to a converged reference computed in the same run — nothing is copied in.
//!
//! - **T1** fig2 with the default accurate settings (adaptive steps, default tolerance) at
//!   N = 200: wall time on 1 and 2 threads, largest onset error against the reference.
//! - **literal** the paper's scheme at its own settings (N = 2000, Δt = 1e-8 s) timed on a
//!   window of the run and extrapolated per simulated second (the window is stated).
//! - **T2** N = 2000, fixed Δt = 1e-8 s, the whole 1.3 ms (run in full when a window
//!   projects ≤ `full_run_limit_s`, else extrapolated and marked so).
//! - **T3** loop time per step against N (fixed steps, fast and dense operators), log–log slope.
//! - **T4** work–precision of adaptive against fixed steps at N = 125.

use crate::plot::{Marker, PALETTE, Panel, Series, render_svg};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The fig2 run length, s.
pub const FIG2_END_S: f64 = 1.3e-3;

/// Where and how to measure.
#[derive(Debug, Clone)]
pub struct BenchSettings {
    /// The release `stickslip` binary.
    pub binary: PathBuf,
    /// The fig2 scene file.
    pub scene: PathBuf,
    /// Scratch directory for run outputs.
    pub work_dir: PathBuf,
    /// Runs per timed configuration (median reported).
    pub repeats: usize,
    /// Node counts of the cost-per-step sweep (T3).
    pub sweep_nodes: Vec<usize>,
    /// Fixed steps timed per node count in the sweep.
    pub sweep_steps: usize,
    /// Run T2 in full when its window projects at most this long, s.
    pub full_run_limit_s: f64,
    /// Nodes of the reference run.
    pub reference_nodes: usize,
    /// Tolerance of the reference run.
    pub reference_tolerance: f64,
    /// Fewer and shorter runs (smoke test of the pipeline, not for the report).
    pub quick: bool,
}

/// One finished subprocess run.
#[derive(Debug, Clone, Serialize)]
pub struct CliRun {
    /// Wall time of the whole process, s.
    pub wall_s: f64,
    /// Wall time of the time loop (run.json `wall_seconds`), s.
    pub loop_s: f64,
    /// Steps taken (sub-steps when adaptive).
    pub steps: u64,
    /// Rejected adaptive attempts.
    pub rejected_steps: u64,
    /// Event onsets, s.
    pub onsets_s: Vec<f64>,
    /// Coupling-solver iterations (run.json).
    pub coupling_iterations: u64,
}

/// Runs `stickslip run SCENE --out DIR --quiet --set …` with `threads` rayon threads.
///
/// # Errors
/// The process could not start, failed, or its outputs could not be read.
pub fn run_cli(
    s: &BenchSettings,
    tag: &str,
    sets: &[String],
    threads: usize,
) -> Result<CliRun, String> {
    let out = s.work_dir.join(tag);
    let _ = std::fs::remove_dir_all(&out);
    let mut cmd = Command::new(&s.binary);
    cmd.arg("run")
        .arg(&s.scene)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .env("RAYON_NUM_THREADS", threads.to_string());
    for set in sets {
        cmd.arg("--set").arg(set);
    }
    let start = Instant::now();
    let output = cmd
        .output()
        .map_err(|e| format!("{}: {e}", s.binary.display()))?;
    let wall_s = start.elapsed().as_secs_f64();
    if !output.status.success() {
        return Err(format!(
            "stickslip run {} failed ({}): {}",
            sets.join(" "),
            output.status,
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    let report: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("run.json")).map_err(|e| e.to_string())?,
    )
    .map_err(|e| e.to_string())?;
    let num = |k: &str| report.get(k).and_then(serde_json::Value::as_f64);
    let events = std::fs::read_to_string(out.join("events.csv")).map_err(|e| e.to_string())?;
    Ok(CliRun {
        wall_s,
        loop_s: num("wall_seconds").unwrap_or(f64::NAN),
        steps: num("steps").unwrap_or(0.0) as u64,
        rejected_steps: num("rejected_steps").unwrap_or(0.0) as u64,
        onsets_s: csv_column(&events, "t_onset")?,
        coupling_iterations: num("coupling_iterations").unwrap_or(0.0) as u64,
    })
}

/// The values of column `name` of a CSV text with a header row.
///
/// # Errors
/// No such column, or a value that is not a number.
pub fn csv_column(text: &str, name: &str) -> Result<Vec<f64>, String> {
    let mut lines = text.lines();
    let header = lines.next().ok_or("empty CSV")?;
    let col = header
        .split(',')
        .position(|h| h.trim() == name)
        .ok_or_else(|| format!("no column {name} in {header}"))?;
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .nth(col)
                .and_then(|v| v.trim().parse::<f64>().ok())
                .ok_or_else(|| format!("bad value in column {name}: {l}"))
        })
        .collect()
}

/// Median of a non-empty slice.
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Least-squares slope of log y against log x.
pub fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

/// Largest |onset − reference| over the events both have, s; infinite if the counts differ.
pub fn max_onset_error_s(onsets_s: &[f64], reference_s: &[f64]) -> f64 {
    if onsets_s.len() != reference_s.len() {
        return f64::INFINITY;
    }
    onsets_s
        .iter()
        .zip(reference_s)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

/// Timed runs of one configuration.
#[derive(Debug, Clone, Serialize)]
pub struct Timed {
    /// What was run (the `--set` overrides).
    pub settings: Vec<String>,
    /// Threads.
    pub threads: usize,
    /// Median process wall time, s.
    pub wall_s: f64,
    /// Median loop time, s.
    pub loop_s: f64,
    /// All process wall times, s.
    pub walls_s: Vec<f64>,
    /// Steps of the last run.
    pub steps: u64,
    /// Rejected steps of the last run.
    pub rejected_steps: u64,
    /// Largest onset error against the reference, µs.
    pub max_onset_error_us: f64,
    /// Events of the last run.
    pub events: usize,
    /// Coupling-solver iterations of the last run.
    pub coupling_iterations: u64,
}

fn timed(
    s: &BenchSettings,
    tag: &str,
    sets: &[String],
    threads: usize,
    repeats: usize,
    reference_s: &[f64],
) -> Result<Timed, String> {
    let mut walls = Vec::new();
    let mut loops = Vec::new();
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let r = run_cli(s, tag, sets, threads)?;
        walls.push(r.wall_s);
        loops.push(r.loop_s);
        last = Some(r);
    }
    let last = last.ok_or("no run")?;
    Ok(Timed {
        settings: sets.to_vec(),
        threads,
        wall_s: median(&walls),
        loop_s: median(&loops),
        walls_s: walls,
        steps: last.steps,
        rejected_steps: last.rejected_steps,
        max_onset_error_us: 1e6 * max_onset_error_s(&last.onsets_s, reference_s),
        events: last.onsets_s.len(),
        coupling_iterations: last.coupling_iterations,
    })
}

/// One point of the cost-per-step sweep.
#[derive(Debug, Clone, Serialize)]
pub struct CostPoint {
    /// Nodes N.
    pub nodes: usize,
    /// Operator form (`fast` or `dense`).
    pub operator: String,
    /// Loop time per step, µs (median).
    pub us_per_step: f64,
    /// Threads.
    pub threads: usize,
}

/// One point of the work–precision diagram.
#[derive(Debug, Clone, Serialize)]
pub struct WpPoint {
    /// `adaptive` or `fixed`.
    pub method: String,
    /// Tolerance (adaptive) or Δt in s (fixed).
    pub parameter: f64,
    /// Median process wall time, s.
    pub wall_s: f64,
    /// Largest onset error against the reference, µs.
    pub max_onset_error_us: f64,
    /// Steps (sub-steps when adaptive).
    pub steps: u64,
    /// Rejected attempts (adaptive).
    pub rejected_steps: u64,
}

/// Everything `cargo xtask bench` writes to `reports/performance.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Performance {
    /// T1: fig2, default accurate settings at N = 200, 2 threads, median wall s.
    pub fig2_accurate_s: f64,
    /// T1 on 1 thread.
    pub fig2_accurate_1thread_s: f64,
    /// T1 largest onset error against the reference, µs.
    pub fig2_accurate_max_onset_error_us: f64,
    /// T1 details (2 threads, 1 thread).
    pub fig2_accurate_runs: Vec<Timed>,
    /// The literal scheme at N = 2000, Δt = 1e-8 s, extrapolated to the whole 1.3 ms, s.
    pub fig2_literal_extrapolated_s: f64,
    /// Simulated window the literal scheme was timed on, s.
    pub literal_window_s: f64,
    /// The literal window run.
    pub literal_window_run: Timed,
    /// fig2_literal_extrapolated_s / fig2_accurate_s.
    pub speedup: f64,
    /// T2: N = 2000, fixed Δt = 1e-8 s, whole run, 2 threads, s.
    pub full_resolution_s: f64,
    /// Whether T2 ran in full (else extrapolated from `full_resolution_window_s`).
    pub full_resolution_measured: bool,
    /// Window T2 was timed on first, s.
    pub full_resolution_window_s: f64,
    /// T2 runs.
    pub full_resolution_runs: Vec<Timed>,
    /// T2 profile: loop µs per step on the T2 window with a rigid substrate (everything but
    /// the elastic coupling: Landau steps, forces, output) and with the elastic one.
    pub t2_profile_rigid_us_per_step: f64,
    /// See `t2_profile_rigid_us_per_step`.
    pub t2_profile_elastic_us_per_step: f64,
    /// Coupling-solver (BiCGSTAB) iterations per step on the T2 window.
    pub t2_coupling_iterations_per_step: f64,
    /// T3: fitted log–log slope of loop time per step against N (fast operator, 2 threads).
    pub slope: f64,
    /// T3 slope of the dense operator.
    pub slope_dense: f64,
    /// T3 points.
    pub cost_per_step: Vec<CostPoint>,
    /// T4 points (N = 125).
    pub work_precision: Vec<WpPoint>,
    /// Reference onsets (adaptive, `reference_nodes`, `reference_tolerance`), s.
    pub reference_onsets_s: Vec<f64>,
    /// Reference settings.
    pub reference_settings: Vec<String>,
    /// Largest onset difference of the reference to a half-resolution, 10× looser run, µs:
    /// an upper estimate of the reference's own error.
    pub reference_uncertainty_us: f64,
    /// Total time of the benchmark, s.
    pub total_s: f64,
    /// Machine note.
    pub machine: String,
}

fn set(k: &str, v: impl std::fmt::Display) -> String {
    format!("{k}={v}")
}

/// Runs all measurements.
///
/// # Errors
/// A run that failed.
pub fn measure(s: &BenchSettings) -> Result<Performance, String> {
    let start = Instant::now();
    std::fs::create_dir_all(&s.work_dir).map_err(|e| e.to_string())?;
    let progress = |msg: &str| eprintln!("[{:7.1} s] {msg}", start.elapsed().as_secs_f64());

    // Reference: the accurate scheme at high resolution, and a check run at half of it.
    progress("reference");
    let ref_sets = vec![
        set("contact.nodes", s.reference_nodes),
        set("time.tolerance", s.reference_tolerance),
    ];
    let reference = run_cli(s, "reference", &ref_sets, 2)?;
    let check_sets = vec![
        set("contact.nodes", s.reference_nodes / 2),
        set("time.tolerance", 10.0 * s.reference_tolerance),
    ];
    let check = run_cli(s, "reference_check", &check_sets, 2)?;
    let reference_uncertainty_us = 1e6 * max_onset_error_s(&check.onsets_s, &reference.onsets_s);
    let r = &reference.onsets_s;

    // T1.
    progress("T1: fig2 accurate, default settings, N = 200");
    let t1_sets = vec![set("contact.nodes", 200)];
    let t1_two = timed(s, "t1", &t1_sets, 2, s.repeats, r)?;
    let t1_one = timed(s, "t1", &t1_sets, 1, s.repeats, r)?;

    // The paper's algorithm at its own settings, on a window.
    let literal_window_s = if s.quick { 5e-6 } else { 3.4e-5 };
    progress("literal N = 2000 window");
    let lit_sets = vec![
        set("contact.nodes", 2000),
        set("time.scheme", "literal"),
        set("time.dt", 1e-8),
        set("time.end", literal_window_s),
        format!("output.profile_times=[{literal_window_s:e}]"),
    ];
    let literal_window_run = timed(s, "literal", &lit_sets, 2, 1, &[])?;
    let setup_s = literal_window_run.wall_s - literal_window_run.loop_s;
    let fig2_literal_extrapolated_s =
        setup_s + literal_window_run.loop_s * FIG2_END_S / literal_window_s;

    // T2.
    progress("T2: N = 2000, fixed dt = 1e-8 s");
    let full_resolution_window_s = if s.quick { 2e-6 } else { 2.6e-5 };
    let t2_window_sets = vec![
        set("contact.nodes", 2000),
        set("time.stepping", "fixed"),
        set("time.dt", 1e-8),
        set("time.end", full_resolution_window_s),
        format!("output.profile_times=[{full_resolution_window_s:e}]"),
    ];
    let t2_window = timed(s, "t2_window", &t2_window_sets, 2, s.repeats, &[])?;
    let mut rigid_sets = t2_window_sets.clone();
    rigid_sets.push(set("contact.substrate", "rigid"));
    let t2_rigid = timed(s, "t2_rigid", &rigid_sets, 2, s.repeats, &[])?;
    let per_step = |t: &Timed| 1e6 * t.loop_s / t.steps.max(1) as f64;
    let t2_profile_rigid_us_per_step = per_step(&t2_rigid);
    let t2_profile_elastic_us_per_step = per_step(&t2_window);
    let t2_coupling_iterations_per_step =
        t2_window.coupling_iterations as f64 / t2_window.steps.max(1) as f64;
    let projected = (t2_window.wall_s - t2_window.loop_s)
        + t2_window.loop_s * FIG2_END_S / full_resolution_window_s;
    let mut full_resolution_runs = vec![t2_window];
    let (full_resolution_s, full_resolution_measured) =
        if !s.quick && projected <= s.full_run_limit_s {
            progress("T2: full run");
            let full_sets = vec![
                set("contact.nodes", 2000),
                set("time.stepping", "fixed"),
                set("time.dt", 1e-8),
            ];
            let full = timed(s, "t2_full", &full_sets, 2, 1, r)?;
            let wall = full.wall_s;
            full_resolution_runs.push(full);
            (wall, true)
        } else {
            (projected, false)
        };

    // T3.
    let mut cost_per_step = Vec::new();
    for &n in &s.sweep_nodes {
        for operator in ["fast", "dense"] {
            if operator == "dense" && n > 4000 {
                continue;
            }
            progress(&format!("T3: N = {n}, {operator}"));
            let window = s.sweep_steps as f64 * 1e-8;
            let sets = vec![
                set("contact.nodes", n),
                set("time.stepping", "fixed"),
                set("time.dt", 1e-8),
                set("time.end", window),
                format!("output.profile_times=[{window:e}]"),
                set("numerics.operator", operator),
            ];
            let t = timed(s, &format!("t3_{n}_{operator}"), &sets, 2, s.repeats, &[])?;
            cost_per_step.push(CostPoint {
                nodes: n,
                operator: operator.to_string(),
                us_per_step: 1e6 * t.loop_s / t.steps.max(1) as f64,
                threads: 2,
            });
        }
    }
    let slope_of = |op: &str| {
        let pts: Vec<(f64, f64)> = cost_per_step
            .iter()
            .filter(|p| p.operator == op)
            .map(|p| (p.nodes as f64, p.us_per_step))
            .collect();
        log_log_slope(&pts)
    };
    let slope = slope_of("fast");
    let slope_dense = slope_of("dense");

    // T4.
    let mut work_precision = Vec::new();
    let tolerances: &[f64] = if s.quick {
        &[1e-3, 1e-4]
    } else {
        &[1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6]
    };
    for &tol in tolerances {
        progress(&format!("T4: adaptive tol {tol:e}"));
        let sets = vec![set("contact.nodes", 125), set("time.tolerance", tol)];
        let t = timed(s, "t4", &sets, 2, s.repeats, r)?;
        work_precision.push(WpPoint {
            method: "adaptive".into(),
            parameter: tol,
            wall_s: t.wall_s,
            max_onset_error_us: t.max_onset_error_us,
            steps: t.steps,
            rejected_steps: t.rejected_steps,
        });
    }
    let dts: &[f64] = if s.quick {
        &[8e-8]
    } else {
        &[3.2e-7, 1.6e-7, 8e-8, 4e-8, 2e-8, 1e-8]
    };
    for &dt in dts {
        progress(&format!("T4: fixed dt {dt:e}"));
        let sets = vec![
            set("contact.nodes", 125),
            set("time.stepping", "fixed"),
            set("time.dt", dt),
        ];
        let t = timed(s, "t4", &sets, 2, s.repeats, r)?;
        work_precision.push(WpPoint {
            method: "fixed".into(),
            parameter: dt,
            wall_s: t.wall_s,
            max_onset_error_us: t.max_onset_error_us,
            steps: t.steps,
            rejected_steps: 0,
        });
    }
    let fig2_accurate_s = t1_two.wall_s;
    Ok(Performance {
        fig2_accurate_s,
        fig2_accurate_1thread_s: t1_one.wall_s,
        fig2_accurate_max_onset_error_us: t1_two.max_onset_error_us,
        fig2_accurate_runs: vec![t1_two, t1_one],
        fig2_literal_extrapolated_s,
        literal_window_s,
        literal_window_run,
        speedup: fig2_literal_extrapolated_s / fig2_accurate_s,
        full_resolution_s,
        full_resolution_measured,
        full_resolution_window_s,
        full_resolution_runs,
        t2_profile_rigid_us_per_step,
        t2_profile_elastic_us_per_step,
        t2_coupling_iterations_per_step,
        slope,
        slope_dense,
        cost_per_step,
        work_precision,
        reference_onsets_s: reference.onsets_s,
        reference_settings: ref_sets,
        reference_uncertainty_us,
        total_s: start.elapsed().as_secs_f64(),
        machine: format!(
            "{} logical CPUs; release build; wall times of whole processes",
            std::thread::available_parallelism().map_or(0, usize::from)
        ),
    })
}

fn cost_figure(p: &Performance) -> Result<String, String> {
    let mut panel = Panel::new(
        "T3: loop time per step against N (fixed dt = 1e-8 s, 2 threads)",
        "nodes N",
        "time per step (µs)",
    );
    for (k, op) in ["fast", "dense"].iter().enumerate() {
        let pts: Vec<(f64, f64)> = p
            .cost_per_step
            .iter()
            .filter(|c| c.operator == *op)
            .map(|c| (c.nodes as f64, c.us_per_step))
            .collect();
        let slope = log_log_slope(&pts);
        panel.series.push(
            Series::new(format!("{op} operator (slope {slope:.2})"), pts, PALETTE[k]).marker(
                if k == 0 {
                    Marker::Circle
                } else {
                    Marker::Square
                },
            ),
        );
    }
    panel.auto_guides(&[1.0, 2.0], false);
    render_svg(&[panel], 1, 800, 560)
}

fn wp_figure(p: &Performance) -> Result<String, String> {
    let mut panel = Panel::new(
        "T4: work–precision of fig2 at N = 125 (largest onset error vs wall time)",
        "wall time (s)",
        "largest onset error (µs)",
    );
    for (k, method) in ["adaptive", "fixed"].iter().enumerate() {
        let pts: Vec<(f64, f64)> = p
            .work_precision
            .iter()
            .filter(|w| w.method == *method && w.max_onset_error_us.is_finite())
            .map(|w| (w.wall_s, w.max_onset_error_us.max(1e-6)))
            .collect();
        let labels: Vec<String> = p
            .work_precision
            .iter()
            .filter(|w| w.method == *method && w.max_onset_error_us.is_finite())
            .map(|w| format!("{:.0e}", w.parameter))
            .collect();
        panel.series.push(
            Series::new(
                if k == 0 {
                    "adaptive (labels: tolerance)"
                } else {
                    "fixed (labels: dt in s)"
                },
                pts,
                PALETTE[k],
            )
            .labels(labels),
        );
    }
    panel.hlines.push((0.1, "0.1 µs target".into()));
    render_svg(&[panel], 1, 800, 560)
}

fn markdown(p: &Performance) -> String {
    use std::fmt::Write;
    let mut m = String::new();
    let verdict = |ok: bool| if ok { "**met**" } else { "**not met**" };
    let _ = writeln!(m, "# Performance (`cargo xtask bench`)\n");
    let _ = writeln!(
        m,
        "Generated by `cargo xtask bench` in {:.0} s on this machine ({}). Medians of repeated \
         runs; ratios are from the same run. Onset errors are against a reference computed in \
         the same run ({}; its own uncertainty, from a half-resolution run at 10× the \
         tolerance: ≤ {:.4} µs).\n",
        p.total_s,
        p.machine,
        p.reference_settings.join(", "),
        p.reference_uncertainty_us
    );
    let t1 = &p.fig2_accurate_runs[0];
    let _ = writeln!(
        m,
        "| target | goal | measured | verdict |\n|---|---|---|---|"
    );
    let _ = writeln!(
        m,
        "| T1 fig2, default accurate settings, N = 200 | ≤ 0.5 s, onsets within 0.1 µs | {:.3} s (2 threads), {:.3} s (1 thread); largest onset error {:.4} µs; {} steps, {} rejected | {} |",
        p.fig2_accurate_s,
        p.fig2_accurate_1thread_s,
        p.fig2_accurate_max_onset_error_us,
        t1.steps,
        t1.rejected_steps,
        verdict(p.fig2_accurate_s <= 0.5 && p.fig2_accurate_max_onset_error_us <= 0.1)
    );
    let _ = writeln!(
        m,
        "| T1 speed-up over the literal scheme (N = 2000, dt = 1e-8 s) | ≥ 300× | {:.0}× ({:.1} s extrapolated from a {:.1} µs window = {:.1} % of the run) | {} |",
        p.speedup,
        p.fig2_literal_extrapolated_s,
        p.literal_window_s * 1e6,
        100.0 * p.literal_window_s / FIG2_END_S,
        verdict(p.speedup >= 300.0)
    );
    let _ = writeln!(
        m,
        "| T2 N = 2000, fixed dt = 1e-8 s, whole run | ≤ 10 s | {:.1} s ({}) | {} |",
        p.full_resolution_s,
        if p.full_resolution_measured {
            "measured in full".to_string()
        } else {
            format!(
                "extrapolated from a {:.0} µs window",
                p.full_resolution_window_s * 1e6
            )
        },
        verdict(p.full_resolution_s <= 10.0)
    );
    let _ = writeln!(
        m,
        "| T3 slope of time per step against N (fast operator) | ≤ 1.2 | {:.2} (dense: {:.2}) | {} |",
        p.slope,
        p.slope_dense,
        verdict(p.slope <= 1.2)
    );
    let best_fixed = p
        .work_precision
        .iter()
        .filter(|w| w.method == "fixed" && w.max_onset_error_us <= 0.1)
        .map(|w| w.wall_s)
        .fold(f64::INFINITY, f64::min);
    let best_adaptive = p
        .work_precision
        .iter()
        .filter(|w| w.method == "adaptive" && w.max_onset_error_us <= 0.1)
        .map(|w| w.wall_s)
        .fold(f64::INFINITY, f64::min);
    let _ = writeln!(
        m,
        "| T4 adaptive steps | error-controlled, cheaper than fixed | cheapest run within 0.1 µs: adaptive {:.3} s, fixed {:.3} s | {} |\n",
        best_adaptive,
        best_fixed,
        verdict(best_adaptive < best_fixed)
    );
    let _ = writeln!(
        m,
        "## T1 — fig2 with the default settings\n\n`stickslip run validation/scenes/fig2.toml \
         --set contact.nodes=200` (accurate scheme, adaptive steps, default tolerance). \
         Wall times of the whole process, {} runs each: 2 threads {:?} s, 1 thread {:?} s.\n",
        t1.walls_s.len(),
        t1.walls_s
            .iter()
            .map(|w| (w * 1e3).round() / 1e3)
            .collect::<Vec<_>>(),
        p.fig2_accurate_runs[1]
            .walls_s
            .iter()
            .map(|w| (w * 1e3).round() / 1e3)
            .collect::<Vec<_>>()
    );
    let _ = writeln!(
        m,
        "The literal scheme was timed on t ∈ [0, {:.1} µs] ({} steps, loop {:.2} s, process {:.2} s) and \
         extrapolated per simulated second to 1.3 ms: {:.1} s.\n",
        p.literal_window_s * 1e6,
        p.literal_window_run.steps,
        p.literal_window_run.loop_s,
        p.literal_window_run.wall_s,
        p.fig2_literal_extrapolated_s
    );
    let apply_2000 = p
        .cost_per_step
        .iter()
        .find(|c| c.nodes == 2000 && c.operator == "fast")
        .map_or(f64::NAN, |c| c.us_per_step);
    let _ = writeln!(
        m,
        "## T2 — what bounds the full-resolution run\n\n{:.1} s for 130 000 steps is {:.0} µs \
         per step against the 77 µs the target needs. Profile on the first {:.0} µs (loop time \
         per step, N = 2000): everything but the elastic coupling (rigid substrate: the exact \
         Landau step of 2000 nodes with its exp/expm1/sqrt, forces, a series row every 10 \
         steps) {:.0} µs; with the elastic coupling {:.0} µs, so the coupling costs {:.0} µs. \
         BiCGSTAB takes {:.2} iterations per step on average (warm-started from the \
         extrapolated u3D); each iteration applies the compliance twice and each compliance \
         is two fast transforms (about 12 µs each at N = 2000, see the criterion bench \
         `hodlr_apply`), plus the initial residual: about {:.0} transform applies per step. \
         Reaching 77 µs needs both fewer transforms per step (a preconditioner, or skipping \
         the solve when the extrapolated u3D already meets the tolerance) and a cheaper \
         per-node Landau step (vectorised exp). The cost-per-step sweep below (fixed steps, \
         same run) gives {:.0} µs at N = 2000.\n",
        p.full_resolution_s,
        1e6 * p.full_resolution_s / 130_000.0,
        p.full_resolution_window_s * 1e6,
        p.t2_profile_rigid_us_per_step,
        p.t2_profile_elastic_us_per_step,
        p.t2_profile_elastic_us_per_step - p.t2_profile_rigid_us_per_step,
        p.t2_coupling_iterations_per_step,
        2.0 + 4.0 * p.t2_coupling_iterations_per_step,
        apply_2000
    );
    let _ = writeln!(
        m,
        "## T3 — cost per step against N\n\n![cost](performance_cost.svg)\n\n| N | operator | µs per step |\n|---|---|---|"
    );
    for c in &p.cost_per_step {
        let _ = writeln!(m, "| {} | {} | {:.1} |", c.nodes, c.operator, c.us_per_step);
    }
    let _ = writeln!(
        m,
        "\n## T4 — work–precision at N = 125\n\n![work-precision](performance_work_precision.svg)\n\n| method | tolerance or dt | wall (s) | largest onset error (µs) | steps | rejected |\n|---|---|---|---|---|---|"
    );
    for w in &p.work_precision {
        let _ = writeln!(
            m,
            "| {} | {:e} | {:.3} | {:.4} | {} | {} |",
            w.method, w.parameter, w.wall_s, w.max_onset_error_us, w.steps, w.rejected_steps
        );
    }
    m
}

/// Writes performance.json, performance.md and the two SVGs into `dir`.
///
/// # Errors
/// An I/O or rendering error, as text.
pub fn write_report(p: &Performance, dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut files = Vec::new();
    let mut put = |name: &str, text: String| -> Result<(), String> {
        files.push(crate::report::write_atomic(dir, name, &text)?);
        Ok(())
    };
    let json = serde_json::to_string_pretty(p).map_err(|e| e.to_string())?;
    put("performance.json", json + "\n")?;
    put("performance_cost.svg", cost_figure(p)?)?;
    put("performance_work_precision.svg", wp_figure(p)?)?;
    put("performance.md", markdown(p))?;
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law() {
        let pts: Vec<(f64, f64)> = [125.0, 250.0, 500.0, 1000.0]
            .iter()
            .map(|&n: &f64| (n, 3.0 * n.powf(1.1)))
            .collect();
        assert!((log_log_slope(&pts) - 1.1).abs() < 1e-12);
    }

    #[test]
    fn csv_column_by_name() {
        let text = "k,t_onset,r_first\n1,5e-4,2e-5\n2,6.5e-4,2e-5\n";
        assert_eq!(csv_column(text, "t_onset").unwrap(), vec![5e-4, 6.5e-4]);
        assert!(csv_column(text, "nope").is_err());
    }

    #[test]
    fn onset_error_needs_equal_counts() {
        assert_eq!(max_onset_error_s(&[1.0, 2.0], &[1.0]), f64::INFINITY);
        assert!((max_onset_error_s(&[1.0, 2.5], &[1.5, 2.0]) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn median_of_odd_and_even() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}
