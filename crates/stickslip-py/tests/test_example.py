"""examples/fig2.py, experiment.py and fit.py run (quick sizes; plots only when matplotlib is
installed)."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

from conftest import ROOT


def test_example_script_runs(tmp_path: Path) -> None:
    has_mpl = importlib.util.find_spec("matplotlib") is not None
    args = [sys.executable, str(ROOT / "examples" / "fig2.py"), "--out", str(tmp_path)]
    if not has_mpl:
        args.append("--no-plot")
    env = dict(os.environ, STICKSLIP_EXAMPLE_QUICK="1", MPLBACKEND="Agg")
    done = subprocess.run(args, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "fig2, N = 50" in done.stdout and "friction map: 4 points" in done.stdout
    if has_mpl:
        assert (tmp_path / "fig2.png").is_file() and (tmp_path / "friction_map.png").is_file()


def test_the_experiment_walkthrough_runs(tmp_path: Path) -> None:
    """examples/experiment.py, the script of docs/experiment.md, at its quick sizes."""
    args = [sys.executable, str(ROOT / "examples" / "experiment.py"), "--quick"]
    done = subprocess.run(args, capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    out = done.stdout
    for needle in ("check: first melting expected at", "verify at N = 50: first onset",
                   "run (undamped): 4 meltings", "run (damping", "boundary: stick_slip -> "):
        assert needle in out, out


def test_the_fit_example_runs() -> None:
    """examples/fit.py, synthetic traces fitted (docs/fit.md), at its quick size."""
    args = [sys.executable, str(ROOT / "examples" / "fit.py"), "--quick"]
    done = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    out = done.stdout
    assert "fig2, N = 30, 1 ms" in out and "4 meltings" in out, out
    for needle in ("seed 1: lubricant.tau_max = ", "seed 2: ", "coverage of lubricant.gamma: "):
        assert needle in out, out
