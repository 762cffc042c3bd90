"""Fitting the model to a friction trace (docs/fit.md), on traces whose answer is known: fig2's
scene is run with τmax = 1.15e6 Pa and γ = 8 /(Pa·s), noise is added to its F(t), and
``stickslip.fit`` recovers both from each noisy trace with their 95 % intervals. Over several
noise seeds it counts how often the intervals hold the truth (their coverage, about 95 % when
they are right).

    python examples/fit.py                 # N = 100, 1.3 ms, 10 seeds
    python examples/fit.py --quick         # N = 30, 1 ms, 2 seeds (what the tests run)
    python examples/fit.py --seeds 40 --nodes 50
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import stickslip

ROOT = Path(__file__).resolve().parents[1]
TRUTH = {"lubricant.tau_max": 1.15e6, "lubricant.gamma": 8.0}
BOUNDS = {"lubricant.tau_max": (5e5, 2e6), "lubricant.gamma": (3.0, 30.0)}
NOISE_N = 1e-5  # standard deviation of the noise added to F, N (about 1 % of its peaks)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="N = 30, 1 ms, 2 seeds")
    ap.add_argument("--nodes", type=int, default=None, help="contact.nodes (default 100; 30 with --quick)")
    ap.add_argument("--seeds", type=int, default=None, help="noise seeds (default 10; 2 with --quick)")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    nodes = a.nodes or (30 if a.quick else 100)
    seeds = a.seeds or (2 if a.quick else 10)
    end_s = 1e-3 if a.quick else 1.3e-3

    scene = stickslip.Scene.load(ROOT / "validation" / "scenes" / "fig2.toml").with_overrides(
        {"contact.nodes": nodes, "time.end": end_s, "output.profile_times": []}
    )
    # The true trace, at the tolerance the fit's own runs use (the scene's / 100), sampled
    # about every 2 µs.
    truth = stickslip.run(
        scene.with_overrides(
            {**TRUTH, "time.tolerance": 5e-7, "output.series_interval": 2e-6}
        )
    )
    t, f = truth.series["t"], truth.series["F"]
    print(f"fig2, N = {nodes}, {end_s * 1e3:g} ms: {len(t)} samples, {len(truth.events['t_onset'])} meltings")

    params = [f"{k}={lo:g}:{hi:g}" for k, (lo, hi) in BOUNDS.items()]
    covered = {k: 0 for k in TRUTH}
    for seed in range(1, seeds + 1):
        noisy = f + np.random.default_rng(seed).normal(0.0, NOISE_N, f.shape)
        started = time.perf_counter()
        r = stickslip.fit(scene, {"t": t, "F": noisy}, params, jobs=a.jobs)
        parts = []
        for k, true in TRUTH.items():
            lo, hi = r.intervals[k]
            inside = lo <= true <= hi
            covered[k] += inside
            parts.append(f"{k} = {r.values[k]:.5g} [{lo:.5g}, {hi:.5g}]{'' if inside else ' MISSES'}")
        print(f"seed {seed}: " + "; ".join(parts)
              + f"; χ² {r.misfit:.1f}, {time.perf_counter() - started:.1f} s")
    for k in TRUTH:
        print(f"coverage of {k}: {covered[k]} of {seeds} 95 % intervals hold the truth")


if __name__ == "__main__":
    main()
