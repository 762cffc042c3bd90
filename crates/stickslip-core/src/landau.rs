//! Landau kinetics of the lubricant's order parameter φ (paper Eq. 1–8, 17, 18): parameters,
//! equilibrium, stress, temperature laws and three steppers for Eq. 8 with the strain frozen;
//! [`first_order`] adds the cubic term of the first-order film.
//!
//! Model (SI units throughout; φ is dimensionless, ε is a dimensionless shear strain):
//!
//! - free energy density f = α(T−Tc)φ² + (a/2)φ²ε² + (b/4)φ⁴ (Eq. 1), plus −(b₃/3)φ³ for the
//!   first-order film (b₃ = [`LandauParams::cubic_pa`] > 0; docs/model.md#the-first-order-film);
//! - shear stress τ = a·φ²·ε (Eq. 2, 12);
//! - b = 2a²εmax³/τmax (Eq. 6) and, at constant temperature, A = 1.5·τmax/εmax (Eq. 17);
//! - equilibrium φ0² = A/a − (a/b)ε², zero for ε ≥ εc = √(A·b)/a (Eq. 3, 4);
//! - kinetics dφ/dt = −γ·φ·(a·ε² + b·φ² − A·b/a) + ξ(t) (Eq. 8); the noise ξ lives in
//!   [`crate::noise`], this module handles the deterministic part only.
//!
//! With ε and A frozen over a step, Eq. 8 without noise is a Bernoulli equation. For y = φ² it
//! reads dy/dt = −2γ·y·(c + b·y) with c = a·ε² − A·b/a, whose solution is
//! y(t) = c·y0·e^(−2γct) / (c + b·y0·(1 − e^(−2γct))) (and y0/(1 + 2γ·b·y0·t) for c = 0).
//! [`PhiStepper::Exact`] evaluates it without overflow for any step; [`PhiStepper::ExplicitEuler`]
//! is the paper's scheme; [`PhiStepper::ImplicitEuler`] is a cheap, unconditionally stable
//! first-order alternative. With b₃ > 0 each stepper dispatches to its [`first_order`]
//! counterpart; with b₃ = 0 they run the code above unchanged.

pub mod first_order;

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A lubricant parameter outside its allowed range.
///
/// The message names the field, the offending value and the allowed range, e.g.
/// `invalid tau_max_pa = -1: must be finite and > 0`.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("invalid {field} = {value}: must be {allowed}")]
pub struct LandauParamError {
    /// Name of the offending field (the Rust field name, e.g. `gamma_per_pa_s`).
    pub field: &'static str,
    /// The rejected value.
    pub value: f64,
    /// The allowed range, in words (e.g. `finite and > 0`).
    pub allowed: &'static str,
}

/// Checks that `value` is finite and strictly positive.
fn require_positive(field: &'static str, value: f64) -> Result<(), LandauParamError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(LandauParamError {
            field,
            value,
            allowed: "finite and > 0",
        })
    }
}

/// Material parameters of the Landau model as the user gives them (Eq. 6, 8).
///
/// Fields are public for convenience; [`LandauParams::new`] (or [`LandauParams::validate`])
/// checks that every one of them is finite and > 0. All other functions of this module assume
/// validated parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LandauParams {
    /// Maximum shear stress τmax of the stationary stress–strain curve, Pa.
    pub tau_max_pa: f64,
    /// Strain εmax at which the stationary stress peaks, dimensionless.
    pub eps_max: f64,
    /// Expansion coefficient a of Eq. 1, Pa.
    pub a_pa: f64,
    /// Kinetic coefficient γ of Eq. 8, 1/(Pa·s).
    pub gamma_per_pa_s: f64,
    /// Cubic coefficient b₃ of the first-order film's free energy −(b₃/3)φ³, Pa (≥ 0; 0 is the
    /// paper's second-order film, and then every function here runs the second-order code).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cubic_pa: f64,
    /// Newtonian viscosity η of the film, Pa·s (≥ 0; 0, the default, is the paper's film with
    /// no viscous stress, and then no step computes anything for it): τ gains
    /// η·(Ẋ − u̇3D)/h0 (docs/model.md#viscosity). The film's kinetics (Eq. 8) do not see it.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub viscosity_pa_s: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl LandauParams {
    /// Builds validated parameters.
    ///
    /// # Errors
    /// [`LandauParamError`] naming the first field that is not finite and > 0.
    pub fn new(
        tau_max_pa: f64,
        eps_max: f64,
        a_pa: f64,
        gamma_per_pa_s: f64,
    ) -> Result<Self, LandauParamError> {
        let params = Self {
            tau_max_pa,
            eps_max,
            a_pa,
            gamma_per_pa_s,
            cubic_pa: 0.0,
            viscosity_pa_s: 0.0,
        };
        params.validate()?;
        Ok(params)
    }

    /// The same parameters with the cubic coefficient b₃ (Pa) of the first-order film.
    ///
    /// # Errors
    /// [`LandauParamError`] when b₃ is not finite and ≥ 0.
    pub fn with_cubic(self, cubic_pa: f64) -> Result<Self, LandauParamError> {
        let params = Self { cubic_pa, ..self };
        params.validate()?;
        Ok(params)
    }

    /// Checks that τmax, εmax, a, γ are finite and > 0 and b₃ and η are finite and ≥ 0.
    ///
    /// # Errors
    /// [`LandauParamError`] naming the first offending field.
    pub fn validate(&self) -> Result<(), LandauParamError> {
        require_positive("tau_max_pa", self.tau_max_pa)?;
        require_positive("eps_max", self.eps_max)?;
        require_positive("a_pa", self.a_pa)?;
        require_positive("gamma_per_pa_s", self.gamma_per_pa_s)?;
        if !(self.viscosity_pa_s.is_finite() && self.viscosity_pa_s >= 0.0) {
            return Err(LandauParamError {
                field: "viscosity_pa_s",
                value: self.viscosity_pa_s,
                allowed: "finite and >= 0",
            });
        }
        if self.cubic_pa.is_finite() && self.cubic_pa >= 0.0 {
            Ok(())
        } else {
            Err(LandauParamError {
                field: "cubic_pa",
                value: self.cubic_pa,
                allowed: "finite and >= 0",
            })
        }
    }

    /// Whether the film is the first-order one (b₃ > 0).
    #[must_use]
    pub fn is_first_order(&self) -> bool {
        self.cubic_pa != 0.0
    }

    /// Quartic coefficient b = 2·a²·εmax³/τmax of Eq. 1, in Pa (Eq. 6).
    #[must_use]
    pub fn b_pa(&self) -> f64 {
        2.0 * self.a_pa * self.a_pa * self.eps_max.powi(3) / self.tau_max_pa
    }

    /// Temperature coefficient A = 2α(Tc − T)·a/b at the temperature that produced τmax, εmax:
    /// A = 1.5·τmax/εmax, in Pa (Eq. 17).
    #[must_use]
    pub fn a_coeff_default_pa(&self) -> f64 {
        1.5 * self.tau_max_pa / self.eps_max
    }

    /// Critical strain εc = √(A·b)/a for this A (0 for A ≤ 0); see [`critical_strain`].
    #[must_use]
    pub fn critical_strain(&self, a_coeff_pa: f64) -> f64 {
        critical_strain(a_coeff_pa, self.a_pa, self.b_pa())
    }

    /// Equilibrium order parameter φ0(ε) for this A; see [`equilibrium_phi`].
    #[must_use]
    pub fn equilibrium_phi(&self, eps: f64, a_coeff_pa: f64) -> f64 {
        equilibrium_phi(eps, a_coeff_pa, self.a_pa, self.b_pa())
    }

    /// Bernoulli coefficient c = a·ε² − A·b/a in Pa: y = φ² relaxes as dy/dt = −2γ·y·(c + b·y).
    /// c > 0 means the film melts (y → 0), c < 0 that it grows towards y = −c/b.
    #[must_use]
    pub fn bernoulli_c_pa(&self, eps: f64, a_coeff_pa: f64) -> f64 {
        self.a_pa * eps * eps - a_coeff_pa * self.b_pa() / self.a_pa
    }

    /// The film's free-energy density f = ½·c·φ² − (b₃/3)·φ³ + (b/4)·φ⁴ with c = a·ε² − A·b/a
    /// (Eq. 1 with α(T − Tc) = −A·b/(2a), and the first-order film's cubic term), J/m³:
    /// Eq. 8 is dφ/dt = −γ·∂f/∂φ, so along the film's own path at fixed ε and A it falls
    /// at the rate γ·(∂f/∂φ)², the Landau dissipation; ∂f/∂ε = τ (Eq. 12).
    #[must_use]
    pub fn free_energy_pa(&self, phi: f64, eps: f64, a_coeff_pa: f64) -> f64 {
        // b once (the books call this twice per node and step).
        let (y, b) = (phi * phi, self.b_pa());
        let c = self.a_pa * eps * eps - a_coeff_pa * b / self.a_pa;
        0.5 * c * y - self.cubic_pa / 3.0 * y * phi + 0.25 * b * y * y
    }

    /// The solid film's order parameter at strain ε: [`equilibrium_phi`] (Eq. 3) for b₃ = 0;
    /// for the first-order film the solid branch φ₊(ε) = [b₃ + √(b₃² − 4b·c)]/(2b), c = a·ε² −
    /// A·b/a, while it exists (|ε| ≤ ε₊, [`LandauParams::melting_strain`]), else 0. At ε = 0
    /// this is the film's initial state and the level against which its recovery is measured.
    #[must_use]
    pub fn solid_phi(&self, eps: f64, a_coeff_pa: f64) -> f64 {
        if self.cubic_pa == 0.0 {
            return self.equilibrium_phi(eps, a_coeff_pa);
        }
        match first_order::branches(
            self.bernoulli_c_pa(eps, a_coeff_pa),
            self.b_pa(),
            self.cubic_pa,
        ) {
            first_order::Branches::Real { plus, .. } => plus,
            first_order::Branches::Fold { at } => at,
            first_order::Branches::Liquid => 0.0,
        }
    }

    /// The barrier φ₋(ε) = 2c/(b₃ + √(b₃² − 4b·c)) of the first-order film between the liquid
    /// and the solid branch (negative where the liquid is unstable, c < 0); 0 for b₃ = 0 or
    /// where no solid branch exists.
    #[must_use]
    pub fn barrier_phi(&self, eps: f64, a_coeff_pa: f64) -> f64 {
        if self.cubic_pa == 0.0 {
            return 0.0;
        }
        match first_order::branches(
            self.bernoulli_c_pa(eps, a_coeff_pa),
            self.b_pa(),
            self.cubic_pa,
        ) {
            first_order::Branches::Real { minus, .. } => minus,
            first_order::Branches::Fold { at } => at,
            first_order::Branches::Liquid => 0.0,
        }
    }

    /// The strain at which the solid film melts: εc ([`critical_strain`]) for b₃ = 0; for the
    /// first-order film the end of the solid branch (the fold), ε₊ = √((A·b/a + b₃²/(4b))/a),
    /// where φ drops from b₃/(2b) to 0; 0 when no solid film exists at any strain.
    #[must_use]
    pub fn melting_strain(&self, a_coeff_pa: f64) -> f64 {
        if self.cubic_pa == 0.0 {
            return self.critical_strain(a_coeff_pa);
        }
        let b = self.b_pa();
        let sq =
            (a_coeff_pa * b / self.a_pa + self.cubic_pa * self.cubic_pa / (4.0 * b)) / self.a_pa;
        if sq > 0.0 { sq.sqrt() } else { 0.0 }
    }

    /// The strain below which a liquid film re-solidifies (φ = 0 loses stability): εc for either
    /// film (ε₋ = εc, [`critical_strain`]); the first-order film jumps there to φ₊(εc) = b₃/b.
    #[must_use]
    pub fn solidification_strain(&self, a_coeff_pa: f64) -> f64 {
        self.critical_strain(a_coeff_pa)
    }

    /// Width of the first-order film's hysteresis in the squared strain, ε₊² − ε₋² =
    /// b₃²/(4·a·b), independent of temperature (while A > 0); 0 for b₃ = 0.
    #[must_use]
    pub fn hysteresis_width(&self) -> f64 {
        self.cubic_pa * self.cubic_pa / (4.0 * self.a_pa * self.b_pa())
    }

    /// Shear stress on the solid branch where it ends, τ(ε₊) = a·(b₃/(2b))²·ε₊, Pa (for b₃ = 0
    /// the branch ends at εc with φ = 0: τ = 0).
    #[must_use]
    pub fn melting_stress_pa(&self, a_coeff_pa: f64) -> f64 {
        let phi = self.cubic_pa / (2.0 * self.b_pa());
        stress(phi, self.melting_strain(a_coeff_pa), self.a_pa)
    }

    /// The largest stress on the stationary stress–strain curve, Pa: τmax for the second-order
    /// film (its parameter, Eq. 6); for the first-order film the peak of τ = a·φ₊(ε)²·ε over
    /// the solid branch at this A, which the cubic term raises above τmax. Where
    /// d(φ₊²ε)/dε = 0, φ₊ + 2ε·φ₊' = 0 with φ₊' = −2aε/(2bφ₊ − b₃), so 6b·φ² − 5b₃·φ − 4A' = 0
    /// (A' = A·b/a): φ* = [5b₃ + √(25b₃² + 96b·A')]/(12b), ε*² = (A' + b₃φ* − bφ*²)/a; else the
    /// curve peaks where the branch ends, at ε₊. 0 when no solid film exists.
    #[must_use]
    pub fn peak_stress_pa(&self, a_coeff_pa: f64) -> f64 {
        if self.cubic_pa == 0.0 {
            return self.tau_max_pa;
        }
        let (a, b, b3) = (self.a_pa, self.b_pa(), self.cubic_pa);
        let ap = a_coeff_pa * b / a;
        let at_end = if self.solid_phi(0.0, a_coeff_pa) > 0.0 {
            self.melting_stress_pa(a_coeff_pa)
        } else {
            0.0
        };
        let disc = 25.0 * b3 * b3 + 96.0 * b * ap;
        if disc < 0.0 {
            return at_end;
        }
        let phi = (5.0 * b3 + disc.sqrt()) / (12.0 * b);
        let eps_sq = (ap + b3 * phi - b * phi * phi) / a;
        if eps_sq > 0.0 && 2.0 * b * phi >= b3 {
            at_end.max(stress(phi, eps_sq.sqrt(), a))
        } else {
            at_end
        }
    }

    /// Whether an unstrained film can start solid: always when A > 0; for A ≤ 0 only the
    /// first-order film, as a metastable solid, while b₃² ≥ −4b·A·b/a (the liquid is then
    /// stable at every strain, and a film that melts never re-solidifies without noise).
    #[must_use]
    pub fn starts_solid(&self, a_coeff_pa: f64) -> bool {
        a_coeff_pa > 0.0 || (self.cubic_pa > 0.0 && self.solid_phi(0.0, a_coeff_pa) > 0.0)
    }

    /// b₃ (Pa) that puts the first-order film's melting strain at `eps_melt` for this A:
    /// b₃ = 2·√(b·(a·ε₊² − A·b/a)) (= 2·√(a·b·(ε₊² − εc²)) for A > 0); `None` unless
    /// ε₊ > εc (so b₃ > 0) and the result is finite.
    #[must_use]
    pub fn cubic_for_melting_strain(&self, eps_melt: f64, a_coeff_pa: f64) -> Option<f64> {
        let b = self.b_pa();
        let inner = b * (self.a_pa * eps_melt * eps_melt - a_coeff_pa * b / self.a_pa);
        let b3 = 2.0 * inner.sqrt();
        (eps_melt.is_finite()
            && eps_melt > self.critical_strain(a_coeff_pa)
            && b3.is_finite()
            && b3 > 0.0)
            .then_some(b3)
    }
}

/// Critical strain εc = √(A·b)/a above which the solid film has no equilibrium (Eq. 4).
///
/// Returns 0 when A ≤ 0 (the film is molten at any strain). Never NaN for a > 0, b > 0.
#[must_use]
pub fn critical_strain(a_coeff_pa: f64, a_pa: f64, b_pa: f64) -> f64 {
    if a_coeff_pa > 0.0 {
        (a_coeff_pa * b_pa).sqrt() / a_pa
    } else {
        0.0
    }
}

/// Equilibrium order parameter φ0 = √(max(0, A/a − (a/b)·ε²)) (Eq. 3).
///
/// Returns 0 for A ≤ 0 or |ε| ≥ εc; never NaN for finite inputs with a > 0, b > 0.
#[must_use]
pub fn equilibrium_phi(eps: f64, a_coeff_pa: f64, a_pa: f64, b_pa: f64) -> f64 {
    let phi_sq = a_coeff_pa / a_pa - (a_pa / b_pa) * eps * eps;
    if phi_sq > 0.0 { phi_sq.sqrt() } else { 0.0 }
}

/// Deterministic right-hand side of Eq. 8: dφ/dt = −γ·φ·(a·ε² + b·φ² − A·b/a), in 1/s; for
/// the first-order film −γ·φ·(a·ε² + b·φ² − b₃·φ − A·b/a) ([`first_order::rhs`]).
#[must_use]
pub fn rhs(phi: f64, eps: f64, a_coeff_pa: f64, params: &LandauParams) -> f64 {
    if params.cubic_pa != 0.0 {
        return first_order::rhs(
            phi,
            params.bernoulli_c_pa(eps, a_coeff_pa),
            params.b_pa(),
            params.cubic_pa,
            params.gamma_per_pa_s,
        );
    }
    second_order_rhs(phi, eps, a_coeff_pa, params)
}

/// [`rhs`] of the second-order film (b₃ ignored).
pub(crate) fn second_order_rhs(phi: f64, eps: f64, a_coeff_pa: f64, params: &LandauParams) -> f64 {
    let a = params.a_pa;
    let b = params.b_pa();
    -params.gamma_per_pa_s * phi * (a * eps * eps + b * phi * phi - a_coeff_pa * b / a)
}

/// Shear stress of the film τ = a·φ²·ε, in Pa (Eq. 2, 12).
#[must_use]
pub fn stress(phi: f64, eps: f64, a_pa: f64) -> f64 {
    a_pa * phi * phi * eps
}

/// Temperature law, expressed through the coefficient A(t) (Eq. 17, 18).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Temperature {
    /// Constant temperature: A(t) = `a_coeff_pa` (Eq. 17 gives the default 1.5·τmax/εmax).
    Constant {
        /// A in Pa; any finite value (A ≤ 0 means a completely molten film).
        a_coeff_pa: f64,
    },
    /// Heating lubricant: A(t) = A0·exp(−t/t̃) (Eq. 18).
    Relaxation {
        /// A0 = A(0) in Pa; any finite value.
        a0_pa: f64,
        /// Relaxation time t̃ in s; finite and > 0.
        t_relax_s: f64,
    },
}

impl Temperature {
    /// The coefficient A(t) in Pa at time `t_s`: constant, or A0·exp(−t/t̃) (Eq. 18).
    #[must_use]
    pub fn a_coeff_pa(&self, t_s: f64) -> f64 {
        match *self {
            Self::Constant { a_coeff_pa } => a_coeff_pa,
            Self::Relaxation { a0_pa, t_relax_s } => a0_pa * (-t_s / t_relax_s).exp(),
        }
    }

    /// Checks that A (or A0) is finite and that t̃ is finite and > 0.
    ///
    /// # Errors
    /// [`LandauParamError`] naming the offending field.
    pub fn validate(&self) -> Result<(), LandauParamError> {
        let finite = |field, value: f64| {
            if value.is_finite() {
                Ok(())
            } else {
                Err(LandauParamError {
                    field,
                    value,
                    allowed: "finite",
                })
            }
        };
        match *self {
            Self::Constant { a_coeff_pa } => finite("a_coeff_pa", a_coeff_pa),
            Self::Relaxation { a0_pa, t_relax_s } => {
                finite("a0_pa", a0_pa)?;
                require_positive("t_relax_s", t_relax_s)
            }
        }
    }
}

/// Time stepper for Eq. 8 without noise over one step Δt, with ε and A frozen over the step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PhiStepper {
    /// The paper's explicit Euler: φ1 = φ0 + Δt·rhs(φ0).
    ///
    /// First order; unstable once Δt·|∂rhs/∂φ| > 2 (at the solid equilibrium with ε = 0,
    /// |∂rhs/∂φ| = 2γ·A·b/a). The raw value is returned — it may be negative, huge or NaN —
    /// so that callers of the literal scheme see the instability instead of a clamped number.
    ExplicitEuler,
    /// The closed-form solution of the frozen-ε Bernoulli equation; exact up to rounding for
    /// any Δt ≥ 0 and never overflowing. See [`exact_phi`].
    Exact,
    /// Backward Euler on y = φ²: y1 = y0 − 2γΔt·y1·(c + b·y1), solved in closed form for its
    /// positive root. First order, unconditionally stable, positivity preserving.
    ImplicitEuler,
}

impl PhiStepper {
    /// Advances φ by `dt_s` with strain `eps` and coefficient `a_coeff_pa` frozen.
    ///
    /// - `ExplicitEuler`: φ + Δt·[`rhs`]`(φ, ε, A)` (raw, may be < 0 or non-finite);
    /// - `Exact`: [`exact_phi`]`(φ, ε, A, params, Δt)`, ≥ 0;
    /// - `ImplicitEuler`: with c = a·ε² − A·b/a, y0 = φ², α = 1 + 2γΔt·c, β = 2γΔt·b, the
    ///   positive root of β·y1² + α·y1 − y0 = 0,
    ///   y1 = 2·y0 / (α + √(α² + 4β·y0)) for α ≥ 0 and y1 = (√(α² + 4β·y0) − α)/(2β) for α < 0
    ///   (the same root, each form free of cancellation); returns √y1 ≥ 0.
    ///   For α < 0 (Δt > 1/(2γ|c|) in a growth regime) a tiny y0 > 0 jumps to y1 ≈ −α/β, a
    ///   known large-step artifact of backward Euler; y0 = 0 stays 0.
    ///
    /// `Exact` and `ImplicitEuler` use |φ| (Eq. 8 is odd in φ, so the sign carries no
    /// information) and return a value ≥ 0. `dt_s` must be ≥ 0.
    ///
    /// With b₃ > 0 (the first-order film) the three run [`first_order::rhs`],
    /// [`first_order::exact_phi`] and [`first_order::implicit_euler_phi`] instead.
    #[must_use]
    pub fn step(
        &self,
        phi: f64,
        eps: f64,
        a_coeff_pa: f64,
        params: &LandauParams,
        dt_s: f64,
    ) -> f64 {
        if params.cubic_pa != 0.0 {
            let c = params.bernoulli_c_pa(eps, a_coeff_pa);
            let (b, b3, g) = (params.b_pa(), params.cubic_pa, params.gamma_per_pa_s);
            return match self {
                Self::ExplicitEuler => phi + dt_s * first_order::rhs(phi, c, b, b3, g),
                Self::Exact => first_order::exact_phi(phi, c, b, b3, g, dt_s),
                Self::ImplicitEuler => first_order::implicit_euler_phi(phi, c, b, b3, g, dt_s),
            };
        }
        match self {
            Self::ExplicitEuler => phi + dt_s * rhs(phi, eps, a_coeff_pa, params),
            Self::Exact => exact_phi(phi, eps, a_coeff_pa, params, dt_s),
            Self::ImplicitEuler => implicit_euler_phi(phi, eps, a_coeff_pa, params, dt_s),
        }
    }
}

/// Backward Euler on y = φ² (see [`PhiStepper::ImplicitEuler`]).
fn implicit_euler_phi(
    phi: f64,
    eps: f64,
    a_coeff_pa: f64,
    params: &LandauParams,
    dt_s: f64,
) -> f64 {
    let phi = phi.abs();
    if dt_s == 0.0 || phi == 0.0 {
        return phi;
    }
    let y0 = phi * phi;
    let two_gamma_dt = 2.0 * params.gamma_per_pa_s * dt_s;
    let alpha = 1.0 + two_gamma_dt * params.bernoulli_c_pa(eps, a_coeff_pa);
    let beta = two_gamma_dt * params.b_pa();
    // √(α² + 4β·y0) without overflowing α².
    let root = alpha.hypot(2.0 * (beta * y0).sqrt());
    let y1 = if alpha >= 0.0 {
        2.0 * y0 / (alpha + root)
    } else {
        (root - alpha) / (2.0 * beta)
    };
    y1.sqrt()
}

/// Exact solution φ(t) of dφ/dt = −γ·φ·(a·ε² + b·φ² − A·b/a) with ε, A frozen, from φ(0) = φ0.
///
/// With y = φ², c = a·ε² − A·b/a:
/// y(t) = c·y0·e^(−2γct) / (c + b·y0·(1 − e^(−2γct))), and y0/(1 + 2γ·b·y0·t) for c = 0.
///
/// Evaluated without overflow for any t ≥ 0: with s = |c|, w = 2γ·s·t, e = e^(−w) ≤ 1 and
/// h = (1 − e^(−w))/s = −expm1(−w)/s (→ 2γt as s → 0; taken as 2γt when s is 0 or subnormal),
///
/// - c ≥ 0 (melting): y = y0·e / (1 + b·y0·h);
/// - c < 0 (growth, numerator and denominator divided by e^(2γ|c|t)): y = 1 / (e/y0 + b·h),
///   which tends to the equilibrium −c/b for t → ∞ instead of overflowing.
///
/// All terms are non-negative, so there is no cancellation and the result is exact up to a few
/// rounding errors. Uses |φ0| (Eq. 8 is odd in φ); returns |φ(t)| ≥ 0, and 0 for φ0 = 0.
/// φ0 must satisfy φ0² < f64::MAX.
///
/// # Example
/// ```
/// use stickslip_core::landau::{LandauParams, exact_phi};
/// let p = LandauParams::new(1e6, 1.0, 1e6, 10.0).unwrap();
/// let a_coeff = p.a_coeff_default_pa();
/// // Growth at ε = 0 over a huge step lands on the equilibrium √(A/a) = √1.5.
/// let phi = exact_phi(1e-3, 0.0, a_coeff, &p, 1e3);
/// assert!((phi - 1.5f64.sqrt()).abs() < 1e-15);
/// // Beyond εc = √3 the film melts.
/// assert!(exact_phi(1.2, 2.0, a_coeff, &p, 1e-6) < 1e-4);
/// ```
///
/// With b₃ > 0 this is [`first_order::exact_phi`] (the Bernoulli form above does not hold).
#[must_use]
pub fn exact_phi(phi0: f64, eps: f64, a_coeff_pa: f64, params: &LandauParams, t_s: f64) -> f64 {
    if params.cubic_pa != 0.0 {
        return first_order::exact_phi(
            phi0,
            params.bernoulli_c_pa(eps, a_coeff_pa),
            params.b_pa(),
            params.cubic_pa,
            params.gamma_per_pa_s,
            t_s,
        );
    }
    bernoulli_phi(phi0, eps, a_coeff_pa, params, t_s)
}

/// [`exact_phi`] of the second-order film (b₃ ignored): the closed form above.
pub(crate) fn bernoulli_phi(
    phi0: f64,
    eps: f64,
    a_coeff_pa: f64,
    params: &LandauParams,
    t_s: f64,
) -> f64 {
    let (e, m) = crate::vexp::exp_expm1(bernoulli_exponent(eps, a_coeff_pa, params, t_s));
    bernoulli_finish(phi0, eps, a_coeff_pa, params, t_s, (e, m))
}

/// The argument −w = −2γ·|c|·t of [`bernoulli_phi`]'s one exponential (ignored when |c| is
/// not a normal number): computed for every node first, so that the exponentials of all nodes
/// are taken in one vectorised loop ([`crate::vexp::exp_expm1_all`]).
#[inline(always)]
pub(crate) fn bernoulli_exponent(
    eps: f64,
    a_coeff_pa: f64,
    params: &LandauParams,
    t_s: f64,
) -> f64 {
    let two_gamma = 2.0 * params.gamma_per_pa_s;
    -(two_gamma * params.bernoulli_c_pa(eps, a_coeff_pa).abs() * t_s)
}

/// [`bernoulli_phi`] given (e^(−w), e^(−w) − 1) of [`bernoulli_exponent`]'s argument.
#[inline(always)]
pub(crate) fn bernoulli_finish(
    phi0: f64,
    eps: f64,
    a_coeff_pa: f64,
    params: &LandauParams,
    t_s: f64,
    (e_w, m_w): (f64, f64),
) -> f64 {
    let phi0 = phi0.abs();
    if t_s == 0.0 || phi0 == 0.0 {
        return phi0;
    }
    let y0 = phi0 * phi0;
    let b = params.b_pa();
    let two_gamma = 2.0 * params.gamma_per_pa_s;
    let c = params.bernoulli_c_pa(eps, a_coeff_pa);
    let s = c.abs();
    let (e, h) = if s.is_normal() {
        let w = two_gamma * s * t_s;
        // One exponential per node (`vexp`, within 2 ulp of libm's): below ln 2,
        // e = 1 + expm1(−w) ≥ ½ is as accurate as exp(−w); above, 1 − e with e < ½ has no
        // cancellation.
        // (One division per node where three would do the same: divisions dominate a
        // node's arithmetic.)
        let inv_s = 1.0 / s;
        if w <= std::f64::consts::LN_2 {
            (1.0 + m_w, -m_w * inv_s)
        } else {
            (e_w, (1.0 - e_w) * inv_s)
        }
    } else {
        (1.0, two_gamma * t_s)
    };
    // Growth y0·e/(1 + b·y0·h); decay 1/(e/y0 + b·h), taken as y0/(e + b·y0·h).
    let y = if c >= 0.0 {
        y0 * e / (1.0 + b * y0 * h)
    } else {
        y0 / (e + b * y0 * h)
    };
    y.sqrt()
}

/// [`bernoulli_finish`] with selects in place of branches, bit for bit the same value (the
/// same operations on the taken paths; the untaken ones are computed and discarded), so that
/// a loop over nodes under [`crate::vexp`]'s instruction-set dispatch vectorises. `b_pa` and
/// `two_gamma` are [`LandauParams::b_pa`] and 2γ, hoisted by the caller.
#[inline(always)]
pub(crate) fn bernoulli_finish_select(
    phi0: f64,
    eps: f64,
    a_coeff_pa: f64,
    (params, b_pa, two_gamma): (&LandauParams, f64, f64),
    t_s: f64,
    (e_w, m_w): (f64, f64),
) -> f64 {
    let phi0 = phi0.abs();
    let y0 = phi0 * phi0;
    let c = params.a_pa * eps * eps - a_coeff_pa * b_pa / params.a_pa;
    let s = c.abs();
    let w = two_gamma * s * t_s;
    let small = w <= std::f64::consts::LN_2;
    let normal = s.is_normal();
    let e_small = 1.0 + m_w;
    let inv_s = 1.0 / s;
    let h_small = -m_w * inv_s;
    let h_large = (1.0 - e_w) * inv_s;
    let e = if !normal {
        1.0
    } else if small {
        e_small
    } else {
        e_w
    };
    let h = if !normal {
        two_gamma * t_s
    } else if small {
        h_small
    } else {
        h_large
    };
    // One division: the growth's and the decay's numerators and denominators selected first.
    let grow = c >= 0.0;
    let bh = b_pa * y0 * h;
    let numerator = if grow { y0 * e } else { y0 };
    let denominator = if grow { 1.0 + bh } else { e + bh };
    let y = numerator / denominator;
    let root = y.sqrt();
    if t_s == 0.0 || phi0 == 0.0 {
        phi0
    } else {
        root
    }
}

#[cfg(test)]
mod finish_tests {
    use super::*;

    #[test]
    fn the_select_form_is_the_branch_form_bit_for_bit() {
        // Every path: c of either sign and zero, w either side of ln 2, φ0 of either sign and
        // zero, a zero step; arguments spread over many decades.
        // fig2's film.
        let params = LandauParams::new(1e6, 1.0, 1e6, 10.0).expect("valid");
        let (b, two_gamma) = (params.b_pa(), 2.0 * params.gamma_per_pa_s);
        let a_c = 1.5e6;
        let eps_c = (a_c * b).sqrt() / params.a_pa;
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for k in 0..200_000 {
            let phi0 = match k % 7 {
                0 => 0.0,
                1 => -(next() * 1.3),
                _ => 10f64.powf(-8.0 * next()) * 1.3,
            };
            let eps = match k % 5 {
                0 => eps_c,
                1 => -eps_c,
                _ => 3.0 * (next() - 0.3),
            };
            let t_s = match k % 11 {
                0 => 0.0,
                _ => 10f64.powf(-12.0 + 10.0 * next()),
            };
            let x = bernoulli_exponent(eps, a_c, &params, t_s);
            let em = crate::vexp::exp_expm1(x);
            let want = bernoulli_finish(phi0, eps, a_c, &params, t_s, em);
            let got = bernoulli_finish_select(phi0, eps, a_c, (&params, b, two_gamma), t_s, em);
            assert_eq!(
                want.to_bits(),
                got.to_bits(),
                "phi0 {phi0:e} eps {eps:e} t {t_s:e}: {want:e} vs {got:e}"
            );
            checked += 1;
        }
        assert_eq!(checked, 200_000);
    }
}
