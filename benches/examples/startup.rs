//! Start-up cost of the fast MDR operators: wall time of `MdrOperators::with_form(grid,
//! Product, Fast)` (forward and back together) per N, for `/usr/bin/time -v` and reports.
//!
//! `cargo run --release -p stickslip-benches --example startup -- 125 500 2000`

use std::time::Instant;
use stickslip_core::grid::Grid;
use stickslip_core::mdr::{MdrOperators, OperatorForm, Quadrature};

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("N must be a positive integer"))
        .collect();
    for n in sizes {
        let grid = Grid::new(2e-5, n).expect("valid grid");
        // Best of a few repetitions for the small sizes (timer and cache noise).
        let reps = if n <= 2000 { 5 } else { 1 };
        let mut best = f64::INFINITY;
        let mut summary = String::new();
        for _ in 0..reps {
            let start = Instant::now();
            let ops = MdrOperators::with_form(grid, Quadrature::Product, OperatorForm::Fast);
            best = best.min(start.elapsed().as_secs_f64());
            if let Some((forward, back)) = ops.fast_operators() {
                summary = format!(
                    "factors {:.1} MB (dense would be {:.1} MB), max ranks {}/{}, C {:.0}/{:.0}",
                    ops.fast_bytes() as f64 * 1e-6,
                    MdrOperators::dense_bytes(n) as f64 * 1e-6,
                    forward.max_rank(),
                    back.max_rank(),
                    forward.error_bound_factor(),
                    back.error_bound_factor()
                );
            }
        }
        println!("N = {n:>6}: with_form(Product, Fast) {best:.4} s; {summary}");
    }
}
