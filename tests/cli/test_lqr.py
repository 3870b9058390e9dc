"""``lagrangian lqr`` and ``lagrangian simulate --input/--feedback``, called in-process.

The gain the command writes equals python-control's on the A, B it writes; the closed loop it
then runs (``simulate --feedback``) brings the cart-pole back upright; an input from a CSV file
and from an expression gives the motion `simulate` gives in Python.
"""

from __future__ import annotations

import json

import control
import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.cli.main import main

CART_POLE = str(EXAMPLES_DIR / "inverted_pendulum_cart.toml")


def _table(path) -> tuple[list[str], np.ndarray]:
    lines = [line for line in path.read_text().splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    return header, np.array([[float(v) for v in line.split(",")] for line in lines[1:]])


def test_the_written_gain_is_python_controls_and_closes_the_loop(tmp_path, capsys):
    out = tmp_path / "fb.json"
    assert main(["lqr", CART_POLE, "--Q", "theta=10,x=2", "--R", "0.5", "-o", str(out)]) == 0, \
        capsys.readouterr().err
    doc = json.loads(out.read_text())
    assert doc["schema"] == "lagrangian.feedback" and doc["states"] == ["x", "theta", "x_dot", "theta_dot"]
    K, _, _ = control.lqr(np.array(doc["A"]), np.array(doc["B"]), np.diag([2.0, 10, 1, 1]), [[0.5]])
    assert np.allclose(doc["K"], K, rtol=1e-9)
    traj = tmp_path / "closed.csv"
    assert main(["simulate", CART_POLE, "--feedback", str(out), "--set", "theta=0.2", "--t-end", "15",
                 "--n-out", "16", "--no-reactions", "-o", str(traj)]) == 0, capsys.readouterr().err
    summary = capsys.readouterr().out
    assert "inputs: F = u* - K (x - x*) (feedback)" in summary
    header, rows = _table(traj)
    assert "F" in header and abs(rows[-1, header.index("theta")]) < 1e-3


def test_the_text_form_shows_the_gain_and_the_eigenvalues(capsys):
    assert main(["lqr", CART_POLE, "--at", "x=0", "--at", "theta=0", "--Q", "1,10,1,1"]) == 0
    text = capsys.readouterr().out
    assert "closed-loop eigenvalues (A - B K)" in text and "row of F:" in text and "verdict: the closed loop is " \
        "asymptotically stable" in text


def test_an_input_from_a_csv_file_and_from_an_expression(tmp_path, capsys):
    csv = tmp_path / "push.csv"
    csv.write_text("time,force\n0,0\n0.3,1.5\n0.6,-1\n1,0\n")
    out = tmp_path / "a.csv"
    assert main(["simulate", CART_POLE, "--input", f"F=@{csv}:force:zoh", "--input-time-column", "time",
                 "--t-end", "1", "--n-out", "11", "--no-reactions", "-o", str(out)]) == 0, capsys.readouterr().err
    header, rows = _table(out)
    table = lagrangian.InputTable([0, 0.3, 0.6, 1], [0, 1.5, -1, 0], interpolation="zoh")
    ref = lagrangian.simulate(CART_POLE, 1.0, n_out=11, inputs={"F": table})
    assert np.allclose(rows[:, header.index("x")], ref.q[:, 0], rtol=1e-12, atol=1e-15)
    assert np.array_equal(rows[:, header.index("F")], table(rows[:, 0]))
    out2 = tmp_path / "b.csv"
    assert main(["simulate", CART_POLE, "--input", "F=2*sin(3*t)", "--t-end", "1", "--n-out", "11",
                 "--no-reactions", "-o", str(out2)]) == 0
    header, rows = _table(out2)
    assert np.allclose(rows[:, header.index("F")], 2 * np.sin(3 * rows[:, 0]), atol=1e-15)


@pytest.mark.parametrize(("argv", "message"), [
    (["simulate", CART_POLE, "--input", "G=1"], "`G` in `--input G=1` is not a declared input"),
    (["simulate", CART_POLE, "--input", "m=1"], "(it is a parameter)"),
    (["simulate", CART_POLE, "--input", "F=1", "--input", "F=2"], "given twice"),
    (["simulate", CART_POLE, "--input", "F=@missing.csv"], "no file `missing.csv`"),
    (["simulate", CART_POLE, "--input", "F"], "not of the form NAME=VALUE"),
    (["simulate", CART_POLE, "--feedback", "missing.json"], "cannot be read"),
    (["lqr", CART_POLE, "--Q", "theta=ten"], "`ten` is not a plain decimal number"),
    (["lqr", CART_POLE, "--Q", "1,theta=2"], "mixes a diagonal and named weights"),
    (["lqr", CART_POLE, "--R", "-1"], "R must be positive definite"),
    (["lqr", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--at", "theta=0"], "declares no input"),
])
def test_bad_options_say_what_is_wrong(argv, message, capsys):
    assert main(argv) != 0
    assert message in capsys.readouterr().err


def test_an_interpolation_that_is_not_one_is_refused(tmp_path, capsys):
    csv = tmp_path / "push.csv"
    csv.write_text("t,F\n0,0\n1,1\n")
    assert main(["simulate", CART_POLE, "--input", f"F=@{csv}:F:spline"]) != 0
    assert "`spline` is not an interpolation" in capsys.readouterr().err


def test_the_command_line_offers_every_interpolation_of_a_table(tmp_path, capsys):
    from lagrangian.cli._input_option import _KINDS
    from lagrangian.numerics._input_table import INTERPOLATIONS

    assert _KINDS == INTERPOLATIONS
    csv = tmp_path / "push.csv"
    csv.write_text("t,F\n0,0\n0.5,2\n1,0\n")
    out = tmp_path / "q.csv"
    assert main(["simulate", CART_POLE, "--input", f"F=@{csv}:F:quadratic", "--t-end", "1", "--n-out", "5",
                 "--no-reactions", "-o", str(out)]) == 0, capsys.readouterr().err
    header, rows = _table(out)
    assert np.allclose(rows[:, header.index("F")], 8 * rows[:, 0] * (1 - rows[:, 0]), atol=1e-14)  # the parabola


def test_a_feedback_takes_over_at_the_switching_time(tmp_path, capsys):
    fb_path = tmp_path / "fb.json"
    assert main(["lqr", CART_POLE, "--Q", "theta=10", "-o", str(fb_path)]) == 0
    csv = tmp_path / "push.csv"
    csv.write_text("t,F\n0,0\n0.3,1.5\n0.6,-1\n1,0\n")
    out = tmp_path / "held.csv"
    assert main(["simulate", CART_POLE, "--input", f"F=@{csv}:F:linear", "--feedback", str(fb_path),
                 "--switch-at", "0.8", "--set", "theta=0.1", "--t-end", "3", "--n-out", "31", "--no-reactions",
                 "-o", str(out)]) == 0, capsys.readouterr().err
    assert "until t = 0.8, then u* - K (x - x*) (feedback)" in capsys.readouterr().out
    header, rows = _table(out)
    table = lagrangian.InputTable([0, 0.3, 0.6, 1], [0, 1.5, -1, 0], interpolation="linear")
    F = lagrangian.Switch(table, lagrangian.Feedback.load(fb_path), at=0.8)
    ref = lagrangian.simulate(CART_POLE, 3.0, n_out=31, inputs={"F": F}, initial={"theta": 0.1})
    assert np.allclose(rows[:, header.index("theta")], ref.q[:, 1], rtol=1e-12, atol=1e-15)
    assert main(["simulate", CART_POLE, "--input", f"F=@{csv}", "--switch-at", "0.8"]) != 0
    assert "no --feedback is given" in capsys.readouterr().err
