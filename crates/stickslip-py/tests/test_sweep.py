"""stickslip.sweep: a small friction map from a dict, a file and a Scene, as map.csv's columns,
the same numbers as `stickslip sweep run`; bad sweeps raise SweepError."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest

import stickslip
from conftest import SCENES, read_csv, same_bits

SWEEP_TOML = """\
name = "tiny"
scene = "{scene}"

[set]
"contact.nodes" = 20
"time.end" = 6e-4
"time.max_events" = 2
"output.profile_times" = [6e-4]

[[axis]]
key = "drive.velocity"
values = [1e-3, 3e-3]

[[axis]]
key = "temperature.A0"
range = {{ from = -1e5, to = 1.5e6, count = 3, scale = "linear" }}
"""

COLUMNS = [
    "point", "drive.velocity", "temperature.A0", "status", "regime", "n_events",
    "t_first_onset", "period_last", "x_period_last", "f_peak_first", "f_peak_last", "f_mean",
    "recovery", "melted_time_fraction", "wall_s", "message", "steady", "level",
    "stamp_regime", "n_slips", "slip_interval_median", "melting_interval_median",
    "energy_per_cycle",
]


def sweep_dict(scene) -> dict:
    return {
        "name": "tiny",
        "scene": scene,
        "set": {"contact.nodes": 20, "time.end": 6e-4, "time.max_events": 2,
                "output.profile_times": [6e-4]},
        "axis": [
            {"key": "drive.velocity", "values": [1e-3, 3e-3]},
            {"key": "temperature.A0", "range": {"from": -1e5, "to": 1.5e6, "count": 3}},
        ],
    }


@pytest.fixture(scope="module")
def sweep_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("sweep")
    path = d / "tiny.toml"
    path.write_text(SWEEP_TOML.format(scene=(SCENES / "rigid.toml").as_posix()))
    return path


@pytest.fixture(scope="module")
def table(sweep_file: Path) -> dict:
    return stickslip.sweep(sweep_file, jobs=2)


def test_columns_and_types(table: dict) -> None:
    assert list(table) == COLUMNS
    assert table["point"].dtype == np.int64 and list(table["point"]) == list(range(6))
    assert table["n_events"].dtype == np.int64
    assert list(table["drive.velocity"]) == [1e-3] * 3 + [3e-3] * 3
    assert list(table["temperature.A0"]) == [-1e5, 7e5, 1.5e6] * 2
    assert table["status"].dtype == object and set(table["status"]) == {"ok"}
    assert set(table["regime"]) <= {"sliding", "no_melting", "transient", "stick_slip",
                                    "partial", "smooth"}
    # A0 < 0: complete melting, sliding.
    assert table["regime"][0] == "sliding"
    for name in ("t_first_onset", "f_mean", "wall_s"):
        assert table[name].dtype == np.float64
    assert all(isinstance(m, str) for m in table["message"])
    assert table["n_slips"].dtype == np.int64
    assert set(table["stamp_regime"]) <= {"stick_slip", "steady_sliding", "creep", "transient"}
    # A0 < 0: a liquid film under the rigid drive, F = 0 throughout: no slip, steady sliding.
    assert table["stamp_regime"][0] == "steady_sliding" and table["n_slips"][0] == 0
    for name in ("slip_interval_median", "melting_interval_median"):
        assert table[name].dtype == np.float64
    # The energy dissipated over the last complete cycle: a number where two or more events
    # give one, none (NaN) where there is no complete cycle.
    energy = table["energy_per_cycle"]
    cycles = table["n_events"] >= 2
    assert cycles.any() and np.all(energy[cycles] > 0)
    assert np.all(np.isnan(energy[~cycles]))


def test_same_numbers_as_the_cli(table: dict, sweep_file: Path, cli: Path, tmp_path: Path) -> None:
    out = tmp_path / "map"
    subprocess.run(
        [str(cli), "sweep", "run", str(sweep_file), "--out", str(out), "--jobs", "1", "--quiet"],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    text = (out / "map.csv").read_text().splitlines()
    assert text[0].split(",") == COLUMNS
    rows = [line.split(",") for line in text[1:]]
    for j, name in enumerate(COLUMNS):
        cells = [r[j] for r in rows]
        if name in ("status", "regime", "message", "stamp_regime"):
            assert list(table[name]) == cells, name
        elif name == "steady":
            assert table[name].dtype == np.bool_
            assert [str(v).lower() for v in table[name]] == cells, name
        elif name in ("level", "n_slips"):
            assert table[name].dtype == np.int64
            assert [str(v) for v in table[name]] == cells, name
        elif name != "wall_s":
            written = np.array([float(c) if c else np.nan for c in cells])
            assert same_bits(table[name].astype(np.float64), written), name


def test_dict_and_scene_object_give_the_same_map(table: dict, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(SCENES.parent.parent)  # a dict's scene path is relative to the cwd
    from_dict = stickslip.sweep(sweep_dict("validation/scenes/rigid.toml"), jobs=1)
    from_scene = stickslip.sweep(sweep_dict(stickslip.Scene.load(SCENES / "rigid.toml")))
    for other in (from_dict, from_scene):
        assert list(other) == COLUMNS
        for name in COLUMNS:
            if name != "wall_s":
                assert np.array_equal(other[name], table[name]) or same_bits(
                    other[name], table[name]
                ), name


def test_out_directory_is_kept_and_resumed(sweep_file: Path, tmp_path: Path) -> None:
    out = tmp_path / "kept"
    first = stickslip.sweep(sweep_file, jobs=1, out=out)
    assert (out / "map.csv").is_file() and len(list((out / "points").iterdir())) == 6
    again = stickslip.sweep(sweep_file, jobs=1, out=out)  # every point skipped
    assert np.array_equal(again["wall_s"], first["wall_s"])
    other = sweep_dict(stickslip.Scene.load(SCENES / "rigid.toml"))
    other["axis"][0]["values"] = [2e-3]
    with pytest.raises(OSError, match="another sweep.*force=True"):
        stickslip.sweep(other, out=out)
    assert len(stickslip.sweep(other, out=out, force=True)["point"]) == 3


def test_bad_sweeps() -> None:
    scene = stickslip.Scene.load(SCENES / "rigid.toml")
    bad = sweep_dict(scene)
    bad["axis"][0]["key"] = "drive.speed"
    with pytest.raises(stickslip.SweepError) as e:
        stickslip.sweep(bad)
    assert e.value.key == "axis[0].key" and isinstance(e.value, ValueError)
    bad = sweep_dict(scene)
    bad["axis"][1]["range"]["count"] = 0
    with pytest.raises(stickslip.SweepError, match="count"):
        stickslip.sweep(bad)
    bad = sweep_dict(scene)
    bad["axes"] = bad.pop("axis")
    with pytest.raises(stickslip.SweepError) as e:
        stickslip.sweep(bad)
    assert e.value.key == "axes"
    bad = sweep_dict(scene)
    bad["set"]["contact.nodes"] = 0
    with pytest.raises(stickslip.SceneError) as e:
        stickslip.sweep(bad)
    assert e.value.key == "contact.nodes"
    with pytest.raises(stickslip.SweepError):
        stickslip.sweep("does/not/exist.toml")
    with pytest.raises(ValueError):
        stickslip.sweep(sweep_dict(scene), jobs=0)
    # [refine]: bad values raise a SweepError (a ValueError) naming the key.
    for refine, key in [
        ({"levels": -1}, "refine.levels"),
        ({"levels": 1.5}, "refine.levels"),
        ({"levels": 2, "on": "status"}, "refine.on"),
        ({"levels": 2, "on": "recovery"}, "refine.threshold"),
        ({"levels": 2, "on": "recovery", "threshold": 0}, "refine.threshold"),
        ({"levels": 2, "depth": 1}, "refine.depth"),
        ({"levels": 60}, "refine.levels"),
    ]:
        bad = sweep_dict(scene)
        bad["refine"] = refine
        with pytest.raises(stickslip.SweepError) as e:
            stickslip.sweep(bad)
        assert e.value.key == key and isinstance(e.value, ValueError), (refine, e.value)


def test_a_refined_sweep_has_levels() -> None:
    d = sweep_dict((SCENES / "rigid.toml").as_posix())
    d["refine"] = {"levels": 2}
    table = stickslip.sweep(d, jobs=2)
    assert table.complete and table.points == len(table["point"])
    assert table["level"].dtype == np.int64 and max(table["level"]) >= 1
    # Points are numbered in the finest grid (2 → 5 and 3 → 9 values), in point order.
    assert list(table["point"]) == sorted(table["point"]) and max(table["point"]) < 45
    assert set(table["drive.velocity"][table["level"] == 0]) == {1e-3, 3e-3}


def test_spot_checks_rerun_points_at_a_finer_resolution(tmp_path: Path) -> None:
    d = sweep_dict((SCENES / "rigid.toml").as_posix())
    d["verify"] = {"points": 2}
    table = stickslip.sweep(d, jobs=2, out=tmp_path / "spot")
    spot = table.spot_checks
    assert spot is not None and spot["sampled"] == 2 and spot["checked"] == len(spot["checks"])
    regimes = dict(zip(table["point"], table["regime"]))
    for check in spot["checks"]:
        assert [r["refinement"] for r in check["runs"]] == ["2N", "tolerance/10"]
        assert check["regime"] == regimes[check["point"]]
        assert check["changed"] == any(r["summary"]["regime"] != check["regime"] for r in check["runs"])
    # load_sweep reads them back; a sweep without [verify] has none.
    assert stickslip.load_sweep(tmp_path / "spot").spot_checks == spot
    assert stickslip.sweep(sweep_dict((SCENES / "rigid.toml").as_posix()), jobs=2).spot_checks is None
    with pytest.raises(stickslip.SweepError, match="verify.sample"):
        stickslip.sweep({**d, "verify": {"sample": 1.5}})


def test_argument_errors_are_type_and_value_errors(sweep_file: Path) -> None:
    with pytest.raises(ValueError, match=r"jobs = -1 is invalid; allowed: an int >= 1"):
        stickslip.sweep(sweep_file, jobs=-1)
    with pytest.raises(ValueError, match="jobs = 0"):
        stickslip.sweep(sweep_file, jobs=0)
    for bad in (True, 1.5, "2"):
        with pytest.raises(TypeError, match="jobs = .* is invalid"):
            stickslip.sweep(sweep_file, jobs=bad)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="force = 1 .* allowed: True or False"):
        stickslip.sweep(sweep_file, force=1)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="out = 3 is invalid"):
        stickslip.sweep(sweep_file, out=3)  # type: ignore[arg-type]


def test_sweep_file_errors_carry_the_key_and_the_line(tmp_path: Path) -> None:
    text = SWEEP_TOML.format(scene=(SCENES / "rigid.toml").as_posix()).replace(
        "count = 3", "count = 3.0"
    )
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(stickslip.SweepError) as e:
        stickslip.sweep(path)
    assert e.value.key == "axis[1].range.count" and e.value.line == 16, e.value
    assert "an integer" in str(e.value)
    bad = sweep_dict(stickslip.Scene.load(SCENES / "rigid.toml"))
    bad["regime"] = {"stick_slip": 0.8}
    with pytest.raises(stickslip.SweepError) as e:
        stickslip.sweep(bad)
    assert e.value.key == "regime.stick_slip" and e.value.line is None
    bad = sweep_dict(stickslip.Scene.load(SCENES / "rigid.toml"))
    bad["axis"][0] = {"key": "contact.nodes", "range": {"from": 10, "to": 11, "count": 5}}
    with pytest.raises(stickslip.SweepError, match="gives 10 twice"):
        stickslip.sweep(bad)


def test_a_record_of_another_sweep_is_refused(sweep_file: Path, tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    stickslip.sweep(sweep_file, jobs=1, out=a)
    other = sweep_dict(stickslip.Scene.load(SCENES / "rigid.toml"))
    other["axis"][0]["values"] = [2e-3, 4e-3]
    stickslip.sweep(other, jobs=1, out=b)
    # A's record lands among B's (and B's shard tables are gone): B's rows must not be
    # labelled with A's values; the record is refused by name.
    (b / "points" / "0000004.json").write_bytes((a / "points" / "0000004.json").read_bytes())
    for table in (b / "shards").iterdir():
        table.unlink()
    with pytest.raises(OSError, match=r"0000004\.json is not a result of this sweep.*force=True"):
        stickslip.sweep(other, jobs=1, out=b)


def test_points_of_another_build_are_recomputed_with_a_warning(
    sweep_file: Path, tmp_path: Path
) -> None:
    out = tmp_path / "built"
    first = stickslip.sweep(sweep_file, jobs=1, out=out)
    sweep_json = out / "sweep.json"
    build = __import__("json").loads(sweep_json.read_text())["build"]
    old = "0" * 16
    for f in [sweep_json, *(out / "points").iterdir(), *(out / "shards").iterdir()]:
        f.write_text(f.read_text().replace(build, old))
        f.rename(f.with_name(f.name.replace(build, old)))
    with pytest.warns(RuntimeWarning, match=f"6 points recomputed: computed by build {old}"):
        again = stickslip.sweep(sweep_file, jobs=1, out=out)
    for name in COLUMNS:
        if name != "wall_s":
            assert np.array_equal(again[name], first[name]) or same_bits(
                again[name], first[name]
            ), name
