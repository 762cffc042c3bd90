"""stickslip: stick–slip boundary friction of a nanometre lubricant film under a flat-ended
cylindrical stamp (Landau kinetics of the film coupled to the elastic substrate by the method
of dimensionality reduction), from Python. All quantities are SI.

    import stickslip
    scene = stickslip.Scene.load("validation/scenes/fig2.toml")
    scene = scene.with_overrides({"contact.nodes": 200})      # a new Scene
    scene.check()["cost"]["seconds"]                          # what `stickslip check` says
    res = stickslip.run(scene, progress=True)                 # GIL released; a progress bar
    res.series["F"], res.events["t_onset"], res.summary["regime"]
    res = stickslip.run(scene, out="out/fig2")                # the CLI's files + checkpoints
    res = stickslip.resume("out/fig2")                        # after Ctrl-C or a kill
    res = stickslip.load("out/fig2")                          # any run directory
    table = stickslip.sweep("maps/rigid.toml", jobs=2)        # map.csv as arrays
    table = stickslip.load_sweep("out/rigid")                 # complete or partial
    b = stickslip.boundary(scene, "drive.velocity", 0.01, 3.0, rtol=1e-3)   # b["value"]
    [k["path"] for k in stickslip.keys()]                    # every scene key, documented
    v = stickslip.verify(scene, rtol=1e-3)                    # every number with its error
    f = stickslip.fit(scene, "trace.csv", ["lubricant.tau_max=5e5:2e6"])   # f.values, f.stderr
    q = stickslip.mdr.forward(tau, radius)                    # Eq. 13

The numbers are those of the command line ``stickslip run``, bit for bit, for the same scene.
Ctrl-C during ``run``, ``resume`` or ``sweep`` raises ``Interrupted`` (a
``KeyboardInterrupt``) whose ``.result`` holds the output so far. Errors: ``SceneError`` (a
ValueError; ``.key``), ``SweepError`` (a SceneError), ``NumericalFailure`` (``.time_s``,
``.step``, ``.node``, ``.r_m``, ``.quantity``, ``.result``); missing directories raise
``FileNotFoundError``, bad arguments ``TypeError`` or ``ValueError``.

Installing the package also installs the ``stickslip`` command (``python -m stickslip`` too):
the command line itself (``stickslip run``, ``check``, ``resume``, ``sweep``, ``keys``, …), the
same program as the Rust binary, with its arguments, output, exit statuses and Ctrl-C handling.
"""

from . import _native, mdr
from ._api import PathLike, SceneLike, boundary, fit, load, load_sweep, resume, run, sweep, verify
from ._errors import Interrupted, NumericalFailure, SceneError, SweepError
from ._native import Scene, keys
from ._progress import ProgressArg
from ._result import FitResult, MapTable, RunResult

__version__: str = _native.__version__

# The package's public names; `dir(stickslip)` shows these (and the private modules).
__all__ = [
    "FitResult",
    "Interrupted",
    "MapTable",
    "NumericalFailure",
    "PathLike",
    "ProgressArg",
    "RunResult",
    "Scene",
    "SceneError",
    "SceneLike",
    "SweepError",
    "boundary",
    "fit",
    "keys",
    "load",
    "load_sweep",
    "mdr",
    "resume",
    "run",
    "sweep",
    "verify",
]

# The functions and classes say they belong to the package (help(), repr, pickling).
for _obj in (boundary, fit, keys, verify, load, load_sweep, resume, run, sweep, Interrupted, NumericalFailure,
             SceneError, SweepError, FitResult, MapTable, RunResult):
    _obj.__module__ = __name__
del _obj
