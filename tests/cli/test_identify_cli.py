"""``lagrangian identify``: a CSV record of a pendulum's swing fitted from the command line."""

import json

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR
from scipy.integrate import solve_ivp

from lagrangian.cli.main import main

PENDULUM = str(EXAMPLES_DIR / "simple_pendulum.toml")


@pytest.fixture(scope="module")
def swing(tmp_path_factory):
    """A swing of l = 0.5 m by SciPy (θ̈ = −(g/l) sin θ), θ with noise 1e-3, as a CSV file."""
    t = np.linspace(0.0, 3.0, 151)
    sol = solve_ivp(lambda _, y: [y[1], -9.81 / 0.5 * np.sin(y[0])], (0, 3), [1.0, 0.0], t_eval=t, rtol=1e-12,
                    atol=1e-12)
    theta = sol.y[0] + np.random.default_rng(7).normal(scale=1e-3, size=len(t))
    path = tmp_path_factory.mktemp("swing") / "swing.csv"
    path.write_text("# theta measured\nt,theta\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(t, theta, strict=True)))
    return path


def test_identify_prints_the_estimate_and_its_standard_error(swing, capsys):
    assert main(["identify", PENDULUM, str(swing), "--fit", "l", "--guess", "l=0.4", "--segments", "1"]) == 0
    out = capsys.readouterr().out
    assert "(shooting): converged" in out and "l " in out


def test_identify_writes_its_json_document(swing, tmp_path):
    target = tmp_path / "fit.json"
    assert main(["identify", PENDULUM, str(swing), "--fit", "l", "--json", "-o", str(target)]) == 0
    doc = json.loads(target.read_text())
    assert doc["schema"] == "lagrangian.identify/1" and doc["route"] == "shooting"
    assert abs(doc["estimates"]["l"] - 0.5) < 3 * doc["std"]["l"]


@pytest.mark.parametrize("args, message", [
    (["--fit", "nope"], "`nope` is not a parameter"),
    (["--fit", "l", "--guess", "l=abc"], "not a plain decimal number"),
    (["--fit", "l", "--route", "regressor"], "not linear in l"),
    (["--fit", "l", "--columns", "t,phi"], "no column `phi`"),
])
def test_identify_refuses_bad_requests_with_exit_code_2(swing, capsys, args, message):
    assert main(["identify", PENDULUM, str(swing), *args]) == 2
    assert message in capsys.readouterr().err


def test_identify_refuses_a_file_with_a_missing_value(tmp_path, capsys):
    path = tmp_path / "gap.csv"
    path.write_text("t,theta\n0,1\n0.1,0.9\n0.2,\n0.3,0.5\n0.4,0.3\n0.5,0.1\n")
    assert main(["identify", PENDULUM, str(path), "--fit", "l"]) == 2
    assert "holds nan at row 3" in capsys.readouterr().err


def test_a_file_written_by_simulate_is_read_whole_and_a_misnamed_column_still_refused(tmp_path, capsys):
    # `simulate -o` writes T, U, E and the reaction R_to_P besides t, θ, θ̇, θ̈: outputs of the model, set aside.
    run = tmp_path / "run.csv"
    assert main(["simulate", PENDULUM, "--t-end", "2", "--n-out", "101", "--set", "l=0.6", "-o", str(run)]) == 0
    lines = [line for line in run.read_text().splitlines() if not line.startswith("#")]
    assert "E" in lines[0].split(",") and "R_to_P_x0" in lines[0]
    capsys.readouterr()
    assert main(["identify", PENDULUM, str(run), "--fit", "l", "--guess", "l=0.5", "--segments", "1",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["estimates"]["l"] == pytest.approx(0.6, rel=1e-6)
    (tmp_path / "typo.csv").write_text("\n".join([lines[0].replace("theta_dot", "thetadot"), *lines[1:]]) + "\n")
    assert main(["identify", PENDULUM, str(tmp_path / "typo.csv"), "--fit", "l"]) == 2
    assert "`thetadot`" in capsys.readouterr().err
