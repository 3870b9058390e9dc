"""Closed-form checks for each kind of load, and for what the engine concludes from them:
which loads derive from a potential, whether the system is conservative, and which
first integrals (energy, Jacobi, momenta) follow.
"""

from __future__ import annotations

import textwrap

import pytest
import sympy as sp

import lagrangian

x, y, theta, t = sp.symbols("x y theta t")
x_dot, y_dot, theta_dot = sp.symbols("x_dot y_dot theta_dot")
m, k, c, l0, g, l, F, F0, w, I, Gamma, r, Omega = sp.symbols("m k c l0 g l F F0 w I Gamma r Omega")


def derive(toml: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(textwrap.dedent(toml), source="<test>"))


def sym(expr) -> sp.Expr:  # noqa: ANN001 - a SymEngine expression
    return sp.sympify(expr._sympy_())


def same(a: sp.Expr, b: sp.Expr) -> bool:
    d = sp.expand(a - b)
    return d == 0 or sp.simplify(sp.trigsimp(d)) == 0


def accelerations(eom: lagrangian.EquationsOfMotion) -> list[sp.Expr]:
    """q̈ = M⁻¹F, symbolically."""
    M = sp.Matrix([[sym(e) for e in row] for row in eom.M])
    Fv = sp.Matrix([sym(e) for e in eom.F])
    return list(M.LUsolve(Fv))


def integrals(eom: lagrangian.EquationsOfMotion) -> dict[str, lagrangian.FirstIntegral]:
    return {fi.name: fi for fi in lagrangian.first_integrals(eom)}


def load(eom: lagrangian.EquationsOfMotion, name: str):  # noqa: ANN201
    [found] = [f for f in eom.loads if f.name == name]
    return found


def has_potential(eom: lagrangian.EquationsOfMotion, name: str) -> bool:
    return load(eom, name).potential is not None


# A particle P on the line O x0 (x may take any sign unless a test says otherwise).
LINE = """
[parameters]
m = 2.0
{params}

[coordinates]
x = {{ initial = 1.0, rate = 0.0 }}

[particles.P]
mass = "m"
position = "x*R0.x"

[loads]
{loads}
"""


def on_line(loads: str, params: str = "") -> lagrangian.EquationsOfMotion:
    return derive(LINE.format(loads=loads, params=params))


# -- spring ---------------------------------------------------------------------------------
def test_spring_mass() -> None:
    eom = on_line('spring = { spring = ["O", "P"], stiffness = "k", rest_length = "l0" }', "k = 3.0\nl0 = 0.5")
    xp = sp.Symbol("x", positive=True)  # the closed form holds while P is on the positive side of O
    [acc] = accelerations(eom)
    assert same(acc.subs(x, xp), -k / m * (xp - l0))
    spring = load(eom, "spring")
    assert spring.kind == "spring" and spring.potential is not None
    assert same(sym(spring.potential).subs(x, xp), k * (xp - l0) ** 2 / 2)
    assert eom.conservative
    fi = integrals(eom)
    assert set(fi) == {"E"} and fi["E"].kind == "energy"
    assert same(sym(fi["E"].expression).subs(x, xp), m * x_dot**2 / 2 + k * (xp - l0) ** 2 / 2)


def test_spring_between_two_moving_points() -> None:
    """Zero-rest-length spring between beads on two perpendicular rails: U = ½ k (x² + y²)."""
    eom = derive("""
        [parameters]
        m = 1.0
        k = 4.0
        [coordinates]
        x = { initial = 1.0, rate = 0.0 }
        y = { initial = 0.0, rate = 1.0 }
        [particles.A]
        mass = "m"
        position = "x*R0.x"
        [particles.B]
        mass = "m"
        position = "y*R0.y"
        [loads]
        s = { spring = ["A", "B"], stiffness = "k" }
    """)
    ax, ay = accelerations(eom)
    assert same(ax, -k / m * x) and same(ay, -k / m * y)
    assert has_potential(eom, "s") and same(sym(eom.U), k * (x**2 + y**2) / 2)


# -- damper ---------------------------------------------------------------------------------
def test_damper() -> None:
    eom = on_line('drag = { damper = ["O", "P"], coefficient = "c" }', "c = 0.3")
    [acc] = accelerations(eom)
    assert same(acc, -c / m * x_dot)
    assert load(eom, "drag").kind == "damper"
    assert not has_potential(eom, "drag")
    assert not eom.conservative and eom.L is None
    assert same(sym(eom.Q_nc[0]), -c * x_dot)
    # x is cyclic in T but the damper works on it: no momentum, and no energy integral
    assert integrals(eom) == {}


def test_damper_in_the_plane_acts_along_the_line() -> None:
    eom = derive("""
        [parameters]
        m = 1.0
        c = 0.5
        [coordinates]
        x = { initial = 1.0, rate = 0.0 }
        y = { initial = 0.5, rate = 1.0 }
        [particles.P]
        mass = "m"
        position = "x*R0.x + y*R0.y"
        [loads]
        drag = { damper = ["O", "P"], coefficient = "c" }
    """)
    rate = (x * x_dot + y * y_dot) / (x**2 + y**2)  # ℓ̇/ℓ
    Qx, Qy = (sym(q) for q in load(eom, "drag").Q)
    assert same(Qx, -c * rate * x) and same(Qy, -c * rate * y)


def test_spring_and_damper_lose_energy_at_rate_c_xdot_squared() -> None:
    eom = on_line('spring = { spring = ["O", "P"], stiffness = "k", rest_length = "l0" }\n'
                  'drag = { damper = ["O", "P"], coefficient = "c" }', "k = 3.0\nl0 = 0.5\nc = 0.3")
    assert has_potential(eom, "spring") and not has_potential(eom, "drag")
    assert not eom.conservative
    assert not any(fi.kind in ("energy", "jacobi") for fi in lagrangian.first_integrals(eom))
    xp = sp.Symbol("x", positive=True)
    [acc] = accelerations(eom)
    energy = sym(eom.T + eom.U)
    dE_dt = energy.diff(x) * x_dot + energy.diff(x_dot) * acc
    assert same(dE_dt.subs(x, xp), -c * x_dot**2)


# -- torque ---------------------------------------------------------------------------------
WHEEL = """
[parameters]
I = 0.2
Gamma = 1.5
c = 0.1

[coordinates]
theta = {{ initial = 0.0, rate = 1.0 }}

[frames]
R1 = {{ from = "R0", rotation = ["theta", "z"] }}

[bodies.W]
frame = "R1"
mass = "1"
center = "0"
fixed_point = "O"
inertia = {{ at = "G", frame = "R1", diagonal = ["I/2", "I/2", "I"] }}

[loads]
{loads}
"""


@pytest.mark.parametrize("spec", ['motor = { torque = "Gamma*R0.z", on = "W" }',
                                  'motor = { torque = "Gamma*R1.z", on = "W", reaction_on = "R0" }'])
def test_constant_torque_on_a_wheel(spec: str) -> None:
    eom = derive(WHEEL.format(loads=spec))
    [acc] = accelerations(eom)
    assert same(acc, Gamma / I)
    motor = load(eom, "motor")
    assert motor.kind == "torque"
    assert same(sym(motor.Q[0]), Gamma)
    # a constant couple about a fixed axis derives from U = −Γ θ (found by integration)
    assert motor.potential is not None and same(sym(motor.potential).diff(theta), -Gamma)
    assert eom.conservative


def test_friction_torque_is_not_conservative() -> None:
    eom = derive(WHEEL.format(loads='friction = { torque = "-c*theta_dot*R0.z", on = "W" }'))
    [acc] = accelerations(eom)
    assert same(acc, -c * theta_dot / I)
    assert not has_potential(eom, "friction") and not eom.conservative
    assert integrals(eom) == {}


def test_internal_torque_acts_on_both_bodies() -> None:
    eom = derive("""
        [parameters]
        I1 = 0.2
        I2 = 0.5
        Gamma = 1.5
        [coordinates]
        theta1 = { initial = 0.0, rate = 0.0 }
        theta2 = { initial = 0.0, rate = 0.0 }
        [frames]
        R1 = { from = "R0", rotation = ["theta1", "z"] }
        R2 = { from = "R0", rotation = ["theta2", "z"] }
        [bodies.W1]
        frame = "R1"
        mass = "1"
        center = "0"
        fixed_point = "O"
        inertia = { at = "O", frame = "R1", diagonal = ["I1/2", "I1/2", "I1"] }
        [bodies.W2]
        frame = "R2"
        mass = "1"
        center = "0"
        fixed_point = "O"
        inertia = { at = "O", frame = "R2", diagonal = ["I2/2", "I2/2", "I2"] }
        [loads]
        motor = { torque = "Gamma*R0.z", on = "W1", reaction_on = "W2" }
    """)
    I1, I2 = sp.symbols("I1 I2")
    a1, a2 = accelerations(eom)
    assert same(a1, Gamma / I1) and same(a2, -Gamma / I2)
    # the total angular momentum about O z0 is conserved: the combination I1 θ̇1 + I2 θ̇2
    assert same(I1 * a1 + I2 * a2, 0)


# -- point force ------------------------------------------------------------------------------
PENDULUM = """
[parameters]
m = 1.0
l = 0.5
g = 9.81
F = 2.0
F0 = 2.0
w = 3.0

[coordinates]
theta = {{ initial = 0.3, rate = 0.0 }}

[frames]
R1 = {{ from = "R0", rotation = ["theta", "x"] }}

[particles.P]
mass = "m"
position = "-l*R1.z"

[loads]
weight = {{ gravity = "-g*R0.z" }}
{loads}
"""


def test_constant_point_force_on_a_pendulum() -> None:
    """Horizontal force F y0 at the bob: m l θ̈ = F cos θ − m g sin θ; U = −F l sin θ − m g l cos θ."""
    eom = derive(PENDULUM.format(loads='push = { force = "F*R0.y", at = "P" }'))
    [acc] = accelerations(eom)
    assert same(acc, (F * sp.cos(theta) - m * g * sp.sin(theta)) / (m * l))
    push = load(eom, "push")
    assert push.kind == "pointforce"
    assert same(sym(push.Q[0]), F * l * sp.cos(theta))
    assert push.potential is not None and same(sym(push.potential).diff(theta), -F * l * sp.cos(theta))
    assert eom.conservative
    assert same(sym(eom.U), -F * l * sp.sin(theta) - m * g * l * sp.cos(theta))
    assert set(integrals(eom)) == {"E"}


def test_time_dependent_force_is_not_conservative() -> None:
    eom = derive(PENDULUM.format(loads='shake = { force = "F0*cos(w*t)*R0.y", at = "P" }'))
    [acc] = accelerations(eom)
    assert same(acc, (F0 * sp.cos(w * t) * sp.cos(theta) - m * g * sp.sin(theta)) / (m * l))
    assert not has_potential(eom, "shake") and has_potential(eom, "weight")
    assert not eom.conservative
    assert integrals(eom) == {}


def test_velocity_dependent_force_is_not_conservative() -> None:
    eom = on_line('drag = { force = "-c*x_dot*R0.x", at = "P" }', "c = 0.3")
    [acc] = accelerations(eom)
    assert same(acc, -c * x_dot / m)
    assert not eom.conservative and integrals(eom) == {}


def test_force_on_a_fixed_point_does_nothing() -> None:
    eom = derive(PENDULUM.format(loads='on_pivot = { force = "F*R0.y", at = "O" }'))
    assert sym(load(eom, "on_pivot").Q[0]) == 0
    [acc] = accelerations(eom)
    assert same(acc, -g / l * sp.sin(theta))


# -- given potential ----------------------------------------------------------------------------
def test_given_potential() -> None:
    eom = on_line('quartic = { potential = "k*x^4/4" }', "k = 3.0")
    [acc] = accelerations(eom)
    assert same(acc, -k * x**3 / m)
    quartic = load(eom, "quartic")
    assert quartic.kind == "potential" and same(sym(quartic.potential), k * x**4 / 4)
    assert same(sym(quartic.Q[0]), -k * x**3)
    assert eom.conservative and same(sym(eom.L), m * x_dot**2 / 2 - k * x**4 / 4)
    fi = integrals(eom)
    assert set(fi) == {"E"} and same(sym(fi["E"].expression), m * x_dot**2 / 2 + k * x**4 / 4)


def test_time_dependent_potential_gives_no_energy_integral() -> None:
    eom = on_line('trap = { potential = "k*(x - l0*sin(w*t))^2/2" }', "k = 3.0\nl0 = 0.5\nw = 2.0")
    [acc] = accelerations(eom)
    assert same(acc, -k * (x - l0 * sp.sin(w * t)) / m)
    assert eom.conservative  # it derives from U(q, t) ...
    assert integrals(eom) == {}  # ... but ∂L/∂t ≠ 0: neither energy nor Jacobi integral


# -- given generalized force ------------------------------------------------------------------------
def test_generalized_force_minus_k_x_is_conservative() -> None:
    eom = on_line('restoring = { generalized_force = { x = "-k*x" } }', "k = 3.0")
    [acc] = accelerations(eom)
    assert same(acc, -k * x / m)
    restoring = load(eom, "restoring")
    assert restoring.kind == "generalizedforce"
    assert restoring.potential is not None
    U = sym(restoring.potential)
    assert same(U.diff(x), k * x) and (U - k * x**2 / 2).free_symbols <= {k}
    assert eom.conservative and set(integrals(eom)) == {"E"}


@pytest.mark.parametrize(("component", "expected"), [("-c*x_dot", -c * x_dot), ("F0*cos(w*t)", F0 * sp.cos(w * t))])
def test_generalized_force_depending_on_rate_or_time_is_not_conservative(component: str, expected: sp.Expr) -> None:
    eom = on_line(f'given = {{ generalized_force = {{ x = "{component}" }} }}', "c = 0.3\nF0 = 1.0\nw = 2.0")
    [acc] = accelerations(eom)
    assert same(acc, expected / m)
    assert not has_potential(eom, "given") and not eom.conservative
    assert same(sym(eom.Q_nc[0]), expected)
    assert integrals(eom) == {}


def test_generalized_force_on_a_cyclic_coordinate_kills_its_momentum() -> None:
    """Free particle in the plane: y stays cyclic (momentum m ẏ), x is driven by −c ẋ."""
    eom = derive("""
        [parameters]
        m = 1.0
        c = 0.3
        [coordinates]
        x = { initial = 0.0, rate = 1.0 }
        y = { initial = 0.0, rate = 1.0, momentum = "py" }
        [particles.P]
        mass = "m"
        position = "x*R0.x + y*R0.y"
        [loads]
        brake = { generalized_force = { x = "-c*x_dot" } }
    """)
    fi = integrals(eom)
    assert set(fi) == {"py"}
    assert fi["py"].kind == "momentum" and same(sym(fi["py"].expression), m * y_dot)


# -- Jacobi integral: bead on a hoop turning at a constant rate ---------------------------------------
def test_bead_on_rotating_hoop_has_a_jacobi_integral() -> None:
    """Hoop of radius r turning about the ascending vertical O z0 at the imposed rate Ω (frame
    angle Omega*t); the bead is at θ from the bottom.  T = ½ m r² (θ̇² + Ω² sin²θ) is not
    homogeneous in θ̇, the energy T + U is not conserved, but h = T2 − T0 + U is."""
    eom = derive("""
        [parameters]
        m = 0.1
        r = 0.5
        g = 9.81
        Omega = 6.0
        [coordinates]
        theta = { initial = 0.5, rate = 0.0 }
        [frames]
        R1 = { from = "R0", rotation = ["Omega*t", "z"] }
        R2 = { from = "R1", rotation = ["theta", "y"] }
        [particles.P]
        mass = "m"
        position = "-r*R2.z"
        [loads]
        weight = { gravity = "-g*R0.z" }
    """)
    T = sym(eom.T)
    assert same(T, m * r**2 * (theta_dot**2 + Omega**2 * sp.sin(theta) ** 2) / 2)
    [acc] = accelerations(eom)
    assert same(acc, Omega**2 * sp.sin(theta) * sp.cos(theta) - g / r * sp.sin(theta))
    assert eom.conservative
    fi = integrals(eom)
    assert set(fi) == {"h"}
    assert fi["h"].kind == "jacobi"
    h = m * r**2 * (theta_dot**2 - Omega**2 * sp.sin(theta) ** 2) / 2 - m * g * r * sp.cos(theta)
    assert same(sym(fi["h"].expression), h)
    # and it is a first integral while the energy is not
    E = T + sym(eom.U)
    assert same(h.diff(theta) * theta_dot + h.diff(theta_dot) * acc, 0)
    assert not same(E.diff(theta) * theta_dot + E.diff(theta_dot) * acc, 0)


def test_pendulum_with_a_moving_pivot_has_no_integral() -> None:
    """Pivot driven along the vertical by z = l0 cos(w t): L depends on t, no energy nor Jacobi integral."""
    eom = derive("""
        [parameters]
        m = 1.0
        l = 0.5
        g = 9.81
        l0 = 0.05
        w = 20.0
        [coordinates]
        theta = { initial = 0.3, rate = 0.0 }
        [frames]
        R1 = { from = "R0", rotation = ["theta", "x"] }
        [points]
        S = "l0*cos(w*t)*R0.z"
        [particles.P]
        mass = "m"
        from = "S"
        position = "-l*R1.z"
        [loads]
        weight = { gravity = "-g*R0.z" }
    """)
    [acc] = accelerations(eom)
    # l θ̈ = −(g + z̈_S) sin θ with z̈_S = −l0 w² cos(w t)  (Kapitza pendulum)
    assert same(acc, -(g - l0 * w**2 * sp.cos(w * t)) * sp.sin(theta) / l)
    assert eom.conservative and integrals(eom) == {}
