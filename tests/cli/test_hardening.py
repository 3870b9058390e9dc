"""The command line under hostile conditions.

A full device on standard output, Ctrl-C while the package is still importing, an output
folder that cannot be written, an event written as a vector: each ends in one line and a
non-zero exit code, never a traceback, and a bad destination is said before any work.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from lagrangian.cli import _simulate
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
PENDULUM = str(ROOT / "examples" / "simple_pendulum.toml")


def _cli(*argv: str, stdout=subprocess.PIPE, env: dict | None = None) -> subprocess.CompletedProcess:
    environment = dict(os.environ, PYTHONPATH=str(ROOT / "src"), **(env or {}))
    return subprocess.run([sys.executable, "-c", "from lagrangian.cli.main import entrypoint; entrypoint()", *argv],
                          stdout=stdout, stderr=subprocess.PIPE, text=True, env=environment, timeout=120)


@pytest.mark.slow
@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
@pytest.mark.parametrize("argv", [["derive", PENDULUM], ["derive", "--json", PENDULUM]])
def test_a_full_device_on_standard_output_is_one_line(argv: list[str]) -> None:
    with open("/dev/full", "w") as full:
        run = _cli(*argv, stdout=full)
    assert run.returncode == 3, run.stderr
    assert "Traceback" not in run.stderr and "Exception ignored" not in run.stderr
    assert "standard output" in run.stderr and "No space left" in run.stderr


@pytest.mark.slow
def test_ctrl_c_while_importing_exits_130_without_a_traceback(tmp_path: Path) -> None:
    # A stand-in for SymPy that receives SIGINT while it loads: the real one takes seconds to import.
    fake = tmp_path / "sympy"
    fake.mkdir()
    (fake / "__init__.py").write_text("import os, signal, time\nos.kill(os.getpid(), signal.SIGINT)\ntime.sleep(5)\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), str(ROOT / "src")]))
    run = subprocess.run([sys.executable, "-c", "from lagrangian.cli.main import entrypoint; entrypoint()",
                          "derive", PENDULUM], capture_output=True, text=True, env=env, timeout=60)
    assert run.returncode == 130, run.stderr
    assert run.stderr == "lagrangian: interrupted\n"


def _unwritable(tmp_path: Path) -> Path:
    """A folder this process cannot create files in (root ignores permissions: /proc then)."""
    if os.geteuid() == 0:
        return Path("/proc")
    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    return folder


def test_simulate_into_a_read_only_folder_fails_before_the_run(tmp_path: Path, monkeypatch, capsys) -> None:
    def never(*args, **kwargs):
        raise AssertionError("the simulation ran although its output cannot be written")

    monkeypatch.setattr(_simulate, "simulate", never)
    target = _unwritable(tmp_path) / "traj.csv"
    assert main(["simulate", PENDULUM, "--t-end", "1", "-o", str(target)]) == 3
    err = capsys.readouterr().err
    assert "not writable" in err and "nothing was run" in err and not target.exists()


def test_derive_into_a_read_only_folder_fails_before_the_work(tmp_path: Path, monkeypatch, capsys) -> None:
    import lagrangian.cli._derive as derive_command

    monkeypatch.setattr(derive_command, "derive", lambda *a, **k: pytest.fail("derived before checking -o"))
    target = _unwritable(tmp_path) / "eom.txt"
    assert main(["derive", PENDULUM, "-o", str(target)]) == 3
    assert "not writable" in capsys.readouterr().err


def test_an_event_that_is_a_vector_is_named_as_such(capsys) -> None:
    assert main(["simulate", PENDULUM, "--t-end", "0.1", "--event", "R0.x"]) == 2
    err = capsys.readouterr().err
    assert "is a vector" in err and "unknown frame" not in err and "scalar" in err


def test_equilibria_of_a_model_with_no_coordinate_left_to_solve(capsys) -> None:
    # Found by tools/fuzz.py: the block held on its incline by friction has every coordinate "any";
    # SymEngine's Lambdify refuses zero arguments and the residual crashed with a TypeError.
    assert main(["equilibria", str(ROOT / "examples" / "block_on_incline.toml")]) == 0
    assert "x any" in capsys.readouterr().out
