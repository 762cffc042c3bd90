"""Errors are exception classes: SceneError (a ValueError, `.key`), NumericalFailure for a
blow-up and for a refused run (`.time_s`, `.step`, `.node`, `.r_m`, `.quantity`)."""

from __future__ import annotations

import pickle
from pathlib import Path

import pytest

import stickslip
from conftest import HARD


def test_out_of_range_names_key_value_and_range(fig2_path: Path) -> None:
    s = stickslip.Scene.load(fig2_path)
    with pytest.raises(stickslip.SceneError) as e:
        s.with_overrides({"contact.nodes": 0})
    assert isinstance(e.value, ValueError)
    assert e.value.key == "contact.nodes"
    assert e.value.value == "0"
    assert e.value.allowed and "1" in e.value.allowed
    assert "contact.nodes" in str(e.value)


def test_unknown_and_missing_keys(fig2_path: Path) -> None:
    s = stickslip.Scene.load(fig2_path)
    with pytest.raises(stickslip.SceneError) as e:
        s.with_overrides({"lubricant.taumax": 1e6})
    assert e.value.key == "lubricant.taumax"
    with pytest.raises(stickslip.SceneError) as e:
        s.with_overrides({"lubricant.tau_max": None})
    assert e.value.key == "lubricant.tau_max"
    with pytest.raises(stickslip.SceneError) as e:
        s.with_overrides({"time.scheme": "exact"})
    assert e.value.key == "time.scheme"
    with pytest.raises(stickslip.SceneError) as e:
        s.with_overrides({"contact.nodes": "many"})
    assert e.value.key == "contact.nodes"
    with pytest.raises(stickslip.SceneError) as e:
        stickslip.Scene.from_dict({"name": "x"})
    assert e.value.key is not None


def test_bad_paths_files_and_types(tmp_path: Path, fig2_path: Path) -> None:
    with pytest.raises(stickslip.SceneError) as e:
        stickslip.Scene.load(tmp_path / "missing.toml")
    assert e.value.key is None and "missing.toml" in str(e.value)
    bad = tmp_path / "bad.toml"
    bad.write_text("name = \n")
    with pytest.raises(stickslip.SceneError, match="line 1"):
        stickslip.Scene.load(bad)
    with pytest.raises(stickslip.SceneError, match="not a bare key"):
        stickslip.Scene.load(fig2_path).with_overrides({"contact..nodes": 1})
    with pytest.raises(stickslip.SceneError, match="not a table"):
        stickslip.Scene.load(fig2_path).with_overrides({"name.x": 1})
    with pytest.raises(TypeError):
        stickslip.Scene.from_dict({"name": object()})
    with pytest.raises(TypeError):
        stickslip.Scene.load(fig2_path).with_overrides([("contact.nodes", 1)])


def test_numerical_failure_carries_where_and_partial_output() -> None:
    scene = stickslip.Scene.load(
        HARD / "large_dt.toml", {"time.scheme": "literal", "contact.nodes": 50}
    )
    with pytest.warns(RuntimeWarning, match="stability limit"):
        with pytest.raises(stickslip.NumericalFailure) as e:
            stickslip.run(scene)
    f = e.value
    assert f.step == 10 and f.time_s == pytest.approx(1e-5) and f.node == 0 and f.r_m == 0.0
    assert f.quantity == "phi" and not f.refused
    assert "step 10" in str(f) and "node 0" in str(f)
    assert f.result is not None and f.result.status == "failed" and f.result.stop == "failure"
    assert len(f.result.series["t"]) >= 1
    again = pickle.loads(pickle.dumps(f))
    assert again.step == 10 and str(again) == str(f)


def test_refused_run_is_a_numerical_failure() -> None:
    scene = stickslip.Scene.load(
        HARD / "soft_substrate.toml", {"time.scheme": "literal", "contact.nodes": 50}
    )
    with pytest.raises(stickslip.NumericalFailure) as e:
        stickslip.run(scene)
    f = e.value
    assert f.refused and f.step == 0 and f.time_s == 0.0
    assert f.quantity == "lagged-sweep contraction factor"
    assert f.result is not None and f.result.stop == "refused"


def test_type_errors_name_the_argument() -> None:
    import numpy as np

    with pytest.raises(TypeError, match=r"quadrature = None \(NoneType\) is invalid"):
        stickslip.mdr.forward(np.ones(4), 2e-5, quadrature=None)
    with pytest.raises(TypeError, match=r"form = 3 \(int\) is invalid"):
        stickslip.mdr.back(np.ones(4), 2e-5, form=3)
    with pytest.raises(TypeError, match=r"text = None \(NoneType\) is invalid"):
        stickslip.Scene.from_toml(None)
    with pytest.raises(TypeError, match=r"path = None"):
        stickslip.Scene.load(None)
    # A result that overflows is an error, not an array of inf.
    with pytest.raises(ValueError, match=r"forward: q\[0\] = \S+ is not finite: tau and radius"):
        stickslip.mdr.forward(np.full(5, 1e6), 1e308)
