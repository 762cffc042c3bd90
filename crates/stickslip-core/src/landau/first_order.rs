//! The first-order film (docs/model.md#the-first-order-film): Eq. 8 with the cubic term of the
//! free energy f = α(T−Tc)φ² + (a/2)φ²ε² − (b₃/3)φ³ + (b/4)φ⁴, b₃ > 0,
//!
//! dφ/dt = −γ·φ·(b·φ² − b₃·φ + c),   c = a·ε² − A·b/a,
//!
//! solved exactly with the strain (so c) frozen over a step.
//!
//! ## Stationary states
//! φ = 0 (the liquid) and the roots of bφ² − b₃φ + c: with D = b₃² − 4bc > 0 the solid
//! branch φ₊ = (b₃ + √D)/(2b) (stable) and the barrier φ₋ = 2c/(b₃ + √D) (unstable; ≤ 0 when
//! c ≤ 0, and then the liquid is unstable); at D = 0 the two meet in a fold at b₃/(2b); with
//! D < 0 only the liquid is left and every film melts.
//!
//! ## The exact frozen-strain step
//! No Bernoulli form exists with the cubic term, but the equation is separable. With
//! k = γ·b and q(φ) = φ² − e₁φ + p (e₁ = b₃/b, p = c/b; q = (φ − φ₊)(φ − φ₋)), the time along
//! the path from φ₀ to φ is
//!
//! T(φ) = −(1/k)·I(φ₀, φ),   I = ∫ from φ₀ to φ of ds/(s·q(s)),
//!
//! and the step solves T(φ₁) = Δt. φ never crosses a stationary state, so φ₁ lies between φ₀
//! and the state it moves to (φ₊ from either side, or 0); T rises monotonically from 0 at φ₀
//! to +∞ at that state. The solve is Newton's method with a bracket, in a variable ζ in
//! which T is nearly linear: the logarithm of the ratio of the distances to the two ends of
//! the interval φ lies in (for a logistic flow between two stationary states T is exactly
//! linear in it), or of the distance to the state approached when the other end is ∞. The
//! first Newton step needs no evaluation of T (T = 0 at φ₀), each further one one
//! exponential and two or three logarithms. The result is exact for frozen strain up to
//! rounding, stable for any Δt (φ₁ stays between φ₀ and the state approached, which a huge
//! Δt reaches to the last bit), and the stationary states 0, φ₊, φ₋ map to themselves
//! exactly. Distances to the stationary states are carried separately, never recovered by
//! subtracting nearly equal numbers, so a φ that has relaxed onto φ₊ keeps its relative
//! distance to it to full precision.
//!
//! I is the second divided difference g[0, φ₋, φ₊] of g(ρ) = ln|φ − ρ| − ln|φ₀ − ρ| (partial
//! fractions). It is evaluated in the form that does not cancel in each regime:
//! - **far** (every root below a quarter of min(φ₀, φ)): the series I = Σ_{m≥2} h_{m−2}·(φ₀^−m
//!   − φ^−m)/m with the complete symmetric polynomials h_j of the roots (h_j = e₁·h_{j−1} −
//!   p·h_{j−2}, real also for complex roots); this covers b₃ → 0 at c → 0, where all three
//!   stationary states meet;
//! - **separated real roots** (D ≥ b₃²/2, i.e. c ≤ b₃²/(8b); the stick phase and c ≈ 0):
//!   (g[0, φ₊] − g[0, φ₋])/(φ₊ − φ₋), with g[0, φ₋] through log1p(x)/x when φ₋ is small
//!   (c → 0, where the liquid changes stability);
//! - **near or beyond the fold** (c > b₃²/(8b): two close real roots, the fold, or a complex
//!   pair): I = (1/p)·[ln(φ/φ₀) − ½·ln(q(φ)/q(φ₀)) + (e₁/2)·(W(φ) − W(φ₀))] with W = ∫ds/q
//!   written as artanh or atan of a difference, which stays finite and smooth as the two
//!   roots merge and part again; this is where the film melts.

/// The stationary states other than the liquid φ = 0 of dφ/dt = −γφ(bφ² − b₃φ + c): the roots
/// of bφ² − b₃φ + c.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Branches {
    /// Two real roots: the barrier φ₋ (unstable; ≤ 0 when c ≤ 0) below the solid branch φ₊
    /// (stable).
    Real {
        /// φ₋ = 2c/(b₃ + √D), D = b₃² − 4bc.
        minus: f64,
        /// φ₊ = (b₃ + √D)/(2b).
        plus: f64,
    },
    /// D = 0: barrier and solid branch meet in the fold at b₃/(2b).
    Fold {
        /// b₃/(2b).
        at: f64,
    },
    /// D < 0: no solid state; every film melts.
    Liquid,
}

/// The roots of b·φ² − b₃·φ + c for `c_pa`, `b_pa` > 0 and `b3_pa` ≥ 0 (see [`Branches`]).
///
/// The one place they are computed, so the solid branch reported anywhere and the state the
/// exact step relaxes onto are the same number.
#[must_use]
pub fn branches(c_pa: f64, b_pa: f64, b3_pa: f64) -> Branches {
    let d = b3_pa * b3_pa - 4.0 * b_pa * c_pa;
    if d > 0.0 {
        let sum = b3_pa + d.sqrt();
        Branches::Real {
            minus: 2.0 * c_pa / sum,
            plus: sum / (2.0 * b_pa),
        }
    } else if d == 0.0 {
        Branches::Fold {
            at: b3_pa / (2.0 * b_pa),
        }
    } else {
        Branches::Liquid
    }
}

/// Deterministic right-hand side −γ·φ·(b·φ² − b₃·φ + c), in 1/s.
#[must_use]
pub fn rhs(phi: f64, c_pa: f64, b_pa: f64, b3_pa: f64, gamma_per_pa_s: f64) -> f64 {
    -gamma_per_pa_s * phi * (b_pa * phi * phi - b3_pa * phi + c_pa)
}

/// Largest ζ the solve goes to: the distance to the state approached is then about
/// e^−700 of the interval, below every representable difference.
const Z_MAX: f64 = 700.0;
/// Halley's iteration has converged once its update in ζ is below this (relative to 1 + ζ):
/// the next update would be of its cube times a curvature of order one.
const HALLEY_STOP: f64 = 1e-5;
/// Iterations before the solve stops with the bracket it has (never reached in the tests).
const MAX_ITER: usize = 100;
/// The series is used when every root is below this fraction of min(φ₀, φ).
const FAR: f64 = 0.25;

/// Where φ₀ sits and where it goes, with the stationary states around it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Case {
    /// φ₀ > φ₊: decays onto φ₊; interval (φ₊, ∞).
    AboveSolid,
    /// max(φ₋, 0) < φ₀ < φ₊: grows onto φ₊; interval (max(φ₋, 0), φ₊).
    BelowSolid,
    /// 0 < φ₀ < φ₋: decays to the liquid; interval (0, φ₋).
    BelowBarrier,
    /// φ₀ above the fold: decays onto it (algebraically); interval (s, ∞).
    AboveFold,
    /// φ₀ below the fold: decays to the liquid; interval (0, s).
    BelowFold,
    /// No solid state: decays to the liquid; interval (0, ∞).
    Melting,
}

/// A point of the path with its distances to the stationary states, each accurate on its own.
#[derive(Debug, Clone, Copy)]
struct Point {
    phi: f64,
    /// φ − φ₀.
    dphi: f64,
    /// φ − φ₊ (real roots) or φ − s (fold, complex roots; s = b₃/(2b)).
    dp: f64,
    /// φ − φ₋ (real roots); unused otherwise.
    dm: f64,
    /// dφ/dζ and d²φ/dζ², each divided by the distance u to the state approached (both are
    /// proportional to it; dividing first keeps them finite where u is near underflow).
    dphi_dz_u: f64,
    d2phi_dz2_u: f64,
}

/// The frozen-strain path from φ₀ > 0 (module docs).
#[derive(Debug, Clone, Copy)]
struct Path {
    phi0: f64,
    /// γ·b, 1/s.
    k: f64,
    /// e₁ = b₃/b (the roots' sum).
    e1: f64,
    /// p = c/b (the roots' product).
    p: f64,
    /// φ₊, φ₋ (real roots); s = b₃/(2b) twice (fold); s and κ = √(−D)/(2b) (complex).
    rp: f64,
    rm: f64,
    branches: Branches,
    case: Case,
    /// Separated real roots: the g[0, φ±] form (module docs).
    separated: bool,
    /// Modulus of the largest root.
    rho: f64,
    /// φ₀ − φ₊ and φ₀ − φ₋ (real), or φ₀ − s twice.
    dp0: f64,
    dm0: f64,
    /// The interval's ends (hi = ∞ when unbounded) and φ₀'s distances to them.
    lo: f64,
    hi: f64,
    d0_lo: f64,
    d0_hi: f64,
    /// Whether φ moves towards `hi`.
    up: bool,
    /// Reciprocals used at every evaluation (1/k, 1/(φ₀ − φ±), 1/φ±, 1/(φ₊ − φ₋), 1/(hi − lo)),
    /// d0_lo/d0_hi, and the φ₀ end of g[0, φ₋] when φ₋ is small (module docs).
    inv_k: f64,
    inv_dp0: f64,
    inv_dm0: f64,
    inv_rp: f64,
    inv_rm: f64,
    inv_sep: f64,
    inv_w: f64,
    ratio0: f64,
    g_minus0: f64,
}

impl Path {
    /// The path from `phi0` > 0 with c, b, b₃ > 0 and γ; `None` when φ₀ is stationary.
    fn new(phi0: f64, c: f64, b: f64, b3: f64, gamma: f64) -> Option<Self> {
        let branches = branches(c, b, b3);
        let s = b3 / (2.0 * b);
        let (rp, rm, case, lo, hi) = match branches {
            Branches::Real { minus, plus } => {
                if phi0 == plus || phi0 == minus {
                    return None;
                }
                if phi0 > plus {
                    (plus, minus, Case::AboveSolid, plus, f64::INFINITY)
                } else if phi0 > minus {
                    (plus, minus, Case::BelowSolid, minus.max(0.0), plus)
                } else {
                    (plus, minus, Case::BelowBarrier, 0.0, minus)
                }
            }
            Branches::Fold { at } => {
                if phi0 == at {
                    return None;
                }
                if phi0 > at {
                    (at, at, Case::AboveFold, at, f64::INFINITY)
                } else {
                    (at, at, Case::BelowFold, 0.0, at)
                }
            }
            Branches::Liquid => {
                let kappa = (4.0 * b * c - b3 * b3).sqrt() / (2.0 * b);
                (s, kappa, Case::Melting, 0.0, f64::INFINITY)
            }
        };
        let (dp0, dm0) = match branches {
            Branches::Real { .. } => (phi0 - rp, phi0 - rm),
            _ => (phi0 - s, phi0 - s),
        };
        let up = case == Case::BelowSolid;
        let rho = match branches {
            Branches::Real { .. } => rp.max(rm.abs()),
            Branches::Fold { at } => at,
            Branches::Liquid => (c / b).sqrt(),
        };
        let separated = matches!(branches, Branches::Real { .. })
            && (rp - rm) * (rp - rm) >= 0.5 * (rp + rm) * (rp + rm);
        let (d0_lo, d0_hi) = (phi0 - lo, hi - phi0);
        let g_minus0 = if separated && rm.abs() <= 0.5 * phi0 {
            log1p_over(-rm / phi0) / phi0
        } else {
            0.0
        };
        Some(Self {
            phi0,
            k: gamma * b,
            e1: b3 / b,
            p: c / b,
            rp,
            rm,
            branches,
            case,
            separated,
            rho,
            dp0,
            dm0,
            lo,
            hi,
            d0_lo,
            d0_hi,
            up,
            inv_k: 1.0 / (gamma * b),
            inv_dp0: 1.0 / dp0,
            inv_dm0: 1.0 / dm0,
            inv_rp: 1.0 / rp,
            inv_rm: 1.0 / rm,
            inv_sep: 1.0 / (rp - rm),
            inv_w: 1.0 / (hi - lo),
            ratio0: d0_lo / d0_hi,
            g_minus0,
        })
    }

    /// The point at ζ = ζ₀ + `dz` (dz ≥ 0 moves towards the state approached).
    fn point(&self, dz: f64) -> Point {
        let (d_lo, d_hi, dphi_dz_u, d2phi_dz2_u) = if self.hi.is_finite() {
            // σ = ln(d_lo/d_hi), ζ = ±σ: d_lo = w·E/(1 + E), d_hi = w/(1 + E), E = e^σ,
            // evaluated on the side where E or 1/E is at most 1.
            let w = self.hi - self.lo;
            let grow = dz.exp();
            let e = if self.up {
                self.ratio0 * grow
            } else {
                self.ratio0 / grow
            };
            let (d_lo, d_hi) = if e <= 1.0 {
                let scale = w / (1.0 + e);
                (e * scale, scale)
            } else {
                let f = 1.0 / e;
                let scale = w / (1.0 + f);
                (scale, f * scale)
            };
            let (slope, curve) = self.finite_slopes(d_lo, d_hi);
            (d_lo, d_hi, slope, curve)
        } else {
            // σ = ln(φ − lo), moving towards lo: ζ = −σ; φ' = −u, φ'' = u.
            let d_lo = self.d0_lo * (-dz).exp();
            (d_lo, f64::INFINITY, -1.0, 1.0)
        };
        let phi = if d_lo <= d_hi {
            self.lo + d_lo
        } else {
            self.hi - d_hi
        };
        let dphi = if self.up {
            self.d0_hi - d_hi
        } else {
            d_lo - self.d0_lo
        };
        let (dp, dm) = match self.case {
            Case::AboveSolid => (d_lo, d_lo + (self.rp - self.rm)),
            Case::BelowSolid => (
                -d_hi,
                if self.lo == self.rm {
                    d_lo
                } else {
                    phi - self.rm
                },
            ),
            Case::BelowBarrier => (-(d_hi + (self.rp - self.rm)), -d_hi),
            Case::AboveFold => (d_lo, d_lo),
            Case::BelowFold => (-d_hi, -d_hi),
            Case::Melting => (phi - self.rp, phi - self.rp),
        };
        Point {
            phi,
            dphi,
            dp,
            dm,
            dphi_dz_u,
            d2phi_dz2_u,
        }
    }

    /// The stationary state the path approaches (0 for the liquid).
    fn target(&self) -> f64 {
        if self.up { self.hi } else { self.lo }
    }

    /// dφ/dζ and d²φ/dζ² over u on a finite interval at distances `d_lo`, `d_hi` from its
    /// ends: dφ/dσ = d_lo·d_hi/w, d²φ/dσ² = dφ/dσ·(d_hi − d_lo)/w, ζ = ±σ, u = d_hi moving up,
    /// d_lo moving down.
    fn finite_slopes(&self, d_lo: f64, d_hi: f64) -> (f64, f64) {
        let other = if self.up { d_lo } else { d_hi } * self.inv_w;
        let curve = other * (d_hi - d_lo) * self.inv_w;
        (if self.up { other } else { -other }, curve)
    }

    /// dT/dζ and d²T/dζ² at the point: T' = F·φ', T'' = F_φ·φ'² + F·φ'', F = dT/dφ =
    /// −1/(k·φ·q), F_φ = (q + φ·q_φ)/(k·φ²·q²), evaluated with k·φ·q = m·u (u the distance to
    /// the state approached, which φ', φ'' and either φ or q are proportional to) so that no
    /// intermediate underflows where φ has relaxed onto that state.
    fn slopes(&self, pt: &Point) -> (f64, f64) {
        let q = self.q(pt);
        let dq = match self.branches {
            Branches::Real { .. } => pt.dp + pt.dm,
            _ => 2.0 * pt.dp,
        };
        let m = match self.case {
            Case::AboveSolid => self.k * pt.phi * pt.dm,
            Case::BelowSolid => -self.k * pt.phi * pt.dm,
            Case::AboveFold => self.k * pt.phi * pt.dp,
            Case::BelowBarrier | Case::BelowFold | Case::Melting => self.k * q,
        };
        let r = pt.dphi_dz_u;
        let inv_m = 1.0 / m;
        (
            -r * inv_m,
            ((q + pt.phi * dq) * self.k * r * r * inv_m - pt.d2phi_dz2_u) * inv_m,
        )
    }

    /// The point at a given φ between φ₀ and the state approached (distances by subtraction).
    fn point_at(&self, phi: f64) -> Point {
        let (dp, dm) = match self.branches {
            Branches::Real { .. } => (phi - self.rp, phi - self.rm),
            _ => (phi - self.rp, phi - self.rp),
        };
        Point {
            phi,
            dphi: phi - self.phi0,
            dp,
            dm,
            dphi_dz_u: 0.0,
            d2phi_dz2_u: 0.0,
        }
    }

    /// q(φ) = (φ − φ₊)(φ − φ₋), = b⁻¹·(bφ² − b₃φ + c).
    fn q(&self, pt: &Point) -> f64 {
        match self.branches {
            Branches::Real { .. } => pt.dp * pt.dm,
            Branches::Fold { .. } => pt.dp * pt.dp,
            Branches::Liquid => pt.dp * pt.dp + self.rm * self.rm,
        }
    }

    /// T(φ), s: the time the path takes from φ₀ to the point.
    fn time(&self, pt: &Point) -> f64 {
        -self.integral(pt) * self.inv_k
    }

    /// I = ∫ from φ₀ to φ of ds/(s·q(s)) (module docs).
    fn integral(&self, pt: &Point) -> f64 {
        if pt.dphi == 0.0 {
            return 0.0;
        }
        let (phi0, phi) = (self.phi0, pt.phi);
        if self.rho <= FAR * phi0.min(phi) {
            return self.series(pt);
        }
        if self.separated {
            let rm = self.rm;
            let r = phi0 / phi;
            let g_plus = ((pt.dp * self.inv_dp0).abs() * r).ln() * self.inv_rp;
            let g_minus = if rm.abs() <= 0.5 * phi.min(phi0) {
                // (ln|1 − φ₋/φ| − ln|1 − φ₋/φ₀|)/φ₋ without dividing by a small φ₋.
                let inv_phi = r / phi0;
                self.g_minus0 - log1p_over(-rm * inv_phi) * inv_phi
            } else {
                ((pt.dm * self.inv_dm0).abs() * r).ln() * self.inv_rm
            };
            return (g_plus - g_minus) * self.inv_sep;
        }
        // Near or beyond the fold: p > e₁²/8 > 0.
        let r = phi0 / phi;
        let (log_q, dw) = match self.branches {
            Branches::Real { .. } => {
                let log_q = ln_times_square((pt.dp / self.dp0).abs() * (pt.dm / self.dm0).abs(), r);
                let delta = 0.5 * (self.rp - self.rm);
                let (x, x0) = (pt.dp + delta, self.dp0 + delta);
                let dw = if delta <= 0.5 * x.abs().min(x0.abs()) && x * x0 > 0.0 {
                    // W = −artanh(δ/x)/δ outside the roots, as one artanh of a difference.
                    let y = pt.dphi / (x * x0 - delta * delta);
                    y * artanh_over(delta * y)
                } else {
                    // W = ln|(x − δ)/(x + δ)|/(2δ) near or between the roots.
                    ((pt.dp / self.dp0).abs() * (self.dm0 / pt.dm).abs()).ln() / (2.0 * delta)
                };
                (log_q, dw)
            }
            Branches::Fold { .. } => {
                let (x, x0) = (pt.dp, self.dp0);
                (ln_times_square((x / x0).powi(2), r), pt.dphi / (x * x0))
            }
            Branches::Liquid => {
                let kappa = self.rm;
                let (x, x0) = (pt.dp, self.dp0);
                let q = x * x + kappa * kappa;
                let q0 = x0 * x0 + kappa * kappa;
                let log_q = ln_times_square(q / q0, r);
                // W = atan(x/κ)/κ, a difference of two as one atan where they would cancel.
                let denom = kappa * kappa + x * x0;
                let dw = if denom > 0.0 {
                    let y = pt.dphi / denom;
                    y * atan_over(kappa * y)
                } else {
                    ((x / kappa).atan() - (x0 / kappa).atan()) / kappa
                };
                (log_q, dw)
            }
        };
        (-0.5 * log_q + 0.5 * self.e1 * dw) / self.p
    }

    /// I by its series in the roots (every root below [`FAR`]·min(φ₀, φ)).
    fn series(&self, pt: &Point) -> f64 {
        let u0 = 1.0 / self.phi0;
        let u = 1.0 / pt.phi;
        let d1 = pt.dphi / (pt.phi * self.phi0);
        let ratio = self.rho * u0.max(u);
        let scale = u0.max(u) * d1.abs();
        let (mut d_m, mut u_pow) = (d1, 1.0);
        let (mut h_prev, mut h) = (0.0, 1.0);
        let mut r_pow = 1.0;
        let mut sum = 0.0;
        for m in 2..80 {
            let mf = f64::from(m);
            u_pow *= u;
            d_m = u0 * d_m + u_pow * d1;
            sum += h * d_m / mf;
            let h_next = self.e1 * h - self.p * h_prev;
            h_prev = h;
            h = h_next;
            r_pow *= ratio;
            // |rest| ≤ Σ_{j>m} (j − 1)·ratio^(j−2)·scale ≤ m·ratio^(m−1)·scale/(1 − ratio).
            if mf * r_pow * scale <= 1e-17 * (1.0 - ratio) * sum.abs() {
                break;
            }
        }
        sum
    }

    /// φ after `dt` > 0 along the path.
    fn solve(&self, dt: f64) -> f64 {
        // At ζ₀, T = 0 and its derivatives cost no logarithm: the first step is free.
        let (slope0, curve0) = {
            let (dphi_dz_u, d2phi_dz2_u) = if self.hi.is_finite() {
                self.finite_slopes(self.d0_lo, self.d0_hi)
            } else {
                (-1.0, 1.0)
            };
            self.slopes(&Point {
                phi: self.phi0,
                dphi: 0.0,
                dp: self.dp0,
                dm: self.dm0,
                dphi_dz_u,
                d2phi_dz2_u,
            })
        };
        let mut dz = halley(-dt, slope0, curve0).min(Z_MAX);
        if dz.is_nan() || dz <= 0.0 {
            dz = Z_MAX;
        }
        let (mut lo, mut hi) = (0.0_f64, Z_MAX);
        let mut hi_known = false;
        for _ in 0..MAX_ITER {
            let pt = self.point(dz);
            let t = self.time(&pt);
            if t == dt {
                return pt.phi;
            }
            if t.is_nan() || t > dt {
                hi = dz;
                hi_known = true;
            } else {
                lo = dz;
                if dz >= Z_MAX || pt.phi == self.target() {
                    // The state approached is reached to the last bit.
                    return pt.phi;
                }
            }
            let (slope, curve) = self.slopes(&pt);
            // Halley near the solution; Newton on ln T far from it: T grows like e^ζ where φ
            // approaches a fold algebraically, and there ln T is nearly linear in ζ.
            let step = if (t - dt).abs() <= 0.5 * dt {
                halley(t - dt, slope, curve)
            } else {
                -(t / dt).ln() * t / slope
            };
            if step.abs() <= HALLEY_STOP * (1.0 + dz) {
                return self.point((dz + step).clamp(lo, hi)).phi;
            }
            let next = dz + step;
            let next = if next > lo && next < hi {
                next
            } else if hi_known {
                0.5 * (lo + hi)
            } else {
                Z_MAX
            };
            if hi_known && hi - lo <= 4.0 * f64::EPSILON * (1.0 + hi) {
                return self.point(next).phi;
            }
            dz = next;
        }
        self.point(dz).phi
    }
}

/// Halley's step for f with derivatives f', f'' (Newton's where the correction would exceed
/// a factor 2 either way).
fn halley(f: f64, f1: f64, f2: f64) -> f64 {
    let newton = -f / f1;
    let denom = 1.0 + 0.5 * newton * f2 / f1;
    if (0.5..=2.0).contains(&denom) {
        newton / denom
    } else {
        newton
    }
}

/// ln(a·r²) without overflowing r² (φ0/φ reaches e^700 on a melting path).
fn ln_times_square(a: f64, r: f64) -> f64 {
    if (1e-100..1e100).contains(&r) {
        (a * r * r).ln()
    } else {
        a.ln() + 2.0 * r.ln()
    }
}

/// log1p(z)/z, 1 at z = 0 (|z| ≤ ½ where used).
fn log1p_over(z: f64) -> f64 {
    if z == 0.0 { 1.0 } else { z.ln_1p() / z }
}

/// artanh(z)/z, 1 at z = 0.
fn artanh_over(z: f64) -> f64 {
    if z.abs() < 1e-8 {
        1.0 + z * z / 3.0
    } else {
        z.atanh() / z
    }
}

/// atan(z)/z, 1 at z = 0.
fn atan_over(z: f64) -> f64 {
    if z.abs() < 1e-8 {
        1.0 - z * z / 3.0
    } else {
        z.atan() / z
    }
}

/// Exact solution φ(t) of dφ/dt = −γ·φ·(b·φ² − b₃·φ + c) from φ(0) = φ0 with c frozen
/// (module docs), for b, b₃ > 0 and t ≥ 0. Uses |φ0|; returns a value ≥ 0 (0 for φ0 = 0).
/// A stationary φ0 (0, φ₊, φ₋) is returned unchanged.
///
/// # Example
/// ```
/// use stickslip_core::landau::first_order::{Branches, branches, exact_phi};
/// // fig2's lubricant (b = 2e6 Pa, γ = 10) with b₃ = 4e6 Pa at ε = 0 (c = −A·b/a = −3e6 Pa).
/// let (b, b3, c) = (2e6, 4e6, -3e6);
/// let Branches::Real { plus, .. } = branches(c, b, b3) else { unreachable!() };
/// assert_eq!(exact_phi(1e-3, c, b, b3, 10.0, 1.0), plus); // a huge step lands on φ₊
/// assert_eq!(exact_phi(plus, c, b, b3, 10.0, 1e-7), plus); // stationary
/// ```
#[must_use]
pub fn exact_phi(phi0: f64, c_pa: f64, b_pa: f64, b3_pa: f64, gamma: f64, t_s: f64) -> f64 {
    let phi0 = phi0.abs();
    if t_s == 0.0 || phi0 == 0.0 {
        return phi0;
    }
    match Path::new(phi0, c_pa, b_pa, b3_pa, gamma) {
        Some(path) => path.solve(t_s),
        None => phi0,
    }
}

/// Time the exact frozen-c path from `phi0` > 0 takes to reach `phi`, s; `None` when it never
/// does (φ not between φ0 and the state the path approaches, or φ0 stationary). 0 for φ = φ0.
#[must_use]
pub fn time_to(phi0: f64, phi: f64, c_pa: f64, b_pa: f64, b3_pa: f64, gamma: f64) -> Option<f64> {
    if phi == phi0 {
        return Some(0.0);
    }
    let path = Path::new(phi0, c_pa, b_pa, b3_pa, gamma)?;
    let inside = if path.up {
        phi > phi0 && phi < path.hi
    } else {
        phi < phi0 && phi > path.lo
    };
    if !inside {
        return None;
    }
    let t = path.time(&path.point_at(phi));
    (t.is_finite() && t >= 0.0).then_some(t)
}

/// Backward Euler on φ: the root φ1 of φ1 − φ0 + Δt·γ·φ1·(b·φ1² − b₃·φ1 + c) = 0 between φ0
/// and the stationary state the exact path approaches (one exists there: the residual changes
/// sign across that interval). First order, stays within that interval for any Δt.
#[must_use]
pub fn implicit_euler_phi(
    phi0: f64,
    c_pa: f64,
    b_pa: f64,
    b3_pa: f64,
    gamma: f64,
    dt_s: f64,
) -> f64 {
    let phi0 = phi0.abs();
    if dt_s == 0.0 || phi0 == 0.0 {
        return phi0;
    }
    let Some(path) = Path::new(phi0, c_pa, b_pa, b3_pa, gamma) else {
        return phi0;
    };
    let target = if path.up { path.hi } else { path.lo };
    let g = |x: f64| x - phi0 + dt_s * gamma * x * (b_pa * x * x - b3_pa * x + c_pa);
    let dg = |x: f64| 1.0 + dt_s * gamma * (3.0 * b_pa * x * x - 2.0 * b3_pa * x + c_pa);
    // g(φ0) has the sign of −rhs(φ0), g(target) = target − φ0 the other one.
    let (mut a, mut z) = (phi0, target.min(phi0 * 1e300));
    let sign_a = g(a).signum();
    let mut x = 0.5 * (a + z);
    for _ in 0..200 {
        let gx = g(x);
        if gx == 0.0 {
            return x;
        }
        if gx.signum() == sign_a {
            a = x;
        } else {
            z = x;
        }
        let newton = x - gx / dg(x);
        let next = if (newton - a) * (newton - z) < 0.0 {
            newton
        } else {
            0.5 * (a + z)
        };
        if (next - x).abs() <= 4.0 * f64::EPSILON * x.abs() {
            return next;
        }
        x = next;
    }
    x
}
