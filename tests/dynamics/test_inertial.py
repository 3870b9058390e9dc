"""Equations written in a non-Galilean frame R(O') (seed, Remarque 3): `dynamics._inertial`.

The independent truth is the same motion described twice.  A model file written in the
Galilean R0, where the frame R and the point O' are prescribed by functions of t, gives
equations by T(Σ/R0) alone; the same file with ``[reference] frame = "R", origin = "O'"``
gives them by T(Σ/R) plus the Coriolis and entrainment inertial forces.  Both must yield the
same accelerations q̈ at every state and time — with a rigid body of full inertia matrix, a
rotation rate that changes in size and direction (dΩ/dt ≠ 0) and an accelerated origin, so
that every term of the inertial torsors is exercised.  Closed forms check the potentials:
−½ m Ω² r² for a particle, −½ Ω² I_Δ for a body.
"""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian import ModelError
from lagrangian._identity import are_zero, is_zero
from lagrangian.dynamics._inertial import RelativeKinematics, inertial_torsors

#: A rigid body and a particle carried by a frame E that turns non-uniformly about an axis
#: that itself turns (Ω(E/R0) changes in size and direction) and whose origin A accelerates.
CARRIED = """
[parameters]
m = 1.3
mp = 0.4
g = 9.81
b = 0.4
w = 1.1
c = 0.3
d = 0.25
e = 0.6
L = 0.8
Omega = 0.7
k = 5.0

[coordinates]
th = { initial = 0.3, rate = 0.1 }
ph = { initial = -0.2, rate = 0.5 }
s = { initial = 0.1, rate = 0.0 }

[frames]
E1 = { from = "R0", rotation = ["Omega*t + b*sin(w*t)", "z"] }
E = { from = "E1", rotation = ["c*t", "x"] }
S1 = { from = "E", rotation = ["th", "y"] }
S = { from = "S1", rotation = ["ph", "x"] }

[points]
A = "d*t^2*R0.x + e*sin(t)*R0.y + d*E.z"

[bodies.B]
frame = "S"
mass = "m"
center_from = "A"
center = "L*S.z"
inertia = { at = "G", frame = "S", matrix = [["0.05", "0.01", "0"], ["0.01", "0.07", "0.02"], ["0", "0.02", "0.09"]] }

[particles.P]
mass = "mp"
from = "A"
position = "s*E.x + L*S1.y"

[loads]
weight = { gravity = "-g*R0.z" }
spring = { spring = ["A", "P"], stiffness = "k" }
"""

IN_E = '\n[reference]\nframe = "E"\norigin = "A"\n'


def derive(text: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(text, source="model.toml"))


def accelerations(eom: lagrangian.EquationsOfMotion, states: np.ndarray) -> np.ndarray:
    """q̈ = M⁻¹F at each row (q, q̇, t) of ``states``, parameters replaced by their values."""
    values = {se.Symbol(p.name): p.value for p in eom.model.parameters}
    n = len(eom.q)
    exprs = [se.sympify(x).subs(values) for row in eom.M for x in row] + [se.sympify(x).subs(values) for x in eom.F]
    f = se.Lambdify([*eom.q, *eom.qd, eom.t], exprs, real=True)
    out = []
    for row in states:
        v = np.asarray(f(row), dtype=float).ravel()
        out.append(np.linalg.solve(v[:n * n].reshape(n, n), v[n * n:]))
    return np.array(out)


def random_states(n: int, count: int = 6) -> np.ndarray:
    rng = np.random.default_rng(55)
    return np.column_stack([rng.uniform(-2, 2, (count, n)), rng.uniform(-3, 3, (count, n)), rng.uniform(0, 8, count)])


# -- the same motion described twice -------------------------------------------------------------
def test_a_body_and_a_particle_in_a_tumbling_accelerated_frame_agree_with_R0() -> None:
    galilean, relative = derive(CARRIED), derive(CARRIED + IN_E)
    assert {f.kind for f in relative.loads} >= {"inertial: Coriolis", "inertial: entrainment"}
    assert not {f.kind for f in galilean.loads} & {"inertial: Coriolis", "inertial: entrainment"}
    states = random_states(3)
    ours, theirs = accelerations(relative, states), accelerations(galilean, states)
    assert np.allclose(ours, theirs, rtol=1e-10, atol=1e-10 * np.max(np.abs(theirs))), (ours, theirs)
    # T(Σ/R) is not T(Σ/R0), but the q̈ coefficients (M) are the same: V*(P) does not depend on the frame.
    assert not is_zero(relative.T - galilean.T)
    assert all(are_zero([a - b for ra, rb in zip(relative.M, galilean.M, strict=True) for a, b in zip(ra, rb, strict=True)]))


def test_rigid_body_coriolis_torsor_has_zero_real_power_but_works_virtually() -> None:
    eom = derive(CARRIED + IN_E)
    coriolis = next(f for f in eom.loads if f.name == "Coriolis")
    # The constraints do not move in E, so Σ Q_i q̇_i is the real power: zero.
    assert is_zero(sum((q * qd for q, qd in zip(coriolis.Q, eom.qd, strict=True)), se.Integer(0)))
    assert not all(are_zero(coriolis.Q))
    assert "real power Σ F·V(P/R) ≡ 0" in coriolis.note and "virtual power Σ Q_i q_i* not zero" in coriolis.note
    # Each torsor alone: F·V(G/R) + M_G·Ω(S/R) ≡ 0 for the body.
    kin = eom.kinematics
    [torsor] = [t for t in inertial_torsors(kin) if t.load == "Coriolis" and t.element == "B"]
    power = kin.frames.dot(torsor.force, kin.velocity("B")) + kin.frames.dot(torsor.moment, kin.omega("S"))
    assert is_zero(power)


def test_non_uniform_rotation_has_no_entrainment_potential() -> None:
    eom = derive(CARRIED + IN_E)
    entrainment = next(f for f in eom.loads if f.name == "entrainment")
    assert entrainment.potential is None and "no potential" in entrainment.note
    assert not eom.conservative


def test_the_bead_in_the_hoops_frame_is_the_bead_in_R0() -> None:
    text = (EXAMPLES_DIR / "bead_rotating_hoop.toml").read_text()
    relative = derive(text)
    galilean = derive(text.replace('frame = "R1"   #', '# frame = "R1"').replace("[reference]", ""))
    assert galilean.model.reference is None and relative.model.reference.frame == "R1"
    (theta,), (theta_dot,) = relative.q, relative.qd
    m, R, g, Omega = (se.Symbol(s) for s in ("m", "R", "g", "Omega"))
    assert is_zero(relative.T - m * R**2 * theta_dot**2 / 2)  # T(P/R1): the hoop is still
    assert is_zero(galilean.T - m * R**2 * (theta_dot**2 + Omega**2 * se.sin(theta) ** 2) / 2)  # T(P/R0)
    qdd = [eom.F[0] / eom.M[0][0] for eom in (relative, galilean)]
    assert is_zero(qdd[0] - qdd[1])
    assert is_zero(qdd[0] - se.sin(theta) * (Omega**2 * se.cos(theta) - g / R))
    loads = {f.name: f for f in relative.loads}
    assert all(are_zero(loads["Coriolis"].Q))  # normal to the hoop: no virtual power
    assert is_zero(loads["entrainment"].potential + m * Omega**2 * R**2 * se.sin(theta) ** 2 / 2)  # −½ m Ω² r²
    # The Jacobi integral is the same function of the state whichever way the motion is written.
    [h_rel], [h_gal] = lagrangian.first_integrals(relative), lagrangian.first_integrals(galilean)
    assert (h_rel.name, h_rel.kind, h_gal.name, h_gal.kind) == ("h", "jacobi", "h", "jacobi")
    assert is_zero(h_rel.expression - h_gal.expression)
    assert "entrainment" in h_rel.reason


def test_a_rod_on_a_turntable_has_entrainment_potential_minus_half_omega2_I_axis() -> None:
    rod = """
[parameters]
m = 2.0
L = 0.6
g = 9.81
Omega = 3.0
[coordinates]
theta = { initial = 0.4, rate = 0.0 }
[frames]
T = { from = "R0", rotation = ["Omega*t", "z"] }
S = { from = "T", rotation = ["theta", "y"] }
[bodies.rod]
frame = "S"
mass = "m"
center = "L/2*S.z"
fixed_point = "O"
inertia = { at = "G", frame = "S", diagonal = ["m*L^2/12", "m*L^2/12", "0"] }
[loads]
weight = { gravity = "-g*R0.z" }
[reference]
frame = "T"
"""
    eom = derive(rod)
    entrainment = next(f for f in eom.loads if f.name == "entrainment")
    theta = eom.q[0]
    m, L, Omega = se.Symbol("m"), se.Symbol("L"), se.Symbol("Omega")
    I_axis = m * L**2 / 3 * se.sin(theta) ** 2  # a thin rod hinged at O, at θ from the axis O z0
    assert is_zero(entrainment.potential + Omega**2 * I_axis / 2)
    assert "I_Δ" in entrainment.note
    [h] = lagrangian.first_integrals(eom)
    assert h.kind == "jacobi" and is_zero(h.expression - eom.T - eom.U)
    galilean = derive(rod.replace('[reference]\nframe = "T"\n', ""))
    assert is_zero(eom.F[0] / eom.M[0][0] - galilean.F[0] / galilean.M[0][0])


def test_foucault_in_the_earths_frame_is_foucault_in_R0() -> None:
    text = (EXAMPLES_DIR / "foucault_pendulum.toml").read_text()
    relative = derive(text)
    galilean = derive(text.replace("[reference]", "").replace('frame = "R_T"   #', "#"))
    assert galilean.model.reference is None and relative.model.reference.frame == "R_T"
    states = random_states(2)
    ours, theirs = accelerations(relative, states), accelerations(galilean, states)
    assert np.allclose(ours, theirs, rtol=1e-10, atol=1e-10 * np.max(np.abs(theirs))), (ours, theirs)
    # In R0 the weight turns with the Earth and T has T1, T0: the Jacobi integral T2 − T0 + U there is
    # the energy T(P/E) + U_weight + U_entrainment in E.
    [h_rel], [h_gal] = lagrangian.first_integrals(relative), lagrangian.first_integrals(galilean)
    assert h_rel.kind == h_gal.kind == "jacobi" and is_zero(h_rel.expression - h_gal.expression)


def test_foucault_coriolis_works_virtually_and_not_really() -> None:
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "foucault_pendulum.toml"))
    coriolis = next(f for f in eom.loads if f.kind == "inertial: Coriolis")
    assert coriolis.potential is None
    assert is_zero(sum((q * qd for q, qd in zip(coriolis.Q, eom.qd, strict=True)), se.Integer(0)))
    assert not any(are_zero(coriolis.Q))
    assert not is_zero(coriolis.virtual_power)


def test_a_translating_frame_has_entrainment_only() -> None:
    """Kapitza's pendulum seen from its pivot: −m γ(A/R0), a potential that depends on t."""
    text = (EXAMPLES_DIR / "kapitza_pendulum.toml").read_text()
    relative = derive(text + '\n[reference]\nframe = "R0"\norigin = "A"\n')
    galilean = derive(text)
    assert [f.kind for f in relative.loads] == ["gravity", "inertial: entrainment"]
    entrainment = relative.loads[1]
    theta = relative.q[0]
    m, l, a, nu, t = (se.Symbol(s) for s in ("m", "l", "a", "nu", "t"))
    # U = m γ(A/R0)·AP with γ(A) = −a ν² cos(νt) z0 and AP·z0 = −l cos θ.
    assert is_zero(entrainment.potential - m * a * nu**2 * se.cos(nu * t) * l * se.cos(theta))
    assert is_zero(relative.F[0] / relative.M[0][0] - galilean.F[0] / galilean.M[0][0])
    assert lagrangian.first_integrals(relative) == ()  # L depends on t


def test_R0_as_reference_is_the_galilean_description() -> None:
    text = (EXAMPLES_DIR / "simple_pendulum.toml").read_text()
    eom = derive(text + '\n[reference]\nframe = "R0"\n')
    assert not isinstance(eom.kinematics, RelativeKinematics)
    assert [f.name for f in eom.loads] == ["weight"]


def test_relative_kinematics_measures_from_R() -> None:
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bead_rotating_hoop.toml"))
    kin = eom.kinematics
    assert isinstance(kin, RelativeKinematics)
    Omega = se.Symbol("Omega")
    assert kin.omega("R1").is_zero()
    assert kin.frames.express(kin.omega("R0"), "R0") == (0, 0, -Omega)  # Ω(R0/R1) = −Ω(R1/R0)
    assert kin.frame_omega_rate.is_zero() and kin.origin_acceleration.is_zero()
    # V(P/R1) = R θ̇ along the hoop: its norm is R θ̇.
    v = kin.velocity("P")
    R, theta_dot = se.Symbol("R"), eom.qd[0]
    assert is_zero(kin.frames.dot(v, v) - R**2 * theta_dot**2)


def test_builder_reference() -> None:
    b = lagrangian.ModelBuilder("bead")
    for name, value in (("m", 1.0), ("R", 0.5), ("g", 9.81), ("Omega", 6.0)):
        b.parameter(name, value)
    b.coordinate("theta", 0.5, 0.0)
    b.frame("R1", "R0", rotation=("Omega*t", "z"))
    b.frame("R2", "R1", rotation=("theta", "y"))
    b.particle("P", mass="m", position="-R*R2.z")
    b.gravity("weight", "-g*R0.z")
    b.reference("R1")
    eom = lagrangian.derive(b.build())
    assert [f.name for f in eom.loads] == ["weight", "Coriolis", "entrainment"]


# -- bad input: a reference frame whose motion is undefined --------------------------------------
BASE = (EXAMPLES_DIR / "bead_rotating_hoop.toml").read_text()


def _error(text: str) -> ModelError:
    with pytest.raises(ModelError) as info:
        lagrangian.parse_model(text, source="hoop.toml")
    return info.value


def _line(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), start=1) if needle in line)


@pytest.mark.parametrize(("old", "new", "needle", "words"), [
    ('frame = "R1"   #', 'frame = "R9"   #', 'frame = "R9"', ["`R9` is not a declared frame", "undefined"]),
    ('frame = "R1"   #', 'frame = "R2"   #', 'frame = "R2"', ["turns with coordinate `theta`", "prescribed"]),
    ('frame = "R1"   #', 'frame = "R1"\norigin = "Q"   #', 'origin = "Q"', ["origin `Q`", "not a declared point"]),
    ('frame = "R1"   #', 'frame = "R1"\norigin = "P"   #', 'origin = "P"', ["moves with coordinate `theta`"]),
    ('frame = "R1"   #', 'frame = "R1"\nspeed = 2   #', "speed = 2", ["unknown key `speed` in [reference]"]),
    ('frame = "R1"   #', '# no frame', "[reference]", ["does not say which frame"]),
    ('weight = {', 'Coriolis = {', "Coriolis = {", ["`Coriolis`", "the name of the inertial load"]),
])
def test_reference_errors_name_the_line(old: str, new: str, needle: str, words: list[str]) -> None:
    text = BASE.replace(old, new)
    assert text != BASE
    error = _error(text)
    assert error.file == "hoop.toml"
    assert error.line == _line(text, needle)
    for w in words:
        assert w in error.message, error.message
    assert error.fix


def test_a_frame_turned_through_a_coordinate_is_named() -> None:
    text = BASE.replace('R2 = { from = "R1", rotation = ["theta", "y"], axes = ["x2", "y1", "z2"] }',
                        'R2 = { from = "R1", rotation = ["theta", "y"], axes = ["x2", "y1", "z2"] }\n'
                        'R3 = { from = "R2", rotation = ["Omega*t", "z"] }')
    text = text.replace('frame = "R1"   #', 'frame = "R3"   #')
    error = _error(text)
    assert "through frame `R2`" in error.message and error.symbol == "theta"


def test_reference_must_be_a_table() -> None:
    text = 'reference = "R1"\n' + BASE.replace("[reference]\n", "").replace('frame = "R1"   #', "#")
    error = _error(text)
    assert "must be a table" in error.message and error.line == 1
