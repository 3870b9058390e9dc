"""Bad input to a simulation with contacts: clear errors, before anything is written."""

from __future__ import annotations

import json

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian import ModelError, SimulationError
from lagrangian.cli.main import main

BALL = EXAMPLES_DIR / "bouncing_ball.toml"

WEDGE = """
[parameters]
m = 1.0
e = {e}
[coordinates]
x = {{ initial = 0.0, rate = 1.0 }}
[particles.P]
mass = "m"
position = "x*R0.x"
[constraints]
left = {{ unilateral = "x", restitution = "e" }}
right = {{ unilateral = "-x", restitution = "e" }}
"""


def test_a_contact_violated_at_the_start_is_refused_with_its_line() -> None:
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(BALL, 1.0, initial={"z": -0.1})
    message = info.value.message
    assert "`floor`" in message and "bouncing_ball.toml:" in message and "g = -0.1 < 0" in message
    assert "≥ 0" in info.value.fix


@pytest.mark.parametrize("e", [1.5, -0.2])
def test_a_restitution_outside_zero_one_is_refused(e: float) -> None:
    with pytest.raises(SimulationError, match=r"outside \[0, 1\]"):
        lagrangian.simulate(BALL, 1.0, parameters={"e": e})


@pytest.mark.slow
def test_simultaneous_impacts_with_no_solution_are_refused(tmp_path) -> None:
    path = tmp_path / "wedge.toml"
    path.write_text(WEDGE.format(e=0.5))
    with pytest.raises(SimulationError, match="has no solution") as info:
        lagrangian.simulate(path, 1.0)
    assert "`left`, `right`" in info.value.message and "e = 0" in info.value.fix
    out = tmp_path / "wedge.csv"
    assert main(["simulate", str(path), "--t-end", "1", "-o", str(out)]) == 4
    assert not out.exists()  # nothing written half
    path.write_text(WEDGE.format(e=0.0))  # a plastic wedge stops the body
    tr = lagrangian.simulate(path, 1.0, n_out=11)
    assert np.all(tr.column("x") == 0) and np.all(tr.column("x_dot") == 0)


@pytest.mark.slow
def test_a_persistent_contact_that_would_slide_with_friction_is_refused() -> None:
    # A block on a 30° incline, μ = 0.2 < tan 30°: it cannot stay stuck, and sliding friction is not simulated.
    text = """
[parameters]
m = 1.0
g = 9.81
alpha = 0.5235987755982988
[coordinates]
x = { initial = 0.0, rate = 0.0 }
z = { initial = 0.0, rate = 0.0 }
[frames]
I = { from = "R0", rotation = ["alpha", "y"] }
[particles.B]
mass = "m"
position = "x*I.x + z*I.z"
[loads]
weight = { gravity = "-g*R0.z" }
[constraints]
slope = { unilateral = "z", restitution = "0", friction = "0.2", slip = "x_dot" }
"""
    with pytest.raises(SimulationError, match="sliding with friction") as info:
        lagrangian.simulate(lagrangian.parse_model(text, source="incline.toml"), 1.0)
    assert "friction coefficient" in info.value.fix
    model = lagrangian.parse_model(text.replace('"0.2"', '"0.8"'), source="incline.toml")
    tr = lagrangian.simulate(model, 1.0, n_out=11)  # μ = 0.8 > tan 30°: it stays, held by friction
    assert np.max(np.abs(tr.q)) <= 1e-12
    # I.x points down the slope: the friction holding the block is −m g sin α along it.
    assert np.allclose(tr.column("lambda_slope_t"), -9.81 * np.sin(0.5235987755982988), rtol=1e-12)
    assert np.allclose(tr.column("lambda_slope"), 9.81 * np.cos(0.5235987755982988), rtol=1e-12)


def test_options_that_cannot_work_with_contacts_are_refused() -> None:
    for options in ({"dt": 0.01}, {"method": "RK45"}, {"stabilization": "baumgarte"}):
        with pytest.raises(SimulationError):
            lagrangian.simulate(BALL, 1.0, **options)
    with pytest.raises(SimulationError, match="impact_sweep"):
        lagrangian.ensemble(BALL, 1.0, initial=lagrangian.grid(z=np.linspace(0.5, 1.0, 3)))


def test_exact_coulomb_friction_beside_contacts_is_refused() -> None:
    text = BALL.read_text().replace('weight = { gravity = "-g*R0.z" }',
                                    'weight = { gravity = "-g*R0.z" }\nslide = { coulomb = "P", coefficient = "0.1", '
                                    'normal_force = "m*g", regularization = 0 }')
    with pytest.raises(ModelError, match="not simulated together"):
        lagrangian.simulate(lagrangian.parse_model(text, source="ball.toml"), 1.0)


def test_the_trajectory_file_keeps_the_contact_events(tmp_path, capsys) -> None:
    out = tmp_path / "ball.npz"
    assert main(["simulate", str(BALL), "--t-end", "1", "-o", str(out)]) == 0
    assert "impact_floor at t = 0.451523641" in capsys.readouterr().out
    meta = json.loads(str(np.load(out)["metadata"]))
    [impact] = [e for e in meta["events"] if e["name"] == "impact_floor"]
    assert impact["kind"] == "impact" and impact["contact"] == "floor"
    assert impact["percussion"] == pytest.approx(0.1 * 1.8 * np.sqrt(2 * 9.81), rel=1e-9)
    assert impact["energy_after"] == pytest.approx(0.64 * impact["energy_before"], rel=1e-9)
