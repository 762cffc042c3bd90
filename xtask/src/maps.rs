//! `cargo xtask maps [--jobs J] [--resume]`: runs the showcase sweeps of `maps/*.toml`
//! in-process (their directories under `target/maps/`, afresh unless `--resume` keeps the
//! points an interrupted run finished) and writes `reports/maps.md` and
//! `reports/maps_*.svg` with the checks as measured verdicts.

use std::process::ExitCode;

/// Runs the maps; exit 0 when every check passes, 1 when one fails, 2 on bad arguments or
/// errors.
pub fn main(args: &[String], root: std::path::PathBuf) -> ExitCode {
    let mut jobs = std::thread::available_parallelism().map_or(1, usize::from);
    let mut resume = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match (a.as_str(), it.clone().next()) {
            ("--resume", _) => resume = true,
            ("--jobs", Some(v)) => match v.parse::<usize>() {
                Ok(n) if n > 0 => {
                    jobs = n;
                    it.next();
                }
                _ => {
                    eprintln!("maps: --jobs needs a positive integer, got {v:?}");
                    return ExitCode::from(2);
                }
            },
            (other, _) => {
                eprintln!("maps: unknown option {other:?}; allowed: --jobs J, --resume");
                return ExitCode::from(2);
            }
        }
    }
    match stickslip_maps::run(&stickslip_maps::Options { root, jobs, resume }) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!("maps: a check failed (see reports/maps.md)");
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("maps: {e}");
            ExitCode::from(2)
        }
    }
}
