"""`Switch`: one input's sources in turn at given times, compiled into the right-hand side.

Each motion is held against SciPy's ``solve_ivp`` on the equation written by hand in the test (a mass on
a spring with a damper, m ẍ = −k x − c ẋ + F), integrated phase by phase with each phase's force
written out; the Python evaluation of the law (SciPy methods' hint, the constrained path, no compiler)
and the ensembles against the compiled run.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian
from lagrangian.analysis import lqr
from lagrangian.errors import SimulationError
from lagrangian.numerics import InputTable, Switch, compile_system, simulate

M, K, C = 2.0, 8.0, 0.3
OSCILLATOR = f"""
[model]
name = "forced oscillator"
[parameters]
m = {M}
k = {K}
c = {C}
[inputs]
F = {{ unit = "N" }}
[coordinates]
x = {{ initial = 0.1, rate = 0.0 }}
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = {{ potential = "1/2*k*x^2" }}
damper = {{ dissipation = "1/2*c*x_dot^2" }}
push = {{ force = "F*R0.x", at = "P" }}
"""
TABLE = InputTable([0.0, 0.5, 1.0, 1.5], [0.0, 2.0, -1.0, 0.5], interpolation="linear")


@pytest.fixture(scope="module")
def oscillator() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(OSCILLATOR, source="oscillator.toml"))


def _by_hand(phases, edges, t_eval) -> np.ndarray:
    """x(t) of m ẍ = −k x − c ẋ + F, one solve per phase [edges[k], edges[k + 1]] with its force F(t, x, ẋ)."""
    y, xs = np.array([0.1, 0.0]), []
    for k, force in enumerate(phases):
        a, b = edges[k], edges[k + 1]
        grid = t_eval[(t_eval >= a) & (t_eval < b)] if k < len(phases) - 1 else t_eval[t_eval >= a]
        wanted = grid if len(grid) and grid[-1] == b else np.append(grid, b)
        sol = solve_ivp(lambda s, z, f=force: [z[1], (-K * z[0] - C * z[1] + f(s, z[0], z[1])) / M], (a, b), y,
                        t_eval=wanted, rtol=1e-12, atol=1e-12, method="DOP853")
        xs.append(sol.y[0, :len(grid)])
        y = sol.y[:, -1]
    return np.concatenate(xs)


@pytest.mark.slow
def test_an_expression_then_a_table_then_a_number_drive_the_hand_written_equation(oscillator):
    F = Switch("2*sin(3*t)", TABLE, -0.5, at=(0.8, 1.9))
    t = np.linspace(0, 3, 31)
    traj = simulate(oscillator, 3.0, t_eval=t, inputs={"F": F})
    ref = _by_hand([lambda s, x, v: 2 * math.sin(3 * s), lambda s, x, v: float(TABLE(s)), lambda s, x, v: -0.5],
                   [0.0, 0.8, 1.9, 3.0], t)
    assert np.abs(traj.q[:, 0] - ref).max() < 1e-9
    # the applied force is each phase's, the switch right-continuous (at t = 1.9 the number already)
    expected = np.where(t < 0.8, 2 * np.sin(3 * t), np.where(t < 1.9, TABLE(t), -0.5))
    assert np.allclose(traj.column("F"), expected, rtol=0, atol=1e-14)
    assert traj.integrals == ()  # the force varies: no energy to monitor


@pytest.mark.slow
def test_a_table_then_a_feedback_is_the_swing_up_then_the_catch(oscillator):
    fb = lqr(oscillator, {"x": 0.0}, Q={"x": 10.0})
    (k_x, k_v), = fb.K
    F = Switch(TABLE, fb, at=1.5)
    t = np.linspace(0, 4, 41)
    traj = simulate(oscillator, 4.0, t_eval=t, inputs={"F": F})
    ref = _by_hand([lambda s, x, v: float(TABLE(s)), lambda s, x, v: -(k_x * x + k_v * v)], [0.0, 1.5, 4.0], t)
    assert np.abs(traj.q[:, 0] - ref).max() < 1e-9
    late = t >= 1.5
    assert np.allclose(traj.column("F")[late], -(k_x * traj.q[late, 0] + k_v * traj.qd[late, 0]), atol=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("how", ["RK45", "symengine", "constrained"])
def test_the_law_in_python_switches_where_the_compiled_one_does(oscillator, how):
    F = Switch("2*sin(3*t)", TABLE, at=0.8)
    t = np.linspace(0, 2, 21)
    compiled = simulate(oscillator, 2.0, t_eval=t, inputs={"F": F})
    if how == "RK45":  # SciPy's loop in Python on the compiled law, restarted at the switch
        other = simulate(oscillator, 2.0, t_eval=t, inputs={"F": F}, method="RK45", rtol=1e-11, atol=1e-12)
    elif how == "symengine":  # no C compiler: the law evaluated in Python
        system = compile_system(oscillator, inputs={"F": F}, backend="symengine")
        other = simulate(system, 2.0, t_eval=t, method="DOP853")
    else:  # the same oscillator with a trivial complementary constraint y = 0: the DAE path, in Python
        text = OSCILLATOR.replace('x = { initial = 0.1, rate = 0.0 }',
                                  'x = { initial = 0.1, rate = 0.0 }\ny = { initial = 0.0, rate = 0.0 }')
        text = text.replace('position = "x*R0.x"', 'position = "x*R0.x + y*R0.y"')
        text += '[constraints]\nrail = { holonomic = "y" }\n'
        other = simulate(lagrangian.parse_model(text), 2.0, t_eval=t, inputs={"F": F})
    assert np.abs(other.q[:, 0] - compiled.q[:, 0]).max() < 1e-7
    assert np.allclose(other.column("F"), compiled.column("F"), atol=1e-7)


@pytest.mark.slow
def test_a_switch_time_is_a_breakpoint_and_changing_it_recompiles_nothing(oscillator):
    system = compile_system(oscillator, inputs={"F": Switch(0.0, 1.0, at=0.5)})
    assert np.array_equal(system.law.breakpoints, [0.5])
    later = simulate(system, 2.0, inputs={"F": Switch(0.0, 1.0, at=1.25)}, n_out=5)
    assert later.column("F").tolist() == [0.0, 0.0, 0.0, 1.0, 1.0]  # t = 0, 0.5, 1, 1.5, 2
    twin = lagrangian.numerics._input_run.system_for(system, oscillator, [], "auto",
                                                     {"F": Switch(0.0, 1.0, at=1.25)}, None)
    assert twin._lib is system._lib


@pytest.mark.slow
def test_an_ensemble_runs_the_switch_as_simulate_does(oscillator):
    pytest.importorskip("xarray")
    F = Switch(TABLE, "-3*x - x_dot", at=1.2)
    ds = lagrangian.ensemble(oscillator, 2.0, inputs={"F": F}, initial={"x": [0.1, -0.2]}, n_out=11,
                             keep="trajectories")
    one = simulate(oscillator, 2.0, inputs={"F": F}, initial={"x": -0.2}, n_out=11)
    assert np.array_equal(ds.trajectory.values[1, :, 0], one.q[:, 0])


@pytest.mark.parametrize(("make", "message"), [
    (lambda: Switch(1.0, at=()), "two sources or more"),
    (lambda: Switch(1.0, 2.0, at=(1.0, 2.0)), "2 sources needs 1 switching time, not 2"),
    (lambda: Switch(1.0, 2.0, 3.0, at=(2.0, 1.0)), "increase strictly"),
    (lambda: Switch(1.0, 2.0, at=math.nan), "must be finite"),
    (lambda: Switch(1.0, Switch(1.0, 2.0, at=1.0), at=0.5), "cannot be a source of another Switch"),
    (lambda: Switch(1.0, 2.0, at="soon"), "must be numbers"),
])
def test_a_bad_switch_is_refused_clearly(make, message):
    with pytest.raises(SimulationError, match=message):
        make()


def test_a_bad_source_in_a_switch_is_named_with_its_input(oscillator):
    with pytest.raises(SimulationError, match="In the input `F` = `2\\*sin\\(`"):
        simulate(oscillator, 1.0, inputs={"F": Switch(0.0, "2*sin(", at=0.5)})
    fb = lqr(oscillator, {"x": 0.0})
    other = lqr(oscillator, {"x": 0.0}, Q={"x": 5.0})
    with pytest.raises(SimulationError, match="Two different feedbacks"):
        simulate(oscillator, 1.0, inputs={"F": Switch(fb, other, at=0.5)})
