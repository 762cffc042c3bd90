//! Section 2 of the report, the time steppers against closed forms: the Landau φ-steppers
//! with the strain frozen and the drive integrators on the free spring, their tables and
//! Figure 2 (`convergence_steppers.svg`).

use super::{Paper, header, orders, range, row, same};
use crate::Results;
use crate::steppers::{DRIVE_T_END_S, LANDAU_CASES, omega_t, relaxation_time_s};
use crate::study::Study;
use std::fmt::Write as _;
use stickslip_report::fmt::{sig, tick};
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{LegendAt, Marker, Panel, Series, render_svg};

fn stepper_studies<'a>(r: &'a Results, family: &'a str) -> impl Iterator<Item = &'a Study> {
    r.studies
        .iter()
        .filter(move |s| s.study == "stepper" && s.observable == family)
}

/// The case of a Landau study, from its `fixed` field (`melting (phi0 = …, eps = 2)`).
fn case_of(s: &Study) -> &str {
    s.fixed
        .trim_start_matches("case = ")
        .split(", T")
        .next()
        .unwrap_or("")
}

/// The short name of a case (`melting`).
fn short(case: &str) -> &str {
    case.split(" (").next().unwrap_or(case)
}

/// Writes "## 2. Time steppers against closed forms".
pub(super) fn section(md: &mut String, r: &Results, paper: &Paper) {
    let _ = writeln!(md, "## 2. Time steppers against closed forms\n");
    let _ = writeln!(
        md,
        "Landau φ with ε frozen (error: max over steps of |φ − φ_exact| divided by max(φ0, φ(T))) \
         and the friction-free spring (phase-space error after ωT = {:.2}):\n",
        omega_t(DRIVE_T_END_S)
    );
    for family in ["phi", "spring_phase_space"] {
        let st: Vec<&Study> = stepper_studies(r, family).collect();
        let Some(first) = st.first() else { continue };
        let mut columns = vec!["case".to_string(), "stepper".to_string()];
        columns.extend(first.levels.iter().map(|l| format!("Δt={}", sig(*l, 3))));
        columns.extend(["p per halving", "theory", "note"].map(String::from));
        header(md, &columns);
        for s in st {
            let mut cells = vec![case_of(s).to_string(), s.scheme.clone()];
            cells.extend(
                s.errors
                    .iter()
                    .map(|e| e.map_or("blow-up".into(), |e| sig(e, 2))),
            );
            cells.push(if s.theory == "exact" {
                "(rounding)".into()
            } else {
                orders(s)
            });
            cells.push(s.theory.clone());
            cells.push(s.note.clone());
            row(md, &cells);
        }
        let _ = writeln!(md);
    }
    let drive: Vec<String> = r
        .drive_fig2_rel_error
        .iter()
        .map(|(n, e)| format!("{n} {}", sig(*e, 2)))
        .collect();
    let _ = writeln!(
        md,
        "At fig2's own horizon ({} ms, Δt = {:e} s, ωT = {:.2}) the relative error of X of the \
         free spring is {}: the drive integrator is never what limits fig2's accuracy.\n",
        tick(paper.end_s * 1e3),
        paper.dt_s,
        omega_t(paper.end_s),
        drive.join(", ")
    );
    let _ = writeln!(
        md,
        "![steppers](convergence_steppers.svg)\n\n*Figure 2. Stepper errors against Δt. What to \
         see: {}*\n",
        caption(r, paper)
    );
}

/// What Figure 2 shows, from the studies.
fn caption(r: &Results, paper: &Paper) -> String {
    let euler: Vec<&Study> = stepper_studies(r, "phi")
        .filter(|s| s.scheme != "exact")
        .collect();
    let last: Vec<f64> = euler
        .iter()
        .filter_map(|s| s.observed_order.last().copied().flatten())
        .collect();
    let relax = LANDAU_CASES
        .iter()
        .map(|c| format!("{} s {}", sig(relaxation_time_s(c), 2), short(c.name)))
        .collect::<Vec<_>>()
        .join(", ");
    // The largest Euler error at the paper's Δt, and where.
    let at_paper = euler
        .iter()
        .filter_map(|s| {
            let i = s.levels.iter().position(|&l| same(l, paper.dt_s))?;
            Some((s.errors[i].unwrap_or(f64::INFINITY), s))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    let exact_worst = stepper_studies(r, "phi")
        .filter(|s| s.scheme == "exact")
        .flat_map(|s| s.errors.iter().flatten())
        .fold(0.0_f64, |m, &e| m.max(e));
    let spring: Vec<String> = stepper_studies(r, "spring_phase_space")
        .map(|s| {
            let ps = s.defined_orders();
            let p = range(ps.iter().copied())
                .map_or("–".into(), |(lo, hi)| format!("{lo:.2}–{hi:.2}"));
            format!("{} {p} (theory {})", s.scheme, s.theory)
        })
        .collect();
    format!(
        "explicit and implicit Euler reach order {} on the finest halving (theory 1) once Δt is \
         well below the relaxation time 1/(2γ|c|) ({relax}); at the paper's Δt = {:e} s their \
         largest error is {}; the exact step (not drawn) stays at rounding level (≤ {}) for \
         every Δt; observed orders of the drive integrators: {}.",
        range(last.iter().copied()).map_or("–".into(), |(lo, hi)| format!("{lo:.2}–{hi:.2}")),
        paper.dt_s,
        at_paper.map_or("–".into(), |(e, s)| format!(
            "{} ({}, {})",
            sig(e, 2),
            s.scheme.replace('_', " "),
            short(case_of(s))
        )),
        sig(exact_worst, 1),
        spring.join(", ")
    )
}

/// Figure 2: one panel per Landau case (explicit and implicit Euler) and one for the spring.
pub(super) fn figure(r: &Results) -> Result<String, String> {
    let mut panels = Vec::new();
    let mut cases: Vec<&str> = Vec::new();
    for s in stepper_studies(r, "phi") {
        if !cases.contains(&s.fixed.as_str()) {
            cases.push(&s.fixed);
        }
    }
    for case in cases {
        let title = short(case.trim_start_matches("case = "));
        let mut p = Panel::new(
            &format!("Landau φ, {title}"),
            "time step Δt (s)",
            "max |φ − φ_exact| / φ scale",
        )
        .log_log()
        .x_ticks(r.settings.landau_dts_s.clone())
        .legend(LegendAt::MiddleLeft);
        for (ci, name) in ["explicit_euler", "implicit_euler"].iter().enumerate() {
            if let Some(s) =
                stepper_studies(r, "phi").find(|s| s.fixed == case && s.scheme == *name)
            {
                let pts = s
                    .levels
                    .iter()
                    .zip(&s.errors)
                    .filter_map(|(&l, e)| e.filter(|&e| e > 0.0 && e < 10.0).map(|e| (l, e)))
                    .collect();
                p.series
                    .push(Series::new(*name, pts, PALETTE[ci]).marker(Marker::Circle));
            }
        }
        p.auto_guides(&[1.0], false);
        panels.push(p);
    }
    let mut p = Panel::new(
        &format!(
            "Spring drive, free motion over ωT = {:.2}",
            omega_t(DRIVE_T_END_S)
        ),
        "time step Δt (s)",
        "phase-space error",
    )
    .log_log()
    .legend(LegendAt::UpperLeft);
    for (ci, name) in ["verlet", "rk4"].iter().enumerate() {
        if let Some(s) = stepper_studies(r, "spring_phase_space").find(|s| s.scheme == *name) {
            let pts = s
                .levels
                .iter()
                .zip(&s.errors)
                .filter_map(|(&l, e)| e.map(|e| (l, e)))
                .collect();
            p.series
                .push(Series::new(*name, pts, PALETTE[ci]).marker(Marker::Circle));
        }
    }
    p.auto_guides(&[2.0, 4.0], false);
    panels.push(p);
    render_svg(&panels, 2, 640, 460)
}
