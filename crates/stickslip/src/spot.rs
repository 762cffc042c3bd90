//! A sweep's spot checks on the command line (`[verify]`): run once the map is complete, by
//! `sweep run` and by `sweep merge` (the run library's `sweep::spot`), with a line of progress
//! and a summary.

use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use stickslip_run::exit::Exit;
use stickslip_studies::sweep::Sweep;
use stickslip_studies::sweep::spot::{SpotReport, run_checks};

/// The summary line of the checks.
fn summary(r: &SpotReport) -> String {
    let changed = r.changed_points();
    let changed_text = if changed.is_empty() {
        "no regime changed".to_string()
    } else {
        let list: Vec<String> = changed.iter().take(12).map(ToString::to_string).collect();
        format!(
            "the regime changed at {} (point{} {}{})",
            changed.len(),
            if changed.len() == 1 { "" } else { "s" },
            list.join(", "),
            if changed.len() > 12 { ", …" } else { "" }
        )
    };
    let largest = r.max_change.as_ref().map_or(String::new(), |(c, v, p)| {
        format!(
            "; largest change of a number where the regime held {:.3} % ({c}, point {p})",
            100.0 * v
        )
    });
    format!(
        "spot checks: {} points rerun at 2N and at a tenth of the tolerance ({} sampled, {} \
         next to a regime boundary; {} found done): {changed_text}{largest}; {:.2} s",
        r.checked, r.sampled, r.at_boundaries, r.skipped, r.wall_s
    )
}

/// Runs the spot checks of `sweep` (if it has `[verify]`) on the complete map in `dir`; the
/// exit status `merged` stands unless they are interrupted or cannot be written.
pub fn after_map(
    sweep: &Sweep,
    dir: &Path,
    jobs: usize,
    flag: &AtomicBool,
    quiet: bool,
    merged: ExitCode,
) -> ExitCode {
    let Some(spot) = &sweep.verify else {
        return merged;
    };
    let mut last = std::time::Instant::now();
    let mut progress = |done: usize, total: usize| {
        if !quiet && last.elapsed().as_secs_f64() >= 2.0 {
            eprintln!("spot checks: {done} of {total}");
            last = std::time::Instant::now();
        }
    };
    match run_checks(sweep, spot, dir, jobs, Some(flag), &mut progress) {
        Ok(Some(r)) => {
            say!("{}", summary(&r));
            if r.changed > 0 {
                eprintln!(
                    "warning: {} checked point{} changed regime at a finer resolution: the \
                     map's regimes there are not converged (map.json, spot_checks)",
                    r.changed,
                    if r.changed == 1 { "" } else { "s" }
                );
            }
            merged
        }
        Ok(None) => {
            eprintln!(
                "interrupted: finished spot checks are kept (DIR/checks/); rerun the same \
                 command to make the rest"
            );
            crate::code(Exit::Interrupted)
        }
        Err(e) => crate::fail(e, Exit::Io),
    }
}
