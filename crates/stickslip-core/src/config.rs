//! The resolved configuration of one simulation (what a scene file turns into) and its checks.
//!
//! Errors name the scene key (`contact.radius`), the value and the allowed range, so the
//! command line can pass them to the user unchanged. No TOML here: parsing lives in the
//! `stickslip` crate.

use crate::drive::{Drive, Integrator};
use crate::landau::{LandauParams, Temperature};
use crate::noise::NoiseKind;
pub use events::EventConfig;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A configuration value outside its allowed range.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{key} = {value} is out of range: allowed {allowed}")]
pub struct ConfigError {
    /// Scene key, `section.key`.
    pub key: String,
    /// The offending value as text.
    pub value: String,
    /// The allowed range, in words.
    pub allowed: String,
}

impl ConfigError {
    /// A new error for `key` with `value` and `allowed`.
    pub fn new(key: &str, value: impl std::fmt::Display, allowed: &str) -> Self {
        Self {
            key: key.to_string(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }
}

/// Radial MDR contact or a single homogeneous node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactModel {
    /// φ, ε, τ resolved on the radial grid; substrate by MDR (Eq. 11–16).
    Radial,
    /// One node for the whole contact: uniform τ, substrate as a rigid flat punch of
    /// stiffness 2G*a0 (u3D = F/(2G*a0)), F = πa0²τ.
    Homogeneous,
}

/// Elastic substrate (MDR) or a rigid one (u3D = 0, no operator applied).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Substrate {
    /// u3D from the MDR compliance (Eq. 13–15).
    Elastic,
    /// u3D = 0.
    Rigid,
}

/// The time-stepping scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scheme {
    /// The paper's algorithm: plain sums, explicit Euler, lagged elastic sweep, one reset per step.
    Literal,
    /// Product integration, coupling solved each step, exact Landau step, located crossings.
    Accurate,
}

/// Contact geometry and elasticity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactConfig {
    /// Contact radius a0, m.
    pub radius_m: f64,
    /// Lubricant film thickness h0, m.
    pub film_thickness_m: f64,
    /// Effective shear modulus G* (Eq. 9), Pa.
    pub g_eff_pa: f64,
    /// Number of radial nodes N (forced to 1 for the homogeneous model).
    pub nodes: usize,
    /// How the N nodes are spread over the contact (uniform, or graded toward its edge);
    /// the literal scheme takes the uniform grid only.
    #[serde(default)]
    pub grid: crate::grid::Grading,
    /// Radial or homogeneous.
    pub model: ContactModel,
    /// Elastic or rigid substrate.
    pub substrate: Substrate,
}

/// Time interval and step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimeConfig {
    /// End time, s.
    pub end_s: f64,
    /// Time step Δt, s: the fixed step, or the first step tried when adaptive.
    pub dt_s: f64,
    /// Stepping scheme.
    pub scheme: Scheme,
    /// Error-controlled steps instead of fixed ones (accurate scheme only); `None` = fixed.
    #[serde(default)]
    pub adaptive: Option<AdaptiveConfig>,
}

/// Error control of adaptive stepping (see [`crate::sim::Simulation::step_adaptive`]).
///
/// Each attempt is one accurate step whose local error is estimated from the step itself
/// ([`crate::sim::error_estimate`]) in scales that follow the state ([`crate::sim::StepError`]);
/// it is kept when that error is within `tolerance`, and the next step comes from the PI
/// controller of order 3 ([`crate::sim::step_control`]; docs/model.md#adaptive-steps).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AdaptiveConfig {
    /// Allowed local error per step, relative to the error scales (the scene default is 5e-5).
    pub tolerance: f64,
    /// Longest step, s.
    pub dt_max_s: f64,
    /// Shortest step, s: a step this short is accepted whatever its error (counted as forced).
    pub dt_min_s: f64,
}

/// Numerical controls with documented defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NumericsConfig {
    /// Relative residual to which the accurate scheme solves the elastic coupling (default 1e-10).
    pub coupling_tol: f64,
    /// A step fails as a runaway when |τ| exceeds this multiple of τmax (default 10): the
    /// stationary curve never exceeds τmax and transients stay within a few τmax. For the
    /// first-order film the multiple is of its stationary curve's peak at A(0) when that is
    /// larger ([`crate::landau::LandauParams::peak_stress_pa`]).
    pub runaway_stress_factor: f64,
    /// Form of the MDR transforms; `None` = automatic: fast for the accurate scheme, dense
    /// (the paper's direct sums) for the literal one.
    #[serde(default)]
    pub operator: Option<crate::mdr::OperatorForm>,
    /// The accurate scheme's step of the second-order film (the first-order film's is always
    /// the frozen-strain one).
    #[serde(default)]
    pub film_step: FilmStep,
    /// The smallest scale of a node's φ error in the adaptive step's error norm, as a fraction
    /// of the solid film's φ at zero strain (docs/model.md#adaptive-steps): a node's φ error
    /// is taken relative to max(φ, melt threshold, this·φ_s). 0 (the default) keeps φ
    /// relative down to the melt threshold.
    #[serde(default)]
    pub phi_error_floor: f64,
    /// The φ error's floor for a step that starts while a melting event is open
    /// (docs/model.md#adaptive-steps): such a step takes the larger of this and
    /// `phi_error_floor`; the stick phase up to the next onset (where the onset's error is
    /// made) keeps `phi_error_floor`. 0 (the default) adds nothing.
    #[serde(default)]
    pub event_phi_error_floor: f64,
    /// The factor `time.tolerance` is multiplied by for a step that starts while a melting
    /// event is open (docs/model.md#adaptive-steps): a cascade's steps are taken to a looser
    /// tolerance, the stick phase up to the next onset (where the onset's error is made) to
    /// the scene's. 1 (the default) keeps one tolerance throughout.
    #[serde(default = "NumericsConfig::one")]
    pub event_tolerance_factor: f64,
}

/// The accurate scheme's step of the second-order film (docs/model.md#the-accurate-scheme).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FilmStep {
    /// The frozen-strain exact step, corrected to first order in the film coefficient's
    /// change along the step's strain ramp (u = 1/φ² obeys a linear equation; the correction
    /// is a closed form): the frozen step's error on the approach to melting is removed, and
    /// the step's error estimate is the end strain's prediction error and the correction's
    /// second-order remainder.
    #[default]
    Ramp,
    /// The exact step under a frozen effective strain, its error estimated from its defect
    /// against the strain ramp (the scheme before the ramp correction; kept for comparison).
    Frozen,
}

impl NumericsConfig {
    /// The defaults: the coupling solved to 1e-10 (fixed steps; adaptive steps derive theirs
    /// from the tolerance), runaway at 10·τmax, the operator form chosen by the scheme.
    pub const DEFAULT: Self = Self {
        coupling_tol: 1e-10,
        runaway_stress_factor: 10.0,
        operator: None,
        film_step: FilmStep::Ramp,
        phi_error_floor: 0.0,
        event_phi_error_floor: 0.0,
        event_tolerance_factor: 1.0,
    };

    /// 1, the default of the factors that a configuration written before them lacks.
    const fn one() -> f64 {
        1.0
    }
}

impl Default for NumericsConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Everything one simulation needs, in SI units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimConfig {
    /// Lubricant parameters (Eq. 6, 8).
    pub lubricant: LandauParams,
    /// φ below which a node counts as melted (u0 is held at 0 there); default 0.01.
    pub melt_threshold: f64,
    /// Thermal noise or its deterministic alternative.
    pub noise: NoiseKind,
    /// Temperature law for A (Eq. 17, 18).
    pub temperature: Temperature,
    /// Contact.
    pub contact: ContactConfig,
    /// Drive of the stamp.
    pub drive: Drive,
    /// Integrator of the spring drive.
    pub integrator: Integrator,
    /// Time.
    pub time: TimeConfig,
    /// Numerical controls.
    pub numerics: NumericsConfig,
    /// How melting events are delimited.
    #[serde(default)]
    pub events: EventConfig,
}

pub mod bounds;
mod events;

pub use bounds::{LENGTH_RANGE_M, MAX_NODES, MODULUS_RANGE_PA};

impl SimConfig {
    /// Checks every value; the first problem is returned. Single-key ranges are the
    /// [`bounds`]' (the run library's key registry uses the same ones); the rules between keys
    /// are checked here.
    ///
    /// # Errors
    /// A [`ConfigError`] naming the scene key, value and allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_film()?;
        self.validate_contact()?;
        match self.drive {
            Drive::Spring(s) => {
                bounds::STIFFNESS.check(s.stiffness_n_per_m)?;
                bounds::MASS.check(s.mass_kg)?;
                bounds::VELOCITY.check(s.velocity_m_per_s)?;
                bounds::DAMPING.check(s.damping_n_s_per_m)?;
            }
            Drive::Rigid(r) => {
                bounds::VELOCITY.check(r.velocity_m_per_s)?;
            }
        }
        self.validate_time()?;
        let e = &self.events;
        bounds::EVENT_MERGE_GAP.check(e.merge_gap_s)?;
        bounds::EVENT_RECOVERY.check(e.recovery_factor)?;
        let n = &self.numerics;
        bounds::COUPLING_TOL.check(n.coupling_tol)?;
        bounds::RUNAWAY_STRESS_FACTOR.check(n.runaway_stress_factor)?;
        bounds::PHI_ERROR_FLOOR.check(n.phi_error_floor)?;
        bounds::EVENT_PHI_ERROR_FLOOR.check(n.event_phi_error_floor)?;
        bounds::EVENT_TOLERANCE_FACTOR.check(n.event_tolerance_factor)?;
        self.check_derived()
    }

    /// The lubricant's, the noise's and the temperature's values (see [`SimConfig::validate`]).
    fn validate_film(&self) -> Result<(), ConfigError> {
        let l = &self.lubricant;
        bounds::TAU_MAX.check(l.tau_max_pa)?;
        bounds::EPS_MAX.check(l.eps_max)?;
        bounds::A.check(l.a_pa)?;
        bounds::GAMMA.check(l.gamma_per_pa_s)?;
        bounds::CUBIC.check(l.cubic_pa)?;
        bounds::VISCOSITY.check(l.viscosity_pa_s)?;
        if l.viscosity_pa_s != 0.0 && self.time.scheme == Scheme::Literal {
            return Err(ConfigError::new(
                bounds::VISCOSITY.path,
                bounds::human(l.viscosity_pa_s),
                "0 with time.scheme = \"literal\" (the paper's explicit scheme has no viscous \
                 stress; use time.scheme = \"accurate\", which treats it implicitly)",
            ));
        }
        bounds::MELT_THRESHOLD.check(self.melt_threshold)?;
        match self.noise {
            NoiseKind::Off => {}
            NoiseKind::Floor { floor } => {
                if !(floor.is_finite() && floor >= 0.0 && floor < self.melt_threshold) {
                    return Err(ConfigError::new(
                        bounds::NOISE_FLOOR.path,
                        floor,
                        "finite, >= 0 and below lubricant.melt_threshold",
                    ));
                }
            }
            NoiseKind::Gaussian {
                sigma_per_sqrt_s, ..
            } => {
                bounds::NOISE_SIGMA.check(sigma_per_sqrt_s)?;
            }
        }
        match self.temperature {
            Temperature::Constant { a_coeff_pa } => {
                bounds::TEMPERATURE_A0.check(a_coeff_pa)?;
            }
            Temperature::Relaxation { a0_pa, t_relax_s } => {
                bounds::TEMPERATURE_A0.check(a0_pa)?;
                bounds::T_RELAX.check(t_relax_s)?;
            }
        }
        Ok(())
    }

    /// The contact's values and its grid (see [`SimConfig::validate`]).
    fn validate_contact(&self) -> Result<(), ConfigError> {
        let c = &self.contact;
        bounds::RADIUS.check(c.radius_m)?;
        bounds::FILM_THICKNESS.check(c.film_thickness_m)?;
        bounds::G_EFF.check(c.g_eff_pa)?;
        if self.time.scheme == Scheme::Literal && c.model == ContactModel::Radial && c.nodes < 2 {
            return Err(ConfigError::new(
                bounds::NODES.path,
                c.nodes,
                &format!(
                    "2 ..= {MAX_NODES} with time.scheme = \"literal\" (its sums skip the node \
                     at r = 0, so one node would give F = 0)"
                ),
            ));
        }
        if c.nodes == 0 || c.nodes > MAX_NODES {
            return Err(ConfigError::new(
                bounds::NODES.path,
                c.nodes,
                &format!("1 ..= {MAX_NODES}"),
            ));
        }
        if let crate::grid::Grading::Edge { power } = c.grid {
            if self.time.scheme == Scheme::Literal {
                return Err(ConfigError::new(
                    "contact.grid",
                    "graded",
                    "\"uniform\" with time.scheme = \"literal\" (the paper's sums are defined \
                     on its uniform grid r_i = i·a0/N)",
                ));
            }
            bounds::GRADING.check(power)?;
            if c.model == ContactModel::Radial {
                crate::grid::Grid::graded(c.radius_m, c.nodes, c.grid).map_err(|e| match e {
                    crate::grid::GridError::OutOfRange {
                        field,
                        value,
                        allowed,
                    } => ConfigError::new(field, value, allowed),
                })?;
            }
        }
        Ok(())
    }

    /// The time stepping's values (see [`SimConfig::validate`]).
    fn validate_time(&self) -> Result<(), ConfigError> {
        let t = &self.time;
        bounds::END.check(t.end_s)?;
        if !(t.dt_s.is_finite() && t.dt_s > 0.0 && t.dt_s <= t.end_s) {
            return Err(ConfigError::new(
                bounds::DT.path,
                t.dt_s,
                &format!("finite, > 0 and <= time.end = {:e}", t.end_s),
            ));
        }
        if let Some(a) = &t.adaptive {
            bounds::TOLERANCE.check(a.tolerance)?;
            if !(a.dt_max_s.is_finite() && a.dt_max_s > 0.0 && a.dt_max_s <= t.end_s) {
                return Err(ConfigError::new(
                    bounds::DT_MAX.path,
                    a.dt_max_s,
                    &format!("finite, > 0 and <= time.end = {:e} s", t.end_s),
                ));
            }
            if !(a.dt_min_s.is_finite() && a.dt_min_s > 0.0 && a.dt_min_s <= t.dt_s.min(a.dt_max_s))
            {
                return Err(ConfigError::new(
                    bounds::DT_MIN.path,
                    a.dt_min_s,
                    &format!(
                        "finite, > 0 and <= min(time.dt, time.dt_max) = {:e} s",
                        t.dt_s.min(a.dt_max_s)
                    ),
                ));
            }
            if t.scheme == Scheme::Literal {
                return Err(ConfigError::new(
                    "time.stepping",
                    "adaptive",
                    "\"fixed\" with time.scheme = \"literal\" (the paper's scheme has fixed steps)",
                ));
            }
            if matches!(self.noise, NoiseKind::Gaussian { .. }) {
                return Err(ConfigError::new(
                    "time.stepping",
                    "adaptive",
                    "\"fixed\" with lubricant.noise.kind = \"gaussian\" (a rejected step would \
                     redraw the noise; use \"floor\" or \"off\" for adaptive steps)",
                ));
            }
        }
        Ok(())
    }

    /// The film's derived numbers finite and > 0 (b, and the contact's coupling a/(h0·G*)),
    /// and those of the temperature and the drive finite: a value within its key's range can
    /// still overflow or underflow them (`tau_max = 1e-320` gives b = inf). The error names
    /// the key that moved the number furthest.
    ///
    /// # Errors
    /// As [`bounds::derived_positive`].
    pub fn check_derived(&self) -> Result<(), ConfigError> {
        let l = &self.lubricant;
        bounds::check_film(&self.lubricant)?;
        let c = &self.contact;
        bounds::derived_positive(
            "kappa",
            "a/(h0·G*)",
            l.a_pa / (c.film_thickness_m * c.g_eff_pa),
            &[
                (bounds::A, l.a_pa, 1.0),
                (bounds::FILM_THICKNESS, c.film_thickness_m, -1.0),
                (bounds::G_EFF, c.g_eff_pa, -1.0),
            ],
        )?;
        let a0 = self.temperature.a_coeff_pa(0.0);
        if a0 > 0.0 {
            let b = l.b_pa();
            let factors = [
                (bounds::TEMPERATURE_A0, a0, 0.5),
                (bounds::TAU_MAX, l.tau_max_pa, -0.5),
                (bounds::EPS_MAX, l.eps_max, 1.5),
            ];
            bounds::derived_positive(
                "eps_c",
                "√(A·b)/a = √(2·A·εmax³/τmax)",
                (a0 * b).sqrt() / l.a_pa,
                &factors,
            )?;
            bounds::derived_positive(
                "phi0",
                "√(A/a)",
                (a0 / l.a_pa).sqrt(),
                &[(bounds::TEMPERATURE_A0, a0, 0.5), (bounds::A, l.a_pa, -0.5)],
            )?;
        }
        if let Drive::Spring(s) = self.drive {
            bounds::derived_positive(
                "omega",
                "√(K/m)",
                s.omega_rad_per_s(),
                &[
                    (bounds::STIFFNESS, s.stiffness_n_per_m, 0.5),
                    (bounds::MASS, s.mass_kg, -0.5),
                ],
            )?;
        }
        Ok(())
    }

    /// The operator form actually used (resolves `numerics.operator = None`).
    pub fn operator_form(&self) -> crate::mdr::OperatorForm {
        self.numerics.operator.unwrap_or(match self.time.scheme {
            Scheme::Accurate => crate::mdr::OperatorForm::Fast,
            Scheme::Literal => crate::mdr::OperatorForm::Dense,
        })
    }

    /// Number of nodes actually simulated: N for the radial model, 1 for the homogeneous one.
    pub fn simulated_nodes(&self) -> usize {
        match self.contact.model {
            ContactModel::Radial => self.contact.nodes,
            ContactModel::Homogeneous => 1,
        }
    }
}

/// Derived parameters reported by `stickslip check` and in `run.json`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Derived {
    /// b = 2a²εmax³/τmax, Pa (Eq. 6).
    pub b_pa: f64,
    /// A at t = 0, Pa (Eq. 17/18).
    pub a_coeff_pa: f64,
    /// Critical strain εc = √(A·b)/a at t = 0 (0 when A ≤ 0): where the second-order film
    /// melts, and where a liquid first-order film re-solidifies (ε₋).
    pub eps_c: f64,
    /// The unstrained solid film at t = 0, the initial state: φ0 = √(A/a) (0 when A ≤ 0), or
    /// the first-order film's φ₊(0) = [b₃ + √(b₃² + 4b·A·b/a)]/(2b) (0 when that does not exist).
    pub phi0: f64,
    /// ω = √(K/m) of the spring drive, rad/s (0 for the rigid drive).
    pub omega_rad_per_s: f64,
}

impl Derived {
    /// Derived parameters of `config`.
    pub fn of(config: &SimConfig) -> Self {
        let l = &config.lubricant;
        let a_coeff = config.temperature.a_coeff_pa(0.0);
        Self {
            b_pa: l.b_pa(),
            a_coeff_pa: a_coeff,
            eps_c: l.critical_strain(a_coeff),
            phi0: l.solid_phi(0.0, a_coeff),
            omega_rad_per_s: match config.drive {
                Drive::Spring(s) => s.omega_rad_per_s(),
                Drive::Rigid(_) => 0.0,
            },
        }
    }
}
