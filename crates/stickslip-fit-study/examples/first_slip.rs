//! The cost target's fit alone: the SFA contact's first slip (N = 100) with τmax, γ, h0 and
//! G* free, fitted on noise seeds 1…SEEDS with the STRATEGY (`profile` or `direct`); per seed
//! the wall time, the runs (whole and onset-only), χ² against the true model's, and each
//! parameter's 95 % interval against the truth.
//!
//! `cargo run --release -p stickslip-fit-study --example first_slip -- SEEDS STRATEGY`

use stickslip_fit_study::{cases, fits};

fn main() -> Result<(), String> {
    let seeds: u64 = match std::env::args().nth(1) {
        Some(s) => s
            .parse()
            .map_err(|e| format!("SEEDS = {s}: a whole number ≥ 1 ({e})"))?,
        None => 3,
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
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let case = cases::first_slip(&cases::Sizes::full());
    let mut log = |line: &str| eprintln!("{line}");
    let fitted = fits::per_seed(&root, case, 1..=seeds, (2, strategy, jacobian), &mut log)?;
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
