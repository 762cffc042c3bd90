//! Reproducible thermal noise ξ(t) of Eq. 8 (one seeded ChaCha8 stream per node), its
//! deterministic alternative (a floor on φ), and a serializable generator snapshot.
//!
//! Convention (the paper gives no amplitude): over a step Δt each node receives
//! ξ ~ N(0, σ²·Δt), σ in s^-1/2, added after the deterministic Landau step:
//!
//! φ ← |φ + σ·√Δt·Z|, Z ~ N(0, 1) independent per node and step.
//!
//! This is the Euler–Maruyama step of dφ = rhs(φ)·dt + σ·dW. The absolute value is a reflection
//! at φ = 0: the drift of Eq. 8 is odd in φ (rhs(−φ) = −rhs(φ)) and the noise is symmetric, so
//! the process is symmetric under φ → −φ and |φ| follows exactly the same law as φ would; the
//! reflection only picks the representative φ ≥ 0 that the rest of the model assumes.
//! A molten node (c = a·ε² − A·b/a > 0) then fluctuates about 0 with the Ornstein–Uhlenbeck
//! spread φ ~ σ/√(2γc), e.g. ≈ 2e-4 for σ = 1 s^-1/2, γ = 10 /(Pa·s), c = 1e6 Pa.
//!
//! Reproducibility: node `i` draws from ChaCha8 with key `ChaCha8Rng::seed_from_u64(seed)` and
//! stream id `i`, so the numbers a node receives depend only on (seed, i, step count) — not on
//! the number of nodes, nor on how nodes are split among threads. [`NoiseSource::apply`] and
//! [`NoiseSource::apply_par`] give bit-identical results, and [`NoiseState`] (seed plus each
//! stream's word position) lets a checkpointed run resume bit-identically.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Nodes per rayon task in [`NoiseSource::apply_par`]; below this, splitting costs more than
/// it saves.
const PAR_MIN_NODES: usize = 512;

/// Which noise term is added to φ after each deterministic step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoiseKind {
    /// No noise: φ is left unchanged. No random numbers are drawn.
    Off,
    /// Deterministic alternative: φ ← max(φ, floor). No random numbers are drawn. Keeps a molten
    /// node able to re-solidify (φ = 0 is a fixed point of Eq. 8) while runs stay exactly
    /// reproducible and smooth enough for convergence studies.
    Floor {
        /// Lower bound on φ, dimensionless; finite and ≥ 0.
        floor: f64,
    },
    /// Thermal noise φ ← |φ + σ·√Δt·Z|, Z ~ N(0, 1) per node and step.
    Gaussian {
        /// Amplitude σ in s^-1/2; finite and ≥ 0.
        sigma_per_sqrt_s: f64,
        /// Seed of the per-node ChaCha8 streams.
        seed: u64,
    },
}

/// Errors of [`NoiseSource`] construction and restoration.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NoiseError {
    /// A noise parameter outside its allowed range.
    #[error("invalid {field} = {value}: must be {allowed}")]
    InvalidParam {
        /// Name of the offending field (e.g. `sigma_per_sqrt_s`).
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A [`NoiseState`] that does not belong to this source (other seed, other node count, or
    /// a Gaussian state given to a source that draws nothing, or vice versa).
    #[error(
        "noise state does not match the source: state has seed {state_seed} and {state_nodes} \
         streams, source has seed {source_seed} and {source_nodes} streams"
    )]
    StateMismatch {
        /// Seed recorded in the state.
        state_seed: u64,
        /// Number of streams recorded in the state.
        state_nodes: usize,
        /// Seed of the source (0 when it draws nothing).
        source_seed: u64,
        /// Number of streams of the source (0 when it draws nothing).
        source_nodes: usize,
    },
}

/// Serializable snapshot of a [`NoiseSource`]'s generators.
///
/// For a Gaussian source: its seed and, per node, the position of that node's ChaCha8 stream in
/// 32-bit words (positions beyond 2^64 words would need ~10^19 draws per node and are not
/// representable). For `Off`/`Floor`: seed 0 and no positions.
#[derive(Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct NoiseState {
    /// Seed of the streams (0 for sources that draw nothing).
    pub seed: u64,
    /// Word position of each node's stream, indexed by node.
    pub word_pos: Vec<u64>,
}

/// Field by field, so that `clone_from` reuses the stream positions' buffer.
impl Clone for NoiseState {
    fn clone(&self) -> Self {
        Self {
            seed: self.seed,
            word_pos: self.word_pos.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        let Self { seed, word_pos } = source;
        self.seed = *seed;
        self.word_pos.clone_from(word_pos);
    }
}

/// Source of the noise term for a fixed number of nodes.
///
/// # Example
/// ```
/// use stickslip_core::noise::{NoiseKind, NoiseSource};
/// let kind = NoiseKind::Gaussian { sigma_per_sqrt_s: 1.0, seed: 1 };
/// let mut noise = NoiseSource::new(kind, 4).unwrap();
/// let mut phi = [0.0, 1e-3, 0.5, 1.2];
/// let checkpoint = noise.state();
/// noise.apply(&mut phi, 1e-8);
/// assert!(phi.iter().all(|p| *p >= 0.0));
///
/// // Restoring the snapshot replays the same numbers.
/// let mut again = [0.0, 1e-3, 0.5, 1.2];
/// noise.restore(&checkpoint).unwrap();
/// noise.apply_par(&mut again, 1e-8);
/// assert_eq!(phi, again);
/// ```
#[derive(Debug, Clone)]
pub struct NoiseSource {
    kind: NoiseKind,
    nodes: usize,
    /// One stream per node for `Gaussian`; empty otherwise.
    rngs: Vec<ChaCha8Rng>,
}

/// The stream of node `node` for `seed`: key from `seed_from_u64(seed)`, stream id = `node`.
fn node_stream(seed: u64, node: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(node as u64);
    rng
}

impl NoiseSource {
    /// Creates the source for `nodes` nodes; for `Gaussian`, stream `i` of node `i` starts at
    /// word 0.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] if `floor` or `sigma_per_sqrt_s` is negative or not finite.
    pub fn new(kind: NoiseKind, nodes: usize) -> Result<Self, NoiseError> {
        let non_negative = |field, value: f64| {
            if value.is_finite() && value >= 0.0 {
                Ok(())
            } else {
                Err(NoiseError::InvalidParam {
                    field,
                    value,
                    allowed: "finite and >= 0",
                })
            }
        };
        let rngs = match kind {
            NoiseKind::Off => Vec::new(),
            NoiseKind::Floor { floor } => {
                non_negative("floor", floor)?;
                Vec::new()
            }
            NoiseKind::Gaussian {
                sigma_per_sqrt_s,
                seed,
            } => {
                non_negative("sigma_per_sqrt_s", sigma_per_sqrt_s)?;
                (0..nodes).map(|i| node_stream(seed, i)).collect()
            }
        };
        Ok(Self { kind, nodes, rngs })
    }

    /// The noise kind this source applies.
    #[must_use]
    pub fn kind(&self) -> NoiseKind {
        self.kind
    }

    /// Number of nodes this source serves.
    #[must_use]
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// Applies one step's noise to `phi` in place, node by node:
    ///
    /// - `Off`: nothing;
    /// - `Floor`: φ ← max(φ, floor) (a NaN φ stays NaN so that blow-ups remain visible);
    /// - `Gaussian`: φ ← |φ + σ·√Δt·Z|, one Z ~ N(0, 1) from node i's stream.
    ///
    /// # Panics
    /// If `phi.len()` differs from [`NoiseSource::nodes`].
    #[track_caller]
    pub fn apply(&mut self, phi: &mut [f64], dt_s: f64) {
        self.check_len(phi);
        match self.kind {
            NoiseKind::Off => {}
            NoiseKind::Floor { floor } => phi.iter_mut().for_each(|p| apply_floor(p, floor)),
            NoiseKind::Gaussian {
                sigma_per_sqrt_s, ..
            } => {
                let scale = sigma_per_sqrt_s * dt_s.sqrt();
                phi.iter_mut()
                    .zip(self.rngs.iter_mut())
                    .for_each(|(p, rng)| apply_gaussian(p, scale, rng));
            }
        }
    }

    /// Same as [`NoiseSource::apply`], with nodes processed in parallel chunks by rayon.
    /// Bit-identical to `apply` whatever the thread count, since every node draws only from its
    /// own stream.
    ///
    /// # Panics
    /// If `phi.len()` differs from [`NoiseSource::nodes`].
    #[track_caller]
    pub fn apply_par(&mut self, phi: &mut [f64], dt_s: f64) {
        self.check_len(phi);
        match self.kind {
            NoiseKind::Off => {}
            NoiseKind::Floor { floor } => phi
                .par_iter_mut()
                .with_min_len(PAR_MIN_NODES)
                .for_each(|p| apply_floor(p, floor)),
            NoiseKind::Gaussian {
                sigma_per_sqrt_s, ..
            } => {
                let scale = sigma_per_sqrt_s * dt_s.sqrt();
                phi.par_iter_mut()
                    .zip(self.rngs.par_iter_mut())
                    .with_min_len(PAR_MIN_NODES)
                    .for_each(|(p, rng)| apply_gaussian(p, scale, rng));
            }
        }
    }

    /// Snapshot of the generators (see [`NoiseState`]).
    ///
    /// # Panics
    /// If a stream has advanced beyond 2^64 words (unreachable in practice).
    #[must_use]
    pub fn state(&self) -> NoiseState {
        let seed = match self.kind {
            NoiseKind::Gaussian { seed, .. } => seed,
            NoiseKind::Off | NoiseKind::Floor { .. } => 0,
        };
        let word_pos = self
            .rngs
            .iter()
            .map(|rng| u64::try_from(rng.get_word_pos()).expect("noise stream beyond 2^64 words"))
            .collect();
        NoiseState { seed, word_pos }
    }

    /// Writes the snapshot of [`NoiseSource::state`] into `out`, reusing its allocation.
    ///
    /// # Panics
    /// If a stream has advanced beyond 2^64 words (unreachable in practice).
    pub fn write_state(&self, out: &mut NoiseState) {
        out.seed = match self.kind {
            NoiseKind::Gaussian { seed, .. } => seed,
            NoiseKind::Off | NoiseKind::Floor { .. } => 0,
        };
        out.word_pos.clear();
        out.word_pos.extend(
            self.rngs.iter().map(|rng| {
                u64::try_from(rng.get_word_pos()).expect("noise stream beyond 2^64 words")
            }),
        );
    }

    /// Restores the generators from a snapshot taken by [`NoiseSource::state`] on a source with
    /// the same kind, seed and node count; the following draws are then bit-identical to those
    /// the snapshotted source would have made.
    ///
    /// # Errors
    /// [`NoiseError::StateMismatch`] if the seed or the number of streams differ.
    pub fn restore(&mut self, state: &NoiseState) -> Result<(), NoiseError> {
        let own = self.state();
        if own.seed != state.seed || own.word_pos.len() != state.word_pos.len() {
            return Err(NoiseError::StateMismatch {
                state_seed: state.seed,
                state_nodes: state.word_pos.len(),
                source_seed: own.seed,
                source_nodes: own.word_pos.len(),
            });
        }
        for (rng, &pos) in self.rngs.iter_mut().zip(&state.word_pos) {
            rng.set_word_pos(u128::from(pos));
        }
        Ok(())
    }

    #[track_caller]
    fn check_len(&self, phi: &[f64]) {
        assert_eq!(
            phi.len(),
            self.nodes,
            "noise source built for {} nodes applied to {} values",
            self.nodes,
            phi.len()
        );
    }
}

/// φ ← max(φ, floor), leaving NaN untouched.
#[inline]
fn apply_floor(phi: &mut f64, floor: f64) {
    // A select, not a branch: the loop over the nodes vectorises (a NaN stays NaN).
    *phi = if *phi < floor { floor } else { *phi };
}

/// φ ← |φ + scale·Z|, Z ~ N(0, 1) drawn from `rng`.
#[inline]
fn apply_gaussian(phi: &mut f64, scale: f64, rng: &mut ChaCha8Rng) {
    let z: f64 = StandardNormal.sample(rng);
    *phi = (*phi + scale * z).abs();
}
