//! Section 6 of the report, noisy fixed steps: the weak error of the mean first onset and of
//! its spread over seeds against a fine Δt, the observed weak order against theory, and
//! Figure 7 (`convergence_noise.svg`).

use super::{header, row};
use crate::Results;
use crate::noise::{NoiseStudy, WeakOrder};
use std::fmt::Write as _;
use stickslip_report::fmt::{opt, sig};
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{LegendAt, Marker, Panel, Series, render_svg};
use stickslip_report::stats::log_log_slope;

/// The band of weak orders theory allows here: ½ (first passage dominated by the noise) to 1
/// (the noise step's weak order; first passage carried through by the drift).
pub const THEORY_BAND: (f64, f64) = (0.5, 1.0);

/// Orders within this of the band count as agreeing with it (the seeds' statistical error).
pub const BAND_SLACK: f64 = 0.2;

/// How the measured orders compare with theory, in words.
pub(crate) fn verdict(w: &WeakOrder) -> String {
    let orders: Vec<f64> = w.slope.into_iter().chain(w.fit_p).collect();
    if w.slope.is_none() {
        return "an order that cannot be read: the weak errors stay within twice their \
                standard error at all but one level (the bias is below what these seeds \
                resolve)"
            .to_string();
    }
    let (lo, hi) = THEORY_BAND;
    let band = format!("{}–{} ±{}", sig(lo, 1), sig(hi, 1), sig(BAND_SLACK, 1));
    if orders
        .iter()
        .all(|&p| p >= lo - BAND_SLACK && p <= hi + BAND_SLACK)
    {
        format!("within the noise theory's {band}")
    } else {
        format!("**not** what the noise theory says ({band})")
    }
}

/// The levels where the mean's bias is resolved, as "Δt: bias vs deterministic" pairs, and
/// the largest |bias − deterministic| among them over 2·SE (≤ 1: the same within the seeds'
/// resolution).
fn deterministic_match(w: &WeakOrder) -> Option<(String, f64)> {
    let resolved: Vec<_> = w
        .errors
        .iter()
        .filter(|e| e.error_s.abs() > 2.0 * e.se_s)
        .filter_map(|e| Some((e, e.deterministic_s?)))
        .collect();
    if resolved.is_empty() {
        return None;
    }
    let text = resolved
        .iter()
        .map(|(e, d)| {
            format!(
                "{} ns against {} ns at Δt = {:e} s",
                sig(e.error_s * 1e9, 3),
                sig(d * 1e9, 3),
                e.dt_s
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    let worst = resolved
        .iter()
        .map(|(e, d)| (e.error_s - d).abs() / (2.0 * e.se_s))
        .fold(0.0_f64, f64::max);
    Some((text, worst))
}

/// The noise's own part of the mean's bias (weak error minus the deterministic error, same
/// standard error), its observed order over the levels where it exceeds 2·SE, in words.
fn noise_part(w: &WeakOrder) -> String {
    let parts: Vec<(f64, f64, f64)> = w
        .errors
        .iter()
        .filter_map(|e| Some((e.dt_s, e.error_s - e.deterministic_s?, e.se_s)))
        .collect();
    let resolved: Vec<(f64, f64)> = parts
        .iter()
        .filter(|(_, d, se)| d.abs() > 2.0 * se)
        .map(|&(h, d, _)| (h, d.abs()))
        .collect();
    let listed = parts
        .iter()
        .map(|(h, d, se)| format!("{} ± {} ns at {h:e} s", sig(d * 1e9, 2), sig(se * 1e9, 2)))
        .collect::<Vec<_>>()
        .join(", ");
    let order = (resolved.len() >= 2).then(|| log_log_slope(&resolved));
    format!(
        "The rest, the noise's own part of the bias (weak error minus deterministic error), \
         is {listed}: resolved (beyond 2·SE) at {} level(s), {}; where unresolved it is",
        resolved.len(),
        match order {
            Some(p) => format!(
                "observed order **{}** there, {}",
                super::p2(Some(p)),
                if p >= THEORY_BAND.0 - BAND_SLACK && p <= THEORY_BAND.1 + BAND_SLACK {
                    "within the noise theory's ½–1 (±0.2)"
                } else {
                    "**not** the noise theory's ½–1 (±0.2)"
                }
            ),
            None => "too few for an order".to_string(),
        }
    )
}

/// Writes "## 6. Noisy fixed steps: weak order" (nothing for studies without it).
pub(super) fn section(md: &mut String, r: &Results) {
    let Some(n) = &r.noise else {
        return;
    };
    let s = &n.settings;
    let _ = writeln!(md, "## 6. Noisy fixed steps: weak order\n");
    let _ = writeln!(
        md,
        "fig2 with gaussian noise (`lubricant.noise.kind = \"gaussian\"`, σ = {}, seeds 1 … {}), \
         N = {}, up to {} µs (just past the first onset), fixed steps Δt = {:?} s (fixed is \
         the default with gaussian noise) and a reference Δt = {:e} s with the same seeds. \
         Each step adds ξ ~ N(0, σ²Δt) per node after the exact Landau step, and a seed's \
         draws are different increments at different Δt, so levels are independent samples: \
         the weak errors (mean and spread of the first onset at Δt minus the reference's) \
         carry the standard errors of both. Two parts make the weak error: the deterministic \
         scheme's own Δt error of the onset (second order, §3; measured here too, by the same \
         run with the scene's floor noise instead of gaussian noise, column 'deterministic') \
         and the noise's. Theory for the noise part: the noise step is of weak order 1, and a \
         crossing of the threshold between step ends is seen at the next step end (or located \
         on the deterministic path), a first-passage bias of order 1 where the drift carries φ \
         through the threshold and ½ where the noise does — a weak order between ½ and 1.\n",
        sig(s.sigma, 2),
        s.seeds,
        s.nodes,
        sig(s.end_s * 1e6, 3),
        s.dts_s,
        s.reference_dt_s
    );
    header(
        md,
        &[
            "Δt (s)",
            "seeds with an onset",
            "mean first onset (µs)",
            "weak error of the mean (ns) ± SE",
            "deterministic error (ns)",
            "spread (ns)",
            "weak error of the spread (ns) ± SE",
            "onsets on a step end",
            "wall, all seeds (s)",
        ],
    );
    for (i, l) in n
        .levels
        .iter()
        .chain(std::iter::once(&n.reference))
        .enumerate()
    {
        let err = |w: &WeakOrder| {
            w.errors.get(i).map_or("(reference)".to_string(), |e| {
                format!("{} ± {}", sig(e.error_s * 1e9, 3), sig(e.se_s * 1e9, 2))
            })
        };
        row(
            md,
            &[
                format!("{:e}", l.dt_s),
                format!(
                    "{} / {}",
                    l.first_onsets_s.len() - l.missing(),
                    l.first_onsets_s.len()
                ),
                sig(l.mean_s * 1e6, 8),
                err(&n.mean),
                n.mean
                    .errors
                    .get(i)
                    .and_then(|e| e.deterministic_s)
                    .map_or("–".into(), |d| sig(d * 1e9, 3)),
                sig(l.std_s * 1e9, 3),
                err(&n.spread),
                format!("{:.0} %", 100.0 * l.at_step_end),
                sig(l.wall_s, 3),
            ],
        );
    }
    let _ = writeln!(md);
    for (name, w) in [("mean first onset", &n.mean), ("spread", &n.spread)] {
        let _ = writeln!(
            md,
            "- **Observed weak order of the {name}: {}** (log–log slope of |error| over the {} \
             level(s) where it exceeds twice its standard error); the weighted fit m(Δt) = m0 + \
             C·Δt^p over every level and the reference gives p = {} (limit m0 = {} µs). This is \
             {}.",
            super::p2(w.slope),
            w.slope_points,
            super::p2(w.fit_p),
            opt(w.fit_limit_s.map(|m| m * 1e6), 8),
            verdict(w)
        );
    }
    match deterministic_match(&n.mean) {
        Some((pairs, worst)) => {
            let _ = writeln!(
                md,
                "- Where the mean's bias is resolved it is {}: {pairs}; the largest difference \
                 is {} of twice its standard error. {} at most about {} ns (2·SE at the \
                 coarsest level).",
                if worst <= 1.0 {
                    "the deterministic error within the seeds' resolution"
                } else {
                    "**not** the deterministic error alone"
                },
                sig(worst, 2),
                if worst <= 1.0 {
                    format!(
                        "So the bias of the mean first onset is the deterministic scheme's own \
                         Δt error (its order, not the noise's), and the noise's own bias (first \
                         passage) stays below what {} seeds resolve at every level:",
                        s.seeds
                    )
                } else {
                    noise_part(&n.mean)
                },
                n.mean
                    .errors
                    .first()
                    .map_or("–".into(), |e| sig(2.0 * e.se_s * 1e9, 2))
            );
        }
        None => {
            let _ = writeln!(
                md,
                "- No level resolves a bias of the mean: weak errors below about {} ns (2·SE).",
                n.mean
                    .errors
                    .first()
                    .map_or("–".into(), |e| sig(2.0 * e.se_s * 1e9, 2))
            );
        }
    }
    let _ = writeln!(
        md,
        "\n![noise](convergence_noise.svg)\n\n*Figure 7. |weak error| of the mean first onset \
         and of its spread against Δt, log–log, with twice the standard error of each (dotted): \
         points below their dotted line are not resolved by {} seeds; dashed: the same runs' \
         first onset without gaussian noise against its own at the reference Δt. What to see: \
         {}*\n",
        s.seeds,
        caption(n)
    );
}

fn caption(n: &NoiseStudy) -> String {
    let first = n.mean.errors.first();
    let last = n.mean.errors.last();
    format!(
        "the mean onset's bias goes from {} ns at Δt = {} s to {} ns at {} s (order {}), the \
         spread's from {} ns to {} ns (order {}; – where the seeds resolve too few levels).",
        first.map_or("–".into(), |e| sig(e.error_s * 1e9, 2)),
        first.map_or("–".into(), |e| format!("{:e}", e.dt_s)),
        last.map_or("–".into(), |e| sig(e.error_s * 1e9, 2)),
        last.map_or("–".into(), |e| format!("{:e}", e.dt_s)),
        super::p2(n.mean.slope),
        n.spread
            .errors
            .first()
            .map_or("–".into(), |e| sig(e.error_s * 1e9, 2)),
        n.spread
            .errors
            .last()
            .map_or("–".into(), |e| sig(e.error_s * 1e9, 2)),
        super::p2(n.spread.slope),
    )
}

/// Figure 7.
pub(super) fn figure(n: &NoiseStudy) -> Result<String, String> {
    let mut p = Panel::new(
        "Gaussian noise, fixed steps: weak errors of the first onset",
        "Δt (s)",
        "|statistic(Δt) − statistic(ref.)| (ns)",
    )
    .log_log()
    .legend(LegendAt::LowerRight);
    for (ci, (name, w)) in [("mean", &n.mean), ("spread", &n.spread)]
        .into_iter()
        .enumerate()
    {
        let err: Vec<(f64, f64)> = w
            .errors
            .iter()
            .map(|e| (e.dt_s, e.error_s.abs() * 1e9))
            .filter(|&(_, e)| e > 0.0)
            .collect();
        let se: Vec<(f64, f64)> = w.errors.iter().map(|e| (e.dt_s, 2e9 * e.se_s)).collect();
        p.series
            .push(Series::new(name, err, PALETTE[ci]).marker(if ci == 0 {
                Marker::Circle
            } else {
                Marker::Square
            }));
        p.series.push(
            Series::new(format!("2·SE ({name})"), se, PALETTE[ci])
                .style(stickslip_report::plot::Style::Reference),
        );
    }
    let det: Vec<(f64, f64)> = n
        .mean
        .errors
        .iter()
        .filter_map(|e| Some((e.dt_s, e.deterministic_s?.abs() * 1e9)))
        .filter(|&(_, e)| e > 0.0)
        .collect();
    p.series.push(
        Series::new("deterministic onset (floor noise)", det, PALETTE[2])
            .dashed()
            .marker(Marker::Triangle),
    );
    p.auto_guides(&[1.0, 2.0], true);
    render_svg(&[p], 1, 640, 460)
}
