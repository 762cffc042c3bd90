//! Claim C11's way back down: the first-order film's own kinetics (Eq. 8 with the cubic term,
//! docs/model.md#the-first-order-film) under an imposed strain that ramps up past ε₊ and back
//! down to 0, stepped with the core's exact frozen-strain step.
//!
//! Why in-process: a run cannot strain a liquid film. u0 is held at 0 while the film is melted
//! (docs/model.md#strain-eq-11-and-the-reset-on-melting), so after melting a node's strain drops
//! below εc and the film re-solidifies at once; the binary shows ε₊ (the `hysteresis` runs), but
//! a liquid strained beyond ε₋ and brought back never occurs in a run. Here the strain is the
//! control variable, as in the stationary picture the thresholds come from. The film's
//! parameters, temperature, threshold and floor are read from a run's resolved scene (run.json),
//! so the loop is the same film the binary ran; the loop itself is the film step only — no
//! contact, no drive, no `Simulation`.
//!
//! Each step of length [`RAMP_DT_S`] takes the exact step with the strain frozen at the step's
//! midpoint (the growth exponent of a small φ, ∫c dt, is then exact up to O(Δt³)), then the
//! floor; a crossing of the threshold inside a step is located on that step's exact path
//! (`first_order::time_to`), so the measured strains do not depend on Δt's resolution.

use stickslip_core::landau::{LandauParams, PhiStepper, first_order};
use stickslip_core::noise::NoiseKind;
use stickslip_run::{RunOutput, Scene};

/// Ramp rate of the imposed strain, 1/s. Reason: the liquid regrows from the floor only below
/// ε₋, at a rate that starts at 0 there, so a ramp re-solidifies late (a delayed exchange of
/// stability, Δε ∝ √ε̇: measured 5.2e-5 relative at 0.05 /s, ≈ 2.3e-5 at 0.01 /s); the fold's
/// delay at ε₊ grows only as ε̇^(2/3) and is smaller still. The width ε₊² − ε₋² amplifies
/// both about five times (2ε²/width), and C11 allows 1e-3.
pub const RAMP_RATE_PER_S: f64 = 0.01;
/// Step of the imposed-strain loop, s (Δε = 2e-5 per step; crossings are located inside).
pub const RAMP_DT_S: f64 = 2e-3;
/// Top of the ramp, in units of ε₊: far enough past the fold for the film to have melted.
pub const RAMP_TOP: f64 = 1.2;

/// The film of a run: its parameters, A (constant temperature), threshold and floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Film {
    /// Lubricant parameters (b₃ included).
    pub params: LandauParams,
    /// A, Pa (the run's A at t = 0).
    pub a_coeff_pa: f64,
    /// φ below which the film counts as melted.
    pub threshold: f64,
    /// The noise floor (0 without a floor).
    pub floor: f64,
}

impl Film {
    /// The film of `run`, from its resolved scene (run.json).
    ///
    /// # Errors
    /// When the scene does not resolve again.
    pub fn of(run: &RunOutput) -> Result<Self, String> {
        let scene = Scene::resolve_table(run.info.scene.to_table(), &[] as &[&str])
            .map_err(|e| format!("{}: {e}", run.info.name))?;
        let c = &scene.config;
        Ok(Self {
            params: c.lubricant,
            a_coeff_pa: c.temperature.a_coeff_pa(0.0),
            threshold: c.melt_threshold,
            floor: match c.noise {
                NoiseKind::Floor { floor } => floor,
                _ => 0.0,
            },
        })
    }

    /// b = 2a²εmax³/τmax, Pa (Eq. 6), from the scene values, not from the core.
    pub fn b_pa(&self) -> f64 {
        let p = &self.params;
        2.0 * p.a_pa * p.a_pa * p.eps_max.powi(3) / p.tau_max_pa
    }

    /// ε₊ = √((A·b/a + b₃²/(4b))/a): the closed form, from the scene values.
    pub fn eps_plus(&self) -> f64 {
        let (a, b, b3) = (self.params.a_pa, self.b_pa(), self.params.cubic_pa);
        ((self.a_coeff_pa * b / a + b3 * b3 / (4.0 * b)) / a).sqrt()
    }

    /// ε₋ = εc = √(A·b)/a: the closed form.
    pub fn eps_minus(&self) -> f64 {
        (self.a_coeff_pa * self.b_pa()).sqrt() / self.params.a_pa
    }

    /// ε₊² − ε₋² = b₃²/(4ab): the closed form.
    pub fn width(&self) -> f64 {
        let b3 = self.params.cubic_pa;
        b3 * b3 / (4.0 * self.params.a_pa * self.b_pa())
    }
}

/// One imposed-strain loop and what it measured.
#[derive(Debug, Clone, PartialEq)]
pub struct ImposedLoop {
    /// The film.
    pub film: Film,
    /// Ramp rate, 1/s.
    pub rate_per_s: f64,
    /// Strain at which φ first fell below the threshold on the way up (None: never).
    pub melt_eps: Option<f64>,
    /// Strain at which φ first rose back to the threshold on the way down (None: never).
    pub solid_eps: Option<f64>,
    /// φ at the start of the step in which the film melted (just before the fall).
    pub phi_before_fall: f64,
    /// φ once the strain is 1e-3·ε₋ below the re-solidification (just after the jump).
    pub phi_after_jump: f64,
    /// The path up, (ε, φ), every 20th step.
    pub up: Vec<(f64, f64)>,
    /// The path down, (ε, φ), every 20th step.
    pub down: Vec<(f64, f64)>,
}

/// The film's strain ramp 0 → [`RAMP_TOP`]·ε₊ → 0 at `rate_per_s`, steps of `dt_s`.
pub fn imposed_loop(film: &Film, rate_per_s: f64, dt_s: f64) -> ImposedLoop {
    let p = &film.params;
    let a_coeff = film.a_coeff_pa;
    let (thr, floor) = (film.threshold, film.floor);
    let (b, b3, gamma) = (p.b_pa(), p.cubic_pa, p.gamma_per_pa_s);
    let top = RAMP_TOP * film.eps_plus();
    let de = rate_per_s * dt_s;
    // Time from φ0 to the threshold on the step's frozen-strain path, as a fraction of the step.
    let crossing = |phi0: f64, eps_mid: f64| -> f64 {
        first_order::time_to(phi0, thr, p.bernoulli_c_pa(eps_mid, a_coeff), b, b3, gamma)
            .map_or(1.0, |t| (t / dt_s).clamp(0.0, 1.0))
    };
    let step = |phi: f64, eps_mid: f64| PhiStepper::Exact.step(phi, eps_mid, a_coeff, p, dt_s);
    let mut out = ImposedLoop {
        film: *film,
        rate_per_s,
        melt_eps: None,
        solid_eps: None,
        phi_before_fall: f64::NAN,
        phi_after_jump: f64::NAN,
        up: Vec::new(),
        down: Vec::new(),
    };
    let mut phi = p.solid_phi(0.0, a_coeff);
    let mut k = 0_u64;
    let mut i = 0_u64;
    while i as f64 * de < top {
        let (e0, e1) = (i as f64 * de, (i + 1) as f64 * de);
        let mid = 0.5 * (e0 + e1);
        let phi1 = step(phi, mid);
        if out.melt_eps.is_none() && phi >= thr && phi1 < thr {
            out.melt_eps = Some(e0 + crossing(phi, mid) * de);
            out.phi_before_fall = phi;
        }
        phi = phi1.max(floor);
        if k.is_multiple_of(20) {
            out.up.push((e1, phi));
        }
        k += 1;
        i += 1;
    }
    let start = i as f64 * de;
    let mut j = 0_u64;
    while start - j as f64 * de > 0.0 {
        let e0 = start - j as f64 * de;
        let e1 = (start - (j + 1) as f64 * de).max(0.0);
        let mid = 0.5 * (e0 + e1);
        let phi1 = step(phi, mid);
        if out.solid_eps.is_none() && phi < thr && phi1 >= thr {
            out.solid_eps = Some(e0 - crossing(phi, mid) * (e0 - e1));
        }
        phi = phi1.max(floor);
        if out.phi_after_jump.is_nan()
            && out
                .solid_eps
                .is_some_and(|s| s - e1 >= 1e-3 * film.eps_minus())
        {
            out.phi_after_jump = phi;
        }
        if k.is_multiple_of(20) {
            out.down.push((e1, phi));
        }
        k += 1;
        j += 1;
    }
    out
}
