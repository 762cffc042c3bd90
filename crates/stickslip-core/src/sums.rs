//! Sums over the nodes in eight interleaved partial sums: node i's term goes into partial sum
//! i mod 8, and the eight are added in order at the end.
//!
//! Why: a single running sum is a chain of dependent additions, one add's latency per node
//! (N = 2000: about 2 µs a sum on this project's machines, and a step takes several: the
//! force, the coupling's norms, the energy books, the events' areas). Eight chains run side
//! by side and vectorise. The order is fixed by the node index alone, so a sum has the same
//! bits on every instruction set and every call, and two places that sum the same quantity
//! (the events' melted area and the series', say) agree to the bit.
//!
//! The terms come from columns (one slice per per-node quantity, all of one length), read in
//! blocks of eight, so that the loops carry no bounds checks, and run under the CPU's best
//! instruction set (pulp's run-time dispatch; the term is inlined into each version).

use faer::traits::pulp::{Arch, Simd, WithSimd};

/// Partial sums per sum.
pub const LANES: usize = 8;

/// Σ term(column values at node i) over the nodes, in [`LANES`] interleaved partial sums.
///
/// # Panics
/// If the columns' lengths differ.
#[inline]
pub fn sum_cols<const K: usize>(cols: [&[f64]; K], term: impl Fn([f64; K]) -> f64) -> f64 {
    Arch::new()
        .dispatch(SumCols {
            cols,
            term: |v: [f64; K]| (term(v), 0.0),
        })
        .0
}

/// Two sums in one pass over the nodes, each as [`sum_cols`] sums it.
///
/// # Panics
/// If the columns' lengths differ.
#[inline]
pub fn sum2_cols<const K: usize>(
    cols: [&[f64]; K],
    term: impl Fn([f64; K]) -> (f64, f64),
) -> (f64, f64) {
    Arch::new().dispatch(SumCols { cols, term })
}

/// The largest term over the nodes, from `floor` up (`f64::max`: a NaN term is passed
/// over), taken in [`LANES`] interleaved partial maxima: a maximum is the same in any order,
/// so this is the sequential fold's value, without its chain.
///
/// # Panics
/// If the columns' lengths differ.
#[inline]
pub fn max_cols<const K: usize>(
    cols: [&[f64]; K],
    floor: f64,
    term: impl Fn([f64; K]) -> f64,
) -> f64 {
    Arch::new().dispatch(MaxCols { cols, floor, term })
}

/// Σ w_i·x_i in [`LANES`] interleaved partial sums.
///
/// # Panics
/// If the lengths differ.
#[inline]
#[must_use]
pub fn dot(w: &[f64], x: &[f64]) -> f64 {
    sum_cols([w, x], |[w, x]| w * x)
}

/// [`sum2_cols`]'s loop, compiled once per instruction set.
struct SumCols<'a, const K: usize, F> {
    cols: [&'a [f64]; K],
    term: F,
}

impl<const K: usize, F: Fn([f64; K]) -> (f64, f64)> WithSimd for SumCols<'_, K, F> {
    type Output = (f64, f64);

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) -> (f64, f64) {
        let n = self.cols.first().map_or(0, |c| c.len());
        assert!(
            self.cols.iter().all(|c| c.len() == n),
            "the columns' lengths differ"
        );
        let blocks = self.cols.map(|c| c.as_chunks::<LANES>());
        let mut acc = ([0.0; LANES], [0.0; LANES]);
        for b in 0..n / LANES {
            let block = blocks.map(|(full, _)| &full[b]);
            for l in 0..LANES {
                let (x, y) = (self.term)(block.map(|col| col[l]));
                acc.0[l] += x;
                acc.1[l] += y;
            }
        }
        let tail = blocks.map(|(_, rest)| rest);
        for l in 0..n % LANES {
            let (x, y) = (self.term)(tail.map(|col| col[l]));
            acc.0[l] += x;
            acc.1[l] += y;
        }
        (finish(acc.0), finish(acc.1))
    }
}

/// [`max_cols`]'s loop, compiled once per instruction set.
struct MaxCols<'a, const K: usize, F> {
    cols: [&'a [f64]; K],
    floor: f64,
    term: F,
}

impl<const K: usize, F: Fn([f64; K]) -> f64> WithSimd for MaxCols<'_, K, F> {
    type Output = f64;

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) -> f64 {
        let n = self.cols.first().map_or(0, |c| c.len());
        assert!(
            self.cols.iter().all(|c| c.len() == n),
            "the columns' lengths differ"
        );
        let blocks = self.cols.map(|c| c.as_chunks::<LANES>());
        let mut acc = [self.floor; LANES];
        for b in 0..n / LANES {
            let block = blocks.map(|(full, _)| &full[b]);
            for (l, a) in acc.iter_mut().enumerate() {
                *a = a.max((self.term)(block.map(|col| col[l])));
            }
        }
        let tail = blocks.map(|(_, rest)| rest);
        for (l, a) in acc.iter_mut().enumerate().take(n % LANES) {
            *a = a.max((self.term)(tail.map(|col| col[l])));
        }
        acc.into_iter().fold(self.floor, f64::max)
    }
}

/// The partial sums added in order.
#[inline(always)]
fn finish(acc: [f64; LANES]) -> f64 {
    let mut s = 0.0;
    for a in acc {
        s += a;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_term_is_summed_once_whatever_the_length() {
        // Powers of two are exact in any order: a missed or doubled term shows.
        for n in 0..40 {
            let powers: Vec<f64> = (0..n).map(|i| f64::powi(2.0, i)).collect();
            let ones = vec![1.0; powers.len()];
            let exact: f64 = powers.iter().sum();
            assert_eq!(sum_cols([&powers], |[p]| p), exact, "n = {n}");
            assert_eq!(dot(&powers, &ones), exact, "n = {n}");
            let (a, b) = sum2_cols([&powers, &ones], |[p, o]| (p, o));
            assert_eq!((a, b), (exact, f64::from(n)), "n = {n}");
        }
    }

    #[test]
    fn the_order_is_the_lanes_not_the_sequence() {
        // 1, then fifteen terms of 2^-53: a sequential sum loses every one (1 + 2^-53 rounds
        // to 1). In lanes, lane 0 holds 1 and one of them (lost in the same way), and lanes
        // 1-7 two each, 2^-52, which the 1 keeps: 1 + 7·2^-52.
        let tiny = f64::powi(2.0, -53);
        let terms: Vec<f64> = std::iter::once(1.0)
            .chain(std::iter::repeat_n(tiny, 15))
            .collect();
        let sequential: f64 = terms.iter().sum();
        assert_eq!(sequential, 1.0);
        assert_eq!(sum_cols([&terms], |[t]| t), 1.0 + 7.0 * f64::powi(2.0, -52));
    }

    #[test]
    fn the_largest_term_is_the_sequential_folds() {
        let terms: Vec<f64> = (0..37).map(|i| f64::from(i * 7 % 37) - 3.5).collect();
        let mut with_nan = terms.clone();
        with_nan[5] = f64::NAN;
        for t in [&terms, &with_nan] {
            let sequential = t.iter().fold(0.0_f64, |m, &x| m.max(x.abs()));
            assert_eq!(max_cols([t], 0.0, |[x]| x.abs()), sequential);
        }
        assert_eq!(max_cols([&[] as &[f64]], 2.0, |[x]| x), 2.0);
    }

    #[test]
    #[should_panic(expected = "lengths differ")]
    fn columns_of_different_lengths_are_refused() {
        let _ = dot(&[1.0, 2.0], &[1.0]);
    }
}
