"""The exception classes of stickslip (raised by the native module and by the functions of
``stickslip``)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Optional, Union

if TYPE_CHECKING:  # pragma: no cover
    from ._result import FitResult, MapTable, RunResult


class SceneError(ValueError):
    """A bad scene (the command line's exit status 2).

    The message names the key, the value given and the allowed range, e.g.
    ``contact.nodes = 0 is out of range: allowed >= 1``.

    Attributes:
        key: the scene key, e.g. ``"contact.nodes"`` (None when the problem has no key: a
            file that cannot be read, a TOML syntax error).
        value: the value given, as written in a scene (None if none).
        allowed: what is allowed there (None if not stated).
    """

    def __init__(
        self,
        message: str,
        key: Optional[str] = None,
        value: Optional[str] = None,
        allowed: Optional[str] = None,
    ) -> None:
        super().__init__(message)
        self.key = key
        self.value = value
        self.allowed = allowed


class SweepError(SceneError):
    """A bad sweep (file or dict): ``key`` is the sweep's key (``axis[1].range.count``,
    ``regime.stick_slip_recovery``, ``scene``, …) or the scene key a point's scene got wrong;
    ``point`` the point number when one point's scene is bad; ``line`` the line of the sweep
    file the key is on (None for a dict, or a key that is not written)."""

    def __init__(
        self,
        message: str,
        key: Optional[str] = None,
        value: Optional[str] = None,
        allowed: Optional[str] = None,
        point: Optional[int] = None,
        line: Optional[int] = None,
    ) -> None:
        super().__init__(message, key, value, allowed)
        self.point = point
        self.line = line


class NumericalFailure(RuntimeError):
    """The numerics failed (a blow-up, a non-finite value; the command line's exit status 3),
    or the run was refused before its first step (the preflight's verdict, ``refused``).

    Attributes:
        time_s: time at the end of the failing step, s (0 for a refusal).
        step: number of the failing step, from 1 (0 for a refusal).
        node: index of the node where the bad value appeared first.
        r_m: radius of that node, m.
        quantity: the quantity (``"phi"``, ``"tau"``, ``"coupling residual"``, …).
        value: its value (float, or a string when not finite).
        reason: what it means and what to do.
        refused: True if the run was refused before the first step.
        result: the output recorded up to the failure (a ``RunResult``), or None.
    """

    def __init__(
        self,
        message: str,
        *,
        time_s: float = 0.0,
        step: int = 0,
        node: int = 0,
        r_m: float = 0.0,
        quantity: str = "",
        value: Any = None,
        reason: str = "",
        refused: bool = False,
        result: Optional["RunResult"] = None,
    ) -> None:
        super().__init__(message)
        self.time_s = time_s
        self.step = step
        self.node = node
        self.r_m = r_m
        self.quantity = quantity
        self.value = value
        self.reason = reason
        self.refused = refused
        self.result = result


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT), or a ``KeyboardInterrupt`` raised by a progress callback, stopped
    ``stickslip.run``, ``stickslip.resume``, ``stickslip.sweep`` or ``stickslip.fit``; the
    output up to that moment is kept. A ``KeyboardInterrupt``: code that catches that one (or nothing) behaves
    as before.

    Attributes:
        result: the output so far: a ``RunResult`` (status ``"interrupted"``) for a run, a
            ``MapTable`` of the points finished so far (``complete`` False) for a sweep, a
            ``FitResult`` of the best model so far (status ``"interrupted"``; None when no run
            had ended) for a fit.
        out: the output directory (``out=`` of ``run`` or ``sweep``, ``dir`` of ``resume``),
            or None for a run in memory. A run written there keeps a checkpoint:
            ``stickslip.resume(out)`` finishes it; a sweep run again with the same ``out``
            skips its finished points.
    """

    def __init__(
        self,
        message: str,
        result: Optional[Union["RunResult", "MapTable", "FitResult"]] = None,
        out: Optional[str] = None,
    ) -> None:
        super().__init__(message)
        self.result = result
        self.out = out
