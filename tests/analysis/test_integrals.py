"""First integrals are found from ∂L/∂q ≡ 0 as a function, not as a syntax tree."""

import symengine as se

import lagrangian
from lagrangian._identity import is_zero
from lagrangian.model.zoo import LAGRANGE_TOP_TOML


def test_zero_test_sees_through_trigonometric_identities():
    x, y = se.symbols("x y")
    assert is_zero(se.sin(x) ** 2 + se.cos(x) ** 2 - 1)
    assert is_zero(se.sin(x + y) - se.sin(x) * se.cos(y) - se.cos(x) * se.sin(y))
    assert not is_zero(se.sin(x) ** 2 - se.cos(x) ** 2)
    assert not is_zero(se.Rational(1, 10**40) * x)  # tiny but not zero


def test_top_with_inertia_in_the_body_frame_still_has_K_and_H():
    # Given in R (the body frame) the moments make T depend on φ through sin φ, cos φ;
    # ∂T/∂φ only vanishes after simplification, because the two moments A are equal.
    text = LAGRANGE_TOP_TOML.replace('inertia = { at = "O", frame = "R2", diagonal = ["A", "A", "C"] }',
                                     'inertia = { at = "O", frame = "R", diagonal = ["A", "A", "C"] }')
    assert 'frame = "R",' in text
    eom = lagrangian.derive(lagrangian.parse_model(text))
    phi = eom.q[2]
    assert phi in eom.equation("phi").dT_dq.free_symbols or eom.T.has(phi)  # φ is really there
    integrals = {i.name: i for i in lagrangian.first_integrals(eom)}
    assert set(integrals) == {"K", "H", "E"}
    # and they are the seed's, once simplified
    A, C, theta, psi_dot, phi_dot = (se.Symbol(s) for s in ("A", "C", "theta", "psi_dot", "phi_dot"))
    assert is_zero(integrals["H"].expression - C * (phi_dot + psi_dot * se.cos(theta)))
    assert is_zero(integrals["K"].expression
                   - (A * psi_dot * se.sin(theta) ** 2 + C * se.cos(theta) * (phi_dot + psi_dot * se.cos(theta))))


def test_asymmetric_top_loses_H():
    # With three different moments φ is no longer cyclic: H must disappear, K and E stay.
    text = LAGRANGE_TOP_TOML.replace('frame = "R2", diagonal = ["A", "A", "C"]', 'frame = "R", diagonal = ["A", "B", "C"]')
    text = text.replace('C = { value', 'B = { value = 0.03, unit = "kg m^2" }\nC = { value')
    eom = lagrangian.derive(lagrangian.parse_model(text))
    assert {i.name for i in lagrangian.first_integrals(eom)} == {"K", "E"}
