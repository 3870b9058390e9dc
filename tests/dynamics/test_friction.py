"""Non-conservative efforts: Rayleigh dissipation, joint dampers, Coulomb friction, driving efforts.

Closed forms are the truth: Q_i = −∂D/∂q̇_i term by term; a joint damper's Q equals the
Rayleigh function ½ c |Ω(S2/S1)|²; a block sliding down an incline accelerates at
g (sin α − f cos α) and sticks when tan α < f; a block launched on a level floor stops
after v0²/(2 f g); a driven damped oscillator settles on F0/√((k − m ω²)² + (c ω)²); a
flywheel under a torque Γ0 sin νt spins at Γ0 (1 − cos νt)/(C ν).  The regularised Coulomb
law errs by (ε/v)² relative while sliding and creeps at ε r/√(1 − r²) (r = load/(f N))
while stuck: tolerances below are set from those two numbers.
"""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian import ModelError
from lagrangian._identity import are_zero, is_zero
from lagrangian.analysis import verify
from lagrangian.numerics import simulate


def derive(text: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(text, source="model.toml"))


def example(name: str) -> str:
    return (EXAMPLES_DIR / name).read_text()


S = se.Symbol


# -- Rayleigh dissipation function ---------------------------------------------------------------
def test_rayleigh_function_gives_minus_its_rate_gradient() -> None:
    text = example("cart_pendulum.toml") + '\n[loads.drag]\ndissipation = "1/2*c*x_dot^2 + b*x_dot*theta_dot"\n'
    text = text.replace("[parameters]", "[parameters]\nc = 0.7\nb = 0.2")
    eom = derive(text)
    drag = next(f for f in eom.loads if f.name == "drag")
    x_dot, theta_dot = eom.qd
    assert drag.kind == "dissipation" and drag.potential is None
    assert are_zero([drag.Q[0] + S("c") * x_dot + S("b") * theta_dot, drag.Q[1] + S("b") * x_dot]) == [True, True]
    assert not eom.conservative
    assert all(i.kind == "momentum" for i in lagrangian.first_integrals(eom))  # no energy integral any more
    assert verify(eom).agrees


def test_a_dissipation_function_without_rates_is_refused() -> None:
    text = example("simple_pendulum.toml") + '\n[loads.drag]\ndissipation = "1/2*m*theta^2"\n'
    with pytest.raises(ModelError, match="depends on no rate") as info:
        lagrangian.parse_model(text, source="p.toml")
    assert info.value.line == len(text.splitlines())


# -- viscous friction in a joint -----------------------------------------------------------------
@pytest.mark.parametrize(("bodies", "expected"), [
    ('["S1", "S2"]', lambda c, td1, td2: (0, -c * td2)),  # θ2 is the angle of S2 relative to S1
    ('["R0", "S1"]', lambda c, td1, td2: (-c * td1, 0)),  # the hinge at O, between the ground and S1
])
def test_joint_damper_opposes_the_relative_rotation(bodies: str, expected) -> None:  # noqa: ANN001
    text = example("double_pendulum.toml").replace("[parameters]", "[parameters]\nc = 0.05")
    eom = derive(text + f'\n[loads.hinge]\njoint_damper = {bodies}\ncoefficient = "c"\n')
    hinge = next(f for f in eom.loads if f.name == "hinge")
    td1, td2 = eom.qd
    assert hinge.kind == "jointdamper" and hinge.potential is None
    assert are_zero([q - e for q, e in zip(hinge.Q, expected(S("c"), td1, td2), strict=True)]) == [True, True]
    assert verify(eom).agrees  # taken as two couples by the Newton–Euler check


def test_joint_damper_is_its_rayleigh_function() -> None:
    base = example("double_pendulum.toml").replace("[parameters]", "[parameters]\nc = 0.05")
    damper = derive(base + '\n[loads.hinge]\njoint_damper = ["S1", "S2"]\ncoefficient = "c"\n')
    rayleigh = derive(base + '\n[loads.hinge]\ndissipation = "1/2*c*theta2_dot^2"\n')
    assert all(are_zero([a - b for a, b in zip(damper.loads[-1].Q, rayleigh.loads[-1].Q, strict=True)]))


@pytest.mark.parametrize(("value", "words"), [
    ('["S1"]', "exactly two bodies"),
    ('["S1", "S9"]', "unknown body `S9`"),
    ('["S1", "S1"]', "to itself"),
])
def test_joint_damper_errors(value: str, words: str) -> None:
    text = example("double_pendulum.toml") + f'\n[loads.hinge]\njoint_damper = {value}\ncoefficient = "1"\n'
    with pytest.raises(ModelError, match=words) as info:
        lagrangian.parse_model(text, source="d.toml")
    assert info.value.line == len(text.splitlines()) - 1


# -- Coulomb friction --------------------------------------------------------------------------------
INCLINE = """
[parameters]
m = 2.0
g = 9.81
alpha = 0.5
f = 0.3
[coordinates]
x = { initial = 0.0, rate = 0.0, description = "distance travelled down the slope" }
[frames]
I = { from = "R0", rotation = ["alpha", "y"] }
[particles.B]
mass = "m"
position = "x*I.x"
[loads]
weight = { gravity = "-g*R0.z" }
friction = { coulomb = "B", coefficient = "f", normal_force = "m*g*cos(alpha)", normal = "I.z" }
"""
EPS = 1e-3  # the default regularisation speed


def test_coulomb_generalized_force_is_the_regularised_law() -> None:
    eom = derive(INCLINE)
    friction = next(f for f in eom.loads if f.name == "friction")
    x_dot = eom.qd[0]
    m, g, alpha, f = S("m"), S("g"), S("alpha"), S("f")
    law = -f * m * g * se.cos(alpha) * x_dot / se.sqrt(x_dot**2 + se.Rational(1, 1000) ** 2)
    assert friction.kind == "coulombfriction" and friction.potential is None
    assert is_zero(friction.Q[0] - law)
    assert "f N" in friction.note
    assert verify(eom).agrees


def test_a_block_slides_down_a_steep_incline_at_g_sin_minus_f_cos() -> None:
    tr = simulate(derive(INCLINE), 1.0, initial={"x_dot": 0.5}, n_out=101)
    g, alpha, f = 9.81, 0.5, 0.3  # tan α = 0.546 > f: it slides
    expected = 0.5 + g * (np.sin(alpha) - f * np.cos(alpha)) * tr.t
    # While sliding at v ≥ 0.5 the regularised law differs from f N by (ε/v)²/2 ≤ 2e-6 relative.
    assert np.max(np.abs(tr.column("x_dot") - expected)) <= 1e-5


def test_a_block_sticks_on_a_gentle_incline() -> None:
    eom = derive(INCLINE.replace("alpha = 0.5", "alpha = 0.2"))  # tan α = 0.203 < f = 0.3
    g, alpha, f, v0 = 9.81, 0.2, 0.3, 0.3
    decel = g * (f * np.cos(alpha) - np.sin(alpha))
    tr = simulate(eom, 1.5, initial={"x_dot": v0}, n_out=1501)
    stop = v0 / decel  # it slows down uniformly, then stays
    v = tr.column("x_dot")
    sliding = tr.t < stop - 0.02
    assert np.max(np.abs(v[sliding] - (v0 - decel * tr.t[sliding]))) <= 1e-4
    r = np.tan(alpha) / f  # held: the friction needed is m g sin α = r f N, reached at a creep speed
    creep = EPS * r / np.sqrt(1 - r**2)
    after = tr.t > stop + 0.05
    assert np.max(np.abs(v[after])) <= 1.5 * creep
    assert abs(tr.column("x")[-1] - v0**2 / (2 * decel)) <= 2 * creep * tr.t[-1]


def test_a_block_launched_on_a_level_floor_stops_after_v0_squared_over_2fg() -> None:
    eom = derive(INCLINE.replace("alpha = 0.5", "alpha = 0.0"))
    v0, f, g = 2.0, 0.3, 9.81
    tr = simulate(eom, 1.2, initial={"x_dot": v0}, n_out=1201)
    # Level floor: nothing pushes once stopped, so the block stays within ε·τ of its stop.
    assert abs(tr.column("x")[-1] - v0**2 / (2 * f * g)) <= 1e-5
    stopped = tr.t > v0 / (f * g) + 0.02
    assert np.max(np.abs(tr.column("x_dot")[stopped])) <= 1e-5


def test_friction_on_a_moving_surface_uses_the_sliding_velocity() -> None:
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "block_on_belt.toml"))
    friction = next(f for f in eom.loads if f.name == "friction")
    x_dot = eom.qd[0]
    slip = x_dot - S("v_b")
    assert is_zero(friction.Q[0] + S("f") * S("m") * S("g") * slip / se.sqrt(slip**2 + S("eps") ** 2))


@pytest.mark.parametrize(("old", "new", "words"), [
    ('coulomb = "B"', 'coulomb = "Z"', "unknown point `Z`"),
    (', normal_force = "m*g*cos(alpha)"', "", "needs `normal_force`"),
    ('coefficient = "f",', 'coefficient = "f", stiff = 1,', "unknown key `stiff`"),
])
def test_coulomb_errors(old: str, new: str, words: str) -> None:
    text = INCLINE.replace(old, new)
    with pytest.raises(ModelError, match=words) as info:
        lagrangian.parse_model(text, source="i.toml")
    assert info.value.line == next(i for i, line in enumerate(text.splitlines(), 1) if line.startswith("friction"))


# -- time-dependent driving efforts ----------------------------------------------------------------
def test_a_driven_damped_oscillator_settles_on_the_resonance_curve() -> None:
    text = """
[parameters]
m = 1.0
k = 4.0
c = 1.0
F0 = 0.5
w = 1.5
[coordinates]
x = { initial = 0.2, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = { spring = ["O", "P"], stiffness = "k" }
drag = { dissipation = "1/2*c*x_dot^2" }
drive = { force = "F0*cos(w*t)*R0.x", at = "P" }
"""
    eom = derive(text)
    assert [f.potential is None for f in eom.loads] == [False, True, True]  # a force that depends on t
    assert lagrangian.first_integrals(eom) == ()
    tr = simulate(eom, 40.0, t_eval=np.linspace(30.0, 40.0, 2001), t_start=0.0)
    m, k, c, F0, w = 1.0, 4.0, 1.0, 0.5, 1.5
    amplitude = F0 / np.hypot(k - m * w**2, c * w)  # the transient decays as e^{−c t/2m}: e^{−15} at t = 30
    phase = np.arctan2(c * w, k - m * w**2)
    assert np.max(np.abs(tr.column("x") - amplitude * np.cos(w * tr.t - phase))) <= 1e-6


def test_a_driving_torque_spins_a_flywheel() -> None:
    text = """
[parameters]
C = 0.3
G0 = 0.6
nu = 2.0
[coordinates]
phi = { initial = 0.0, rate = 0.0 }
[frames]
W = { from = "R0", rotation = ["phi", "z"] }
[bodies.wheel]
frame = "W"
mass = "1"
center = "0*R0.z"
fixed_point = "O"
inertia = { diagonal = ["C/2", "C/2", "C"] }
[loads]
motor = { torque = "G0*sin(nu*t)*R0.z", on = "wheel" }
"""
    eom = derive(text)
    t = eom.t
    assert is_zero(eom.equations[0].lhs - S("C") * eom.qdd[0])
    assert is_zero(eom.equations[0].rhs - S("G0") * se.sin(S("nu") * t))
    tr = simulate(eom, 3.0, n_out=301)
    C, G0, nu = 0.3, 0.6, 2.0
    assert np.max(np.abs(tr.column("phi_dot") - G0 * (1 - np.cos(nu * tr.t)) / (C * nu))) <= 1e-8


def test_exact_coulomb_note_and_unchanged_law() -> None:
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "block_on_incline.toml"))
    (friction,) = [f for f in eom.loads if f.name == "friction"]
    assert "T = −f N v_s/‖v_s‖ (exact; sticking handled by the simulation with |T| ≤ f_s N)" in friction.note
    # The derived law stays −f N ẋ/√(ẋ²) (what the sliding phases integrate); only its display is sgn(ẋ).
    assert "sqrt(x_dot**2)" in str(friction.Q[0])
