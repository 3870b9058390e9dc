"""The reference systems of `lagrangian.model.zoo`: the planar n-link pendulum against closed forms."""

from __future__ import annotations

import pytest
import symengine as se

import lagrangian
from lagrangian._identity import are_zero, is_zero
from lagrangian.model import zoo
from lagrangian.model.zoo import planar_chain


def _symbols(n: int):  # type: ignore[no-untyped-def]
    S = se.Symbol
    return ([S(f"theta{k}") for k in range(1, n + 1)], [S(f"theta{k}_dot") for k in range(1, n + 1)],
            [S(f"m{k}") for k in range(1, n + 1)], [S(f"l{k}") for k in range(1, n + 1)], S("g"))


def test_exported() -> None:
    assert "planar_chain" in zoo.__all__


def test_structure_and_values() -> None:
    model = planar_chain(4)
    assert [c.name for c in model.coordinates] == ["theta1", "theta2", "theta3", "theta4"]
    assert {p.name for p in model.parameters} == {"g", *(f"m{k}" for k in range(1, 5)), *(f"l{k}" for k in range(1, 5))}
    assert all(p.value is not None and p.value > 0 for p in model.parameters)
    assert all(c.initial is not None and c.rate is not None for c in model.coordinates)
    # Absolute angles: every rod frame comes straight from R0.
    assert [(f.name, f.parent) for f in model.frames[1:]] == [(f"R{k}", "R0") for k in range(1, 5)]
    assert [p.name for p in model.particles] == ["P1", "P2", "P3", "P4"]


@pytest.mark.parametrize("bad", [0, -1, 2.0, True, "3"])
def test_rejects_bad_length(bad: object) -> None:
    with pytest.raises(ValueError):
        planar_chain(bad)  # type: ignore[arg-type]


def test_one_link_is_the_simple_pendulum() -> None:
    eom = lagrangian.derive(planar_chain(1))
    (theta,), _, (m,), (l,), g = _symbols(1)
    assert is_zero(eom.M[0][0] - m * l**2)
    # θ̈ = F/M = −(g/l) sin θ
    assert is_zero(eom.F[0] / eom.M[0][0] + g / l * se.sin(theta))
    assert eom.conservative
    assert is_zero(eom.U + m * g * l * se.cos(theta))


def test_two_links_are_the_textbook_double_pendulum() -> None:
    eom = lagrangian.derive(planar_chain(2))
    (t1, t2), (w1, w2), (m1, m2), (l1, l2), g = _symbols(2)
    M = [[(m1 + m2) * l1**2, m2 * l1 * l2 * se.cos(t1 - t2)],
         [m2 * l1 * l2 * se.cos(t1 - t2), m2 * l2**2]]
    F = [-m2 * l1 * l2 * w2**2 * se.sin(t1 - t2) - (m1 + m2) * g * l1 * se.sin(t1),
         m2 * l1 * l2 * w1**2 * se.sin(t1 - t2) - m2 * g * l2 * se.sin(t2)]
    assert all(are_zero([eom.M[i][j] - M[i][j] for i in range(2) for j in range(2)]))
    assert all(are_zero([eom.F[i] - F[i] for i in range(2)]))


def test_mass_matrix_of_a_longer_chain() -> None:
    n = 5
    eom = lagrangian.derive(planar_chain(n))
    q, _, m, l, g = _symbols(n)
    residues = []
    for i in range(n):
        for j in range(n):
            below = se.Add(*m[max(i, j):])  # the masses carried by both rods
            residues.append(eom.M[i][j] - below * l[i] * l[j] * se.cos(q[i] - q[j]))
        residues.append(eom.loads[0].Q[i] + se.Add(*m[i:]) * g * l[i] * se.sin(q[i]))
    assert all(are_zero(residues))


def test_lagrange_equations_agree_with_the_matrix_form() -> None:
    eom = lagrangian.derive(planar_chain(3))
    residues = []
    for i, eq in enumerate(eom.equations):
        m_qdd = se.Add(*(eom.M[i][j] * eom.qdd[j] for j in range(3)))
        residues.append((eq.lhs - eq.rhs) - (m_qdd - eom.F[i]))
    assert all(are_zero(residues))


def test_long_chain_lagrange_equations_agree_with_the_matrix_form() -> None:
    # Beyond 12 coordinates d/dt(∂T/∂q̇_i) is taken by the shared chain rule (`TimeDerivative.many`)
    # instead of being grouped by q̈_j, q̇_j: the equations must stay the same functions.
    from lagrangian.dynamics._lagrange import GROUPED_MAX_COORDINATES

    n = GROUPED_MAX_COORDINATES + 1
    eom = lagrangian.derive(planar_chain(n))
    residues = []
    for i, eq in enumerate(eom.equations):
        m_qdd = se.Add(*(eom.M[i][j] * eom.qdd[j] for j in range(n)))
        residues.append((eq.lhs - eq.rhs) - (m_qdd - eom.F[i]))
        residues.append(eq.lhs - (eom.kinematics.d_dt(eq.dT_dqd) - eq.dT_dq))
    assert all(are_zero(residues))
