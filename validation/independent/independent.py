"""An independent implementation of the model: melting events of a flat-ended stamp's film.

It shares no code with the stickslip crates and does not import the `stickslip` package.
It uses only NumPy and SciPy. It reads the same scene TOML, takes the keys it supports and
refuses the others: the second-order film, a radial elastic contact, the spring or the rigid
drive, constant temperature or its relaxation law A(t) = A0·exp(−t/t̃).

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
- **Time.** SciPy's Radau (`--rtol`, default 1e-11) with the exact Jacobian. The coupling
  (I + C·D)·u3D = C·D·u0 is solved densely at every evaluation.
- **Meltings.** Each node's melting (φ falling through the threshold) and re-solidification
  (φ rising through it) is a terminal event of the integrator, which then restarts. At a
  melting u0 is reset to 0; a node whose φ then grows accumulates u0 again at once, one whose
  φ still falls is held at u0 = 0 until it re-solidifies. The spring drive
  m·X'' = K·(V0·t − X) − F carries the force F = 2π∫τ·r dr.
- **Events.** One per melt–recover cycle, by stickslip's documented rule: it begins when a
  node melts while none is open and ends when every node is back at or above
  φ_rec(t) = min(2·threshold, ½·(threshold + √(A(t)/a))). f_peak is the largest F since the
  previous event began (from t = 0 for the first), from the integrator's dense output.

Writes DIR/events.csv: k, t_onset (s), f_peak (N), r_first (m), t_end (s; nan while open).

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
from scipy.optimize import minimize_scalar

# The scene keys this version supports (others are refused, naming the key).
SUPPORTED = {
    "name": None,
    "lubricant": {"tau_max", "eps_max", "a", "gamma", "melt_threshold"},
    "contact": {"radius", "film_thickness", "g_eff", "nodes", "model", "substrate"},
    "drive": {"kind", "stiffness", "mass", "velocity", "integrator"},
    "time": {"end", "dt", "scheme", "tolerance", "stepping", "max_events"},
    "temperature": {"law", "A0", "t_relax"},
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
    if drive.get("kind", "spring") not in ("spring", "rigid"):
        refuse("drive.kind must be \"spring\" or \"rigid\"")


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


class Film:
    """The model on the spectral nodes: parameters, operators and the right-hand side."""

    def __init__(self, scene, m):
        lub, con, drv = scene["lubricant"], scene["contact"], scene["drive"]
        self.tau_max, eps_max = lub["tau_max"], lub["eps_max"]
        self.a, self.gamma = lub["a"], lub["gamma"]
        self.threshold = lub.get("melt_threshold", 0.01)
        self.b = 2 * self.a * self.a * eps_max**3 / self.tau_max
        temp = scene.get("temperature", {})
        law = temp.get("law", "constant")
        if law == "constant":
            self.a0_temp, self.t_relax = temp.get("A0", 1.5 * self.tau_max / eps_max), math.inf
        elif law == "relaxation":
            self.a0_temp, self.t_relax = temp["A0"], temp["t_relax"]
        else:
            refuse(f"temperature.law = {law!r}; allowed: \"constant\", \"relaxation\"")
        self.h0, g_eff = con["film_thickness"], con["g_eff"]
        self.rigid = drv.get("kind", "spring") == "rigid"
        self.v0 = drv["velocity"]
        self.k_spring = drv.get("stiffness", 0.0)
        self.mass = drv.get("mass", 0.0)
        self.r, compliance, self.force_w = operators(con["radius"], m, 4 * m + 40)
        self.c = compliance / g_eff
        self.n = m + 1
        # u0 = held[i] ? 0 : X − x_reset[i]  (u0 grows with the stamp since the last reset)
        self.x_reset = np.zeros(self.n)
        self.held = np.zeros(self.n, dtype=bool)
        # (t, y) of the largest F since the last onset (the film's reset state is the same)
        self.peak = None

    def big_a(self, t):
        return self.a0_temp * math.exp(-t / self.t_relax)

    def recovery_level(self, t):
        """φ_rec(t) = min(2·threshold, ½·(threshold + √(A(t)/a)))."""
        return min(2 * self.threshold, 0.5 * (self.threshold + math.sqrt(max(self.big_a(t), 0.0) / self.a)))

    def stamp(self, t, y):
        if self.rigid:
            return self.v0 * t, self.v0
        return y[self.n], y[self.n + 1]

    def fields(self, t, y):
        """Strain, coupling matrix and the pieces the Jacobian reuses."""
        phi = y[: self.n]
        x, _ = self.stamp(t, y)
        u0 = np.where(self.held, 0.0, x - self.x_reset)
        d = self.a * phi**2 / self.h0
        coupling = np.eye(self.n) + self.c * d[None, :]
        u = np.linalg.solve(coupling, self.c @ (d * u0))
        return phi, (u0 - u) / self.h0, coupling

    def force(self, t, y):
        phi, eps, _ = self.fields(t, y)
        return self.force_w @ (self.a * phi**2 * eps)

    def rhs(self, t, y):
        phi, eps, _ = self.fields(t, y)
        big_a = self.big_a(t)
        dphi = -self.gamma * phi * (self.a * eps**2 + self.b * phi**2 - big_a * self.b / self.a)
        if self.rigid:
            return dphi
        x, v = y[self.n], y[self.n + 1]
        f = self.force_w @ (self.a * phi**2 * eps)
        return np.concatenate([dphi, [v, (self.k_spring * (self.v0 * t - x) - f) / self.mass]])

    def jac(self, t, y):
        """The exact Jacobian: ∂u/∂φ_j = (I + C·D)⁻¹·C·e_j·2a·φ_j·ε_j, ∂u/∂X = (I + C·D)⁻¹·C·D·s."""
        n, a, g = self.n, self.a, self.gamma
        phi, eps, coupling = self.fields(t, y)
        solid = (~self.held).astype(float)
        d = a * phi**2 / self.h0
        rhs_cols = np.concatenate([self.c * (2 * a * phi * eps)[None, :], (self.c @ (d * solid))[:, None]], axis=1)
        du = np.linalg.solve(coupling, rhs_cols)
        deps_dphi = -du[:, :n] / self.h0
        deps_dx = (solid - du[:, n]) / self.h0
        big_a = self.big_a(t)
        dg_dphi = -g * phi[:, None] * 2 * a * eps[:, None] * deps_dphi
        dg_dphi[np.diag_indices(n)] += -g * (a * eps**2 + 3 * self.b * phi**2 - big_a * self.b / a)
        if self.rigid:
            return dg_dphi
        jac = np.zeros((n + 2, n + 2))
        jac[:n, :n] = dg_dphi
        jac[:n, n] = -g * phi * 2 * a * eps * deps_dx
        df_dphi = self.force_w * 2 * a * phi * eps + (self.force_w * a * phi**2) @ deps_dphi
        df_dx = (self.force_w * a * phi**2) @ deps_dx
        jac[n, n + 1] = 1.0
        jac[n + 1, :n] = -df_dphi / self.mass
        jac[n + 1, n] = (-self.k_spring - df_dx) / self.mass
        return jac


def simulate(scene, m, end_s, max_events=None, rtol=1e-11):
    """Follow the meltings to end_s (or max_events onsets); the events, and the film with its
    last state (t, y). Stopped by max_events, that state is the one at the last onset, before
    the melting node's u0 is reset.

    Each node's melting and re-solidification is an event of the integrator. At a melting, u0
    is reset to 0. A node whose φ then grows (its strain −u3D/h0 is below εc) accumulates u0
    again at once; one whose φ still falls is held at u0 = 0 until it re-solidifies. Events
    of the film (one per melt–recover cycle) follow stickslip's documented rule: one begins
    when a node melts while none is open and ends when every node is back at or above
    φ_rec(t). f_peak is the largest F since the previous event began (from t = 0 for the first).
    """
    film = Film(scene, m)
    n, thr = film.n, film.threshold
    y = np.full(n, math.sqrt(film.big_a(0.0) / film.a))
    if not film.rigid:
        y = np.concatenate([y, [0.0, 0.0]])
    atol = np.full(y.size, 1e-12)
    if not film.rigid:
        atol[n] = 1e-12 * film.h0
        atol[n + 1] = 1e-12 * abs(film.v0)
    t = 0.0
    events, open_event, window_peak = [], False, -math.inf

    def crossing(i, falling):
        def g(_t, yy):
            return yy[i] - thr

        g.terminal = True
        g.direction = -1 if falling else 1
        return g

    def recovered(tt, yy):
        return np.min(yy[:n]) - film.recovery_level(tt)

    recovered.direction = 1
    recovered.terminal = True
    while t < end_s:
        funcs = [crossing(i, not film.held[i]) for i in range(n)]
        if open_event:
            funcs.append(recovered)
        sol = solve_ivp(film.rhs, (t, end_s), y, method="Radau", rtol=rtol, atol=atol,
                        jac=film.jac, events=funcs, dense_output=True)
        if sol.status < 0:
            refuse(f"the integrator failed at t = {sol.t[-1]!r} s: {sol.message}")
        t_new = sol.t[-1]
        peak = peak_force(film, sol, t, t_new)
        if peak[0] > window_peak:
            window_peak, film.peak = peak[0], (peak[1], peak[2].copy())
        t, y = t_new, sol.y[:, -1].copy()
        if sol.status == 0:
            break
        hit = [j for j, te in enumerate(sol.t_events) if te.size]
        j = hit[0]
        if j == n:  # recovery
            open_event = False
            events[-1]["t_end"] = t
            continue
        i = j
        if not film.held[i]:  # a melting: u0 ← 0
            y[i] = thr
            if not open_event:
                open_event = True
                events.append({"k": len(events) + 1, "t_onset": t, "f_peak": window_peak,
                               "r_first": film.r[i], "t_end": math.nan})
                if max_events is not None and len(events) >= max_events:
                    return events, film, t, y  # film.peak: the largest F before this onset
                window_peak, film.peak = film.force(t, y), (t, y.copy())
            x, _ = film.stamp(t, y)
            film.x_reset[i] = x
            film.held[i] = film.rhs(t, y)[i] <= 0.0
        else:  # re-solidified: u0 accumulates from here
            y[i] = thr
            film.held[i] = False
            film.x_reset[i] = film.stamp(t, y)[0]
    return events, film, t, y


def peak_force(film, sol, t0, t1):
    """The largest F on [t0, t1] from the dense output, refined around the best sample, with
    its time and state."""
    if t1 <= t0:
        return film.force(t0, sol.y[:, 0]), t0, sol.y[:, 0]
    ts = np.unique(np.concatenate([np.linspace(t0, t1, 401), sol.t]))
    fs = np.array([film.force(tt, sol.sol(tt)) for tt in ts])
    k = int(np.argmax(fs))
    best, t_best = fs[k], ts[k]
    if 0 < k < ts.size - 1:
        res = minimize_scalar(lambda tt: -film.force(tt, sol.sol(tt)), bounds=(ts[k - 1], ts[k + 1]),
                              method="bounded", options={"xatol": 1e-15 * max(abs(ts[k]), 1e-300) + 1e-18})
        if -res.fun > best:
            best, t_best = -res.fun, res.x
    return best, t_best, sol.sol(t_best)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--end", type=float, help="end time, s (default: the scene's)")
    parser.add_argument("--resolution", type=int, default=24, help="M: series terms (≥ 4)")
    parser.add_argument("--rtol", type=float, default=1e-11, help="Radau's relative tolerance")
    parser.add_argument("--events", type=int, help="stop at this many onsets (default: time.max_events)")
    parser.add_argument("--out", required=True)
    args = parser.parse_args(argv)
    if args.resolution < 4:
        refuse(f"--resolution = {args.resolution}; allowed: an integer ≥ 4")
    with open(args.scene, "rb") as f:
        scene = tomllib.load(f)
    check_scene(scene)
    end_s = args.end if args.end is not None else scene.get("time", {}).get("end", 1.0)
    max_events = args.events if args.events is not None else scene.get("time", {}).get("max_events")
    if args.events is not None and args.events < 1:
        refuse(f"--events = {args.events}; allowed: an integer ≥ 1")
    if pathlib.Path(args.out).exists() and not pathlib.Path(args.out).is_dir():
        refuse(f"--out = {args.out} is a file; allowed: a directory (made if missing)")
    if not 0 < args.rtol < 1e-3:
        refuse(f"--rtol = {args.rtol}; allowed: 0 < rtol < 1e-3")
    events, _, _, _ = simulate(scene, args.resolution, end_s, max_events, rtol=args.rtol)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    columns = ["k", "t_onset", "f_peak", "r_first", "t_end"]
    rows = [",".join(columns)] + [",".join(repr(float(e[c])) if c != "k" else str(e[c]) for c in columns) for e in events]
    tmp = out / "events.csv.tmp"
    tmp.write_text("\n".join(rows) + "\n")
    tmp.replace(out / "events.csv")
    for e in events:
        print(f"event {e['k']}: onset {float(e['t_onset'])!r} s, f_peak {float(e['f_peak'])!r} N (M = {args.resolution})")
    if not events:
        print("no onset")

if __name__ == "__main__":
    main(sys.argv[1:])
