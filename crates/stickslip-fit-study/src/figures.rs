//! The study's figures, drawn with the reporting kit's one plotting layer: each seed's 95 %
//! interval against the truth (coverage), the intervals' widths against the number of samples
//! on log–log axes with the n^−½ guide, and the single fits' data and model (the kit's `fit`
//! figure, as `stickslip fit` draws it).

use crate::measures;
use crate::record::{CoverageRun, SingleFit, WidthRun};
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{LegendAt, Marker, Panel, Segment, Series, render_svg};

/// Pixels of one panel of the study's own figures.
const PANEL: (u32, u32) = (620, 330);

/// The last part of a key.
fn short(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}

/// One panel per set and parameter: per seed the fitted value and its 95 % interval as
/// fitted/true − 1, the truth at 0; intervals missing the truth in a second colour. The axis
/// spans the fits that reach the true model's χ²; a fit that stops short of it and lies
/// beyond is drawn at the axis's edge with its own marker.
///
/// # Errors
/// A drawing error, as text.
pub fn coverage_svg(runs: &[CoverageRun]) -> Result<String, String> {
    let mut panels = Vec::new();
    for run in runs {
        for (key, truth) in &run.case.truth {
            let rel = |v: f64| v / truth - 1.0;
            // The axis: the reaching fits' values and intervals (every fit's when none reach).
            let reaching: Vec<_> = run
                .fits
                .iter()
                .filter(|f| measures::reached(std::slice::from_ref(*f)) == 1)
                .collect();
            let basis = if reaching.is_empty() {
                run.fits.iter().collect()
            } else {
                reaching
            };
            let (mut lo, mut hi) = (0.0f64, 0.0f64);
            for p in basis.iter().filter_map(|f| f.param(key)) {
                for v in [Some(p.value), p.lo95, p.hi95].into_iter().flatten() {
                    lo = lo.min(rel(v));
                    hi = hi.max(rel(v));
                }
            }
            let pad = 0.08 * (hi - lo).max(f64::MIN_POSITIVE);
            let (lo, hi) = (lo - pad, hi + pad);
            let clamp = |y: f64| y.clamp(lo, hi);
            let mut hits = Vec::new();
            let mut misses = Vec::new();
            let mut beyond = Vec::new();
            let mut ends = Vec::new();
            let mut segments = Vec::new();
            for f in &run.fits {
                let Some(p) = f.param(key) else { continue };
                let x = f.seed as f64;
                let hit = p.covers() == Some(true);
                let color = if hit { PALETTE[0] } else { PALETTE[3] };
                if let (Some(a), Some(b)) = (p.lo95, p.hi95) {
                    segments.push(Segment {
                        from: (x, clamp(rel(a))),
                        to: (x, clamp(rel(b))),
                        color,
                        width: 2,
                    });
                    ends.extend(
                        [rel(a), rel(b)]
                            .into_iter()
                            .filter(|y| (lo..=hi).contains(y))
                            .map(|y| (x, y)),
                    );
                }
                let y = rel(p.value);
                if !(lo..=hi).contains(&y) {
                    beyond.push((x, clamp(y)));
                } else if hit {
                    hits.push((x, y));
                } else {
                    misses.push((x, y));
                }
            }
            let c = measures::coverage(&run.fits, key);
            let mut panel = Panel::new(
                &format!(
                    "set {} ({}): {} — {} of {} judged intervals hold the truth",
                    run.case.id,
                    run.case.scene.trim_end_matches(".toml"),
                    short(key),
                    c.covered,
                    c.judged
                ),
                "noise seed",
                &format!("{} fitted/true − 1", short(key)),
            )
            .with(
                [
                    Series::new("fitted, 95 % interval holds the truth", hits, PALETTE[0])
                        .points()
                        .marker(Marker::Circle),
                    Series::new("fitted, interval misses the truth", misses, PALETTE[3])
                        .points()
                        .marker(Marker::Triangle),
                    Series::new(
                        "fitted beyond the axis (short of the truth's χ²)",
                        beyond,
                        PALETTE[5],
                    )
                    .points()
                    .marker(Marker::Square),
                    Series::new("", ends, PALETTE[7])
                        .points()
                        .marker(Marker::Cross),
                ]
                .into_iter()
                .filter(|s| !s.points.is_empty())
                .collect(),
            )
            .hline(0.0, "truth")
            .legend(LegendAt::UpperLeft)
            .y_range(lo, hi + 0.45 * (hi - lo));
            panel.segments = segments;
            panels.push(panel);
        }
    }
    render_svg(&panels, 2, PANEL.0, PANEL.1)
}

/// The standard normal's quantile at probability `p` (Acklam's rational approximation, relative
/// error below 1.2e-9: far below what 20 pulls resolve).
#[must_use]
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.024_25 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.024_25 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// One panel per set and parameter: the judged fits' pulls, sorted, against the standard
/// normal's quantiles at (i − ½)/n, with the line y = x.
///
/// # Errors
/// A drawing error, as text.
pub fn pulls_svg(runs: &[CoverageRun]) -> Result<String, String> {
    let mut panels = Vec::new();
    for run in runs {
        for (key, _) in &run.case.truth {
            let c = measures::coverage(&run.fits, key);
            let n = c.pulls.len();
            let points: Vec<(f64, f64)> = c
                .pulls
                .iter()
                .enumerate()
                .map(|(i, &y)| (normal_quantile((i as f64 + 0.5) / n as f64), y))
                .collect();
            let span = points
                .iter()
                .map(|(x, y)| x.abs().max(y.abs()))
                .fold(2.0f64, f64::max)
                * 1.1;
            panels.push(
                Panel::new(
                    &format!(
                        "set {}: {} — pull SD {}",
                        run.case.id,
                        short(key),
                        stickslip_report::fmt::sig(c.pull_sd, 2)
                    ),
                    "standard normal quantile",
                    "pull (fitted − true) / stderr",
                )
                .with(vec![
                    Series::new(format!("{n} judged fits"), points, PALETTE[0])
                        .points()
                        .marker(Marker::Circle),
                    Series::new("y = x", vec![(-span, -span), (span, span)], PALETTE[7]).dashed(),
                ])
                .legend(LegendAt::UpperLeft)
                .x_range(-span, span)
                .y_range(-span, span),
            );
        }
    }
    render_svg(&panels, 2, PANEL.0, PANEL.1)
}

/// Log–log panels, one per misfit: each parameter's median relative 95 % half-width against
/// the number of samples, with the n^−½ guide.
///
/// # Errors
/// A drawing error, as text.
pub fn width_svg(w: &WidthRun) -> Result<String, String> {
    let mut panels = Vec::new();
    for (kind, fits) in [("events", &w.events), ("trace", &w.trace)] {
        let series: Vec<Series> = w
            .case
            .truth
            .iter()
            .enumerate()
            .map(|(i, (key, _))| {
                let s = measures::scaling(fits, key, &w.levels);
                Series::new(
                    format!("{} (slope {:.2})", short(key), s.slope),
                    s.points,
                    PALETTE[i],
                )
                .marker(if i == 0 {
                    Marker::Circle
                } else {
                    Marker::Square
                })
            })
            .collect();
        let mut panel = Panel::new(
            &format!(
                "{kind} misfit: set {}'s trace sampled more densely",
                w.case.id
            ),
            "samples over the trace",
            "median 95 % half-width / value",
        )
        .with(series)
        .log_log()
        .x_ticks(w.levels.iter().map(|&n| n as f64).collect());
        panel.auto_guides(&[0.5], true);
        panels.push(panel);
    }
    render_svg(&panels, 2, PANEL.0, PANEL.1)
}

/// A single fit's figure: the kit's fit.svg from the record's thinned curves, over the part
/// of the window with the meltings (from a quarter of their span before the first onset; the
/// slow loading before it is a straight rise).
///
/// # Errors
/// A drawing error, as text.
pub fn single_svg(s: &SingleFit) -> Result<String, String> {
    let c = &s.curves;
    let end = c.t_s.last().copied().unwrap_or(0.0);
    let from = s.report.data_events.first().map_or(0.0, |e| {
        let t0 = e.t_onset_s;
        (t0 - 0.25 * (end - t0)).max(0.0)
    });
    let keep: Vec<usize> = (0..c.t_s.len()).filter(|&i| c.t_s[i] >= from).collect();
    let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    stickslip_report::fit::svg(
        &s.report,
        &pick(&c.t_s),
        &pick(&c.data_f_n),
        &pick(&c.model_f_n),
    )
}

#[cfg(test)]
mod tests {
    use super::normal_quantile;

    #[test]
    fn the_normal_quantile_is_the_inverse_of_the_normal_cdf() {
        assert!(normal_quantile(0.5).abs() < 1e-12);
        assert!((normal_quantile(0.975) - 1.959_963_985).abs() < 1e-8);
        assert!((normal_quantile(0.01) + 2.326_347_874).abs() < 1e-8);
        assert!((normal_quantile(0.99) - 2.326_347_874).abs() < 1e-8);
    }
}
