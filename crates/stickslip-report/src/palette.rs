//! The one palette of the reports: Okabe–Ito (colour-blind safe) for categories, a viridis-like
//! ramp for continuous values, and the colours of the regimes
//! (docs/model.md#regimes-and-friction-maps).

use plotters::style::RGBColor;

/// Okabe–Ito colours, then a grey.
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

/// Grey for reference lines and guides.
pub const GREY: RGBColor = RGBColor(140, 140, 140);
/// Dark grey for annotations.
pub const DARK: RGBColor = RGBColor(60, 60, 60);

/// A sequential colour from dark blue (s = 0) through green to yellow (s = 1), viridis-like.
#[must_use]
pub fn sequential(s: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (220.0, 200.0, 30.0),
    ];
    let s = if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) };
    let s = s * (STOPS.len() - 1) as f64;
    let i = (s.floor() as usize).min(STOPS.len() - 2);
    let f = s - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |x: f64, y: f64| (x + f * (y - x)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Colour of a regime name (`sliding`, `no_melting`, `transient`, `stick_slip`, `partial`,
/// `smooth`; anything else grey): melting-free and sliding at the ends, stick–slip in blue,
/// the loss of recovery in warm colours.
#[must_use]
pub fn regime(name: &str) -> RGBColor {
    match name {
        "stick_slip" => PALETTE[0],
        "partial" => PALETTE[4],
        "smooth" => PALETTE[1],
        "sliding" => PALETTE[3],
        "transient" => PALETTE[5],
        "no_melting" => RGBColor(200, 200, 200),
        _ => PALETTE[7],
    }
}
