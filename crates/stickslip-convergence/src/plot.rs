//! Log–log convergence charts with plotters' SVG backend (no fonts needed: text is `<text>`).
//!
//! A figure is a grid of [`Panel`]s; each panel holds [`Series`] (line with markers, solid or
//! dashed) and optional slope guides (thin dotted lines of a given order through an anchor).

use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// Okabe–Ito colours (colour-blind safe).
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(120, 120, 120),
];

/// Marker of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// Filled circle.
    Circle,
    /// Open square.
    Square,
    /// Cross.
    Cross,
    /// Filled triangle.
    Triangle,
}

/// One line with markers.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points (x, y), both > 0 (others are dropped).
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Dashed instead of solid.
    pub dashed: bool,
    /// Marker at each point.
    pub marker: Marker,
    /// Optional text next to each point (same order as `points`; empty: none).
    pub point_labels: Vec<String>,
}

impl Series {
    /// A solid series with circles.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self {
            label: label.into(),
            points,
            color,
            dashed: false,
            marker: Marker::Circle,
            point_labels: Vec::new(),
        }
    }

    /// Text next to each point.
    pub fn labels(mut self, labels: Vec<String>) -> Self {
        self.point_labels = labels;
        self
    }

    /// Dashed line.
    pub fn dashed(mut self) -> Self {
        self.dashed = true;
        self
    }

    /// Sets the marker.
    pub fn marker(mut self, m: Marker) -> Self {
        self.marker = m;
        self
    }
}

/// A slope guide y = c·x^(±order) through `anchor`, drawn across the panel's x range.
#[derive(Debug, Clone, PartialEq)]
pub struct Guide {
    /// Order p of the guide.
    pub order: f64,
    /// Point the guide passes through.
    pub anchor: (f64, f64),
    /// Error falls with x (x = N: y ∝ x^−p) or rises with x (x = Δt: y ∝ x^p).
    pub falling: bool,
}

/// One log–log chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// Title.
    pub title: String,
    /// x-axis description.
    pub x_label: String,
    /// y-axis description.
    pub y_label: String,
    /// Series.
    pub series: Vec<Series>,
    /// Slope guides.
    pub guides: Vec<Guide>,
    /// Horizontal reference lines (y, label), e.g. a tolerance.
    pub hlines: Vec<(f64, String)>,
    /// Where the legend goes.
    pub legend: SeriesLabelPosition,
    /// Explicit x ticks (e.g. the refinement levels); default: 1, 2, 5 per decade.
    pub x_ticks: Option<Vec<f64>>,
}

impl Panel {
    /// An empty panel.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            guides: Vec::new(),
            hlines: Vec::new(),
            legend: SeriesLabelPosition::UpperRight,
            x_ticks: None,
        }
    }

    /// Sets explicit x ticks.
    pub fn x_ticks(mut self, ticks: Vec<f64>) -> Self {
        self.x_ticks = Some(ticks);
        self
    }

    /// Sets the legend position.
    pub fn legend(mut self, at: SeriesLabelPosition) -> Self {
        self.legend = at;
        self
    }

    /// Adds a fan of slope guides of `orders` through half the smallest error at the finest
    /// resolution shown (largest x when `falling`, smallest x otherwise).
    pub fn auto_guides(&mut self, orders: &[f64], falling: bool) {
        let pts: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| positive(&s.points))
            .collect();
        let xs = pts.iter().map(|p| p.0);
        let x = if falling {
            xs.fold(f64::NEG_INFINITY, f64::max)
        } else {
            xs.fold(f64::INFINITY, f64::min)
        };
        let y = pts
            .iter()
            .filter(|p| (p.0 / x - 1.0).abs() < 1e-9)
            .map(|p| p.1)
            .fold(f64::INFINITY, f64::min);
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        for &order in orders {
            self.guides.push(Guide {
                order,
                anchor: (x, 0.5 * y),
                falling,
            });
        }
    }
}

fn positive(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
        .collect()
}

fn ranges(panel: &Panel) -> ((f64, f64), (f64, f64)) {
    let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
    let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
    for s in &panel.series {
        for (x, y) in positive(&s.points) {
            xr = (xr.0.min(x), xr.1.max(x));
            yr = (yr.0.min(y), yr.1.max(y));
        }
    }
    for (y, _) in &panel.hlines {
        if *y > 0.0 {
            yr = (yr.0.min(*y), yr.1.max(*y));
        }
    }
    if !xr.0.is_finite() {
        xr = (1.0, 10.0);
    }
    if !yr.0.is_finite() {
        yr = (1e-3, 1.0);
    }
    let pad = |(a, b): (f64, f64), f: f64| {
        let (a, b) = if b > a { (a, b) } else { (a / 2.0, a * 2.0) };
        let l = (b / a).ln() * f;
        (a * (-l).exp(), b * l.exp())
    };
    (pad(xr, 0.06), pad(yr, 0.12))
}

/// Tick label: integers for 1 ≤ v < 1e5, otherwise `2.5e-9` with at most three significant
/// digits.
fn tick_label(v: f64) -> String {
    if v <= 0.0 || !v.is_finite() {
        return String::new();
    }
    if (1.0..1e5).contains(&v) && (v - v.round()).abs() < 1e-6 * v {
        return format!("{v:.0}");
    }
    let e = v.log10().floor() as i32;
    let m = v / 10f64.powi(e);
    let m = format!("{m:.2}");
    let m = m.trim_end_matches('0').trim_end_matches('.');
    format!("{m}e{e}")
}

/// 1, 2, 5 × 10^k inside [lo, hi] (only 10^k when the range spans more than four decades).
fn decade_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
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

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("{e:?}");
    let ((x0, x1), (y0, y1)) = ranges(panel);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 19))
        .margin(12)
        .margin_right(24)
        .x_label_area_size(48)
        .y_label_area_size(74)
        .build_cartesian_2d(
            (x0..x1).log_scale().with_key_points(
                panel
                    .x_ticks
                    .clone()
                    .unwrap_or_else(|| decade_ticks(x0, x1)),
            ),
            (y0..y1).log_scale().with_key_points(decade_ticks(y0, y1)),
        )
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .axis_desc_style(("sans-serif", 16))
        .label_style(("sans-serif", 13))
        .x_label_formatter(&|v: &f64| tick_label(*v))
        .y_label_formatter(&|v: &f64| tick_label(*v))
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(228, 228, 228))
        .draw()
        .map_err(e)?;
    for g in &panel.guides {
        let sign = if g.falling { -1.0 } else { 1.0 };
        let (ax, ay) = g.anchor;
        let y = |x: f64| ay * (x / ax).powf(sign * g.order);
        let pts: Vec<(f64, f64)> = (0..=40)
            .map(|i| x0 * (x1 / x0).powf(f64::from(i) / 40.0))
            .map(|x| (x, y(x)))
            .filter(|&(_, v)| v >= y0 && v <= y1)
            .collect();
        if pts.len() >= 2 {
            let grey = RGBColor(140, 140, 140);
            chart
                .draw_series(DashedLineSeries::new(
                    pts.clone(),
                    3,
                    4,
                    grey.stroke_width(1),
                ))
                .map_err(e)?;
            let (lx, ly) = pts[pts.len() / 2];
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("order {}", trim(g.order)),
                    (lx, ly),
                    ("sans-serif", 13).into_font().color(&grey),
                )))
                .map_err(e)?;
        }
    }
    for (y, label) in &panel.hlines {
        let black = RGBColor(60, 60, 60);
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x0, *y), (x1, *y)],
                8,
                5,
                black.stroke_width(1),
            ))
            .map_err(e)?;
        chart
            .draw_series(std::iter::once(Text::new(
                label.clone(),
                (x0 * (x1 / x0).powf(0.02), *y * 1.08),
                ("sans-serif", 13).into_font().color(&black),
            )))
            .map_err(e)?;
    }
    for s in &panel.series {
        let pts = positive(&s.points);
        if pts.is_empty() {
            continue;
        }
        let color = s.color;
        let style = color.stroke_width(2);
        if s.dashed {
            chart
                .draw_series(DashedLineSeries::new(pts.clone(), 7, 5, style))
                .map_err(e)?;
        } else {
            chart
                .draw_series(LineSeries::new(pts.clone(), style))
                .map_err(e)?;
        }
        if !s.point_labels.is_empty() {
            let labelled: Vec<((f64, f64), String)> = s
                .points
                .iter()
                .zip(&s.point_labels)
                .filter(|((x, y), _)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
                .map(|(&p, l)| (p, l.clone()))
                .collect();
            chart
                .draw_series(labelled.into_iter().map(|(p, l)| {
                    EmptyElement::at(p)
                        + Text::new(l, (6, 4), ("sans-serif", 12).into_font().color(&color))
                }))
                .map_err(e)?;
        }
        let anno = match s.marker {
            Marker::Circle => chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(e)?,
            Marker::Square => chart
                .draw_series(pts.iter().map(|&p| {
                    EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], color.stroke_width(2))
                }))
                .map_err(e)?,
            Marker::Cross => chart
                .draw_series(pts.iter().map(|&p| Cross::new(p, 5, color.stroke_width(2))))
                .map_err(e)?,
            Marker::Triangle => chart
                .draw_series(
                    pts.iter()
                        .map(|&p| TriangleMarker::new(p, 5, color.filled())),
                )
                .map_err(e)?,
        };
        let dashed = s.dashed;
        anno.label(s.label.as_str())
            .legend(move |(x, y)| -> DynElement<'static, DB, (i32, i32)> {
                if dashed {
                    DashedPathElement::new(vec![(x, y), (x + 22, y)], 5, 3, color.stroke_width(2))
                        .into_dyn()
                } else {
                    PathElement::new(vec![(x, y), (x + 22, y)], color.stroke_width(2)).into_dyn()
                }
            });
    }
    if panel.series.iter().any(|s| !s.label.is_empty()) {
        chart
            .configure_series_labels()
            .position(panel.legend.clone())
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .label_font(("sans-serif", 13))
            .margin(8)
            .draw()
            .map_err(e)?;
    }
    Ok(())
}

fn trim(v: f64) -> String {
    if (v - v.round()).abs() < 1e-9 {
        format!("{v:.0}")
    } else {
        format!("{v}")
    }
}

/// Renders `panels` on a grid of `cols` columns, each panel `w` × `h` pixels, as SVG text.
///
/// # Errors
/// A plotters drawing error, as text.
pub fn render_svg(panels: &[Panel], cols: usize, w: u32, h: u32) -> Result<String, String> {
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (w * cols as u32, h * rows as u32))
            .into_drawing_area();
        root.fill(&WHITE).map_err(|e| format!("{e:?}"))?;
        let areas = root.split_evenly((rows, cols));
        for (area, panel) in areas.iter().zip(panels) {
            draw_panel(area, panel)?;
        }
        root.present().map_err(|e| format!("{e:?}"))?;
    }
    Ok(buf)
}
