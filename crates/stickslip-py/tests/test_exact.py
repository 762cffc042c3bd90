"""A Python run gives the command line's numbers bit for bit: every column of every CSV file
the CLI wrote, and run.json's summary, for fig2 at N = 200 and for a gaussian-noise scene."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import stickslip
from conftest import SCENES, read_csv, same_bits

TABLES = ("series", "events", "profiles", "probes")

CASES = {
    # fig2 at N = 200 with its defaults (accurate scheme, adaptive steps, fast operator).
    "fig2_n200": ("fig2.toml", {"contact.nodes": 200}),
    # Thermal noise: fixed steps, per-node random streams; up to just past the first event.
    "fig2_gaussian": (
        "fig2.toml",
        {
            "contact.nodes": 200,
            "lubricant.noise.kind": "gaussian",
            "lubricant.noise.sigma": 1.0,
            "lubricant.noise.seed": 7,
            "time.end": 6.1e-4,
            "output.profile_times": [3e-4, 6.1e-4],
        },
    ),
}


def set_args(overrides: dict) -> list:
    args = []
    for key, value in overrides.items():
        if isinstance(value, list):
            text = "[" + ", ".join(repr(v) for v in value) + "]"
        else:
            text = str(value)
        args += ["--set", f"{key}={text}"]
    return args


@pytest.mark.parametrize("case", sorted(CASES))
def test_python_run_matches_the_cli_bit_for_bit(case: str, cli: Path, tmp_path: Path) -> None:
    scene_file, overrides = CASES[case]
    out = tmp_path / "out"
    subprocess.run(
        [str(cli), "run", str(SCENES / scene_file), "--out", str(out), "--quiet"]
        + set_args(overrides),
        check=True,
        stdout=subprocess.DEVNULL,
    )
    res = stickslip.run(stickslip.Scene.load(SCENES / scene_file).with_overrides(overrides))
    assert res.status == "ok"
    compared = 0
    for table in TABLES:
        written = read_csv(out / f"{table}.csv")
        ours = getattr(res, table)
        assert list(ours) == list(written), f"{table}: columns differ"
        for name, col in written.items():
            assert same_bits(ours[name], col), (
                f"{case}: {table}.csv column {name} differs: max |Δ| = "
                f"{np.nanmax(np.abs(ours[name] - col)) if len(col) else 0}"
            )
            compared += col.size
    assert compared > 1000
    assert len(res.events["k"]) >= 1
    run_json = json.loads((out / "run.json").read_text())
    assert res.summary == run_json["summary"]
    # run.json otherwise: everything but the wall-clock time.
    for key, value in run_json.items():
        if key in ("summary", "wall_seconds"):
            continue
        assert res.run_info[key] == value, key
    assert list(res.run_info) == [k for k in run_json if k != "summary"]
