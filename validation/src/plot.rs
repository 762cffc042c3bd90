//! A small line-chart layer over plotters' SVG backend: panels of solid, dashed and point
//! series with labelled axes and a legend. No fonts are needed: SVG text is written as
//! `<text>` and the viewer chooses the font.

use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// Solid line.
    Solid,
    /// Dashed line.
    Dashed,
    /// Filled circles.
    Points,
    /// Thin dotted reference line (no legend entry unless labelled).
    Reference,
}

/// One series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Legend text (empty: no legend entry).
    pub label: String,
    /// (x, y) points in the panel's units.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Drawing style.
    pub style: Style,
}

impl Line {
    /// A series.
    pub fn new(label: &str, points: Vec<(f64, f64)>, color: RGBColor, style: Style) -> Self {
        Self {
            label: label.to_string(),
            points,
            color,
            style,
        }
    }
}

/// Where the legend goes.
pub type LegendAt = SeriesLabelPosition;

/// One chart.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Title above the chart.
    pub title: String,
    /// x-axis description with unit.
    pub x_label: String,
    /// y-axis description with unit.
    pub y_label: String,
    /// The series.
    pub lines: Vec<Line>,
    /// x range (None: from the data).
    pub x_range: Option<(f64, f64)>,
    /// y range (None: from the data, with 5 % headroom).
    pub y_range: Option<(f64, f64)>,
    /// Legend position.
    pub legend: LegendAt,
    /// Space above the data as a fraction of the data's y span (room for the legend).
    pub headroom: f64,
}

impl Panel {
    /// A panel with automatic ranges and the legend at the upper left.
    pub fn new(title: &str, x_label: &str, y_label: &str, lines: Vec<Line>) -> Self {
        Self {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            lines,
            x_range: None,
            y_range: None,
            legend: SeriesLabelPosition::UpperLeft,
            headroom: 0.06,
        }
    }

    /// Sets the space above the data, as a fraction of the y span.
    pub fn headroom(mut self, fraction: f64) -> Self {
        self.headroom = fraction;
        self
    }

    /// Sets the legend position.
    pub fn legend(mut self, at: LegendAt) -> Self {
        self.legend = at;
        self
    }

    /// Sets the x range.
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// Sets the y range.
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
}

/// Colour-blind-safe palette (Okabe–Ito).
pub const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
    RGBColor(0, 0, 0),
];

/// A sequential colour from dark blue (s = 0) through green to yellow (s = 1), viridis-like.
pub fn sequential(s: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (220.0, 200.0, 30.0),
    ];
    let s = s.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (s.floor() as usize).min(STOPS.len() - 2);
    let f = s - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |x: f64, y: f64| (x + f * (y - x)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Keeps at most ~2·`buckets` points: per x-bucket the points of least and greatest y, in
/// order, so sharp drops survive. Points must be sorted by x.
pub fn decimate(points: &[(f64, f64)], buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= 2 * buckets || points.len() < 3 {
        return points.to_vec();
    }
    let (x0, x1) = (points[0].0, points[points.len() - 1].0);
    let width = (x1 - x0) / buckets as f64;
    let mut out = Vec::with_capacity(2 * buckets + 2);
    let mut i = 0;
    while i < points.len() {
        let b = ((points[i].0 - x0) / width).floor();
        let mut j = i;
        let (mut lo, mut hi) = (i, i);
        while j < points.len() && ((points[j].0 - x0) / width).floor() == b {
            if points[j].1 < points[lo].1 {
                lo = j;
            }
            if points[j].1 > points[hi].1 {
                hi = j;
            }
            j += 1;
        }
        let (a, c) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        out.push(points[a]);
        if c != a {
            out.push(points[c]);
        }
        i = j;
    }
    out
}

fn data_range(panel: &Panel) -> ((f64, f64), (f64, f64)) {
    let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
    let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
    for l in &panel.lines {
        for &(x, y) in &l.points {
            if x.is_finite() && y.is_finite() {
                xr = (xr.0.min(x), xr.1.max(x));
                yr = (yr.0.min(y), yr.1.max(y));
            }
        }
    }
    if !xr.0.is_finite() {
        xr = (0.0, 1.0);
    }
    if !yr.0.is_finite() {
        yr = (0.0, 1.0);
    }
    let xr = panel.x_range.unwrap_or(xr);
    let yr = panel.y_range.unwrap_or_else(|| {
        let pad = 0.06 * (yr.1 - yr.0).max(1e-300);
        let lo = if yr.0 >= 0.0 && yr.0 < 0.3 * (yr.1 - yr.0) {
            0.0
        } else {
            yr.0 - pad
        };
        (lo, yr.1 + panel.headroom * (yr.1 - yr.0).max(1e-300))
    });
    let fix = |(a, b): (f64, f64)| if b > a { (a, b) } else { (a - 0.5, a + 0.5) };
    (fix(xr), fix(yr))
}

fn tick_decimals(lo: f64, hi: f64) -> usize {
    let step = (hi - lo) / 8.0;
    if step <= 0.0 || !step.is_finite() {
        return 2;
    }
    (-step.log10().floor()).max(0.0) as usize
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = data_range(panel);
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("{e:?}");
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 22))
        .margin(14)
        .margin_right(28)
        .x_label_area_size(52)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    let (dx, dy) = (tick_decimals(x0, x1), tick_decimals(y0, y1));
    let fx = move |v: &f64| format!("{v:.dx$}");
    let fy = move |v: &f64| format!("{v:.dy$}");
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 15))
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(e)?;
    let mut any_label = false;
    for line in &panel.lines {
        let pts = decimate(&line.points, 1500);
        let color = line.color;
        let anno = match line.style {
            Style::Solid => chart
                .draw_series(LineSeries::new(pts, color.stroke_width(2)))
                .map_err(e)?,
            Style::Dashed => chart
                .draw_series(DashedLineSeries::new(pts, 9, 6, color.stroke_width(2)))
                .map_err(e)?,
            Style::Reference => chart
                .draw_series(DashedLineSeries::new(pts, 4, 4, color.stroke_width(1)))
                .map_err(e)?,
            Style::Points => chart
                .draw_series(pts.into_iter().map(|p| Circle::new(p, 4, color.filled())))
                .map_err(e)?,
        };
        if !line.label.is_empty() {
            any_label = true;
            let style = line.style;
            anno.label(line.label.as_str()).legend(
                move |(x, y)| -> DynElement<'static, DB, (i32, i32)> {
                    match style {
                        Style::Solid => {
                            PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
                                .into_dyn()
                        }
                        Style::Dashed | Style::Reference => DashedPathElement::new(
                            vec![(x, y), (x + 24, y)],
                            6,
                            4,
                            color.stroke_width(2),
                        )
                        .into_dyn(),
                        Style::Points => Circle::new((x + 12, y), 4, color.filled()).into_dyn(),
                    }
                },
            );
        }
    }
    if any_label {
        chart
            .configure_series_labels()
            .position(panel.legend.clone())
            .background_style(WHITE.mix(0.88))
            .border_style(RGBColor(150, 150, 150))
            .label_font(("sans-serif", 15))
            .margin(10)
            .draw()
            .map_err(e)?;
    }
    Ok(())
}

/// Renders `panels` stacked vertically into an SVG document of `width` × (`panel_height` per
/// panel) pixels.
///
/// # Errors
/// A plotters drawing error, as text.
pub fn render_svg(panels: &[Panel], width: u32, panel_height: u32) -> Result<String, String> {
    let mut buf = String::new();
    {
        let height = panel_height * panels.len().max(1) as u32;
        let root = SVGBackend::with_string(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| format!("{e:?}"))?;
        let areas = root.split_evenly((panels.len().max(1), 1));
        for (area, panel) in areas.iter().zip(panels) {
            draw_panel(area, panel)?;
        }
        root.present().map_err(|e| format!("{e:?}"))?;
    }
    Ok(buf)
}
