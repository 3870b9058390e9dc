"""Motions with unilateral contacts (`numerics._contact`), against closed forms.

Each shipped example is checked against its textbook solution, derived in the test:

* the bouncing ball (h₀, e): impacts at t_k = t₁ + Σ_{j<k} 2 v₁ eʲ/g with t₁ = √(2h₀/g), v₁ = √(2gh₀);
  apexes h_k = e^{2k} h₀; percussions m (1 + e) v₁ e^{k−1}; the accumulation at
  t_∞ = t₁ (1 + e)/(1 − e), then rest with λ = m g;
* the ladder on a smooth wall and floor: θ̇² = (3g/2a)(sin θ₀ − sin θ), the wall's reaction
  m ẍ_G = (3/4) m g cos θ (3 sin θ − 2 sin θ₀), lift-off at sin θ = (2/3) sin θ₀;
* the rocking block (Housner): θ̇⁺/θ̇⁻ = 1 − (3/2) sin²α at every impact, kinetic energy × r²,
  and the accumulation to rest flat on both corners (λ = m g/2 each);
* Newton's cradle: the simultaneous impact of the linear complementarity problem with the
  Delassus matrix (1/m) tridiag(−1, 2, −1), for 3 and 5 balls, e = 1 and e < 1;
* the slack rope: slack at cos φ_s = (2gl − v₀²)/(3gl), free flight on the parabola from there, taut
  again where that parabola meets the circle (a quartic solved by NumPy), the radial velocity
  stopped (e = 0) and the tangential one kept.

Events are located to a few ulp and the phases integrated at rtol = atol = 1e-10 (1e-9 below).
"""

from __future__ import annotations

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.numerics import ContactEvent, EventSpec

G = 9.81


@pytest.fixture(scope="module")
def ball() -> lagrangian.Model:
    return lagrangian.load_model(EXAMPLES_DIR / "bouncing_ball.toml")


def _events(tr: lagrangian.Trajectory, name: str) -> list:
    return [e for e in tr.events if e.name == name]


# -- the bouncing ball -------------------------------------------------------------------------------------
@pytest.mark.slow
def test_the_bouncing_ball_bounces_at_the_closed_form_times_and_heights(ball: lagrangian.Model) -> None:
    h0, e, m = 1.0, 0.8, 0.1
    tr = lagrangian.simulate(ball, 6.0, n_out=601, events=[EventSpec("apex", "z_dot", -1)])
    impacts, apexes = _events(tr, "impact_floor"), _events(tr, "apex")
    t1, v1 = np.sqrt(2 * h0 / G), np.sqrt(2 * G * h0)
    k = np.arange(len(impacts))
    times = t1 + np.concatenate([[0.0], np.cumsum(2 * v1 * e ** k[1:] / G)])
    assert len(impacts) > 30
    assert np.max(np.abs([i.t for i in impacts] - times)) <= 1e-9
    heights = np.array([a.q[0] for a in apexes[:20]])
    assert np.max(np.abs(heights - e ** (2 * np.arange(1, 21)) * h0)) <= 1e-9
    P = np.array([i.percussion for i in impacts[:20]])
    assert np.allclose(P, m * (1 + e) * v1 * e ** np.arange(20), rtol=1e-9)
    for i in impacts[:20]:  # at z = 0 the energy is kinetic: E⁺ = e² E⁻
        assert isinstance(i, ContactEvent) and i.energy_after == pytest.approx(e**2 * i.energy_before, rel=1e-9)
        assert i.qd_after[0] == pytest.approx(-e * i.qd[0], rel=1e-12)


def test_the_bouncing_ball_comes_to_rest_at_the_accumulation_time(ball: lagrangian.Model) -> None:
    h0, e, m = 1.0, 0.8, 0.1
    tr = lagrangian.simulate(ball, 6.0, n_out=601)
    [rest] = _events(tr, "rest_floor")
    t_inf = np.sqrt(2 * h0 / G) * (1 + e) / (1 - e)
    assert rest.t == pytest.approx(t_inf, abs=1e-9)
    after = tr.t > t_inf
    assert np.max(np.abs(tr.column("z")[after])) <= 1e-12 and np.all(tr.column("z_dot")[after] == 0)
    assert np.all(tr.column("closed_floor")[after] == 1)
    assert np.allclose(tr.column("lambda_floor")[after], m * G, rtol=1e-12)
    assert np.allclose(tr.column("R_floor_z0")[after], m * G, rtol=1e-12)  # the floor's force on the ball
    assert tr.drift["E"] <= 1e-12  # between impacts the energy holds
    assert not tr.warnings


def test_an_elastic_ball_keeps_its_energy_and_height(ball: lagrangian.Model) -> None:
    tr = lagrangian.simulate(ball, 3.0, parameters={"e": 1.0}, n_out=301, events=[EventSpec("apex", "z_dot", -1)])
    impacts = _events(tr, "impact_floor")
    assert len(impacts) == 3 and not _events(tr, "rest_floor")  # at t₁ (2k + 1), t₁ = 0.4515
    assert all(abs(i.energy_after - i.energy_before) <= 1e-12 for i in impacts)
    assert np.allclose([a.q[0] for a in _events(tr, "apex")], 1.0, atol=1e-9)


def test_a_plastic_ball_stays_on_the_floor(ball: lagrangian.Model) -> None:
    tr = lagrangian.simulate(ball, 1.0, parameters={"e": 0.0}, n_out=101)
    [impact] = _events(tr, "impact_floor")
    assert impact.qd_after[0] == 0.0 and impact.energy_after == pytest.approx(0.0, abs=1e-15)
    after = tr.t > impact.t
    assert np.all(tr.column("closed_floor")[after] == 1) and np.max(np.abs(tr.column("z")[after])) <= 1e-15


# -- the sliding ladder --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def ladder() -> lagrangian.Trajectory:
    return lagrangian.simulate(EXAMPLES_DIR / "sliding_ladder.toml", 1.5, n_out=1501)


@pytest.mark.slow
def test_the_ladder_leaves_the_wall_at_two_thirds_of_its_height(ladder: lagrangian.Trajectory) -> None:
    a, th0 = 1.5, np.radians(70.0)
    [lift] = _events(ladder, "liftoff_wall")
    _, y, th = lift.q
    top = y + a * np.sin(th)  # the height of A
    assert top / (2 * a * np.sin(th0)) == pytest.approx(2 / 3, abs=1e-8)
    assert lift.qd[2] ** 2 == pytest.approx(3 * G / (2 * a) * (np.sin(th0) - np.sin(th)), rel=1e-8)


def test_the_walls_reaction_is_the_closed_form_until_lift_off(ladder: lagrangian.Trajectory) -> None:
    m, th0 = 10.0, np.radians(70.0)
    [lift] = _events(ladder, "liftoff_wall")
    before = ladder.t < lift.t
    th = ladder.column("theta")[before]
    N = 0.75 * m * G * np.cos(th) * (3 * np.sin(th) - 2 * np.sin(th0))
    assert np.max(np.abs(ladder.column("lambda_wall")[before] - N)) <= 1e-8 * m * G
    assert np.all(ladder.column("lambda_wall")[before] >= 0) and np.all(ladder.column("lambda_floor") >= 0)
    after = ladder.t > lift.t
    assert np.all(ladder.column("lambda_wall")[after] == 0) and np.all(ladder.column("closed_wall")[after] == 0)
    # From lift-off on, no horizontal force: ẋ stays what it was.
    assert np.max(np.abs(ladder.column("x_dot")[after] - lift.qd[0])) <= 1e-9


def test_the_ladder_lands_flat_and_slides_on(ladder: lagrangian.Trajectory) -> None:
    [lift] = _events(ladder, "liftoff_wall")
    [land] = _events(ladder, "impact_top")
    assert land.t > lift.t and abs(land.q[2]) <= 1e-9  # flat: its top A reaches the floor
    assert np.max(np.abs(land.qd_after[1:])) <= 1e-9 and land.qd_after[0] == pytest.approx(lift.qd[0], rel=1e-9)
    before = ladder.t < land.t
    E = ladder.column("E")
    assert np.max(np.abs(E[before] - E[0])) <= 1e-8 * abs(E[0])
    after = ladder.t > land.t
    assert np.all(ladder.column("closed_floor")[after] == 1) and np.all(ladder.column("closed_top")[after] == 1)


# -- the rocking block -----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def block() -> lagrangian.Model:
    return lagrangian.load_model(EXAMPLES_DIR / "rocking_block.toml")


@pytest.mark.slow
def test_the_rocking_block_keeps_housners_ratio_at_every_impact(block: lagrangian.Model) -> None:
    b, h, m = 0.1, 0.5, 2.0
    r = 1 - 1.5 * np.sin(np.arctan(b / h)) ** 2
    tr = lagrangian.simulate(block, 2.0, n_out=401)
    impacts = [e for e in tr.events if e.kind == "impact"]
    assert [e.contact for e in impacts[:4]] == ["right", "left", "right", "left"]
    for i in impacts:
        assert i.qd_after[2] / i.qd[2] == pytest.approx(r, abs=1e-10)
        T0 = 0.5 * m * (i.qd[0] ** 2 + i.qd[1] ** 2) + 0.5 * m * (b**2 + h**2) / 3 * i.qd[2] ** 2
        assert (i.energy_before - i.energy_after) == pytest.approx((1 - r**2) * T0, rel=1e-9)
    # It rocks without sliding: the pivot's friction stays within the cone, μ = 1.
    for side in ("left", "right"):
        closed = tr.column(f"closed_{side}") == 1
        assert np.all(np.abs(tr.column(f"lambda_{side}_t")[closed]) <= tr.column(f"lambda_{side}")[closed])


@pytest.mark.slow
def test_the_rocking_block_settles_flat_on_both_corners(block: lagrangian.Model) -> None:
    m, b, h, th = 2.0, 0.3, 0.5, 0.1  # a stouter block (r = 0.60): fewer impacts before it settles
    start = {"x": b * np.cos(th) - h * np.sin(th), "y": b * np.sin(th) + h * np.cos(th)}  # resting on L
    tr = lagrangian.simulate(block, 3.0, parameters={"b": b}, initial=start, n_out=201)
    rests = [e for e in tr.events if e.kind == "rest"]
    assert {e.contact for e in rests} == {"left", "right"}
    after = tr.t > rests[0].t
    assert np.max(np.abs(tr.qd[after])) <= 1e-9 and np.max(np.abs(tr.column("theta")[after])) <= 1e-9
    assert np.allclose(tr.column("lambda_left")[after], m * G / 2, rtol=1e-9)
    assert np.allclose(tr.column("lambda_right")[after], m * G / 2, rtol=1e-9)


# -- Newton's cradle -----------------------------------------------------------------------------------------------
def _cradle(balls: int) -> lagrangian.Model:
    text = (EXAMPLES_DIR / "newtons_cradle.toml").read_text()
    head = text[:text.index("[coordinates]")]
    parts = ["[coordinates]"]
    for k in range(1, balls + 1):
        parts.append(f'theta{k} = {{ initial = {-0.3 if k == 1 else 0.0}, rate = 0.0 }}')
    for k in range(1, balls + 1):
        parts += [f"[particles.B{k}]", 'mass = "m"',
                  f'position = "({k - 1}*d + l*sin(theta{k}))*R0.x - l*cos(theta{k})*R0.y"']
    parts += ["[loads]", 'weight = { gravity = "-g*R0.y" }', "[constraints]"]
    for k in range(1, balls):
        gap = (f"sqrt((d + l*sin(theta{k + 1}) - l*sin(theta{k}))^2 + (l*cos(theta{k}) - l*cos(theta{k + 1}))^2) - d")
        parts.append(f'c{k}{k + 1} = {{ unilateral = "{gap}", restitution = "e" }}')
    return lagrangian.parse_model(head + "\n".join(parts) + "\n", source=f"cradle{balls}.toml")


@pytest.mark.slow
@pytest.mark.parametrize("balls", [3, 5])
@pytest.mark.parametrize("e", [1.0, 0.6])
def test_newtons_cradle_impact_is_the_complementarity_problems(balls: int, e: float) -> None:
    model = lagrangian.load_model(EXAMPLES_DIR / "newtons_cradle.toml") if balls == 3 else _cradle(balls)
    m, l = 0.1, 1.0
    tr = lagrangian.simulate(model, 0.6, parameters={"e": e}, n_out=61)
    impacts = [ev for ev in tr.events if ev.kind == "impact"]
    assert {ev.t for ev in impacts} == {impacts[0].t} and len(impacts) == balls - 1  # every contact at once
    first = impacts[0]
    w = first.qd[0]
    assert w == pytest.approx(np.sqrt(2 * G / l * (1 - np.cos(0.3))), rel=1e-9)  # energy of the swing
    expected = np.full(balls, (1 + e) * w / balls)
    expected[0] = w * (1 - (balls - 1) * (1 + e) / balls)
    assert np.allclose(first.qd_after, expected, rtol=1e-9, atol=1e-12)
    k = np.arange(1, balls)
    P = sorted((ev.contact, ev.percussion) for ev in impacts)
    assert np.allclose([p for _, p in P], (1 + e) * m * l * w * (balls - k) / balls, rtol=1e-9)
    assert m * l * first.qd_after.sum() == pytest.approx(m * l * w, rel=1e-12)  # momentum about the pivots' line
    lost = 0.5 * m * l**2 * (w**2 - first.qd_after @ first.qd_after)
    assert first.energy_before - first.energy_after == pytest.approx(lost, abs=1e-12)
    assert lost == pytest.approx(0.5 * (1 - e) * P[0][1] * l * w, abs=1e-12)


# -- the slack rope ---------------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_the_rope_goes_slack_the_bob_flies_on_a_parabola_and_the_rope_jerks_taut() -> None:
    m, l, v0 = 0.5, 1.0, 5.859607495387383
    tr = lagrangian.simulate(EXAMPLES_DIR / "slack_rope_pendulum.toml", 2.0, n_out=2001)
    [slack], [taut] = _events(tr, "liftoff_rope"), _events(tr, "impact_rope")
    cos_s = (2 * G * l - v0**2) / (3 * G * l)
    phi = np.arccos(cos_s)
    xs, ys = l * np.sin(phi), -l * np.cos(phi)
    v = np.sqrt(G * l * -cos_s)
    vx, vy = v * np.cos(phi), v * np.sin(phi)  # l φ̇ (cos φ, sin φ): turning counterclockwise
    assert slack.q == pytest.approx([xs, ys], abs=1e-9) and slack.qd == pytest.approx([vx, vy], abs=1e-8)
    # Taut again where the parabola meets the circle: (xs + vx τ)² + (ys + vy τ − g τ²/2)² = l², τ > 0.
    coefficients = np.polynomial.polynomial.polyadd(np.polynomial.polynomial.polypow([xs, vx], 2),
                                                    np.polynomial.polynomial.polypow([ys, vy, -G / 2], 2))
    coefficients[0] -= l**2
    roots = np.polynomial.polynomial.polyroots(coefficients)
    tau = min(r.real for r in roots if abs(r.imag) < 1e-9 and r.real > 1e-6)
    assert taut.t - slack.t == pytest.approx(tau, abs=1e-9)
    flight = (tr.t > slack.t) & (tr.t < taut.t)
    s = tr.t[flight] - slack.t
    assert np.max(np.abs(tr.column("x")[flight] - (xs + vx * s))) <= 1e-8
    assert np.max(np.abs(tr.column("y")[flight] - (ys + vy * s - G * s**2 / 2))) <= 1e-8
    assert np.all(tr.column("lambda_rope")[flight] == 0) and np.all(tr.column("closed_rope")[flight] == 0)
    # The jerk (e = 0) stops the radial velocity and keeps the tangential one.
    u = taut.q / np.linalg.norm(taut.q)
    radial = taut.qd @ u
    assert abs(taut.qd_after @ u) <= 1e-9
    tangent = np.array([-u[1], u[0]])
    assert taut.qd_after @ tangent == pytest.approx(taut.qd @ tangent, rel=1e-12)
    assert taut.energy_before - taut.energy_after == pytest.approx(0.5 * m * radial**2, rel=1e-9)
    assert taut.percussion == pytest.approx(m * abs(radial), rel=1e-9)  # the rope pulls: P ≥ 0
    taut_after = tr.t > taut.t
    assert np.all(tr.column("closed_rope")[taut_after] == 1) and np.all(tr.column("lambda_rope")[taut_after] > 0)


# -- friction at an impact ------------------------------------------------------------------------------------------------
OBLIQUE = """
[parameters]
m = 0.2
g = 9.81
e = 0.5
mu = 0.3
[coordinates]
x = { initial = 0.0, rate = 1.0 }
z = { initial = 0.5, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x + z*R0.z"
[loads]
weight = { gravity = "-g*R0.z" }
[constraints]
floor = { unilateral = "z", restitution = "e", friction = "mu", slip = "x_dot" }
"""


@pytest.mark.slow
@pytest.mark.parametrize(("vx", "stick"), [(0.5, True), (3.0, False)])
def test_a_ball_hitting_a_rough_floor_sticks_or_slides_at_the_impact(vx: float, stick: bool) -> None:
    # Coulomb at the impact: P_n = m (1 + e) v, |P_t| ≤ μ P_n; v = √(2 g h) = 3.13 m/s, μ (1 + e) v = 1.41 m/s.
    model = lagrangian.parse_model(OBLIQUE, source="oblique.toml")
    m, e, mu = 0.2, 0.5, 0.3
    tr = lagrangian.simulate(model, 0.5, initial={"x_dot": vx}, n_out=51)
    [impact] = _events(tr, "impact_floor")
    v = np.sqrt(2 * G * 0.5)
    assert impact.qd[1] == pytest.approx(-v, rel=1e-9) and impact.percussion == pytest.approx(m * (1 + e) * v, rel=1e-9)
    assert impact.qd_after[1] == pytest.approx(e * v, rel=1e-9)  # it bounces off
    if stick:
        assert abs(impact.qd_after[0]) <= 1e-12 and impact.tangential == pytest.approx(-m * vx, rel=1e-9)
    else:
        assert impact.qd_after[0] == pytest.approx(vx - mu * (1 + e) * v, rel=1e-9)
        assert impact.tangential == pytest.approx(-mu * impact.percussion, rel=1e-9)
    lost = 0.5 * m * (impact.qd @ impact.qd - impact.qd_after @ impact.qd_after)
    assert impact.energy_before - impact.energy_after == pytest.approx(lost, rel=1e-9) and lost > 0
