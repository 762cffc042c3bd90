"""``RunResult`` (what ``stickslip.run``, ``resume`` and ``load`` return: the five output files
of a run, in memory), ``MapTable`` (what ``stickslip.sweep`` and ``load_sweep`` return:
map.csv's columns) and ``FitResult`` (what ``stickslip.fit`` returns: fit.json's content)."""

from __future__ import annotations

from typing import Any, Dict, Optional, Union

import numpy as np

Columns = Dict[str, np.ndarray]


def _pandas(who: str, instead: str) -> Any:
    """The pandas module, or an ImportError saying how to install it."""
    try:
        import pandas  # type: ignore[import-untyped, unused-ignore]
    except ImportError as e:
        raise ImportError(
            f"{who} needs pandas, which is not installed; install it with "
            f"`pip install pandas` (the arrays are in {instead} without it)"
        ) from e
    return pandas

TABLES = ("series", "events", "slips", "profiles", "probes")


class RunResult:
    """The output of one run: the tables of series.csv, events.csv, slips.csv, profiles.csv
    and probes.csv as ``dict[str, numpy.ndarray]`` (the CSV columns under the same names, in
    file order, float64; ``events["k"]``, ``slips["k"]`` and ``slips["meltings"]`` int64; an
    empty CSV cell is NaN) and run.json as
    ``summary`` plus ``run_info``. The numbers are the command line's, bit for bit.

    Units (run_info["columns"] has them all): ``series``: t s, X m, V m/s, F N, phi_mean –,
    eps_mean –, melted_fraction –, F_1d N. ``events``: k –, t_onset s, r_first m, x_onset m,
    f_peak N, r_min m, t_center s, t_end s, max_melted_fraction –, recovery –, f_mean N,
    melted_area –. ``slips`` (one row per slip of the stamp): k –, t_start s, t_end s,
    f_start N, f_end N, drop N, x_start m, x_end m, jump m, duration s, meltings –.
    ``profiles``: t s, r m, phi –, eps –, tau Pa, u0 m, u3d m (one block of rows per
    profile time). ``probes``: t s, ``phi@<r>`` –, ``t_melt@<r>`` s (r in m as ``{:e}``).

    Attributes:
        series, events, slips, profiles, probes: the tables.
        summary: run.json's ``summary`` (n_events, t_first_onset s, period_last s,
            x_period_last m, f_peak_first N, f_peak_last N, f_mean N, recovery,
            melted_time_fraction, regime, steady, n_slips, stamp_regime, cycles: the
            settled part's statistics of meltings and of slips); None values where the
            run has none.
        run_info: the rest of run.json (name, status, failure, stop, version, scene as
            resolved, derived, warnings, steps, accepted_steps, rejected_steps, forced_steps,
            t_final, wall_seconds, coupling_iterations, seed, events, series_rows, columns).
    """

    __slots__ = (
        "series",
        "events",
        "slips",
        "profiles",
        "probes",
        "summary",
        "run_info",
    )

    def __init__(self, parts: Dict[str, Any]) -> None:
        self.series: Columns = parts["series"]
        self.events: Columns = parts["events"]
        self.slips: Columns = parts["slips"]
        self.profiles: Columns = parts["profiles"]
        self.probes: Columns = parts["probes"]
        self.summary: Optional[Dict[str, Any]] = parts["summary"]
        self.run_info: Dict[str, Any] = parts["run_info"]

    @property
    def status(self) -> str:
        """``"ok"``, ``"failed"``, ``"interrupted"`` (run.json's ``status``), or
        ``"running"`` for a directory whose run was killed (or still runs): ``load`` then
        gives its data as of the last checkpoint."""
        return str(self.run_info["status"])

    @property
    def stop(self) -> Optional[str]:
        """Why the run stopped: ``end``, ``max_events``, ``open_event``, ``failure``,
        ``refused``, ``interrupted`` (run.json's ``stop``); None for a run that has not
        stopped (status ``"running"``)."""
        stop = self.run_info.get("stop")
        return None if stop is None else str(stop)

    @property
    def units(self) -> Dict[str, Dict[str, str]]:
        """The unit of every column: table name → column → unit (from run.json's
        ``columns``)."""
        return {
            name: self.run_info["columns"].get(f"{name}.csv", {}) for name in TABLES
        }

    def to_pandas(self, table: Optional[str] = None) -> Union[Any, Dict[str, Any]]:
        """The tables as pandas DataFrames: ``table`` one of ``"series"``, ``"events"``,
        ``"slips"``, ``"profiles"``, ``"probes"`` gives that one; without it, a dict of all
        five.

        Raises ImportError if pandas is not installed (it is optional:
        ``pip install pandas``).
        """
        pd = _pandas(
            "RunResult.to_pandas",
            "result.series, .events, .slips, .profiles, .probes",
        )
        if table is not None:
            if table not in TABLES:
                raise ValueError(f"table = {table!r}; allowed: one of {TABLES}")
            return pd.DataFrame(getattr(self, table), copy=False)
        return {name: pd.DataFrame(getattr(self, name), copy=False) for name in TABLES}

    def __repr__(self) -> str:
        n = len(self.series.get("t", ()))
        s = self.summary or {}
        return (
            f"<stickslip.RunResult {self.run_info.get('name')!r}: status {self.status}, "
            f"{n} series rows, {len(self.events.get('k', ()))} events, "
            f"regime {s.get('regime')}>"
        )


class MapTable(Dict[str, np.ndarray]):
    """The table of a sweep: a ``dict[str, numpy.ndarray]`` of map.csv's columns, in its
    order, one row per point in point order (a partial table holds the points finished so
    far). Columns: ``point`` (int64), one per axis key (float64, or str objects for words),
    ``status`` (``ok`` | ``failed`` | ``refused``), ``regime`` (str objects), ``n_events``
    (int64), ``t_first_onset`` s, ``period_last`` s, ``x_period_last`` m, ``f_peak_first``
    N, ``f_peak_last`` N, ``f_mean`` N, ``recovery``, ``melted_time_fraction``, ``wall_s`` s
    (float64, NaN for none), ``message`` (str objects), ``steady`` (bool: the point's last
    cycles repeat), ``level`` (int64: the point's level in a refined sweep, 0 the base grid),
    ``stamp_regime`` (str objects: ``stick_slip``, ``steady_sliding``, ``creep``,
    ``transient``; empty for a table written before it existed), ``n_slips`` (int64),
    ``slip_interval_median`` s and ``melting_interval_median`` s (float64: the median
    intervals over the settled part).

    Attributes:
        points: the number of points of the sweep (of a refined sweep: of the levels
            reached so far).
        complete: every point has its row.
        spot_checks: what a sweep's ``[verify]`` spot checks found (map.json's
            ``spot_checks``: ``checked``, ``sampled``, ``at_boundaries``, ``changed``,
            ``max_change`` as ``[column, relative change, point]``, ``checks`` with each
            point's reruns at 2N and tolerance/10), or None (no ``[verify]``, or the map not
            complete yet).
    """

    def __init__(
        self,
        columns: Dict[str, np.ndarray],
        *,
        points: int,
        complete: bool,
        spot_checks: Optional[Dict[str, Any]] = None,
    ) -> None:
        super().__init__(columns)
        self.points = points
        self.complete = complete
        self.spot_checks = spot_checks

    @property
    def rows(self) -> int:
        """The number of rows (points finished)."""
        return len(self.get("point", ()))

    def to_pandas(self) -> Any:
        """The table as a pandas DataFrame (columns as in map.csv).

        Raises ImportError if pandas is not installed (it is optional:
        ``pip install pandas``).
        """
        pd = _pandas("MapTable.to_pandas", "the table itself, a dict of arrays,")
        return pd.DataFrame(dict(self), copy=False)

    def __repr__(self) -> str:
        state = "complete" if self.complete else "partial"
        return (
            f"<stickslip.MapTable: {self.rows} of {self.points} points ({state}), "
            f"columns {list(self)}>"
        )


class FitResult:
    """What ``stickslip.fit`` found (the content of ``stickslip fit``'s fit.json).

    Attributes:
        values: the fitted value of each parameter, ``{key: value}`` (in the key's unit;
            ``time_shift`` in s for the trace misfit).
        stderr: each parameter's standard error (None: not determined, or interrupted).
        intervals: each parameter's 95 % interval ``(lo, hi)`` (None likewise).
        correlation: the parameters' correlation matrix (``numpy.ndarray``, NaN where
            undefined; the correlations of the logarithms for log-space parameters).
        unidentified: the combinations the data cannot determine, in words.
        misfit: χ², the sum of the squared residuals, each in units of its noise.
        status: ``"ok"`` or ``"interrupted"``.
        scene: the fitted scene (a ``stickslip.Scene``; ``stickslip.run`` reproduces the
            fitted model with it).
        fitted_toml: that scene as TOML text (the command line's fitted.toml).
        t, f, model_f: the data's times (s) and force (N), and the fitted model's force at
            those times (N), as ``numpy.ndarray``.
    """

    def __init__(self, parts: Dict[str, Any], scene: Any) -> None:
        self._report: Dict[str, Any] = parts["report"]
        params = self._report["parameters"]
        self.values: Dict[str, float] = {p["key"]: p["value"] for p in params}
        self.stderr: Dict[str, Optional[float]] = {p["key"]: p["stderr"] for p in params}
        self.intervals: Dict[str, Optional[tuple]] = {
            p["key"]: None if p["lo95"] is None else (p["lo95"], p["hi95"]) for p in params
        }
        self.correlation = np.array(
            [[np.nan if c is None else c for c in row] for row in self._report["correlation"]],
            dtype=float,
        )
        self.unidentified = list(self._report["unidentified"])
        self.misfit: float = self._report["misfit"]
        self.status: str = self._report["status"]
        self.fitted_toml: str = parts["fitted_toml"]
        self.scene = scene
        self.t = np.asarray(parts["t"], dtype=float)
        self.f = np.asarray(parts["f"], dtype=float)
        self.model_f = np.asarray(parts["model_f"], dtype=float)

    def to_dict(self) -> Dict[str, Any]:
        """fit.json's content as a dict (a copy)."""
        import copy

        return copy.deepcopy(self._report)

    def __repr__(self) -> str:
        values = ", ".join(f"{k}={v:.6g}" for k, v in self.values.items())
        return f"FitResult({self.status}: {values}; misfit {self.misfit:.4g})"
