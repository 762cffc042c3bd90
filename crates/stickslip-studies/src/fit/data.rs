//! The measured trace a fit reads: a CSV file with a header line and columns `t` (s) and `F`
//! (N), optionally `X` (m, the stamp's position, which the trace misfit fits too), other names mapped by `--columns t=NAME,F=NAME,X=NAME`; read under
//! the trace file's cap ([`stickslip_run::bounded::TRACE`]) and checked before any run: every cell a
//! finite number, t ≥ 0 (the model's drive starts at t = 0) and strictly increasing, at least
//! [`MIN_SAMPLES`] samples. The noise of F is estimated from the data
//! ([`noise_sigma_n`], docs/fit.md#noise).

use super::error::FitError;
use stickslip_run::stats::median;

/// Fewest samples a trace may have: fewer cannot show a stick–slip cycle and its noise.
pub const MIN_SAMPLES: usize = 20;

/// The columns of the trace file that hold t, F and (optionally) X.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Columns {
    /// The time column's name (default `t`), s.
    pub t: String,
    /// The friction force's column (default `F`), N.
    pub f: String,
    /// The stamp position's column (default `X`, used when present), m.
    pub x: String,
}

impl Default for Columns {
    fn default() -> Self {
        Self {
            t: "t".into(),
            f: "F".into(),
            x: "X".into(),
        }
    }
}

/// Longest piece of a trace's text a message quotes, characters.
const QUOTED_CHARS: usize = 40;

/// `text` as a message quotes it: whole when short, else its start and its length (a 60 MB
/// line is not echoed).
fn clip(text: &str) -> String {
    match text.char_indices().nth(QUOTED_CHARS) {
        None => text.to_string(),
        Some((end, _)) => format!("{}… ({} bytes in all)", &text[..end], text.len()),
    }
}

impl Columns {
    /// Refuses an ambiguous mapping of the trace's `header` names: t and F (and an X named in
    /// `--columns`) on one column, a column name the header holds twice, or an X asked for by
    /// name that the header lacks.
    ///
    /// # Errors
    /// [`FitError::Input`] naming `--columns` or the header.
    fn check_against(&self, header: &[&str]) -> Result<(), FitError> {
        let used = [("t", &self.t), ("F", &self.f), ("X", &self.x)];
        for (i, (a, name_a)) in used.iter().enumerate() {
            for (b, name_b) in &used[i + 1..] {
                if name_a == name_b {
                    return Err(FitError::input(
                        "--columns",
                        format!("{a}={name_a}, {b}={name_b}"),
                        "a different column for each of t, F and X",
                    ));
                }
            }
        }
        for (which, name) in used {
            let count = header.iter().filter(|h| **h == name.as_str()).count();
            if count > 1 {
                return Err(FitError::input(
                    "trace header",
                    clip(&header.join(",")),
                    format!(
                        "column names each once: {name} (the {which} column) appears {count} \
                         times, so which one is meant is ambiguous"
                    ),
                ));
            }
        }
        if self.x != "X" && !header.contains(&self.x.as_str()) {
            return Err(FitError::input(
                "--columns X",
                self.x.as_str(),
                format!(
                    "one of the header's columns ({}), or no X= to fit without X",
                    clip(&header.join(", "))
                ),
            ));
        }
        Ok(())
    }

    /// The default names with `spec`'s (`t=time,F=force`, comma-separated) in their place.
    ///
    /// # Errors
    /// [`FitError::Input`] naming `--columns` for an entry that is not `t=`, `F=` or `X=` a
    /// non-empty name.
    pub fn parse(spec: &str) -> Result<Self, FitError> {
        let mut out = Self::default();
        for part in spec.split(',').filter(|p| !p.trim().is_empty()) {
            let bad = || {
                FitError::input(
                    "--columns",
                    part,
                    "comma-separated t=NAME, F=NAME or X=NAME (the trace's column names)",
                )
            };
            let (which, name) = part.split_once('=').ok_or_else(bad)?;
            let name = name.trim();
            if name.is_empty() {
                return Err(bad());
            }
            match which.trim() {
                "t" => out.t = name.into(),
                "F" => out.f = name.into(),
                "X" => out.x = name.into(),
                _ => return Err(bad()),
            }
        }
        Ok(out)
    }
}

/// A measured friction trace.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// Sample times, s (≥ 0, strictly increasing).
    pub t_s: Vec<f64>,
    /// Friction force, N.
    pub f_n: Vec<f64>,
    /// Stamp position, m, when the trace has it.
    pub x_m: Option<Vec<f64>>,
}

impl Trace {
    /// A trace from arrays, checked as a file's would be (for code and Python).
    ///
    /// # Errors
    /// As [`Trace::parse`]'s checks.
    pub fn new(t_s: Vec<f64>, f_n: Vec<f64>, x_m: Option<Vec<f64>>) -> Result<Self, FitError> {
        let trace = Self { t_s, f_n, x_m };
        trace.check()?;
        Ok(trace)
    }

    /// Reads and checks the trace at `path`.
    ///
    /// # Errors
    /// [`FitError::Read`] when the file cannot be read (or is over the cap); else as
    /// [`Trace::parse`].
    pub fn read(path: &std::path::Path, columns: &Columns) -> Result<Self, FitError> {
        let text = stickslip_run::bounded::read_text(path, stickslip_run::bounded::TRACE).map_err(
            |e| FitError::Read {
                path: path.display().to_string(),
                message: e.to_string(),
            },
        )?;
        Self::parse(&text, columns)
    }

    /// Parses CSV text: a header line naming the columns, then one sample per line
    /// (blank lines and lines starting with `#` skipped).
    ///
    /// # Errors
    /// [`FitError::Input`] naming the column or line: a missing column, a cell that is not a
    /// finite number, t not increasing or negative, too few samples.
    pub fn parse(text: &str, columns: &Columns) -> Result<Self, FitError> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let Some((_, header)) = lines.next() else {
            return Err(FitError::input(
                "trace",
                "an empty file",
                "a header line naming the columns, then one sample per line",
            ));
        };
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        columns.check_against(&names)?;
        let index = |name: &str, which: &str| {
            names.iter().position(|n| *n == name).ok_or_else(|| {
                FitError::input(
                    format!("trace column {which}"),
                    name,
                    format!(
                        "one of the header's columns ({}); map another name with --columns \
                         {which}=NAME",
                        names.join(", ")
                    ),
                )
            })
        };
        let it = index(&columns.t, "t")?;
        let i_f = index(&columns.f, "F")?;
        let ix = names.iter().position(|n| *n == columns.x);
        let (mut t, mut f, mut x) = (Vec::new(), Vec::new(), Vec::new());
        for (line, row) in lines {
            let cells: Vec<&str> = row.split(',').map(str::trim).collect();
            let cell = |i: usize, name: &str| -> Result<f64, FitError> {
                let text = cells.get(i).copied().unwrap_or("");
                match text.parse::<f64>() {
                    Ok(v) if v.is_finite() => Ok(v),
                    _ => Err(FitError::input(
                        format!("trace {name} at line {}", line + 1),
                        if text.is_empty() {
                            "(empty)".to_string()
                        } else {
                            clip(text)
                        },
                        "a finite number",
                    )),
                }
            };
            t.push(cell(it, &columns.t)?);
            f.push(cell(i_f, &columns.f)?);
            if let Some(ix) = ix {
                x.push(cell(ix, &columns.x)?);
            }
        }
        Self::new(t, f, ix.map(|_| x))
    }

    /// The checks of [`Trace::parse`] on the arrays.
    fn check(&self) -> Result<(), FitError> {
        let n = self.t_s.len();
        if self.f_n.len() != n || self.x_m.as_ref().is_some_and(|x| x.len() != n) {
            return Err(FitError::input(
                "trace columns",
                format!("lengths t {n}, F {}", self.f_n.len()),
                "columns of equal length",
            ));
        }
        if n < MIN_SAMPLES {
            return Err(FitError::input(
                "trace samples",
                n.to_string(),
                format!("at least {MIN_SAMPLES}"),
            ));
        }
        let columns = [("t", Some(&self.t_s)), ("F", Some(&self.f_n))];
        for (name, col) in columns.into_iter().chain([("X", self.x_m.as_ref())]) {
            if let Some((i, v)) =
                col.and_then(|c| c.iter().enumerate().find(|(_, v)| !v.is_finite()))
            {
                return Err(FitError::input(
                    format!("trace {name} at sample {}", i + 1),
                    stickslip_run::keys::human(*v),
                    "a finite number",
                ));
            }
        }
        if self.f_range_n() == 0.0 {
            return Err(FitError::input(
                "trace F",
                format!(
                    "{} N at every sample",
                    stickslip_run::keys::human(self.f_n[0])
                ),
                "a force that varies (a constant trace holds nothing to fit, and no noise to \
                 weigh it by)",
            ));
        }
        if self.t_s[0] < 0.0 {
            return Err(FitError::input(
                "trace t at sample 1",
                format!("{:e}", self.t_s[0]),
                ">= 0 s (the time since the drive started: the model's t = 0)",
            ));
        }
        if let Some(i) = (1..n).find(|&i| self.t_s[i] <= self.t_s[i - 1]) {
            return Err(FitError::input(
                format!("trace t at sample {}", i + 1),
                format!("{:e} after {:e}", self.t_s[i], self.t_s[i - 1]),
                "strictly increasing times",
            ));
        }
        Ok(())
    }

    /// The median spacing of the samples, s.
    #[must_use]
    pub fn median_spacing_s(&self) -> f64 {
        let d: Vec<f64> = self.t_s.windows(2).map(|w| w[1] - w[0]).collect();
        if d.is_empty() { 0.0 } else { median(&d) }
    }

    /// The span F covers, max − min, N.
    #[must_use]
    pub fn f_range_n(&self) -> f64 {
        let (lo, hi) = self
            .f_n
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        hi - lo
    }
}

/// Smallest noise level a fit assumes, as a fraction of F's span: a noise-free (synthetic)
/// trace would otherwise give every residual an infinite weight.
pub const NOISE_FLOOR_OF_RANGE: f64 = 1e-6;

/// The standard deviation of F's noise, N, estimated from the data: the second differences
/// d = F(i+1) − 2F(i) + F(i−1) of white noise have variance 6σ², and their median absolute
/// deviation (× 1.4826 for a normal distribution) ignores the few large ones at slips and
/// the curvature of the smooth signal between them; at least [`NOISE_FLOOR_OF_RANGE`] of F's
/// span.
#[must_use]
pub fn noise_sigma_n(trace: &Trace) -> f64 {
    noise_sigma(&trace.f_n)
}

/// The standard deviation of the noise of evenly or unevenly sampled values `v` (F in N, or
/// the stamp's position X in m), estimated as [`noise_sigma_n`] describes; at least
/// [`NOISE_FLOOR_OF_RANGE`] of their span.
#[must_use]
pub fn noise_sigma(v: &[f64]) -> f64 {
    let d: Vec<f64> = v.windows(3).map(|w| w[2] - 2.0 * w[1] + w[0]).collect();
    // Fewer than three values: no second difference, no noise seen.
    let sigma = if d.is_empty() {
        0.0
    } else {
        let m = median(&d);
        let dev: Vec<f64> = d.iter().map(|x| (*x - m).abs()).collect();
        1.4826 * median(&dev) / 6f64.sqrt()
    };
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    sigma.max(NOISE_FLOOR_OF_RANGE * (hi - lo))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(n: usize) -> String {
        let mut s = String::from("time,force\n");
        for i in 0..n {
            s.push_str(&format!("{:e},{:e}\n", i as f64 * 1e-6, (i % 7) as f64));
        }
        s
    }

    #[test]
    fn renamed_columns_are_read_and_the_defaults_refused_naming_the_column() {
        let cols = Columns::parse("t=time,F=force").unwrap();
        let tr = Trace::parse(&ramp(30), &cols).unwrap();
        assert_eq!(tr.t_s.len(), 30);
        assert_eq!(tr.f_n[8], 1.0);
        assert!(tr.x_m.is_none());
        let e = Trace::parse(&ramp(30), &Columns::default()).unwrap_err();
        assert!(
            e.to_string().starts_with("trace column t = t is invalid"),
            "{e}"
        );
        for bad in ["q=time", "t=", "time"] {
            let e = Columns::parse(bad).unwrap_err().to_string();
            assert!(e.starts_with("--columns = "), "{e}");
        }
    }

    #[test]
    fn bad_traces_name_the_field() {
        let cols = Columns::parse("t=time,F=force").unwrap();
        let cases = [
            (ramp(5), "trace samples = 5"),
            (
                ramp(30).replace("7e-6,0e0", "7e-6,NaN"),
                "trace force at line 9 = NaN",
            ),
            (
                ramp(30).replace("7e-6,", "5e-6,"),
                "trace t at sample 8 = 5e-6 after 6e-6",
            ),
            (
                ramp(30).replacen("0e0,0e0", "-1e0,0e0", 1),
                "trace t at sample 1",
            ),
        ];
        for (text, start) in cases {
            let e = Trace::parse(&text, &cols).unwrap_err();
            assert!(e.to_string().starts_with(start), "{e}");
            assert_eq!(e.exit(), stickslip_run::exit::Exit::BadInput);
        }
    }

    #[test]
    fn the_noise_estimate_sees_white_noise_and_not_the_slips() {
        // A sawtooth with drops every 100 samples plus ±s alternating noise of RMS s.
        let s = 0.01;
        let n = 2000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-6).collect();
        let mut state = 1u64;
        let f: Vec<f64> = (0..n)
            .map(|i| {
                // A small deterministic generator: uniform on [-√3, √3]·s has RMS s.
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (state >> 11) as f64 / (1u64 << 53) as f64;
                (i % 100) as f64 * 0.1 + (2.0 * u - 1.0) * 3f64.sqrt() * s
            })
            .collect();
        let sigma = noise_sigma_n(&Trace::new(t, f, None).unwrap());
        assert!((sigma / s - 1.0).abs() < 0.15, "{sigma}");
    }
}
