"""A minimum-time slew with a free final time, against the bang-bang closed form.

The satellite of examples/satellite_reaction_wheel.toml: a body B (axial inertia Ib) turned by a wheel
(Iw) whose motor gives |τ| ≤ τmax.  By hand, with the angular momentum about the axis conserved and zero,
Ib θ̈ = −τ: a double integrator, whose least time from rest to rest through Θ is (Pontryagin; Bryson &
Ho, *Applied Optimal Control*, §3.9) full thrust one way, then the other, switching halfway:

    T* = 2 √(Θ Ib / τmax).
"""

import math

import numpy as np
import pytest

pytest.importorskip("casadi")

from lagrangian_test_support import EXAMPLES_DIR

from lagrangian.optimal import load_problem, optimize

IB, IW, TAU_MAX, THETA = 10.0, 0.1, 0.5, 1.0


@pytest.fixture(scope="module")
def slew():
    return optimize(load_problem(EXAMPLES_DIR / "optimal" / "satellite_slew.toml"))


@pytest.mark.slow
def test_the_least_time_is_the_bang_bang_closed_form(slew):
    assert slew.status == "optimal" and slew.free_time
    assert slew.t_end == pytest.approx(2 * math.sqrt(THETA * IB / TAU_MAX), rel=1e-6)
    assert slew.objective == pytest.approx(slew.t_end, rel=1e-12)


@pytest.mark.slow
def test_the_torque_is_full_one_way_then_the_other(slew):
    tau, t = slew.column("tau"), slew.t
    first, second = t < 0.45 * slew.t_end, t > 0.55 * slew.t_end
    # Ib θ̈ = −τ: the body turns to +Θ with τ = −τmax first
    assert np.allclose(tau[first], -TAU_MAX, atol=1e-6) and np.allclose(tau[second], TAU_MAX, atol=1e-6)


def test_the_wheel_stops_with_the_body(slew):
    # (Ib + Iw) θ̇ + Iw φ̇ = 0 throughout: at rest again, the wheel is at rest too (not a condition given)
    momentum = (IB + IW) * slew.column("theta_dot") + IW * slew.column("phi_dot")
    assert np.max(np.abs(momentum)) < 1e-9
    assert abs(slew.column("phi_dot")[-1]) < 1e-8
    assert slew.replay is not None and slew.replay.within and slew.replay.max_error < 1e-6
