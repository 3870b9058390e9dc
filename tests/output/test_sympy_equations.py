"""``lagrangian.sympy_equations(eom)``: the SymPy form of the equations with the first integrals, in the same symbols."""

from __future__ import annotations

import numpy as np
import pytest
import sympy

import lagrangian


@pytest.fixture(scope="module")
def top() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.lagrange_top())


def test_the_tops_integrals_are_the_seeds(top: lagrangian.EquationsOfMotion) -> None:
    s = lagrangian.sympy_equations(top)
    assert set(s.first_integrals) == {"K", "H", "E"}
    theta, psi_dot, phi_dot = sympy.symbols("theta psi_dot phi_dot")
    m, g, a, A, C = s.parameters
    # Seed, section III: H = C (φ̇ + ψ̇ cosθ), the spin about the axis of symmetry.
    assert sympy.expand(s.first_integrals["H"] - C * (phi_dot + psi_dot * sympy.cos(theta))) == 0
    assert sympy.expand(s.first_integrals["E"] - (s.T + s.U)) == 0
    bare = top.to_sympy()
    assert bare.first_integrals is None and bare.equations == s.equations


def test_integrals_in_time_functions_are_constant_along_the_equations(top: lagrangian.EquationsOfMotion) -> None:
    """d/dt of each integral (SymPy's diff of its θ(t) form) vanishes where q̈ = M⁻¹F, at random states."""
    s = lagrangian.sympy_equations(top, time_functions=True)
    assert s.time_functions and not any(x.has(sympy.Symbol("theta_dot")) for x in s.first_integrals.values())
    rng = np.random.default_rng(3)
    for _ in range(3):
        state = dict(zip(s.q, rng.uniform(0.3, 1.2, 3), strict=True)) | dict(zip(s.qd, rng.uniform(-2, 2, 3), strict=True))

        def at(expr: sympy.Basic, state: dict = state) -> sympy.Basic:
            # rates first: Derivative(θ(t), t) contains θ(t)
            return expr.subs({k: state[k] for k in s.qd}).subs({k: state[k] for k in s.q}).subs(s.values)

        qdd = np.linalg.solve(np.array(at(s.M), float), np.array(at(s.F), float).ravel())
        for name, integral in s.first_integrals.items():
            rate = sympy.diff(integral, s.t).subs(dict(zip(s.qdd, qdd, strict=True)))
            assert float(at(rate)) == pytest.approx(0.0, abs=1e-9), name
