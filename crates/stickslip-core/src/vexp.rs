//! e^x and e^x − 1 without a library call: one range reduction and one polynomial, branch-free
//! (selects only), so a loop over nodes that calls [`exp_expm1`] inline is vectorised by the
//! compiler, where a call to libm's `exp` per node is not.
//!
//! x = k·ln 2 + r with k = round(x/ln 2) and |r| ≤ ln 2/2 (Cody–Waite: ln 2 split in a high
//! part with trailing zeros, so k·ln2_hi is exact, and a low part); p = e^r − 1 by its Taylor
//! series to r¹³ (the first term left out is below 2⁻⁵³·|r| on the reduced range), so
//! e^x = 2^k·(1 + p) and e^x − 1 = 2^k·p + (2^k − 1), both within 2 ulp of the exact value
//! (tested against libm on a million arguments). 2^k is built from its exponent bits; k
//! beyond the normal range is split into two factors, so results underflow gradually into
//! the subnormals and overflow to +∞ exactly where libm's do. NaN stays NaN.

use faer::traits::pulp::{Arch, Simd, WithSimd};

/// ln 2's high part: 32 trailing zero bits, so k·LN2_HI is exact for |k| < 2²⁰.
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
/// ln 2 − LN2_HI.
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// 1.5·2⁵²: adding it rounds to an integer held in the low mantissa bits.
const SHIFTER: f64 = 6_755_399_441_055_744.0;
/// Below this e^x is 0 (half the least subnormal is at −745.13).
const X_MIN: f64 = -746.0;
/// Above this e^x is +∞ (overflow at 709.78).
const X_MAX: f64 = 710.0;

/// (e^x, e^x − 1), each within 2 ulp; `#[inline(always)]` so loops over nodes vectorise.
#[inline(always)]
#[must_use]
pub fn exp_expm1(x: f64) -> (f64, f64) {
    // NaN stays NaN; ±∞ land on the clamps.
    let x = x.clamp(X_MIN, X_MAX);
    let t = x * std::f64::consts::LOG2_E + SHIFTER;
    let kf = t - SHIFTER;
    // k as an integer from t's low bits (two's complement around the shifter's mantissa).
    let k = (t.to_bits().wrapping_sub(SHIFTER.to_bits())) as i64;
    let r = (x - kf * LN2_HI) - kf * LN2_LO;
    let p = r + r * r * taylor_tail(r);
    // k outside [−1000, 1000]: 2^k = 2^(k + off)·2^(−off) with a normal first factor.
    let (off, factor) = if k < -1000 {
        (1000, f64::from_bits((0x3ff - 1000) << 52))
    } else if k > 1000 {
        (-1, 2.0)
    } else {
        (0, 1.0)
    };
    let s = f64::from_bits(((k + off + 0x3ff) as u64) << 52);
    let e = (s + s * p) * factor;
    // e − 1 loses nothing once |k| is large (e ≫ 1 or e ≪ 1); near 0 it would cancel.
    let m = if off == 0 { s * p + (s - 1.0) } else { e - 1.0 };
    (e, m)
}

/// e^x (within 2 ulp); see [`exp_expm1`].
#[inline(always)]
#[must_use]
pub fn exp(x: f64) -> f64 {
    exp_expm1(x).0
}

/// e^x − 1 (within 2 ulp); see [`exp_expm1`].
#[inline(always)]
#[must_use]
pub fn expm1(x: f64) -> f64 {
    exp_expm1(x).1
}

/// `(e[i], m[i]) = exp_expm1(x[i])` for every element, under the best instruction set the CPU
/// has (pulp's run-time dispatch, as the HODLR apply): the loop is vectorised there. No fused
/// multiply-add is used, so the bits are those of [`exp_expm1`] on every instruction set.
///
/// # Panics
/// If the three slices differ in length.
pub fn exp_expm1_all(x: &[f64], e: &mut [f64], m: &mut [f64]) {
    assert!(
        x.len() == e.len() && x.len() == m.len(),
        "slice lengths differ"
    );
    Arch::new().dispatch(Kernel { x, e, m });
}

/// [`exp_expm1_all`]'s loop, compiled once per instruction set.
struct Kernel<'a> {
    x: &'a [f64],
    e: &'a mut [f64],
    m: &'a mut [f64],
}

impl WithSimd for Kernel<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        for ((&x, e), m) in self.x.iter().zip(self.e.iter_mut()).zip(self.m.iter_mut()) {
            (*e, *m) = exp_expm1(x);
        }
    }
}

/// (e^r − 1 − r)/r² = Σ_{n≥2} rⁿ⁻²/n! to r¹³ by Horner's rule.
#[inline(always)]
fn taylor_tail(r: f64) -> f64 {
    const C: [f64; 12] = [
        1.0 / 2.0,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5_040.0,
        1.0 / 40_320.0,
        1.0 / 362_880.0,
        1.0 / 3_628_800.0,
        1.0 / 39_916_800.0,
        1.0 / 479_001_600.0,
        1.0 / 6_227_020_800.0,
    ];
    let mut q = C[11];
    for &c in C[..11].iter().rev() {
        q = c + r * q;
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between two finite doubles of the same sign (0 for
    /// equal bits, including both zero or both NaN).
    fn ulps(a: f64, b: f64) -> u64 {
        if a.is_nan() && b.is_nan() || a == b {
            return 0;
        }
        assert!(
            a.is_finite() && b.is_finite() && (a >= 0.0) == (b >= 0.0),
            "{a:e} vs {b:e}"
        );
        let (ia, ib) = (a.abs().to_bits(), b.abs().to_bits());
        ia.abs_diff(ib)
    }

    /// A deterministic spread of arguments: uniform in [lo, hi], plus log-uniform magnitudes.
    fn samples(n: usize, seed: u64) -> Vec<f64> {
        let mut state = seed;
        let mut next = move || {
            // splitmix64
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let u = next();
            let x = match i % 3 {
                // The whole finite range of results, subnormal ones included.
                0 => -746.0 + u * (709.78 + 746.0),
                // Where the steps live: |x| up to 40.
                1 => -40.0 + 80.0 * u,
                // Tiny magnitudes of both signs, 1e-300 … 1.
                _ => {
                    let mag = 10f64.powf(-300.0 * next());
                    if u < 0.5 { -mag } else { mag }
                }
            };
            out.push(x);
        }
        out
    }

    #[test]
    fn exp_and_expm1_are_within_two_ulp_of_libm_on_a_million_arguments() {
        let mut edge = vec![
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            5e-324,
            1e-300,
            -1e-300,
            1e-17,
            -1e-17,
            0.5 * std::f64::consts::LN_2,
            -0.5 * std::f64::consts::LN_2,
            std::f64::consts::LN_2,
            -std::f64::consts::LN_2,
            1.0,
            -1.0,
            36.0,
            -36.0,
            -40.0,
            -700.0,
            -708.3,
            -708.4,
            -709.0,
            -720.0,
            -740.0,
            -745.0,
            -745.1,
            -745.2,
            -1e4,
            709.0,
            709.7,
            709.78,
            709.8,
            1e4,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        // Both sides of every rounding switch of k, and around the subnormal threshold.
        for k in -1080..=1030 {
            let x = (f64::from(k) + 0.5) * std::f64::consts::LN_2;
            edge.extend([x, x.next_up(), x.next_down()]);
        }
        let mut worst = (0u64, 0.0, 0u64, 0.0);
        for &x in edge.iter().chain(&samples(1_000_000, 7)) {
            let (e, m) = exp_expm1(x);
            let (de, dm) = (ulps(e, x.exp()), ulps(m, x.exp_m1()));
            if de > worst.0 {
                worst.0 = de;
                worst.1 = x;
            }
            if dm > worst.2 {
                worst.2 = dm;
                worst.3 = x;
            }
        }
        // Measured: 1 ulp for e^x, 2 ulp for e^x − 1 (near x = 0.39, where k = 1).
        assert!(worst.0 <= 1, "exp: {} ulp at x = {:e}", worst.0, worst.1);
        assert!(worst.2 <= 2, "expm1: {} ulp at x = {:e}", worst.2, worst.3);
    }

    #[test]
    fn the_dispatched_loop_gives_the_scalar_bits() {
        let x = samples(10_001, 3);
        let (mut e, mut m) = (vec![0.0; x.len()], vec![0.0; x.len()]);
        exp_expm1_all(&x, &mut e, &mut m);
        for (i, &xi) in x.iter().enumerate() {
            let (se, sm) = exp_expm1(xi);
            assert_eq!(
                (e[i].to_bits(), m[i].to_bits()),
                (se.to_bits(), sm.to_bits()),
                "x = {xi:e}"
            );
        }
    }

    #[test]
    fn special_values_are_libms() {
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
        assert_eq!(exp(f64::INFINITY), f64::INFINITY);
        assert_eq!(exp(710.0), f64::INFINITY);
        assert_eq!(exp(-746.0), 0.0);
        assert!(exp(f64::NAN).is_nan() && expm1(f64::NAN).is_nan());
        assert_eq!(expm1(f64::NEG_INFINITY), -1.0);
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(expm1(0.0), 0.0);
        // Subnormal results are produced, not flushed to zero.
        assert!(exp(-740.0) > 0.0 && exp(-740.0) < f64::MIN_POSITIVE);
    }
}
