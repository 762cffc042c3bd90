//! stickslip-core: the numerical model of stick–slip boundary friction under a flat-ended stamp.
//!
//! Pieces (each verified against exact answers in `tests/`):
//! - [`grid`]: the paper's radial grid r_i = i·a0/N;
//! - [`mdr`]: the method-of-dimensionality-reduction operators (Eq. 13–16), as the
//!   paper's plain sums and as product integration;
//! - [`landau`]: Landau kinetics of the film order parameter (Eq. 1–8, 17, 18);
//! - [`noise`]: reproducible thermal noise ξ(t) from seeded ChaCha streams;
//! - [`drive`]: the spring-driven stamp (Eq. 10) and the rigid coupler;
//! - [`sim`]: one step of either scheme, melting events, adaptive steps;
//! - [`preflight`]: derived and stability numbers, estimates and the run-or-refuse verdict;
//! - [`sums`]: sums over the nodes in interleaved partial sums, in a fixed order.
//!
//! Invariant: this crate does no file I/O and knows nothing of TOML, CSV or SVG.

pub mod config;
pub mod drive;
pub mod failure;
pub mod grid;
pub mod landau;
pub mod mdr;
pub mod noise;
pub mod preflight;
pub mod sim;
pub mod sums;
pub mod vexp;
