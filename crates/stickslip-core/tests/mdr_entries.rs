//! Entry-wise access to the MDR operators (what the hierarchical build reads) against the dense builders: the same bits for every entry, one by one and row by row.

use stickslip_core::grid::Grid;
use stickslip_core::mdr::{OperatorEntries, TriangularOperator, literal, product};

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
