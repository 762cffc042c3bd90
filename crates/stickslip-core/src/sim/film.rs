//! The film's kinetics as the accurate step uses them, for the paper's second-order film and
//! the first-order one (docs/model.md#the-first-order-film): the frozen-strain step, its
//! relaxation rate, the exponent of the error estimate's propagator, the crossing of a level
//! and whether a film regrows from one.
//!
//! The accurate step is generic over [`Film`]; the implementation is picked once, when the
//! simulation is built (b₃ = 0 or not, `stepper_for` in `sim/mod.rs`), so the second-order film runs
//! exactly the arithmetic it always ran.

use super::error_estimate;
use crate::landau::{
    LandauParams, bernoulli_exponent, bernoulli_finish_select, bernoulli_phi, first_order,
};

/// What the accurate step needs from the film's kinetics (y = φ²; c = a·ε² − A·b/a, Pa).
pub(super) trait Film {
    /// Whether the step is corrected along the strain ramp ([`Film::ramp_coefficients`]): the
    /// error estimate then takes the end strain's prediction error and the correction's
    /// second-order remainder instead of the frozen step's defect.
    const RAMP: bool = false;
    /// (a, b, 2γ) for the correction along the strain ramp ([`super::ramp::correct_all`]);
    /// only called when [`Film::RAMP`] is true.
    fn ramp_coefficients(&self) -> (f64, f64, f64) {
        (0.0, 0.0, 0.0)
    }
    /// The exact frozen-strain step of φ over `dt_s` at strain `eps` and coefficient A.
    fn step(&self, phi0: f64, eps: f64, a_coeff: f64, dt_s: f64) -> f64;
    /// [`Film::step`] at every node, `out[i] = step(phi0[i], eps[i], …)` bit for bit; `e` and
    /// `m` are scratch of the same length (a film whose step takes an exponential takes
    /// those of all nodes in one vectorised loop there).
    fn step_all(
        &self,
        phi0: &[f64],
        eps: &[f64],
        a_coeff: f64,
        dt_s: f64,
        out: &mut [f64],
        (e, m): (&mut [f64], &mut [f64]),
    ) {
        let _ = (e, m);
        for ((o, &p), &ep) in out.iter_mut().zip(phi0).zip(eps) {
            *o = self.step(p, ep, a_coeff, dt_s);
        }
    }
    /// The local relaxation rate λ = −∂(dy/dt)/∂y of y = φ² at (φ, c), 1/s: the weight θ(λΔt)
    /// of the effective strain.
    fn rate(&self, c: f64, phi: f64, y: f64) -> f64;
    /// The exponent z ≈ ∫λ ds of the error estimate's propagator over a path from (φ0, y0)
    /// to (φ1, y1) of length `h_s` ([`error_estimate::propagator_exponent`]).
    fn exponent(&self, y0: f64, y1: f64, phi0: f64, phi1: f64, c: f64, h_s: f64) -> f64;
    /// Fraction θ ∈ [0, 1] of the step at which the exact path from φ0 to φ1 meets `level`
    /// (rising or falling); 1 when the path cannot explain the crossing (noise, the floor).
    fn crossing(&self, phi0: f64, phi1: f64, level: f64, eps: f64, a_coeff: f64, dt_s: f64) -> f64;
    /// Whether a film at `phi` under coefficient `c` grows at once.
    fn regrows(&self, phi: f64, c: f64) -> bool;
}

/// The paper's film (b₃ = 0): the Bernoulli solution of Eq. 8.
#[derive(Debug, Clone, Copy)]
pub(super) struct SecondOrder {
    pub params: LandauParams,
    pub b: f64,
    pub two_gamma: f64,
}

impl SecondOrder {
    pub fn new(params: LandauParams) -> Self {
        Self {
            params,
            b: params.b_pa(),
            two_gamma: 2.0 * params.gamma_per_pa_s,
        }
    }
}

impl Film for SecondOrder {
    fn step(&self, phi0: f64, eps: f64, a_coeff: f64, dt_s: f64) -> f64 {
        bernoulli_phi(phi0, eps, a_coeff, &self.params, dt_s)
    }

    /// The arguments of all nodes first, their exponentials in one vectorised loop, then the
    /// closed form: the same arithmetic as [`bernoulli_phi`] node by node.
    fn step_all(
        &self,
        phi0: &[f64],
        eps: &[f64],
        a_coeff: f64,
        dt_s: f64,
        out: &mut [f64],
        (e, m): (&mut [f64], &mut [f64]),
    ) {
        let p = &self.params;
        for (o, &ep) in out.iter_mut().zip(eps) {
            *o = bernoulli_exponent(ep, a_coeff, p, dt_s);
        }
        crate::vexp::exp_expm1_all(out, e, m);
        faer::traits::pulp::Arch::new().dispatch(FinishKernel {
            phi0,
            eps,
            em: (e, m),
            hoisted: (p, self.b, self.two_gamma),
            a_coeff,
            dt_s,
            out,
        });
    }

    fn rate(&self, c: f64, _phi: f64, y: f64) -> f64 {
        self.two_gamma * (c + 2.0 * self.b * y)
    }

    fn exponent(&self, y0: f64, y1: f64, _phi0: f64, _phi1: f64, c: f64, h_s: f64) -> f64 {
        error_estimate::propagator_exponent(y0, y1, c, self.b, self.two_gamma, h_s)
    }

    fn crossing(&self, phi0: f64, phi1: f64, level: f64, eps: f64, a_coeff: f64, dt_s: f64) -> f64 {
        if phi0 <= 0.0 || (phi0 - level) * (phi1 - level) > 0.0 {
            return 1.0;
        }
        let y0 = phi0 * phi0;
        let ys = level * level;
        let b = self.b;
        let c = self.params.bernoulli_c_pa(eps, a_coeff);
        let two_gamma = self.two_gamma;
        // y(t) = c·y0·E/(c + b·y0·(1 − E)), E = e^(−2γct), solved for y(t) = ys; for c = 0,
        // y = y0/(1 + 2γ·b·y0·t).
        let t = if c == 0.0 {
            (y0 / ys - 1.0) / (two_gamma * b * y0)
        } else {
            let e = ys * (c + b * y0) / (y0 * (c + b * ys));
            -e.ln() / (two_gamma * c)
        };
        if t.is_finite() {
            (t / dt_s).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    fn regrows(&self, _phi: f64, c: f64) -> bool {
        c < 0.0
    }
}

/// [`SecondOrder::step_all`]'s closed form over all nodes, compiled once per instruction set
/// (pulp's run-time dispatch) and branch-free ([`bernoulli_finish_select`]), so that it
/// vectorises; the bits are those of [`crate::landau::bernoulli_finish`] node by node.
struct FinishKernel<'a> {
    phi0: &'a [f64],
    eps: &'a [f64],
    em: (&'a [f64], &'a [f64]),
    hoisted: (&'a LandauParams, f64, f64),
    a_coeff: f64,
    dt_s: f64,
    out: &'a mut [f64],
}

impl faer::traits::pulp::WithSimd for FinishKernel<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: faer::traits::pulp::Simd>(self, _simd: S) {
        let n = self.out.len();
        let (phi0, eps) = (&self.phi0[..n], &self.eps[..n]);
        let (e, m) = (&self.em.0[..n], &self.em.1[..n]);
        for i in 0..n {
            self.out[i] = bernoulli_finish_select(
                phi0[i],
                eps[i],
                self.a_coeff,
                self.hoisted,
                self.dt_s,
                (e[i], m[i]),
            );
        }
    }
}

/// The paper's film with the ramp-corrected step (`numerics.film_step = "ramp"`): the
/// frozen step of [`SecondOrder`], then [`super::ramp::correct_all`].
#[derive(Debug, Clone, Copy)]
pub(super) struct SecondOrderRamp(pub SecondOrder);

impl Film for SecondOrderRamp {
    const RAMP: bool = true;

    fn ramp_coefficients(&self) -> (f64, f64, f64) {
        let f = &self.0;
        (f.params.a_pa, f.b, f.two_gamma)
    }

    fn step(&self, phi0: f64, eps: f64, a_coeff: f64, dt_s: f64) -> f64 {
        self.0.step(phi0, eps, a_coeff, dt_s)
    }

    fn step_all(
        &self,
        phi0: &[f64],
        eps: &[f64],
        a_coeff: f64,
        dt_s: f64,
        out: &mut [f64],
        scratch: (&mut [f64], &mut [f64]),
    ) {
        self.0.step_all(phi0, eps, a_coeff, dt_s, out, scratch);
    }

    fn rate(&self, c: f64, phi: f64, y: f64) -> f64 {
        self.0.rate(c, phi, y)
    }

    fn exponent(&self, y0: f64, y1: f64, phi0: f64, phi1: f64, c: f64, h_s: f64) -> f64 {
        self.0.exponent(y0, y1, phi0, phi1, c, h_s)
    }

    fn crossing(&self, phi0: f64, phi1: f64, level: f64, eps: f64, a_coeff: f64, dt_s: f64) -> f64 {
        self.0.crossing(phi0, phi1, level, eps, a_coeff, dt_s)
    }

    fn regrows(&self, phi: f64, c: f64) -> bool {
        self.0.regrows(phi, c)
    }
}

/// The first-order film (b₃ > 0): [`first_order`]'s exact step.
#[derive(Debug, Clone, Copy)]
pub(super) struct FirstOrder {
    pub params: LandauParams,
    pub b: f64,
    pub b3: f64,
    pub two_gamma: f64,
}

impl FirstOrder {
    pub fn new(params: LandauParams) -> Self {
        Self {
            params,
            b: params.b_pa(),
            b3: params.cubic_pa,
            two_gamma: 2.0 * params.gamma_per_pa_s,
        }
    }
}

impl Film for FirstOrder {
    fn step(&self, phi0: f64, eps: f64, a_coeff: f64, dt_s: f64) -> f64 {
        let c = self.params.bernoulli_c_pa(eps, a_coeff);
        first_order::exact_phi(phi0, c, self.b, self.b3, self.params.gamma_per_pa_s, dt_s)
    }

    /// dy/dt = −2γ·y·(c + b·y − b₃·√y): λ = 2γ·(c + 2b·y − (3/2)·b₃·φ), which vanishes on the
    /// solid branch at the fold.
    fn rate(&self, c: f64, phi: f64, y: f64) -> f64 {
        self.two_gamma * (c + 2.0 * self.b * y - 1.5 * self.b3 * phi)
    }

    /// The trapezoidal rule in λ as for the second-order film, with the cubic term's
    /// −(3/2)·b₃·φ averaged over the two ends.
    fn exponent(&self, y0: f64, y1: f64, phi0: f64, phi1: f64, c: f64, h_s: f64) -> f64 {
        self.two_gamma * (c + self.b * (y0 + y1) - 0.75 * self.b3 * (phi0 + phi1)) * h_s
    }

    fn crossing(&self, phi0: f64, phi1: f64, level: f64, eps: f64, a_coeff: f64, dt_s: f64) -> f64 {
        if phi0 <= 0.0 || (phi0 - level) * (phi1 - level) > 0.0 {
            return 1.0;
        }
        let c = self.params.bernoulli_c_pa(eps, a_coeff);
        match first_order::time_to(phi0, level, c, self.b, self.b3, self.params.gamma_per_pa_s) {
            Some(t) => (t / dt_s).clamp(0.0, 1.0),
            None => 1.0,
        }
    }

    /// φ grows where b·φ² − b₃·φ + c < 0, between the barrier and the solid branch.
    fn regrows(&self, phi: f64, c: f64) -> bool {
        self.b * phi * phi - self.b3 * phi + c < 0.0
    }
}
