"""Exact Coulomb friction (``regularization = 0``): stick/slip phases switched by events.

Closed forms are the truth (any mechanics textbook; e.g. Pfeiffer & Glocker, *Multibody
Dynamics with Unilateral Contacts*, ch. 7, for the stick-slip oscillator):

* a block on an incline with tan α < f_s, released at rest, stays at rest exactly;
* launched at v0 it decelerates at g (sin α ± f cos α), stops at t* = v0/decel after
  v0²/(2 decel), then sticks (tan α < f_s) or slides back at g (sin α − f cos α);
* on a belt of speed v_b, tied by a spring k, from rest at x = 0 it slips with
  x = x*(1 − cos ωt) (x* = f m g/k, ω² = k/m), sticks when ẋ = v_b, is carried until
  k x = f_s m g, then slips on an arc of centre x*: with f_s = f the limit cycle
  x* ± v_b/ω, with f_s > f a cycle that sticks from 2x* − x_s to x_s (x_s = f_s m g/k).

The phases end at events located to a few ulp, and each phase is integrated at
rtol = atol = 1e-10 of a polynomial or harmonic motion, so 1e-9 bounds the errors below.
"""

from __future__ import annotations

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian import ModelError
from lagrangian.errors import SimulationError
from lagrangian.numerics import simulate_stick_slip

TOL = 1e-9  # events to a few ulp, phases integrated at rtol = atol = 1e-10 (module docstring)
G = 9.81

INCLINE = """
[parameters]
m = 2.0
g = 9.81
alpha = {alpha}
f = 0.3
f_s = {f_s}
[coordinates]
x = {{ initial = 0.0, rate = 0.0, description = "distance travelled down the slope" }}
[frames]
I = {{ from = "R0", rotation = ["alpha", "y"] }}
[particles.B]
mass = "m"
position = "x*I.x"
[loads]
weight = {{ gravity = "-g*R0.z" }}
friction = {{ coulomb = "B", coefficient = "f", static_coefficient = "f_s", normal_force = "m*g*cos(alpha)", normal = "I.z", regularization = 0 }}
"""


def incline(alpha: float, f_s: float = 0.3) -> lagrangian.Model:
    return lagrangian.parse_model(INCLINE.format(alpha=alpha, f_s=f_s), source="incline.toml")


def belt(f_s: float | None = None) -> lagrangian.Model:
    text = (EXAMPLES_DIR / "block_on_belt.toml").read_text().replace('regularization = "eps"', 'regularization = 0')
    if f_s is not None:
        text = text.replace('coefficient = "f",', f'coefficient = "f", static_coefficient = "{f_s}",')
    return lagrangian.parse_model(text, source="belt.toml")


# -- the incline ---------------------------------------------------------------------------------
def test_a_block_released_on_a_gentle_incline_stays_exactly_at_rest() -> None:
    tr = simulate_stick_slip(incline(0.2), 5.0, n_out=501)  # tan α = 0.203 < f_s = 0.3
    assert np.max(np.abs(tr.column("x"))) < 1e-12 and np.max(np.abs(tr.column("x_dot"))) < 1e-12
    assert np.all(tr.column("mode_friction") == 0) and not tr.events
    friction = tr.column("friction_friction")  # the multiplier: m g sin α up the slope (−x)
    assert np.allclose(friction, -2.0 * G * np.sin(0.2), rtol=1e-12, atol=0)
    assert np.max(np.abs(friction)) <= 0.3 * 2.0 * G * np.cos(0.2)


@pytest.mark.parametrize("v0", [0.3, -0.3])  # down the slope, then up it
def test_a_block_launched_on_a_gentle_incline_stops_at_the_closed_form_time_then_sticks(v0: float) -> None:
    alpha, f = 0.2, 0.3
    s = np.sign(v0)
    decel = G * (f * np.cos(alpha) - s * np.sin(alpha))  # g (f cos α ∓ sin α)
    tr = simulate_stick_slip(incline(alpha), 1.0, initial={"x_dot": v0}, n_out=1001)
    stop = abs(v0) / decel
    assert [e.name for e in tr.events] == ["stick_friction"]
    assert abs(tr.events[0].t - stop) <= TOL
    sliding = tr.t < stop
    x, v = tr.column("x"), tr.column("x_dot")
    assert np.max(np.abs(v[sliding] - (v0 - s * decel * tr.t[sliding]))) <= TOL
    assert np.max(np.abs(x[~sliding] - s * v0**2 / (2 * decel))) <= TOL
    assert np.max(np.abs(v[~sliding])) < 1e-12  # stuck: no creep
    assert np.all(tr.column("mode_friction")[sliding] == s) and np.all(tr.column("mode_friction")[~sliding] == 0)


def test_a_block_launched_up_a_steep_incline_stops_then_slides_back() -> None:
    alpha, f, v0 = 0.5, 0.3, 1.0  # tan α = 0.546 > f_s = f: it cannot stay
    up, down = G * (np.sin(alpha) + f * np.cos(alpha)), G * (np.sin(alpha) - f * np.cos(alpha))
    tr = simulate_stick_slip(incline(alpha), 0.8, initial={"x_dot": -v0}, n_out=801)
    stop = v0 / up
    assert [e.name for e in tr.events] == ["slip_friction"] and abs(tr.events[0].t - stop) <= TOL
    t = tr.t
    expected = np.where(t < stop, -v0 * t + up * t**2 / 2, -v0**2 / (2 * up) + down * (t - stop) ** 2 / 2)
    assert np.max(np.abs(tr.column("x") - expected)) <= TOL
    assert np.allclose(tr.column("x_ddot"), np.where(t < stop, up, down), rtol=1e-12, atol=0)
    assert set(tr.column("mode_friction")) == {-1.0, 1.0}


def test_the_example_block_slides_up_stops_and_sticks() -> None:
    tr = simulate_stick_slip(EXAMPLES_DIR / "block_on_incline.toml", 2.0)
    decel = G * (np.sin(0.2) + 0.3 * np.cos(0.2))
    assert [e.name for e in tr.events] == ["stick_friction"] and abs(tr.events[0].t - 1 / decel) <= TOL
    assert abs(tr.column("x")[-1] + 1 / (2 * decel)) <= TOL
    stuck = tr.column("mode_friction") == 0
    assert np.ptp(tr.column("x")[stuck]) < 1e-12
    assert np.max(np.abs(tr.column("friction_friction")[stuck])) <= 0.4 * 2 * G * np.cos(0.2)


# -- the belt ------------------------------------------------------------------------------------
M, K, F, VB = 1.0, 10.0, 0.3, 0.5
W = np.sqrt(K / M)
X_STAR = F * M * G / K


def test_belt_sticks_until_k_x_reaches_f_m_g_then_slips_on_the_limit_cycle() -> None:
    tr = simulate_stick_slip(belt(), 10.0, n_out=4001)
    t1 = np.arcsin(VB / (X_STAR * W)) / W  # x*(1 − cos ωt) has ẋ = v_b
    x1 = X_STAR * (1 - np.cos(W * t1))
    t2 = t1 + (X_STAR - x1) / VB  # carried at v_b to k x = f m g
    names = [e.name for e in tr.events]
    assert names[:2] == ["stick_friction", "slip_friction"]
    stick, slip = tr.events[:2]
    assert abs(stick.t - t1) <= TOL and abs(stick.q[0] - x1) <= TOL
    assert abs(slip.t - t2) <= TOL and abs(slip.q[0] - X_STAR) <= TOL
    x = tr.column("x")
    later = tr.t > t2
    expected = X_STAR + VB / W * np.sin(W * (tr.t[later] - t2))  # the limit cycle x* ± v_b/ω
    assert np.max(np.abs(x[later] - expected)) <= 1e-8
    stuck = tr.column("mode_friction") == 0
    assert np.max(np.abs(tr.column("x_dot")[stuck] - VB)) < 1e-12
    assert np.max(np.abs(tr.column("friction_friction")[stuck])) <= F * M * G * (1 + 1e-12)


@pytest.mark.slow
def test_belt_with_static_friction_above_kinetic_sticks_from_2x_star_minus_xs_to_xs() -> None:
    f_s = 0.4
    x_s = f_s * M * G / K
    tr = simulate_stick_slip(belt(f_s), 12.0, n_out=1201)
    sticks = [e for e in tr.events if e.name == "stick_friction"]
    slips = [e for e in tr.events if e.name == "slip_friction"]
    assert len(sticks) >= 3 and len(slips) >= 3
    assert all(abs(e.q[0] - x_s) <= TOL for e in slips)  # breaks away where k x = f_s m g
    assert all(abs(e.q[0] - (2 * X_STAR - x_s)) <= TOL for e in sticks[1:])  # catches the belt there
    phi = np.arctan2(W * (x_s - X_STAR), VB)
    period = (2 * np.pi - 2 * phi) / W + 2 * (x_s - X_STAR) / VB  # slip arc, then carried
    assert abs(slips[2].t - slips[1].t - period) <= TOL
    stuck = tr.column("mode_friction") == 0
    assert np.max(np.abs(tr.column("friction_friction")[stuck])) <= f_s * M * G * (1 + 1e-12)


# -- what is refused, what is unchanged ------------------------------------------------------------
def test_omitted_regularization_keeps_the_regularised_law() -> None:
    text = INCLINE.format(alpha=0.2, f_s=0.3).replace(", regularization = 0", "")
    model = lagrangian.parse_model(text.replace(' static_coefficient = "f_s",', ""), source="m.toml")
    load = model.loads[-1]
    assert not load.exact and float(load.regularization) == pytest.approx(1e-3)
    with pytest.raises(ModelError, match="no exact Coulomb contact"):
        simulate_stick_slip(model, 1.0)


def test_a_sliding_velocity_without_a_fixed_direction_is_refused() -> None:
    text = """
[parameters]
m = 1.0
[coordinates]
x = { initial = 0.0, rate = 1.0 }
y = { initial = 0.0, rate = 0.0 }
[particles.B]
mass = "m"
position = "x*R0.x + y*R0.y"
[loads]
friction = { coulomb = "B", coefficient = "0.3", normal_force = "m*9.81", normal = "R0.z", regularization = 0 }
"""
    with pytest.raises(ModelError, match="no fixed direction"):
        simulate_stick_slip(lagrangian.parse_model(text, source="puck.toml"), 1.0)


def test_two_exact_contacts_are_refused() -> None:
    text = INCLINE.format(alpha=0.2, f_s=0.3) + (
        'other = { coulomb = "B", coefficient = "f", normal_force = "1", normal = "I.z", regularization = 0 }\n')
    with pytest.raises(ModelError, match="2 exact Coulomb contacts"):
        simulate_stick_slip(lagrangian.parse_model(text, source="two.toml"), 1.0)


@pytest.mark.parametrize(("options", "words"), [
    ({"dt": 1e-3}, "fixed steps"),
    ({"parameters": {"f_s": 0.1}}, "f ≤ f_s"),
])
def test_bad_options_are_refused(options: dict, words: str) -> None:
    with pytest.raises(SimulationError, match=words):
        simulate_stick_slip(incline(0.2), 1.0, **options)


@pytest.mark.slow
def test_newton_euler_and_reactions_hold_through_the_stuck_phase():
    """Along a motion that slides then sticks, each phase is checked with its own equations:
    no NaN from the exact law's v_s/|v_s| at rest, the normal reaction N·n throughout."""
    from lagrangian.cli.main import main
    from lagrangian.numerics import check_trajectory_along, reaction_history_along

    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "block_on_incline.toml"))
    run = lagrangian.simulate(eom, 1.0, n_out=201)
    assert (run.column("mode_friction") == 0).any() and (run.column("mode_friction") != 0).any()
    res = check_trajectory_along(eom, run)
    assert np.isfinite(res.projections).all() and res.max_relative <= 1e-9
    [history] = reaction_history_along(eom, run).values()
    values = {p.name: p.value for p in eom.model.parameters}
    m, g, alpha = values["m"], values["g"], values["alpha"]
    normal = m * g * np.cos(alpha) * np.array([np.sin(alpha), 0.0, np.cos(alpha)])  # N along the incline's normal
    np.testing.assert_allclose(history.force, np.broadcast_to(normal, history.force.shape), atol=1e-9)
    assert main(["verify", str(EXAMPLES_DIR / "block_on_incline.toml"), "--simulate", "1"]) == 0


@pytest.mark.parametrize("replacement, words", [
    ('regularization = -1', "negative regularization"),
    ('regularization = "eps", static_coefficient = "0.5"', "only the exact law uses"),
])
def test_friction_options_that_would_be_ignored_are_refused(tmp_path, replacement, words):
    text = (EXAMPLES_DIR / "block_on_belt.toml").read_text().replace('regularization = "eps"', replacement)
    path = tmp_path / "belt.toml"
    path.write_text(text)
    with pytest.raises(ModelError, match=words) as info:
        lagrangian.load_model(path)
    assert info.value.line is not None
