"""Ctrl-C: SIGINT to a Python process in the middle of a long run (or sweep) raises
KeyboardInterrupt there within a fraction of a second, and the GIL was free meanwhile."""

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
except KeyboardInterrupt:
    print(f"interrupted after {time.perf_counter() - start:.2f} s, ticks {ticks[0]}", flush=True)
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
