//! Drawing a [`Panel`] with plotters: ranges, axes and mesh, then cells, guides, reference
//! lines, series, notes and the legend, the same code for every combination of scales.

use super::{Marker, Panel, Scale, Style, decimate, positive};
use crate::fmt::{tick, trim};
use crate::palette::{DARK, GREY};
use plotters::coord::ranged1d::ValueFormatter;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

type Range2 = ((f64, f64), (f64, f64));

/// The data range of one axis over the panel's content.
fn extent(panel: &Panel, axis: usize, log: bool) -> (f64, f64) {
    let mut r = (f64::INFINITY, f64::NEG_INFINITY);
    let mut take = |v: f64| {
        if v.is_finite() && (!log || v > 0.0) {
            r = (r.0.min(v), r.1.max(v));
        }
    };
    for s in &panel.series {
        for &(x, y) in &s.points {
            let ok = x.is_finite() && y.is_finite();
            let pos = x > 0.0 && y > 0.0;
            let both_log = panel.x_scale == Scale::Log && panel.y_scale == Scale::Log;
            if ok && (!both_log || pos) {
                take(if axis == 0 { x } else { y });
            }
        }
    }
    for c in &panel.cells {
        let (a, b) = if axis == 0 { c.x } else { c.y };
        take(a);
        take(b);
    }
    if axis == 1 {
        for (y, _) in &panel.hlines {
            take(*y);
        }
    } else {
        for (x, _) in &panel.vlines {
            take(*x);
        }
    }
    r
}

fn ranges(panel: &Panel) -> Range2 {
    let xlog = panel.x_scale == Scale::Log;
    let ylog = panel.y_scale == Scale::Log;
    let mut xr = extent(panel, 0, xlog);
    let mut yr = extent(panel, 1, ylog);
    if !xr.0.is_finite() {
        xr = if xlog { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if !yr.0.is_finite() {
        yr = if ylog { (1e-3, 1.0) } else { (0.0, 1.0) };
    }
    let log_pad = |(a, b): (f64, f64), f: f64| {
        let (a, b) = if b > a { (a, b) } else { (a / 2.0, a * 2.0) };
        let l = (b / a).ln() * f;
        (a * (-l).exp(), b * l.exp())
    };
    let has_cells = !panel.cells.is_empty();
    let x = panel.x_range.unwrap_or(if xlog {
        if has_cells { xr } else { log_pad(xr, 0.06) }
    } else {
        xr
    });
    let y = panel.y_range.unwrap_or_else(|| {
        if ylog {
            if has_cells { yr } else { log_pad(yr, 0.12) }
        } else if has_cells {
            yr
        } else {
            let span = (yr.1 - yr.0).max(1e-300);
            let lo = if yr.0 >= 0.0 && yr.0 < 0.3 * span {
                0.0
            } else {
                yr.0 - 0.06 * span
            };
            (lo, yr.1 + panel.headroom * span)
        }
    });
    let fix = |(a, b): (f64, f64)| if b > a { (a, b) } else { (a - 0.5, a + 0.5) };
    (fix(x), fix(y))
}

/// 1, 2, 5 × 10^k inside [lo, hi] (only 10^k when the range spans more than four decades).
pub(super) fn decade_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
    if !(lo > 0.0 && hi >= lo && hi.is_finite()) {
        return out;
    }
    let mantissas: &[f64] = if hi / lo > 1e4 {
        &[1.0]
    } else {
        &[1.0, 2.0, 5.0]
    };
    let mut e = lo.log10().floor() as i32 - 1;
    while 10f64.powi(e) <= hi {
        for &m in mantissas {
            let v = m * 10f64.powi(e);
            if v >= lo && v <= hi {
                out.push(v);
            }
        }
        e += 1;
    }
    out
}

fn linear_decimals(lo: f64, hi: f64) -> usize {
    let step = (hi - lo) / 8.0;
    if step <= 0.0 || !step.is_finite() {
        return 2;
    }
    (-step.log10().floor()).max(0.0) as usize
}

/// Tick text for a linear axis over [lo, hi].
fn linear_tick(v: f64, lo: f64, hi: f64) -> String {
    // A tick at zero computed as a rounding residue (−1.69e-21 on an axis of 1e-4) reads 0.
    let v = if v.abs() <= 1e-9 * (hi - lo).abs() {
        0.0
    } else {
        v
    };
    let big = lo.abs().max(hi.abs());
    if big >= 1e5 || (big < 1e-3 && big > 0.0) {
        tick(v)
    } else {
        let d = linear_decimals(lo, hi);
        format!("{v:.d$}")
    }
}

fn err<E: std::fmt::Debug>(e: E) -> String {
    format!("{e:?}")
}

/// Draws `panel` into `area`.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = ranges(panel);
    let strip = panel.legend_outside || panel.colorbar.is_some();
    let (w, _) = area.dim_in_pixel();
    let strip_px = strip_width(panel, w);
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(
            fit_title(
                &panel.title,
                w.saturating_sub(12 + if strip { 26 + strip_px } else { 26 }),
            ),
            (
                "sans-serif",
                caption_size(
                    &panel.title,
                    w.saturating_sub(12 + if strip { 26 + strip_px } else { 26 }),
                ),
            ),
        )
        .margin(12)
        .margin_right(if strip { 26 + strip_px } else { 26 })
        .x_label_area_size(50)
        .y_label_area_size(76);
    // Key points only matter on log axes (a linear axis may start at 0).
    let xt = match panel.x_scale {
        Scale::Log => panel
            .x_ticks
            .clone()
            .unwrap_or_else(|| decade_ticks(x0, x1)),
        Scale::Linear => Vec::new(),
    };
    let yt = match panel.y_scale {
        Scale::Log => decade_ticks(y0, y1),
        Scale::Linear => Vec::new(),
    };
    let drawn = match (panel.x_scale, panel.y_scale) {
        (Scale::Linear, Scale::Linear) => fill(
            builder.build_cartesian_2d(x0..x1, y0..y1).map_err(err)?,
            panel,
        ),
        (Scale::Log, Scale::Log) => fill(
            builder
                .build_cartesian_2d(
                    (x0..x1).log_scale().with_key_points(xt),
                    (y0..y1).log_scale().with_key_points(yt),
                )
                .map_err(err)?,
            panel,
        ),
        (Scale::Log, Scale::Linear) => fill(
            builder
                .build_cartesian_2d((x0..x1).log_scale().with_key_points(xt), y0..y1)
                .map_err(err)?,
            panel,
        ),
        (Scale::Linear, Scale::Log) => fill(
            builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale().with_key_points(yt))
                .map_err(err)?,
            panel,
        ),
    };
    drawn?;
    if strip {
        side_strip(area, panel, strip_px)?;
    }
    Ok(())
}

/// A point label: its point, its text and its offset in pixels.
type PlacedLabel = ((f64, f64), String, (i32, i32));

/// Least width of the strip right of a chart that holds its colour bar and legend, px.
const STRIP_PX: u32 = 170;

/// A generous estimate of a sans-serif text's width, px: 0.55 em per character (no fonts are
/// loaded, so the width is not measured; the average sans-serif glyph is about 0.5 em).
#[must_use]
pub(crate) fn text_width_px(text: &str, size_px: f64) -> f64 {
    0.55 * size_px * text.chars().count() as f64
}

/// The strip's width: wide enough for the longest legend label (swatch and gap: 38 px) and
/// the colour bar's ticks, at most half the panel.
fn strip_width(panel: &Panel, panel_px: u32) -> u32 {
    let longest = if panel.legend_outside {
        panel
            .series
            .iter()
            .filter(|s| !s.label.is_empty())
            .map(|s| text_width_px(&s.label, 13.0) + 38.0)
            .fold(0.0, f64::max)
    } else {
        0.0
    };
    let bar = panel
        .colorbar
        .as_ref()
        .map_or(0.0, |b| text_width_px(&b.label, 13.0) + 8.0);
    let want = longest.max(bar).ceil() as u32;
    want.clamp(STRIP_PX, (panel_px / 2).max(STRIP_PX))
}

/// Smallest title font, px.
const CAPTION_MIN_PX: u32 = 10;

/// The title's font size: 20 px, smaller (down to [`CAPTION_MIN_PX`]) when a long title would
/// not fit the width it is centred on.
fn caption_size(title: &str, room_px: u32) -> u32 {
    let room = f64::from(room_px);
    let at_20 = text_width_px(title, 20.0);
    if at_20 <= room {
        20
    } else {
        ((20.0 * room / at_20).floor() as u32).max(CAPTION_MIN_PX)
    }
}

/// The title, shortened with an ellipsis when even the smallest font would not fit it.
fn fit_title(title: &str, room_px: u32) -> String {
    let max = (f64::from(room_px) / (0.55 * f64::from(CAPTION_MIN_PX))).floor() as usize;
    if title.chars().count() <= max {
        title.to_string()
    } else {
        let mut t: String = title.chars().take(max.saturating_sub(1)).collect();
        t.push('…');
        t
    }
}

/// `label` broken at spaces into lines of at most `max_chars` characters (a word longer
/// than that stays whole on its own line).
fn wrap(label: &str, max_chars: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in label.split(' ') {
        let len = line.chars().count();
        if len > 0 && len + 1 + word.chars().count() > max_chars {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    lines.push(line);
    lines
}

/// The strip right of the chart: the colour bar (if any) and below it the legend (if it is
/// outside), drawn in pixels so nothing covers the data.
fn side_strip<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
    strip_px: u32,
) -> Result<(), String> {
    let (w, h) = area.dim_in_pixel();
    let left = w as i32 - strip_px as i32 - 8;
    let font = ("sans-serif", 13).into_font();
    let mut y = 48;
    if let Some(bar) = &panel.colorbar {
        area.draw(&Text::new(bar.label.clone(), (left, y), font.clone()))
            .map_err(err)?;
        y += 20;
        let bar_h = ((h as f64) * 0.45) as i32;
        let steps = 64;
        for k in 0..steps {
            // Top is hi.
            let f_hi = 1.0 - f64::from(k) / f64::from(steps);
            let f_lo = 1.0 - f64::from(k + 1) / f64::from(steps);
            let y0 = y + (f64::from(bar_h) * (1.0 - f_hi)) as i32;
            let y1 = y + (f64::from(bar_h) * (1.0 - f_lo)).ceil() as i32;
            let colour = crate::palette::sequential(0.5 * (f_hi + f_lo));
            area.draw(&Rectangle::new(
                [(left, y0), (left + 18, y1)],
                colour.filled(),
            ))
            .map_err(err)?;
        }
        area.draw(&Rectangle::new(
            [(left, y), (left + 18, y + bar_h)],
            RGBColor(150, 150, 150).stroke_width(1),
        ))
        .map_err(err)?;
        for (v, text) in bar.ticks() {
            let f = bar.norm(v);
            if !(-1e-9..=1.0 + 1e-9).contains(&f) {
                continue;
            }
            let ty = y + (f64::from(bar_h) * (1.0 - f)).round() as i32;
            area.draw(&PathElement::new(
                vec![(left + 18, ty), (left + 23, ty)],
                DARK.stroke_width(1),
            ))
            .map_err(err)?;
            area.draw(&Text::new(text, (left + 27, ty - 7), font.clone()))
                .map_err(err)?;
        }
        y += bar_h + 22;
    }
    if panel.legend_outside {
        for s in panel.series.iter().filter(|s| !s.label.is_empty()) {
            let c = s.color;
            let mid = y + 7;
            let swatch: DynElement<'static, DB, (i32, i32)> = match (s.style, s.marker) {
                (Style::Dashed | Style::Reference, _) => DashedPathElement::new(
                    vec![(left, mid), (left + 24, mid)],
                    6,
                    4,
                    c.stroke_width(2),
                )
                .into_dyn(),
                (Style::Solid, None) => {
                    PathElement::new(vec![(left, mid), (left + 24, mid)], c.stroke_width(2))
                        .into_dyn()
                }
                (_, Some(Marker::Cross)) => {
                    Cross::new((left + 12, mid), 5, c.stroke_width(2)).into_dyn()
                }
                (_, Some(Marker::Triangle)) => {
                    TriangleMarker::new((left + 12, mid), 5, c.filled()).into_dyn()
                }
                (_, Some(Marker::Square)) => Rectangle::new(
                    [(left + 8, mid - 4), (left + 16, mid + 4)],
                    c.stroke_width(2),
                )
                .into_dyn(),
                _ => Rectangle::new([(left + 5, mid - 6), (left + 19, mid + 6)], c.filled())
                    .into_dyn(),
            };
            area.draw(&swatch).map_err(err)?;
            let max_chars = ((f64::from(strip_px) - 38.0) / (0.55 * 13.0)).floor() as usize;
            for (k, line) in wrap(&s.label, max_chars.max(8)).into_iter().enumerate() {
                if k > 0 {
                    y += 16;
                }
                area.draw(&Text::new(line, (left + 30, y), font.clone()))
                    .map_err(err)?;
            }
            y += 20;
        }
    }
    Ok(())
}

/// Everything inside the axes, for any pair of coordinate kinds.
fn fill<'a, DB, X, Y>(
    mut chart: ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel,
) -> Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let ((x0, x1), (y0, y1)) = ranges(panel);
    let xlog = panel.x_scale == Scale::Log;
    let ylog = panel.y_scale == Scale::Log;
    let fx = move |v: &f64| {
        if xlog {
            tick(*v)
        } else {
            linear_tick(*v, x0, x1)
        }
    };
    let fy = move |v: &f64| {
        if ylog {
            tick(*v)
        } else {
            linear_tick(*v, y0, y1)
        }
    };
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .axis_desc_style(("sans-serif", 17))
        .label_style(("sans-serif", 14))
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(220, 220, 220))
        .draw()
        .map_err(err)?;
    chart
        .draw_series(panel.cells.iter().flat_map(|c| {
            let corners = [(c.x.0, c.y.0), (c.x.1, c.y.1)];
            std::iter::once(Rectangle::new(corners, c.color.filled())).chain(
                panel
                    .cell_outline
                    .map(|o| Rectangle::new(corners, o.stroke_width(1))),
            )
        }))
        .map_err(err)?;
    chart
        .draw_series(
            panel
                .segments
                .iter()
                .map(|s| PathElement::new(vec![s.from, s.to], s.color.stroke_width(s.width))),
        )
        .map_err(err)?;
    let at_x = |f: f64| {
        if xlog {
            x0 * (x1 / x0).powf(f)
        } else {
            x0 + f * (x1 - x0)
        }
    };
    for g in &panel.guides {
        let sign = if g.falling { -1.0 } else { 1.0 };
        let (ax, ay) = g.anchor;
        let pts: Vec<(f64, f64)> = (0..=40)
            .map(|i| at_x(f64::from(i) / 40.0))
            .map(|x| (x, ay * (x / ax).powf(sign * g.order)))
            .filter(|&(_, v)| v >= y0 && v <= y1)
            .collect();
        if pts.len() >= 2 {
            chart
                .draw_series(DashedLineSeries::new(
                    pts.clone(),
                    3,
                    4,
                    GREY.stroke_width(1),
                ))
                .map_err(err)?;
            let (lx, ly) = pts[pts.len() / 2];
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("order {}", trim(g.order)),
                    (lx, ly),
                    ("sans-serif", 13).into_font().color(&GREY),
                )))
                .map_err(err)?;
        }
    }
    for (y, label) in &panel.hlines {
        // A light band under the dashed line: a curve lying on the reference (Fig. 2b's final
        // profile on φ0) covers the dashes but not the band's edges.
        chart
            .draw_series(LineSeries::new(
                vec![(x0, *y), (x1, *y)],
                RGBColor(214, 214, 214).stroke_width(8),
            ))
            .map_err(err)?;
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x0, *y), (x1, *y)],
                8,
                5,
                DARK.stroke_width(1),
            ))
            .map_err(err)?;
        let ly = if ylog {
            *y * 1.08
        } else {
            *y + 0.02 * (y1 - y0)
        };
        chart
            .draw_series(std::iter::once(Text::new(
                label.clone(),
                (at_x(0.02), ly),
                ("sans-serif", 13).into_font().color(&DARK),
            )))
            .map_err(err)?;
    }
    for (x, label) in &panel.vlines {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(*x, y0), (*x, y1)],
                8,
                5,
                DARK.stroke_width(2),
            ))
            .map_err(err)?;
        // Near the bottom: legends sit in the upper corners.
        let ly = if ylog {
            y0 * (y1 / y0).powf(0.04)
        } else {
            y0 + 0.04 * (y1 - y0)
        };
        chart
            .draw_series(std::iter::once(Text::new(
                label.clone(),
                (*x, ly),
                ("sans-serif", 13).into_font().color(&DARK),
            )))
            .map_err(err)?;
    }
    let both_log = xlog && ylog;
    for s in &panel.series {
        let pts = if both_log {
            positive(&s.points)
        } else {
            s.points
                .iter()
                .copied()
                .filter(|(x, y)| {
                    x.is_finite() && y.is_finite() && (!xlog || *x > 0.0) && (!ylog || *y > 0.0)
                })
                .collect()
        };
        let pts = if s.style == Style::Points || s.marker.is_some() {
            pts
        } else {
            decimate(&pts, 1500)
        };
        let color = s.color;
        if !s.point_labels.is_empty() {
            let labelled: Vec<((f64, f64), String)> = s
                .points
                .iter()
                .zip(&s.point_labels)
                .filter(|((x, y), _)| pts.contains(&(*x, *y)))
                .map(|(&p, l)| (p, l.clone()))
                .collect();
            // A label that would run past the plotting area's right edge goes left of its
            // point, so that it stays on the canvas.
            let right = chart.plotting_area().get_pixel_range().0.end;
            let placed: Vec<PlacedLabel> = labelled
                .into_iter()
                .map(|(p, l)| {
                    let (px, _) = chart.backend_coord(&p);
                    let w = text_width_px(&l, 12.0).ceil() as i32;
                    let offset = if px + 6 + w > right {
                        (-6 - w, 4)
                    } else {
                        (6, 4)
                    };
                    (p, l, offset)
                })
                .collect();
            chart
                .draw_series(placed.into_iter().map(|(p, l, offset)| {
                    EmptyElement::at(p)
                        + Text::new(l, offset, ("sans-serif", 12).into_font().color(&color))
                }))
                .map_err(err)?;
        }
        let marker = match (s.marker, s.style) {
            (Some(m), _) => Some(m),
            (None, Style::Points) => Some(Marker::Circle),
            _ => None,
        };
        let line_anno = match s.style {
            Style::Solid => Some(
                chart
                    .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                    .map_err(err)?,
            ),
            Style::Dashed => Some(
                chart
                    .draw_series(DashedLineSeries::new(
                        pts.clone(),
                        9,
                        6,
                        color.stroke_width(2),
                    ))
                    .map_err(err)?,
            ),
            Style::Reference => Some(
                chart
                    .draw_series(DashedLineSeries::new(
                        pts.clone(),
                        4,
                        4,
                        color.stroke_width(1),
                    ))
                    .map_err(err)?,
            ),
            Style::Points => None,
        };
        // The legend entry hangs on the last series drawn: the markers if any, else the line.
        let anno = match (marker, line_anno) {
            (None, Some(a)) => a,
            (None, None) => continue,
            (Some(m), _) => match m {
                Marker::Circle => chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
                    .map_err(err)?,
                Marker::Square => chart
                    .draw_series(pts.iter().map(|&p| {
                        EmptyElement::at(p)
                            + Rectangle::new([(-4, -4), (4, 4)], color.stroke_width(2))
                    }))
                    .map_err(err)?,
                Marker::Cross => chart
                    .draw_series(pts.iter().map(|&p| Cross::new(p, 5, color.stroke_width(2))))
                    .map_err(err)?,
                Marker::Triangle => chart
                    .draw_series(
                        pts.iter()
                            .map(|&p| TriangleMarker::new(p, 5, color.filled())),
                    )
                    .map_err(err)?,
            },
        };
        if !s.label.is_empty() {
            let style = s.style;
            let has_line = style != Style::Points;
            anno.label(s.label.as_str()).legend(
                move |(x, y)| -> DynElement<'static, DB, (i32, i32)> {
                    match (has_line, style, marker) {
                        (true, Style::Dashed | Style::Reference, _) => DashedPathElement::new(
                            vec![(x, y), (x + 24, y)],
                            6,
                            4,
                            color.stroke_width(2),
                        )
                        .into_dyn(),
                        (true, _, _) => {
                            PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
                                .into_dyn()
                        }
                        (false, _, Some(Marker::Cross)) => {
                            Cross::new((x + 12, y), 5, color.stroke_width(2)).into_dyn()
                        }
                        (false, _, _) => {
                            Rectangle::new([(x + 5, y - 6), (x + 19, y + 6)], color.filled())
                                .into_dyn()
                        }
                    }
                },
            );
        }
    }
    for n in &panel.notes {
        chart
            .draw_series(std::iter::once(Text::new(
                n.text.clone(),
                n.at,
                ("sans-serif", 13).into_font().color(&n.color),
            )))
            .map_err(err)?;
    }
    if !panel.legend_outside && panel.series.iter().any(|s| !s.label.is_empty()) {
        chart
            .configure_series_labels()
            .position(panel.legend.clone())
            .background_style(WHITE.mix(0.88))
            .border_style(RGBColor(150, 150, 150))
            .label_font(("sans-serif", 14))
            .margin(9)
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// Renders `panels` on a grid of `cols` columns.
pub(super) fn render(
    panels: &[Panel],
    cols: usize,
    width: u32,
    height: u32,
) -> Result<String, String> {
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (width * cols as u32, height * rows as u32))
            .into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let areas = root.split_evenly((rows, cols));
        for (area, p) in areas.iter().zip(panels) {
            panel(area, p)?;
        }
        root.present().map_err(err)?;
    }
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use super::linear_tick;

    #[test]
    fn labels_wrap_at_spaces_and_titles_shorten() {
        assert_eq!(super::wrap("one two three", 7), ["one two", "three"]);
        assert_eq!(super::wrap("unbreakable", 4), ["unbreakable"]);
        assert_eq!(super::fit_title("abcdef", 1000), "abcdef");
        assert!(super::fit_title(&"x".repeat(500), 100).ends_with('…'));
    }

    #[test]
    fn a_rounding_residue_at_zero_reads_zero() {
        assert_eq!(linear_tick(-1.69e-21, -2e-4, 6e-4), "0");
        assert_eq!(linear_tick(2e-4, -2e-4, 6e-4), "2e-4");
        assert_eq!(linear_tick(0.5, 0.0, 1.0), "0.5");
    }
}
