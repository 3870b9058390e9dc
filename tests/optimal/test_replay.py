"""The replay of an optimum: its inputs, read between the points as each scheme stands for them, run
through `simulate`'s compiled integrator — held against SciPy on the hand-written equation.

A mass m on a spring k with a damper c, driven by F: m ẍ = −k x − c ẋ + F.  For each scheme the input
between the collocation points is written out here (Hermite–Simpson: Lagrange's parabola through u_k,
u_c, u_{k+1}; trapezoidal: the line; backward Euler: u_{k+1} held over (t_k, t_{k+1}]) and integrated by
SciPy's DOP853 interval by interval; the replay's states, its open-loop and its local errors must be
those.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

pytest.importorskip("casadi")

import lagrangian
from lagrangian.model import parse_model
from lagrangian.optimal import optimize

M, K, C, T = 2.0, 3.0, 0.4, 2.0
SPRING = f"""
[model]
name = "Damped mass on a spring"
[parameters]
m = {M}
k = {K}
c = {C}
[inputs]
F = {{}}
[coordinates]
x = {{ initial = 0.0, rate = 0.0 }}
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = {{ potential = "1/2*k*x^2" }}
damper = {{ dissipation = "1/2*c*x_dot^2" }}
push = {{ force = "F*R0.x", at = "P" }}
"""


@pytest.fixture(scope="module")
def spring():
    return lagrangian.derive(parse_model(SPRING))


def _input_by_hand(method: str, t: np.ndarray, u: np.ndarray, k: int):
    """u(s) on the k-th interval between nodes, as the scheme stands for it."""
    if method == "hermite-simpson":
        a, c, b = t[2 * k], t[2 * k + 1], t[2 * k + 2]
        ua, uc, ub = u[2 * k], u[2 * k + 1], u[2 * k + 2]
        return lambda s: (ua * (s - c) * (s - b) / ((a - c) * (a - b)) + uc * (s - a) * (s - b) / ((c - a) * (c - b))
                          + ub * (s - a) * (s - c) / ((b - a) * (b - c)))
    if method == "trapezoidal":
        return lambda s: u[k] + (s - t[k]) * (u[k + 1] - u[k]) / (t[k + 1] - t[k])
    return lambda s: u[k + 1]


def _by_hand(force, a: float, b: float, y: np.ndarray) -> np.ndarray:
    sol = solve_ivp(lambda s, z: [z[1], (-K * z[0] - C * z[1] + force(s)) / M], (a, b), y, method="DOP853",
                    rtol=1e-12, atol=1e-12)
    return sol.y[:, -1]


@pytest.mark.slow
@pytest.mark.parametrize("method", ["hermite-simpson", "trapezoidal", "backward-euler"])
def test_the_replay_is_the_hand_written_equation_under_the_schemes_input(spring, method):
    best = optimize(spring, t_end=T, initial={"x": 1.0, "x_dot": 0.5}, final={"x": -0.3, "x_dot": 0.0}, nodes=9,
                    method=method)
    replay = best.replay
    rows = best.node_rows
    t, u = best.t, best.column("F")
    nodes = np.column_stack([best.q[:, 0], best.qd[:, 0]])[rows]
    # open loop: interval after interval from the initial state; local: each from the optimum's node
    y, ends = [nodes[0]], [nodes[0]]
    for k in range(len(rows) - 1):
        force = _input_by_hand(method, t, u, k)
        a, b = t[rows[k]], t[rows[k + 1]]
        y.append(_by_hand(force, a, b, y[-1]))
        ends.append(_by_hand(force, a, b, nodes[k]))
    y, ends = np.array(y), np.array(ends)
    assert np.abs(replay.y - y).max() < 1e-9
    scale = np.maximum(1.0, np.abs(nodes).max(axis=1))
    assert replay.final_error == pytest.approx(np.abs(y[-1] - nodes[-1]).max(), rel=1e-6, abs=1e-12)
    assert replay.local_error == pytest.approx((np.abs(ends - nodes).max(axis=1) / scale).max(), rel=1e-6, abs=1e-12)
    assert "simulate" in replay.integrator
    # what the replay ran is the optimum's own table
    table = best.input_table("F")
    assert table.interpolation == {"hermite-simpson": "quadratic", "trapezoidal": "linear",
                                   "backward-euler": "zoh"}[method]
    again = lagrangian.simulate(spring, T, t_eval=t[rows], initial={"x": 1.0, "x_dot": 0.5}, inputs={"F": table})
    assert np.abs(np.column_stack([again.q[:, 0], again.qd[:, 0]]) - replay.y).max() < 1e-12
    with pytest.raises(KeyError, match="`G` is not an input"):
        best.input_table("G")
