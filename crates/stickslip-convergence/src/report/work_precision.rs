//! Section 4 of the report, work–precision: the reference (per-event onsets and peak forces
//! with their uncertainties), the timed points of each method, and Figure 5
//! (`convergence_work_precision.svg`, error against wall time).

use super::{
    ONSET_TOL_S, Paper, header, range, reference_n_error_s, reference_onset_uncertainty_s, row,
    runs, span, tol_text,
};
use crate::Results;
use std::fmt::Write as _;
use stickslip_report::fmt::{opt, sig};
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{LegendAt, Marker, Panel, Series, render_svg};
use stickslip_report::stats::log_log_slope;

/// Writes "## 4. Work–precision".
pub(super) fn section(md: &mut String, r: &Results, paper: &Paper) {
    let wp = &r.work_precision;
    let rf = &wp.reference;
    let finest_n = r.settings.wp_points.iter().map(|p| p.0).max().unwrap_or(0);
    let finest_dt = r
        .settings
        .wp_points
        .iter()
        .map(|p| p.1)
        .fold(f64::INFINITY, f64::min);
    let coarsest_ref_dt = rf.dts_s.first().copied().unwrap_or(f64::NAN);
    let _ = writeln!(md, "## 4. Work–precision\n");
    let _ = writeln!(
        md,
        "**Reference.** The accurate scheme at N = {} ({}× the finest N of any curve point) with \
         Δt = {:?} s (the coarsest {} the finest curve point's Δt), extrapolated in Δt per \
         event with Celik's procedure; F(t) extrapolated pointwise with the order of its \
         difference norms (p = {}, GCI {} relative). The three runs took {} s. Its N-error is \
         estimated by the accurate N study: at N = {} the onsets are within {} µs of the N \
         extrapolation. Per event:\n",
        rf.nodes,
        sig(rf.nodes as f64 / finest_n.max(1) as f64, 2),
        rf.dts_s,
        if super::same(coarsest_ref_dt, finest_dt) {
            "equal to".to_string()
        } else {
            format!("{}×", sig(coarsest_ref_dt / finest_dt, 2))
        },
        opt(rf.force_order, 2),
        opt(rf.force_uncertainty_rel, 2),
        rf.wall_s
            .iter()
            .map(|w| sig(*w, 2))
            .collect::<Vec<_>>()
            .join(" + "),
        r.settings
            .sim_nodes
            .iter()
            .find(|&&n| n >= rf.nodes)
            .copied()
            .unwrap_or(0),
        reference_n_error_s(r).map_or("–".into(), |e| sig(e * 1e6, 2))
    );
    if let Some(x) = &rf.n_extrapolation {
        let _ = writeln!(
            md,
            "**Extrapolated in N.** The estimate above is applied: the accurate N study's three \
             finest levels (N = {:?}, Δt = {:e} s) give each event's limit and order in N \
             (Celik), the error model e(N) = (φ_m − φ∞)·(m/N)^p from the level m nearest above \
             N = {} gives the reference's own N error, and it is subtracted: the onsets move by \
             up to {} µs (orders in N {}). The uncertainties below hold the Δt GCI, the N \
             GCI and the spread of e between the two levels above N = {} (the model's distance \
             from a pure power); the Δt and N errors are assumed to add. Runs are judged again \
             from their stored events{}. The F(t) reference stays at N = {}.\n",
            x.levels,
            r.settings.sim_nodes_dt_s,
            rf.nodes,
            sig(x.max_onset_correction_s() * 1e6, 2),
            range(x.onset_order.iter().flatten().copied())
                .map_or("–".into(), |(lo, hi)| span(lo, hi, 2)),
            rf.nodes,
            if x.bounded_points > 0 {
                format!(
                    "; {} work–precision points, stored without theirs, carry the bound old \
                     error + largest correction",
                    x.bounded_points
                )
            } else {
                String::new()
            },
            rf.nodes
        );
    }
    header(
        md,
        &[
            "event",
            "onset (µs)",
            "± GCI (µs)",
            "p in Δt",
            "f_peak (mN)",
            "± GCI (mN)",
        ],
    );
    for k in 0..rf.onsets_s.len() {
        row(
            md,
            &[
                (k + 1).to_string(),
                sig(rf.onsets_s[k] * 1e6, 8),
                sig(rf.onset_uncertainty_s[k] * 1e6, 2),
                opt(rf.onset_order[k], 3),
                sig(rf.f_peaks_n[k] * 1e3, 7),
                sig(rf.f_peak_uncertainty_n[k] * 1e3, 2),
            ],
        );
    }
    let _ = writeln!(
        md,
        "\n**Points** (each timed {} time(s) in this run; the median is shown):\n",
        wp.repeats
    );
    header(
        md,
        &[
            "method",
            "N",
            "Δt (s)",
            "wall (s)",
            "timings (s)",
            "max onset error (µs)",
            "max f_peak error (rel.)",
            "stick F error (rel. RMS)",
            "events",
        ],
    );
    for p in &wp.points {
        row(
            md,
            &[
                p.method.clone(),
                p.nodes.to_string(),
                format!("{:e}", p.dt_s),
                format!("{:.2}", p.wall_s),
                p.walls_s
                    .iter()
                    .map(|w| format!("{w:.2}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                opt(p.onset_error_s.map(|e| e * 1e6), 2),
                opt(p.f_peak_error_rel, 2),
                opt(p.force_error_rel, 2),
                format!(
                    "{}{}",
                    p.events,
                    p.failure
                        .as_ref()
                        .map_or(String::new(), |f| format!(" (failed: {f})"))
                ),
            ],
        );
    }
    let _ = writeln!(
        md,
        "\n![work-precision](convergence_work_precision.svg)\n\n*Figure 5. Error against wall \
         time, log–log, one curve per method along (N, Δt) = {:?}; each point is labelled N, \
         Δt. What to see: {}*\n",
        r.settings.wp_points,
        caption(r, paper)
    );
}

/// What Figure 5 shows, from the points.
fn caption(r: &Results, paper: &Paper) -> String {
    let wp = &r.work_precision;
    let ref_unc = reference_onset_uncertainty_s(r);
    let acc: Vec<(f64, f64)> = wp
        .points
        .iter()
        .filter(|p| p.method == "accurate")
        .filter_map(|p| p.onset_error_s.map(|e| (p.wall_s, e)))
        .collect();
    let slope = (acc.len() >= 2).then(|| log_log_slope(&acc));
    // Cost per step against N: wall time per fixed step of the accurate points.
    let per_step: Vec<(f64, f64)> = wp
        .points
        .iter()
        .filter(|p| p.method == "accurate")
        .map(|p| (p.nodes as f64, p.wall_s * p.dt_s / paper.end_s))
        .collect();
    let cost_slope = (per_step.len() >= 2).then(|| log_log_slope(&per_step));
    let literal = range(
        wp.points
            .iter()
            .filter(|p| p.method == "literal")
            .filter_map(|p| p.onset_error_s.map(|e| e * 1e6)),
    );
    let unstable: Vec<String> = wp
        .points
        .iter()
        .filter(|p| p.method == "literal" && p.dt_s > paper.euler_limit_s())
        .map(|p| format!("Δt = {:e} s", p.dt_s))
        .collect();
    let cheapest = |from: &mut dyn Iterator<Item = (f64, Option<f64>)>| {
        from.filter(|(_, e)| e.is_some_and(|e| e + ref_unc <= ONSET_TOL_S))
            .map(|(w, _)| w)
            .fold(f64::INFINITY, f64::min)
    };
    let diagonal = cheapest(
        &mut wp
            .points
            .iter()
            .filter(|p| p.method == "accurate")
            .map(|p| (p.wall_s, p.onset_error_s)),
    );
    let dt_alone = cheapest(
        &mut runs(r, "dt", "accurate")
            .into_iter()
            .map(|x| (x.wall_s, x.onset_error_s)),
    );
    let comparison = if diagonal.is_finite() && dt_alone.is_finite() {
        format!(
            "The cheapest run within {1} (with the reference's uncertainty) takes {2} s when \
             refining Δt alone at N = {0} (answer 2) and {3} s along this diagonal.",
            r.settings.sim_dts_nodes,
            tol_text(),
            sig(dt_alone, 2),
            sig(diagonal, 2)
        )
    } else {
        String::new()
    };
    format!(
        "the accurate onset error falls like (wall time)^{} here (least-squares slope) — each \
         halving of the error costs about {}× the time (fixed steps; the cost per step grows \
         like N^{} at these N); the literal onset error stays at {} µs however much time it \
         gets{}. {} {}Adaptive, error-controlled steps against fixed ones — the work–precision \
         curve of the fast methods — are in [performance.md](performance.md) (T4, \
         `performance_work_precision.svg`, from `cargo xtask bench`).",
        slope.map_or("–".into(), |s| format!("{s:.2}")),
        slope.map_or("–".into(), |s| sig(0.5f64.powf(1.0 / s), 2)),
        cost_slope.map_or("–".into(), |s| format!("{s:.2}")),
        literal.map_or("–".into(), |(lo, hi)| span(lo, hi, 2)),
        if unstable.is_empty() {
            String::new()
        } else {
            format!(
                " ({} beyond explicit Euler's stability limit)",
                unstable.join(", ")
            )
        },
        comparison,
        if r.tolerance.as_ref().is_some_and(|t| t.old.is_some()) {
            "The second row: the default adaptive stepping per tolerance against its same-N \
             reference (§5), the current controller against the one before the redesign, by \
             step evaluations and by loop wall time measured in one session. "
        } else {
            ""
        }
    )
}

/// Figure 5: error against wall time per method, for onsets, peak forces and F(t).
pub(super) fn figure(r: &Results) -> Result<String, String> {
    let wp = &r.work_precision;
    let mut panels = Vec::new();
    for (obs, ylabel) in [
        ("onset", "max |onset − reference| (µs)"),
        ("f_peak", "max |f_peak − reference| / reference"),
        ("force", "stick-phase RMS |F − F_ref| / max F"),
    ] {
        let mut p = Panel::new(
            &format!("Work–precision: {obs}"),
            "wall time (s), median of repeats",
            ylabel,
        )
        .log_log()
        .legend(LegendAt::LowerLeft);
        for (ci, method) in ["literal", "accurate"].iter().enumerate() {
            let (pts, labels): (Vec<(f64, f64)>, Vec<String>) = wp
                .points
                .iter()
                .filter(|x| x.method == *method)
                .filter_map(|x| {
                    let e = match obs {
                        "onset" => x.onset_error_s.map(|e| e * 1e6),
                        "f_peak" => x.f_peak_error_rel,
                        _ => x.force_error_rel,
                    }?;
                    Some(((x.wall_s, e), format!("{}, {:e}", x.nodes, x.dt_s)))
                })
                .unzip();
            let s = Series::new(*method, pts, PALETTE[ci]).labels(labels);
            p.series.push(if *method == "literal" {
                s.dashed().marker(Marker::Square)
            } else {
                s.marker(Marker::Circle)
            });
        }
        if obs == "onset" {
            p = p.hline(ONSET_TOL_S * 1e6, tol_text());
        }
        if let Some((v, label)) = super::reference_band(r, obs) {
            p = p.hline(v, label);
        }
        panels.push(p);
    }
    panels.extend(super::tolerance::work_precision_panels(r));
    render_svg(&panels, 3, 560, 430)
}
