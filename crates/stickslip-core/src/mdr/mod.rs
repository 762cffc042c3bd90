//! Method of dimensionality reduction (MDR) operators, paper Eq. 13–16, on the grid of [`crate::grid`].
//!
//! Continuous operators (a0 the contact radius, G* the effective shear modulus):
//! - forward  q(x) = 2 ∫_x^a0 r τ(r) / √(r² − x²) dr                 (Eq. 13, Pa → N/m)
//! - back     u3D(r) = (2/π) ∫_0^r u1D(x) / √(r² − x²) dx            (Eq. 15, m → m)
//! - compliance u3D = back(forward(τ)) / G*                          (Eq. 13–15, Pa → m)
//! - forces   F = 2 ∫_0^a0 q dx = 2π ∫_0^a0 τ r dr                    (Eq. 16, N)
//!
//! Two quadratures ([`Quadrature`]):
//! - [`Quadrature::Literal`]: the paper's plain sums with weight h that skip the
//!   singular term (see [`literal`]); converges at order ½ at best;
//! - [`Quadrature::Product`]: product integration, the kernel 1/√(r² − x²) integrated
//!   exactly on each cell against piecewise-linear data (see [`product`]); second order
//!   on smooth data.
//!
//! Both are stored as packed triangular matrices ([`TriangularOperator`]) and applied
//! as mat-vecs ([`OperatorForm::Dense`]), or built straight from entries computed on demand
//! ([`OperatorEntries`]) into the hierarchical form of [`hodlr`] ([`OperatorForm::Fast`],
//! O(N log N) memory: the packed matrices then exist only if asked for);
//! [`MdrOperators::compliance_dense`] gives the composite as a faer matrix.
//!
//! In the fast form from [`PAIR_MIN_NODES`] nodes, [`MdrOperators::compliance`] runs on two
//! threads where the run has a core to spare (`paired`): each applies both transforms to
//! half the rows, with the one-thread apply's bits.

mod entries;
pub mod hodlr;
pub mod literal;
mod paired;
pub use paired::PAIR_MIN_NODES;
pub mod pairs;
pub mod product;
mod triangular;

pub use entries::{OperatorEntries, probe_norm_lower_bound};
pub use triangular::{Triangle, TriangularOperator};

use crate::grid::Grid;
use faer::Mat;
use std::sync::{Arc, OnceLock};

/// Which discretisation of the MDR integrals to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Quadrature {
    /// The paper's plain sums (weight h, singular term skipped).
    Literal,
    /// Product integration: exact kernel integrals against piecewise-linear data.
    Product,
}

/// How the transforms are applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OperatorForm {
    /// Packed triangular mat-vec, O(N²) per apply (row-parallel from 512 nodes).
    Dense,
    /// Hierarchical low-rank form ([`hodlr`]) compressed to [`FAST_REL_TOL`], O(N) per apply,
    /// built from sampled entries without the dense matrices (O(N log N) time and memory).
    Fast,
}

/// Relative tolerance of the fast form: ‖A·x − Ã·x‖ ≲ C·tol·‖A‖·‖x‖ with C ≈ 25 at N = 2000
/// (see [`hodlr::HodlrOperator::error_bound_factor`]; measured ‖A − Ã‖₂ 2–4·tol·‖A‖₂ for
/// N ≤ 4000), far below the quadrature's own error.
pub const FAST_REL_TOL: f64 = 1e-10;

/// The compressed operators and their work space.
#[derive(Debug)]
struct FastForms {
    forward: Arc<hodlr::HodlrOperator>,
    back: Arc<hodlr::HodlrOperator>,
    forward_scratch: std::sync::Mutex<hodlr::HodlrScratch>,
    back_scratch: std::sync::Mutex<hodlr::HodlrScratch>,
    /// The compliance on two threads ([`paired`]), decided at the first compliance: `None`
    /// where it does not pay (or from a rayon worker); a call that finds it busy (another
    /// thread's apply) takes the one-thread path, with the same bits.
    paired: OnceLock<Option<std::sync::Mutex<paired::PairedCompliance>>>,
}

/// The MDR operators for one grid and one quadrature, built once and applied per step.
#[derive(Debug, Clone)]
pub struct MdrOperators {
    grid: Grid,
    quadrature: Quadrature,
    /// The packed operators: built by [`Self::new`], or on first request in the fast form.
    forward: OnceLock<TriangularOperator>,
    back: OnceLock<TriangularOperator>,
    fast: Option<Box<FastForms>>,
    force_3d_m2: Vec<f64>,
    force_1d_m: Vec<f64>,
    /// Fᵀ·c, the 1D force's weights on τ ([`Self::force_1d_from_tau_n`]), m²: on first use.
    force_1d_tau_m2: OnceLock<Vec<f64>>,
}

impl MdrOperators {
    /// Builds all operators for `grid` with `quadrature`: O(N²) time and memory
    /// ([`Self::dense_bytes`]).
    pub fn new(grid: Grid, quadrature: Quadrature) -> Self {
        let (forward, back) = match quadrature {
            Quadrature::Literal => (literal::forward(&grid), literal::back(&grid)),
            Quadrature::Product => (product::forward(&grid), product::back(&grid)),
        };
        let mut ops = Self::without_dense(grid, quadrature);
        ops.forward = OnceLock::from(forward);
        ops.back = OnceLock::from(back);
        ops
    }

    /// The force weights, no transform yet.
    fn without_dense(grid: Grid, quadrature: Quadrature) -> Self {
        let (force_3d_m2, force_1d_m) = match quadrature {
            Quadrature::Literal => (
                literal::force_3d_weights(&grid),
                literal::force_1d_weights(&grid),
            ),
            Quadrature::Product => (
                product::force_3d_weights(&grid),
                product::force_1d_weights(&grid),
            ),
        };
        Self {
            grid,
            quadrature,
            forward: OnceLock::new(),
            back: OnceLock::new(),
            fast: None,
            force_3d_m2,
            force_1d_m,
            force_1d_tau_m2: OnceLock::new(),
        }
    }

    /// As [`MdrOperators::new`], applied in `form`. The fast form is built from entries
    /// computed on demand (O(N log N) time, O(N·r·log N) memory; forward and back side by
    /// side where threads are free, with the same result either way) and stores no dense
    /// operator: [`Self::forward_operator`], [`Self::back_operator`] and
    /// [`Self::compliance_dense`] build one on first call.
    pub fn with_form(grid: Grid, quadrature: Quadrature, form: OperatorForm) -> Self {
        if form == OperatorForm::Dense {
            return Self::new(grid, quadrature);
        }
        let mut ops = Self::without_dense(grid, quadrature);
        let (forward, back) = match quadrature {
            Quadrature::Literal => rayon::join(
                || hodlr::HodlrOperator::build(&literal::ForwardEntries::new(grid), FAST_REL_TOL),
                || hodlr::HodlrOperator::build(&literal::BackEntries::new(grid), FAST_REL_TOL),
            ),
            Quadrature::Product => rayon::join(
                || hodlr::HodlrOperator::build(&product::ForwardEntries::new(grid), FAST_REL_TOL),
                || hodlr::HodlrOperator::build(&product::BackEntries::new(grid), FAST_REL_TOL),
            ),
        };
        ops.fast = Some(Box::new(FastForms {
            forward_scratch: std::sync::Mutex::new(forward.scratch()),
            back_scratch: std::sync::Mutex::new(back.scratch()),
            forward: Arc::new(forward),
            back: Arc::new(back),
            paired: OnceLock::new(),
        }));
        ops
    }

    /// Bytes the two packed dense operators of N nodes take (8·N(N + 1)): what
    /// [`Self::new`] allocates, and what [`Self::forward_operator`] plus
    /// [`Self::back_operator`] allocate in the fast form (e.g. 32 MB at N = 2000,
    /// 320 GB at N = 200 000). Saturates instead of overflowing.
    pub fn dense_bytes(nodes: usize) -> usize {
        nodes
            .saturating_mul(nodes.saturating_add(1))
            .saturating_mul(8)
    }

    /// Whether the packed operators exist: always in the dense form; in the fast form only
    /// after [`Self::forward_operator`], [`Self::back_operator`] or
    /// [`Self::compliance_dense`] (then [`Self::dense_bytes`] more are held).
    pub fn has_dense_operators(&self) -> bool {
        self.forward.get().is_some() || self.back.get().is_some()
    }

    /// Bytes held by the fast form's factors (0 in the dense form).
    pub fn fast_bytes(&self) -> usize {
        self.fast.as_ref().map_or(0, |f| {
            8 * (f.forward.stored_entries() + f.back.stored_entries())
        })
    }

    /// The fast operators (forward, back), if this is the fast form.
    pub fn fast_operators(&self) -> Option<(&hodlr::HodlrOperator, &hodlr::HodlrOperator)> {
        self.fast.as_ref().map(|f| (&*f.forward, &*f.back))
    }

    /// Threads the compliance runs on: 2 once a first [`Self::compliance`] found the fast
    /// form large enough and a core free for its helper (see [`PAIR_MIN_NODES`]), else 1.
    /// Either way the bits are the same.
    pub fn compliance_threads(&self) -> usize {
        match self.fast.as_ref().and_then(|f| f.paired.get()) {
            Some(Some(_)) => 2,
            _ => 1,
        }
    }

    /// The form the transforms are applied in.
    pub fn form(&self) -> OperatorForm {
        if self.fast.is_some() {
            OperatorForm::Fast
        } else {
            OperatorForm::Dense
        }
    }

    fn apply_forward(&self, x: &[f64], y: &mut [f64]) {
        match &self.fast {
            Some(f) => f.forward.apply(x, y, &mut lock(&f.forward_scratch)),
            None => apply_sized(self.forward_operator(), x, y),
        }
    }

    fn apply_back(&self, x: &[f64], y: &mut [f64]) {
        match &self.fast {
            Some(f) => f.back.apply(x, y, &mut lock(&f.back_scratch)),
            None => apply_sized(self.back_operator(), x, y),
        }
    }

    /// The grid the operators live on.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The quadrature they were built with.
    pub fn quadrature(&self) -> Quadrature {
        self.quadrature
    }

    /// Forward transform (Eq. 13): `q_out[j] ≈ q(x_j) = 2∫_{x_j}^{a0} r τ(r)/√(r² − x_j²) dr`.
    ///
    /// # Panics
    /// If `tau_pa.len()` or `q_out_n_per_m.len()` differs from N.
    #[track_caller]
    pub fn forward(&self, tau_pa: &[f64], q_out_n_per_m: &mut [f64]) {
        self.apply_forward(tau_pa, q_out_n_per_m);
    }

    /// Back transform (Eq. 15): `u3d_out[i] ≈ (2/π)∫_0^{r_i} u1D(x)/√(r_i² − x²) dx`
    /// (at r = 0 the product scheme returns the limit u1D(0)).
    ///
    /// # Panics
    /// If `u1d_m.len()` or `u3d_out_m.len()` differs from N.
    #[track_caller]
    pub fn back(&self, u1d_m: &[f64], u3d_out_m: &mut [f64]) {
        self.apply_back(u1d_m, u3d_out_m);
    }

    /// Composite compliance without the modulus: `out = back(forward(τ))` in Pa·m,
    /// so that u3D = out / G*. `scratch` (length N) receives q.
    ///
    /// # Panics
    /// If any slice length differs from N.
    #[track_caller]
    pub fn compliance(&self, tau_pa: &[f64], scratch_q: &mut [f64], out_pa_m: &mut [f64]) {
        if let Some(f) = &self.fast {
            let pair = f.paired.get_or_init(|| {
                paired::PairedCompliance::new_if_useful(&f.forward, &f.back)
                    .map(std::sync::Mutex::new)
            });
            if let Some(Ok(mut pair)) = pair.as_ref().map(std::sync::Mutex::try_lock)
                && pair.usable()
            {
                let n = self.grid.nodes();
                assert!(
                    tau_pa.len() == n && scratch_q.len() == n && out_pa_m.len() == n,
                    "vector lengths must equal the node count"
                );
                let (mut fs, mut bs) = (lock(&f.forward_scratch), lock(&f.back_scratch));
                pair.compliance((tau_pa, scratch_q, out_pa_m), (&mut fs, &mut bs));
                return;
            }
        }
        self.apply_forward(tau_pa, scratch_q);
        self.apply_back(scratch_q, out_pa_m);
    }

    /// F = 2π∫τ r dr as Σ w_i τ_i (Eq. 16, 3D form), in N.
    ///
    /// # Panics
    /// If `tau_pa.len()` differs from N.
    #[track_caller]
    pub fn force_3d_n(&self, tau_pa: &[f64]) -> f64 {
        dot(&self.force_3d_m2, tau_pa)
    }

    /// F = 2∫q dx as Σ c_j q_j (Eq. 16, 1D form), in N.
    ///
    /// # Panics
    /// If `q_n_per_m.len()` differs from N.
    #[track_caller]
    pub fn force_1d_n(&self, q_n_per_m: &[f64]) -> f64 {
        dot(&self.force_1d_m, q_n_per_m)
    }

    /// F = 2∫q dx with q = forward(τ) (Eq. 13 and 16, 1D form), in N, as Σ v_i τ_i with
    /// v = Fᵀ·c ([`Self::force_1d_tau_weights_m2`]): the same discrete quantity as
    /// `force_1d_n(forward(τ))`, equal to rounding and the fast form's compression
    /// (‖Ã − A‖ ≈ 1e-10·‖A‖), without a transform per call.
    ///
    /// Why: the series writes F_1d beside F at every row, and a forward transform per row
    /// was 8 % of fig2's run at N = 2000.
    ///
    /// # Panics
    /// If `tau_pa.len()` differs from N.
    #[track_caller]
    pub fn force_1d_from_tau_n(&self, tau_pa: &[f64]) -> f64 {
        dot(self.force_1d_tau_weights_m2(), tau_pa)
    }

    /// v = Fᵀ·c, the weights of [`Self::force_1d_from_tau_n`], m² (computed on first call:
    /// one transposed forward transform).
    pub fn force_1d_tau_weights_m2(&self) -> &[f64] {
        self.force_1d_tau_m2.get_or_init(|| {
            let mut v = vec![0.0; self.force_1d_m.len()];
            match &self.fast {
                Some(f) => f.forward.apply_transpose(&self.force_1d_m, &mut v),
                None => self
                    .forward_operator()
                    .apply_transpose(&self.force_1d_m, &mut v),
            }
            v
        })
    }

    /// Weights w_i of the 3D force, F = Σ w_i τ_i, in m².
    pub fn force_3d_weights_m2(&self) -> &[f64] {
        &self.force_3d_m2
    }

    /// Weights c_j of the 1D force, F = Σ c_j q_j, in m.
    pub fn force_1d_weights_m(&self) -> &[f64] {
        &self.force_1d_m
    }

    /// The forward operator in packed form. In the fast form it is built on first call
    /// (O(N²) time and [`Self::dense_bytes`]/2 memory, kept for later calls): for analysis
    /// and tests; the transforms themselves never need it.
    pub fn forward_operator(&self) -> &TriangularOperator {
        self.forward.get_or_init(|| match self.quadrature {
            Quadrature::Literal => literal::forward(&self.grid),
            Quadrature::Product => product::forward(&self.grid),
        })
    }

    /// The back operator in packed form (in the fast form built on first call, as
    /// [`Self::forward_operator`]).
    pub fn back_operator(&self) -> &TriangularOperator {
        self.back.get_or_init(|| match self.quadrature {
            Quadrature::Literal => literal::back(&self.grid),
            Quadrature::Product => product::back(&self.grid),
        })
    }

    /// The composite back·forward of the packed operators as a dense faer matrix (Pa·m per
    /// Pa; divide by G*), also in the fast form (then building the packed operators first).
    /// O(N³) to build: meant for analysis (spectral radius, direct solves at small N).
    pub fn compliance_dense(&self) -> Mat<f64> {
        let f = self.forward_operator().to_dense();
        let b = self.back_operator().to_dense();
        let mut c = Mat::<f64>::zeros(f.nrows(), f.ncols());
        faer::linalg::matmul::matmul(
            c.as_mut(),
            faer::Accum::Replace,
            b.as_ref(),
            f.as_ref(),
            1.0,
            faer::Par::Seq,
        );
        c
    }
}

/// Below this size a mat-vec is too short to pay for sharing it among threads.
const PARALLEL_MIN_NODES: usize = 512;

/// Sequential or row-parallel apply by size; both give identical bits.
#[track_caller]
fn apply_sized(op: &TriangularOperator, x: &[f64], y: &mut [f64]) {
    if op.size() >= PARALLEL_MIN_NODES {
        op.apply_par(x, y);
    } else {
        op.apply(x, y);
    }
}

#[track_caller]
/// F = 2π∫τ r dr (Eq. 16) on `grid` with the weights of `quadrature`, in N, without building
/// any operator: O(N) time and memory. Equal, bit for bit, to
/// [`MdrOperators::force_3d_n`] of operators on the same grid and quadrature.
///
/// # Panics
/// If `tau_pa.len()` differs from the grid's node count.
#[must_use]
pub fn force_3d_n(grid: &Grid, quadrature: Quadrature, tau_pa: &[f64]) -> f64 {
    let weights = match quadrature {
        Quadrature::Literal => literal::force_3d_weights(grid),
        Quadrature::Product => product::force_3d_weights(grid),
    };
    dot(&weights, tau_pa)
}

fn dot(w: &[f64], v: &[f64]) -> f64 {
    assert_eq!(w.len(), v.len(), "vector length must equal the node count");
    crate::sums::dot(w, v)
}

impl Clone for FastForms {
    fn clone(&self) -> Self {
        Self {
            forward_scratch: std::sync::Mutex::new(self.forward.scratch()),
            back_scratch: std::sync::Mutex::new(self.back.scratch()),
            forward: Arc::clone(&self.forward),
            back: Arc::clone(&self.back),
            paired: OnceLock::new(),
        }
    }
}

/// The scratch of a fast operator; a poisoned lock still holds usable work space (it is
/// overwritten by every apply).
fn lock(
    m: &std::sync::Mutex<hodlr::HodlrScratch>,
) -> std::sync::MutexGuard<'_, hodlr::HodlrScratch> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}
