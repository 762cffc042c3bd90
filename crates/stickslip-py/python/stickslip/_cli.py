"""The ``stickslip`` command of the Python package (a console script, ``python -m stickslip``
too): the command line of the Rust binary, the same program (the ``stickslip`` crate's
library), run in this process by ``_native.cli``."""

from __future__ import annotations

import os
import shutil
import signal
import sys
from pathlib import Path
from typing import List, Optional

from . import _native


def _program() -> Optional[str]:
    """The command that starts this program again (``sweep slurm`` writes it into its job
    script): this script, else the ``stickslip`` script beside the interpreter or on PATH."""
    invoked = Path(sys.argv[0]) if sys.argv and sys.argv[0] else None
    if invoked is not None and invoked.name == "stickslip" and invoked.is_file():
        return os.path.abspath(invoked)
    beside = Path(sys.executable).parent / "stickslip"
    if beside.is_file():
        return str(beside)
    return shutil.which("stickslip")


def main(argv: Optional[List[str]] = None) -> None:
    """Runs ``stickslip ARGS...`` (``argv``: the arguments after the program's name, default
    ``sys.argv[1:]``) and exits with its status, as the Rust binary would: its output, its
    statuses, and Ctrl-C (SIGINT or SIGTERM: a checkpoint, status 130)."""
    args = sys.argv[1:] if argv is None else list(argv)
    # The command line handles SIGINT itself, as the binary does; Python's handler (a
    # KeyboardInterrupt once the call returns) would turn status 130 into a traceback.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    sys.stdout.flush()
    sys.exit(_native.cli(["stickslip", *args], _program()))
