"""simulate(..., sensitivities=...): ∂y/∂p and ∂y/∂y(t0) against a closed form and central differences.

References: the linear oscillator m ẍ + k x = 0 has x(t) = x0 cos ωt + (v0/ω) sin ωt, ω = √(k/m),
differentiated by hand below; for the others, central differences of `simulate` with a step
h = ε^(1/3) max(1, |p|) (truncation O(h²) and the integration error over h both near 1e-7 at the
tolerances used).
"""

import math
import warnings

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR as EXAMPLES
from urdf_robots import DOUBLE_PENDULUM

import lagrangian
from lagrangian.errors import SimulationError
from lagrangian.model.urdf import parse_urdf
from lagrangian.numerics import Sensitivities, compile_system, simulate
from lagrangian.numerics._forward import forward_jacobian

#: Central-difference step, relative: ε^(1/3) balances the O(h²) truncation against round-off ε/h.
FD_STEP = np.finfo(float).eps ** (1 / 3)

OSCILLATOR = """
[model]
name = "oscillator"
[parameters]
m = { value = 2.0 }
k = { value = 8.0 }
[coordinates]
x = { initial = 0.3, rate = 0.5 }
[frames]
R0 = { axes = ["x0", "y0", "z0"] }
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = { potential = "1/2*k*x^2" }
"""


@pytest.fixture(scope="module")
def oscillator():
    return compile_system(lagrangian.derive(lagrangian.parse_model(OSCILLATOR)))


@pytest.fixture(scope="module")
def pendulum():
    return compile_system(lagrangian.derive(lagrangian.load_model(EXAMPLES / "simple_pendulum.toml")))


def test_oscillator_sensitivities_equal_the_closed_form(oscillator):
    m, k, x0, v0 = 2.0, 8.0, 0.3, 0.5
    tr = simulate(oscillator, 3.0, sensitivities=["k", "m", "x(t0)", "x_dot(t0)"], n_out=61, rtol=1e-12, atol=1e-12)
    t = tr.t
    w = math.sqrt(k / m)
    # x = x0 cos wt + v0/w sin wt; dx/dw = -x0 t sin wt + v0 (t cos wt / w - sin wt / w²); dw/dk = 1/(2 w m)
    dx_dw = -x0 * t * np.sin(w * t) + v0 * (t * np.cos(w * t) / w - np.sin(w * t) / w**2)
    dv_dw = -x0 * (np.sin(w * t) + w * t * np.cos(w * t)) - v0 * t * np.sin(w * t)
    dw_dk, dw_dm = 1 / (2 * w * m), -k / (2 * w * m**2)
    np.testing.assert_allclose(tr.sensitivity("k"), np.column_stack([dx_dw, dv_dw]) * dw_dk, atol=1e-10)
    np.testing.assert_allclose(tr.sensitivity("m"), np.column_stack([dx_dw, dv_dw]) * dw_dm, atol=1e-10)
    np.testing.assert_allclose(tr.sensitivity("x(t0)"), np.column_stack([np.cos(w * t), -w * np.sin(w * t)]),
                               atol=1e-10)
    np.testing.assert_allclose(tr.sensitivity("x_dot(t0)"), np.column_stack([np.sin(w * t) / w, np.cos(w * t)]),
                               atol=1e-10)
    assert tr.column("d(x)/d(k)") is tr.extra["d(x)/d(k)"]
    assert tr.sensitivity_names == ("k", "m", "x(t0)", "x_dot(t0)")


def _central(system, name, t_end, n_out, **options):
    values = {p: v for p, v in system.eom.model.parameter_values.items() if v is not None}
    h = FD_STEP * max(1.0, abs(values[name]))
    runs = [simulate(system, t_end, n_out=n_out, parameters={name: values[name] + s * h}, **options)
            for s in (1, -1)]
    return np.hstack([runs[0].q - runs[1].q, runs[0].qd - runs[1].qd]) / (2 * h)


def test_pendulum_sensitivities_equal_central_differences(pendulum):
    tr = simulate(pendulum, 4.0, sensitivities=["l", "g"], n_out=41, rtol=1e-12, atol=1e-12)
    for name in ("l", "g"):
        fd = _central(pendulum, name, 4.0, 41, rtol=1e-12, atol=1e-12)
        scale = np.abs(fd).max()
        np.testing.assert_allclose(tr.sensitivity(name), fd, atol=2e-7 * scale, err_msg=name)


def test_fixed_steps_give_the_exact_derivative_of_the_numerical_solution(pendulum):
    # With fixed steps the discrete map is smooth in p, and Runge-Kutta commutes with differentiation:
    # S is the derivative of the numerical solution itself, to the central difference's O(h²).
    tr = simulate(pendulum, 2.0, sensitivities=["l"], dt=0.05, n_out=21)
    fd = _central(pendulum, "l", 2.0, 21, dt=0.05)
    np.testing.assert_allclose(tr.sensitivity("l"), fd, atol=1e-9 * np.abs(fd).max())


def test_the_state_is_the_plain_runs_bit_for_bit_unless_the_sensitivities_join_the_error_norm(pendulum):
    plain = simulate(pendulum, 5.0, n_out=51, rtol=1e-8, atol=1e-8)
    with_s = simulate(pendulum, 5.0, n_out=51, rtol=1e-8, atol=1e-8, sensitivities=["l"])
    assert np.array_equal(plain.q, with_s.q) and np.array_equal(plain.qd, with_s.qd)
    assert plain.steps == with_s.steps
    controlled = simulate(pendulum, 5.0, n_out=51, rtol=1e-8, atol=1e-8,
                          sensitivities=Sensitivities(("l",), in_error_norm=True))
    assert controlled.steps > plain.steps  # S grows like t: it asks for shorter steps
    exact = simulate(pendulum, 5.0, n_out=51, rtol=1e-13, atol=1e-13, sensitivities=["l"]).sensitivity("l")
    error_free = np.abs(with_s.sensitivity("l") - exact).max()
    error_controlled = np.abs(controlled.sensitivity("l") - exact).max()
    assert error_controlled < error_free


def test_sensitivities_through_the_recursive_form_equal_central_differences():
    # A URDF double pendulum with its links' inertial parameters symbolic, derived by the recursive
    # algorithms: the Jacobian goes through the named intermediates (and through m·(h/m)).
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = parse_urdf(DOUBLE_PENDULUM, inertial_parameters=True)
    system = compile_system(lagrangian.derive(model, formulation="recursive"))
    assert system.eom.recursive is not None
    names = ["m_rod2", "mz_rod1", "Iyy_rod2", "shoulder(t0)"]
    initial = {"shoulder": 0.7, "elbow": -0.4}
    tr = simulate(system, 1.5, sensitivities=names, n_out=16, initial=initial, rtol=1e-12, atol=1e-12)
    for name in names[:3]:
        fd = _central(system, name, 1.5, 16, initial=initial, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(tr.sensitivity(name), fd, atol=2e-7 * np.abs(fd).max(), err_msg=name)
    h = FD_STEP * 0.7
    runs = [simulate(system, 1.5, n_out=16, initial={**initial, "shoulder": 0.7 + s * h}, rtol=1e-12, atol=1e-12)
            for s in (1, -1)]
    fd = np.hstack([runs[0].q - runs[1].q, runs[0].qd - runs[1].qd]) / (2 * h)
    np.testing.assert_allclose(tr.sensitivity("shoulder(t0)"), fd, atol=2e-7 * np.abs(fd).max())


def test_forward_jacobian_through_intermediates_equals_the_expanded_derivative():
    x, y, a = se.symbols("x y a")
    w0, w1, w2 = se.Dummy("w0"), se.Dummy("w1"), se.Dummy("w2")
    definitions = [(w0, se.sin(x) * a), (w1, w0 * y + x**2), (w2, w1 / (1 + w0**2))]
    outputs = [w2 * y + w0, w1 - a]
    jac = forward_jacobian(definitions, outputs, [x, y])
    expanded = [o.xreplace({w2: definitions[2][1]}).xreplace({w1: definitions[1][1]}).xreplace({w0: definitions[0][1]})
                for o in outputs]
    values = {x: 0.3, y: -1.2, a: 0.7}
    known = {}
    for sym, expr in jac.definitions:
        known[sym] = float(expr.xreplace(values).xreplace(known)) if expr.free_symbols else float(expr)
    for i, out in enumerate(expanded):
        for j, v in enumerate((x, y)):
            expected = float(out.diff(v).xreplace(values))
            got = float(se.sympify(jac.jacobian[i][j]).xreplace(values).xreplace(known))
            assert got == pytest.approx(expected, rel=1e-13)


@pytest.mark.parametrize("names, message", [
    (["tau"], "is an input"),
    (["nope"], "neither a parameter"),
    (["x"], r"x\(t0\)"),
    (["k", "k"], "twice"),
])
def test_bad_sensitivity_names_are_refused_clearly(names, message):
    driven = OSCILLATOR.replace("[coordinates]", "[inputs]\ntau = {}\n[coordinates]") + \
        'push = { force = "tau*R0.x", at = "P" }\n'
    with pytest.raises(SimulationError, match=message):
        simulate(lagrangian.parse_model(driven), 1.0, sensitivities=names)


def test_sensitivities_refuse_other_methods_and_events(pendulum):
    with pytest.raises(SimulationError, match="dop853"):
        simulate(pendulum, 1.0, method="gauss-legendre", sensitivities=["l"])
    with pytest.raises(SimulationError, match="events"):
        simulate(pendulum, 1.0, events=["theta"], sensitivities=["l"])
    with pytest.raises(SimulationError, match="complementary constraints"):
        simulate(lagrangian.load_model(EXAMPLES / "pendulum_tension.toml"), 1.0, sensitivities=["l"])
