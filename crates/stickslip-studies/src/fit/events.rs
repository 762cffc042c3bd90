//! Events of a friction trace, found the same way in the data and in the model (both sampled
//! at the data's times, so that a model that reproduces the data finds the same events): a
//! zigzag of F with hysteresis `h` — an event begins at F's peak once F has fallen more than
//! `h` below it, and its drop ends at F's least value before F has risen by `h` again (an
//! event still falling at the trace's end ends at its least value so far).
//!
//! The zigzag runs on F smoothed by a centred moving average of [`SMOOTH`] samples (the same
//! filter on data and model). An event's onset is the time the smoothed F crosses half-way
//! between its largest and least smoothed values, linearly interpolated between the two
//! samples around it: the steepest part of the fall, where noise moves the time least, and
//! unlike a peak's sample it moves continuously with the model's parameters, which the
//! finite-difference Jacobians need.
//!
//! Peak and least values are not the extreme samples — the largest of noisy samples is biased
//! upwards by about the noise, the same way at every event, which no number of events averages
//! out — but the extremes of least-squares parabolas through the raw samples within
//! [`EXTREMUM_HALF`] of the data's extreme samples ([`Windows`]), linear in the data for a
//! given window. The model's peak and least of a matched event are measured over the same
//! windows moved by the difference of the onsets, on the model's own curve, so they too move
//! continuously, and a model equal to the data (shifted or not) gives the data's values
//! (docs/fit.md#events).

/// Samples of the centred moving average applied before events are found.
pub const SMOOTH: usize = 5;
/// Samples on each side of a peak or a least value through which a parabola is fitted.
pub const EXTREMUM_HALF: usize = 10;

/// The centred moving average of `f` over [`SMOOTH`] samples (fewer at the ends).
#[must_use]
pub fn smooth(f: &[f64]) -> Vec<f64> {
    let half = SMOOTH / 2;
    (0..f.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(f.len()));
            f[a..b].iter().sum::<f64>() / (b - a) as f64
        })
        .collect()
}

/// One event of a trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// Onset: when the smoothed F crosses half-way down its drop, s.
    pub t_onset_s: f64,
    /// The peak's sample time, s.
    pub t_peak_s: f64,
    /// F at the peak, N.
    pub f_peak_n: f64,
    /// F's fall from the peak to its least value before it rises again by h, N.
    pub drop_n: f64,
    /// |dF/dt| at the onset's crossing, N/s (the timing's sensitivity to noise in F).
    pub slope_n_per_s: f64,
    /// The onset's error from the sampling, s: (Δt/√12)·(q/D)², with q the largest fall of
    /// the raw F from one sample to the next within the drop D. A drop faster than the
    /// sampling (q ≈ D) is a step in the samples, whose smoothed crossing sits at a fixed
    /// place between the samples around the step: it moves with the drop's phase against the
    /// sample times, not with the drop, and is known to its interval (Δt/√12). A drop spread
    /// over n samples (q ≈ D/n) is resolved, its error falling as 1/n².
    pub interpolation_s: f64,
    /// The peak's error from the sampling, N: its parabola's change per sample of window
    /// shift (the larger of one sample either way) times the onset's sampling error in
    /// samples — the model's windows are placed by the onsets, so an onset off by a fraction
    /// of a sample moves them by as much.
    pub peak_resolution_n: f64,
    /// The least value's, likewise.
    pub least_resolution_n: f64,
    /// The peak's variance per unit variance of the samples' noise (1 for a sample; smaller
    /// for a parabola's extremum, which averages the window's samples).
    pub peak_variance: f64,
    /// The least value's, likewise.
    pub least_variance: f64,
}

/// The samples (first, last, inclusive) through which an event's peak and least parabolas
/// are fitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Windows {
    /// Around the peak.
    pub peak: (usize, usize),
    /// Around the least value.
    pub least: (usize, usize),
}

/// The events of `(t, f)` with hysteresis `h_n` (> 0), with their windows: the onset from
/// the smoothed F, peak and drop still those of the smoothed samples (see [`refine`]).
#[must_use]
pub fn find(t_s: &[f64], f_n: &[f64], h_n: f64) -> Vec<(Event, Windows)> {
    let smoothed = smooth(f_n);
    let turns = zigzag(&smoothed, h_n);
    let mut out = Vec::with_capacity(turns.len());
    let mut before = 0;
    for (k, &(peak, least)) in turns.iter().enumerate() {
        let after = turns.get(k + 1).map_or(f_n.len() - 1, |n| n.0);
        let h = EXTREMUM_HALF;
        let windows = Windows {
            peak: (peak.saturating_sub(h).max(before), (peak + h).min(least)),
            least: (least.saturating_sub(h).max(peak), (least + h).min(after)),
        };
        let e = event(t_s, &smoothed, peak, least);
        out.push((with_resolution(e, t_s, f_n, peak, least), windows));
        before = least;
    }
    out
}

/// The data's events: [`find`]'s, their peak and drop from the parabolas through the raw
/// samples of their windows, with their sampling errors.
#[must_use]
pub fn refine(t_s: &[f64], f_n: &[f64], found: &[(Event, Windows)]) -> Vec<Event> {
    found
        .iter()
        .map(|(e, w)| {
            let mut out = with_extrema(e, &window(t_s, f_n, w.peak), &window(t_s, f_n, w.least));
            let j = t_s
                .partition_point(|&x| x <= e.t_onset_s)
                .clamp(1, t_s.len() - 1);
            let samples = e.interpolation_s / (t_s[j] - t_s[j - 1]);
            out.peak_resolution_n = samples * window_sensitivity(t_s, f_n, w.peak, true);
            out.least_resolution_n = samples * window_sensitivity(t_s, f_n, w.least, false);
            out
        })
        .collect()
}

/// How much the parabola's extremum through the samples `(a, b)` changes when the window
/// moves by one sample, the larger of either way, N.
fn window_sensitivity(t: &[f64], f: &[f64], (a, b): (usize, usize), max: bool) -> f64 {
    let at = |a: usize, b: usize| extremum(&window(t, f, (a, b)), max).0;
    let here = at(a, b);
    let mut change: f64 = 0.0;
    if a > 0 {
        change = change.max((at(a - 1, b - 1) - here).abs());
    }
    if b + 1 < f.len() {
        change = change.max((at(a + 1, b + 1) - here).abs());
    }
    change
}

/// `e` with its peak force and drop from the parabolas through the samples `peak` and
/// `least` (and their variances).
fn with_extrema(e: &Event, peak: &[(f64, f64)], least: &[(f64, f64)]) -> Event {
    let (top, peak_variance) = extremum(peak, true);
    let (bottom, least_variance) = extremum(least, false);
    Event {
        f_peak_n: top,
        drop_n: top - bottom,
        peak_variance,
        least_variance,
        ..*e
    }
}

/// The model's events ([`find`]'s on its F at the data's times): each matched to a data event
/// (`data`, in order) gets its peak and drop from the parabolas through `model` (F at any
/// time) at the data event's window times moved by the difference of the onsets; the model's
/// extra events keep their smoothed values.
#[must_use]
pub fn refine_model(
    t_s: &[f64],
    model: &dyn Fn(f64) -> f64,
    data: &[(Event, Windows)],
    found: &[(Event, Windows)],
) -> Vec<Event> {
    found
        .iter()
        .enumerate()
        .map(|(k, (e, _))| {
            let Some((d, w)) = data.get(k) else { return *e };
            let shift = e.t_onset_s - d.t_onset_s;
            let points = |(a, b): (usize, usize)| -> Vec<(f64, f64)> {
                (a..=b)
                    .map(|i| (t_s[i] + shift, model(t_s[i] + shift)))
                    .collect()
            };
            with_extrema(e, &points(w.peak), &points(w.least))
        })
        .collect()
}

/// The events of `(t, f)` as they are: unsmoothed, extremes as sampled.
#[must_use]
pub fn detect_raw(t_s: &[f64], f_n: &[f64], h_n: f64) -> Vec<Event> {
    zigzag(f_n, h_n)
        .into_iter()
        .map(|(peak, least)| event(t_s, f_n, peak, least))
        .collect()
}

/// The samples `a..=b` as points.
fn window(t: &[f64], f: &[f64], (a, b): (usize, usize)) -> Vec<(f64, f64)> {
    (a..=b).map(|i| (t[i], f[i])).collect()
}

/// The (peak, least) sample indices of F's zigzag with hysteresis `h`.
fn zigzag(f: &[f64], h: f64) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i_max = 0;
    // Some((peak, least)) while falling.
    let mut falling: Option<(usize, usize)> = None;
    for i in 1..f.len() {
        match falling {
            None => {
                if f[i] > f[i_max] {
                    i_max = i;
                } else if f[i] < f[i_max] - h {
                    falling = Some((i_max, i));
                }
            }
            Some((peak, least)) => {
                if f[i] < f[least] {
                    falling = Some((peak, i));
                } else if f[i] > f[least] + h {
                    out.push((peak, least));
                    falling = None;
                    i_max = i;
                }
            }
        }
    }
    out.extend(falling);
    out
}

/// The largest (`max`) or least value, over the points' time span, of the least-squares
/// parabola through `points` (the extreme point itself when there are fewer than 5), and its
/// variance per unit variance of the points' noise, pᵀ·(AᵀA)⁻¹·p at the extremum's
/// p = (1, x, x²).
fn extremum(points: &[(f64, f64)], max: bool) -> (f64, f64) {
    let pick = |x: f64, y: f64| if max { x.max(y) } else { x.min(y) };
    let start = if max {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    };
    let extreme_point = || (points.iter().map(|p| p.1).fold(start, pick), 1.0);
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return (0.0, 1.0);
    };
    if points.len() < 5 || last.0 <= first.0 {
        return extreme_point();
    }
    // Centred and scaled time, so the normal equations are well conditioned.
    let (t0, w) = (0.5 * (first.0 + last.0), 0.5 * (last.0 - first.0));
    let mut m = [[0.0; 3]; 3];
    let mut r = [0.0; 3];
    for &(t, f) in points {
        let x = (t - t0) / w;
        let p = [1.0, x, x * x];
        for j in 0..3 {
            r[j] += p[j] * f;
            for k in 0..3 {
                m[j][k] += p[j] * p[k];
            }
        }
    }
    let Some([c0, c1, c2]) = solve3(m, r) else {
        return extreme_point();
    };
    let at = |x: f64| c0 + c1 * x + c2 * x * x;
    let mut x_best = if pick(at(-1.0), at(1.0)) == at(-1.0) {
        -1.0
    } else {
        1.0
    };
    if c2 != 0.0 {
        let x = -c1 / (2.0 * c2);
        if (-1.0..=1.0).contains(&x) && pick(at(x), at(x_best)) == at(x) {
            x_best = x;
        }
    }
    let p = [1.0, x_best, x_best * x_best];
    let variance = solve3(m, p).map_or(1.0, |q| q.iter().zip(&p).map(|(a, b)| a * b).sum());
    (at(x_best), variance)
}

/// The solution of the 3 × 3 system m·x = r by Cramer's rule (none when singular).
fn solve3(m: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det = |a: [[f64; 3]; 3]| {
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    };
    let d = det(m);
    if d.abs() < 1e-300 || !d.is_finite() {
        return None;
    }
    let mut x = [0.0; 3];
    for (col, xc) in x.iter_mut().enumerate() {
        let mut a = m;
        for (row, &rv) in a.iter_mut().zip(&r) {
            row[col] = rv;
        }
        *xc = det(a) / d;
    }
    Some(x)
}

/// [`Event::interpolation_s`] of the drop from sample `peak` to `least` of `f` (raw, or as
/// smoothed: [`find`] passes it the raw samples through [`with_resolution`]), its crossing
/// between samples `j − 1` and `j`.
fn resolution_s(t: &[f64], f: &[f64], peak: usize, least: usize, j: usize) -> f64 {
    let dt = t[j] - t[j - 1];
    let (a, b) = (
        peak.saturating_sub(SMOOTH / 2),
        (least + SMOOTH / 2).min(f.len() - 1),
    );
    let drop = f[a..=b].iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x))
        - f[a..=b].iter().fold(f64::INFINITY, |m, &x| m.min(x));
    let fall = (a..b).map(|i| f[i] - f[i + 1]).fold(0.0, f64::max);
    if drop > 0.0 {
        dt / 12f64.sqrt() * (fall / drop).clamp(0.0, 1.0).powi(2)
    } else {
        dt / 12f64.sqrt()
    }
}

/// `e` (found on the smoothed samples) with its onset's sampling error from the raw `f`.
fn with_resolution(e: Event, t: &[f64], f: &[f64], peak: usize, least: usize) -> Event {
    let j = t
        .partition_point(|&x| x <= e.t_onset_s)
        .clamp(1, t.len() - 1);
    Event {
        interpolation_s: resolution_s(t, f, peak, least, j),
        ..e
    }
}

/// An event from its peak and least samples of `f`: the onset where `f` crosses half-way
/// between them.
fn event(t: &[f64], f: &[f64], peak: usize, least: usize) -> Event {
    let level = 0.5 * (f[peak] + f[least]);
    // The first sample below the level after the peak (at the latest the least one).
    let j = (peak + 1..=least).find(|&j| f[j] < level).unwrap_or(least);
    let (f0, f1) = (f[j - 1], f[j]);
    let w = if f0 > f1 {
        (f0 - level) / (f0 - f1)
    } else {
        1.0
    };
    let dt = t[j] - t[j - 1];
    Event {
        t_onset_s: t[j - 1] + w.clamp(0.0, 1.0) * dt,
        t_peak_s: t[peak],
        f_peak_n: f[peak],
        drop_n: f[peak] - f[least],
        slope_n_per_s: ((f0 - f1) / dt).abs(),
        interpolation_s: resolution_s(t, f, peak, least, j),
        peak_resolution_n: 0.0,
        least_resolution_n: 0.0,
        peak_variance: 1.0,
        least_variance: 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sawtooth_gives_one_event_per_drop_with_interpolated_onsets() {
        // F rises by 1 per sample for 10 samples, then drops by 8 over 2 samples.
        let mut t = Vec::new();
        let mut f = Vec::new();
        let mut v = 0.0;
        for i in 0..60 {
            t.push(i as f64);
            f.push(v);
            v = if i % 12 == 9 || i % 12 == 10 {
                v - 4.0
            } else {
                v + 1.0
            };
        }
        let ev = detect_raw(&t, &f, 3.0);
        assert_eq!(ev.len(), 5, "{ev:?}");
        let e = ev[0];
        assert_eq!((e.t_peak_s, e.f_peak_n), (9.0, 9.0));
        // Crosses half-way, 9 − 4 = 5, at t = 10 (between 9 at t = 9 and 5 at t = 10).
        assert!((e.t_onset_s - 10.0).abs() < 1e-12, "{e:?}");
        assert_eq!(e.drop_n, 8.0);
        assert_eq!(e.slope_n_per_s, 4.0);
        // A rise smaller than h is no event.
        assert!(detect_raw(&t, &f, 9.0).is_empty());
        // Smoothing keeps the events of a clean sawtooth, and the model's values over the
        // data's windows are the data's when the model is the data.
        let found = find(&t, &f, 3.0);
        assert!(found.len() >= 4, "{found:?}");
        let data = refine(&t, &f, &found);
        let curve = |x: f64| f[(x.round() as usize).min(f.len() - 1)];
        let measured = |e: &[Event]| -> Vec<(f64, f64, f64)> {
            e.iter()
                .map(|e| (e.t_onset_s, e.f_peak_n, e.drop_n))
                .collect()
        };
        assert_eq!(
            measured(&refine_model(&t, &curve, &found, &found)),
            measured(&data)
        );
        // A parabola's extremum: exact for samples on a parabola, the noise averaged out.
        let t: Vec<f64> = (0..21).map(f64::from).collect();
        let f: Vec<f64> = t
            .iter()
            .map(|x| 3.0 - (x - 10.3) * (x - 10.3) / 50.0)
            .collect();
        let pts: Vec<(f64, f64)> = t.iter().copied().zip(f.iter().copied()).collect();
        let (top, variance) = extremum(&pts, true);
        assert!((top - 3.0).abs() < 1e-12);
        // About 9/4 of a sample's variance over 21 samples.
        assert!(variance > 0.05 && variance < 0.2, "{variance}");
        let noisy: Vec<f64> = f
            .iter()
            .enumerate()
            .map(|(i, y)| y + if i % 2 == 0 { 0.1 } else { -0.1 })
            .collect();
        let pts: Vec<(f64, f64)> = t.iter().copied().zip(noisy).collect();
        assert!((extremum(&pts, true).0 - 3.0).abs() < 0.02);
    }

    #[test]
    fn a_drop_faster_than_the_sampling_carries_its_sampling_error() {
        // A slow rise, then a drop of 10 within one sample (a step) or over 10 samples.
        let trace = |fall_samples: usize| {
            let t: Vec<f64> = (0..200).map(f64::from).collect();
            let mut f = Vec::new();
            let mut v = 0.0;
            for i in 0..200 {
                f.push(v);
                v = if (100..100 + fall_samples).contains(&i) {
                    v - 10.0 / fall_samples as f64
                } else {
                    v + 0.01
                };
            }
            (t, f)
        };
        let (t, f) = trace(1);
        let found = find(&t, &f, 3.0);
        let step = refine(&t, &f, &found)[0];
        assert!(
            (step.interpolation_s - 1.0 / 12f64.sqrt()).abs() < 0.01,
            "{step:?}"
        );
        let (t, f) = trace(10);
        let found = find(&t, &f, 3.0);
        let ramp = refine(&t, &f, &found)[0];
        assert!(ramp.interpolation_s < 0.02 / 12f64.sqrt(), "{ramp:?}");
        // The step's parabolas, fitted across it, move with the window: sampling errors of
        // a percent of the drop, a hundred times the resolved drop's.
        for (a, b) in [
            (step.peak_resolution_n, ramp.peak_resolution_n),
            (step.least_resolution_n, ramp.least_resolution_n),
        ] {
            assert!(
                a > 0.005 * step.drop_n && a > 100.0 * b,
                "{step:?} {ramp:?}"
            );
        }
    }
}
