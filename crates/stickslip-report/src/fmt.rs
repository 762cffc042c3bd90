//! The one number formatter of the reports: significant digits, plain for moderate
//! magnitudes and scientific otherwise; times in µs/ns; lists; axis ticks.

/// `x` with `digits` significant digits: plain decimals for 1e-4 ≤ |x| < 1e5, else
/// scientific (`1.25e-9`); `0` for zero, `–` for NaN, `∞`/`-∞` for infinities.
#[must_use]
pub fn sig(x: f64, digits: usize) -> String {
    if x.is_nan() {
        return "–".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "∞" } else { "-∞" }.into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-4..1e5).contains(&a) {
        let decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.prec$e}", prec = digits.saturating_sub(1))
    }
}

/// An optional value with [`sig`], `–` for none.
#[must_use]
pub fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "–".to_string(), |x| sig(x, digits))
}

/// A time in s as `… µs`, `… ns` (below 1 µs) or `0 s`, with `digits` significant digits.
#[must_use]
pub fn time(t_s: f64, digits: usize) -> String {
    if t_s == 0.0 {
        "0 s".into()
    } else if t_s.abs() < 1e-6 {
        format!("{} ns", sig(t_s * 1e9, digits))
    } else if t_s.abs() < 1e-3 {
        format!("{} µs", sig(t_s * 1e6, digits))
    } else if t_s.abs() < 1.0 {
        format!("{} ms", sig(t_s * 1e3, digits))
    } else {
        format!("{} s", sig(t_s, digits))
    }
}

/// Times in s as µs, comma-separated, with `digits` significant digits.
#[must_use]
pub fn us_list(ts_s: &[f64], digits: usize) -> String {
    ts_s.iter()
        .map(|t| sig(t * 1e6, digits))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Values with `decimals` decimals in brackets: `[1.00, 2.50]`.
#[must_use]
pub fn list(xs: &[f64], decimals: usize) -> String {
    let items: Vec<String> = xs.iter().map(|x| format!("{x:.decimals$}")).collect();
    format!("[{}]", items.join(", "))
}

/// An axis tick: integers for 1 ≤ |v| < 1e5, plain short decimals for 1e-3 ≤ |v| < 1,
/// otherwise `2.5e-9` with at most three significant digits.
#[must_use]
pub fn tick(v: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1.0..1e5).contains(&a) && (v - v.round()).abs() < 1e-6 * a {
        return format!("{v:.0}");
    }
    if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.3}");
        return s.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    let e = a.log10().floor() as i32;
    let m = v / 10f64.powi(e);
    let m = format!("{m:.2}");
    let m = m.trim_end_matches('0').trim_end_matches('.');
    format!("{m}e{e}")
}

/// `v` without a fractional part when it is an integer.
#[must_use]
pub fn trim(v: f64) -> String {
    if (v - v.round()).abs() < 1e-9 {
        format!("{v:.0}")
    } else {
        format!("{v}")
    }
}

/// The first line of `s`, at most 160 characters.
#[must_use]
pub fn first_line(s: &str) -> String {
    let l = s.lines().next().unwrap_or("").trim();
    if l.chars().count() > 160 {
        format!("{}…", l.chars().take(160).collect::<String>())
    } else {
        l.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits_plain_or_scientific() {
        assert_eq!(sig(1.23456, 3), "1.23");
        assert_eq!(sig(1234.6, 3), "1235");
        assert_eq!(sig(2.5e-9, 2), "2.5e-9");
        assert_eq!(sig(f64::NAN, 3), "–");
        assert_eq!(time(5.975e-4, 4), "597.5 µs");
        assert_eq!(time(3e-7, 3), "300 ns");
        assert_eq!(tick(2.5e-9), "2.5e-9");
        assert_eq!(tick(0.25), "0.25");
        assert_eq!(tick(200.0), "200");
    }
}
