//! The fast form's apply cut at the root (two halves that exchange the root's coefficients)
//! and the compliance on two threads give the one-thread apply's bits.

use stickslip_core::grid::Grid;
use stickslip_core::mdr::hodlr::{Half, HodlrOperator};
use stickslip_core::mdr::{MdrOperators, OperatorForm, PAIR_MIN_NODES, Quadrature};

const A0: f64 = 2e-5;

fn fast(n: usize) -> MdrOperators {
    MdrOperators::with_form(
        Grid::new(A0, n).expect("valid grid"),
        Quadrature::Product,
        OperatorForm::Fast,
    )
}

/// A smooth vector with a kink and a sign change, so every panel sees non-trivial data.
fn vector(n: usize, seed: f64) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let r = i as f64 / n as f64;
            (seed * 7.3 * r).sin() + (r - 0.4).abs() * seed
        })
        .collect()
}

/// Both halves in one thread, in the order the two threads would take.
fn split_apply(op: &HodlrOperator, x: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut y = vec![f64::NAN; n];
    let (mut first, mut second) = (op.scratch(), op.scratch());
    op.apply_up(Half::First, x, &mut first);
    op.apply_up(Half::Second, x, &mut second);
    match op.split_target() {
        Half::First => {
            let src = op.child_coefficients(Half::Second, &second).to_vec();
            op.child_coefficients_mut(Half::Second, &mut first)
                .copy_from_slice(&src);
        }
        Half::Second => {
            let src = op.child_coefficients(Half::First, &first).to_vec();
            op.child_coefficients_mut(Half::First, &mut second)
                .copy_from_slice(&src);
        }
    }
    let mut y_first = vec![f64::NAN; n];
    op.apply_down(Half::First, x, &mut y_first, &mut first);
    op.apply_down(Half::Second, x, &mut y, &mut second);
    let mid = op.split_row().expect("splits");
    y[..mid].copy_from_slice(&y_first[..mid]);
    y
}

#[test]
fn the_halves_give_the_whole_apply_bit_for_bit() {
    for n in [65, 200, 1000, 1537] {
        let ops = fast(n);
        let (forward, back) = ops.fast_operators().expect("fast form");
        for op in [forward, back] {
            let mid = op.split_row().expect("more than one leaf splits");
            assert!(mid > 0 && mid < n);
            let mut scratch = op.scratch();
            for seed in [1.0, -2.5, 3.7] {
                let x = vector(n, seed);
                let mut whole = vec![0.0; n];
                op.apply(&x, &mut whole, &mut scratch);
                let halves = split_apply(op, &x);
                assert!(
                    whole
                        .iter()
                        .zip(&halves)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "N = {n}, {:?}: the split apply differs",
                    op.triangle()
                );
            }
        }
    }
}

#[test]
fn an_operator_of_one_leaf_does_not_split() {
    let ops = fast(20);
    let (forward, _) = ops.fast_operators().expect("fast form");
    assert_eq!(forward.split_row(), None);
}

/// back(forward(x)) on one thread, through the public transforms.
fn sequential(ops: &MdrOperators, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = x.len();
    let (mut q, mut y) = (vec![0.0; n], vec![0.0; n]);
    ops.forward(x, &mut q);
    ops.back(&q, &mut y);
    (q, y)
}

fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[test]
fn the_compliance_on_two_threads_gives_the_one_thread_bits() {
    let n = PAIR_MIN_NODES + 37;
    let ops = fast(n);
    // Built and first applied outside any rayon worker, with two threads in the budget.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("pool");
    let expected_threads = if rayon::current_num_threads() >= 2 {
        2
    } else {
        1
    };
    let (mut q, mut y) = (vec![0.0; n], vec![0.0; n]);
    for seed in [0.5, 1.0, -4.0, 2.0] {
        let x = vector(n, seed);
        ops.compliance(&x, &mut q, &mut y);
        let (q_seq, y_seq) = sequential(&ops, &x);
        assert!(same_bits(&q, &q_seq), "q differs (seed {seed})");
        assert!(same_bits(&y, &y_seq), "u differs (seed {seed})");
    }
    assert_eq!(ops.compliance_threads(), expected_threads);
    // Two callers at once: the one that finds the pair busy takes the one-thread path.
    let x = vector(n, 3.0);
    let (_, y_seq) = sequential(&ops, &x);
    std::thread::scope(|s| {
        let calls: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    let (mut q, mut y) = (vec![0.0; n], vec![0.0; n]);
                    for _ in 0..50 {
                        ops.compliance(&x, &mut q, &mut y);
                    }
                    y
                })
            })
            .collect();
        for c in calls {
            assert!(same_bits(&c.join().expect("no panic"), &y_seq));
        }
    });
    // Operators first applied from a pool's worker keep to one thread (the pool's other
    // workers are other runs').
    let in_pool = fast(n);
    pool.install(|| {
        let (mut q, mut y) = (vec![0.0; n], vec![0.0; n]);
        in_pool.compliance(&x, &mut q, &mut y);
        assert!(same_bits(&y, &y_seq));
    });
    assert_eq!(in_pool.compliance_threads(), 1);
    // Dropping the operators ends the helper (the test would hang otherwise).
    drop(ops);
}

#[test]
fn small_operators_keep_to_one_thread() {
    let n = PAIR_MIN_NODES / 2;
    let ops = fast(n);
    let x = vector(n, 1.0);
    let (mut q, mut y) = (vec![0.0; n], vec![0.0; n]);
    ops.compliance(&x, &mut q, &mut y);
    assert_eq!(ops.compliance_threads(), 1);
}
