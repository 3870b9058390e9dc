"""Properties every derivation must have, checked with Hypothesis at random states of every example.

* T = ½ q̇ᵀ M q̇ + T1 + T0 (T2 = ½ q̇ᵀ M q̇; T1 and T0 vanish unless a constraint depends on t);
* M is symmetric positive definite;
* each conservative load's Q_i (virtual power) is −∂U/∂q_i, with U computed here from
  the positions alone (gravity: U = −Σ m g·OG; spring: U = ½ k (ℓ − ℓ0)²);
* Γ_i from T (``lhs`` of L(q_i)) equals Σ_j M_ij q̈_j + Q_i − F_i (Γ from its definition);
* L(q_i) holds once q̈ = M⁻¹F;
* listing the coordinates in another order in the model file changes nothing;
* every first integral has a zero time derivative along the motion.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import symengine as se
from hypothesis import given
from hypothesis import strategies as st
from lagrangian_test_support import (
    EXAMPLES_DIR,
    Numeric,
    coordinate_entry_lines,
    domain,
    engine_qdd,
    eom_of,
    example_names,
    example_text,
    integrals_of,
    numeric_eom,
    other_orders,
    permuted_coordinates,
    with_accelerations,
)

import lagrangian
from lagrangian._identity import is_zero
from lagrangian.model import Gravity, Spring

EXAMPLES = example_names()
RTOL = 1e-9


def states(name: str, *, accelerations: bool = False) -> st.SearchStrategy[dict[str, float]]:
    """A strategy of states {q: ., q_dot: .} (and q_ddot) inside the example's safe domain."""
    coords = eom_of(name).coordinates
    fields = {}
    for c in coords:
        for s in (c, c + "_dot"):
            lo, hi = domain(name, s)
            fields[s] = st.floats(lo, hi, allow_nan=False, allow_infinity=False)
        if accelerations:
            fields[c + "_ddot"] = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
    return st.fixed_dictionaries(fields)


def _scale(*arrays: np.ndarray) -> float:
    return max([1.0] + [float(np.max(np.abs(a))) for a in arrays if np.size(a)])


# -- T and M ---------------------------------------------------------------------------------
@functools.cache
def _energy_and_quadratic_form(name: str) -> Numeric:
    eom = eom_of(name)
    n = len(eom.q)
    quadratic = se.Rational(1, 2) * se.Add(*(eom.qd[i] * eom.M[i][j] * eom.qd[j] for i in range(n) for j in range(n)))
    # T1 + T0 from T alone: its value and slope at q̇ = 0 (both zero when no constraint moves with t).
    rest = eom.T.subs({qd: 0 for qd in eom.qd})
    rest += se.Add(*(eom.T.diff(qd).subs({r: 0 for r in eom.qd}) * qd for qd in eom.qd))
    return Numeric(eom, [eom.T, quadratic, rest])


@pytest.mark.slow
@pytest.mark.parametrize("name", EXAMPLES)
@given(data=st.data())
def test_kinetic_energy_is_half_qdot_M_qdot(name: str, data: st.DataObject) -> None:
    state = data.draw(states(name))
    state["t"] = data.draw(st.floats(0.0, 10.0))  # prescribed motions (Kapitza's pivot) depend on t
    T, quadratic, rest = _energy_and_quadratic_form(name)(state)
    assert T >= 0.0
    assert abs(T - quadratic - rest) <= RTOL * max(1.0, abs(T)), (T, quadratic, rest)


@pytest.mark.parametrize("name", EXAMPLES)
def test_mass_matrix_is_symbolically_symmetric(name: str) -> None:
    eom = eom_of(name)
    n = len(eom.q)
    for i in range(n):
        for j in range(i + 1, n):
            assert se.expand(eom.M[i][j] - eom.M[j][i]) == 0, (i, j)
        # M depends on q only (and t), never on rates or accelerations
        for entry in eom.M[i]:
            assert not entry.free_symbols & (set(eom.qd) | set(eom.qdd))


@pytest.mark.slow
@pytest.mark.parametrize("name", EXAMPLES)
@given(data=st.data())
def test_mass_matrix_is_symmetric_positive_definite(name: str, data: st.DataObject) -> None:
    state = data.draw(states(name))
    n = len(eom_of(name).q)
    M = numeric_eom(name)[0](state).reshape(n, n)
    assert np.allclose(M, M.T, rtol=RTOL, atol=0.0)
    eigenvalues = np.linalg.eigvalsh(M)
    assert eigenvalues[0] > 1e-12 * eigenvalues[-1], eigenvalues


# -- conservative loads: virtual power vs potential ----------------------------------------------
def _independent_potential(eom: lagrangian.EquationsOfMotion, load) -> se.Basic | None:  # noqa: ANN001
    """U of a gravity or spring load from the positions alone (no velocity, no partial velocity)."""
    kin = eom.kinematics
    model = eom.model

    def r0(vector) -> tuple[se.Basic, ...]:  # noqa: ANN001
        return kin.frames.express(vector, "R0")

    if isinstance(load, Gravity):
        field = r0(load.field)
        masses = {b.name: b.mass for b in model.bodies} | {p.name: p.mass for p in model.particles}
        names = load.on or tuple(masses)
        U = se.Integer(0)
        for name in names:
            position = r0(kin.position(name))
            U -= masses[name] * se.Add(*(f * x for f, x in zip(field, position, strict=True)))
        return U
    if isinstance(load, Spring):
        a, b = load.ends
        d = [xb - xa for xa, xb in zip(r0(kin.position(a)), r0(kin.position(b)), strict=True)]
        length = se.sqrt(se.Add(*(c**2 for c in d)))
        return se.Rational(1, 2) * load.stiffness * (length - load.rest_length) ** 2
    return None


@functools.cache
def _load_checks(name: str) -> list[tuple[str, Numeric]]:
    """Per gravity/spring load: numeric (Q_i + ∂U/∂q_i, Q_i + ∂U_engine/∂q_i, Q_i) for every i."""
    eom = eom_of(name)
    out = []
    # The model's loads come first; a non-Galilean model's inertial forces follow them in eom.loads.
    for spec, forces in zip(eom.model.loads, eom.loads[:len(eom.model.loads)], strict=True):
        assert spec.name == forces.name
        U = _independent_potential(eom, spec)
        if U is None:
            continue
        assert forces.potential is not None, f"{name}: load {forces.name} should be detected conservative"
        exprs = [Q + U.diff(q) for Q, q in zip(forces.Q, eom.q, strict=True)]
        exprs += [Q + forces.potential.diff(q) for Q, q in zip(forces.Q, eom.q, strict=True)]
        exprs += list(forces.Q)
        out.append((forces.name, Numeric(eom, exprs)))
    return out


#: Examples with no weight: a satellite's attitude about its centre of mass, in free fall with it.
WEIGHTLESS = {"satellite_reaction_wheel.toml"}


def test_some_example_has_a_spring_and_all_have_gravity() -> None:
    """So that the load test below really exercises both potentials."""
    kinds = {name: {type(load) for load in eom_of(name).model.loads} for name in EXAMPLES}
    assert all(Gravity in k for name, k in kinds.items() if name not in WEIGHTLESS)
    assert not any(Gravity in kinds[name] for name in WEIGHTLESS)
    assert any(Spring in k for k in kinds.values())


@pytest.mark.slow
@pytest.mark.parametrize("name", [name for name in EXAMPLES if name not in WEIGHTLESS])
@given(data=st.data())
def test_conservative_loads_Q_is_minus_gradient_of_U(name: str, data: st.DataObject) -> None:
    state = data.draw(states(name))
    n = len(eom_of(name).q)
    checks = _load_checks(name)
    assert checks
    for load, numeric in checks:
        values = numeric(state)
        independent, engine, Q = values[:n], values[n:2 * n], values[2 * n:]
        tol = RTOL * _scale(Q)
        assert np.all(np.abs(independent) <= tol), f"{load}: Q + ∂U/∂q = {independent} (Q = {Q})"
        assert np.all(np.abs(engine) <= tol), f"{load}: Q + ∂U_engine/∂q = {engine} (Q = {Q})"


# -- the two formulations of Γ_i ------------------------------------------------------------------
@functools.cache
def _gamma_forms(name: str) -> Numeric:
    eom = eom_of(name)
    n = len(eom.q)
    Q = [se.Add(*(f.Q[i] for f in eom.loads)) for i in range(n)]
    from_T = [eq.lhs for eq in eom.equations]
    from_definition = [se.Add(*(eom.M[i][j] * eom.qdd[j] for j in range(n))) + Q[i] - eom.F[i] for i in range(n)]
    residual = [eq.lhs - eq.rhs for eq in eom.equations]
    return Numeric(eom, [*from_T, *from_definition, *residual])


@pytest.mark.slow
@pytest.mark.parametrize("name", EXAMPLES)
@given(data=st.data())
def test_gamma_from_T_equals_gamma_from_definition(name: str, data: st.DataObject) -> None:
    state = data.draw(states(name, accelerations=True))
    n = len(eom_of(name).q)
    values = _gamma_forms(name)(state)
    from_T, from_definition = values[:n], values[n:2 * n]
    assert np.allclose(from_T, from_definition, rtol=RTOL, atol=RTOL * _scale(from_T, from_definition)), (
        from_T, from_definition)


@pytest.mark.slow
@pytest.mark.parametrize("name", EXAMPLES)
@given(data=st.data())
def test_lagrange_equations_hold_at_qdd_from_M_and_F(name: str, data: st.DataObject) -> None:
    eom = eom_of(name)
    n = len(eom.q)
    state = data.draw(states(name))
    full = with_accelerations(eom, state, engine_qdd(name, state))
    values = _gamma_forms(name)(full)
    gamma, residual = values[:n], values[2 * n:]
    assert np.all(np.abs(residual) <= RTOL * _scale(gamma)), residual


# -- order of the coordinates -------------------------------------------------------------------
@functools.cache
def _permuted(name: str, order: tuple[int, ...]) -> lagrangian.EquationsOfMotion:
    text = permuted_coordinates(example_text(name), order)
    return lagrangian.derive(lagrangian.parse_model(text, source=str(EXAMPLES_DIR / name)))


# The coordinates counted in the file's text: nothing is derived while the tests are collected.
PERMUTATIONS = [(name, order) for name in EXAMPLES
                for order in other_orders(len(coordinate_entry_lines(example_text(name))))]


def test_permutations_cover_every_multi_coordinate_example() -> None:
    covered = {name for name, _ in PERMUTATIONS}
    assert covered == {name for name in EXAMPLES if len(eom_of(name).q) > 1}
    assert len(PERMUTATIONS) >= 5 + 3  # the top alone has 5 other orders


@pytest.mark.parametrize(("name", "order"), PERMUTATIONS)
def test_permuted_model_lists_coordinates_in_the_new_order(name: str, order: tuple[int, ...]) -> None:
    original = eom_of(name).coordinates
    permuted = _permuted(name, order)
    assert permuted.coordinates == tuple(original[k] for k in order)
    assert sorted(c.name for c in permuted.model.coordinates) == sorted(original)


@functools.cache
def _order_comparison(name: str, order: tuple[int, ...]) -> Numeric:
    eom, other = eom_of(name), _permuted(name, order)
    names = eom.coordinates
    exprs = []
    for i, c in enumerate(names):
        eq, eq2 = eom.equation(c), other.equation(c)
        exprs += [eq.lhs - eq.rhs, eq2.lhs - eq2.rhs]
        k = other.coordinates.index(c)
        for j, c2 in enumerate(names):
            exprs += [eom.M[i][j], other.M[k][other.coordinates.index(c2)]]
        exprs += [eom.F[i], other.F[k]]
    exprs += [eom.T, other.T, eom.U, other.U]
    return Numeric(eom, exprs)  # same symbol names in both derivations


@pytest.mark.slow
@pytest.mark.parametrize(("name", "order"), PERMUTATIONS)
@given(data=st.data())
def test_equations_do_not_depend_on_coordinate_order(name: str, order: tuple[int, ...], data: st.DataObject) -> None:
    state = data.draw(states(name, accelerations=True))
    values = _order_comparison(name, order)(state)
    ours, theirs = values[0::2], values[1::2]
    assert np.allclose(ours, theirs, rtol=RTOL, atol=RTOL * _scale(ours)), (ours, theirs)


#: The bicycle's first integrals take seconds per order (its energy is long): the reversal and an
#: interleaving, which move every coordinate, are enough there.
_LONG = {"whipple_bicycle.toml"}
INTEGRAL_ORDERS = [(name, order) for name, order in PERMUTATIONS
                   if name not in _LONG or order in (other_orders(len(order))[0], other_orders(len(order))[-1])]


@pytest.mark.slow
@pytest.mark.parametrize(("name", "order"), INTEGRAL_ORDERS)
def test_first_integrals_do_not_depend_on_coordinate_order(name: str, order: tuple[int, ...]) -> None:
    ours = {(fi.name, fi.kind, fi.coordinate): fi.expression for fi in integrals_of(name)}
    permuted = lagrangian.first_integrals(_permuted(name, order))
    theirs = {(fi.name, fi.kind, fi.coordinate): fi.expression for fi in permuted}
    assert set(ours) == set(theirs)
    for key, expr in ours.items():
        assert is_zero(expr - theirs[key]), key


# -- first integrals ---------------------------------------------------------------------------
EXPECTED_INTEGRALS = {
    "simple_pendulum.toml": {"E"},
    "spherical_pendulum.toml": {"Lz", "E"},
    "double_pendulum.toml": {"E"},
    "cart_pendulum.toml": {"E"},
    # With its push F off (an input's default), x is cyclic: p_x and E (a constant F would leave E only).
    "inverted_pendulum_cart.toml": {"p_x", "E"},
    "furuta_pendulum.toml": {"p_phi", "E"},  # the motor off: the momentum about its axis, and the energy
    "double_pendulum_cart.toml": {"p_x", "E"},  # the same with two rods
    "torque_pendulum.toml": {"E"},  # a constant motor torque derives from U = −τ θ
    "acrobot.toml": {"E"},  # the elbow's constant couple from U = −τ θ2
    # θ is cyclic (the angular momentum about z0), and φ too while the motor is off
    "satellite_reaction_wheel.toml": {"p_theta", "p_phi", "E"},
    "lagrange_top.toml": {"K", "H", "E"},
    "sleeping_top.toml": {"p_phi", "E", "sigma_O_z0"},  # the spin's momentum, and σ_O·z0 by Noether
    "bead_rotating_hoop.toml": {"h"},  # Jacobi: energy in the hoop's frame, with the entrainment potential
    "foucault_pendulum.toml": {"h"},
    "kapitza_pendulum.toml": set(),  # L depends on t
    "block_on_belt.toml": set(),  # the belt's friction works
    "block_on_incline.toml": set(),  # dry friction works while it slides
    # Complementary constraints: only the integrals their reactions leave (admissible_integrals).
    "pendulum_tension.toml": {"E"},
    "rolling_disk_incline.toml": {"E"},
    "rolling_coin.toml": {"p_psi", "E", "phi_dot"},  # φ̇ from the reduced (nonholonomic) equations
    # K is lost (the pivot's reaction acts on psi with x_G, y_G free) but σ_O·z0 stays (Noether: the
    # rotations about O z0 keep the pivot at O).
    "top_reaction.toml": {"H", "E", "sigma_O_z0"},
    # The wheels' angles are cyclic in T but the rolling rows act on them; the contacts do no work: E.
    "whipple_bicycle.toml": {"E"},
    # A free body under gravity, in its course's coordinates: x, y and ψ cyclic, σ_O·z0 by Noether (the
    # quaternion route monitors all of σ_G: tests/numerics/test_free_body.py).
    "tumbling_body.toml": {"p_x", "p_y", "p_psi", "E", "sigma_O_z0"},
    # Unilateral contacts: E between impacts (an impact takes its share: tests/numerics/test_contact.py).
    "bouncing_ball.toml": {"E"},
    "sliding_ladder.toml": {"E"},
    "rocking_block.toml": {"E"},
    "newtons_cradle.toml": {"E"},
    "slack_rope_pendulum.toml": {"E"},
}
#: The examples that have first integrals to check along the motion.
WITH_INTEGRALS = [name for name in EXAMPLES if EXPECTED_INTEGRALS.get(name, True)]


@pytest.mark.slow
def test_expected_first_integrals_of_each_example() -> None:
    assert set(EXPECTED_INTEGRALS) == set(EXAMPLES)
    for name in EXAMPLES:
        assert {fi.name for fi in integrals_of(name)} == EXPECTED_INTEGRALS[name], name


@functools.cache
def _integral_rates(name: str) -> tuple[list[str], Numeric]:
    """Per first integral I: the terms ∂I/∂q_i q̇_i, ∂I/∂q̇_i q̈_i and ∂I/∂t of dI/dt."""
    eom = eom_of(name)
    names, exprs = [], []
    for fi in integrals_of(name):
        names.append(fi.name)
        terms = [fi.expression.diff(q) * qd for q, qd in zip(eom.q, eom.qd, strict=True)]
        terms += [fi.expression.diff(qd) * qdd for qd, qdd in zip(eom.qd, eom.qdd, strict=True)]
        terms.append(fi.expression.diff(eom.t))
        exprs += terms
    return names, Numeric(eom, exprs)


@pytest.mark.parametrize("name", WITH_INTEGRALS)
@given(data=st.data())
def test_first_integrals_are_constant_along_the_motion(name: str, data: st.DataObject) -> None:
    eom = eom_of(name)
    state = data.draw(states(name))
    names, numeric = _integral_rates(name)
    assert names
    full = with_accelerations(eom, state, engine_qdd(name, state))
    terms = numeric(full).reshape(len(names), -1)
    for integral, row in zip(names, terms, strict=True):
        rate = float(np.sum(row))
        assert abs(rate) <= RTOL * _scale(row), f"d{integral}/dt = {rate} (terms {row})"


@pytest.mark.parametrize("name", WITH_INTEGRALS)
def test_first_integrals_are_not_trivially_constant(name: str) -> None:
    """Guard for the test above: each integral does change along a wrong motion (q̈ = M⁻¹F + 1)."""
    eom = eom_of(name)
    names, numeric = _integral_rates(name)
    rng = np.random.default_rng(7)
    state = {}
    for c in eom.coordinates:
        for s in (c, c + "_dot"):
            state[s] = float(rng.uniform(*domain(name, s)))
    wrong = with_accelerations(eom, state, engine_qdd(name, state) + 1.0)
    terms = numeric(wrong).reshape(len(names), -1)
    for integral, row in zip(names, terms, strict=True):
        assert abs(float(np.sum(row))) > 1e-6 * _scale(row), integral
