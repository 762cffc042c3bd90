//! What every step ends with, whatever its scheme: the state checked (finite, no film stress
//! running away, with advice that names the scene's keys), and the step's outcome handed to
//! the event tracker ([`super::events`]).

use super::energy::{EnergyFlows, StoredEnergy};
use super::events::StepSample;
use super::problem::Problem;
use super::stepper::StepReport;
use super::{NumericalFailure, SimState};
use crate::config::{Scheme, SimConfig};
use crate::sums;

/// Node `i` is below the threshold now or melted during the last step.
fn is_melted(problem: &Problem, state: &SimState, i: usize) -> bool {
    state.physical.phi[i] < problem.config.melt_threshold
        || state.events.melted_in_step.get(i).copied().unwrap_or(false)
}

/// The film's area-weighted mean φ and the melted area (φ < `thr`) with its node count, by
/// the area weights `w`: one computation for the events and the series alike, so that they
/// agree to the bit (the sums in lanes, [`crate::sums`]).
pub(super) fn film_means(w: &[f64], phi: &[f64], thr: f64) -> (f64, (f64, usize)) {
    let n = w.len();
    let phi = &phi[..n];
    let (mean, melted) = sums::sum2_cols([w, phi], |[w, phi]| {
        (w * phi, if phi < thr { w } else { 0.0 })
    });
    (mean, (melted, phi.iter().filter(|&&p| p < thr).count()))
}

/// Hands the event tracker what the step just taken ended with (`report`: what the stepper
/// located inside it; `energy`: the step's flows and the energy stored at its end, for the
/// books).
pub(super) fn observe_events(
    problem: &Problem,
    state: &mut SimState,
    report: &StepReport,
    energy: (EnergyFlows, StoredEnergy),
) {
    let thr = problem.config.melt_threshold;
    let a_coeff = problem
        .config
        .temperature
        .a_coeff_pa(state.physical.drive.t_s);
    let phi_eq = problem.config.lubricant.solid_phi(0.0, a_coeff);
    let recovery_phi = problem.config.events.recovery_phi(thr, phi_eq);
    let open = state.events.tracker.is_open();
    let w = &problem.area_weights[..];
    let n = w.len();
    let phi = &state.physical.phi[..n];
    let (phi_mean, (fraction, fraction_count)) = film_means(w, phi, thr);
    // A node counts unrecovered below φ_rec whether melted or solid. A node that melted inside
    // the step and regrew past φ_rec before its end has recovered by the rule (its crossing
    // is located in `recovered_at_s`); counting it unrecovered would hold the event open to
    // the next step's end.
    let unrecovered_nodes = phi.iter().filter(|&&p| p < recovery_phi).count();
    let melted_in_step = &state.events.melted_in_step;
    // Folds without an early exit, which vectorise (`any` goes byte by byte).
    let any_melted = fraction_count > 0 || melted_in_step.iter().fold(false, |a, &m| a | m);
    let swept_flags = &mut state.events.swept;
    // The melted nodes' extent and the swept area: only where a node is melted, an event is
    // open or the last one's swept nodes are still to be cleared.
    let (melted_nodes, outer, inner, swept, swept_count) =
        if any_melted || open || swept_flags.iter().fold(false, |a, &s| a | s) {
            let mut melted_nodes = 0;
            let mut outer = 0.0_f64;
            let mut inner = f64::INFINITY;
            for i in 0..n {
                if !open {
                    swept_flags[i] = false;
                }
                if phi[i] < thr || melted_in_step.get(i).copied().unwrap_or(false) {
                    melted_nodes += 1;
                    outer = outer.max(problem.radii_m[i]);
                    inner = inner.min(problem.radii_m[i]);
                    swept_flags[i] = true;
                }
            }
            // Sequential: only while an event is open or a node melted.
            let swept: f64 = w
                .iter()
                .zip(swept_flags.iter())
                .filter(|(_, s)| **s)
                .map(|(w, _)| w)
                .sum();
            let swept_count = swept_flags.iter().filter(|&&s| s).count();
            (melted_nodes, outer, inner, swept, swept_count)
        } else {
            (0, 0.0, f64::INFINITY, 0.0, 0)
        };
    let solid_nodes = n - melted_nodes;
    let fraction = whole_area(fraction, fraction_count, n);
    let swept = whole_area(swept, swept_count, n);
    let t_s = state.physical.drive.t_s;
    // Located times where the scheme knows them (the accurate scheme's melting of the
    // axis node and recovery crossings), else the step's end.
    let center_melt_s = if state
        .events
        .melted_in_step
        .first()
        .copied()
        .unwrap_or(false)
        && state.events.last_melt_s[0] >= 0.0
    {
        state.events.last_melt_s[0].min(t_s)
    } else {
        t_s
    };
    let recovered_s = if report.recovered_at_s.is_finite() {
        report.recovered_at_s.min(t_s)
    } else {
        t_s
    };
    let sample = StepSample {
        t_s: state.physical.drive.t_s,
        first_melt_s: state.physical.drive.t_s
            - (1.0 - report.first_melt_fraction) * state.stepper.last_dt_s,
        v_m_per_s: state.physical.drive.v_m_per_s,
        x_m: state.physical.drive.x_m,
        f_n: state.physical.force_n,
        melted_nodes,
        unrecovered_nodes,
        solid_nodes,
        outermost_melted_m: outer,
        innermost_melted_m: inner,
        center_melted: is_melted(problem, state, 0),
        center_melt_s,
        recovered_s,
        melted_fraction: fraction,
        swept_fraction: swept,
        phi_mean,
        phi_eq,
        energy_step: energy.0,
        stored: energy.1,
    };
    state.events.tracker.observe(&sample);
}

/// The state after a step: finite, and no film stress beyond the runaway limit.
///
/// # Errors
/// [`NumericalFailure`] naming the first non-finite value or the node running away.
pub(super) fn check_state(problem: &Problem, state: &SimState) -> Result<(), NumericalFailure> {
    let s = &state.physical;
    let fail = |node: usize, quantity: &'static str, value: f64, diagnosis: String| {
        Err(NumericalFailure {
            t_s: s.drive.t_s,
            step: state.counters.step,
            node,
            r_m: problem.radii_m.get(node).copied().unwrap_or(0.0),
            quantity,
            value,
            diagnosis,
        })
    };
    let d = &s.drive;
    if !(d.x_m.is_finite() && d.v_m_per_s.is_finite() && s.force_n.is_finite()) {
        return fail(
            0,
            "X, V or F",
            d.x_m + d.v_m_per_s + s.force_n,
            non_finite_advice(&problem.config),
        );
    }
    let l = &problem.config.lubricant;
    // τmax; the first-order film's stationary curve peaks higher (at A(0), its largest).
    let scale = if l.cubic_pa == 0.0 {
        l.tau_max_pa
    } else {
        l.tau_max_pa
            .max(l.peak_stress_pa(problem.config.temperature.a_coeff_pa(0.0)))
    };
    let limit = problem.config.numerics.runaway_stress_factor * scale;
    // A node whose order a noise kick raised above the solid's φ0 carries proportionally
    // more: a·φ²·ε at the same strain. Its limit grows with (φ/φ0)², so that only a stress
    // beyond what its own order can hold counts as running away (hard case 7: σ = 1e6
    // kicks φ to ~300, and the graded grid's edge node then holds 15·τmax legitimately).
    let phi0 = l.solid_phi(0.0, problem.config.temperature.a_coeff_pa(0.0));
    let order_factor = |phi: f64| {
        if phi0 > 0.0 {
            (phi * phi / (phi0 * phi0)).max(1.0)
        } else {
            1.0
        }
    };
    let viscous = problem.config.lubricant.viscosity_pa_s > 0.0;
    // The film's elastic stress runs away, not the viscous one, which is the drive's rate:
    // with viscosity the limit applies to a·φ²·ε alone. Measured in units of the node's own
    // limit.
    let excess = |i: usize| {
        let phi = s.phi[i];
        let tau_film = if viscous {
            l.a_pa * phi * phi * s.eps[i]
        } else {
            s.tau_pa[i]
        };
        tau_film.abs() / order_factor(phi)
    };
    // The scan compares without dividing (|τ| against limit·max((φ/φ0)², 1)); the excesses
    // are computed only for a state that fails it.
    let scan = faer::traits::pulp::Arch::new().dispatch(NodeScan {
        n: s.phi.len(),
        limit,
        inv_phi0_sq: if phi0 > 0.0 { 1.0 / (phi0 * phi0) } else { 0.0 },
        film_stress: viscous.then_some((l.a_pa, s.eps.as_slice())),
        values: (&s.tau_pa, &s.phi, &s.u3d_m),
    });
    if !scan.all_finite {
        for (i, ((&tau, &phi), &u)) in s.tau_pa.iter().zip(&s.phi).zip(&s.u3d_m).enumerate() {
            for (q, v) in [("phi", phi), ("tau", tau), ("u3d", u)] {
                if !v.is_finite() {
                    return fail(i, q, v, non_finite_advice(&problem.config));
                }
            }
        }
    }
    let max_excess = if scan.beyond {
        (0..s.phi.len()).map(excess).fold(0.0_f64, f64::max)
    } else {
        0.0
    };
    // The first node with the largest excess (NaN never counts).
    let worst = if max_excess > limit {
        let i = (0..s.phi.len())
            .find(|&i| excess(i) == max_excess)
            .unwrap_or(0);
        (i, max_excess)
    } else {
        (0, max_excess)
    };
    if worst.1 > limit {
        return fail(
            worst.0,
            "tau",
            s.tau_pa[worst.0],
            format!(
                "|tau| exceeds numerics.runaway_stress_factor x {} = {limit:e} Pa{}: the \
                 solution is running away. {}",
                if l.cubic_pa == 0.0 {
                    "tau_max"
                } else {
                    "the stationary curve's peak"
                },
                if order_factor(s.phi[worst.0]) > 1.0 {
                    format!(" x (phi/phi0)^2 = {:e}", order_factor(s.phi[worst.0]))
                } else {
                    String::new()
                },
                runaway_advice(&problem.config)
            ),
        );
    }
    Ok(())
}

/// Advice on a stress beyond the runaway limit: with error-controlled steps a smaller step
/// changes nothing; the overshoot is the film lagging behind its equilibrium when sheared
/// faster than it relaxes, which the drive's strain rate against the film's rate says.
fn runaway_advice(config: &SimConfig) -> String {
    if config.time.scheme == Scheme::Literal || config.time.adaptive.is_none() {
        return non_finite_advice(config);
    }
    let l = &config.lubricant;
    let v0 = match config.drive {
        crate::drive::Drive::Spring(s) => s.velocity_m_per_s,
        crate::drive::Drive::Rigid(r) => r.velocity_m_per_s,
    };
    let strain_rate = v0.abs() / config.contact.film_thickness_m;
    let a = config.temperature.a_coeff_pa(0.0).abs();
    let relaxation = l.gamma_per_pa_s * a * crate::config::Derived::of(config).b_pa / l.a_pa;
    format!(
        "The steps are error-controlled, so a smaller time.dt changes nothing. A stress above \
         tau_max is the film lagging behind its equilibrium when it is sheared faster than it \
         relaxes: here the drive's strain rate |V0|/h0 = {strain_rate:.3e} 1/s against the \
         film's relaxation rate gamma*|A|*b/a = {relaxation:.3e} 1/s. If that overshoot is the \
         physics you want, raise numerics.runaway_stress_factor (now {}); otherwise check the \
         scene's parameters.",
        config.numerics.runaway_stress_factor
    )
}

fn non_finite_advice(config: &SimConfig) -> String {
    match config.time.scheme {
        Scheme::Literal => "The literal scheme is unstable here (explicit Euler beyond its \
                            stability limit, or a lagged elastic sweep with contraction factor \
                            >= 1): reduce time.dt or use time.scheme = \"accurate\"."
            .to_string(),
        Scheme::Accurate => "Reduce time.dt or check the scene's parameters.".to_string(),
    }
}

/// An area fraction summed from `count` of the `n` nodes' weights: exactly 1 when every node
/// counts (the midpoint weights sum to 1 only to rounding on the graded grid, and "the whole
/// contact melted" must read as 1).
pub(super) fn whole_area(sum: f64, count: usize, n: usize) -> f64 {
    if count == n { 1.0 } else { sum }
}

/// [`check_state`]'s pass over the nodes under the CPU's best instruction set (pulp's
/// run-time dispatch), written so that it vectorises: whether every φ, τ and u3D is finite,
/// and whether any node's stress may exceed its runaway limit (|τ| against
/// limit·max((φ/φ0)², 1), multiplied out; a NaN never counts).
struct NodeScan<'a> {
    n: usize,
    limit: f64,
    /// 1/φ0² (0 without a solid φ0: every node's limit is then `limit`).
    inv_phi0_sq: f64,
    /// With viscosity: a and ε, for the film's elastic stress a·φ²·ε in place of τ.
    film_stress: Option<(f64, &'a [f64])>,
    values: (&'a [f64], &'a [f64], &'a [f64]),
}

/// What [`NodeScan`] found.
struct Scanned {
    all_finite: bool,
    beyond: bool,
}

impl faer::traits::pulp::WithSimd for NodeScan<'_> {
    type Output = Scanned;

    #[inline(always)]
    fn with_simd<S: faer::traits::pulp::Simd>(self, _simd: S) -> Scanned {
        let (tau, phi, u3d) = self.values;
        let (tau, phi, u3d) = (&tau[..self.n], &phi[..self.n], &u3d[..self.n]);
        let mut finite = true;
        let mut beyond = false;
        let bound = |p: f64| self.limit * (p * p * self.inv_phi0_sq).max(1.0);
        match self.film_stress {
            None => {
                for i in 0..self.n {
                    // `&`, not `&&`: no early exit, so the loop vectorises.
                    finite &= tau[i].is_finite() & phi[i].is_finite() & u3d[i].is_finite();
                    beyond |= tau[i].abs() > bound(phi[i]);
                }
            }
            Some((a, eps)) => {
                let eps = &eps[..self.n];
                for i in 0..self.n {
                    finite &= tau[i].is_finite() & phi[i].is_finite() & u3d[i].is_finite();
                    beyond |= (a * phi[i] * phi[i] * eps[i]).abs() > bound(phi[i]);
                }
            }
        }
        Scanned {
            all_finite: finite,
            beyond,
        }
    }
}
