"""Your own contact from scratch: a surface-force-apparatus (SFA) experiment, step by step
(docs/experiment.md walks through the same steps with the command line).

1. The scene: fig2's film under a 20 µm stamp, a 1 nm film, a soft spring pulled at 1 µm/s.
2. check: when the first melting comes (the linearised problem), what the run will cost and
   how large its output will be; time.end and the series interval chosen from them.
3. verify: the error of every number at the chosen N; refine N until the numbers you need
   are within your accuracy, or know how far off they are.
4. A run to just past the first melting, with and without a dashpot (drive.damping) that
   damps the stamp's ringing after the slip.
5. Slips and statistics: the stamp's slips (each made of meltings of the film), the
   stamp-scale regime, and how often the film melts and the stamp slips once settled.
6. boundary: where along the drive speed the regime changes, each change with its error.

    pip install ./crates/stickslip-py        # from the workspace root; gives `stickslip` too
    python examples/experiment.py [--quick]

--quick (or STICKSLIP_EXAMPLE_QUICK=1): small sizes for a smoke test (the test command runs
it so); without it the script takes a few minutes.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import stickslip

ROOT = Path(__file__).resolve().parents[1]

# The contact, as a user writes it: every value with its unit (docs/reference.md lists every
# key, its unit, default and range).
SCENE = """
name = "my-sfa"

[lubricant]            # fig2's film
tau_max = 1e6          # Pa
eps_max = 1.0
a = 1e6                # Pa
gamma = 10.0           # 1/(Pa·s)

[contact]
radius = 2e-5          # m   stamp radius a0
film_thickness = 1e-9  # m   a 1 nm film
g_eff = 1e9            # Pa  effective shear modulus G*
nodes = 200

[drive]
kind = "spring"
stiffness = 5000.0     # N/m
mass = 0.1             # kg
velocity = 1e-6        # m/s: 1 µm/s

[time]
end = 1.0              # s: a first guess, checked below

[output]
profile_times = []
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    quick = args.quick or os.environ.get("STICKSLIP_EXAMPLE_QUICK") == "1"
    nodes = 50 if quick else 200

    # 1. The scene.
    scene = stickslip.Scene.from_toml(SCENE).with_overrides({"contact.nodes": nodes})

    # 2. check: the first onset, the cost, the output's size.
    report = scene.check()
    onset = report["derived"]["first_onset_estimate"]
    spring = report["contact_spring"]
    print(
        f"check: first melting expected at {onset:.4g} s (the contact as a spring of "
        f"{spring['f_melt_n'] / spring['x_melt_m']:.3g} N/m melting at F = "
        f"{spring['f_melt_n'] * 1e3:.3g} mN)"
    )
    print(f"check: output {report['output']['bytes'] / 1e6:.1f} MB at the default series interval")
    for w in report["warnings"]:
        print(f"check: {w['severity']}: {w['message'][:120]}…")
    # time.end a little past the first melting, a series row every 0.1 ms, and the run stopped
    # after its first few meltings.
    end = 1.2 * onset
    scene = scene.with_overrides({"time.end": end, "output.series_interval": 1e-4})
    short = scene.with_overrides({"time.max_events": 4})

    # 3. verify: every number's error at this N (a loose accuracy in the quick version).
    rtol = 5e-2 if quick else 1e-2
    v = stickslip.verify(short, rtol=rtol)
    first = next(q for q in v["quantities"] if q["name"] == "t_first_onset")
    print(
        f"verify at N = {nodes}: first onset {first['value']:.5g} s ± {first['uncertainty']:.2g} s "
        f"({first['verdict']})"
    )

    # 4. The run, without and with a dashpot of damping ratio about 0.5.
    zeta = 0.5
    damping = 2 * zeta * (5000.0 * 0.1) ** 0.5
    plain = stickslip.run(short)
    damped = stickslip.run(short.with_overrides({"drive.damping": damping}))
    for label, res in (("undamped", plain), (f"damping {damping:.3g} N·s/m", damped)):
        s = res.summary
        print(
            f"run ({label}): {s['n_events']} meltings, first at {s['t_first_onset']:.5g} s, "
            f"regime {s['regime']}"
        )

    # 5. Slips and statistics over three times the first stick, damped and not.
    for label, extra in (("undamped", {}), ("damped", {"drive.damping": damping})):
        long = stickslip.run(scene.with_overrides({"time.end": 3 * onset, **extra}))
        s, slips = long.summary, long.slips
        c = s["cycles"]
        biggest = int(slips["drop"].argmax()) if len(slips["k"]) else None
        line = f"slips ({label}): {s['n_slips']} slips, stamp regime {s['stamp_regime']}"
        if biggest is not None:
            line += (
                f"; the largest drops {slips['drop'][biggest] * 1e3:.3g} mN, the stamp jumps "
                f"{slips['jump'][biggest] * 1e6:.3g} µm through {slips['meltings'][biggest]} meltings"
            )
        print(line)
        for scale in ("slips", "meltings"):
            iv = c[scale]["interval"]
            if iv is not None:
                print(
                    f"  settled from {c['settled_from']:.4g} s: {scale} every "
                    f"{iv['median'] * 1e3:.4g} ms (median; CV {iv['cv']:.2g}, {iv['n']} intervals)"
                )

    # 6. boundary: where the regime changes along the drive speed, each change with its
    # error, for the same contact under a rigid drive (X = V0·t; on the command line:
    # `--unset drive.stiffness --unset drive.mass --set drive.kind=rigid`).
    rigid_toml = SCENE.replace(
        'kind = "spring"\nstiffness = 5000.0     # N/m\nmass = 0.1             # kg\n',
        'kind = "rigid"\n',
    )
    rigid = stickslip.Scene.from_toml(rigid_toml).with_overrides(
        {
            "contact.nodes": 50 if quick else 100,
            "time.end": 5e-5 if quick else 1e-4,
            "time.max_events": 6,
        }
    )
    lo, hi = (1e-3, 1e-2) if quick else (1e-3, 1e-1)
    b = stickslip.boundary(
        rigid, "drive.velocity", lo, hi, rtol=5e-2 if quick else 1e-3, scan=3 if quick else 17
    )
    for c in b["changes"]:
        print(
            f"boundary: {c['below']} -> {c['above']} at {c['value']:.4g} m/s ± {c['error']:.2g} m/s"
        )
    for w in b["warnings"]:
        print(f"boundary: warning: {w[:120]}…")


if __name__ == "__main__":
    main()
