//! The timings' spread and CPU time, verdicts within noise, and the per-step costs of the
//! paper's configuration side by side (`performance.md`'s "Timings" section).
//!
//! A timed run is repeated (`--repeats`); its median is the figure quoted, its min–max the
//! spread. A ratio of two timed runs spans [min a / max b, max a / min b]. A verdict whose
//! threshold lies inside that span reads "within noise": another run on this host could
//! flip it.

use super::{Performance, Timed};
use std::fmt::Write as _;
use stickslip_report::fmt::sig;
use stickslip_report::stats::median;

/// min and max of `xs` (NaN for none).
#[must_use]
pub fn min_max(xs: &[f64]) -> (f64, f64) {
    xs.iter()
        .fold((f64::NAN, f64::NAN), |(lo, hi), &x| (lo.min(x), hi.max(x)))
}

/// The span of the ratio a/b over the two runs' repeats.
#[must_use]
pub fn ratio_span(a: &Timed, b: &Timed) -> (f64, f64) {
    let (alo, ahi) = min_max(&a.walls_s);
    let (blo, bhi) = min_max(&b.walls_s);
    (alo / bhi, ahi / blo)
}

/// Whether `goal` lies inside the span (lo, hi).
#[must_use]
pub fn within_noise((lo, hi): (f64, f64), goal: f64) -> bool {
    lo <= goal && goal <= hi
}

/// The verdict in the report's words, marked when within noise.
#[must_use]
pub fn verdict(ok: bool, noisy: bool) -> String {
    let v = if ok { "**met**" } else { "**not met**" };
    if noisy {
        format!("{v} (within noise)")
    } else {
        v.to_string()
    }
}

/// "median (min–max, n runs)" for a timed run, s.
fn wall_text(t: &Timed) -> String {
    let (lo, hi) = min_max(&t.walls_s);
    if t.walls_s.len() > 1 {
        format!(
            "{} ({}–{}, {} runs)",
            sig(t.wall_s, 3),
            sig(lo, 3),
            sig(hi, 3),
            t.walls_s.len()
        )
    } else {
        format!("{} (1 run)", sig(t.wall_s, 3))
    }
}

fn cpu_text(t: &Timed) -> (String, String) {
    if t.cpus_s.is_empty() {
        return ("–".into(), "–".into());
    }
    let cpu = median(&t.cpus_s);
    (sig(cpu, 3), sig(cpu / t.wall_s, 2))
}

/// The timed runs of the report, by what they time.
fn runs(p: &Performance) -> Vec<(String, &Timed)> {
    let mut out = Vec::new();
    let names = ["P3 fig2 N = 200, 2 threads", "P3 fig2 N = 200, 1 thread"];
    for (name, t) in names.iter().zip(&p.fig2_accurate_runs) {
        out.push(((*name).to_string(), t));
    }
    out.push(("P1 fig2 as shipped (N = 2000)".into(), &p.shipped));
    out.push(("P1 the same, rigid substrate".into(), &p.shipped_rigid));
    out.push((
        format!(
            "P1 literal scheme, window of {} µs",
            sig(p.literal_window_s * 1e6, 3)
        ),
        &p.literal_window_run,
    ));
    out.push(("P6 fig2 N = 200, first-order film".into(), &p.first_order));
    let t2 = [
        format!(
            "P2 profile window (first {} µs)",
            sig(p.full_resolution_window_s * 1e6, 2)
        ),
        "P2 whole run (0 → 1.3 ms)".to_string(),
    ];
    for (name, t) in t2.iter().zip(&p.full_resolution_runs) {
        out.push((name.clone(), t));
    }
    if let Some(r) = &p.rigid_full {
        out.push(("P2 whole run, rigid substrate".into(), r));
    }
    out
}

/// The section.
pub(super) fn section(m: &mut String, p: &Performance) {
    let _ = writeln!(
        m,
        "## Timings: spread and CPU time\n\n\
         Each timed configuration, its process wall time as the median with the min–max over \
         its repeats, and the process's CPU time (user + system over all its threads, from the \
         kernel's accounting of that child; the median over repeats) beside it: a CPU/wall \
         ratio near 2 uses both cores, near 1 one. A ratio target whose threshold lies inside \
         the span of its ratio over the repeats, [min a / max b, max a / min b], reads \
         \"within noise\" in the table above (P1, P3, P6; the others are single runs or \
         counts; for P1, a is each repeat of the literal window extrapolated and capped as its \
         median is).\n\n\
         | run | wall (s): median (min–max) | CPU (s) | CPU / wall |\n|---|---|---|---|"
    );
    for (name, t) in runs(p) {
        let (cpu, ratio) = cpu_text(t);
        let _ = writeln!(m, "| {name} | {} | {cpu} | {ratio} |", wall_text(t));
    }
    let _ = writeln!(m);
    per_step_costs(m, p);
}

/// The paper's configuration (N = 2000, fixed Δt) timed three ways, side by side.
fn per_step_costs(m: &mut String, p: &Performance) {
    let Some(t3) = p
        .cost_per_step
        .iter()
        .find(|c| c.nodes == p.paper_nodes && c.operator == "fast")
    else {
        return;
    };
    let window = p.full_resolution_runs.first();
    let whole = p.full_resolution_runs.get(1);
    let _ = writeln!(
        m,
        "**One configuration, three per-step costs.** N = {}, fixed Δt = {:e} s, the fast \
         operator, 2 threads, is timed three times in this run, over three windows:\n\n\
         | measurement | window | loop µs per step | coupling iterations per step |\n|---|---|---|---|",
        p.paper_nodes, p.paper_dt_s
    );
    // (measurement, window end in µs with its digits, loop µs per step, iterations per step)
    let per_step = |t: &Timed| t.coupling_iterations as f64 / t.steps.max(1) as f64;
    let mut rows = Vec::new();
    if let Some(w) = window {
        let end = sig(p.full_resolution_window_s * 1e6, 2);
        rows.push(("P2 profile", end, w.us_per_step(), per_step(w)));
    }
    let t3_end = sig(p.sweep_window_s * 1e6, 2);
    rows.push((
        "T3",
        t3_end,
        t3.us_per_step,
        t3.coupling_iterations_per_step,
    ));
    if let Some(w) = whole {
        let end = sig(p.scene_end_s * 1e6, 3);
        rows.push(("P2 whole run", end, w.us_per_step(), per_step(w)));
    }
    for (name, end, us, iterations) in &rows {
        let _ = writeln!(
            m,
            "| {name} | 0 → {end} µs | {} | {} |",
            sig(*us, 3),
            sig(*iterations, 3)
        );
    }
    let costs: Vec<f64> = rows.iter().map(|r| r.2).collect();
    let (lo, hi) = min_max(&costs);
    let iterations: Vec<f64> = rows.iter().map(|r| r.3).collect();
    let (ilo, ihi) = min_max(&iterations);
    let _ = writeln!(
        m,
        "\nThey differ by {}× at most. The windows differ: the two short ones see only the \
         start of the first stick phase, the whole run its ten slips too, and the coupling's \
         work per step differs with them ({}–{} iterations per step). Each is a separate \
         process on a shared host, whose spread the table above gives where the run was \
         repeated. The P2 verdict uses the whole run; the T3 slope uses only ratios within its \
         own sweep.\n",
        sig(hi / lo, 3),
        sig(ilo, 2),
        sig(ihi, 2)
    );
}
