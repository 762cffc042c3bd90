"""The paper's Figure 2 from Python, and a small friction map.

1. Runs validation/scenes/fig2.toml at N = 200 nodes (stickslip.run) and plots the friction
   force F(t) with the melting onsets, and the order parameter φ(r) at the end.
2. Runs a friction map over drive.velocity × temperature.A0 of validation/scenes/rigid.toml
   (stickslip.sweep) and draws the regime of every point and its mean force.

    pip install ./crates/stickslip-py matplotlib      # from the workspace root
    python examples/fig2.py [--quick] [--no-plot] [--out DIR] [--jobs J]

--quick (or STICKSLIP_EXAMPLE_QUICK=1): small sizes, for a smoke test (N = 50, a 2 × 2 map).
--no-plot: numbers only. Without matplotlib the plots are skipped with a message.
Figures are written to DIR (default out/python-example) as PNG.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

import stickslip

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "validation" / "scenes"


def run_fig2(nodes: int) -> stickslip.RunResult:
    scene = stickslip.Scene.load(SCENES / "fig2.toml").with_overrides({"contact.nodes": nodes})
    start = time.perf_counter()
    res = stickslip.run(scene)
    s = res.summary

    def us(x: float | None) -> str:
        return "none" if x is None else f"{x * 1e6:.2f} µs"

    print(
        f"fig2, N = {nodes}: {res.run_info['steps']} steps in {time.perf_counter() - start:.2f} s; "
        f"{s['n_events']} events, regime {s['regime']}, first onset {us(s['t_first_onset'])}, "
        f"last period {us(s['period_last'])}"
    )
    return res


def friction_map(quick: bool, jobs: int | None) -> dict:
    velocity = {"values": [1e-3, 1.0]} if quick else {
        "range": {"from": 1e-3, "to": 3.0, "count": 6, "scale": "log"}}
    a0 = {"values": [-2e5, 1.5e6]} if quick else {
        "range": {"from": -3e5, "to": 1.5e6, "count": 5}}
    sweep = {
        "name": "rigid-speed-temperature (example)",
        "scene": stickslip.Scene.load(SCENES / "rigid.toml"),
        "set": {
            "contact.nodes": 20 if quick else 50,
            "time.end": 2e-3,
            "time.max_events": 3 if quick else 6,
            "time.max_open_event": 2e-5,
            "output.profile_times": [2e-3],
        },
        "axis": [{"key": "drive.velocity", **velocity}, {"key": "temperature.A0", **a0}],
    }
    start = time.perf_counter()
    table = stickslip.sweep(sweep, jobs=jobs)
    regimes, counts = np.unique(table["regime"].astype(str), return_counts=True)
    print(
        f"friction map: {len(table['point'])} points in {time.perf_counter() - start:.2f} s; "
        + ", ".join(f"{r} {c}" for r, c in zip(regimes, counts))
    )
    return table


def plot(res: stickslip.RunResult, table: dict, out: Path) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: plots skipped (pip install matplotlib)")
        return
    out.mkdir(parents=True, exist_ok=True)

    fig, (ax_f, ax_phi) = plt.subplots(1, 2, figsize=(11, 4))
    ax_f.plot(res.series["t"] * 1e3, res.series["F"] * 1e3, lw=0.8)
    for t in res.events["t_onset"]:
        ax_f.axvline(t * 1e3, color="C3", lw=0.5, alpha=0.5)
    ax_f.set(xlabel="t (ms)", ylabel="F (mN)", title="friction force; red: melting onsets")
    end = res.profiles["t"] == res.profiles["t"].max()
    ax_phi.plot(res.profiles["r"][end] * 1e6, res.profiles["phi"][end])
    ax_phi.set(xlabel="r (µm)", ylabel="φ", title=f"order parameter at t = {res.profiles['t'].max() * 1e3:g} ms")
    fig.tight_layout()
    fig.savefig(out / "fig2.png", dpi=120)
    plt.close(fig)

    v = np.unique(table["drive.velocity"])
    a = np.unique(table["temperature.A0"])
    names = ["sliding", "no_melting", "transient", "stick_slip", "partial", "smooth"]
    code = np.array([names.index(r) for r in table["regime"]]).reshape(len(v), len(a))
    f_mean = table["f_mean"].reshape(len(v), len(a))
    fig, (ax_r, ax_m) = plt.subplots(1, 2, figsize=(11, 4))
    # One cell per point, on the point indices (the speeds are log-spaced), values as labels.
    ax_r.imshow(code, cmap="tab10", vmin=0, vmax=9, origin="lower", aspect="auto")
    for i in range(len(v)):
        for j in range(len(a)):
            ax_r.text(j, i, names[code[i, j]], ha="center", va="center", fontsize=7)
    ax_r.set_title("regime")
    im = ax_m.imshow(f_mean * 1e3, origin="lower", aspect="auto")
    fig.colorbar(im, ax=ax_m, label="mean F over the last cycle (mN)")
    ax_m.set_title("mean friction force (blank: no complete cycle)")
    for ax in (ax_r, ax_m):
        ax.set_xticks(range(len(a)), [f"{x / 1e6:g}" for x in a])
        ax.set_yticks(range(len(v)), [f"{x:.3g}" for x in v])
        ax.set(xlabel="A0 (MPa)", ylabel="V0 (m/s)")
    fig.tight_layout()
    fig.savefig(out / "friction_map.png", dpi=120)
    plt.close(fig)
    print(f"figures written to {out / 'fig2.png'} and {out / 'friction_map.png'}")


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="small sizes (smoke test)")
    p.add_argument("--no-plot", action="store_true", help="numbers only")
    p.add_argument("--out", type=Path, default=ROOT / "out" / "python-example")
    p.add_argument("--jobs", type=int, default=None, help="map points in parallel")
    args = p.parse_args(argv)
    quick = args.quick or os.environ.get("STICKSLIP_EXAMPLE_QUICK") == "1"
    res = run_fig2(50 if quick else 200)
    table = friction_map(quick, args.jobs)
    if not args.no_plot:
        plot(res, table, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
