//! stickslip-studies: many runs of one scene asking one question, each run through the
//! one-run library ([`stickslip_run`]) with a null sink or in memory.
//!
//! - [`sweep`]: friction maps, points run in-process on threads, sharded, resumable,
//!   refined, spot-checked, merged;
//! - [`boundary`]: where the regime changes along one key (`stickslip boundary`), by
//!   bisection or a scan;
//! - [`verify`]: a result's discretisation error from refinements in N and in the tolerance
//!   (`stickslip verify`), with its estimate and the target settings;
//! - [`fit`]: the model fitted to a measured friction trace (`stickslip fit`);
//! - [`pool`]: scoped worker threads shared by the above;
//! - [`options`]: the defaults of the commands' options, for the command line and Python.
//!
//! Invariant: no command-line or terminal code here (as in the run library); a run's numbers
//! come from the run library and the core, never from here: a study decides which scenes run
//! and what their results say.

pub mod boundary;
pub mod fit;
pub mod options;
pub mod pool;
pub mod sweep;
pub mod verify;
