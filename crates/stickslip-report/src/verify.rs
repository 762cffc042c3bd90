//! The figures of `stickslip verify`: for one quantity, its value at each level against the
//! node count and against the time stepping's refinement, with the extrapolated value and the
//! uncertainty band around the scene's own value.

use crate::palette::PALETTE;
use crate::plot::{Panel, Scale, Series};
use stickslip_studies::verify::{Axis, Quantity, VerifyReport};

/// Pixels of one panel.
pub const PANEL_PX: (u32, u32) = (520, 380);

/// The panels of quantity `q` of `report`: value against N (space) and against the tolerance
/// or Δt (time), each with the scene's own level, the extrapolated value and the band
/// value ± uncertainty. Empty for a discrete quantity.
#[must_use]
pub fn panels(report: &VerifyReport, q: &Quantity) -> Vec<Panel> {
    if q.text.is_some() {
        return Vec::new();
    }
    let mut out = Vec::new();
    for axis in [Axis::Space, Axis::Time] {
        // The scene's own run belongs to both axes.
        let points: Vec<(f64, f64)> = report
            .levels
            .iter()
            .enumerate()
            .filter(|(i, l)| *i == 0 || l.axis == axis)
            .filter_map(|(i, l)| {
                let x = match axis {
                    Axis::Space => l.nodes as f64,
                    Axis::Time => l.tolerance.or(l.dt_s)?,
                };
                Some((x, q.values.get(i).copied().flatten()?))
            })
            .collect();
        if points.len() < 2 {
            continue;
        }
        let x_label = match (axis, report.levels.first().and_then(|l| l.tolerance)) {
            (Axis::Space, _) => "nodes N",
            (Axis::Time, Some(_)) => "time.tolerance",
            (Axis::Time, None) => "time.dt (s)",
        };
        let title = format!(
            "{} against {}",
            q.name,
            if axis == Axis::Space { "N" } else { x_label }
        );
        let y_label = format!("{} ({})", q.name, q.unit);
        let band = [q.value - q.uncertainty, q.value + q.uncertainty];
        let x0 = points[0].0;
        let mut panel = Panel::new(&title, x_label, &y_label)
            .scales(Scale::Log, Scale::Linear)
            .with(vec![
                Series::new("levels", points, PALETTE[0]).points(),
                Series::new(
                    "± uncertainty at the scene's level",
                    vec![(x0, band[0]), (x0, band[1])],
                    PALETTE[1],
                ),
            ]);
        if let Some(e) = q.extrapolated {
            panel = panel.hline(e, "extrapolated");
        }
        out.push(panel);
    }
    out
}

/// The SVG of quantity `q` (its panels side by side), or `None` for a discrete quantity.
///
/// # Errors
/// A drawing error, as text.
pub fn svg(report: &VerifyReport, q: &Quantity) -> Result<Option<String>, String> {
    let panels = panels(report, q);
    if panels.is_empty() {
        return Ok(None);
    }
    crate::plot::render_svg(&panels, panels.len(), PANEL_PX.0, PANEL_PX.1).map(Some)
}
