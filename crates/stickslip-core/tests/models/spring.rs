//! The stamp on its spring with exact solutions: m·Ẍ = K·(V0·t − X) + c_d·(V0 − Ẋ) − F with the
//! friction force F = k_c·X + F0·sin(Ωt), from rest. k_c = F0 = 0 is the free spring, c_d > 0
//! the damped one, F0 > 0 the forced one, k_c > 0 the loaded spring (the contact as a spring of
//! stiffness k_c, the stick phase of every slip), all of them the same linear equation, solved
//! here in closed form; and the drive's integrators as methods on it.

use super::Convergent;
use stickslip_core::drive::{DriveState, Integrator, SpringDrive};

/// A spring model: the drive, the contact's stiffness k_c (N/m) and the forcing F0 (N) at Ω
/// (rad/s), over 0 … `t_end_s`.
#[derive(Debug, Clone, Copy)]
pub struct SpringModel {
    pub name: &'static str,
    pub drive: SpringDrive,
    pub contact_n_per_m: f64,
    pub forcing_n: f64,
    pub forcing_rad_per_s: f64,
    pub t_end_s: f64,
}

/// The paper's spring (fig2): K = 500 N/m, m = 0.1 kg, V0 = 1 m/s, ω ≈ 70.7 rad/s.
#[must_use]
pub fn fig2_drive() -> SpringDrive {
    SpringDrive::new(500.0, 0.1, 1.0).unwrap()
}

/// A dashpot of damping ratio ζ on the paper's K and m: c_d = 2ζ·√(K·m).
#[must_use]
pub fn damped_drive(zeta: f64) -> SpringDrive {
    let d = fig2_drive();
    d.with_damping(2.0 * zeta * (d.stiffness_n_per_m * d.mass_kg).sqrt())
        .unwrap()
}

impl SpringModel {
    /// The free spring of fig2 over 0.1 s (ωT ≈ 7.07, a little more than one period).
    #[must_use]
    pub fn free() -> Self {
        Self {
            name: "free spring",
            drive: fig2_drive(),
            contact_n_per_m: 0.0,
            forcing_n: 0.0,
            forcing_rad_per_s: 30.0,
            t_end_s: 0.1,
        }
    }

    /// The damped spring of ratio ζ, free.
    #[must_use]
    pub fn damped(zeta: f64) -> Self {
        Self {
            name: "damped spring",
            drive: damped_drive(zeta),
            ..Self::free()
        }
    }

    /// The spring under F0·sin(Ωt), F0 = 3 N (about half the spring's force amplitude
    /// K·V0/ω ≈ 7 N), Ω = 30 rad/s, with a dashpot of ratio ζ (0: none).
    #[must_use]
    pub fn forced(zeta: f64) -> Self {
        Self {
            name: "forced spring",
            drive: damped_drive(zeta),
            forcing_n: 3.0,
            ..Self::free()
        }
    }

    /// The loaded spring: the contact as a spring of k_c = 74·K (the SFA contact's ratio,
    /// ω' ≈ 612 rad/s) and the forcing of [`forced`](Self::forced), over 0.1 s (ω'T ≈ 61).
    #[must_use]
    pub fn loaded(zeta: f64) -> Self {
        Self {
            name: "loaded spring",
            contact_n_per_m: 74.0 * 500.0,
            ..Self::forced(zeta)
        }
    }

    /// The friction force F(t, X) = k_c·X + F0·sin(Ωt), N.
    #[must_use]
    pub fn force_n(&self, state: &DriveState) -> f64 {
        self.contact_n_per_m * state.x_m
            + self.forcing_n * (self.forcing_rad_per_s * state.t_s).sin()
    }

    /// ω' = √((K + k_c)/m), rad/s.
    #[must_use]
    pub fn omega_rad_per_s(&self) -> f64 {
        ((self.drive.stiffness_n_per_m + self.contact_n_per_m) / self.drive.mass_kg).sqrt()
    }

    /// The exact state at `t_s` from rest. With K' = K + k_c and c = c_d, X = X_p + Y_s + Y_h:
    /// the moving rest point X_p = α + β·t (β = K·V0/K', α = c·(V0 − β)/K'); the forced part
    /// Y_s = A·sin Ωt + B·cos Ωt, (K' − mΩ²)·A − cΩ·B = −F0, cΩ·A + (K' − mΩ²)·B = 0; and the
    /// free damped motion Y_h that starts from what remains of rest.
    #[must_use]
    pub fn exact(&self, t_s: f64) -> DriveState {
        let d = &self.drive;
        let (m, c, v0) = (d.mass_kg, d.damping_n_s_per_m, d.velocity_m_per_s);
        let k_total = d.stiffness_n_per_m + self.contact_n_per_m;
        let beta = d.stiffness_n_per_m * v0 / k_total;
        let alpha = c * (v0 - beta) / k_total;
        let w_f = self.forcing_rad_per_s;
        let stiff = k_total - m * w_f * w_f;
        let det = stiff * stiff + (c * w_f).powi(2);
        let a = -self.forcing_n * stiff / det;
        let b = self.forcing_n * c * w_f / det;
        let omega = self.omega_rad_per_s();
        let zeta = c / (2.0 * (k_total * m).sqrt());
        let (yh, yhv) = damped_free(omega, zeta, -alpha - b, -beta - a * w_f, t_s);
        let (s, co) = ((w_f * t_s).sin(), (w_f * t_s).cos());
        DriveState {
            t_s,
            x_m: alpha + beta * t_s + a * s + b * co + yh,
            v_m_per_s: beta + w_f * (a * co - b * s) + yhv,
        }
    }

    /// Phase-space distance of `state` from the exact state at its time, over the oscillation's
    /// scale (V0/ω' for X, V0 for V).
    #[must_use]
    pub fn error(&self, state: &DriveState) -> f64 {
        let exact = self.exact(state.t_s);
        let v0 = self.drive.velocity_m_per_s;
        let ex = (state.x_m - exact.x_m) * self.omega_rad_per_s() / v0;
        let ev = (state.v_m_per_s - exact.v_m_per_s) / v0;
        ex.hypot(ev)
    }
}

/// The damped oscillator ÿ + 2ζω·ẏ + ω²·y = 0 from (y0, ẏ0) at t, written directly (under-,
/// critically or over-damped). Returns (y, ẏ).
#[must_use]
pub fn damped_free(omega: f64, zeta: f64, y0: f64, yv0: f64, t: f64) -> (f64, f64) {
    let a = zeta * omega;
    if zeta < 1.0 {
        let wd = omega * (1.0 - zeta * zeta).sqrt();
        let (c, s) = ((wd * t).cos(), (wd * t).sin());
        let e = (-a * t).exp();
        let b = (yv0 + a * y0) / wd;
        (
            e * (y0 * c + b * s),
            e * (-a * (y0 * c + b * s) + (-y0 * wd * s + b * wd * c)),
        )
    } else if zeta == 1.0 {
        let e = (-omega * t).exp();
        let b = yv0 + omega * y0;
        (e * (y0 + b * t), e * (b - omega * (y0 + b * t)))
    } else {
        let root = omega * (zeta * zeta - 1.0).sqrt();
        let (r1, r2) = (-a + root, -a - root);
        // y0 = c1 + c2, ẏ0 = r1·c1 + r2·c2.
        let c1 = (yv0 - r2 * y0) / (r1 - r2);
        let c2 = y0 - c1;
        let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
        (c1 * e1 + c2 * e2, r1 * c1 * e1 + r2 * c2 * e2)
    }
}

/// The drive's integrators as methods on a spring model, F evaluated where each needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpringMethod {
    /// Velocity Verlet: kick with F(t0, X0), drift, kick with F(t1, X1).
    Verlet,
    /// Classical RK4 with F held at the step's start (so order 4 only where F is 0).
    Rk4,
    /// The plain split: friction half kicks around the spring's exact flow.
    Split,
    /// The shipped default: the flow loaded with the stiffness k (N/m), the friction force
    /// linearised at the step's start, and the closing kick of F's departure from it
    /// ([`SpringDrive::loaded_split_step`]).
    LoadedSplit { stiffness_n_per_m: f64 },
}

impl SpringMethod {
    /// One step of `h_s` on `model` from `state`.
    pub fn step(self, model: &SpringModel, state: &mut DriveState, h_s: f64) {
        let d = &model.drive;
        let f0 = model.force_n(state);
        match self {
            Self::Verlet => {
                d.half_kick(state, f0, h_s);
                d.drift(state, h_s);
                let f1 = model.force_n(state);
                d.closing_half_kick(state, f1, h_s);
            }
            Self::Rk4 => d.step(Integrator::Rk4, state, h_s, f0),
            Self::Split => {
                d.friction_half_kick(state, f0, h_s);
                d.spring_flow(state, h_s);
                let f1 = model.force_n(state);
                d.friction_half_kick(state, f1, h_s);
            }
            Self::LoadedSplit { stiffness_n_per_m } => {
                d.loaded_split_step(state, h_s, stiffness_n_per_m, f0, |s| model.force_n(s));
            }
        }
    }

    /// The state at the model's end after `n` equal steps from rest.
    #[must_use]
    pub fn run(self, model: &SpringModel, n: u32) -> DriveState {
        let h = model.t_end_s / f64::from(n);
        let mut state = DriveState::at_rest();
        for _ in 0..n {
            self.step(model, &mut state, h);
        }
        assert!((state.t_s - model.t_end_s).abs() <= 1e-12 * model.t_end_s);
        state
    }
}

/// A method on a model, for [`super::assert_order`]: level k is 2^k steps.
pub struct Case(pub SpringMethod, pub SpringModel);

impl Convergent for Case {
    fn label(&self) -> String {
        format!(
            "{:?} on the {} (K = {} N/m, k_c = {} N/m, c_d = {:.4} N·s/m, F0 = {} N), T = {} s",
            self.0,
            self.1.name,
            self.1.drive.stiffness_n_per_m,
            self.1.contact_n_per_m,
            self.1.drive.damping_n_s_per_m,
            self.1.forcing_n,
            self.1.t_end_s
        )
    }

    fn levels(&self, order: f64) -> std::ops::RangeInclusive<u32> {
        // From ω'·h ≤ 1/4 (the fastest motion resolved), seven levels for second order, six
        // for fourth, whose errors reach rounding sooner.
        let steps = self.1.omega_rad_per_s() * self.1.t_end_s / 0.25;
        let first = steps.log2().ceil().max(0.0) as u32;
        first..=first + if order > 3.0 { 5 } else { 6 }
    }

    fn error(&self, level: u32) -> f64 {
        self.1.error(&self.0.run(&self.1, 1 << level))
    }
}
