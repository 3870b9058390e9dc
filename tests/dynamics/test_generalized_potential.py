"""Potentials that depend on the rates (generalized potentials): Q_i = d/dt(∂U/∂q̇_i) − ∂U/∂q_i, against the
Lorentz force of a charge in a uniform field B (two gauges), the cyclotron motion in closed form, and the
Coriolis and entrainment forces of a turning frame written by the engine's own [reference] derivation."""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se
from more_systems import CHARGE
from more_systems import eom as system_eom

import lagrangian
from lagrangian import ModelError
from lagrangian.model import parse_model

m, qc, B = se.symbols("m qc B")
x, y, xd, yd = se.symbols("x y x_dot y_dot")


def _eom(text: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(parse_model(text))


def _same(a: se.Basic, b: se.Basic) -> bool:
    return se.expand(a - b) == 0


def test_the_vector_potential_of_a_uniform_field_gives_the_whole_lorentz_force():
    eom = system_eom("charge")  # U = −qc A·v, A = B/2 (−y, x, 0)
    # qc v ∧ B with v = (ẋ, ẏ, 0), B = B z: (qc B ẏ, −qc B ẋ, 0), not half of it
    assert _same(eom.F[0], qc * B * yd) and _same(eom.F[1], -qc * B * xd)
    load = eom.loads[0]
    assert load.kind == "generalized potential" and load.potential is None and load.generalized is not None
    assert not eom.conservative  # not a potential energy U_P(q): its Q are in Q_nc
    energy = next(fi for fi in lagrangian.first_integrals(eom) if fi.name == "E")
    assert _same(energy.expression, m / 2 * (xd**2 + yd**2))  # the magnetic force does no work


def test_another_gauge_gives_the_same_equations_and_its_canonical_momentum():
    landau = _eom(CHARGE.replace("-qc*B/2*(x*y_dot - y*x_dot)", "qc*B*y*x_dot"))  # A = (−B y, 0, 0)
    assert _same(landau.F[0], qc * B * yd) and _same(landau.F[1], -qc * B * xd)
    momenta = {fi.coordinate: fi.expression for fi in lagrangian.first_integrals(landau) if fi.kind == "momentum"}
    # x is absent from L = T − U: ∂L/∂ẋ = m ẋ − qc B y is constant (m ẍ = qc B ẏ)
    assert set(momenta) == {"x"} and _same(momenta["x"], m * xd - qc * B * y)


def test_the_charge_turns_on_the_cyclotron_circle():
    mass, charge, field, v0 = 2.0, 1.5, 4.0, 1.0
    w = charge * field / mass
    run = lagrangian.simulate(system_eom("charge"), 3.0, n_out=31)
    t = run.t
    # m ẍ = qc B ẏ, m ÿ = −qc B ẋ from (0, 0) at (v0, 0): a circle of radius v0/ω at ω = qc B/m
    np.testing.assert_allclose(run.q[:, 0], v0 / w * np.sin(w * t), atol=1e-8)
    np.testing.assert_allclose(run.q[:, 1], v0 / w * (np.cos(w * t) - 1), atol=1e-8)


def test_an_electric_potential_beside_it_stays_in_the_energy():
    eom = _eom(CHARGE.replace('B = { value = 4.0 }', 'B = { value = 4.0 }\nE0 = { value = 0.5 }')
               .replace("-qc*B/2*(x*y_dot - y*x_dot)", "qc*E0*x - qc*B/2*(x*y_dot - y*x_dot)"))
    E0 = se.Symbol("E0")
    assert _same(eom.F[0], qc * B * yd - qc * E0)
    energy = next(fi for fi in lagrangian.first_integrals(eom) if fi.name == "E")
    assert _same(energy.expression, m / 2 * (xd**2 + yd**2) + qc * E0 * x)  # T + qc V: the rate part drops


ROTATING = """
[model]
name = "Puck on a turntable"
[parameters]
m = { value = 1.0 }
k = { value = 3.0 }
Omega = { value = 0.7 }
[coordinates]
x = { initial = 0.2, rate = 0.0 }
y = { initial = 0.0, rate = 0.1 }
[frames]
R1 = { from = "R0", rotation = ["Omega*t", "z"] }
[particles.P]
mass = "m"
position = "x*R1.x + y*R1.y"
[loads]
spring = { potential = "k/2*(x^2 + y^2)" }
[reference]
frame = "R1"
"""

INERTIAL_AS_POTENTIAL = """
[model]
name = "Puck, inertial forces as a generalized potential"
[parameters]
m = { value = 1.0 }
k = { value = 3.0 }
Omega = { value = 0.7 }
[coordinates]
x = { initial = 0.2, rate = 0.0 }
y = { initial = 0.0, rate = 0.1 }
[particles.P]
mass = "m"
position = "x*R0.x + y*R0.y"
[loads]
spring = { potential = "k/2*(x^2 + y^2)" }
inertial = { potential = "-m*Omega*(x*y_dot - y*x_dot) - m*Omega^2/2*(x^2 + y^2)" }
"""


def test_the_coriolis_and_entrainment_forces_are_a_generalized_potential():
    # In R1 turning at Ω: L = ½ m |v_r + Ω ∧ r|² − U, so U_inertial = −m Ω·(r ∧ v_r) − ½ m |Ω ∧ r|².
    course = _eom(ROTATING)  # the engine's Coriolis and entrainment loads (seed, Remarque 3)
    written = _eom(INERTIAL_AS_POTENTIAL)
    for a, b in zip(course.F, written.F, strict=True):
        assert _same(a, b)
    Om = se.Symbol("Omega")
    assert _same(written.F[0], -se.Symbol("k") * x + 2 * m * Om * yd + m * Om**2 * x)


def test_a_potential_quadratic_in_the_rates_is_refused_with_the_fix():
    with pytest.raises(ModelError) as info:
        parse_model(CHARGE.replace("-qc*B/2*(x*y_dot - y*x_dot)", "m*x_dot^2*y"), source="quadratic.toml")
    assert "not affine in the rates" in info.value.message and "kinetic energy" in info.value.fix


@pytest.mark.parametrize("lang", ["fr", "en"])
def test_the_report_says_which_formula_it_used(lang: str):
    text = lagrangian.report(system_eom("charge"), lang=lang).markdown()
    assert r"\frac{d}{dt}\frac{\partial U}{\partial \dot{q}_i} - \frac{\partial U}{\partial q_i}" in text
    assert ("potentiel généralisé" if lang == "fr" else "generalized potential") in text
    assert r"Q_{x}(\text{lorentz}) = \mathrm{qc} B \dot{y}" in text
