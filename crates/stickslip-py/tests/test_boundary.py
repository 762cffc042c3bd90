"""stickslip.boundary: the command line's scan and bisections from Python, the same numbers,
every change with its error, bad calls as exceptions."""

from __future__ import annotations

import os
import subprocess

import pytest

import stickslip
from conftest import ROOT

SETS = {
    "contact.nodes": 50,
    "time.max_events": 6,
    "time.max_open_event": 2e-5,
    "temperature.A0": 1e6,
}


def rigid() -> stickslip.Scene:
    return stickslip.Scene.load(ROOT / "validation" / "scenes" / "rigid.toml").with_overrides(SETS)


def test_boundary_brackets_the_critical_speed_as_the_cli_does() -> None:
    b = stickslip.boundary(rigid(), "drive.velocity", 0.01, 3.0, rtol=1e-3)
    assert b["below"] == "stick_slip" and b["above"] == "partial"
    assert b["lo"] < b["value"] < b["hi"] and b["hi"] - b["lo"] <= 1e-3 * b["hi"] * 1.0001
    assert b["runs"] == len(b["probes"]) == sum(c["runs"] for c in b["changes"]) + len(b["scan"])
    assert b["error"] >= 0.5 * (b["hi"] - b["lo"]) * 0.999
    assert [(c["below"], c["above"]) for c in b["changes"]] == [("stick_slip", "partial"), ("partial", "smooth")]
    assert set(b["changes"][0]["moves"]) == {"2N", "tolerance/10"}
    assert {p["stage"] for p in b["probes"]} >= {"scan", "bisect", "2N", "tolerance/10"}
    # The command line finds the same bracket.
    args = [os.environ["STICKSLIP_BIN"], "boundary", str(ROOT / "validation/scenes/rigid.toml"),
            "--key", "drive.velocity", "--from", "0.01", "--to", "3", "--quiet"]
    for k, v in SETS.items():
        args += ["--set", f"{k}={v}"]
    out = subprocess.run(args, capture_output=True, text=True, check=True).stdout
    assert f"{b['runs']} runs" in out
    lo_text = out.split("bracket ")[1].split(" …")[0]
    assert float(lo_text) == pytest.approx(b["lo"], rel=1e-5)


def test_a_scan_of_the_ends_alone_finds_one_change() -> None:
    b = stickslip.boundary(rigid(), "drive.velocity", 0.01, 3.0, rtol=1e-2, scan=2, jobs=1)
    assert len(b["changes"]) == 1 and b["changes"][0]["value"] == b["value"]
    assert [p["value"] for p in b["scan"]] == [0.01, 3.0]


@pytest.mark.parametrize(
    "key, lo, hi, kw, exc, needle",
    [
        ("drive.velocity", 0.01, 0.02, {}, ValueError, "both give the regime"),
        ("drive.speed", 0.01, 3.0, {}, ValueError, "no such scene key"),
        ("contact.nodes", 10, 30, {}, ValueError, "does not take a real number"),
        ("drive.velocity", 0.01, 3.0, {"rtol": 0.0}, ValueError, "rtol"),
        ("drive.velocity", 0.01, 3.0, {"scan": 1}, ValueError, "scan = 1"),
        ("drive.velocity", 0.01, 3.0, {"scan": 2.5}, ValueError, "scan"),
        ("drive.velocity", 0.01, 3.0, {"jobs": 0}, ValueError, "jobs = 0"),
        ("drive.velocity", 0.01, 3.0, {"scale": "slips"}, ValueError, "scale = 'slips'"),
        ("drive.velocity", 0.01, 0.01, {}, ValueError, "--from"),
        ("drive.velocity", float("nan"), 3.0, {}, ValueError, "finite"),
        ("drive.velocity", "0.01", 3.0, {}, TypeError, "lo"),
        (5, 0.01, 3.0, {}, TypeError, "key"),
        ("contact.radius", -1.0, 2e-5, {}, stickslip.SceneError, "contact.radius"),
    ],
)
def test_bad_boundary_calls_raise(key, lo, hi, kw, exc, needle) -> None:
    with pytest.raises(exc, match=needle):
        stickslip.boundary(rigid(), key, lo, hi, **kw)


def test_the_stamp_scale_follows_the_stamp_regime() -> None:
    # The h0 = 1 nm contact: a weak film lets the stamp slide steadily, a strong one makes it
    # slip; scale="stamp" finds the change of the stamp-scale regime.
    sfa = stickslip.Scene.load(ROOT / "validation" / "scenes" / "sfa.toml").with_overrides(
        {"contact.nodes": 50, "time.end": 0.25, "output.profile_times": []}
    )
    b = stickslip.boundary(sfa, "temperature.A0", -2e5, 1e6, rtol=0.2, scan=3, scale="stamp")
    assert b["below"] == "steady_sliding" and b["above"] in ("stick_slip", "transient")
    assert all(p["regime"] in ("steady_sliding", "stick_slip", "transient", "creep")
               for p in b["probes"])
