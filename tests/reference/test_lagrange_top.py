"""The seed's worked example (SMP5, chapter IV, "Mouvement de Lagrange"), typed by hand.

Every formula below is copied from the course text in SymPy, independently of the
engine's code path, and the engine's T, U, the terms of each Lagrange equation
L(ψ), L(θ), L(φ), and the first integrals K, H and the energy must differ from them
by something SymPy simplifies to 0.
"""

from __future__ import annotations

import pytest
import sympy as sp
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian

# -- the seed's notation ---------------------------------------------------------------
m, g, a, A, C = sp.symbols("m g a A C")
t = sp.Symbol("t")
psi, theta, phi = sp.symbols("psi theta phi")
psi_d, theta_d, phi_d = sp.symbols("psi_dot theta_dot phi_dot")
psi_dd, theta_dd, phi_dd = sp.symbols("psi_ddot theta_ddot phi_ddot")
Q, QD, QDD = (psi, theta, phi), (psi_d, theta_d, phi_d), (psi_dd, theta_dd, phi_dd)


def d_dt(f: sp.Expr) -> sp.Expr:
    """Total time derivative along q(t): Σ ∂f/∂q q̇ + ∂f/∂q̇ q̈ (the seed's d/dt[...])."""
    return sum((f.diff(q) * qd + f.diff(qd) * qdd for q, qd, qdd in zip(Q, QD, QDD, strict=True)), sp.Integer(0))


# T(S/R0) = ½ A [θ̇² + ψ̇² sin²θ] + ½ C (φ̇ + ψ̇ cos θ)²
T_SEED = sp.Rational(1, 2) * A * (theta_d**2 + psi_d**2 * sp.sin(theta) ** 2) \
    + sp.Rational(1, 2) * C * (phi_d + psi_d * sp.cos(theta)) ** 2
# U_p(S/R0) = m g a cos θ + cste
U_SEED = m * g * a * sp.cos(theta)

# L(ψ): ∂T/∂ψ̇ = A ψ̇ sin²θ + C cos θ (φ̇ + ψ̇ cos θ);  ∂T/∂ψ = 0;  ∂U/∂ψ = 0;  Q_ψ = 0
K_SEED = A * psi_d * sp.sin(theta) ** 2 + C * sp.cos(theta) * (phi_d + psi_d * sp.cos(theta))
# L(φ): ∂T/∂φ̇ = C (φ̇ + ψ̇ cos θ);  ∂T/∂φ = 0;  ∂U/∂φ = 0;  Q_φ = 0
H_SEED = C * (phi_d + psi_d * sp.cos(theta))
# L(θ): ∂T/∂θ̇ = A θ̇;  ∂T/∂θ = A ψ̇² sin θ cos θ + C ψ̇ sin θ (φ̇ + ψ̇ cos θ);  ∂U/∂θ = −m g a sin θ;  Q_θ = 0
# Erratum: the seed prints "+ C ψ̇ sin θ (φ̇ + ψ̇ cos θ)" in ∂T/∂θ, but differentiating its own T
# gives "− C ψ̇ sin θ (φ̇ + ψ̇ cos θ)", and its final L(θ) below (… + C ψ̇ sin θ (φ̇ + ψ̇ cos θ) = m g a
# sin θ, i.e. −∂T/∂θ) uses the minus sign.  The sign is corrected here; see test_seed_erratum.
DT_DTHETA_AS_PRINTED = A * psi_d**2 * sp.sin(theta) * sp.cos(theta) \
    + C * psi_d * sp.sin(theta) * (phi_d + psi_d * sp.cos(theta))
SEED_TERMS = {
    "psi": dict(dT_dqd=K_SEED, dT_dq=sp.Integer(0), dU_dq=sp.Integer(0), Q_nc=sp.Integer(0)),
    "theta": dict(dT_dqd=A * theta_d,
                  dT_dq=A * psi_d**2 * sp.sin(theta) * sp.cos(theta)
                  - C * psi_d * sp.sin(theta) * (phi_d + psi_d * sp.cos(theta)),
                  dU_dq=-m * g * a * sp.sin(theta), Q_nc=sp.Integer(0)),
    "phi": dict(dT_dqd=H_SEED, dT_dq=sp.Integer(0), dU_dq=sp.Integer(0), Q_nc=sp.Integer(0)),
}
# The three equations as the seed writes them, as (left side, right side):
SEED_EQUATIONS = {
    # d/dt[A ψ̇ sin²θ + C cos θ (φ̇ + ψ̇ cos θ)] = 0
    "psi": (d_dt(K_SEED), sp.Integer(0)),
    # A θ̈ − A ψ̇² sin θ cos θ + C ψ̇ sin θ (φ̇ + ψ̇ cos θ) = m g a sin θ
    "theta": (A * theta_dd - A * psi_d**2 * sp.sin(theta) * sp.cos(theta)
              + C * psi_d * sp.sin(theta) * (phi_d + psi_d * sp.cos(theta)), m * g * a * sp.sin(theta)),
    # d/dt[C (φ̇ + ψ̇ cos θ)] = 0
    "phi": (d_dt(H_SEED), sp.Integer(0)),
}
# Energy integral: ½ A [θ̇² + ψ̇² sin²θ] + ½ C (φ̇ + ψ̇ cos θ)² + m g a cos θ = cste
E_SEED = T_SEED + U_SEED


def is_zero(expr: sp.Expr) -> bool:
    expr = sp.expand(expr)
    return expr == 0 or sp.simplify(sp.trigsimp(expr)) == 0


def sym(expr) -> sp.Expr:  # noqa: ANN001 - a SymEngine expression
    return sp.sympify(expr._sympy_() if hasattr(expr, "_sympy_") else expr)


@pytest.fixture(scope="module", params=["example file", "zoo"])
def eom(request: pytest.FixtureRequest) -> lagrangian.EquationsOfMotion:
    if request.param == "example file":
        model = lagrangian.load_model(EXAMPLES_DIR / "lagrange_top.toml")
    else:
        model = lagrangian.lagrange_top()
    return lagrangian.derive(model)


def test_seed_formulas_are_self_consistent() -> None:
    """Guard for the typing above: the seed's partial derivatives are those of its T and U."""
    for q, qd, name in zip(Q, QD, ("psi", "theta", "phi"), strict=True):
        terms = SEED_TERMS[name]
        assert is_zero(T_SEED.diff(qd) - terms["dT_dqd"])
        assert is_zero(T_SEED.diff(q) - terms["dT_dq"])
        assert is_zero(U_SEED.diff(q) - terms["dU_dq"])
        lhs, rhs = SEED_EQUATIONS[name]
        assert is_zero((lhs - rhs) - (d_dt(terms["dT_dqd"]) - terms["dT_dq"] + terms["dU_dq"] - terms["Q_nc"]))


def test_seed_erratum() -> None:
    """The seed's printed ∂T/∂θ disagrees with its T and with its own L(θ); the corrected one agrees."""
    assert not is_zero(T_SEED.diff(theta) - DT_DTHETA_AS_PRINTED)
    lhs, rhs = SEED_EQUATIONS["theta"]
    assert is_zero(lhs - (d_dt(A * theta_d) - SEED_TERMS["theta"]["dT_dq"]))
    assert not is_zero(lhs - (d_dt(A * theta_d) - DT_DTHETA_AS_PRINTED))


def test_coordinates_are_the_euler_angles(eom: lagrangian.EquationsOfMotion) -> None:
    assert eom.coordinates == ("psi", "theta", "phi")
    assert [str(s) for s in eom.q] == ["psi", "theta", "phi"]
    assert [str(s) for s in eom.qd] == ["psi_dot", "theta_dot", "phi_dot"]
    assert [str(s) for s in eom.qdd] == ["psi_ddot", "theta_ddot", "phi_ddot"]


def test_kinetic_energy(eom: lagrangian.EquationsOfMotion) -> None:
    assert is_zero(sym(eom.T) - T_SEED)
    # T is the fixed-point formula ½ Ω·Π_O Ω, for the single body S
    assert [term.formula for term in eom.T_terms] == ["fixed point"]


def test_potential_energy(eom: lagrangian.EquationsOfMotion) -> None:
    # U is defined up to a constant: compare gradients, then the values at one point.
    diff = sym(eom.U) - U_SEED
    assert all(is_zero(diff.diff(q)) for q in Q)
    assert diff.free_symbols <= {m, g, a, A, C}
    assert is_zero(diff)  # the engine drops the constant, as the seed does


@pytest.mark.parametrize("name", ["psi", "theta", "phi"])
def test_lagrange_equation_terms(eom: lagrangian.EquationsOfMotion, name: str) -> None:
    eq = eom.equation(name)
    for field, expected in SEED_TERMS[name].items():
        assert is_zero(sym(getattr(eq, field)) - expected), f"L({name}): {field} = {getattr(eq, field)}"


@pytest.mark.parametrize("name", ["psi", "theta", "phi"])
def test_lagrange_equation(eom: lagrangian.EquationsOfMotion, name: str) -> None:
    eq = eom.equation(name)
    lhs, rhs = SEED_EQUATIONS[name]
    # the same equation, side by side: Γ_i and −∂U/∂q_i + Q_i(nc)
    assert is_zero(sym(eq.lhs) - lhs), f"L({name}): Γ = {eq.lhs}"
    assert is_zero(sym(eq.rhs) - rhs), f"L({name}): right side = {eq.rhs}"


def test_theta_equation_with_H(eom: lagrangian.EquationsOfMotion) -> None:
    """The seed's second form: A θ̈ − A ψ̇² sin θ cos θ + H ψ̇ sin θ = m g a sin θ, H = C(φ̇ + ψ̇ cos θ)."""
    H = sp.Symbol("H")
    seed = A * theta_dd - A * psi_d**2 * sp.sin(theta) * sp.cos(theta) + H * psi_d * sp.sin(theta) \
        - m * g * a * sp.sin(theta)
    eq = eom.equation("theta")
    assert is_zero(sym(eq.lhs - eq.rhs) - seed.subs(H, H_SEED))


def test_matrix_form_solves_the_seed_equations(eom: lagrangian.EquationsOfMotion) -> None:
    """M q̈ = F is the same system: each seed equation is a row of M q̈ − F."""
    for i, name in enumerate(("psi", "theta", "phi")):
        row = sum((sym(eom.M[i][j]) * QDD[j] for j in range(3)), sp.Integer(0)) - sym(eom.F[i])
        lhs, rhs = SEED_EQUATIONS[name]
        assert is_zero(row - (lhs - rhs)), f"row {name} of M q̈ − F"


def test_conservative(eom: lagrangian.EquationsOfMotion) -> None:
    assert eom.conservative
    assert eom.L is not None and is_zero(sym(eom.L) - (T_SEED - U_SEED))
    [weight] = eom.loads
    assert weight.kind == "gravity" and weight.potential is not None
    assert all(is_zero(sym(qi)) for qi in eom.Q_nc)


def test_first_integrals_are_K_H_and_E(eom: lagrangian.EquationsOfMotion) -> None:
    integrals = {fi.name: fi for fi in lagrangian.first_integrals(eom)}
    assert set(integrals) == {"K", "H", "E"}
    assert (integrals["K"].kind, integrals["K"].coordinate) == ("momentum", "psi")
    assert (integrals["H"].kind, integrals["H"].coordinate) == ("momentum", "phi")
    assert integrals["E"].kind == "energy"
    assert is_zero(sym(integrals["K"].expression) - K_SEED)
    assert is_zero(sym(integrals["H"].expression) - H_SEED)
    assert is_zero(sym(integrals["E"].expression) - E_SEED)


@pytest.mark.slow
def test_seed_integrals_are_constant_along_the_seed_equations() -> None:
    """Sanity of the reference itself: dK/dt, dH/dt, dE/dt vanish once q̈ solves the seed's equations."""
    solution = sp.solve([lhs - rhs for lhs, rhs in SEED_EQUATIONS.values()], QDD, dict=True)[0]
    for integral in (K_SEED, H_SEED, E_SEED):
        assert is_zero(d_dt(integral).subs(solution))
