"""stickslip: stick–slip boundary friction of a nanometre lubricant film under a flat-ended
cylindrical stamp (Landau kinetics of the film coupled to the elastic substrate by the method
of dimensionality reduction), from Python. All quantities are SI.

    import stickslip
    scene = stickslip.Scene.load("validation/scenes/fig2.toml")
    scene = scene.with_overrides({"contact.nodes": 200})      # a new Scene
    res = stickslip.run(scene)                                # GIL released; Ctrl-C works
    res.series["F"], res.events["t_onset"], res.summary["regime"]
    table = stickslip.sweep("maps/rigid.toml", jobs=2)        # map.csv as arrays
    q = stickslip.mdr.forward(tau, radius)                    # Eq. 13

The numbers are those of the command line ``stickslip run``, bit for bit, for the same scene.
Errors: ``SceneError`` (a ValueError; ``.key``), ``SweepError`` (a SceneError),
``NumericalFailure`` (``.time_s``, ``.step``, ``.node``, ``.r_m``, ``.quantity``).
"""

from __future__ import annotations

import os
import warnings
from typing import Any, Dict, Mapping, Optional, Union

import numpy as np

from . import _native
from . import mdr
from ._errors import NumericalFailure, SceneError, SweepError
from ._native import Scene
from ._result import RunResult

__version__: str = _native.__version__

__all__ = [
    "NumericalFailure",
    "RunResult",
    "Scene",
    "SceneError",
    "SweepError",
    "mdr",
    "run",
    "sweep",
]

SceneLike = Union[Scene, str, "os.PathLike[str]", Mapping[str, Any]]


def _scene(scene: SceneLike) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(scene)
    if isinstance(scene, (str, os.PathLike)):
        return Scene.load(scene)
    raise TypeError(
        f"a scene is a stickslip.Scene, a path to a scene file or a dict; got {type(scene).__name__}"
    )


def run(scene: SceneLike, *, overrides: Optional[Mapping[str, Any]] = None) -> RunResult:
    """Runs a scene in memory and returns its output as a ``RunResult``.

    ``scene``: a ``Scene``, a path to a scene file (TOML) or a scene dict; ``overrides``:
    ``{"section.key": value}`` applied first (like ``--set``).

    The GIL is released while the run steps (other Python threads go on); Ctrl-C raises
    ``KeyboardInterrupt`` within about 0.1 s. Raises ``SceneError`` for a bad scene and
    ``NumericalFailure`` when the numerics fail or the run is refused before its first step;
    its ``.result`` holds the output recorded up to the failure. The preflight's warnings
    (likely unit slips, a step beyond a stability limit; run_info["warnings"]) are issued as
    ``RuntimeWarning``, as the command line prints them.

    The numbers are those of ``stickslip run SCENE --out DIR`` for the same scene, bit for
    bit (run_info's ``wall_seconds`` aside).
    """
    s = _scene(scene)
    if overrides:
        s = s.with_overrides(overrides)
    result = RunResult(_native.run(s))
    for w in result.run_info.get("warnings", ()):
        if w.get("severity") == "warning":
            warnings.warn(f"stickslip: {w.get('message')}", RuntimeWarning, stacklevel=2)
    if result.stop in ("failure", "refused"):
        f = result.run_info.get("failure") or {}
        raise NumericalFailure(
            f.get("message") or f"the run stopped with {result.stop}",
            time_s=f.get("time_s", 0.0),
            step=f.get("step", 0),
            node=f.get("node", 0),
            r_m=f.get("r_m", 0.0),
            quantity=f.get("quantity", ""),
            value=f.get("value"),
            reason=f.get("reason", ""),
            refused=result.stop == "refused",
            result=result,
        )
    return result


def sweep(
    sweep: Union[str, "os.PathLike[str]", Mapping[str, Any]],
    jobs: Optional[int] = None,
    *,
    out: Union[str, "os.PathLike[str]", None] = None,
    force: bool = False,
    allow_large: bool = False,
) -> Dict[str, np.ndarray]:
    """Runs a friction map and returns its table (map.csv) as ``dict[str, numpy.ndarray]``.

    ``sweep``: a sweep file (TOML, docs/reference.md "Sweeps"; its ``scene`` is relative to
    the file) or a dict with the same keys, e.g.::

        {"name": "v-A0", "scene": "validation/scenes/rigid.toml",   # relative to the cwd
         "set": {"contact.nodes": 50, "time.max_events": 4},
         "axis": [{"key": "drive.velocity", "values": [1e-3, 1e-2]},
                  {"key": "temperature.A0",
                   "range": {"from": 0.0, "to": 1.5e6, "count": 4}}]}

    In a dict, ``scene`` is a path relative to the current directory, or a ``Scene``.
    ``jobs``: points run in parallel, an int >= 1 (default None: the available cores).
    ``out``: a sweep directory to keep (points/, map.csv, map.json; a rerun skips finished
    points, as ``stickslip sweep run --out``); by default a temporary one. ``force``: start
    afresh, removing the earlier results in ``out`` (of another sweep, or of this one).
    ``allow_large``: allow more than 100000 points (at most 10000000).

    Columns, in map.csv's order: ``point`` (int64), one per axis key (float64, or str
    objects for words), ``status`` (``ok`` | ``failed`` | ``refused``), ``regime`` (str
    objects), ``n_events`` (int64), ``t_first_onset`` s, ``period_last`` s, ``x_period_last``
    m, ``f_peak_first`` N, ``f_peak_last`` N, ``f_mean`` N, ``recovery``,
    ``melted_time_fraction``, ``wall_s`` s (float64, NaN for none), ``message`` (str).
    A failing point is a row with its status and message; the sweep goes on.

    Every point's record in ``out`` carries the sweep's fingerprint (the sweep and the build
    of the numerics) and its values: points another build computed are recomputed (a
    ``RuntimeWarning`` says how many and why), and a record of another sweep raises
    ``OSError`` naming it, as does a directory holding another sweep without ``force``.

    The GIL is released while points run; Ctrl-C raises ``KeyboardInterrupt``. Raises
    ``SweepError`` (a ``SceneError``) for a bad sweep, ``TypeError`` or ``ValueError`` for a
    bad ``jobs``, ``force``, ``allow_large`` or ``out``.
    """
    return _native.sweep(sweep, jobs, out=out, force=force, allow_large=allow_large)
