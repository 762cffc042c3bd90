//! The cost target's fit alone: the SFA contact's first slip (N = 100) with τmax, γ, h0 and
//! G* free, fitted on the noise seeds SEEDS (N: 1…N; A-B: A…B) with the STRATEGY (`profile` or `direct`); per seed
//! the wall time, the runs (whole and onset-only), χ² against the true model's, and each
//! parameter's 95 % interval against the truth. JACOBIAN is `differences` (the default) or
//! `replay`; START `truth` starts the local stage at the true values and skips the global
//! search (what the fit costs once a search has found the truth's basin; the default
//! `search` searches).
//!
//! `cargo run --release -p stickslip-fit-study --example first_slip -- SEEDS STRATEGY JACOBIAN START`

use stickslip_fit_study::{cases, fits};

fn main() -> Result<(), String> {
    // SEEDS: N (the seeds 1…N) or A-B (the seeds A…B).
    let seeds = match std::env::args().nth(1) {
        Some(s) => {
            let number = |t: &str| {
                t.parse::<u64>()
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or(format!("SEEDS = {s}: N or A-B, whole numbers ≥ 1"))
            };
            match s.split_once('-') {
                Some((a, b)) => number(a)?..=number(b)?,
                None => 1..=number(&s)?,
            }
        }
        None => 1..=3,
    };
    let strategy = stickslip_studies::fit::Strategy::from_name(
        &std::env::args().nth(2).unwrap_or_else(|| "profile".into()),
    )
    .map_err(|e| e.to_string())?;
    let jacobian = stickslip_studies::fit::JacobianKind::from_name(
        &std::env::args()
            .nth(3)
            .unwrap_or_else(|| "differences".into()),
    )
    .map_err(|e| e.to_string())?;
    let from_truth = match std::env::args().nth(4).as_deref() {
        None | Some("search") => false,
        Some("truth") => true,
        Some(other) => return Err(format!("START = {other}: `search` or `truth`")),
    };
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let case = cases::first_slip(&cases::Sizes::full());
    let mut log = |line: &str| eprintln!("{line}");
    let fitted = fits::per_seed(
        &root,
        case,
        seeds,
        (2, strategy, jacobian),
        from_truth,
        &mut log,
    )?;
    for (s, out) in &fitted {
        let r = &out.report;
        let held = s.params.iter().filter(|p| p.covers() == Some(true)).count();
        println!(
            "seed {}: {:.1} s wall, {} runs + {} onset runs, χ² {:.2} (truth {}), {held} of {} \
             intervals hold the truth, strategy {}, Jacobians {}{}",
            s.seed,
            s.wall_s,
            r.evaluations,
            r.onset_runs,
            s.chi2,
            s.chi2_truth.map_or("–".into(), |c| format!("{c:.2}")),
            s.params.len(),
            r.strategy,
            r.jacobian,
            r.scan.as_ref().map_or(String::new(), |sc| format!(
                " (pinned {}, scanned {} at {:?}: χ² {:?})",
                sc.pinned, sc.key, sc.values, sc.chi2
            )),
        );
    }
    Ok(())
}
