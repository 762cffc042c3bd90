"""The Python surface: Scene (load, from_dict, overrides, to_dict, to_toml, check), run and
its RunResult, to_pandas, the GIL released during a run, the package's public names."""

from __future__ import annotations

import copy
import math
import pickle
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import stickslip
from conftest import HARD, SCENES

SMALL = {"contact.nodes": 50, "time.end": 7e-4, "output.profile_times": [7e-4]}


@pytest.fixture(scope="module")
def small_result() -> stickslip.RunResult:
    return stickslip.run(stickslip.Scene.load(SCENES / "fig2.toml", SMALL))


def test_version_and_exports() -> None:
    assert stickslip.__version__.count(".") == 2
    for name in ("Scene", "run", "sweep", "mdr", "SceneError", "SweepError", "NumericalFailure"):
        assert hasattr(stickslip, name), name
    assert issubclass(stickslip.SceneError, ValueError)
    assert issubclass(stickslip.SweepError, stickslip.SceneError)
    assert stickslip.Scene.__doc__ and "Pa" in stickslip.Scene.__doc__
    assert "N/m" in stickslip.mdr.forward.__doc__


def test_package_ships_stubs_and_marker() -> None:
    pkg = Path(stickslip.__file__).parent
    assert (pkg / "py.typed").is_file()
    assert (pkg / "_native.pyi").is_file()
    assert any(p.name.startswith("_native") and p.suffix in (".so", ".pyd") for p in pkg.iterdir())


def test_load_and_overrides_give_new_scenes(fig2_path: Path) -> None:
    base = stickslip.Scene.load(fig2_path)
    assert base.name == "fig2" and base.nodes == 2000 and base.end_s == 1.3e-3
    small = base.with_overrides({"contact.nodes": 200, "time.dt": 2e-8})
    assert small.nodes == 200 and base.nodes == 2000, "a scene never changes"
    d = small.to_dict()
    assert d["contact"]["nodes"] == 200 and d["time"]["dt"] == 2e-8
    # Defaults are filled in the resolved dict, not in the dict as written.
    assert "stepping" in d["time"]
    assert "stepping" not in small.to_dict(resolved=False)["time"]
    # Load with overrides is the same as load, then with_overrides.
    assert stickslip.Scene.load(fig2_path, {"contact.nodes": 200, "time.dt": 2e-8}) == small
    # None removes a key: its default applies again.
    back = small.with_overrides({"time.dt": None})
    assert back.to_dict()["time"]["dt"] == 1e-8
    # Derived defaults follow: time.dt_max = time.end (no cap), coupling_tol = tolerance / 100.
    shorter = base.with_overrides({"time.end": 1e-3, "output.profile_times": [1e-3]})
    assert shorter.to_dict()["time"]["dt_max"] == pytest.approx(1e-3)
    looser = base.with_overrides({"time.tolerance": 1e-3})
    assert looser.to_dict()["numerics"]["coupling_tol"] == pytest.approx(1e-5)


def test_from_dict_nested_and_dotted(fig2_path: Path) -> None:
    nested = stickslip.Scene.load(fig2_path).to_dict(resolved=False)
    a = stickslip.Scene.from_dict(nested)
    assert a == stickslip.Scene.load(fig2_path)
    dotted = dict(nested)
    contact = dict(dotted.pop("contact"))
    nodes = contact.pop("nodes")
    dotted["contact"] = contact
    dotted["contact.nodes"] = nodes
    assert stickslip.Scene.from_dict(dotted) == a
    flat = {"name": "flat"}
    for section, keys in nested.items():
        if isinstance(keys, dict):
            for k, v in keys.items():
                flat[f"{section}.{k}"] = v
    assert stickslip.Scene.from_dict(flat).to_dict()["contact"] == a.to_dict()["contact"]
    # NumPy values are accepted.
    b = stickslip.Scene.from_dict(
        {**nested, "output": {**nested["output"], "probe_radii": np.array([2e-6, 4e-6])}}
    )
    assert b.to_dict()["output"]["probe_radii"] == [2e-6, 4e-6]
    c = a.with_overrides({"contact.nodes": np.int64(100), "drive.velocity": np.float32(0.5)})
    assert c.nodes == 100 and c.to_dict()["drive"]["velocity"] == 0.5


def test_toml_round_trip_and_pickle(fig2_path: Path) -> None:
    s = stickslip.Scene.load(fig2_path).with_overrides({"contact.nodes": 123})
    assert stickslip.Scene.from_toml(s.to_toml()) == s
    assert stickslip.Scene.from_toml(s.to_toml(resolved=False)) == s
    assert "nodes = 123" in s.to_toml()
    assert pickle.loads(pickle.dumps(s)) == s
    assert copy.deepcopy(s) is s
    assert "fig2" in repr(s)


def test_run_result_tables(small_result: stickslip.RunResult) -> None:
    r = small_result
    assert r.status == "ok" and r.stop == "end"
    assert list(r.series) == ["t", "X", "V", "F", "phi_mean", "eps_mean", "melted_fraction", "F_1d"]
    assert list(r.events)[:5] == ["k", "t_onset", "r_first", "x_onset", "f_peak"]
    assert list(r.profiles) == ["t", "r", "phi", "eps", "tau", "u0", "u3d"]
    assert list(r.probes)[0] == "t" and list(r.probes)[1].startswith("phi@")
    for table in (r.series, r.profiles, r.probes):
        for name, col in table.items():
            assert isinstance(col, np.ndarray) and col.dtype == np.float64 and col.ndim == 1
            assert col.flags.c_contiguous and col.flags.writeable
    assert r.events["k"].dtype == np.int64
    n = len(r.series["t"])
    assert n == r.run_info["series_rows"] and all(len(c) == n for c in r.series.values())
    assert len(r.profiles["r"]) == 50
    assert r.series["t"][0] == 0.0 and r.series["t"][-1] == 7e-4
    assert r.summary["n_events"] == len(r.events["k"]) == r.run_info["events"] == 1
    assert r.summary["regime"] == "transient"
    assert r.run_info["scene"]["contact"]["nodes"] == 50
    assert r.run_info["columns"]["series.csv"]["F"] == "N"
    assert r.units["profiles"]["tau"] == "Pa"
    assert "summary" not in r.run_info
    assert "regime transient" in repr(r)
    # The energy books: per event (its cycle), and the whole run's in the summary.
    assert r.events["dissipated_energy"][0] > 0
    assert r.events["dissipated_energy"][0] == pytest.approx(
        sum(r.events[k][0] for k in (
            "landau_energy", "reset_energy", "sliding_energy", "viscous_energy", "dashpot_energy"
        )), rel=1e-12)
    assert r.units["events"]["dissipated_energy"] == "J"
    books = r.summary["energy"]
    assert abs(books["residual_j"]) < 1e-4 * books["flows"]["drive_work_j"]
    assert r.summary["energy_per_cycle"] is None  # one event: no complete cycle


def test_slips_and_the_stamps_scale(small_result: stickslip.RunResult) -> None:
    # fig2's film under the rigid drive, whose force is F: every melting is a slip.
    fig2 = stickslip.Scene.load(SCENES / "fig2.toml").to_dict(resolved=False)
    fig2["drive"] = {"kind": "rigid", "velocity": 1.0}
    r = stickslip.run(
        stickslip.Scene.from_dict(fig2),
        overrides={**SMALL, "time.end": 2e-5, "output.profile_times": [2e-5]},
    )
    s = r.slips
    assert list(s) == [
        "k", "t_start", "t_end", "f_start", "f_end", "drop", "x_start", "x_end", "jump",
        "duration", "meltings", "dissipated_energy",
    ]
    assert s["k"].dtype == np.int64 and s["meltings"].dtype == np.int64
    assert len(s["k"]) == r.summary["n_slips"] >= 20
    assert np.array_equal(s["drop"], s["f_start"] - s["f_end"])
    # Each slip dissipates; together no more than the whole run.
    assert np.all(s["dissipated_energy"] > 0)
    assert s["dissipated_energy"].sum() <= r.summary["energy"]["flows"]["landau_j"] * 1.01
    assert r.summary["stamp_regime"] == "stick_slip"
    cycles = r.summary["cycles"]
    assert set(cycles) == {"settled_from", "slip_drop", "meltings", "slips"}
    for scale in ("meltings", "slips"):
        assert set(cycles[scale]) == {"count", "interval", "peak", "drop", "advance", "f_mean"}
        assert set(cycles[scale]["interval"]) == {"n", "median", "mean", "min", "max", "cv"}
    assert r.run_info["columns"]["slips.csv"]["jump"] == "m"
    # fig2 on its spring is inertial: the spring's force only grows within 0.7 ms.
    assert len(small_result.slips["k"]) == 0
    assert small_result.summary["stamp_regime"] == "creep"


def test_run_accepts_paths_dicts_and_overrides(fig2_path: Path) -> None:
    a = stickslip.run(str(fig2_path), overrides=SMALL)
    b = stickslip.run(stickslip.Scene.load(fig2_path).to_dict(resolved=False), overrides=SMALL)
    assert np.array_equal(a.series["F"], b.series["F"])
    with pytest.raises(TypeError):
        stickslip.run(42)  # type: ignore[arg-type]


def test_to_pandas(small_result: stickslip.RunResult, monkeypatch: pytest.MonkeyPatch) -> None:
    try:
        import pandas as pd  # noqa: F401
    except ImportError:
        pd = None
    if pd is not None:
        frames = small_result.to_pandas()
        assert set(frames) == {"series", "events", "slips", "profiles", "probes"}
        df = small_result.to_pandas("series")
        assert list(df.columns) == list(small_result.series)
        assert np.array_equal(df["F"].to_numpy(), small_result.series["F"])
        with pytest.raises(ValueError):
            small_result.to_pandas("nope")
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        small_result.to_pandas()


def test_the_gil_is_released_during_a_run(fig2_path: Path) -> None:
    # fig2 at N = 200 to 4 ms: about 0.8 s on a fast host (to its default 1.3 ms it took
    # 0.03 s there, too short for a ticking thread to show anything).
    scene = stickslip.Scene.load(fig2_path, {"contact.nodes": 200, "time.end": 4e-3})
    ticks = []
    done = threading.Event()

    def tick() -> None:
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    t = threading.Thread(target=tick)
    t.start()
    start = time.perf_counter()
    try:
        stickslip.run(scene)
    finally:
        done.set()
        t.join()
    during = [x for x in ticks if x > start + 0.02]
    elapsed = time.perf_counter() - start
    # A thread that cannot get the GIL would not tick at all while Rust runs.
    assert len(during) >= max(3, int(0.3 * elapsed / 0.005)), (len(during), elapsed)


def test_dir_shows_the_api_only() -> None:
    public = {n for n in dir(stickslip) if not n.startswith("_")}
    assert public == set(stickslip.__all__)
    for name in ("Any", "Dict", "Optional", "Union", "Mapping", "np", "os", "warnings",
                 "annotations"):
        assert name not in dir(stickslip), name
    for name in stickslip.__all__:
        assert getattr(stickslip, name) is not None, name
    for name in ("run", "resume", "load", "sweep", "load_sweep", "Interrupted", "MapTable"):
        assert getattr(stickslip, name).__module__ == "stickslip", name
    assert issubclass(stickslip.Interrupted, KeyboardInterrupt)
    assert {n for n in dir(stickslip.mdr) if not n.startswith("_")} == set(stickslip.mdr.__all__)


def test_interrupted_pickles_with_its_result(small_result: stickslip.RunResult) -> None:
    e = stickslip.Interrupted("stopped", result=None, out="out/x")
    again = pickle.loads(pickle.dumps(e))
    assert isinstance(again, stickslip.Interrupted) and str(again) == "stopped"
    assert again.out == "out/x" and again.result is None


def test_check_reports_what_the_cli_prints(fig2_path: Path) -> None:
    scene = stickslip.Scene.load(fig2_path, {"contact.nodes": 200})
    c = scene.check()
    assert set(c) == {
        "name", "verdict", "derived", "cost", "warnings", "scene", "resolution", "output",
        "contact_spring", "edge_layer",
    }
    assert c["resolution"]["nodes"] == [200, 400]
    # fig2's edge layer is half the contact (rho about 0.47): no N is too coarse.
    edge = c["edge_layer"]
    assert 0.4 < edge["rho"] < 0.5 and edge["width_m"] > 1e-5 and edge["nodes_needed"] == 1
    # fig2's output: 13 001 series marks at most, 9 probes, one profile of 200 nodes.
    assert c["output"]["probes"] == 9 and c["output"]["profile_rows"] == 200
    assert 0 < c["output"]["series_rows"] <= 13001 and c["output"]["interval_for_limit_s"] is None
    # The contact spring behind the first-onset estimate: it melts at X about εc·h0 (a
    # compliant 100 nm film; the static contact folds just before the edge reaches εc, since
    # the film's stress peaks below it), F below τmax·πa0².
    spring = c["contact_spring"]
    assert abs(spring["x_melt_m"] / c["derived"]["critical_displacement"] - 1) < 0.05
    assert 0 < spring["f_melt_n"] <= c["derived"]["melting_force"]
    assert c["resolution"]["relative_change"] < 0.01
    assert c["name"] == "fig2" and c["verdict"] == "run"
    assert c["scene"] == scene.to_dict()
    derived = dict(c["derived"])
    assert derived.pop("stamp_travel") > 0
    # The derived numbers are run.json's, bit for bit.
    assert derived == stickslip.run(scene).run_info["derived"]
    cost = c["cost"]
    assert cost["probe_steps"] > 0 and cost["seconds_per_step"] > 0
    assert cost["seconds"] == pytest.approx(cost["steps"] * cost["seconds_per_step"])
    assert cost["probe_pace_seconds"] > 0
    assert "adaptive" in cost["basis"]
    slip = scene.with_overrides({"contact.radius": 20.0}).check()
    assert any(
        w["severity"] == "warning" and w["key"] == "contact.radius" and "usual range" in
        w["message"] for w in slip["warnings"]
    ), slip["warnings"]
    # A viscous film: the drag η·πa0²/h0 and the viscous time η·a0/(h0·G*) join the derived
    # numbers (fig2: a0 = 20 µm, h0 = 100 nm, G* = 1e9 Pa).
    viscous = scene.with_overrides({"lubricant.viscosity": 10.0}).check()["derived"]
    assert viscous["viscous_drag"] == pytest.approx(10.0 * math.pi * 4e-10 / 1e-7)
    assert viscous["viscous_time"] == pytest.approx(10.0 * 2e-5 / (1e-7 * 1e9))
    assert "viscous_drag" not in c["derived"]
    refused = stickslip.Scene.load(
        HARD / "soft_substrate.toml", {"time.scheme": "literal", "contact.nodes": 50}
    ).check()
    assert refused["verdict"] == "refused"
    assert any(w["severity"] == "refusal" for w in refused["warnings"])


def test_first_order_film_from_dict_equals_its_scene_file(fig2_path: Path) -> None:
    """The first-order film's keys through Scene.from_dict: eps_melt resolves to the b3 the
    scene file gives, a run is the CLI scene's, check() reports the thresholds, and giving both
    keys (or a melting strain below eps_c) is a SceneError naming the key."""
    fo_file = stickslip.Scene.load(SCENES / "fig2_first_order.toml", SMALL)
    d = stickslip.Scene.load(fig2_path).to_dict(resolved=False)
    d["lubricant"]["eps_melt"] = fo_file.to_dict(resolved=False)["lubricant"]["eps_melt"]
    d["name"] = "fig2_first_order"
    fo_dict = stickslip.Scene.from_dict(d).with_overrides(SMALL)
    b3 = fo_file.to_dict()["lubricant"]["cubic"]
    assert b3 > 0 and fo_dict.to_dict()["lubricant"]["cubic"] == b3
    # The same b3 given as lubricant.cubic is the same film.
    by_cubic = stickslip.Scene.load(fig2_path, {**SMALL, "lubricant.cubic": b3})
    assert by_cubic.to_dict()["lubricant"] == fo_dict.to_dict()["lubricant"]
    a, b = stickslip.run(fo_file), stickslip.run(fo_dict)
    np.testing.assert_array_equal(a.series["F"], b.series["F"])
    assert a.summary == b.summary
    derived = dict(fo_dict.check()["derived"])
    assert derived["eps_melt"] == pytest.approx(2.2516660498395, rel=1e-12)
    assert derived["hysteresis_width"] > 0 and derived["tau_melt"] > 0
    # b3 = 0 is the paper's film, bit for bit.
    zero = stickslip.run(stickslip.Scene.load(fig2_path, {**SMALL, "lubricant.cubic": 0.0}))
    paper = stickslip.run(stickslip.Scene.load(fig2_path, SMALL))
    np.testing.assert_array_equal(zero.series["F"], paper.series["F"])
    for bad, key in (
        ({"lubricant.cubic": 1e6, "lubricant.eps_melt": 2.0}, "lubricant.eps_melt"),
        ({"lubricant.eps_melt": 1.5}, "lubricant.eps_melt"),
        ({"lubricant.cubic": -1.0}, "lubricant.cubic"),
    ):
        with pytest.raises(stickslip.SceneError) as err:
            stickslip.Scene.load(fig2_path, bad)
        assert err.value.key == key, (bad, err.value.key)


def test_keys_are_the_registry_and_its_defaults_resolve() -> None:
    keys = {k["path"]: k for k in stickslip.keys()}
    assert len(keys) >= 50
    tol = keys["time.tolerance"]
    assert tol["type"] == "real" and tol["default"] == "5e-5" and tol["unit"] == "–"
    assert keys["time.scheme"]["words"] == ["accurate", "literal"]
    assert keys["time.dt_max"]["default"] == "time.end (no cap)"
    assert keys["contact.radius"]["usual"] == (1e-9, 1e-2)
    assert all(k["since"] for k in keys.values())
    # The stated fixed defaults are those a minimal scene resolves to.
    resolved = stickslip.Scene.load(SCENES / "fig2.toml").to_dict()
    assert resolved["time"]["tolerance"] == float(tol["default"])
    assert resolved["output"]["event_recovery"] == float(keys["output.event_recovery"]["default"])


def test_verify_gives_every_quantity_with_its_error() -> None:
    scene = stickslip.Scene.load(
        SCENES / "fig2.toml",
        {"contact.nodes": 50, "time.end": 8e-4, "output.profile_times": [8e-4]},
    )
    v = stickslip.verify(scene, rtol=0.5)
    assert len(v["levels"]) == 5 and v["rtol"] == 0.5
    q = {x["name"]: x for x in v["quantities"]}
    onset = q["t_first_onset"]
    assert onset["verdict"] == "within" and onset["uncertainty"] >= 0
    # The default, edge-graded grid: the onset converges at second order in N.
    assert onset["space"]["order_theoretical"] == 2.0
    assert q["regime"]["text"] == "stick_slip"
    with pytest.raises(ValueError, match="rtol = 0 is invalid"):
        stickslip.verify(scene, rtol=0.0)
    with pytest.raises(TypeError, match="rtol"):
        stickslip.verify(scene, rtol="tight")


def test_verify_target_finds_the_cheapest_resolution_within_it() -> None:
    # fig2 on the graded grid to 1e-6 relative: the pair found, applied to the scene, puts the
    # first onset within the target of a much finer run.
    scene = stickslip.Scene.load(SCENES / "fig2.toml", {"contact.grid": "graded"})
    t = stickslip.verify(scene, target=1e-6)
    c = t["choice"]
    assert c is not None and t["target"] == 1e-6
    assert [p["ladder"] for p in t["probes"]][0] == "space"
    assert t["probes"][-1]["ladder"] == "chosen"
    first = {"time.max_events": 1, "output.probe_radii": [], "output.series_interval": 1e-5}
    chosen = scene.with_overrides({**first, "contact.nodes": c["nodes"], "time.tolerance": c["tolerance"]})
    fine = scene.with_overrides({**first, "contact.nodes": 1600, "time.tolerance": 5e-9})
    onset = stickslip.run(chosen).events["t_onset"][0]
    reference = stickslip.run(fine).events["t_onset"][0]
    assert abs(onset - reference) <= 1e-6 * reference
    with pytest.raises(ValueError, match="--target = 0"):
        stickslip.verify(scene, target=0.0)
    with pytest.raises(TypeError, match="target"):
        stickslip.verify(scene, target="fine")
