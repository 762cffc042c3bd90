//! The report's SVG figures: the paper's Fig. 2a–d, 3, 4a–b, 5a–b, and the rigid-drive,
//! homogeneous-vs-radial and literal-vs-accurate comparisons. Each comes with a two-line
//! caption that says what to see.

use crate::claims::{Runs, probe_melts};
use crate::data::RunOutput;
use crate::plot::{LegendAt, Line, PALETTE, Panel, Style, render_svg, sequential};
use plotters::style::RGBColor;

/// One rendered figure.
#[derive(Debug, Clone)]
pub struct Figure {
    /// File name in `reports/`.
    pub file: &'static str,
    /// Short title for the index.
    pub title: &'static str,
    /// Two-line caption: what is shown, and what to see.
    pub caption: String,
    /// The SVG document, or why it could not be drawn.
    pub svg: Result<String, String>,
}

const W: u32 = 960;
const H: u32 = 540;
const BLUE: RGBColor = PALETTE[0];
const ORANGE: RGBColor = PALETTE[1];
const GREEN: RGBColor = PALETTE[2];
const GREY: RGBColor = RGBColor(120, 120, 120);

fn pts(x: &[f64], y: &[f64], sx: f64, sy: f64) -> Vec<(f64, f64)> {
    x.iter().zip(y).map(|(&a, &b)| (a * sx, b * sy)).collect()
}

fn force_line(run: &RunOutput, label: &str, color: RGBColor, style: Style, t_scale: f64) -> Line {
    let s = &run.series;
    Line::new(label, pts(&s.t_s, &s.f_n, t_scale, 1e3), color, style)
}

fn onset_marks(run: &RunOutput, t_scale: f64, color: RGBColor) -> Line {
    let s = &run.series;
    let p = run
        .events
        .events
        .iter()
        .map(|e| (e.t_onset_s * t_scale, s.interp(&s.f_n, e.t_onset_s) * 1e3))
        .collect();
    Line::new("melting onset", p, color, Style::Points)
}

fn figure(
    file: &'static str,
    title: &'static str,
    caption: String,
    panels: Result<Vec<Panel>, String>,
    height: u32,
) -> Figure {
    Figure {
        file,
        title,
        caption,
        svg: panels.and_then(|p| render_svg(&p, W, height)),
    }
}

fn fig2a(runs: &Runs) -> Figure {
    let panels = runs.get("fig2").map(|r| {
        vec![
            Panel::new(
                "Fig. 2a — friction force, spring drive (fig2)",
                "time t, ms",
                "friction force F, mN",
                vec![
                    force_line(r, "F(t) = 2π∫τ r dr", BLUE, Style::Solid, 1e3),
                    onset_marks(r, 1e3, ORANGE),
                ],
            )
            .headroom(0.22)
            .legend(LegendAt::UpperLeft),
        ]
    });
    figure(
        "fig2a_force.svg",
        "Fig. 2a: F(t)",
        "Friction force against time for the paper's fig2 parameters (spring drive, N = 200, accurate scheme).\n\
         See the long first stick phase, then teeth that come ever faster; F falls to ≈ 0 as φ collapses, and the melting onset (dot) follows."
            .into(),
        panels,
        H,
    )
}

/// `x` with an explicit sign and a true minus, two decimals.
fn signed(x: f64) -> String {
    let x = if x.abs() < 5e-3 { 0.0 } else { x };
    if x < 0.0 {
        format!("−{:.2}", -x)
    } else {
        format!("+{x:.2}")
    }
}

/// The last event of `run` that ended (contact fully solid again) before the run's end.
fn last_complete_event(run: &RunOutput) -> Option<&crate::data::Event> {
    run.events
        .events
        .iter()
        .rev()
        .find(|e| e.t_end_s.is_some_and(|t| t < run.info.end_s))
}

fn profile_fig(runs: &Runs, file: &'static str, title: &'static str, which: &str) -> Figure {
    let is_phi = which == "phi";
    let pick = |p: &crate::data::Profile| -> Vec<(f64, f64)> {
        let y = if is_phi { &p.phi } else { &p.eps };
        p.r_m.iter().zip(y).map(|(&a, &b)| (a * 1e6, b)).collect()
    };
    let panels = runs.get("fig2").and_then(|r| {
        let p = r
            .profile_near(r.info.end_s)
            .ok_or_else(|| "fig2 wrote no profile".to_string())?;
        let mut lines = Vec::new();
        let mut subtitle = String::new();
        if let Ok(f3) = runs.get("fig3")
            && let Some(ev) = last_complete_event(f3)
        {
            let snaps: Vec<&crate::data::Profile> = f3
                .profiles
                .iter()
                .filter(|q| q.t_s < ev.t_end_s.unwrap_or(f64::INFINITY) + 1e-9)
                .collect();
            let n = snaps.len().max(2) - 1;
            for (j, q) in snaps.iter().enumerate() {
                lines.push(Line::new(
                    &format!("t − t_onset = {} µs", signed((q.t_s - ev.t_onset_s) * 1e6)),
                    pick(q),
                    sequential(j as f64 / n as f64),
                    Style::Solid,
                ));
            }
            subtitle = format!(", and through the melting at {:.2} µs", ev.t_onset_s * 1e6);
        }
        lines.push(Line::new(
            &format!("t = {:.2} ms (the paper's time)", p.t_s * 1e3),
            pick(p),
            RGBColor(0, 0, 0),
            Style::Dashed,
        ));
        let (ref_y, ref_label) = if is_phi {
            (1.5_f64.sqrt(), "φ0 = √(A/a), solid film at ε = 0")
        } else {
            (3.0_f64.sqrt(), "εc = √(A·b)/a, melting strain")
        };
        let a0 = r.info.radius_m * 1e6;
        lines.push(Line::new(
            ref_label,
            vec![(0.0, ref_y), (a0, ref_y)],
            GREY,
            Style::Reference,
        ));
        Ok(vec![
            Panel::new(
                &format!(
                    "Fig. 2{} — {} at t = {:.1} ms{}",
                    if is_phi { "b" } else { "d" },
                    if is_phi { "φ(r)" } else { "ε(r)" },
                    p.t_s * 1e3,
                    subtitle
                ),
                "radius r, µm",
                if is_phi {
                    "order parameter φ"
                } else {
                    "elastic strain ε"
                },
                lines,
            )
            .x_range(0.0, a0)
            .y_range(0.0, ref_y * if is_phi { 1.75 } else { 1.85 })
            .legend(LegendAt::UpperLeft),
        ])
    });
    let caption = if is_phi {
        "φ(r) at the paper's t = 1.3 ms (black dashed) and at six instants through the last complete melting before it (colours, fig3 run = fig2 with probes).\n\
         See φ fall almost uniformly to ≈ 0 in the last µs before the onset, then the film re-solidify from the edge (r = 20 µm) to the axis within ~0.2 µs; at 1.3 ms it is solid again."
    } else {
        "ε(r) at t = 1.3 ms (black dashed) and at the same six instants through the last melting (colours).\n\
         See the strain largest at the edge, where the substrate gives least, and reset to 0 from the edge inwards as the front passes."
    };
    figure(file, title, caption.into(), panels, H + 60)
}

fn means_fig(
    runs: &Runs,
    name: &str,
    file: &'static str,
    title: &'static str,
    fig: &str,
) -> Figure {
    let panels = runs.get(name).map(|r| {
        let s = &r.series;
        vec![
            Panel::new(
                &format!("Fig. {fig} — mean order parameter and strain ({name})"),
                "time t, ms",
                "area-weighted mean (dimensionless)",
                vec![
                    Line::new(
                        "⟨φ⟩",
                        pts(&s.t_s, &s.phi_mean, 1e3, 1.0),
                        BLUE,
                        Style::Solid,
                    ),
                    Line::new(
                        "⟨ε⟩",
                        pts(&s.t_s, &s.eps_mean, 1e3, 1.0),
                        ORANGE,
                        Style::Dashed,
                    ),
                ],
            )
            .legend(LegendAt::UpperLeft),
        ]
    });
    let caption = if name == "fig2" {
        "Area-weighted means ⟨φ⟩ (solid) and ⟨ε⟩ (dashed) against time, fig2.\n\
         See the slow transition before the first melting, then ⟨φ⟩ collapsing and ⟨ε⟩ resetting at every event."
    } else {
        "Area-weighted means ⟨φ⟩ (solid) and ⟨ε⟩ (dashed) against time, fig4 (A(t) = A0·e^(−t/t̃), heating).\n\
         See both amplitudes shrink from cycle to cycle as A falls, while the cycles still come faster."
    };
    figure(file, title, caption.into(), panels, H)
}

fn fig3(runs: &Runs) -> Figure {
    let panels = runs.get("fig3").and_then(|r| {
        let p = r
            .probes
            .as_ref()
            .ok_or_else(|| "fig3 wrote no probes".to_string())?;
        let ev = last_complete_event(r).ok_or_else(|| "fig3 has no complete event".to_string())?;
        let k = ev.k.saturating_sub(1);
        let melts = probe_melts(r);
        let last = melts
            .iter()
            .filter(|m| m.event == k)
            .filter_map(|m| m.t_solid_s)
            .fold(ev.t_end_s.unwrap_or(ev.t_onset_s), f64::max);
        let stick_start = crate::claims::stick_start_s(r, k);
        let r_max = p.radii_m.iter().copied().fold(0.0, f64::max);
        let curves = |ta: f64, tb: f64, log: bool, legend: bool| -> Vec<Line> {
            let i0 = p.t_s.partition_point(|&t| t < ta);
            let i1 = p.t_s.partition_point(|&t| t <= tb);
            let mut lines: Vec<Line> = p
                .radii_m
                .iter()
                .zip(&p.phi)
                .map(|(&rad, phi)| {
                    let curve = (i0..i1)
                        .map(|i| {
                            let y = if log { phi[i].max(1e-12).log10() } else { phi[i] };
                            (p.t_s[i] * 1e6, y)
                        })
                        .collect();
                    Line::new(
                        &if legend {
                            format!("r = {:.0} µm", rad * 1e6)
                        } else {
                            String::new()
                        },
                        curve,
                        sequential(1.0 - rad / r_max),
                        Style::Solid,
                    )
                })
                .collect();
            if log {
                let thr = r.info.melt_threshold.log10();
                lines.push(Line::new(
                    "melting threshold φ = 0.01",
                    vec![(ta * 1e6, thr), (tb * 1e6, thr)],
                    RGBColor(200, 0, 0),
                    Style::Reference,
                ));
            }
            lines
        };
        let (za, zb) = (ev.t_onset_s - 0.1e-6, last + 0.1e-6);
        let (wa, wb) = (stick_start, last + 2e-6);
        Ok(vec![
            Panel::new(
                &format!(
                    "Fig. 3 — φ(t) at r = 2…18 µm over the stick phase before the melting at {:.2} µs",
                    ev.t_onset_s * 1e6
                ),
                "time t, µs",
                "order parameter φ",
                curves(wa, wb, false, true),
            )
            .x_range(wa * 1e6, wb * 1e6)
            .y_range(0.0, 1.3)
            .legend(LegendAt::LowerLeft),
            Panel::new(
                "Inset — the melting itself, log scale: each radius dips below 0.01 and recovers",
                "time t, µs",
                "log10 φ",
                curves(za, zb, true, false),
            )
            .x_range(za * 1e6, zb * 1e6)
            .legend(LegendAt::UpperLeft),
        ])
    });
    figure(
        "fig3_probes.svg",
        "Fig. 3: φ(t) at r = 2…18 µm",
        "φ(t) at r = 2, 4, …, 18 µm (dark = outer 18 µm, yellow = inner 2 µm), fig3; top: the whole stick phase, bottom: the melting, log scale, sampled every 1e-8 s.\n\
         See all radii decline together while the strain builds, the outer radii cross φ = 0.01 first, and each radius re-solidify right after — at once next to the ~45 µs interval."
            .into(),
        panels,
        H,
    )
}

fn force_fig(runs: &Runs, name: &str, file: &'static str, title: &'static str) -> Figure {
    let panels = runs.get(name).map(|r| {
        vec![
            Panel::new(
                "Fig. 4a — friction force with heating lubricant (fig4)",
                "time t, ms",
                "friction force F, mN",
                vec![
                    force_line(r, "F(t)", BLUE, Style::Solid, 1e3),
                    onset_marks(r, 1e3, ORANGE),
                ],
            )
            .headroom(0.22)
            .legend(LegendAt::UpperRight),
        ]
    });
    figure(
        file,
        title,
        "Friction force against time for fig4: fig2 with A(t) = 1.5e6·e^(−t/1 ms) Pa (rising temperature).\n\
         See the peaks of F fall event by event while the events still come faster."
            .into(),
        panels,
        H,
    )
}

fn f_vs_x(runs: &Runs, name: &str, file: &'static str, title: &'static str) -> Figure {
    let panels = runs.get(name).map(|r| {
        let s = &r.series;
        let marks = r
            .events
            .events
            .iter()
            .map(|e| (e.x_onset_m * 1e6, s.interp(&s.f_n, e.t_onset_s) * 1e3))
            .collect();
        vec![
            Panel::new(
                &format!(
                    "Fig. 5{} — friction force against stamp position ({name})",
                    if name == "fig2" { "a" } else { "b" }
                ),
                "stamp position X, µm",
                "friction force F, mN",
                vec![
                    Line::new("F(X)", pts(&s.x_m, &s.f_n, 1e6, 1e3), BLUE, Style::Solid),
                    Line::new("melting onset", marks, ORANGE, Style::Points),
                ],
            )
            .headroom(0.22)
            .legend(LegendAt::UpperRight),
        ]
    });
    let caption = if name == "fig2" {
        "Friction force against the stamp position X for fig2.\n\
         See the teeth repeat at a nearly constant X-spacing: F(X) is periodic although F(t) is not."
    } else {
        "Friction force against the stamp position X for fig4 (heating).\n\
         See the same X-periodic teeth damped in amplitude, the spacing shrinking with the critical strain."
    };
    figure(file, title, caption.into(), panels, H)
}

fn rigid(runs: &Runs) -> Figure {
    let panels = runs.get("rigid").and_then(|slow| {
        let fast = runs.get("rigid_fast")?;
        Ok(vec![
            Panel::new(
                &format!(
                    "Rigid coupler X = V0·t, V0 = {:.0e} m/s",
                    slow.info.velocity_m_per_s
                ),
                "time t, ms",
                "friction force F, mN",
                vec![
                    force_line(slow, "F(t)", BLUE, Style::Solid, 1e3),
                    onset_marks(slow, 1e3, ORANGE),
                ],
            )
            .headroom(0.22)
            .legend(LegendAt::UpperRight),
            Panel::new(
                &format!(
                    "Rigid coupler X = V0·t, V0 = {:.0} m/s",
                    fast.info.velocity_m_per_s
                ),
                "time t, µs",
                "friction force F, mN",
                vec![
                    force_line(fast, "F(t)", GREEN, Style::Solid, 1e6),
                    onset_marks(fast, 1e6, ORANGE),
                ],
            )
            .headroom(0.22)
            .legend(LegendAt::UpperRight),
        ])
    });
    figure(
        "rigid.svg",
        "Rigid drive (slow and fast)",
        "Friction force with the stamp moved at constant speed: V0 = 1e-3 m/s (top) and V0 = 1 m/s (bottom).\n\
         Top: regular stick–slip, evenly spaced in time (C10). Bottom: what happens when the drive outruns the film's recovery."
            .into(),
        panels,
        H - 40,
    )
}

fn homogeneous(runs: &Runs) -> Figure {
    let panels = runs.get("fig2").and_then(|r| {
        let h = runs.get("homogeneous")?;
        Ok(vec![
            Panel::new(
                "Homogeneous (one node) against radial MDR model, fig2 parameters",
                "time t, ms",
                "friction force F, mN",
                vec![
                    force_line(r, "radial (MDR, N = 200)", BLUE, Style::Solid, 1e3),
                    force_line(h, "homogeneous (one node)", ORANGE, Style::Dashed, 1e3),
                ],
            )
            .headroom(0.22)
            .legend(LegendAt::UpperLeft),
        ])
    });
    figure(
        "homogeneous_vs_radial.svg",
        "Homogeneous vs radial (C6)",
        "F(t) of the radial MDR model (solid) and of the homogeneous one-node model (dashed), fig2 parameters.\n\
         See how closely the two agree in event times and peak forces: the measure of C6."
            .into(),
        panels,
        H,
    )
}

fn literal(runs: &Runs) -> Figure {
    let panels = runs.get("fig2").and_then(|acc| {
        let lit = runs.get("fig2_literal")?;
        let rf = |r: &RunOutput| -> Vec<(f64, f64)> {
            r.events
                .events
                .iter()
                .map(|e| (e.t_onset_s * 1e3, e.r_first_m * 1e6))
                .collect()
        };
        let a0 = acc.info.radius_m * 1e6;
        let (t0, t1) = (0.0, acc.info.end_s * 1e3);
        Ok(vec![
            Panel::new(
                "Friction force: accurate scheme against the paper's literal scheme (N = 200)",
                "time t, ms",
                "friction force F, mN",
                vec![
                    force_line(acc, "accurate", BLUE, Style::Solid, 1e3),
                    force_line(
                        lit,
                        "literal (paper's algorithm)",
                        ORANGE,
                        Style::Dashed,
                        1e3,
                    ),
                ],
            )
            .x_range(t0, t1)
            .headroom(0.22)
            .legend(LegendAt::UpperLeft),
            Panel::new(
                "Where each melting starts: outermost melted radius at the onset",
                "onset time, ms",
                "first melted radius r_first, µm",
                vec![
                    Line::new("accurate", rf(acc), BLUE, Style::Points),
                    Line::new("literal", rf(lit), ORANGE, Style::Points),
                ],
            )
            .x_range(t0, t1)
            .y_range(-1.0, a0 + 1.0)
            .legend(LegendAt::MiddleRight),
        ])
    });
    figure(
        "literal_vs_accurate.svg",
        "Literal vs accurate scheme",
        "Top: F(t) of fig2 with the accurate scheme (solid) and the paper's literal algorithm (dashed), both N = 200, Δt = 1e-8 s.\n\
         Bottom: radius of the outermost melted node at each onset — a value near 0 means the axis melted (see Findings)."
            .into(),
        panels,
        H - 40,
    )
}

/// Every figure of the report, in the order of the index.
pub fn all(runs: &Runs) -> Vec<Figure> {
    vec![
        fig2a(runs),
        profile_fig(
            runs,
            "fig2b_phi_profile.svg",
            "Fig. 2b: φ(r) at 1.3 ms",
            "phi",
        ),
        means_fig(
            runs,
            "fig2",
            "fig2c_means.svg",
            "Fig. 2c: ⟨φ⟩(t), ⟨ε⟩(t)",
            "2c",
        ),
        profile_fig(
            runs,
            "fig2d_eps_profile.svg",
            "Fig. 2d: ε(r) at 1.3 ms",
            "eps",
        ),
        fig3(runs),
        force_fig(
            runs,
            "fig4",
            "fig4a_force.svg",
            "Fig. 4a: F(t) with heating",
        ),
        means_fig(
            runs,
            "fig4",
            "fig4b_means.svg",
            "Fig. 4b: ⟨φ⟩(t), ⟨ε⟩(t) with heating",
            "4b",
        ),
        f_vs_x(runs, "fig2", "fig5a_f_vs_x.svg", "Fig. 5a: F(X), fig2"),
        f_vs_x(runs, "fig4", "fig5b_f_vs_x.svg", "Fig. 5b: F(X), fig4"),
        rigid(runs),
        homogeneous(runs),
        literal(runs),
    ]
}
