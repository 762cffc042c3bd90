//! Where P7's step evaluations go, phase by phase (`performance::phases`): P7's scene (the SFA
//! contact at K = 500 N/m, 0 → 1 s, N = 200 on the uniform grid, as `cargo xtask bench` runs
//! it), with any `section.key=value` settings given as arguments, e.g.
//!
//! `cargo run --release -p stickslip-convergence --example p7_phases -- numerics.event_tolerance_factor=100`

use std::path::PathBuf;
use std::process::ExitCode;
use stickslip_convergence::performance::experiment::{P7_END_S, SFA_SCENE, sfa_sets};
use stickslip_convergence::performance::phases;

fn main() -> ExitCode {
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../validation/scenes")
        .join(SFA_SCENE);
    let mut sets = sfa_sets(P7_END_S);
    sets.extend(std::env::args().skip(1));
    match phases::measure(&scene, &sets) {
        Ok(p) => {
            println!("P7's scene with {}:\n", sets.join(", "));
            print!("{}", p.table());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
