"""Shared fixtures: the workspace root, the command-line binary, and a CSV reader that keeps
every number's bits (the CLI writes shortest round-trip `{:e}` text)."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path
from typing import Dict

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
SCENES = ROOT / "validation" / "scenes"
HARD = ROOT / "validation" / "hard"


def read_csv(path: Path) -> Dict[str, np.ndarray]:
    """A numeric CSV of the CLI as float64 columns (an empty cell is NaN)."""
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    cols = [[] for _ in header]
    for line in lines[1:]:
        cells = line.split(",")
        assert len(cells) == len(header), f"{path}: {line!r}"
        for col, cell in zip(cols, cells):
            col.append(float(cell) if cell else float("nan"))
    return {name: np.array(col, dtype=np.float64) for name, col in zip(header, cols)}


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal as float64 bit patterns (NaN equals NaN, 0.0 differs from -0.0)."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    b = np.ascontiguousarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.fixture(scope="session")
def cli() -> Path:
    """The release `stickslip` binary: $STICKSLIP_BIN, or target/release/stickslip, brought
    up to date with cargo when cargo is there (a stale binary would not match the extension
    built from the current sources)."""
    env = os.environ.get("STICKSLIP_BIN")
    if env:
        path = Path(env)
        if not path.is_file():
            pytest.fail(f"STICKSLIP_BIN={env} is not a file")
        return path
    path = ROOT / "target" / "release" / "stickslip"
    cargo = shutil.which("cargo")
    if cargo is not None:
        subprocess.run(
            [cargo, "build", "--release", "-q", "-p", "stickslip"], cwd=ROOT, check=True
        )
    elif not path.is_file():
        pytest.skip("no stickslip binary (set STICKSLIP_BIN) and no cargo to build one")
    return path


@pytest.fixture(scope="session")
def fig2_path() -> Path:
    return SCENES / "fig2.toml"
