"""Runs and sweeps in directories: ``run(out=)`` writes the command line's bytes; an
interrupted run's data are readable (pandas, ``load``) and ``resume`` (or the CLI's) finishes
it bit for bit, and another build's checkpoint only with ``allow_other_build=True``; ``load``
reads finished, failed, interrupted and killed runs; ``load_sweep`` reads complete and partial
maps."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import stickslip
from conftest import HARD, SCENES, read_csv, same_bits

OUTPUTS = ("series.csv", "events.csv", "slips.csv", "profiles.csv", "probes.csv")
TABLES = ("series", "events", "slips", "profiles", "probes")

# fig2 at N = 1000 at a tight tolerance, carried on to 2.5 ms: profiles and probes, and a run
# that outlasts several of the progress bridge's 100 ms intervals on any host. To its own
# 1.3 ms it now ends in about 0.2 s, near the second report the interrupt tests wait for; to
# 2.5 ms, with its events coming ever faster, it takes about 1.3 s (0.65 s to 2 ms).
LONG = {
    "contact.nodes": 1000,
    "time.tolerance": 1e-6,
    "time.end": 2.5e-3,
    "output.profile_times": [4e-4, 1.3e-3],
    "output.probe_radii": [2e-6, 1e-5],
}
LONG_ARGS = [
    "--set", "contact.nodes=1000",
    "--set", "time.tolerance=1e-6",
    "--set", "time.end=2.5e-3",
    "--set", "output.profile_times=[4e-4, 1.3e-3]",
    "--set", "output.probe_radii=[2e-6, 1e-5]",
]


def run_json_without_wall_time(d: Path) -> dict:
    info = json.loads((d / "run.json").read_text())
    info.pop("wall_seconds")
    return info


def assert_same_files(a: Path, b: Path) -> None:
    for f in OUTPUTS:
        assert (a / f).read_bytes() == (b / f).read_bytes(), f"{f} differs"
    assert run_json_without_wall_time(a) == run_json_without_wall_time(b)


def assert_same_result(a: stickslip.RunResult, b: stickslip.RunResult) -> None:
    for table in TABLES:
        ta, tb = getattr(a, table), getattr(b, table)
        assert list(ta) == list(tb), table
        for name in ta:
            assert same_bits(ta[name], tb[name]), f"{table}.{name}"
    assert a.summary == b.summary
    assert a.status == b.status and a.stop == b.stop


@pytest.fixture(scope="module")
def reference(cli: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The CLI's run of the LONG scene."""
    out = tmp_path_factory.mktemp("cli") / "reference"
    subprocess.run(
        [str(cli), "run", str(SCENES / "fig2.toml"), "--out", str(out), "--quiet"] + LONG_ARGS,
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return out


def test_out_writes_the_bytes_of_the_cli(reference: Path, tmp_path: Path) -> None:
    scene = stickslip.Scene.load(SCENES / "fig2.toml", LONG)
    res = stickslip.run(scene, out=tmp_path / "py")
    assert res.status == "ok"
    assert_same_files(reference, tmp_path / "py")
    assert sorted(os.listdir(tmp_path / "py")) == sorted(OUTPUTS + ("run.json",))
    # What run(out=) returns is the run in memory, bit for bit.
    assert_same_result(res, stickslip.run(scene))
    assert_same_result(res, stickslip.load(tmp_path / "py"))
    # A directory with an earlier run: refused without force, replaced with it.
    with pytest.raises(FileExistsError, match="force=True"):
        stickslip.run(scene, out=tmp_path / "py")
    stickslip.run(scene, out=tmp_path / "py", force=True, checkpoint_every=0)
    assert_same_files(reference, tmp_path / "py")


def interrupt_at_second_report(calls: list):
    def callback(info: dict) -> None:
        calls.append(info)
        if len(calls) == 2 and info["stop"] is None:
            raise KeyboardInterrupt

    return callback


def test_interrupted_data_are_readable_and_resume_is_bit_identical(
    reference: Path, cli: Path, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    scene = stickslip.Scene.load(SCENES / "fig2.toml", LONG)
    with pytest.raises(stickslip.Interrupted) as e:
        stickslip.run(scene, out=out, progress=interrupt_at_second_report([]))
    part = e.value.result
    assert e.value.out == str(out) and f"stickslip.resume({str(out)!r})" in str(e.value)
    assert part.status == "interrupted" and part.stop == "interrupted"
    n = len(part.series["t"])
    assert 1 < n < len(read_csv(reference / "series.csv")["t"])
    # The files under their usual names: what the run wrote so far, for any reader.
    for f in ("series.csv", "profiles.csv", "probes.csv"):
        assert (reference / f).read_bytes().startswith((out / f).read_bytes()), f
    written = read_csv(out / "series.csv")
    for name, col in part.series.items():
        assert same_bits(written[name], col), name
    pd = pytest.importorskip("pandas")
    df = pd.read_csv(out / "series.csv")
    assert len(df) == n and np.array_equal(df["F"].to_numpy(), part.series["F"])
    assert len(pd.read_csv(out / "events.csv")) == len(part.events["k"])
    assert_same_result(part, stickslip.load(out))

    # Finished by Python, and a copy by the command line: both as the uninterrupted run.
    shutil.copytree(out, tmp_path / "copy")
    calls: list = []
    whole = stickslip.resume(out, progress=calls.append)
    assert whole.status == "ok" and calls[-1]["stop"] == "end"
    assert_same_files(reference, out)
    assert not any(p.name.startswith((".", "checkpoint")) for p in out.iterdir())
    assert_same_result(whole, stickslip.load(out))
    subprocess.run(
        [str(cli), "resume", str(tmp_path / "copy"), "--quiet"],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    assert_same_files(reference, tmp_path / "copy")
    # Resuming an ended run changes nothing and gives it back.
    again = stickslip.resume(out)
    assert_same_result(again, whole)
    assert_same_files(reference, out)


def as_another_build(checkpoint: Path, build: bytes = b"0123456789abcdef") -> None:
    """Rewrites ``checkpoint`` as another build of the numerics would have written it: the
    header line, the payload's length and FNV-1a checksum (little-endian u64), then the CBOR
    payload, whose first key is the text "build" followed by the 16-character identity."""
    data = checkpoint.read_bytes()
    header = b"stickslip checkpoint 3\n"
    assert data.startswith(header)
    payload = bytearray(data[len(header) + 16 :])
    key = b"\x65build\x70"  # text(5) "build", then a text(16)
    i = payload.index(key) + len(key)
    payload[i : i + 16] = build
    checksum = 0xCBF29CE484222325
    for byte in payload:
        checksum = ((checksum ^ byte) * 0x100000001B3) % 2**64
    checkpoint.write_bytes(
        header
        + len(payload).to_bytes(8, "little")
        + checksum.to_bytes(8, "little")
        + bytes(payload)
    )


def test_another_builds_checkpoint_is_refused_unless_allowed(
    reference: Path, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    scene = stickslip.Scene.load(SCENES / "fig2.toml", LONG)
    with pytest.raises(stickslip.Interrupted):
        stickslip.run(scene, out=out, progress=interrupt_at_second_report([]))
    as_another_build(out / "checkpoint.cbor")
    with pytest.raises(ValueError) as e:
        stickslip.resume(out)
    message = str(e.value)
    assert "was written by build 0123456789abcdef and this is build " in message, message
    assert message.endswith(
        "its numbers would differ; rerun, or resume with allow_other_build=True to continue "
        "anyway"
    ), message
    this_build = message.split("this is build ")[1].split(":")[0]
    whole = stickslip.resume(out, allow_other_build=True)
    assert whole.status == "ok"
    assert whole.run_info["resumed_across_builds"] == [
        {"checkpoint_build": "0123456789abcdef", "build": this_build}
    ]
    # The "other" build is this one in disguise: the numbers are the uninterrupted run's.
    for f in OUTPUTS:
        assert (reference / f).read_bytes() == (out / f).read_bytes(), f
    recorded = run_json_without_wall_time(out)
    assert recorded.pop("resumed_across_builds") == whole.run_info["resumed_across_builds"]
    assert recorded == run_json_without_wall_time(reference)


KILLED_CHILD = r"""
import json, sys, stickslip
scene = stickslip.Scene.load(sys.argv[1], json.loads(sys.argv[3]))
print("ready", flush=True)
stickslip.run(scene, out=sys.argv[2], checkpoint_every=0.05)
print("finished", flush=True)
"""


def test_a_killed_run_loads_as_of_its_checkpoint_and_resumes(
    reference: Path, tmp_path: Path
) -> None:
    out = tmp_path / "killed"
    child = subprocess.Popen(
        [sys.executable, "-c", KILLED_CHILD, str(SCENES / "fig2.toml"), str(out), json.dumps(LONG)],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout is not None and child.stdout.readline().strip() == "ready"
        deadline = time.monotonic() + 60
        while not (out / "checkpoint.cbor").exists():
            assert child.poll() is None, "the run ended before its first checkpoint"
            assert time.monotonic() < deadline
            time.sleep(0.005)
        child.send_signal(signal.SIGKILL)
        child.wait(timeout=30)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert child.returncode == -signal.SIGKILL, "the run finished before it was killed"
    assert not (out / "series.csv").exists()
    got = stickslip.load(out)
    assert got.status == "running" and got.stop is None
    n = len(got.series["t"])
    assert n == got.run_info["series_rows"] >= 1 and len(got.probes["t"]) == n
    assert len(got.profiles["t"]) % 1000 == 0
    assert got.summary is not None and got.summary["n_events"] == len(got.events["k"])
    ref = read_csv(reference / "series.csv")
    assert same_bits(got.series["F"], ref["F"][:n])
    whole = stickslip.resume(out)
    assert whole.status == "ok"
    assert_same_files(reference, out)


def test_a_failed_run_in_a_directory_loads_without_raising(tmp_path: Path) -> None:
    scene = stickslip.Scene.load(
        HARD / "large_dt.toml", {"time.scheme": "literal", "contact.nodes": 50}
    )
    with pytest.warns(RuntimeWarning), pytest.raises(stickslip.NumericalFailure) as e:
        stickslip.run(scene, out=tmp_path / "failed")
    assert str(tmp_path / "failed") in str(e.value)
    got = stickslip.load(tmp_path / "failed")
    assert got.status == "failed" and got.run_info["failure"]["step"] == 10
    assert_same_result(got, e.value.result)
    with pytest.raises(stickslip.NumericalFailure):
        stickslip.resume(tmp_path / "failed")


def test_nothing_to_resume_or_load_is_a_file_not_found_error(tmp_path: Path) -> None:
    for f in (stickslip.resume, stickslip.load, stickslip.load_sweep):
        with pytest.raises(FileNotFoundError, match="missing"):
            f(tmp_path / "missing")
    (tmp_path / "empty").mkdir()
    with pytest.raises(FileNotFoundError, match="no checkpoint"):
        stickslip.resume(tmp_path / "empty")
    with pytest.raises(FileNotFoundError, match="no run.json"):
        stickslip.load(tmp_path / "empty")
    with pytest.raises(FileNotFoundError, match="sweep.json"):
        stickslip.load_sweep(tmp_path / "empty")


def long_sweep(scene_nodes: int = 500) -> dict:
    # Six points of about 0.25 s each.
    return {
        "name": "long",
        "scene": stickslip.Scene.load(SCENES / "fig2.toml"),
        "set": {"contact.nodes": scene_nodes},
        "axis": [{"key": "drive.velocity", "values": [1.0, 1.1, 1.2, 1.3, 1.4, 1.5]}],
    }


def test_an_interrupted_sweep_keeps_a_partial_table_and_goes_on(tmp_path: Path) -> None:
    out = tmp_path / "map"
    calls: list = []

    def stop_after_first_point(info: dict) -> None:
        calls.append(info)
        if info["done"] >= 1 and info["stop"] is None:
            raise KeyboardInterrupt

    with pytest.raises(stickslip.Interrupted) as e:
        stickslip.sweep(long_sweep(), jobs=1, out=out, progress=stop_after_first_point)
    part = e.value.result
    assert isinstance(part, stickslip.MapTable) and isinstance(part, dict)
    assert not part.complete and part.points == 6 and 1 <= part.rows < 6
    assert e.value.out == str(out) and "not run" in str(e.value)
    assert list(part["point"]) == list(range(part.rows))
    assert not (out / "map.csv").exists()
    loaded = stickslip.load_sweep(out)
    assert not loaded.complete and loaded.rows == part.rows
    for name in part:
        if part[name].dtype == object:
            assert list(loaded[name]) == list(part[name]), name
        else:
            assert same_bits(loaded[name], part[name]), name
    # Run again: the finished points are skipped, the rest run; the map is complete.
    calls.clear()
    whole = stickslip.sweep(long_sweep(), jobs=1, out=out, progress=calls.append)
    assert whole.complete and whole.rows == 6 and (out / "map.csv").is_file()
    assert calls[-1]["skipped"] == part.rows and calls[-1]["done"] == 6 - part.rows
    for name in part:
        if name != "wall_s" and part[name].dtype != object:
            assert same_bits(whole[name][: part.rows], part[name]), name
    complete = stickslip.load_sweep(out)
    assert complete.complete and complete.rows == 6
    assert list(complete) == list(whole)
    assert same_bits(complete["f_mean"], whole["f_mean"])
    pd = pytest.importorskip("pandas")
    df = complete.to_pandas()
    assert list(df.columns) == list(whole) and len(df) == 6
