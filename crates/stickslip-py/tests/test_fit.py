"""stickslip.fit: a synthetic trace (fig2 at N = 30, made by the model itself with a known
noise) fitted from a dict of arrays with renamed columns; the same report as the command line
on the same data; the fitted scene; bad input as ValueError naming the field; a progress
callback's KeyboardInterrupt keeps the best fit so far."""

from __future__ import annotations

import json
import math
import os
import subprocess

import numpy as np
import pytest

import stickslip
from conftest import ROOT

FIG2 = ROOT / "validation" / "scenes" / "fig2.toml"
TAU_MAX = 1.15e6
PARAMS = ["lubricant.tau_max=5e5:2e6"]


def scene() -> stickslip.Scene:
    return stickslip.Scene.load(FIG2).with_overrides({"contact.nodes": 30})


@pytest.fixture(scope="module")
def trace() -> dict:
    truth = scene().with_overrides(
        {
            "time.end": 1e-3,
            "time.tolerance": 5e-7,
            "output.profile_times": [],
            "output.series_interval": 2e-6,
            "lubricant.tau_max": TAU_MAX,
        }
    )
    res = stickslip.run(truth)
    rng = np.random.default_rng(7)
    f = res.series["F"] + rng.normal(0.0, 1e-5, res.series["F"].shape)
    return {"time": res.series["t"].copy(), "force": f}


def test_a_fit_finds_known_parameters_and_matches_the_command_line(trace, tmp_path) -> None:
    r = stickslip.fit(scene(), trace, PARAMS, columns={"t": "time", "F": "force"}, jobs=2)
    lo, hi = r.intervals["lubricant.tau_max"]
    assert lo <= TAU_MAX <= hi
    assert r.status == "ok" and r.stderr["lubricant.tau_max"] > 0
    assert r.correlation.shape == (1, 1)
    assert isinstance(r.scene, stickslip.Scene)
    assert r.scene.to_dict()["lubricant"]["tau_max"] == r.values["lubricant.tau_max"]
    assert r.model_f.shape == r.t.shape == r.f.shape
    report = r.to_dict()
    assert report["parameters"][0]["key"] == "lubricant.tau_max"
    # The command line, on the same numbers written as a file, reports the same fit.
    path = tmp_path / "trace.csv"
    path.write_text("time,force\n" + "".join(f"{float(t)!r},{float(f)!r}\n" for t, f in zip(trace["time"], trace["force"])))
    out = tmp_path / "fit"
    subprocess.run(
        [os.environ["STICKSLIP_BIN"], "fit", str(FIG2), "--set", "contact.nodes=30", "--data", str(path),
         "--columns", "t=time,F=force", "--param", PARAMS[0], "--out", str(out), "--quiet"],
        check=True, capture_output=True,
    )
    cli = json.loads((out / "fit.json").read_text())
    for d in (cli, report):
        d.pop("wall_s")
    assert cli == report
    # And from the file through Python too, writing the command line's three files: fit.json
    # equal but for the wall time, fit.svg and fitted.toml byte for byte.
    mine = tmp_path / "py" / "fit"
    again = stickslip.fit(scene(), path, PARAMS, columns={"t": "time", "F": "force"}, out=mine)
    assert again.values == r.values
    written = json.loads((mine / "fit.json").read_text())
    written.pop("wall_s")
    assert written == cli
    for name in ("fit.svg", "fitted.toml"):
        assert (mine / name).read_bytes() == (out / name).read_bytes(), name
    # A directory that cannot be made is an OSError.
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(OSError, match="cannot write"):
        stickslip.fit(scene(), path, PARAMS, columns={"t": "time", "F": "force"}, out=blocker / "sub")


def test_bad_input_raises_value_error_naming_the_field(trace) -> None:
    cols = {"t": "time", "F": "force"}
    with pytest.raises(ValueError, match="--param = lubricant.nope"):
        stickslip.fit(scene(), trace, ["lubricant.nope"], columns=cols)
    with pytest.raises(ValueError, match="LO < HI"):
        stickslip.fit(scene(), trace, ["lubricant.tau_max=2e6:1e6"], columns=cols)
    bad = {"time": trace["time"].copy(), "force": trace["force"].copy()}
    bad["force"][3] = np.nan
    with pytest.raises(ValueError, match="trace F at sample 4 = nan"):
        stickslip.fit(scene(), bad, PARAMS, columns=cols)
    back = {"time": trace["time"][::-1].copy(), "force": trace["force"]}
    with pytest.raises(ValueError, match="trace t at sample 2"):
        stickslip.fit(scene(), back, PARAMS, columns=cols)
    with pytest.raises(ValueError, match="no column 't'"):
        stickslip.fit(scene(), trace, PARAMS)
    with pytest.raises(ValueError, match="misfit"):
        stickslip.fit(scene(), trace, PARAMS, misfit="nope", columns=cols)
    with pytest.raises(ValueError, match="jacobian = 'adjoint' is invalid"):
        stickslip.fit(scene(), trace, PARAMS, columns=cols, jacobian="adjoint")


def test_a_fit_with_replayed_jacobians_matches_the_command_lines(trace, tmp_path) -> None:
    # jacobian="replay" as `stickslip fit --jacobian replay`: the same fit.json, which says
    # how its Jacobians were made.
    cols = {"t": "time", "F": "force"}
    r = stickslip.fit(scene(), trace, PARAMS, columns=cols, jobs=2, jacobian="replay")
    lo, hi = r.intervals["lubricant.tau_max"]
    assert lo <= TAU_MAX <= hi
    report = r.to_dict()
    assert report["jacobian"] == "replay"
    path = tmp_path / "trace.csv"
    path.write_text("time,force\n" + "".join(f"{float(t)!r},{float(f)!r}\n" for t, f in zip(trace["time"], trace["force"])))
    out = tmp_path / "fit"
    subprocess.run(
        [os.environ["STICKSLIP_BIN"], "fit", str(FIG2), "--set", "contact.nodes=30", "--data", str(path),
         "--columns", "t=time,F=force", "--param", PARAMS[0], "--out", str(out), "--quiet",
         "--jacobian", "replay"],
        check=True, capture_output=True,
    )
    cli = json.loads((out / "fit.json").read_text())
    for d in (cli, report):
        d.pop("wall_s")
    assert cli == report


def test_an_interrupt_keeps_the_best_fit_so_far(trace) -> None:
    seen = []

    tolerances = []

    def stop_in_the_local_stage(p: dict) -> None:
        seen.append(p["stage"])
        tolerances.append(p["tolerance"])
        if p["stage"] == "local":
            raise KeyboardInterrupt

    with pytest.raises(stickslip.Interrupted) as e:
        stickslip.fit(
            scene(), trace, PARAMS + ["lubricant.gamma=3:30"], columns={"t": "time", "F": "force"},
            jobs=1, progress=stop_in_the_local_stage,
        )
    assert "local" in seen
    # The runs' tolerance: the scene's adaptive steps, tightened tenfold at a time from the
    # fit's first one, never looser.
    assert all(isinstance(t, float) and 0 < t <= tolerances[0] for t in tolerances)
    assert all(round(math.log10(tolerances[0] / t), 9).is_integer() for t in tolerances)
    result = e.value.result
    assert result is not None and result.status == "interrupted"
    assert set(result.values) == {"lubricant.tau_max", "lubricant.gamma"}
