//! Exact MDR transform pairs (docs/model.md#exact-answers) for verifying the discrete operators.
//!
//! All pairs are written for G* = 1 Pa and unit stress scale, on a contact of radius a0:
//! τ(r) [Pa] ⇔ q(x) = 2∫_x^{a0} rτ/√(r² − x²) dr [N/m] ⇔ u3D(r)·G* [Pa·m] ⇔ F [N].
//! With τ = (a0² − r²)^ν one has q = B(½, ν + 1)·(a0² − x²)^{ν + ½} (B the beta function),
//! which yields the four pairs below.

use std::f64::consts::PI;

/// One exact pair τ ⇔ q ⇔ u3D ⇔ F.
#[derive(Debug, Clone, Copy)]
pub struct ExactPair {
    /// Short name used in tables (`flat_punch`, `uniform`, `smooth`, `smoother`).
    pub name: &'static str,
    /// What it exercises.
    pub description: &'static str,
    /// τ(r, a0) in Pa.
    pub tau: fn(f64, f64) -> f64,
    /// q(x, a0) in N/m.
    pub q: fn(f64, f64) -> f64,
    /// u3D(r, a0)·G* in Pa·m.
    pub u3d_g: fn(f64, f64) -> f64,
    /// F(a0) in N.
    pub force: fn(f64) -> f64,
}

fn edge_sq(a0: f64, r: f64) -> f64 {
    ((a0 - r) * (a0 + r)).max(0.0)
}

/// Flat punch: τ = 1/(π√(a0² − r²)) ⇔ q = 1 ⇔ u3D·G* = 1 ⇔ F = 2a0 (edge singularity).
pub const FLAT_PUNCH: ExactPair = ExactPair {
    name: "flat_punch",
    description: "rigid flat punch, τ ∝ (a0² − r²)^(−1/2): singular at the edge",
    tau: |r, a0| 1.0 / (PI * edge_sq(a0, r).sqrt()),
    q: |_, _| 1.0,
    u3d_g: |_, _| 1.0,
    force: |a0| 2.0 * a0,
};

/// Uniform stress: τ = 1 ⇔ q = 2√(a0² − x²) ⇔ u3D·G* = (4a0/π)E(r/a0) ⇔ F = πa0².
pub const UNIFORM: ExactPair = ExactPair {
    name: "uniform",
    description: "uniform stress, τ = const: q has a square-root edge",
    tau: |_, _| 1.0,
    q: |x, a0| 2.0 * edge_sq(a0, x).sqrt(),
    u3d_g: |r, a0| 4.0 * a0 / PI * elliptic_e_modulus(r / a0),
    force: |a0| PI * a0 * a0,
};

/// Smooth pair: τ = √(a0² − r²) ⇔ q = (π/2)(a0² − x²) ⇔ u3D·G* = (π/2)(a0² − r²/2) ⇔ F = 2πa0³/3.
pub const SMOOTH: ExactPair = ExactPair {
    name: "smooth",
    description: "τ ∝ (a0² − r²)^(1/2): q polynomial, τ has an infinite slope at the edge",
    tau: |r, a0| edge_sq(a0, r).sqrt(),
    q: |x, a0| PI / 2.0 * edge_sq(a0, x),
    u3d_g: |r, a0| PI / 2.0 * (a0 * a0 - r * r / 2.0),
    force: |a0| 2.0 * PI * a0.powi(3) / 3.0,
};

/// Smoother pair: τ = (a0² − r²)^{3/2} ⇔ q = (3π/8)(a0² − x²)²
/// ⇔ u3D·G* = (3π/8)(a0⁴ − a0²r² + 3r⁴/8) ⇔ F = 2πa0⁵/5.
pub const SMOOTHER: ExactPair = ExactPair {
    name: "smoother",
    description: "τ ∝ (a0² − r²)^(3/2): bounded slope everywhere",
    tau: |r, a0| edge_sq(a0, r).powf(1.5),
    q: |x, a0| 3.0 * PI / 8.0 * edge_sq(a0, x).powi(2),
    u3d_g: |r, a0| 3.0 * PI / 8.0 * (a0.powi(4) - a0 * a0 * r * r + 3.0 * r.powi(4) / 8.0),
    force: |a0| 2.0 * PI * a0.powi(5) / 5.0,
};

/// All four pairs, roughest first.
pub const ALL: [ExactPair; 4] = [FLAT_PUNCH, UNIFORM, SMOOTH, SMOOTHER];

/// Complete elliptic integral of the second kind E(k) with modulus k ∈ [0, 1].
///
/// # Panics
/// If k is outside [0, 1] (the elliptic parameter m = k² must be ≤ 1).
#[track_caller]
pub fn elliptic_e_modulus(k: f64) -> f64 {
    ellip::ellipe(k * k).expect("elliptic modulus must lie in [0, 1]")
}
