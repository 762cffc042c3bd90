//! The fast MDR operators as a simulation builds them (`MdrOperators::with_form(…, Fast)`, from entries computed on demand) against the dense ones, the lazily built dense operators of the fast form, and a large build that holds no dense matrix.

use stickslip_core::grid::Grid;
use stickslip_core::mdr::{FAST_REL_TOL, MdrOperators, OperatorForm, Quadrature};

/// Contact radius a0 in m (the paper's scale).
const A0: f64 = 2e-5;

/// Bound on max |y_fast − y_dense| in units of FAST_REL_TOL·ν·‖x‖₂ (ν the build's norm
/// estimate); measured at most 0.09 (N = 33) over the sizes and vectors below.
const C_MEASURED: f64 = 0.5;

/// Sizes: one leaf (N ≤ 32, exact), the first split (33), and the tree at depth 2–6.
const SIZES: [usize; 9] = [1, 2, 3, 31, 32, 33, 125, 1000, 2000];

/// Three deterministic vectors in [−1, 1) (SplitMix64).
fn random_vectors(n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        2.0 * ((z >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    };
    (0..3).map(|_| (0..n).map(|_| next()).collect()).collect()
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|a| a.to_bits()).collect()
}

#[test]
fn fast_form_agrees_with_dense_within_the_stated_bound() {
    for quadrature in [Quadrature::Product, Quadrature::Literal] {
        for n in SIZES {
            let grid = Grid::new(A0, n).expect("valid grid");
            let dense = MdrOperators::new(grid, quadrature);
            let fast = MdrOperators::with_form(grid, quadrature, OperatorForm::Fast);
            assert_eq!(fast.form(), OperatorForm::Fast);
            assert!(
                !fast.has_dense_operators(),
                "the fast form built a dense matrix"
            );
            let (fast_forward, fast_back) = fast.fast_operators().expect("fast form");
            let mut worst = 0.0_f64;
            for x in random_vectors(n, n as u64) {
                let (mut yd, mut yf) = (vec![0.0; n], vec![0.0; n]);
                for (op, name) in [(fast_forward, "forward"), (fast_back, "back")] {
                    if name == "forward" {
                        dense.forward(&x, &mut yd);
                        fast.forward(&x, &mut yf);
                    } else {
                        dense.back(&x, &mut yd);
                        fast.back(&x, &mut yf);
                    }
                    if n <= 32 {
                        // One dense leaf: the same bits as the packed mat-vec.
                        assert_eq!(bits(&yf), bits(&yd), "{quadrature:?} {name} N={n}");
                        continue;
                    }
                    let diff: Vec<f64> = yd.iter().zip(&yf).map(|(d, f)| d - f).collect();
                    let err_max = diff.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
                    let scale = FAST_REL_TOL * op.norm_estimate() * norm2(&x);
                    worst = worst.max(err_max / scale);
                    assert!(
                        err_max <= C_MEASURED * scale,
                        "{quadrature:?} {name} N={n}: max error {err_max:e} > {:e}",
                        C_MEASURED * scale
                    );
                    let rounding = 1e-15 * (n as f64).sqrt() * op.norm_estimate() * norm2(&x);
                    assert!(
                        norm2(&diff) <= op.error_bound() * norm2(&x) + rounding,
                        "{quadrature:?} {name} N={n}: 2-norm error {:e} above the stated \
                         bound {:e}",
                        norm2(&diff),
                        op.error_bound() * norm2(&x)
                    );
                }
            }
            println!("{quadrature:?} N={n:>4}: max err/(tol·ν·‖x‖) = {worst:.3e}");
            assert!(!fast.has_dense_operators());
        }
    }
}

#[test]
fn fast_form_builds_its_dense_operators_on_request_with_the_dense_bits() {
    for quadrature in [Quadrature::Product, Quadrature::Literal] {
        let grid = Grid::new(A0, 300).expect("valid grid");
        let dense = MdrOperators::new(grid, quadrature);
        let fast = MdrOperators::with_form(grid, quadrature, OperatorForm::Fast);
        assert!(!fast.has_dense_operators());
        let c_fast = fast.compliance_dense();
        assert!(fast.has_dense_operators());
        let c_dense = dense.compliance_dense();
        for i in 0..300 {
            for k in 0..300 {
                assert_eq!(c_fast[(i, k)].to_bits(), c_dense[(i, k)].to_bits());
                let (f, d) = (fast.forward_operator(), dense.forward_operator());
                assert_eq!(f.get(i, k).to_bits(), d.get(i, k).to_bits());
                let (f, d) = (fast.back_operator(), dense.back_operator());
                assert_eq!(f.get(i, k).to_bits(), d.get(i, k).to_bits());
            }
        }
        // The transforms still use the fast form; a clone keeps what was built.
        assert_eq!(fast.form(), OperatorForm::Fast);
        assert!(fast.clone().has_dense_operators());
    }
}

#[test]
fn dense_bytes_counts_both_packed_triangles() {
    assert_eq!(MdrOperators::dense_bytes(1), 16);
    assert_eq!(MdrOperators::dense_bytes(2000), 2000 * 2001 * 8);
    assert_eq!(MdrOperators::dense_bytes(200_000), 320_001_600_000);
    assert_eq!(MdrOperators::dense_bytes(usize::MAX), usize::MAX);
    let grid = Grid::new(A0, 500).expect("valid grid");
    let dense = MdrOperators::new(grid, Quadrature::Product);
    assert_eq!(dense.fast_bytes(), 0);
    let fast = MdrOperators::with_form(grid, Quadrature::Product, OperatorForm::Fast);
    assert!(fast.fast_bytes() < MdrOperators::dense_bytes(500));
}

/// The largest N a scene accepts: the build holds no dense matrix (N(N+1)/2 = 2·10⁸
/// values, 1.6 GB per operator) and stores a few hundred values per node. About 1–2 s in
/// release on one core.
#[test]
fn fast_build_at_20000_holds_no_dense_matrix() {
    let n = 20_000;
    let grid = Grid::new(A0, n).expect("valid grid");
    let start = std::time::Instant::now();
    let ops = MdrOperators::with_form(grid, Quadrature::Product, OperatorForm::Fast);
    let seconds = start.elapsed().as_secs_f64();
    assert!(!ops.has_dense_operators());
    let (forward, back) = ops.fast_operators().expect("fast form");
    for op in [forward, back] {
        assert!(
            op.stored_entries() < 100 * n,
            "{} stored, against {} dense",
            op.stored_entries(),
            n * (n + 1) / 2
        );
        assert!(op.max_rank() <= 30, "{:?}", op.rank_profile());
        assert!(op.error_bound_factor() < 200.0);
    }
    // Uniform stress has the exact image q = 2√(a0² − x²) (product integration), and a
    // constant u1D is reproduced by the back transform: checks at a size without a
    // dense reference.
    let tau = vec![1.0; n];
    let mut q = vec![0.0; n];
    ops.forward(&tau, &mut q);
    let mut u = vec![0.0; n];
    ops.back(&tau, &mut u);
    for (j, (qj, uj)) in q.iter().zip(&u).enumerate() {
        let x = grid.node_radius_m(j);
        let exact = 2.0 * ((A0 - x) * (A0 + x)).sqrt();
        assert!((qj - exact).abs() <= 1e-8 * 2.0 * A0, "q at node {j}");
        assert!((uj - 1.0).abs() <= 1e-8, "u3D at node {j}");
    }
    println!(
        "N = {n}: built in {seconds:.2} s, {} MB of factors",
        ops.fast_bytes() / 1_000_000
    );
}

/// The build runs independent parts side by side where threads are free; the operators
/// (and so every apply) must not depend on how many there are.
#[test]
fn fast_build_does_not_depend_on_the_thread_count() {
    let grid = Grid::new(A0, 1500).expect("valid grid");
    let build = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| MdrOperators::with_form(grid, Quadrature::Product, OperatorForm::Fast))
    };
    let (one, three) = (build(1), build(3));
    for x in random_vectors(1500, 5) {
        let (mut a, mut b) = (vec![0.0; 1500], vec![0.0; 1500]);
        one.forward(&x, &mut a);
        three.forward(&x, &mut b);
        assert_eq!(bits(&a), bits(&b));
        one.back(&x, &mut a);
        three.back(&x, &mut b);
        assert_eq!(bits(&a), bits(&b));
    }
    let (f1, b1) = one.fast_operators().expect("fast form");
    let (f3, b3) = three.fast_operators().expect("fast form");
    assert_eq!(f1.stored_entries(), f3.stored_entries());
    assert_eq!(b1.error_bound().to_bits(), b3.error_bound().to_bits());
}
