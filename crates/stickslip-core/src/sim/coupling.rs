//! The quasi-static elastic coupling u3D = (a/(h0·G*))·C·diag(φ²)·(u0 − u3D), solved per step.
//!
//! Writing K = κ·C·D with κ = a/(h0·G*), C the MDR compliance (back∘forward) and D = diag(φ²),
//! the substrate displacement satisfies (I + K)·u3D = K·u0. The paper's lagged sweep
//! u3D ← K·(u0 − u3D_prev) is a fixed-point iteration of this system: it contracts only when
//! the spectral radius ρ(K) < 1. The accurate scheme instead solves the system with BiCGSTAB
//! (faer's matrix-free solver), warm-started from the previous step: K has a non-negative
//! spectrum (C is an elastic compliance), so I + K has eigenvalues in [1, 1 + ρ] and the
//! solve converges whatever ρ is.

use crate::mdr::MdrOperators;
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

/// Reusable workspace of the coupling solve.
pub struct CouplingSolver {
    n: usize,
    buffer: MemBuffer,
    scratch: Mutex<Scratch>,
    rhs: faer::Mat<f64>,
    sol: faer::Mat<f64>,
}

impl std::fmt::Debug for CouplingSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CouplingSolver")
            .field("n", &self.n)
            .finish_non_exhaustive()
    }
}

/// Outcome of one coupling solve.
#[derive(Debug, Clone, Copy)]
pub struct CouplingReport {
    /// BiCGSTAB iterations.
    pub iterations: usize,
    /// Final relative residual.
    pub rel_residual: f64,
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
            rhs: faer::Mat::zeros(n, 1),
            sol: faer::Mat::zeros(n, 1),
        }
    }

    /// Solves (I + κ·C·diag(φ²))·u3d = κ·C·diag(φ²)·u0 in place, starting from `u3d`.
    pub fn solve(
        &mut self,
        ops: &MdrOperators,
        phi_sq: &[f64],
        kappa: f64,
        u0: &[f64],
        u3d: &mut [f64],
        rel_tol: f64,
    ) -> CouplingReport {
        let n = self.n;
        let op = CouplingOperator {
            ops,
            phi_sq,
            kappa,
            scratch: &self.scratch,
        };
        {
            let mut guard = self.scratch.lock().expect("coupling scratch poisoned");
            let Scratch { dx, q, y: b, .. } = &mut *guard;
            apply_k(ops, phi_sq, kappa, u0, dx, q, b);
            for i in 0..n {
                self.rhs[(i, 0)] = b[i];
                self.sol[(i, 0)] = u3d[i];
            }
        }
        let params = BicgParams {
            initial_guess: InitialGuessStatus::MaybeNonZero,
            abs_tolerance: 0.0,
            rel_tolerance: rel_tol,
            max_iters: 500,
            ..Default::default()
        };
        let stack = MemStack::new(&mut self.buffer);
        let result = bicgstab(
            self.sol.as_mut(),
            IdentityPrecond { dim: n },
            IdentityPrecond { dim: n },
            &op,
            self.rhs.as_ref(),
            params,
            |_| {},
            Par::Seq,
            stack,
        );
        for (i, u) in u3d.iter_mut().enumerate() {
            *u = self.sol[(i, 0)];
        }
        match result {
            Ok(info) => CouplingReport {
                iterations: info.iter_count,
                rel_residual: info.rel_residual,
                converged: true,
            },
            Err(faer::matrix_free::bicgstab::BicgError::NoConvergence { rel_residual, .. }) => {
                CouplingReport {
                    iterations: params.max_iters,
                    rel_residual,
                    converged: false,
                }
            }
        }
    }
}
