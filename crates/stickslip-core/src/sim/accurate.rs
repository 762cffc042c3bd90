//! The accurate step: the exact Landau step per node under an exponentially weighted strain,
//! melting located inside the step, the coupling solved, and the step's local error estimated.
//! The film's kinetics come from [`super::film`]: the second-order film's, or the first-order
//! film's when b₃ > 0, chosen once when the simulation is built ([`super::stepper`]).

use super::error_estimate;
use super::film::Film;
use super::{NumericalFailure, PHI_REPRESENTABLE_MIN, Simulation, StepError, V_FLOOR, X_FLOOR};
use crate::drive::{Drive, DriveState, Integrator};

impl Simulation {
    /// One accurate step of `dt_s` with the film's kinetics `film` (the `Accurate` stepper's).
    pub(super) fn step_accurate_with<F: Film>(
        &mut self,
        film: &F,
        dt_s: f64,
    ) -> Result<(), NumericalFailure> {
        let t0 = self.state.physical.drive.t_s;
        let a_mid = self.config.temperature.a_coeff_pa(t0 + 0.5 * dt_s);
        let params = self.config.lubricant;
        let a = params.a_pa;
        let two_gamma = 2.0 * params.gamma_per_pa_s;
        let thr = self.config.melt_threshold;
        let h0 = self.config.contact.film_thickness_m;
        self.viscous_step_start(dt_s);
        // The force the drive's kicks carry: F, or with viscosity its part outside the spring's
        // flow.
        let drive_before = (self.state.physical.drive, self.kick_force_n());
        let dx = self.drive_first_half(dt_s);
        // The substrate's change over this step, predicted from its last values (the coupling
        // solve below corrects u3D itself; only the strain seen by φ uses it).
        let predictor = SubstratePredictor::new(
            &self.state.stepper,
            dt_s,
            self.config.time.adaptive.is_some(),
            BEND_NOISE_FACTOR * self.coupling_abs_rms_m(t0),
        );
        let mut first_melt = 1.0_f64;
        // The film's recovery level at the step's end: the last node to cross it upwards,
        // located on its path, ends an open event (see `events`).
        let a_end = self.config.temperature.a_coeff_pa(t0 + dt_s);
        let solid_phi_end = params.solid_phi(0.0, a_end);
        let recovery_phi = self.config.events.recovery_phi(thr, solid_phi_end);
        // The error norm's φ scale: φ itself, but not below the melt threshold nor below
        // `numerics.phi_error_floor`·φ_s (squared: the norm divides y = φ²'s error).
        let phi_scale = thr.max(self.config.numerics.phi_error_floor * solid_phi_end);
        let y_scale_min = phi_scale * phi_scale;
        let mut recovered_s = f64::NEG_INFINITY;
        let n = self.state.physical.phi.len();
        // The per-node step in passes, so that each pass's exponentials are taken for all
        // nodes in one vectorised loop (`vexp`) rather than by a library call per node; the
        // arithmetic per node is the same as in one pass. (a) The weight θ's argument −λΔt.
        for i in 0..n {
            let phi0 = self.state.physical.phi[i];
            let eps0 = self.state.physical.eps[i];
            let lambda = film.rate(params.bernoulli_c_pa(eps0, a_mid), phi0, phi0 * phi0);
            self.node_arg[i] = -(lambda * dt_s);
            self.node_du3d[i] = predictor.du3d(
                self.state.physical.u3d_m[i],
                self.state.stepper.u3d_prev_m[i],
                self.state.stepper.u3d_prev2_m.get(i).copied(),
            );
        }
        crate::vexp::exp_expm1_all(&self.node_arg, &mut self.node_exp, &mut self.node_expm1);
        // (b) The effective strain, then the film's step at every node.
        for i in 0..n {
            let phi0 = self.state.physical.phi[i];
            let solid0 = phi0 >= thr;
            let du3d = self.node_du3d[i];
            let du0 = if solid0 { dx } else { 0.0 };
            let eps0 = self.state.physical.eps[i];
            let eps1 = eps0 + (du0 - du3d) / h0;
            // Frozen strain for the exact step: the weight θ(z) makes the step exact for a
            // linearised φ² relaxing at rate λ towards a target that moves linearly over the
            // step — ½ (midpoint, second order) for slow relaxation, → 1 (the end-of-step
            // strain, no lag) for the stiff stick phase where φ is slaved to ε.
            let theta = linear_forcing_weight_from(-self.node_arg[i], self.node_exp[i]);
            self.node_theta[i] = theta;
            self.est_eps_eff[i] = eps0 + theta * (eps1 - eps0);
        }
        film.step_all(
            &self.state.physical.phi,
            &self.est_eps_eff,
            a_mid,
            dt_s,
            &mut self.node_phi1,
            (&mut self.node_exp, &mut self.node_expm1),
        );
        // (b′) The ramp correction (`numerics.film_step = "ramp"`): the frozen step's φ1
        // corrected to first order in the coefficient's change along the strain ramp; the
        // scratch θ then holds the correction's relative second-order remainder (v/u)²/2.
        if F::RAMP {
            let coefficients = film.ramp_coefficients();
            super::ramp::correct_all(super::ramp::RampPass {
                phi0: &self.state.physical.phi,
                du3d_m: &self.node_du3d,
                eps_eff: &self.est_eps_eff,
                e_w: &self.node_exp,
                phi1: &mut self.node_phi1,
                theta: &mut self.node_theta,
                threshold: thr,
                dx_m: dx,
                h0_m: h0,
                c_shift_pa: a_mid * coefficients.1 / coefficients.0,
                coefficients,
                h_s: dt_s,
            });
        }
        // (c) The error estimate's propagator exponent z (see `error_estimate`), clamped as
        // `defect_weights` clamps it, and e^(−z).
        for i in 0..n {
            let phi0 = self.state.physical.phi[i];
            let phi1 = self.node_phi1[i];
            let c_eff = params.bernoulli_c_pa(self.est_eps_eff[i], a_mid);
            let z = film.exponent(phi0 * phi0, phi1 * phi1, phi0, phi1, c_eff, dt_s);
            self.node_arg[i] = -z.max(-40.0);
        }
        crate::vexp::exp_expm1_all(&self.node_arg, &mut self.node_exp, &mut self.node_expm1);
        // (d) Everything else, node by node.
        for i in 0..n {
            let phi0 = self.state.physical.phi[i];
            let solid0 = phi0 >= thr;
            let du3d = self.node_du3d[i];
            // u0 is held at 0 while melted, so only solid nodes see the stamp's advance.
            let du0 = if solid0 { dx } else { 0.0 };
            let eps0 = self.state.physical.eps[i];
            let eps1 = eps0 + (du0 - du3d) / h0;
            let y0 = phi0 * phi0;
            let eps_eff = self.est_eps_eff[i];
            let phi1 = self.node_phi1[i];
            // The error estimate's pieces (see `error_estimate`): the defect at the start now,
            // at the end once the coupling solve has given the end strain.
            let y1 = phi1 * phi1;
            let c_eff = params.bernoulli_c_pa(eps_eff, a_mid);
            let (w0, w1) = error_estimate::defect_weights_from(
                -self.node_arg[i],
                (self.node_exp[i], self.node_expm1[i]),
            );
            self.est_base[i] =
                dt_s * w0 * (-two_gamma * a * y0 * (eps_eff * eps_eff - eps0 * eps0));
            self.est_gain[i] = dt_s * w1 * (-two_gamma * a * y1);
            if F::RAMP {
                // The ramp step's error: its second-order remainder, and the end strain's
                // prediction error (the defect at the end against ε1, the ramp's end).
                self.est_base[i] = y1 * self.node_theta[i];
                self.est_eps_eff[i] = eps1;
            }
            self.est_norm[i] = 0.5 / y1.max(y_scale_min);
            let u0 = self.state.physical.u0_m[i];
            // `path`: where the node's last exact path starts (φ, strain, offset and length in
            // the step, s), to locate its crossing of the recovery level.
            let whole = (phi0, eps_eff, 0.0, dt_s);
            let (phi_end, u0_end, melted_at, path) = match (solid0, phi1 >= thr) {
                (true, true) => (phi1, u0 + dx, None, whole),
                (false, true) => {
                    let theta = film.crossing(phi0, phi1, thr, eps_eff, a_mid, dt_s);
                    (phi1, (1.0 - theta) * dx, None, whole)
                }
                (false, false) => (phi1, 0.0, None, whole),
                (true, false) => {
                    // The film melts at θ: u0 drops to 0 there, and the node carries on from
                    // φ = thr under the strain of a melted node, −u3D/h0. Below εc that strain
                    // makes φ grow at once: melting is instantaneous and u0 accumulates again
                    // from θ on. Continuing the decay to the step's end instead would leave φ
                    // far below thr by an amount set by Δt, and the recovery with it.
                    let theta = film.crossing(phi0, phi1, thr, eps_eff, a_mid, dt_s);
                    // The estimate covers the solid part of the path, up to the crossing, with
                    // the strain there predicted (no solved value exists at θ).
                    let ys = thr * thr;
                    let h_c = theta * dt_s;
                    let eps_c = eps0 + theta * (eps1 - eps0);
                    let zc = film.exponent(y0, ys, phi0, thr, c_eff, h_c);
                    let (w0c, w1c) = error_estimate::defect_weights(zc);
                    self.est_base[i] = h_c
                        * (w0c * (-two_gamma * a * y0 * (eps_eff * eps_eff - eps0 * eps0))
                            + w1c * (-two_gamma * a * ys * (eps_eff * eps_eff - eps_c * eps_c)));
                    self.est_gain[i] = 0.0;
                    self.est_norm[i] = 0.5 / ys.max(y_scale_min);
                    let rest_s = (1.0 - theta) * dt_s;
                    let u3d = self.state.physical.u3d_m[i];
                    let eps_a = -(u3d + theta * du3d) / h0;
                    let c_a = params.bernoulli_c_pa(eps_a, a_mid);
                    if film.regrows(thr, c_a) {
                        let eps_b = ((1.0 - theta) * dx - (u3d + du3d)) / h0;
                        let lambda = film.rate(c_a, thr, thr * thr);
                        let eps_rest =
                            eps_a + linear_forcing_weight(lambda * rest_s) * (eps_b - eps_a);
                        let phi2 = film.step(thr, eps_rest, a_mid, rest_s);
                        let u0_end = if phi2 >= thr { (1.0 - theta) * dx } else { 0.0 };
                        let path = (thr, eps_rest, theta * dt_s, rest_s);
                        (phi2, u0_end, Some(theta), path)
                    } else {
                        let phi2 = film.step(thr, eps_a, a_mid, rest_s);
                        (phi2, 0.0, Some(theta), (thr, eps_a, theta * dt_s, rest_s))
                    }
                }
            };
            if let Some(theta) = melted_at {
                first_melt = first_melt.min(theta);
            }
            // From φ > 0 Eq. 8 never reaches 0, but a long decay underflows φ² to 0, where
            // φ = 0 is a fixed point and the node could never re-solidify.
            let (phi_from, eps_path, offset_s, len_s) = path;
            if phi_from < recovery_phi && phi_end >= recovery_phi {
                let f = film.crossing(phi_from, phi_end, recovery_phi, eps_path, a_mid, len_s);
                recovered_s = recovered_s.max(t0 + offset_s + f * len_s);
            }
            let phi_end = if phi0 > 0.0 {
                phi_end.max(PHI_REPRESENTABLE_MIN)
            } else {
                phi_end
            };
            self.state.events.melted_in_step[i] = melted_at.is_some();
            if let Some(theta) = melted_at {
                self.state.events.last_melt_s[i] = t0 + theta * dt_s;
            }
            self.state.physical.u0_m[i] = u0_end;
            self.state.physical.phi[i] = phi_end;
        }
        self.first_melt_fraction = first_melt;
        self.recovered_at_s = recovered_s;
        self.noise.apply(&mut self.state.physical.phi, dt_s);
        for (u0, &phi) in self
            .state
            .physical
            .u0_m
            .iter_mut()
            .zip(&self.state.physical.phi)
        {
            if phi < thr {
                *u0 = 0.0;
            }
        }
        self.solve_coupling(self.state.counters.step + 1, t0 + dt_s, dt_s, dx)?;
        self.state.stepper.prev_dt_s = self.state.stepper.last_dt_s;
        self.state.stepper.last_dt_s = dt_s;
        self.update_strain_and_stress();
        self.add_viscous_stress(dt_s, dx);
        self.state.physical.force_n = self.force_3d();
        self.drive_second_half(dt_s);
        self.estimate_step_error(dt_s, drive_before);
        Ok(())
    }

    /// The local error of the accurate step just taken (see [`error_estimate`]), in units of scales
    /// that follow the state: φ relative to max(φ, threshold, `numerics.phi_error_floor`·φ_s) per
    /// node, ε relative to the melting
    /// strain (εc(t); ε₊(t) for the first-order film), X to
    /// max(|X|, 1e-3·h0), V to max(|V|, 1e-6·V0). V's scale is its own size, not V0: a
    /// spring-driven stamp creeps at V ≪ V0 before the first slip, and an error in V is an error in
    /// X that grows with time.
    fn estimate_step_error(&mut self, dt_s: f64, (before, f_before): (DriveState, f64)) {
        // The kicks' force at the step's end (F itself without viscosity).
        let f_after = self.kick_force_n();
        let (s, memory) = (&self.state.physical, &self.state.stepper);
        let mut phi_err = 0.0_f64;
        for i in 0..s.phi.len() {
            let (eps_eff, eps_end) = (self.est_eps_eff[i], s.eps[i]);
            let e_y = self.est_base[i] + self.est_gain[i] * (eps_eff * eps_eff - eps_end * eps_end);
            phi_err = phi_err.max(e_y.abs() * self.est_norm[i]);
        }
        let drive = match (&self.config.drive, self.config.integrator) {
            (Drive::Rigid(_), _) => error_estimate::DriveError::default(),
            (Drive::Spring(sp), integrator @ (Integrator::Verlet | Integrator::Split)) => {
                // Verlet's remainder on the acceleration's change over the step; with the split
                // integrator only the friction force's kicks carry an error (a = −F/m).
                let change = if integrator == Integrator::Split {
                    // The kicks carry F − k·X (the flow takes the contact's stiffness k).
                    let k = self.flow_stiffness_n_per_m;
                    -((f_after - k * s.drive.x_m) - (f_before - k * before.x_m)) / sp.mass_kg
                } else if let Some(v) = &self.viscous {
                    // The viscous drag as a dashpot on the absolute velocity (see
                    // `viscous_drive_half`).
                    let loaded = sp.with_drag(v.flow_drag_n_s_per_m);
                    let offset = v.flow_drag_n_s_per_m * sp.velocity_m_per_s;
                    let d = &s.drive;
                    loaded.acceleration_m_per_s2(d.t_s, d.x_m, d.v_m_per_s, f_after + offset)
                        - loaded.acceleration_m_per_s2(
                            before.t_s,
                            before.x_m,
                            before.v_m_per_s,
                            f_before + offset,
                        )
                } else {
                    let d = &s.drive;
                    sp.acceleration_m_per_s2(d.t_s, d.x_m, d.v_m_per_s, f_after)
                        - sp.acceleration_m_per_s2(
                            before.t_s,
                            before.x_m,
                            before.v_m_per_s,
                            f_before,
                        )
                };
                let est = error_estimate::verlet_error(
                    dt_s,
                    change,
                    memory.prev_dt_s,
                    memory.accel_change_prev_m_per_s2,
                );
                self.state.stepper.accel_change_prev_m_per_s2 = change;
                est
            }
            (Drive::Spring(sp), Integrator::Rk4) => {
                let est = error_estimate::frozen_force_error(dt_s, f_after - f_before, sp.mass_kg);
                match &self.viscous {
                    None => est,
                    Some(v) => {
                        // RK4 takes the drag explicitly: its error on the damping's own decay of
                        // V − V0, which also rejects steps beyond RK4's stability bound.
                        let rate = (sp.damping_n_s_per_m + v.flow_drag_n_s_per_m) / sp.mass_kg;
                        let extra = error_estimate::rk4_decay_error(
                            rate * dt_s,
                            before.v_m_per_s - sp.velocity_m_per_s,
                        );
                        error_estimate::DriveError {
                            x_m: est.x_m + dt_s * extra,
                            v_m_per_s: est.v_m_per_s + extra,
                        }
                    }
                }
            }
        };
        // The viscous coupling's backward-Euler error in u3D shifts the strain as the stamp's
        // position error does (0 without viscosity, and then not taken).
        let eps_shift_m = if self.viscous.is_some() {
            drive.x_m.max(self.viscous_step_end(dt_s))
        } else {
            drive.x_m
        };
        // The coupling solve's residual shifts the strain as much (see
        // `Simulation::coupling_abs_rms_m`).
        let eps_shift_m = eps_shift_m.max(self.last_coupling_rms_m);
        let s = &self.state.physical;
        let a_now = self.config.temperature.a_coeff_pa(s.drive.t_s);
        let eps_c = self.config.lubricant.melting_strain(a_now);
        let eps_scale = if eps_c > 0.0 {
            eps_c
        } else {
            self.config.lubricant.eps_max
        };
        let h0 = self.config.contact.film_thickness_m;
        let v0 = self.config.drive.velocity_m_per_s().abs();
        self.last_error = StepError {
            phi: phi_err,
            eps: eps_shift_m / (h0 * eps_scale),
            x: drive.x_m / s.drive.x_m.abs().max(X_FLOOR * h0),
            v: drive.v_m_per_s
                / s.drive
                    .v_m_per_s
                    .abs()
                    .max(V_FLOOR * v0)
                    .max(f64::MIN_POSITIVE),
        };
    }
}

/// The quadratic prediction of u3D is used only where its bend is at least this many times
/// the coupling solve's absolute residual floor (`Simulation::coupling_abs_rms_m`): u3D is
/// solved only to that floor, and the quadratic through three such values amplifies their
/// noise about fourfold. Measured with the ramp step: the SFA contact (sfa.toml, 0 → 0.11 s,
/// its long stick on the h0 = 1 nm film) in 6646 + 1266 rejected steps against 18 056 + 2989
/// without this condition and 7267 + 720 with the linear prediction alone; fig2 (N = 2000) in
/// 1486 + 168 against 2948 + 58 with the linear one alone.
const BEND_NOISE_FACTOR: f64 = 3.0;

/// The substrate's displacement change over the coming step, per node, from its last values:
/// the quadratic through the last three (u3D's error O(Δt³), so the strain the film steps
/// under is off by O(Δt³) and the error estimate's end-strain part is that small where u3D
/// is smooth), or the linear one through the last two where the quadratic's bend is more
/// than half the linear change — in a melting cascade, where u3D's history has kinks the
/// quadratic would throw forward — or below [`BEND_NOISE_FACTOR`] times the coupling's
/// residual floor (noise), and where there is no history yet. Fixed steps keep the
/// linear one: no error estimate rejects a step whose quadratic overshoots a kink there (the
/// hard case of fig2 at Δt = 1 µs had its onsets 5.55 µs off the reference with it, beyond
/// the case's 5·Δt), and their runs stay bit for bit what they were.
struct SubstratePredictor {
    /// The linear extrapolation's factor Δt/Δt_last on u − u_prev (0 without a last step).
    ratio: f64,
    /// Lagrange weights of the quadratic's change (u, u_prev, u_prev2), when three values
    /// exist.
    quadratic: Option<(f64, f64, f64)>,
    /// The smallest bend of the quadratic that is taken as signal, m.
    noise_m: f64,
}

impl SubstratePredictor {
    fn new(memory: &super::state::StepperMemory, dt_s: f64, adaptive: bool, noise_m: f64) -> Self {
        let (h_last, h_prev) = (memory.last_dt_s, memory.prev_dt_s);
        let ratio = if h_last > 0.0 { dt_s / h_last } else { 0.0 };
        let has_three = adaptive
            && h_last > 0.0
            && h_prev > 0.0
            && memory.u3d_prev2_m.len() == memory.u3d_prev_m.len();
        // Lagrange weights at t_n + x from t_n, t_n − a, t_n − b, less 1 on u: the change.
        let (x, a, b) = (dt_s, h_last, h_last + h_prev);
        let quadratic = has_three.then(|| {
            (
                (x + a) * (x + b) / (a * b) - 1.0,
                -x * (x + b) / (a * (b - a)),
                x * (x + a) / (b * (b - a)),
            )
        });
        Self {
            ratio,
            quadratic,
            noise_m,
        }
    }

    #[inline(always)]
    fn du3d(&self, u: f64, prev: f64, prev2: Option<f64>) -> f64 {
        let linear = self.ratio * (u - prev);
        match (self.quadratic, prev2) {
            (Some((w0, w1, w2)), Some(prev2)) => {
                let quadratic = w0 * u + w1 * prev + w2 * prev2;
                let bend = (quadratic - linear).abs();
                if bend <= 0.5 * linear.abs() && bend >= self.noise_m {
                    quadratic
                } else {
                    linear
                }
            }
            _ => linear,
        }
    }
}

/// Weight θ(z) = 1/(1 − e^(−z)) − 1/z with z = λ·Δt: y' = −λ(y − g(t)) with g linear over
/// the step is solved exactly by freezing g at g(t0) + θ·(g(t1) − g(t0)).
/// θ → ½ + z/12 for z → 0, → 1 for z → +∞, → 0 for z → −∞.
fn linear_forcing_weight(z: f64) -> f64 {
    linear_forcing_weight_from(z, crate::vexp::exp(-z))
}

/// [`linear_forcing_weight`] given e^(−z).
#[inline(always)]
fn linear_forcing_weight_from(z: f64, e: f64) -> f64 {
    if z.abs() < 1e-4 {
        0.5 + z / 12.0
    } else {
        1.0 / (1.0 - e) - 1.0 / z
    }
}
