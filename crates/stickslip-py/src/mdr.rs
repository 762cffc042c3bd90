//! `stickslip.mdr`: the MDR transforms of the core (Eq. 13–16) on NumPy arrays, in the style
//! of PyAbel's transforms: one function per transform, the grid implied by the array length.
//!
//! Inputs are checked before anything is built: a 1-D array of real numbers, finite, not
//! empty; a radius finite and > 0; and a size whose operators fit in the memory available
//! (the dense form holds 8·N·(N + 1) bytes), so a bad call raises instead of aborting the
//! interpreter.

use crate::args;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::{PyMemoryError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyString};
use std::sync::{Arc, Mutex};
use stickslip_core::grid::Grid;
use stickslip_core::mdr::{MdrOperators, OperatorForm, Quadrature};

/// Operators kept for reuse: the most recent few (building costs O(N²)).
const CACHE_ENTRIES: usize = 2;
/// Operators above this size are built for the call and dropped (N² memory).
const CACHE_MAX_NODES: usize = 4096;
/// Share of the available memory an operator may take: the rest is left to the arrays, the
/// interpreter and the other programs.
const MEMORY_SHARE: f64 = 0.5;
/// Bytes per node and level of the hierarchy the fast form's construction takes at its peak
/// (both operators built side by side, with their work space): measured about 480 at 10⁴
/// nodes, 320 at 5·10⁴ and 270 at 2·10⁵; twice the largest, as an upper estimate.
const FAST_BYTES_PER_NODE_LEVEL: f64 = 1024.0;

type Key = (u64, usize, OperatorForm, Quadrature);
static CACHE: Mutex<Vec<(Key, Arc<MdrOperators>)>> = Mutex::new(Vec::new());

/// The word of a keyword argument (`form`, `quadrature`): a `TypeError` naming the argument
/// for anything but a str.
fn word_arg(value: &Bound<'_, PyAny>, name: &str, allowed: &str) -> PyResult<String> {
    value.extract::<String>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name} = {} ({}) is invalid; allowed: {allowed}",
            args::shown(value),
            args::type_name(value)
        ))
    })
}

/// `form=` as an operator form.
fn form_arg(value: &Bound<'_, PyAny>) -> PyResult<OperatorForm> {
    form_of(&word_arg(value, "form", "\"dense\" or \"fast\"")?)
}

/// `quadrature=` as a quadrature.
fn quadrature_arg(value: &Bound<'_, PyAny>) -> PyResult<Quadrature> {
    quadrature_of(&word_arg(
        value,
        "quadrature",
        "\"product\" or \"literal\"",
    )?)
}

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

/// Bytes of memory available to this process: the smaller of the system's available memory
/// and a cgroup's limit (Linux); `None` where neither can be read.
fn available_bytes() -> Option<f64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("MemAvailable:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
                .map(|kb| kb * 1024.0)
        });
    let cgroup = std::fs::read_to_string("/sys/fs/cgroup/memory.max")
        .ok()
        .and_then(|t| t.trim().parse::<f64>().ok());
    match (meminfo, cgroup) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Bytes in words: `320 GB`, `4.2 MB`.
fn bytes_text(b: f64) -> String {
    let (v, unit) = [(1e12, "TB"), (1e9, "GB"), (1e6, "MB"), (1e3, "kB")]
        .into_iter()
        .find(|(scale, _)| b >= *scale)
        .map_or((b, "bytes"), |(scale, unit)| (b / scale, unit));
    format!("{v:.1} {unit}").replace(".0 ", " ")
}

/// Bytes the operators of `n` nodes in `form` take (the fast form's as an upper estimate).
fn operator_bytes(n: usize, form: OperatorForm) -> f64 {
    match form {
        OperatorForm::Dense => MdrOperators::dense_bytes(n) as f64,
        OperatorForm::Fast => {
            let levels = (n as f64 / 32.0).log2().max(1.0);
            FAST_BYTES_PER_NODE_LEVEL * n as f64 * levels
        }
    }
}

/// Refuses `n` nodes in `form` when the operators would take more than [`MEMORY_SHARE`] of
/// the memory available; the message names the size, the memory and the way out.
fn check_size(n: usize, form: OperatorForm, name: &str) -> PyResult<()> {
    let need = operator_bytes(n, form);
    let Some(available) = available_bytes() else {
        return Ok(());
    };
    let budget = MEMORY_SHARE * available;
    if need <= budget {
        return Ok(());
    }
    let largest = |form| {
        // The largest N within the budget (bisection; operator_bytes grows with N).
        let (mut lo, mut hi) = (1usize, n);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if operator_bytes(mid, form) <= budget {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    let way_out = match form {
        OperatorForm::Dense if operator_bytes(n, OperatorForm::Fast) <= budget => format!(
            "form=\"fast\" (O(N) memory and time, within 1e-10 relative of the dense form), \
             or at most {} nodes in the dense form",
            largest(OperatorForm::Dense)
        ),
        OperatorForm::Dense => format!(
            "at most {} nodes in the fast form (form=\"fast\") or {} in the dense one",
            largest(OperatorForm::Fast),
            largest(OperatorForm::Dense)
        ),
        OperatorForm::Fast => format!("at most {} nodes", largest(OperatorForm::Fast)),
    };
    let (what, formula) = match form {
        OperatorForm::Dense => ("dense operators (form=\"dense\")", "8·N·(N + 1) bytes"),
        OperatorForm::Fast => ("fast operators (form=\"fast\")", "an estimate"),
    };
    Err(PyMemoryError::new_err(format!(
        "{name} has {n} nodes: the {what} would need {} ({formula}), more than half of the \
         {} of memory available; allowed: {way_out}",
        bytes_text(need),
        bytes_text(available)
    )))
}

/// Refuses an allocation of `need` bytes beyond [`MEMORY_SHARE`] of the memory available:
/// "`what` would need …; allowed: `way_out`".
fn check_bytes(need: f64, what: &str, way_out: &str) -> PyResult<()> {
    match available_bytes() {
        Some(available) if need > MEMORY_SHARE * available => Err(PyMemoryError::new_err(format!(
            "{what} would need {}, more than half of the {} of memory available; allowed: \
             {way_out}",
            bytes_text(need),
            bytes_text(available)
        ))),
        _ => Ok(()),
    }
}

/// A contact radius: a real number, finite and > 0, in m.
fn radius_of(value: &Bound<'_, PyAny>) -> PyResult<f64> {
    positive(value, "radius", "m", "the contact radius a0")
}

/// A real number, finite and > 0, named `name` in messages.
fn positive(value: &Bound<'_, PyAny>, name: &str, unit: &str, meaning: &str) -> PyResult<f64> {
    let not_a_number = value.cast::<PyBool>().is_ok()
        || value.cast::<PyString>().is_ok()
        || value.cast::<PyBytes>().is_ok();
    let x: Option<f64> = if not_a_number {
        None
    } else {
        value.extract().ok()
    };
    match x {
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        Some(x) => Err(PyValueError::new_err(format!(
            "{name} = {x} {unit} is invalid; allowed: finite and > 0 ({meaning} in {unit})"
        ))),
        None => Err(PyTypeError::new_err(format!(
            "{name} = {} ({}) is invalid; allowed: a real number > 0 ({meaning} in {unit})",
            args::shown(value),
            args::type_name(value)
        ))),
    }
}

/// The node values of a 1-D input, checked: an array (or sequence) of real numbers, one
/// dimension, not empty, a size `fits` accepts (before anything is copied), every value
/// finite. A contiguous float64 array is read in place; anything else is converted once.
/// `what` says what the values are, for messages.
fn values<'py>(
    py: Python<'py>,
    value: &Bound<'py, PyAny>,
    name: &str,
    what: &str,
    fits: impl FnOnce(usize) -> PyResult<()>,
) -> PyResult<PyReadonlyArray1<'py, f64>> {
    let expected = format!("expected a 1-D array of {what} (float64, or real numbers)");
    if value.is_none() || value.cast::<PyString>().is_ok() || value.cast::<PyBytes>().is_ok() {
        return Err(PyTypeError::new_err(format!(
            "{name} = {} ({}) is invalid; {expected}",
            args::shown(value),
            args::type_name(value)
        )));
    }
    let np = py.import("numpy")?;
    let array = np.call_method1("asarray", (value,)).map_err(|e| {
        let message = format!(
            "{name} cannot be read as an array ({}); {expected}",
            e.value(py)
        );
        if e.is_instance_of::<PyTypeError>(py) {
            PyTypeError::new_err(message)
        } else {
            PyValueError::new_err(message)
        }
    })?;
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        let of = match kind.as_str() {
            "c" => "complex numbers (take .real, .imag or abs() first)".to_string(),
            "b" => "booleans".to_string(),
            "U" | "S" => "strings".to_string(),
            "O" => "Python objects (not all real numbers)".to_string(),
            _ => format!("dtype {}", dtype.str()?),
        };
        return Err(PyTypeError::new_err(format!(
            "{name} holds {of}; {expected}"
        )));
    }
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 1 {
        let got = if shape.is_empty() {
            "a scalar".to_string()
        } else {
            format!(
                "shape ({})",
                shape
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        return Err(PyValueError::new_err(format!(
            "{name}: {expected}, got {got}"
        )));
    }
    if shape[0] == 0 {
        return Err(PyValueError::new_err(format!(
            "{name} is an empty array; allowed: at least one node value ({what})"
        )));
    }
    fits(shape[0])?;
    let contiguous = np
        .call_method1("ascontiguousarray", (array, np.getattr("float64")?))?
        .cast_into::<PyArray1<f64>>()?;
    let ro = contiguous.readonly();
    if let Some(i) = ro.as_slice()?.iter().position(|v| !v.is_finite()) {
        let v = ro.as_slice()?[i];
        return Err(PyValueError::new_err(format!(
            "{name}[{i}] = {v} is not finite; allowed: finite values of {what}"
        )));
    }
    Ok(ro)
}

/// `out` if every value is finite, else a `ValueError`: inputs finite in themselves can
/// overflow the transform (`tau` of 1e6 Pa on a radius of 1e308 m).
fn finite_result(
    out: Vec<f64>,
    function: &str,
    quantity: &str,
    inputs: &str,
) -> PyResult<Vec<f64>> {
    match out.iter().position(|v| !v.is_finite()) {
        None => Ok(out),
        Some(i) => Err(PyValueError::new_err(format!(
            "{function}: {quantity}[{i}] = {} is not finite: {inputs} overflow double \
             precision; allowed: values whose result stays finite (|x| < 1.8e308)",
            out[i]
        ))),
    }
}

/// The operators for `n` nodes on radius `radius_m`, from the cache or built (without the
/// GIL); the size was checked by [`values`] with [`check_size`].
fn operators(
    py: Python<'_>,
    radius_m: f64,
    n: usize,
    form: OperatorForm,
    quadrature: Quadrature,
) -> PyResult<Arc<MdrOperators>> {
    let grid = Grid::new(radius_m, n).map_err(|e| PyValueError::new_err(e.to_string()))?;
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

/// Forward MDR transform, Eq. 13: q(x) = 2 ∫ₓ^a0 r τ(r) / √(r² − x²) dr.
///
/// ``tau``: the shear stress τ in Pa at the N nodes r_i = i·radius/N, i = 0 … N−1 (1-D array
/// or sequence of real numbers, all finite; the edge r = radius carries no node).
/// ``radius``: the contact radius a0 in m (finite, > 0). Returns q in N/m at the same nodes
/// x_i = r_i (a new float64 array).
///
/// ``form``: ``"dense"`` (default; 8·N·(N + 1) bytes, refused with a ``MemoryError`` when that
/// exceeds half the memory available) or ``"fast"`` (hierarchical low-rank, O(N), within
/// 1e-10 relative); ``quadrature``: ``"product"`` (default: the kernel integrated exactly
/// against piecewise-linear data, second order) or ``"literal"`` (the paper's sums).
/// Exact for uniform stress: τ = τc gives q = 2τc√(a0² − x²) to rounding.
///
/// Raises ``ValueError`` for a wrong shape, an empty array, a value that is not finite
/// (naming its index), a bad radius or a result that overflows (``tau`` and ``radius``
/// finite, their product not), ``TypeError`` for values that are not real numbers.
#[pyfunction]
#[pyo3(signature = (tau, radius, *, form = OperatorForm::Dense, quadrature = Quadrature::Product))]
#[pyo3(text_signature = "(tau, radius, *, form='dense', quadrature='product')")]
pub fn forward<'py>(
    py: Python<'py>,
    tau: &Bound<'py, PyAny>,
    radius: &Bound<'py, PyAny>,
    #[pyo3(from_py_with = form_arg)] form: OperatorForm,
    #[pyo3(from_py_with = quadrature_arg)] quadrature: Quadrature,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let radius = radius_of(radius)?;
    let tau = values(py, tau, "tau", "the shear stress τ in Pa", |n| {
        check_size(n, form, "tau")
    })?;
    let x = tau.as_slice()?;
    let ops = operators(py, radius, x.len(), form, quadrature)?;
    let mut out = vec![0.0; x.len()];
    ops.forward(x, &mut out);
    Ok(finite_result(out, "forward", "q", "tau and radius")?.into_pyarray(py))
}

/// Back MDR transform, Eq. 15: u3D(r) = (2/π) ∫₀^r u1D(x) / √(r² − x²) dx.
///
/// ``u1d``: the 1-D displacement u1D in m at the N nodes x_i = i·radius/N. ``radius``: a0 in
/// m. Returns u3D in m at r_i = x_i (at r = 0 the limit u1D(0)). ``form`` and
/// ``quadrature`` as for ``forward``, and the same checks. Exact for the flat punch: u1D = u0
/// gives u3D = u0.
#[pyfunction]
#[pyo3(signature = (u1d, radius, *, form = OperatorForm::Dense, quadrature = Quadrature::Product))]
#[pyo3(text_signature = "(u1d, radius, *, form='dense', quadrature='product')")]
pub fn back<'py>(
    py: Python<'py>,
    u1d: &Bound<'py, PyAny>,
    radius: &Bound<'py, PyAny>,
    #[pyo3(from_py_with = form_arg)] form: OperatorForm,
    #[pyo3(from_py_with = quadrature_arg)] quadrature: Quadrature,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let radius = radius_of(radius)?;
    let u1d = values(py, u1d, "u1d", "the 1-D displacement u1D in m", |n| {
        check_size(n, form, "u1d")
    })?;
    let x = u1d.as_slice()?;
    let ops = operators(py, radius, x.len(), form, quadrature)?;
    let mut out = vec![0.0; x.len()];
    ops.back(x, &mut out);
    Ok(finite_result(out, "back", "u3d", "u1d and radius")?.into_pyarray(py))
}

/// Surface displacement of the elastic half-space under the shear stress τ (Eq. 13–15):
/// u3D = back(forward(τ)) / G*.
///
/// ``tau`` in Pa at r_i = i·radius/N; ``radius`` a0 in m; ``g_eff`` the effective shear
/// modulus G* in Pa (finite, > 0). Returns u3D in m (as the simulation computes it: the
/// product, then times 1/G*). ``form`` and ``quadrature`` as for ``forward``, and the same
/// checks.
#[pyfunction]
#[pyo3(signature = (tau, radius, g_eff, *, form = OperatorForm::Dense, quadrature = Quadrature::Product))]
#[pyo3(text_signature = "(tau, radius, g_eff, *, form='dense', quadrature='product')")]
pub fn compliance<'py>(
    py: Python<'py>,
    tau: &Bound<'py, PyAny>,
    radius: &Bound<'py, PyAny>,
    g_eff: &Bound<'py, PyAny>,
    #[pyo3(from_py_with = form_arg)] form: OperatorForm,
    #[pyo3(from_py_with = quadrature_arg)] quadrature: Quadrature,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let radius = radius_of(radius)?;
    let g_eff = positive(g_eff, "g_eff", "Pa", "the effective shear modulus G*")?;
    let tau = values(py, tau, "tau", "the shear stress τ in Pa", |n| {
        check_size(n, form, "tau")
    })?;
    let x = tau.as_slice()?;
    let ops = operators(py, radius, x.len(), form, quadrature)?;
    let mut q = vec![0.0; x.len()];
    let mut out = vec![0.0; x.len()];
    ops.compliance(x, &mut q, &mut out);
    let inv_g = 1.0 / g_eff;
    out.iter_mut().for_each(|u| *u *= inv_g);
    Ok(finite_result(out, "compliance", "u3d", "tau, radius and g_eff")?.into_pyarray(py))
}

/// Friction force F = 2π ∫₀^a0 τ r dr (Eq. 16), in N, for τ in Pa at r_i = i·radius/N
/// (``radius`` a0 in m), with the weights of ``quadrature`` (as in ``forward``; no operator
/// is built, any size that fits in memory works). The same checks as ``forward``.
#[pyfunction]
#[pyo3(signature = (tau, radius, *, quadrature = Quadrature::Product))]
#[pyo3(text_signature = "(tau, radius, *, quadrature='product')")]
pub fn force<'py>(
    py: Python<'py>,
    tau: &Bound<'py, PyAny>,
    radius: &Bound<'py, PyAny>,
    #[pyo3(from_py_with = quadrature_arg)] quadrature: Quadrature,
) -> PyResult<f64> {
    let radius = radius_of(radius)?;
    let tau = values(py, tau, "tau", "the shear stress τ in Pa", |n| {
        // A float64 copy of the input and the weights, 16·N bytes.
        check_bytes(
            16.0 * n as f64,
            &format!("tau has {n} nodes: its float64 copy and the force weights"),
            "fewer nodes",
        )
    })?;
    let x = tau.as_slice()?;
    let grid = Grid::new(radius, x.len()).map_err(|e| PyValueError::new_err(e.to_string()))?;
    // The weights alone: O(N), no operator (a dense one would cost 8·N² bytes).
    let f = py.detach(|| stickslip_core::mdr::force_3d_n(&grid, quadrature, x));
    Ok(finite_result(vec![f], "force", "F", "tau and radius")?[0])
}

/// The node radii r_i = i·radius/N, i = 0 … N−1, in m (``radius`` a0 in m, ``n`` = N, an int
/// ≥ 1 whose array fits in memory): the grid of ``forward``, ``back`` and ``compliance``.
#[pyfunction]
pub fn radii<'py>(
    py: Python<'py>,
    radius: &Bound<'py, PyAny>,
    n: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let radius = radius_of(radius)?;
    if n.cast::<PyBool>().is_ok() || n.cast::<pyo3::types::PyInt>().is_err() {
        return Err(PyTypeError::new_err(format!(
            "n = {} ({}) is invalid; allowed: an int >= 1 (the number of nodes)",
            args::shown(n),
            args::type_name(n)
        )));
    }
    let count = n.extract::<i64>().ok().filter(|&c| c >= 1);
    let Some(count) = count.and_then(|c| usize::try_from(c).ok()) else {
        return Err(PyValueError::new_err(format!(
            "n = {} is invalid; allowed: an int >= 1 (the number of nodes)",
            args::shown(n)
        )));
    };
    check_bytes(
        8.0 * count as f64,
        &format!("n = {count}: the radii"),
        "fewer nodes",
    )?;
    let grid = Grid::new(radius, count).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(grid.radii_m().into_pyarray(py))
}
