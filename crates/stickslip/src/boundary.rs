//! `stickslip boundary`: every value of one key where the regime changes, by a first scan and
//! a bisection of each change (the run library's `boundary::scan`).

use std::path::Path;
use std::process::ExitCode;
use stickslip_run::exit::Exit;
use stickslip_run::scene::Scene;
use stickslip_run::summary::RegimeThresholds;
use stickslip_studies::boundary::scan::{Change, Scan, ScanOptions, scan};
use stickslip_studies::boundary::{BoundaryError, Probe};

/// Arguments of `stickslip boundary`.
pub struct Args<'a> {
    /// Scene file.
    pub scene: &'a Path,
    /// `--set` overrides.
    pub set: &'a [String],
    /// `--unset` keys.
    pub unset: &'a [String],
    /// The key to search along.
    pub key: &'a str,
    /// One end.
    pub from: f64,
    /// The other end.
    pub to: f64,
    /// Relative tolerance.
    pub rtol: f64,
    /// Points of the first scan.
    pub scan: usize,
    /// Runs at a time.
    pub jobs: usize,
    /// The regime followed.
    pub scale: stickslip_studies::boundary::Scale,
    /// No line per run.
    pub quiet: bool,
    /// Where the runs are kept for a rerun after an interrupt.
    pub out: Option<&'a Path>,
}

/// Digits enough to tell a bracket of relative width `rtol` apart.
fn digits(rtol: f64) -> usize {
    (-rtol.log10()).ceil().max(0.0) as usize + 2
}

/// One change as a line: value ± error, the regimes, and what the error is made of.
fn change_line(c: &Change, unit: &str, d: usize) -> String {
    let rel = if c.value == 0.0 {
        String::new()
    } else {
        format!(" ({:.2} %)", 100.0 * c.error / c.value.abs())
    };
    let mut parts = vec![format!("bracket ±{:.2e}", c.bracket)];
    for s in &c.shifts {
        parts.push(match s.value {
            Some(_) if s.moved == 0.0 => format!("{}: inside the bracket", s.stage.name()),
            Some(_) => format!("{}: moves {:.2e}", s.stage.name(), s.moved),
            None => format!("{}: not found", s.stage.name()),
        });
    }
    format!(
        "{:.d$e} ± {:.2e} {unit}{rel}: {} → {} [{}; {} runs]",
        c.value,
        c.error,
        c.below.regime.name(),
        c.above.regime.name(),
        parts.join("; "),
        c.runs
    )
}

fn print(s: &Scan, unit: &str) {
    let d = digits(s.rtol);
    // The first change in the form `boundary` has always printed.
    if let Some(first) = s.changes.first() {
        say!(
            "{} = {:.d$e} ± {:.2e} (bracket {:.d$e} … {:.d$e}, rtol {})",
            s.key,
            first.value,
            first.error,
            first.below.value,
            first.above.value,
            s.rtol
        );
        say!(
            "below: {} (at {:.d$e}); above: {} (at {:.d$e}); {} runs, {} midpoints",
            first.below.regime.name(),
            first.below.value,
            first.above.regime.name(),
            first.above.value,
            s.runs,
            if s.geometric {
                "geometric"
            } else {
                "arithmetic"
            }
        );
    }
    let scanned: Vec<String> = s
        .points
        .iter()
        .map(|p| format!("{:.3e} {}", p.value, p.regime.said()))
        .collect();
    say!(
        "scan of {} points ({} {}): {}",
        s.points.len(),
        if s.geometric { "ratio" } else { "step" },
        if s.geometric {
            format!("{:.3}", s.spacing)
        } else {
            format!("{:.3e}", s.spacing)
        },
        scanned.join(", ")
    );
    say!(
        "{} change{} (value ± error, {unit}):",
        s.changes.len(),
        if s.changes.len() == 1 { "" } else { "s" }
    );
    for (i, c) in s.changes.iter().enumerate() {
        say!(
            "  {}. {}{}",
            i + 1,
            change_line(c, unit, d),
            if c.complete {
                ""
            } else {
                " (interrupted: the bracket so far)"
            }
        );
    }
    if !s.undecided.is_empty() {
        say!(
            "{} undecided stretch{} (a change may lie inside; not located):",
            s.undecided.len(),
            if s.undecided.len() == 1 { "" } else { "es" }
        );
        for u in &s.undecided {
            say!(
                "  {:.d$e} {} … {:.d$e} {}: undecided at {}",
                u.below.value,
                u.below.regime.said(),
                u.above.value,
                u.above.regime.said(),
                u.undecided
                    .iter()
                    .map(|v| format!("{v:.3e}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
}

/// Runs the search and prints its answer; exit 0, 2 for bad input (including a range whose
/// scan points all have the same regime), 3 for a run that failed numerically, 130 when
/// interrupted.
pub fn main(a: &Args<'_>) -> ExitCode {
    let base = match Scene::from_path_unsetting(a.scene, a.unset, a.set) {
        Ok(s) => s,
        Err(e) => return crate::fail(e, Exit::BadInput),
    };
    if a.jobs == 0 {
        return crate::fail(
            "--jobs 0 is invalid; allowed: an integer >= 1",
            Exit::BadInput,
        );
    }
    let cache = match a
        .out
        .map(stickslip_studies::boundary::cache::ProbeCache::open)
    {
        None => None,
        Some(Ok(c)) => Some(c),
        Some(Err(e)) => return crate::fail(format!("--out: cannot keep the runs: {e}"), Exit::Io),
    };
    if let (Some(c), Some(dir)) = (&cache, a.out)
        && !c.is_empty()
    {
        eprintln!(
            "boundary: {} runs kept in {} (an earlier, interrupted search): runs already made \
             are not made again",
            c.len(),
            dir.join(stickslip_studies::boundary::cache::FILE).display()
        );
    }
    let flag = match crate::interrupt_flag() {
        Ok(f) => f,
        Err(e) => return crate::fail(format!("cannot install the signal handler: {e}"), Exit::Io),
    };
    let quiet = a.quiet;
    let key = a.key;
    let show = |p: &Probe| {
        if !quiet {
            eprintln!(
                "boundary: {key} = {:e}: {} ({})",
                p.value,
                p.regime.said(),
                p.stage.name()
            );
        }
    };
    let found = scan(
        &base,
        a.key,
        (a.from, a.to),
        a.rtol,
        ScanOptions {
            points: a.scan,
            jobs: a.jobs,
            scale: a.scale,
            cache: cache.as_ref(),
        },
        RegimeThresholds::default(),
        Some(&flag),
        &show,
        &mut || {},
    );
    match found {
        Ok(s) => {
            let unit = stickslip_run::keys::find(a.key).map_or("", |k| k.unit);
            print(&s, unit);
            ExitCode::SUCCESS
        }
        Err(e @ BoundaryError::Failed { .. }) => crate::fail(e, Exit::Numerical),
        Err(e @ BoundaryError::Interrupted { .. }) => crate::fail(e, Exit::Interrupted),
        Err(BoundaryError::ScanInterrupted { runs, partial }) => {
            // What the scan had found is printed as its answer would be, marked as cut short.
            let unit = stickslip_run::keys::find(a.key).map_or("", |k| k.unit);
            print(&partial, unit);
            crate::fail(
                format!(
                    "interrupted after {runs} runs; the changes above are as far as the scan got{}",
                    match a.out {
                        Some(d) => format!(
                            " (its runs are kept: the same command with --out {} finishes it)",
                            d.display()
                        ),
                        None => " (with --out DIR a rerun would not repeat the runs made)".into(),
                    }
                ),
                Exit::Interrupted,
            )
        }
        Err(BoundaryError::Start(e)) => crate::fail(e, Exit::BadInput),
        Err(e) => crate::fail(e, Exit::BadInput),
    }
}
