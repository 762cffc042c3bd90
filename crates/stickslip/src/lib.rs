//! stickslip: scene files, output files and the run loop behind the `stickslip` command line.
//!
//! - [`scene`]: TOML scenes (INTERFACE.md) with `--set` overrides, defaults and validation,
//!   resolved into the engine's configuration;
//! - [`output`]: atomic files, the CSV tables and run.json;
//! - [`runner`]: the fixed-step time loop with recording and a progress bar;
//! - [`checkpoint`]: periodic checkpoints of a run and what `resume` reads back.
//!
//! The numerics live in `stickslip-core`; this crate does the I/O.

pub mod checkpoint;
pub mod output;
pub mod runner;
pub mod scene;

pub use runner::{RunError, RunOptions, RunSummary, resume, run};
pub use scene::{ResolvedScene, Scene, SceneError};
