"""Ctrl-C: SIGINT to a Python process in the middle of a long run (or sweep) raises
``stickslip.Interrupted`` (a KeyboardInterrupt) there within a fraction of a second, with the
output so far in ``.result``, and the GIL was free meanwhile; a KeyboardInterrupt raised by a
progress callback does the same."""

from __future__ import annotations

import signal
import subprocess
import sys
import time

import pytest

from conftest import SCENES

CHILD = r"""
import signal, sys, threading, time
# Ctrl-C as in a terminal. A parent that ignores SIGINT (a shell's background job, some CI
# runners) passes that on, and Python then installs no KeyboardInterrupt handler at all.
signal.signal(signal.SIGINT, signal.default_int_handler)
import stickslip
what = sys.argv[1]
ticks = [0]
def tick():
    while True:
        ticks[0] += 1
        time.sleep(0.01)
threading.Thread(target=tick, daemon=True).start()
if what == "run":
    # fig2 at N = 2000 with fixed steps of 1e-8 s: 130000 steps, minutes of work.
    scene = stickslip.Scene.load(sys.argv[2], {"time.stepping": "fixed"})
    job = lambda: stickslip.run(scene)
else:
    job = lambda: stickslip.sweep({
        "name": "long", "scene": stickslip.Scene.load(sys.argv[2]),
        "set": {"time.stepping": "fixed"},
        "axis": [{"key": "drive.velocity", "values": [1.0, 1.1, 1.2, 1.3]}]}, jobs=2)
print("ready", flush=True)
start = time.perf_counter()
try:
    job()
except KeyboardInterrupt as e:
    took = time.perf_counter() - start
    assert isinstance(e, stickslip.Interrupted), type(e)
    r = e.result
    if what == "run":
        assert isinstance(r, stickslip.RunResult) and r.status == "interrupted", r
        assert r.stop == "interrupted" and len(r.series["t"]) > 1
        assert 0 < r.series["t"][-1] < scene.end_s
        rows = len(r.series["t"])
    else:
        assert isinstance(r, stickslip.MapTable) and not r.complete and r.points == 4, r
        assert isinstance(r, dict) and list(r)[0] == "point"
        rows = r.rows
    print(f"interrupted after {took:.2f} s, {rows} rows, ticks {ticks[0]}", flush=True)
    sys.exit(0)
print("finished without interruption", flush=True)
sys.exit(1)
"""


@pytest.mark.parametrize("what", ["run", "sweep"])
def test_sigint_raises_keyboard_interrupt_quickly(what: str) -> None:
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, what, str(SCENES / "fig2.toml")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout is not None
        assert child.stdout.readline().strip() == "ready"
        time.sleep(1.5)  # well inside the run
        assert child.poll() is None, "the run ended before it could be interrupted"
        sent = time.perf_counter()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=30)
        latency = time.perf_counter() - sent
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert child.returncode == 0, (out, err)
    assert "interrupted after" in out, (out, err)
    ticks = int(out.split("ticks")[1])
    # The ticking thread ran while Rust worked (about 100 ticks a second with the GIL free).
    assert ticks > 30, out
    # Python checks its signals every 0.1 s; process exit adds a little.
    assert latency < 2.0, latency


def test_a_keyboard_interrupt_from_a_progress_callback_is_interrupted_with_the_result(
    fig2_path,
) -> None:
    import stickslip

    # A run that outlasts several of the bridge's 100 ms callback intervals on any host: fig2
    # at N = 1000 to its own 1.3 ms now ends in about 0.2 s, near the second call; carried on
    # to 2.5 ms, with its events coming ever faster, it takes about 1.3 s.
    scene = stickslip.Scene.load(
        fig2_path, {"contact.nodes": 1000, "time.tolerance": 1e-6, "time.end": 2.5e-3}
    )
    calls = []

    def stop_at_second(info: dict) -> None:
        calls.append(info)
        if len(calls) == 2 and info["stop"] is None:
            raise KeyboardInterrupt

    with pytest.raises(stickslip.Interrupted) as e:
        stickslip.run(scene, progress=stop_at_second)
    assert isinstance(e.value, KeyboardInterrupt)
    r = e.value.result
    assert r.status == "interrupted" and r.stop == "interrupted" and e.value.out is None
    assert 0 < r.series["t"][-1] < scene.end_s
    assert r.run_info["t_final"] == pytest.approx(calls[-1]["t_s"], rel=0.2)
    assert "interrupted at t =" in str(e.value) and ".result" in str(e.value)
    # The run stopped at once: no call after the one that raised.
    assert len(calls) == 2
