"""``compiled.rhs_function()``: a plain f(t, y) for solve_ivp, fresh arrays, and an analytic Jacobian."""

from __future__ import annotations

import numpy as np
import pytest
from lagrangian_test_support import eom_of, random_states
from scipy.integrate import solve_ivp

import lagrangian


@pytest.fixture(scope="module")
def top():  # type: ignore[no-untyped-def]
    eom = lagrangian.derive(lagrangian.lagrange_top())
    return eom, lagrangian.compile_system(eom)


def test_each_call_returns_a_fresh_array(top) -> None:  # type: ignore[no-untyped-def]
    """PyDy's generated rhs returns one buffer for every call and corrupts solve_ivp: not ours."""
    _, system = top
    f = system.rhs_function()
    y1, y2 = np.array([0.0, 0.5, 0.0, 2.0, 0.1, 80.0]), np.array([0.3, 1.0, 0.2, -1.0, 0.4, 10.0])
    a = f(0.0, y1)
    kept = a.copy()
    b = f(0.0, y2)
    assert a is not b and not np.shares_memory(a, b)
    np.testing.assert_array_equal(a, kept)
    np.testing.assert_array_equal(a, system.rhs(0.0, y1, system.parameter_vector()))
    c = f(0.0, y1)
    assert c is not a and np.array_equal(c, a)
    J1, J2 = f.jac(0.0, y1), f.jac(0.0, y2)
    assert not np.shares_memory(J1, J2)


def test_solve_ivp_dop853_matches_simulate(top) -> None:  # type: ignore[no-untyped-def]
    eom, system = top
    traj = lagrangian.simulate(system, 2.0, rtol=1e-12, atol=1e-12, n_out=201)
    y0 = np.concatenate([traj.q[0], traj.qd[0]])
    f = system.rhs_function()
    sol = solve_ivp(f, (0.0, 2.0), y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=traj.t)
    assert sol.success
    np.testing.assert_allclose(sol.y[:3].T, traj.q, rtol=0, atol=1e-8)
    np.testing.assert_allclose(sol.y[3:].T, traj.qd, rtol=1e-8, atol=1e-8)


def test_parameters_override_the_models(top) -> None:  # type: ignore[no-untyped-def]
    _, system = top
    y = np.array([0.0, 0.5, 0.0, 0.0, 0.0, 0.0])
    a = system.rhs_function()(0.0, y)
    b = system.rhs_function({"g": 2 * system.eom.model.parameter_values["g"]})(0.0, y)
    assert b[4] == pytest.approx(2 * a[4])  # θ̈ = m g a sinθ / A at rest


@pytest.mark.parametrize("name", ["lagrange_top.toml", "double_pendulum.toml", "kapitza_pendulum.toml",
                                  "cart_pendulum.toml"])
def test_jacobian_is_analytic_and_matches_finite_differences(name: str) -> None:
    eom = eom_of(name)
    f = lagrangian.compile_system(eom).rhs_function()
    assert f.jacobian == "analytic"
    for k, s in enumerate(random_states(name, eom.coordinates, 4, seed=4)):
        y = np.array([s[c] for c in eom.coordinates] + [s[c + "_dot"] for c in eom.coordinates])
        t = 0.37 * k
        J = f.jac(t, y)
        h = 1e-6
        fd = np.column_stack([(f(t, y + h * e) - f(t, y - h * e)) / (2 * h) for e in np.eye(len(y))])
        np.testing.assert_allclose(J, fd, rtol=1e-6, atol=1e-6 * max(1.0, np.abs(fd).max()))


@pytest.mark.slow
def test_radau_with_the_jacobian(top) -> None:  # type: ignore[no-untyped-def]
    eom, system = top
    traj = lagrangian.simulate(system, 1.0, rtol=1e-12, atol=1e-12, n_out=11)
    y0 = np.concatenate([traj.q[0], traj.qd[0]])
    f = system.rhs_function()
    sol = solve_ivp(f, (0.0, 1.0), y0, method="Radau", jac=f.jac, rtol=1e-10, atol=1e-10, t_eval=traj.t)
    assert sol.success and sol.njev > 0
    np.testing.assert_allclose(sol.y[:3].T, traj.q, rtol=0, atol=1e-6)


def test_vectorized_calls(top) -> None:  # type: ignore[no-untyped-def]
    _, system = top
    f = system.rhs_function()
    Y = np.random.default_rng(1).uniform(0.2, 1.0, (6, 5))
    out = f(0.0, Y)
    assert out.shape == (6, 5)
    for k in range(5):
        np.testing.assert_array_equal(out[:, k], f(0.0, Y[:, k]))


@pytest.mark.slow
def test_a_constrained_model_is_refused_with_the_fix() -> None:
    system = lagrangian.compile_system(eom_of("pendulum_tension.toml"))
    with pytest.raises(lagrangian.SimulationError, match="differential-algebraic") as info:
        system.rhs_function()
    assert "lagrangian.simulate" in str(info.value.fix)
