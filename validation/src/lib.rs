//! stickslip-validation: the paper's scenes run through the `stickslip` binary, the paper's
//! claims C1–C10 as measured criteria, and the SVG reports of `cargo xtask validate`.
//!
//! Layout: [`runner`] spawns `stickslip run` per scene and [`data`] parses what it wrote;
//! [`claims`] turns parsed outputs into verdicts; [`figures`] (over [`plot`]) draws the SVGs;
//! [`report`] writes `reports/index.md` and `reports/summary.json`; [`reduced`] is the small
//! in-process fig2 run whose features the fast test compares with the committed summary;
//! [`hard`] runs the hard cases of `validation/hard/` and writes `reports/hard-cases.md`;
//! [`validate`] ties it together.
//!
//! Invariant: the claims read output files only; they know nothing of the runner's internals.

pub mod claims;
pub mod data;
pub mod figures;
pub mod hard;
pub mod plot;
pub mod reduced;
pub mod report;
pub mod runner;
pub mod validate;
