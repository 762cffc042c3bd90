"""docs/python.md, the reference of the Python API, is generated from the installed package's
signatures and docstrings; this test keeps the committed file equal to it.

Regenerate after changing the API: ``STICKSLIP_WRITE_REFERENCE=1 cargo xtask python-test -- -k
reference``.
"""

from __future__ import annotations

import inspect
import os
import textwrap
from pathlib import Path

import stickslip

REFERENCE = Path(__file__).resolve().parents[3] / "docs" / "python.md"


def _signature(obj: object, name: str) -> str:
    try:
        return f"{name}{inspect.signature(obj)}"  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return f"{name}(…)"


def _doc(obj: object) -> str:
    doc = inspect.getdoc(obj) or "(no docstring)"
    return textwrap.dedent(doc).strip()


def _entry(title: str, obj: object) -> str:
    return f"### `{title}`\n\n```text\n{_doc(obj)}\n```\n"


def markdown() -> str:
    parts = [
        "# stickslip Python reference\n",
        "Generated from the package's signatures and docstrings by "
        "`crates/stickslip-py/tests/test_reference.py` (a test keeps this file current; "
        "regenerate with `STICKSLIP_WRITE_REFERENCE=1 cargo xtask python-test -- -k "
        "reference`). SI units throughout; scene keys, output columns and sweep files are in "
        "[reference.md](reference.md).\n",
        "## Module `stickslip`\n",
        f"```text\n{_doc(stickslip)}\n```\n",
        "## Functions\n",
    ]
    for name in ("run", "resume", "load", "sweep", "load_sweep", "boundary", "verify", "fit", "keys"):
        fn = getattr(stickslip, name)
        parts.append(_entry(_signature(fn, f"stickslip.{name}"), fn))
    parts.append("## Types\n")
    parts.append(
        "- `SceneLike`: a `Scene`, a path to a scene file (str or os.PathLike) or a scene "
        "dict.\n- `PathLike`: a path, str or os.PathLike.\n- `ProgressArg`: None, True, False "
        "or a callable receiving a dict (see `run` and `sweep`).\n"
    )
    parts.append("## `stickslip.Scene`\n")
    parts.append(f"```text\n{_doc(stickslip.Scene)}\n```\n")
    for name, member in sorted(vars(stickslip.Scene).items()):
        if name.startswith("_"):
            continue
        if isinstance(member, (staticmethod, classmethod)):
            member = member.__func__
        target = getattr(stickslip.Scene, name)
        title = (
            f"Scene.{name}"
            if isinstance(member, property) or type(member).__name__ == "getset_descriptor"
            else _signature(target, f"Scene.{name}")
        )
        parts.append(_entry(title, target))
    parts.append("## `stickslip.RunResult`\n")
    parts.append(f"```text\n{_doc(stickslip.RunResult)}\n```\n")
    for name in ("status", "stop", "units"):
        parts.append(_entry(f"RunResult.{name}", getattr(stickslip.RunResult, name)))
    parts.append(
        _entry(
            _signature(stickslip.RunResult.to_pandas, "RunResult.to_pandas"),
            stickslip.RunResult.to_pandas,
        )
    )
    parts.append("## `stickslip.MapTable`\n")
    parts.append(f"```text\n{_doc(stickslip.MapTable)}\n```\n")
    parts.append(_entry("MapTable.rows", stickslip.MapTable.rows))
    parts.append(
        _entry(
            _signature(stickslip.MapTable.to_pandas, "MapTable.to_pandas"),
            stickslip.MapTable.to_pandas,
        )
    )
    parts.append("## `stickslip.FitResult`\n")
    parts.append(f"```text\n{_doc(stickslip.FitResult)}\n```\n")
    parts.append(
        _entry(
            _signature(stickslip.FitResult.to_dict, "FitResult.to_dict"),
            stickslip.FitResult.to_dict,
        )
    )
    parts.append("## Module `stickslip.mdr`\n")
    parts.append(f"```text\n{_doc(stickslip.mdr)}\n```\n")
    for name in stickslip.mdr.__all__:
        fn = getattr(stickslip.mdr, name)
        parts.append(_entry(_signature(fn, f"mdr.{name}"), fn))
    parts.append("## Exceptions\n")
    for cls in (
        stickslip.SceneError,
        stickslip.SweepError,
        stickslip.NumericalFailure,
        stickslip.Interrupted,
    ):
        base = cls.__mro__[1].__name__
        parts.append(_entry(f"{cls.__name__}({base})", cls))
    return "\n".join(parts)


def test_python_reference_is_current() -> None:
    text = markdown()
    if os.environ.get("STICKSLIP_WRITE_REFERENCE") == "1":
        REFERENCE.write_text(text, encoding="utf-8")
    committed = REFERENCE.read_text(encoding="utf-8") if REFERENCE.exists() else ""
    assert committed == text, (
        f"{REFERENCE} is not what the package documents; regenerate it with "
        "STICKSLIP_WRITE_REFERENCE=1 cargo xtask python-test -- -k reference"
    )


def test_reference_names_every_public_name() -> None:
    text = markdown()
    for name in stickslip.__all__:
        assert name in text, f"stickslip.{name} is missing from the Python reference"
