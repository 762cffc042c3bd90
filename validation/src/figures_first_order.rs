//! The first-order film's figures (claims C11 and C12), drawn with the reporting kit like the
//! rest of [`crate::figures`]: the stationary φ(ε) loop with the simulated paths over it, and
//! radial against homogeneous for both films. Captions are computed from the runs drawn.

use crate::claims::Runs;
use crate::claims_first_order::{Hysteresis, contrasts, hysteresis_all};
use crate::figures::Figure;
use plotters::style::RGBColor;
use stickslip_report::fmt;
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{LegendAt, Marker, Panel, Series, render_svg};
use stickslip_run::RunOutput;

const W: u32 = 960;
const BLUE: RGBColor = PALETTE[0];
const ORANGE: RGBColor = PALETTE[1];
const GREEN: RGBColor = PALETTE[2];
const BLACK: RGBColor = PALETTE[6];

/// `n + 1` points of `f` on [lo, hi].
fn curve(lo: f64, hi: f64, n: usize, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|i| {
            let x = lo + (hi - lo) * i as f64 / n as f64;
            (x, f(x))
        })
        .collect()
}

/// The stationary loop of one film and the paths over it.
fn loop_panel(h: &Hysteresis, run: &RunOutput) -> Panel {
    let f = &h.imposed.film;
    let (p, a) = (&f.params, f.a_coeff_pa);
    let (ep, em) = (f.eps_plus(), f.eps_minus());
    let top = h.imposed.up.last().map_or(1.2 * ep, |q| q.0);
    // The run's path while solid: up to its first melting (after it, u0 is reset to 0).
    let t_melt = run
        .events
        .events()
        .first()
        .map_or(f64::INFINITY, |e| e.t_onset_s);
    let s = &run.series;
    let binary: Vec<(f64, f64)> = (0..s.len())
        .filter(|&i| s.t_s[i] < t_melt)
        .map(|i| (s.eps_mean[i], s.phi_mean[i]))
        .collect();
    Panel::new(
        &format!(
            "The first-order film's hysteresis at A = {} Pa: stationary states and the simulated paths",
            fmt::sig(a, 3)
        ),
        "strain ε",
        "order parameter φ",
    )
    .with(vec![
        Series::new(
            "solid branch φ₊(ε)",
            curve(0.0, ep, 400, |e| p.solid_phi(e, a)),
            BLACK,
        ),
        Series::new(
            "barrier φ₋(ε) (unstable)",
            curve(em, ep, 200, |e| p.barrier_phi(e, a)),
            BLACK,
        )
        .dashed(),
        Series::new("liquid φ = 0 (stable beyond ε₋)", vec![(em, 0.0), (top, 0.0)], GREEN),
        Series::new("imposed strain, up", h.imposed.up.clone(), BLUE),
        Series::new("imposed strain, down", h.imposed.down.clone(), ORANGE).dashed(),
        Series::new("the run (rigid drive), solid until it melts", binary, BLUE)
            .points()
            .marker(Marker::Cross),
    ])
    .vline(ep, format!("ε₊ = {}", fmt::sig(ep, 5)))
    .vline(em, format!("ε₋ = εc = {}", fmt::sig(em, 5)))
    .headroom(0.15)
    .legend(LegendAt::UpperRight)
}

/// Every loop's paths against ε², where the widths line up.
fn width_panel(hs: &[Hysteresis]) -> Panel {
    let colors = [BLUE, ORANGE, GREEN];
    let mut series = Vec::new();
    for (h, c) in hs.iter().zip(colors) {
        let sq = |v: &[(f64, f64)]| v.iter().map(|&(e, p)| (e * e, p)).collect::<Vec<_>>();
        let mut path = sq(&h.imposed.up);
        path.extend(sq(&h.imposed.down));
        series.push(Series::new(
            format!(
                "A = {} Pa: width {}",
                fmt::sig(h.imposed.film.a_coeff_pa, 3),
                fmt::sig(h.width(), 5)
            ),
            path,
            c,
        ));
    }
    Panel::new(
        "The same loops against ε²: each temperature shifts the loop, not its width",
        "ε²",
        "order parameter φ",
    )
    .with(series)
    .headroom(0.15)
    .legend(LegendAt::UpperRight)
}

fn hysteresis_fig(runs: &Runs) -> Figure {
    let all = hysteresis_all(runs);
    let ok: Vec<(String, Hysteresis)> = all
        .iter()
        .filter_map(|(n, h)| h.clone().ok().map(|h| (n.clone(), h)))
        .collect();
    let middle = ok
        .get(ok.len() / 2)
        .and_then(|(n, h)| runs.get(n).ok().map(|r| (h, r)));
    let svg = match middle {
        Some((h, r)) => {
            let hs: Vec<Hysteresis> = ok.iter().map(|(_, h)| h.clone()).collect();
            render_svg(&[loop_panel(h, r), width_panel(&hs)], 1, W, 900)
        }
        None => Err(all
            .iter()
            .find_map(|(_, h)| h.clone().err())
            .unwrap_or_else(|| "no hysteresis run".into())),
    };
    let caption = middle.map_or_else(
        || "Not available: the hysteresis runs failed.".to_string(),
        |(h, _)| {
            let (ep, em, w) = h.theory();
            format!(
                "Top: the stationary states of the first-order film (solid branch, barrier, \
                 liquid) at A = {} Pa, the hysteresis run's path while solid (crosses; after \
                 melting its strain resets to 0) and the film under an imposed strain ramp \
                 0 → {} → 0 at {} /s. Bottom: the imposed loops at every temperature against ε².\n\
                 See φ fall from {} (b₃/(2b) = {}) to 0 at ε = {} (ε₊ = {}) and jump back to {} \
                 (b₃/b = {}) only at ε = {} (ε₋ = {}); the loops shift with A while their widths \
                 stay at b₃²/(4ab) = {} (C11).",
                fmt::sig(h.imposed.film.a_coeff_pa, 3),
                fmt::sig(h.imposed.up.last().map_or(f64::NAN, |q| q.0), 3),
                fmt::trim(h.imposed.rate_per_s),
                fmt::sig(h.imposed.phi_before_fall, 3),
                fmt::sig(
                    h.imposed.film.params.cubic_pa / (2.0 * h.imposed.film.b_pa()),
                    3
                ),
                fmt::sig(h.melt_binary, 6),
                fmt::sig(ep, 6),
                fmt::sig(h.imposed.phi_after_jump, 3),
                fmt::sig(h.imposed.film.params.cubic_pa / h.imposed.film.b_pa(), 3),
                fmt::sig(h.imposed.solid_eps.unwrap_or(f64::NAN), 6),
                fmt::sig(em, 6),
                fmt::sig(w, 5)
            )
        },
    );
    Figure {
        file: "first_order_hysteresis.svg",
        title: "First-order film: the hysteresis loop (C11)".into(),
        caption,
        svg,
    }
}

fn force(run: &RunOutput, label: String, color: RGBColor) -> Series {
    let s = &run.series;
    let p = s
        .t_s
        .iter()
        .zip(&s.f_n)
        .map(|(&t, &f)| (t * 1e3, f * 1e3))
        .collect();
    Series::new(label, p, color)
}

fn pair_panel(title: &str, radial: &RunOutput, hom: &RunOutput) -> Panel {
    Panel::new(title, "time t, ms", "friction force F, mN")
        .with(vec![
            force(
                radial,
                format!("radial (MDR, N = {})", radial.info.derived.nodes),
                BLUE,
            ),
            force(hom, "homogeneous (one node)".into(), ORANGE).dashed(),
        ])
        .headroom(0.22)
        .legend(LegendAt::UpperLeft)
}

fn contrast_fig(runs: &Runs) -> Figure {
    let four = (|| {
        Ok::<_, String>((
            runs.get("fig2")?,
            runs.get("homogeneous")?,
            runs.get("fig2_first_order")?,
            runs.get("homogeneous_first_order")?,
        ))
    })();
    let svg = four.clone().and_then(|(r2, h2, r1, h1)| {
        render_svg(
            &[
                pair_panel("Second-order film (b₃ = 0): fig2 against homogeneous", r2, h2),
                pair_panel(
                    "First-order film (ε₊ = 1.3·εc): fig2_first_order against homogeneous_first_order",
                    r1,
                    h1,
                ),
            ],
            1,
            W,
            900,
        )
    });
    let caption = contrasts(runs).map_or_else(
        |e| format!("Not available: {e}"),
        |(s, f)| {
            format!(
                "F(t) of the radial MDR model (solid) and the one-node homogeneous model (dashed) \
                 at fig2's parameters, for the paper's second-order film (top) and the \
                 first-order film (bottom).\n\
                 See the two models part further for the first-order film: relative L2 \
                 difference of F(t) {} against {}, peak forces {} % apart against {} % (C12).",
                fmt::sig(f.rel_l2_f, 3),
                fmt::sig(s.rel_l2_f, 3),
                fmt::sig(100.0 * f.f_peak, 2),
                fmt::sig(100.0 * s.f_peak, 2)
            )
        },
    );
    Figure {
        file: "first_order_homogeneous_vs_radial.svg",
        title: "Radial vs homogeneous, second- and first-order film (C12)".into(),
        caption,
        svg,
    }
}

/// The first-order film's figures, in the order of the index.
pub fn all(runs: &Runs) -> Vec<Figure> {
    vec![hysteresis_fig(runs), contrast_fig(runs)]
}
