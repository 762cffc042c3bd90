//! The quasi-static elastic coupling u3D = (a/(h0·G*))·C·diag(φ²)·(u0 − u3D), solved per step.
//!
//! Writing K = κ·C·D with κ = a/(h0·G*), C the MDR compliance (back∘forward) and D = diag(φ²),
//! the substrate displacement satisfies (I + K)·u3D = K·u0. The paper's lagged sweep
//! u3D ← K·(u0 − u3D_prev) is a fixed-point iteration of this system: it contracts only when
//! the spectral radius ρ(K) < 1. The accurate scheme instead solves the system, starting from
//! the quadratic extrapolation of the last three steps, which often meets the tolerance
//! already and is then only checked; a guess that misses is corrected by minimal-residual
//! steps where a few suffice (a soft coupling, ρ ≤ 2), else by BiCGSTAB (faer's matrix-free
//! solver). K has a non-negative spectrum (C is an elastic compliance), so I + K has
//! eigenvalues in [1, 1 + ρ] and the solve converges whatever ρ is.

use crate::mdr::MdrOperators;
use crate::sums;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::matrix_free::bicgstab::{BicgParams, bicgstab, bicgstab_scratch};
use faer::matrix_free::{IdentityPrecond, InitialGuessStatus, LinOp};
use faer::{MatMut, MatRef, Par};
use std::sync::Mutex;

/// Work vectors of one operator application: D·x, q, x and the result.
#[derive(Debug)]
struct Scratch {
    dx: Vec<f64>,
    q: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
}

impl Scratch {
    fn new(n: usize) -> Self {
        Self {
            dx: vec![0.0; n],
            q: vec![0.0; n],
            x: vec![0.0; n],
            y: vec![0.0; n],
        }
    }
}

/// (I + κ·C·D) as a faer linear operator.
#[derive(Debug)]
struct CouplingOperator<'a> {
    ops: &'a MdrOperators,
    phi_sq: &'a [f64],
    kappa: f64,
    /// Scratch for D·x and for q; a Mutex only because faer requires `Sync`.
    scratch: &'a Mutex<Scratch>,
}

/// out = κ·C·(φ² ∘ x), with `dx` and `q` as scratch.
fn apply_k(
    ops: &MdrOperators,
    phi_sq: &[f64],
    kappa: f64,
    x: &[f64],
    dx: &mut [f64],
    q: &mut [f64],
    out: &mut [f64],
) {
    for ((d, &p), &xi) in dx.iter_mut().zip(phi_sq).zip(x) {
        *d = kappa * p * xi;
    }
    ops.compliance(dx, q, out);
}

impl LinOp<f64> for CouplingOperator<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        self.phi_sq.len()
    }
    fn ncols(&self) -> usize {
        self.phi_sq.len()
    }
    fn apply(
        &self,
        mut out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        _par: Par,
        _stack: &mut MemStack,
    ) {
        let mut guard = self.scratch.lock().expect("coupling scratch poisoned");
        let Scratch { dx, q, x, y } = &mut *guard;
        for col in 0..rhs.ncols() {
            // BiCGSTAB's vectors are contiguous columns: read and write them as slices,
            // without a copy or an index check per element.
            if rhs.row_stride() == 1 && out.row_stride() == 1 {
                let src = rhs.col(col).try_as_col_major().expect("unit stride");
                let dst = out.as_mut().col_mut(col).try_as_col_major_mut();
                let (src, dst) = (src.as_slice(), dst.expect("unit stride").as_slice_mut());
                apply_k(self.ops, self.phi_sq, self.kappa, src, dx, q, y);
                for ((d, &s), &yi) in dst.iter_mut().zip(src).zip(y.iter()) {
                    *d = s + yi;
                }
                continue;
            }
            for (i, xi) in x.iter_mut().enumerate() {
                *xi = rhs[(i, col)];
            }
            apply_k(self.ops, self.phi_sq, self.kappa, x, dx, q, y);
            for i in 0..x.len() {
                out[(i, col)] = x[i] + y[i];
            }
        }
    }
    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        self.apply(out, rhs, par, stack);
    }
}

/// A guess that misses the tolerance by less than this factor is followed by a solve to
/// [`DEEP_SOLVE`] of the tolerance; one that misses by more, by a solve to the tolerance.
///
/// Why: the guess extrapolates the last three solutions with weights 3, −3, 1, so it carries
/// their residuals, amplified up to 7×, besides the extrapolation's own truncation error.
/// With fixed steps the truncation is far below the tolerance and the carried residuals are
/// what the guess misses by: solved only to the tolerance, every guess missed (fig2 at
/// N = 2000 in its stick phase, Δt = 2e-8 s: guesses at 2.6–6.1 times the tolerance, none
/// passing, 2.4 compliance applies per step); solved to a tenth of it, 80 % pass and a step
/// takes 1.19 applies (1.38 when BiCGSTAB did the deeper solve, see
/// [`CouplingSolver::minimal_residual`]). With adaptive steps a guess that misses is mostly
/// far off (the truncation dominates: fig2 as shipped, median 4.3, 90th percentile 7e5 times the
/// tolerance), and there the deeper solve did not pay: the smaller residual, which enters
/// the step's error estimate, moved the steps (the SFA contact of `cargo xtask bench`'s P7:
/// 3 % fewer evaluations but 26 % more coupling iterations, and the first onset 12.8 µs
/// from the tight reference instead of 4.1 µs). So only fixed steps take it
/// ([`CouplingTolerance::deepen_near_misses`]); adaptive runs keep their bits.
const NEAR_MISS: f64 = 10.0;

/// The depth, relative to the tolerance, of the solve after a near miss ([`NEAR_MISS`]).
const DEEP_SOLVE: f64 = 0.1;

/// Minimal-residual steps tried before BiCGSTAB takes over
/// ([`CouplingSolver::minimal_residual`]).
const MR_STEPS: usize = 3;

/// The largest contraction per minimal-residual step, ρ/(2 + ρ), for which they are tried:
/// on a stiff coupling (the h0 = 1 nm contact: ρ ≈ 52, 0.96 per step) they barely move the
/// residual, and where three just suffice they end nearer the tolerance than BiCGSTAB, whose
/// last iteration overshoots it; the residual enters the adaptive step's error estimate, and
/// P7's run took 0.8 % more evaluations with them.
const MR_MAX_CONTRACTION: f64 = 0.5;

/// Reusable workspace of the coupling solve.
pub struct CouplingSolver {
    n: usize,
    buffer: MemBuffer,
    scratch: Mutex<Scratch>,
    /// The correction's right-hand side and solution, BiCGSTAB's single columns.
    rhs: Vec<f64>,
    sol: Vec<f64>,
}

impl std::fmt::Debug for CouplingSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CouplingSolver")
            .field("n", &self.n)
            .finish_non_exhaustive()
    }
}

/// What a coupling solve must reach, and what it knows of the operator.
#[derive(Debug, Clone, Copy)]
pub struct CouplingTolerance {
    /// ‖K·(u0 − u) − u‖ ≤ `rel_tol`·‖u‖ at the end (`numerics.coupling_tol`) …
    pub rel_tol: f64,
    /// … or the residual's root mean square over the nodes ≤ this, m: the displacement
    /// whose strain the step's error estimate tolerates anyway (0: none; see
    /// `Simulation::coupling_tolerance`).
    pub abs_rms_m: f64,
    /// ρ ≥ the spectral radius of K (the lagged sweep's contraction factor); sets the relaxed
    /// correction of an accepted guess.
    pub spectral_bound: f64,
    /// Whether a guess that missed by less than [`NEAR_MISS`] is followed by a solve to
    /// [`DEEP_SOLVE`] of the tolerance (with fixed steps; see there).
    pub deepen_near_misses: bool,
}

/// Outcome of one coupling solve.
#[derive(Debug, Clone, Copy)]
pub struct CouplingReport {
    /// Minimal-residual steps and BiCGSTAB iterations.
    pub iterations: usize,
    /// Final relative residual.
    pub rel_residual: f64,
    /// The final residual's root mean square over the nodes, m (before an accepted guess's
    /// relaxed correction, which only shrinks it).
    pub rms_residual_m: f64,
    /// Whether the tolerance was met.
    pub converged: bool,
}

impl CouplingSolver {
    /// Workspace for `n` nodes.
    pub fn new(n: usize) -> Self {
        let req = bicgstab_scratch::<f64>(
            IdentityPrecond { dim: n },
            IdentityPrecond { dim: n },
            // Stands in for the coupling operator, whose own scratch is empty too.
            IdentityPrecond { dim: n },
            1,
            Par::Seq,
        );
        Self {
            n,
            buffer: MemBuffer::new(req),
            scratch: Mutex::new(Scratch::new(n)),
            rhs: vec![0.0; n],
            sol: vec![0.0; n],
        }
    }

    /// Solves (I + κ·C·diag(φ²))·u3d = κ·C·diag(φ²)·u0 in place, starting from the guess in
    /// `u3d`, to `tolerance` (whose names are used below: `rel_tol`, `rho`).
    ///
    /// The guess's residual r = K·(u0 − u) − u costs one application of K. When
    /// ‖r‖ ≤ `rel_tol`·‖u‖ the guess stands, improved by the relaxed correction
    /// u += r/(1 + ρ/2) (`rho` bounds K's real, non-negative spectrum, so the correction
    /// shrinks the error in every direction by at least (ρ/2)/(1 + ρ/2)); otherwise BiCGSTAB
    /// solves (I + K)·δ = r to the same absolute residual (to a tenth of it after a near miss,
    /// [`NEAR_MISS`]) and u += δ. Either way the
    /// returned u satisfies ‖K·(u0 − u) − u‖ ≤ `rel_tol`·‖u‖ (to rounding), or `converged`
    /// is false.
    ///
    /// Why the correction: an accepted guess's error enters the next three quadratic
    /// extrapolations with weights 3, −3, 1, a recursion with a triple root at 1, so uncorrected
    /// acceptances compound and only about one guess in three passes; shrunk by q < 1 per
    /// acceptance the recursion's roots lie inside the unit circle (q = 0.21 for fig2: 0.72).
    pub fn solve(
        &mut self,
        ops: &MdrOperators,
        phi_sq: &[f64],
        kappa: f64,
        u0: &[f64],
        u3d: &mut [f64],
        tolerance: CouplingTolerance,
    ) -> CouplingReport {
        let CouplingTolerance {
            rel_tol,
            abs_rms_m,
            spectral_bound: rho,
            deepen_near_misses,
        } = tolerance;
        let n = self.n;
        let abs_norm = abs_rms_m * (n as f64).sqrt();
        // A contact melted at every node has u0 = 0, and I + K is non-singular: u3D = 0 exactly
        // (and so F = 0). The relative criterion below cannot say so: it would shrink the
        // extrapolated guess by the tolerance each step, towards the underflow.
        if u0.iter().all(|&u| u == 0.0) {
            u3d.fill(0.0);
            return CouplingReport {
                iterations: 0,
                rel_residual: 0.0,
                rms_residual_m: 0.0,
                converged: true,
            };
        }
        let (r_norm, u_norm) = self.guess_residual(ops, (phi_sq, kappa), u0, u3d);
        if r_norm <= (rel_tol * u_norm).max(abs_norm) || r_norm == 0.0 {
            let relax = 1.0 / (1.0 + 0.5 * rho.max(0.0));
            for (u, &r) in u3d.iter_mut().zip(&self.rhs) {
                *u += relax * r;
            }
            return CouplingReport {
                iterations: 0,
                rel_residual: if u_norm > 0.0 { r_norm / u_norm } else { 0.0 },
                rms_residual_m: r_norm / (n as f64).sqrt(),
                converged: true,
            };
        }
        // The correction's tolerance relative to ‖r‖ that makes the final residual
        // rel_tol·‖u‖ (relative to ‖r‖ = ‖K·u0‖ itself when u = 0, as at the first step), or
        // [`DEEP_SOLVE`] of it for a guess that missed by less than [`NEAR_MISS`] (see there),
        // which minimal-residual steps take first.
        let mut r_norm = r_norm;
        let mut steps_taken = 0;
        let target = if u_norm > 0.0 {
            let tol_norm = (rel_tol * u_norm).max(abs_norm);
            let deep = deepen_near_misses && r_norm <= NEAR_MISS * tol_norm;
            let goal = if deep {
                DEEP_SOLVE * tol_norm
            } else {
                tol_norm
            };
            // A minimal-residual step shrinks the residual by q = ρ/(2 + ρ) or better (I + K
            // has its spectrum in [1, 1 + ρ]); they are taken where each at least halves it
            // and [`MR_STEPS`] of them reach the goal.
            let q = rho.max(0.0) / (2.0 + rho.max(0.0));
            let mr_goal = (q <= MR_MAX_CONTRACTION && q.powi(MR_STEPS as i32) * r_norm <= goal)
                .then_some(goal);
            if let Some(goal) = mr_goal {
                match self.minimal_residual(ops, (phi_sq, kappa), u3d, (goal, rho)) {
                    Ok(report) => return report,
                    Err((norm, steps)) => (r_norm, steps_taken) = (norm, steps),
                }
            }
            (goal / r_norm).min(0.5)
        } else {
            rel_tol.max(abs_norm / r_norm).min(0.5)
        };
        let mut report = self.correct(ops, (phi_sq, kappa), u3d, (r_norm, target, rho));
        report.iterations += steps_taken;
        report
    }

    /// Minimal-residual steps u += α·r, α = (r, A·r)/‖A·r‖² with A = I + K, each one
    /// application of K that also gives the new residual r − α·A·r exactly, until
    /// ‖r‖ ≤ `goal`; then the relaxed correction of an accepted guess. When [`MR_STEPS`] steps
    /// do not get there: the residual's norm and the steps taken, with u3d and `rhs` (the
    /// residual) at the last step's values, for BiCGSTAB to finish.
    ///
    /// Why: the residual is in `rhs` already; BiCGSTAB spends one application recomputing it
    /// and two per iteration, a minimal-residual step one. With fixed steps a near miss needs
    /// a reduction of at most 10/[`DEEP_SOLVE`] (fig2 at N = 2000 in its stick phase:
    /// 1.38 → 1.19 applications per step at Δt = 2e-8 s, 1.42 → 1.21 at 1e-8 s); fig2 as
    /// shipped (adaptive) takes 2 % fewer evaluations and 4.5 % less wall time.
    fn minimal_residual(
        &mut self,
        ops: &MdrOperators,
        (phi_sq, kappa): (&[f64], f64),
        u3d: &mut [f64],
        (goal, rho): (f64, f64),
    ) -> Result<CouplingReport, (f64, usize)> {
        let n = self.n;
        let mut norm = f64::NAN;
        for step in 1..=MR_STEPS {
            let mut guard = self.scratch.lock().expect("coupling scratch poisoned");
            let Scratch { dx, q, x: _, y } = &mut *guard;
            apply_k(ops, phi_sq, kappa, &self.rhs, dx, q, y);
            let (y, rhs) = (&mut y[..n], &mut self.rhs[..n]);
            for (yi, &r) in y.iter_mut().zip(rhs.iter()) {
                *yi += r;
            }
            let (ra, aa) = sums::sum2_cols([rhs, y], |[r, y]| (r * y, y * y));
            if !(aa > 0.0 && ra.is_finite()) {
                return Err((sums::dot(rhs, rhs).sqrt(), step));
            }
            let alpha = ra / aa;
            for ((u, r), &a) in u3d.iter_mut().zip(rhs.iter_mut()).zip(y.iter()) {
                *u += alpha * *r;
                *r -= alpha * a;
            }
            norm = sums::dot(rhs, rhs).sqrt();
            if norm <= goal {
                let relax = 1.0 / (1.0 + 0.5 * rho.max(0.0));
                for (u, &r) in u3d.iter_mut().zip(rhs.iter()) {
                    *u += relax * r;
                }
                let u_final = sums::dot(u3d, u3d).sqrt();
                return Ok(CouplingReport {
                    iterations: step,
                    rel_residual: norm / u_final.max(f64::MIN_POSITIVE),
                    rms_residual_m: norm / (n as f64).sqrt(),
                    converged: true,
                });
            }
        }
        Err((norm, MR_STEPS))
    }

    /// The guess's residual r = K·(u0 − u) − u into `rhs`: ‖r‖ and ‖u‖.
    fn guess_residual(
        &mut self,
        ops: &MdrOperators,
        (phi_sq, kappa): (&[f64], f64),
        u0: &[f64],
        u3d: &[f64],
    ) -> (f64, f64) {
        let mut guard = self.scratch.lock().expect("coupling scratch poisoned");
        let Scratch { dx, q, x, y } = &mut *guard;
        let n = self.n;
        let (x, u0, u3d_in) = (&mut x[..n], &u0[..n], &u3d[..n]);
        for i in 0..n {
            x[i] = u0[i] - u3d_in[i];
        }
        apply_k(ops, phi_sq, kappa, x, dx, q, y);
        let (y, u3d, rhs) = (&y[..n], &u3d[..n], &mut self.rhs[..n]);
        for i in 0..n {
            rhs[i] = y[i] - u3d[i];
        }
        let (rr, uu) = sums::sum2_cols([rhs, u3d], |[r, u]| (r * r, u * u));
        (rr.sqrt(), uu.sqrt())
    }

    /// BiCGSTAB on (I + K)·δ = r (the residual of norm `r_norm` in `rhs`) to `target`
    /// relative to ‖r‖, and u3d += δ (see [`CouplingSolver::solve`]).
    fn correct(
        &mut self,
        ops: &MdrOperators,
        (phi_sq, kappa): (&[f64], f64),
        u3d: &mut [f64],
        (r_norm, target, rho): (f64, f64, f64),
    ) -> CouplingReport {
        let n = self.n;
        // BiCGSTAB's inner products square the residual: a film melted to φ ≈ 0.01 leaves
        // ‖r‖ ≈ 1e-150 m, whose squares underflow and turn the iteration into 0/0 (hard case
        // 4b). The system is linear, so solve for r/2^e with 2^e ≈ ‖r‖: scaling by a power of
        // two is exact in every operation, so results are unchanged wherever nothing underflows.
        let exponent = r_norm.log2().round().clamp(-1000.0, 1000.0) as i64;
        let to_unit = f64::from_bits(((1023 - exponent) as u64) << 52);
        let from_unit = f64::from_bits(((1023 + exponent) as u64) << 52);
        // BiCGSTAB starts from the relaxed correction δ0 = r/(1 + ρ/2) rather than from 0: its
        // first application of the operator then gives the residual of δ0, which often meets
        // the tolerance already (no iteration), and otherwise starts the iteration closer than
        // the residual of 0 would, which is r itself and costs the same application.
        let relax = 1.0 / (1.0 + 0.5 * rho.max(0.0));
        for (r, d) in self.rhs.iter_mut().zip(&mut self.sol) {
            *r *= to_unit;
            *d = relax * *r;
        }
        let op = CouplingOperator {
            ops,
            phi_sq,
            kappa,
            scratch: &self.scratch,
        };
        // `MaybeNonZero`: faer 0.24's `Zero` leaves its residual vector uninitialised (it never
        // copies b into it) and diverges; with δ0 above the first application is not wasted.
        let params = BicgParams {
            initial_guess: InitialGuessStatus::MaybeNonZero,
            abs_tolerance: 0.0,
            rel_tolerance: target,
            max_iters: 500,
            ..Default::default()
        };
        let stack = MemStack::new(&mut self.buffer);
        let result = bicgstab(
            MatMut::from_column_major_slice_mut(&mut self.sol, n, 1),
            IdentityPrecond { dim: n },
            IdentityPrecond { dim: n },
            &op,
            MatRef::from_column_major_slice(&self.rhs, n, 1),
            params,
            |_| {},
            Par::Seq,
            stack,
        );
        for (u, &s) in u3d.iter_mut().zip(&self.sol) {
            *u += s * from_unit;
        }
        // faer's residual is relative to ‖r‖; the criterion is relative to the solution's
        // norm (not the guess's, which is 0 at the first step).
        let u_final = sums::dot(u3d, u3d).sqrt();
        let scale = |r: f64| r * r_norm / u_final.max(f64::MIN_POSITIVE);
        let rms = |r: f64| r * r_norm / (n as f64).sqrt();
        match result {
            Ok(info) => CouplingReport {
                iterations: info.iter_count.max(1),
                rel_residual: scale(info.rel_residual),
                rms_residual_m: rms(info.rel_residual),
                converged: true,
            },
            Err(faer::matrix_free::bicgstab::BicgError::NoConvergence { rel_residual, .. }) => {
                CouplingReport {
                    iterations: params.max_iters,
                    rel_residual: scale(rel_residual),
                    rms_residual_m: rms(rel_residual),
                    converged: false,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
