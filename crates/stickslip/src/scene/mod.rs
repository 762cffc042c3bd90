//! Scenes: parse the TOML, apply `--set` overrides, fill in the defaults, validate, and hand back
//! a [`ResolvedScene`] (the engine's [`SimConfig`] plus the output settings).
//!
//! Pipeline (each stage stops at the first problem, as a [`SceneError`] naming the key, the
//! value and the allowed range; nothing here panics on any input):
//! 1. the text is parsed as a TOML table;
//! 2. `--set` overrides are applied to the table ([`overrides`]);
//! 3. the table is deserialized into [`Scene`] (unknown keys and wrong types are rejected);
//! 4. required keys, defaults and cross-key rules are resolved ([`resolve`]);
//! 5. [`SimConfig::validate`] and the scene-level checks (output times and radii, step count,
//!    no non-finite number anywhere) run.
//!
//! Defaults (documented in INTERFACE.md or added here): see the `DEFAULT_*` constants.

pub mod error;
pub mod file;
pub mod overrides;

pub use error::SceneError;
pub use file::{
    ContactSection, DriveSection, LubricantSection, NoiseSection, NumericsSection, OutputSection,
    Scene, TemperatureSection, TimeSection,
};

use stickslip_core::config::{
    AdaptiveConfig, ContactConfig, ContactModel, Derived, MAX_NODES, NumericsConfig, Scheme,
    SimConfig, Substrate, TimeConfig,
};
use stickslip_core::drive::{Drive, Integrator, RigidDrive, SpringDrive};
use stickslip_core::landau::{LandauParams, Temperature};
use stickslip_core::mdr::OperatorForm;
use stickslip_core::noise::NoiseKind;

/// Default `lubricant.melt_threshold`.
pub const DEFAULT_MELT_THRESHOLD: f64 = 0.01;
/// Default `lubricant.noise.kind`.
pub const DEFAULT_NOISE_KIND: &str = "floor";
/// Default `lubricant.noise.floor` (kind `"floor"`): deterministic, draws no random numbers.
pub const DEFAULT_NOISE_FLOOR: f64 = 1e-6;
/// Default `lubricant.noise.sigma` (kind `"gaussian"`), s^-1/2.
pub const DEFAULT_NOISE_SIGMA_PER_SQRT_S: f64 = 1.0;
/// Default `lubricant.noise.seed` (kind `"gaussian"`).
pub const DEFAULT_NOISE_SEED: i64 = 1;
/// Default `contact.nodes`.
pub const DEFAULT_NODES: i64 = 2000;
/// Default `time.dt`, s.
pub const DEFAULT_DT_S: f64 = 1e-8;
/// Default `time.tolerance` (adaptive stepping): fig2 onsets within 0.01 µs of the converged
/// reference at N = 125 (reports/performance.md).
pub const DEFAULT_TOLERANCE: f64 = 1e-4;
/// Default `time.dt_max` as a fraction of `time.end`.
pub const DEFAULT_DT_MAX_FRACTION: f64 = 1e-3;
/// Default `time.dt_min` as a fraction of min(`time.dt`, `time.dt_max`).
pub const DEFAULT_DT_MIN_FRACTION: f64 = 1e-6;
/// Default `output.event_merge_gap`, s.
pub const DEFAULT_EVENT_MERGE_GAP_S: f64 = 1e-5;
/// Default `output.series_interval`, s.
pub const DEFAULT_SERIES_INTERVAL_S: f64 = 1e-7;
/// Largest number of steps a scene may ask for (time.end / time.dt).
pub const MAX_STEPS: f64 = 1e12;

/// What the runner records, besides the simulation itself.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputSettings {
    /// Times of the profiles, s, as given (each within [0, time.end]).
    pub profile_times_s: Vec<f64>,
    /// Radii of the φ(t) probes, m, as given (each within [0, a0)).
    pub probe_radii_m: Vec<f64>,
    /// Merge gap of melting events, s (≥ 0).
    pub event_merge_gap_s: f64,
    /// Interval between rows of series.csv and probes.csv, s (> 0).
    pub series_interval_s: f64,
}

/// A validated scene, ready to run.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedScene {
    /// The scene's `name`.
    pub name: String,
    /// The engine configuration.
    pub config: SimConfig,
    /// Output settings.
    pub output: OutputSettings,
    /// The scene with every default filled in (written to run.json, printed by `check`).
    pub resolved: Scene,
    /// Derived parameters b, A, εc, φ0, ω.
    pub derived: Derived,
    /// Number of steps: ⌈end/dt − 1e-9⌉, all of length dt except the last, which lands on end
    /// (fixed stepping; with adaptive steps only a scale for the progress bar).
    pub steps: u64,
}

/// Number of steps for `end_s` and `dt_s`: ⌈end/dt − 1e-9⌉, at least 1.
pub fn step_count(end_s: f64, dt_s: f64) -> u64 {
    let n = (end_s / dt_s - 1e-9).ceil();
    if n.is_finite() && n >= 1.0 {
        // Validation caps end/dt at MAX_STEPS, far inside u64.
        n as u64
    } else {
        1
    }
}

impl Scene {
    /// Reads a scene file as UTF-8 text.
    ///
    /// # Errors
    /// [`SceneError::Read`] if the file cannot be read or is not UTF-8.
    pub fn read_text(path: &std::path::Path) -> Result<String, SceneError> {
        let bytes = std::fs::read(path).map_err(|e| SceneError::Read {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        String::from_utf8(bytes).map_err(|e| SceneError::Read {
            path: path.display().to_string(),
            message: format!("not UTF-8 text ({e})"),
        })
    }

    /// Parses `text`, applies `overrides` (`section.key=value`, in order), resolves defaults and
    /// validates.
    ///
    /// # Errors
    /// The first problem, as a [`SceneError`] naming key, value and allowed range.
    pub fn from_toml_str<S: AsRef<str>>(
        text: &str,
        overrides: &[S],
    ) -> Result<ResolvedScene, SceneError> {
        let mut root: toml::Table = text.parse().map_err(|e| syntax_error(text, &e))?;
        for o in overrides {
            overrides::apply_override(&mut root, o.as_ref())?;
        }
        error::check_sections(&root)?;
        let scene: Scene = root
            .clone()
            .try_into()
            .map_err(|e| error::from_de_error(&root, &e))?;
        let resolved = resolve(&scene)?;
        check_finite(&root, &mut Vec::new())?;
        Ok(resolved)
    }

    /// [`Scene::read_text`] then [`Scene::from_toml_str`].
    ///
    /// # Errors
    /// As those two.
    pub fn from_path<S: AsRef<str>>(
        path: &std::path::Path,
        overrides: &[S],
    ) -> Result<ResolvedScene, SceneError> {
        Self::from_toml_str(&Self::read_text(path)?, overrides)
    }
}

impl Scene {
    /// The scene as TOML text, numbers in shortest round-trip `{:e}` form (e.g. `1e-8`); the
    /// text parses back to the same scene.
    pub fn to_toml_string(&self) -> String {
        let mut out = String::new();
        match toml::Table::try_from(self) {
            Ok(t) => emit_table(&mut out, &mut Vec::new(), &t),
            Err(e) => out.push_str(&format!("# cannot print the scene: {e}\n")),
        }
        out
    }
}

fn emit_key(out: &mut String, k: &str) {
    if !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        out.push_str(k);
    } else {
        out.push_str(&toml::Value::String(k.to_string()).to_string());
    }
}

fn emit_value(out: &mut String, v: &toml::Value) {
    match v {
        toml::Value::Float(f) => out.push_str(&error::format_float(*f)),
        toml::Value::Array(a) => {
            out.push('[');
            for (i, x) in a.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                emit_value(out, x);
            }
            out.push(']');
        }
        toml::Value::Table(t) => {
            out.push('{');
            for (i, (k, x)) in t.iter().enumerate() {
                out.push_str(if i > 0 { ", " } else { " " });
                emit_key(out, k);
                out.push_str(" = ");
                emit_value(out, x);
            }
            out.push_str(" }");
        }
        other => out.push_str(&other.to_string()),
    }
}

fn emit_table(out: &mut String, path: &mut Vec<String>, t: &toml::Table) {
    for (k, v) in t.iter().filter(|(_, v)| !v.is_table()) {
        emit_key(out, k);
        out.push_str(" = ");
        emit_value(out, v);
        out.push('\n');
    }
    for (k, v) in t {
        if let toml::Value::Table(sub) = v {
            path.push(k.clone());
            out.push_str("\n[");
            for (i, p) in path.iter().enumerate() {
                if i > 0 {
                    out.push('.');
                }
                emit_key(out, p);
            }
            out.push_str("]\n");
            emit_table(out, path, sub);
            path.pop();
        }
    }
}

fn syntax_error(text: &str, e: &toml::de::Error) -> SceneError {
    let start = e.span().map_or(0, |s| s.start).min(text.len());
    let before = &text.as_bytes()[..start];
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    let rest = &text.as_bytes()[line_start..];
    let line_end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
    let excerpt = String::from_utf8_lossy(&rest[..line_end]);
    SceneError::Syntax {
        line,
        column,
        message: error::shorten(e.message().trim()),
        excerpt: error::shorten(excerpt.trim()),
    }
}

/// Rejects NaN and infinities anywhere in the table (after the specific checks, so a value that
/// has its own range gets that range in the message).
fn check_finite(v: &toml::Table, path: &mut Vec<String>) -> Result<(), SceneError> {
    for (k, x) in v {
        path.push(k.clone());
        check_finite_value(x, path)?;
        path.pop();
    }
    Ok(())
}

fn check_finite_value(x: &toml::Value, path: &mut Vec<String>) -> Result<(), SceneError> {
    match x {
        toml::Value::Float(f) if !f.is_finite() => Err(SceneError::invalid(
            &path.join("."),
            error::human(*f),
            "a finite number",
        )),
        toml::Value::Table(t) => check_finite(t, path),
        toml::Value::Array(a) => a.iter().try_for_each(|y| check_finite_value(y, path)),
        _ => Ok(()),
    }
}

/// Quotes a string for messages.
fn q(s: &str) -> String {
    format!("{:?}", error::shorten(s))
}

fn required(v: Option<f64>, key: &str, allowed: &str) -> Result<f64, SceneError> {
    v.ok_or_else(|| SceneError::missing(key, allowed))
}

fn choice(
    v: Option<&String>,
    key: &str,
    default: &'static str,
    options: &[&'static str],
) -> Result<&'static str, SceneError> {
    match v {
        None => Ok(default),
        Some(s) => options.iter().copied().find(|o| o == s).ok_or_else(|| {
            SceneError::invalid(
                key,
                q(s),
                format!(
                    "one of {}",
                    options
                        .iter()
                        .map(|o| format!("{o:?}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )
        }),
    }
}

fn contradiction(
    key: &str,
    value: Option<f64>,
    other: &str,
    allowed: &str,
) -> Result<(), SceneError> {
    match value {
        Some(v) => Err(SceneError::Contradictory {
            key: key.to_string(),
            value: error::human(v),
            other: other.to_string(),
            allowed: allowed.to_string(),
        }),
        None => Ok(()),
    }
}

fn positive(key: &str, v: f64, unit: &str) -> Result<(), SceneError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            key,
            error::human(v),
            format!("finite and > 0{unit}"),
        ))
    }
}

/// Resolves the lubricant's noise section into the engine's kind and its filled-in section.
fn resolve_noise(n: &NoiseSection) -> Result<(NoiseKind, NoiseSection), SceneError> {
    let kind = choice(
        n.kind.as_ref(),
        "lubricant.noise.kind",
        DEFAULT_NOISE_KIND,
        &["gaussian", "floor", "off"],
    )?;
    let other = format!("lubricant.noise.kind = {kind:?}");
    let seed_as_f64 = n.seed.map(|s| s as f64);
    match kind {
        "gaussian" => {
            contradiction(
                "lubricant.noise.floor",
                n.floor,
                &other,
                "floor only with kind = \"floor\"",
            )?;
            let sigma = n.sigma.unwrap_or(DEFAULT_NOISE_SIGMA_PER_SQRT_S);
            let seed = n.seed.unwrap_or(DEFAULT_NOISE_SEED);
            if seed < 0 {
                return Err(SceneError::invalid(
                    "lubricant.noise.seed",
                    seed,
                    format!("an integer in 0 ..= {}", i64::MAX),
                ));
            }
            Ok((
                NoiseKind::Gaussian {
                    sigma_per_sqrt_s: sigma,
                    seed: seed as u64,
                },
                NoiseSection {
                    kind: Some(kind.to_string()),
                    sigma: Some(sigma),
                    floor: None,
                    seed: Some(seed),
                },
            ))
        }
        "floor" => {
            let allowed = "sigma and seed only with kind = \"gaussian\"";
            contradiction("lubricant.noise.sigma", n.sigma, &other, allowed)?;
            contradiction("lubricant.noise.seed", seed_as_f64, &other, allowed)?;
            let floor = n.floor.unwrap_or(DEFAULT_NOISE_FLOOR);
            Ok((
                NoiseKind::Floor { floor },
                NoiseSection {
                    kind: Some(kind.to_string()),
                    floor: Some(floor),
                    ..NoiseSection::default()
                },
            ))
        }
        _ => {
            let allowed = "no sigma, floor or seed with kind = \"off\"";
            contradiction("lubricant.noise.sigma", n.sigma, &other, allowed)?;
            contradiction("lubricant.noise.floor", n.floor, &other, allowed)?;
            contradiction("lubricant.noise.seed", seed_as_f64, &other, allowed)?;
            Ok((
                NoiseKind::Off,
                NoiseSection {
                    kind: Some(kind.to_string()),
                    ..NoiseSection::default()
                },
            ))
        }
    }
}

fn resolve_temperature(
    t: &TemperatureSection,
    lubricant: &LandauParams,
) -> Result<(Temperature, TemperatureSection), SceneError> {
    let law = choice(
        t.law.as_ref(),
        "temperature.law",
        "constant",
        &["constant", "relaxation"],
    )?;
    match law {
        "constant" => {
            contradiction(
                "temperature.t_relax",
                t.t_relax,
                "temperature.law = \"constant\"",
                "t_relax only with law = \"relaxation\"",
            )?;
            let a = t.a0.unwrap_or_else(|| lubricant.a_coeff_default_pa());
            Ok((
                Temperature::Constant { a_coeff_pa: a },
                TemperatureSection {
                    law: Some(law.to_string()),
                    a0: Some(a),
                    t_relax: None,
                },
            ))
        }
        _ => {
            let a0 = required(
                t.a0,
                "temperature.A0",
                "a finite number of Pa (required when temperature.law = \"relaxation\")",
            )?;
            let t_relax = required(
                t.t_relax,
                "temperature.t_relax",
                "finite and > 0 s (required when temperature.law = \"relaxation\")",
            )?;
            Ok((
                Temperature::Relaxation {
                    a0_pa: a0,
                    t_relax_s: t_relax,
                },
                TemperatureSection {
                    law: Some(law.to_string()),
                    a0: Some(a0),
                    t_relax: Some(t_relax),
                },
            ))
        }
    }
}

/// G* from g_eff or from g1, nu1, g2, nu2 by Eq. 9: G* = ((2−ν1)/(4G1) + (2−ν2)/(4G2))^−1.
fn resolve_modulus(c: &ContactSection) -> Result<f64, SceneError> {
    let pair = [
        ("contact.g1", c.g1),
        ("contact.nu1", c.nu1),
        ("contact.g2", c.g2),
        ("contact.nu2", c.nu2),
    ];
    if let Some(g) = c.g_eff {
        if let Some((key, Some(v))) = pair.iter().find(|(_, v)| v.is_some()) {
            return Err(SceneError::Contradictory {
                key: (*key).to_string(),
                value: error::human(*v),
                other: format!("contact.g_eff = {}", error::human(g)),
                allowed: "either g_eff or all of g1, nu1, g2, nu2 (Eq. 9), not both".to_string(),
            });
        }
        return Ok(g);
    }
    if pair.iter().all(|(_, v)| v.is_none()) {
        return Err(SceneError::missing(
            "contact.g_eff",
            "finite and > 0 Pa (or all of contact.g1, nu1, g2, nu2 by Eq. 9)",
        ));
    }
    if let Some((key, _)) = pair.iter().find(|(_, v)| v.is_none()) {
        return Err(SceneError::missing(
            key,
            "all of contact.g1, nu1, g2, nu2 together (Eq. 9), or contact.g_eff alone",
        ));
    }
    let [g1, nu1, g2, nu2] = pair.map(|(_, v)| v.unwrap_or(f64::NAN));
    positive("contact.g1", g1, " Pa")?;
    positive("contact.g2", g2, " Pa")?;
    for (key, nu) in [("contact.nu1", nu1), ("contact.nu2", nu2)] {
        if !(nu > -1.0 && nu <= 0.5) {
            return Err(SceneError::invalid(key, error::human(nu), "-1 < nu <= 0.5"));
        }
    }
    Ok(1.0 / ((2.0 - nu1) / (4.0 * g1) + (2.0 - nu2) / (4.0 * g2)))
}

fn resolve_drive(d: &DriveSection) -> Result<(Drive, Integrator, DriveSection), SceneError> {
    let kind = choice(
        d.kind.as_ref(),
        "drive.kind",
        "spring",
        &["spring", "rigid"],
    )?;
    let velocity = required(d.velocity, "drive.velocity", "a finite number of m/s")?;
    let integrator_name = choice(
        d.integrator.as_ref(),
        "drive.integrator",
        "verlet",
        &["verlet", "rk4"],
    )?;
    let integrator = if integrator_name == "rk4" {
        Integrator::Rk4
    } else {
        Integrator::Verlet
    };
    let mut section = DriveSection {
        kind: Some(kind.to_string()),
        stiffness: None,
        mass: None,
        velocity: Some(velocity),
        integrator: Some(integrator_name.to_string()),
    };
    let drive = if kind == "spring" {
        let stiffness = required(
            d.stiffness,
            "drive.stiffness",
            "finite and > 0 N/m; drive.stiffness is required when drive.kind = \"spring\"",
        )?;
        let mass = required(
            d.mass,
            "drive.mass",
            "finite and > 0 kg; drive.mass is required when drive.kind = \"spring\"",
        )?;
        section.stiffness = Some(stiffness);
        section.mass = Some(mass);
        Drive::Spring(SpringDrive {
            stiffness_n_per_m: stiffness,
            mass_kg: mass,
            velocity_m_per_s: velocity,
        })
    } else {
        let allowed = "no stiffness or mass with the rigid drive (X = V0·t)";
        contradiction(
            "drive.stiffness",
            d.stiffness,
            "drive.kind = \"rigid\"",
            allowed,
        )?;
        contradiction("drive.mass", d.mass, "drive.kind = \"rigid\"", allowed)?;
        Drive::Rigid(RigidDrive {
            velocity_m_per_s: velocity,
        })
    };
    Ok((drive, integrator, section))
}

/// Fills in defaults, applies the cross-key rules and validates a deserialized scene.
///
/// # Errors
/// The first problem found.
pub fn resolve(scene: &Scene) -> Result<ResolvedScene, SceneError> {
    let name = scene
        .name
        .clone()
        .ok_or_else(|| SceneError::missing("name", "a non-empty string"))?;
    if name.trim().is_empty() {
        return Err(SceneError::invalid("name", q(&name), "a non-empty string"));
    }

    let l = scene.lubricant.clone().unwrap_or_default();
    let lubricant = LandauParams {
        tau_max_pa: required(l.tau_max, "lubricant.tau_max", "finite and > 0 Pa")?,
        eps_max: required(l.eps_max, "lubricant.eps_max", "finite and > 0")?,
        a_pa: required(l.a, "lubricant.a", "finite and > 0 Pa")?,
        gamma_per_pa_s: required(l.gamma, "lubricant.gamma", "finite and > 0 1/(Pa·s)")?,
    };
    let melt_threshold = l.melt_threshold.unwrap_or(DEFAULT_MELT_THRESHOLD);
    let (noise, noise_section) = resolve_noise(&l.noise.clone().unwrap_or_default())?;
    let (temperature, temperature_section) =
        resolve_temperature(&scene.temperature.clone().unwrap_or_default(), &lubricant)?;

    let c = scene.contact.clone().unwrap_or_default();
    let radius = required(c.radius, "contact.radius", "finite and > 0 m")?;
    let film_thickness = required(
        c.film_thickness,
        "contact.film_thickness",
        "finite and > 0 m",
    )?;
    let g_eff = resolve_modulus(&c)?;
    let nodes = c.nodes.unwrap_or(DEFAULT_NODES);
    if nodes < 1 || nodes > MAX_NODES as i64 {
        return Err(SceneError::invalid(
            "contact.nodes",
            nodes,
            format!("an integer in 1 ..= {MAX_NODES}"),
        ));
    }
    let model_name = choice(
        c.model.as_ref(),
        "contact.model",
        "radial",
        &["radial", "homogeneous"],
    )?;
    let substrate_name = choice(
        c.substrate.as_ref(),
        "contact.substrate",
        "elastic",
        &["elastic", "rigid"],
    )?;

    let (drive, integrator, drive_section) =
        resolve_drive(&scene.drive.clone().unwrap_or_default())?;

    let t = scene.time.clone().unwrap_or_default();
    let end = required(t.end, "time.end", "finite and > 0 s")?;
    let dt = t.dt.unwrap_or(DEFAULT_DT_S);
    let scheme_name = choice(
        t.scheme.as_ref(),
        "time.scheme",
        "accurate",
        &["accurate", "literal"],
    )?;

    let gaussian = matches!(noise, NoiseKind::Gaussian { .. });
    let default_stepping = if scheme_name == "accurate" && !gaussian {
        "adaptive"
    } else {
        "fixed"
    };
    let stepping_name = choice(
        t.stepping.as_ref(),
        "time.stepping",
        default_stepping,
        &["adaptive", "fixed"],
    )?;
    let adaptive = if stepping_name == "adaptive" {
        let dt_max = t.dt_max.unwrap_or(DEFAULT_DT_MAX_FRACTION * end);
        Some(AdaptiveConfig {
            tolerance: t.tolerance.unwrap_or(DEFAULT_TOLERANCE),
            dt_max_s: dt_max,
            dt_min_s: t.dt_min.unwrap_or(DEFAULT_DT_MIN_FRACTION * dt.min(dt_max)),
        })
    } else {
        let other = "time.stepping = \"fixed\"";
        let allowed = "only with time.stepping = \"adaptive\"";
        contradiction("time.tolerance", t.tolerance, other, allowed)?;
        contradiction("time.dt_max", t.dt_max, other, allowed)?;
        contradiction("time.dt_min", t.dt_min, other, allowed)?;
        None
    };

    let nm = scene.numerics.clone().unwrap_or_default();
    let defaults = NumericsConfig::default();
    let operator_name = choice(
        nm.operator.as_ref(),
        "numerics.operator",
        "auto",
        &["auto", "fast", "dense"],
    )?;
    let numerics = NumericsConfig {
        coupling_tol: nm.coupling_tol.unwrap_or(defaults.coupling_tol),
        runaway_stress_factor: nm
            .runaway_stress_factor
            .unwrap_or(defaults.runaway_stress_factor),
        operator: match operator_name {
            "fast" => Some(OperatorForm::Fast),
            "dense" => Some(OperatorForm::Dense),
            _ => None,
        },
    };

    let config = SimConfig {
        lubricant,
        melt_threshold,
        noise,
        temperature,
        contact: ContactConfig {
            radius_m: radius,
            film_thickness_m: film_thickness,
            g_eff_pa: g_eff,
            nodes: nodes as usize,
            model: if model_name == "homogeneous" {
                ContactModel::Homogeneous
            } else {
                ContactModel::Radial
            },
            substrate: if substrate_name == "rigid" {
                Substrate::Rigid
            } else {
                Substrate::Elastic
            },
        },
        drive,
        integrator,
        time: TimeConfig {
            end_s: end,
            dt_s: dt,
            scheme: if scheme_name == "literal" {
                Scheme::Literal
            } else {
                Scheme::Accurate
            },
            adaptive,
        },
        numerics,
    };
    config.validate()?;
    if end / dt > MAX_STEPS {
        return Err(SceneError::invalid(
            "time.dt",
            error::human(dt),
            format!(
                "finite, > 0 and >= time.end / {MAX_STEPS:e} = {:e} s (at most {MAX_STEPS:e} steps)",
                end / MAX_STEPS
            ),
        ));
    }

    let o = scene.output.clone().unwrap_or_default();
    let profile_times = o.profile_times.clone().unwrap_or_else(|| vec![end]);
    if let Some(bad) = profile_times
        .iter()
        .find(|&&p| !(p.is_finite() && (0.0..=end).contains(&p)))
    {
        return Err(SceneError::invalid(
            "output.profile_times",
            error::human(*bad),
            format!("each within [0, time.end = {end:e}] s"),
        ));
    }
    let probe_radii = o.probe_radii.clone().unwrap_or_default();
    if let Some(bad) = probe_radii
        .iter()
        .find(|&&r| !(r.is_finite() && r >= 0.0 && r < radius))
    {
        return Err(SceneError::invalid(
            "output.probe_radii",
            error::human(*bad),
            format!("each within [0, contact.radius = {radius:e}) m"),
        ));
    }
    let merge_gap = o.event_merge_gap.unwrap_or(DEFAULT_EVENT_MERGE_GAP_S);
    if !(merge_gap.is_finite() && merge_gap >= 0.0) {
        return Err(SceneError::invalid(
            "output.event_merge_gap",
            error::human(merge_gap),
            "finite and >= 0 s",
        ));
    }
    let series_interval = o.series_interval.unwrap_or(DEFAULT_SERIES_INTERVAL_S);
    positive("output.series_interval", series_interval, " s")?;

    let resolved = Scene {
        name: Some(name.clone()),
        lubricant: Some(LubricantSection {
            tau_max: Some(lubricant.tau_max_pa),
            eps_max: Some(lubricant.eps_max),
            a: Some(lubricant.a_pa),
            gamma: Some(lubricant.gamma_per_pa_s),
            melt_threshold: Some(melt_threshold),
            noise: Some(noise_section),
        }),
        temperature: Some(temperature_section),
        contact: Some(ContactSection {
            radius: Some(radius),
            film_thickness: Some(film_thickness),
            g_eff: c.g_eff.or(if c.g1.is_some() { None } else { Some(g_eff) }),
            g1: c.g1,
            nu1: c.nu1,
            g2: c.g2,
            nu2: c.nu2,
            nodes: Some(nodes),
            model: Some(model_name.to_string()),
            substrate: Some(substrate_name.to_string()),
        }),
        drive: Some(drive_section),
        time: Some(TimeSection {
            end: Some(end),
            dt: Some(dt),
            scheme: Some(scheme_name.to_string()),
            stepping: Some(stepping_name.to_string()),
            tolerance: adaptive.map(|a| a.tolerance),
            dt_max: adaptive.map(|a| a.dt_max_s),
            dt_min: adaptive.map(|a| a.dt_min_s),
        }),
        output: Some(OutputSection {
            profile_times: Some(profile_times.clone()),
            probe_radii: Some(probe_radii.clone()),
            event_merge_gap: Some(merge_gap),
            series_interval: Some(series_interval),
        }),
        numerics: Some(NumericsSection {
            coupling_tol: Some(numerics.coupling_tol),
            runaway_stress_factor: Some(numerics.runaway_stress_factor),
            operator: Some(operator_name.to_string()),
        }),
    };
    let derived = Derived::of(&config);
    Ok(ResolvedScene {
        name,
        steps: step_count(end, dt),
        config,
        output: OutputSettings {
            profile_times_s: profile_times,
            probe_radii_m: probe_radii,
            event_merge_gap_s: merge_gap,
            series_interval_s: series_interval,
        },
        resolved,
        derived,
    })
}
