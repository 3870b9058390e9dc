"""Steady motions by Routh's reduction, against textbook closed forms and against the linearization."""

from __future__ import annotations

import math

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.analysis import StructureError


def _eom(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / f"{name}.toml"))


TOP = dict(m=1.0, g=9.81, a=0.1, A=0.02, C=0.01)


@pytest.mark.slow
def test_top_routhian_and_the_steady_precession_relation():
    """Goldstein §5.7: steady precession at θ0 iff m g a = ψ̇ (C ω3 − A ψ̇ cos θ0), ω3 = φ̇ + ψ̇ cos θ0;
    U_eff = (K − H cos θ)²/(2 A sin²θ) + H²/(2 C) + m g a cos θ."""
    red = lagrangian.routh_reduction(_eom("lagrange_top"))
    assert red.cyclic == ("psi", "phi") and red.remaining == ("theta",)
    assert [str(p) for p in red.momenta] == ["K", "H"]
    rng = np.random.default_rng(1)
    m, g, a, A, C = (TOP[k] for k in ("m", "g", "a", "A", "C"))
    for _ in range(5):
        th, pd, fd, K, H = rng.uniform(0.2, 1.3, 5)
        subs = {se.Symbol(k): v for k, v in TOP.items()} | {se.Symbol("theta"): th, se.Symbol("psi_dot"): pd,
                                                           se.Symbol("phi_dot"): fd, se.Symbol("K"): K,
                                                           se.Symbol("H"): H}
        ueff = (K - H * math.cos(th)) ** 2 / (2 * A * math.sin(th) ** 2) + H**2 / (2 * C) + m * g * a * math.cos(th)
        assert float(red.effective_potential.subs(subs)) == pytest.approx(ueff, rel=1e-12)
        w3 = fd + pd * math.cos(th)
        relation = m * g * a - pd * (C * w3 - A * pd * math.cos(th))
        # ∂U_eff/∂θ at the momenta of the rates = −sin θ × (the relation): zero exactly at steady precession.
        assert float(red.conditions[0].subs(subs)) == pytest.approx(-math.sin(th) * relation, rel=1e-10)
    assert float(red.inertia[0, 0].subs({se.Symbol("A"): A})) == A


@pytest.mark.slow
def test_top_steady_precession_rates_slow_and_fast():
    """Given θ0 and φ̇: (A − C) cos θ0 ψ̇² − C φ̇ ψ̇ + m g a = 0, two real roots (slow, fast precession)."""
    m, g, a, A, C = (TOP[k] for k in ("m", "g", "a", "A", "C"))
    th, fd = 0.5, 80.0
    found = lagrangian.steady_motions(_eom("lagrange_top"), {"theta": th, "phi_dot": fd})
    roots = np.sort(np.roots([(A - C) * math.cos(th), -C * fd, m * g * a]).real)
    np.testing.assert_allclose(sorted(s.rates["psi_dot"] for s in found), roots, rtol=1e-12)
    assert all(s.stable is True and "Routh" in s.reason for s in found)


@pytest.mark.slow
def test_routh_stiffness_agrees_with_the_linearization():
    """Two formulations: U_eff''(θ0)/a (Routh, fixed K and H) and the nutation eigenvalue of the full
    linearization about the same steady precession."""
    eom = _eom("lagrange_top")
    slow = min(lagrangian.steady_motions(eom, {"theta": 0.5, "phi_dot": 80.0}), key=lambda s: s.rates["psi_dot"])
    lin = lagrangian.linearize(eom, {"psi": 0, "theta": 0.5, "phi": 0, "psi_dot": slow.rates["psi_dot"],
                                     "phi_dot": 80.0})
    nutation = max(m.damped_frequency for m in lin.modes().modes)
    assert nutation**2 == pytest.approx(slow.stiffness[0, 0] / TOP["A"], rel=1e-9)


@pytest.mark.slow
def test_spherical_pendulum_conical_motion():
    """Conical pendulum: ψ̇² = g/(l cos θ0) (θ from the descending vertical); none above the pivot."""
    eom = _eom("spherical_pendulum")
    values = {p.name: p.value for p in eom.model.parameters}
    g, l = values["g"], values["l"]
    found = lagrangian.steady_motions(eom, {"theta": 0.6})
    assert sorted(abs(s.rates["psi_dot"]) for s in found) == pytest.approx([math.sqrt(g / (l * math.cos(0.6)))] * 2)
    assert all(s.stable for s in found)
    assert lagrangian.steady_motions(eom, {"theta": 2.5}) == ()


def test_no_cyclic_coordinate_is_refused():
    with pytest.raises(StructureError, match="none is cyclic"):
        lagrangian.routh_reduction(_eom("double_pendulum"))
    with pytest.raises(StructureError, match="complementary constraints"):
        lagrangian.routh_reduction(_eom("rolling_coin"))
