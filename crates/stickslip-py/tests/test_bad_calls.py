"""Bad input never kills the interpreter: every public function and class of the package,
called with bad shapes, types and dtypes, sizes that would not fit in memory, NaN and
infinities, bad radii, wrong arguments and missing or damaged files, raises a Python
exception of a sensible class.

The cases run in one child interpreter, one after the other (a case that aborted the process
would end them all: the child says which one it started last), and each is checked here."""

from __future__ import annotations

import json
import subprocess
import sys
from typing import Dict, List, Tuple

import pytest

from conftest import ROOT

# (call, expected exception class: the class or one of its bases).
CASES: List[Tuple[str, str]] = [
    # stickslip.run
    ("stickslip.run(42)", "TypeError"),
    ("stickslip.run(None)", "TypeError"),
    ("stickslip.run(SCENES / 'missing.toml')", "SceneError"),
    ("stickslip.run({'name': 'x'})", "SceneError"),
    ("stickslip.run(scene, overrides=[1])", "TypeError"),
    ("stickslip.run(scene, overrides={'contact.nodes': -5})", "SceneError"),
    ("stickslip.run(scene, overrides={'contact.nodes': 10**6})", "SceneError"),
    ("stickslip.run(scene, overrides={'contact.nodes': 10**30})", "TypeError"),
    ("stickslip.run(scene, overrides={'contact.nodes': 'many'})", "SceneError"),
    ("stickslip.run(scene, overrides={'time.end': math.inf})", "SceneError"),
    ("stickslip.run(scene, overrides={'time.dt': math.nan})", "SceneError"),
    ("stickslip.run(scene, overrides={'contact.radius': -1.0})", "SceneError"),
    ("stickslip.run(scene, overrides={'output.profile_times': [math.nan]})", "SceneError"),
    ("stickslip.run(scene, progress=3)", "TypeError"),
    ("stickslip.run(scene, out=3)", "TypeError"),
    ("stickslip.run(scene, out=done)", "FileExistsError"),
    ("stickslip.run(scene, out=afile)", "OSError"),
    ("stickslip.run(scene, out=tmp / 'a', force=1)", "TypeError"),
    ("stickslip.run(scene, out=tmp / 'b', checkpoint_every=-1)", "ValueError"),
    ("stickslip.run(scene, out=tmp / 'c', checkpoint_every=math.nan)", "ValueError"),
    ("stickslip.run(scene, out=tmp / 'd', checkpoint_every='x')", "TypeError"),
    ("stickslip.run(scene, out=tmp / 'e', checkpoint_every=True)", "TypeError"),
    # stickslip.resume
    ("stickslip.resume(tmp / 'missing')", "FileNotFoundError"),
    ("stickslip.resume(empty)", "FileNotFoundError"),
    ("stickslip.resume(afile)", "NotADirectoryError"),
    ("stickslip.resume(garbage)", "ValueError"),
    ("stickslip.resume(None)", "TypeError"),
    ("stickslip.resume(3)", "TypeError"),
    ("stickslip.resume(done, checkpoint_every=-2)", "ValueError"),
    ("stickslip.resume(done, progress='x')", "TypeError"),
    ("stickslip.resume(done, allow_other_build='yes')", "TypeError"),
    # stickslip.load
    ("stickslip.load(tmp / 'missing')", "FileNotFoundError"),
    ("stickslip.load(empty)", "FileNotFoundError"),
    ("stickslip.load(afile)", "NotADirectoryError"),
    ("stickslip.load(garbage)", "ValueError"),
    ("stickslip.load(damaged)", "ValueError"),
    ("stickslip.load(None)", "TypeError"),
    ("stickslip.load(3.5)", "TypeError"),
    # stickslip.load_sweep
    ("stickslip.load_sweep(tmp / 'missing')", "FileNotFoundError"),
    ("stickslip.load_sweep(empty)", "FileNotFoundError"),
    ("stickslip.load_sweep(garbage)", "ValueError"),
    ("stickslip.load_sweep(afile)", "OSError"),
    ("stickslip.load_sweep(None)", "TypeError"),
    # stickslip.sweep
    ("stickslip.sweep(3)", "TypeError"),
    ("stickslip.sweep(None)", "TypeError"),
    ("stickslip.sweep(tmp / 'missing.toml')", "SweepError"),
    ("stickslip.sweep({})", "SweepError"),
    ("stickslip.sweep({'name': 'x'})", "SweepError"),
    ("stickslip.sweep(small_sweep, jobs='2')", "TypeError"),
    ("stickslip.sweep(small_sweep, jobs=1.5)", "TypeError"),
    ("stickslip.sweep(small_sweep, jobs=0)", "ValueError"),
    ("stickslip.sweep(small_sweep, jobs=-1)", "ValueError"),
    ("stickslip.sweep(small_sweep, jobs=10**30)", "ValueError"),
    ("stickslip.sweep(small_sweep, force='yes')", "TypeError"),
    ("stickslip.sweep(small_sweep, allow_large=1)", "TypeError"),
    ("stickslip.sweep(small_sweep, out=3)", "TypeError"),
    ("stickslip.sweep(small_sweep, out=afile)", "OSError"),
    ("stickslip.sweep(small_sweep, progress='x')", "TypeError"),
    ("stickslip.sweep(with_axis({'key': 'drive.velocity', 'values': [math.nan]}))",
     "SceneError"),
    ("stickslip.sweep(with_axis({'key': 'drive.velocity', 'values': ['fast']}))",
     "SceneError"),
    ("stickslip.sweep(with_axis({'key': 'drive.velocity', "
     "'range': {'from': 0.1, 'to': 1.0, 'count': 10**12}}))", "SweepError"),
    ("stickslip.sweep(with_axis({'key': 'contact.nodes', 'values': [10**6]}))", "SceneError"),
    # stickslip.Scene
    ("stickslip.Scene.load(3)", "TypeError"),
    ("stickslip.Scene.load(None)", "TypeError"),
    ("stickslip.Scene.load(tmp / 'missing.toml')", "SceneError"),
    ("stickslip.Scene.load(empty)", "SceneError"),
    ("stickslip.Scene.load(afile)", "SceneError"),
    ("stickslip.Scene.load(SCENES / 'fig2.toml', 3)", "TypeError"),
    ("stickslip.Scene.from_dict(3)", "TypeError"),
    ("stickslip.Scene.from_dict([1, 2])", "TypeError"),
    ("stickslip.Scene.from_dict({'name': object()})", "TypeError"),
    ("stickslip.Scene.from_dict({1: 2})", "TypeError"),
    ("stickslip.Scene.from_dict({**fig2, 'contact.nodes': 1.5})", "SceneError"),
    ("stickslip.Scene.from_dict({**fig2, 'contact.nodes': np.int64(-1)})", "SceneError"),
    ("stickslip.Scene.from_dict({**fig2, 'lubricant.tau_max': np.nan})", "SceneError"),
    ("stickslip.Scene.from_dict({**fig2, 'lubricant.tau_max': 1 + 2j})", "TypeError"),
    ("stickslip.Scene.from_toml(3)", "TypeError"),
    ("stickslip.Scene.from_toml('= =')", "SceneError"),
    ("stickslip.Scene.from_toml('name = \"x\"\\n[contact]\\nnodes = \"a\"\\n')", "SceneError"),
    ("scene.with_overrides(None)", "TypeError"),
    ("scene.with_overrides({3: 1})", "TypeError"),
    ("scene.with_overrides({'contact..nodes': 1})", "SceneError"),
    ("scene.with_overrides({'contact.nodes': [1, 2]})", "SceneError"),
    ("scene.with_overrides({'output.probe_radii': [-1e-6]})", "SceneError"),
    ("scene.with_overrides({'output.probe_radii': np.array([[1e-6]])})", "SceneError"),
    ("scene.to_dict(resolved='yes')", "TypeError"),
    # Values that contain themselves, and nesting no file has.
    ("stickslip.Scene.from_dict(loop_dict)", "ValueError"),
    ("scene.with_overrides({'output.probe_radii': loop_list})", "ValueError"),
    ("stickslip.sweep({**small_sweep, 'set': loop_dict})", "ValueError"),
    ("stickslip.Scene.from_toml('a = ' + '[' * 100000 + ']' * 100000)", "SceneError"),
    ("stickslip.Scene.from_toml('a = ' + '{b = ' * 100000 + '1' + '}' * 100000)",
     "SceneError"),
    ("scene.with_overrides({'a' + '.a' * 100000: 1})", "SceneError"),
    # stickslip.mdr
    ("mdr.forward(np.ones(200_000), 2e-5)", "MemoryError"),
    ("mdr.forward(huge, 2e-5)", "MemoryError"),
    ("mdr.forward(huge, 2e-5, form='fast')", "MemoryError"),
    ("mdr.forward(np.ones((3, 3)), 2e-5)", "ValueError"),
    ("mdr.forward(np.ones(()), 2e-5)", "ValueError"),
    ("mdr.forward(5.0, 2e-5)", "ValueError"),
    ("mdr.forward([1.0, math.nan], 2e-5)", "ValueError"),
    ("mdr.forward(np.array([1.0, np.inf]), 2e-5)", "ValueError"),
    ("mdr.forward(np.array([-np.inf], dtype=np.float32), 2e-5)", "ValueError"),
    ("mdr.forward(np.array(['a', 'b']), 2e-5)", "TypeError"),
    ("mdr.forward(np.array([1 + 1j]), 2e-5)", "TypeError"),
    ("mdr.forward(np.array([1.0, None], dtype=object), 2e-5)", "TypeError"),
    ("mdr.forward(np.array([True, False]), 2e-5)", "TypeError"),
    ("mdr.forward('abc', 2e-5)", "TypeError"),
    ("mdr.forward(b'ab', 2e-5)", "TypeError"),
    ("mdr.forward(None, 2e-5)", "TypeError"),
    ("mdr.forward([1, [2, 3]], 2e-5)", "ValueError"),
    ("mdr.forward([], 2e-5)", "ValueError"),
    ("mdr.forward(np.ones(4), -1.0)", "ValueError"),
    ("mdr.forward(np.ones(4), 0.0)", "ValueError"),
    ("mdr.forward(np.ones(4), math.nan)", "ValueError"),
    ("mdr.forward(np.ones(4), math.inf)", "ValueError"),
    ("mdr.forward(np.ones(4), np.float64(-2e-5))", "ValueError"),
    ("mdr.forward(np.ones(4), 'x')", "TypeError"),
    ("mdr.forward(np.ones(4), None)", "TypeError"),
    ("mdr.forward(np.ones(4), True)", "TypeError"),
    ("mdr.forward(np.ones(4), 1 + 1j)", "TypeError"),
    ("mdr.forward(np.ones(4), 2e-5, form='sparse')", "ValueError"),
    ("mdr.forward(np.ones(4), 2e-5, form=3)", "TypeError"),
    ("mdr.forward(np.ones(4), 2e-5, quadrature='simpson')", "ValueError"),
    ("mdr.forward(np.ones(4), 2e-5, quadrature=None)", "TypeError"),
    ("stickslip.verify(42)", "TypeError"),
    ("stickslip.verify(scene, rtol=-1.0)", "ValueError"),
    ("stickslip.verify(scene, rtol=math.nan)", "ValueError"),
    ("stickslip.verify(scene, jobs=0)", "ValueError"),
    ("stickslip.verify(scene, jobs=True)", "TypeError"),
    ("mdr.forward(np.full(5, 1e6), 1e308)", "ValueError"),
    ("mdr.force(np.full(5, 1e300), 1e300)", "ValueError"),
    ("stickslip.Scene.load('/dev/zero')", "SceneError"),
    ("stickslip.Scene.load(None)", "TypeError"),
    ("stickslip.Scene.from_toml(None)", "TypeError"),
    ("mdr.back(np.ones(200_000), 2e-5)", "MemoryError"),
    ("mdr.back(np.ones((2, 2)), 2e-5)", "ValueError"),
    ("mdr.back([math.nan], 2e-5)", "ValueError"),
    ("mdr.back(np.ones(4), -1)", "ValueError"),
    ("mdr.back(np.array(['x']), 2e-5)", "TypeError"),
    ("mdr.compliance(np.ones(200_000), 2e-5, 1e9)", "MemoryError"),
    ("mdr.compliance(np.ones(4), 2e-5, 0.0)", "ValueError"),
    ("mdr.compliance(np.ones(4), 2e-5, -1e9)", "ValueError"),
    ("mdr.compliance(np.ones(4), 2e-5, math.nan)", "ValueError"),
    ("mdr.compliance(np.ones(4), 2e-5, 'x')", "TypeError"),
    ("mdr.compliance([math.inf], 2e-5, 1e9)", "ValueError"),
    ("mdr.compliance(np.ones(4), -2e-5, 1e9)", "ValueError"),
    ("mdr.force(huge, 2e-5)", "MemoryError"),
    ("mdr.force([math.nan], 2e-5)", "ValueError"),
    ("mdr.force(np.ones((2, 2)), 2e-5)", "ValueError"),
    ("mdr.force(np.ones(3), 0)", "ValueError"),
    ("mdr.force(np.array([1j]), 2e-5)", "TypeError"),
    ("mdr.radii(2e-5, 10**13)", "MemoryError"),
    ("mdr.radii(2e-5, 10**30)", "ValueError"),
    ("mdr.radii(2e-5, 0)", "ValueError"),
    ("mdr.radii(2e-5, -3)", "ValueError"),
    ("mdr.radii(2e-5, 1.5)", "TypeError"),
    ("mdr.radii(2e-5, '3')", "TypeError"),
    ("mdr.radii(-1.0, 3)", "ValueError"),
    ("mdr.radii(math.nan, 3)", "ValueError"),
]

CHILD = r"""
import json, math, pathlib, shutil, sys, tempfile, traceback
import numpy as np
import stickslip
from stickslip import mdr

ROOT = pathlib.Path(sys.argv[1])
SCENES = ROOT / "validation" / "scenes"
tmp = pathlib.Path(tempfile.mkdtemp(prefix="stickslip-bad-"))
scene = stickslip.Scene.load(
    SCENES / "fig2.toml",
    {"contact.nodes": 20, "time.end": 1e-5, "output.profile_times": [1e-5]},
)
fig2 = scene.to_dict(resolved=False)
done = tmp / "done"
stickslip.run(scene, out=done)
damaged = tmp / "damaged"
shutil.copytree(done, damaged)
(damaged / "series.csv").write_text("t,X\n1,2,3\n")
afile = tmp / "afile"
afile.write_text("x = [\n")
empty = tmp / "empty"
empty.mkdir()
garbage = tmp / "garbage"
garbage.mkdir()
(garbage / "run.json").write_text("{not json")
(garbage / "checkpoint.cbor").write_bytes(b"junk")
(garbage / "sweep.json").write_text("{]")
huge = np.broadcast_to(1.0, (10**10,))  # 80 GB as float64, held as one number
small_sweep = {
    "name": "small", "scene": scene,
    "axis": [{"key": "drive.velocity", "values": [1.0]}],
}
loop_dict = {}
loop_dict["a"] = loop_dict
loop_list = []
loop_list.append(loop_list)
def with_axis(axis):
    return {**small_sweep, "axis": [axis]}
cases = json.loads(sys.argv[2])
for i, (call, _) in enumerate(cases):
    print(json.dumps({"start": i}), flush=True)
    try:
        eval(call)
        got = {"case": i, "raised": None}
    except BaseException as e:
        got = {"case": i, "raised": type(e).__name__,
               "mro": [c.__name__ for c in type(e).__mro__], "message": str(e)[:300]}
    print(json.dumps(got), flush=True)
shutil.rmtree(tmp)
print(json.dumps({"alive": True}), flush=True)
"""


@pytest.fixture(scope="module")
def outcomes() -> Tuple[Dict[int, dict], subprocess.CompletedProcess]:
    child = subprocess.run(
        [sys.executable, "-c", CHILD, str(ROOT), json.dumps(CASES)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    got: Dict[int, dict] = {}
    for line in child.stdout.splitlines():
        record = json.loads(line)
        if "case" in record:
            got[record["case"]] = record
    return got, child


def test_the_interpreter_survives_every_case(outcomes) -> None:
    got, child = outcomes
    started = [json.loads(line)["start"] for line in child.stdout.splitlines() if '"start"' in line]
    last = CASES[started[-1]][0] if started else "(setup)"
    assert child.returncode == 0, (
        f"the child interpreter died (status {child.returncode}) in the case {last!r}: "
        f"{child.stderr[-2000:]}"
    )
    assert '"alive": true' in child.stdout and len(got) == len(CASES)


@pytest.mark.parametrize("index", range(len(CASES)), ids=[c for c, _ in CASES])
def test_a_bad_call_raises_a_sensible_exception(index: int, outcomes) -> None:
    got, child = outcomes
    call, expected = CASES[index]
    assert index in got, f"{call}: not reached (the child died: {child.stderr[-1000:]})"
    record = got[index]
    assert record["raised"] is not None, f"{call} raised nothing"
    assert expected in record["mro"], (
        f"{call} raised {record['raised']} ({record['message']}), expected {expected}"
    )
    # A message in words, not a bare class: it names what was wrong.
    assert len(record["message"]) > 10, record
