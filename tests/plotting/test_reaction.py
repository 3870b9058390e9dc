"""R_O(t) drawn from the resultant theorem, against finite differences and statics."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian import parse_model
from lagrangian.dynamics import derive
from lagrangian.errors import OutputError
from lagrangian.numerics import simulate
from lagrangian.plotting import apex_path, applicable_kinds, plot_reaction, reactions_along


def _components(fig):
    lines = fig.axes[0].get_lines()
    return np.column_stack([np.asarray(lines[k].get_ydata(), dtype=float) for k in range(3)])


def test_top_reaction_is_m_gamma_G_minus_weight_by_finite_differences(run):
    # R_O = m γ(G) − m g with OG = a z: γ(G) = a z̈, z̈ from the axis tip by central differences
    # (independent of the kinematics' symbolic acceleration).
    eom, traj = run("lagrange_top.toml")
    R = _components(plot_reaction(traj, eom))
    p = traj.parameters
    h = traj.t[1] - traj.t[0]
    z = apex_path(traj, eom)
    zdd = (z[2:] - 2 * z[1:-1] + z[:-2]) / h**2
    expected = p["m"] * p["a"] * zdd - np.array([0.0, 0.0, -p["m"] * p["g"]])
    scale = np.max(np.abs(R))
    # Central differences err by h² z⁗/12: about 3e-5 N here.
    assert np.max(np.abs(R[1:-1] - expected)) < 1e-5 * scale


def test_rest_hanging_double_pendulum_carries_its_weight(run):
    eom, traj = run("double_pendulum.toml", theta1=0.0, theta2=0.0)
    (reaction,) = reactions_along(traj, eom).values()
    p = traj.parameters
    np.testing.assert_allclose(reaction.force, np.tile([0, 0, (p["m1"] + p["m2"]) * p["g"]], (len(traj), 1)),
                               rtol=0, atol=1e-12)
    assert reaction.name == "R_O"


def test_frictionless_rail_pushes_only_vertically(run):
    # The only horizontal given force on the cart and bob is the spring's, which the x equation
    # balances: the rail's reaction has no x0 and no y0 component.
    eom, traj = run("cart_pendulum.toml")
    R = _components(plot_reaction(traj, eom))
    assert np.max(np.abs(R[:, :2])) < 1e-10 * np.max(np.abs(R))
    assert np.all(R[:, 2] > 0)


POTENTIAL_MODEL = """
[model]
name = "Potential well"
[parameters]
m = { value = 1.0 }
k = { value = 4.0 }
[coordinates]
x = { initial = 0.1, rate = 0.0 }
[frames]
R0 = { axes = ["x0", "y0", "z0"] }
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
well = { potential = "1/2*k*x^2" }
"""


def test_no_reaction_without_force_form():
    eom = derive(parse_model(POTENTIAL_MODEL))
    traj = simulate(eom, 0.2, n_out=11)
    with pytest.raises(OutputError, match="potential"):
        reactions_along(traj, eom)
    assert "reaction" not in applicable_kinds(traj, eom)
