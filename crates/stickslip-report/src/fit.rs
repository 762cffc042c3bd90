//! The figure of `stickslip fit` (fit.svg): the data and the fitted model over time with the
//! matched events' onsets and peaks marked, and below it the residual F_model − F_data at the
//! data's times against ±2σF; and [`write_outputs`], the fit's three files as both
//! `stickslip fit` and `stickslip.fit(…, out=DIR)` write them.

use crate::palette::PALETTE;
use crate::plot::{LegendAt, Marker, Panel, Series, decimate};
use std::path::Path;
use stickslip_studies::fit::FitOutcome;
use stickslip_studies::fit::report::FitReport;

/// Pixels of one panel.
pub const PANEL_PX: (u32, u32) = (900, 340);
/// Buckets of the decimated curves (each keeps its least and largest point).
const BUCKETS: usize = 1500;

/// The panels: data and model against time (in ms), events marked; the residuals.
#[must_use]
pub fn panels(report: &FitReport, t_s: &[f64], data_f_n: &[f64], model_f_n: &[f64]) -> Vec<Panel> {
    let ms = |t: f64| t * 1e3;
    let curve = |f: &[f64]| -> Vec<(f64, f64)> {
        decimate(
            &t_s.iter()
                .zip(f)
                .map(|(&t, &f)| (ms(t), f))
                .collect::<Vec<_>>(),
            BUCKETS,
        )
    };
    let events = |ev: &[stickslip_studies::fit::report::FitEvent]| -> Vec<(f64, f64)> {
        ev.iter().map(|e| (ms(e.t_onset_s), e.f_peak_n)).collect()
    };
    let title = format!(
        "{}: {} fit of {} parameter{}, χ² = {:.4} over {} residuals",
        report.scene,
        report.misfit_kind,
        report.parameters.len(),
        if report.parameters.len() == 1 {
            ""
        } else {
            "s"
        },
        report.misfit,
        report.residuals,
    );
    let mut series = vec![
        Series::new("data", curve(data_f_n), PALETTE[7]),
        Series::new("fitted model", curve(model_f_n), PALETTE[0]),
    ];
    if !report.data_events.is_empty() {
        series.push(
            Series::new(
                "data events (onset, peak)",
                events(&report.data_events),
                PALETTE[1],
            )
            .points()
            .marker(Marker::Square),
        );
        series.push(
            Series::new(
                "model events (onset, peak)",
                events(&report.model_events),
                PALETTE[2],
            )
            .points()
            .marker(Marker::Cross),
        );
    }
    let top = Panel::new(&title, "t (ms)", "F (N)")
        .with(series)
        .legend(LegendAt::UpperLeft)
        .headroom(0.25);
    let residual: Vec<f64> = model_f_n.iter().zip(data_f_n).map(|(m, d)| m - d).collect();
    let two_sigma = 2.0 * report.noise_n;
    let bottom = Panel::new(
        "residual: model − data at the data's times",
        "t (ms)",
        "F_model − F_data (N)",
    )
    .with(vec![Series::new("residual", curve(&residual), PALETTE[0])])
    .hline(two_sigma, "+2σF")
    .hline(-two_sigma, "−2σF");
    vec![top, bottom]
}

/// fit.svg's text.
///
/// # Errors
/// A drawing error, as text.
pub fn svg(
    report: &FitReport,
    t_s: &[f64],
    data_f_n: &[f64],
    model_f_n: &[f64],
) -> Result<String, String> {
    crate::plot::render_svg(
        &panels(report, t_s, data_f_n, model_f_n),
        1,
        PANEL_PX.0,
        PANEL_PX.1,
    )
}

/// Writes `dir/fit.json`, `dir/fit.svg` and `dir/fitted.toml` of `outcome` (creating `dir`),
/// each through the atomic writer.
///
/// # Errors
/// The figure cannot be drawn (`cannot draw fit.svg: …`) or a file cannot be written
/// (`cannot write DIR: …`).
pub fn write_outputs(dir: &Path, outcome: &FitOutcome) -> Result<(), String> {
    let r = &outcome.report;
    let svg = svg(
        r,
        &outcome.trace.t_s,
        &outcome.trace.f_n,
        &outcome.model_f_n,
    )
    .map_err(|e| format!("cannot draw fit.svg: {e}"))?;
    std::fs::create_dir_all(dir)
        .and_then(|()| r.write(dir))
        .and_then(|()| stickslip_run::atomic::write_atomic(dir, "fit.svg", svg.as_bytes()))
        .and_then(|()| {
            stickslip_run::atomic::write_atomic(
                dir,
                stickslip_run::layout::fit::FITTED_SCENE,
                outcome.fitted_toml.as_bytes(),
            )
        })
        .map_err(|e| format!("cannot write {}: {e}", dir.display()))
}
