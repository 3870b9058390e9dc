"""Ctrl-C stops a long compiled run within a second.

Each run is a real process sent SIGINT once its progress bar shows the C loop running:
it must exit 130 with one line and no traceback, and with ``-o`` keep the part computed
so far in the file, its header saying "interrupted ... (partial)".
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from lagrangian_test_support import interrupt_when_started

from lagrangian.numerics import _compile

SRC = str(Path(_compile.__file__).resolve().parents[2])


def interrupt(tmp_path: Path, *argv: str) -> tuple[subprocess.CompletedProcess, float]:
    """Run ``simulate`` with ``argv``, send SIGINT ~1 s after the integration started; (result, seconds to stop)."""
    env = {**os.environ, "PYTHONPATH": SRC, "LAGRANGIAN_CACHE": str(tmp_path / "cache")}
    command = [sys.executable, "-m", "lagrangian.cli.main", "simulate", "zoo:planar_chain:2", "--t-end", "1e6",
               "--progress", *argv]
    seen = interrupt_when_started(command, env, b"[")  # the progress bar: the C loop runs
    return seen.process, seen.stopped


def last_line(stderr: str) -> str:
    return stderr.replace("\r", "\n").strip().splitlines()[-1]


@pytest.mark.slow
@pytest.mark.parametrize("method", [["--method", "dop853"], ["--method", "gauss-legendre", "--dt", "0.01"]],
                         ids=["dop853", "gauss-legendre"])
def test_ctrl_c_keeps_the_part_computed_so_far(tmp_path, method):
    out = tmp_path / "traj.npz"
    result, stopped = interrupt(tmp_path, *method, "-o", str(out))
    assert result.returncode == 130, result.stderr
    assert stopped < 3.0
    assert "Traceback" not in result.stderr
    assert last_line(result.stderr).startswith("lagrangian: interrupted at t = ")
    assert f"wrote the part computed so far to {out} (marked partial)" in result.stderr
    data = np.load(out)
    meta = json.loads(str(data["metadata"]))
    assert meta["status"].startswith("interrupted at t = ") and meta["status"].endswith("(partial)")
    assert 0 < data["t"][-1] < 1e6 and np.all(np.isfinite(data["q"]))


@pytest.mark.slow
def test_ctrl_c_without_output_file_prints_one_line(tmp_path):
    result, stopped = interrupt(tmp_path)
    assert result.returncode == 130, result.stderr
    assert stopped < 3.0
    assert "Traceback" not in result.stderr
    assert last_line(result.stderr).startswith("lagrangian: interrupted at t = ")
    assert result.stdout == ""


@pytest.mark.slow
def test_ctrl_c_in_a_scipy_method_prints_one_line_and_leaves_the_old_file(tmp_path):
    out = tmp_path / "traj.csv"
    out.write_text("previous\n")
    result, stopped = interrupt(tmp_path, "--method", "RK45", "-o", str(out))
    assert result.returncode == 130, result.stderr
    assert stopped < 3.0
    assert "Traceback" not in result.stderr
    line = last_line(result.stderr)
    assert line.startswith("lagrangian: interrupted at t = ") and line.endswith("; nothing written")
    assert out.read_text() == "previous\n"
