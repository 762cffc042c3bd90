//! Section 7 of the report, findings for the engine: the accurate scheme's order in Δt, the
//! literal scheme beyond its stability limit, where onsets are located, and what N costs.

use super::{
    Paper, literal_gaps_s, max_error_per_level, median_p, p2, range, runs, sims, span, tol_text,
};
use crate::Results;
use crate::fig2::RunSpec;
use crate::study::Refined;
use std::fmt::Write as _;
use stickslip_core::config::Scheme;
use stickslip_core::mdr::OperatorForm;
use stickslip_core::preflight::EULER_STABILITY_LIMIT;
use stickslip_report::fmt::{sig, tick};
use stickslip_report::stats::log_log_slope;

/// Writes "## 7. Findings for the engine".
pub(super) fn section(md: &mut String, r: &Results, paper: &Paper) {
    let _ = writeln!(md, "## 7. Findings for the engine\n");
    let e_dt = max_error_per_level(&sims(r, "accurate", Refined::Dt, "onset"), 1e-6);
    let at_paper_dt = e_dt
        .iter()
        .find(|(l, _)| paper.is_paper_dt(*l))
        .map(|&(_, e)| e);
    let _ = writeln!(
        md,
        "1. **The accurate scheme's onsets converge at p ≈ {} in Δt.** The film step uses the \
         exact Landau solution under a strain weighted by θ(λΔt) between the start of the step \
         and the end predicted from the extrapolated substrate (½ for slow relaxation, → 1 \
         when φ is slaved to ε), melting is located inside the step and is instantaneous \
         (φ touches the threshold and recovers), and event onsets are located on the node's \
         exact path. At the paper's Δt = {:e} s the largest onset error (Δt part, N = {}) is \
         {} µs. Adaptive, error-controlled steps: §5 here (per tolerance, against same-N \
         references) and reports/performance.md, T4.",
        p2(median_p(r, "accurate", Refined::Dt, "onset")),
        paper.dt_s,
        r.settings.sim_dts_nodes,
        at_paper_dt.map_or("–".into(), |e| sig(e, 2))
    );
    let limit = paper.euler_limit_s();
    let lit_dt = runs(r, "dt", "literal");
    let finished_beyond: Vec<String> = lit_dt
        .iter()
        .filter(|x| x.dt_s > limit && x.failure.is_none())
        .map(|x| {
            format!(
                "At Δt = {:e} s (Δt·2γAb/a = {} > {}, beyond explicit Euler's limit) the core's \
                 runaway checks pass and the run finishes, with f_peak {} % off.",
                x.dt_s,
                sig(paper.euler_number(x.dt_s), 2),
                tick(EULER_STABILITY_LIMIT),
                sig(100.0 * x.f_peak_error_rel.unwrap_or(f64::NAN), 2)
            )
        })
        .collect();
    let smallest_failed = lit_dt
        .iter()
        .filter(|x| x.failure.is_some())
        .map(|x| x.dt_s)
        .fold(f64::INFINITY, f64::min);
    let gaps = range(literal_gaps_s(r).iter().map(|&(_, g)| g.abs() * 1e6));
    let _ = writeln!(
        md,
        "2. **The literal scheme can be silently wrong.** {}{}The preflight warns when \
         Δt·2γAb/a > {} for the literal scheme (run.json `derived.euler_number`, a warning on \
         `time.dt`). The paper's u3D(0) = 0 moves the onsets by {} µs (answer 4).",
        finished_beyond.join(" "),
        if smallest_failed.is_finite() {
            format!(" Only Δt ≥ {smallest_failed:e} s fails. ")
        } else {
            " No level fails. ".to_string()
        },
        tick(EULER_STABILITY_LIMIT),
        gaps.map_or("–".into(), |(lo, hi)| span(lo, hi, 2))
    );
    let _ = writeln!(
        md,
        "3. **Event onsets in `events.csv` are located inside the step** by the accurate \
         scheme (on the first melting node's exact path); the literal scheme reports the end of \
         the step, and this study locates its onsets from the public state (ln φ interpolated in \
         time). The JSON keeps both (`onset_step_s`, `onset_s`).",
    );
    let acc_n = runs(r, "N", "accurate");
    let n_top = r.settings.sim_nodes.last().copied().unwrap_or(0);
    let top = acc_n.iter().find(|x| x.nodes == n_top);
    let cost: Vec<(f64, f64)> = acc_n
        .iter()
        .filter(|x| x.failure.is_none())
        .map(|x| (x.nodes as f64, x.wall_s))
        .collect();
    let cost_slope = (cost.len() >= 2).then(|| log_log_slope(&cost));
    let form = match RunSpec::fig2(Scheme::Accurate, n_top.max(1), r.settings.sim_nodes_dt_s)
        .scene()
        .config
        .operator_form()
    {
        OperatorForm::Fast => "fast",
        OperatorForm::Dense => "dense",
    };
    let e_n = max_error_per_level(&sims(r, "accurate", Refined::Nodes, "onset"), 1e-6);
    let n0 = r.settings.sim_nodes.first().copied().unwrap_or(0);
    let _ = writeln!(
        md,
        "4. **Cost.** The accurate run at N = {n_top}, Δt = {:e} s took {} s here (operator \
         `{form}` as the scene resolves it; wall time ∝ N^{} over the N study), yet the N part \
         of the onset error is at most {} µs from N = {n0} on; the cheapest run within {} is in \
         answer 2.\n",
        r.settings.sim_nodes_dt_s,
        top.map_or("–".into(), |x| sig(x.wall_s, 2)),
        cost_slope.map_or("–".into(), |s| format!("{s:.2}")),
        e_n.first().map_or("–".into(), |&(_, e)| sig(e, 2)),
        tol_text()
    );
}
