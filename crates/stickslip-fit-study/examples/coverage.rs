//! One coverage set of the fit study, alone: its seeds' fits (events misfit) with each
//! parameter's pulls' mean and standard deviation and how many intervals hold the truth —
//! section 1 of `cargo xtask fit-study` without the rest of its four hours.
//!
//! `cargo run --release -p stickslip-fit-study --example coverage -- SET SEEDS` with SET `a`
//! (fig2, N = 100) or `b` (the SFA contact, N = 100) and SEEDS the number of noise seeds
//! (the study's full size is 20). Set A takes about 2 minutes on 2 cores, set B about 5
//! minutes per seed.

use stickslip_fit_study::{cases, fits};

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (set, seeds) = match args.as_slice() {
        [set, seeds] if set == "a" || set == "b" => (
            set.clone(),
            seeds
                .parse::<usize>()
                .map_err(|e| format!("SEEDS = {seeds}: a whole number ≥ 2 ({e})"))?,
        ),
        _ => return Err("usage: coverage SET SEEDS, SET a or b, SEEDS ≥ 2".into()),
    };
    if seeds < 2 {
        return Err(format!(
            "SEEDS = {seeds}: at least 2 for a standard deviation"
        ));
    }
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut sizes = cases::Sizes::full();
    sizes.seeds = seeds;
    let case = if set == "a" {
        cases::set_a(&sizes)
    } else {
        cases::set_b(&sizes)
    };
    let mut log = |line: &str| eprintln!("{line}");
    let (run, _) = fits::coverage(&root, case, &sizes, 2, None, &mut log)?;
    for k in 0..run.fits[0].params.len() {
        let pulls: Vec<f64> = run.fits.iter().filter_map(|f| f.params[k].pull()).collect();
        let n = pulls.len() as f64;
        let mean = pulls.iter().sum::<f64>() / n;
        let sd = (pulls.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let held = run
            .fits
            .iter()
            .filter(|f| f.params[k].covers() == Some(true))
            .count();
        println!(
            "{}: {} pulls, mean {mean:.3}, SD {sd:.3}; {held} of {} intervals hold the truth",
            run.fits[0].params[k].key,
            pulls.len(),
            run.fits.len()
        );
    }
    Ok(())
}
