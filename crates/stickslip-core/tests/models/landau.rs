//! The film at a frozen strain: φ̇ = −γ·(c(ε)·φ + b·φ³) (second order, ε fixed) from φ0,
//! whose exact solution is closed-form ([`exact_phi`]); the φ steppers as methods on it.

use super::Convergent;
use stickslip_core::landau::{LandauParams, PhiStepper, exact_phi};

/// The paper's lubricant (fig2): τmax = 1e6 Pa, εmax = 1, a = 1e6 Pa, γ = 10 /(Pa·s).
#[must_use]
pub fn fig2_film() -> LandauParams {
    LandauParams::new(1e6, 1.0, 1e6, 10.0).unwrap()
}

/// The film from `phi0` at the frozen strain `eps` over 0 … `t_end_s`.
#[derive(Debug, Clone, Copy)]
pub struct FrozenStrain {
    pub params: LandauParams,
    pub phi0: f64,
    pub eps: f64,
    pub t_end_s: f64,
}

impl FrozenStrain {
    /// The exact φ at the end.
    #[must_use]
    pub fn exact_end(&self) -> f64 {
        let a_coeff = self.params.a_coeff_default_pa();
        exact_phi(self.phi0, self.eps, a_coeff, &self.params, self.t_end_s)
    }

    /// φ at the end after `n` equal steps of `stepper`.
    #[must_use]
    pub fn run(&self, stepper: PhiStepper, n: u32) -> f64 {
        let a_coeff = self.params.a_coeff_default_pa();
        let dt = self.t_end_s / f64::from(n);
        let mut phi = self.phi0;
        for _ in 0..n {
            phi = stepper.step(phi, self.eps, a_coeff, &self.params, dt);
        }
        phi
    }
}

/// A stepper on the frozen-strain film over given levels (2^k steps), for
/// [`super::assert_order`]; the error is relative to the exact φ.
pub struct Case(
    pub PhiStepper,
    pub FrozenStrain,
    pub std::ops::RangeInclusive<u32>,
);

impl Convergent for Case {
    fn label(&self) -> String {
        let m = &self.1;
        format!(
            "{:?} on the film at frozen ε = {} from φ0 = {}, T = {:e} s (exact φ(T) = {})",
            self.0,
            m.eps,
            m.phi0,
            m.t_end_s,
            m.exact_end()
        )
    }

    fn levels(&self, _order: f64) -> std::ops::RangeInclusive<u32> {
        self.2.clone()
    }

    fn error(&self, level: u32) -> f64 {
        let reference = self.1.exact_end();
        (self.1.run(self.0, 1 << level) - reference).abs() / reference.abs()
    }
}
