"""An independent implementation of the model up to the first melting onset.

It shares no code with the stickslip crates and does not import the `stickslip` package.
It uses only NumPy and SciPy. It reads the same scene TOML, takes the keys it supports and
refuses the others.

- **Discretisation.** Spectral, not stickslip's grids. Every field is an even Chebyshev
  series in r on [0, a0]: T_2j(r/a0), j = 0..M, collocated at the M + 1 non-negative
  Chebyshev–Lobatto points. So the contact's edge r = a0, where the film melts first, is a
  node.
- **The MDR pair (Eqs. 13 and 15).** Both transforms are taken after substitutions that
  remove the Abel kernel's 1/√ singularity:
  - forward, r² = x² + s²: q(x) = 2∫_0^√(a0²−x²) τ(√(x²+s²)) ds;
  - back, x = r·sin θ: u3D(r) = (2/π)∫_0^{π/2} u1D(r·sin θ) dθ.
- **Why Gauss–Legendre is exact here.** For τ an even polynomial in r, q(x) = √(a0² − x²)·g(x)
  with g an even polynomial. The back transform therefore integrates √(a0² − x²)·g, whose
  integrand is smooth in θ. Both integrals are then polynomial or smooth, and Gauss–Legendre
  takes them to rounding.
- **Time.** SciPy's Radau (rtol 1e-11), with the onset located as an event: the smallest φ
  reaching the melt threshold. Before it every node is solid, so u0 = X everywhere. The
  spring drive m·X'' = K·(V0·t − X) − F carries the force F = 2π∫τ·r dr.

This first version stops at the first onset and writes DIR/events.csv with `k` and
`t_onset`. Following the meltings (u0's hold and release) comes next.

Usage: python3 validation/independent/independent.py SCENE [--end T] [--resolution M] --out DIR
"""

import argparse
import math
import pathlib
import sys
import tomllib

import numpy as np
from numpy.polynomial.legendre import leggauss
from scipy.integrate import solve_ivp

# The scene keys this version supports (others are refused, naming the key).
SUPPORTED = {
    "name": None,
    "lubricant": {"tau_max", "eps_max", "a", "gamma", "melt_threshold"},
    "contact": {"radius", "film_thickness", "g_eff", "nodes", "model", "substrate"},
    "drive": {"kind", "stiffness", "mass", "velocity", "integrator"},
    "time": {"end", "dt", "scheme", "tolerance", "stepping"},
    "output": None,
    "numerics": None,
}


def refuse(message):
    print(f"independent.py: {message}", file=sys.stderr)
    sys.exit(2)


def check_scene(scene):
    for section, value in scene.items():
        if section not in SUPPORTED:
            refuse(f"[{section}] is not supported by this implementation")
        keys = SUPPORTED[section]
        if keys is not None and isinstance(value, dict):
            for key in value:
                if key not in keys:
                    refuse(f"{section}.{key} is not supported by this implementation")
    contact, drive = scene.get("contact", {}), scene.get("drive", {})
    if contact.get("model", "radial") != "radial":
        refuse("contact.model must be \"radial\"")
    if contact.get("substrate", "elastic") != "elastic":
        refuse("contact.substrate must be \"elastic\"")
    if drive.get("kind", "spring") != "spring":
        refuse("drive.kind must be \"spring\"")


def even_basis(x, m):
    """T_2j(x), j = 0..m, as columns."""
    angle = np.arccos(np.clip(x, -1.0, 1.0))
    return np.stack([np.cos(2 * j * angle) for j in range(m + 1)], axis=-1)


def operators(a0, m, points):
    """Nodes r (m), the compliance matrix u3D = C·τ·G* (m per Pa·G*) and the force weights."""
    rho = np.cos(np.arange(m + 1) * np.pi / (2 * m))  # r/a0, from the edge (1) to the axis (0)
    vinv = np.linalg.inv(even_basis(rho, m))
    t, w = leggauss(points)
    s_edge = np.sqrt(np.maximum(1.0 - rho**2, 0.0))
    forward = np.zeros((m + 1, m + 1))
    for k in range(m + 1):
        s = s_edge[k] * (1 + t) / 2
        forward[k] = 2 * (s_edge[k] / 2) * (w @ even_basis(np.sqrt(rho[k] ** 2 + s**2), m))
    forward = a0 * forward @ vinv  # q at the nodes from τ at the nodes, N/m per Pa
    # g = q/√(a0² − x²) at the nodes; at the edge its limit, 2·τ(a0).
    to_g = np.zeros((m + 1, m + 1))
    to_g[1:, :] = forward[1:, :] / (a0 * s_edge[1:, None])
    to_g[0, 0] = 2.0
    theta = (np.pi / 2) * (1 + t) / 2
    w_theta = w * np.pi / 4
    back = np.zeros((m + 1, m + 1))
    for k in range(m + 1):
        x = rho[k] * np.sin(theta)
        back[k] = (2 / np.pi) * (w_theta * a0 * np.sqrt(1 - x**2)) @ even_basis(x, m)
    back = back @ vinv
    rr = (1 + t) / 2
    force = 2 * np.pi * a0**2 * ((w / 2 * rr) @ even_basis(rr, m)) @ vinv
    return rho * a0, back @ to_g, force


def first_onset(scene, m, end_s):
    lub, con, drv = scene["lubricant"], scene["contact"], scene["drive"]
    tau_max, eps_max, a, gamma = lub["tau_max"], lub["eps_max"], lub["a"], lub["gamma"]
    threshold = lub.get("melt_threshold", 0.01)
    b = 2 * a * a * eps_max**3 / tau_max
    big_a = 1.5 * tau_max / eps_max
    h0, g_eff = con["film_thickness"], con["g_eff"]
    k_spring, mass, v0 = drv["stiffness"], drv["mass"], drv["velocity"]
    _, compliance, force_w = operators(con["radius"], m, 4 * m + 40)
    compliance = compliance / g_eff
    n = m + 1

    def rhs(t, y):
        phi, x, v = y[:n], y[n], y[n + 1]
        d = a * phi**2 / h0
        u = np.linalg.solve(np.eye(n) + compliance * d[None, :], compliance @ (d * x))
        eps = (x - u) / h0
        force = force_w @ (a * phi**2 * eps)
        dphi = -gamma * phi * (a * eps**2 + b * phi**2 - big_a * b / a)
        return np.concatenate([dphi, [v, (k_spring * (v0 * t - x) - force) / mass]])

    def onset(_t, y):
        return np.min(y[:n]) - threshold

    onset.terminal = True
    onset.direction = -1
    y0 = np.concatenate([np.full(n, math.sqrt(big_a / a)), [0.0, 0.0]])
    atol = np.concatenate([np.full(n, 1e-12), [1e-22 + 1e-12 * h0, 1e-14]])
    sol = solve_ivp(rhs, (0.0, end_s), y0, method="Radau", rtol=1e-11, atol=atol, events=onset)
    return sol.t_events[0][0] if sol.t_events[0].size else None


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--end", type=float, help="end time, s (default: the scene's)")
    parser.add_argument("--resolution", type=int, default=24, help="M: series terms (≥ 4)")
    parser.add_argument("--out", required=True)
    args = parser.parse_args(argv)
    if args.resolution < 4:
        refuse(f"--resolution = {args.resolution}; allowed: an integer ≥ 4")
    with open(args.scene, "rb") as f:
        scene = tomllib.load(f)
    check_scene(scene)
    end_s = args.end if args.end is not None else scene.get("time", {}).get("end", 1.0)
    t_onset = first_onset(scene, args.resolution, end_s)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = ["k,t_onset"] + ([f"1,{float(t_onset)!r}"] if t_onset is not None else [])
    (out / "events.csv").write_text("\n".join(rows) + "\n")
    print(f"first onset: {float(t_onset)!r} s (M = {args.resolution})" if t_onset else "no onset")


if __name__ == "__main__":
    main(sys.argv[1:])
