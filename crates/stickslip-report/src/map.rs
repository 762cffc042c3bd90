//! Friction maps from a sweep's table: one panel of regimes as colours and one of a
//! continuous quantity, over the first two numeric axes (log axes where the axis is
//! log-spaced), failed and refused points marked; further axes (and word axes) give one pair
//! of panels per value. A refined map draws each point's cell at its level's size, finer
//! cells over coarser, and the regime boundary as a line (`stickslip_studies::sweep::refine::
//! geometry`).

use crate::palette;
use crate::plot::{Cell, ColorBar, Marker, Panel, Scale, Segment, Series};
use plotters::style::RGBColor;
use std::collections::{BTreeMap, HashMap};
use stickslip_run::summary::Regime;
use stickslip_studies::sweep::map::{
    ENERGY_COLUMN, MapJson, MapRow, STAMP_COLUMNS, SUMMARY_COLUMNS,
};
use stickslip_studies::sweep::record::PointStatus;
use stickslip_studies::sweep::refine::{self, geometry};
use stickslip_studies::sweep::{Axis, Sweep, value_text};

/// Quantities a map can show as colours: every numeric column of map.csv after the axes
/// (the summary's numbers, `wall_s`, the stamp's `n_slips` and median intervals, and the
/// energy dissipated per cycle); a
/// numeric axis may be shown too.
pub fn quantities() -> Vec<&'static str> {
    SUMMARY_COLUMNS
        .iter()
        .chain(STAMP_COLUMNS.iter())
        .chain(std::iter::once(&ENERGY_COLUMN))
        .map(|c| c.name)
        .filter(|&n| n != "regime" && n != "stamp_regime")
        .collect()
}

/// Pixel size of one map panel (room for the colour bar and legend beside the chart).
pub const PANEL_PX: (u32, u32) = (800, 500);

/// Cell edges around sorted axis values: midpoints (geometric on a log axis), the ends half
/// a step out.
fn edges(values: &[f64], log: bool) -> Vec<(f64, f64)> {
    let n = values.len();
    let mid = |a: f64, b: f64| if log { (a * b).sqrt() } else { 0.5 * (a + b) };
    let out_of = |a: f64, b: f64| if log { a * a / b } else { 2.0 * a - b };
    (0..n)
        .map(|i| {
            let lo = if i > 0 {
                mid(values[i - 1], values[i])
            } else if n > 1 {
                mid(out_of(values[0], values[1]), values[0])
            } else if log {
                values[0] / 1.5
            } else {
                values[0] - 0.5 * values[0].abs().max(1e-300)
            };
            let hi = if i + 1 < n {
                mid(values[i], values[i + 1])
            } else if n > 1 {
                mid(values[n - 1], out_of(values[n - 1], values[n - 2]))
            } else if log {
                values[0] * 1.5
            } else {
                values[0] + 0.5 * values[0].abs().max(1e-300)
            };
            (lo, hi)
        })
        .collect()
}

fn numeric(axis: &Axis) -> bool {
    axis.numbers().iter().all(|v| v.is_finite())
}

fn label(axis: &Axis) -> String {
    let unit = axis.unit();
    if unit.is_empty() || unit == "–" {
        axis.key.clone()
    } else {
        format!("{} [{unit}]", axis.key)
    }
}

/// The unit of a summary column.
#[must_use]
pub fn unit(column: &str) -> &'static str {
    SUMMARY_COLUMNS
        .iter()
        .chain(STAMP_COLUMNS.iter())
        .chain(std::iter::once(&ENERGY_COLUMN))
        .find(|c| c.name == column)
        .map_or("", |c| c.unit)
}

/// Which axes go where: x, optional y, then the facet axes.
struct Layout {
    x: usize,
    y: Option<usize>,
    facets: Vec<usize>,
}

fn layout(axes: &[Axis]) -> Result<Layout, String> {
    let numeric: Vec<usize> = (0..axes.len()).filter(|&i| numeric(&axes[i])).collect();
    let Some(&x) = numeric.first() else {
        return Err("a map needs at least one numeric axis".into());
    };
    let y = numeric.get(1).copied();
    let facets = (0..axes.len())
        .filter(|i| *i != x && Some(*i) != y)
        .collect();
    Ok(Layout { x, y, facets })
}

/// The panels of a map of `json` showing `quantity` (a summary column), and per facet value
/// the regime panel then the quantity panel. Panels carry no overlays; callers add their own
/// lines (critical speeds, diagonals) before rendering.
///
/// # Errors
/// When no axis is numeric or `quantity` is not a summary column.
pub fn panels(json: &MapJson, quantity: &str) -> Result<Vec<Panel>, String> {
    let axes = &json.sweep.axes;
    let axis_quantity = axes.iter().any(|a| a.key == quantity && numeric(a));
    if !quantities().contains(&quantity) && !axis_quantity {
        let numeric_axes: Vec<&str> = axes
            .iter()
            .filter(|a| numeric(a))
            .map(|a| a.key.as_str())
            .collect();
        return Err(format!(
            "quantity {quantity:?}; allowed: a numeric column of map.csv ({}) or a numeric \
             axis ({})",
            quantities().join(", "),
            numeric_axes.join(", ")
        ));
    }
    let lay = layout(axes)?;
    let sweep = &json.sweep;
    // The points without a row (a sweep still running or interrupted): drawn as empty cells.
    let present: std::collections::HashSet<usize> =
        json.table.rows.iter().map(|r| r.point).collect();
    let refined = Refined::of(sweep, &json.table.rows);
    let missing: Vec<Vec<String>> = if let Some(r) = &refined {
        r.missing
            .iter()
            .map(|&p| sweep.values(p).iter().map(value_text).collect())
            .collect()
    } else if sweep.points <= MAX_MISSING_DRAWN {
        (0..sweep.points)
            .filter(|p| !present.contains(p))
            .map(|p| sweep.values(p).iter().map(value_text).collect())
            .collect()
    } else {
        Vec::new()
    };
    let facet_values: Vec<Vec<String>> = {
        let mut seen: Vec<Vec<String>> = Vec::new();
        let all = json.table.rows.iter().map(|r| &r.values).chain(&missing);
        for values in all {
            let key: Vec<String> = lay.facets.iter().map(|&i| values[i].clone()).collect();
            if !seen.contains(&key) {
                seen.push(key);
            }
        }
        seen
    };
    // One colour scale for every facet, so their colours compare.
    let range = json
        .table
        .rows
        .iter()
        .map(|r| quantity_of(axes, r, quantity))
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let points = refined.as_ref().map_or(sweep.points, |r| r.points);
    let partial = if missing.is_empty() && json.table.rows.len() >= points {
        String::new()
    } else {
        format!(" — partial, {} of {} points", json.table.rows.len(), points)
    };
    let mut out = Vec::new();
    for facet in &facet_values {
        let rows: Vec<&MapRow> = json
            .table
            .rows
            .iter()
            .filter(|r| {
                lay.facets
                    .iter()
                    .zip(facet)
                    .all(|(&i, v)| r.values[i] == *v)
            })
            .collect();
        let in_facet =
            |values: &&Vec<String>| lay.facets.iter().zip(facet).all(|(&i, v)| values[i] == *v);
        let not_run: Vec<&Vec<String>> = missing.iter().filter(in_facet).collect();
        let suffix = if facet.is_empty() {
            partial.clone()
        } else {
            format!(
                " ({})",
                lay.facets
                    .iter()
                    .zip(facet)
                    .map(|(&i, v)| format!("{} = {v}", axes[i].key))
                    .collect::<Vec<_>>()
                    .join(", ")
            ) + &partial
        };
        let mut rows = rows;
        if refined.is_some() {
            // Coarse cells first: finer ones are drawn over them.
            rows.sort_by_key(|r| (r.level, r.point));
        }
        let geometry = Geometry {
            axes,
            lay: &lay,
            refined: refined.as_ref(),
            sweep,
        };
        let mut panels = pair(
            sweep.name.as_str(),
            &geometry,
            &rows,
            &not_run,
            quantity,
            &suffix,
            range,
        );
        // Checked points whose regime changed at a finer resolution, on the regime panel.
        if let (Some(spot), Some(regimes)) = (&json.spot_checks, panels.first_mut()) {
            let changed: Vec<(f64, f64)> = spot
                .checks
                .iter()
                .filter(|c| c.changed)
                .map(|c| c.values.iter().map(value_text).collect::<Vec<String>>())
                .filter(|v| in_facet(&v))
                .map(|v| coords(&lay, &v))
                .collect();
            if !changed.is_empty() {
                regimes.series.push(
                    Series::new(
                        format!(
                            "regime changed at 2N or tolerance/10 ({} of {} checked)",
                            spot.changed, spot.checked
                        ),
                        changed,
                        RGBColor(0, 0, 0),
                    )
                    .points()
                    .marker(Marker::Square),
                );
            }
        }
        out.extend(panels);
    }
    Ok(out)
}

/// A row's value of `quantity`: a map.csv column, or a numeric axis.
fn quantity_of(axes: &[Axis], row: &MapRow, quantity: &str) -> f64 {
    match axes.iter().position(|a| a.key == quantity) {
        Some(i) => row.values[i].parse().unwrap_or(f64::NAN),
        None => row.number(quantity),
    }
}

fn coords(lay: &Layout, values: &[String]) -> (f64, f64) {
    let num = |i: usize| values[i].parse::<f64>().unwrap_or(f64::NAN);
    (num(lay.x), lay.y.map_or(0.0, num))
}

/// A cell's x and y extent.
type Rect = ((f64, f64), (f64, f64));

/// What a refined map adds: each point's cell (at its level's size), the regime boundary, and
/// the points of the levels reached that have not run.
struct Refined {
    cells: HashMap<usize, Rect>,
    boundary: Vec<geometry::Segment>,
    missing: Vec<usize>,
    points: usize,
}

impl Refined {
    fn of(sweep: &Sweep, rows: &[MapRow]) -> Option<Self> {
        let r = sweep.refine.as_ref()?;
        let by_point: BTreeMap<usize, &MapRow> = rows.iter().map(|row| (row.point, row)).collect();
        let walk = refine::walk(sweep, r, |p| {
            Ok::<_, ()>(by_point.get(&p).map(|row| (*row).clone()))
        })
        .ok()?;
        // The cells of the rows and of the points not run yet.
        let mut all: Vec<usize> = rows.iter().map(|row| row.point).collect();
        all.extend(&walk.missing);
        let one_axis = sweep.axes.len() == 1;
        let cells = geometry::cells_of(sweep, r, &all)
            .into_iter()
            .map(|c| {
                let y = if one_axis {
                    (0.0, 1.0)
                } else {
                    (c.lo[1], c.hi[1])
                };
                (c.point, ((c.lo[0], c.hi[0]), y))
            })
            .collect();
        Some(Self {
            cells,
            boundary: geometry::boundary(sweep, r, rows),
            points: walk.points(),
            missing: walk.missing,
        })
    }

    /// The boundary as the plot's segments.
    fn segments(&self) -> Vec<Segment> {
        self.boundary
            .iter()
            .map(|s| Segment {
                from: s.from,
                to: s.to,
                color: BOUNDARY,
                width: 2,
            })
            .collect()
    }
}

/// Refined maps with more cells than this draw no cell outlines.
const MAX_OUTLINED: usize = 5000;

/// The colour of a refined map's cell outlines.
const OUTLINE: RGBColor = RGBColor(250, 250, 250);

/// The colour of a refined map's regime boundary.
const BOUNDARY: RGBColor = RGBColor(20, 20, 20);

/// Where a map's cells are.
struct Geometry<'a> {
    axes: &'a [Axis],
    lay: &'a Layout,
    refined: Option<&'a Refined>,
    sweep: &'a Sweep,
}

impl Geometry<'_> {
    /// The cell of the point with `values` (`point` its number).
    fn cell(&self, point: usize, values: &[String]) -> Rect {
        match self.refined.and_then(|r| r.cells.get(&point)) {
            Some(&c) => c,
            None => cell_of(self.axes, self.lay, values),
        }
    }

    /// The number of the point with `values` (a point not run has no row).
    fn point_of(&self, values: &[String]) -> usize {
        let idx: Vec<usize> = self
            .axes
            .iter()
            .zip(values)
            .map(|(a, v)| {
                a.values
                    .iter()
                    .position(|x| value_text(x) == *v)
                    .unwrap_or(0)
            })
            .collect();
        self.sweep.point(&idx)
    }
}

fn cell_of(axes: &[Axis], lay: &Layout, point: &[String]) -> ((f64, f64), (f64, f64)) {
    let find = |i: usize| {
        let a = &axes[i];
        let values: Vec<String> = a.values.iter().map(value_text).collect();
        let k = values.iter().position(|v| *v == point[i]).unwrap_or(0);
        edges(&a.numbers(), a.log)[k]
    };
    (find(lay.x), lay.y.map_or((0.0, 1.0), find))
}

/// Sweeps larger than this draw no cells for their missing points.
const MAX_MISSING_DRAWN: usize = 1_000_000;

/// The colour of a point that has not run.
const NOT_RUN: RGBColor = RGBColor(246, 246, 246);

fn pair(
    name: &str,
    geo: &Geometry<'_>,
    rows: &[&MapRow],
    not_run: &[&Vec<String>],
    quantity: &str,
    suffix: &str,
    (lo, hi): (f64, f64),
) -> Vec<Panel> {
    let (axes, lay) = (geo.axes, geo.lay);
    let xs = if axes[lay.x].log {
        Scale::Log
    } else {
        Scale::Linear
    };
    let x_label = label(&axes[lay.x]);
    let two_d = lay.y.is_some();
    let ys = lay.y.map_or(Scale::Linear, |y| {
        if axes[y].log {
            Scale::Log
        } else {
            Scale::Linear
        }
    });
    let y_label = lay.y.map_or_else(String::new, |y| label(&axes[y]));
    let failed = |status: PointStatus| -> Series {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.status == status)
            .map(|r| coords(lay, &r.values))
            .map(|(x, y)| (x, if two_d { y } else { 0.5 }))
            .collect();
        let n = pts.len();
        Series::new(
            if n > 0 {
                format!("{} ({n})", status.name())
            } else {
                String::new()
            },
            pts,
            if status == PointStatus::Failed {
                RGBColor(0, 0, 0)
            } else {
                RGBColor(180, 0, 0)
            },
        )
        .points()
        .marker(Marker::Cross)
    };
    // Points not run yet: pale cells with an open square each.
    let add_not_run = |panel: &mut Panel| {
        if not_run.is_empty() {
            return;
        }
        let mut centres = Vec::new();
        for values in not_run {
            let (x, y) = geo.cell(geo.point_of(values), values);
            panel.cells.push(Cell {
                x,
                y,
                color: NOT_RUN,
            });
            let (cx, cy) = coords(lay, values);
            centres.push((cx, if two_d { cy } else { 0.5 }));
        }
        panel.series.push(
            Series::new(
                format!("not run yet ({})", not_run.len()),
                centres,
                RGBColor(150, 150, 150),
            )
            .points()
            .marker(Marker::Square),
        );
    };
    // Regimes.
    let mut regime = Panel::new(
        &format!("{name}: regime{suffix}"),
        &x_label,
        if two_d { &y_label } else { "" },
    )
    .scales(xs, ys)
    .legend_outside();
    for r in rows {
        let (x, y) = geo.cell(r.point, &r.values);
        regime.cells.push(Cell {
            x,
            y,
            color: if r.status == PointStatus::Ok {
                palette::regime(r.summary.regime.name())
            } else {
                RGBColor(255, 255, 255)
            },
        });
    }
    for reg in Regime::ALL {
        let n = rows
            .iter()
            .filter(|r| r.status == PointStatus::Ok && r.summary.regime == reg)
            .count();
        if n > 0 {
            regime.series.push(
                Series::new(
                    format!("{} ({n})", reg.name()),
                    Vec::new(),
                    palette::regime(reg.name()),
                )
                .points(),
            );
        }
    }
    regime.series.push(failed(PointStatus::Failed));
    regime.series.push(failed(PointStatus::Refused));
    add_not_run(&mut regime);
    let boundary = |panel: &mut Panel| {
        if let Some(r) = geo.refined {
            panel.segments = r.segments();
            // Outlined cells, so the levels show where neighbours share a colour.
            if r.cells.len() <= MAX_OUTLINED {
                panel.cell_outline = Some(OUTLINE);
            }
            if !r.boundary.is_empty() {
                panel
                    .series
                    .push(Series::new("regime boundary", Vec::new(), BOUNDARY));
            }
        }
    };
    boundary(&mut regime);
    // The quantity.
    let values: Vec<f64> = rows
        .iter()
        .map(|r| quantity_of(axes, r, quantity))
        .collect();
    let u = match axes.iter().find(|a| a.key == quantity) {
        Some(a) => a.unit(),
        None => unit(quantity),
    };
    let u = if u == "–" { "" } else { u };
    let title = if u.is_empty() {
        quantity.to_string()
    } else {
        format!("{quantity} [{u}]")
    };
    let bar = ColorBar::new(lo, hi, title.clone());
    let log_colour = bar.log;
    let mut q = Panel::new(
        &format!("{name}: {title}{suffix}"),
        &x_label,
        if two_d { &y_label } else { &title },
    )
    .scales(xs, ys)
    .legend_outside();
    if two_d {
        for (r, &v) in rows.iter().zip(&values) {
            let (x, y) = geo.cell(r.point, &r.values);
            q.cells.push(Cell {
                x,
                y,
                color: if v.is_finite() {
                    bar.color(v)
                } else {
                    RGBColor(225, 225, 225)
                },
            });
        }
        if lo.is_finite() {
            q = q.colorbar(bar);
        }
        if values.iter().any(|v| !v.is_finite()) {
            q.series
                .push(Series::new("no value", Vec::new(), RGBColor(225, 225, 225)).points());
        }
    } else {
        // One axis: the quantity against it, coloured by regime.
        q = q.scales(
            xs,
            if log_colour {
                Scale::Log
            } else {
                Scale::Linear
            },
        );
        for reg in Regime::ALL {
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .zip(&values)
                .filter(|(r, v)| {
                    r.status == PointStatus::Ok && r.summary.regime == reg && v.is_finite()
                })
                .map(|(r, &v)| (coords(lay, &r.values).0, v))
                .collect();
            if !pts.is_empty() {
                q.series
                    .push(Series::new(reg.name(), pts, palette::regime(reg.name())).points());
            }
        }
    }
    q.series.push(failed(PointStatus::Failed));
    q.series.push(failed(PointStatus::Refused));
    if two_d {
        add_not_run(&mut q);
        boundary(&mut q);
    }
    if !two_d {
        regime = regime.y_range(0.0, 1.0);
    }
    vec![regime, q]
}

#[cfg(test)]
mod tests {
    use super::edges;

    #[test]
    fn cells_meet_halfway_on_linear_and_log_axes() {
        assert_eq!(
            edges(&[0.0, 1.0, 2.0], false),
            vec![(-0.5, 0.5), (0.5, 1.5), (1.5, 2.5)]
        );
        let e = edges(&[1.0, 10.0, 100.0], true);
        assert!((e[1].0 - 10f64.sqrt()).abs() < 1e-12 && (e[1].1 - 1000f64.sqrt()).abs() < 1e-9);
        assert!((e[0].0 - 10f64.powf(-0.5)).abs() < 1e-12);
    }
}
