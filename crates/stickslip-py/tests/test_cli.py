"""The ``stickslip`` command that ``pip install`` puts beside the interpreter: the Rust
binary's program (the same library, run in the Python process), so its output, exit statuses
and Ctrl-C handling equal the binary's (``STICKSLIP_BIN``)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import List, Sequence

import pytest

from conftest import SCENES

SCRIPT = Path(sys.executable).parent / "stickslip"

# fig2, short: two profile times, a few events, a fraction of a second.
SHORT = [
    "--set",
    "contact.nodes=50",
    "--set",
    "time.end=2e-4",
    "--set",
    "output.profile_times=[2e-4]",
    "--quiet",
]


def call(cmd: Sequence[object], **kw: object) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(c) for c in cmd],
        capture_output=True,
        text=True,
        timeout=300,
        stdin=subprocess.DEVNULL,
        **kw,  # type: ignore[arg-type]
    )


def both(cli: Path, args: Sequence[object]) -> List[subprocess.CompletedProcess]:
    """The binary's result and the script's for the same arguments."""
    return [call([cli, *args]), call([SCRIPT, *args])]


def test_the_command_is_installed_beside_the_interpreter() -> None:
    assert SCRIPT.is_file(), SCRIPT
    assert os.access(SCRIPT, os.X_OK), SCRIPT


@pytest.mark.parametrize(
    "args",
    [
        ["--version"],
        ["--help"],
        ["keys"],
        ["keys", "--markdown"],
        ["run", "--help"],
        ["sweep", "--help"],
    ],
)
def test_fixed_output_equals_the_binarys(cli: Path, args: List[str]) -> None:
    rust, py = both(cli, args)
    assert rust.returncode == 0, rust.stderr
    assert (py.returncode, py.stdout, py.stderr) == (rust.returncode, rust.stdout, rust.stderr)


def test_python_dash_m_runs_the_same_program(cli: Path) -> None:
    rust = call([cli, "--version"])
    py = call([sys.executable, "-m", "stickslip", "--version"])
    assert (py.returncode, py.stdout) == (0, rust.stdout), py.stderr


def test_check_equals_the_binarys_but_for_timings(cli: Path, fig2_path: Path) -> None:
    def untimed(text: str) -> List[str]:
        # The cost estimate's lines carry the measured pace, and so does the output's
        # expected row count (a row per step at the timed probe's pace is one of its ends).
        return [
            line
            for line in text.splitlines()
            if "seconds" not in line and not line.startswith("series_rows")
        ]

    rust, py = both(cli, ["check", fig2_path])
    assert rust.returncode == py.returncode == 0, (rust.stderr, py.stderr)
    assert untimed(py.stdout) == untimed(rust.stdout)
    assert len(untimed(py.stdout)) > 20
    assert py.stderr == rust.stderr


@pytest.mark.parametrize(
    "args",
    [
        [],
        ["run"],
        ["frobnicate"],
        ["check", "no/such/scene.toml"],
        ["check", SCENES / "fig2.toml", "--set", "contact.nodes=-3"],
        ["check", SCENES / "fig2.toml", "--set", "no.such_key=1"],
        ["run", SCENES / "fig2.toml", "--out", "x", "--checkpoint-every", "-1"],
        ["resume", "no/such/dir"],
    ],
)
def test_bad_input_exits_2_with_the_binarys_message(
    cli: Path, args: List[object], tmp_path: Path
) -> None:
    rust, py = (call([c, *args], cwd=tmp_path) for c in (cli, SCRIPT))
    assert rust.returncode == 2, (rust.stdout, rust.stderr)
    assert (py.returncode, py.stdout, py.stderr) == (rust.returncode, rust.stdout, rust.stderr)


def test_run_output_is_the_binarys_bit_for_bit(cli: Path, fig2_path: Path, tmp_path: Path) -> None:
    dirs = {who: tmp_path / who for who in ("rust", "py")}
    rust = call([cli, "run", fig2_path, "--out", dirs["rust"], *SHORT])
    py = call([SCRIPT, "run", fig2_path, "--out", dirs["py"], *SHORT])
    assert rust.returncode == py.returncode == 0, (rust.stderr, py.stderr)
    # The report line names the directory and the wall time; the summary line is exact.
    assert [line for line in py.stdout.splitlines() if line.startswith("summary:")] == [
        line for line in rust.stdout.splitlines() if line.startswith("summary:")
    ]
    for name in ("series.csv", "events.csv", "profiles.csv", "probes.csv"):
        assert (dirs["py"] / name).read_bytes() == (dirs["rust"] / name).read_bytes(), name
    info = {who: json.loads((d / "run.json").read_text()) for who, d in dirs.items()}
    assert info["py"]["summary"] == info["rust"]["summary"]
    assert info["py"]["status"] == info["rust"]["status"] == "ok"
    # A second run into the same directory is refused, as by the binary.
    rust, py = (call([c, "run", fig2_path, "--out", dirs["rust"], *SHORT]) for c in (cli, SCRIPT))
    assert rust.returncode == py.returncode == 2
    assert py.stderr == rust.stderr


def test_sweep_slurm_scripts_start_the_command_not_python(tmp_path: Path) -> None:
    sweep = tmp_path / "tiny.toml"
    sweep.write_text(
        f'name = "tiny"\nscene = "{SCENES / "fig2.toml"}"\n'
        '[set]\n"contact.nodes" = 20\n"time.end" = 1e-5\n"output.profile_times" = [1e-5]\n'
        '[[axis]]\nkey = "drive.velocity"\nvalues = [1.0, 2.0]\n'
    )
    out = tmp_path / "map"
    done = call([SCRIPT, "sweep", "slurm", sweep, "--out", out, "--tasks", "2"])
    assert done.returncode == 0, done.stderr
    text = (out / "sweep.sbatch").read_text()
    # The job runs the command itself; the interpreter (this process's executable) alone
    # would not know what to do with the arguments.
    assert str(SCRIPT) in text, text
    assert str(Path(sys.executable).resolve()) not in text, text


def run_json(dir: Path) -> dict:
    try:
        return json.loads((dir / "run.json").read_text())
    except (OSError, ValueError):
        return {}


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_sigint_checkpoints_exits_130_and_resume_finishes(
    cli: Path, fig2_path: Path, tmp_path: Path, sig: signal.Signals
) -> None:
    # fig2 at N = 200 to 10 ms: about 2 s of the release build on a fast host (to 5 ms it took
    # 0.99 s there and ended just as the signal came, a second after it started); no periodic
    # checkpoints, so the one in the directory comes from the signal.
    long = ["--set", "contact.nodes=200", "--set", "time.end=1e-2", "--quiet"]
    dir = tmp_path / "run"
    child = subprocess.Popen(
        [str(SCRIPT), "run", str(fig2_path), "--out", str(dir), *long, "--checkpoint-every", "0"],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 60
        while run_json(dir).get("status") != "running":
            assert child.poll() is None, child.communicate()
            assert time.monotonic() < deadline, "no run.json with status running"
            time.sleep(0.01)
        time.sleep(0.25)
        assert child.poll() is None, "the run ended before it could be interrupted"
        child.send_signal(sig)
        out, err = child.communicate(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert child.returncode == 130, (out, err)
    assert f"resume with: stickslip resume {dir}" in err, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert run_json(dir)["status"] == "interrupted"
    assert (dir / "checkpoint.cbor").is_file(), list(dir.iterdir())

    resumed = call([SCRIPT, "resume", dir, "--quiet"])
    assert resumed.returncode == 0, resumed.stderr
    assert run_json(dir)["status"] == "ok"
    # The same numbers as the binary's uninterrupted run.
    reference = tmp_path / "reference"
    whole = call([cli, "run", fig2_path, "--out", reference, *long])
    assert whole.returncode == 0, whole.stderr
    for name in ("series.csv", "events.csv", "profiles.csv", "probes.csv"):
        assert (dir / name).read_bytes() == (reference / name).read_bytes(), name
    assert run_json(dir)["summary"] == run_json(reference)["summary"]


def test_a_closed_stdout_is_no_error(cli: Path) -> None:
    # `stickslip keys | head -1`: output nobody reads ends nothing in error, in either.
    for command in (cli, SCRIPT):
        child = subprocess.Popen(
            [str(command), "keys"], stdout=subprocess.PIPE, stderr=subprocess.PIPE
        )
        assert child.stdout is not None and child.stderr is not None
        child.stdout.close()
        err = child.stderr.read()
        child.wait(timeout=60)
        assert (child.returncode, err) == (0, b""), (command, err)


def test_the_python_functions_defaults_are_the_command_lines():
    # One definition of each option's default: the Python keyword's default and the value
    # `stickslip COMMAND --help` states are both the extension's `option_defaults`.
    import inspect
    import re

    import stickslip
    from stickslip import _native

    defaults = _native.option_defaults()
    assert {"verify.rtol", "boundary.scan", "fit.jobs", "run.checkpoint_every"} <= set(defaults)
    functions = {
        "run": stickslip.run,
        "verify": stickslip.verify,
        "boundary": stickslip.boundary,
        "fit": stickslip.fit,
    }
    for name, value in defaults.items():
        command, option = name.split(".")
        assert inspect.signature(functions[command]).parameters[option].default == value, name
        flag = "--" + option.replace("_", "-")
        shown = call([SCRIPT, command, "--help"]).stdout
        # The flag's line and its description's, up to the next option's line.
        found = re.search(
            re.escape(flag) + r"[ <][^\n]*(?:\n(?!\s*-)[^\n]*)*?\[default: ([^\]]+)\]", shown
        )
        assert found, (name, shown)
        text = found.group(1)
        assert (float(text) if isinstance(value, (int, float)) else text) == value, (name, text)
