"""The energy balance dE/dt = P_nc (`lagrangian.analysis.energy_balance`).

Three independent checks of the power P_nc the module returns:

1. symbolically, d/dt(T + U) along the equations (q̈ = M⁻¹F substituted) minus P_nc is
   identically zero (`is_zero`), for every example and for damped, driven and rheonomic
   models;
2. numerically, at random states of every example (complementary multipliers λ drawn at
   random too: the balance holds for any λ, their power being a term of its own; the rates
   projected onto the complementary rows A q̇ + b = 0, where that power is −Σ λ_k b_k);
3. along simulated motions, E(t) − E(0) equals ∫ P_nc dt (Simpson's rule on the output grid).

Closed forms pin the individual terms: the power of a hoop driven at Ω is
d/dt(m R² Ω² sin²θ); a Rayleigh function's power is −c ẋ².
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR, example_names, random_states
from scipy.integrate import cumulative_simpson

import lagrangian
from lagrangian._identity import is_zero
from lagrangian.analysis import energy_balance
from lagrangian.analysis._energy_balance import accelerations
from lagrangian.numerics import simulate

DAMPED_PENDULUM = (EXAMPLES_DIR / "double_pendulum.toml").read_text().replace(
    "[parameters]", "[parameters]\nc = 0.05") + '\n[loads.hinge]\njoint_damper = ["R0", "S1"]\ncoefficient = "c"\n'
BEAD_IN_R0 = (EXAMPLES_DIR / "bead_rotating_hoop.toml").read_text().replace("[reference]", "").replace(
    'frame = "R1"   #', "#")


@functools.cache
def eom_of(name: str) -> lagrangian.EquationsOfMotion:
    if name == "damped_pendulum":
        return lagrangian.derive(lagrangian.parse_model(DAMPED_PENDULUM))
    if name == "bead_in_R0":
        return lagrangian.derive(lagrangian.parse_model(BEAD_IN_R0))
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))


def rate_along_motion(eom: lagrangian.EquationsOfMotion, E: se.Basic) -> se.Basic:
    """dE/dt = Σ ∂E/∂q_i q̇_i + ∂E/∂q̇_i q̈_i + ∂E/∂t with q̈ = M⁻¹(F + Aᵀλ)."""
    qdd = accelerations(eom)
    terms = [E.diff(q) * qd for q, qd in zip(eom.q, eom.qd, strict=True)]
    terms += [E.diff(qd) * a for qd, a in zip(eom.qd, qdd, strict=True)]
    return se.Add(*terms, E.diff(eom.t))


# -- 1. symbolically ------------------------------------------------------------------------------
SMALL = ["simple_pendulum.toml", "cart_pendulum.toml", "bead_rotating_hoop.toml", "foucault_pendulum.toml",
         "kapitza_pendulum.toml", "block_on_belt.toml", "damped_pendulum", "bead_in_R0"]


@pytest.mark.parametrize("name", SMALL)
def test_dE_dt_along_the_equations_is_P_nc(name: str) -> None:
    eom = eom_of(name)
    balance = energy_balance(eom)
    assert is_zero(balance.E - eom.T - eom.U)
    assert is_zero(rate_along_motion(eom, balance.E) - balance.P_nc)
    assert balance.P_nc.free_symbols.isdisjoint(eom.qdd)


# -- 2. numerically, every example ----------------------------------------------------------------
def _admissible(eom: lagrangian.EquationsOfMotion, values: dict, point: list[float]) -> list[float]:
    """``point`` (q, q̇, t, λ) with q̇ projected onto A q̇ + b = 0: the reactions' power is −Σ λ_k b_k only
    on the motions that satisfy the complementary rows (A and b depend on q and t only)."""
    n = len(eom.q)
    if not eom.constraints:
        return point
    rows = [[a.subs(values) for a in row.coefficients] + [row.b.subs(values)] for row in eom.constraints]
    f = se.Lambdify([*eom.q, *eom.qd, eom.t], [x for row in rows for x in row], real=True)
    Ab = np.asarray(f(point[:2 * n + 1]), dtype=float).reshape(len(rows), n + 1)
    A, b = Ab[:, :n], Ab[:, n]
    qd = np.asarray(point[n:2 * n])
    qd = qd - np.linalg.pinv(A) @ (A @ qd + b)  # rows may be dependent: a block's two corners stuck on the ground
    return point[:n] + list(qd) + point[2 * n:]


@pytest.mark.slow
@pytest.mark.parametrize("name", example_names())
def test_balance_holds_at_random_states_of_every_example(name: str) -> None:
    eom = eom_of(name)
    balance = energy_balance(eom)
    n = len(eom.q)
    values = {se.Symbol(p.name): p.value for p in eom.model.parameters}
    lam = list(eom.multipliers)
    args = [*eom.q, *eom.qd, eom.t, *lam]
    E_parts = [balance.E.diff(x) for x in (*eom.q, *eom.qd, eom.t)]
    exprs = [e.subs(values) for e in (*(x for row in eom.M for x in row), *eom.F, *E_parts, balance.P_nc)]
    exprs += [a.subs(values) for row in eom.A for a in row]
    f = se.Lambdify(args, exprs, real=True)
    rng = np.random.default_rng(11)
    for state in random_states(name, eom.coordinates, 4, seed=12):
        t, mult = rng.uniform(0, 5), rng.uniform(-2, 2, len(lam))
        point = [state[c] for c in eom.coordinates] + [state[c + "_dot"] for c in eom.coordinates] + [t, *mult]
        point = _admissible(eom, values, point)
        v = np.asarray(f(point), dtype=float).ravel()
        M, F = v[:n * n].reshape(n, n), v[n * n:n * n + n]
        dq, dqd, dt = v[n * n + n:n * n + 2 * n], v[n * n + 2 * n:n * n + 3 * n], v[n * n + 3 * n]
        P = v[n * n + 3 * n + 1]
        A = v[n * n + 3 * n + 2:].reshape(len(lam), n)
        qdd = np.linalg.solve(M, F + A.T @ mult)
        rate = dq @ point[n:2 * n] + dqd @ qdd + dt
        scale = max(1.0, np.max(np.abs([dq @ point[n:2 * n], dqd @ qdd, dt, P])))
        assert abs(rate - P) <= 1e-9 * scale, (name, rate, P)


# -- 3. along simulated motions -------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize(("name", "t_end", "n_out"), [
    ("block_on_belt.toml", 3.0, 60001),  # stick and slip: friction switches within ε m/(f N) = 0.3 ms
    ("kapitza_pendulum.toml", 0.3, 12001),  # the pivot works: 19 fast periods, 630 points each
    ("damped_pendulum", 4.0, 4001),  # the hinge's damper dissipates
    ("bead_in_R0", 2.0, 2001),  # the hoop's drive works on the bead
])
def test_energy_change_is_the_integral_of_P_nc(name: str, t_end: float, n_out: int) -> None:
    eom = eom_of(name)
    balance = energy_balance(eom)
    assert not balance.conserved
    tr = simulate(eom, t_end, n_out=n_out, rtol=1e-12, atol=1e-12)
    values = {se.Symbol(p.name): p.value for p in eom.model.parameters}
    f = se.Lambdify([*eom.q, *eom.qd, eom.t], [balance.E.subs(values), balance.P_nc.subs(values)], real=True)
    Y = np.column_stack([tr.q, tr.qd, tr.t])
    E, P = np.asarray(f(Y), dtype=float).reshape(len(tr.t), 2).T
    work = cumulative_simpson(P, x=tr.t, initial=0.0)
    scale = np.max(np.abs(work)) + np.max(np.abs(E - E[0]))
    assert scale > 1e-3 * np.max(np.abs(E))  # the energy does change
    assert np.max(np.abs(E - E[0] - work)) <= 1e-6 * scale


def test_foucaults_jacobi_energy_is_conserved_in_the_earths_frame() -> None:
    eom = eom_of("foucault_pendulum.toml")
    balance = energy_balance(eom)
    assert balance.conserved
    assert [t.name for t in balance.terms] == ["Coriolis"] and balance.term("Coriolis").power == 0
    assert "does no work" in balance.term("Coriolis").note


# -- closed forms of the terms ----------------------------------------------------------------------
def test_the_hoop_drive_power_in_R0() -> None:
    eom = eom_of("bead_in_R0")
    term = energy_balance(eom).term("prescribed motion")
    (theta,), (theta_dot,) = eom.q, eom.qd
    m, R, Omega = se.Symbol("m"), se.Symbol("R"), se.Symbol("Omega")
    assert is_zero(term.power - 2 * m * R**2 * Omega**2 * se.sin(theta) * se.cos(theta) * theta_dot)
    assert term.kind == "prescribed motion"


def test_damper_and_friction_terms() -> None:
    damper = energy_balance(eom_of("damped_pendulum")).term("hinge")
    assert is_zero(damper.power + se.Symbol("c") * eom_of("damped_pendulum").qd[0] ** 2)
    belt = eom_of("block_on_belt.toml")
    friction = energy_balance(belt).term("friction")
    x_dot = belt.qd[0]
    slip = x_dot - se.Symbol("v_b")
    law = -se.Symbol("f") * se.Symbol("m") * se.Symbol("g") * slip / se.sqrt(slip**2 + se.Symbol("eps") ** 2)
    assert is_zero(friction.power - law * x_dot)  # T·V(B/R0): positive while the belt drags the block


def test_explicit_time_in_a_potential() -> None:
    """Kapitza's pendulum seen from its pivot: the entrainment potential m γ(A)·AP depends on t."""
    text = (EXAMPLES_DIR / "kapitza_pendulum.toml").read_text() + '\n[reference]\nframe = "R0"\norigin = "A"\n'
    eom = lagrangian.derive(lagrangian.parse_model(text))
    balance = energy_balance(eom)
    assert [t.kind for t in balance.terms] == ["explicit time"]
    assert is_zero(balance.P_nc - balance.terms[0].power)
    assert is_zero(rate_along_motion(eom, balance.E) - balance.P_nc)


@pytest.mark.parametrize("name", ["simple_pendulum.toml", "lagrange_top.toml", "cart_pendulum.toml"])
def test_conservative_examples_balance_to_zero(name: str) -> None:
    eom = eom_of(name)
    balance = energy_balance(eom)
    assert balance.conserved and balance.terms == ()
    assert any(i.kind == "energy" for i in lagrangian.first_integrals(eom))


@pytest.mark.parametrize("name", ["kapitza_pendulum.toml", "block_on_belt.toml", "damped_pendulum", "bead_in_R0"])
def test_no_energy_integral_where_the_balance_is_not_zero(name: str) -> None:
    eom = eom_of(name)
    assert not energy_balance(eom).conserved
    assert not any(i.kind == "energy" for i in lagrangian.first_integrals(eom))


# -- complementary constraints: their reactions' real power is −Σ λ_k b_k ---------------------------
@pytest.mark.slow
@pytest.mark.parametrize("name", ["pendulum_tension.toml", "rolling_disk_incline.toml", "top_reaction.toml"])
def test_scleronomic_reactions_do_no_work_and_E_is_conserved(name: str) -> None:
    """The balance agrees with `first_integrals`: b_k ≡ 0, so the reaction's power is 0 and E is offered."""
    eom = eom_of(name)
    balance = energy_balance(eom)
    assert balance.conserved and is_zero(balance.P_nc)
    assert all(t.power == 0 and "does no work" in t.note for t in balance.terms if t.kind == "constraint")
    assert any(i.kind == "energy" for i in lagrangian.first_integrals(eom))


def test_a_rheonomic_constraint_reaction_works() -> None:
    """A rod whose length l(t) = l0 + a sin(νt) is kept as a complementary row: b = −2 l l̇, power −λ b."""
    text = (EXAMPLES_DIR / "pendulum_tension.toml").read_text()
    assert "x^2 + y^2 - l^2" in text
    text = text.replace("x^2 + y^2 - l^2", "x^2 + y^2 - (l + a*sin(nu*t))^2").replace(
        "[parameters]", "[parameters]\na = 0.05\nnu = 3.0")
    eom = lagrangian.derive(lagrangian.parse_model(text))
    balance = energy_balance(eom)
    (row,) = eom.constraints
    (term,) = [t for t in balance.terms if t.kind == "constraint"]
    l, a, nu, t = (se.Symbol(s) for s in ("l", "a", "nu", "t"))
    assert is_zero(term.power - row.multiplier * 2 * (l + a * se.sin(nu * t)) * a * nu * se.cos(nu * t))
    assert not balance.conserved
