"""``eom.to_sympy()``: SymPy objects with the engine's value, named as in the model, and SymPy mechanics' form."""

from __future__ import annotations

import numpy as np
import pytest
import sympy
from lagrangian_test_support import eom_of, random_states
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

import lagrangian

ROUND_TRIP = ["simple_pendulum.toml", "double_pendulum.toml", "cart_pendulum.toml", "lagrange_top.toml",
              "spherical_pendulum.toml", "kapitza_pendulum.toml", "foucault_pendulum.toml",
              "bead_rotating_hoop.toml"]


@pytest.mark.parametrize("name", ROUND_TRIP)
def test_qdd_from_the_sympy_form_is_the_engines(name: str) -> None:
    """q̈ = M⁻¹F from the SymPy Matrix M, F, lambdified, equals the compiled q̈ at random states (1e-12)."""
    eom = eom_of(name)
    s = eom.to_sympy()
    system = lagrangian.compile_system(eom)
    p = system.parameter_vector()
    args = [s.t, *s.q, *s.qd, *s.parameters]
    M = sympy.lambdify(args, s.M, "numpy")
    F = sympy.lambdify(args, s.F, "numpy")
    pvals = [s.values[x] for x in s.parameters]
    for k, state in enumerate(random_states(name, eom.coordinates, 8, seed=12)):
        t = 0.3 * k
        q = [state[c] for c in eom.coordinates]
        qd = [state[c + "_dot"] for c in eom.coordinates]
        qdd = np.linalg.solve(np.asarray(M(t, *q, *qd, *pvals), float),
                              np.asarray(F(t, *q, *qd, *pvals), float).ravel())
        ours = system.rhs(t, np.array(q + qd), p)[len(q):]
        np.testing.assert_allclose(qdd, ours, rtol=1e-12, atol=1e-12)


def test_symbols_are_named_as_in_the_model() -> None:
    eom = lagrangian.derive(lagrangian.lagrange_top())
    s = eom.to_sympy()
    assert s.coordinates == ("psi", "theta", "phi")
    assert [str(x) for x in s.q] == ["psi", "theta", "phi"]
    assert [str(x) for x in s.qd] == ["psi_dot", "theta_dot", "phi_dot"]
    assert [str(x) for x in s.qdd] == ["psi_ddot", "theta_ddot", "phi_ddot"]
    assert [str(x) for x in s.parameters] == ["m", "g", "a", "A", "C"]
    assert all(isinstance(x, sympy.Symbol) for x in (*s.q, *s.qd, *s.parameters, s.t))
    assert isinstance(s.M, sympy.MutableDenseMatrix) and s.M.shape == (3, 3) and s.F.shape == (3, 1)
    assert s.first_integrals is None  # the analysis stage's: `lagrangian.sympy_equations` (tests/output)
    theta, theta_dot, theta_ddot = sympy.symbols("theta theta_dot theta_ddot")
    psi_dot, phi_dot = sympy.symbols("psi_dot phi_dot")
    m, g, a, A, C = s.parameters
    # The seed's L(θ): A θ̈ − A ψ̇² sinθ cosθ + C ψ̇ sinθ (φ̇ + ψ̇ cosθ) = m g a sinθ.
    eq = s.equations[1]
    assert isinstance(eq, sympy.Eq)
    expected = A * theta_ddot - A * psi_dot**2 * sympy.sin(theta) * sympy.cos(theta) \
        + C * psi_dot * sympy.sin(theta) * (phi_dot + psi_dot * sympy.cos(theta))
    assert sympy.expand(eq.lhs - expected) == 0
    assert sympy.expand(eq.rhs - m * g * a * sympy.sin(theta)) == 0
    assert s.L is not None and sympy.expand(s.L - (s.T - s.U)) == 0
    assert s.multipliers == () and s.multiplier_formulas == {}


def _numeric(expr: sympy.Basic, s, rng: np.random.Generator) -> float:  # type: ignore[no-untyped-def]
    """Value of a time-function expression at a random (q, q̇, q̈, t), derivatives replaced first."""
    subs = {}
    for q, qd, qdd in zip(s.q, s.qd, s.qdd, strict=True):
        subs[qdd], subs[qd], subs[q] = rng.uniform(-1, 1, 3)
    out = expr.subs({k: subs[k] for k in s.qdd}).subs({k: subs[k] for k in s.qd}).subs(
        {k: subs[k] for k in s.q})
    return float(out.subs(s.values).subs(s.t, rng.uniform(0, 2)))


@pytest.mark.slow
@pytest.mark.parametrize("name", ["lagrange_top.toml", "double_pendulum.toml", "kapitza_pendulum.toml"])
def test_time_function_form_differentiates_correctly(name: str) -> None:
    """d/dt of T's dynamicsymbols form (SymPy's diff) equals the engine's total derivative d/dt(T)."""
    eom = eom_of(name)
    s = eom.to_sympy(time_functions=True)
    assert s.time_functions and s.t == dynamicsymbols._t
    assert all(q == dynamicsymbols(c) for q, c in zip(s.q, s.coordinates, strict=True))
    assert all(qd == q.diff(s.t) and qdd == q.diff(s.t, 2) for q, qd, qdd in zip(s.q, s.qd, s.qdd, strict=True))
    from lagrangian.dynamics._sympy_form import _convert  # the same structural conversion, of the engine's d/dt(T)

    dT_engine = _convert(eom.kinematics.d_dt(eom.T)).xreplace(
        {sympy.Symbol(f"{c}_{k}"): v for c, qd, qdd in zip(s.coordinates, s.qd, s.qdd, strict=True)
         for k, v in (("dot", qd), ("ddot", qdd))} | {sympy.Symbol(c): q for c, q in zip(s.coordinates, s.q, strict=True)})
    dT_sympy = sympy.diff(s.T, s.t)
    for seed in range(5):
        a, b = (_numeric(e, s, np.random.default_rng(seed)) for e in (dT_sympy, dT_engine))
        assert a == pytest.approx(b, rel=1e-12, abs=1e-12)


@pytest.mark.slow
def test_time_function_form_drops_into_sympy_mechanics() -> None:
    """SymPy's LagrangesMethod on our L(t) finds our mass matrix and forcing (the double pendulum)."""
    eom = eom_of("double_pendulum.toml")
    s = eom.to_sympy(time_functions=True)
    lm = LagrangesMethod(s.L, list(s.q))
    lm.form_lagranges_equations()
    n = len(s.q)
    M_theirs = lm.mass_matrix_full[n:, n:]
    F_theirs = lm.forcing_full[n:, :]
    assert sympy.simplify(M_theirs - s.M) == sympy.zeros(n, n)
    assert sympy.simplify(F_theirs - s.F) == sympy.zeros(n, 1)


def test_constrained_model_has_its_multipliers_and_formulas() -> None:
    """The pendulum with its tension kept: λ in the equations, A, and λ(q, q̇) in closed form."""
    eom = eom_of("pendulum_tension.toml")
    s = eom.to_sympy()
    assert [str(x) for x in s.multipliers] == ["lambda_length"]
    assert s.A.shape == (1, len(s.q))
    assert set(s.multiplier_formulas) == {"lambda_length"}
    assert any(eq.rhs.has(s.multipliers[0]) for eq in s.equations)
    assert s.L == s.T - s.U  # gravity and a perfect time-independent constraint: conservative
    tf = eom.to_sympy(time_functions=True)
    assert tf.multipliers == (dynamicsymbols("lambda_length"),)
    assert not any(eq.has(sympy.Symbol("lambda_length")) for eq in tf.equations)
