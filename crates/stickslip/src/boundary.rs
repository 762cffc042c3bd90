//! `stickslip boundary`: the value of one key where the regime changes, by bisection
//! (the run library's `boundary::find`).

use std::path::Path;
use std::process::ExitCode;
use stickslip_run::boundary::{BoundaryError, Probe, find};
use stickslip_run::exit::Exit;
use stickslip_run::scene::Scene;
use stickslip_run::summary::RegimeThresholds;

/// Arguments of `stickslip boundary`.
pub struct Args<'a> {
    /// Scene file.
    pub scene: &'a Path,
    /// `--set` overrides.
    pub set: &'a [String],
    /// The key to search along.
    pub key: &'a str,
    /// One end.
    pub from: f64,
    /// The other end.
    pub to: f64,
    /// Relative tolerance.
    pub rtol: f64,
    /// No line per run.
    pub quiet: bool,
}

/// Runs the search and prints its answer; exit 0, 2 for bad input (including ends of the same
/// regime), 3 for a run that failed numerically, 130 when interrupted.
pub fn main(a: &Args<'_>) -> ExitCode {
    let base = match Scene::from_path(a.scene, a.set) {
        Ok(s) => s,
        Err(e) => return crate::fail(e, Exit::BadInput),
    };
    let flag = match crate::interrupt_flag() {
        Ok(f) => f,
        Err(e) => return crate::fail(format!("cannot install the signal handler: {e}"), Exit::Io),
    };
    let quiet = a.quiet;
    let key = a.key;
    let mut show = |p: &Probe| {
        if !quiet {
            eprintln!("boundary: {key} = {:e}: {}", p.value, p.regime.name());
        }
    };
    let found = find(
        &base,
        a.key,
        (a.from, a.to),
        a.rtol,
        RegimeThresholds::default(),
        Some(&flag),
        &mut show,
    );
    match found {
        Ok(b) => {
            // Digits enough to tell the bracket's ends apart.
            let d = (-b.rtol.log10()).ceil().max(0.0) as usize + 2;
            say!(
                "{} = {:.d$e} (bracket {:.d$e} … {:.d$e}, rtol {})",
                b.key,
                b.value,
                b.below.value,
                b.above.value,
                b.rtol
            );
            say!(
                "below: {} (at {:.d$e}); above: {} (at {:.d$e}); {} runs, {} midpoints",
                b.below.regime.name(),
                b.below.value,
                b.above.regime.name(),
                b.above.value,
                b.runs,
                if b.geometric {
                    "geometric"
                } else {
                    "arithmetic"
                }
            );
            ExitCode::SUCCESS
        }
        Err(e @ BoundaryError::Failed { .. }) => crate::fail(e, Exit::Numerical),
        Err(e @ BoundaryError::Interrupted { .. }) => crate::fail(e, Exit::Interrupted),
        Err(BoundaryError::Start(e)) => crate::fail(e, Exit::BadInput),
        Err(e) => crate::fail(e, Exit::BadInput),
    }
}
