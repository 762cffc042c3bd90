//! The hard cases' figures: a stability chart (each case's runs by scheme and outcome), case
//! 3's F(t) at the large step against its Δt = 1e-8 s reference, and case 9's melting strain
//! per event (the large step, the adaptive run and the reference, with ε₊).

use super::Attempt;
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{LegendAt, Marker, Note, Panel, Series, decimate, render_svg};

/// A figure of the hard-case page.
#[derive(Debug, Clone)]
pub struct HardFigure {
    /// File name in `reports/`.
    pub file: &'static str,
    /// Title.
    pub title: &'static str,
    /// What to see.
    pub caption: String,
    /// The SVG, or why it could not be drawn.
    pub svg: Result<String, String>,
}

/// How one run ended, for the stability chart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Exit 0 with finite outputs.
    Ran,
    /// Exit 3 with run.json's failure record (a loud failure).
    FailedLoudly,
    /// Refused up front (exit 2: a bad scene, by design in some cases).
    Refused,
    /// Anything else (killed, unreadable, a failure without its record).
    Other,
}

/// The outcome of `a`.
#[must_use]
pub fn outcome_of(a: &Attempt) -> Outcome {
    match a.exit_code() {
        Some(0) if a.ok() => Outcome::Ran,
        Some(3) if a.failure().is_some() => Outcome::FailedLoudly,
        Some(2) => Outcome::Refused,
        _ => Outcome::Other,
    }
}

/// Whether a run used the paper's literal scheme (from its resolved scene).
fn is_literal(a: &Attempt) -> bool {
    a.scene
        .as_ref()
        .is_ok_and(|s| s.config.time.scheme == stickslip_core::config::Scheme::Literal)
}

/// The stability chart: one column per case, the literal runs above and the accurate below,
/// one marker per run by outcome (runs of a case spread across its column).
///
/// # Errors
/// A drawing error.
pub fn stability(cases: &[(usize, Vec<&Attempt>)]) -> Result<String, String> {
    let mut by: [Vec<(f64, f64)>; 4] = Default::default();
    for (number, attempts) in cases {
        for (row, literal) in [(1.0, true), (0.0, false)] {
            let runs: Vec<&&Attempt> = attempts
                .iter()
                .filter(|a| is_literal(a) == literal)
                .collect();
            let n = runs.len().max(1) as f64;
            for (j, a) in runs.iter().enumerate() {
                let x = *number as f64 + 0.6 * ((j as f64 + 0.5) / n - 0.5);
                let i = match outcome_of(a) {
                    Outcome::Ran => 0,
                    Outcome::FailedLoudly => 1,
                    Outcome::Refused => 2,
                    Outcome::Other => 3,
                };
                by[i].push((x, row));
            }
        }
    }
    let labels = [
        ("exit 0, finite", PALETTE[2], Marker::Circle),
        (
            "exit 3 with run.json's failure (loud)",
            PALETTE[1],
            Marker::Triangle,
        ),
        ("exit 2: refused up front", PALETTE[0], Marker::Square),
        ("other (silent or unexplained)", PALETTE[3], Marker::Cross),
    ];
    let series: Vec<Series> = labels
        .iter()
        .zip(by)
        .filter(|(_, pts)| !pts.is_empty())
        .map(|((label, color, marker), pts)| {
            Series::new(*label, pts, *color).points().marker(*marker)
        })
        .collect();
    let last = cases.iter().map(|c| c.0).max().unwrap_or(1) as f64;
    let mut p = Panel::new(
        "Hard cases: every run by scheme and outcome",
        "hard case",
        "scheme (1 literal, 0 accurate)",
    )
    .with(series)
    .legend_outside()
    .x_range(0.4, last + 0.6)
    .y_range(-0.5, 1.5);
    p.notes = vec![
        Note {
            at: (0.5, 1.3),
            text: "literal (the paper's scheme)".into(),
            color: PALETTE[7],
        },
        Note {
            at: (0.5, 0.3),
            text: "accurate".into(),
            color: PALETTE[7],
        },
    ];
    render_svg(&[p], 1, 960, 360)
}

/// Case 3: F(t) at Δt = 1e-6 s (accurate, fixed and adaptive) against the Δt = 1e-8 s
/// reference.
///
/// # Errors
/// A drawing error, or no reference to draw.
pub fn large_dt(
    reference: &Attempt,
    accurate: &Attempt,
    adaptive: &Attempt,
) -> Result<String, String> {
    let series = |a: &Attempt, label: &str, color, marker: Option<Marker>| {
        a.out().map(|o| {
            let pts: Vec<(f64, f64)> = o
                .series
                .t_s
                .iter()
                .zip(&o.series.f_n)
                .map(|(t, f)| (t * 1e6, f * 1e3))
                .collect();
            let s = Series::new(label, decimate(&pts, 1500), color);
            match marker {
                Some(m) => s.points().marker(m),
                None => s,
            }
        })
    };
    let reference = series(reference, "reference, Δt = 1e-8 s", PALETTE[7], None)
        .ok_or("the reference run left no outputs")?;
    let mut all = vec![reference];
    all.extend(series(
        accurate,
        "accurate, fixed Δt = 1e-6 s",
        PALETTE[1],
        Some(Marker::Circle),
    ));
    all.extend(series(
        adaptive,
        "accurate, adaptive from Δt = 1e-6 s",
        PALETTE[0],
        Some(Marker::Cross),
    ));
    let p = Panel::new(
        "Case 3: F(t) at a hundred times the paper's Δt",
        "t (µs)",
        "F (mN)",
    )
    .with(all)
    .legend_outside();
    render_svg(&[p], 1, 960, 400)
}

/// Case 9: the strain at which each event's first node melted, per event, for the large step,
/// the adaptive run and the reference (each a list of strains), with ε₊.
///
/// # Errors
/// A drawing error, or no reference strains.
pub fn first_order_fold(
    reference: &[f64],
    accurate: &[f64],
    adaptive: &[f64],
    eps_plus: f64,
) -> Result<String, String> {
    let pts = |strains: &[f64]| -> Vec<(f64, f64)> {
        strains
            .iter()
            .enumerate()
            .map(|(k, e)| ((k + 1) as f64, *e))
            .collect()
    };
    if reference.is_empty() {
        return Err("the reference run has no melting strains".into());
    }
    let p = Panel::new(
        "Case 9: melting strain per event, first-order film",
        "event",
        "strain at melting",
    )
    .with(vec![
        Series::new("reference, Δt = 1e-10 s", pts(reference), PALETTE[7])
            .points()
            .marker(Marker::Square),
        Series::new("accurate, fixed Δt = 1e-6 s", pts(accurate), PALETTE[1])
            .points()
            .marker(Marker::Circle),
        Series::new("accurate, adaptive", pts(adaptive), PALETTE[0])
            .points()
            .marker(Marker::Cross),
    ])
    .hline(eps_plus, "ε₊")
    .legend(LegendAt::UpperLeft)
    .legend_outside();
    render_svg(&[p], 1, 960, 400)
}
