//! Step 4 of scene resolution: required keys, defaults, rules between keys, and the single-key
//! ranges of the key table, turning a deserialized [`Scene`] into a [`ResolvedScene`].

use super::error::{self, SceneError};
use super::file::{DriveKind, NoiseKindName, OperatorChoice, Stepping, TemperatureLaw};
use super::{
    ContactSection, DEFAULT_DT_MAX_FRACTION, DEFAULT_DT_MIN_FRACTION, DEFAULT_DT_S,
    DEFAULT_EVENT_MERGE_GAP_S, DEFAULT_EVENT_RECOVERY, DEFAULT_MELT_THRESHOLD, DEFAULT_NODES,
    DEFAULT_NOISE_FLOOR, DEFAULT_NOISE_SEED, DEFAULT_NOISE_SIGMA_PER_SQRT_S,
    DEFAULT_SERIES_INTERVAL_S, DEFAULT_TOLERANCE, DriveSection, LubricantSection, MAX_STEPS,
    NoiseSection, NumericsSection, OutputSection, OutputSettings, ResolvedScene, Scene,
    TemperatureSection, TimeSection, step_count,
};
use crate::keys;
use stickslip_core::config::{
    AdaptiveConfig, ContactConfig, ContactModel, Derived, EventConfig, NumericsConfig, Scheme,
    SimConfig, Substrate, TimeConfig,
};
use stickslip_core::drive::{Drive, Integrator, RigidDrive, SpringDrive};
use stickslip_core::landau::{LandauParams, Temperature};
use stickslip_core::mdr::OperatorForm;
use stickslip_core::noise::NoiseKind;

/// The key's value, or a [`SceneError::MissingKey`] with the table's allowed range.
fn required(v: Option<f64>, key: &str) -> Result<f64, SceneError> {
    v.ok_or_else(|| SceneError::missing(key, keys::key(key).allowed()))
        .and_then(|v| keys::check(key, v))
}

/// The key's value checked against the table, or `default`.
fn or_default(v: Option<f64>, key: &str, default: f64) -> Result<f64, SceneError> {
    keys::check(key, v.unwrap_or(default))
}

/// A value that the other keys exclude.
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

/// The word of a choice key as written in a scene.
fn word<T: serde::Serialize>(v: T) -> String {
    match toml::Value::try_from(v) {
        Ok(toml::Value::String(s)) => s,
        _ => String::new(),
    }
}

/// Resolves the lubricant's noise section into the engine's kind and its filled-in section.
fn resolve_noise(n: &NoiseSection) -> Result<(NoiseKind, NoiseSection), SceneError> {
    let kind = n.kind.unwrap_or(NoiseKindName::Floor);
    let other = format!("lubricant.noise.kind = {:?}", word(kind));
    let seed_as_f64 = n.seed.map(|s| s as f64);
    match kind {
        NoiseKindName::Gaussian => {
            contradiction(
                "lubricant.noise.floor",
                n.floor,
                &other,
                "floor only with kind = \"floor\"",
            )?;
            let sigma = or_default(
                n.sigma,
                "lubricant.noise.sigma",
                DEFAULT_NOISE_SIGMA_PER_SQRT_S,
            )?;
            let seed = n.seed.unwrap_or(DEFAULT_NOISE_SEED);
            if seed < 0 {
                return Err(SceneError::invalid(
                    "lubricant.noise.seed",
                    seed,
                    keys::key("lubricant.noise.seed").allowed(),
                ));
            }
            Ok((
                NoiseKind::Gaussian {
                    sigma_per_sqrt_s: sigma,
                    seed: seed.unsigned_abs(),
                },
                NoiseSection {
                    kind: Some(kind),
                    sigma: Some(sigma),
                    floor: None,
                    seed: Some(seed),
                },
            ))
        }
        NoiseKindName::Floor => {
            let allowed = "sigma and seed only with kind = \"gaussian\"";
            contradiction("lubricant.noise.sigma", n.sigma, &other, allowed)?;
            contradiction("lubricant.noise.seed", seed_as_f64, &other, allowed)?;
            let floor = n.floor.unwrap_or(DEFAULT_NOISE_FLOOR);
            Ok((
                NoiseKind::Floor { floor },
                NoiseSection {
                    kind: Some(kind),
                    floor: Some(floor),
                    ..NoiseSection::default()
                },
            ))
        }
        NoiseKindName::Off => {
            let allowed = "no sigma, floor or seed with kind = \"off\"";
            contradiction("lubricant.noise.sigma", n.sigma, &other, allowed)?;
            contradiction("lubricant.noise.floor", n.floor, &other, allowed)?;
            contradiction("lubricant.noise.seed", seed_as_f64, &other, allowed)?;
            Ok((
                NoiseKind::Off,
                NoiseSection {
                    kind: Some(kind),
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
    let law = t.law.unwrap_or(TemperatureLaw::Constant);
    match law {
        TemperatureLaw::Constant => {
            contradiction(
                "temperature.t_relax",
                t.t_relax,
                "temperature.law = \"constant\"",
                "t_relax only with law = \"relaxation\"",
            )?;
            let a = or_default(t.a0, "temperature.A0", lubricant.a_coeff_default_pa())?;
            Ok((
                Temperature::Constant { a_coeff_pa: a },
                TemperatureSection {
                    law: Some(law),
                    a0: Some(a),
                    t_relax: None,
                },
            ))
        }
        TemperatureLaw::Relaxation => {
            let a0 = t.a0.ok_or_else(|| {
                SceneError::missing(
                    "temperature.A0",
                    "a finite number of Pa (required when temperature.law = \"relaxation\")",
                )
            })?;
            let a0 = keys::check("temperature.A0", a0)?;
            let t_relax = t.t_relax.ok_or_else(|| {
                SceneError::missing(
                    "temperature.t_relax",
                    "finite and > 0 s (required when temperature.law = \"relaxation\")",
                )
            })?;
            let t_relax = keys::check("temperature.t_relax", t_relax)?;
            Ok((
                Temperature::Relaxation {
                    a0_pa: a0,
                    t_relax_s: t_relax,
                },
                TemperatureSection {
                    law: Some(law),
                    a0: Some(a0),
                    t_relax: Some(t_relax),
                },
            ))
        }
    }
}

/// b₃ of the first-order film (docs/model.md#the-first-order-film) from `lubricant.cubic` or
/// from `lubricant.eps_melt` (never both): b₃ = 2·√(a·b·(ε₊² − εc²)), εc at the initial
/// temperature A(0). b₃ is a material constant, converted once; with a temperature law the
/// melting strain then follows A(t) (ε₊² − εc² stays b₃²/(4ab)).
fn resolve_cubic(
    l: &LubricantSection,
    lubricant: LandauParams,
    temperature: &Temperature,
) -> Result<LandauParams, SceneError> {
    if let (Some(cubic), Some(eps_melt)) = (l.cubic, l.eps_melt) {
        return Err(SceneError::Contradictory {
            key: "lubricant.eps_melt".to_string(),
            value: error::human(eps_melt),
            other: format!("lubricant.cubic = {}", error::human(cubic)),
            allowed: "either lubricant.cubic (b3) or lubricant.eps_melt (the melting strain it \
                      gives), not both"
                .to_string(),
        });
    }
    let cubic = match (l.cubic, l.eps_melt) {
        (Some(cubic), _) => keys::check("lubricant.cubic", cubic)?,
        (None, Some(eps_melt)) => {
            let a0 = temperature.a_coeff_pa(0.0);
            let eps_c = lubricant.critical_strain(a0);
            lubricant
                .cubic_for_melting_strain(eps_melt, a0)
                .ok_or_else(|| {
                    SceneError::invalid(
                        "lubricant.eps_melt",
                        error::human(eps_melt),
                        format!(
                            "finite and > eps_c = {} (√(A0·b)/a at the initial temperature, \
                             temperature.A0 = {} Pa; 0 when A0 <= 0); not with lubricant.cubic",
                            error::human(eps_c),
                            error::human(a0)
                        ),
                    )
                })?
        }
        (None, None) => 0.0,
    };
    // -0 is 0: the second-order film.
    Ok(LandauParams {
        cubic_pa: if cubic == 0.0 { 0.0 } else { cubic },
        ..lubricant
    })
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
        return keys::check("contact.g_eff", g);
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
    let [g1, nu1, g2, nu2] = pair.map(|(key, v)| keys::check(key, v.unwrap_or(f64::NAN)));
    let (g1, nu1, g2, nu2) = (g1?, nu1?, g2?, nu2?);
    keys::check(
        "contact.g_eff",
        1.0 / ((2.0 - nu1) / (4.0 * g1) + (2.0 - nu2) / (4.0 * g2)),
    )
}

fn resolve_drive(d: &DriveSection) -> Result<(Drive, Integrator, DriveSection), SceneError> {
    let kind = d.kind.unwrap_or(DriveKind::Spring);
    let velocity = required(d.velocity, "drive.velocity")?;
    let integrator = d.integrator.unwrap_or(Integrator::Split);
    let mut section = DriveSection {
        kind: Some(kind),
        stiffness: None,
        mass: None,
        velocity: Some(velocity),
        integrator: Some(integrator),
    };
    let drive = match kind {
        DriveKind::Spring => {
            let needed = |v: Option<f64>, key: &str, unit: &str| {
                v.ok_or_else(|| {
                    SceneError::missing(
                        key,
                        format!(
                            "finite and > 0 {unit}; {key} is required when drive.kind = \"spring\""
                        ),
                    )
                })
                .and_then(|v| keys::check(key, v))
            };
            let stiffness = needed(d.stiffness, "drive.stiffness", "N/m")?;
            let mass = needed(d.mass, "drive.mass", "kg")?;
            section.stiffness = Some(stiffness);
            section.mass = Some(mass);
            Drive::Spring(SpringDrive {
                stiffness_n_per_m: stiffness,
                mass_kg: mass,
                velocity_m_per_s: velocity,
            })
        }
        DriveKind::Rigid => {
            let allowed = "no stiffness or mass with the rigid drive (X = V0·t)";
            let other = "drive.kind = \"rigid\"";
            contradiction("drive.stiffness", d.stiffness, other, allowed)?;
            contradiction("drive.mass", d.mass, other, allowed)?;
            Drive::Rigid(RigidDrive {
                velocity_m_per_s: velocity,
            })
        }
    };
    Ok((drive, integrator, section))
}

/// Stepping, adaptive control and the filled-in `[time]` section.
/// The stop rules of `[time]` besides the end: `max_events`, `max_open_event` (s), and the
/// steady-cycle rule (`until`, `steady_cycles`, `steady_rtol`).
type Stops = (Option<u64>, Option<f64>, crate::steady::SteadyRule);

fn resolve_time(
    t: &TimeSection,
    noise: &NoiseKind,
) -> Result<(TimeConfig, Stops, TimeSection), SceneError> {
    let end = required(t.end, "time.end")?;
    let dt = t.dt.unwrap_or(DEFAULT_DT_S);
    if !(dt.is_finite() && dt > 0.0 && dt <= end) {
        return Err(SceneError::invalid(
            "time.dt",
            error::human(dt),
            format!("finite, > 0 and <= time.end = {end:e} s"),
        ));
    }
    let scheme = t.scheme.unwrap_or(Scheme::Accurate);
    let gaussian = matches!(noise, NoiseKind::Gaussian { .. });
    let stepping = t
        .stepping
        .unwrap_or(if scheme == Scheme::Accurate && !gaussian {
            Stepping::Adaptive
        } else {
            Stepping::Fixed
        });
    let adaptive = if stepping == Stepping::Adaptive {
        let dt_max = or_default(t.dt_max, "time.dt_max", DEFAULT_DT_MAX_FRACTION * end)?;
        Some(AdaptiveConfig {
            tolerance: or_default(t.tolerance, "time.tolerance", DEFAULT_TOLERANCE)?,
            dt_max_s: dt_max,
            dt_min_s: or_default(
                t.dt_min,
                "time.dt_min",
                DEFAULT_DT_MIN_FRACTION * dt.min(dt_max),
            )?,
        })
    } else {
        let other = "time.stepping = \"fixed\"";
        let allowed = "only with time.stepping = \"adaptive\"";
        contradiction("time.tolerance", t.tolerance, other, allowed)?;
        contradiction("time.dt_max", t.dt_max, other, allowed)?;
        contradiction("time.dt_min", t.dt_min, other, allowed)?;
        None
    };
    let max_events = match t.max_events {
        None => None,
        Some(n) => Some(keys::check("time.max_events", n as f64).map(|_| n.unsigned_abs())?),
    };
    let max_open_event = t
        .max_open_event
        .map(|v| keys::check("time.max_open_event", v))
        .transpose()?;
    let until = t.until.unwrap_or(super::file::Until::End);
    let steady_cycles = match t.steady_cycles {
        None => crate::steady::DEFAULT_CYCLES,
        Some(n) => keys::check("time.steady_cycles", n as f64).map(|_| n.unsigned_abs())?,
    };
    let steady_rtol = or_default(
        t.steady_rtol,
        "time.steady_rtol",
        crate::steady::DEFAULT_RTOL,
    )?;
    let steady = crate::steady::SteadyRule {
        stop: until == super::file::Until::Periodic,
        cycles: steady_cycles,
        rtol: steady_rtol,
    };
    let section = TimeSection {
        end: Some(end),
        dt: Some(dt),
        scheme: Some(scheme),
        stepping: Some(stepping),
        tolerance: adaptive.map(|a| a.tolerance),
        dt_max: adaptive.map(|a| a.dt_max_s),
        dt_min: adaptive.map(|a| a.dt_min_s),
        max_events: t.max_events,
        max_open_event,
        until: Some(until),
        steady_cycles: Some(steady_cycles as i64),
        steady_rtol: Some(steady_rtol),
    };
    let config = TimeConfig {
        end_s: end,
        dt_s: dt,
        scheme,
        adaptive,
    };
    Ok((config, (max_events, max_open_event, steady), section))
}

/// `adaptive_tolerance`: `time.tolerance` when stepping is adaptive (the coupling solve's
/// default tolerance follows it).
fn resolve_numerics(
    nm: &NumericsSection,
    adaptive_tolerance: Option<f64>,
) -> Result<(NumericsConfig, NumericsSection), SceneError> {
    let defaults = NumericsConfig::default();
    let coupling_default = adaptive_tolerance.map_or(defaults.coupling_tol, |tol| {
        tol / super::TOLERANCE_PER_COUPLING_TOL
    });
    let operator = nm.operator.unwrap_or(OperatorChoice::Auto);
    let numerics = NumericsConfig {
        coupling_tol: or_default(nm.coupling_tol, "numerics.coupling_tol", coupling_default)?,
        runaway_stress_factor: or_default(
            nm.runaway_stress_factor,
            "numerics.runaway_stress_factor",
            defaults.runaway_stress_factor,
        )?,
        operator: match operator {
            OperatorChoice::Fast => Some(OperatorForm::Fast),
            OperatorChoice::Dense => Some(OperatorForm::Dense),
            OperatorChoice::Auto => None,
        },
    };
    let section = NumericsSection {
        coupling_tol: Some(numerics.coupling_tol),
        runaway_stress_factor: Some(numerics.runaway_stress_factor),
        operator: Some(operator),
    };
    Ok((numerics, section))
}

/// Output settings, event rules and the filled-in `[output]` section.
fn resolve_output(
    o: &OutputSection,
    end: f64,
    radius: f64,
) -> Result<(OutputSettings, EventConfig, OutputSection), SceneError> {
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
    let events = EventConfig {
        merge_gap_s: or_default(
            o.event_merge_gap,
            "output.event_merge_gap",
            DEFAULT_EVENT_MERGE_GAP_S,
        )?,
        recovery_factor: or_default(
            o.event_recovery,
            "output.event_recovery",
            DEFAULT_EVENT_RECOVERY,
        )?,
    };
    let series_interval = or_default(
        o.series_interval,
        "output.series_interval",
        DEFAULT_SERIES_INTERVAL_S,
    )?;
    let section = OutputSection {
        profile_times: Some(profile_times.clone()),
        probe_radii: Some(probe_radii.clone()),
        event_merge_gap: Some(events.merge_gap_s),
        event_recovery: Some(events.recovery_factor),
        series_interval: Some(series_interval),
    };
    let settings = OutputSettings {
        profile_times_s: profile_times,
        probe_radii_m: probe_radii,
        series_interval_s: series_interval,
    };
    Ok((settings, events, section))
}

/// Fills in defaults, applies the rules between keys and validates a deserialized scene.
///
/// # Errors
/// The first problem found.
pub fn resolve(scene: &Scene) -> Result<ResolvedScene, SceneError> {
    let name = scene
        .name
        .clone()
        .ok_or_else(|| SceneError::missing("name", "a non-empty string"))?;
    if name.trim().is_empty() {
        return Err(SceneError::invalid(
            "name",
            format!("{:?}", error::shorten(&name)),
            "a non-empty string",
        ));
    }

    let l = scene.lubricant.clone().unwrap_or_default();
    let lubricant = LandauParams {
        tau_max_pa: required(l.tau_max, "lubricant.tau_max")?,
        eps_max: required(l.eps_max, "lubricant.eps_max")?,
        a_pa: required(l.a, "lubricant.a")?,
        gamma_per_pa_s: required(l.gamma, "lubricant.gamma")?,
        cubic_pa: 0.0,
    };
    let melt_threshold = or_default(
        l.melt_threshold,
        "lubricant.melt_threshold",
        DEFAULT_MELT_THRESHOLD,
    )?;
    let (noise, noise_section) = resolve_noise(&l.noise.clone().unwrap_or_default())?;
    let (temperature, temperature_section) =
        resolve_temperature(&scene.temperature.clone().unwrap_or_default(), &lubricant)?;
    let lubricant = resolve_cubic(&l, lubricant, &temperature)?;

    let c = scene.contact.clone().unwrap_or_default();
    let radius = required(c.radius, "contact.radius")?;
    let film_thickness = required(c.film_thickness, "contact.film_thickness")?;
    let g_eff = resolve_modulus(&c)?;
    let nodes = c.nodes.unwrap_or(DEFAULT_NODES);
    keys::check("contact.nodes", nodes as f64).map_err(|_| {
        SceneError::invalid(
            "contact.nodes",
            nodes,
            keys::key("contact.nodes").range.describe("nodes", ""),
        )
    })?;
    let model = c.model.unwrap_or(ContactModel::Radial);
    let substrate = c.substrate.unwrap_or(Substrate::Elastic);

    let (drive, integrator, drive_section) =
        resolve_drive(&scene.drive.clone().unwrap_or_default())?;
    let (time, (max_events, max_open_event_s, steady), time_section) =
        resolve_time(&scene.time.clone().unwrap_or_default(), &noise)?;
    let (numerics, numerics_section) = resolve_numerics(
        &scene.numerics.clone().unwrap_or_default(),
        time.adaptive.map(|a| a.tolerance),
    )?;
    let end = time.end_s;
    let (output, events, output_section) =
        resolve_output(&scene.output.clone().unwrap_or_default(), end, radius)?;

    let config = SimConfig {
        lubricant,
        melt_threshold,
        noise,
        temperature,
        contact: ContactConfig {
            radius_m: radius,
            film_thickness_m: film_thickness,
            g_eff_pa: g_eff,
            nodes: nodes.unsigned_abs() as usize,
            model,
            substrate,
        },
        drive,
        integrator,
        time,
        numerics,
        events,
    };
    config.validate()?;
    if end / time.dt_s > MAX_STEPS {
        return Err(SceneError::invalid(
            "time.dt",
            error::human(time.dt_s),
            format!(
                "finite, > 0 and >= time.end / {MAX_STEPS:e} = {:e} s (at most {MAX_STEPS:e} steps)",
                end / MAX_STEPS
            ),
        ));
    }

    let resolved = Scene {
        name: Some(name.clone()),
        lubricant: Some(LubricantSection {
            tau_max: Some(lubricant.tau_max_pa),
            eps_max: Some(lubricant.eps_max),
            a: Some(lubricant.a_pa),
            gamma: Some(lubricant.gamma_per_pa_s),
            melt_threshold: Some(melt_threshold),
            // b₃ as resolved, whichever key gave it; absent for the second-order film, so that
            // its resolved scene (and run.json) is what it was before the key existed.
            cubic: (lubricant.cubic_pa > 0.0).then_some(lubricant.cubic_pa),
            eps_melt: None,
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
            model: Some(model),
            substrate: Some(substrate),
        }),
        drive: Some(drive_section),
        time: Some(time_section),
        output: Some(output_section),
        numerics: Some(numerics_section),
    };
    let derived = Derived::of(&config);
    Ok(ResolvedScene {
        name,
        steps: step_count(end, time.dt_s),
        config,
        output,
        max_events,
        max_open_event_s,
        steady,
        resolved,
        source: toml::Table::new(),
        derived,
    })
}
