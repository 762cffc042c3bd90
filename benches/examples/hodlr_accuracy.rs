//! Accuracy of the fast MDR operators against the dense ones: ‖A − Ã‖₂ (power iteration
//! on the explicit difference, N ≤ 4000), errors on random vectors, the stated bound, ranks
//! and stored values, per N and tolerance. Product operators by default, literal with
//! `--literal`; O(N²·r) per N, a development tool, not a bench.
//!
//! `cargo run --release -p stickslip-benches --example hodlr_accuracy -- 1e-10 125 2000`

use std::time::Instant;
use stickslip_core::grid::Grid;
use stickslip_core::mdr::hodlr::HodlrOperator;
use stickslip_core::mdr::{OperatorEntries, TriangularOperator, literal, product};

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// A deterministic vector in [−1, 1) (linear congruential, seeded by `seed`).
fn random_vector(n: usize, seed: u64) -> Vec<f64> {
    let mut state = seed;
    (0..n)
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

/// ‖A − Ã‖₂ by 30 power iterations on the explicit difference (Ã column by column).
fn spectral_error(op: &TriangularOperator, fast: &HodlrOperator) -> f64 {
    let n = op.size();
    let mut scratch = fast.scratch();
    let mut e = vec![0.0; n * n]; // column-major A − Ã
    let mut unit = vec![0.0; n];
    let mut col = vec![0.0; n];
    for j in 0..n {
        unit[j] = 1.0;
        fast.apply(&unit, &mut col, &mut scratch);
        unit[j] = 0.0;
        for i in 0..n {
            e[j * n + i] = op.get(i, j) - col[i];
        }
    }
    let mut v = random_vector(n, 7);
    let mut ev = vec![0.0; n];
    let mut estimate = 0.0_f64;
    for _ in 0..30 {
        let nv = norm2(&v);
        v.iter_mut().for_each(|a| *a /= nv);
        ev.fill(0.0);
        for (j, vj) in v.iter().enumerate() {
            for i in 0..n {
                ev[i] += e[j * n + i] * vj;
            }
        }
        estimate = estimate.max(norm2(&ev));
        for (j, vj) in v.iter_mut().enumerate() {
            *vj = (0..n).map(|i| e[j * n + i] * ev[i]).sum();
        }
    }
    estimate
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let literal = args.iter().any(|a| a == "--literal");
    args.retain(|a| a != "--literal");
    let tol: f64 = args[0]
        .parse()
        .expect("first argument: the relative tolerance");
    for n in args[1..].iter().map(|a| a.parse::<usize>().expect("N")) {
        let grid = Grid::new(2e-5, n).expect("valid grid");
        let cases: [(&str, TriangularOperator, Box<dyn OperatorEntries + Sync>); 2] = if literal {
            [
                (
                    "forward",
                    literal::forward(&grid),
                    Box::new(literal::ForwardEntries::new(grid)),
                ),
                (
                    "back",
                    literal::back(&grid),
                    Box::new(literal::BackEntries::new(grid)),
                ),
            ]
        } else {
            [
                (
                    "forward",
                    product::forward(&grid),
                    Box::new(product::ForwardEntries::new(grid)),
                ),
                (
                    "back",
                    product::back(&grid),
                    Box::new(product::BackEntries::new(grid)),
                ),
            ]
        };
        for (name, op, entries) in &cases {
            let start = Instant::now();
            let fast = HodlrOperator::build(entries.as_ref(), tol);
            let seconds = start.elapsed().as_secs_f64();
            let scale = tol * fast.norm_estimate();
            let mut scratch = fast.scratch();
            let (mut worst_max, mut worst_2) = (0.0_f64, 0.0_f64);
            for seed in 0..4 {
                let x = random_vector(n, seed + n as u64);
                let (mut yd, mut yf) = (vec![0.0; n], vec![0.0; n]);
                op.apply(&x, &mut yd);
                fast.apply(&x, &mut yf, &mut scratch);
                let d: Vec<f64> = yd.iter().zip(&yf).map(|(a, b)| a - b).collect();
                let err_max = d.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                worst_max = worst_max.max(err_max / (scale * norm2(&x)));
                worst_2 = worst_2.max(norm2(&d) / (fast.error_bound() * norm2(&x)));
            }
            let spectral = if n <= 4000 {
                format!("{:.2}", spectral_error(op, &fast) / scale)
            } else {
                "-".into()
            };
            let ranks: Vec<String> = fast
                .rank_profile()
                .iter()
                .map(|l| format!("{}/{}", l.max_row_rank, l.max_col_rank))
                .collect();
            println!(
                "N={n:>6} {name:>7}: build {seconds:.4} s; ‖A−Ã‖₂/(tol·ν) {spectral}; random x: \
                 max|err|/(tol·ν·‖x‖) {worst_max:.3}, ‖err‖/(B·‖x‖) {worst_2:.3}; C {:.1} \
                 (skeleton {:.2}); stored {}; ranks {}",
                fast.error_bound_factor(),
                fast.skeleton_error_estimate() / scale,
                fast.stored_entries(),
                ranks.join(" ")
            );
        }
    }
}
