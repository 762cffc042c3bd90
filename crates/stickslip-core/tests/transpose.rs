//! Transposed applies of the MDR operators, and the 1D force through the forward
//! transform's transposed weights (what every series row's F_1d uses).

use stickslip_core::grid::Grid;
use stickslip_core::mdr::{MdrOperators, OperatorForm, Quadrature, product};

const A0: f64 = 2e-5;

fn vector(n: usize, seed: f64) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let r = i as f64 / n as f64;
            (seed * 5.1 * r).cos() + (r - 0.6).abs() * seed
        })
        .collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[test]
fn the_packed_transpose_is_the_dense_transpose() {
    let grid = Grid::new(A0, 37).expect("grid");
    for op in [product::forward(&grid), product::back(&grid)] {
        let dense = op.to_dense();
        let x = vector(37, 1.3);
        let mut y = vec![0.0; 37];
        op.apply_transpose(&x, &mut y);
        for (k, &yk) in y.iter().enumerate() {
            let exact: f64 = (0..37).map(|i| dense[(i, k)] * x[i]).sum();
            assert!((yk - exact).abs() <= 1e-13 * exact.abs().max(1e-300) + 1e-300);
        }
    }
}

#[test]
fn the_fast_transpose_is_the_adjoint_of_the_fast_apply() {
    for n in [20, 200, 1537] {
        let ops = MdrOperators::with_form(
            Grid::new(A0, n).expect("grid"),
            Quadrature::Product,
            OperatorForm::Fast,
        );
        let (forward, back) = ops.fast_operators().expect("fast form");
        for op in [forward, back] {
            let (x, w) = (vector(n, 0.7), vector(n, -2.2));
            let (mut ax, mut atw) = (vec![0.0; n], vec![0.0; n]);
            op.apply(&x, &mut ax, &mut op.scratch());
            op.apply_transpose(&w, &mut atw);
            let (lhs, rhs) = (dot(&w, &ax), dot(&atw, &x));
            let scale = w.iter().zip(&ax).map(|(a, b)| (a * b).abs()).sum::<f64>();
            assert!(
                (lhs - rhs).abs() <= 1e-13 * scale,
                "N = {n}, {:?}: <w, Ax> = {lhs}, <Aᵀw, x> = {rhs}",
                op.triangle()
            );
            // And it approximates the exact transpose as the apply does the operator.
            let dense = match op.triangle() {
                stickslip_core::mdr::Triangle::Upper => product::forward(ops.grid()),
                stickslip_core::mdr::Triangle::Lower => product::back(ops.grid()),
            };
            let mut exact = vec![0.0; n];
            dense.apply_transpose(&w, &mut exact);
            let err = exact
                .iter()
                .zip(&atw)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            let norm = exact.iter().map(|a| a * a).sum::<f64>().sqrt();
            assert!(
                err <= 1e-8 * norm,
                "N = {n}: ‖Ãᵀw − Aᵀw‖ = {err:e} of {norm:e}"
            );
        }
    }
}

#[test]
fn the_1d_force_from_tau_is_the_1d_force_of_the_forward_transform() {
    for (n, form) in [
        (30, OperatorForm::Dense),
        (300, OperatorForm::Dense),
        (300, OperatorForm::Fast),
        (2000, OperatorForm::Fast),
    ] {
        for quadrature in [Quadrature::Product, Quadrature::Literal] {
            let ops = MdrOperators::with_form(Grid::new(A0, n).expect("grid"), quadrature, form);
            for seed in [1.0, -3.0] {
                let tau: Vec<f64> = vector(n, seed).iter().map(|v| 1e6 * v).collect();
                let mut q = vec![0.0; n];
                ops.forward(&tau, &mut q);
                let through_q = ops.force_1d_n(&q);
                let direct = ops.force_1d_from_tau_n(&tau);
                let scale: f64 = ops
                    .force_1d_weights_m()
                    .iter()
                    .zip(&q)
                    .map(|(c, q)| (c * q).abs())
                    .sum();
                assert!(
                    (through_q - direct).abs() <= 1e-13 * scale,
                    "N = {n}, {form:?}, {quadrature:?}: {through_q} against {direct}"
                );
            }
            let zero = vec![0.0; n];
            assert_eq!(ops.force_1d_from_tau_n(&zero), 0.0);
        }
    }
}
