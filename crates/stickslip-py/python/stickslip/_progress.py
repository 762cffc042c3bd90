"""Progress of runs and sweeps: ``progress=True`` draws a bar (tqdm's, through ``tqdm.auto``
so notebooks get a widget, when tqdm is installed; else one line on stderr redrawn in place),
``progress=callable`` receives the dicts the native module reports (at most ten a second,
and once more at the end with ``stop`` set)."""

from __future__ import annotations

import sys
from typing import Any, Callable, Dict, Optional, Tuple, Union

#: What ``progress=`` accepts.
ProgressArg = Union[bool, Callable[[Dict[str, Any]], Any], None]

#: Runs that ended on their own (the bar is then full).
_ENDED = ("end", "max_events", "open_event")


def _clock(seconds: Optional[float]) -> str:
    """Seconds as ``m:ss`` or ``h:mm:ss`` (``?`` when unknown)."""
    if seconds is None:
        return "?"
    s = int(round(seconds))
    h, rest = divmod(s, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


class _Line:
    """One line on stderr, redrawn in place (carriage return, padded over the last one)."""

    def __init__(self) -> None:
        self._width = 0

    def show(self, text: str) -> None:
        pad = " " * max(0, self._width - len(text))
        sys.stderr.write("\r" + text + pad)
        sys.stderr.flush()
        self._width = len(text)

    def close(self) -> None:
        if self._width:
            sys.stderr.write("\n")
            sys.stderr.flush()
            self._width = 0


class Bar:
    """A progress display for ``kind`` ``"run"`` (position in simulated time) or ``"sweep"``
    (points done), called with the native module's progress dicts; ``close`` ends it."""

    def __init__(self, kind: str, desc: str) -> None:
        self.kind = kind
        self.desc = desc
        self._tqdm: Any = None
        self._line: Optional[_Line] = None
        try:
            from tqdm.auto import tqdm  # type: ignore[import-untyped, unused-ignore]
        except ImportError:
            self._factory: Any = None
        else:
            self._factory = tqdm

    def _state(self, info: Dict[str, Any]) -> Tuple[int, int, str]:
        """Total, position and words after the bar."""
        if self.kind == "run":
            total = 1000
            n = int(round(1000 * float(info.get("fraction", 0.0))))
            if info.get("stop") in _ENDED:
                n = total
            words = f"t = {info.get('t_s', 0.0):.4e} s, {info.get('events', 0)} events"
        else:
            total = int(info.get("total", 0))
            n = int(info.get("done", 0))
            words = f"{info.get('failed', 0)} failed"
            if info.get("skipped"):
                words += f", {info['skipped']} done before"
        return total, n, words

    def __call__(self, info: Dict[str, Any]) -> None:
        total, n, words = self._state(info)
        if self._factory is not None and self._tqdm is None:
            try:
                if self.kind == "run":
                    fmt = "{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}, {postfix}]"
                    self._tqdm = self._factory(total=total, desc=self.desc, bar_format=fmt)
                else:
                    self._tqdm = self._factory(total=total, desc=self.desc, unit="point")
            except Exception:
                # E.g. tqdm's notebook bar without ipywidgets: the plain line instead, never
                # an error that would stop the run.
                self._factory = None
        if self._tqdm is not None:
            bar = self._tqdm
            if bar.total != total:
                bar.total = total
            bar.set_postfix_str(words, refresh=False)
            bar.update(max(0, n - bar.n))
            return
        if self._line is None:
            self._line = _Line()
        fraction = n / total if total else 1.0
        eta = "" if info.get("stop") else f", eta {_clock(info.get('eta_s'))}"
        done = f" ({n}/{total})" if self.kind == "sweep" else ""
        self._line.show(
            f"{self.desc}: {100 * fraction:5.1f}%{done} {words}, "
            f"{_clock(info.get('elapsed_s'))} elapsed{eta}"
        )

    def close(self) -> None:
        if self._tqdm is not None:
            self._tqdm.close()
            self._tqdm = None
        if self._line is not None:
            self._line.close()
            self._line = None


def start(
    progress: ProgressArg, kind: str, desc: str
) -> Tuple[Optional[Callable[[Dict[str, Any]], Any]], Optional[Bar]]:
    """The callback to hand to the native module and the bar to close afterwards."""
    if progress is None or progress is False:
        return None, None
    if progress is True:
        bar = Bar(kind, desc)
        return bar, bar
    if callable(progress):
        return progress, None
    raise TypeError(
        f"progress = {progress!r} ({type(progress).__name__}) is invalid; allowed: None, "
        "True, False or a callable receiving a dict"
    )
