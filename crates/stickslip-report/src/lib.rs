//! stickslip-report: the kit every report of the project is made with.
//!
//! - [`plot`]: one plotting layer over plotters' SVG backend (linear and log axes, lines,
//!   markers, slope guides, reference lines, cells for maps), with one [`palette`];
//! - [`fmt`]: one number formatter for report prose and tables;
//! - [`stats`]: one median, mean, coefficient of variation, differences and log–log slope;
//! - [`fit`]: the figure of `stickslip fit` (data, model, events, residuals);
//! - [`map`]: friction-map panels (regime colours, a continuous quantity) from a sweep;
//! - [`binary`]: builds the `stickslip` binary and runs scenes through it as a user would,
//!   reading what it wrote through the run library's schema;
//! - [`build_timing`]: the schema of `reports/build-timing.json` (a fresh clone's build and
//!   test times) and of the stage times `cargo xtask test` records;
//! - [`provenance`]: the commit a report was generated at, and the sentence that says so;
//! - [`files`]: the one report writer ([`files::ReportFiles`]: a report's files, each atomic);
//! - [`write_atomic`]: the run library's atomic writer, re-exported (there is one).
//!
//! Invariant: no physics and no time loop here; reports are computed from data they are
//! handed.

pub mod binary;
pub mod build_timing;
pub mod files;
pub mod fit;
pub mod fmt;
pub mod map;
pub mod options;
pub mod palette;
pub mod plot;
pub mod provenance;
pub mod stats;
pub mod verify;

pub use stickslip_run::atomic::write_atomic_path as write_atomic;
