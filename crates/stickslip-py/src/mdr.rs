//! `stickslip.mdr`: the MDR transforms of the core (Eq. 13–16) on NumPy arrays, in the style
//! of PyAbel's transforms: one function per transform, the grid implied by the array length.

use numpy::{AllowTypeChange, IntoPyArray, PyArray1, PyArrayLike1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::borrow::Cow;
use std::sync::{Arc, Mutex};
use stickslip_core::grid::Grid;
use stickslip_core::mdr::{MdrOperators, OperatorForm, Quadrature};

/// Operators kept for reuse: the most recent few (building costs O(N²)).
const CACHE_ENTRIES: usize = 2;
/// Operators above this size are built for the call and dropped (N² memory).
const CACHE_MAX_NODES: usize = 4096;

type Key = (u64, usize, OperatorForm, Quadrature);
static CACHE: Mutex<Vec<(Key, Arc<MdrOperators>)>> = Mutex::new(Vec::new());

fn form_of(form: &str) -> PyResult<OperatorForm> {
    match form {
        "dense" => Ok(OperatorForm::Dense),
        "fast" => Ok(OperatorForm::Fast),
        other => Err(PyValueError::new_err(format!(
            "form = {other:?}; allowed: \"dense\" (product integration applied as a mat-vec, \
             O(N²)) or \"fast\" (its hierarchical low-rank form, O(N), within 1e-10 relative)"
        ))),
    }
}

fn quadrature_of(q: &str) -> PyResult<Quadrature> {
    match q {
        "product" => Ok(Quadrature::Product),
        "literal" => Ok(Quadrature::Literal),
        other => Err(PyValueError::new_err(format!(
            "quadrature = {other:?}; allowed: \"product\" (product integration, second order) \
             or \"literal\" (the paper's plain sums)"
        ))),
    }
}

/// The operators for `n` nodes on radius `radius_m`, from the cache or built (without the
/// GIL).
fn operators(
    py: Python<'_>,
    radius_m: f64,
    n: usize,
    form: &str,
    quadrature: &str,
) -> PyResult<Arc<MdrOperators>> {
    let form = form_of(form)?;
    let quadrature = quadrature_of(quadrature)?;
    if n == 0 {
        return Err(PyValueError::new_err(
            "an empty array; allowed: at least one node value",
        ));
    }
    let grid = Grid::new(radius_m, n)
        .map_err(|e| PyValueError::new_err(format!("radius = {radius_m:e} m: {e}")))?;
    let key = (radius_m.to_bits(), n, form, quadrature);
    let lock = || {
        CACHE
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    };
    if let Some((_, ops)) = lock().iter().find(|(k, _)| *k == key) {
        return Ok(Arc::clone(ops));
    }
    let ops = Arc::new(py.detach(|| MdrOperators::with_form(grid, quadrature, form)));
    if n <= CACHE_MAX_NODES {
        let mut cache = lock();
        cache.retain(|(k, _)| *k != key);
        cache.insert(0, (key, Arc::clone(&ops)));
        cache.truncate(CACHE_ENTRIES);
    }
    Ok(ops)
}

/// The array's data: borrowed when contiguous, else copied once.
fn data<'a>(a: &'a PyArrayLike1<'_, f64, AllowTypeChange>) -> Cow<'a, [f64]> {
    match a.as_slice() {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(a.as_array().to_vec()),
    }
}

/// Forward MDR transform, Eq. 13: q(x) = 2 ∫ₓ^a0 r τ(r) / √(r² − x²) dr.
///
/// ``tau``: the shear stress τ in Pa at the N nodes r_i = i·radius/N, i = 0 … N−1 (1-D array
/// or sequence; the edge r = radius carries no node). ``radius``: the contact radius a0 in m.
/// Returns q in N/m at the same nodes x_i = r_i (a new float64 array).
///
/// ``form``: ``"dense"`` (default) or ``"fast"`` (hierarchical low-rank, O(N), within 1e-10
/// relative); ``quadrature``: ``"product"`` (default: the kernel integrated exactly against
/// piecewise-linear data, second order) or ``"literal"`` (the paper's sums).
/// Exact for uniform stress: τ = τc gives q = 2τc√(a0² − x²) to rounding.
#[pyfunction]
#[pyo3(signature = (tau, radius, *, form = "dense", quadrature = "product"))]
pub fn forward<'py>(
    py: Python<'py>,
    tau: PyArrayLike1<'py, f64, AllowTypeChange>,
    radius: f64,
    form: &str,
    quadrature: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = data(&tau);
    let ops = operators(py, radius, x.len(), form, quadrature)?;
    let mut out = vec![0.0; x.len()];
    ops.forward(&x, &mut out);
    Ok(out.into_pyarray(py))
}

/// Back MDR transform, Eq. 15: u3D(r) = (2/π) ∫₀^r u1D(x) / √(r² − x²) dx.
///
/// ``u1d``: the 1-D displacement u1D in m at the N nodes x_i = i·radius/N. ``radius``: a0 in
/// m. Returns u3D in m at r_i = x_i (at r = 0 the limit u1D(0)). ``form`` and
/// ``quadrature`` as for ``forward``. Exact for the flat punch: u1D = u0 gives u3D = u0.
#[pyfunction]
#[pyo3(signature = (u1d, radius, *, form = "dense", quadrature = "product"))]
pub fn back<'py>(
    py: Python<'py>,
    u1d: PyArrayLike1<'py, f64, AllowTypeChange>,
    radius: f64,
    form: &str,
    quadrature: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = data(&u1d);
    let ops = operators(py, radius, x.len(), form, quadrature)?;
    let mut out = vec![0.0; x.len()];
    ops.back(&x, &mut out);
    Ok(out.into_pyarray(py))
}

/// Surface displacement of the elastic half-space under the shear stress τ (Eq. 13–15):
/// u3D = back(forward(τ)) / G*.
///
/// ``tau`` in Pa at r_i = i·radius/N; ``radius`` a0 in m; ``g_eff`` the effective shear
/// modulus G* in Pa. Returns u3D in m (as the simulation computes it: the product, then times
/// 1/G*). ``form`` and ``quadrature`` as for ``forward``.
#[pyfunction]
#[pyo3(signature = (tau, radius, g_eff, *, form = "dense", quadrature = "product"))]
pub fn compliance<'py>(
    py: Python<'py>,
    tau: PyArrayLike1<'py, f64, AllowTypeChange>,
    radius: f64,
    g_eff: f64,
    form: &str,
    quadrature: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    if !(g_eff.is_finite() && g_eff > 0.0) {
        return Err(PyValueError::new_err(format!(
            "g_eff = {g_eff:e} Pa; allowed: finite and > 0"
        )));
    }
    let x = data(&tau);
    let ops = operators(py, radius, x.len(), form, quadrature)?;
    let mut q = vec![0.0; x.len()];
    let mut out = vec![0.0; x.len()];
    ops.compliance(&x, &mut q, &mut out);
    let inv_g = 1.0 / g_eff;
    out.iter_mut().for_each(|u| *u *= inv_g);
    Ok(out.into_pyarray(py))
}

/// Friction force F = 2π ∫₀^a0 τ r dr (Eq. 16), in N, for τ in Pa at r_i = i·radius/N
/// (``radius`` a0 in m), with the weights of ``quadrature`` (as in ``forward``).
#[pyfunction]
#[pyo3(signature = (tau, radius, *, quadrature = "product"))]
pub fn force<'py>(
    py: Python<'py>,
    tau: PyArrayLike1<'py, f64, AllowTypeChange>,
    radius: f64,
    quadrature: &str,
) -> PyResult<f64> {
    let x = data(&tau);
    let quadrature = quadrature_of(quadrature)?;
    if x.is_empty() {
        return Err(PyValueError::new_err(
            "an empty array; allowed: at least one node value",
        ));
    }
    let grid = Grid::new(radius, x.len())
        .map_err(|e| PyValueError::new_err(format!("radius = {radius:e} m: {e}")))?;
    // The weights alone: O(N), no operator (a dense one would cost 8·N² bytes).
    Ok(py.detach(|| stickslip_core::mdr::force_3d_n(&grid, quadrature, &x)))
}

/// The node radii r_i = i·radius/N, i = 0 … N−1, in m (``radius`` a0 in m, ``n`` = N ≥ 1):
/// the grid of ``forward``, ``back`` and ``compliance``.
#[pyfunction]
pub fn radii(py: Python<'_>, radius: f64, n: usize) -> PyResult<Bound<'_, PyArray1<f64>>> {
    let grid = Grid::new(radius, n).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(grid.radii_m().into_pyarray(py))
}
