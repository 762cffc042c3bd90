//! The words of the choice keys: serde enums (the core's where it has them), each with its
//! list of words in the reference's order.

use super::values::Word;
use serde::{Deserialize, Serialize};
pub use stickslip_core::config::{ContactModel, FilmStep, Scheme, Substrate};
pub use stickslip_core::drive::Integrator;

/// Implements [`Word`]: the variants and their serde words, in the reference's order.
macro_rules! words {
    ($ty:ty: $($variant:ident = $word:literal),+ $(,)?) => {
        impl Word for $ty {
            const WORDS: &'static [&'static str] = &[$($word),+];
            const ALL: &'static [Self] = &[$(<$ty>::$variant),+];
        }
    };
}

/// `lubricant.noise.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NoiseKindName {
    /// ξ ~ N(0, σ²Δt) per node and step.
    Gaussian,
    /// Deterministic floor φ ≥ floor.
    Floor,
    /// No noise.
    Off,
}
words!(NoiseKindName: Gaussian = "gaussian", Floor = "floor", Off = "off");
words!(FilmStep: Ramp = "ramp", Frozen = "frozen");

/// `temperature.law`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TemperatureLaw {
    /// A constant.
    Constant,
    /// A(t) = A0·exp(−t/t̃).
    Relaxation,
}
words!(TemperatureLaw: Constant = "constant", Relaxation = "relaxation");

/// `drive.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DriveKind {
    /// Spring of stiffness K and stamp of mass m (Eq. 10).
    Spring,
    /// X = V0·t.
    Rigid,
}
words!(DriveKind: Spring = "spring", Rigid = "rigid");

/// `time.stepping`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stepping {
    /// Error-controlled steps.
    Adaptive,
    /// Fixed steps of `time.dt`.
    Fixed,
}
words!(Stepping: Adaptive = "adaptive", Fixed = "fixed");

/// `time.until`: how long a run goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Until {
    /// To `time.end` (or another stop rule).
    End,
    /// Until the last cycles repeat (see `crate::steady`), at most to `time.end`.
    Periodic,
}
words!(Until: End = "end", Periodic = "periodic");

/// `numerics.operator`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OperatorChoice {
    /// Fast for the accurate scheme, dense for the literal one.
    Auto,
    /// Hierarchical low-rank, O(N) per apply.
    Fast,
    /// Dense mat-vec, O(N²) per apply.
    Dense,
}
words!(OperatorChoice: Auto = "auto", Fast = "fast", Dense = "dense");

/// `contact.grid`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GridChoice {
    /// r_i = i·a0/N, the paper's grid.
    Uniform,
    /// r_i = a0·(1 − (1 − i/N)^p), p = `contact.grading`: nodes clustered toward the edge.
    Graded,
}
words!(GridChoice: Uniform = "uniform", Graded = "graded");

words!(ContactModel: Radial = "radial", Homogeneous = "homogeneous");
words!(Substrate: Elastic = "elastic", Rigid = "rigid");
words!(Scheme: Accurate = "accurate", Literal = "literal");
words!(Integrator: Split = "split", Verlet = "verlet", Rk4 = "rk4");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keys::KeyValue;

    fn check<W: Word + for<'de> Deserialize<'de> + PartialEq + std::fmt::Debug>() {
        assert_eq!(W::ALL.len(), W::WORDS.len());
        for (v, w) in W::ALL.iter().zip(W::WORDS) {
            assert_eq!(&v.show(), w);
            let back: W = toml::Value::String((*w).to_string()).try_into().unwrap();
            assert_eq!(&back, v);
        }
    }

    #[test]
    fn every_listed_word_is_its_variants_serde_name() {
        check::<NoiseKindName>();
        check::<TemperatureLaw>();
        check::<DriveKind>();
        check::<Stepping>();
        check::<Until>();
        check::<OperatorChoice>();
        check::<GridChoice>();
        check::<ContactModel>();
        check::<Substrate>();
        check::<Scheme>();
        check::<Integrator>();
        check::<FilmStep>();
    }
}
