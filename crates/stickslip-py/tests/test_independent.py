"""The first onset of fig2 from an implementation that shares no code with stickslip
(validation/independent/independent.py: a spectral MDR pair and SciPy's Radau) against
stickslip's own, run from Python. A regression of more than a nanosecond in either code fails.

Measured when this test was written:
- independent, M = 12: 0.59754713285 ms, within 1e-15 s of its M = 32 value;
- stickslip, N = 200, time.tolerance = 5e-7: 0.5975470990 ms;
- stickslip, N = 4000, time.tolerance = 5e-7: 0.5975471806 ms, 0.05 ns from the independent
  value.

At N = 200 stickslip's own spatial error is about 0.8 ns.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import stickslip
from conftest import ROOT, SCENES, read_csv

INDEPENDENT = ROOT / "validation" / "independent" / "independent.py"


def test_fig2s_first_onset_agrees_with_the_independent_implementation(tmp_path: Path) -> None:
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
            "--out",
            str(out),
        ],
        check=True,
        capture_output=True,
    )
    independent = float(read_csv(out / "events.csv")["t_onset"][0])
    ours = stickslip.run(
        stickslip.Scene.load(
            SCENES / "fig2.toml",
            {
                "contact.nodes": 200,
                "time.tolerance": 5e-7,
                "time.max_events": 1,
                "output.profile_times": [],
                "output.series_interval": 1e-5,
            },
        )
    )
    onset = float(ours.events["t_onset"][0])
    print(f"independent {independent!r} s, stickslip {onset!r} s")
    assert abs(onset - independent) < 1.5e-9, (onset, independent)


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
