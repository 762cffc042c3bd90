//! The accurate step: the exact Landau step per node under an exponentially weighted strain,
//! melting located inside the step, the coupling solved, and the step's local error estimated.
//! The film's kinetics come from [`super::film`]: the second-order film's, or the first-order
//! film's when b₃ > 0, chosen once when the simulation is built (`stepper_for`).

use super::books;
use super::drive_step;
use super::energy::StepSinks;
use super::error_estimate;
use super::film::Film;
use super::node_pass::{
    self, NodeScratch, THETA_STIFF_Z, all_below, linear_forcing_weight, linear_forcing_weight_from,
};
use super::problem::{Contact, Problem};
use super::stepper::{StepError, StepReport, Stepper};
use super::substrate::{BEND_NOISE_FACTOR, SubstratePredictor, SubstrateSolver};
use super::viscous::Viscous;
use super::{NumericalFailure, PHI_REPRESENTABLE_MIN, SimState, V_FLOOR_MELT_FRACTION, X_FLOOR};
use crate::config::Substrate;
use crate::drive::{Drive, DriveState, Integrator};
use crate::noise::NoiseSource;
use std::f64::consts::PI;

/// The accurate scheme with the film's kinetics `F`: its coupling solver, the film's viscous
/// stress when `lubricant.viscosity` > 0, and its per-node scratch.
pub(super) struct Accurate<F> {
    film: F,
    substrate: SubstrateSolver,
    /// `None` for η = 0, which then costs nothing and changes no bit.
    viscous: Option<Viscous>,
    scratch: NodeScratch,
}

/// What the film's step at one node ends with: φ and u0 at the step's end, the melting's
/// place θ in the step when the node melted, and where its last exact path starts (φ, strain,
/// offset and length in the step, s), to locate its crossing of the recovery level.
type NodeEnd = (f64, f64, Option<f64>, (f64, f64, f64, f64));

/// A node's energy sinks over the step (per unit volume of film, J/m³; the stamp's advance
/// while its u0 was held, m): Landau dissipation, the u0 reset, and the held advance.
#[derive(Clone, Copy, Default)]
struct NodeSinks {
    landau_pa: f64,
    reset_pa: f64,
    held_m: f64,
}

impl<F: Film> Accurate<F> {
    /// The stepper of `problem` with the film's kinetics `film`.
    pub fn new(problem: &Problem, film: F) -> Self {
        let n = problem.nodes();
        let c = problem.config.contact;
        let elastic = c.substrate == Substrate::Elastic;
        let substrate = SubstrateSolver::new(problem);
        let eta = problem.config.lubricant.viscosity_pa_s;
        let viscous = (eta > 0.0).then(|| {
            // The contact's area as the force quadrature integrates a uniform stress (πa0² up
            // to rounding), and κ·C's spectral radius at unit film stiffness.
            let (area_m2, unit) = match &problem.contact {
                Contact::Radial(ops) => {
                    let area = ops.force_3d_n(&vec![1.0; n]);
                    let unit = if problem.coupling_solver().is_some() {
                        problem.contraction_with(&vec![1.0; n])
                    } else {
                        0.0
                    };
                    (area, unit)
                }
                Contact::Homogeneous { area_m2, .. } => (*area_m2, 0.0),
            };
            let drag = eta * area_m2 / c.film_thickness_m;
            let relaxation = if elastic {
                eta * PI * c.radius_m / (2.0 * c.g_eff_pa * c.film_thickness_m)
            } else {
                0.0
            };
            Viscous::new(eta, (drag, relaxation), unit, n)
        });
        Self {
            film,
            substrate,
            viscous,
            scratch: NodeScratch::new(n),
        }
    }

    /// The force the drive's kicks carry: F, or with viscosity its part outside the spring's
    /// flow.
    fn kick_force_n(&self, state: &SimState) -> f64 {
        match &self.viscous {
            None => state.physical.force_n,
            Some(v) => v.kick_force_n(state),
        }
    }
}

impl<F: Film + Send + Sync> Stepper for Accurate<F> {
    fn step(
        &mut self,
        problem: &Problem,
        state: &mut SimState,
        noise: &mut NoiseSource,
        dt_s: f64,
    ) -> Result<StepReport, NumericalFailure> {
        let t0 = state.physical.drive.t_s;
        let a_mid = problem.config.temperature.a_coeff_pa(t0 + 0.5 * dt_s);
        let thr = problem.config.melt_threshold;
        let a = problem.config.lubricant.a_pa;
        let p = &state.physical;
        for ((tau0, &phi), &eps) in self.scratch.book_tau0.iter_mut().zip(&p.phi).zip(&p.eps) {
            *tau0 = a * phi * phi * eps;
        }
        if let Some(v) = self.viscous.as_mut() {
            v.step_start(problem, state, dt_s);
        }
        // The force the drive's kicks carry: F, or with viscosity its part outside the spring's
        // flow (the drag `drag` the flow takes).
        let drag = self.viscous.as_ref().map(|v| v.flow_drag_n_s_per_m);
        let drive_before = (state.physical.drive, self.kick_force_n(state));
        let (dx, anchor) = drive_step::open(
            problem,
            &mut state.physical.drive,
            drive_before.1,
            drag,
            dt_s,
        );
        // The substrate's change over this step, predicted from its last values (the coupling
        // solve below corrects u3D itself; only the strain seen by φ uses it).
        let predictor = SubstratePredictor::new(
            &state.stepper,
            dt_s,
            problem.config.time.adaptive.is_some(),
            BEND_NOISE_FACTOR * problem.coupling_abs_rms_m(t0),
        );
        self.film_passes(problem, state, &predictor, (a_mid, dx, dt_s));
        let (first_melt, recovered_s, mut sinks) =
            self.node_ends(problem, state, (t0, a_mid, dx, dt_s));
        let noisy = !matches!(problem.config.noise, crate::noise::NoiseKind::Off);
        if noisy {
            self.scratch.book_phi.clone_from(&state.physical.phi);
        }
        noise.apply(&mut state.physical.phi, dt_s);
        if noisy {
            let sc = &self.scratch;
            let after = &state.physical.phi;
            sinks.noise_work_j =
                books::noise_work_j(problem, a_mid, (&sc.book_phi, after), &sc.book_eps_path);
        }
        // A select, not a branch: the loop vectorises.
        for (u0, &phi) in state.physical.u0_m.iter_mut().zip(&state.physical.phi) {
            *u0 = if phi < thr { 0.0 } else { *u0 };
        }
        let coupling_rms_m =
            self.substrate
                .solve(problem, state, self.viscous.as_mut(), (t0 + dt_s, dt_s, dx))?;
        state.stepper.prev_dt_s = state.stepper.last_dt_s;
        state.stepper.last_dt_s = dt_s;
        problem.update_strain_and_stress(&mut state.physical);
        let sc = &self.scratch;
        sinks.sliding_j = books::sliding_j(problem, &state.physical, &sc.book_tau0, &sc.book_slide);
        if let Some(v) = &self.viscous {
            v.add_stress(problem, state, dt_s, dx);
            sinks.viscous_j = v.loss_j(problem, state, dt_s);
        }
        state.physical.force_n = problem.force_3d_n(&state.physical.tau_pa);
        let kick_after = self.kick_force_n(state);
        drive_step::close(
            problem,
            &mut state.physical.drive,
            kick_after,
            drag,
            (dt_s, &anchor),
        );
        let error = self.step_error(problem, state, dt_s, drive_before, coupling_rms_m);
        Ok(StepReport {
            error,
            first_melt_fraction: first_melt,
            recovered_at_s: recovered_s,
            coupling_rms_m,
            sinks,
        })
    }
}

impl<F: Film> Accurate<F> {
    /// The film's step at every node up to φ1 (the passes (a)–(c)): the per-node step in
    /// passes, so that each pass's exponentials are taken for all nodes in one vectorised loop
    /// (`vexp`) rather than by a library call per node; the arithmetic per node is the same as
    /// in one pass. The passes run under the CPU's best instruction set ([`FilmPasses`]).
    fn film_passes(
        &mut self,
        problem: &Problem,
        state: &SimState,
        predictor: &SubstratePredictor,
        args: (f64, f64, f64),
    ) {
        faer::traits::pulp::Arch::new().dispatch(FilmPasses {
            stepper: self,
            problem,
            state,
            predictor,
            args,
        });
    }

    /// [`Accurate::film_passes`]'s body, inlined into [`FilmPasses`]'s kernel.
    #[inline(always)]
    fn film_passes_body(
        &mut self,
        problem: &Problem,
        state: &SimState,
        predictor: &SubstratePredictor,
        (a_mid, dx, dt_s): (f64, f64, f64),
    ) {
        let params = problem.config.lubricant;
        let thr = problem.config.melt_threshold;
        let h0 = problem.config.contact.film_thickness_m;
        // Strains as multiplications by 1/h0: a division per node costs more than the rest of
        // its arithmetic here (see `node_pass`).
        let inv_h0 = 1.0 / h0;
        let (film, sc, p) = (&self.film, &mut self.scratch, &state.physical);
        let n = p.phi.len();
        // (a) The weight θ's argument −λΔt, and the substrate's predicted change. (Every
        // slice cut to n first: loops free of bounds checks, which vectorise.)
        let (phi, eps) = (&p.phi[..n], &p.eps[..n]);
        let arg = &mut sc.arg[..n];
        for i in 0..n {
            let (phi0, eps0) = (phi[i], eps[i]);
            let lambda = film.rate(params.bernoulli_c_pa(eps0, a_mid), phi0, phi0 * phi0);
            arg[i] = -(lambda * dt_s);
        }
        let memory = &state.stepper;
        predictor.du3d_all(
            (&p.u3d_m, &memory.u3d_prev_m, &memory.u3d_prev2_m),
            &mut sc.du3d,
        );
        // A step long against every node's relaxation (λΔt > THETA_STIFF_Z: a stick phase's
        // adaptive steps) needs no exponential: e^(−λΔt) is below half an ulp of 1, and θ's
        // 1/(1 − e) is 1 with e = 0 as with e itself (the same bits).
        if all_below(&sc.arg, -THETA_STIFF_Z) {
            sc.exp.fill(0.0);
        } else {
            crate::vexp::exp_expm1_all(&sc.arg, &mut sc.exp, &mut sc.expm1);
        }
        // (b) The effective strain, then the film's step at every node.
        let (arg, exp, du3d) = (&sc.arg[..n], &sc.exp[..n], &sc.du3d[..n]);
        let (theta_w, eps_eff) = (&mut sc.theta[..n], &mut sc.est_eps_eff[..n]);
        for i in 0..n {
            let phi0 = phi[i];
            let solid0 = phi0 >= thr;
            let du0 = if solid0 { dx } else { 0.0 };
            let eps0 = eps[i];
            let eps1 = eps0 + (du0 - du3d[i]) * inv_h0;
            // Frozen strain for the exact step: the weight θ(z) makes the step exact for a
            // linearised φ² relaxing at rate λ towards a target that moves linearly over the
            // step — ½ (midpoint, second order) for slow relaxation, → 1 (the end-of-step
            // strain, no lag) for the stiff stick phase where φ is slaved to ε.
            let theta = linear_forcing_weight_from(-arg[i], exp[i]);
            theta_w[i] = theta;
            eps_eff[i] = eps0 + theta * (eps1 - eps0);
        }
        film.step_all(
            &p.phi,
            &sc.est_eps_eff,
            a_mid,
            dt_s,
            &mut sc.phi1,
            (&mut sc.exp, &mut sc.expm1),
        );
        // (b′) The ramp correction (`numerics.film_step = "ramp"`): the frozen step's φ1
        // corrected to first order in the coefficient's change along the strain ramp; the
        // scratch θ then holds the correction's relative second-order remainder (v/u)²/2.
        if F::RAMP {
            let coefficients = film.ramp_coefficients();
            super::ramp::correct_all(super::ramp::RampPass {
                phi0: &p.phi,
                du3d_m: &sc.du3d,
                eps_eff: &sc.est_eps_eff,
                e_w: &sc.exp,
                phi1: &mut sc.phi1,
                theta: &mut sc.theta,
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
        let (phi1s, eps_eff, arg) = (&sc.phi1[..n], &sc.est_eps_eff[..n], &mut sc.arg[..n]);
        for i in 0..n {
            let (phi0, phi1) = (phi[i], phi1s[i]);
            let c_eff = params.bernoulli_c_pa(eps_eff[i], a_mid);
            let z = film.exponent(phi0 * phi0, phi1 * phi1, phi0, phi1, c_eff, dt_s);
            arg[i] = -z.max(-40.0);
        }
        // Where every node's z is above STIFF_Z the weights take their stiff forms, which use
        // no exponential (`defect_weights_select` discards the others): none is taken.
        if !all_below(&sc.arg, -error_estimate::STIFF_Z) {
            crate::vexp::exp_expm1_all(&sc.arg, &mut sc.exp, &mut sc.expm1);
        }
    }

    /// (d) Everything else: the error estimate's pieces ([`node_pass`], every node at once), melting located in the
    /// step, φ and u0 at the step's end. The fraction of the step at which the first node
    /// melted (1: none), the latest located recovery crossing, s (−∞: none), and the energy
    /// books' Landau and reset sinks (the held advances kept per node for the sliding work).
    fn node_ends(
        &mut self,
        problem: &Problem,
        state: &mut SimState,
        (t0, a_mid, dx, dt_s): (f64, f64, f64, f64),
    ) -> (f64, f64, StepSinks) {
        let mut sinks = StepSinks::default();
        let h0_m = problem.config.contact.film_thickness_m;
        let params = problem.config.lubricant;
        let thr = problem.config.melt_threshold;
        let h0 = problem.config.contact.film_thickness_m;
        // The film's recovery level at the step's end: the last node to cross it upwards,
        // located on its path, ends an open event (see `events`).
        let a_end = problem.config.temperature.a_coeff_pa(t0 + dt_s);
        let solid_phi_end = params.solid_phi(0.0, a_end);
        let recovery_phi = problem.config.events.recovery_phi(thr, solid_phi_end);
        let y_scale_min =
            node_pass::y_scale_min(problem, state.events.tracker.is_open(), solid_phi_end);
        let mut first_melt = 1.0_f64;
        let mut recovered_s = f64::NEG_INFINITY;
        // Every node's estimate and dissipation as if it did not melt, vectorised; the loop
        // below replaces them for the nodes that melt.
        self.scratch.estimate_ends(
            (&state.physical.phi, &state.physical.eps),
            node_pass::EndConstants {
                params,
                threshold: thr,
                h0_m: h0,
                dx_m: dx,
                dt_s,
                a_mid_pa: a_mid,
                y_scale_min,
                ramp: F::RAMP,
            },
        );
        // The nodes that stay on their side of the threshold, vectorised, with their Landau
        // sink; the loop below takes the others one by one.
        let p = &mut state.physical;
        let (special, landau_j) = self.scratch.stay_ends(
            (&mut p.phi, &mut p.u0_m),
            (thr, recovery_phi, dx),
            (&problem.energy_weights_m2, h0_m),
        );
        sinks.landau_j = landau_j;
        state.events.melted_in_step.fill(false);
        for i in 0..state.physical.phi.len() * usize::from(special > 0) {
            if self.scratch.special[i] == 0.0 {
                continue;
            }
            let phi0 = state.physical.phi[i];
            let solid0 = phi0 >= thr;
            let sc = &self.scratch;
            let eps_eff = sc.book_eps_path[i];
            let phi1 = sc.phi1[i];
            let u0 = state.physical.u0_m[i];
            let whole = (phi0, eps_eff, 0.0, dt_s);
            // The dissipation along the whole path; a melting node replaces it.
            let mut node = NodeSinks {
                landau_pa: sc.landau_pa[i],
                ..NodeSinks::default()
            };
            let (phi_end, u0_end, melted_at, path): NodeEnd = match (solid0, phi1 >= thr) {
                (true, true) => (phi1, u0 + dx, None, whole),
                (false, true) => {
                    let theta = self.film.crossing(phi0, phi1, thr, eps_eff, a_mid, dt_s);
                    node.held_m = theta * dx;
                    (phi1, (1.0 - theta) * dx, None, whole)
                }
                (false, false) => {
                    node.held_m = dx;
                    (phi1, 0.0, None, whole)
                }
                (true, false) => self.melting_node(
                    problem,
                    state,
                    i,
                    (a_mid, dx, dt_s),
                    // The ramp's end strain of a solid node (u0 advances by dx).
                    (
                        eps_eff,
                        state.physical.eps[i] + (dx - sc.du3d[i]) * (1.0 / h0),
                    ),
                    (y_scale_min, &mut node),
                ),
            };
            let w = problem.energy_weights_m2[i] * h0_m;
            sinks.landau_j += w * node.landau_pa;
            sinks.reset_j += w * node.reset_pa;
            self.scratch.book_slide[i] = node.held_m;
            self.scratch.book_eps_path[i] = path.1;
            if let Some(theta) = melted_at {
                first_melt = first_melt.min(theta);
            }
            // From φ > 0 Eq. 8 never reaches 0, but a long decay underflows φ² to 0, where
            // φ = 0 is a fixed point and the node could never re-solidify.
            let (phi_from, eps_path, offset_s, len_s) = path;
            if phi_from < recovery_phi && phi_end >= recovery_phi {
                let f = self
                    .film
                    .crossing(phi_from, phi_end, recovery_phi, eps_path, a_mid, len_s);
                recovered_s = recovered_s.max(t0 + offset_s + f * len_s);
            }
            let phi_end = if phi0 > 0.0 {
                phi_end.max(PHI_REPRESENTABLE_MIN)
            } else {
                phi_end
            };
            if let Some(theta) = melted_at {
                state.events.melted_in_step[i] = true;
                state.events.last_melt_s[i] = t0 + theta * dt_s;
            }
            state.physical.u0_m[i] = u0_end;
            state.physical.phi[i] = phi_end;
        }
        (first_melt, recovered_s, sinks)
    }

    /// Node `i`, solid at the step's start, melts within it at θ: u0 drops to 0 there, and
    /// the node carries on from φ = thr under the strain of a melted node, −u3D/h0. Below εc
    /// that strain makes φ grow at once: melting is instantaneous and u0 accumulates again
    /// from θ on. Continuing the decay to the step's end instead would leave φ far below thr
    /// by an amount set by Δt, and the recovery with it.
    fn melting_node(
        &mut self,
        problem: &Problem,
        state: &SimState,
        i: usize,
        (a_mid, dx, dt_s): (f64, f64, f64),
        (eps_eff, eps1): (f64, f64),
        (y_scale_min, book): (f64, &mut NodeSinks),
    ) -> NodeEnd {
        let params = problem.config.lubricant;
        let (a, two_gamma) = (params.a_pa, 2.0 * params.gamma_per_pa_s);
        let thr = problem.config.melt_threshold;
        let h0 = problem.config.contact.film_thickness_m;
        let (film, sc) = (&self.film, &mut self.scratch);
        let phi0 = state.physical.phi[i];
        let eps0 = state.physical.eps[i];
        // `eps_eff`: the step's effective strain, passed in (the ramp step's estimate has
        // already put the end strain in its place in the scratch).
        let (y0, phi1, du3d) = (phi0 * phi0, sc.phi1[i], sc.du3d[i]);
        let c_eff = params.bernoulli_c_pa(eps_eff, a_mid);
        let theta = film.crossing(phi0, phi1, thr, eps_eff, a_mid, dt_s);
        // The estimate covers the solid part of the path, up to the crossing, with the strain
        // there predicted (no solved value exists at θ).
        let ys = thr * thr;
        let h_c = theta * dt_s;
        let eps_c = eps0 + theta * (eps1 - eps0);
        let zc = film.exponent(y0, ys, phi0, thr, c_eff, h_c);
        let (w0c, w1c) = error_estimate::defect_weights(zc);
        sc.est_base[i] = h_c
            * (w0c * (-two_gamma * a * y0 * (eps_eff * eps_eff - eps0 * eps0))
                + w1c * (-two_gamma * a * ys * (eps_eff * eps_eff - eps_c * eps_c)));
        sc.est_gain[i] = 0.0;
        sc.est_norm[i] = 0.5 / ys.max(y_scale_min);
        let rest_s = (1.0 - theta) * dt_s;
        let u3d = state.physical.u3d_m[i];
        let eps_a = -(u3d + theta * du3d) / h0;
        let c_a = params.bernoulli_c_pa(eps_a, a_mid);
        // The books: f's drop on the solid path to the threshold, then the reset's elastic
        // energy at θ (strain ε_c before, ε_a after), then f's drop on the rest of the path.
        let f = |phi: f64, eps: f64| params.free_energy_pa(phi, eps, a_mid);
        book.landau_pa = f(phi0, eps_eff) - f(thr, eps_eff);
        book.reset_pa = 0.5 * params.a_pa * ys * (eps_c * eps_c - eps_a * eps_a);
        if film.regrows(thr, c_a) {
            let eps_b = ((1.0 - theta) * dx - (u3d + du3d)) / h0;
            let lambda = film.rate(c_a, thr, thr * thr);
            let eps_rest = eps_a + linear_forcing_weight(lambda * rest_s) * (eps_b - eps_a);
            let phi2 = film.step(thr, eps_rest, a_mid, rest_s);
            let u0_end = if phi2 >= thr { (1.0 - theta) * dx } else { 0.0 };
            book.landau_pa += f(thr, eps_rest) - f(phi2, eps_rest);
            if phi2 < thr {
                book.held_m = (1.0 - theta) * dx;
            }
            let path = (thr, eps_rest, theta * dt_s, rest_s);
            (phi2, u0_end, Some(theta), path)
        } else {
            let phi2 = film.step(thr, eps_a, a_mid, rest_s);
            book.landau_pa += f(thr, eps_a) - f(phi2, eps_a);
            book.held_m = (1.0 - theta) * dx;
            (phi2, 0.0, Some(theta), (thr, eps_a, theta * dt_s, rest_s))
        }
    }

    /// The local error of the accurate step just taken (see [`error_estimate`]), in units of
    /// scales that follow the state: φ relative to max(φ, threshold,
    /// `numerics.phi_error_floor`·φ_s) per node, ε relative to the melting strain (εc(t); ε₊(t)
    /// for the first-order film), X to max(|X|, 1e-3·h0), V to max(|V|, 0.1·ω·h0·εc) with
    /// ω = √(K/m) (see [`V_FLOOR_MELT_FRACTION`]). `coupling_rms_m`: the coupling
    /// solve's residual, which shifts the strain as the stamp's position error does.
    fn step_error(
        &mut self,
        problem: &Problem,
        state: &mut SimState,
        dt_s: f64,
        before: (DriveState, f64),
        coupling_rms_m: f64,
    ) -> StepError {
        let sc = &self.scratch;
        let s = &state.physical;
        let cols: [&[f64]; 5] = [
            &sc.est_eps_eff,
            &s.eps,
            &sc.est_base,
            &sc.est_gain,
            &sc.est_norm,
        ];
        let phi_err = crate::sums::max_cols(cols, 0.0, |[eps_eff, eps_end, base, gain, norm]| {
            (base + gain * (eps_eff * eps_eff - eps_end * eps_end)).abs() * norm
        });
        let drive = self.drive_error(problem, state, dt_s, before);
        // The viscous coupling's backward-Euler error in u3D shifts the strain as the stamp's
        // position error does (0 without viscosity, and then not taken).
        let eps_shift_m = match &self.viscous {
            Some(v) => drive.x_m.max(v.step_end(problem, state, dt_s)),
            None => drive.x_m,
        };
        // The coupling solve's residual shifts the strain as much (see
        // `Problem::coupling_abs_rms_m`).
        let eps_shift_m = eps_shift_m.max(coupling_rms_m);
        let config = &problem.config;
        let s = &state.physical;
        let a_now = config.temperature.a_coeff_pa(s.drive.t_s);
        let eps_c = config.lubricant.melting_strain(a_now);
        let eps_scale = if eps_c > 0.0 {
            eps_c
        } else {
            config.lubricant.eps_max
        };
        let h0 = config.contact.film_thickness_m;
        let v_floor = match &config.drive {
            Drive::Spring(sp) => V_FLOOR_MELT_FRACTION * sp.omega_rad_per_s() * h0 * eps_scale,
            Drive::Rigid(_) => 0.0,
        };
        StepError {
            phi: phi_err,
            eps: eps_shift_m / (h0 * eps_scale),
            x: drive.x_m / s.drive.x_m.abs().max(X_FLOOR * h0),
            v: drive.v_m_per_s / s.drive.v_m_per_s.abs().max(v_floor).max(f64::MIN_POSITIVE),
        }
    }

    /// The stamp's local error over the step, from the drive's state and kick force `before`
    /// it and the state now.
    fn drive_error(
        &self,
        problem: &Problem,
        state: &mut SimState,
        dt_s: f64,
        (before, f_before): (DriveState, f64),
    ) -> error_estimate::DriveError {
        // The kicks' force at the step's end (F itself without viscosity).
        let f_after = self.kick_force_n(state);
        let (s, memory) = (&state.physical, &mut state.stepper);
        match (&problem.config.drive, problem.config.integrator) {
            (Drive::Rigid(_), _) => error_estimate::DriveError::default(),
            (Drive::Spring(sp), integrator @ (Integrator::Verlet | Integrator::Split)) => {
                // Verlet's remainder on the acceleration's change over the step; with the split
                // integrator only the friction force's kicks carry an error (a = −F/m).
                let d = &s.drive;
                let change = if integrator == Integrator::Split {
                    // The kicks carry F − k·X (the flow takes the contact's stiffness k).
                    let k = problem.flow_stiffness_n_per_m;
                    -((f_after - k * d.x_m) - (f_before - k * before.x_m)) / sp.mass_kg
                } else if let Some(v) = &self.viscous {
                    // The viscous drag as a dashpot on the absolute velocity (see
                    // `drive_step::viscous_half`).
                    let loaded = sp.with_drag(v.flow_drag_n_s_per_m);
                    let offset = v.flow_drag_n_s_per_m * sp.velocity_m_per_s;
                    loaded.acceleration_m_per_s2(d.t_s, d.x_m, d.v_m_per_s, f_after + offset)
                        - loaded.acceleration_m_per_s2(
                            before.t_s,
                            before.x_m,
                            before.v_m_per_s,
                            f_before + offset,
                        )
                } else {
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
                memory.accel_change_prev_m_per_s2 = change;
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
        }
    }
}

/// [`Accurate::film_passes`] compiled once per instruction set (pulp's run-time dispatch), so
/// that its loops over nodes, branch-free, vectorise where the CPU allows; the arithmetic, and
/// so the bits, are the same on every instruction set (no fused multiply-add).
struct FilmPasses<'a, F> {
    stepper: &'a mut Accurate<F>,
    problem: &'a Problem,
    state: &'a SimState,
    predictor: &'a SubstratePredictor,
    args: (f64, f64, f64),
}

impl<F: Film> faer::traits::pulp::WithSimd for FilmPasses<'_, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: faer::traits::pulp::Simd>(self, _simd: S) {
        self.stepper
            .film_passes_body(self.problem, self.state, self.predictor, self.args);
    }
}
