"""``lagrangian optimize``, called in-process: summary, JSON document, trajectory file, plots, exit codes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("casadi")

from lagrangian_test_support import EXAMPLES_DIR

from lagrangian.cli.main import main

SLEW = str(EXAMPLES_DIR / "optimal" / "satellite_slew.toml")
PENDULUM = str(EXAMPLES_DIR / "optimal" / "pendulum_swing_up.toml")


def test_the_summary_says_status_objective_and_replay(capsys):
    assert main(["optimize", SLEW, "--nodes", "21"]) == 0
    out = capsys.readouterr().out
    assert "status: optimal" in out and "objective J = 8.944" in out
    assert "replay (simulate: DOP853" in out and "free final time" in out


def test_json_document_and_trajectory_file(capsys, tmp_path):
    target = tmp_path / "slew.csv"
    assert main(["optimize", SLEW, "--nodes", "21", "--json", "-o", str(target)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["schema"] == "lagrangian.optimize/1" and doc["status"] == "optimal"
    assert doc["objective"] == pytest.approx(2 * np.sqrt(20), rel=1e-6) and doc["nodes"] == 21
    assert len(doc["columns"]["tau"]) == 2 * 21 - 1 and doc["replay"]["within"]
    table = np.loadtxt(target, delimiter=",", comments="#", skiprows=5)
    header = next(line for line in target.read_text().splitlines() if not line.startswith("#")).split(",")
    assert "tau" in header and table.shape == (41, len(header))
    assert table[-1, header.index("theta")] == pytest.approx(1.0)


def test_options_override_the_file(capsys):
    assert main(["optimize", SLEW, "--nodes", "25", "--method", "trapezoidal", "--set", "Ib=20", "--json",
                 "--no-verify"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["method"] == "trapezoidal" and doc["nodes"] == 25 and doc["parameters"]["Ib"] == 20
    assert doc["replay"] is None
    # T* = 2 √(Θ Ib / τmax), to the accuracy of the trapezoidal rule on a bang-bang input
    assert doc["t_end"] == pytest.approx(2 * np.sqrt(1.0 * 20 / 0.5), rel=5e-3)


@pytest.mark.slow
def test_plots_include_the_inputs(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    folder = tmp_path / "figs"
    assert main(["optimize", SLEW, "--nodes", "15", "--plot", str(folder), "--animation", "none"]) == 0
    assert (folder / "inputs.png").stat().st_size > 0 and (folder / "time_series.png").exists()


def test_a_problem_mistake_exits_2_with_the_file_and_line(capsys, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(Path(PENDULUM).read_text().replace("tau = [-3, 3]", "tau = [3, -3]")
                   .replace("../torque_pendulum.toml", str(EXAMPLES_DIR / "torque_pendulum.toml")), encoding="utf-8")
    assert main(["optimize", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:" in err and "bounds of `tau` are reversed" in err and "tip:" in err


def test_no_optimum_exits_4_and_keeps_the_last_iterate(capsys, tmp_path):
    hopeless = tmp_path / "hopeless.toml"
    hopeless.write_text(Path(PENDULUM).read_text().replace("t_end = 5.0", "t_end = 1.0")
                        .replace("tau = [-3, 3]", "tau = [-0.5, 0.5]")
                        .replace("../torque_pendulum.toml", str(EXAMPLES_DIR / "torque_pendulum.toml")),
                        encoding="utf-8")
    target = tmp_path / "last.npz"
    assert main(["optimize", str(hopeless), "--nodes", "20", "-o", str(target)]) == 4
    err = capsys.readouterr().err
    assert "No optimal motion was found" in err and "infeasible" in err
    with np.load(target) as data:
        assert json.loads(str(data["metadata"]))["status"] == "infeasible"


@pytest.mark.slow
def test_ctrl_c_writes_the_solvers_last_iterate_and_exits_130(tmp_path):
    import os
    import subprocess
    import sys

    from lagrangian_test_support import interrupt_when_started

    from lagrangian.numerics import _compile

    src = str(Path(_compile.__file__).resolve().parents[2])
    env = {**os.environ, "PYTHONPATH": src, "LAGRANGIAN_CACHE": str(tmp_path / "cache")}
    out = tmp_path / "last.npz"
    command = [sys.executable, "-m", "lagrangian.cli.main", "optimize",
               str(EXAMPLES_DIR / "optimal" / "acrobot_swing_up.toml"), "--nodes", "400", "--verbose", "-o", str(out)]
    seen = interrupt_when_started(command, env, b"iter", delay=0.3)  # IPOPT's iterations have started
    assert isinstance(seen.process, subprocess.CompletedProcess)
    assert seen.process.returncode == 130, seen.process.stderr[-2000:]
    assert "status: interrupted" in seen.process.stderr
    assert f"wrote the part computed so far to {out}" in seen.process.stderr
    with np.load(out) as data:
        assert json.loads(str(data["metadata"]))["status"] == "interrupted"
