//! The comparison's page section and figure: tables of both codes' converged values with
//! their uncertainties, the differences and verdicts, and each code's error against its own
//! resolution.

use super::{
    Comparison, Convergence, MDR3D_MEAN_TOLERANCE, MDR3D_ORDER, MDR3D_SCRIPT, Mdr3d, Quantity,
    SCRIPT, Target,
};
use std::fmt::Write as _;
use stickslip_report::fmt::sig;
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{Marker, Panel, Series, render_svg};

/// The figure's file name in `reports/`.
pub const FIGURE: &str = "independent.svg";

fn target_text(t: Target) -> String {
    match t {
        Target::AbsoluteS(s) => format!("≤ {} ns", sig(s * 1e9, 2)),
        Target::Relative(r) => format!("≤ {r:e} rel."),
    }
}

fn value_text(name: &str, c: &Convergence) -> String {
    let order = c
        .order
        .map_or_else(|| "p –".to_string(), |p| format!("p {}", sig(p, 2)));
    if name == "t_onset" && c.value >= 1e-2 {
        format!(
            "{} s ± {} ns ({order})",
            sig(c.value, 12),
            sig(c.uncertainty() * 1e9, 2)
        )
    } else if name == "t_onset" {
        format!(
            "{} µs ± {} ns ({order})",
            sig(c.value * 1e6, 12),
            sig(c.uncertainty() * 1e9, 2)
        )
    } else {
        format!(
            "{} mN ± {} rel. ({order})",
            sig(c.value * 1e3, 10),
            sig(c.uncertainty() / c.value.abs(), 2)
        )
    }
}

fn difference_text(q: &Quantity) -> String {
    if q.name == "t_onset" {
        format!(
            "{} ns ({} rel.)",
            sig(q.difference * 1e9, 2),
            sig(q.difference / q.independent.value, 2)
        )
    } else {
        format!("{} rel.", sig(q.difference / q.independent.value, 2))
    }
}

/// The section of reports/index.md.
#[must_use]
pub fn markdown(c: &Comparison) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "## Independent implementation\n");
    let _ = writeln!(
        s,
        "`{SCRIPT}` is a second implementation of the model that shares no code with the \
         crates: NumPy and SciPy only ({}). Its fields are even Chebyshev series in r with the \
         contact's edge a node (M + 1 collocation points), its MDR pair is integrated after \
         substitutions that remove the Abel kernels' 1/√ singularity, and its time stepping is \
         SciPy's Radau with each node's melting and re-solidification located as an event. It \
         reads the same scene files. Each code ran at three resolutions of its own (M for the \
         independent code, N on stickslip's default grid, each doubling) and was extrapolated \
         by Richardson's rule with its observed order p; the uncertainty is the GCI band \
         (1.25 × the extrapolation's correction, or 3 × the last change where the sequence is \
         not monotone, shown as p –) plus the time-stepping part (the middle resolution at \
         Radau's rtol {:e} against {:e}, and at stickslip's time.tolerance {:e} against {:e}). \
         The verdict compares the two converged values with the target; \"consistent\" says \
         whether their difference lies within the two uncertainties together. The paper-literal \
         scheme is not an independent check (it shares stickslip's driver and events) and is \
         not used here.\n",
        c.python,
        super::INDEPENDENT_RTOL[1],
        super::INDEPENDENT_RTOL[0],
        super::OURS_TOLERANCE[1],
        super::OURS_TOLERANCE[0],
    );
    let agree: usize = c
        .cases
        .iter()
        .filter_map(|r| r.quantities.as_ref().ok())
        .flatten()
        .filter(|q| q.agrees)
        .count();
    let total: usize = c
        .cases
        .iter()
        .map(|r| r.quantities.as_ref().map_or(1, Vec::len))
        .sum();
    let _ = writeln!(
        s,
        "**{agree} of {total} compared quantities meet their targets.**\n"
    );
    for r in &c.cases {
        let case = &r.case;
        let which = if case.events == 1 {
            "the first event".to_string()
        } else {
            format!("the first {} events", case.events)
        };
        let _ = writeln!(s, "### {} ({}): {which}\n", case.scene, case.target_name);
        let _ = writeln!(
            s,
            "Independent code at M = {:?}, stickslip at N = {:?} (wall times: the terminal of \
             `cargo xtask validate`; the reports hold none).\n",
            case.resolutions_m, case.nodes
        );
        match &r.quantities {
            Err(e) => {
                let _ = writeln!(s, "*Not compared: {e}*\n");
            }
            Ok(qs) => {
                let _ = writeln!(
                    s,
                    "| event | quantity | independent | stickslip | difference | target | \
                     verdict | consistent |\n|---|---|---|---|---|---|---|---|"
                );
                for q in qs {
                    let _ = writeln!(
                        s,
                        "| {} | {} | {} | {} | {} | {} | {} | {} |",
                        q.k,
                        q.name,
                        value_text(&q.name, &q.independent),
                        value_text(&q.name, &q.stickslip),
                        difference_text(q),
                        target_text(q.target),
                        if q.agrees {
                            "✅ agree"
                        } else {
                            "❌ DISAGREE"
                        },
                        if q.consistent { "yes" } else { "no" }
                    );
                }
                let _ = writeln!(s);
                let time_parts: Vec<String> = qs
                    .iter()
                    .filter(|q| q.name == "f_peak")
                    .map(|q| {
                        format!(
                            "event {}: stickslip {}, independent {}",
                            q.k,
                            sig(q.stickslip.time / q.stickslip.value.abs(), 2),
                            sig(q.independent.time / q.independent.value.abs(), 2)
                        )
                    })
                    .collect();
                let _ = writeln!(
                    s,
                    "Time-stepping part of f_peak's relative uncertainty: {}.\n",
                    time_parts.join("; ")
                );
            }
        }
    }
    let f_peaks: Vec<&Quantity> = c
        .cases
        .iter()
        .filter_map(|r| r.quantities.as_ref().ok())
        .flatten()
        .filter(|q| q.name == "f_peak")
        .collect();
    let low = f_peaks.iter().filter(|q| q.difference < 0.0).count();
    let _ = writeln!(
        s,
        "stickslip's f_peak is the largest F at its step ends, so the sampling biases it low; \
         the independent code maximises its dense output. {low} of the {} f_peak differences \
         are negative; where one is positive, stickslip's time-stepping part (above) is larger \
         than the sampling's bias.\n",
        f_peaks.len()
    );
    let _ = writeln!(
        s,
        "![Each code's error against its own resolution]({FIGURE})\n\nEach code's first onset \
         against its own resolution (M + 1 collocation points, or N nodes), as the distance to \
         its own extrapolated value; the dashed line is the other code's converged value's \
         distance from it.\n"
    );
    mdr3d_markdown(&mut s, &c.mdr3d);
    s
}

/// The 3D check's subsection.
fn mdr3d_markdown(s: &mut String, checks: &[Mdr3d]) {
    let _ = writeln!(s, "## MDR against 3D elasticity\n");
    let _ = writeln!(
        s,
        "`{MDR3D_SCRIPT}` takes the film's shear traction τ(r) from the independent code, at \
         the first onset and at the largest force before it, points it along the drive (x) on \
         the disk r ≤ a0, and integrates Cerruti's surface displacement of an elastic \
         half-space, u_x = Q/(2πG)·((1 − ν)/ρ + ν·cos²ψ/ρ), in polar coordinates about each \
         field point (Gauss–Legendre, {MDR3D_ORDER} points per panel; ± is the change at half \
         that). Each ν is taken at the scene's G* = 4G/(2 − ν), MDR's tangential modulus. \
         Because τ is axisymmetric, u_x(r, θ) = ū(r) + U2(r)·cos 2θ exactly. The average ū is \
         compared with MDR's u3D(r) at r/a0 = 0 … 1; U2 is what MDR cannot represent: the \
         film at the edge is strained ±Δε = |U2(a0)|/h0 about MDR's strain, depending on the \
         angle (less along the drive, more across it). The quadrature reproduces Johnson's \
         closed form for τ = q0·√(1 − r²/a²) (a test).\n"
    );
    let _ = writeln!(
        s,
        "| scene (M) | moment | t | ν | max abs(ū − u3D)/max u3D | Δε at the edge | Δε/εc |\n\
         |---|---|---|---|---|---|---|"
    );
    for m in checks {
        match &m.rows {
            Err(e) => {
                let _ = writeln!(
                    s,
                    "| {} ({}) | *not computed: {e}* | | | | | |",
                    m.scene, m.resolution_m
                );
            }
            Ok(rows) => {
                for r in rows {
                    let _ = writeln!(
                        s,
                        "| {} ({}) | {} | {} | {} | {:.1e} (± {:.0e}) | {} (± {:.0e}) | {} |",
                        m.scene,
                        m.resolution_m,
                        r.moment,
                        stickslip_report::fmt::time(r.t_s, 9),
                        r.nu,
                        r.mean_rel_diff,
                        r.mean_rel_diff_change,
                        sig(r.delta_eps_edge, 4),
                        r.delta_eps_edge_change,
                        sig(r.delta_eps_over_eps_c, 3)
                    );
                }
            }
        }
    }
    let all: Vec<&super::Mdr3dRow> = checks
        .iter()
        .filter_map(|m| m.rows.as_ref().ok())
        .flatten()
        .collect();
    let worst_mean = all.iter().map(|r| r.mean_rel_diff).fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "\n**The average is exact**: over every scene, moment and ν the angle-averaged 3D \
         displacement equals MDR's u3D within {worst_mean:.1e} of its largest value (the \
         criterion: ≤ {MDR3D_MEAN_TOLERANCE:e}). Averaged over the angle, Cerruti's kernel \
         becomes (1 − ν/2)/(2πG·ρ) = 1/(π·G*·ρ), Boussinesq's with G* for E*, and MDR is exact \
         for that axisymmetric integral. **The model error is the angular part.**"
    );
    for m in checks {
        let Ok(rows) = &m.rows else { continue };
        let worst = rows
            .iter()
            .max_by(|a, b| a.delta_eps_over_eps_c.total_cmp(&b.delta_eps_over_eps_c));
        if let Some(w) = worst {
            let _ = writeln!(
                s,
                "- {}: at most Δε = {} = {} % of εc (ν = {}, at the {}); none at ν = 0, where \
                 Cerruti's kernel has no angular part. A film on such a substrate melts first \
                 across the drive, where its strain is Δε higher than MDR's.",
                m.scene,
                sig(w.delta_eps_edge, 3),
                sig(100.0 * w.delta_eps_over_eps_c, 2),
                w.nu,
                if w.moment == "peak" {
                    "largest force before the first onset"
                } else {
                    "first onset"
                }
            );
        }
    }
    let _ = writeln!(s);
}

/// The figure: per case, the first onset's distance from each code's own converged value
/// against resolution, and the distance between the two converged values.
///
/// # Errors
/// A drawing error, or no case to draw.
pub fn figure(c: &Comparison) -> Result<String, String> {
    let mut panels = Vec::new();
    for r in &c.cases {
        let Ok(qs) = &r.quantities else { continue };
        let Some(q) = qs.iter().find(|q| q.k == 1 && q.name == "t_onset") else {
            continue;
        };
        let err = |conv: &Convergence, shift: usize| -> Vec<(f64, f64)> {
            conv.values
                .iter()
                .map(|(res, v)| ((res + shift) as f64, (v - conv.value).abs().max(1e-16)))
                .collect()
        };
        let floor = q.difference.abs().max(1e-16);
        let all_x: Vec<f64> = err(&q.independent, 1)
            .into_iter()
            .chain(err(&q.stickslip, 0))
            .map(|p| p.0)
            .collect();
        let (lo, hi) = all_x
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(l, h), x| (l.min(*x), h.max(*x)));
        let p = Panel::new(
            &format!("{}: first onset", r.case.scene),
            "resolution (M + 1 or N)",
            "|t_onset − own converged| (s)",
        )
        .log_log()
        .legend_outside()
        .with(vec![
            Series::new("independent (M + 1)", err(&q.independent, 1), PALETTE[0])
                .marker(Marker::Circle),
            Series::new("stickslip (N)", err(&q.stickslip, 0), PALETTE[1]).marker(Marker::Square),
            Series::new(
                "|difference of converged values|",
                vec![(lo, floor), (hi, floor)],
                PALETTE[2],
            )
            .dashed(),
        ]);
        panels.push(p);
    }
    if panels.is_empty() {
        return Err("no case was compared".into());
    }
    render_svg(&panels, 2, 560, 360)
}
