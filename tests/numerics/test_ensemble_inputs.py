"""Ensembles with inputs: every member runs the compiled law exactly as `simulate` runs it.

The LQR-stabilized cart-pole from a grid of initial angles (its basin of attraction), and the same
start under several gains (one feedback per member): each member equals `simulate` of that
member to the last bit.
"""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian
from lagrangian.analysis import lqr
from lagrangian.errors import SimulationError
from lagrangian.numerics import ensemble, grid, simulate

pytest.importorskip("xarray")

CART_POLE = "examples/inverted_pendulum_cart.toml"


@pytest.fixture(scope="module")
def cart_pole() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(CART_POLE))


@pytest.mark.slow
def test_a_basin_map_of_the_closed_loop_equals_simulate_member_by_member(cart_pole):
    fb = lqr(cart_pole, {"x": 0, "theta": 0}, Q={"theta": 10})
    thetas = np.array([0.2, 0.6, 1.0, 1.4])
    ds = ensemble(cart_pole, 4.0, inputs=fb, initial=grid(theta=thetas), n_out=41, keep="trajectories",
                  events=[lagrangian.EventSpec("fell", "abs(theta) - 1.5", direction=1, terminal=True)])
    for k, theta in enumerate(thetas):
        one = simulate(cart_pole, 4.0, inputs=fb, initial={"theta": theta}, n_out=41,
                       events=[lagrangian.EventSpec("fell", "abs(theta) - 1.5", direction=1, terminal=True)])
        rows = len(one.t)
        assert np.array_equal(ds.trajectory.values[k, :rows, :2], one.q)
    caught = ds.status.values == 0  # reached t_end upright, against "stopped" (it fell)
    assert caught[0] and not caught[-1]
    assert np.abs(ds.state_final.values[0, 1]) < 1e-2


@pytest.mark.slow
def test_each_member_may_run_its_own_gains(cart_pole):
    gains = [lqr(cart_pole, {"x": 0, "theta": 0}, Q={"theta": q}) for q in (1.0, 10.0, 100.0)]
    ds = ensemble(cart_pole, 3.0, inputs=gains, initial={"theta": [0.3, 0.3, 0.3]}, n_out=31, keep="trajectories")
    for k, fb in enumerate(gains):
        one = simulate(cart_pole, 3.0, inputs=fb, initial={"theta": 0.3}, n_out=31)
        assert np.array_equal(ds.trajectory.values[k, :, :2], one.q)
    with pytest.raises(SimulationError, match="3 feedbacks were given for 2 members"):
        ensemble(cart_pole, 1.0, inputs=gains, initial={"theta": [0.1, 0.2]})


@pytest.mark.slow
def test_an_expression_input_is_the_same_for_every_member(cart_pole):
    ds = ensemble(cart_pole, 1.0, inputs={"F": "0.5*sin(2*t)"}, initial={"theta": [0.0, 0.1]}, n_out=11,
                  keep="trajectories")
    one = simulate(cart_pole, 1.0, inputs={"F": "0.5*sin(2*t)"}, initial={"theta": 0.1}, n_out=11)
    assert np.array_equal(ds.trajectory.values[1, :, :2], one.q)


@pytest.mark.slow
def test_python_functions_are_refused_in_ensembles(cart_pole):
    with pytest.raises(SimulationError, match="Python function; ensembles run compiled laws only"):
        ensemble(cart_pole, 1.0, inputs={"F": lambda t, y: 0.0}, initial={"theta": [0.1, 0.2]})
