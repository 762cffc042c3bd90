//! Section 3 of the report, the whole fig2 simulation: the F(t) table, the per-event tables
//! of onsets and peak forces per scheme and refinement, "where p is far from theory, and
//! why", and Figures 3 (`convergence_simulation.svg`, self-convergence) and 4
//! (`convergence_vs_reference.svg`, the same runs against the reference).

use super::{
    ONSET_TOL_S, Paper, event_count, header, level_name, level_ticks, max_error_per_level,
    median_p, orders, oscillatory, p2, range, row, runs, sims, span, theory_words, tol_text,
};
use crate::study::{ErrorKind, Refined, Study};
use crate::{Results, RunSummary};
use std::fmt::Write as _;
use stickslip_report::fmt::{opt, sig};
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{LegendAt, Marker, Panel, Series, render_svg};

/// The four (scheme, refinement) sequences in the order of the tables.
const SEQUENCES: [(&str, Refined); 4] = [
    ("literal", Refined::Nodes),
    ("accurate", Refined::Nodes),
    ("literal", Refined::Dt),
    ("accurate", Refined::Dt),
];

/// Writes "## 3. Whole simulation: fig2".
pub(super) fn section(md: &mut String, r: &Results, paper: &Paper) {
    let _ = writeln!(md, "## 3. Whole simulation: fig2\n");
    let _ = writeln!(
        md,
        "No exact answer: each observable is refined in N (Δt fixed) and in Δt (N fixed) \
         separately, for each scheme, and treated with Celik's three-grid procedure. A level \
         that fails or loses events is shown as –.\n"
    );
    force_table(md, r);
    for (scheme, refined) in [
        ("accurate", Refined::Nodes),
        ("accurate", Refined::Dt),
        ("literal", Refined::Nodes),
        ("literal", Refined::Dt),
    ] {
        let _ = writeln!(md, "### {scheme}, refining {}\n", refined.as_str());
        event_tables(md, r, scheme, refined);
    }
    let _ = writeln!(md, "### Where p is far from theory, and why\n");
    why(md, r, paper);
    let _ = writeln!(
        md,
        "![simulation](convergence_simulation.svg)\n\n*Figure 3. Self-convergence of fig2: error \
         against the Celik extrapolation, max over the {} events (onsets, f_peak) or the \
         stick-phase norm (F), top row refining N at Δt = {:e} s, bottom row refining Δt at \
         N = {}; grey dotted = slope guides. What to see: {} Self-convergence says each scheme \
         converges to *something*; which something is Figure 4's question.*\n",
        event_count(r),
        r.settings.sim_nodes_dt_s,
        r.settings.sim_dts_nodes,
        self_convergence_caption(r, paper)
    );
    let _ = writeln!(
        md,
        "![against the reference](convergence_vs_reference.svg)\n\n*Figure 4. The same runs \
         measured against the reference of §4 (accurate scheme, N = {}, extrapolated in Δt{}). \
         What to see: {}*\n",
        r.work_precision.reference.nodes,
        if r.work_precision.reference.n_extrapolation.is_some() {
            " and, by the N study, in N; F(t) in Δt only"
        } else {
            ""
        },
        reference_caption(r, paper)
    );
}

/// The F(t) stick-phase studies, one row per scheme and refinement.
fn force_table(md: &mut String, r: &Results) {
    let _ = writeln!(md, "### F(t) over the stick phases\n");
    header(
        md,
        &[
            "scheme",
            "refined",
            "levels",
            "error per level (relative RMS)",
            "p (triples)",
            "Celik p",
            "GCI (relative)",
            "note",
        ],
    );
    for (scheme, refined) in SEQUENCES {
        for s in sims(r, scheme, refined, "force_stick_rms") {
            let levels = s
                .levels
                .iter()
                .map(|&l| sig(l, 3))
                .collect::<Vec<_>>()
                .join(", ");
            let errs = s
                .errors
                .iter()
                .map(|e| opt(*e, 2))
                .collect::<Vec<_>>()
                .join(", ");
            let (p, gci) = s.gci.map_or(("–".into(), "–".into()), |g| {
                (format!("{:.2}", g.p), sig(g.gci_fine, 2))
            });
            row(
                md,
                &[
                    scheme,
                    refined.as_str(),
                    &levels,
                    &errs,
                    &orders(s),
                    &p,
                    &gci,
                    &s.note,
                ],
            );
        }
    }
    let _ = writeln!(md);
}

/// The per-event onset and f_peak tables of one scheme and refinement.
fn event_tables(md: &mut String, r: &Results, scheme: &str, refined: Refined) {
    for (obs, scale, unit) in [("onset", 1e6, "µs"), ("f_peak", 1e3, "mN")] {
        let st = sims(r, scheme, refined, obs);
        let Some(first) = st.first() else { continue };
        let _ = writeln!(
            md,
            "**{obs}, {scheme}, refining {} ({})** — error per level in {unit} ({}):\n",
            refined.as_str(),
            first.fixed,
            match first.error_kind {
                ErrorKind::VsExtrapolated => "against the extrapolated value",
                ErrorKind::VsFinest => "against the finest level",
                ErrorKind::Exact => "exact",
            }
        );
        let mut columns = vec!["k".to_string()];
        columns.extend(first.levels.iter().map(|&l| level_name(refined, l)));
        columns.extend([
            "p (triples)".to_string(),
            "Celik p".to_string(),
            format!("extrapolated ({unit})"),
            format!("GCI ({unit})"),
            "note".to_string(),
        ]);
        header(md, &columns);
        for s in &st {
            let mut cells = vec![s.event.unwrap_or(0).to_string()];
            cells.extend(s.errors.iter().map(|e| opt(e.map(|e| e * scale), 2)));
            let (p, ext, gci, osc) = match s.gci {
                Some(g) => (
                    format!("{:.2}", g.p),
                    sig(g.phi_ext * scale, 7),
                    sig(g.gci_fine_abs * scale, 2),
                    if g.oscillatory { "oscillatory" } else { "" },
                ),
                None => (
                    s.gci_failure.map_or("–".into(), |f| f.to_string()),
                    "–".into(),
                    "–".into(),
                    "",
                ),
            };
            let note = [osc, s.note.as_str()]
                .iter()
                .filter(|x| !x.is_empty())
                .copied()
                .collect::<Vec<_>>()
                .join("; ");
            cells.extend([orders(s), p, ext, gci, note]);
            row(md, &cells);
        }
        let _ = writeln!(md);
    }
}

/// The observed orders of event `k`'s study, per triple.
fn event_orders(r: &Results, scheme: &str, refined: Refined, obs: &str, k: usize) -> String {
    sims(r, scheme, refined, obs)
        .iter()
        .find(|s| s.event == Some(k))
        .map_or("–".into(), |s| orders(s))
}

/// Spread of observed orders beyond which they are called erratic.
const ERRATIC_SPREAD: f64 = 0.3;

/// The event whose per-triple orders spread most (the clearest step-grid effect): (event,
/// spread, its orders).
fn most_erratic(
    r: &Results,
    scheme: &str,
    refined: Refined,
    obs: &str,
) -> Option<(usize, f64, String)> {
    sims(r, scheme, refined, obs)
        .iter()
        .filter_map(|s| {
            let (lo, hi) = range(s.defined_orders())?;
            Some((hi - lo, s))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .and_then(|(spread, s)| Some((s.event?, spread, orders(s))))
}

/// The per-triple orders of the F(t) study of (scheme, refined).
fn force_orders(r: &Results, scheme: &str, refined: Refined) -> String {
    sims(r, scheme, refined, "force_stick_rms")
        .first()
        .map_or("–".into(), |s| orders(s))
}

/// The largest |difference| between the two finest valid levels over the events from
/// `from_event` on, in the observable's unit.
fn finest_change(studies: &[&Study], from_event: usize) -> f64 {
    studies
        .iter()
        .filter(|s| s.event.is_some_and(|k| k >= from_event))
        .filter_map(|s| {
            let v: Vec<f64> = s.values.iter().flatten().filter_map(|v| *v).collect();
            (v.len() >= 2).then(|| (v[v.len() - 1] - v[v.len() - 2]).abs())
        })
        .fold(0.0_f64, f64::max)
}

/// "Where p is far from theory, and why", one bullet per scheme and refinement.
fn why(md: &mut String, r: &Results, paper: &Paper) {
    let p = |scheme, refined, obs| p2(median_p(r, scheme, refined, obs));
    let th = |scheme, refined, obs| theory_words(r, scheme, refined, obs);
    let loc = &r.localisation;
    let [o_coarse, o_fine, o_coarse_fine, o_fine_coarse] = loc.onsets_s;
    let localised = (o_coarse_fine - o_fine).abs() < (o_coarse_fine - o_coarse).abs()
        && (o_fine_coarse - o_coarse).abs() < (o_fine_coarse - o_fine).abs();
    let lead_us = (o_fine - loc.t_switch_s) * 1e6;
    let acc_dt_fp = sims(r, "accurate", Refined::Dt, "f_peak");
    let fp_orders = range(acc_dt_fp.iter().filter_map(|s| s.gci.map(|g| g.p)));
    let fp_finest = acc_dt_fp
        .iter()
        .filter_map(|s| s.finest_error())
        .fold(0.0_f64, f64::max);
    let early = sims(r, "accurate", Refined::Dt, "force_stick_rms")
        .first()
        .and_then(|s| s.early_stick_rel_diff);
    let _ = writeln!(
        md,
        "- **Accurate, Δt — onsets p ≈ {on} (theory {on_th}), f_peak p ≈ {fp}, F(t) p ≈ {fo}.** \
         The pieces are each second order or exact (Verlet, the exact Landau step under the \
         θ-weighted strain with the substrate predicted by extrapolation, melting and \
         re-solidification located inside the step). Where the error is made: half-way to the \
         first onset F(t) of all Δt levels ({c0:e} … {f0:e} s) agrees to {early} relative; \
         Δt = {c:e} s throughout gives the first onset at {o0} µs, {f:e} s throughout {o1} µs, \
         {c:e} s switched to {f:e} s at t = {ts} µs ({lead} µs before the onset) gives {o2} µs, \
         and the reverse switch {o3} µs: {verdict}. f_peak: F(t) peaks when the strain passes \
         εmax, before the edge reaches εc, in the accurately integrated part of the stick \
         phase, and shifting the previous event in time does not change a maximum; Celik's p \
         ranges {fp_range} over the events, whose finest-level errors are ≤ {fp_fin} mN{fp_erratic}.",
        on = p("accurate", Refined::Dt, "onset"),
        on_th = th("accurate", Refined::Dt, "onset"),
        fp = p("accurate", Refined::Dt, "f_peak"),
        fo = p("accurate", Refined::Dt, "force_stick_rms"),
        c0 = r.settings.sim_dts_s.first().copied().unwrap_or(f64::NAN),
        f0 = r.settings.sim_dts_s.last().copied().unwrap_or(f64::NAN),
        early = opt(early, 2),
        c = loc.dts_s.0,
        f = loc.dts_s.1,
        o0 = sig(o_coarse * 1e6, 7),
        o1 = sig(o_fine * 1e6, 7),
        ts = sig(loc.t_switch_s * 1e6, 6),
        lead = sig(lead_us, 2),
        o2 = sig(o_coarse_fine * 1e6, 7),
        o3 = sig(o_fine_coarse * 1e6, 7),
        verdict = if localised {
            "the step taken in the approach to the melting decides the onset (near the \
             bifurcation ε → εc the φ–u3D feedback is strong), not the stick phase before it"
        } else {
            "the switch does not localise the error to the approach to the melting"
        },
        fp_range = fp_orders.map_or("–".into(), |(lo, hi)| format!("{lo:.2} … {hi:.2}")),
        fp_fin = sig(fp_finest * 1e3, 2),
        fp_erratic = match fp_orders {
            Some((lo, hi)) if hi - lo > ERRATIC_SPREAD =>
                ": at that size discrete step-grid effects (which step a node melts or \
                 re-solidifies in) make p erratic",
            _ => "",
        },
    );
    let e_n = max_error_per_level(&sims(r, "accurate", Refined::Nodes, "onset"), 1e-6);
    let n_part = e_n.iter().map(|&(_, e)| e).fold(0.0_f64, f64::max);
    let force_floor = sims(r, "accurate", Refined::Nodes, "force_stick_rms")
        .first()
        .and_then(|s| s.finest_error());
    let erratic = most_erratic(r, "accurate", Refined::Nodes, "onset");
    let _ = writeln!(
        md,
        "- **Accurate, N — onsets p ≈ {an} (theory {an_th}).** The first node to melt is the \
         outermost one, r = a0 − h, which moves with N; near the edge u3D varies like \
         (a0 − r)·ln(a0 − r), so order ≈ 1, slightly less through the logarithm: event 1 shows \
         p = {e1} per triple. The N-part of the onset error is at most {n_part} µs for N ≥ \
         {n0} (answer 2). At fixed Δt = {dt:e} s the onsets also carry discrete effects of the \
         step grid (in which step a node melts or re-solidifies){erratic}. The stick-phase \
         force's N-differences fall at p per triple {fno} (finest error {ff} of max F). f_peak: p ≈ {afp} (theory {afp_th}).",
        an = p("accurate", Refined::Nodes, "onset"),
        an_th = th("accurate", Refined::Nodes, "onset"),
        e1 = event_orders(r, "accurate", Refined::Nodes, "onset", 1),
        n_part = sig(n_part, 2),
        n0 = r.settings.sim_nodes.first().copied().unwrap_or(0),
        dt = r.settings.sim_nodes_dt_s,
        erratic = match erratic {
            Some((k, spread, o)) if spread > ERRATIC_SPREAD => format!(
                ", which make some events' differences jump between levels (most: event {k}, \
                 p = {o})"
            ),
            Some((_, spread, _)) => format!(
                "; here they stay below what the onset differences resolve (every event's \
                 per-triple orders agree to {spread:.2})"
            ),
            None => String::new(),
        },
        ff = opt(force_floor, 2),
        fno = force_orders(r, "accurate", Refined::Nodes),
        afp = p("accurate", Refined::Nodes, "f_peak"),
        afp_th = th("accurate", Refined::Nodes, "f_peak"),
    );
    let lit_on = sims(r, "literal", Refined::Nodes, "onset");
    let (lo_osc, lo_n) = oscillatory(r, "literal", Refined::Nodes, "onset");
    let lit_fp_p = median_p(r, "literal", Refined::Nodes, "f_peak");
    let lit_fp_theory = sims(r, "literal", Refined::Nodes, "f_peak")
        .first()
        .and_then(|s| s.theory_order);
    let on_range = range(lit_on.iter().filter_map(|s| s.gci.map(|g| g.p)));
    let _ = writeln!(
        md,
        "- **Literal, N — onsets p ≈ {ln} ({lo_osc} of {lo_n} oscillatory), f_peak p ≈ {lfp}, \
         F(t) p ≈ {lfo}.** The plain sums are order {sums} (F(t) shows it), but the onsets are \
         decided at the axis node, whose u3D = 0 is exact for every N: they move by at most {lc} \
         ns over the last refinement, with orders from {on_lo} to {on_hi}, and converge to a \
         different limit (answer 4). f_peak converges at order {lfp}, {cmp} the {sums} \
         expected from the sums (and seen in F(t)); we have not derived why — a peak is a \
         stationary point of F(t), so an error that mostly shifts F(t) in time changes its \
         height only at higher order, which is plausible but unproven here.",
        ln = p("literal", Refined::Nodes, "onset"),
        lfp = p2(lit_fp_p),
        lfo = p("literal", Refined::Nodes, "force_stick_rms"),
        sums = th("literal", Refined::Nodes, "force_stick_rms"),
        lc = sig(finest_change(&lit_on, 1) * 1e9, 2),
        on_lo = on_range.map_or("–".into(), |(lo, _)| format!("{lo:.2}")),
        on_hi = on_range.map_or("–".into(), |(_, hi)| format!("{hi:.2}")),
        cmp = match (lit_fp_p, lit_fp_theory) {
            (Some(p), Some(t)) if p > t + 0.2 => "faster than",
            (Some(p), Some(t)) if p < t - 0.2 => "slower than",
            _ => "close to",
        },
    );
    let lit_dt_on = sims(r, "literal", Refined::Dt, "onset");
    let (lt_osc, lt_n) = oscillatory(r, "literal", Refined::Dt, "onset");
    let limit = paper.euler_limit_s();
    let triple_stable = lit_dt_on.iter().all(|s| {
        let valid: Vec<f64> = s
            .levels
            .iter()
            .zip(s.values.iter().flatten())
            .filter(|(_, v)| v.is_some())
            .map(|(&l, _)| l)
            .collect();
        valid.iter().rev().take(3).all(|&l| l <= limit)
    });
    let _ = writeln!(
        md,
        "- **Literal, Δt — onsets p ≈ {lt} ({lt_osc} of {lt_n} oscillatory), event 1 p = \
         {le1}.** Theory: order {lt_th} (explicit Euler, lagged sweep, once-per-step reset), \
         seen where the differences are resolved (event 1; F(t): p per triple {lfd}); from \
         event 2 on the Δt differences between the two finest levels are at most {later} ns \
         and the same step-grid effects make p erratic. {triple}\n",
        lt = p("literal", Refined::Dt, "onset"),
        le1 = event_orders(r, "literal", Refined::Dt, "onset", 1),
        lt_th = th("literal", Refined::Dt, "onset"),
        lfd = force_orders(r, "literal", Refined::Dt),
        later = sig(finest_change(&lit_dt_on, 2) * 1e9, 2),
        triple = if triple_stable {
            format!(
                "Celik's three finest levels all lie below the stability limit Δt ≈ {} s.",
                sig(limit, 2)
            )
        } else {
            format!(
                "Some of Celik's three finest levels lie beyond the stability limit Δt ≈ {} s.",
                sig(limit, 2)
            )
        },
    );
}

/// The literal Δt runs beyond explicit Euler's stability limit: (those that finished, those
/// that failed).
fn literal_beyond_limit<'a>(
    r: &'a Results,
    paper: &Paper,
) -> (Vec<&'a RunSummary>, Vec<&'a RunSummary>) {
    let limit = paper.euler_limit_s();
    runs(r, "dt", "literal")
        .into_iter()
        .filter(|x| x.dt_s > limit)
        .partition(|x| x.failure.is_none())
}

/// Words about the literal runs beyond explicit Euler's limit.
fn beyond_words(r: &Results, paper: &Paper) -> String {
    let (ran, failed) = literal_beyond_limit(r, paper);
    let mut parts = Vec::new();
    if !failed.is_empty() {
        parts.push(format!(
            "{} level(s) beyond its stability limit fail and are not drawn ({})",
            failed.len(),
            failed
                .iter()
                .map(|x| format!("{:e} s", x.dt_s))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let beyond = if failed.is_empty() {
        "beyond its stability limit"
    } else {
        "beyond the limit too"
    };
    parts.extend(ran.iter().map(|x| {
        format!(
            "Δt = {:e} s, {beyond}, runs with f_peak {} % off",
            x.dt_s,
            sig(100.0 * x.f_peak_error_rel.unwrap_or(f64::NAN), 2)
        )
    }));
    if parts.is_empty() {
        "no level lies beyond its stability limit".into()
    } else {
        parts.join("; ")
    }
}

fn self_convergence_caption(r: &Results, paper: &Paper) -> String {
    let p = |scheme, refined, obs| p2(median_p(r, scheme, refined, obs));
    let n0 = r.settings.sim_nodes.first().copied().unwrap_or(0);
    let at_first = |obs: &str, scale: f64| {
        max_error_per_level(&sims(r, "accurate", Refined::Nodes, obs), scale)
            .first()
            .map(|&(_, e)| e)
    };
    format!(
        "along Δt (bottom) the accurate scheme's errors fall at p ≈ {} (onsets), {} (f_peak) and \
         {} (F) (medians of Celik's p, §3), the literal scheme's at {}, {} and {}, while {}. \
         Along N (top) the literal f_peak and F(t) fall at p ≈ {} and {}, while the accurate \
         errors are small from N = {n0} on ({} ns onsets, {} relative f_peak, {} of max F).",
        p("accurate", Refined::Dt, "onset"),
        p("accurate", Refined::Dt, "f_peak"),
        p("accurate", Refined::Dt, "force_stick_rms"),
        p("literal", Refined::Dt, "onset"),
        p("literal", Refined::Dt, "f_peak"),
        p("literal", Refined::Dt, "force_stick_rms"),
        beyond_words(r, paper),
        p("literal", Refined::Nodes, "f_peak"),
        p("literal", Refined::Nodes, "force_stick_rms"),
        opt(at_first("onset", 1e-9), 2),
        opt(at_first("f_peak", 0.0), 2),
        opt(at_first("force_stick_rms", 1.0), 2),
    )
}

fn reference_caption(r: &Results, paper: &Paper) -> String {
    let onset_range = |role: &str, scheme: &str| {
        range(
            runs(r, role, scheme)
                .iter()
                .filter(|x| x.failure.is_none() && x.dt_s <= paper.euler_limit_s())
                .filter_map(|x| x.onset_error_s.map(|e| e * 1e6)),
        )
        .map_or("–".into(), |(lo, hi)| span(lo, hi, 2))
    };
    let ends = |role: &str, scheme: &str, get: fn(&RunSummary) -> Option<f64>| {
        let v: Vec<f64> = runs(r, role, scheme)
            .iter()
            .filter(|x| x.failure.is_none())
            .filter_map(|x| get(x))
            .collect();
        match (v.first(), v.last()) {
            (Some(a), Some(b)) => format!("{} to {}", sig(*a, 2), sig(*b, 2)),
            _ => "–".into(),
        }
    };
    let stable_range = |get: fn(&RunSummary) -> Option<f64>| {
        range(
            runs(r, "dt", "literal")
                .iter()
                .filter(|x| x.failure.is_none() && x.dt_s <= paper.euler_limit_s())
                .filter_map(|x| get(x)),
        )
        .map_or("–".into(), |(lo, hi)| span(lo, hi, 2))
    };
    let onset_us = |x: &RunSummary| x.onset_error_s.map(|e| e * 1e6);
    format!(
        "refining N alone (top) leaves the accurate onset error at {} µs: {}, and refining Δt \
         (bottom) takes it from {} µs against the {} line (dashed). The literal \
         onset error sits at {} (stable levels) — a different limit (the axis melts first) — \
         while its f_peak error falls from {} and its F(t) error \
         from {} with N; along Δt (stable levels) they stay at {} and {} (N = {} dominates), \
         and {}.",
        onset_range("N", "accurate"),
        floor_words(r),
        ends("dt", "accurate", onset_us),
        tol_text(),
        {
            let (n, dt) = (onset_range("N", "literal"), onset_range("dt", "literal"));
            if n == dt {
                format!("{n} µs along N and Δt")
            } else {
                format!("{n} µs along N and {dt} µs along Δt")
            }
        },
        ends("N", "literal", |x| x.f_peak_error_rel),
        ends("N", "literal", |x| x.force_error_rel),
        stable_range(|x| x.f_peak_error_rel),
        stable_range(|x| x.force_error_rel),
        r.settings.sim_dts_nodes,
        beyond_words(r, paper),
    )
}

/// What sets the floor of the accurate onset error along N, from the data: the runs' own Δt
/// error at the N study's step (measured by the Δt study), or the reference's uncertainty.
fn floor_words(r: &Results) -> String {
    let floor = runs(r, "N", "accurate")
        .iter()
        .filter_map(|x| x.onset_error_s)
        .fold(f64::INFINITY, f64::min);
    let dt_part = max_error_per_level(&sims(r, "accurate", Refined::Dt, "onset"), 1e-6)
        .iter()
        .find(|(l, _)| super::same(*l, r.settings.sim_nodes_dt_s))
        .map(|&(_, e)| e * 1e-6);
    let ref_unc = super::reference_onset_uncertainty_s(r);
    let judged = if r.work_precision.reference.n_extrapolation.is_some() {
        "the reference extrapolated in N and Δt"
    } else {
        "the reference at its own N"
    };
    match dt_part {
        Some(d) if d >= ref_unc => format!(
            "against {judged} (± {} µs, its horizontal line), that floor is the runs' own Δt error \
             at Δt = {:e} s ({} µs by the Δt study at N = {}), not the reference's",
            sig(ref_unc * 1e6, 2),
            r.settings.sim_nodes_dt_s,
            sig(d * 1e6, 2),
            r.settings.sim_dts_nodes
        ),
        Some(d) => format!(
            "against {judged}, that floor is within the reference's own uncertainty (± {} µs, \
             its horizontal line; the runs' Δt error at Δt = {:e} s is {} µs): bounded, not measured",
            sig(ref_unc * 1e6, 2),
            r.settings.sim_nodes_dt_s,
            sig(d * 1e6, 2)
        ),
        None => format!(
            "(floor {} µs; the Δt study has no level at the N study's step)",
            sig(floor * 1e6, 2)
        ),
    }
}

/// Literal dashed with squares, accurate solid with circles.
fn scheme_series(scheme: &str, ci: usize, pts: Vec<(f64, f64)>) -> Series {
    let s = Series::new(scheme, pts, PALETTE[ci]);
    if scheme == "literal" {
        s.dashed().marker(Marker::Square)
    } else {
        s.marker(Marker::Circle)
    }
}

fn x_label(r: &Results, refined: Refined) -> String {
    match refined {
        Refined::Nodes => format!("nodes N (Δt = {:e} s)", r.settings.sim_nodes_dt_s),
        Refined::Dt => format!("time step Δt (s) (N = {})", r.settings.sim_dts_nodes),
    }
}

/// Figure 3: self-convergence, errors against the Celik extrapolation.
pub(super) fn self_convergence_figure(r: &Results) -> Result<String, String> {
    let mut panels = Vec::new();
    for refined in [Refined::Nodes, Refined::Dt] {
        for (obs, title, ylabel, scale) in [
            (
                "onset",
                "event onsets, max over events",
                "|onset − extrapolated| (µs)",
                1e-6,
            ),
            (
                "f_peak",
                "peak force per event, max over events",
                "|f_peak − extrapolated| / f_peak",
                0.0,
            ),
            (
                "force_stick_rms",
                "F(t) over the stick phases",
                "RMS |F − F_ext| / max F",
                1.0,
            ),
        ] {
            let mut p = Panel::new(
                &format!("{title}, refining {}", refined.as_str()),
                &x_label(r, refined),
                ylabel,
            )
            .log_log()
            .x_ticks(level_ticks(r, refined));
            for (ci, scheme) in ["literal", "accurate"].iter().enumerate() {
                let pts = max_error_per_level(&sims(r, scheme, refined, obs), scale);
                p.series.push(scheme_series(scheme, ci, pts));
            }
            if refined == Refined::Nodes {
                p.auto_guides(&[0.5, 1.0, 2.0], true);
            } else {
                p = p.legend(LegendAt::UpperLeft);
                p.auto_guides(&[1.0, 2.0], false);
            }
            panels.push(p);
        }
    }
    render_svg(&panels, 3, 560, 430)
}

/// Figure 4: the runs of Figure 3 against the reference.
pub(super) fn reference_figure(r: &Results) -> Result<String, String> {
    let mut panels = Vec::new();
    for refined in [Refined::Nodes, Refined::Dt] {
        let role = refined.as_str();
        for (obs, ylabel) in [
            ("onset", "max |onset − reference| (µs)"),
            ("f_peak", "max |f_peak − reference| / reference"),
            ("force", "stick-phase RMS |F − F_ref| / max F"),
        ] {
            let mut p = Panel::new(
                &format!("{obs} error against the reference, refining {role}"),
                &x_label(r, refined),
                ylabel,
            )
            .log_log()
            .x_ticks(level_ticks(r, refined))
            .legend(if refined == Refined::Dt {
                LegendAt::LowerRight
            } else {
                LegendAt::MiddleLeft
            });
            for (ci, scheme) in ["literal", "accurate"].iter().enumerate() {
                let pts = runs(r, role, scheme)
                    .iter()
                    .filter_map(|run| {
                        let x = match refined {
                            Refined::Nodes => run.nodes as f64,
                            Refined::Dt => run.dt_s,
                        };
                        let e = match obs {
                            "onset" => run.onset_error_s.map(|e| e * 1e6),
                            "f_peak" => run.f_peak_error_rel,
                            _ => run.force_error_rel,
                        }?;
                        Some((x, e))
                    })
                    .collect();
                p.series.push(scheme_series(scheme, ci, pts));
            }
            if obs == "onset" {
                p = p.hline(ONSET_TOL_S * 1e6, tol_text());
            }
            if let Some((v, label)) = super::reference_band(r, obs) {
                p = p.hline(v, label);
            }
            panels.push(p);
        }
    }
    render_svg(&panels, 3, 560, 430)
}
