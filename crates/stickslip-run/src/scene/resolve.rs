//! Step 4 of scene resolution: required keys, defaults, rules between keys, and the single-key
//! ranges of the key registry, turning a deserialized [`Scene`] into a [`ResolvedScene`].
//!
//! Each key's default and range come from its registry entry ([`keys::Key::resolve`]); a
//! derived default reads the keys it depends on from the scene as resolved so far, so the
//! sections are resolved in the order their defaults need (the lubricant before the
//! temperature, the time before the numerics and the output).

use super::error::{self, SceneError};
use super::file::{
    DriveKind, GridChoice, NoiseKindName, OperatorChoice, Scheme, Stepping, TemperatureLaw,
};
use super::{
    ContactSection, DriveSection, LubricantSection, MAX_STEPS, NoiseSection, NumericsSection,
    OutputSection, OutputSettings, ResolvedScene, Scene, TemperatureSection, TimeSection,
    step_count,
};
use crate::keys::{self, contact, drive, lubricant, noise, numerics, output, temperature, time};
use stickslip_core::config::{
    AdaptiveConfig, ContactConfig, Derived, EventConfig, NumericsConfig, SimConfig, TimeConfig,
};
use stickslip_core::drive::{Drive, Integrator, RigidDrive, SpringDrive};
use stickslip_core::grid::Grading;
use stickslip_core::landau::{LandauParams, Temperature};
use stickslip_core::mdr::OperatorForm;
use stickslip_core::noise::NoiseKind;

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
fn word<T: keys::KeyValue>(v: T) -> String {
    v.show()
}

/// An empty scene to resolve defaults against: a key whose default derives from nothing.
fn nothing() -> Scene {
    Scene::default()
}

/// Resolves the lubricant's noise section into the engine's kind and its filled-in section.
fn resolve_noise(n: &NoiseSection) -> Result<(NoiseKind, NoiseSection), SceneError> {
    let kind = noise::KIND.value(n.kind, &nothing())?;
    let other = format!("lubricant.noise.kind = {:?}", word(kind));
    let seed_as_f64 = n.seed.map(|s| s as f64);
    match kind {
        NoiseKindName::Gaussian => {
            contradiction(
                noise::FLOOR.path,
                n.floor,
                &other,
                "floor only with kind = \"floor\"",
            )?;
            let sigma = noise::SIGMA.value(n.sigma, &nothing())?;
            let seed = noise::SEED.value(n.seed, &nothing())?;
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
            contradiction(noise::SIGMA.path, n.sigma, &other, allowed)?;
            contradiction(noise::SEED.path, seed_as_f64, &other, allowed)?;
            // Checked against the melting threshold with the engine's configuration.
            let floor = n.floor.or(noise::FLOOR.fixed_default()).unwrap_or(f64::NAN);
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
            contradiction(noise::SIGMA.path, n.sigma, &other, allowed)?;
            contradiction(noise::FLOOR.path, n.floor, &other, allowed)?;
            contradiction(noise::SEED.path, seed_as_f64, &other, allowed)?;
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

/// `so_far`: the scene as resolved up to the temperature (the lubricant's keys, from which
/// A's default derives).
fn resolve_temperature(
    t: &TemperatureSection,
    so_far: &Scene,
) -> Result<(Temperature, TemperatureSection), SceneError> {
    let law = temperature::LAW.value(t.law, &nothing())?;
    match law {
        TemperatureLaw::Constant => {
            contradiction(
                temperature::T_RELAX.path,
                t.t_relax,
                "temperature.law = \"constant\"",
                "t_relax only with law = \"relaxation\"",
            )?;
            let a = temperature::A0.value(t.a0, so_far)?;
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
                    temperature::A0.path,
                    "a finite number of Pa (required when temperature.law = \"relaxation\")",
                )
            })?;
            let a0 = temperature::A0.check(a0)?;
            let t_relax = t.t_relax.ok_or_else(|| {
                SceneError::missing(
                    temperature::T_RELAX.path,
                    "finite and > 0 s (required when temperature.law = \"relaxation\")",
                )
            })?;
            let t_relax = temperature::T_RELAX.check(t_relax)?;
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
            key: lubricant::EPS_MELT.path.to_string(),
            value: error::human(eps_melt),
            other: format!("lubricant.cubic = {}", error::human(cubic)),
            allowed: "either lubricant.cubic (b3) or lubricant.eps_melt (the melting strain it \
                      gives), not both"
                .to_string(),
        });
    }
    let cubic = match (l.cubic, l.eps_melt) {
        (None, Some(eps_melt)) => {
            let a0 = temperature.a_coeff_pa(0.0);
            let eps_c = lubricant.critical_strain(a0);
            lubricant
                .cubic_for_melting_strain(eps_melt, a0)
                .ok_or_else(|| {
                    SceneError::invalid(
                        lubricant::EPS_MELT.path,
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
        (cubic, _) => lubricant::CUBIC.value(cubic, &nothing())?,
    };
    // -0 is 0: the second-order film.
    Ok(LandauParams {
        cubic_pa: if cubic == 0.0 { 0.0 } else { cubic },
        ..lubricant
    })
}

/// G* from g_eff or from g1, nu1, g2, nu2 by Eq. 9: G* = ((2−ν1)/(4G1) + (2−ν2)/(4G2))^−1.
fn resolve_modulus(c: &ContactSection) -> Result<f64, SceneError> {
    let keys = [contact::G1, contact::NU1, contact::G2, contact::NU2];
    let pair = [
        (keys[0].path, c.g1),
        (keys[1].path, c.nu1),
        (keys[2].path, c.g2),
        (keys[3].path, c.nu2),
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
        return Ok(contact::G_EFF.check(g)?);
    }
    if pair.iter().all(|(_, v)| v.is_none()) {
        return Err(SceneError::missing(
            contact::G_EFF.path,
            "finite and > 0 Pa (or all of contact.g1, nu1, g2, nu2 by Eq. 9)",
        ));
    }
    if let Some((key, _)) = pair.iter().find(|(_, v)| v.is_none()) {
        return Err(SceneError::missing(
            key,
            "all of contact.g1, nu1, g2, nu2 together (Eq. 9), or contact.g_eff alone",
        ));
    }
    let mut values = [0.0; 4];
    for ((key, v), out) in keys.iter().zip(pair).zip(&mut values) {
        *out = key.check(v.1.unwrap_or(f64::NAN))?;
    }
    let [g1, nu1, g2, nu2] = values;
    Ok(contact::G_EFF.check(1.0 / ((2.0 - nu1) / (4.0 * g1) + (2.0 - nu2) / (4.0 * g2)))?)
}

fn resolve_drive(d: &DriveSection) -> Result<(Drive, Integrator, DriveSection), SceneError> {
    let kind = drive::KIND.value(d.kind, &nothing())?;
    let velocity = drive::VELOCITY.value(d.velocity, &nothing())?;
    let integrator = drive::INTEGRATOR.value(d.integrator, &nothing())?;
    let mut section = DriveSection {
        kind: Some(kind),
        stiffness: None,
        mass: None,
        damping: None,
        velocity: Some(velocity),
        integrator: Some(integrator),
    };
    let drive = match kind {
        DriveKind::Spring => {
            let needed = |v: Option<f64>, key: keys::Key<f64>| {
                v.ok_or_else(|| {
                    SceneError::missing(
                        key.path,
                        format!(
                            "finite and > 0 {}; {} is required when drive.kind = \"spring\"",
                            key.unit, key.path
                        ),
                    )
                })
                .and_then(|v| Ok(key.check(v)?))
            };
            let stiffness = needed(d.stiffness, drive::STIFFNESS)?;
            let mass = needed(d.mass, drive::MASS)?;
            // -0.0 is 0: the paper's model, bit for bit.
            let damping = drive::DAMPING.value(d.damping, &nothing())?;
            let damping = if damping == 0.0 { 0.0 } else { damping };
            section.stiffness = Some(stiffness);
            section.mass = Some(mass);
            section.damping = Some(damping);
            Drive::Spring(SpringDrive {
                stiffness_n_per_m: stiffness,
                mass_kg: mass,
                velocity_m_per_s: velocity,
                damping_n_s_per_m: damping,
            })
        }
        DriveKind::Rigid => {
            let allowed = "no stiffness, mass or damping with the rigid drive (X = V0·t)";
            let other = "drive.kind = \"rigid\"";
            contradiction(drive::STIFFNESS.path, d.stiffness, other, allowed)?;
            contradiction(drive::MASS.path, d.mass, other, allowed)?;
            contradiction(drive::DAMPING.path, d.damping, other, allowed)?;
            Drive::Rigid(RigidDrive {
                velocity_m_per_s: velocity,
            })
        }
    };
    Ok((drive, integrator, section))
}

/// The end of the run, s: `time.end`, or the time the drive needs to advance `time.travel`
/// (m) at |drive.velocity|, or the earlier of the two when both are given. Errors name the
/// key the user gave, with the value they gave.
fn resolve_end(end: Option<f64>, travel: Option<f64>, so_far: &Scene) -> Result<f64, SceneError> {
    let end = end.map(|e| time::END.check(e)).transpose()?;
    let Some(travel) = travel else {
        return end.ok_or_else(|| {
            SceneError::missing(
                time::END.path,
                format!(
                    "{}; or time.travel (m), the drive's advance that ends the run",
                    time::END.allowed()
                ),
            )
        });
    };
    let velocity = so_far
        .drive
        .as_ref()
        .and_then(|d| d.velocity)
        .unwrap_or(0.0);
    let by_travel = travel / velocity.abs();
    if !(by_travel.is_finite() && by_travel > 0.0) {
        return Err(SceneError::invalid(
            time::TRAVEL.path,
            error::human(travel),
            format!(
                "an advance the drive makes in a finite time: at drive.velocity = {} m/s it \
                 takes {} s; or time.end alone",
                error::human(velocity),
                error::human(by_travel)
            ),
        ));
    }
    Ok(match end {
        Some(e) => e.min(by_travel),
        None => time::END.check(by_travel).map_err(|_| {
            SceneError::invalid(
                time::TRAVEL.path,
                error::human(travel),
                format!(
                    "an advance taking a time.end that is {}: at drive.velocity = {} m/s it \
                     takes {} s",
                    time::END.allowed(),
                    error::human(velocity),
                    error::human(by_travel)
                ),
            )
        })?,
    })
}

/// The stop rules of `[time]` besides the end: `max_events`, `max_open_event` (s), and the
/// steady-cycle rule (`until`, `steady_cycles`, `steady_rtol`).
type Stops = (Option<u64>, Option<f64>, crate::steady::SteadyRule);

/// Stepping, adaptive control, the stop rules and the filled-in `[time]` section. `so_far`:
/// the scene as resolved before the time (the noise's kind decides the default stepping).
fn resolve_time(
    t: &TimeSection,
    so_far: &Scene,
) -> Result<(TimeConfig, Stops, TimeSection), SceneError> {
    let travel = time::TRAVEL.resolve(t.travel, &nothing())?;
    let end = resolve_end(t.end, travel, so_far)?;
    let dt = t.dt.or(time::DT.fixed_default()).unwrap_or(f64::NAN);
    if !(dt.is_finite() && dt > 0.0 && dt <= end) {
        return Err(SceneError::invalid(
            time::DT.path,
            error::human(dt),
            format!("finite, > 0 and <= time.end = {end:e} s"),
        ));
    }
    let scheme = time::SCHEME.value(t.scheme, &nothing())?;
    // The section as resolved so far, for the derived defaults that follow.
    let mut section = TimeSection {
        end: Some(end),
        travel,
        dt: Some(dt),
        scheme: Some(scheme),
        ..TimeSection::default()
    };
    let with = |section: &TimeSection| Scene {
        time: Some(section.clone()),
        ..so_far.clone()
    };
    let stepping = time::STEPPING.value(t.stepping, &with(&section))?;
    section.stepping = Some(stepping);
    let adaptive = if stepping == Stepping::Adaptive {
        section.tolerance = Some(time::TOLERANCE.value(t.tolerance, &nothing())?);
        section.dt_max = Some(time::DT_MAX.value(t.dt_max, &with(&section))?);
        section.dt_min = Some(time::DT_MIN.value(t.dt_min, &with(&section))?);
        Some(AdaptiveConfig {
            tolerance: section.tolerance.unwrap_or(f64::NAN),
            dt_max_s: section.dt_max.unwrap_or(f64::NAN),
            dt_min_s: section.dt_min.unwrap_or(f64::NAN),
        })
    } else {
        let other = "time.stepping = \"fixed\"";
        let allowed = "only with time.stepping = \"adaptive\"";
        contradiction(time::TOLERANCE.path, t.tolerance, other, allowed)?;
        contradiction(time::DT_MAX.path, t.dt_max, other, allowed)?;
        contradiction(time::DT_MIN.path, t.dt_min, other, allowed)?;
        None
    };
    let max_events = time::MAX_EVENTS
        .resolve(t.max_events, &nothing())?
        .map(i64::unsigned_abs);
    let max_open_event = time::MAX_OPEN_EVENT.resolve(t.max_open_event, &nothing())?;
    let until = time::UNTIL.value(t.until, &nothing())?;
    let steady_cycles = time::STEADY_CYCLES.value(t.steady_cycles, &nothing())?;
    let steady_rtol = time::STEADY_RTOL.value(t.steady_rtol, &nothing())?;
    let steady = crate::steady::SteadyRule {
        stop: until == super::file::Until::Periodic,
        cycles: steady_cycles.unsigned_abs(),
        rtol: steady_rtol,
    };
    let section = TimeSection {
        max_events: t.max_events,
        max_open_event,
        until: Some(until),
        steady_cycles: Some(steady_cycles),
        steady_rtol: Some(steady_rtol),
        ..section
    };
    let config = TimeConfig {
        end_s: end,
        dt_s: dt,
        scheme,
        adaptive,
    };
    Ok((config, (max_events, max_open_event, steady), section))
}

/// `contact.grid` and `contact.grading`, resolved once the scheme is known (the literal
/// scheme's sums are the uniform grid's): the grading for the core, and the two keys as the
/// resolved scene states them (no grading with the uniform grid).
fn resolve_grid(
    c: &ContactSection,
    scheme: Scheme,
    so_far: &Scene,
) -> Result<(Grading, GridChoice, Option<f64>), SceneError> {
    let grid = contact::GRID.value(c.grid, so_far)?;
    match grid {
        GridChoice::Uniform => {
            contradiction(
                contact::GRADING.path,
                c.grading,
                "contact.grid = \"uniform\"",
                "only with contact.grid = \"graded\"",
            )?;
            Ok((Grading::Uniform, grid, None))
        }
        GridChoice::Graded => {
            if scheme == Scheme::Literal {
                return Err(SceneError::Contradictory {
                    key: contact::GRID.path.to_string(),
                    value: word(grid),
                    other: "time.scheme = \"literal\"".to_string(),
                    allowed: "\"uniform\" with time.scheme = \"literal\" (the paper's sums are \
                              defined on its uniform grid r_i = i·a0/N)"
                        .to_string(),
                });
            }
            let power = contact::GRADING.value(c.grading, so_far)?;
            Ok((Grading::Edge { power }, grid, Some(power)))
        }
    }
}

/// `so_far`: the scene as resolved up to the numerics (with the time, from which the coupling
/// solve's default tolerance derives).
fn resolve_numerics(
    nm: &NumericsSection,
    so_far: &Scene,
) -> Result<(NumericsConfig, NumericsSection), SceneError> {
    let operator = numerics::OPERATOR.value(nm.operator, &nothing())?;
    let film_step = numerics::FILM_STEP.value(nm.film_step, &nothing())?;
    // The φ error's floors scale the adaptive step's error norm and the cascade's factor its
    // tolerance: nothing to scale with fixed steps, where they are refused and left out of the
    // resolved scene.
    let adaptive = keys::adaptive(so_far) == Some(true);
    let phi_error_floor = adaptive_only(adaptive, &numerics::PHI_ERROR_FLOOR, nm.phi_error_floor)?;
    let event_phi_error_floor = adaptive_only(
        adaptive,
        &numerics::EVENT_PHI_ERROR_FLOOR,
        nm.event_phi_error_floor,
    )?;
    let event_tolerance_factor = adaptive_only(
        adaptive,
        &numerics::EVENT_TOLERANCE_FACTOR,
        nm.event_tolerance_factor,
    )?;
    let numerics = NumericsConfig {
        coupling_tol: numerics::COUPLING_TOL.value(nm.coupling_tol, so_far)?,
        runaway_stress_factor: numerics::RUNAWAY_STRESS_FACTOR
            .value(nm.runaway_stress_factor, &nothing())?,
        operator: match operator {
            OperatorChoice::Fast => Some(OperatorForm::Fast),
            OperatorChoice::Dense => Some(OperatorForm::Dense),
            OperatorChoice::Auto => None,
        },
        film_step,
        phi_error_floor: phi_error_floor.unwrap_or(0.0),
        event_phi_error_floor: event_phi_error_floor.unwrap_or(0.0),
        event_tolerance_factor: event_tolerance_factor.unwrap_or(1.0),
    };
    let section = NumericsSection {
        coupling_tol: Some(numerics.coupling_tol),
        runaway_stress_factor: Some(numerics.runaway_stress_factor),
        operator: Some(operator),
        film_step: Some(film_step),
        phi_error_floor,
        event_phi_error_floor,
        event_tolerance_factor,
    };
    Ok((numerics, section))
}

/// A key of the adaptive step only: its value (given or default) with adaptive steps; with
/// fixed steps nothing, and an error naming the key when it was given.
fn adaptive_only(
    adaptive: bool,
    key: &crate::keys::Key<f64>,
    given: Option<f64>,
) -> Result<Option<f64>, SceneError> {
    if adaptive {
        return Ok(Some(key.value(given, &nothing())?));
    }
    contradiction(
        key.path,
        given,
        "time.stepping = \"fixed\"",
        "only with time.stepping = \"adaptive\"",
    )?;
    Ok(None)
}

/// Output settings, event rules and the filled-in `[output]` section. `so_far`: the scene as
/// resolved up to the output (with the time and the contact).
fn resolve_output(
    o: &OutputSection,
    so_far: &Scene,
    end: f64,
    radius: f64,
) -> Result<(OutputSettings, EventConfig, OutputSection), SceneError> {
    let profile_times = output::PROFILE_TIMES.value(o.profile_times.clone(), so_far)?;
    if let Some(bad) = profile_times
        .iter()
        .find(|&&p| !(p.is_finite() && (0.0..=end).contains(&p)))
    {
        return Err(SceneError::invalid(
            output::PROFILE_TIMES.path,
            error::human(*bad),
            format!("each within [0, time.end = {end:e}] s"),
        ));
    }
    let probe_radii = output::PROBE_RADII.value(o.probe_radii.clone(), so_far)?;
    if let Some(bad) = probe_radii
        .iter()
        .find(|&&r| !(r.is_finite() && r >= 0.0 && r < radius))
    {
        return Err(SceneError::invalid(
            output::PROBE_RADII.path,
            error::human(*bad),
            format!("each within [0, contact.radius = {radius:e}) m"),
        ));
    }
    let events = EventConfig {
        merge_gap_s: output::EVENT_MERGE_GAP.value(o.event_merge_gap, so_far)?,
        recovery_factor: output::EVENT_RECOVERY.value(o.event_recovery, so_far)?,
    };
    let series_interval = output::SERIES_INTERVAL.value(o.series_interval, so_far)?;
    let slip_drop = output::SLIP_DROP.value(o.slip_drop, so_far)?;
    // Marks closer than end·1e-12 round onto the same time (and more than 1e12 rows is no
    // record anyone reads): a subnormal interval would run with a handful of rows.
    if series_interval < end / MAX_STEPS {
        // A default the user never gave is said to be one, and time.end named as the cause.
        return Err(SceneError::invalid(
            output::SERIES_INTERVAL.path,
            format!(
                "{}{}",
                error::human(series_interval),
                if o.series_interval.is_none() {
                    " (its default)"
                } else {
                    ""
                }
            ),
            format!(
                "finite, > 0 and >= time.end / {MAX_STEPS:e} = {:e} s; or a shorter time.end \
                 (now {} s)",
                end / MAX_STEPS,
                error::human(end)
            ),
        ));
    }
    let section = OutputSection {
        profile_times: Some(profile_times.clone()),
        probe_radii: Some(probe_radii.clone()),
        event_merge_gap: Some(events.merge_gap_s),
        event_recovery: Some(events.recovery_factor),
        slip_drop: Some(slip_drop),
        series_interval: Some(series_interval),
    };
    let settings = OutputSettings {
        profile_times_s: profile_times,
        probe_radii_m: probe_radii,
        series_interval_s: series_interval,
        slip_drop,
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
        .ok_or_else(|| SceneError::missing(keys::NAME.path, "a non-empty string"))?;
    if name.trim().is_empty() {
        return Err(SceneError::invalid(
            keys::NAME.path,
            format!("{:?}", error::shorten(&name)),
            "a non-empty string",
        ));
    }

    let l = scene.lubricant.clone().unwrap_or_default();
    let lubricant = LandauParams {
        tau_max_pa: lubricant::TAU_MAX.value(l.tau_max, &nothing())?,
        eps_max: lubricant::EPS_MAX.value(l.eps_max, &nothing())?,
        a_pa: lubricant::A.value(l.a, &nothing())?,
        gamma_per_pa_s: lubricant::GAMMA.value(l.gamma, &nothing())?,
        cubic_pa: 0.0,
        viscosity_pa_s: 0.0,
    };
    // b and the default A derive from these: before A's default is taken from them.
    stickslip_core::config::bounds::check_film(&lubricant)?;
    let melt_threshold = lubricant::MELT_THRESHOLD.value(l.melt_threshold, &nothing())?;
    // -0.0 is 0: the paper's film, bit for bit.
    let viscosity = lubricant::VISCOSITY.value(l.viscosity, &nothing())?;
    let viscosity = if viscosity == 0.0 { 0.0 } else { viscosity };
    let lubricant = LandauParams {
        viscosity_pa_s: viscosity,
        ..lubricant
    };
    let (noise, noise_section) = resolve_noise(&l.noise.clone().unwrap_or_default())?;
    // The scene as resolved so far, for the derived defaults of the sections that follow.
    let mut so_far = Scene {
        name: Some(name.clone()),
        lubricant: Some(LubricantSection {
            tau_max: Some(lubricant.tau_max_pa),
            eps_max: Some(lubricant.eps_max),
            a: Some(lubricant.a_pa),
            gamma: Some(lubricant.gamma_per_pa_s),
            melt_threshold: Some(melt_threshold),
            cubic: None,
            eps_melt: None,
            viscosity: Some(viscosity),
            noise: Some(noise_section),
        }),
        ..Scene::default()
    };
    let (temperature, temperature_section) =
        resolve_temperature(&scene.temperature.clone().unwrap_or_default(), &so_far)?;
    let lubricant = resolve_cubic(&l, lubricant, &temperature)?;
    if let Some(section) = so_far.lubricant.as_mut() {
        // b₃ as resolved, whichever key gave it; absent for the second-order film, so that
        // its resolved scene (and run.json) is what it was before the key existed.
        section.cubic = (lubricant.cubic_pa > 0.0).then_some(lubricant.cubic_pa);
    }
    so_far.temperature = Some(temperature_section);

    let c = scene.contact.clone().unwrap_or_default();
    let radius = contact::RADIUS.value(c.radius, &nothing())?;
    let film_thickness = contact::FILM_THICKNESS.value(c.film_thickness, &nothing())?;
    let g_eff = resolve_modulus(&c)?;
    let nodes = contact::NODES.value(c.nodes, &nothing()).map_err(|_| {
        let nodes = c.nodes.unwrap_or_default();
        SceneError::invalid(
            contact::NODES.path,
            nodes,
            contact::NODES.range.describe("nodes", ""),
        )
    })?;
    let model = contact::MODEL.value(c.model, &nothing())?;
    let substrate = contact::SUBSTRATE.value(c.substrate, &nothing())?;
    so_far.contact = Some(ContactSection {
        radius: Some(radius),
        film_thickness: Some(film_thickness),
        g_eff: c.g_eff.or(if c.g1.is_some() { None } else { Some(g_eff) }),
        g1: c.g1,
        nu1: c.nu1,
        g2: c.g2,
        nu2: c.nu2,
        nodes: Some(nodes),
        grid: None,
        grading: None,
        model: Some(model),
        substrate: Some(substrate),
    });

    let (drive, integrator, drive_section) =
        resolve_drive(&scene.drive.clone().unwrap_or_default())?;
    so_far.drive = Some(drive_section);
    let (time, (max_events, max_open_event_s, steady), time_section) =
        resolve_time(&scene.time.clone().unwrap_or_default(), &so_far)?;
    so_far.time = Some(time_section);
    let (grading, grid_word, grading_value) = resolve_grid(&c, time.scheme, &so_far)?;
    if let Some(section) = so_far.contact.as_mut() {
        section.grid = Some(grid_word);
        section.grading = grading_value;
    }
    let (numerics, numerics_section) =
        resolve_numerics(&scene.numerics.clone().unwrap_or_default(), &so_far)?;
    so_far.numerics = Some(numerics_section);
    let end = time.end_s;
    let (output, events, output_section) = resolve_output(
        &scene.output.clone().unwrap_or_default(),
        &so_far,
        end,
        radius,
    )?;
    so_far.output = Some(output_section);

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
            grid: grading,
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
        let given = scene.time.as_ref().and_then(|t| t.dt).is_some();
        return Err(SceneError::invalid(
            time::DT.path,
            format!(
                "{}{}",
                error::human(time.dt_s),
                if given { "" } else { " (its default)" }
            ),
            format!(
                "finite, > 0 and >= time.end / {MAX_STEPS:e} = {:e} s (at most {MAX_STEPS:e} \
                 steps); or a shorter time.end (now {} s)",
                end / MAX_STEPS,
                error::human(end)
            ),
        ));
    }

    let derived = Derived::of(&config);
    Ok(ResolvedScene {
        name,
        steps: step_count(end, time.dt_s),
        config,
        output,
        max_events,
        max_open_event_s,
        steady,
        resolved: so_far,
        source: toml::Table::new(),
        derived,
    })
}
