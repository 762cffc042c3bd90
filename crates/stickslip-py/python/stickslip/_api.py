"""The functions of ``stickslip``: run, resume, load, sweep, load_sweep, boundary, fit (re-exported by the
package; they wrap the native module, raise the package's exceptions and draw progress)."""

from __future__ import annotations

import os
import warnings
from typing import Any, Dict, Mapping, Optional, Union

from . import _native, _progress
from ._errors import Interrupted, NumericalFailure
from ._native import Scene
from ._progress import ProgressArg
from ._result import FitResult, MapTable, RunResult

# The options' defaults, the command line's own (one definition, in the run library).
_DEFAULTS = _native.option_defaults()

#: What a scene argument may be: a ``Scene``, a path to a scene file, or a scene dict.
SceneLike = Union[Scene, str, "os.PathLike[str]", Mapping[str, Any]]
#: A path: str or os.PathLike.
PathLike = Union[str, "os.PathLike[str]"]


def _scene(scene: SceneLike) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(scene)
    if isinstance(scene, (str, os.PathLike)):
        return Scene.load(scene)
    raise TypeError(
        f"scene = {scene!r} ({type(scene).__name__}) is invalid; allowed: a stickslip.Scene, "
        "a path to a scene file or a scene dict"
    )


def _path_text(path: Optional[PathLike]) -> Optional[str]:
    return None if path is None else os.fspath(path)


def _finish(parts: Dict[str, Any], out: Optional[PathLike], warn: bool) -> RunResult:
    """The RunResult of ``parts``; raises ``Interrupted``, ``NumericalFailure`` or the
    exception a progress callback raised."""
    result = RunResult(parts)
    if warn:
        for w in result.run_info.get("warnings", ()):
            if w.get("severity") == "warning":
                warnings.warn(f"stickslip: {w.get('message')}", RuntimeWarning, stacklevel=3)
    error = parts.get("error")
    where = _path_text(out)
    if isinstance(error, KeyboardInterrupt):
        info = result.run_info
        message = (
            f"run {info.get('name')!r} interrupted at t = {info.get('t_final', 0.0):e} s "
            f"(step {info.get('steps', 0)}, {info.get('events', 0)} events); "
        )
        if where is None:
            message += "the output so far is in .result"
        else:
            message += (
                f"the output so far is in .result and in {where}, with a checkpoint: "
                f"stickslip.resume({where!r}) finishes the run"
            )
        raise Interrupted(message, result=result, out=where) from None
    if error is not None:
        raise error
    if result.stop in ("failure", "refused"):
        f = result.run_info.get("failure") or {}
        message = f.get("message") or f"the run stopped with {result.stop}"
        if where is not None:
            message += f" (output up to the failure in {where})"
        raise NumericalFailure(
            message,
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


def run(
    scene: SceneLike,
    *,
    overrides: Optional[Mapping[str, Any]] = None,
    progress: ProgressArg = None,
    out: Optional[PathLike] = None,
    force: bool = False,
    checkpoint_every: float = _DEFAULTS["run.checkpoint_every"],
) -> RunResult:
    """Runs a scene and returns its output as a ``RunResult``.

    ``scene``: a ``Scene``, a path to a scene file (TOML) or a scene dict; ``overrides``:
    ``{"section.key": value}`` applied first (like ``--set``).

    ``progress``: None (default, silent), True for a bar (tqdm's when it is installed,
    through ``tqdm.auto`` so a notebook shows a widget; else one line on stderr redrawn in
    place), or a callable receiving a dict at most ten times a second and once at the end:
    ``fraction`` (of time.end), ``t_s``, ``end_s``, ``steps``, ``events``, ``elapsed_s``,
    ``eta_s`` (None until known), ``stop`` (None while running, then why the run stopped).
    An exception the callable raises stops the run and is raised here (a
    ``KeyboardInterrupt`` as ``Interrupted``).

    ``out``: a directory to write the command line's files into, as ``stickslip run SCENE
    --out DIR`` does (the same bytes; run.json's ``wall_seconds`` aside), with checkpoints
    every ``checkpoint_every`` seconds of wall time (0 = none; an interruption writes one
    anyway), so that ``stickslip.resume(out)`` (or ``stickslip resume DIR``) finishes an
    interrupted or killed run. A directory holding an earlier run raises
    ``FileExistsError`` unless ``force=True``, which replaces it. Without ``out`` the run
    stays in memory.

    The GIL is released while the run steps (other Python threads go on). Ctrl-C stops it
    within about 0.1 s and raises ``Interrupted`` (a ``KeyboardInterrupt``) whose ``.result``
    holds the output so far. Raises ``SceneError`` for a bad scene and ``NumericalFailure``
    when the numerics fail or the run is refused before its first step; its ``.result``
    holds the output recorded up to the failure. The preflight's warnings (likely unit
    slips, a step beyond a stability limit; run_info["warnings"]) are issued as
    ``RuntimeWarning``, as the command line prints them.

    The numbers are those of ``stickslip run SCENE --out DIR`` for the same scene, bit for
    bit (run_info's ``wall_seconds`` aside).
    """
    s = _scene(scene)
    if overrides:
        s = s.with_overrides(overrides)
    callback, bar = _progress.start(progress, "run", s.name)
    try:
        parts = _native.run(
            s, progress=callback, out=out, force=force, checkpoint_every=checkpoint_every
        )
    finally:
        if bar is not None:
            bar.close()
    return _finish(parts, out, warn=True)


def resume(
    dir: PathLike,
    *,
    progress: ProgressArg = None,
    checkpoint_every: Optional[float] = None,
    allow_other_build: bool = False,
) -> RunResult:
    """Finishes the interrupted (or killed) run in ``dir`` from its checkpoint, as
    ``stickslip resume DIR`` does, and returns the whole run's output: the files are those
    of an uninterrupted run, bit for bit (run.json's ``wall_seconds`` aside). ``dir`` is the
    ``out`` of ``stickslip.run`` or of ``stickslip run --out``.

    ``progress`` as for ``run``; ``checkpoint_every`` (seconds of wall time, 0 = none)
    replaces the run's interval. A run that has already ended is returned as it is (as
    ``load`` gives it). The checkpoint is bound to the build of the numerics that wrote it
    (the package and the command line built from one tree share it): another build's (other
    sources, compiler, target or optimisation level) would not continue the same numbers and
    is refused with ``ValueError`` naming both builds, unless ``allow_other_build=True``,
    which continues it and records the crossing in ``run_info["resumed_across_builds"]``.
    Raises ``FileNotFoundError`` when there is nothing to resume (no directory, no
    checkpoint: a run killed before its first one is run again with ``stickslip.run``),
    ``ValueError`` for a damaged checkpoint or partial output, one of an older format or
    another build's, ``Interrupted`` and ``NumericalFailure`` as ``run`` does.
    """
    callback, bar = _progress.start(progress, "run", os.path.basename(os.fspath(dir)))
    try:
        parts = _native.resume(
            dir,
            progress=callback,
            checkpoint_every=checkpoint_every,
            allow_other_build=allow_other_build,
        )
    finally:
        if bar is not None:
            bar.close()
    return _finish(parts, dir, warn=False)


def load(dir: PathLike) -> RunResult:
    """Reads the run in ``dir`` (written by ``stickslip.run(…, out=dir)`` or ``stickslip run
    --out``), whatever its state, as a ``RunResult``; nothing is run or written.

    - finished (``status`` ``"ok"``) or failed (``"failed"``, with run_info["failure"]): the
      files as they are;
    - interrupted (``"interrupted"``): the data up to the interruption, which the run
      published under the usual names (``resume`` finishes it);
    - killed without a graceful stop (``"running"``: SIGKILL, a power loss, or still
      running): the data as of its last checkpoint, read from the temporary files (counters,
      events and summary from the checkpoint); without a checkpoint, the complete rows the
      temporary files hold, and no events.

    Raises ``FileNotFoundError`` when ``dir`` holds no run, ``ValueError`` for a file that
    does not read as its format says.
    """
    return RunResult(_native.load(dir))


def sweep(
    sweep: Union[PathLike, Mapping[str, Any]],
    jobs: Optional[int] = None,
    *,
    out: Optional[PathLike] = None,
    force: bool = False,
    allow_large: bool = False,
    progress: ProgressArg = None,
) -> MapTable:
    """Runs a friction map and returns its table (map.csv) as a ``MapTable``, a
    ``dict[str, numpy.ndarray]`` (with ``points``, ``complete`` and ``to_pandas()``).

    ``sweep``: a sweep file (TOML, docs/reference.md "Sweeps"; its ``scene`` is relative to
    the file) or a dict with the same keys, e.g.::

        {"name": "v-A0", "scene": "validation/scenes/rigid.toml",   # relative to the cwd
         "set": {"contact.nodes": 50, "time.max_events": 4},
         "axis": [{"key": "drive.velocity", "values": [1e-3, 1e-2]},
                  {"key": "temperature.A0",
                   "range": {"from": 0.0, "to": 1.5e6, "count": 4}}]}

    In a dict, ``scene`` is a path relative to the current directory, or a ``Scene``.
    ``jobs``: points run in parallel, an int >= 1 (default None: the available cores; no
    more threads than points are started). ``out``: a sweep directory to keep (points/,
    map.csv, map.json; a rerun skips finished points, as ``stickslip sweep run --out``;
    ``load_sweep`` reads it); by default a temporary one. ``force``: start afresh, removing
    the earlier results in ``out`` (of another sweep, or of this one). ``allow_large``: allow
    more than 100000 points (at most 10000000).

    ``progress``: None (silent), True for a bar (as in ``run``), or a callable receiving a
    dict at most ten times a second and once at the end: ``done`` (points run so far),
    ``total`` (points to run; those found finished in ``out`` left out), ``skipped``,
    ``failed`` (failed or refused so far), ``fraction``, ``elapsed_s``, ``eta_s``, ``stop``
    (None while running, then ``"end"`` or ``"interrupted"``).

    Columns, in map.csv's order: see ``MapTable``. A failing point is a row with its status
    and message; the sweep goes on. A sweep with ``[verify]`` (``"verify": {"sample": 0.1}``
    in a dict) reruns its spot checks at 2N and at a tenth of the tolerance once the map is
    complete; the table's ``spot_checks`` says what changed.

    Every point's record in ``out`` carries the sweep's fingerprint (the sweep and the build
    of the numerics) and its values: points another build computed are recomputed (a
    ``RuntimeWarning`` says how many and why), and a record of another sweep raises
    ``OSError`` naming it, as does a directory holding another sweep without ``force``
    (``FileExistsError``).

    The GIL is released while points run. Ctrl-C stops the sweep within about 0.1 s and
    raises ``Interrupted`` (a ``KeyboardInterrupt``) whose ``.result`` is the partial table
    of the points finished so far (with ``out``, a rerun goes on from there). Raises
    ``SweepError`` (a ``SceneError``) for a bad sweep, ``TypeError`` or ``ValueError`` for a
    bad ``jobs``, ``force``, ``allow_large``, ``out`` or ``progress``.
    """
    callback, bar = _progress.start(progress, "sweep", "sweep")
    try:
        parts = _native.sweep(
            sweep,
            jobs,
            out=out,
            force=force,
            allow_large=allow_large,
            progress=callback,
        )
    finally:
        if bar is not None:
            bar.close()
    table = MapTable(
        parts["table"], points=parts["points"], complete=parts["complete"], spot_checks=parts["spot_checks"]
    )
    if parts["warning"]:
        warnings.warn(f"stickslip.sweep: {parts['warning']}", RuntimeWarning, stacklevel=2)
    error = parts["error"]
    if isinstance(error, KeyboardInterrupt):
        where = _path_text(out)
        message = (
            f"sweep interrupted: {table.rows} of {table.points} points finished, "
            f"{table.points - table.rows} not run; the partial table is in .result"
        )
        if where is not None:
            message += f"; stickslip.sweep with out={where!r} again goes on from there"
        raise Interrupted(message, result=table, out=where) from None
    if error is not None:
        raise error
    return table


def load_sweep(dir: PathLike) -> MapTable:
    """Reads the table of the sweep in ``dir`` (the ``out`` of ``stickslip.sweep`` or of
    ``stickslip sweep run``) as a ``MapTable``, without running or writing anything: map.csv
    when the map is complete; else (a sweep interrupted, still running, or whose shards run
    elsewhere) the rows of the points finished so far, from their records, in point order
    (``complete`` False). Records of another build count as not finished, as in ``stickslip
    sweep merge``.

    Raises ``FileNotFoundError`` when ``dir`` holds no sweep (no sweep.json), ``OSError`` for
    a record of another sweep.
    """
    parts = _native.load_sweep(dir)
    return MapTable(
        parts["table"], points=parts["points"], complete=parts["complete"], spot_checks=parts["spot_checks"]
    )


def verify(
    scene: SceneLike,
    rtol: float = _DEFAULTS["verify.rtol"],
    *,
    jobs: int = _DEFAULTS["verify.jobs"],
    target: Optional[float] = None,
) -> Dict[str, Any]:
    """The error of every summary number of ``scene``, as ``stickslip verify`` gives it: the
    scene runs at its own settings and refined in space (N, 2N, 4N) and in time (tolerance
    /10, /100, or Δt /2, /4) apart, ``jobs`` runs at a time.

    Returns a dict (verify.json's content): ``quantities``, a list with per quantity
    ``name``, ``unit``, ``value`` (at the scene's settings), ``text`` (a discrete quantity's
    value: the event count, the regime), ``extrapolated``, ``uncertainty`` (of ``value``, in
    its unit: Celik's GCI with safety factor 1.25 in the asymptotic range, 3 outside),
    ``space`` and ``time`` (each refinement's ``order_observed``, ``order_theoretical``,
    ``asymptotic``, ``uncertainty``, ``note``), ``asymptotic``, ``changed`` and ``verdict``
    (``"within"`` rtol, ``"outside"``, ``"not_converged"`` or ``"changed"``); ``levels`` (the
    runs: axis, nodes, tolerance or dt_s, steps, wall_s, status); ``rtol``; ``scene``.

    With ``target`` (a relative error in (0, 1)) it searches instead, as ``stickslip verify
    --target``: the cheapest ``contact.nodes`` and ``time.tolerance`` whose estimated error of
    the first onset and of its peak force is within ``target``, from runs to the first event
    (N doubling from 25, then the tolerance falling tenfold). Returns target.json's content:
    ``choice`` (``nodes``, ``tolerance``, ``grid``, ``space_error`` and ``time_error`` as
    [onset, peak force] relative, ``estimated_wall_s``, ``wall_s``, ``t_first_onset``,
    ``f_peak_first``; None when the node limit or the smallest tolerance came first, with
    ``note`` saying which), ``probes`` (every run), ``target``, ``scene``. Apply the choice with
    ``scene.with_overrides({"contact.nodes": c["nodes"], "time.tolerance": c["tolerance"]})``.

    Raises ``ValueError`` for an rtol or target outside (0, 1) or a target with fixed steps or
    a homogeneous contact, ``SceneError`` when a refined scene is invalid (e.g. 4N above the
    node limit), ``TypeError`` for arguments of the wrong type.
    """
    if target is not None:
        if isinstance(target, bool) or not isinstance(target, (int, float)):
            raise TypeError(f"target: expected a number, got {type(target).__name__}")
        return dict(_native.verify_target(_scene(scene), float(target)))
    for name, value in (("rtol", rtol), ("jobs", jobs)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"{name}: expected a number, got {type(value).__name__}")
    if isinstance(jobs, float) or jobs < 1:
        raise ValueError(f"jobs = {jobs!r} is invalid; allowed: an int >= 1")
    return dict(_native.verify(_scene(scene), float(rtol), int(jobs)))


def boundary(
    scene: SceneLike,
    key: str,
    lo: float,
    hi: float,
    *,
    rtol: float = _DEFAULTS["boundary.rtol"],
    scan: int = _DEFAULTS["boundary.scan"],
    jobs: int = _DEFAULTS["boundary.jobs"],
    scale: str = _DEFAULTS["boundary.scale"],
) -> Dict[str, Any]:
    """Every value of ``key`` (a scene key taking a number, in its unit) between ``lo`` and
    ``hi`` where the regime changes, as ``stickslip boundary`` finds them: a first scan of
    ``scan`` points (the ends included; log-spaced when both ends are > 0), then each change
    between neighbouring points is bisected until ``hi - lo <= rtol * max(|lo|, |hi|)`` and
    rerun at 2N and at a tenth of the tolerance. ``jobs`` runs go on at a time. ``scale``
    says which regime: ``"film"`` (the summary's ``regime``) or ``"stamp"`` (its
    ``stamp_regime``: where the stamp's slips stop recurring).

    Returns a dict for the lowest change: ``value`` (the final bracket's midpoint), ``below``
    and ``above`` (the regimes either side), ``lo`` and ``hi`` (the final bracket),
    ``error`` (half the bracket plus how far the change moves at the finer resolution;
    ``inf`` when it is not found there), and ``changes``: every change as such a dict (also
    with ``bracket``, ``moves`` per refinement, ``third``: a regime met inside, and ``runs``).
    Also ``runs`` (all of them), ``probes`` (every run as ``{"value", "regime", "stage"}``),
    ``scan`` (the scan's points), ``undecided`` (stretches where the stamp-scale regime
    stayed ``transient``, i.e. undecided, even over 8 times the scene's window: each
    ``{"below", "above", "undecided"}``, a change there not located and never counted as one),
    ``warnings`` (changes closer than the scan's spacing, a third regime, a change lost at the
    finer resolution, an undecided stretch), ``key`` and ``rtol``.

    Raises ``ValueError`` when every scan point has the same regime or every change found is
    undecided, for a key that is not a number and for a bad bracket, tolerance, scan or jobs;
    ``SceneError`` for a value the scene refuses; ``RuntimeError`` when a run fails
    numerically; ``Interrupted`` on Ctrl-C (``.result`` is None; its message lists the
    changes bracketed so far).
    """
    if isinstance(key, bool) or not isinstance(key, str):
        raise TypeError(f"key: expected a scene key as a str, got {type(key).__name__}")
    for name, value in (("lo", lo), ("hi", hi), ("rtol", rtol), ("scan", scan), ("jobs", jobs)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"{name}: expected a number, got {type(value).__name__}")
    if scale not in ("film", "stamp"):
        raise ValueError(f"scale = {scale!r} is invalid; allowed: \"film\" or \"stamp\"")
    if isinstance(scan, float) or scan < 2:
        raise ValueError(f"scan = {scan!r} is invalid; allowed: an int >= 2 (the range's ends included)")
    if isinstance(jobs, float) or jobs < 1:
        raise ValueError(f"jobs = {jobs!r} is invalid; allowed: an int >= 1")
    try:
        return dict(
            _native.boundary(
                _scene(scene), key, float(lo), float(hi), float(rtol), int(scan), int(jobs), scale
            )
        )
    except KeyboardInterrupt as e:
        if isinstance(e, Interrupted):
            raise
        raise Interrupted(f"stickslip.boundary interrupted ({e})") from None


def _trace_arrays(data: Any, columns: Mapping[str, str]) -> Dict[str, Any]:
    """t, F and (if present) X of a dict of arrays or a pandas DataFrame, as float lists."""
    out: Dict[str, Any] = {}
    for which, required in (("t", True), ("F", True), ("X", False)):
        name = columns.get(which, which)
        if name not in data:
            if required:
                raise ValueError(
                    f"data: no column {name!r} for {which}; allowed: a dict or DataFrame with "
                    f"columns {columns.get('t', 't')!r} and {columns.get('F', 'F')!r} (map other "
                    "names with columns={'t': NAME, 'F': NAME})"
                )
            continue
        values = data[name]
        values = values.to_numpy() if hasattr(values, "to_numpy") else values
        out[which] = [float(v) for v in values]
    return out


def fit(
    scene: SceneLike,
    data: Any,
    params: Any,
    misfit: str = _DEFAULTS["fit.misfit"],
    *,
    noise: Optional[float] = None,
    columns: Optional[Mapping[str, str]] = None,
    jobs: int = _DEFAULTS["fit.jobs"],
    profile: Optional[str] = None,
    progress: Optional[Any] = None,
    out: Optional[PathLike] = None,
    jacobian: str = "differences",
) -> FitResult:
    """Fits scene parameters to a measured friction trace, as ``stickslip fit`` does
    (docs/fit.md): a space-filling sample of the bounds, then bounded Levenberg–Marquardt
    whose finite-difference Jacobians stay above the solver's noise; ``jobs`` runs at a time.

    ``data``: a trace file's path (CSV with a header line, columns ``t`` in s and ``F`` in N,
    optionally ``X`` in m), a dict of arrays or a pandas DataFrame with those columns;
    ``columns`` maps other names, e.g. ``{"t": "time", "F": "force"}``. ``params``: the free
    parameters, each ``"KEY"`` or ``"KEY=LO:HI"`` (a scene key taking a number; bounds default
    to the key's usual range; searched in log space when both are > 0), a str or a list.
    ``misfit``: ``"events"`` (onsets, intervals, peak forces and drops matched event by event)
    or ``"trace"`` (F at the data's times, with a fitted time shift). ``noise``: the standard
    deviation of F's noise, N (default: estimated from the data). ``profile``: a parameter whose
    profile likelihood to compute. ``progress``: None, or a callable receiving a dict
    (``stage``, ``evaluations``, ``failed_runs``, ``best_chi2``, ``tolerance``: the runs'
    ``time.tolerance``, which the fit tightens near its optimum, ``elapsed_s``) a few times a
    second. ``out``: a directory to write ``fit.json``, ``fit.svg`` and ``fitted.toml`` into,
    the files ``stickslip fit --out DIR`` writes (created if missing; an interrupted fit's best
    model so far is written too). ``jacobian``: ``"differences"`` (central differences grown out
    of the solver's noise) or ``"replay"`` (forward differences of runs that take the point's
    own run's steps again: the derivative of the discrete solution, one run per parameter;
    adaptive steps; fit.json's ``jacobian`` says which was used).

    Returns a ``FitResult`` (``.values``, ``.stderr``, ``.intervals``, ``.correlation``,
    ``.unidentified``, ``.scene``, ``.to_dict()``: fit.json's content).

    Raises ``ValueError`` for bad input (naming the field: an unknown key, a bound outside the
    key's range, lo >= hi, a trace whose t is not increasing, a value that is not a finite
    number, too few samples, a trace without events for the events misfit), ``SceneError``
    for a value the scene refuses, ``OSError`` for a trace file that cannot be read or an
    ``out`` that cannot be written, ``RuntimeError`` when no run of the optimiser succeeded,
    ``Interrupted`` on Ctrl-C (``.result``: the best fit so far, status ``"interrupted"``, or
    None before any run ended).
    """
    if isinstance(params, str):
        params = [params]
    if not isinstance(params, (list, tuple)) or not all(isinstance(p, str) for p in params):
        raise TypeError("params: expected a str or a list of str (KEY or KEY=LO:HI)")
    if misfit not in ("events", "trace"):
        raise ValueError(f"misfit = {misfit!r} is invalid; allowed: \"events\" or \"trace\"")
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"jobs = {jobs!r} is invalid; allowed: an int >= 1")
    if jacobian not in ("differences", "replay"):
        raise ValueError(f"jacobian = {jacobian!r} is invalid; allowed: \"differences\" or \"replay\"")
    if progress is not None and not callable(progress):
        raise TypeError("progress: expected None or a callable taking a dict")
    cols = dict(columns or {})
    s = _scene(scene)
    kwargs: Dict[str, Any] = {
        "noise": None if noise is None else float(noise),
        "jobs": int(jobs),
        "profile": profile,
        "progress": progress,
        "out": None if out is None else os.fspath(out),
        "jacobian": jacobian,
    }
    if isinstance(data, (str, os.PathLike)):
        spec = ",".join(f"{k}={v}" for k, v in cols.items()) or None
        kwargs.update(path=os.fspath(data), columns=spec)
    else:
        arrays = _trace_arrays(data, cols)
        kwargs.update(t=arrays["t"], f=arrays["F"], x=arrays.get("X"))
    try:
        parts = _native.fit(s, list(params), misfit, **kwargs)
    except KeyboardInterrupt as e:
        if isinstance(e, Interrupted):
            raise
        raise Interrupted(f"stickslip.fit interrupted ({e})") from None
    result = FitResult(parts, Scene.from_toml(parts["fitted_toml"]))
    if result.status == "interrupted":
        raise Interrupted("stickslip.fit interrupted; .result holds the best fit so far", result=result)
    return result
