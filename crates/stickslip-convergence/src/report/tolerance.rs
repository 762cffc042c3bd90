//! Section 5 of the report, the tolerance of the default adaptive stepping: same-N references
//! and their spatial error, errors, step counts and wall time per tolerance, log–log slopes,
//! the controller before the redesign, Figure 6 (`convergence_tolerance.svg`) and the
//! adaptive panels of Figure 5.

use super::{header, row, same};
use crate::Results;
use crate::same_n::SameNReference;
use crate::tolerance::{
    DEFAULT_TOLERANCE, FLOOR_FACTOR, KEYS, OldComparison, QUANTITIES, Slope, TolPoint,
    ToleranceStudy,
};
use std::fmt::Write as _;
use stickslip_report::fmt::{opt, sig};
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{LegendAt, Marker, Panel, Series};

/// ns with 3 significant digits (`–` for none).
fn ns(v: Option<f64>) -> String {
    opt(v.map(|s| s * 1e9), 3)
}

/// The study's points at `nodes`, loose to tight.
fn at(t: &ToleranceStudy, nodes: usize) -> Vec<&TolPoint> {
    t.points.iter().filter(|p| p.nodes == nodes).collect()
}

/// The slope of quantity `key` at `nodes` against `against`.
fn slope<'a>(t: &'a ToleranceStudy, nodes: usize, key: &str, against: &str) -> Option<&'a Slope> {
    t.slopes
        .iter()
        .find(|s| s.nodes == nodes && s.quantity == key && s.against == against)
}

/// Writes "## 5. Tolerance of the default adaptive stepping" (nothing for studies without it).
pub(super) fn section(md: &mut String, r: &Results) {
    let Some(t) = &r.tolerance else {
        return;
    };
    let s = &t.settings;
    let _ = writeln!(md, "## 5. Tolerance of the default adaptive stepping\n");
    let _ = writeln!(
        md,
        "The default path (`time.stepping = \"adaptive\"`: one accurate step per attempt, its \
         local error estimated from the step itself, a PI controller of order 3, no cap on the \
         step, the coupling solved to tolerance/100) at `time.tolerance` = {} (default {}) on \
         the whole fig2 run at N = {:?}, each against a **same-N reference**: fixed steps \
         Δt = {:?} s at that N, Richardson (4·f(h/4) − f(h/2))/3 on the two finest (fixed steps \
         are second order), the coarsest giving a second extrapolation whose distance is the \
         reference's stated uncertainty. So these errors are time-stepping errors only; the \
         spatial error of the reference itself is stated separately. Quantities: the first \
         onset, the largest error over all onsets, t_end (located recovery) and f_peak over \
         all events, and F(t) on the {} µs grid (linear between step ends) as the stick-phase \
         RMS (as in §3) and as the largest error over the whole run, both over max F. Wall \
         time: building the simulation and stepping it, in this process{}.\n",
        s.tolerances
            .iter()
            .map(|x| format!("{x:e}"))
            .collect::<Vec<_>>()
            .join(", "),
        sig(DEFAULT_TOLERANCE, 1),
        s.nodes,
        s.ref_dts_s,
        stickslip_report::fmt::tick(crate::fig2::SAMPLE_DT_S * 1e6),
        if s.repeats > 1 {
            format!(
                " (median of {} at N = {}, one run at larger N)",
                s.repeats,
                s.nodes.first().copied().unwrap_or(0)
            )
        } else {
            String::new()
        }
    );
    references(md, t);
    for &n in &s.nodes {
        points_table(md, t, n);
    }
    slopes_table(md, t);
    if let Some(old) = &t.old {
        old_section(md, t, old);
    } else {
        let _ = writeln!(
            md,
            "The controller before the redesign was measured at N = {} only \
             (`data/old_controller.json`), which this study did not run.\n",
            crate::tolerance::old_controller().nodes
        );
    }
    let _ = writeln!(
        md,
        "![tolerance](convergence_tolerance.svg)\n\n*Figure 6. Error against `time.tolerance`, \
         log–log, per N (solid: N = {}, dashed: the others): left, onsets and t_end in ns; \
         right, f_peak and F(t) relative. Horizontal lines: the N = {} reference's uncertainty \
         in onsets and F(t). What to see: {}*\n",
        s.nodes.first().copied().unwrap_or(0),
        s.nodes.first().copied().unwrap_or(0),
        caption(t)
    );
}

fn references(md: &mut String, t: &ToleranceStudy) {
    let _ = writeln!(md, "**References** (per N):\n");
    header(
        md,
        &[
            "N",
            "events",
            "onset ± (ns)",
            "t_end ± (ns)",
            "f_peak ± (rel.)",
            "F(t) ± (rel. RMS)",
            "observed order onset / t_end / f_peak",
            "wall (s)",
        ],
    );
    for rf in &t.references {
        row(
            md,
            &[
                rf.nodes.to_string(),
                rf.onsets_s.len().to_string(),
                sig(rf.onset_uncertainty_s * 1e9, 2),
                sig(rf.t_end_uncertainty_s * 1e9, 2),
                sig(rf.f_peak_uncertainty_rel, 2),
                opt(rf.force_uncertainty_rel, 2),
                rf.orders
                    .iter()
                    .map(|p| super::p2(*p))
                    .collect::<Vec<_>>()
                    .join(" / "),
                rf.wall_s
                    .iter()
                    .map(|w| sig(*w, 2))
                    .collect::<Vec<_>>()
                    .join(" + "),
            ],
        );
    }
    let _ = writeln!(md);
    for sp in &t.spatial {
        let e = &sp.errors;
        let default = t
            .points
            .iter()
            .find(|p| p.nodes == sp.nodes && same(p.tolerance, DEFAULT_TOLERANCE));
        let ratio = match (e.max_onset_s, default.and_then(|p| p.errors.max_onset_s)) {
            (Some(a), Some(b)) if b > 0.0 => format!(
                " — {}× the default tolerance's time-stepping error in onsets at that N",
                sig(a / b, 2)
            ),
            _ => String::new(),
        };
        let _ = writeln!(
            md,
            "**Spatial error of the reference.** The N = {} reference against the N = {} one: \
             first onset {} ns, all onsets up to {} ns, t_end up to {} ns, f_peak up to {} \
             relative, F(t) stick-phase RMS {}{ratio}. This is the N-error a user at N = {} \
             carries whatever the tolerance (§3 has its order in N).\n",
            sp.nodes,
            sp.finer_nodes,
            ns(e.first_onset_s),
            ns(e.max_onset_s),
            ns(e.max_t_end_s),
            opt(e.max_f_peak_rel, 2),
            opt(sp.force_stick_rel, 2),
            sp.nodes
        );
    }
    if t.spatial.is_empty() {
        let _ = writeln!(
            md,
            "**Spatial error of the reference**: not measured (one N only).\n"
        );
    }
}

fn points_table(md: &mut String, t: &ToleranceStudy, nodes: usize) {
    let _ = writeln!(md, "**N = {nodes}**, per tolerance:\n");
    header(
        md,
        &[
            "tolerance",
            "accepted",
            "rejected",
            "onset retakes",
            "evaluations",
            "wall (s)",
            "first onset (ns)",
            "max onset (ns)",
            "max t_end (ns)",
            "max f_peak (rel.)",
            "F stick RMS (rel.)",
            "F max (rel.)",
        ],
    );
    for p in at(t, nodes) {
        row(
            md,
            &[
                format!("{:e}", p.tolerance),
                p.steps.to_string(),
                p.rejected_steps.to_string(),
                p.onset_retakes.to_string(),
                p.evaluations.to_string(),
                sig(p.wall_s, 2),
                ns(p.errors.first_onset_s),
                ns(p.errors.max_onset_s),
                ns(p.errors.max_t_end_s),
                opt(p.errors.max_f_peak_rel, 2),
                opt(p.force_stick_rel, 2),
                format!(
                    "{}{}",
                    opt(p.force_max_rel, 2),
                    p.failure
                        .as_ref()
                        .map_or(String::new(), |f| format!(" (failed: {f})"))
                ),
            ],
        );
    }
    let _ = writeln!(md);
}

fn slopes_table(md: &mut String, t: &ToleranceStudy) {
    let _ = writeln!(
        md,
        "**Observed slopes** (least squares of log error against log tolerance, and against \
         log evaluations; errors within {}× the reference's uncertainty are left out, their \
         count after the slash):\n",
        sig(FLOOR_FACTOR, 1)
    );
    let mut cols = vec!["quantity".to_string()];
    for &n in &t.settings.nodes {
        cols.push(format!("N = {n}: vs tolerance"));
        cols.push(format!("N = {n}: vs evaluations"));
    }
    header(md, &cols);
    for (q, key) in KEYS.iter().enumerate() {
        let mut cells = vec![QUANTITIES[q].to_string()];
        for &n in &t.settings.nodes {
            for against in ["tolerance", "evaluations"] {
                cells.push(slope(t, n, key, against).map_or("–".into(), |s| {
                    format!("{} ({} pts / {})", super::p2(s.slope), s.points, s.left_out)
                }));
            }
        }
        row(md, &cells);
    }
    let _ = writeln!(
        md,
        "\nWhat a slope means: a controller that keeps the local error of a second-order step \
         (∝ h³) at the tolerance takes h ∝ tol^(1/3), so a global error ∝ h² falls like \
         tol^(2/3) ≈ tol^0.67 and like evaluations^(−2); a slope nearer 1 in tolerance says \
         the error is made where the step is short anyway (at the onsets and during slip) and \
         follows the per-step tolerance directly.\n"
    );
}

fn old_section(md: &mut String, t: &ToleranceStudy, old: &OldComparison) {
    let src = &old.source;
    let _ = writeln!(
        md,
        "**Against the controller before the redesign** (commit `{}`: step doubling, {} \
         evaluations per attempt; its outputs were measured with its own binary and are kept \
         in `crates/stickslip-convergence/data/old_controller.json`, {}; how: {}). Errors \
         against this study's N = {} reference; loop wall times (run.json) of both binaries \
         measured interleaved in that session:\n",
        src.commit,
        src.evaluations_per_attempt,
        src.measured,
        src.commands.join("; "),
        src.nodes
    );
    header(
        md,
        &[
            "tolerance",
            "old evaluations",
            "new evaluations",
            "old loop (s)",
            "new loop (s)",
            "old max onset (ns)",
            "new max onset (ns)",
            "old max t_end (ns)",
            "new max t_end (ns)",
            "old f_peak (rel.)",
            "new f_peak (rel.)",
        ],
    );
    let mut counts_agree = true;
    for o in &old.points {
        let new = t
            .points
            .iter()
            .find(|p| p.nodes == src.nodes && same(p.tolerance, o.tolerance));
        if let Some(n) = new {
            counts_agree &= n.steps + n.rejected_steps == o.new_evaluations;
        }
        row(
            md,
            &[
                format!("{:e}", o.tolerance),
                o.evaluations.to_string(),
                new.map_or("–".into(), |n| n.evaluations.to_string()),
                sig(o.loop_s, 2),
                sig(o.new_loop_s, 2),
                ns(o.errors.max_onset_s),
                ns(new.and_then(|n| n.errors.max_onset_s)),
                ns(o.errors.max_t_end_s),
                ns(new.and_then(|n| n.errors.max_t_end_s)),
                opt(o.errors.max_f_peak_rel, 2),
                opt(new.and_then(|n| n.errors.max_f_peak_rel), 2),
            ],
        );
    }
    let old_default = old.points.iter().find(|o| same(o.tolerance, 1e-4));
    let new_default = t
        .points
        .iter()
        .find(|p| p.nodes == src.nodes && same(p.tolerance, DEFAULT_TOLERANCE));
    let compare = match (old_default, new_default) {
        (Some(o), Some(n)) => format!(
            " At each one's default (old 1e-4, new {}): onsets within {} ns against {} ns, \
             t_end within {} ns against {} ns, f_peak {} against {}, with {} evaluations \
             against {} ({}×) and {} s of loop against {} s in that session.",
            sig(DEFAULT_TOLERANCE, 1),
            ns(n.errors.max_onset_s),
            ns(o.errors.max_onset_s),
            ns(n.errors.max_t_end_s),
            ns(o.errors.max_t_end_s),
            opt(n.errors.max_f_peak_rel, 2),
            opt(o.errors.max_f_peak_rel, 2),
            n.evaluations,
            o.evaluations,
            sig(n.evaluations as f64 / o.evaluations as f64, 2),
            sig(
                old.points
                    .iter()
                    .find(|x| same(x.tolerance, DEFAULT_TOLERANCE))
                    .map_or(f64::NAN, |x| x.new_loop_s),
                2
            ),
            sig(o.loop_s, 2)
        ),
        _ => String::new(),
    };
    let old_slope = {
        let pts: Vec<(f64, f64)> = old
            .points
            .iter()
            .filter_map(|o| Some((o.tolerance, o.errors.max_onset_s?)))
            .collect();
        let floor = t
            .references
            .iter()
            .find(|r| r.nodes == src.nodes)
            .map_or(0.0, |r| FLOOR_FACTOR * r.onset_uncertainty_s);
        crate::tolerance::fitted_slope(&pts, floor).0
    };
    let _ = writeln!(
        md,
        "\nThe old controller's onset error falls like tol^{} (max over onsets), the new \
         one's like tol^{}.{compare} {}\n",
        super::p2(old_slope),
        super::p2(slope(t, src.nodes, "onsets", "tolerance").and_then(|s| s.slope)),
        if counts_agree {
            "The current binary's step counts in that session equal this study's at every \
             tolerance (the same runs)."
        } else {
            "The current binary's step counts in that session differ from this study's at \
             some tolerance: the data file predates a change of the stepping."
        }
    );
}

/// What Figure 6 shows.
fn caption(t: &ToleranceStudy) -> String {
    let Some(&n) = t.settings.nodes.first() else {
        return String::new();
    };
    let s = |key: &str| super::p2(slope(t, n, key, "tolerance").and_then(|s| s.slope));
    let pts = at(t, n);
    let tight = pts.last().copied();
    let loose = pts.first().copied();
    format!(
        "at N = {n} the onset errors fall like tol^{} (first) and tol^{} (all), t_end like \
         tol^{}, f_peak like tol^{}, F(t) like tol^{} (stick RMS) and tol^{} (max), from {} ns \
         (all onsets) at {} to {} ns at {}, while evaluations grow from {} to {}.",
        s("onset1"),
        s("onsets"),
        s("t_end"),
        s("f_peak"),
        s("F_stick"),
        s("F_max"),
        ns(loose.and_then(|p| p.errors.max_onset_s)),
        loose.map_or("–".into(), |p| format!("{:e}", p.tolerance)),
        ns(tight.and_then(|p| p.errors.max_onset_s)),
        tight.map_or("–".into(), |p| format!("{:e}", p.tolerance)),
        loose.map_or(0, |p| p.evaluations),
        tight.map_or(0, |p| p.evaluations)
    )
}

fn reference_of(t: &ToleranceStudy, nodes: usize) -> Option<&SameNReference> {
    t.references.iter().find(|r| r.nodes == nodes)
}

/// Figure 6: error against tolerance.
pub(super) fn figure(r: &Results) -> Result<String, String> {
    let Some(t) = &r.tolerance else {
        return stickslip_report::plot::render_svg(&[], 2, 560, 430);
    };
    let mut time_panel = Panel::new(
        "Adaptive default: time errors",
        "time.tolerance",
        "error (ns)",
    )
    .log_log()
    .legend(LegendAt::LowerRight);
    let mut rel_panel = Panel::new(
        "Adaptive default: relative errors",
        "time.tolerance",
        "relative error",
    )
    .log_log()
    .legend(LegendAt::LowerRight);
    let markers = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
    ];
    for (i, &n) in t.settings.nodes.iter().enumerate() {
        let pts = at(t, n);
        for (q, key) in KEYS.iter().enumerate() {
            let scale = if q <= 2 { 1e9 } else { 1.0 };
            let data: Vec<(f64, f64)> = pts
                .iter()
                .filter_map(|p| Some((p.tolerance, p.error(q)? * scale)))
                .filter(|&(_, e)| e > 0.0)
                .collect();
            let label = if i == 0 {
                (*key).to_string()
            } else {
                format!("{key} N={n}")
            };
            let mut series = Series::new(label, data, PALETTE[q % PALETTE.len()])
                .marker(markers[q % markers.len()]);
            if i > 0 {
                series = series.dashed();
            }
            if q <= 2 {
                time_panel.series.push(series);
            } else {
                rel_panel.series.push(series);
            }
        }
    }
    if let Some(rf) = t.settings.nodes.first().and_then(|&n| reference_of(t, n)) {
        if rf.onset_uncertainty_s > 0.0 {
            time_panel = time_panel.hline(rf.onset_uncertainty_s * 1e9, "reference ±");
        }
        if let Some(u) = rf.force_uncertainty_rel.filter(|&u| u > 0.0) {
            rel_panel = rel_panel.hline(u, "reference F ±");
        }
    }
    stickslip_report::plot::render_svg(&[time_panel, rel_panel], 2, 560, 430)
}

/// The adaptive panels of Figure 5: onset and f_peak error against evaluations, onset error
/// against loop wall time, new controller against old (at the old data's N).
pub(super) fn work_precision_panels(r: &Results) -> Vec<Panel> {
    let Some(t) = &r.tolerance else {
        return Vec::new();
    };
    let Some(old) = &t.old else {
        return Vec::new();
    };
    let n = old.source.nodes;
    let new_pts = at(t, n);
    let mut panels = Vec::new();
    for (title, ylabel, q) in [
        ("onsets", "max |onset − same-N ref.| (ns)", 1usize),
        ("f_peak", "max |f_peak − same-N ref.| / ref.", 3),
    ] {
        let scale = if q == 1 { 1e9 } else { 1.0 };
        let mut p = Panel::new(
            &format!("Adaptive, N = {n}: {title} vs evaluations"),
            "step evaluations",
            ylabel,
        )
        .log_log()
        .legend(LegendAt::UpperRight);
        let (new_xy, new_labels): (Vec<(f64, f64)>, Vec<String>) = new_pts
            .iter()
            .filter_map(|x| {
                Some((
                    (x.evaluations as f64, x.error(q)? * scale),
                    format!("{:e}", x.tolerance),
                ))
            })
            .unzip();
        let (old_xy, old_labels): (Vec<(f64, f64)>, Vec<String>) = old
            .points
            .iter()
            .filter_map(|x| {
                let e = if q == 1 {
                    x.errors.max_onset_s
                } else {
                    x.errors.max_f_peak_rel
                }?;
                Some((
                    (x.evaluations as f64, e * scale),
                    format!("{:e}", x.tolerance),
                ))
            })
            .unzip();
        p.series.push(
            Series::new("new (PI, one evaluation)", new_xy, PALETTE[1])
                .marker(Marker::Circle)
                .labels(new_labels),
        );
        p.series.push(
            Series::new(
                format!("old ({}, step doubling)", old.source.commit),
                old_xy,
                PALETTE[3],
            )
            .dashed()
            .marker(Marker::Square)
            .labels(old_labels),
        );
        panels.push(p);
    }
    let mut wall = Panel::new(
        &format!("Adaptive, N = {n}: onsets vs loop wall time"),
        "loop wall time (s), one session, median",
        "max |onset − same-N ref.| (ns)",
    )
    .log_log()
    .legend(LegendAt::UpperRight);
    let new_wall: Vec<(f64, f64)> = old
        .points
        .iter()
        .filter_map(|o| {
            let p = new_pts.iter().find(|p| same(p.tolerance, o.tolerance))?;
            Some((o.new_loop_s, p.errors.max_onset_s? * 1e9))
        })
        .collect();
    let old_wall: Vec<(f64, f64)> = old
        .points
        .iter()
        .filter_map(|o| Some((o.loop_s, o.errors.max_onset_s? * 1e9)))
        .collect();
    wall.series
        .push(Series::new("new", new_wall, PALETTE[1]).marker(Marker::Circle));
    wall.series.push(
        Series::new("old", old_wall, PALETTE[3])
            .dashed()
            .marker(Marker::Square),
    );
    panels.push(wall);
    panels
}
