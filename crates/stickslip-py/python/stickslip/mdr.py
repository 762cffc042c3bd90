"""The MDR transforms of the paper (Eq. 13–16) on NumPy arrays, in the style of PyAbel's
transforms: one function per transform, the grid implied by the length N of the array.

Grid: the N nodes r_i = i·radius/N, i = 0 … N−1 (``radii(radius, n)``); the contact edge
r = radius carries no node. Units: τ in Pa, q in N/m, u1D and u3D in m, radius in m, G* in Pa,
F in N. Inputs are 1-D arrays or sequences (float64 arrays are read in place; anything else is
converted once); results are new float64 arrays (handed over without a copy).

- ``forward(tau, radius)``: q(x) = 2 ∫ₓ^a0 r τ(r)/√(r² − x²) dr  (Eq. 13)
- ``back(u1d, radius)``: u3D(r) = (2/π) ∫₀^r u1D(x)/√(r² − x²) dx  (Eq. 15)
- ``compliance(tau, radius, g_eff)``: u3D = back(forward(τ))/G*  (Eq. 13–15), in m
- ``force(tau, radius)``: F = 2π ∫₀^a0 τ r dr  (Eq. 16), in N

Keyword ``form``: ``"dense"`` (default; product integration as a mat-vec, O(N²) time and
8·N·(N + 1) bytes) or ``"fast"`` (its hierarchical low-rank form, O(N), within 1e-10
relative). Keyword ``quadrature``: ``"product"`` (default; second order on smooth data) or
``"literal"`` (the paper's plain sums). Operators are built once per (radius, N, form,
quadrature) and reused for the next calls.

Inputs are checked before anything is built: values must be a 1-D array (or sequence) of
real numbers, all finite (``ValueError`` naming the first bad index; ``TypeError`` for
strings, complex numbers, booleans or objects), not empty; ``radius`` and ``g_eff`` finite
and > 0. A size whose operators would take more than half of the memory available raises
``MemoryError`` saying how much they would need and what fits (``form="fast"``, or fewer
nodes), instead of the allocation aborting the interpreter.
"""

from ._native import back, compliance, force, forward, radii

__all__ = ["forward", "back", "compliance", "force", "radii"]
