//! How melting events are delimited: the settings of the event tracker
//! ([`crate::sim::events`]), kept with the configuration that holds them.

use serde::{Deserialize, Serialize};

/// How events are delimited (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EventConfig {
    /// A melting that begins less than this after the previous event ended continues that
    /// event, s (0 = never).
    pub merge_gap_s: f64,
    /// k of the recovery level φ_rec = min(k·threshold, ½·(threshold + φ_eq)); > 1.
    pub recovery_factor: f64,
}

impl Default for EventConfig {
    fn default() -> Self {
        Self {
            merge_gap_s: 0.0,
            recovery_factor: 2.0,
        }
    }
}

impl EventConfig {
    /// The recovery level φ_rec for melting threshold `threshold` and the solid equilibrium
    /// `phi_eq` (√(A/a), or the first-order film's φ₊(0)) now. When φ_eq ≤ threshold no solid
    /// film exists, and φ_rec is
    /// k·threshold (out of reach: the event stays open).
    #[must_use]
    pub fn recovery_phi(&self, threshold: f64, phi_eq: f64) -> f64 {
        let level = self.recovery_factor * threshold;
        if phi_eq > threshold {
            level.min(0.5 * (threshold + phi_eq))
        } else {
            level
        }
    }
}
