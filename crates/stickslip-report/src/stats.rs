//! The one set of small statistics of the reports.

/// Median (the mean of the two middle values for an even count); NaN when empty: the run
/// library's one median.
pub use stickslip_run::stats::median;

/// Arithmetic mean; NaN when empty.
#[must_use]
pub fn mean(values: &[f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.iter().sum::<f64>() / values.len() as f64
}

/// Sample coefficient of variation: standard deviation (n − 1) over the mean; NaN for fewer
/// than two values.
#[must_use]
pub fn cv(values: &[f64]) -> f64 {
    if values.len() < 2 {
        return f64::NAN;
    }
    let n = values.len() as f64;
    let m = mean(values);
    let var = values.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    var.sqrt() / m
}

/// Successive differences x_{k+1} − x_k.
#[must_use]
pub fn diffs(values: &[f64]) -> Vec<f64> {
    values.windows(2).map(|w| w[1] - w[0]).collect()
}

/// Largest ratio x_{k+1}/x_k (below 1 for a strictly decreasing positive sequence).
#[must_use]
pub fn max_ratio(values: &[f64]) -> f64 {
    values
        .windows(2)
        .map(|w| w[1] / w[0])
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Linear interpolation of y(x) at `x0`, `x` ascending; clamped outside; NaN when empty.
#[must_use]
pub fn interp(x: &[f64], y: &[f64], x0: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let i = x.partition_point(|&v| v <= x0);
    if i == 0 {
        return y[0];
    }
    if i >= x.len() {
        return y[x.len() - 1];
    }
    let (x_a, x_b) = (x[i - 1], x[i]);
    if x_b == x_a {
        return y[i];
    }
    y[i - 1] + (y[i] - y[i - 1]) * (x0 - x_a) / (x_b - x_a)
}

/// Least-squares slope of log y against log x over the points with x, y > 0.
#[must_use]
pub fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn cv_uses_the_sample_deviation() {
        let c = cv(&[1.0, 2.0, 3.0]);
        assert!((c - 0.5).abs() < 1e-15, "{c}");
    }

    #[test]
    fn slope_of_a_power_law() {
        let pts: Vec<(f64, f64)> = (1..6)
            .map(|i| (f64::from(i), f64::from(i).powi(2)))
            .collect();
        assert!((log_log_slope(&pts) - 2.0).abs() < 1e-12);
    }
}
