"""Inputs that vary during a motion: expressions, tables, Python functions, compiled into the right-hand side.

Each motion is held against SciPy's ``solve_ivp`` on equations written by hand in the test
(a mass on a spring with a damper, m ẍ = −k x − c ẋ + F; a pendulum pushed horizontally),
never against the engine itself; the tables against their definitions (`numpy.interp`,
SciPy's ``CubicSpline``, the hold and Lagrange's quadratic written out); the slow path (a Python function) against
the compiled one.
"""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

import lagrangian
from lagrangian.errors import SimulationError
from lagrangian.numerics import InputTable, compile_system, simulate

RTOL = 1e-10
M, K, C = 2.0, 8.0, 0.3

OSCILLATOR = f"""
[model]
name = "forced oscillator"

[parameters]
m = {M}
k = {K}
c = {C}
k1 = 3.0
k2 = 1.5

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


def _by_hand(force, t_span, y0, t_eval, **kw):
    """m ẍ = −k x − c ẋ + F(t, x, ẋ), written out, by SciPy."""
    def f(t, y):
        x, v = y
        return [v, (-K * x - C * v + force(t, x, v)) / M]
    return solve_ivp(f, t_span, y0, t_eval=t_eval, rtol=1e-12, atol=1e-12, method="DOP853", **kw)


@pytest.fixture(scope="module")
def oscillator() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(OSCILLATOR, source="oscillator.toml"))


@pytest.mark.slow
def test_an_expression_of_t_drives_the_oscillator_as_the_hand_written_equations(oscillator):
    t = np.linspace(0, 6, 61)
    traj = simulate(oscillator, 6.0, t_eval=t, inputs={"F": "2*sin(3*t)"}, rtol=RTOL, atol=RTOL)
    ref = _by_hand(lambda t, x, v: 2 * math.sin(3 * t), (0, 6), [0.1, 0.0], t)
    assert np.abs(traj.q[:, 0] - ref.y[0]).max() < 100 * RTOL
    assert np.allclose(traj.column("F"), 2 * np.sin(3 * t), rtol=0, atol=1e-14)
    assert "F" not in traj.parameters  # it varied: a column, not a parameter value


@pytest.mark.slow
def test_an_expression_of_the_state_is_a_feedback_law_compiled_in(oscillator):
    t = np.linspace(0, 5, 51)
    traj = simulate(oscillator, 5.0, t_eval=t, inputs={"F": "-k1*x - k2*x_dot + 0.5*cos(t)"}, rtol=RTOL, atol=RTOL)
    ref = _by_hand(lambda t, x, v: -3.0 * x - 1.5 * v + 0.5 * math.cos(t), (0, 5), [0.1, 0.0], t)
    assert np.abs(traj.q[:, 0] - ref.y[0]).max() < 100 * RTOL
    assert np.allclose(traj.column("F"), -3.0 * traj.q[:, 0] - 1.5 * traj.qd[:, 0] + 0.5 * np.cos(t), atol=1e-13)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["RK45", "Radau", "gauss-legendre"])
def test_every_method_takes_the_inputs(oscillator, method):
    t = np.linspace(0, 3, 31)
    kw = {"dt": 1e-3} if method == "gauss-legendre" else {"rtol": 1e-9, "atol": 1e-12}
    traj = simulate(oscillator, 3.0, t_eval=t, inputs={"F": "2*sin(3*t)"}, method=method, **kw)
    ref = _by_hand(lambda t, x, v: 2 * math.sin(3 * t), (0, 3), [0.1, 0.0], t)
    assert np.abs(traj.q[:, 0] - ref.y[0]).max() < 1e-7


@pytest.mark.slow
def test_a_number_holds_the_input_and_keeps_the_integrals_of_a_constant_force():
    # Without the damper the energy T + U − F x of a constant force is a first integral.
    text = OSCILLATOR.replace('damper = { dissipation = "1/2*c*x_dot^2" }\n', "")
    eom = lagrangian.derive(lagrangian.parse_model(text))
    traj = simulate(eom, 3.0, inputs={"F": 1.5}, n_out=31)
    assert traj.integrals == ("E",) and traj.drift["E"] < 1e-9
    # the equilibrium moves to x = F/k: the motion is a cosine about it
    t = traj.t
    assert np.allclose(traj.q[:, 0], 1.5 / K + (0.1 - 1.5 / K) * np.cos(np.sqrt(K / M) * t), atol=1e-9)
    assert np.all(traj.column("F") == 1.5)


# -- tables --------------------------------------------------------------------------------------------
SAMPLES_T = np.array([0.0, 0.4, 1.0, 1.3, 2.2, 3.0])
SAMPLES_V = np.array([0.0, 1.0, -0.5, 0.8, 0.2, 0.0])
# A quadratic table: knots 0, 1, 2.2, 3 and one sample inside each knot interval (not at its middle).
QUADRATIC_T = np.array([0.0, 0.4, 1.0, 1.3, 2.2, 2.7, 3.0])
QUADRATIC_V = np.array([0.0, 1.0, -0.5, 0.8, 0.2, -0.3, 0.0])
KINDS = ["zoh", "linear", "quadratic", "cubic"]


def _samples(kind: str) -> tuple[np.ndarray, np.ndarray]:
    return (QUADRATIC_T, QUADRATIC_V) if kind == "quadratic" else (SAMPLES_T, SAMPLES_V)


def _definition(kind: str, t: np.ndarray) -> np.ndarray:
    """Each interpolation written out (held ends)."""
    ts, vs = _samples(kind)
    if kind == "zoh":
        k = np.searchsorted(ts, t, side="right") - 1
        return vs[np.clip(k, 0, len(vs) - 1)]
    if kind == "linear":
        return np.interp(t, ts, vs)
    inside = np.clip(t, ts[0], ts[-1])
    if kind == "cubic":
        return CubicSpline(ts, vs, bc_type="not-a-knot")(inside)
    # Lagrange's quadratic through (a, c, b) = (t_2j, t_2j+1, t_2j+2) on each knot interval
    j = np.clip((np.searchsorted(ts, inside, side="right") - 1) // 2, 0, (len(ts) - 3) // 2)
    a, c, b = ts[2 * j], ts[2 * j + 1], ts[2 * j + 2]
    va, vc, vb = vs[2 * j], vs[2 * j + 1], vs[2 * j + 2]
    s = inside
    return (va * (s - c) * (s - b) / ((a - c) * (a - b)) + vc * (s - a) * (s - b) / ((c - a) * (c - b))
            + vb * (s - a) * (s - c) / ((b - a) * (b - c)))


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
def test_each_interpolation_matches_its_definition_at_and_between_samples(oscillator, kind):
    ts, vs = _samples(kind)
    table = InputTable(ts, vs, interpolation=kind)
    t = np.concatenate([ts, np.linspace(-0.5, 3.5, 97)])
    assert np.allclose(table(t), _definition(kind, t), rtol=0, atol=1e-14)
    # the compiled code reads the same numbers
    system = compile_system(oscillator, inputs={"F": table})
    p = system.parameter_vector()
    Y = np.zeros((len(t), 2))
    assert np.allclose(system.input_values(t, Y, p)[:, 0], _definition(kind, t), rtol=0, atol=1e-14)


def test_a_quadratic_table_breaks_at_its_knots_only_and_reads_one_parabola_across_its_inner_sample(oscillator):
    table = InputTable(QUADRATIC_T, QUADRATIC_V, interpolation="quadratic")
    assert np.array_equal(table.breakpoints, QUADRATIC_T[0::2])
    # between two restarts (knots 1.0 and 2.2) the hint is their middle, 1.6, past the inner sample 1.3:
    # the piece read at t = 1.1 is still the knot interval's parabola
    system = compile_system(oscillator, inputs={"F": table})
    p = system.parameter_vector()
    system.law_block(p)[0] = 1.6
    t = np.array([1.0, 1.1, 1.3, 2.2])
    assert np.allclose(system.input_values(t, np.zeros((4, 2)), p)[:, 0], _definition("quadratic", t),
                       rtol=0, atol=1e-14)
    assert np.allclose(table(t, window=1.6), _definition("quadratic", t), rtol=0, atol=1e-14)


def test_a_hold_reads_the_interval_it_is_in_up_to_its_right_end(oscillator):
    # Between two restarts the integrator's last stage lands on the next sample: it must still see
    # the value before the jump (the hint is a time inside the interval).
    system = compile_system(oscillator, inputs={"F": InputTable(SAMPLES_T, SAMPLES_V, interpolation="zoh")})
    p = system.parameter_vector()
    system.law_block(p)[0] = 0.7  # inside [0.4, 1.0)
    assert system.input_values([1.0], np.zeros((1, 2)), p)[0, 0] == SAMPLES_V[1]
    system.law_block(p)[0] = np.nan
    assert system.input_values([1.0], np.zeros((1, 2)), p)[0, 0] == SAMPLES_V[2]


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("method", ["dop853", "RK45"])
def test_a_table_drives_the_oscillator_as_the_hand_written_equations_piece_by_piece(oscillator, kind, method):
    ts, vs = _samples(kind)
    table = InputTable(ts, vs, interpolation=kind)
    t = np.linspace(0, 3.5, 36)
    traj = simulate(oscillator, 3.5, t_eval=t, inputs={"F": table}, method=method, rtol=1e-10, atol=1e-12)
    # By hand: one solve per interval between samples, each with its own piece (no kink inside a step).
    edges = [0.0, *ts[1:], 3.5]
    y, xs = [0.1, 0.0], []
    for a, b in pairwise(edges):
        mid = 0.5 * (a + b)
        piece = (lambda s, m=mid: vs[np.searchsorted(ts, m, side="right") - 1]) if kind == "zoh" else \
            (lambda s: float(_definition(kind, np.array([s]))[0]))
        grid = t[(t >= a) & (t <= b)] if a == 0 else t[(t > a) & (t <= b)]
        wanted = grid if len(grid) and grid[-1] == b else np.append(grid, b)
        sol = _by_hand(lambda s, x, v, piece=piece: piece(s), (a, b), y, wanted)
        xs.append(sol.y[0, :len(grid)])
        y = sol.y[:, -1]
    assert np.abs(traj.q[:, 0] - np.concatenate(xs)).max() < 1e-8


def test_a_table_from_a_csv_file(tmp_path, oscillator):
    path = tmp_path / "push.csv"
    path.write_text("t,force\n" + "".join(f"{a},{b}\n" for a, b in zip(SAMPLES_T, SAMPLES_V, strict=True)))
    table = InputTable.from_csv(path, "force", interpolation="linear")
    assert np.array_equal(table.t, SAMPLES_T) and np.array_equal(table.values, SAMPLES_V)
    with pytest.raises(SimulationError, match="no column `push`.*its columns: t, force"):
        InputTable.from_csv(path, "push")
    # a trajectory file written by lagrangian begins with comment lines
    path.write_text("# lagrangian trajectory\n# parameters: m = 2\nt,force\n0,1\n0.5,2\n")
    assert InputTable.from_csv(path, "force").values.tolist() == [1.0, 2.0]
    path.write_text("t,force\n0,1\n0.5,oops\n")
    with pytest.raises(SimulationError, match="line 3: `oops` is not a number"):
        InputTable.from_csv(path, "force")


@pytest.mark.parametrize(("t", "v", "message"), [
    ([0.0, 1.0, 1.0], [0, 1, 2], "increase strictly"),
    ([0.0, 2.0, 1.0], [0, 1, 2], "increase strictly"),
    ([0.0, np.nan, 1.0], [0, 1, 2], "not a finite number"),
    ([0.0, 1.0], [0, np.nan], "not a finite number"),
    ([0.0, 1.0, 2.0], [0, 1], "3 times but 2 values"),
    ([0.0], [1.0], "at least 2"),
])
def test_a_bad_table_is_refused_clearly(t, v, message):
    with pytest.raises(SimulationError, match=message):
        InputTable(t, v)


def test_a_quadratic_table_needs_an_odd_number_of_samples():
    with pytest.raises(SimulationError, match="4 samples; a quadratic table needs an odd number"):
        InputTable([0.0, 1.0, 2.0, 3.0], [0, 1, 2, 3], interpolation="quadratic")


def test_an_unknown_interpolation_is_refused():
    with pytest.raises(SimulationError, match="unknown interpolation `spline`"):
        InputTable([0, 1], [0, 1], interpolation="spline")


# -- the slow path -------------------------------------------------------------------------------------
@pytest.mark.slow
def test_a_python_function_gives_the_motion_of_the_compiled_expression(oscillator):
    t = np.linspace(0, 4, 41)
    slow = simulate(oscillator, 4.0, t_eval=t, inputs={"F": lambda t, y: 2 * math.sin(3 * t) - 0.5 * y[1]})
    fast = simulate(oscillator, 4.0, t_eval=t, inputs={"F": "2*sin(3*t) - 0.5*x_dot"})
    assert np.abs(slow.q - fast.q).max() < 1e-12
    assert slow.rhs_calls == fast.rhs_calls
    assert np.allclose(slow.column("F"), fast.column("F"), atol=1e-12)


def test_a_failing_python_function_stops_the_run_with_its_error(oscillator):
    def push(t, y):
        if t > 0.5:
            raise ValueError("sensor lost")
        return 0.0

    with pytest.raises(SimulationError, match=r"input function of `F` failed at t = 0\.5.*sensor lost") as info:
        simulate(oscillator, 2.0, inputs={"F": push})
    assert isinstance(info.value.__cause__, ValueError)
    with pytest.raises(SimulationError, match="returned nan"):
        simulate(oscillator, 2.0, inputs={"F": lambda t, y: math.nan}, method="RK45")


# -- what is refused -----------------------------------------------------------------------------------------
@pytest.mark.parametrize(("inputs", "message"), [
    ({"G": 1.0}, "`G` is not an input of `forced oscillator` \\(its inputs: F\\)"),
    ({"k": 1.0}, "`k` is a parameter of `forced oscillator`, not an input"),
    ({"F": "2*sin(3*"}, "In the input `F` = `2\\*sin\\(3\\*`"),
    ({"F": "y + 1"}, "unknown symbol `y`"),
    ({"F": "R0.x"}, "unknown frame `R0`"),
    ({"F": [1, 2]}, "is a list"),
    ({"F": math.inf}, "not a finite number"),
    ({"F": True}, "give a number, an expression"),
])
def test_bad_inputs_are_refused_clearly(oscillator, inputs, message):
    with pytest.raises(SimulationError, match=message):
        simulate(oscillator, 1.0, inputs=inputs)


@pytest.mark.slow
def test_an_input_given_twice_is_refused(oscillator):
    with pytest.raises(SimulationError, match="given both as a parameter value and by the inputs' law"):
        simulate(oscillator, 1.0, inputs={"F": "sin(t)"}, parameters={"F": 1.0})


# -- [controls], constrained models, no C compiler ---------------------------------------------------------------------
@pytest.mark.slow
def test_the_models_controls_run_unless_inputs_override_them():
    text = OSCILLATOR + '\n[controls]\nF = "-k1*x - k2*x_dot"\n'
    eom = lagrangian.derive(lagrangian.parse_model(text))
    t = np.linspace(0, 3, 31)
    traj = simulate(eom, 3.0, t_eval=t)
    ref = _by_hand(lambda t, x, v: -3.0 * x - 1.5 * v, (0, 3), [0.1, 0.0], t)
    assert np.abs(traj.q[:, 0] - ref.y[0]).max() < 1e-8
    off = simulate(eom, 3.0, t_eval=t, inputs={"F": 0})
    free = _by_hand(lambda t, x, v: 0.0, (0, 3), [0.1, 0.0], t)
    assert np.abs(off.q[:, 0] - free.y[0]).max() < 1e-8


@pytest.mark.slow
def test_a_model_with_complementary_constraints_takes_the_inputs():
    # The pendulum in Cartesian coordinates (the rod a complementary constraint) pushed horizontally by
    # F(t) against the same pendulum written by hand in its angle: m l² θ̈ = −m g l sin θ + F l cos θ.
    from lagrangian_test_support import example_text

    text = example_text("pendulum_tension.toml").replace(
        "[loads]", '[inputs]\nF = { unit = "N" }\n\n[loads]\npush = { force = "F*R0.x", at = "P" }')
    model = lagrangian.parse_model(text)
    m, l, g = (model.parameter_values[k] for k in ("m", "l", "g"))
    x0, y0 = (c.initial for c in model.coordinates)
    theta0 = math.atan2(x0, -y0)
    t = np.linspace(0, 2, 21)
    table = InputTable([0.0, 0.7, 1.4], [0.0, 1.5, -1.0], interpolation="zoh")
    for given, force in (("0.5*sin(3*t)", lambda s: 0.5 * math.sin(3 * s)),
                         (table, lambda s: float(table(s)))):
        traj = simulate(model, 2.0, t_eval=t, inputs={"F": given})

        def f(s, y, force=force):
            return [y[1], (-m * g * l * math.sin(y[0]) + force(s) * l * math.cos(y[0])) / (m * l * l)]

        ref = solve_ivp(f, (0, 2), [theta0, 0.0], t_eval=t, rtol=1e-12, atol=1e-12, method="DOP853",
                        max_step=0.01)  # the hold's jumps, crossed by small steps
        assert np.abs(traj.q[:, 0] - l * np.sin(ref.y[0])).max() < 1e-6
        assert traj.integrals == ()  # the push works: no energy to monitor


@pytest.mark.slow
def test_the_symengine_fallback_applies_the_same_law(oscillator):
    law = {"F": "2*sin(3*t) - k2*x_dot"}
    c = compile_system(oscillator, inputs=law)
    s = compile_system(oscillator, inputs=law, backend="symengine")
    rng = np.random.default_rng(3)
    T, Y = rng.uniform(0, 2, 7), rng.normal(size=(7, 2))
    assert np.allclose(s.rhs(T, Y, s.parameter_vector()), c.rhs(T, Y, c.parameter_vector()), rtol=1e-13, atol=1e-13)


def test_without_a_compiler_a_hold_reads_the_interval_the_integrator_is_in(oscillator):
    # The Python law has its own hint: SciPy's solves between samples see each interval's value to its end.
    table = InputTable(SAMPLES_T, SAMPLES_V, interpolation="zoh")
    t = np.linspace(0, 3, 31)
    compiled = simulate(oscillator, 3.0, t_eval=t, inputs={"F": table})
    python = simulate(compile_system(oscillator, inputs={"F": table}, backend="symengine"), 3.0, t_eval=t,
                      method="DOP853")
    assert np.abs(python.q - compiled.q).max() < 1e-8


@pytest.mark.slow
def test_the_analytic_jacobian_refuses_a_law_it_cannot_see(oscillator):
    f = compile_system(oscillator, inputs={"F": "-k1*x"}).rhs_function()
    assert np.allclose(f(0.0, np.array([0.1, 0.0])), [0.0, (-K * 0.1 - 3.0 * 0.1) / M])
    with pytest.raises(SimulationError, match="analytic Jacobian differentiates M and F with the inputs as constants"):
        f.jac(0.0, np.array([0.1, 0.0]))
