//! Before a run: derived numbers, stability numbers, quasi-static estimates and the verdict
//! (run, or refuse with a typed failure).
//!
//! Everything here is physics of the configuration, decided once, in one place: the command
//! line's `check`, a run's `run.json` and a sweep's refusals all read this record.

use crate::config::{Derived, Scheme, SimConfig};
use crate::drive::{Drive, SpringDrive, free_spring_exact};
use crate::failure::NumericalFailure;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Explicit Euler on Eq. 8 is unstable for Δt·|∂rhs/∂φ| above this.
pub const EULER_STABILITY_LIMIT: f64 = 2.0;

/// How much a finding matters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Worth knowing; the run is meaningful.
    Note,
    /// The run goes ahead but its result may be wrong or empty.
    Warning,
    /// The run is refused (it would diverge).
    Refusal,
}

/// One statement about a configuration before it runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Finding {
    /// How much it matters.
    pub severity: Severity,
    /// The scene key it is mostly about.
    pub key: String,
    /// What it means and what to do, in one or two sentences.
    pub message: String,
}

/// The physics of a configuration before it runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Preflight {
    /// b, A, εc, φ0 and ω.
    pub derived: Derived,
    /// Largest friction force the film can carry, τmax·π·a0², N (the first-order film: the peak
    /// of its stationary stress curve at A(0) times π·a0²,
    /// [`crate::landau::LandauParams::peak_stress_pa`]).
    pub melting_force_n: f64,
    /// Stamp advance at which the unloaded film melts, m (at t = 0): εc·h0, or ε₊·h0 for the
    /// first-order film.
    pub critical_displacement_m: f64,
    /// Period of the free spring 2π/ω, s (none for the rigid drive).
    pub spring_period_s: Option<f64>,
    /// Explicit Euler's stability number Δt·|∂rhs/∂φ| at the unstrained solid film, Δt·2γ·A·b/a
    /// (first-order film: Δt·γ·φ₊·(2b·φ₊ − b₃)) (literal scheme only; stable below 2).
    pub euler_number: Option<f64>,
    /// Contraction factor ρ of the paper's lagged elastic sweep at t = 0 for this scheme's
    /// compliance (the literal scheme needs ρ < 1; 0 for a rigid substrate).
    pub lagged_sweep_contraction: f64,
    /// Stamp position at `time.end` if friction did not slow it, m.
    pub stamp_travel_m: f64,
    /// Estimate of the first melting, s: with [`Preflight::contact_spring`] the stamp on its
    /// drive against the contact as a spring reaching the contact's melting displacement (the
    /// static problem's fold, [`crate::sim::Simulation::onset_spring`]; quasi-static and
    /// inertial loading alike), else the first time the free stamp has advanced the
    /// melting strain times h0; 0 when the film is liquid from the start; none when the drive
    /// never gets there. It does not depend on `time.end` (a warning says when it lies beyond).
    /// Real onsets come later at high speed (φ lags behind its equilibrium).
    pub first_onset_estimate_s: Option<f64>,
    /// The contact as a linear spring up to the first melting, when the simulation computed
    /// it (none in a preflight made from the configuration alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_spring: Option<ContactSpring>,
    /// Notes, warnings and refusals, in this order of appearance.
    pub findings: Vec<Finding>,
    /// The first-order film's thresholds (none for the second-order film, b₃ = 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_order: Option<FirstOrderFilm>,
    /// The viscous film's scales (none for η = 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscous: Option<ViscousFilm>,
}

/// The viscous film's scales (`lubricant.viscosity` = η > 0; docs/model.md#viscosity).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ViscousFilm {
    /// η, Pa·s.
    pub viscosity_pa_s: f64,
    /// c_v = η·π·a0²/h0, N·s/m: a liquid film's drag on the stamp per velocity on a rigid
    /// substrate (the Couette force is c_v·V).
    pub drag_n_s_per_m: f64,
    /// η·a0/(h0·G*), s: the time on which the substrate's displacement relaxes through the
    /// viscous film (0 on a rigid substrate).
    pub time_s: f64,
}

impl ViscousFilm {
    /// The scales of `config`'s viscous film; none for η = 0.
    #[must_use]
    pub fn of(config: &SimConfig) -> Option<Self> {
        let eta = config.lubricant.viscosity_pa_s;
        if eta == 0.0 {
            return None;
        }
        let c = &config.contact;
        let time_s = match c.substrate {
            crate::config::Substrate::Elastic => {
                eta * c.radius_m / (c.film_thickness_m * c.g_eff_pa)
            }
            crate::config::Substrate::Rigid => 0.0,
        };
        Some(Self {
            viscosity_pa_s: eta,
            drag_n_s_per_m: eta * PI * c.radius_m * c.radius_m / c.film_thickness_m,
            time_s,
        })
    }
}

/// The first-order film's thresholds at t = 0 (docs/model.md#the-first-order-film).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FirstOrderFilm {
    /// b₃, Pa.
    pub cubic_pa: f64,
    /// ε₊: the solid branch ends and the film melts (φ drops from b₃/(2b) to 0); 0 when no solid
    /// film exists.
    pub eps_melt: f64,
    /// ε₋ = εc: a liquid film re-solidifies (φ jumps to b₃/b); 0 when A ≤ 0 (never).
    pub eps_solidify: f64,
    /// ε₊² − ε₋² = b₃²/(4ab) while A > 0 (independent of temperature); ε₊² for A ≤ 0.
    pub hysteresis_width: f64,
    /// τ on the solid branch at ε₊, a·(b₃/(2b))²·ε₊, Pa.
    pub tau_melt_pa: f64,
    /// φ on the solid branch at ε₊, b₃/(2b).
    pub phi_melt: f64,
    /// φ on the solid branch at ε₋ = εc, b₃/b.
    pub phi_solidify: f64,
    /// Above the melting temperature (A ≤ 0): whether the film starts as a metastable solid
    /// (b₃² ≥ −4b·A·b/a; it melts once and does not re-solidify without noise); none for A > 0.
    pub metastable_solid: Option<bool>,
}

impl FirstOrderFilm {
    /// The thresholds of `config`'s first-order film at t = 0; none for b₃ = 0.
    #[must_use]
    pub fn of(config: &SimConfig) -> Option<Self> {
        let l = &config.lubricant;
        if !l.is_first_order() {
            return None;
        }
        let a_coeff = config.temperature.a_coeff_pa(0.0);
        let (eps_melt, eps_solidify) =
            (l.melting_strain(a_coeff), l.solidification_strain(a_coeff));
        let b = l.b_pa();
        Some(Self {
            cubic_pa: l.cubic_pa,
            eps_melt,
            eps_solidify,
            hysteresis_width: eps_melt * eps_melt - eps_solidify * eps_solidify,
            tau_melt_pa: l.melting_stress_pa(a_coeff),
            phi_melt: l.cubic_pa / (2.0 * b),
            phi_solidify: l.cubic_pa / b,
            metastable_solid: (a_coeff <= 0.0).then(|| l.starts_solid(a_coeff)),
        })
    }
}

/// Stamp position without friction at `t_s`, m (spring: the exact free motion; rigid: V0·t).
#[must_use]
pub fn free_stamp_position_m(drive: &Drive, t_s: f64) -> f64 {
    match drive {
        Drive::Spring(s) => free_spring_exact(s, t_s).0,
        Drive::Rigid(r) => r.velocity_m_per_s * t_s,
    }
}

/// The contact as a linear spring up to the first melting (the film at its secant stiffness at
/// melting in series with the substrate's static response; the simulation computes it).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactSpring {
    /// Stamp displacement at which the first node reaches the melting strain, m.
    pub x_melt_m: f64,
    /// The friction force then, N.
    pub f_melt_n: f64,
}

impl ContactSpring {
    /// Its stiffness F_m / X_m, N/m.
    #[must_use]
    pub fn stiffness_n_per_m(&self) -> f64 {
        self.f_melt_n / self.x_melt_m
    }
}

/// t − sin(Ω·t)/Ω without cancellation at small Ω·t.
fn t_minus_sin(t: f64, omega: f64) -> f64 {
    let x = omega * t;
    if x.abs() < 1e-2 {
        // x³/6 − x⁵/120 + x⁷/5040, over Ω.
        let x2 = x * x;
        x * x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0)) / omega
    } else {
        t - x.sin() / omega
    }
}

/// The first onset of the linearised problem: the stamp on its drive against the contact as
/// the spring `k` (rigid drive: X = V0·t; spring drive from rest: m·Ẍ = K(V0·t − X) − k·X,
/// X = K·V0/(K + k)·(t − sin(Ω·t)/Ω) with Ω² = (K + k)/m), reaching the melting displacement
/// (scaled with the melting strain when the temperature changes); none if it never does.
fn linear_onset(config: &SimConfig, k: ContactSpring) -> Option<f64> {
    let end = config.time.end_s;
    let l = &config.lubricant;
    let eps0 = l.melting_strain(config.temperature.a_coeff_pa(0.0));
    let stamp = |t: f64| match config.drive {
        Drive::Rigid(r) => (r.velocity_m_per_s * t).abs(),
        Drive::Spring(s) if s.damping_n_s_per_m == 0.0 => {
            let ks = k.stiffness_n_per_m();
            let kk = s.stiffness_n_per_m;
            let omega = ((kk + ks) / s.mass_kg).sqrt();
            (kk * s.velocity_m_per_s / (kk + ks) * t_minus_sin(t, omega)).abs()
        }
        Drive::Spring(s) => {
            // With the dashpot: m·Ẍ = K(V0·t − X) + c(V0 − Ẋ) − k·X is the damped drive of
            // stiffness K' = K + k and speed V' = K·V0/K', shifted by the constant
            // δ = c·(V0 − V')/K'; its exact flow from X = −δ at rest, plus δ.
            let ks = k.stiffness_n_per_m();
            let kk = s.stiffness_n_per_m + ks;
            let v = s.stiffness_n_per_m * s.velocity_m_per_s / kk;
            let delta = s.damping_n_s_per_m * (s.velocity_m_per_s - v) / kk;
            let Ok(shifted) = SpringDrive::new(kk, s.mass_kg, v)
                .and_then(|d| d.with_damping(s.damping_n_s_per_m))
            else {
                return f64::NAN;
            };
            let mut state = crate::drive::DriveState::at_rest();
            state.x_m = -delta;
            shifted.spring_flow(&mut state, t);
            (state.x_m + delta).abs()
        }
    };
    let gap = |t: f64| {
        let eps = l.melting_strain(config.temperature.a_coeff_pa(t));
        stamp(t) - k.x_melt_m * eps / eps0
    };
    crossing(end, gap)
}

impl Preflight {
    /// The preflight of `config`; `lagged_sweep_contraction` comes from the operators
    /// ([`crate::sim::Simulation::lagged_sweep_contraction`]). The first-onset estimate is the
    /// free stamp's reaching the melting strain times h0.
    #[must_use]
    pub fn of(config: &SimConfig, lagged_sweep_contraction: f64) -> Self {
        Self::with_contact(config, lagged_sweep_contraction, None)
    }

    /// As [`Preflight::of`], with the first-onset estimate of the stamp against the contact's
    /// spring `contact` when it is known ([`crate::sim::Simulation::onset_spring`]).
    #[must_use]
    pub fn with_contact(
        config: &SimConfig,
        lagged_sweep_contraction: f64,
        contact: Option<ContactSpring>,
    ) -> Self {
        let derived = Derived::of(config);
        let l = &config.lubricant;
        let c = &config.contact;
        let end = config.time.end_s;
        let mut findings = Vec::new();
        let spring_period_s = match config.drive {
            Drive::Spring(s) => Some(2.0 * PI / s.omega_rad_per_s()),
            Drive::Rigid(_) => None,
        };
        let euler_number =
            literal_findings(config, &derived, lagged_sweep_contraction, &mut findings);
        let stamp_travel_m = free_stamp_position_m(&config.drive, end);
        let first_onset_estimate_s =
            first_onset(config, &derived, (contact, stamp_travel_m), &mut findings);
        if let Some(period) = spring_period_s.filter(|&p| end > 0.25 * p) {
            findings.push(Finding {
                severity: Severity::Note,
                key: "time.end".into(),
                message: format!(
                    "time.end = {end:e} s is more than a quarter of the spring period 2*pi/omega \
                     = {period:e} s: the stamp no longer follows X = K*V0*t^3/(6m), so runs with \
                     equal K*V0/m need not agree"
                ),
            });
        }
        Self {
            melting_force_n: l.peak_stress_pa(derived.a_coeff_pa) * PI * c.radius_m * c.radius_m,
            critical_displacement_m: l.melting_strain(derived.a_coeff_pa) * c.film_thickness_m,
            derived,
            spring_period_s,
            euler_number,
            lagged_sweep_contraction,
            stamp_travel_m,
            first_onset_estimate_s,
            contact_spring: contact,
            findings,
            first_order: FirstOrderFilm::of(config),
            viscous: ViscousFilm::of(config),
        }
    }

    /// The refusal, if the configuration must not run: the literal scheme's lagged sweep
    /// diverges when ρ ≥ 1 (an oscillating, meaningless history).
    #[must_use]
    pub fn refusal(&self) -> Option<NumericalFailure> {
        self.findings
            .iter()
            .find(|f| f.severity == Severity::Refusal)
            .map(|f| NumericalFailure {
                t_s: 0.0,
                step: 0,
                node: 0,
                r_m: 0.0,
                quantity: "lagged-sweep contraction factor",
                value: self.lagged_sweep_contraction,
                diagnosis: f.message.clone(),
            })
    }

    /// Findings of at least `severity`.
    pub fn at_least(&self, severity: Severity) -> impl Iterator<Item = &Finding> {
        self.findings
            .iter()
            .filter(move |f| f.severity as u8 >= severity as u8)
    }
}

fn lagged_sweep_message(rho: f64) -> String {
    format!(
        "the literal scheme takes u3D from the previous step, a fixed-point sweep that diverges \
         when its contraction factor rho((a*phi0^2/h0)*C/G*) = {rho:.3} is >= 1 (softer \
         substrate or thinner film than the scheme can follow); use time.scheme = \"accurate\", \
         which solves the coupling each step"
    )
}

/// First time in [0, end] at which the free stamp has advanced the melting strain times h0
/// (εc(t)·h0, ε₊(t)·h0 for the first-order film); none if it never does.
fn first_crossing(config: &SimConfig) -> Option<f64> {
    let h0 = config.contact.film_thickness_m;
    crossing(config.time.end_s, |t: f64| {
        let a = config.temperature.a_coeff_pa(t);
        free_stamp_position_m(&config.drive, t).abs() - config.lubricant.melting_strain(a) * h0
    })
}

/// The first t ≥ 0 with gap(t) ≥ 0: [0, end] scanned in 4096 intervals, then the windows
/// [end·2^k, end·2^(k+1)] in 256 each up to end·2^[`CROSSING_DOUBLINGS`], and bisection; none
/// if there is none. Past time.end the search only says when, so the estimate is the same
/// whatever time.end (within the scan's resolution).
fn crossing(end: f64, gap: impl Fn(f64) -> f64) -> Option<f64> {
    let bisect = |mut lo: f64, mut hi: f64| {
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if gap(mid) >= 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    };
    let windows = std::iter::once((0.0, end, 4096))
        .chain((0..CROSSING_DOUBLINGS).map(|k| (end * 2f64.powi(k), end * 2f64.powi(k + 1), 256)));
    for (from, to, scan) in windows {
        let mut lo = from;
        for j in 1..=scan {
            let t = from + (to - from) * j as f64 / scan as f64;
            if gap(t) >= 0.0 {
                return Some(bisect(lo, t));
            }
            lo = t;
        }
    }
    None
}

/// How many times past time.end the onset search doubles its horizon (to end·2^40 ≈ 1e12·end).
const CROSSING_DOUBLINGS: i32 = 40;

/// The literal scheme's findings (explicit Euler's stability number against its limit, the
/// lagged sweep's contraction `rho`): its Euler number, `None` for the accurate scheme.
fn literal_findings(
    config: &SimConfig,
    derived: &Derived,
    rho: f64,
    findings: &mut Vec<Finding>,
) -> Option<f64> {
    let l = &config.lubricant;
    let lagged_sweep_contraction = rho;
    let euler_number = (config.time.scheme == Scheme::Literal).then(|| {
        if l.is_first_order() {
            let phi = derived.phi0;
            config.time.dt_s * l.gamma_per_pa_s * phi * (2.0 * derived.b_pa * phi - l.cubic_pa)
        } else {
            config.time.dt_s * 2.0 * l.gamma_per_pa_s * derived.a_coeff_pa.max(0.0) * derived.b_pa
                / l.a_pa
        }
    });
    if let Some(number) = euler_number.filter(|&n| n > EULER_STABILITY_LIMIT) {
        findings.push(Finding {
            severity: Severity::Warning,
            key: "time.dt".into(),
            message: format!(
                "time.dt x {} = {number:.3} > {EULER_STABILITY_LIMIT}: the literal \
                     scheme's explicit Euler is beyond its stability limit; the run may fail \
                     (exit 3) or finish with wrong numbers. Use time.dt < {:e} s or \
                     time.scheme = \"accurate\".",
                if l.is_first_order() {
                    "gamma*phi0*(2*b*phi0 - b3)"
                } else {
                    "2*gamma*A*b/a"
                },
                EULER_STABILITY_LIMIT * config.time.dt_s / number
            ),
        });
    }
    if config.time.scheme == Scheme::Literal && lagged_sweep_contraction >= 1.0 {
        findings.push(Finding {
            severity: Severity::Refusal,
            key: "time.scheme".into(),
            message: lagged_sweep_message(lagged_sweep_contraction),
        });
    }
    euler_number
}

/// The first onset's estimate, s (`contact`: the contact as a spring when known, else the free
/// stamp's advance alone; `stamp_travel_m`: the free stamp's position at time.end), with the
/// findings that go with it: a film molten from the start, a metastable one, nothing melting
/// within time.end or at all.
fn first_onset(
    config: &SimConfig,
    derived: &Derived,
    (contact, stamp_travel_m): (Option<ContactSpring>, f64),
    findings: &mut Vec<Finding>,
) -> Option<f64> {
    let l = &config.lubricant;
    let c = &config.contact;
    let end = config.time.end_s;
    if !l.starts_solid(derived.a_coeff_pa) {
        findings.push(Finding {
            severity: Severity::Note,
            key: "temperature.A0".into(),
            message: if l.is_first_order() {
                format!(
                    "A = {:e} Pa <= 0 and lubricant.cubic^2 = {:e} Pa^2 < -4*b*A*b/a = {:e} \
                         Pa^2: not even a metastable solid exists, the film is molten from the \
                         start (complete melting, F = 0, smooth sliding)",
                    derived.a_coeff_pa,
                    l.cubic_pa * l.cubic_pa,
                    -4.0 * derived.b_pa * derived.a_coeff_pa * derived.b_pa / l.a_pa
                )
            } else {
                format!(
                    "A = {:e} Pa <= 0: the film is molten from the start (complete melting, \
                         F = 0, smooth sliding)",
                    derived.a_coeff_pa
                )
            },
        });
        Some(0.0)
    } else {
        if derived.a_coeff_pa <= 0.0 {
            findings.push(Finding {
                severity: Severity::Note,
                key: "temperature.A0".into(),
                message: format!(
                    "A = {:e} Pa <= 0, but the first-order film starts as a metastable solid \
                         (phi0 = {:e}): it melts once at eps_melt = {:e} and, with the liquid \
                         stable at every strain, does not re-solidify without noise",
                    derived.a_coeff_pa,
                    derived.phi0,
                    l.melting_strain(derived.a_coeff_pa)
                ),
            });
        }
        // With the contact's spring the stamp is held back by it; without one (a preflight
        // from the configuration alone) the free stamp's advance is all there is. Neither
        // depends on time.end: the search runs on past it.
        let onset = match contact {
            Some(k) => linear_onset(config, k),
            None => first_crossing(config),
        };
        match onset {
            Some(t) if t <= end => {}
            Some(t) => findings.push(Finding {
                severity: Severity::Warning,
                key: "time.end".into(),
                message: format!(
                    "nothing melts within time.end = {end:e} s: the first melting comes at about \
                         {t:.3e} s (first_onset_estimate{}). Lengthen time.end to about {:.2e} s, \
                         or raise drive.velocity.",
                    if contact.is_some() {
                        ", the stamp held back by the contact's stiffness"
                    } else {
                        ""
                    },
                    1.2 * t
                ),
            }),
            // The free stamp's motion overflowed (a dashpot or speed at the edge of the
            // doubles): nothing is known of when it melts, and saying "never" would be
            // wrong; check names the inputs.
            None if !stamp_travel_m.is_finite() => {}
            None => {
                let a_end = config.temperature.a_coeff_pa(end);
                findings.push(Finding {
                        severity: Severity::Warning,
                        key: "time.end".into(),
                        message: format!(
                            "nothing can melt: the drive never advances the stamp the {}*h0 = {:e} m the \
                             film needs (free stamp at time.end: {:e} m). Raise drive.velocity or \
                             the temperature.",
                            if l.is_first_order() {
                                "eps_melt"
                            } else {
                                "eps_c"
                            },
                            l.melting_strain(a_end) * c.film_thickness_m,
                            stamp_travel_m.abs(),
                        ),
                    });
            }
        }
        onset
    }
}
