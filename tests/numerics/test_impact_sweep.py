"""Impact outcomes over a grid (`numerics._impact_sweep`): the bouncing ball against e, in closed form.

Dropped from h₀, the ball's approach speeds are v₁ e^{k−1} (v₁ = √(2 g h₀)), so the impacts faster
than v_min are 1 + ⌊ln(v_min/v₁)/ln e⌋, and they accumulate at t_∞ = √(2h₀/g)(1 + e)/(1 − e), where
the ball has lost all its energy m g h₀.
"""

from __future__ import annotations

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian import SimulationError
from lagrangian.cli.main import main

BALL = EXAMPLES_DIR / "bouncing_ball.toml"
G, H0, M = 9.81, 1.0, 0.1


@pytest.fixture(scope="module")
def model() -> lagrangian.Model:
    return lagrangian.load_model(BALL)


def test_the_bounces_and_the_rest_time_against_e_are_the_closed_forms(model: lagrangian.Model) -> None:
    e = np.array([0.3, 0.5, 0.7, 0.85])
    v_min = 0.1
    s = lagrangian.sweep(model, "e", e, t_end=15.0, min_speed=v_min)
    assert isinstance(s, lagrangian.ImpactSweep) and s.shape == (4,) and list(s.status) == ["ok"] * 4
    v1 = np.sqrt(2 * G * H0)
    assert np.array_equal(s.bounces, 1 + np.floor(np.log(v_min / v1) / np.log(e)))
    assert np.allclose(s.rest_time, np.sqrt(2 * H0 / G) * (1 + e) / (1 - e), rtol=0, atol=1e-9)
    assert np.allclose(s.first_impact, np.sqrt(2 * H0 / G), atol=1e-12)
    assert np.allclose(s.energy_lost, M * G * H0, rtol=1e-9)
    assert np.all(s.impacts > s.bounces) and np.all(np.diff(s.impacts) > 0) and np.all(s.liftoffs == 0)


def test_a_grid_over_a_parameter_and_an_initial_height(model: lagrangian.Model) -> None:
    s = lagrangian.impact_sweep(model, {"e": [0.5, 0.8], "z": [0.5, 2.0]}, 15.0)
    e, h = np.meshgrid([0.5, 0.8], [0.5, 2.0], indexing="ij")
    assert s.shape == (2, 2)
    assert np.allclose(s.rest_time, np.sqrt(2 * h / G) * (1 + e) / (1 - e), atol=1e-9)
    xr = pytest.importorskip("xarray")
    ds = s.to_dataset()
    assert isinstance(ds, xr.Dataset) and ds["rest_time"].dims == ("e", "z")
    assert float(ds["rest_time"].sel(e=0.8, z=2.0)) == pytest.approx(np.sqrt(4 / G) * 9, abs=1e-9)


def test_a_member_that_fails_keeps_its_error_and_the_others_go_on(model: lagrangian.Model) -> None:
    s = lagrangian.impact_sweep(model, {"e": [0.5, 1.5]}, 5.0)
    assert s.status[0] == "ok" and "outside [0, 1]" in s.status[1] and np.isnan(s.rest_time[1])


def test_bad_sweeps_are_refused(model: lagrangian.Model) -> None:
    with pytest.raises(SimulationError, match="not a parameter"):
        lagrangian.impact_sweep(model, {"k": [1.0]}, 1.0)
    with pytest.raises(SimulationError, match="both swept and set"):
        lagrangian.impact_sweep(model, {"e": [0.5]}, 1.0, parameters={"e": 0.4})
    with pytest.raises(SimulationError, match="unilateral contacts"):
        lagrangian.impact_sweep(EXAMPLES_DIR / "simple_pendulum.toml", {"g": [1.0]}, 1.0)
    with pytest.raises(lagrangian.LinearizationError, match="t_end"):
        lagrangian.sweep(model, "e", [0.5])


def test_the_command_line_sweeps_a_contact_model_to_csv(tmp_path, capsys) -> None:
    out = tmp_path / "bounces.csv"
    assert main(["sweep", str(BALL), "--grid", "e=0.5:0.8:2", "--t-end", "10", "--min-speed", "0.1",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "2 members" in text and "rest time" in text
    rows = [line.split(",") for line in out.read_text().splitlines() if not line.startswith("#")]
    assert rows[0][:6] == ["e", "impacts", "bounces", "first_impact", "rest_time", "liftoffs"]
    assert float(rows[2][4]) == pytest.approx(np.sqrt(2 / G) * 1.8 / 0.2, abs=1e-9) and rows[2][-1] == '"ok"'
    assert main(["sweep", str(BALL), "--grid", "e=0.5:0.8:2", "--out", str(tmp_path / "x.zarr")]) == 3
