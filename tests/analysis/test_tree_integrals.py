"""The first integrals `simulate` monitors on a model that takes the recursive route, against the course's
`first_integrals` and the angular momentum of a satellite with a reaction wheel written out by hand."""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se
from more_systems import eom as system_eom

import lagrangian
from lagrangian.analysis._tree_integrals import tree_integrals


def _rz(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _rx(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _sigma_O(q: np.ndarray, qd: np.ndarray, v: dict[str, float]) -> np.ndarray:
    """σ_O(Σ/R0) in R0: Π_O(sat) Ω(S) + Π_G(wheel) Ω(W) + mw OG ∧ V(G), Euler angles z-x-z (ψ, θ, φ), the
    wheel turning by α about S x at OG = d S x."""
    psi, theta, phi, _ = q
    psid, thetad, phid, alphad = qd
    R1 = _rz(psi)
    R2 = R1 @ _rx(theta)
    RS = R2 @ _rz(phi)
    omega = psid * np.array([0, 0, 1.0]) + thetad * R1[:, 0] + phid * R2[:, 2]
    omega_w = omega + alphad * RS[:, 0]
    sat = RS @ np.diag([v["A"], v["B"], v["C"]]) @ RS.T
    wheel = RS @ np.diag([v["Iw"], v["Jw"], v["Jw"]]) @ RS.T  # axisymmetric about S x: the same in S's basis
    OG = v["d"] * RS[:, 0]
    return sat @ omega + wheel @ omega_w + v["mw"] * np.cross(OG, np.cross(omega, OG))


def test_the_satellite_takes_the_recursive_route_and_keeps_the_integrals_derive_reports():
    eom = system_eom("satellite")
    assert eom.formulation == "recursive"
    course = lagrangian.first_integrals(eom)
    tree = tree_integrals(eom)
    assert [(f.name, f.kind) for f in tree] == [(f.name, f.kind) for f in course] == [
        ("p_psi", "momentum"), ("p_alpha", "momentum"), ("E", "energy"), ("sigma_O_x0", "symmetry"),
        ("sigma_O_y0", "symmetry")]


def test_simulate_monitors_the_momenta_and_the_angular_momentum_of_the_satellite():
    eom = system_eom("satellite")
    run = lagrangian.simulate(eom, 2.0, n_out=41)
    assert run.integrals == ("p_psi", "p_alpha", "E", "sigma_O_x0", "sigma_O_y0")
    values = {p.name: p.value for p in eom.model.parameters}
    k = [20, 40]
    for i in k:
        sigma = _sigma_O(run.q[i], run.qd[i], values)
        assert run.monitors["sigma_O_x0"][i] == pytest.approx(sigma[0], rel=1e-9, abs=1e-9)
        assert run.monitors["sigma_O_y0"][i] == pytest.approx(sigma[1], rel=1e-9, abs=1e-9)
        assert run.monitors["p_psi"][i] == pytest.approx(sigma[2], rel=1e-9)  # K = σ_O·z0
        # the wheel's axial momentum, by hand: Iw (α̇ + Ω(S)·S x)
        psi, theta, phi, _ = run.q[i]
        S_x = (_rz(psi) @ _rx(theta) @ _rz(phi))[:, 0]
        w = run.qd[i][0] * np.array([0, 0, 1.0]) + run.qd[i][1] * _rz(psi)[:, 0] \
            + run.qd[i][2] * (_rz(psi) @ _rx(theta))[:, 2]
        assert run.monitors["p_alpha"][i] == pytest.approx(values["Iw"] * (run.qd[i][3] + w @ S_x), rel=1e-9)
    for name in run.integrals:
        assert np.ptp(run.monitors[name]) <= 1e-8 * max(1.0, float(np.abs(run.monitors[name]).max()))
    # The course's expressions of the same integrals, evaluated on the trajectory, agree.
    course = {f.name: f.expression for f in lagrangian.first_integrals(eom)}
    at = {se.Symbol(n): se.RealDouble(v) for n, v in values.items()}
    for name in ("p_psi", "sigma_O_x0"):
        for i in k:
            state = {**at, **{s: se.RealDouble(x) for s, x in zip(eom.q, run.q[i], strict=True)},
                     **{s: se.RealDouble(x) for s, x in zip(eom.qd, run.qd[i], strict=True)}}
            assert float(course[name].xreplace(state)) == pytest.approx(run.monitors[name][i], rel=1e-9, abs=1e-9)
