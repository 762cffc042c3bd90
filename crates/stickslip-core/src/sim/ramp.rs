//! The second-order film's step along a strain ramp, corrected to first order in the
//! coefficient's change over the step.
//!
//! With u = 1/φ² the film's equation (Eq. 8) is linear: u′ = L(s)·u + g, L = 2γ·c(ε(s)),
//! g = 2γ·b, c = a·ε² − A·b/a. The frozen step solves it with L held at L̄ = L(θh), the
//! strain ε_eff = ε0 + θ·(ε1 − ε0): ū(s) = A·e^(L̄s) + B, A = u0 + g/L̄, B = −g/L̄. Along the
//! ramp ε(σ) = ε0 + σ·Δ (σ = s/h) the coefficient differs by
//! δL(σ) = 2γ·[2a·ε_eff·Δ·(σ − θ) + a·Δ²·(σ − θ)²], exactly (c is quadratic in ε). The
//! first-order perturbation v(h) = ∫₀ʰ e^(L̄(h−s))·δL(s)·ū(s) ds has a closed form in the
//! moments m_k(z) = ∫₀¹ e^(−z(1−σ))·σ^k dσ, z = −L̄h:
//!
//! v = h·[u0·E·I0 + (b/c̄)·(E·I0 − I1)],  E = e^(−z), I0 = ∫₀¹ δL dσ, I1 = ∫₀¹ e^(−z(1−σ))·δL dσ,
//!
//! and (b/c̄)·(E·I0 − I1) = −2γbh·Q with Q = (E·I0 − I1)/z, taken by its series for |z| < 1
//! (where the closed form cancels). The corrected step u1 = ū(h) + v is exact to first order
//! in the coefficient's change over the step, whatever θ: the frozen step's own error there
//! — the film's response to the strain's change, largest on the approach to melting, where φ
//! is no longer slaved to ε — is removed, and what is left is second order in it.

/// Largest |z| for which Q's series is used ([`SERIES_TERMS`] terms: the first left out,
/// |z|¹²/13!, is below 1e-18 there); above, the closed forms lose to cancellation a relative
/// 2e-12 at the switch (measured), less beyond: far below what a correction needs.
const SERIES_Z: f64 = 0.2;

/// Terms of Q's series.
const SERIES_TERMS: usize = 12;

/// Q's series as three polynomials in z, for the parts q0, q1, q2 of p (see [`q_series`]):
/// `SERIES[m][j − 1]` = (−1)^j/j!·(1/(m + 1) − 1/(j + m + 1)), the coefficient of z^(j−1).
const SERIES: [[f64; SERIES_TERMS]; 3] = series_tables();

const fn series_tables() -> [[f64; SERIES_TERMS]; 3] {
    let mut t = [[0.0; SERIES_TERMS]; 3];
    let mut m = 0;
    while m < 3 {
        let mut sign_over_factorial = -1.0;
        let mut j = 1;
        while j <= SERIES_TERMS {
            let (mf, jf) = (m as f64, j as f64);
            t[m][j - 1] = sign_over_factorial * (1.0 / (mf + 1.0) - 1.0 / (jf + mf + 1.0));
            sign_over_factorial = -sign_over_factorial / (jf + 1.0);
            j += 1;
        }
        m += 1;
    }
    t
}

/// Below z = −Z_GROW (a melted node's decay, E = e^(−z) ≫ 1) the term in u0·E dominates and
/// v = h·ū(h)·I0 without forming E.
const Z_GROW: f64 = 40.0;

/// m0, m1, m2 of z (|z| ≥ [`SERIES_Z`]) given 1/z and E = e^(−z).
#[inline(always)]
fn moments_closed(z: f64, iz: f64, e: f64) -> (f64, f64, f64) {
    let m0 = (1.0 - e) * iz;
    let m1 = (z - 1.0 + e) * (iz * iz);
    let m2 = (z * z - 2.0 * z + 2.0 - 2.0 * e) * (iz * iz * iz);
    (m0, m1, m2)
}

/// The three polynomials of [`SERIES`] at z (Horner), for p's parts in τ⁰, τ¹, τ².
#[inline(always)]
fn series_sums(z: f64) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (o, row) in out.iter_mut().zip(&SERIES) {
        *o = row.iter().rev().fold(0.0, |acc, &c| acc * z + c);
    }
    out
}

/// Q_p = (E·∫₀¹p − ∫₀¹e^(−z(1−σ))·p dσ)/z for p(σ) = q0 + q1·τ + q2·τ², τ = 1 − σ, by its
/// series: e^(−z) − e^(−zτ) = Σ_{j≥1} (−z)^j·(1 − τ^j)/j!, so Q_p = Σ_m q_m·S_m(z) with
/// S_m(z) = Σ_j (−1)^j z^(j−1)/j!·∫₀¹ (1 − τ^j)·τ^m dτ.
#[inline(always)]
fn q_series(sums: &[f64; 3], q0: f64, q1: f64, q2: f64) -> f64 {
    q0 * sums[0] + q1 * sums[1] + q2 * sums[2]
}

/// The first-order correction v of u = 1/φ² over a step of `h_s` (see the module docs).
/// `u_frozen` = ū(h) = 1/φ1² of the frozen step, `u0` = 1/φ0², `theta` the frozen strain's
/// place on the ramp, `eps_eff` = ε0 + θ·Δ, `delta` = Δ = ε1 − ε0, `c_eff` = c(ε_eff),
/// `e_w` = e^(−2γ·|c_eff|·h) (the frozen step's exponential).
///
/// Without branches: v = 0 for Δ = 0; v = h·ū(h)·I0 below z = −[`Z_GROW`]; else Q by its
/// series for |z| < [`SERIES_Z`] or by the closed moments. Every case is computed and the one
/// that applies is selected, so a loop over nodes that calls this inline is vectorised
/// ([`correct_all`]); the cases not selected may be ∞ or NaN, which a select discards.
/// `SERIES`: Q's series is computed and selected where |z| < [`SERIES_Z`]; without it Q is
/// taken by the closed moments whatever z, the same bits wherever |z| ≥ [`SERIES_Z`], which
/// is all a caller may use it for ([`correct_all`] checks the step's nodes first).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
#[must_use]
pub fn correction<const SERIES: bool>(
    (u0, u_frozen): (f64, f64),
    (theta, eps_eff, delta): (f64, f64, f64),
    (a_pa, b_pa, two_gamma): (f64, f64, f64),
    c_eff: f64,
    e_w: f64,
    h_s: f64,
) -> f64 {
    let alpha = 2.0 * a_pa * eps_eff * delta;
    let beta = a_pa * delta * delta;
    // ∫₀¹ (σ − θ) dσ and ∫₀¹ (σ − θ)² dσ.
    let p1 = 0.5 - theta;
    let p2 = 1.0 / 3.0 - theta + theta * theta;
    let i0 = two_gamma * (alpha * p1 + beta * p2);
    let z = -two_gamma * c_eff * h_s;
    let grow = h_s * u_frozen * i0;
    let e = if c_eff <= 0.0 { e_w } else { 1.0 / e_w };
    // One division for the moments and Q's closed forms.
    let iz = 1.0 / z;
    let (m0, m1, m2) = moments_closed(z, iz, e);
    let mm1 = m1 - theta * m0;
    let mm2 = m2 - 2.0 * theta * m1 + theta * theta * m0;
    let (q1c, q2c) = ((e * p1 - mm1) * iz, (e * p2 - mm2) * iz);
    let (q1, q2) = if SERIES {
        let sums = series_sums(z);
        let d = 1.0 - theta;
        let (q1s, q2s) = (
            q_series(&sums, d, -1.0, 0.0),
            q_series(&sums, d * d, -2.0 * d, 1.0),
        );
        let series = z.abs() < SERIES_Z;
        (
            if series { q1s } else { q1c },
            if series { q2s } else { q2c },
        )
    } else {
        (q1c, q2c)
    };
    let q = two_gamma * (alpha * q1 + beta * q2);
    let general = h_s * (u0 * e * i0 - two_gamma * b_pa * h_s * q);
    let v = if z < -Z_GROW { grow } else { general };
    if delta == 0.0 { 0.0 } else { v }
}

/// Largest correction relative to the frozen step's u = 1/φ² that is applied (an accepted
/// step at the default tolerance corrects by far less: its remainder (v/u)²/2 is within the
/// tolerance).
pub(super) const CORRECTION_MAX: f64 = 0.5;

/// One step's correction pass over every node: the frozen step's φ1 in, the corrected φ1 out.
pub(super) struct RampPass<'a> {
    /// φ at the step's start.
    pub phi0: &'a [f64],
    /// u3D's predicted change over the step, m.
    pub du3d_m: &'a [f64],
    /// The frozen step's strain ε_eff = ε0 + θ·Δ.
    pub eps_eff: &'a [f64],
    /// The frozen step's exponential e^(−2γ·|c_eff|·h).
    pub e_w: &'a [f64],
    /// In: the frozen step's φ1; out: the corrected φ1 (the frozen one where the correction is
    /// not applied).
    pub phi1: &'a mut [f64],
    /// In: θ, the frozen strain's place on the ramp; out: the correction's relative
    /// second-order remainder (v/u)²/2 — 0 where φ0 or φ1 is 0, 1 where the correction is
    /// larger than [`CORRECTION_MAX`]·u (which rejects an adaptive step).
    pub theta: &'a mut [f64],
    /// The melting threshold: below it the node's u0 does not follow the stamp.
    pub threshold: f64,
    /// The stamp's advance over the step, m.
    pub dx_m: f64,
    /// h0, m.
    pub h0_m: f64,
    /// A·b/a at the step's middle, Pa (c = a·ε² − A·b/a).
    pub c_shift_pa: f64,
    /// (a, b, 2γ) of the film.
    pub coefficients: (f64, f64, f64),
    /// The step, s.
    pub h_s: f64,
}

/// The correction pass (see [`RampPass`]) under the best instruction set the CPU has (pulp's
/// run-time dispatch, as [`crate::vexp::exp_expm1_all`]): branch-free per node, so the loop is
/// vectorised; no fused multiply-add, so the bits are the scalar arithmetic's.
///
/// # Panics
/// If the slices differ in length.
pub(super) fn correct_all(pass: RampPass<'_>) {
    let n = pass.phi0.len();
    assert!(
        [
            pass.du3d_m.len(),
            pass.eps_eff.len(),
            pass.e_w.len(),
            pass.phi1.len(),
            pass.theta.len()
        ]
        .iter()
        .all(|&l| l == n),
        "slice lengths differ"
    );
    faer::traits::pulp::Arch::new().dispatch(pass);
}

impl faer::traits::pulp::WithSimd for RampPass<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: faer::traits::pulp::Simd>(self, _simd: S) {
        // Q's series (36 multiply-adds a node) only on a step where some node's |z| is
        // below SERIES_Z: a stick phase's steps have none, a cascade's shortest steps many.
        // The same bits either way (`correction`).
        let (a_pa, _, two_gamma) = self.coefficients;
        let any_series = self.eps_eff.iter().fold(false, |any, &eps_eff| {
            let c_eff = a_pa * eps_eff * eps_eff - self.c_shift_pa;
            any | ((-two_gamma * c_eff * self.h_s).abs() < SERIES_Z)
        });
        if any_series {
            self.pass::<true>();
        } else {
            self.pass::<false>();
        }
    }
}

impl RampPass<'_> {
    /// The pass's loop, with Q's series where `SERIES`.
    #[inline(always)]
    fn pass<const SERIES: bool>(self) {
        let (a_pa, _, _) = self.coefficients;
        let inv_h0 = 1.0 / self.h0_m;
        let nodes = self
            .phi0
            .iter()
            .zip(self.du3d_m)
            .zip(self.eps_eff)
            .zip(self.e_w)
            .zip(self.phi1.iter_mut())
            .zip(self.theta.iter_mut());
        for (((((&phi0, &du3d), &eps_eff), &e_w), phi1), theta) in nodes {
            let frozen = *phi1;
            let du0 = if phi0 >= self.threshold {
                self.dx_m
            } else {
                0.0
            };
            let delta = (du0 - du3d) * inv_h0;
            let c_eff = a_pa * eps_eff * eps_eff - self.c_shift_pa;
            let uf = 1.0 / (frozen * frozen);
            let v = correction::<SERIES>(
                (1.0 / (phi0 * phi0), uf),
                (*theta, eps_eff, delta),
                self.coefficients,
                c_eff,
                e_w,
                self.h_s,
            );
            let u1 = uf + v;
            let applied = v.abs() <= CORRECTION_MAX * uf && u1.is_finite();
            let inv_u1 = 1.0 / u1;
            let r = v * inv_u1;
            let valid = !(phi0 <= 0.0 || frozen <= 0.0);
            *phi1 = if valid && applied {
                inv_u1.sqrt()
            } else {
                frozen
            };
            *theta = if !valid {
                0.0
            } else if applied {
                0.5 * r * r
            } else {
                1.0
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// u′ = 2γ·c(ε(s))·u + 2γb along the ramp, by RK4 with `n` steps.
    fn reference_u(
        u0: f64,
        eps0: f64,
        delta: f64,
        k: f64,
        (a, b, tg): (f64, f64, f64),
        h: f64,
        n: usize,
    ) -> f64 {
        let f = |s: f64, u: f64| {
            let eps = eps0 + delta * s / h;
            tg * (a * eps * eps - k) * u + tg * b
        };
        let dt = h / n as f64;
        let mut u = u0;
        for i in 0..n {
            let s = i as f64 * dt;
            let k1 = f(s, u);
            let k2 = f(s + 0.5 * dt, u + 0.5 * dt * k1);
            let k3 = f(s + 0.5 * dt, u + 0.5 * dt * k2);
            let k4 = f(s + dt, u + dt * k3);
            u += dt * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
        }
        u
    }

    /// The frozen exact step of u at coefficient c over h.
    fn frozen_u(u0: f64, c: f64, b: f64, tg: f64, h: f64) -> f64 {
        let l = tg * c;
        if l == 0.0 {
            return u0 + tg * b * h;
        }
        (u0 + b / c) * (l * h).exp() - b / c
    }

    #[test]
    fn the_corrected_step_is_second_order_in_the_coefficients_change() {
        // fig2's film: a = 1e6 Pa, b = 2e6 Pa, 2γ = 20 /(Pa·s), A·b/a = 3e6 Pa (εc = √3).
        let (a, b, tg) = (1e6, 2e6, 20.0);
        let k = 1.5e6 * b / a;
        for (eps0, u0, h_base) in [
            (1.2, 1.0 / 0.3, 1e-7),
            (1.7, 1.0 / 0.02, 2e-7),
            (0.5, 1.0 / 1.1, 1e-6),
        ] {
            let mut errs = Vec::new();
            for halving in 0..3 {
                let h = h_base / f64::from(1 << halving);
                let delta = 2e5 * h; // strain rate 2e5 /s
                for theta in [0.5, 0.8] {
                    let eps_eff = eps0 + theta * delta;
                    let c = a * eps_eff * eps_eff - k;
                    let uf = frozen_u(u0, c, b, tg, h);
                    let e_w = (-tg * c.abs() * h).exp();
                    let v = correction::<true>(
                        (u0, uf),
                        (theta, eps_eff, delta),
                        (a, b, tg),
                        c,
                        e_w,
                        h,
                    );
                    let exact = reference_u(u0, eps0, delta, k, (a, b, tg), h, 4000);
                    let (before, after) = ((uf - exact).abs(), (uf + v - exact).abs());
                    assert!(
                        after < 0.2 * before || after < 1e-13 * exact.abs(),
                        "eps0 {eps0} h {h} θ {theta}: {before:e} → {after:e}"
                    );
                    if theta == 0.5 {
                        errs.push(after.max(1e-300));
                    }
                }
            }
            // Local error O(h³) at least (the frozen step's is O(h²) in this measure).
            let order = (errs[1] / errs[2]).log2();
            assert!(
                order > 2.5 || errs[2] < 1e-13 * u0,
                "eps0 {eps0}: order {order} ({errs:?})"
            );
        }
    }

    #[test]
    fn series_and_closed_forms_agree_at_the_switch() {
        for z in [-SERIES_Z, SERIES_Z] {
            let e = (-z).exp();
            let (m0, m1, m2) = moments_closed(z, 1.0 / z, e);
            let theta = 0.7;
            let p1 = 0.5 - theta;
            let closed = (e * p1 - (m1 - theta * m0)) / z;
            let sums = series_sums(z);
            let series = q_series(&sums, 1.0 - theta, -1.0, 0.0);
            assert!(
                (closed - series).abs() < 1e-11 * series.abs(),
                "z {z}: {closed} vs {series}"
            );
            let d = 1.0 - theta;
            let p2 = 1.0 / 3.0 - theta + theta * theta;
            let closed2 = (e * p2 - (m2 - 2.0 * theta * m1 + theta * theta * m0)) / z;
            let series2 = q_series(&sums, d * d, -2.0 * d, 1.0);
            assert!(
                (closed2 - series2).abs() < 1e-11 * series2.abs(),
                "z {z}: {closed2} vs {series2}"
            );
        }
    }
}
