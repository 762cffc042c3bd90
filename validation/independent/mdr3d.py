"""MDR against 3D elasticity: the tangential surface displacement of an elastic half-space
under the film's shear traction at the first onset, against MDR's u3D(r).

The traction is the film's τ(r), axisymmetric in magnitude and pointing along x (the drive's
direction), on the disk r ≤ a0. The half-space's surface displacement along x under a point
force Q_x at distance ρ in direction ψ is Cerruti's

    u_x = Q/(2πG)·((1 − ν)/ρ + ν·cos²ψ/ρ)            (Johnson, Contact Mechanics, Eq. 2.19)

with G the shear modulus. For one elastic body on a rigid one MDR's tangential modulus is
G* = 4G/(2 − ν), so each ν is compared at the scene's G*: G = G*·(2 − ν)/4. The normal
displacement that a tangential traction also causes (the (1 − 2ν) coupling) does not strain
the film in shear and is left out, as MDR leaves it out.

Because τ is axisymmetric, u_x at radius r and angle θ has only two harmonics:
u_x(r, θ) = ū(r) + U2(r)·cos 2θ. So its average over the angle is ū = (u_x(r, 0) + u_x(r, π/2))/2
and its angular part is U2 = (u_x(r, 0) − u_x(r, π/2))/2.

- **The average.** ū(r) is compared with MDR's u3D(r) from the Abel pair (Eqs. 13–15),
  evaluated here by quadrature at the same radii. (Averaged over θ, the kernel's cos²ψ
  becomes ½, ū = (1/(π·G*))∫∫τ/|r − r'|dA', the same integral as Boussinesq's normal one,
  for which MDR is exact; the comparison checks that numerically.)
- **The angular part.** U2 is what MDR cannot represent: the film at the edge is strained
  by ±U2(a0)/h0 more or less than MDR says, depending on the angle. That is the model's
  error for this loading; it is reported as Δε = |U2(a0)|/h0 and as a share of εc.

Quadrature: polar coordinates about the field point (ρ, ψ), which take the 1/ρ singularity
into the area element; Gauss–Legendre in ρ on [0, ρ_max(ψ)] and in ψ (on the half-circle that
points into the disk for a point on the edge, otherwise on panels graded toward the outward
direction). Each result is given with its change when both quadrature orders are halved.

Usage: python3 validation/independent/mdr3d.py SCENE [--resolution M] [--order Q] --out DIR
       python3 validation/independent/mdr3d.py --exact [--order Q]
Writes DIR/mdr3d.csv: one row per moment (the first onset, and the largest F before it) and ν.
"""

import argparse
import math
import pathlib
import sys
import tomllib

import numpy as np
from numpy.polynomial.legendre import leggauss

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import independent  # noqa: E402  (the same directory: the independent implementation)

NUS = (0.0, 0.25, 0.5)
# Radii (r/a0) at which the average is compared; the edge is where the film melts first.
RADII = (0.0, 0.2, 0.4, 0.6, 0.8, 0.9, 0.95, 0.98, 0.99, 1.0)


def cerruti_integrals(tau, a0, r, order):
    """I1 = ∫∫ τ/ρ dA and I2 = ∫∫ τ·cos²ψ/ρ dA about the point (r, 0), ψ measured from x."""
    t, w = leggauss(order)
    if r >= a0 * (1 - 1e-14):
        # On the edge: only directions into the disk, ψ ∈ (π/2, 3π/2), ρ_max = −2a0·cos ψ.
        psi = np.pi / 2 + np.pi * (1 + t) / 2
        wpsi = w * np.pi / 2
    else:
        # Panels in ψ graded toward the outward direction ψ = 0, where ρ_max = a0 − r is least
        # and varies fastest (on the angular scale (a0 − r)/r).
        scale = max((a0 - r) / max(r, 1e-300), 1e-6)
        edges = [0.0]
        while edges[-1] < np.pi:
            edges.append(min(np.pi, max(2 * edges[-1], scale) if edges[-1] > 0 else scale))
        psi_list, w_list = [], []
        for lo, hi in zip(edges[:-1], edges[1:]):
            psi_list.append(lo + (hi - lo) * (1 + t) / 2)
            w_list.append(w * (hi - lo) / 2)
        half = np.concatenate(psi_list)
        whalf = np.concatenate(w_list)
        psi = np.concatenate([half, -half])  # symmetric about the x axis
        wpsi = np.concatenate([whalf, whalf])
    c, s = np.cos(psi), np.sin(psi)
    rho_max = -r * c + np.sqrt(np.maximum(a0**2 - (r * s) ** 2, 0.0))
    rho = rho_max[:, None] * (1 + t[None, :]) / 2
    wrho = rho_max[:, None] * w[None, :] / 2
    x = r + rho * c[:, None]
    y = rho * s[:, None]
    values = tau(np.sqrt(x**2 + y**2)) * wrho
    per_direction = values.sum(axis=1)
    return float(wpsi @ per_direction), float(wpsi @ (per_direction * c**2))


def displacement_3d(tau, a0, g_star, nu, r, order):
    """(ū, U2) at radius r for Poisson's ratio ν."""
    g = g_star * (2 - nu) / 4
    # u_x(r, θ) for θ = 0 and π/2: rotating the field point by π/2 turns cos²ψ into sin²ψ.
    i1, i2 = cerruti_integrals(tau, a0, r, order)
    u0 = ((1 - nu) * i1 + nu * i2) / (2 * np.pi * g)
    u90 = ((1 - nu) * i1 + nu * (i1 - i2)) / (2 * np.pi * g)
    return (u0 + u90) / 2, (u0 - u90) / 2


def mdr_u3d(tau, a0, g_star, r, order):
    """MDR's u3D(r) = (2/π)∫_0^{π/2} q(r·sin θ)/G* dθ, q(x) = 2∫_0^{√(a0²−x²)} τ(√(x² + s²)) ds."""
    t, w = leggauss(order)
    theta = (np.pi / 2) * (1 + t) / 2
    x = r * np.sin(theta)
    s_max = np.sqrt(np.maximum(a0**2 - x**2, 0.0))
    s = s_max[:, None] * (1 + t[None, :]) / 2
    q = 2 * (tau(np.sqrt(x[:, None] ** 2 + s**2)) * (s_max[:, None] * w[None, :] / 2)).sum(axis=1)
    return float((2 / np.pi) * (w * np.pi / 4) @ q) / g_star


def compare(tau, a0, g_star, h0, eps_c, order):
    """Per ν: the largest |ū − u3D| / max|u3D| over RADII, Δε = |U2(a0)|/h0, and each's change
    when the quadrature orders are halved."""
    rows = []
    for nu in NUS:
        def measure(q):
            mdr = np.array([mdr_u3d(tau, a0, g_star, f * a0, q) for f in RADII])
            three = [displacement_3d(tau, a0, g_star, nu, f * a0, q) for f in RADII]
            mean = np.array([m for m, _ in three])
            diff = float(np.max(np.abs(mean - mdr)) / np.max(np.abs(mdr)))
            return diff, abs(three[-1][1]) / h0, float(mdr[-1]), float(mean[-1])

        fine, coarse = measure(order), measure(order // 2)
        rows.append({
            "nu": nu,
            "mean_rel_diff": fine[0],
            "mean_rel_diff_change": abs(fine[0] - coarse[0]),
            "delta_eps_edge": fine[1],
            "delta_eps_edge_change": abs(fine[1] - coarse[1]),
            "delta_eps_over_eps_c": fine[1] / eps_c,
            "u3d_mdr_edge": fine[2],
            "u_mean_3d_edge": fine[3],
        })
    return rows


def tractions(scene, m):
    """τ(r) at the first onset and at the largest F before it, each as the spectral code's even
    Chebyshev series (a function of r), with its time. Before the first onset no node has been
    reset, so the state at the peak is read with the same u0 = X."""
    end = scene.get("time", {}).get("end", 1.0)
    events, film, t, y = independent.simulate(scene, m, end, max_events=1)
    if not events:
        independent.refuse(f"no onset before t = {end} s")
    a0 = scene["contact"]["radius"]
    rho = np.cos(np.arange(m + 1) * np.pi / (2 * m))
    basis = independent.even_basis(rho, m)
    out = {}
    for moment, (tt, yy) in (("onset", (t, y)), ("peak", film.peak)):
        phi, eps, _ = film.fields(tt, yy)
        coeffs = np.linalg.solve(basis, film.a * phi**2 * eps)
        out[moment] = (
            float(tt),
            lambda r, c=coeffs: independent.even_basis(np.clip(np.asarray(r) / a0, 0.0, 1.0), m) @ c,
        )
    return out


def exact_check(order):
    """Johnson's traction τ = q0·√(1 − r²/a²): ū = π·q0·(2a² − r²)/(4·G*·a) exactly (MDR
    included) and U2 = π·q0·ν·r²/(32·G·a). Returns the largest relative errors."""
    a0, q0, g_star = 2e-5, 1e6, 1e9
    tau = lambda r: q0 * np.sqrt(np.maximum(1 - (np.asarray(r) / a0) ** 2, 0.0))  # noqa: E731
    worst = 0.0
    for nu in NUS:
        g = g_star * (2 - nu) / 4
        for f in RADII:
            r = f * a0
            mean, amp = displacement_3d(tau, a0, g_star, nu, r, order)
            exact_mean = np.pi * q0 * (2 * a0**2 - r**2) / (4 * g_star * a0)
            exact_amp = np.pi * q0 * nu * r**2 / (32 * g * a0)
            mdr = mdr_u3d(tau, a0, g_star, r, order)
            scale = np.pi * q0 * a0 / (2 * g_star)
            worst = max(worst, abs(mean - exact_mean) / scale, abs(amp - exact_amp) / scale,
                        abs(mdr - exact_mean) / scale)
    return worst


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?")
    parser.add_argument("--resolution", type=int, default=24, help="M of the spectral code")
    parser.add_argument("--order", type=int, default=96, help="Gauss–Legendre points per panel")
    parser.add_argument("--exact", action="store_true", help="only the exact traction's check")
    parser.add_argument("--out")
    args = parser.parse_args(argv)
    if args.resolution < 4:
        independent.refuse(f"--resolution = {args.resolution}; allowed: an integer ≥ 4")
    if args.out is not None and pathlib.Path(args.out).exists() and not pathlib.Path(args.out).is_dir():
        independent.refuse(f"--out = {args.out} is a file; allowed: a directory (made if missing)")
    if args.order < 8:
        independent.refuse(f"--order = {args.order}; allowed: an integer ≥ 8")
    if args.exact:
        print(f"exact traction: largest relative error {exact_check(args.order):.3e}")
        return
    if args.scene is None or args.out is None:
        independent.refuse("SCENE and --out are needed (or --exact)")
    with open(args.scene, "rb") as f:
        scene = tomllib.load(f)
    independent.check_scene(scene)
    lub, con = scene["lubricant"], scene["contact"]
    b = 2 * lub["a"] ** 2 * lub["eps_max"] ** 3 / lub["tau_max"]
    big_a = 1.5 * lub["tau_max"] / lub["eps_max"]
    eps_c = math.sqrt(big_a * b) / lub["a"]
    lines = []
    for moment, (t, tau) in tractions(scene, args.resolution).items():
        rows = compare(tau, con["radius"], con["g_eff"], con["film_thickness"], eps_c, args.order)
        columns = list(rows[0].keys())
        if not lines:
            lines = [",".join(["moment", "t"] + columns)]
        lines += [",".join([moment, repr(t)] + [repr(float(r[c])) for c in columns]) for r in rows]
        for r in rows:
            print(f"{moment} (t = {t:.9e} s), ν = {r['nu']}: mean against MDR {r['mean_rel_diff']:.2e} "
              f"(±{r['mean_rel_diff_change']:.1e}), Δε at the edge {r['delta_eps_edge']:.4e} "
                  f"= {r['delta_eps_over_eps_c']:.3e}·εc (±{r['delta_eps_edge_change']:.1e})")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tmp = out / "mdr3d.csv.tmp"
    tmp.write_text("\n".join(lines) + "\n")
    tmp.replace(out / "mdr3d.csv")


if __name__ == "__main__":
    main(sys.argv[1:])
