//! The one plotting layer: panels of lines, markers, slope guides, reference lines and filled
//! cells on linear or log axes, rendered with plotters' SVG backend into a grid. No fonts are
//! needed: SVG text is written as `<text>` and the viewer chooses the font.
//!
//! A figure is a list of [`Panel`]s drawn on `cols` columns by [`render_svg`].

mod draw;
pub mod svg_check;

use crate::palette::GREY;
use plotters::style::RGBColor;

pub use plotters::prelude::SeriesLabelPosition as LegendAt;

/// Axis scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// Linear axis.
    Linear,
    /// Logarithmic axis (only positive values are drawn).
    Log,
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// Solid line.
    Solid,
    /// Dashed line.
    Dashed,
    /// Markers only.
    Points,
    /// Thin dotted reference line.
    Reference,
}

/// Marker at each point of a series.
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

/// One series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text (empty: no legend entry).
    pub label: String,
    /// (x, y) points in the panel's units.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Line style.
    pub style: Style,
    /// Marker at each point (`Points` style without a marker draws circles).
    pub marker: Option<Marker>,
    /// Text next to each point (same order as `points`; empty: none).
    pub point_labels: Vec<String>,
}

impl Series {
    /// A solid line without markers.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self {
            label: label.into(),
            points,
            color,
            style: Style::Solid,
            marker: None,
            point_labels: Vec::new(),
        }
    }

    /// Sets the style.
    #[must_use]
    pub fn style(mut self, style: Style) -> Self {
        self.style = style;
        self
    }

    /// Dashed line.
    #[must_use]
    pub fn dashed(self) -> Self {
        self.style(Style::Dashed)
    }

    /// Markers only.
    #[must_use]
    pub fn points(self) -> Self {
        self.style(Style::Points)
    }

    /// Sets the marker.
    #[must_use]
    pub fn marker(mut self, m: Marker) -> Self {
        self.marker = Some(m);
        self
    }

    /// Text next to each point.
    #[must_use]
    pub fn labels(mut self, labels: Vec<String>) -> Self {
        self.point_labels = labels;
        self
    }
}

/// A slope guide y = c·x^(±order) through `anchor`, across the panel's x range (log–log).
#[derive(Debug, Clone, PartialEq)]
pub struct Guide {
    /// Order p of the guide.
    pub order: f64,
    /// Point the guide passes through.
    pub anchor: (f64, f64),
    /// y ∝ x^−p (falling, x = N) or y ∝ x^p (rising, x = Δt).
    pub falling: bool,
}

/// A filled rectangle in data coordinates (a map's cell).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// x extent.
    pub x: (f64, f64),
    /// y extent.
    pub y: (f64, f64),
    /// Fill colour.
    pub color: RGBColor,
}

/// A straight segment in data coordinates, drawn over the cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Start.
    pub from: (f64, f64),
    /// End.
    pub to: (f64, f64),
    /// Colour.
    pub color: RGBColor,
    /// Stroke width in pixels.
    pub width: u32,
}

/// Text at a point in data coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Note {
    /// Where.
    pub at: (f64, f64),
    /// What.
    pub text: String,
    /// Colour.
    pub color: RGBColor,
}

/// A continuous colour scale (the sequential palette from `lo` to `hi`) drawn as a bar
/// beside the chart, with ticks that suit its range: 1, 2, 5 per decade on a log scale, a
/// round step (1, 2, 2.5 or 5 × 10^k) with as many decimals as it needs on a linear one.
#[derive(Debug, Clone, PartialEq)]
pub struct ColorBar {
    /// Value at the bottom.
    pub lo: f64,
    /// Value at the top.
    pub hi: f64,
    /// Logarithmic colour (both ends > 0).
    pub log: bool,
    /// Title above the bar (quantity and unit).
    pub label: String,
}

impl ColorBar {
    /// A bar from `lo` to `hi`, logarithmic when both are positive and span more than a
    /// decade.
    pub fn new(lo: f64, hi: f64, label: impl Into<String>) -> Self {
        Self {
            lo,
            hi,
            log: lo > 0.0 && hi / lo > 10.0,
            label: label.into(),
        }
    }

    /// Where `v` falls on the bar, 0 … 1 (½ when the range is a single value).
    #[must_use]
    pub fn norm(&self, v: f64) -> f64 {
        if self.hi.partial_cmp(&self.lo) != Some(std::cmp::Ordering::Greater) {
            0.5
        } else if self.log {
            (v / self.lo).ln() / (self.hi / self.lo).ln()
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    /// The colour of `v`.
    #[must_use]
    pub fn color(&self, v: f64) -> RGBColor {
        crate::palette::sequential(self.norm(v).clamp(0.0, 1.0))
    }

    /// The tick values and their texts.
    #[must_use]
    pub fn ticks(&self) -> Vec<(f64, String)> {
        let (lo, hi) = (self.lo, self.hi);
        if !(lo.is_finite() && hi.is_finite()) {
            return Vec::new();
        }
        if hi <= lo {
            return vec![(lo, crate::fmt::sig(lo, 4))];
        }
        if self.log {
            let mut t = draw::decade_ticks(lo, hi);
            if t.len() > 9 {
                t.retain(|v| (v.log10() - v.log10().round()).abs() < 1e-9);
            }
            if t.len() > 9 {
                let stride = t.len().div_ceil(9);
                t = t.into_iter().step_by(stride).collect();
            }
            if t.len() < 2 {
                t = vec![lo, hi];
            }
            return t.into_iter().map(|v| (v, crate::fmt::tick(v))).collect();
        }
        let (step, decimals) = round_step((hi - lo) / 5.0);
        let big = lo.abs().max(hi.abs());
        let scientific = !(1e-3..1e5).contains(&big);
        // The ends count as on a tick within rounding (0.35 / 0.05 = 6.999…).
        let first = (lo / step - 1e-9).ceil() as i64;
        let last = (hi / step + 1e-9).floor() as i64;
        (first..=last)
            .map(|k| k as f64 * step)
            .map(|v| {
                let text = if scientific {
                    crate::fmt::sig(v, significant(v, step))
                } else {
                    format!("{v:.decimals$}")
                };
                (v, text)
            })
            .collect()
    }
}

/// A round step near `raw` (1, 2, 2.5 or 5 × 10^k) and the decimals it needs.
fn round_step(raw: f64) -> (f64, usize) {
    let e = raw.log10().floor();
    let base = 10f64.powf(e);
    let m = raw / base;
    let (mantissa, extra) = if m < 1.5 {
        (1.0, 0)
    } else if m < 2.2 {
        (2.0, 0)
    } else if m < 3.5 {
        (2.5, 1)
    } else if m < 7.5 {
        (5.0, 0)
    } else {
        (10.0, 0)
    };
    let step = mantissa * base;
    let decimals = (-(step.log10().floor())).max(0.0) as usize + extra;
    (step, decimals)
}

/// Significant digits that tell multiples of `step` apart near `v`.
fn significant(v: f64, step: f64) -> usize {
    if v == 0.0 {
        return 1;
    }
    let digits = (v.abs().log10().floor() - step.log10().floor()) as i64 + 2;
    digits.clamp(1, 8) as usize
}

/// One chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// Title above the chart.
    pub title: String,
    /// x-axis description with unit.
    pub x_label: String,
    /// y-axis description with unit.
    pub y_label: String,
    /// x scale.
    pub x_scale: Scale,
    /// y scale.
    pub y_scale: Scale,
    /// Series.
    pub series: Vec<Series>,
    /// Slope guides (log–log panels).
    pub guides: Vec<Guide>,
    /// Horizontal reference lines (y, label).
    pub hlines: Vec<(f64, String)>,
    /// Vertical reference lines (x, label).
    pub vlines: Vec<(f64, String)>,
    /// Filled cells, drawn first.
    pub cells: Vec<Cell>,
    /// Each cell outlined in this colour, drawn with it (so later cells cover earlier
    /// outlines).
    pub cell_outline: Option<RGBColor>,
    /// Straight segments drawn over the cells (a regime boundary).
    pub segments: Vec<Segment>,
    /// Text notes.
    pub notes: Vec<Note>,
    /// Legend position.
    pub legend: LegendAt,
    /// x range (None: from the data).
    pub x_range: Option<(f64, f64)>,
    /// y range (None: from the data with padding).
    pub y_range: Option<(f64, f64)>,
    /// Space above the data as a fraction of the y span (linear y; room for the legend).
    pub headroom: f64,
    /// Explicit x ticks (log x; default 1, 2, 5 per decade).
    pub x_ticks: Option<Vec<f64>>,
    /// Legend in a strip right of the chart, where it cannot cover data.
    pub legend_outside: bool,
    /// Colour bar in the strip right of the chart (above the legend).
    pub colorbar: Option<ColorBar>,
}

impl Panel {
    /// An empty linear panel, legend at the upper left.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: Vec::new(),
            guides: Vec::new(),
            hlines: Vec::new(),
            vlines: Vec::new(),
            cells: Vec::new(),
            cell_outline: None,
            segments: Vec::new(),
            notes: Vec::new(),
            legend: LegendAt::UpperLeft,
            x_range: None,
            y_range: None,
            headroom: 0.06,
            x_ticks: None,
            legend_outside: false,
            colorbar: None,
        }
    }

    /// Puts the legend in a strip right of the chart.
    #[must_use]
    pub fn legend_outside(mut self) -> Self {
        self.legend_outside = true;
        self
    }

    /// Adds a colour bar (in the strip right of the chart).
    #[must_use]
    pub fn colorbar(mut self, bar: ColorBar) -> Self {
        self.colorbar = Some(bar);
        self
    }

    /// Adds series.
    #[must_use]
    pub fn with(mut self, series: Vec<Series>) -> Self {
        self.series.extend(series);
        self
    }

    /// Sets the scales.
    #[must_use]
    pub fn scales(mut self, x: Scale, y: Scale) -> Self {
        self.x_scale = x;
        self.y_scale = y;
        self
    }

    /// Log–log axes, legend at the upper right.
    #[must_use]
    pub fn log_log(self) -> Self {
        self.scales(Scale::Log, Scale::Log)
            .legend(LegendAt::UpperRight)
    }

    /// Sets the legend position.
    #[must_use]
    pub fn legend(mut self, at: LegendAt) -> Self {
        self.legend = at;
        self
    }

    /// Sets the space above the data, as a fraction of the y span.
    #[must_use]
    pub fn headroom(mut self, fraction: f64) -> Self {
        self.headroom = fraction;
        self
    }

    /// Sets the x range.
    #[must_use]
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// Sets the y range.
    #[must_use]
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// Sets explicit x ticks.
    #[must_use]
    pub fn x_ticks(mut self, ticks: Vec<f64>) -> Self {
        self.x_ticks = Some(ticks);
        self
    }

    /// Adds a horizontal reference line.
    #[must_use]
    pub fn hline(mut self, y: f64, label: impl Into<String>) -> Self {
        self.hlines.push((y, label.into()));
        self
    }

    /// Adds a vertical reference line.
    #[must_use]
    pub fn vline(mut self, x: f64, label: impl Into<String>) -> Self {
        self.vlines.push((x, label.into()));
        self
    }

    /// Adds a fan of slope guides of `orders` through half the smallest value at the finest
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

/// The points with finite coordinates, both > 0.
fn positive(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
        .collect()
}

/// Keeps at most ~2·`buckets` points: per x-bucket the points of least and greatest y, in
/// order, so sharp drops survive. Points must be sorted by x.
#[must_use]
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

/// The grey used for guides and reference lines.
pub const GUIDE: RGBColor = GREY;

/// Renders `panels` on a grid of `cols` columns, each panel `width` × `height` pixels, as
/// SVG text.
///
/// # Errors
/// A plotters drawing error, as text.
pub fn render_svg(
    panels: &[Panel],
    cols: usize,
    width: u32,
    height: u32,
) -> Result<String, String> {
    draw::render(panels, cols, width, height)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::palette::PALETTE;

    fn texts(bar: &ColorBar) -> Vec<String> {
        bar.ticks().into_iter().map(|t| t.1).collect()
    }

    #[test]
    fn colour_bar_ticks_follow_the_range() {
        // A narrow range near 1 gets four decimals, not five times "1.000".
        let bar = ColorBar::new(0.99957, 0.99999, "recovery");
        assert!(!bar.log);
        assert_eq!(texts(&bar), ["0.9996", "0.9997", "0.9998", "0.9999"]);
        // Decades get a log bar with 1, 2, 5 ticks.
        let bar = ColorBar::new(1e-6, 3e-4, "t [s]");
        assert!(bar.log);
        assert_eq!(
            texts(&bar),
            [
                "1e-6", "2e-6", "5e-6", "1e-5", "2e-5", "5e-5", "1e-4", "2e-4"
            ]
        );
        // Many decades: only powers of ten, then every k-th.
        assert_eq!(texts(&ColorBar::new(1e-9, 1e-1, "q")).len(), 9);
        assert_eq!(
            texts(&ColorBar::new(1e-20, 1e-1, "q")),
            ["1e-20", "1e-17", "1e-14", "1e-11", "1e-8", "1e-5", "0.01"]
        );
        // Plain ranges.
        assert_eq!(
            texts(&ColorBar::new(0.0, 10.0, "n")),
            ["0", "2", "4", "6", "8", "10"]
        );
        assert_eq!(
            texts(&ColorBar::new(0.1, 0.35, "f")),
            ["0.10", "0.15", "0.20", "0.25", "0.30", "0.35"]
        );
        // Large values in scientific form, still distinct.
        let t = texts(&ColorBar::new(1.21e6, 1.26e6, "F"));
        let mut d = t.clone();
        d.dedup();
        assert_eq!(t, d, "{t:?}");
        assert!(t.len() >= 3, "{t:?}");
        // Colours run from one end to the other.
        let bar = ColorBar::new(1.0, 1000.0, "x");
        assert!((bar.norm(1.0)).abs() < 1e-12 && (bar.norm(1000.0) - 1.0).abs() < 1e-12);
        assert!((bar.norm(10f64.powf(1.5)) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn outside_legends_and_colour_bars_render() {
        let pts: Vec<(f64, f64)> = (1..=5).map(|i| (f64::from(i), f64::from(i))).collect();
        let p = Panel::new("t", "x", "y")
            .with(vec![Series::new("a line", pts, PALETTE[0])])
            .legend_outside()
            .colorbar(ColorBar::new(0.99957, 0.99999, "recovery"));
        let svg = render_svg(&[p], 1, 700, 400).unwrap();
        assert!(svg.contains("a line") && svg.contains("0.9998") && svg.contains("recovery"));
    }

    #[test]
    fn every_scale_combination_renders_lines_markers_cells_and_guides() {
        let pts: Vec<(f64, f64)> = (1..=20)
            .map(|i| (f64::from(i), 1.0 / f64::from(i)))
            .collect();
        let mut panels = Vec::new();
        for (x, y) in [
            (Scale::Linear, Scale::Linear),
            (Scale::Log, Scale::Log),
            (Scale::Log, Scale::Linear),
            (Scale::Linear, Scale::Log),
        ] {
            let mut p = Panel::new("t", "x [m]", "y [s]")
                .scales(x, y)
                .with(vec![
                    Series::new("line", pts.clone(), PALETTE[0]),
                    Series::new("dashed", pts.clone(), PALETTE[1]).dashed(),
                    Series::new("marks", pts.clone(), PALETTE[2]).marker(Marker::Square),
                    Series::new("", pts.clone(), PALETTE[3]).points(),
                ])
                .hline(0.5, "half")
                .vline(5.0, "five");
            p.cells.push(Cell {
                x: (1.0, 2.0),
                y: (0.1, 0.2),
                color: PALETTE[4],
            });
            p.auto_guides(&[1.0], true);
            panels.push(p);
        }
        let svg = render_svg(&panels, 2, 400, 300).unwrap();
        assert!(svg.starts_with("<svg"));
        assert_eq!(
            svg.matches("\nline\n").count(),
            4,
            "one legend entry per panel"
        );
        assert!(svg.contains("order 1"));
    }
}
