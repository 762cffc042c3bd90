//! The local error of one accurate step, estimated from what the step computed: no second
//! solution, no extra coupling solve.
//!
//! ## The film (φ)
//! Per node the accurate step follows the exact solution of Eq. 8 with the strain frozen at
//! an effective value ε_eff. That path y(s) = φ(s)² is a continuous extension of the step,
//! and its **defect** against the true equation is
//!
//! D(s) = F(y, ε_eff) − F(y, ε(s)) = −2γ·a·y(s)·(ε_eff² − ε(s)²),  F(y, ε) = −2γy(c(ε) + by).
//!
//! The local error of y at the step's end is ∫₀ʰ P(s)·D(s) ds, P(s) = ∂y(h)/∂y(s) the
//! propagator along the path. With ε known at both ends (ε0 from the last step, ε_end from
//! this step's coupling solve — so the estimate also sees how far the predicted end strain
//! was off) D is interpolated linearly in s, and P exponentially between P(0) and P(h) = 1:
//! P(s) = e^(−z(1−s/h)) with z = −ln P(0) = ∫₀ʰ λ ds, λ = 2γ·(c + 2b·y) the path's local
//! relaxation rate, taken by the trapezoidal rule ([`propagator_exponent`]). Then
//!
//! e_y ≈ h·[w0(z)·D(0) + w1(z)·D(h)],
//! w0(z) = ∫₀¹ e^(−zv) v dv = (1 − e^(−z)(1 + z))/z²,  w1(z) = ∫₀¹ e^(−z(1−u)) u du = (z − 1 + e^(−z))/z².
//!
//! For a linearised film and a linear strain ramp the step's weight θ(z) makes this vanish
//! (the step is exact there); what remains measures the nonlinearity of the film's response
//! over the step (largest near the fold, where φ collapses) and the strain's deviation from
//! the predicted ramp. Both are O(h³) for the second-order step, and the estimate is too:
//! the controller uses exponent 1/3. Stiff nodes (z ≫ 1, φ slaved to ε) get weights
//! ~1/z, so their error is the equilibrium's shift with the strain error, as it should be;
//! growing nodes (z < 0) see the amplification of the regrowth.
//!
//! ## The stamp (X, V)
//! Velocity Verlet's local errors are h³·X'''/6 in X and −h³·X''''/12 in V; with the
//! accelerations a0, a1 at the step's ends and the change of the previous step,
//! e_X ≈ h²·|a1 − a0|/6 and e_V ≈ h³·|a''|/12, a'' from the two last changes. RK4 with the
//! friction force frozen over the step is first order in F: e_X ≈ h²·|ΔF|/(6m),
//! e_V ≈ h·|ΔF|/(2m). The rigid drive is exact.

/// Weights (w0, w1) of the defect at the start and at the end of a step (module docs).
///
/// Series for |z| < 0.01 (the closed forms cancel there); above [`STIFF_Z`] e^(−z) is below
/// rounding against 1 and the weights are 1/z² and (z − 1)/z² without an exponential;
/// `z` is clamped below at −40 (an amplification of e^40 means the error is hopeless anyway).
#[must_use]
pub fn defect_weights(z: f64) -> (f64, f64) {
    let z = z.max(-40.0);
    defect_weights_from(z, crate::vexp::exp_expm1(-z))
}

/// [`defect_weights`] of a `z` already clamped below at −40, given (e^(−z), e^(−z) − 1): the
/// accurate step takes the exponentials of all nodes in one vectorised loop
/// ([`crate::vexp::exp_expm1_all`]) and then the weights here.
#[inline(always)]
#[must_use]
pub fn defect_weights_from(z: f64, (e, m): (f64, f64)) -> (f64, f64) {
    if z > STIFF_Z {
        let inv = 1.0 / z;
        return (inv * inv, (z - 1.0) * inv * inv);
    }
    if z.abs() < 0.01 {
        // w0 = Σ (−z)^k/(k!(k+2)), w1 = Σ (−z)^k/(k+2)!
        // (Constant reciprocals multiplied, not divided by: divisions dominate a node's
        // arithmetic.)
        let w0 = 0.5 - z * (1.0 / 3.0) + z * z * (1.0 / 8.0) - z * z * z * (1.0 / 30.0);
        let w1 = 0.5 - z * (1.0 / 6.0) + z * z * (1.0 / 24.0) - z * z * z * (1.0 / 120.0);
        return (w0, w1);
    }
    // 1 − e^(−z) directly where it does not cancel, expm1 where it would.
    let one_minus_e = if z.abs() > 0.5 { 1.0 - e } else { -m };
    let inv = 1.0 / z;
    let inv_sq = inv * inv;
    let w0 = (one_minus_e - z * e) * inv_sq;
    let w1 = (z - one_minus_e) * inv_sq;
    (w0, w1)
}

/// [`defect_weights_from`] with selects in place of branches, bit for bit the same weights
/// (every form computed, the one the branches would take kept), so that a loop over nodes
/// vectorises ([`super::node_pass`]).
#[inline(always)]
#[must_use]
pub fn defect_weights_select(z: f64, (e, m): (f64, f64)) -> (f64, f64) {
    let inv = 1.0 / z;
    let stiff = (inv * inv, (z - 1.0) * inv * inv);
    let small = (
        0.5 - z * (1.0 / 3.0) + z * z * (1.0 / 8.0) - z * z * z * (1.0 / 30.0),
        0.5 - z * (1.0 / 6.0) + z * z * (1.0 / 24.0) - z * z * z * (1.0 / 120.0),
    );
    let one_minus_e = if z.abs() > 0.5 { 1.0 - e } else { -m };
    let inv_sq = inv * inv;
    let mid = ((one_minus_e - z * e) * inv_sq, (z - one_minus_e) * inv_sq);
    let (is_stiff, is_small) = (z > STIFF_Z, z.abs() < 0.01);
    let pick = |s: f64, sm: f64, md: f64| {
        if is_stiff {
            s
        } else if is_small {
            sm
        } else {
            md
        }
    };
    (pick(stiff.0, small.0, mid.0), pick(stiff.1, small.1, mid.1))
}

/// Above this exponent the defect weights take their stiff forms (e^(−36) ≈ 2e-16).
pub const STIFF_Z: f64 = 36.0;

/// The exponent z = −ln(∂y1/∂y0) = ∫₀ʰ λ(s) ds, λ = 2γ·(c + 2b·y), of the frozen Bernoulli
/// step from y0 to y1 over `h_s` with coefficient `c_pa` (see the module docs), by the
/// trapezoidal rule in λ: z ≈ 2γ·(c + b·(y0 + y1))·h. The weights only need z's size, and
/// this costs no logarithm (the exact −2γch − 2·ln(y1/y0) cost 5 % of a run at N = 2000);
/// it is exact when y does not change, and its relative error stays below a tenth of y's
/// relative change over the step (tested).
#[must_use]
pub fn propagator_exponent(
    y0: f64,
    y1: f64,
    c_pa: f64,
    b_pa: f64,
    two_gamma: f64,
    h_s: f64,
) -> f64 {
    two_gamma * (c_pa + b_pa * (y0 + y1)) * h_s
}

/// Local errors of the stamp's position (m) and velocity (m/s) over one spring-drive step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DriveError {
    /// Position error estimate, m.
    pub x_m: f64,
    /// Velocity error estimate, m/s.
    pub v_m_per_s: f64,
}

/// Velocity Verlet's local errors from the accelerations at the step's ends (`accel_change`
/// = a1 − a0 over `h_s`) and the previous step's change over `h_prev_s` (0 = none).
#[must_use]
pub fn verlet_error(h_s: f64, accel_change: f64, h_prev_s: f64, prev_change: f64) -> DriveError {
    let a2 = if h_prev_s > 0.0 {
        2.0 * (accel_change / h_s - prev_change / h_prev_s) / (h_s + h_prev_s)
    } else {
        accel_change / h_s
    };
    DriveError {
        x_m: h_s * h_s * accel_change.abs() / 6.0,
        v_m_per_s: h_s * h_s * h_s * a2.abs() / 12.0,
    }
}

/// RK4's local errors when the friction force, held constant over the step, changed by
/// `force_change_n` (N) on a stamp of `mass_kg`.
#[must_use]
pub fn frozen_force_error(h_s: f64, force_change_n: f64, mass_kg: f64) -> DriveError {
    let da = force_change_n.abs() / mass_kg;
    DriveError {
        x_m: h_s * h_s * da / 6.0,
        v_m_per_s: 0.5 * h_s * da,
    }
}

/// RK4's error on a decay y' = −λ·y over one step, |R(−z) − e^(−z)|·|y0| with z = λ·h and
/// R(x) = 1 + x + x²/2 + x³/6 + x⁴/24 its stability polynomial (≈ z⁵/120·|y0| for small z,
/// growing as z⁴/24 beyond RK4's stability bound z ≈ 2.79, where the step must be rejected).
#[must_use]
pub fn rk4_decay_error(z: f64, y0: f64) -> f64 {
    let x = -z;
    let r = 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x / 24.0)));
    (r - x.exp()).abs() * y0.abs()
}

#[cfg(test)]
mod tests {

    #[test]
    fn the_select_weights_are_the_branch_weights_bit_for_bit() {
        // z over every form: stiff, the small series, the middle with and without expm1,
        // negative down to the clamp, and the switch points themselves.
        let mut zs: Vec<f64> = vec![0.0, 0.01, -0.01, 0.5, -0.5, STIFF_Z, -40.0, 1e-300];
        for k in 0..20_000 {
            let t = f64::from(k) / 20_000.0;
            zs.push(-40.0 + 100.0 * t);
            zs.push(10f64.powf(-12.0 + 13.0 * t));
            zs.push(-(10f64.powf(-12.0 + 13.5 * t)));
        }
        for z in zs {
            let em = crate::vexp::exp_expm1(-z);
            let (a, b) = (defect_weights_from(z, em), defect_weights_select(z, em));
            assert_eq!(a.0.to_bits(), b.0.to_bits(), "w0 at z = {z:e}");
            assert_eq!(a.1.to_bits(), b.1.to_bits(), "w1 at z = {z:e}");
        }
    }
    use super::*;

    fn quad(f: impl Fn(f64) -> f64) -> f64 {
        // Composite Simpson on [0, 1] with 20 000 cells (error ~(z/n)⁴: 1e-12 at z = 80).
        let n = 20_000;
        let h = 1.0 / n as f64;
        (0..=n)
            .map(|i| {
                let w = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * f(i as f64 * h)
            })
            .sum::<f64>()
            * h
            / 3.0
    }

    #[test]
    fn weights_are_the_integrals_they_stand_for_on_both_sides_of_the_series_switch() {
        for z in [
            -30.0, -3.0, -0.5, -0.011, -0.009, -1e-5, 0.0, 1e-5, 0.009, 0.011, 0.7, 5.0, 80.0,
        ] {
            let (w0, w1) = defect_weights(z);
            let r0 = quad(|v| (-z * v).exp() * v);
            let r1 = quad(|u| (-z * (1.0 - u)).exp() * u);
            assert!(
                (w0 - r0).abs() <= 1e-9 * r0.abs().max(1e-3),
                "z {z}: w0 {w0} vs {r0}"
            );
            assert!(
                (w1 - r1).abs() <= 1e-9 * r1.abs().max(1e-3),
                "z {z}: w1 {w1} vs {r1}"
            );
        }
    }

    #[test]
    fn propagator_exponent_approximates_minus_log_of_the_exact_sensitivity() {
        // y(t) = c·y0·E/(c + b·y0·(1 − E)), E = e^(−2γct); differentiate numerically in y0.
        let (b, two_gamma, h): (f64, f64, f64) = (2e6, 20.0, 3e-8);
        for c in [-1.5e6, -1e5, 2e5, 1e6] {
            let y = |y0: f64| {
                let e = (-two_gamma * c * h).exp();
                c * y0 * e / (c + b * y0 * (1.0 - e))
            };
            let y0 = 0.3;
            let d = (y(y0 * (1.0 + 1e-6)) - y(y0 * (1.0 - 1e-6))) / (2e-6 * y0);
            let y1 = y(y0);
            let z = propagator_exponent(y0, y1, c, b, two_gamma, h);
            let exact = -d.ln();
            // The trapezoidal rule's error: small while y changes little over the step.
            let change = (y1 / y0 - 1.0).abs();
            assert!(
                (z - exact).abs() <= 0.1 * exact.abs().max(1.0) * change.max(0.01),
                "c {c}: z {z} vs exact {exact} (y changed by {change})"
            );
        }
    }

    #[test]
    fn verlet_error_matches_the_taylor_remainder_of_a_cubic_acceleration() {
        // a(t) = t³: X''' = 3t², X'''' = 6t; over [1, 1 + h] from exact X, V.
        let h = 1e-3;
        let a = |t: f64| t * t * t;
        let x = |t: f64| t.powi(5) / 20.0;
        let v = |t: f64| t.powi(4) / 4.0;
        let (t0, t1) = (1.0, 1.0 + h);
        let v_half = v(t0) + 0.5 * h * a(t0);
        let x1 = x(t0) + h * v_half;
        let v1 = v_half + 0.5 * h * a(t1);
        let est = verlet_error(h, a(t1) - a(t0), h, a(t0) - a(t0 - h));
        let (ex, ev) = ((x1 - x(t1)).abs(), (v1 - v(t1)).abs());
        assert!((est.x_m / ex - 1.0).abs() < 0.01, "{} vs {ex}", est.x_m);
        assert!(
            (est.v_m_per_s / ev - 1.0).abs() < 0.01,
            "{} vs {ev}",
            est.v_m_per_s
        );
    }
}
