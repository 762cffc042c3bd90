"""stickslip.mdr against the exact pairs of docs/model.md#exact-answers (uniform stress, smooth
pair, flat punch back transform), the fast form against the dense one, units (compliance in
metres) and argument checks."""

from __future__ import annotations

import math
import os
import signal

import numpy as np
import pytest

from stickslip import mdr

A0 = 2e-5  # m
G = 1e9  # Pa
TAU_C = 1e6  # Pa


def ellip_e(k: float) -> float:
    """Complete elliptic integral of the second kind E(k), modulus k in [0, 1), by the
    arithmetic-geometric mean."""
    a, b = 1.0, math.sqrt(1.0 - k * k)
    s, w = k * k / 2.0, 0.5
    for _ in range(60):
        if a - b <= 1e-15 * a:
            break
        c = (a - b) / 2.0
        a, b = (a + b) / 2.0, math.sqrt(a * b)
        w *= 2.0
        s += w * c * c
    return math.pi / (2.0 * a) * (1.0 - s)


def test_ellip_e_reference_values() -> None:
    assert ellip_e(0.0) == pytest.approx(math.pi / 2, rel=1e-15)
    assert ellip_e(0.5) == pytest.approx(1.4674622093394272, rel=1e-14)
    assert ellip_e(math.sqrt(0.5)) == pytest.approx(1.3506438810476755, rel=1e-14)


def rel_max(a: np.ndarray, b: np.ndarray, mask=None) -> float:
    d = np.abs(a - b)
    if mask is not None:
        d = d[mask]
    return float(d.max() / np.abs(b).max())


def test_grid() -> None:
    r = mdr.radii(A0, 200)
    assert r.shape == (200,) and r[0] == 0.0 and r[-1] == pytest.approx(A0 - A0 / 200)
    assert np.array_equal(r, np.arange(200) * A0 / 200)


@pytest.mark.parametrize("form", ["dense", "fast"])
@pytest.mark.parametrize("n", [200, 1000])
def test_uniform_stress_forward_is_exact_to_rounding(n: int, form: str) -> None:
    r = mdr.radii(A0, n)
    q = mdr.forward(np.full(n, TAU_C), A0, form=form)
    exact = 2.0 * TAU_C * np.sqrt(A0**2 - r**2)  # N/m
    tol = 1e-13 if form == "dense" else 1e-9
    assert rel_max(q, exact) < tol
    # F = 2∫q dx = 2π∫τ r dr = τc π a0², also exact.
    assert mdr.force(np.full(n, TAU_C), A0) == pytest.approx(TAU_C * math.pi * A0**2, rel=1e-14)


def test_uniform_stress_compliance_in_metres() -> None:
    errs = {}
    for n in (200, 400, 800):
        r = mdr.radii(A0, n)
        u = mdr.compliance(np.full(n, TAU_C), A0, G)
        exact = np.array([4 * TAU_C * A0 / (math.pi * G) * ellip_e(x / A0) for x in r])  # m
        assert u[0] == pytest.approx(2 * TAU_C * A0 / G, rel=1e-3)  # E(0) = π/2: metres
        inner = (r >= 0.25 * A0) & (r <= 0.75 * A0)
        errs[n] = (rel_max(u, exact), rel_max(u, exact, inner))
    assert errs[200][0] < 2e-4 and errs[200][1] < 1e-5
    # Observed orders: one in the max norm (the edge), two in the interior.
    assert math.log2(errs[200][0] / errs[400][0]) > 0.9
    assert math.log2(errs[400][1] / errs[800][1]) > 1.8


def test_smooth_pair_forward_converges() -> None:
    errs = {}
    for n in (200, 400, 800):
        r = mdr.radii(A0, n)
        q = mdr.forward(np.sqrt(A0**2 - r**2), A0)
        exact = math.pi / 2 * (A0**2 - r**2)
        inner = (r >= 0.25 * A0) & (r <= 0.75 * A0)
        errs[n] = (rel_max(q, exact), rel_max(q, exact, inner))
    assert errs[200][0] < 3e-3
    # τ has an infinite slope at the edge: order 1 in the max norm, 3/2 in the interior.
    assert math.log2(errs[400][0] / errs[800][0]) > 0.9
    assert math.log2(errs[400][1] / errs[800][1]) > 1.4


@pytest.mark.parametrize("form", ["dense", "fast"])
def test_flat_punch_back_transform_is_exact(form: str) -> None:
    u0 = 3e-9  # m
    u = mdr.back(np.full(500, u0), A0, form=form)
    assert np.max(np.abs(u - u0)) / u0 < (1e-13 if form == "dense" else 1e-9)


def test_fast_form_within_1e_10_of_dense() -> None:
    n = 1500
    r = mdr.radii(A0, n)
    tau = np.sqrt(A0**2 - r**2) * (1 + 0.3 * np.sin(7 * r / A0))
    for f in (mdr.forward, mdr.back):
        dense, fast = f(tau, A0), f(tau, A0, form="fast")
        assert rel_max(fast, dense) < 1e-9
    dense = mdr.compliance(tau, A0, G)
    fast = mdr.compliance(tau, A0, G, form="fast")
    assert rel_max(fast, dense) < 1e-9


def test_literal_quadrature_is_the_papers_sum() -> None:
    n = 200
    r = mdr.radii(A0, n)
    q = mdr.forward(np.full(n, TAU_C), A0, quadrature="literal")
    exact = 2.0 * TAU_C * np.sqrt(A0**2 - r**2)
    # The paper's sums skip the singular term: their error is far above rounding, and the
    # last node's q is an empty sum.
    assert 1e-4 < rel_max(q, exact) < 0.5
    assert q[-1] == 0.0


def test_inputs_arrays_and_sequences() -> None:
    n = 64
    tau = np.linspace(1.0, 2.0, n)
    q = mdr.forward(tau, A0)
    assert q.dtype == np.float64 and q.shape == (n,) and q.flags.c_contiguous
    assert q.flags.writeable
    # Lists, float32 and strided views give the same numbers (converted once).
    assert np.array_equal(mdr.forward(list(tau), A0), q)
    assert np.array_equal(mdr.forward(np.repeat(tau, 2)[::2], A0), q)
    assert np.allclose(mdr.forward(tau.astype(np.float32), A0), q, rtol=1e-6)
    # The input is not modified; the result is a new array.
    before = tau.copy()
    q2 = mdr.forward(tau, A0)
    assert np.array_equal(tau, before) and not np.shares_memory(q2, tau)


def test_argument_errors() -> None:
    with pytest.raises(ValueError, match="form"):
        mdr.forward(np.ones(10), A0, form="sparse")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="quadrature"):
        mdr.back(np.ones(10), A0, quadrature="simpson")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="radius"):
        mdr.forward(np.ones(10), -1.0)
    with pytest.raises(ValueError, match="empty"):
        mdr.forward(np.ones(0), A0)
    with pytest.raises(ValueError, match="g_eff"):
        mdr.compliance(np.ones(10), A0, 0.0)
    with pytest.raises((TypeError, ValueError)):
        mdr.forward(np.ones((3, 3)), A0)


def test_force_of_a_huge_grid_needs_no_operator() -> None:
    # 2e5 nodes: a dense operator would need 320 GB; the weights alone take milliseconds.
    # Uniform stress: F = tau * pi * a0^2 exactly for piecewise-linear data.
    radius = 2e-5
    f = mdr.force(np.full(200_000, 1e6), radius)
    assert f == pytest.approx(1e6 * math.pi * radius**2, rel=1e-12)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork")
def test_fast_compliance_in_a_child_forked_after_its_helper_started() -> None:
    # From 1000 nodes the fast compliance applies on two threads, the second a helper the
    # cached operators keep. A child forked afterwards (multiprocessing's default on Linux)
    # inherits the operators but not the thread: it must compute alone, with the same bits,
    # and not wait for a helper that is not there.
    n = 1200
    tau = 1e6 * np.cos(np.linspace(0.0, 3.0, n))
    parent = mdr.compliance(tau, 2e-5, 1e9, form="fast")
    pid = os.fork()
    if pid == 0:
        signal.alarm(60)  # a child waiting for the helper dies by SIGALRM
        try:
            child = mdr.compliance(tau, 2e-5, 1e9, form="fast")
            os._exit(0 if np.array_equal(child, parent) else 1)
        except BaseException:
            os._exit(2)
    _, status = os.waitpid(pid, 0)
    assert os.WIFEXITED(status), f"the child was killed (status {status}): it hung"
    assert os.WEXITSTATUS(status) == 0, "the child's compliance differs from the parent's"
    again = mdr.compliance(tau, 2e-5, 1e9, form="fast")
    assert np.array_equal(again, parent)
