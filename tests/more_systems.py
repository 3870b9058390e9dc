"""Systems the examples do not cover, as model files written for the tests of the analysis.

Each is a TOML text with the hand derivation it is checked against in a comment; `model(name)`
reads one (cached), `eom(name)` derives it.  `tests/conftest.py` puts this directory on
``sys.path``.
"""

from __future__ import annotations

import functools

import lagrangian
from lagrangian.model import parse_model

#: Furuta pendulum: an arm (inertia J about the vertical O z0) turned by φ, a bob m at the end of
#: a massless rod of length l hinged at the arm's tip A (OA = r x1), swinging by θ in the plane
#: normal to the arm (θ = 0 hanging).  T = ½ (J + m r² + m l² sin²θ) φ̇² + m r l cosθ φ̇ θ̇ + ½ m l² θ̇²,
#: U = −m g l cosθ.  Hanging: M = [[J + m r², m r l], [m r l, m l²]], K = diag(0, m g l), and the
#: one pulsation, φ being ignorable, is ω² = (g/l) (J + m r²)/J (not g/l: the arm swings back).
FURUTA = """
[model]
name = "Furuta pendulum"
[parameters]
J = { value = 0.02 }
m = { value = 0.1 }
r = { value = 0.3 }
l = { value = 0.25 }
g = { value = 9.81 }
[coordinates]
phi = { initial = 0.0, rate = 0.0 }
theta = { initial = 0.1, rate = 0.0 }
[frames]
R1 = { from = "R0", rotation = ["phi", "z"] }
R2 = { from = "R1", rotation = ["theta", "x"] }
[bodies.arm]
frame = "R1"
center = "0*R1.x"
inertia = { at = "G", diagonal = ["J", "J", "J"] }
[particles.P]
mass = "m"
position = "r*R1.x - l*R2.z"
[loads]
weight = { gravity = "-g*R0.z" }
"""

#: Elastic pendulum: a bob m on a spring of stiffness k and rest length L from O, in a vertical
#: plane, r = OP along −z1 (no range declared).  Rests: hanging r = L + m g/k, θ = 0 (0.6308 with
#: these values) and upright r = L − m g/k, θ = π (0.3692), the spring compressed.
ELASTIC = """
[model]
name = "Elastic pendulum"
[parameters]
m = { value = 1.0 }
g = { value = 9.81 }
k = { value = 75.0 }
L = { value = 0.5 }
[coordinates]
r = { initial = 0.6, rate = 0.0 }
theta = { initial = 0.1, rate = 0.0 }
[frames]
R1 = { from = "R0", rotation = ["theta", "y"] }
[particles.P]
mass = "m"
position = "-r*R1.z"
[loads]
weight = { gravity = "-g*R0.z" }
spring = { spring = ["O", "P"], stiffness = "k", rest_length = "L" }
"""

#: A bead on the parabola z = a r² turning at Ω about O z0, written in the turning frame:
#: U = m g a r² − ½ m Ω² r², so at Ω² = 2 g a every r is a rest (4.905 m/s² here: Ω = √9.81).
PARABOLA = """
[model]
name = "Bead on a turning parabola"
[parameters]
m = { value = 1.0 }
g = { value = 9.81 }
a = { value = 0.5 }
Omega = { value = 3.132091952673165 }
[coordinates]
r = { initial = 0.1, rate = 0.0 }
[frames]
R1 = { from = "R0", rotation = ["Omega*t", "z"] }
[particles.P]
mass = "m"
position = "r*R1.x + a*r^2*R0.z"
[loads]
weight = { gravity = "-g*R0.z" }
[reference]
frame = "R1"
"""

#: A tilted thrust: m ẍ = k sin θ, J θ̈ = 0 (a quadcopter's horizontal motion and its tilt, no
#: attitude control).  About rest, A² ≠ 0: a shift of θ makes x grow like t², of θ̇ like t³.
THRUST = """
[model]
name = "Tilted thrust"
[parameters]
m = { value = 1.0 }
k = { value = 2.0 }
J = { value = 0.1 }
[coordinates]
x = { initial = 0.0, rate = 0.0 }
theta = { initial = 0.0, rate = 0.0 }
[frames]
R1 = { from = "R0", rotation = ["theta", "z"] }
[bodies.B]
frame = "R1"
mass = "m"
center = "x*R0.x"
inertia = { at = "G", diagonal = ["J", "J", "J"] }
[loads]
thrust = { generalized_force = { x = "k*sin(theta)" } }
"""

#: Two carts joined by a spring on a rail: shifting both is another rest, changing their common
#: momentum makes them drift together (a Jordan chain of length 2, neutral).
TWO_CARTS = """
[model]
name = "Two carts and a spring"
[parameters]
m = { value = 1.0 }
k = { value = 4.0 }
[coordinates]
x1 = { initial = 0.0, rate = 0.0 }
x2 = { initial = 0.1, rate = 0.0 }
[particles.P1]
mass = "m"
position = "x1*R0.x"
[particles.P2]
mass = "m"
position = "x2*R0.x"
[loads]
spring = { potential = "k/2*(x2 - x1)^2" }
"""

#: Swinging Atwood machine: M hangs on one side of a pulley at O, m swings on the other at a
#: distance r, angle θ from the downward vertical.  T = ½ (M + m) ṙ² + ½ m r² θ̇²,
#: U = g r (M − m cos θ); M(q) = diag(M + m, m r²) is singular at r = 0.
ATWOOD = """
[model]
name = "Swinging Atwood machine"
[parameters]
M = { value = 1.0 }
m = { value = 2.0 }
g = { value = 9.81 }
[coordinates]
r = { initial = 1.0, rate = 0.0 }
theta = { initial = 0.5, rate = 0.0 }
[frames]
R1 = { from = "R0", rotation = ["theta", "y"] }
[particles.counterweight]
mass = "M"
position = "r*R0.z"
[particles.P]
mass = "m"
position = "-r*R1.z"
[loads]
weight = { gravity = "-g*R0.z" }
"""

#: Damped driven oscillator: m ẍ + c ẋ + k x = F0 cos(w t); with F0 = 0 no t is left.
DRIVEN = """
[model]
name = "Damped driven oscillator"
[parameters]
m = { value = 1.0 }
c = { value = 0.4 }
k = { value = 4.0 }
F0 = { value = 1.0 }
w = { value = 1.5 }
[coordinates]
x = { initial = 0.1, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = { potential = "k/2*x^2" }
damping = { generalized_force = { x = "-c*x_dot" } }
drive = { generalized_force = { x = "F0*cos(w*t)" } }
"""

#: A satellite (principal moments A, B, C at its centre O) with a reaction wheel (axial moment Iw,
#: transverse Jw) on its axis S x at O S = d x, in Euler angles (ψ, θ, φ) and the wheel's angle α:
#: four rotations in series, so `derive` takes the recursive route.  No load: ψ and α are cyclic
#: (p_ψ, p_α), the energy is constant, and Noether's theorem gives the angular momentum about O.
SATELLITE = """
[model]
name = "Satellite with a reaction wheel"
[parameters]
m = { value = 100.0 }
A = { value = 10.0 }
B = { value = 12.0 }
C = { value = 8.0 }
mw = { value = 2.0 }
Iw = { value = 0.05 }
Jw = { value = 0.03 }
d = { value = 0.3 }
[coordinates]
psi = { initial = 0.1, rate = 0.2 }
theta = { initial = 0.7, rate = 0.1 }
phi = { initial = 0.2, rate = 0.3 }
alpha = { initial = 0.0, rate = 20.0 }
[frames]
S = { from = "R0", rotation = [["psi", "z"], ["theta", "x"], ["phi", "z"]] }
W = { from = "S", rotation = ["alpha", "x"] }
[bodies.sat]
frame = "S"
mass = "m"
center = "0*R0.x"
inertia = { at = "G", frame = "S", diagonal = ["A", "B", "C"] }
[bodies.wheel]
frame = "W"
mass = "mw"
center = "d*S.x"
inertia = { at = "G", frame = "W", diagonal = ["Iw", "Jw", "Jw"] }
"""

#: A charge qc of mass m in a uniform field B along z0, with the vector potential A = B/2 (−y, x, 0):
#: U = −qc A·v = −qc B/2 (x ẏ − y ẋ), a generalized potential (Q_i = d/dt ∂U/∂q̇_i − ∂U/∂q_i gives
#: the Lorentz force qc v ∧ B).  The motion is a circle at the cyclotron pulsation ω = qc B/m.
CHARGE = """
[model]
name = "Charge in a magnetic field"
[parameters]
m = { value = 2.0 }
qc = { value = 1.5 }
B = { value = 4.0 }
[coordinates]
x = { initial = 0.0, rate = 1.0 }
y = { initial = 0.0, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x + y*R0.y"
[loads]
lorentz = { potential = "-qc*B/2*(x*y_dot - y*x_dot)" }
"""

TEXTS = {"furuta": FURUTA, "elastic": ELASTIC, "parabola": PARABOLA, "thrust": THRUST, "two_carts": TWO_CARTS,
         "atwood": ATWOOD, "driven": DRIVEN, "satellite": SATELLITE, "charge": CHARGE}


@functools.cache
def model(name: str) -> lagrangian.Model:
    return parse_model(TEXTS[name], source=f"{name}.toml")


@functools.cache
def eom(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(model(name))
