//! Property tests of the MDR operators: linearity, positivity, monotonicity, constants, kernels.

use faer::{Accum, Mat, Par};
use proptest::prelude::*;
use stickslip_core::grid::Grid;
use stickslip_core::mdr::{MdrOperators, Quadrature};

const A0: f64 = 2e-5;

fn quadrature() -> impl Strategy<Value = Quadrature> {
    prop_oneof![Just(Quadrature::Literal), Just(Quadrature::Product)]
}

prop_compose! {
    /// A grid size and two non-negative stress fields on it, in Pa.
    fn two_fields()(n in 1usize..80)
        (a in prop::collection::vec(0.0f64..2e6, n), b in prop::collection::vec(0.0f64..2e6, n))
        -> (Vec<f64>, Vec<f64>) { (a, b) }
}

fn apply_all(ops: &MdrOperators, tau: &[f64]) -> (Vec<f64>, Vec<f64>, f64, f64) {
    let n = tau.len();
    let mut q = vec![0.0; n];
    let mut u = vec![0.0; n];
    ops.compliance(tau, &mut q, &mut u);
    let f3 = ops.force_3d_n(tau);
    let f1 = ops.force_1d_n(&q);
    (q, u, f3, f1)
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-12 * scale.max(1e-300)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn operators_are_linear((t1, t2) in two_fields(), quad in quadrature(), alpha in -3.0f64..3.0) {
        let ops = MdrOperators::new(Grid::new(A0, t1.len()).unwrap(), quad);
        let combo: Vec<f64> = t1.iter().zip(&t2).map(|(a, b)| alpha * a + b).collect();
        let (q1, u1, f31, f11) = apply_all(&ops, &t1);
        let (q2, u2, f32, f12) = apply_all(&ops, &t2);
        let (qc, uc, f3c, f1c) = apply_all(&ops, &combo);
        let qs = q1.iter().chain(&q2).fold(0.0f64, |m, v| m.max(v.abs())) * 4.0;
        let us = u1.iter().chain(&u2).fold(0.0f64, |m, v| m.max(v.abs())) * 4.0;
        for i in 0..t1.len() {
            prop_assert!(close(qc[i], alpha * q1[i] + q2[i], qs));
            prop_assert!(close(uc[i], alpha * u1[i] + u2[i], us));
        }
        prop_assert!(close(f3c, alpha * f31 + f32, 4.0 * (f31.abs() + f32.abs())));
        prop_assert!(close(f1c, alpha * f11 + f12, 4.0 * (f11.abs() + f12.abs())));
    }

    #[test]
    fn nonnegative_stress_gives_nonnegative_load_and_displacement(
        (t1, _) in two_fields(), quad in quadrature()
    ) {
        let ops = MdrOperators::new(Grid::new(A0, t1.len()).unwrap(), quad);
        let (q, u, f3, f1) = apply_all(&ops, &t1);
        prop_assert!(q.iter().all(|&v| v >= 0.0));
        prop_assert!(u.iter().all(|&v| v >= 0.0));
        prop_assert!(f3 >= 0.0 && f1 >= 0.0);
    }

    #[test]
    fn operators_are_monotone_in_stress((t1, t2) in two_fields(), quad in quadrature()) {
        // τ_hi = τ1 + τ2 ≥ τ1 pointwise ⇒ q, u3D and both forces are ≥ pointwise.
        let ops = MdrOperators::new(Grid::new(A0, t1.len()).unwrap(), quad);
        let hi: Vec<f64> = t1.iter().zip(&t2).map(|(a, b)| a + b).collect();
        let (ql, ul, f3l, f1l) = apply_all(&ops, &t1);
        let (qh, uh, f3h, f1h) = apply_all(&ops, &hi);
        for i in 0..t1.len() {
            prop_assert!(qh[i] >= ql[i] * (1.0 - 1e-14));
            prop_assert!(uh[i] >= ul[i] * (1.0 - 1e-14));
        }
        prop_assert!(f3h >= f3l * (1.0 - 1e-14) && f1h >= f1l * (1.0 - 1e-14));
    }

    #[test]
    fn product_back_transform_reproduces_constants(n in 1usize..300, c in -1e-6f64..1e-6) {
        // The flat-punch identity: a uniform u1D maps to the same uniform u3D, at every node.
        let ops = MdrOperators::new(Grid::new(A0, n).unwrap(), Quadrature::Product);
        let mut u = vec![0.0; n];
        ops.back(&vec![c; n], &mut u);
        prop_assert!(u.iter().all(|&v| (v - c).abs() <= 1e-13 * c.abs()));
    }

    #[test]
    fn product_forward_is_exact_for_uniform_stress(n in 1usize..300, a0 in 1e-9f64..1e3) {
        // Piecewise-linear data reproduce τ = const exactly, so q(x_j) = 2√(a0² − x_j²)
        // to rounding at any scale of a0 (no overflow or precision loss from 1 nm to 1 km).
        let grid = Grid::new(a0, n).unwrap();
        let ops = MdrOperators::new(grid, Quadrature::Product);
        let mut q = vec![0.0; n];
        ops.forward(&vec![1.0; n], &mut q);
        for (j, &qj) in q.iter().enumerate() {
            let x = grid.node_radius_m(j);
            let exact = 2.0 * ((a0 - x) * (a0 + x)).sqrt();
            prop_assert!((qj - exact).abs() <= 1e-12 * 2.0 * a0, "j={} q={} exact={}", j, qj, exact);
        }
    }
}

/// The packed triangular mat-vec (our fast kernel) against faer's dense product, on random
/// data, sequential and parallel, over a sweep of sizes.
#[test]
fn packed_apply_matches_dense_faer_product() {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal};
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for n in [1usize, 2, 3, 7, 8, 9, 64, 255, 1000] {
        for quad in [Quadrature::Literal, Quadrature::Product] {
            let ops = MdrOperators::new(Grid::new(A0, n).unwrap(), quad);
            let x: Vec<f64> = (0..n).map(|_| StandardNormal.sample(&mut rng)).collect();
            for op in [ops.forward_operator(), ops.back_operator()] {
                let dense = op.to_dense();
                let xm = Mat::from_fn(n, 1, |i, _| x[i]);
                let mut ym = Mat::<f64>::zeros(n, 1);
                faer::linalg::matmul::matmul(
                    ym.as_mut(),
                    Accum::Replace,
                    dense.as_ref(),
                    xm.as_ref(),
                    1.0,
                    Par::Seq,
                );
                let mut y = vec![0.0; n];
                let mut y_par = vec![0.0; n];
                op.apply(&x, &mut y);
                op.apply_par(&x, &mut y_par);
                let abs_row_sum: f64 = (0..n)
                    .map(|i| (0..n).map(|k| (dense[(i, k)] * x[k]).abs()).sum::<f64>())
                    .fold(0.0, f64::max);
                for i in 0..n {
                    assert!(
                        (y[i] - ym[(i, 0)]).abs() <= 1e-14 * abs_row_sum,
                        "n={n} {quad:?} row {i}: {} vs {}",
                        y[i],
                        ym[(i, 0)]
                    );
                    assert_eq!(
                        y[i].to_bits(),
                        y_par[i].to_bits(),
                        "apply_par must be bit-identical"
                    );
                }
            }
        }
    }
}

/// The composite compliance matrix equals back∘forward applied in two steps.
#[test]
fn dense_compliance_equals_two_step_apply() {
    let n = 200;
    let ops = MdrOperators::new(Grid::new(A0, n).unwrap(), Quadrature::Product);
    let c = ops.compliance_dense();
    let tau: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64 * 0.37).sin()).collect();
    let mut q = vec![0.0; n];
    let mut u = vec![0.0; n];
    ops.compliance(&tau, &mut q, &mut u);
    let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for i in 0..n {
        let ci: f64 = (0..n).map(|k| c[(i, k)] * tau[k]).sum();
        assert!((ci - u[i]).abs() <= 1e-12 * scale, "row {i}");
    }
}

#[test]
fn force_from_weights_alone_equals_the_operators_force_bit_for_bit() {
    for quad in [Quadrature::Literal, Quadrature::Product] {
        for n in [1, 2, 3, 17, 64, 301] {
            let grid = Grid::new(A0, n).unwrap();
            let tau: Vec<f64> = (0..n)
                .map(|i| 1e6 * (1.0 + (i as f64 * 0.37).sin()))
                .collect();
            let ops = MdrOperators::new(grid, quad);
            let direct = stickslip_core::mdr::force_3d_n(&grid, quad, &tau);
            assert_eq!(
                direct.to_bits(),
                ops.force_3d_n(&tau).to_bits(),
                "{quad:?}, N = {n}"
            );
        }
    }
}
