//! Drive of the stamp: the spring of Eq. 10 (m·Ẍ = K(V0·t − X) + c_d·(V0 − Ẋ) − F, with an
//! optional dashpot c_d parallel to the spring; c_d = 0 is the paper's model) with the split,
//! velocity-Verlet and RK4 integrators, the rigid coupler X = V0·t, and the exact
//! friction-free spring motion.
//!
//! In the co-moving coordinate ξ = X − V0·t the spring equation is the (damped) harmonic
//! oscillator ξ̈ = −ω²ξ − 2ζω·ξ̇ − F/m with ω = √(K/m), ζ = c_d/(2√(K·m)). Both integrators are invariant under this change of
//! variable, so for F = 0 velocity Verlet conserves a modified co-moving energy (bounded
//! energy error) while RK4 slowly dissipates it (|R(iωΔt)| < 1).

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A drive parameter outside its allowed range.
///
/// The message names the field, the offending value and the allowed range, e.g.
/// `invalid mass_kg = 0: must be finite and > 0`.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("invalid {field} = {value}: must be {allowed}")]
pub struct DriveParamError {
    /// Name of the offending field (the Rust field name, e.g. `stiffness_n_per_m`).
    pub field: &'static str,
    /// The rejected value.
    pub value: f64,
    /// The allowed range, in words.
    pub allowed: &'static str,
}

fn require_positive(field: &'static str, value: f64) -> Result<(), DriveParamError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(DriveParamError {
            field,
            value,
            allowed: "finite and > 0",
        })
    }
}

fn require_non_negative(field: &'static str, value: f64) -> Result<(), DriveParamError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(DriveParamError {
            field,
            value,
            allowed: "finite and >= 0",
        })
    }
}

fn require_finite(field: &'static str, value: f64) -> Result<(), DriveParamError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(DriveParamError {
            field,
            value,
            allowed: "finite",
        })
    }
}

/// Kinematic state of the stamp.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct DriveState {
    /// Time t, s.
    pub t_s: f64,
    /// Stamp position X, m.
    pub x_m: f64,
    /// Stamp velocity V = Ẋ, m/s.
    pub v_m_per_s: f64,
}

impl DriveState {
    /// The initial state: t = 0, X = 0, V = 0 (stamp at rest).
    #[must_use]
    pub fn at_rest() -> Self {
        Self::default()
    }
}

/// Time integrator of the spring drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// Strang splitting: the spring's own motion (F = 0) solved exactly, the friction force
    /// applied as two half kicks, with F at the step's start and end. Symplectic, second
    /// order in the friction force only, exact for a free spring.
    ///
    /// Why the default: velocity Verlet's local error in X, h³·X'''/6, has one sign while the
    /// spring accelerates the stamp towards its first slip, so with long adaptive steps it
    /// adds up to a position offset that delays the first onset (≈ 15 ns at fig2's default
    /// tolerance); here X''' of the spring part is integrated exactly.
    #[default]
    Split,
    /// Velocity Verlet: symplectic, second order, one force evaluation per step.
    Verlet,
    /// Classical Runge–Kutta: fourth order, not symplectic (slowly dissipates energy).
    Rk4,
}

/// Where the loaded split's flow linearised the friction force: the stamp's position X0 (m)
/// and the force F0 (N) at the step's start, and the stiffness k (N/m) of the linearisation,
/// F ≈ F0 + k·(X − X0).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FlowAnchor {
    /// X0, m.
    pub x_m: f64,
    /// F0, N.
    pub force_n: f64,
    /// k, N/m.
    pub stiffness_n_per_m: f64,
}

impl FlowAnchor {
    /// F's departure from the linearisation at the stamp's position `x_m`:
    /// f − F0 − k·(X − X0), N.
    #[must_use]
    pub fn departure_n(&self, force_n: f64, x_m: f64) -> f64 {
        force_n - self.force_n - self.stiffness_n_per_m * (x_m - self.x_m)
    }
}

/// Stamp pulled through a spring of stiffness K whose free end moves at V0 (Eq. 10), with a
/// dashpot c_d parallel to the spring: m·Ẍ = K·(V0·t − X) + c_d·(V0 − Ẋ) − F.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpringDrive {
    /// Spring stiffness K, N/m; finite and > 0.
    pub stiffness_n_per_m: f64,
    /// Stamp mass m, kg; finite and > 0.
    pub mass_kg: f64,
    /// Velocity V0 of the spring's free end, m/s; finite.
    pub velocity_m_per_s: f64,
    /// Damping c_d of the dashpot parallel to the spring, N·s/m; finite and ≥ 0 (0: the
    /// paper's model, whose arithmetic is then unchanged). Not serialized when 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub damping_n_s_per_m: f64,
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// The factors of the damped oscillator's flow over a step h from (y, ẏ), with α = ζω:
/// y(h) = ec·y + es·(ẏ + α·y), ẏ(h) = ec·ẏ − es·(α·ẏ + ω²·y), where ec and es stand for
/// e^(−αh)·C(h) and e^(−αh)·S(h), C, S the even and odd solutions of ÿ = (α² − ω²)·y
/// (C(0) = 1, S'(0) = 1). Returned as (ec, ec − 1, es), each formed without overflow or
/// cancellation (ec − 1 through expm1 and −2·sin²(x/2)): under-damped C = cos(ω_d h),
/// S = sin(ω_d h)/ω_d; critical C = 1, S = h; over-damped through the two real rates
/// r₁ = −ω/(ζ + √(ζ² − 1)) (slow, taken without cancellation) and r₂ = −ω·(ζ + √(ζ² − 1)):
/// ec = ½(e^(r₁h) + e^(r₂h)), es = −e^(r₁h)·expm1(−2μh)/(2μ), μ = ω√(ζ² − 1).
/// sin(x)/x and expm1(x)/x keep full relative accuracy as ω_d or μ → 0 (ζ → 1), so no series
/// is needed there.
fn damped_flow_factors(omega: f64, zeta: f64, h: f64) -> (f64, f64, f64) {
    let alpha = zeta * omega;
    if zeta < 1.0 {
        let wd = omega * ((1.0 - zeta) * (1.0 + zeta)).sqrt();
        let (sin, half_sin) = ((wd * h).sin(), (0.5 * wd * h).sin());
        let (e, em1) = ((-alpha * h).exp(), (-alpha * h).exp_m1());
        (
            e * (wd * h).cos(),
            em1 * (wd * h).cos() - 2.0 * half_sin * half_sin,
            e * (sin / wd),
        )
    } else if zeta == 1.0 {
        let (e, em1) = ((-alpha * h).exp(), (-alpha * h).exp_m1());
        (e, em1, e * h)
    } else {
        let root = ((zeta - 1.0) * (zeta + 1.0)).sqrt();
        let mu = omega * root;
        let r1 = -omega / (zeta + root);
        let r2 = -omega * (zeta + root);
        let (e1, e2) = ((r1 * h).exp(), (r2 * h).exp());
        let (m1, m2) = ((r1 * h).exp_m1(), (r2 * h).exp_m1());
        (
            0.5 * (e1 + e2),
            0.5 * (m1 + m2),
            -e1 * ((-2.0 * mu * h).exp_m1() / (2.0 * mu)),
        )
    }
}

/// g(h) = e^(−αh)·(C(h) + α·S(h)) − 1 = −ω²·∫₀ʰ e^(−αs)·S(s) ds (α = ζω, C and S as in
/// `damped_flow_factors`): the damped oscillator's response to a unit step of its rest point,
/// ≈ −ω²h²/2 for short steps, → −1 for long ones. Without cancellation: a Taylor series of the
/// integral while max(α, ω)·h ≤ 1/2 (its coefficients from ÿ + 2αẏ + ω²y = 0); beyond, the
/// closed forms, over-damped as (r₁·expm1(r₂h) − r₂·expm1(r₁h))/(r₁ − r₂).
fn damped_step_response(omega: f64, zeta: f64, h: f64) -> f64 {
    let alpha = zeta * omega;
    if alpha.max(omega) * h <= 0.5 {
        // e^(−αs)·S(s) = Σ c_k s^k, c_0 = 0, c_1 = 1,
        // (k + 2)(k + 1)·c_{k+2} = −2α(k + 1)·c_{k+1} − ω²·c_k; in powers of h.
        let (a, w2) = (alpha * h, omega * omega * h * h);
        let (mut c_prev, mut c) = (0.0_f64, 1.0_f64);
        let mut sum = 0.5; // c_1·h²/2, in units of h²
        // With 2αh ≤ 1 and ωh ≤ 1/2 the terms fall about like 1/k!: 24 of them reach 1e-20.
        for k in 0..24_u32 {
            let k = f64::from(k);
            let next = -(2.0 * a * (k + 1.0) * c + w2 * c_prev) / ((k + 2.0) * (k + 1.0));
            sum += next / (k + 3.0);
            c_prev = c;
            c = next;
        }
        return -omega * omega * h * h * sum;
    }
    if zeta < 1.0 {
        let (_, ec_minus_one, es) = damped_flow_factors(omega, zeta, h);
        ec_minus_one + alpha * es
    } else if zeta == 1.0 {
        (-alpha * h).exp_m1() + alpha * h * (-alpha * h).exp()
    } else {
        let root = ((zeta - 1.0) * (zeta + 1.0)).sqrt();
        let r1 = -omega / (zeta + root);
        let r2 = -omega * (zeta + root);
        (r1 * (r2 * h).exp_m1() - r2 * (r1 * h).exp_m1()) / (r1 - r2)
    }
}

impl SpringDrive {
    /// Builds a validated spring drive.
    ///
    /// # Errors
    /// [`DriveParamError`] naming the first offending field (K and m must be finite and > 0,
    /// V0 finite).
    pub fn new(
        stiffness_n_per_m: f64,
        mass_kg: f64,
        velocity_m_per_s: f64,
    ) -> Result<Self, DriveParamError> {
        let drive = Self {
            stiffness_n_per_m,
            mass_kg,
            velocity_m_per_s,
            damping_n_s_per_m: 0.0,
        };
        drive.validate()?;
        Ok(drive)
    }

    /// The same drive with a dashpot c_d (N·s/m) parallel to the spring.
    ///
    /// # Errors
    /// [`DriveParamError`] if c_d is negative or not finite.
    pub fn with_damping(self, damping_n_s_per_m: f64) -> Result<Self, DriveParamError> {
        let drive = Self {
            damping_n_s_per_m,
            ..self
        };
        drive.validate()?;
        Ok(drive)
    }

    /// Checks the ranges listed in [`SpringDrive::new`] and c_d finite and ≥ 0.
    ///
    /// # Errors
    /// [`DriveParamError`] naming the first offending field.
    pub fn validate(&self) -> Result<(), DriveParamError> {
        require_positive("stiffness_n_per_m", self.stiffness_n_per_m)?;
        require_positive("mass_kg", self.mass_kg)?;
        require_finite("velocity_m_per_s", self.velocity_m_per_s)?;
        require_non_negative("damping_n_s_per_m", self.damping_n_s_per_m)
    }

    /// Angular frequency ω = √(K/m) of the free spring, rad/s.
    #[must_use]
    pub fn omega_rad_per_s(&self) -> f64 {
        (self.stiffness_n_per_m / self.mass_kg).sqrt()
    }

    /// Damping ratio ζ = c_d/(2√(K·m)) of the dashpot (0 without one; 1 critical).
    #[must_use]
    pub fn damping_ratio(&self) -> f64 {
        self.damping_n_s_per_m / (2.0 * (self.stiffness_n_per_m * self.mass_kg).sqrt())
    }

    /// The spring's force on the stamp, K·(V0·t − X), N: the force the drive measures.
    #[must_use]
    pub fn spring_force_n(&self, t_s: f64, x_m: f64) -> f64 {
        self.stiffness_n_per_m * (self.velocity_m_per_s * t_s - x_m)
    }

    /// Acceleration Ẍ = (K·(V0·t − X) + c_d·(V0 − V) − F)/m in m/s², F the friction force in
    /// N (without a dashpot, c_d = 0, the paper's (K·(V0·t − X) − F)/m exactly).
    #[must_use]
    pub fn acceleration_m_per_s2(
        &self,
        t_s: f64,
        x_m: f64,
        v_m_per_s: f64,
        friction_n: f64,
    ) -> f64 {
        let spring = self.spring_force_n(t_s, x_m);
        if self.damping_n_s_per_m == 0.0 {
            (spring - friction_n) / self.mass_kg
        } else {
            (spring + self.damping_n_s_per_m * (self.velocity_m_per_s - v_m_per_s) - friction_n)
                / self.mass_kg
        }
    }

    /// First half kick of velocity Verlet: V ← V + (Δt/2)·Ẍ(t, X, V, F), at the current t, X
    /// and V.
    pub fn half_kick(&self, state: &mut DriveState, friction_n: f64, dt_s: f64) {
        state.v_m_per_s += 0.5
            * dt_s
            * self.acceleration_m_per_s2(state.t_s, state.x_m, state.v_m_per_s, friction_n);
    }

    /// Second half kick of velocity Verlet: V ← V + (Δt/2)·Ẍ(t, X, V_new, F) with the
    /// dashpot's force taken at the new velocity (implicit, solved in closed form: the force
    /// is linear in V), which keeps the step second order and time-symmetric. Without a
    /// dashpot it is [`half_kick`](Self::half_kick).
    pub fn closing_half_kick(&self, state: &mut DriveState, friction_n: f64, dt_s: f64) {
        if self.damping_n_s_per_m == 0.0 {
            self.half_kick(state, friction_n, dt_s);
            return;
        }
        let h2m = 0.5 * dt_s / self.mass_kg;
        let others = self.spring_force_n(state.t_s, state.x_m)
            + self.damping_n_s_per_m * self.velocity_m_per_s
            - friction_n;
        state.v_m_per_s = (state.v_m_per_s + h2m * others) / (1.0 + h2m * self.damping_n_s_per_m);
    }

    /// Kick by the friction force alone: V ← V − (Δt/2)·F/m (the split integrator's half kick).
    pub fn friction_half_kick(&self, state: &mut DriveState, friction_n: f64, dt_s: f64) {
        state.v_m_per_s -= 0.5 * dt_s * friction_n / self.mass_kg;
    }

    /// Exact motion of the spring without friction over `dt_s`, and time advance: with
    /// Y = X − V0·t, Ÿ = −ω²·Y, so Y and Ẏ = V − V0 rotate by ωΔt. cos ωΔt − 1 is taken as
    /// −2·sin²(ωΔt/2), free of cancellation for short steps. With a dashpot,
    /// Ÿ = −ω²·Y − 2ζω·Ẏ, whose flow is exact too (under-, critically or over-damped; see
    /// `damped_flow_factors`).
    pub fn spring_flow(&self, state: &mut DriveState, dt_s: f64) {
        let omega = self.omega_rad_per_s();
        let v0 = self.velocity_m_per_s;
        if self.damping_n_s_per_m != 0.0 {
            let zeta = self.damping_ratio();
            let alpha = zeta * omega;
            let (ec, ec_minus_one, es) = damped_flow_factors(omega, zeta, dt_s);
            let y = state.x_m - v0 * state.t_s;
            let yv = state.v_m_per_s - v0;
            // A short step changes the state little: y + (ec − 1)·y keeps that change's digits;
            // a long one shrinks it: ec·y does not cancel where ec ≪ 1.
            let scale = |u: f64| {
                if ec_minus_one.abs() < 0.5 {
                    u + ec_minus_one * u
                } else {
                    ec * u
                }
            };
            let y1 = scale(y) + es * (yv + alpha * y);
            let yv1 = scale(yv) - es * (alpha * yv + omega * omega * y);
            state.t_s += dt_s;
            state.x_m = y1 + v0 * state.t_s;
            state.v_m_per_s = yv1 + v0;
            return;
        }
        let (sin, half_sin) = ((omega * dt_s).sin(), (0.5 * omega * dt_s).sin());
        let cos_minus_one = -2.0 * half_sin * half_sin;
        let y = state.x_m - v0 * state.t_s;
        let yv = state.v_m_per_s - v0;
        let y1 = y + cos_minus_one * y + sin * (yv / omega);
        let yv1 = yv + cos_minus_one * yv - sin * (omega * y);
        state.t_s += dt_s;
        state.x_m = y1 + v0 * state.t_s;
        state.v_m_per_s = yv1 + v0;
    }

    /// The same spring with a viscous drag c_v = `drag_n_s_per_m` on the stamp's absolute
    /// velocity written as a dashpot: −c_v·Ẋ = c_v·(V0 − Ẋ) − c_v·V0, so the drive's damping
    /// becomes c_d + c_v and the force c_v·V0 joins the friction (for Verlet and RK4, whose
    /// steps take the force as given; docs/model.md#viscosity).
    #[must_use]
    pub fn with_drag(&self, drag_n_s_per_m: f64) -> Self {
        Self {
            damping_n_s_per_m: self.damping_n_s_per_m + drag_n_s_per_m,
            ..*self
        }
    }

    /// Exact motion over `dt_s`, and time advance, of the stamp on the spring and dashpot with a
    /// viscous drag c_v = `drag_n_s_per_m` on its absolute velocity and no friction:
    /// m·Ẍ = K·(V0·t − X) + c_d·(V0 − Ẋ) − c_v·Ẋ (the film's viscous drag on a rigid
    /// substrate; docs/model.md#viscosity). In Y = X − V0·t this is
    /// m·Ÿ = −K·Y − (c_d + c_v)·Ẏ − c_v·V0, the damped oscillator of
    /// [`spring_flow`](Self::spring_flow) about the shifted rest point Y = −δ, δ = c_v·V0/K:
    /// Y(h) = [flow of Y] + δ·g(h), Ẏ(h) = [flow of Ẏ] − e·S·c_v·V0/m, with the factors of
    /// `damped_flow_factors` and g = e·(C + α·S) − 1 from `damped_step_response`, formed
    /// without cancellation (δ·g ≈ −c_v·V0·h²/(2m) for a short step). Exact for any step,
    /// however stiff c_v·Δt/m.
    pub fn spring_flow_with_drag(&self, state: &mut DriveState, dt_s: f64, drag_n_s_per_m: f64) {
        let total = self.with_drag(drag_n_s_per_m);
        let omega = total.omega_rad_per_s();
        let zeta = total.damping_ratio();
        let alpha = zeta * omega;
        let v0 = self.velocity_m_per_s;
        let (ec, ec_minus_one, es) = damped_flow_factors(omega, zeta, dt_s);
        let y = state.x_m - v0 * state.t_s;
        let yv = state.v_m_per_s - v0;
        let scale = |u: f64| {
            if ec_minus_one.abs() < 0.5 {
                u + ec_minus_one * u
            } else {
                ec * u
            }
        };
        let delta = drag_n_s_per_m * v0 / self.stiffness_n_per_m;
        let y1 = scale(y) + es * (yv + alpha * y) + delta * damped_step_response(omega, zeta, dt_s);
        let yv1 = scale(yv)
            - es * (alpha * yv + omega * omega * y)
            - es * (drag_n_s_per_m * v0 / self.mass_kg);
        state.t_s += dt_s;
        state.x_m = y1 + v0 * state.t_s;
        state.v_m_per_s = yv1 + v0;
    }

    /// Exact motion over `dt_s`, and time advance, of the stamp on the spring and dashpot with
    /// an extra linear stiffness k = `extra_n_per_m`, a constant force P = `force_n` and a drag
    /// c_v = `drag_n_s_per_m` on its absolute velocity, without friction:
    /// m·Ẍ = K·(V0·t − X) + c_d·(V0 − Ẋ) − c_v·Ẋ − k·X + P.
    ///
    /// The split integrator lets this flow carry the friction force linearised at the step's
    /// start, F ≈ F0 + k·(X − X0), i.e. P = k·X0 − F0, so that its kicks carry only the
    /// departure F − F0 − k·(X − X0): in the stick phase the contact is the stiffest spring on
    /// the stamp, and the stamp's oscillation on it is then followed exactly rather than by
    /// kicks whose phase error grows with every period.
    ///
    /// With K' = K + k and c = c_d + c_v the motion is the damped oscillator
    /// m·Ÿ = −K'·Y − c·Ẏ about the moving rest point X_p = α + β·t, β = K·V0/K',
    /// α = (c_d·V0 + P − c·β)/K' (for k = c_v = P = 0: β = V0, α = 0, the plain spring's flow).
    pub fn loaded_flow(
        &self,
        state: &mut DriveState,
        dt_s: f64,
        extra_n_per_m: f64,
        drag_n_s_per_m: f64,
        force_n: f64,
    ) {
        let m = self.mass_kg;
        let k_total = self.stiffness_n_per_m + extra_n_per_m;
        let c = self.damping_n_s_per_m + drag_n_s_per_m;
        let omega = (k_total / m).sqrt();
        let zeta = c / (2.0 * (k_total * m).sqrt());
        let alpha_decay = zeta * omega;
        let beta = self.stiffness_n_per_m * self.velocity_m_per_s / k_total;
        let alpha = (self.damping_n_s_per_m * self.velocity_m_per_s + force_n - c * beta) / k_total;
        let (ec, ec_minus_one, es) = damped_flow_factors(omega, zeta, dt_s);
        let y = state.x_m - alpha - beta * state.t_s;
        let yv = state.v_m_per_s - beta;
        let scale = |u: f64| {
            if ec_minus_one.abs() < 0.5 {
                u + ec_minus_one * u
            } else {
                ec * u
            }
        };
        let y1 = scale(y) + es * (yv + alpha_decay * y);
        let yv1 = scale(yv) - es * (alpha_decay * yv + omega * omega * y);
        state.t_s += dt_s;
        state.x_m = y1 + alpha + beta * state.t_s;
        state.v_m_per_s = yv1 + beta;
    }

    /// The loaded split's first part, the default spring integrator's: the flow
    /// ([`loaded_flow`](Self::loaded_flow)) with the friction force linearised at the step's
    /// start, F ≈ F0 + k·(X − X0), F0 = `force_n`, k = `stiffness_n_per_m` (the contact as a
    /// spring), c_v = `drag_n_s_per_m`. Its opening kick, of F's departure from the
    /// linearisation, is 0. Returns the linearisation, for
    /// [`loaded_split_close`](Self::loaded_split_close).
    pub fn loaded_split_open(
        &self,
        state: &mut DriveState,
        dt_s: f64,
        stiffness_n_per_m: f64,
        drag_n_s_per_m: f64,
        force_n: f64,
    ) -> FlowAnchor {
        let anchor = FlowAnchor {
            x_m: state.x_m,
            force_n,
            stiffness_n_per_m,
        };
        self.loaded_flow(
            state,
            dt_s,
            stiffness_n_per_m,
            drag_n_s_per_m,
            stiffness_n_per_m * anchor.x_m - force_n,
        );
        anchor
    }

    /// The loaded split's closing half kick with F = `force_n` at the step's end: of F's
    /// departure from the linearisation `anchor` that the flow carried.
    pub fn loaded_split_close(
        &self,
        state: &mut DriveState,
        dt_s: f64,
        anchor: &FlowAnchor,
        force_n: f64,
    ) {
        self.friction_half_kick(state, anchor.departure_n(force_n, state.x_m), dt_s);
    }

    /// One whole loaded split step (second order; see
    /// [`loaded_split_open`](Self::loaded_split_open)): the friction force `force_n` at the
    /// start, `force_at_end` of the state after the flow (the simulation solves the film with
    /// the stamp's new position there).
    pub fn loaded_split_step(
        &self,
        state: &mut DriveState,
        dt_s: f64,
        stiffness_n_per_m: f64,
        force_n: f64,
        force_at_end: impl FnOnce(&DriveState) -> f64,
    ) {
        let anchor = self.loaded_split_open(state, dt_s, stiffness_n_per_m, 0.0, force_n);
        let end = force_at_end(state);
        self.loaded_split_close(state, dt_s, &anchor, end);
    }

    /// One split step: friction half kick with `friction_before_n`, the spring's exact flow,
    /// friction half kick with `friction_after_n` (see [`Integrator::Split`]).
    pub fn split_step(
        &self,
        state: &mut DriveState,
        dt_s: f64,
        friction_before_n: f64,
        friction_after_n: f64,
    ) {
        self.friction_half_kick(state, friction_before_n, dt_s);
        self.spring_flow(state, dt_s);
        self.friction_half_kick(state, friction_after_n, dt_s);
    }

    /// Drift of velocity Verlet and time advance: X ← X + Δt·V, t ← t + Δt.
    pub fn drift(&self, state: &mut DriveState, dt_s: f64) {
        state.x_m += dt_s * state.v_m_per_s;
        state.t_s += dt_s;
    }

    /// One velocity-Verlet step: [`half_kick`](Self::half_kick) with `friction_before_n`
    /// (F at the old t, X), [`drift`](Self::drift), then a half kick with `friction_after_n`
    /// (F at the new t, X):
    ///
    /// V½ = V + (Δt/2)·Ẍ(t, X, F0); X1 = X + Δt·V½; V1 = V½ + (Δt/2)·Ẍ(t + Δt, X1, F1).
    ///
    /// Second order and symplectic. A coupled simulation that needs F1 = F(X1) calls the three
    /// pieces itself and computes F1 between the drift and the second half kick.
    ///
    /// # Example
    /// ```
    /// use stickslip_core::drive::{DriveState, SpringDrive};
    /// let spring = SpringDrive::new(500.0, 0.1, 1.0).unwrap();
    /// let mut state = DriveState::at_rest();
    /// let friction = |x_m: f64| 1e-3 * x_m; // any force law F(X), in N
    /// let dt_s = 1e-8;
    /// let mut f = friction(state.x_m);
    /// for _ in 0..100 {
    ///     spring.half_kick(&mut state, f, dt_s);
    ///     spring.drift(&mut state, dt_s);
    ///     f = friction(state.x_m); // the new force, from the new position
    ///     spring.half_kick(&mut state, f, dt_s);
    /// }
    /// assert!((state.t_s - 1e-6).abs() < 1e-18);
    /// ```
    pub fn verlet_step(
        &self,
        state: &mut DriveState,
        dt_s: f64,
        friction_before_n: f64,
        friction_after_n: f64,
    ) {
        self.half_kick(state, friction_before_n, dt_s);
        self.drift(state, dt_s);
        self.closing_half_kick(state, friction_after_n, dt_s);
    }

    /// One classical RK4 step of (Ẋ, V̇) = (V, Ẍ(t, X, V, F)) with F held constant over the step:
    ///
    /// k1 = f(t, y), k2 = f(t + Δt/2, y + Δt/2·k1), k3 = f(t + Δt/2, y + Δt/2·k2),
    /// k4 = f(t + Δt, y + Δt·k3), y1 = y + Δt/6·(k1 + 2k2 + 2k3 + k4). Fourth order.
    pub fn rk4_step(&self, state: &mut DriveState, dt_s: f64, friction_n: f64) {
        let DriveState {
            t_s,
            x_m,
            v_m_per_s,
        } = *state;
        let h = dt_s;
        let acc = |t, x, v| self.acceleration_m_per_s2(t, x, v, friction_n);
        let (k1x, k1v) = (v_m_per_s, acc(t_s, x_m, v_m_per_s));
        let k2x = v_m_per_s + 0.5 * h * k1v;
        let k2v = acc(t_s + 0.5 * h, x_m + 0.5 * h * k1x, k2x);
        let k3x = v_m_per_s + 0.5 * h * k2v;
        let k3v = acc(t_s + 0.5 * h, x_m + 0.5 * h * k2x, k3x);
        let k4x = v_m_per_s + h * k3v;
        let k4v = acc(t_s + h, x_m + h * k3x, k4x);
        state.x_m = x_m + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        state.v_m_per_s = v_m_per_s + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        state.t_s = t_s + h;
    }

    /// One step with the friction force constant over the step: [`verlet_step`](Self::verlet_step)
    /// with F before = F after = `friction_n`, or [`rk4_step`](Self::rk4_step).
    pub fn step(&self, integrator: Integrator, state: &mut DriveState, dt_s: f64, friction_n: f64) {
        match integrator {
            Integrator::Split => self.split_step(state, dt_s, friction_n, friction_n),
            Integrator::Verlet => self.verlet_step(state, dt_s, friction_n, friction_n),
            Integrator::Rk4 => self.rk4_step(state, dt_s, friction_n),
        }
    }
}

/// Stamp rigidly coupled to the drive (the predecessor paper's case): X = V0·t, V = V0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RigidDrive {
    /// Stamp velocity V0, m/s; finite.
    pub velocity_m_per_s: f64,
}

impl RigidDrive {
    /// Builds a validated rigid drive.
    ///
    /// # Errors
    /// [`DriveParamError`] if V0 is not finite.
    pub fn new(velocity_m_per_s: f64) -> Result<Self, DriveParamError> {
        let drive = Self { velocity_m_per_s };
        drive.validate()?;
        Ok(drive)
    }

    /// Checks that V0 is finite.
    ///
    /// # Errors
    /// [`DriveParamError`] if it is not.
    pub fn validate(&self) -> Result<(), DriveParamError> {
        require_finite("velocity_m_per_s", self.velocity_m_per_s)
    }

    /// The exact state at time t: X = V0·t, V = V0.
    #[must_use]
    pub fn state_at(&self, t_s: f64) -> DriveState {
        DriveState {
            t_s,
            x_m: self.velocity_m_per_s * t_s,
            v_m_per_s: self.velocity_m_per_s,
        }
    }

    /// Advances t by Δt and sets X = V0·t, V = V0 (exact; the friction force is irrelevant).
    pub fn step(&self, state: &mut DriveState, dt_s: f64) {
        *state = self.state_at(state.t_s + dt_s);
    }
}

/// Either drive of the stamp.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Drive {
    /// Spring drive of Eq. 10.
    Spring(SpringDrive),
    /// Rigid coupler X = V0·t.
    Rigid(RigidDrive),
}

impl Drive {
    /// Velocity V0 of the driving end, m/s.
    #[must_use]
    pub fn velocity_m_per_s(&self) -> f64 {
        match self {
            Self::Spring(s) => s.velocity_m_per_s,
            Self::Rigid(r) => r.velocity_m_per_s,
        }
    }

    /// Checks the parameters of the wrapped drive.
    ///
    /// # Errors
    /// [`DriveParamError`] naming the first offending field.
    pub fn validate(&self) -> Result<(), DriveParamError> {
        match self {
            Self::Spring(s) => s.validate(),
            Self::Rigid(r) => r.validate(),
        }
    }

    /// One step with the friction force constant over the step: [`SpringDrive::step`] for a
    /// spring, the exact [`RigidDrive::step`] (ignoring `integrator` and `friction_n`) otherwise.
    pub fn step(&self, integrator: Integrator, state: &mut DriveState, dt_s: f64, friction_n: f64) {
        match self {
            Self::Spring(s) => s.step(integrator, state, dt_s, friction_n),
            Self::Rigid(r) => r.step(state, dt_s),
        }
    }
}

/// θ − sin θ without cancellation: the Taylor series θ³/3! − θ⁵/5! + … for |θ| < 1 (terms
/// shrink by ≥ 20× each, truncated below 1e-17 relative), the direct difference otherwise.
fn theta_minus_sin(theta: f64) -> f64 {
    if theta.abs() >= 1.0 {
        return theta - theta.sin();
    }
    let theta_sq = theta * theta;
    let mut term = theta * theta_sq / 6.0;
    let mut sum = term;
    let mut k = 3.0;
    while term.abs() > 1e-17 * sum.abs() {
        term *= -theta_sq / ((k + 1.0) * (k + 2.0));
        sum += term;
        k += 2.0;
    }
    sum
}

/// Exact motion of the spring drive without friction (F = 0) from rest at t = 0:
///
/// X(t) = V0·t − (V0/ω)·sin ωt = (V0/ω)·(ωt − sin ωt),  V(t) = V0·(1 − cos ωt) = 2V0·sin²(ωt/2),
///
/// evaluated without cancellation for small ωt (X ≈ V0·ω²t³/6). Returns (X in m, V in m/s).
///
/// With a dashpot (c_d > 0) the damped motion from rest: the exact flow of
/// [`SpringDrive::spring_flow`] over t, X = V0·t + Y(t), which loses the relative accuracy of
/// X to the cancellation in V0·t + Y where X ≪ V0·t (about ε·V0·t absolute).
#[must_use]
pub fn free_spring_exact(drive: &SpringDrive, t_s: f64) -> (f64, f64) {
    if drive.damping_n_s_per_m != 0.0 {
        let mut state = DriveState::at_rest();
        drive.spring_flow(&mut state, t_s);
        return (state.x_m, state.v_m_per_s);
    }
    let omega = drive.omega_rad_per_s();
    let v0 = drive.velocity_m_per_s;
    let theta = omega * t_s;
    let half_sin = (0.5 * theta).sin();
    (
        v0 / omega * theta_minus_sin(theta),
        2.0 * v0 * half_sin * half_sin,
    )
}

/// Energy in the frame co-moving with the spring's free end, in J:
///
/// E = ½·m·(V − V0)² + ½·K·(X − V0·t)²,
///
/// conserved by the exact motion when F = 0 and c_d = 0 (d/dt E = −F·(V − V0) − c_d·(V − V0)²).
#[must_use]
pub fn comoving_energy_j(drive: &SpringDrive, state: &DriveState) -> f64 {
    let dv = state.v_m_per_s - drive.velocity_m_per_s;
    let dx = state.x_m - drive.velocity_m_per_s * state.t_s;
    0.5 * drive.mass_kg * dv * dv + 0.5 * drive.stiffness_n_per_m * dx * dx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_step_response_is_its_integral_on_both_sides_of_the_series_switch() {
        // g(h) = −ω²·∫₀ʰ e^(−αs)·S(s) ds by composite Simpson on es from damped_flow_factors.
        for zeta in [0.0, 0.3, 1.0, 1.5, 40.0] {
            for omega_h in [1e-6, 1e-2, 0.3, 0.49, 0.51, 2.0, 7.0] {
                let (omega, h) = (1.0, omega_h);
                let n = 20_000;
                let step = h / f64::from(n);
                let integral = (0..=n)
                    .map(|i| {
                        let w = if i == 0 || i == n {
                            1.0
                        } else if i % 2 == 1 {
                            4.0
                        } else {
                            2.0
                        };
                        w * damped_flow_factors(omega, zeta, f64::from(i) * step).2
                    })
                    .sum::<f64>()
                    * step
                    / 3.0;
                let g = damped_step_response(omega, zeta, h);
                let exact = -omega * omega * integral;
                assert!(
                    (g - exact).abs() <= 1e-10 * exact.abs(),
                    "zeta {zeta}, omega h {omega_h}: {g:e} vs {exact:e}"
                );
            }
        }
    }
}
