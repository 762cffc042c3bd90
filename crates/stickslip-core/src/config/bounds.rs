//! The allowed range of every configuration value the engine checks, named by its scene key.
//!
//! Each [`Bound`] is the one definition of its key's path, unit and allowed range: the
//! engine's [`SimConfig::validate`](super::SimConfig::validate) checks with it, and the run
//! library's key registry takes its entries' unit and range from it (a compile-time check
//! there keeps the paths equal), so the range and its wording exist once. Rules between keys
//! (`time.dt <= time.end`) are checked in `validate` and stated in the registry's text.

use super::ConfigError;

/// A float for messages, spelled as it could be written in a scene: plain decimals for
/// 1e-3 ≤ |x| < 1e4 and for 0 (`0.5`, `500`, `0`), else shortest scientific (`2e-5`, `1e9`),
/// and `nan`, `inf`, `-inf`.
#[must_use]
pub fn human(f: f64) -> String {
    if f.is_nan() {
        "nan".to_string()
    } else if f.is_infinite() {
        if f > 0.0 { "inf" } else { "-inf" }.to_string()
    } else if f == 0.0 || (1e-3..1e4).contains(&f.abs()) {
        format!("{f}")
    } else {
        format!("{f:e}")
    }
}

/// What is allowed, checked where it depends on the key alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// Any finite number.
    Finite,
    /// Finite and > 0.
    Positive,
    /// Finite and ≥ 0.
    NonNegative,
    /// Finite and > lo.
    Above(f64),
    /// lo ≤ x ≤ hi.
    Closed(f64, f64),
    /// lo < x < hi.
    Open(f64, f64),
    /// lo < x ≤ hi.
    OpenClosed(f64, f64),
    /// An integer in lo ..= hi.
    Integers(i64, i64),
    /// A word of the key's list.
    Word,
    /// A non-empty string.
    NonEmpty,
    /// Set by rules between keys, stated in the key's rule and checked in code.
    ByRule,
}

impl Range {
    /// Whether `v` is allowed (rules between keys aside).
    #[must_use]
    pub fn contains(&self, v: f64) -> bool {
        match *self {
            Self::Finite | Self::ByRule => v.is_finite(),
            Self::Positive => v.is_finite() && v > 0.0,
            Self::NonNegative => v.is_finite() && v >= 0.0,
            Self::Above(lo) => v.is_finite() && v > lo,
            Self::Closed(lo, hi) => v.is_finite() && (lo..=hi).contains(&v),
            Self::Open(lo, hi) => v.is_finite() && v > lo && v < hi,
            Self::OpenClosed(lo, hi) => v.is_finite() && v > lo && v <= hi,
            Self::Integers(lo, hi) => v.fract() == 0.0 && v >= lo as f64 && v <= hi as f64,
            Self::Word | Self::NonEmpty => true,
        }
    }

    /// The range in words, `var` naming the value in two-sided bounds, `unit` after numbers.
    #[must_use]
    pub fn describe(&self, var: &str, unit: &str) -> String {
        let u = if unit.is_empty() || unit == "–" {
            String::new()
        } else {
            format!(" {unit}")
        };
        match *self {
            Self::Finite | Self::ByRule => format!("finite{u}"),
            Self::Positive => format!("finite and > 0{u}"),
            Self::NonNegative => format!("finite and >= 0{u}"),
            Self::Above(lo) => format!("finite and > {}{u}", human(lo)),
            Self::Closed(lo, hi) if lo > 0.0 => {
                format!(
                    "finite and within [{}, {}]{u} (so > 0)",
                    human(lo),
                    human(hi)
                )
            }
            Self::Closed(lo, hi) => format!("finite and within [{}, {}]{u}", human(lo), human(hi)),
            Self::Open(lo, hi) => format!("finite, > {} and < {}{u}", human(lo), human(hi)),
            Self::OpenClosed(lo, hi) => format!("{} < {var} <= {}{u}", human(lo), human(hi)),
            Self::Integers(lo, hi) => format!("an integer in {lo} ..= {hi}"),
            Self::Word => "one of the listed words".to_string(),
            Self::NonEmpty => "a non-empty string".to_string(),
        }
    }
}

/// A key's path, unit and allowed range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// Full scene-key path, `section.key`.
    pub path: &'static str,
    /// SI unit (`–` for dimensionless).
    pub unit: &'static str,
    /// Allowed values of the key alone.
    pub range: Range,
}

impl Bound {
    /// The last part of the path (`nu1` of `contact.nu1`), without trailing digits.
    #[must_use]
    pub fn short_name(&self) -> &'static str {
        let last = self.path.rsplit('.').next().unwrap_or(self.path);
        last.trim_end_matches(|c: char| c.is_ascii_digit())
    }

    /// The range in words.
    #[must_use]
    pub fn describe(&self) -> String {
        self.range.describe(self.short_name(), self.unit)
    }

    /// `v` if the range allows it.
    ///
    /// # Errors
    /// A [`ConfigError`] naming the key, the value and the range.
    pub fn check(&self, v: f64) -> Result<f64, ConfigError> {
        if self.range.contains(v) {
            Ok(v)
        } else {
            Err(ConfigError::new(self.path, human(v), &self.describe()))
        }
    }
}

/// Far beyond any physical contact, yet inside the range where products such as a0²·G*/h0
/// neither overflow nor underflow.
pub const LENGTH_RANGE_M: (f64, f64) = (1e-15, 1e15);
/// Moduli (and the first-order film's b₃, so that b₃² stays finite).
pub const MODULUS_RANGE_PA: (f64, f64) = (1e-15, 1e20);
/// Largest number of nodes (the dense operators take 8·N² bytes each).
pub const MAX_NODES: usize = 20_000;

/// A derived number that must be finite and > 0, checked from the keys it is made of: when it
/// is not, the error names the key that moved it furthest (the largest |exponent·log10|value||
/// among `factors`, each a key, its value and its power in the product), with the formula.
///
/// # Errors
/// A [`ConfigError`] naming that key and its value, the derived number and its formula.
pub fn derived_positive(
    name: &str,
    formula: &str,
    value: f64,
    factors: &[(Bound, f64, f64)],
) -> Result<f64, ConfigError> {
    if value.is_finite() && value > 0.0 {
        return Ok(value);
    }
    let weight = |(_, v, p): &(Bound, f64, f64)| (p * v.abs().log10()).abs();
    let Some(culprit) = factors
        .iter()
        .max_by(|a, b| weight(a).total_cmp(&weight(b)))
    else {
        return Err(ConfigError::new(name, human(value), "finite and > 0"));
    };
    let others: Vec<String> = factors
        .iter()
        .filter(|f| f.0.path != culprit.0.path)
        .map(|(b, v, _)| format!("{} = {}", b.path, human(*v)))
        .collect();
    let with = if others.is_empty() {
        String::new()
    } else {
        format!(" with {}", others.join(", "))
    };
    Err(ConfigError::new(
        culprit.0.path,
        human(culprit.1),
        &format!(
            "a value for which the derived {name} = {formula} is finite and > 0{with} (here {name} = {})",
            human(value)
        ),
    ))
}

/// The film's b (and the default A = 1.5·τmax/εmax) finite and > 0: keys within their ranges
/// can still overflow or underflow them; the error names the key that moved b furthest.
///
/// # Errors
/// A [`ConfigError`] naming that key.
pub fn check_film(l: &crate::landau::LandauParams) -> Result<(), ConfigError> {
    let factors = [
        (A, l.a_pa, 2.0),
        (EPS_MAX, l.eps_max, 3.0),
        (TAU_MAX, l.tau_max_pa, -1.0),
    ];
    derived_positive("b", "2·a²·εmax³/τmax", l.b_pa(), &factors)?;
    derived_positive(
        "A",
        "1.5·τmax/εmax",
        l.a_coeff_default_pa(),
        &[(TAU_MAX, l.tau_max_pa, 1.0), (EPS_MAX, l.eps_max, -1.0)],
    )?;
    Ok(())
}

const fn bound(path: &'static str, unit: &'static str, range: Range) -> Bound {
    Bound { path, unit, range }
}

/// `lubricant.tau_max`: a stress, within the moduli's range.
pub const TAU_MAX: Bound = bound(
    "lubricant.tau_max",
    "Pa",
    Range::Closed(MODULUS_RANGE_PA.0, MODULUS_RANGE_PA.1),
);
/// `lubricant.eps_max`.
pub const EPS_MAX: Bound = bound("lubricant.eps_max", "–", Range::Positive);
/// `lubricant.a`: a modulus.
pub const A: Bound = bound(
    "lubricant.a",
    "Pa",
    Range::Closed(MODULUS_RANGE_PA.0, MODULUS_RANGE_PA.1),
);
/// `lubricant.gamma`.
pub const GAMMA: Bound = bound("lubricant.gamma", "1/(Pa·s)", Range::Positive);
/// `lubricant.melt_threshold`.
pub const MELT_THRESHOLD: Bound = bound("lubricant.melt_threshold", "–", Range::Positive);
/// `lubricant.cubic`.
pub const CUBIC: Bound = bound(
    "lubricant.cubic",
    "Pa",
    Range::Closed(0.0, MODULUS_RANGE_PA.1),
);
/// `lubricant.viscosity`: η of the film's Newtonian viscous stress.
pub const VISCOSITY: Bound = bound("lubricant.viscosity", "Pa·s", Range::NonNegative);
/// `lubricant.noise.sigma`.
pub const NOISE_SIGMA: Bound = bound("lubricant.noise.sigma", "s^-1/2", Range::NonNegative);
/// `lubricant.noise.floor` (below the melting threshold: a rule).
pub const NOISE_FLOOR: Bound = bound("lubricant.noise.floor", "–", Range::ByRule);
/// `temperature.A0`.
pub const TEMPERATURE_A0: Bound = bound("temperature.A0", "Pa", Range::Finite);
/// `temperature.t_relax`.
pub const T_RELAX: Bound = bound("temperature.t_relax", "s", Range::Positive);
/// `contact.radius`.
pub const RADIUS: Bound = bound(
    "contact.radius",
    "m",
    Range::Closed(LENGTH_RANGE_M.0, LENGTH_RANGE_M.1),
);
/// `contact.film_thickness`.
pub const FILM_THICKNESS: Bound = bound(
    "contact.film_thickness",
    "m",
    Range::Closed(LENGTH_RANGE_M.0, LENGTH_RANGE_M.1),
);
/// `contact.g_eff`.
pub const G_EFF: Bound = bound(
    "contact.g_eff",
    "Pa",
    Range::Closed(MODULUS_RANGE_PA.0, MODULUS_RANGE_PA.1),
);
/// `contact.nodes`.
pub const NODES: Bound = bound("contact.nodes", "–", Range::Integers(1, MAX_NODES as i64));
/// `contact.grading`: the edge grading's exponent p of r_i = a0·(1 − (1 − i/N)^p).
pub const GRADING: Bound = bound(
    "contact.grading",
    "–",
    Range::Closed(1.0, crate::grid::Grading::MAX_POWER),
);
/// `drive.stiffness`.
pub const STIFFNESS: Bound = bound("drive.stiffness", "N/m", Range::Positive);
/// `drive.mass`.
pub const MASS: Bound = bound("drive.mass", "kg", Range::Positive);
/// `drive.damping`: c_d of the dashpot parallel to the spring.
pub const DAMPING: Bound = bound("drive.damping", "N·s/m", Range::NonNegative);
/// `drive.velocity`.
pub const VELOCITY: Bound = bound("drive.velocity", "m/s", Range::Finite);
/// `time.end`.
pub const END: Bound = bound("time.end", "s", Range::Positive);
/// `time.dt` (at most `time.end`: a rule).
pub const DT: Bound = bound("time.dt", "s", Range::ByRule);
/// Smallest `time.tolerance`: relative errors below it are beyond what double precision
/// resolves in a step (about 1e-16 per operation, summed over a step's arithmetic), so the
/// error control could not meet them and the steps would shrink to `time.dt_min`.
pub const MIN_TOLERANCE: f64 = 1e-12;
/// `time.tolerance`.
pub const TOLERANCE: Bound = bound("time.tolerance", "–", Range::Open(MIN_TOLERANCE, 1.0));
/// `time.dt_max` (at most `time.end`: a rule).
pub const DT_MAX: Bound = bound("time.dt_max", "s", Range::Positive);
/// `time.dt_min` (at most min(dt, dt_max): a rule).
pub const DT_MIN: Bound = bound("time.dt_min", "s", Range::Positive);
/// `output.event_merge_gap`.
pub const EVENT_MERGE_GAP: Bound = bound("output.event_merge_gap", "s", Range::NonNegative);
/// `output.event_recovery`.
pub const EVENT_RECOVERY: Bound = bound("output.event_recovery", "–", Range::Above(1.0));
/// `numerics.coupling_tol`.
pub const COUPLING_TOL: Bound = bound("numerics.coupling_tol", "–", Range::Open(0.0, 1.0));
/// `numerics.runaway_stress_factor`.
pub const RUNAWAY_STRESS_FACTOR: Bound =
    bound("numerics.runaway_stress_factor", "–", Range::Above(1.0));
/// `numerics.phi_error_floor`.
pub const PHI_ERROR_FLOOR: Bound = bound("numerics.phi_error_floor", "–", Range::Closed(0.0, 1.0));
/// `numerics.event_phi_error_floor`.
pub const EVENT_PHI_ERROR_FLOOR: Bound = bound(
    "numerics.event_phi_error_floor",
    "–",
    Range::Closed(0.0, 1.0),
);
/// `numerics.event_tolerance_factor`: 1 (the same tolerance throughout) up to a factor that
/// still leaves a step's relative error below 1 at the loosest `time.tolerance` worth using.
pub const EVENT_TOLERANCE_FACTOR: Bound = bound(
    "numerics.event_tolerance_factor",
    "–",
    Range::Closed(1.0, 1e4),
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bound_names_key_value_and_range() {
        let e = RADIUS.check(1e16).unwrap_err().to_string();
        assert!(e.contains("contact.radius = 1e16"), "{e}");
        assert!(e.contains("[1e-15, 1e15] m"), "{e}");
        assert!(TOLERANCE.check(1.0).is_err());
        assert!(TOLERANCE.check(0.5).is_ok());
        assert_eq!(human(0.5), "0.5");
        assert_eq!(human(2e-5), "2e-5");
        assert_eq!(human(f64::NEG_INFINITY), "-inf");
    }
}
