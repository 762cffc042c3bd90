//! The energy books: where the drive's work goes, step by step, for any scheme.
//!
//! ## What is stored
//! At any instant ([`StoredEnergy`]): the spring's ½K·(V0·t − X)², the stamp's ½m·V², the film's
//! free energy h0·∫f dA (f = ½c·φ² − (b₃/3)φ³ + (b/4)φ⁴, c = a·ε² − A·b/a: its Landau part and
//! its elastic ½a·φ²·ε² together) and the substrate's ½∫τ·u3D dA. The integrals over the
//! contact use the force's quadrature weights (F = Σ w_i τ_i), so the stamp's work F·V and the
//! film's are summed alike.
//!
//! ## What flows ([`EnergyFlows`], cumulative since t = 0)
//! In: the **drive's work** (the spring's free end moved at V0 against the spring's and the
//! dashpot's tension, V0·(K·(V0·t − X) + c_d·(V0 − V)); the rigid coupler's F·V0), the
//! **temperature's** (∂f/∂A·Ȧ at fixed φ and ε: the free energy the film gains as A(t) falls,
//! supplied by the heat bath), and the **noise's** (what the φ floor or the noise adds to f).
//! Out, the sinks:
//! - **Landau**: γ·(∂f/∂φ)² per volume, the film's relaxation. Each scheme computes it from its
//!   own film step: the accurate one as the drop of f along the exact path at the step's frozen
//!   strain (exact for that path), the literal one from its Euler step.
//! - **reset**: the film's elastic energy removed when u0 is reset to 0 at a melting,
//!   ½a·φ²·(ε_before² − ε_after²)·h0 per area at the located melting (which the model
//!   discards: it is the energy of the strain the stamp's surface no longer carries).
//! - **sliding**: the work the stamp does on melted nodes, whose u0 is held at 0 while the
//!   stamp moves: ∫τ·(V − u̇0) dA. τ there is a·φ²·ε with φ below the melt threshold, so this
//!   is small, and it can be negative (the substrate strains a held node backwards).
//! - **viscous**: η·(Ẋ − u̇3D)²/h0 per area, when `lubricant.viscosity` > 0.
//! - **dashpot**: c_d·(V0 − V)², when `drive.damping` > 0.
//!
//! The books are computed by `books` (the stored energy, the drive's and the temperature's
//! work) and by each stepper (its sinks); this module holds what they hand on.
//!
//! The rates that are smooth over a step (temperature, viscous, dashpot, sliding, the rigid
//! coupler's F·V0) are integrated by the trapezoidal rule, second order; the spring's work
//! with the end-corrected trapezoidal rule, fourth order. The **residual** is
//! in − sinks − (stored now − stored at t = 0): zero for the exact solution of the model, and for
//! a scheme the sum of its time-stepping error and of the discrete operators' departure from
//! reciprocity (d/dt ½∫τ·u3D dA = ∫τ·u̇3D dA holds for a symmetric compliance, and the
//! discrete one is symmetric only to the spatial discretisation's order).

use serde::{Deserialize, Serialize};

/// Energy that entered or left since t = 0 (or over a cycle), J.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct EnergyFlows {
    /// Work of the drive on the stamp, J.
    pub drive_work_j: f64,
    /// Free energy the film gained from the change of A(t) at fixed φ and ε, J.
    pub temperature_work_j: f64,
    /// Free energy the φ floor or the noise added to the film, J.
    pub noise_work_j: f64,
    /// Landau dissipation γ·(∂f/∂φ)², J.
    pub landau_j: f64,
    /// Elastic energy removed by the u0 resets at meltings, J.
    pub reset_j: f64,
    /// Work of the stamp on melted nodes, whose u0 is held, J.
    pub sliding_j: f64,
    /// Viscous dissipation of the film, J.
    pub viscous_j: f64,
    /// Dissipation of the drive's dashpot, J.
    pub dashpot_j: f64,
}

impl EnergyFlows {
    /// Every sink together, J.
    #[must_use]
    pub fn dissipated_j(&self) -> f64 {
        self.landau_j + self.reset_j + self.sliding_j + self.viscous_j + self.dashpot_j
    }

    /// Everything that entered, J.
    #[must_use]
    pub fn input_j(&self) -> f64 {
        self.drive_work_j + self.temperature_work_j + self.noise_work_j
    }

    /// `self + w·other`, field by field.
    #[must_use]
    pub fn plus_scaled(&self, other: &Self, w: f64) -> Self {
        Self {
            drive_work_j: self.drive_work_j + w * other.drive_work_j,
            temperature_work_j: self.temperature_work_j + w * other.temperature_work_j,
            noise_work_j: self.noise_work_j + w * other.noise_work_j,
            landau_j: self.landau_j + w * other.landau_j,
            reset_j: self.reset_j + w * other.reset_j,
            sliding_j: self.sliding_j + w * other.sliding_j,
            viscous_j: self.viscous_j + w * other.viscous_j,
            dashpot_j: self.dashpot_j + w * other.dashpot_j,
        }
    }
}

/// Energy stored at one instant, J.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct StoredEnergy {
    /// The drive's spring, ½K·(V0·t − X)², J.
    pub spring_j: f64,
    /// The stamp's kinetic energy ½m·V², J.
    pub kinetic_j: f64,
    /// The film's free energy h0·∫f dA, J (negative: the solid film's f is below the liquid's 0).
    pub film_j: f64,
    /// The substrate's elastic energy ½∫τ·u3D dA, J.
    pub substrate_j: f64,
}

impl StoredEnergy {
    /// All of it, J.
    #[must_use]
    pub fn total_j(&self) -> f64 {
        self.spring_j + self.kinetic_j + self.film_j + self.substrate_j
    }

    /// `self + w·(other − self)`, field by field.
    #[must_use]
    pub fn lerp(&self, other: &Self, w: f64) -> Self {
        let l = |a: f64, b: f64| a + w * (b - a);
        Self {
            spring_j: l(self.spring_j, other.spring_j),
            kinetic_j: l(self.kinetic_j, other.kinetic_j),
            film_j: l(self.film_j, other.film_j),
            substrate_j: l(self.substrate_j, other.substrate_j),
        }
    }
}

/// The books at one instant: the flows since t = 0 and what is stored now and was at t = 0.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct EnergyBooks {
    /// Flows since t = 0, J.
    pub flows: EnergyFlows,
    /// Stored now, J.
    pub stored: StoredEnergy,
    /// Stored at t = 0, J.
    pub stored_initial: StoredEnergy,
}

impl EnergyBooks {
    /// in − sinks − (stored now − stored at t = 0), J: see the module docs.
    #[must_use]
    pub fn residual_j(&self) -> f64 {
        residual_j(&self.flows, &self.stored_initial, &self.stored)
    }
}

/// in − sinks − (stored at the end − stored at the start), J.
#[must_use]
pub fn residual_j(flows: &EnergyFlows, start: &StoredEnergy, end: &StoredEnergy) -> f64 {
    flows.input_j() - flows.dissipated_j() - (end.total_j() - start.total_j())
}

/// The sinks a stepper computes from its own film step, J (see the module docs); the generic
/// part of the books (`books`) adds the rest.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepSinks {
    /// Landau dissipation, J.
    pub landau_j: f64,
    /// u0 resets, J.
    pub reset_j: f64,
    /// Work on held (melted) nodes, J.
    pub sliding_j: f64,
    /// Viscous dissipation, J.
    pub viscous_j: f64,
    /// Free energy the φ floor or the noise added, J.
    pub noise_work_j: f64,
}
