//! The report's SVG figures: the paper's Fig. 2a–d, 3, 4a–b, 5a–b, and the rigid-drive,
//! homogeneous-vs-radial and literal-vs-accurate comparisons, drawn with the reporting kit
//! (`stickslip_report::plot`, one palette). Each comes with a two-line caption — what is
//! shown, and what to see — whose numbers are computed from the runs drawn.

use crate::claims::{Runs, probe_melts, stick_start_s, x_distances};
use crate::facts::{Facts, word};
use plotters::style::RGBColor;
use stickslip_core::sim::events::MeltingEvent;
use stickslip_report::fmt;
use stickslip_report::palette::{PALETTE, sequential};
use stickslip_report::plot::{LegendAt, Marker, Panel, Scale, Series, render_svg};
use stickslip_report::stats::{cv, diffs, interp};
use stickslip_run::RunOutput;
use stickslip_run::schema::profiles::ProfileView;

/// One rendered figure.
#[derive(Debug, Clone)]
pub struct Figure {
    /// File name in `reports/`.
    pub file: &'static str,
    /// Short title for the index.
    pub title: String,
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
const BLACK: RGBColor = PALETTE[6];

fn pts(x: &[f64], y: &[f64], sx: f64, sy: f64) -> Vec<(f64, f64)> {
    x.iter().zip(y).map(|(&a, &b)| (a * sx, b * sy)).collect()
}

fn force_line(run: &RunOutput, label: &str, color: RGBColor, t_scale: f64) -> Series {
    let s = &run.series;
    Series::new(label, pts(&s.t_s, &s.f_n, t_scale, 1e3), color)
}

fn onset_marks(run: &RunOutput, t_scale: f64, color: RGBColor) -> Series {
    let s = &run.series;
    let p = run
        .events
        .events()
        .iter()
        .map(|e| {
            (
                e.t_onset_s * t_scale,
                interp(&s.t_s, &s.f_n, e.t_onset_s) * 1e3,
            )
        })
        .collect();
    Series::new("melting onset", p, color).points()
}

fn figure(
    file: &'static str,
    title: impl Into<String>,
    caption: String,
    panels: Result<Vec<Panel>, String>,
    height: u32,
) -> Figure {
    Figure {
        file,
        title: title.into(),
        caption,
        svg: panels.and_then(|p| render_svg(&p, 1, W, height)),
    }
}

/// `scheme, stepping` of a run in words.
fn how(run: &RunOutput) -> String {
    format!(
        "{} scheme, N = {}, {}",
        word(&run.info.scheme()),
        run.info.nodes(),
        run.info.stepping_text()
    )
}

/// Onset intervals of a run: (first onset, first interval, last interval), s.
fn rhythm(run: &RunOutput) -> (f64, f64, f64) {
    let on = run.events.onsets_s();
    let d = diffs(&on);
    (
        on.first().copied().unwrap_or(f64::NAN),
        d.first().copied().unwrap_or(f64::NAN),
        d.last().copied().unwrap_or(f64::NAN),
    )
}

fn fig2a(runs: &Runs) -> Figure {
    let r = runs.get("fig2");
    let panels = r.clone().map(|r| {
        vec![
            Panel::new(
                "Fig. 2a — friction force, spring drive (fig2)",
                "time t, ms",
                "friction force F, mN",
            )
            .with(vec![
                force_line(r, "F(t) = 2π∫τ r dr", BLUE, 1e3),
                onset_marks(r, 1e3, ORANGE),
            ])
            .headroom(0.22)
            .legend(LegendAt::UpperLeft),
        ]
    });
    let caption = r.map_or_else(
        |e| format!("Not available: {e}"),
        |r| {
            let (first, d0, d1) = rhythm(r);
            format!(
                "Friction force against time for the paper's fig2 parameters ({}).\n\
                 See the long first stick phase up to the first melting at {}, then {} more \
                 teeth ({} meltings in all) that come ever faster (intervals {} → {}); F falls \
                 to ≈ 0 as φ collapses, and the melting onset (dot) follows.",
                how(r),
                fmt::time(first, 4),
                r.events.len().saturating_sub(1),
                r.events.len(),
                fmt::time(d0, 4),
                fmt::time(d1, 3)
            )
        },
    );
    figure("fig2a_force.svg", "Fig. 2a: F(t)", caption, panels, H)
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

/// The last event of `run` whose film recovered (`t_end`) before the run's end.
fn last_complete_event(run: &RunOutput) -> Option<&MeltingEvent> {
    run.events
        .events()
        .iter()
        .rev()
        .find(|e| e.t_end_s.is_some_and(|t| t < run.info.end_s()))
}

/// fig3's snapshots through its last complete melting: every profile before the end (the
/// times [`crate::runner::fig3_overrides`] asked for, from fig2's events).
fn snapshots(f3: &RunOutput) -> Vec<ProfileView<'_>> {
    let end = f3.info.end_s();
    f3.profiles
        .blocks()
        .into_iter()
        .filter(|q| q.t_s < end)
        .collect()
}

fn profile_fig(runs: &Runs, file: &'static str, is_phi: bool) -> Figure {
    let pick = |p: &ProfileView<'_>| -> Vec<(f64, f64)> {
        let y = if is_phi { p.phi } else { p.eps };
        p.r_m.iter().zip(y).map(|(&a, &b)| (a * 1e6, b)).collect()
    };
    let fig2 = runs.get("fig2");
    let at = fig2
        .as_ref()
        .ok()
        .and_then(|r| r.profiles.nearest(r.info.end_s()).map(|p| p.t_s));
    let last = runs
        .get("fig3")
        .ok()
        .and_then(|f3| last_complete_event(f3).map(|ev| (f3, ev)));
    let panels = fig2.clone().and_then(|r| {
        let p = r
            .profiles
            .nearest(r.info.end_s())
            .ok_or_else(|| "fig2 wrote no profile".to_string())?;
        let mut lines = Vec::new();
        let mut subtitle = String::new();
        if let Some((f3, ev)) = last {
            let snaps = snapshots(f3);
            let n = snaps.len().max(2) - 1;
            for (j, q) in snaps.iter().enumerate() {
                lines.push(Series::new(
                    format!("t − t_onset = {} µs", signed((q.t_s - ev.t_onset_s) * 1e6)),
                    pick(q),
                    sequential(j as f64 / n as f64),
                ));
            }
            subtitle = format!(
                ", and through the melting at {}",
                fmt::time(ev.t_onset_s, 6)
            );
        }
        lines.push(
            Series::new(
                format!("t = {} (the paper's time)", fmt::time(p.t_s, 3)),
                pick(&p),
                BLACK,
            )
            .dashed(),
        );
        let (ref_y, ref_label) = if is_phi {
            (r.info.derived.phi0, "φ0 = √(A/a), solid film at ε = 0")
        } else {
            (r.info.derived.eps_c, "εc = √(A·b)/a, melting strain")
        };
        let a0 = r.info.radius_m() * 1e6;
        // φ on a log axis: a melting front takes φ down to the threshold (0.01), two decades
        // below the solid film, which a linear axis flattens onto zero.
        let threshold = r.info.melt_threshold();
        let panel = Panel::new(
            &format!(
                "Fig. 2{} — {} at t = {}{}",
                if is_phi { "b" } else { "d" },
                if is_phi { "φ(r)" } else { "ε(r)" },
                fmt::time(p.t_s, 3),
                subtitle
            ),
            "radius r, µm",
            if is_phi {
                "order parameter φ"
            } else {
                "elastic strain ε"
            },
        )
        .with(lines)
        .hline(ref_y, ref_label)
        .x_range(0.0, a0)
        .legend(LegendAt::UpperLeft);
        Ok(vec![if is_phi {
            panel
                .scales(Scale::Linear, Scale::Log)
                .hline(threshold, "melting threshold")
                .y_range(threshold / 5.0, ref_y * 20.0)
        } else {
            panel.y_range(0.0, ref_y * 1.85)
        }])
    });
    let when = at.map_or_else(|| "the end".to_string(), |t| fmt::time(t, 3));
    let caption = match (&fig2, last) {
        (Ok(r), Some((f3, ev))) => {
            let snaps = snapshots(f3);
            let before = snaps.first();
            let (lo, hi) = before.map_or((f64::NAN, f64::NAN), |q| {
                let y = if is_phi { q.phi } else { q.eps };
                y.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                        (a.min(v), b.max(v))
                    })
            });
            let front = ev.t_center_s.map_or(f64::NAN, |t| t - ev.t_onset_s);
            let recovered = ev.t_end_s.map_or(f64::NAN, |t| t - ev.t_onset_s);
            let lead = before.map_or(f64::NAN, |q| ev.t_onset_s - q.t_s);
            let end_min = r.profiles.nearest(r.info.end_s()).map_or(f64::NAN, |p| {
                p.phi.iter().copied().fold(f64::INFINITY, f64::min)
            });
            if is_phi {
                format!(
                    "φ(r) at the paper's t = {when} (black dashed) and at {} instants through \
                     the last complete melting before it (colours, fig3 run = fig2 with probes).\n\
                     See φ already low everywhere {} before the onset ({} ≤ φ ≤ {}), the \
                     melting front run from the edge (r = {} µm) to the axis in {}, and the film \
                     recover (every node back above the recovery level) {} after the onset; at \
                     {when} it is solid again (φ ≥ {}).",
                    snaps.len(),
                    fmt::time(lead, 2),
                    fmt::sig(lo, 2),
                    fmt::sig(hi, 2),
                    fmt::sig(r.info.radius_m() * 1e6, 3),
                    fmt::time(front, 2),
                    fmt::time(recovered, 2),
                    fmt::sig(end_min, 3)
                )
            } else {
                let (axis, edge) = before.map_or((f64::NAN, f64::NAN), |q| {
                    (
                        q.eps.first().copied().unwrap_or(f64::NAN),
                        q.eps.last().copied().unwrap_or(f64::NAN),
                    )
                });
                format!(
                    "ε(r) at t = {when} (black dashed) and at the same {} instants through the \
                     last melting (colours).\n\
                     See the strain {} at the edge, where the substrate gives least ({} \
                     before the onset: ε = {} at the outermost node against {} on the axis, \
                     {} ≤ ε ≤ {}), and reset to 0 from the edge inwards as the front passes.",
                    snaps.len(),
                    if edge > axis {
                        "largest"
                    } else {
                        "NOT largest"
                    },
                    fmt::time(lead, 2),
                    fmt::sig(edge, 4),
                    fmt::sig(axis, 4),
                    fmt::sig(lo, 4),
                    fmt::sig(hi, 4)
                )
            }
        }
        _ => format!(
            "{} at the end of fig2; the snapshots through a melting need fig3: {}",
            if is_phi { "φ(r)" } else { "ε(r)" },
            runs.get("fig3").err().unwrap_or_default()
        ),
    };
    let title = format!(
        "Fig. 2{}: {} at {when}",
        if is_phi { "b" } else { "d" },
        if is_phi { "φ(r)" } else { "ε(r)" }
    );
    figure(file, title, caption, panels, H + 60)
}

fn means_fig(runs: &Runs, name: &str, file: &'static str, fig: &str) -> Figure {
    let r = runs.get(name);
    let panels = r.clone().map(|r| {
        let s = &r.series;
        vec![
            Panel::new(
                &format!("Fig. {fig} — mean order parameter and strain ({name})"),
                "time t, ms",
                "area-weighted mean (dimensionless)",
            )
            .with(vec![
                Series::new("⟨φ⟩", pts(&s.t_s, &s.phi_mean, 1e3, 1.0), BLUE),
                Series::new("⟨ε⟩", pts(&s.t_s, &s.eps_mean, 1e3, 1.0), ORANGE).dashed(),
            ])
            .legend(LegendAt::UpperLeft),
        ]
    });
    let caption = if name == "fig2" {
        "Area-weighted means ⟨φ⟩ (solid) and ⟨ε⟩ (dashed) against time, fig2.\n\
         See the slow transition before the first melting, then ⟨φ⟩ collapsing and ⟨ε⟩ \
         resetting at every event."
            .to_string()
    } else {
        format!(
            "Area-weighted means ⟨φ⟩ (solid) and ⟨ε⟩ (dashed) against time, {name} ({}).\n\
             See both amplitudes shrink from cycle to cycle as A falls, while the cycles still \
             come faster.",
            r.map_or_else(|_| "heating".to_string(), temperature_law)
        )
    };
    figure(
        file,
        format!("Fig. {fig}: ⟨φ⟩(t), ⟨ε⟩(t) ({name})"),
        caption,
        panels,
        H,
    )
}

/// The temperature law of a run in words, e.g. `A(t) = 1.5e6·e^(−t/1e-3 s) Pa`.
fn temperature_law(r: &RunOutput) -> String {
    let t = r.info.scene.temperature.as_ref();
    match (
        t.and_then(|t| t.a0),
        t.and_then(|t| t.t_relax),
        t.and_then(|t| t.law),
    ) {
        (Some(a0), Some(tr), Some(stickslip_run::scene::file::TemperatureLaw::Relaxation)) => {
            format!("A(t) = {a0:e}·e^(−t/{tr:e} s) Pa, rising temperature")
        }
        (Some(a0), _, _) => format!("A = {a0:e} Pa"),
        _ => format!("A = {:e} Pa", r.info.derived.a),
    }
}

fn fig3(runs: &Runs) -> Figure {
    let run = runs.get("fig3");
    let panels = run.clone().and_then(|r| {
        let p = &r.probes;
        if p.radii_m.is_empty() {
            return Err("fig3 wrote no probes".to_string());
        }
        let ev = last_complete_event(r).ok_or_else(|| "fig3 has no complete event".to_string())?;
        let k = ev.k.saturating_sub(1);
        let melts = probe_melts(r);
        let last = melts
            .iter()
            .filter(|m| m.event == k)
            .filter_map(|m| m.t_solid_s)
            .fold(ev.t_end_s.unwrap_or(ev.t_onset_s), f64::max);
        let stick_start = stick_start_s(r, k);
        let r_max = p.radii_m.iter().copied().fold(0.0, f64::max);
        let curves = |ta: f64, tb: f64, log: bool, legend: bool| -> Vec<Series> {
            let i0 = p.t_s.partition_point(|&t| t < ta);
            let i1 = p.t_s.partition_point(|&t| t <= tb);
            p.radii_m
                .iter()
                .zip(&p.phi)
                .map(|(&rad, phi)| {
                    let curve = (i0..i1)
                        .map(|i| {
                            let y = if log { phi[i].max(1e-12) } else { phi[i] };
                            (p.t_s[i] * 1e6, y)
                        })
                        .collect();
                    Series::new(
                        if legend {
                            format!("r = {} µm", fmt::sig(rad * 1e6, 3))
                        } else {
                            String::new()
                        },
                        curve,
                        sequential(1.0 - rad / r_max),
                    )
                })
                .collect()
        };
        let (za, zb) = (ev.t_onset_s - 0.1e-6, last + 0.1e-6);
        let (wa, wb) = (stick_start, last + 2e-6);
        let thr = r.info.melt_threshold();
        Ok(vec![
            Panel::new(
                &format!(
                    "Fig. 3 — φ(t) at the probe radii over the stick phase before the melting at {}",
                    fmt::time(ev.t_onset_s, 6)
                ),
                "time t, µs",
                "order parameter φ",
            )
            .with(curves(wa, wb, false, true))
            .x_range(wa * 1e6, wb * 1e6)
            .y_range(0.0, 1.3)
            .legend(LegendAt::LowerLeft),
            Panel::new(
                &format!(
                    "Inset — the melting, log scale: each radius falls to {} (melts) and recovers at once",
                    fmt::trim(thr)
                ),
                "time t, µs",
                "order parameter φ (log scale)",
            )
            .with(curves(za, zb, true, false))
            .scales(Scale::Linear, Scale::Log)
            .hline(thr, format!("melting threshold φ = {}", fmt::trim(thr)))
            .x_range(za * 1e6, zb * 1e6)
            .legend(LegendAt::UpperLeft),
        ])
    });
    let caption = run.map_or_else(
        |e| format!("Not available: {e}"),
        |r| {
            let radii: Vec<String> = r
                .probes
                .radii_m
                .iter()
                .map(|x| fmt::sig(x * 1e6, 3))
                .collect();
            let shortest = diffs(&r.events.onsets_s())
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            format!(
                "φ(t) at r = {} µm (dark = outer, yellow = inner), fig3; top: the whole stick \
                 phase, bottom: the melting, log scale, sampled every {}.\n\
                 See all radii decline together while the strain builds, the outer radii cross \
                 φ = {} first, and each radius re-solidify right after — at once next to the \
                 shortest interval between events, {}.",
                radii.join(", "),
                fmt::time(r.info.series_interval_s(), 2),
                fmt::trim(r.info.melt_threshold()),
                fmt::time(shortest, 3)
            )
        },
    );
    figure(
        "fig3_probes.svg",
        "Fig. 3: φ(t) at the probe radii",
        caption,
        panels,
        H,
    )
}

fn fig4a(runs: &Runs) -> Figure {
    let r = runs.get("fig4");
    let panels = r.clone().map(|r| {
        vec![
            Panel::new(
                "Fig. 4a — friction force with heating lubricant (fig4)",
                "time t, ms",
                "friction force F, mN",
            )
            .with(vec![
                force_line(r, "F(t)", BLUE, 1e3),
                onset_marks(r, 1e3, ORANGE),
            ])
            .headroom(0.22)
            .legend(LegendAt::UpperRight),
        ]
    });
    let caption = r.map_or_else(
        |e| format!("Not available: {e}"),
        |r| {
            let ev = r.events.events();
            let (f0, f1) = (
                ev.first().map_or(f64::NAN, |e| e.f_peak_n),
                ev.last().map_or(f64::NAN, |e| e.f_peak_n),
            );
            let (_, d0, d1) = rhythm(r);
            format!(
                "Friction force against time for fig4: fig2 with {} ({}).\n\
                 See the peaks of F fall event by event ({} → {} mN over {} events) while the \
                 events still come faster (intervals {} → {}).",
                temperature_law(r),
                how(r),
                fmt::sig(f0 * 1e3, 3),
                fmt::sig(f1 * 1e3, 3),
                ev.len(),
                fmt::time(d0, 4),
                fmt::time(d1, 3)
            )
        },
    );
    figure(
        "fig4a_force.svg",
        "Fig. 4a: F(t) with heating",
        caption,
        panels,
        H,
    )
}

fn f_vs_x(runs: &Runs, name: &str, file: &'static str) -> Figure {
    let r = runs.get(name);
    let panels = r.clone().map(|r| {
        let s = &r.series;
        let marks = r
            .events
            .events()
            .iter()
            .map(|e| (e.x_onset_m * 1e6, interp(&s.t_s, &s.f_n, e.t_onset_s) * 1e3))
            .collect();
        vec![
            Panel::new(
                &format!(
                    "Fig. 5{} — friction force against stamp position ({name})",
                    if name == "fig2" { "a" } else { "b" }
                ),
                "stamp position X, µm",
                "friction force F, mN",
            )
            .with(vec![
                Series::new("F(X)", pts(&s.x_m, &s.f_n, 1e6, 1e3), BLUE),
                Series::new("melting onset", marks, ORANGE).points(),
            ])
            .headroom(0.22)
            .legend(LegendAt::UpperRight),
        ]
    });
    let caption = r.map_or_else(
        |e| format!("Not available: {e}"),
        |r| {
            let cx = cv(&x_distances(r));
            let ct = cv(&diffs(&r.events.onsets_s()));
            if name == "fig2" {
                format!(
                    "Friction force against the stamp position X for fig2.\n\
                     See the teeth repeat at a nearly constant X-spacing (CV of the X-distances \
                     between onsets {}, of the time intervals {}): F(X) is periodic although \
                     F(t) is not.",
                    fmt::sig(cx, 2),
                    fmt::sig(ct, 2)
                )
            } else {
                format!(
                    "Friction force against the stamp position X for {name} (heating).\n\
                     See the teeth damped in amplitude, their X-spacing shrinking with the \
                     critical strain (CV of the X-distances {}).",
                    fmt::sig(cx, 2)
                )
            }
        },
    );
    figure(
        file,
        format!(
            "Fig. 5{}: F(X), {name}",
            if name == "fig2" { "a" } else { "b" }
        ),
        caption,
        panels,
        H,
    )
}

fn rigid(runs: &Runs) -> Figure {
    let both = runs
        .get("rigid")
        .and_then(|slow| runs.get("rigid_fast").map(|fast| (slow, fast)));
    let panel = |r: &RunOutput, scale: f64, unit: &str, color: RGBColor| {
        Panel::new(
            &format!(
                "Rigid coupler X = V0·t, V0 = {} m/s",
                fmt::trim(r.info.velocity_m_per_s())
            ),
            &format!("time t, {unit}"),
            "friction force F, mN",
        )
        .with(vec![
            force_line(r, "F(t)", color, scale),
            onset_marks(r, scale, ORANGE),
        ])
        .headroom(0.22)
        .legend(LegendAt::UpperRight)
    };
    let panels = both
        .clone()
        .map(|(slow, fast)| vec![panel(slow, 1e3, "ms", BLUE), panel(fast, 1e6, "µs", GREEN)]);
    let caption = both.map_or_else(
        |e| format!("Not available: {e}"),
        |(slow, fast)| {
            let cs = cv(&diffs(&slow.events.onsets_s()));
            let fe = fast.events.events();
            let first = fe.first().map_or(f64::NAN, |e| e.f_peak_n);
            let later = fe.iter().skip(1).map(|e| e.f_peak_n).fold(0.0, f64::max);
            format!(
                "Friction force with the stamp moved at constant speed: V0 = {} m/s (top) and \
                 V0 = {} m/s (bottom).\n\
                 Top: {} events evenly spaced in time (CV of the intervals {}; C10). Bottom: the \
                 drive outruns the film's recovery: after the first melting F peaks at only {} % \
                 of its first peak.",
                fmt::trim(slow.info.velocity_m_per_s()),
                fmt::trim(fast.info.velocity_m_per_s()),
                slow.events.len(),
                fmt::sig(cs, 2),
                fmt::sig(100.0 * later / first, 2)
            )
        },
    );
    figure(
        "rigid.svg",
        "Rigid drive (slow and fast)",
        caption,
        panels,
        H - 40,
    )
}

fn homogeneous(runs: &Runs) -> Figure {
    let both = runs
        .get("fig2")
        .and_then(|r| runs.get("homogeneous").map(|h| (r, h)));
    let panels = both.clone().map(|(r, h)| {
        vec![
            Panel::new(
                "Homogeneous (one node) against radial MDR model, fig2 parameters",
                "time t, ms",
                "friction force F, mN",
            )
            .with(vec![
                force_line(
                    r,
                    &format!("radial (MDR, N = {})", r.info.nodes()),
                    BLUE,
                    1e3,
                ),
                force_line(h, "homogeneous (one node)", ORANGE, 1e3).dashed(),
            ])
            .headroom(0.22)
            .legend(LegendAt::UpperLeft),
        ]
    });
    figure(
        "homogeneous_vs_radial.svg",
        "Homogeneous vs radial (C6)",
        "F(t) of the radial MDR model (solid) and of the homogeneous one-node model (dashed), \
         fig2 parameters.\n\
         See how closely the two agree in event times and peak forces: the measure of C6 (its \
         numbers are in the claims table)."
            .into(),
        panels,
        H,
    )
}

fn literal(runs: &Runs) -> Figure {
    let all = runs.get("fig2").and_then(|acc| {
        let lit = runs.get("fig2_literal")?;
        let lit_default = runs.get("fig2_literal_default")?;
        Ok((acc, lit, lit_default))
    });
    let panels = all.clone().map(|(acc, lit, lit_default)| {
        let rf = |r: &RunOutput| -> Vec<(f64, f64)> {
            r.events
                .events()
                .iter()
                .map(|e| (e.t_onset_s * 1e3, e.r_first_m * 1e6))
                .collect()
        };
        let a0 = acc.info.radius_m() * 1e6;
        let (t0, t1) = (0.0, acc.info.end_s() * 1e3);
        vec![
            Panel::new(
                &format!(
                    "Friction force: accurate scheme against the paper's literal scheme (N = {})",
                    acc.info.nodes()
                ),
                "time t, ms",
                "friction force F, mN",
            )
            .with(vec![
                force_line(acc, "accurate", BLUE, 1e3),
                force_line(lit, "literal (paper's algorithm)", ORANGE, 1e3).dashed(),
            ])
            .x_range(t0, t1)
            .headroom(0.22)
            .legend(LegendAt::UpperLeft),
            Panel::new(
                "Where each melting starts: outermost melted radius at the onset",
                "onset time, ms",
                "first melted radius r_first, µm",
            )
            .with(vec![
                Series::new("accurate", rf(acc), BLUE).points(),
                Series::new("literal, default event settings", rf(lit_default), ORANGE)
                    .points()
                    .marker(Marker::Cross),
            ])
            .x_range(t0, t1)
            .y_range(-1.0, a0 + 1.0)
            .legend(LegendAt::MiddleRight),
        ]
    });
    let caption = all.map_or_else(
        |e| format!("Not available: {e}"),
        |(acc, lit, lit_default)| {
            format!(
                "Top: F(t) of fig2 — solid: {}; dashed: the paper's literal algorithm, {}.\n\
                 Bottom: radius of the outermost melted node at each onset; the literal run with \
                 the default event settings has {} events, the accurate one {} — a value near 0 \
                 means the axis melted first (see Findings).",
                how(acc),
                how(lit),
                lit_default.events.len(),
                acc.events.len()
            )
        },
    );
    figure(
        "literal_vs_accurate.svg",
        "Literal vs accurate scheme",
        caption,
        panels,
        H - 40,
    )
}

/// The figures of the paper's (second-order) film, in the order of the index; the
/// first-order film's follow them (`crate::figures_first_order::all`).
pub fn all(runs: &Runs) -> Vec<Figure> {
    vec![
        fig2a(runs),
        profile_fig(runs, "fig2b_phi_profile.svg", true),
        means_fig(runs, "fig2", "fig2c_means.svg", "2c"),
        profile_fig(runs, "fig2d_eps_profile.svg", false),
        fig3(runs),
        fig4a(runs),
        means_fig(runs, "fig4", "fig4b_means.svg", "4b"),
        f_vs_x(runs, "fig2", "fig5a_f_vs_x.svg"),
        f_vs_x(runs, "fig4", "fig5b_f_vs_x.svg"),
        rigid(runs),
        homogeneous(runs),
        literal(runs),
    ]
}

/// The margin chart's file name in `reports/`.
pub const MARGINS_SVG: &str = "claims_margins.svg";

/// Each claim's margin to its threshold (`crate::margins`), one marker per claim, with the
/// line at 0 where a claim would fail.
///
/// # Errors
/// A drawing error, or no claim with a margin.
pub fn margins_svg(claims: &[crate::claims::Claim]) -> Result<String, String> {
    let margins: Vec<crate::margins::Margin> =
        claims.iter().filter_map(crate::margins::of).collect();
    if margins.is_empty() {
        return Err("no claim has a margin".into());
    }
    let pts: Vec<(f64, f64)> = margins
        .iter()
        .enumerate()
        .map(|(i, m)| ((i + 1) as f64, m.value))
        .collect();
    let labels: Vec<String> = margins.iter().map(|m| m.id.to_string()).collect();
    let hi = pts.iter().map(|p| p.1).fold(1.0f64, f64::max) * 1.15;
    let lo = pts.iter().map(|p| p.1).fold(0.0f64, f64::min).min(-0.1);
    let p = Panel::new(
        "Each claim's margin to its threshold (0: the claim would fail)",
        "claim (in the table's order)",
        "margin, share of the threshold's room",
    )
    .with(vec![
        Series::new("margin of the binding number", pts, PALETTE[0])
            .points()
            .marker(Marker::Circle)
            .labels(labels),
    ])
    .hline(0.0, "fails below")
    .x_range(0.5, margins.len() as f64 + 0.5)
    .y_range(lo, hi)
    .legend_outside();
    render_svg(&[p], 1, 960, 420)
}
