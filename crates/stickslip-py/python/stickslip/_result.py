"""``RunResult``: what ``stickslip.run`` returns (the five output files of a run, in memory)."""

from __future__ import annotations

from typing import Any, Dict, Optional, Union

import numpy as np

Columns = Dict[str, np.ndarray]

TABLES = ("series", "events", "profiles", "probes")


class RunResult:
    """The output of one run: the tables of series.csv, events.csv, profiles.csv and
    probes.csv as ``dict[str, numpy.ndarray]`` (the CSV columns under the same names, in
    file order, float64; ``events["k"]`` int64; an empty CSV cell is NaN) and run.json as
    ``summary`` plus ``run_info``. The numbers are the command line's, bit for bit.

    Units (run_info["columns"] has them all): ``series``: t s, X m, V m/s, F N, phi_mean –,
    eps_mean –, melted_fraction –, F_1d N. ``events``: k –, t_onset s, r_first m, x_onset m,
    f_peak N, r_min m, t_center s, t_end s, max_melted_fraction –, recovery –, f_mean N,
    melted_area –.
    ``profiles``: t s, r m, phi –, eps –, tau Pa, u0 m, u3d m (one block of rows per
    profile time). ``probes``: t s, ``phi@<r>`` –, ``t_melt@<r>`` s (r in m as ``{:e}``).

    Attributes:
        series, events, profiles, probes: the tables.
        summary: run.json's ``summary`` (n_events, t_first_onset s, period_last s,
            x_period_last m, f_peak_first N, f_peak_last N, f_mean N, recovery,
            melted_time_fraction, regime); None values where the run has none.
        run_info: the rest of run.json (name, status, failure, stop, version, scene as
            resolved, derived, warnings, steps, accepted_steps, rejected_steps, forced_steps,
            t_final, wall_seconds, coupling_iterations, seed, events, series_rows, columns).
    """

    __slots__ = ("series", "events", "profiles", "probes", "summary", "run_info")

    def __init__(self, parts: Dict[str, Any]) -> None:
        self.series: Columns = parts["series"]
        self.events: Columns = parts["events"]
        self.profiles: Columns = parts["profiles"]
        self.probes: Columns = parts["probes"]
        self.summary: Optional[Dict[str, Any]] = parts["summary"]
        self.run_info: Dict[str, Any] = parts["run_info"]

    @property
    def status(self) -> str:
        """``"ok"``, ``"failed"`` or ``"interrupted"`` (run.json's ``status``)."""
        return str(self.run_info["status"])

    @property
    def stop(self) -> str:
        """Why the run stopped: ``end``, ``max_events``, ``open_event``, ``failure``,
        ``refused`` (run.json's ``stop``)."""
        return str(self.run_info["stop"])

    @property
    def units(self) -> Dict[str, Dict[str, str]]:
        """The unit of every column: table name → column → unit (from run.json's
        ``columns``)."""
        return {
            name: self.run_info["columns"].get(f"{name}.csv", {}) for name in TABLES
        }

    def to_pandas(self, table: Optional[str] = None) -> Union[Any, Dict[str, Any]]:
        """The tables as pandas DataFrames: ``table`` one of ``"series"``, ``"events"``,
        ``"profiles"``, ``"probes"`` gives that one; without it, a dict of all four.

        Raises ImportError if pandas is not installed (it is optional:
        ``pip install pandas``).
        """
        try:
            import pandas as pd  # type: ignore[import-untyped, unused-ignore]
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError(
                "RunResult.to_pandas needs pandas, which is not installed; "
                "install it with `pip install pandas` (the arrays are in "
                "result.series, .events, .profiles, .probes without it)"
            ) from e
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
