"""Every example against an independent oracle: SymPy's `sympy.physics.mechanics`.

Each oracle builds the same system from scratch with ReferenceFrame, Point,
Particle/RigidBody and LagrangesMethod (forces applied through a force list, so the
generalized forces come from SymPy's own partial velocities, not from a potential),
then q̈ = M⁻¹ f is compared with the engine's q̈ = M⁻¹ F at random states.

SymPy is used here only as a test oracle.  A new example file without an oracle
fails `test_every_example_has_an_oracle`.
"""

from __future__ import annotations

import sys
from collections.abc import Callable

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from lagrangian_test_support import EXAMPLES_DIR, engine_qdd, eom_of, example_names, random_states

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

STATES = 5
RTOL = 1e-9

# An oracle returns (coordinates q(t) in the model's order, kinetic energy T, force list, frame N).
Oracle = tuple[list, sp.Expr, list, me.ReferenceFrame]


def _params(names: str) -> tuple[sp.Symbol, ...]:
    return sp.symbols(names)


def simple_pendulum() -> Oracle:
    m, l, g = _params("m l g")
    theta = me.dynamicsymbols("theta")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (theta, N.x))
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", -l * R1.z)
    P.v2pt_theory(O, N, R1)
    bob = me.Particle("bob", P, m)
    return [theta], bob.kinetic_energy(N), [(P, -m * g * N.z)], N


def spherical_pendulum() -> Oracle:
    m, l, g = _params("m l g")
    psi, theta = me.dynamicsymbols("psi theta")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (psi, N.z))
    R2 = R1.orientnew("R2", "Axis", (theta, R1.x))
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", -l * R2.z)
    P.v2pt_theory(O, N, R2)
    bob = me.Particle("bob", P, m)
    return [psi, theta], bob.kinetic_energy(N), [(P, -m * g * N.z)], N


def double_pendulum() -> Oracle:
    # Two homogeneous thin rods, theta2 measured relative to rod 1.
    m1, l1, m2, l2, g = _params("m1 l1 m2 l2 g")
    th1, th2 = me.dynamicsymbols("theta1 theta2")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (th1, N.x))
    R2 = R1.orientnew("R2", "Axis", (th2, R1.x))
    O = me.Point("O")
    O.set_vel(N, 0)
    A = O.locatenew("A", -l1 * R1.z)
    A.v2pt_theory(O, N, R1)
    G1 = O.locatenew("G1", -l1 / 2 * R1.z)
    G1.v2pt_theory(O, N, R1)
    G2 = A.locatenew("G2", -l2 / 2 * R2.z)
    G2.v2pt_theory(A, N, R2)
    S1 = me.RigidBody("S1", G1, R1, m1, (me.inertia(R1, m1 * l1**2 / 12, m1 * l1**2 / 12, 0), G1))
    S2 = me.RigidBody("S2", G2, R2, m2, (me.inertia(R2, m2 * l2**2 / 12, m2 * l2**2 / 12, 0), G2))
    T = S1.kinetic_energy(N) + S2.kinetic_energy(N)
    return [th1, th2], T, [(G1, -m1 * g * N.z), (G2, -m2 * g * N.z)], N


def cart_pendulum() -> Oracle:
    mc, m, l, k, g = _params("mc m l k g")
    x, theta = me.dynamicsymbols("x theta")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (theta, N.y))
    O = me.Point("O")
    O.set_vel(N, 0)
    C = O.locatenew("C", x * N.x)
    C.set_vel(N, x.diff() * N.x)
    P = C.locatenew("P", -l * R1.z)
    P.v2pt_theory(C, N, R1)
    cart, bob = me.Particle("cart", C, mc), me.Particle("bob", P, m)
    T = cart.kinetic_energy(N) + bob.kinetic_energy(N)
    # The spring (rest length l0, fixed at x = -l0) pulls the cart back with -k x while x > -l0.
    forces = [(C, -mc * g * N.z - k * x * N.x), (P, -m * g * N.z)]
    return [x, theta], T, forces, N


def lagrange_top() -> Oracle:
    m, g, a, A, C = _params("m g a A C")
    psi, theta, phi = me.dynamicsymbols("psi theta phi")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (psi, N.z))
    R2 = R1.orientnew("R2", "Axis", (theta, R1.x))
    R = R2.orientnew("R", "Axis", (phi, R2.z))
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", a * R.z)
    G.v2pt_theory(O, N, R)
    S = me.RigidBody("S", G, R, m, (me.inertia(R2, A, A, C), O))  # inertia given at O
    return [psi, theta, phi], S.kinetic_energy(N), [(G, -m * g * N.z)], N


# -- the same motions described in R0, with the prescribed motions written out -----------
def bead_rotating_hoop() -> Oracle:
    # The engine writes it in the hoop's frame R1 (inertial forces); the oracle in R0, where R1
    # is a frame turned by the prescribed angle Omega t.
    m, R, g, Omega = _params("m R g Omega")
    theta = me.dynamicsymbols("theta")
    t = me.dynamicsymbols._t
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (Omega * t, N.z))
    R2 = R1.orientnew("R2", "Axis", (theta, R1.y))
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", -R * R2.z)
    P.v2pt_theory(O, N, R2)
    return [theta], me.Particle("bead", P, m).kinetic_energy(N), [(P, -m * g * N.z)], N


def foucault_pendulum() -> Oracle:
    # The engine writes it in the Earth's frame E; the oracle in R0, E turning as Omega t.
    m, l, g, Omega, lam = _params("m l g Omega lam")
    alpha, beta = me.dynamicsymbols("alpha beta")
    t = me.dynamicsymbols._t
    N = me.ReferenceFrame("N")
    E = N.orientnew("E", "Axis", (Omega * t, N.z))
    L = E.orientnew("L", "Axis", (sp.pi / 2 - lam, E.y))
    R1 = L.orientnew("R1", "Axis", (alpha, L.x))
    R2 = R1.orientnew("R2", "Axis", (beta, R1.y))
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", -l * R2.z)
    P.v2pt_theory(O, N, R2)
    # The attraction: the apparent gravity −g u at the bob's rest place, less the centrifugal Ω² OP⊥ there.
    attraction = -(g - Omega**2 * l) * L.z - Omega**2 * l * sp.sin(lam) * N.z
    return [alpha, beta], me.Particle("bob", P, m).kinetic_energy(N), [(P, m * attraction)], N


def kapitza_pendulum() -> Oracle:
    m, l, g, a, nu = _params("m l g a nu")
    theta = me.dynamicsymbols("theta")
    t = me.dynamicsymbols._t
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (theta, N.x))
    O = me.Point("O")
    O.set_vel(N, 0)
    A = O.locatenew("A", a * sp.cos(nu * t) * N.z)
    A.set_vel(N, A.pos_from(O).dt(N))
    P = A.locatenew("P", -l * R1.z)
    P.v2pt_theory(A, N, R1)
    return [theta], me.Particle("bob", P, m).kinetic_energy(N), [(P, -m * g * N.z)], N


def block_on_belt() -> Oracle:
    m, k, f, g, v_b, eps = _params("m k f g v_b eps")
    x = me.dynamicsymbols("x")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    B = O.locatenew("B", x * N.x)
    B.set_vel(N, x.diff() * N.x)
    slip = x.diff() - v_b  # sliding velocity on the belt, regularised Coulomb law
    friction = -f * m * g * slip / sp.sqrt(slip**2 + eps**2) * N.x
    return [x], me.Particle("block", B, m).kinetic_energy(N), [(B, -m * g * N.z - k * x * N.x + friction)], N


# -- examples with complementary constraints: the oracle is the unconstrained system
# (M q̈ = F without the multiplier terms); tests/dynamics/test_constraints.py checks the
# constrained accelerations and the multipliers against LagrangesMethod/KanesMethod with the
# same constraints.
def pendulum_tension() -> Oracle:
    m, g = _params("m g")
    x, y = me.dynamicsymbols("x y")
    N = me.ReferenceFrame("N")
    P = me.Point("P")
    P.set_vel(N, x.diff() * N.x + y.diff() * N.y)
    bob = me.Particle("bob", P, m)
    return [x, y], bob.kinetic_energy(N), [(P, -m * g * N.y)], N


def rolling_disk_incline() -> Oracle:
    m, r, g, alpha = _params("m r g alpha")
    x, phi = me.dynamicsymbols("x phi")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (alpha, N.y))
    R2 = R1.orientnew("R2", "Axis", (phi, R1.y))
    G = me.Point("G")
    G.set_vel(N, x.diff() * R1.x)
    disk = me.RigidBody("S", G, R2, m, (me.inertia(R2, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4), G))
    return [x, phi], disk.kinetic_energy(N), [(G, -m * g * N.z)], N


def rolling_coin() -> Oracle:
    m, r, g = _params("m r g")
    x, y, psi, phi = me.dynamicsymbols("x y psi phi")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (psi, N.z))
    R2 = R1.orientnew("R2", "Axis", (phi, R1.y))
    G = me.Point("G")
    G.set_vel(N, x.diff() * N.x + y.diff() * N.y)
    coin = me.RigidBody("S", G, R2, m, (me.inertia(R2, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4), G))
    return [x, y, psi, phi], coin.kinetic_energy(N), [(G, -m * g * N.z)], N


def top_reaction() -> Oracle:
    m, g, a, A, C = _params("m g a A C")
    xG, yG, zG, psi, theta, phi = me.dynamicsymbols("xG yG zG psi theta phi")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (psi, N.z))
    R2 = R1.orientnew("R2", "Axis", (theta, R1.x))
    R = R2.orientnew("R", "Axis", (phi, R2.z))
    G = me.Point("G")
    G.set_vel(N, xG.diff() * N.x + yG.diff() * N.y + zG.diff() * N.z)
    S = me.RigidBody("S", G, R, m, (me.inertia(R2, A - m * a**2, A - m * a**2, C), G))
    return [xG, yG, zG, psi, theta, phi], S.kinetic_energy(N), [(G, -m * g * N.z)], N


def block_on_incline() -> Oracle:
    m, g, alpha, f = _params("m g alpha f")
    x = me.dynamicsymbols("x")
    N = me.ReferenceFrame("N")
    slope = N.orientnew("slope", "Axis", [alpha, N.y])  # slope.x points down the incline
    O = me.Point("O")
    O.set_vel(N, 0)
    B = O.locatenew("B", x * slope.x)
    B.set_vel(N, x.diff() * slope.x)
    friction = -f * m * g * sp.cos(alpha) * x.diff() / sp.sqrt(x.diff() ** 2) * slope.x  # exact Coulomb law
    return [x], me.Particle("block", B, m).kinetic_energy(N), [(B, -m * g * N.z + friction)], N


def inverted_pendulum_cart() -> Oracle:
    mc, m, l, g, F = _params("mc m l g F")
    x, theta = me.dynamicsymbols("x theta")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (theta, N.y))
    O = me.Point("O")
    O.set_vel(N, 0)
    C = O.locatenew("C", x * N.x)
    C.set_vel(N, x.diff() * N.x)
    P = C.locatenew("P", l * R1.z)
    P.v2pt_theory(C, N, R1)
    cart, bob = me.Particle("cart", C, mc), me.Particle("bob", P, m)
    T = cart.kinetic_energy(N) + bob.kinetic_energy(N)
    return [x, theta], T, [(C, -mc * g * N.z + F * N.x), (P, -m * g * N.z)], N


def furuta_pendulum() -> Oracle:
    # The arm (a rod from O along x1, inertia given at O) turned about z0 by the motor's torque τ, whose
    # reaction is on the ground; the pendulum (a rod hinged at the tip A about x1, its centre G at −lp z2).
    ma, r, mp, lp, g, tau = _params("ma r mp lp g tau")
    phi, alpha = me.dynamicsymbols("phi alpha")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (phi, N.z))
    R2 = R1.orientnew("R2", "Axis", (alpha, R1.x))
    O = me.Point("O")
    O.set_vel(N, 0)
    Ga = O.locatenew("Ga", r / 2 * R1.x)
    Ga.v2pt_theory(O, N, R1)
    A = O.locatenew("A", r * R1.x)
    A.v2pt_theory(O, N, R1)
    Gp = A.locatenew("Gp", -lp * R2.z)
    Gp.v2pt_theory(A, N, R2)
    arm = me.RigidBody("arm", Ga, R1, ma, (me.inertia(R1, 0, ma * r**2 / 3, ma * r**2 / 3), O))
    pendulum = me.RigidBody("pendulum", Gp, R2, mp, (me.inertia(R2, mp * lp**2 / 3, mp * lp**2 / 3, 0), Gp))
    T = arm.kinetic_energy(N) + pendulum.kinetic_energy(N)
    return [phi, alpha], T, [(Ga, -ma * g * N.z), (Gp, -mp * g * N.z), (R1, tau * N.z)], N


def torque_pendulum() -> Oracle:
    m, l, g, tau = _params("m l g tau")
    theta = me.dynamicsymbols("theta")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (theta, N.y))
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", -l * R1.z)
    P.v2pt_theory(O, N, R1)
    bob = me.Particle("bob", P, m)
    return [theta], bob.kinetic_energy(N), [(P, -m * g * N.z), (R1, tau * N.y)], N


def double_pendulum_cart() -> Oracle:
    mc, m1, m2, l1, l2, g, F = _params("mc m1 m2 l1 l2 g F")
    x, th1, th2 = me.dynamicsymbols("x theta1 theta2")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (th1, N.y))
    R2 = N.orientnew("R2", "Axis", (th2, N.y))
    O = me.Point("O")
    O.set_vel(N, 0)
    C = O.locatenew("C", x * N.x)
    C.set_vel(N, x.diff() * N.x)
    P1 = C.locatenew("P1", l1 * R1.z)
    P1.v2pt_theory(C, N, R1)
    P2 = P1.locatenew("P2", l2 * R2.z)
    P2.v2pt_theory(P1, N, R2)
    parts = [me.Particle("cart", C, mc), me.Particle("b1", P1, m1), me.Particle("b2", P2, m2)]
    T = sum(p.kinetic_energy(N) for p in parts)
    return [x, th1, th2], T, [(C, -mc * g * N.z + F * N.x), (P1, -m1 * g * N.z), (P2, -m2 * g * N.z)], N


def acrobot() -> Oracle:
    # Two rods as rigid bodies (inertia I1, I2 about their centres, about y), the elbow angle relative.
    m1, m2, l1, lc1, lc2, I1, I2, g, tau = _params("m1 m2 l1 lc1 lc2 I1 I2 g tau")
    th1, th2 = me.dynamicsymbols("theta1 theta2")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (th1, N.y))
    R2 = R1.orientnew("R2", "Axis", (th2, R1.y))
    O = me.Point("O")
    O.set_vel(N, 0)
    A = O.locatenew("A", -l1 * R1.z)
    A.v2pt_theory(O, N, R1)
    G1 = O.locatenew("G1", -lc1 * R1.z)
    G1.v2pt_theory(O, N, R1)
    G2 = A.locatenew("G2", -lc2 * R2.z)
    G2.v2pt_theory(A, N, R2)
    L1 = me.RigidBody("L1", G1, R1, m1, (me.inertia(R1, I1, I1, 0), G1))
    L2 = me.RigidBody("L2", G2, R2, m2, (me.inertia(R2, I2, I2, 0), G2))
    T = L1.kinetic_energy(N) + L2.kinetic_energy(N)
    return [th1, th2], T, [(G1, -m1 * g * N.z), (G2, -m2 * g * N.z), (R2, tau * R1.y), (R1, -tau * R1.y)], N


def satellite_reaction_wheel() -> Oracle:
    # The body B and the wheel W turn about z through their common centre of mass; the motor's couple
    # acts on W and, reacted, on B; no other load (a satellite's attitude, weightless about its centre).
    Ib, Iw, M, mw, tau = _params("Ib Iw M mw tau")
    theta, phi = me.dynamicsymbols("theta phi")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (theta, N.z))
    R2 = R1.orientnew("R2", "Axis", (phi, R1.z))
    O = me.Point("O")
    O.set_vel(N, 0)
    B = me.RigidBody("B", O, R1, M, (me.inertia(R1, Ib, Ib, Ib), O))
    W = me.RigidBody("W", O, R2, mw, (me.inertia(R2, Iw / 2, Iw / 2, Iw), O))
    T = B.kinetic_energy(N) + W.kinetic_energy(N)
    return [theta, phi], T, [(R2, tau * R1.z), (R1, -tau * R1.z)], N


def sleeping_top() -> Oracle:
    m, g, a, A, C = _params("m g a A C")
    alpha, beta, phi = me.dynamicsymbols("alpha beta phi")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (alpha, N.x))
    R2 = R1.orientnew("R2", "Axis", (beta, R1.y))
    R = R2.orientnew("R", "Axis", (phi, R2.z))
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", a * R2.z)
    G.v2pt_theory(O, N, R)
    top = me.RigidBody("S", G, R, m, (me.inertia(R2, A, A, C), O))
    return [alpha, beta, phi], top.kinetic_energy(N), [(G, -m * g * N.z)], N


def whipple_bicycle_bodies() -> tuple[list, list, list, me.ReferenceFrame]:
    # Meijaard et al. (2007): z down, the steer axis tilted back by lambda, the front hub found from the
    # hubs' distances to the steer axis (Moore's d1, d2, d3). The bodies are placed with SymPy's points and
    # their velocities differentiated by SymPy; the constraints are the engine's business (the oracle is the
    # unconstrained system, as for the other constrained examples).
    (w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IByy, IBzz, IBxz, xH, zH, mH, IHxx, IHyy, IHzz, IHxz,
     rF, mF, IFxx, IFyy) = _params("w c lam g rR mR IRxx IRyy xB zB mB IBxx IByy IBzz IBxz xH zH mH IHxx IHyy "
                                   "IHzz IHxz rF mF IFxx IFyy")
    x, y, psi, phi, thB, delta, thR, thF = me.dynamicsymbols("x y psi phi thetaB delta thetaR thetaF")
    N = me.ReferenceFrame("N")
    yaw = N.orientnew("yaw", "Axis", (psi, N.z))
    lean = yaw.orientnew("lean", "Axis", (phi, yaw.x))
    B = lean.orientnew("B", "Axis", (thB, lean.y))
    R = B.orientnew("R", "Axis", (thR, B.y))
    S = B.orientnew("S", "Axis", (lam, B.y))
    H = S.orientnew("H", "Axis", (delta, S.z))
    Hg = H.orientnew("Hg", "Axis", (-lam, H.y))
    F = H.orientnew("F", "Axis", (thF, H.y))
    O = me.Point("O")
    O.set_vel(N, 0)
    d1 = sp.cos(lam) * (c + w - rR * sp.tan(lam))
    d2 = w * sp.sin(lam) + (rR - rF) * sp.cos(lam)
    d3 = -sp.cos(lam) * (c - rF * sp.tan(lam))
    CR = O.locatenew("CR", x * N.x + y * N.y - rR * lean.z)
    CF = CR.locatenew("CF", d1 * S.x + d2 * S.z + d3 * H.x)
    GB = CR.locatenew("GB", xB * B.x + (zB + rR) * B.z)
    GH = CF.locatenew("GH", (xH - w) * Hg.x + (zH + rF) * Hg.z)
    for P in (CR, CF, GB, GH):
        P.set_vel(N, P.pos_from(O).dt(N))
    bodies = [
        me.RigidBody("B", GB, B, mB, (me.inertia(B, IBxx, IByy, IBzz, 0, 0, IBxz), GB)),
        me.RigidBody("H", GH, Hg, mH, (me.inertia(Hg, IHxx, IHyy, IHzz, 0, 0, IHxz), GH)),
        me.RigidBody("R", CR, R, mR, (me.inertia(R, IRxx, IRyy, IRxx), CR)),
        me.RigidBody("F", CF, F, mF, (me.inertia(F, IFxx, IFyy, IFxx), CF)),
    ]
    forces = [(body.masscenter, body.mass * g * N.z) for body in bodies]
    return [x, y, psi, phi, thB, delta, thR, thF], bodies, forces, N


def whipple_bicycle() -> Oracle:
    q, bodies, forces, N = whipple_bicycle_bodies()
    return q, sum(body.kinetic_energy(N) for body in bodies), forces, N


def tumbling_body() -> Oracle:
    # A free rigid body: G at (x, y, z), the course's Euler angles ψ, θ, φ about z0, x, z, moments A, B, C.
    m, g, A, B, C = _params("m g A B C")
    x, y, z, psi, theta, phi = me.dynamicsymbols("x y z psi theta phi")
    N = me.ReferenceFrame("N")
    R = N.orientnew("R", "Body", (psi, theta, phi), "ZXZ")
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", x * N.x + y * N.y + z * N.z)
    G.set_vel(N, G.pos_from(O).dt(N))
    S = me.RigidBody("S", G, R, m, (me.inertia(R, A, B, C), G))
    return [x, y, z, psi, theta, phi], S.kinetic_energy(N), [(G, -m * g * N.z)], N


# -- examples with unilateral contacts: the oracle is the system with every contact open (M q̈ = F);
# tests/numerics/test_contact.py checks the motions, impacts and reactions against closed forms.
def bouncing_ball() -> Oracle:
    m, g = _params("m g")
    z = me.dynamicsymbols("z")
    N = me.ReferenceFrame("N")
    P = me.Point("P")
    P.set_vel(N, z.diff() * N.z)
    return [z], me.Particle("ball", P, m).kinetic_energy(N), [(P, -m * g * N.z)], N


def sliding_ladder() -> Oracle:
    m, a, g = _params("m a g")
    x, y, theta = me.dynamicsymbols("x y theta")
    N = me.ReferenceFrame("N")
    R = N.orientnew("R", "Axis", (-theta, N.z))
    G = me.Point("G")
    G.set_vel(N, x.diff() * N.x + y.diff() * N.y)
    rod = me.RigidBody("S", G, R, m, (me.inertia(R, 0, m * a**2 / 3, m * a**2 / 3), G))
    return [x, y, theta], rod.kinetic_energy(N), [(G, -m * g * N.y)], N


def rocking_block() -> Oracle:
    m, b, h, g = _params("m b h g")
    x, y, theta = me.dynamicsymbols("x y theta")
    N = me.ReferenceFrame("N")
    R = N.orientnew("R", "Axis", (theta, N.z))
    G = me.Point("G")
    G.set_vel(N, x.diff() * N.x + y.diff() * N.y)
    block = me.RigidBody("S", G, R, m, (me.inertia(R, m * h**2 / 3, m * b**2 / 3, m * (b**2 + h**2) / 3), G))
    return [x, y, theta], block.kinetic_energy(N), [(G, -m * g * N.y)], N


def newtons_cradle() -> Oracle:
    m, l, d, g = _params("m l d g")
    thetas = me.dynamicsymbols("theta1 theta2 theta3")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    T, forces = 0, []
    for k, th in enumerate(thetas):
        R = N.orientnew(f"R{k}", "Axis", (th, N.z))
        pivot = O.locatenew(f"O{k}", k * d * N.x)
        pivot.set_vel(N, 0)
        P = pivot.locatenew(f"P{k}", -l * R.y)
        P.v2pt_theory(pivot, N, R)
        T += me.Particle(f"B{k}", P, m).kinetic_energy(N)
        forces.append((P, -m * g * N.y))
    return list(thetas), T, forces, N


def slack_rope_pendulum() -> Oracle:
    m, g = _params("m g")
    x, y = me.dynamicsymbols("x y")
    N = me.ReferenceFrame("N")
    P = me.Point("P")
    P.set_vel(N, x.diff() * N.x + y.diff() * N.y)
    return [x, y], me.Particle("bob", P, m).kinetic_energy(N), [(P, -m * g * N.y)], N


ORACLES: dict[str, Callable[[], Oracle]] = {
    "tumbling_body.toml": tumbling_body,
    "bouncing_ball.toml": bouncing_ball,
    "sliding_ladder.toml": sliding_ladder,
    "rocking_block.toml": rocking_block,
    "newtons_cradle.toml": newtons_cradle,
    "slack_rope_pendulum.toml": slack_rope_pendulum,
    "pendulum_tension.toml": pendulum_tension,
    "rolling_disk_incline.toml": rolling_disk_incline,
    "rolling_coin.toml": rolling_coin,
    "top_reaction.toml": top_reaction,
    "simple_pendulum.toml": simple_pendulum,
    "spherical_pendulum.toml": spherical_pendulum,
    "double_pendulum.toml": double_pendulum,
    "cart_pendulum.toml": cart_pendulum,
    "inverted_pendulum_cart.toml": inverted_pendulum_cart,
    "furuta_pendulum.toml": furuta_pendulum,
    "torque_pendulum.toml": torque_pendulum,
    "double_pendulum_cart.toml": double_pendulum_cart,
    "acrobot.toml": acrobot,
    "satellite_reaction_wheel.toml": satellite_reaction_wheel,
    "lagrange_top.toml": lagrange_top,
    "sleeping_top.toml": sleeping_top,
    "bead_rotating_hoop.toml": bead_rotating_hoop,
    "foucault_pendulum.toml": foucault_pendulum,
    "kapitza_pendulum.toml": kapitza_pendulum,
    "block_on_incline.toml": block_on_incline,
    "block_on_belt.toml": block_on_belt,
    "whipple_bicycle.toml": whipple_bicycle,
}


def test_every_example_has_an_oracle() -> None:
    assert example_names(), "no example files found"
    assert set(ORACLES) == set(example_names()), (
        "examples/*.toml and the oracles must match one to one; "
        f"missing oracles: {sorted(set(example_names()) - set(ORACLES))}, "
        f"oracles without example: {sorted(set(ORACLES) - set(example_names()))}"
    )


#: Examples whose T is too large for LagrangesMethod in a test (the bicycle: about a minute, then
#: three for its 55,000-operation forcing): their oracle is the same system written body by body and
#: solved by d'Alembert's principle instead (`_dalembert_qdd`).
BY_BODIES: dict[str, Callable[[], tuple[list, list, list, me.ReferenceFrame]]] = {
    "whipple_bicycle.toml": whipple_bicycle_bodies,
}


def _parameter_values(name: str) -> dict[sp.Symbol, float]:
    data = tomllib.loads((EXAMPLES_DIR / name).read_text(encoding="utf-8"))
    values = {sp.Symbol(k): (v["value"] if isinstance(v, dict) else v) for k, v in data["parameters"].items()}
    values.update({sp.Symbol(k): 0.0 for k in data.get("inputs", {})})  # inputs are off (0) in simulations
    return values


def _dalembert_qdd(name: str) -> Callable[[dict[str, float]], np.ndarray]:
    """q̈ from Σ_b [m_b ∂V(G_b)/∂q̇_i · γ(G_b) + ∂Ω_b/∂q̇_i · (I_b α_b + Ω_b ∧ I_b Ω_b)] = Σ_b ∂V(G_b)/∂q̇_i · F_b.

    SymPy gives each body's velocity, angular velocity and their derivatives (partial velocities
    by differentiation, the accelerations with q̈ = 0); the sum over bodies is assembled numerically.
    """
    q, bodies, forces, N = BY_BODIES[name]()
    t = me.dynamicsymbols._t
    qd = [qi.diff(t) for qi in q]
    names = [str(qi.func) for qi in q]
    qs, qds = sp.symbols(names), sp.symbols([n + "_dot" for n in names])
    to_symbols = {**dict(zip(qd, qds, strict=True)), **dict(zip(q, qs, strict=True))}
    no_qdd = {qi.diff(t, 2): 0 for qi in q}
    values = _parameter_values(name)
    force_on = {point.name: force for point, force in forces}

    def numeric(expr: sp.Matrix) -> Callable:
        expr = expr.xreplace(no_qdd).xreplace(to_symbols).xreplace(values)
        return sp.lambdify([*qs, *qds], expr, modules="numpy", cse=True)

    terms = []
    for b in bodies:
        V, W = b.masscenter.vel(N), b.frame.ang_vel_in(N)
        terms.append((float(b.mass.xreplace(values)),
                      numeric(sp.Matrix.hstack(*[V.diff(d, N).to_matrix(N) for d in qd])),        # ∂V/∂q̇
                      numeric(sp.Matrix.hstack(*[W.diff(d, N).to_matrix(b.frame) for d in qd])),  # ∂Ω/∂q̇
                      numeric(V.dt(N).to_matrix(N)), numeric(W.dt(N).to_matrix(b.frame)),  # γ, α at q̈ = 0
                      numeric(W.to_matrix(b.frame)),
                      np.array(b.central_inertia.to_matrix(b.frame).xreplace(values), dtype=float),
                      np.array(force_on[b.masscenter.name].to_matrix(N).xreplace(values), dtype=float).ravel()))

    def qdd(state: dict[str, float]) -> np.ndarray:
        args = [state[n] for n in names] + [state[n + "_dot"] for n in names]
        M, f = np.zeros((len(q), len(q))), np.zeros(len(q))
        for m, Jv, Jw, gamma0, alpha0, omega, inertia, force in terms:
            Jv_, Jw_ = np.asarray(Jv(*args), dtype=float), np.asarray(Jw(*args), dtype=float)
            w = np.asarray(omega(*args), dtype=float).ravel()
            M += m * Jv_.T @ Jv_ + Jw_.T @ inertia @ Jw_
            f += Jv_.T @ (force - m * np.asarray(gamma0(*args), dtype=float).ravel())
            f -= Jw_.T @ (inertia @ np.asarray(alpha0(*args), dtype=float).ravel() + np.cross(w, inertia @ w))
        return np.linalg.solve(M, f)

    return qdd


def oracle_qdd(name: str) -> Callable[[dict[str, float]], np.ndarray]:
    """q̈ = M⁻¹ f from SymPy's LagrangesMethod, as a numeric function of a state dict."""
    if name in BY_BODIES:
        return _dalembert_qdd(name)
    q, T, forces, N = ORACLES[name]()
    method = me.LagrangesMethod(T, q, forcelist=forces, frame=N)
    method.form_lagranges_equations()
    t = me.dynamicsymbols._t
    names = [str(qi.func) for qi in q]
    qs = sp.symbols(names)
    qds = sp.symbols([n + "_dot" for n in names])
    to_symbols = {qi.diff(t): s for qi, s in zip(q, qds, strict=True)}
    to_symbols_q = {qi: s for qi, s in zip(q, qs, strict=True)}
    ts = sp.Symbol("t")  # prescribed motions depend on the time
    values = _parameter_values(name)

    def numeric(expr: sp.Matrix) -> Callable:
        expr = expr.xreplace(to_symbols).xreplace(to_symbols_q).xreplace({t: ts}).subs(values)
        assert expr.free_symbols <= set(qs) | set(qds) | {ts}, expr.free_symbols
        return sp.lambdify([*qs, *qds, ts], expr, modules="numpy")

    M = numeric(method.mass_matrix)
    f = numeric(method.forcing)

    def qdd(state: dict[str, float]) -> np.ndarray:
        args = [state[n] for n in names] + [state[n + "_dot"] for n in names] + [state["t"]]
        return np.linalg.solve(np.asarray(M(*args), dtype=float), np.asarray(f(*args), dtype=float).ravel())

    return qdd


@pytest.mark.slow
@pytest.mark.parametrize("name", example_names())
def test_accelerations_match_sympy_mechanics(name: str) -> None:
    assert name in ORACLES, f"example {name} has no SymPy oracle in {__file__}"
    eom = eom_of(name)
    assert list(eom.coordinates) == [str(qi.func) for qi in ORACLES[name]()[0]], "coordinate order differs"
    oracle = oracle_qdd(name)
    times = np.random.default_rng(20240602).uniform(0.0, 10.0, STATES)
    for state, t in zip(random_states(name, eom.coordinates, STATES, seed=20240601), times, strict=True):
        state["t"] = float(t)  # examples with prescribed motions depend on t
        ours = engine_qdd(name, state)
        theirs = oracle(state)
        assert np.allclose(ours, theirs, rtol=RTOL, atol=RTOL * max(1.0, float(np.max(np.abs(theirs))))), (
            f"{name} at {state}: engine q̈ = {ours}, SymPy q̈ = {theirs}")
