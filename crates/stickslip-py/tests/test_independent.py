"""fig2's first three events from an implementation that shares no code with stickslip
(validation/independent/independent.py: a spectral MDR pair and SciPy's Radau with each
node's melting an event) against stickslip's own, run from Python. A regression of more than
a nanosecond in either code's onsets, or of 1e-6 in f_peak, fails.

Measured when this test was written (onsets in µs):
- independent, M = 12: 597.5471328, 753.7851635, 863.6629236, within 0.1 ns of M = 32;
- stickslip, N = 200, time.tolerance = 5e-7: 597.5470990, 753.7851288, 863.6628854;
- f_peak: 1.2539342, 1.2540381, 1.2541217 mN against stickslip's within 2.3e-7 relative.

At N = 200 stickslip's own spatial error is about 0.4–0.8 ns (reports/index.md, "Independent
implementation", has both codes converged).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import stickslip
from conftest import ROOT, SCENES, read_csv

INDEPENDENT = ROOT / "validation" / "independent" / "independent.py"


def test_fig2s_first_events_agree_with_the_independent_implementation(tmp_path: Path) -> None:
    out = tmp_path / "independent"
    subprocess.run(
        [
            sys.executable,
            str(INDEPENDENT),
            str(SCENES / "fig2.toml"),
            "--end",
            "1e-3",
            "--resolution",
            "12",
            "--events",
            "3",
            "--out",
            str(out),
        ],
        check=True,
        capture_output=True,
    )
    theirs = read_csv(out / "events.csv")
    ours = stickslip.run(
        stickslip.Scene.load(
            SCENES / "fig2.toml",
            {
                "contact.nodes": 200,
                "time.tolerance": 5e-7,
                "time.max_events": 3,
                "output.profile_times": [],
                "output.series_interval": 1e-5,
            },
        )
    )
    assert len(theirs["t_onset"]) == 3 and len(ours.events["t_onset"]) == 3
    for k in range(3):
        t_theirs, t_ours = float(theirs["t_onset"][k]), float(ours.events["t_onset"][k])
        f_theirs, f_ours = float(theirs["f_peak"][k]), float(ours.events["f_peak"][k])
        print(f"event {k + 1}: onset {t_theirs!r} / {t_ours!r} s, f_peak {f_theirs!r} / {f_ours!r} N")
        assert abs(t_ours - t_theirs) < 1.5e-9, (k, t_ours, t_theirs)
        assert abs(f_ours / f_theirs - 1) < 1e-6, (k, f_ours, f_theirs)


def test_the_independent_implementation_refuses_what_it_does_not_model(tmp_path: Path) -> None:
    done = subprocess.run(
        [
            sys.executable,
            str(INDEPENDENT),
            str(SCENES / "fig2_first_order.toml"),
            "--out",
            str(tmp_path / "x"),
        ],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert "lubricant.eps_melt" in done.stderr


MDR3D = ROOT / "validation" / "independent" / "mdr3d.py"


def test_the_3d_quadrature_reproduces_johnsons_exact_tangential_displacement() -> None:
    """τ = q0·√(1 − r²/a²) along x: the mean displacement (and MDR's) and the cos 2θ part
    against Johnson's closed form, for ν = 0, 0.25, 0.5 (measured 7.6e-6 at order 32)."""
    done = subprocess.run(
        [sys.executable, str(MDR3D), "--exact", "--order", "32"],
        check=True,
        capture_output=True,
        text=True,
    )
    worst = float(done.stdout.split()[-1])
    assert worst < 2e-5, done.stdout


def test_mdr_against_3d_elasticity_on_fig2s_first_slip(tmp_path: Path) -> None:
    """Averaged over the angle, Cerruti's half-space displacement equals MDR's u3D (to
    rounding: the average of the kernel is Boussinesq's, for which MDR is exact). What MDR
    misses is the cos 2θ part, ∝ ν/(2 − ν) at the same G*: none at ν = 0. At the largest force
    before fig2's first onset it strains the edge by ±0.0283 (1.6 % of εc) at ν = 0.5
    (measured at M = 24, order 96: 2.8269e-2; reports/index.md, "MDR against 3D elasticity")."""
    out = tmp_path / "mdr3d"
    subprocess.run(
        [
            sys.executable,
            str(MDR3D),
            str(SCENES / "fig2.toml"),
            "--resolution",
            "12",
            "--order",
            "64",
            "--out",
            str(out),
        ],
        check=True,
        capture_output=True,
    )
    lines = (out / "mdr3d.csv").read_text().splitlines()
    header = lines[0].split(",")
    rows = [dict(zip(header, line.split(","))) for line in lines[1:]]
    assert {r["moment"] for r in rows} == {"onset", "peak"}
    for r in rows:
        assert float(r["mean_rel_diff"]) < 1e-10, r
    peak = {float(r["nu"]): float(r["delta_eps_edge"]) for r in rows if r["moment"] == "peak"}
    assert peak[0.0] == 0.0
    assert abs(peak[0.5] / 2.8269e-2 - 1) < 0.01, peak
    # The angular part scales as ν/(2 − ν) (Cerruti's ν term over G = G*·(2 − ν)/4).
    assert abs(peak[0.25] / peak[0.5] - (0.25 / 1.75) / (0.5 / 1.5)) < 1e-9, peak


def test_the_independent_codes_refuse_bad_options_before_computing(tmp_path: Path) -> None:
    afile = tmp_path / "afile"
    afile.write_text("")
    for script, args in [
        (INDEPENDENT, ["--out", str(afile)]),
        (INDEPENDENT, ["--events", "0", "--out", str(tmp_path / "x")]),
        (MDR3D, ["--resolution", "2", "--out", str(tmp_path / "y")]),
    ]:
        done = subprocess.run(
            [sys.executable, str(script), str(SCENES / "fig2.toml"), *args],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert done.returncode == 2, (script, args, done.stderr)
        assert "allowed" in done.stderr, done.stderr
    assert afile.read_text() == ""
