"""The examples in moving frames and on moving supports against their textbook results.

* Bead on a hoop turning at Ω, written in the hoop's frame: the relative equilibria
  cos θ = g/(R Ω²) exist beyond the critical rate Ω² = g/R, where the bottom loses its
  stability; small oscillations about them have ω² = Ω² sin²θ_e = Ω² − g²/(R² Ω²); the
  Jacobi integral is constant along the motion.
* Foucault's pendulum at latitude λ: the plane of oscillation turns at −Ω sin λ about the
  local vertical (Foucault 1851; Landau & Lifshitz, *Mechanics*, §39, problem 3).
* Kapitza's pendulum, pivot at a cos(νt): the inverted position is stable when
  a² ν² > 2 g l, and then oscillates slowly with ω² = a² ν²/(2 l²) − g/l (Landau & Lifshitz,
  *Mechanics*, §30, problem 1).
* The block on a belt (stick-slip): from rest it slips until ẋ = v_b at
  t1 = asin(k v_b/(f m g ω))/ω, sticks until k x = f m g, then follows the limit cycle
  x = f m g/k + (v_b/ω) sin ω(t − t2), ω = √(k/m).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR
from scipy.optimize import brentq

import lagrangian
from lagrangian.numerics import simulate


@functools.cache
def eom_of(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))


def values(eom: lagrangian.EquationsOfMotion) -> dict[str, float]:
    return {p.name: p.value for p in eom.model.parameters}


def slow_crossings(t: np.ndarray, x: np.ndarray, period: float) -> np.ndarray:
    """Times where ``x`` averaged over a sliding window of ``period`` changes sign."""
    width = max(1, int(round(period / (t[1] - t[0]))))
    smooth = np.convolve(x, np.ones(width) / width, mode="valid")
    times = t[:len(smooth)] + (width - 1) * (t[1] - t[0]) / 2
    return times[1:][np.sign(smooth[1:]) != np.sign(smooth[:-1])]


# -- bead on a rotating hoop ------------------------------------------------------------------------
def _bead_rhs(Omega: float):  # noqa: ANN202
    """θ ↦ θ̈ at θ̇ = 0, from the engine's M and F, with the hoop turning at ``Omega``."""
    eom = eom_of("bead_rotating_hoop.toml")
    p = {se.Symbol(k): v for k, v in values(eom).items()} | {se.Symbol("Omega"): Omega}
    f = se.Lambdify([eom.q[0]], [(eom.F[0] / eom.M[0][0]).subs(p).subs({eom.qd[0]: 0})], real=True)
    return lambda theta: float(np.asarray(f([theta])).ravel()[0])


def test_bead_relative_equilibria_beyond_the_critical_rate() -> None:
    p = values(eom_of("bead_rotating_hoop.toml"))
    g, R, Omega = p["g"], p["R"], p["Omega"]
    assert Omega**2 > g / R  # 36 > 19.6: beyond the critical rate
    rhs = _bead_rhs(Omega)
    theta_e = brentq(rhs, 0.1, np.pi / 2)  # where the right side of L(θ) vanishes
    assert theta_e == pytest.approx(np.arccos(g / (R * Omega**2)), rel=1e-12)
    h = 1e-6
    slope_e = (rhs(theta_e + h) - rhs(theta_e - h)) / (2 * h)
    slope_0 = (rhs(h) - rhs(-h)) / (2 * h)
    assert slope_e == pytest.approx(-(Omega**2 - g**2 / (R**2 * Omega**2)), rel=1e-6)  # stable: ω² > 0
    assert slope_0 == pytest.approx(Omega**2 - g / R, rel=1e-6)  # the bottom is unstable


def test_bead_below_the_critical_rate_rests_at_the_bottom() -> None:
    p = values(eom_of("bead_rotating_hoop.toml"))
    Omega = 0.8 * np.sqrt(p["g"] / p["R"])
    rhs = _bead_rhs(Omega)
    grid = np.linspace(0.01, np.pi - 0.01, 400)
    assert np.all(np.array([rhs(x) for x in grid]) < 0)  # no equilibrium between 0 and π
    h = 1e-6
    assert (rhs(h) - rhs(-h)) / (2 * h) < 0  # θ = 0 is stable


def test_bead_oscillates_about_its_equilibrium_with_the_jacobi_integral_constant() -> None:
    eom = eom_of("bead_rotating_hoop.toml")
    p = values(eom)
    g, R, Omega = p["g"], p["R"], p["Omega"]
    theta_e = np.arccos(g / (R * Omega**2))
    omega = np.sqrt(Omega**2 - g**2 / (R**2 * Omega**2))
    tr = simulate(eom, 5.0, initial={"theta": theta_e + 0.01, "theta_dot": 0.0}, n_out=5001)
    assert tr.integrals == ("h",) and tr.drift["h"] < 1e-9
    crossings = slow_crossings(tr.t, tr.column("theta") - theta_e, 1e-9)
    # Amplitude 0.01: the anharmonic shift of the period is of order 1e-4 relative.
    assert 2 * np.mean(np.diff(crossings)) == pytest.approx(2 * np.pi / omega, rel=1e-3)


# -- Foucault's pendulum ----------------------------------------------------------------------------
def precession_rate(latitude: float) -> tuple[float, float]:
    """(measured rate of the plane of oscillation, −Ω sin λ) over 10 swings."""
    eom = eom_of("foucault_pendulum.toml")
    tr = simulate(eom, 20.0, parameters={"lam": latitude}, n_out=20001)
    alpha, beta = tr.column("alpha"), tr.column("beta")
    x, y = -np.sin(beta), np.sin(alpha) * np.cos(beta)  # the bob in the horizontal plane (south, east)
    r = np.hypot(x, y)
    turning = (r[1:-1] >= r[:-2]) & (r[1:-1] > r[2:])  # the ends of each swing
    k = np.flatnonzero(turning) + 1
    plane = np.unwrap(2 * np.arctan2(y[k], x[k])) / 2  # a line: angles modulo π
    rate = np.polyfit(tr.t[k], plane, 1)[0]
    return rate, -values(eom)["Omega"] * np.sin(latitude)


@pytest.mark.parametrize("latitude", [np.pi / 4, np.pi / 6, -np.pi / 3])
def test_foucault_plane_turns_at_minus_omega_sin_latitude(latitude: float) -> None:
    measured, expected = precession_rate(latitude)
    # Ω/ω0 = 0.064: the O(Ω²/ω0²) centrifugal terms and the 0.1 rad amplitude shift it by < 1 %.
    assert measured == pytest.approx(expected, rel=0.01)


# -- Kapitza's pendulum -----------------------------------------------------------------------------
def kapitza_threshold() -> float:
    p = values(eom_of("kapitza_pendulum.toml"))
    return np.sqrt(2 * p["g"] * p["l"]) / p["a"]  # a² ν² = 2 g l


@pytest.mark.parametrize(("ratio", "stays"), [(2.0, True), (1.3, True), (0.8, False), (0.6, False)])
def test_kapitza_inverted_position_is_stable_above_the_threshold(ratio: float, stays: bool) -> None:
    eom = eom_of("kapitza_pendulum.toml")
    tr = simulate(eom, 2.0, parameters={"nu": ratio * kapitza_threshold()}, n_out=2001)
    deviation = np.max(np.abs(tr.column("theta") - np.pi))
    start = abs(eom.model.coordinate("theta").initial - np.pi)
    if stays:
        assert deviation <= start * 1.2  # it oscillates about π with the starting amplitude
    else:
        assert deviation > 1.0  # it falls


def test_kapitza_slow_oscillation_about_the_inverted_position() -> None:
    eom = eom_of("kapitza_pendulum.toml")
    p = values(eom)
    a, l, g, nu = p["a"], p["l"], p["g"], p["nu"]
    omega = np.sqrt(a**2 * nu**2 / (2 * l**2) - g / l)  # the effective potential's curvature at π
    tr = simulate(eom, 2.0, n_out=40001)
    crossings = slow_crossings(tr.t, tr.column("theta") - np.pi, 2 * np.pi / nu)
    # Averaging is exact to O(ω/ν)² ≈ 1e-3, plus the 0.14 rad amplitude's anharmonicity.
    assert 2 * np.mean(np.diff(crossings)) == pytest.approx(2 * np.pi / omega, rel=0.01)


# -- the block on a belt ----------------------------------------------------------------------------
def test_block_on_belt_slips_sticks_then_settles_on_the_limit_cycle() -> None:
    eom = eom_of("block_on_belt.toml")
    p = values(eom)
    m, k, f, g, v_b, eps = p["m"], p["k"], p["f"], p["g"], p["v_b"], p["eps"]
    w = np.sqrt(k / m)
    x_star = f * m * g / k
    t1 = np.arcsin(v_b / (x_star * w)) / w  # end of the first slip: ẋ = x* ω sin ωt reaches v_b
    x1 = x_star * (1 - np.cos(w * t1))
    t2 = t1 + (x_star - x1) / v_b  # carried by the belt until k x = f m g
    tr = simulate(eom, 8.0, n_out=8001)
    t, x, v = tr.t, tr.column("x"), tr.column("x_dot")
    slip = t < t1 - 0.01
    assert np.max(np.abs(x[slip] - x_star * (1 - np.cos(w * t[slip])))) <= 1e-5
    stick = (t > t1 + 0.01) & (t < t2 - 0.05)
    assert np.max(np.abs(v[stick] - v_b)) <= 10 * eps  # carried at the belt's speed (creep of order ε)
    # The first half cycle after the stick phase.  Near k x = f m g the regularised contact
    # creeps ahead of the belt (ε r/√(1 − r²) grows as r → 1) and the slip starts 0.5 mm early,
    # with v within ε of v_b where the friction is weakened: 1.3 % of the amplitude (measured).
    first = (t > t2) & (t < t2 + np.pi / w)
    cycle = x_star + v_b / w * np.sin(w * (t[first] - t2))
    assert np.max(np.abs(x[first] - cycle)) <= 0.02 * v_b / w
    # Later cycles: x* ± v_b/ω at the period 2π/ω.  The regularised law weakens the friction
    # where each slip comes within ε of v_b, which slowly shrinks the cycle: after three
    # cycles the top speed is v_b − 12 ε (measured), the amplitude 2.4 % short of v_b/ω.
    late = t > t[-1] - 2 * np.pi / w
    assert (np.max(x[late]) + np.min(x[late])) / 2 == pytest.approx(x_star, rel=1e-3)
    assert (np.max(x[late]) - np.min(x[late])) / 2 == pytest.approx(v_b / w, rel=0.05)
    assert v_b - 30 * eps <= np.max(v[late]) <= v_b
    crossings = slow_crossings(t[t > t2], x[t > t2] - x_star, 1e-9)
    assert 2 * np.mean(np.diff(crossings)) == pytest.approx(2 * np.pi / w, rel=1e-3)
