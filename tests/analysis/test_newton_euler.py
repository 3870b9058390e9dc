"""The Newton–Euler cross-check (`lagrangian.analysis.verify`) against independent truths.

* The top's dynamic moment at O is derived here by hand, as a student does it after the
  seed's last remark: σ_O = A θ̇ u + A ψ̇ sinθ w + C r z (r = φ̇ + ψ̇ cosθ) in R2, and
  δ_O = dσ_O/dt|R2 + Ω(R2/R0) ∧ σ_O; its projections on z0, u and z must be the seed's
  three Lagrange equations, typed from the course text.
* Every example (and a few harder models: loads of every kind, an asymmetric top with
  products of inertia, a bead on a hoop turned at a prescribed rate) must verify.
* A deliberately wrong equation must be caught.
"""

from __future__ import annotations

import dataclasses
import textwrap

import pytest
import sympy as sp
from lagrangian_test_support import EXAMPLES_DIR, example_names, mutated_example

import lagrangian
from lagrangian.analysis import verify
from lagrangian.model.zoo import planar_chain

# -- the seed's notation ---------------------------------------------------------------------------
m, g, a, A, C = sp.symbols("m g a A C")
psi, theta, phi = sp.symbols("psi theta phi")
psi_d, theta_d, phi_d = sp.symbols("psi_dot theta_dot phi_dot")
psi_dd, theta_dd, phi_dd = sp.symbols("psi_ddot theta_ddot phi_ddot")
Q, QD, QDD = (psi, theta, phi), (psi_d, theta_d, phi_d), (psi_dd, theta_dd, phi_dd)
s, c = sp.sin(theta), sp.cos(theta)


def d_dt(f: sp.Expr) -> sp.Expr:
    return sum((f.diff(q) * qd + f.diff(qd) * qdd for q, qd, qdd in zip(Q, QD, QDD, strict=True)), sp.Integer(0))


def cross(u: sp.Matrix, v: sp.Matrix) -> sp.Matrix:
    return u.cross(v)


# By hand, components in R2 (u, w, z).  z0 = sinθ w + cosθ z (R2 comes from R1 by θ about u).
Z0 = sp.Matrix([0, s, c])
U_AXIS, Z_AXIS = sp.Matrix([1, 0, 0]), sp.Matrix([0, 0, 1])
r = phi_d + psi_d * c
OMEGA_R2 = sp.Matrix([theta_d, psi_d * s, psi_d * c])  # Ω(R2/R0) = ψ̇ z0 + θ̇ u
SIGMA_O = sp.Matrix([A * theta_d, A * psi_d * s, C * r])  # Π_O·Ω(S/R0), Ω(S/R0) = Ω(R2/R0) + φ̇ z
DELTA_O = sp.Matrix([d_dt(x) for x in SIGMA_O]) + cross(OMEGA_R2, SIGMA_O)
MOMENT_O = cross(a * Z_AXIS, -m * g * Z0)  # OG ∧ P, P = −m g z0

# The seed's three equations, (left side, right side), typed from the course.
K_SEED = A * psi_d * s**2 + C * c * r
SEED = {
    "psi": (d_dt(K_SEED), 0, Z0),
    "theta": (A * theta_dd - A * psi_d**2 * s * c + C * psi_d * s * r, m * g * a * s, U_AXIS),
    "phi": (d_dt(C * r), 0, Z_AXIS),
}


def sym(e) -> sp.Expr:  # noqa: ANN001 - a SymEngine expression
    return sp.sympify(e._sympy_())


def same(x, y) -> bool:  # noqa: ANN001 - SymEngine or SymPy expressions
    x, y = (e if isinstance(e, sp.Basic) else sp.sympify(e._sympy_() if hasattr(e, "_sympy_") else e)
            for e in (x, y))
    return sp.simplify(sp.expand(x - y)) == 0


@pytest.fixture(scope="module")
def top():
    eom = lagrangian.derive(lagrangian.lagrange_top())
    return eom, verify(eom)


def in_r2(eom, vector) -> sp.Matrix:  # noqa: ANN001
    return sp.Matrix([sym(x) for x in eom.kinematics.frames.express(vector, "R2")])


def test_the_tops_projections_are_the_seeds_equations(top) -> None:
    eom, v = top
    assert v.agrees
    for name, (lhs, rhs, _) in SEED.items():
        check = v.check(name)
        assert same(check.newton_euler, lhs), name
        assert same(check.newton_euler_efforts, rhs), name
        assert same(eom.equation(name).lhs, lhs) and same(eom.equation(name).rhs, rhs)


def test_the_tops_theorems_match_the_hand_derivation(top) -> None:
    eom, v = top
    body = v.element("S")
    assert body.point == "O" and body.efforts == ("weight",)
    assert sp.simplify(in_r2(eom, body.angular_momentum) - SIGMA_O) == sp.zeros(3, 1)
    assert sp.simplify(in_r2(eom, body.dynamic_moment) - DELTA_O) == sp.zeros(3, 1)
    assert sp.simplify(in_r2(eom, body.moment) - MOMENT_O) == sp.zeros(3, 1)
    assert sp.simplify(in_r2(eom, body.force) + m * g * Z0) == sp.zeros(3, 1)
    # δ_O·z0, δ_O·u, δ_O·z by hand are the three projections, and the moments of P too.
    for name, (_, _, axis) in SEED.items():
        assert same(v.check(name).newton_euler, (DELTA_O.T * axis)[0]), name
        assert same(v.check(name).newton_euler_efforts, (MOMENT_O.T * axis)[0]), name


def test_the_tops_directions_are_the_rotation_axes(top) -> None:
    _, v = top
    assert [(c.theorem, c.point, c.axis) for c in v.checks] == [
        ("moment", "O", "z0"), ("moment", "O", "u"), ("moment", "O", "z")]
    assert v.check("theta").describe() == "moment theorem at O projected on u"
    assert all(c.whole_system and c.elements == ("S",) for c in v.checks)


# -- every model ------------------------------------------------------------------------------------
LOADED = """
[parameters]
m1 = 1.0
m2 = 0.7
mp = 0.3
l = 1.0
b = 0.4
h = 0.2
g = 9.81
k = 5.0
l0 = 0.3
c = 0.4
k2 = 2.0
c2 = 0.1
F = 1.5
Gamma = 0.8
w = 2.0
I1 = 0.09
I2 = 0.12
I3 = 0.1
J = 0.01

[coordinates]
theta = { initial = 0.3, rate = 0.1 }
phi = { initial = 0.2, rate = -0.2 }
beta = { initial = 0.1, rate = 0.3 }
x = { initial = 0.5, rate = 0.0 }

[frames]
R0 = { axes = ["x0", "y0", "z0"] }
R1 = { from = "R0", rotation = ["theta", "z"], axes = ["x1", "y1", "z0"] }
R2 = { from = "R1", rotation = ["phi", "x"], axes = ["x1", "y2", "z2"] }
R3 = { from = "R2", rotation = ["beta", "z"], axes = ["x3", "y3", "z2"] }

[points]
A = "l*R1.x"
B = { from = "A", position = "b*R3.x + h*R3.y" }
D = "x*R0.x + h*R0.z"

[bodies.S1]
frame = "R1"
mass = "m1"
center = "l/2*R1.x"
fixed_point = "O"
inertia = { at = "G", frame = "R1", diagonal = ["0", "m1*l^2/12", "m1*l^2/12"] }

[bodies.S2]
frame = "R3"
mass = "m2"
center_from = "A"
center = "b/2*R3.x + h/3*R3.z"
inertia = { at = "A", frame = "R3", matrix = [["I1", "-J", "0"], ["-J", "I2", "0"], ["0", "0", "I3"]] }

[particles.P]
mass = "mp"
position = "x*R0.x + l*R0.y"

[loads]
weight = { gravity = "-g*R0.z" }
spring = { spring = ["P", "B"], stiffness = "k", rest_length = "l0" }
damper = { damper = ["A", "P"], coefficient = "c" }
motor = { torque = "Gamma*cos(w*t)*R2.z", on = "S2", reaction_on = "S1" }
brake = { torque = "-c2*theta_dot*R0.z", on = "S1", reaction_on = "R0" }
push = { force = "F*R1.y", at = "B" }
wind = { force = "F*sin(t)*R0.x", at = "D" }
well = { potential = "1/2*k2*x^2" }
friction = { generalized_force = { x = "-c2*x_dot" } }
"""

# A heavy asymmetric body with products of inertia at G, G off the axis, fixed point O.
ASYMMETRIC_TOP = """
[parameters]
m = 1.2
g = 9.81
a = 0.1
b = 0.03
I1 = 0.02
I2 = 0.03
I3 = 0.04
J = 0.004

[coordinates]
psi = { initial = 0.1, rate = 1.0 }
theta = { initial = 0.7, rate = 0.2 }
phi = { initial = 0.0, rate = 20.0 }

[frames]
R0 = { axes = ["x0", "y0", "z0"] }
R = { from = "R0", rotation = [["psi", "z"], ["theta", "x"], ["phi", "z"]], axes = ["x", "y", "z"] }

[bodies.S]
frame = "R"
mass = "m"
center = "b*R.x + a*R.z"
fixed_point = "O"
inertia = { at = "G", frame = "R", matrix = [["I1", "-J", "0"], ["-J", "I2", "0"], ["0", "0", "I3"]] }

[loads]
weight = { gravity = "-g*R0.z" }
"""

# A bead on a hoop turned about the vertical at the prescribed rate Omega (rheonomic).
HOOP = """
[parameters]
m = 0.2
r = 0.5
g = 9.81
Omega = 3.0

[coordinates]
theta = { initial = 0.4, rate = 0.0 }

[frames]
R0 = { axes = ["x0", "y0", "z0"] }
W = { from = "R0", rotation = ["Omega*t", "z"], axes = ["x1", "y1", "z0"] }
R1 = { from = "W", rotation = ["theta", "y"], axes = ["x2", "y1", "z2"] }

[particles.P]
mass = "m"
position = "-r*R1.z"

[loads]
weight = { gravity = "-g*R0.z" }
"""

EXTRA = {"loaded": LOADED, "asymmetric_top": ASYMMETRIC_TOP, "hoop": HOOP}


def model_of(name: str) -> lagrangian.Model:
    if name in EXTRA:
        return lagrangian.parse_model(textwrap.dedent(EXTRA[name]), source=f"<{name}>")
    if name.startswith("planar_chain"):
        return planar_chain(int(name.rpartition("_")[2]))
    return lagrangian.load_model(EXAMPLES_DIR / name)


ALL_MODELS = [*example_names(), "planar_chain_1", "planar_chain_4", *EXTRA]


@pytest.mark.slow
@pytest.mark.parametrize("name", ALL_MODELS)
def test_every_model_verifies(name: str) -> None:
    v = verify(lagrangian.derive(model_of(name)))
    bad = [(c.coordinate, c.lhs_agrees, c.rhs_agrees) for c in v.checks if not c.agrees]
    assert v.agrees and not bad, bad
    assert len(v.checks) == len(v.eom.coordinates)


@pytest.mark.parametrize("name, expected", [
    ("simple_pendulum.toml", ["moment theorem at O projected on x0"]),
    ("spherical_pendulum.toml", ["moment theorem at O projected on z0", "moment theorem at O projected on u"]),
    ("cart_pendulum.toml", ["resultant theorem projected on x0", "moment theorem at C of P projected on y0"]),
    ("double_pendulum.toml", ["moment theorem at O projected on x0", "moment theorem at A of S2 projected on x0"]),
    ("planar_chain_1", ["moment theorem at O projected on z0"]),
    ("hoop", ["moment theorem at O projected on y1"]),
])
def test_the_directions_of_remarque_4(name: str, expected: list[str]) -> None:
    """Rotation angles go with moment theorems on their axes, translations with resultant theorems."""
    v = verify(lagrangian.derive(model_of(name)))
    assert [c.describe() for c in v.checks] == expected


def test_a_chain_link_is_a_resultant_theorem_on_its_partial_velocity() -> None:
    v = verify(lagrangian.derive(planar_chain(3)))
    first, second, last = v.checks
    # θ1 moves every mass by l1 y1 θ̇1: the resultant theorem of the whole chain on l1 y1.
    assert first.theorem == "resultant" and first.whole_system and first.axis is None
    assert second.theorem == "resultant" and second.elements == ("P2", "P3")
    assert last.describe() == "moment theorem at P2 of P3 projected on z0"


def test_loads_without_a_force_form_go_by_virtual_power() -> None:
    v = verify(lagrangian.derive(model_of("loaded")))
    assert v.virtual_power_loads == ("wind", "well", "friction")  # D is carried by no body
    efforts = {th.name: th.efforts for th in v.theorems}
    assert efforts == {"S1": ("weight", "damper", "motor", "brake"), "S2": ("weight", "spring", "motor", "push"),
                       "P": ("weight", "spring", "damper")}
    assert [th.point for th in v.theorems] == ["O", "S2", "P"]


# -- a wrong equation is caught --------------------------------------------------------------------
def tampered(eom: lagrangian.EquationsOfMotion, coordinate: str, **change) -> lagrangian.EquationsOfMotion:
    equations = tuple(dataclasses.replace(eq, **{k: f(eq) for k, f in change.items()})
                      if eq.coordinate == coordinate else eq for eq in eom.equations)
    return dataclasses.replace(eom, equations=equations)


def test_a_wrong_left_side_is_caught(top) -> None:
    eom, _ = top
    # A classic slip: the gyroscopic term with the wrong sign in L(θ).
    wrong = tampered(eom, "theta", lhs=lambda eq: eq.lhs - 2 * (eq.lhs - eq.dT_dqd.diff(eom.qd[1]) * eom.qdd[1]))
    v = verify(wrong)
    assert not v.agrees
    assert [(c.coordinate, c.lhs_agrees, c.rhs_agrees) for c in v.checks] == [
        ("psi", True, True), ("theta", False, True), ("phi", True, True)]


def test_a_wrong_right_side_is_caught(top) -> None:
    eom, _ = top
    v = verify(tampered(eom, "theta", rhs=lambda eq: -eq.rhs))  # U = −m g a cosθ: the top upside down
    assert [(c.coordinate, c.agrees) for c in v.checks] == [("psi", True), ("theta", False), ("phi", True)]
    assert v.check("theta").lhs_agrees and not v.check("theta").rhs_agrees


def test_a_small_error_is_caught() -> None:
    eom = lagrangian.derive(model_of("double_pendulum.toml"))
    # One part in a million on one inertia term of L(θ2).
    wrong = tampered(eom, "theta2", lhs=lambda eq: eq.lhs + eq.lhs.diff(eom.qdd[1]) * 1e-6 * eom.qdd[1])
    assert not verify(wrong).check("theta2").lhs_agrees


def test_forces_are_taken_as_forces_not_from_the_generalized_forces() -> None:
    """Blank the Q_i that `derive` found for gravity, springs, dampers, forces and couples: the
    Newton–Euler side does not read them, so it still matches the Lagrange equations."""
    eom = lagrangian.derive(model_of("loaded"))
    kept = {"well", "friction"}  # no force form: these two are read by their Q_i
    blank = tuple(f if f.name in kept else dataclasses.replace(f, Q=(0,) * len(f.Q)) for f in eom.loads)
    assert verify(dataclasses.replace(eom, loads=blank)).agrees


def test_an_angle_of_1e308_theta_is_still_checked(tmp_path):
    # tools/fuzz.py seed 105, case 11158: the double pendulum's R2 turned by 1e308 θ2.  The quick numeric
    # rejection overflowed (OverflowError), and the random-point identity test cannot evaluate
    # cos(1e308 θ2) (its argument is rounded by far more than 2π): the exact expansion decides, and the
    # equations agree with the theorems, as they must.
    path = mutated_example(tmp_path, "double_pendulum.toml", 'rotation = ["theta2", "x"]',
                           'rotation = ["(theta2)*1e308", "x"]')
    v = verify(lagrangian.derive(lagrangian.load_model(path)))
    assert all(c.agrees for c in v.checks) and len(v.checks) == 2
