//! The defaults of the commands' options, in one place: the command line's flags and the
//! Python functions' keyword arguments are both built from these (Python reads them through
//! the extension, [`all`]), so the two cannot drift apart.

/// Runs at a time, for `verify`, `boundary` and `fit` (`--jobs`).
pub const JOBS: usize = 2;
/// `verify --rtol`: the relative accuracy each quantity's uncertainty must be within.
pub const VERIFY_RTOL: f64 = 1e-3;
/// `boundary --rtol`: the final bracket's relative width.
pub const BOUNDARY_RTOL: f64 = 1e-3;
/// `boundary --scan`: points of the first scan, the range's ends included.
pub const BOUNDARY_SCAN: usize = crate::boundary::scan::DEFAULT_SCAN;
/// `boundary --scale`: whose regime is followed.
pub const BOUNDARY_SCALE: &str = "film";
/// `fit --misfit`: what is compared.
pub const FIT_MISFIT: &str = "events";
/// `run --checkpoint-every`, s of wall time between checkpoints.
pub const CHECKPOINT_EVERY_S: f64 = stickslip_run::sink::dir::DEFAULT_CHECKPOINT_EVERY_S;

/// One option's default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OptionDefault {
    /// A count.
    Count(usize),
    /// A number.
    Number(f64),
    /// A word.
    Word(&'static str),
}

/// Every default, as `command.option` (Python's keyword name for the option).
#[must_use]
pub fn all() -> Vec<(&'static str, OptionDefault)> {
    use OptionDefault::{Count, Number, Word};
    vec![
        ("run.checkpoint_every", Number(CHECKPOINT_EVERY_S)),
        ("verify.rtol", Number(VERIFY_RTOL)),
        ("verify.jobs", Count(JOBS)),
        ("boundary.rtol", Number(BOUNDARY_RTOL)),
        ("boundary.scan", Count(BOUNDARY_SCAN)),
        ("boundary.jobs", Count(JOBS)),
        ("boundary.scale", Word(BOUNDARY_SCALE)),
        ("fit.misfit", Word(FIT_MISFIT)),
        ("fit.jobs", Count(JOBS)),
    ]
}
