//! Entry-wise access to the MDR operators (what the hierarchical build reads) against the dense builders: the same bits for every entry, one by one and row by row; the accurate entries of the product operators equal them to rounding, reproduce the exact transform pairs at large N where the dense formulas' rounding grows, and differ from the dense builders far below the fast form's tolerance.

use stickslip_core::grid::Grid;
use stickslip_core::mdr::{FAST_REL_TOL, OperatorEntries, TriangularOperator, literal, product};

/// Contact radius a0 in m (the paper's scale).
const A0: f64 = 2e-5;

/// Sizes checked entry by entry: every small N (leaf-sized and across the first splits)
/// and one larger.
fn sizes() -> impl Iterator<Item = usize> {
    (1..=70).chain([300])
}

/// Every entry of `source`, one by one, then whole rows and every third column of each
/// row (runs and gaps: the shared-cell path), against the dense operator's bits.
fn assert_same_bits(name: &str, source: &dyn OperatorEntries, dense: &TriangularOperator) {
    let n = dense.size();
    assert_eq!(source.size(), n);
    assert_eq!(source.triangle(), dense.triangle());
    let all: Vec<usize> = (0..n).collect();
    let every_third: Vec<usize> = (0..n).filter(|k| k % 3 != 1).collect();
    let mut row = vec![0.0; n];
    for i in 0..n {
        for k in 0..n {
            assert_eq!(
                source.entry(i, k).to_bits(),
                dense.get(i, k).to_bits(),
                "{name} N={n} entry ({i}, {k})"
            );
        }
        for cols in [&all, &every_third] {
            source.row_into(i, cols, &mut row);
            for (c, &k) in cols.iter().enumerate() {
                assert_eq!(
                    row[c].to_bits(),
                    dense.get(i, k).to_bits(),
                    "{name} N={n} row {i} at column {k}"
                );
            }
        }
    }
}

#[test]
fn product_entries_equal_dense_builders_bit_for_bit() {
    for n in sizes() {
        let grid = Grid::new(A0, n).expect("valid grid");
        let forward = product::forward(&grid);
        let back = product::back(&grid);
        assert_same_bits(
            "product forward",
            &product::ForwardEntries::new(grid),
            &forward,
        );
        assert_same_bits("product back", &product::BackEntries::new(grid), &back);
        let (j, m) = (n / 3, n - 1);
        assert_eq!(
            product::forward_entry(&grid, j, m).to_bits(),
            forward.get(j, m).to_bits()
        );
        assert_eq!(
            product::back_entry(&grid, m, j).to_bits(),
            back.get(m, j).to_bits()
        );
    }
}

#[test]
fn literal_entries_equal_dense_builders_bit_for_bit() {
    for n in sizes() {
        let grid = Grid::new(A0, n).expect("valid grid");
        assert_same_bits(
            "literal forward",
            &literal::ForwardEntries::new(grid),
            &literal::forward(&grid),
        );
        assert_same_bits(
            "literal back",
            &literal::BackEntries::new(grid),
            &literal::back(&grid),
        );
    }
}

/// The sources' cheap norm bounds lie below ‖A‖₂ (here the dense power-iteration
/// estimate, itself a lower bound, so the check is strict up to its few per cent).
#[test]
fn norm_lower_bounds_lie_below_the_norm() {
    for n in [1, 2, 33, 500] {
        let grid = Grid::new(A0, n).expect("valid grid");
        let cases: [(&str, &dyn OperatorEntries, TriangularOperator); 4] = [
            (
                "product forward",
                &product::ForwardEntries::new(grid),
                product::forward(&grid),
            ),
            (
                "product back",
                &product::BackEntries::new(grid),
                product::back(&grid),
            ),
            (
                "literal forward",
                &literal::ForwardEntries::new(grid),
                literal::forward(&grid),
            ),
            (
                "literal back",
                &literal::BackEntries::new(grid),
                literal::back(&grid),
            ),
        ];
        for (name, source, dense) in cases {
            let bound = source.norm_lower_bound();
            let norm = dense.norm_lower_bound();
            assert!(
                bound <= norm * (1.0 + 1e-9),
                "{name} N={n}: bound {bound:e} above the norm estimate {norm:e}"
            );
            assert!(bound > 0.0 || n == 1, "{name} N={n}: no bound");
        }
    }
}

/// The accurate product entries (Gauss rules on the cells away from the singular point,
/// what the build samples) equal the dense builders' closed forms to rounding at sizes
/// where the latter lose little (relative rounding ≈ (k/h)²·1e-16 at cell k).
#[test]
fn accurate_product_entries_equal_the_dense_builders_to_rounding() {
    for n in (1..=70).chain([300]) {
        let grid = Grid::new(A0, n).expect("valid grid");
        let cases: [(&str, &dyn OperatorEntries, TriangularOperator); 2] = [
            (
                "forward",
                &product::ForwardEntries::new(grid),
                product::forward(&grid),
            ),
            (
                "back",
                &product::BackEntries::new(grid),
                product::back(&grid),
            ),
        ];
        let all: Vec<usize> = (0..n).collect();
        let mut row = vec![0.0; n];
        for (name, source, dense) in cases {
            for i in 0..n {
                source.row_into_accurate(i, &all, &mut row);
                let scale = (0..n).map(|k| dense.get(i, k).abs()).fold(0.0, f64::max);
                for (k, &v) in row.iter().enumerate() {
                    let d = dense.get(i, k);
                    assert!(
                        (v - d).abs() <= 1e-13 * (n as f64) * scale,
                        "{name} N={n} ({i}, {k}): {v} vs {d}"
                    );
                    // Zeros outside the triangle stay exact zeros.
                    if d == 0.0 {
                        assert_eq!(v, 0.0);
                    }
                }
            }
        }
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1] by Newton's iteration (test reference).
fn gauss_legendre(points: usize) -> Vec<(f64, f64)> {
    let n = points as f64;
    (0..points)
        .map(|i| {
            let mut t = (std::f64::consts::PI * (i as f64 + 0.75) / (n + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, t);
                for k in 2..=points {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k);
                }
                derivative = n * (t * p1 - p0) / (t * t - 1.0);
                t -= p1 / derivative;
            }
            (t, 2.0 / ((1.0 - t * t) * derivative * derivative))
        })
        .collect()
}

/// ∫ f over [lo, lo + len] by a 12-point Gauss rule on each of 32 equal pieces (the
/// length passed separately: hi − lo would cancel).
fn composite(lo: f64, len: f64, rule: &[(f64, f64)], f: impl Fn(f64) -> f64) -> f64 {
    let pieces = 32;
    let width = len / pieces as f64;
    (0..pieces)
        .map(|p| {
            let (a, half) = (lo + p as f64 * width, 0.5 * width);
            rule.iter()
                .map(|&(t, w)| w * half * f(a + half * (1.0 + t)))
                .sum::<f64>()
        })
        .sum()
}

/// Reference hat weights of one cell [a, b] (left node a, right node b) by composite
/// Gauss rules in the variables where the integrands are smooth: the forward transform at
/// x ≤ a in s = √(r² − x²), the back transform at r ≥ b in c = √(r² − x²), with the
/// cancellation-free differences b − r = (b² − r²)/(b + r) etc.
fn reference_cell(
    forward: bool,
    a: f64,
    b: f64,
    y: f64,
    h: f64,
    rule: &[(f64, f64)],
) -> (f64, f64) {
    let diff_sq = |p: f64, q: f64| ((p - q) * (p + q)).max(0.0);
    if forward {
        let (sa, sb) = (diff_sq(a, y).sqrt(), diff_sq(b, y).sqrt());
        let len = (b - a) * (b + a) / (sa + sb);
        let r = |s: f64| (s * s + y * y).sqrt();
        // sb − s and s − sa from the offset within [sa, sa + len], without cancellation.
        let left = composite(0.0, len, rule, |u| {
            (len - u) * (sb + sa + u) / (b + r(sa + u))
        });
        let right = composite(0.0, len, rule, |u| u * (2.0 * sa + u) / (r(sa + u) + a));
        (2.0 / h * left, 2.0 / h * right)
    } else {
        let (ca, cb) = (diff_sq(y, a).sqrt(), diff_sq(y, b).sqrt());
        let len = (b - a) * (b + a) / (ca + cb);
        let gap = a * a / (y + ca);
        // c = cb + u, u ∈ [0, len]: c − cb = u, ca − c = len − u, y − c = gap + len − u.
        let x = |u: f64| ((gap + (len - u)) * (y + cb + u)).sqrt();
        let left = composite(0.0, len, rule, |u| u * (2.0 * cb + u) / ((b + x(u)) * x(u)));
        let right = composite(0.0, len, rule, |u| {
            (len - u) * (ca + cb + u) / ((x(u) + a) * x(u))
        });
        let scale = 2.0 / std::f64::consts::PI / h;
        (scale * left, scale * right)
    }
}

/// At N = 20000, where the dense formulas lose up to ~(N)²·1e-16 of an entry, the accurate
/// entries match an independent high-order quadrature of the same integrals to ~1e-14
/// relative (cells away from the singular point; the few next to it or to the axis use
/// the closed form, accurate there, and are compared with it).
#[test]
fn accurate_product_entries_match_a_high_order_quadrature_at_large_n() {
    let n = 20_000;
    let grid = Grid::new(A0, n).expect("valid grid");
    let h = grid.spacing_m();
    let rule = gauss_legendre(12);
    let forward = product::ForwardEntries::new(grid);
    let back = product::BackEntries::new(grid);
    let r = |k: usize| grid.node_radius_m(k);
    let (mut worst_accurate, mut worst_dense) = (0.0_f64, 0.0_f64);
    let mut row = vec![0.0; n];
    let mut dense_row = vec![0.0; n];
    for i in [1, 9, 300, 5000, 12_345, 19_990, n - 1] {
        let cols: Vec<usize> = (0..n)
            .filter(|k| k % 97 == 0 || k.abs_diff(i) < 20)
            .collect();
        for is_forward in [true, false] {
            let source: &dyn OperatorEntries = if is_forward { &forward } else { &back };
            source.row_into_accurate(i, &cols, &mut row);
            source.row_into(i, &cols, &mut dense_row);
            for (c, &m) in cols.iter().enumerate() {
                // Cells m − 1 and m, where they exist and lie on the triangle's side.
                let cell = |k: usize| reference_cell(is_forward, r(k), r(k + 1), r(i), h, &rule);
                let exact = if is_forward {
                    if m < i {
                        continue;
                    }
                    let right = if m > i { cell(m - 1).1 } else { 0.0 };
                    let left = if m + 1 < n {
                        cell(m).0
                    } else {
                        // Constant data on the last cell: 2∫ r/√(r² − x²) dr = 2(s_b − s_a).
                        let (a, b, x) = (r(m), r(m + 1), r(i));
                        let s = |p: f64| ((p - x) * (p + x)).sqrt();
                        2.0 * (b - a) * (b + a) / (s(a) + s(b))
                    };
                    right + left
                } else {
                    if m > i || m == 0 || i < 20 {
                        continue; // closed form only (first cell, rows near the axis)
                    }
                    let right = cell(m - 1).1;
                    let left = if m < i { cell(m).0 } else { 0.0 };
                    right + left
                };
                let rel = |v: f64| (v - exact).abs() / exact.abs();
                worst_accurate = worst_accurate.max(rel(row[c]));
                worst_dense = worst_dense.max(rel(dense_row[c]));
                assert!(
                    rel(row[c]) <= 1e-14,
                    "forward={is_forward} ({i}, {m}): {} vs {exact}",
                    row[c]
                );
            }
        }
    }
    println!("N = {n}: accurate entries {worst_accurate:.2e}, dense formulas {worst_dense:.2e}");
    assert!(
        worst_dense > 100.0 * worst_accurate,
        "the dense formulas should lose more"
    );
}

/// The dense builders' rounding noise (what the fast form, built from accurate entries,
/// does not reproduce) at N = 2000, on random vectors: far below the fast form's tolerance.
#[test]
fn dense_builders_noise_is_below_the_fast_tolerance() {
    let n = 2000;
    let grid = Grid::new(A0, n).expect("valid grid");
    let cases: [(&dyn OperatorEntries, TriangularOperator); 2] = [
        (&product::ForwardEntries::new(grid), product::forward(&grid)),
        (&product::BackEntries::new(grid), product::back(&grid)),
    ];
    let all: Vec<usize> = (0..n).collect();
    let mut row = vec![0.0; n];
    let x: Vec<f64> = (0..n)
        .map(|i| ((i * 7919 % 2003) as f64 / 1001.5) - 1.0)
        .collect();
    let norm_x = x.iter().map(|a| a * a).sum::<f64>().sqrt();
    for (source, dense) in cases {
        let mut y = vec![0.0; n];
        dense.apply(&x, &mut y);
        let mut worst = 0.0_f64;
        for (i, yi) in y.iter().enumerate() {
            source.row_into_accurate(i, &all, &mut row);
            let accurate: f64 = row.iter().zip(&x).map(|(a, b)| a * b).sum();
            worst = worst.max((accurate - yi).abs());
        }
        let scale = FAST_REL_TOL * dense.norm_lower_bound() * norm_x;
        println!(
            "{:?}: max |A_acc·x − A·x| = {:.2e}·tol·ν·‖x‖",
            dense.triangle(),
            worst / scale
        );
        assert!(worst <= 0.01 * scale, "{worst:e} vs {scale:e}");
    }
}
