"""Progress of runs and sweeps: a callable receives dicts at most about ten times a second and
once at the end; ``progress=True`` draws tqdm's bar when tqdm is there, else a line on stderr;
the numbers do not change; an exception from the callable stops the run and is raised."""

from __future__ import annotations

import sys
import time
import types
from pathlib import Path

import pytest

import stickslip
from conftest import SCENES, same_bits

# fig2 at N = 1000: about 0.1 s.
SCENE = {"contact.nodes": 1000}
# The same carried on to 2.5 ms, about 0.5 s: long enough for reports before the end (to its
# own 1.3 ms the first report may come only at the end).
LONG_SCENE = {"contact.nodes": 1000, "time.end": 2.5e-3}
RUN_KEYS = {"fraction", "t_s", "end_s", "steps", "events", "elapsed_s", "eta_s", "stop"}
SWEEP_KEYS = {"done", "total", "skipped", "failed", "fraction", "elapsed_s", "eta_s", "stop"}


@pytest.fixture(scope="module")
def scene() -> stickslip.Scene:
    return stickslip.Scene.load(SCENES / "fig2.toml", SCENE)


@pytest.fixture(scope="module")
def long_scene() -> stickslip.Scene:
    return stickslip.Scene.load(SCENES / "fig2.toml", LONG_SCENE)


@pytest.fixture(scope="module")
def silent(scene: stickslip.Scene) -> stickslip.RunResult:
    return stickslip.run(scene)


def test_a_callback_gets_dicts_at_a_bounded_rate_and_the_same_numbers(
    scene: stickslip.Scene, silent: stickslip.RunResult
) -> None:
    calls: list = []
    start = time.perf_counter()
    res = stickslip.run(scene, progress=calls.append)
    took = time.perf_counter() - start
    assert calls and all(set(c) == RUN_KEYS for c in calls)
    assert len(calls) <= took / 0.1 + 2, (len(calls), took)
    fractions = [c["fraction"] for c in calls]
    assert fractions == sorted(fractions) and all(0 <= f <= 1 for f in fractions)
    assert all(c["stop"] is None for c in calls[:-1])
    last = calls[-1]
    assert last["stop"] == "end" and last["fraction"] == 1.0 and last["eta_s"] == 0.0
    assert last["t_s"] == scene.end_s == last["end_s"]
    assert last["events"] == len(res.events["k"]) and last["steps"] == res.run_info["steps"]
    if len(calls) > 2:
        assert calls[1]["eta_s"] is not None and calls[1]["eta_s"] >= 0
    for name, col in silent.series.items():
        assert same_bits(res.series[name], col), name


class FakeTqdm:
    """What the bar does with tqdm, recorded."""

    made: list = []

    def __init__(self, total: int, desc: str, **kwargs: object) -> None:
        self.total, self.desc, self.n, self.closed = total, desc, 0, False
        self.postfix = ""
        FakeTqdm.made.append(self)

    def update(self, k: int) -> None:
        assert k >= 0
        self.n += k

    def set_postfix_str(self, s: str, refresh: bool = True) -> None:
        self.postfix = s

    def close(self) -> None:
        self.closed = True


def test_progress_true_uses_tqdm_auto_when_there(
    scene: stickslip.Scene, monkeypatch: pytest.MonkeyPatch
) -> None:
    auto = types.ModuleType("tqdm.auto")
    auto.tqdm = FakeTqdm  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    FakeTqdm.made.clear()
    stickslip.run(scene, progress=True)
    [bar] = FakeTqdm.made
    assert bar.desc == "fig2" and bar.total == 1000 and bar.n == 1000 and bar.closed
    assert "10 events" in bar.postfix


def test_progress_true_without_tqdm_redraws_a_line_on_stderr(
    scene: stickslip.Scene, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)  # import fails
    stickslip.run(scene, progress=True)
    err = capsys.readouterr().err
    assert err.startswith("\rfig2: ") and err.endswith("\n")
    last = err.rstrip().split("\r")[-1]
    assert "100.0%" in last and "10 events" in last and "elapsed" in last


def test_a_tqdm_that_cannot_draw_gives_the_line_not_an_error(
    scene: stickslip.Scene, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    class Broken:
        # As tqdm's notebook bar without ipywidgets.
        def __init__(self, *args: object, **kwargs: object) -> None:
            raise ImportError("IProgress not found")

    auto = types.ModuleType("tqdm.auto")
    auto.tqdm = Broken  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    assert stickslip.run(scene, progress=True).status == "ok"
    assert "100.0%" in capsys.readouterr().err


def test_sweep_progress(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture) -> None:
    sweep = {
        "name": "v",
        "scene": stickslip.Scene.load(SCENES / "fig2.toml"),
        "set": {"contact.nodes": 300},
        "axis": [{"key": "drive.velocity", "values": [1.0, 1.2, 1.4]}],
    }
    calls: list = []
    table = stickslip.sweep(sweep, jobs=1, progress=calls.append)
    assert calls and all(set(c) == SWEEP_KEYS for c in calls)
    assert [c["done"] for c in calls] == sorted(c["done"] for c in calls)
    assert calls[-1] == {**calls[-1], "done": 3, "total": 3, "failed": 0, "stop": "end"}
    assert table.complete and table.rows == 3
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    stickslip.sweep(sweep, jobs=1, progress=True)
    assert "(3/3) 0 failed" in capsys.readouterr().err


def test_an_exception_from_the_callback_stops_the_run_and_is_raised(
    long_scene: stickslip.Scene, tmp_path: Path
) -> None:
    scene = long_scene
    calls: list = []

    def broken(info: dict) -> None:
        calls.append(info)
        raise ValueError("from the callback")

    with pytest.raises(ValueError, match="from the callback"):
        stickslip.run(scene, progress=broken)
    assert len(calls) == 1 and calls[0]["stop"] is None  # no report after it
    with pytest.raises(ValueError, match="from the callback"):
        stickslip.run(scene, progress=broken, out=tmp_path / "out")
    stopped = stickslip.load(tmp_path / "out")
    assert stopped.status == "interrupted" and stopped.run_info["t_final"] < scene.end_s


def test_bad_progress_arguments() -> None:
    for bad in (1, "yes", 2.5, [print]):
        with pytest.raises(TypeError, match="progress = .* is invalid"):
            stickslip.run(SCENES / "fig2.toml", progress=bad)  # type: ignore[arg-type]
        with pytest.raises(TypeError, match="progress = .* is invalid"):
            stickslip.sweep({"name": "x"}, progress=bad)  # type: ignore[arg-type]
