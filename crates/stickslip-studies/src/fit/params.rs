//! The free parameters of a fit: `KEY[=LO:HI]`, a scene key that takes a real number, its
//! bounds checked against the key's own range in the registry (`keys/`) and defaulting to the
//! key's usual range. The optimiser works in the unit box: z = (ln v − ln lo)/(ln hi − ln lo)
//! when both bounds are positive (the key is searched in log space: a factor is the same step
//! anywhere in the box), else z = (v − lo)/(hi − lo); one unit of z is the whole bound range,
//! so damping, finite-difference steps and the space-filling sample treat every parameter
//! alike.

use super::error::FitError;
use stickslip_run::keys::{KEYS, ValueType, human};

/// The name in fit.json of the trace misfit's time shift (not a scene key).
pub const TIME_SHIFT: &str = "time_shift";

/// One free parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// The scene key (`lubricant.tau_max`), or [`TIME_SHIFT`].
    pub key: String,
    /// Its unit.
    pub unit: &'static str,
    /// Lower bound, in the unit.
    pub lo: f64,
    /// Upper bound, in the unit.
    pub hi: f64,
    /// Searched in log space (both bounds > 0).
    pub log: bool,
    /// Whether it is a scene key (set on the scene as `--set KEY=VALUE`); false for the time
    /// shift, which moves the model's times.
    pub scene_key: bool,
}

impl Param {
    /// The value at box coordinate `z` (z outside [0, 1] extrapolates the same map, for
    /// intervals that reach past a bound).
    #[must_use]
    pub fn value(&self, z: f64) -> f64 {
        if self.log {
            self.lo * (self.hi / self.lo).powf(z)
        } else {
            self.lo + z * (self.hi - self.lo)
        }
    }

    /// The box coordinate of `v`.
    #[must_use]
    pub fn z(&self, v: f64) -> f64 {
        if self.log {
            (v / self.lo).ln() / (self.hi / self.lo).ln()
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    /// dv/dz at `z`, in the unit.
    #[must_use]
    pub fn slope(&self, z: f64) -> f64 {
        if self.log {
            self.value(z) * (self.hi / self.lo).ln()
        } else {
            self.hi - self.lo
        }
    }

    /// The `--set` text giving the key the value at `z`, in shortest round-trip form.
    #[must_use]
    pub fn setting(&self, z: f64) -> String {
        format!("{}={:e}", self.key, self.value(z))
    }
}

/// Parses `KEY[=LO:HI]`; `current` is the key's value in the scene (the sign of the usual
/// range, which the registry states as absolute values, follows it).
///
/// # Errors
/// [`FitError::Input`] naming `--param`: an unknown key, a key that does not take a real
/// number, bounds that are not numbers, lo ≥ hi, a bound outside the key's range, or a key
/// without a usual range and no bounds given.
pub fn parse(text: &str, current: Option<f64>) -> Result<Param, FitError> {
    let (key, bounds) = match text.split_once('=') {
        Some((k, b)) => (k.trim(), Some(b.trim())),
        None => (text.trim(), None),
    };
    let bad = |value: String, allowed: String| FitError::input("--param", value, allowed);
    let info = KEYS.iter().find(|k| k.path == key).ok_or_else(|| {
        bad(
            key.to_string(),
            "a scene key that takes a number (stickslip keys), as KEY or KEY=LO:HI".into(),
        )
    })?;
    if let Some(section) = ["time.", "output.", "numerics."]
        .iter()
        .find(|s| key.starts_with(**s))
    {
        return Err(bad(
            key.to_string(),
            format!(
                "a physical parameter; the {}* keys are the fit's numerics (it sets time.end \
                 from the trace and tightens time.tolerance itself)",
                section
            ),
        ));
    }
    if info.value != ValueType::Real {
        return Err(bad(
            key.to_string(),
            format!("a key that takes a real number; {key} does not"),
        ));
    }
    let (lo, hi) = match bounds {
        Some(b) => {
            let (lo, hi) = b
                .split_once(':')
                .ok_or_else(|| bad(text.to_string(), "KEY=LO:HI with two numbers".to_string()))?;
            let num = |s: &str| {
                s.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        bad(
                            text.to_string(),
                            format!("finite numbers LO:HI ({s:?} is not)"),
                        )
                    })
            };
            (num(lo)?, num(hi)?)
        }
        None => {
            let (lo, hi) = info.usual.ok_or_else(|| {
                bad(
                    key.to_string(),
                    format!("{key}=LO:HI: the key has no usual range to default to"),
                )
            })?;
            if current.is_some_and(|v| v < 0.0) {
                (-hi, -lo)
            } else {
                (lo, hi)
            }
        }
    };
    if lo >= hi {
        return Err(bad(
            format!("{key}={}:{}", human(lo), human(hi)),
            "LO < HI".into(),
        ));
    }
    for (which, v) in [("lower", lo), ("upper", hi)] {
        if !info.range.contains(v) {
            return Err(bad(
                format!("{key}={}:{}", human(lo), human(hi)),
                format!("a {which} bound within the key's range: {}", info.allowed()),
            ));
        }
    }
    // The box maps z ∈ [0, 1] to lo·(hi/lo)^z (or lo + (hi − lo)·z): both must be finite
    // numbers with room between them.
    let log = lo > 0.0;
    let spread = if log { hi / lo } else { hi - lo };
    if !spread.is_finite() {
        return Err(bad(
            format!("{key}={}:{}", human(lo), human(hi)),
            format!(
                "a range whose {} is a finite number",
                if log {
                    "ratio HI/LO"
                } else {
                    "width HI − LO"
                }
            ),
        ));
    }
    if hi - lo <= MIN_RELATIVE_WIDTH * lo.abs().max(hi.abs()) {
        return Err(bad(
            format!("{key}={}:{}", human(lo), human(hi)),
            format!("HI − LO above {MIN_RELATIVE_WIDTH:e} of the bounds (a range to search)"),
        ));
    }
    Ok(Param {
        key: key.to_string(),
        unit: info.unit,
        lo,
        hi,
        log,
        scene_key: true,
    })
}

/// The narrowest box, relative to its bounds, that the fit searches.
pub const MIN_RELATIVE_WIDTH: f64 = 1e-9;

/// The trace misfit's time shift, within ±`max_s`: the model's F at t + shift is compared with
/// the data's at t.
#[must_use]
pub fn time_shift(max_s: f64) -> Param {
    Param {
        key: TIME_SHIFT.into(),
        unit: "s",
        lo: -max_s,
        hi: max_s,
        log: false,
        scene_key: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_default_to_the_usual_range_and_positive_keys_are_logarithmic() {
        let p = parse("lubricant.tau_max=1e5:1e7", None).unwrap();
        assert!(p.log);
        assert!((p.value(0.5) - 1e6).abs() < 1e-6);
        assert!((p.z(1e6) - 0.5).abs() < 1e-12);
        let q = parse("lubricant.tau_max", None).unwrap();
        assert!(q.lo > 0.0 && q.lo < q.hi);
        let s = time_shift(1e-6);
        assert!(!s.log && s.value(0.5) == 0.0);
        assert_eq!(p.setting(0.5), "lubricant.tau_max=1e6");
    }

    #[test]
    fn bad_parameters_name_the_field() {
        for (text, part) in [
            (
                "lubricant.nope",
                "lubricant.nope is invalid; allowed: a scene key",
            ),
            ("contact.nodes=10:20", "takes a real number"),
            ("lubricant.tau_max=2e6:1e6", "LO < HI"),
            (
                "lubricant.tau_max=-1:1e6",
                "lower bound within the key's range",
            ),
            ("lubricant.tau_max=1:x", "finite numbers"),
            ("lubricant.tau_max=1e6", "KEY=LO:HI"),
            (
                "time.tolerance=1e-6:1e-4",
                "the time.* keys are the fit's numerics",
            ),
            (
                "time.end=1e-4:1e-2",
                "the time.* keys are the fit's numerics",
            ),
            ("numerics.coupling_tol=1e-9:1e-6", "numerics.* keys"),
            (
                "lubricant.gamma=1e-300:1e300",
                "ratio HI/LO is a finite number",
            ),
            (
                "temperature.A0=-1.5e308:1.5e308",
                "width HI − LO is a finite number",
            ),
            (
                "lubricant.tau_max=1e6:1.0000000000000002e6",
                "HI − LO above",
            ),
        ] {
            let e = parse(text, None).unwrap_err().to_string();
            assert!(e.starts_with("--param = "), "{e}");
            assert!(e.contains(part), "{text}: {e}");
        }
    }
}
