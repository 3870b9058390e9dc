"""`lagrangian simulate`, in-process: output files, --set, events, errors and exit codes."""

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

from lagrangian.cli.main import main


def test_top_to_csv_reports_conservation_and_applies_settings(tmp_path, capsys):
    out = tmp_path / "top.csv"
    assert main(["simulate", "--t-end", "1", "--set", "theta=0.3", "--set", "phi_dot=80", "--set", "g=1.62",
                 "--n-out", "101", "-o", str(out)]) == 0
    summary = capsys.readouterr().out
    assert "conservation: K relative drift" in summary and "E " in summary and f"wrote {out}" in summary
    lines = out.read_text().splitlines()
    header = next(line for line in lines if not line.startswith("#"))
    assert header.split(",")[:4] == ["t", "psi", "theta", "phi"]
    data = np.loadtxt(out, delimiter=",", comments="#", skiprows=lines.index(header) + 1)
    columns = header.split(",")
    assert data.shape == (101, len(columns))
    assert data[0, columns.index("theta")] == 0.3 and data[0, columns.index("phi_dot")] == 80.0
    assert "g = 1.62" in out.read_text()
    E = data[:, columns.index("E")]
    assert np.ptp(E) <= 1e-9 * abs(E[0])


def test_npz_output_and_csv_to_stdout(tmp_path, capsys):
    out = tmp_path / "pendulum.npz"
    model = str(EXAMPLES_DIR / "simple_pendulum.toml")
    assert main(["simulate", model, "--t-end", "0.5", "--n-out", "11", "-o", str(out)]) == 0
    data = np.load(out)
    assert data["q"].shape == (11, 1) and data["t"][-1] == 0.5 and "monitor_E" in data
    capsys.readouterr()
    assert main(["simulate", model, "--t-end", "0.5", "--n-out", "3"]) == 0
    captured = capsys.readouterr()
    assert captured.out.splitlines()[0].startswith("t,theta,theta_dot,theta_ddot")
    assert len(captured.out.splitlines()) == 4
    assert "conservation:" in captured.err


def test_events_and_stop_when(capsys, tmp_path):
    assert main(["simulate", "--t-end", "5", "--event", "theta_dot", "--stop-when", "t - 0.3",
                 "-o", str(tmp_path / "a.csv")]) == 0
    out = capsys.readouterr().out
    assert "events:" in out and "stop: t - 0.3 at t = 0.3" in out and "stopped by a terminal event" in out


@pytest.mark.parametrize("argv, code, message", [
    (["--set", "theta=0"], 4, "singular at the initial state"),
    (["--t-end", "-1"], 4, "not increasing"),
    (["--set", "omega=1"], 2, "`omega`"),
    (["--set", "theta=abc"], 2, "not a number"),
    (["--event", "import os"], 2, "event"),
])
def test_bad_input_exits_non_zero_and_keeps_the_old_output(tmp_path, capsys, argv, code, message):
    out = tmp_path / "keep.csv"
    out.write_text("precious\n")
    assert main(["simulate", "--t-end", "1", *argv, "-o", str(out)]) == code
    err = capsys.readouterr().err
    assert message in err and "tip:" in err and "Traceback" not in err
    assert out.read_text() == "precious\n"


def test_parameter_without_value(tmp_path, capsys):
    model = tmp_path / "p.toml"
    model.write_text((EXAMPLES_DIR / "simple_pendulum.toml").read_text().replace("l = { value = 0.5,", "l = {"))
    assert main(["simulate", str(model), "--t-end", "1"]) == 4
    assert "`l` has no value" in capsys.readouterr().err
    assert main(["simulate", str(model), "--t-end", "0.1", "--set", "l=0.5", "-o", str(tmp_path / "x.npz")]) == 0


def test_unwritable_output_is_exit_3(tmp_path, capsys):
    assert main(["simulate", "--t-end", "0.1", "-o", str(tmp_path / "missing" / "x.csv")]) == 3
    assert main(["simulate", "--t-end", "0.1", "-o", str(tmp_path / "x.txt")]) == 3
    assert ".csv" in capsys.readouterr().err


def test_reaction_columns_hold_the_rod_tension(tmp_path, capsys):
    # Simple pendulum released at rest from θ0: the rod's pull on P is m g cos θ0 at t = 0
    # (no centripetal part yet), directed from P to O.
    out = tmp_path / "p.csv"
    assert main(["simulate", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--t-end", "0.2", "--n-out", "3",
                 "-o", str(out)]) == 0
    lines = out.read_text().splitlines()
    header = next(line for line in lines if not line.startswith("#")).split(",")
    row = [float(v) for v in lines[lines.index(",".join(header)) + 1].split(",")]
    force = np.array([row[header.index(f"R_to_P_{axis}")] for axis in ("x0", "y0", "z0")])
    m, g, l, theta0 = 1.0, 9.81, 0.5, 0.5
    assert np.linalg.norm(force) == pytest.approx(m * g * np.cos(theta0), rel=1e-12)
    P = l * np.array([0.0, np.sin(theta0), -np.cos(theta0)])
    assert np.dot(force, -P) > 0    # pulls towards O
    assert main(["simulate", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--t-end", "0.2", "--no-reactions",
                 "-o", str(out)]) == 0
    assert "R_to_P" not in out.read_text()



def test_a_robots_reactions_are_asked_for_not_computed_by_default(tmp_path, capsys):
    # The only reaction of a robot is the ground's wrench on the arm: motion first, the wrench on request.
    out = tmp_path / "arm.csv"
    assert main(["simulate", "zoo:serial_arm:4", "--t-end", "0.05", "--n-out", "3", "-o", str(out)]) == 0
    assert "R_to_link1" not in out.read_text()
    assert "reactions: not computed for a kinematic tree" in capsys.readouterr().out
    assert main(["simulate", "zoo:serial_arm:4", "--t-end", "0.05", "--n-out", "3", "--reactions",
                 "-o", str(out)]) == 0
    assert "R_to_link1_link2_link3_link4_x0" in out.read_text()
    assert "reactions: not computed" not in capsys.readouterr().out


# -- the audit of `simulate`: bare --plot, checks before the run, validation, MP4, stabilization --------

PENDULUM_FILE = str(EXAMPLES_DIR / "simple_pendulum.toml")


@pytest.mark.slow
def test_bare_plot_writes_into_the_model_stem_folder(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", PENDULUM_FILE, "--t-end", "0.2", "--n-out", "11", "--animation", "none",
                 "--plot"]) == 0
    out = capsys.readouterr().out
    assert (tmp_path / "simple_pendulum_plots" / "time_series.png").is_file()
    assert "files in simple_pendulum_plots/" in out
    assert not list((tmp_path / "simple_pendulum_plots").glob("animation*"))


@pytest.mark.parametrize("argv, message", [
    (["--plot", "{file}"], "is a file, not a folder"),
    (["--plot", "{dir}", "--animation", "mp4"], "needs ffmpeg"),
])
def test_plot_problems_are_found_before_the_run(tmp_path, capsys, monkeypatch, argv, message):
    from lagrangian.cli import _simulate

    monkeypatch.setattr(_simulate, "_ffmpeg", lambda: None)
    out = tmp_path / "keep.csv"
    out.write_text("precious\n")
    blocker = tmp_path / "blocker"
    blocker.write_text("a file\n")
    argv = [a.format(file=blocker, dir=tmp_path / "figs") for a in argv]
    assert main(["simulate", PENDULUM_FILE, "--t-end", "0.2", "-o", str(out), *argv]) == 3
    captured = capsys.readouterr()
    assert message in captured.err and "conservation" not in captured.out + captured.err
    assert out.read_text() == "precious\n" and blocker.read_text() == "a file\n"


def test_output_suffix_and_folder_are_checked_before_the_run(tmp_path, capsys):
    assert main(["simulate", PENDULUM_FILE, "--t-end", "0.2", "-o", str(tmp_path / "x.txt")]) == 3
    assert main(["simulate", PENDULUM_FILE, "--t-end", "0.2", "-o", str(tmp_path / "no" / "x.csv")]) == 3
    captured = capsys.readouterr()
    assert "conservation" not in captured.out + captured.err and "does not exist" in captured.err


@pytest.mark.parametrize("argv, message", [
    (["--tolerance", "0"], "positive"),
    (["--rtol", "1e-300"], "below 1e-14"),
    (["--n-out", "100000000"], "GiB"),
    (["--method", "Radau", "--rtol", "1e-13", "--atol", "1e-300"], "SciPy's Radau failed at t ="),
])
def test_bad_numbers_exit_4_with_a_message_and_keep_the_old_output(tmp_path, capsys, argv, message):
    out = tmp_path / "keep.npz"
    out.write_bytes(b"precious")
    assert main(["simulate", "--t-end", "1", *argv, "-o", str(out)]) == 4
    err = capsys.readouterr().err
    assert message in err and "tip:" in err and "Traceback" not in err
    assert out.read_bytes() == b"precious"


@pytest.mark.parametrize("value", ["inf", "nan", "1_0", "\u0663", "1e400", "2*pi"])
def test_numeric_options_are_plain_finite_decimal_numbers(tmp_path, capsys, value):
    # Python's float() takes 1_0, Arabic-Indic digits, inf and nan; the help says "a number".
    out = tmp_path / "keep.npz"
    out.write_bytes(b"precious")
    with pytest.raises(SystemExit) as exit_:
        main(["simulate", "--t-end", value, "-o", str(out)])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "argument --t-end" in err and ("plain decimal number" in err or "finite" in err)
    assert "Traceback" not in err and out.read_bytes() == b"precious"


def test_horizontal_pendulum_drift_is_small_and_not_flagged(capsys, tmp_path):
    assert main(["simulate", PENDULUM_FILE, "--set", "theta=1.5707963267948966", "-o",
                 str(tmp_path / "p.csv")]) == 0
    out = capsys.readouterr().out
    drift = float(out.split("E relative drift ")[1].split()[0].rstrip(","))
    assert drift < 1e-8 and "warning" not in out


def test_scipy_steps_are_the_integrators_not_the_output_points(capsys, tmp_path):
    assert main(["simulate", "--t-end", "1", "--method", "RK45", "--n-out", "11", "-o", str(tmp_path / "a.csv")]) == 0
    out = capsys.readouterr().out
    steps = int(out.split(" steps,")[0].rsplit(" ", 1)[1])
    assert steps > 11


def test_stabilization_flag_reaches_the_dae(capsys, tmp_path):
    model = str(EXAMPLES_DIR / "pendulum_tension.toml")
    assert main(["simulate", model, "--t-end", "0.2", "--n-out", "11", "--stabilization", "baumgarte",
                 "-o", str(tmp_path / "a.csv")]) == 0
    assert "dop853 + baumgarte" in capsys.readouterr().out
    assert main(["simulate", PENDULUM_FILE, "--t-end", "0.2", "--stabilization", "both"]) == 4
    assert "complementary" in capsys.readouterr().err


# A gimbal gyroscope: the outer ring turns about z0, the inner ring about x1 in it, the rotor about z2 in the
# inner ring; every centre is at O, so the rings may leave out their masses (the motion does not need them).
GYROSCOPE = """
[parameters]
A = 0.01
C = 0.02
J1 = 0.003
J2 = 0.002
m = 0.5
g = 9.81
[coordinates]
psi = { initial = 0.0, rate = 0.5 }
theta = { initial = 0.3, rate = 0.0 }
phi = { initial = 0.0, rate = 100.0 }
[frames]
R1 = { from = "R0", rotation = ["psi", "z"] }
R2 = { from = "R1", rotation = ["theta", "x"] }
R3 = { from = "R2", rotation = ["phi", "z"] }
[bodies.outer]
frame = "R1"
center = "0*R1.z"
inertia = { diagonal = ["J1", "J1", "J1"] }
[bodies.inner]
frame = "R2"
center = "0*R2.z"
inertia = { diagonal = ["J2", "J2", "J2"] }
[bodies.rotor]
frame = "R3"
mass = "m"
center = "0*R3.z"
inertia = { diagonal = ["A", "A", "C"] }
[loads]
weight = { gravity = "-g*R0.z", on = ["rotor"] }
"""


def test_a_gyroscope_whose_rings_leave_out_their_masses_is_simulated_and_says_what_reactions_need(tmp_path, capsys):
    model = tmp_path / "gyroscope.toml"
    model.write_text(GYROSCOPE)
    out = tmp_path / "run.csv"
    assert main(["simulate", str(model), "--t-end", "0.2", "-o", str(out)]) == 0
    err = capsys.readouterr()
    text = err.out + err.err
    lines = [line for line in text.splitlines() if line.startswith("reactions:")]
    assert lines == [("reactions: not computed: they need the masses of bodies `outer`, `inner`, which the model "
                      'leaves out (give mass = "..." under [bodies.outer]; the motion does not need it)')]
    lines = [line for line in out.read_text().splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    assert "psi" in header and not any(name.startswith("R_") for name in header)
    # The motion itself: the balanced rotor keeps its spin rate (φ̇ + ψ̇ cos θ is a first integral, C times it H).
    rows = np.loadtxt(lines[1:], delimiter=",")
    spin = rows[:, header.index("phi_dot")] + rows[:, header.index("psi_dot")] * np.cos(rows[:, header.index("theta")])
    assert np.allclose(spin, spin[0], rtol=1e-6)
    # Asked for explicitly, the reactions still stop the run with the error and its fix.
    assert main(["simulate", str(model), "--t-end", "0.2", "--reactions", "-o", str(out)]) != 0
    assert "the reactions need the mass of body `outer`" in capsys.readouterr().err
