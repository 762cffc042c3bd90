# Type stubs of the native module stickslip._native (Rust, PyO3). Use the `stickslip`
# package: it re-exports Scene and the mdr functions and wraps run, resume, load, sweep and
# load_sweep.

import os
from typing import Any, Callable, Dict, List, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

_ArrayLike = Union[npt.NDArray[np.floating[Any]], npt.NDArray[np.integer[Any]], Sequence[float]]
_Path = Union[str, os.PathLike[str]]
_Callback = Optional[Callable[[Dict[str, Any]], Any]]
_Form = Literal["dense", "fast"]
_Quadrature = Literal["product", "literal"]

class Scene:
    """A validated scene (the keys of a scene file, SI units), immutable. Build one with
    ``Scene.load``, ``Scene.from_dict`` or ``Scene.from_toml``; ``with_overrides`` gives a
    new one. A bad scene raises ``stickslip.SceneError`` (``.key`` names the key)."""

    @staticmethod
    def load(
        path: Union[str, os.PathLike[str]],
        overrides: Optional[Mapping[str, Any]] = None,
    ) -> Scene:
        """Reads and validates a scene file (TOML), then applies ``overrides``
        (``{"section.key": value}``, like ``--set``)."""
    @staticmethod
    def from_dict(d: Mapping[str, Any]) -> Scene:
        """A scene from a dict nested like the TOML file; dotted keys
        (``{"contact.nodes": 200}``) are accepted at any level; None values are left out."""
    @staticmethod
    def from_toml(text: str) -> Scene:
        """A scene from the text of a scene file."""
    def with_overrides(self, overrides: Mapping[str, Any]) -> Scene:
        """A new scene: this one as written with ``overrides`` applied (``None`` removes a
        key so its default applies)."""
    def to_dict(self, *, resolved: bool = True) -> Dict[str, Any]:
        """The scene as a nested dict: every default filled in, or as written."""
    def to_toml(self, *, resolved: bool = True) -> str:
        """The scene as TOML text: every default filled in, or as written."""
    def check(self) -> Dict[str, Any]:
        """What `stickslip check` reports: verdict, derived, cost, warnings, name, scene."""
    @property
    def name(self) -> str:
        """The scene's ``name``."""
    @property
    def nodes(self) -> int:
        """Nodes simulated (``contact.nodes``; 1 for the homogeneous model)."""
    @property
    def end_s(self) -> float:
        """``time.end``, s."""
    def __eq__(self, other: object) -> bool: ...

def run(
    scene: Scene,
    *,
    progress: _Callback = None,
    out: Optional[_Path] = None,
    force: bool = False,
    checkpoint_every: Optional[float] = None,
) -> Dict[str, Any]:
    """Internal: runs ``scene`` in memory or into ``out`` (GIL released) and returns the
    parts of a ``RunResult`` with ``error``. Use ``stickslip.run``."""

def resume(
    dir: _Path,
    *,
    progress: _Callback = None,
    checkpoint_every: Optional[float] = None,
    allow_other_build: bool = False,
) -> Dict[str, Any]:
    """Internal: finishes the interrupted run in ``dir``. Use ``stickslip.resume``."""

def load(dir: _Path) -> Dict[str, Any]:
    """Internal: reads the run in ``dir``. Use ``stickslip.load``."""

def boundary(
    scene: Scene, key: str, lo: float, hi: float, rtol: float = ..., scan: int = ..., jobs: int = ...
) -> Dict[str, Any]:
    """Internal: the scan and bisections of ``stickslip.boundary``."""

def verify(scene: Scene, rtol: float = ..., jobs: int = ...) -> Dict[str, Any]:
    """Internal: the refinements of ``stickslip.verify``."""

def fit(
    scene: Scene,
    params: List[str],
    misfit: str = ...,
    path: Optional[str] = ...,
    columns: Optional[str] = ...,
    t: Optional[List[float]] = ...,
    f: Optional[List[float]] = ...,
    x: Optional[List[float]] = ...,
    noise: Optional[float] = ...,
    jobs: int = ...,
    profile: Optional[str] = ...,
    progress: Optional[Any] = ...,
    out: Optional[str] = ...,
) -> Dict[str, Any]:
    """Internal: the fit of ``stickslip.fit``."""

def keys() -> List[Dict[str, Any]]:
    """Every scene key as a dict: ``path``, ``type`` (``"real"``, ``"integer"``, ``"text"``,
    ``"choice"`` or ``"real list"``), ``words`` (a choice key's words, else ``None``),
    ``unit`` (SI; ``"–"`` for dimensionless), ``default`` (in words: a value, ``"required"``,
    or how it derives from other keys), ``allowed`` (the range and the rules between keys, in
    words), ``usual`` (``(lo, hi)`` of the absolute value outside which ``check`` warns, else
    ``None``), ``meaning`` and ``since`` (the version that added the key)."""

def sweep(
    sweep: Union[_Path, Mapping[str, Any]],
    jobs: Optional[int] = None,
    *,
    out: Optional[_Path] = None,
    force: bool = False,
    allow_large: bool = False,
    progress: _Callback = None,
) -> Dict[str, Any]:
    """Internal: runs a sweep and returns map.csv as arrays with ``points``, ``complete``,
    ``error`` and ``warning``. Use ``stickslip.sweep``."""

def load_sweep(dir: _Path) -> Dict[str, Any]:
    """Internal: reads the table of the sweep in ``dir``. Use ``stickslip.load_sweep``."""

def forward(
    tau: _ArrayLike,
    radius: float,
    *,
    form: _Form = "dense",
    quadrature: _Quadrature = "product",
) -> npt.NDArray[np.float64]:
    """Eq. 13: q(x) = 2∫ₓ^a0 rτ/√(r² − x²) dr. tau in Pa at r_i = i·radius/N, radius in m;
    returns q in N/m at the same nodes."""

def back(
    u1d: _ArrayLike,
    radius: float,
    *,
    form: _Form = "dense",
    quadrature: _Quadrature = "product",
) -> npt.NDArray[np.float64]:
    """Eq. 15: u3D(r) = (2/π)∫₀^r u1D/√(r² − x²) dx. u1d in m at x_i = i·radius/N, radius
    in m; returns u3D in m."""

def compliance(
    tau: _ArrayLike,
    radius: float,
    g_eff: float,
    *,
    form: _Form = "dense",
    quadrature: _Quadrature = "product",
) -> npt.NDArray[np.float64]:
    """u3D = back(forward(τ))/G*: tau in Pa at r_i = i·radius/N, radius in m, g_eff G* in
    Pa; returns u3D in m."""

def force(
    tau: _ArrayLike,
    radius: float,
    *,
    quadrature: _Quadrature = "product",
) -> float:
    """Eq. 16: F = 2π∫₀^a0 τ r dr in N, tau in Pa at r_i = i·radius/N, radius in m."""

def radii(radius: float, n: int) -> npt.NDArray[np.float64]:
    """The node radii r_i = i·radius/N, i = 0 … N−1, in m."""

def cli(argv: Sequence[str], program: Optional[_Path] = None) -> int:
    """Runs ``stickslip ARGS...`` (``argv[0]`` is the program's name) as the Rust binary does
    and returns its exit status; for the ``stickslip`` command (``stickslip._cli``)."""

def option_defaults() -> Dict[str, Any]:
    """The defaults of the commands' options, ``{"command.option": value}``."""
