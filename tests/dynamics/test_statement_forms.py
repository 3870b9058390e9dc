"""A model written as its statement says gives the equations of the longer formulation.

Each short form is compared with the formulation that worked before it: the same M and F
(simplified difference zero, and the same numbers at random states).
"""

from __future__ import annotations

import random
import textwrap

import pytest
import sympy as sp

import lagrangian
from lagrangian.errors import ModelError


def parse(toml: str) -> lagrangian.Model:
    return lagrangian.parse_model(textwrap.dedent(toml), source="<test>")


def derive(toml: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(parse(toml))


def sym(expr) -> sp.Expr:  # noqa: ANN001 - a SymEngine expression
    return sp.sympify(expr._sympy_())


def mass_and_forces(eom: lagrangian.EquationsOfMotion, subs: dict | None = None) -> tuple[sp.Matrix, sp.Matrix]:
    M = sp.Matrix([[sym(e) for e in row] for row in eom.M]).subs(subs or {})
    F = sp.Matrix([sym(e) for e in eom.F]).subs(subs or {})
    return M, F


def assert_same_equations(a: lagrangian.EquationsOfMotion, b: lagrangian.EquationsOfMotion,
                          subs_b: dict | None = None, *, states: int = 3) -> None:
    """The same M and F: symbolically (simplified difference zero) and numerically at random states."""
    assert a.coordinates == b.coordinates
    Ma, Fa = mass_and_forces(a)
    Mb, Fb = mass_and_forces(b, subs_b)
    for x, y in zip(list(Ma) + list(Fa), list(Mb) + list(Fb), strict=True):
        d = sp.expand(x - y)
        assert d == 0 or sp.simplify(sp.trigsimp(d)) == 0, (x, y)
    symbols = sorted((Ma.free_symbols | Fa.free_symbols | Mb.free_symbols | Fb.free_symbols), key=str)
    rng = random.Random(16)
    for _ in range(states):
        point = {s: rng.uniform(0.3, 1.7) for s in symbols}
        for x, y in zip(list(Ma) + list(Fa), list(Mb) + list(Fb), strict=True):
            assert abs(complex(x.subs(point)) - complex(y.subs(point))) < 1e-9 * (1 + abs(complex(x.subs(point))))


# -- a couple on a massless link --------------------------------------------------------
DOUBLE_PENDULUM = """
    [parameters]
    m1 = 1.0
    m2 = 0.5
    l1 = 1.0
    l2 = 0.8
    g = 9.81
    Gamma1 = {{}}
    Gamma2 = {{}}
    {extra_parameters}
    [coordinates]
    theta1 = {{ initial = 0.3 }}
    theta2 = {{ initial = -0.2 }}
    [frames]
    R1 = {{ from = "R0", rotation = ["theta1", "x"] }}
    R2 = {{ from = "R1", rotation = ["theta2", "x"] }}
    [points]
    A = "-l1*R1.z"
    [particles.P1]
    mass = "m1"
    position = "-l1*R1.z"
    [particles.P2]
    mass = "m2"
    position = "-l1*R1.z - l2*R2.z"
    {bodies}
    [loads]
    weight = {{ gravity = "-g*R0.z" }}
    shoulder = {{ torque = "Gamma1*R0.x", on = "{link1}" }}
    elbow = {{ torque = "Gamma2*R1.x", on = "{link2}", reaction_on = "{link1}" }}
"""

INVENTED_BODIES = """
    [bodies.L1]
    frame = "R1"
    mass = "mu"
    center = "-l1/2*R1.z"
    inertia = { diagonal = ["J", "J", "J"] }
    [bodies.L2]
    frame = "R2"
    mass = "mu"
    center_from = "A"
    center = "-l2/2*R2.z"
    inertia = { diagonal = ["J", "J", "J"] }
"""


@pytest.mark.slow
def test_couple_on_massless_links_is_that_on_invented_zero_mass_bodies() -> None:
    """Motors at the shoulder and the elbow of a double pendulum of massless rods: a couple on a
    frame (virtual power C·Ω*(frame)) gives the equations of the old form, where the rods had to
    be bodies of mass mu and inertia J, set to zero afterwards."""
    on_frames = derive(DOUBLE_PENDULUM.format(extra_parameters="", bodies="", link1="R1", link2="R2"))
    on_bodies = derive(DOUBLE_PENDULUM.format(extra_parameters="mu = {}\n    J = {}", bodies=INVENTED_BODIES,
                                              link1="L1", link2="L2"))
    mu, J = sp.symbols("mu J")
    assert_same_equations(on_frames, on_bodies, {mu: 0, J: 0})
    # and independently: the elbow couple's generalized forces are (0, Γ2), the shoulder's (Γ1, 0)
    Q = {f.name: [sym(x) for x in f.Q] for f in on_frames.loads}
    assert Q["shoulder"] == [sp.Symbol("Gamma1"), 0]
    assert Q["elbow"] == [0, sp.Symbol("Gamma2")]


def test_couple_on_an_unknown_name_names_bodies_and_frames() -> None:
    with pytest.raises(ModelError, match="unknown body or frame `R9`"):
        parse(DOUBLE_PENDULUM.format(extra_parameters="", bodies="", link1="R9", link2="R2"))


# -- a rotation about a constant axis of the parent ------------------------------------
FOUCAULT_AXIS = """
    # The Foucault pendulum as its statement says: the Earth E turns at Omega about its polar
    # axis, cos(lam) north + sin(lam) up in the local frame R0 (x east, y north, z up); the attraction
    # is the apparent gravity −g z at the bob's rest place, less the centrifugal Ω² OP⊥ there.
    [parameters]
    m = 1.0
    l = 1.0
    g = 9.81
    Omega = 0.2
    lam = 0.7853981633974483
    [coordinates]
    alpha = { initial = 0.0 }
    beta = { initial = 0.1 }
    [frames]
    E = { from = "R0", rotation = ["Omega*t", "cos(lam)*R0.y + sin(lam)*R0.z"] }
    R1 = { from = "E", rotation = ["-alpha", "y"] }
    R2 = { from = "R1", rotation = ["beta", "x"] }
    [reference]
    frame = "E"
    [particles.P]
    mass = "m"
    position = "-l*R2.z"
    [loads]
    weight = { gravity = "-(g - Omega^2*l)*E.z - Omega^2*l*sin(lam)*cos(lam)*E.y - Omega^2*l*sin(lam)^2*E.z" }
"""


@pytest.mark.slow
def test_foucault_about_the_polar_axis_is_the_chained_formulation() -> None:
    """One rotation about cos(λ) y + sin(λ) z gives the equations of examples/foucault_pendulum.toml
    (rotation about z0, then the tilt π/2 − λ of the local frame): the bob is at the same place
    (x = l sin α cos β east, l sin β north) and Ω(E/R0) is the same vector."""
    from pathlib import Path

    chained = lagrangian.derive(lagrangian.load_model(Path(__file__).parents[2] / "examples" / "foucault_pendulum.toml"))
    axis = derive(FOUCAULT_AXIS)
    assert_same_equations(axis, chained)
    rotation = axis.model.frame("E").rotation
    assert not rotation.elementary and not rotation.normalized  # cos² + sin² = 1: kept as written


def test_builder_takes_the_axis_too() -> None:
    b = lagrangian.ModelBuilder("Foucault")
    for name, value in (("m", 1.0), ("l", 1.0), ("g", 9.81), ("Omega", 0.2), ("lam", 0.785)):
        b.parameter(name, value)
    b.coordinate("alpha")
    b.coordinate("beta")
    b.frame("E", "R0", rotation=("Omega*t", "cos(lam)*R0.y + sin(lam)*R0.z"))
    b.frame("R1", "E", rotation=("-alpha", "y"))
    b.frame("R2", "R1", rotation=("beta", "x"))
    b.reference("E")
    b.particle("P", mass="m", position="-l*R2.z")
    b.gravity("weight", "-(g - Omega^2*l)*E.z - Omega^2*l*sin(lam)*cos(lam)*E.y - Omega^2*l*sin(lam)^2*E.z")
    assert_same_equations(lagrangian.derive(b.build()), derive(FOUCAULT_AXIS.replace("0.7853981633974483", "0.785")),
                          states=1)


@pytest.mark.slow
def test_axis_not_unit_is_normalized_and_basis_vector_is_elementary() -> None:
    tilted = parse(FOUCAULT_AXIS.replace("cos(lam)*R0.y + sin(lam)*R0.z", "3*R0.y + 4*R0.z")).frame("E").rotation
    assert tilted.normalized and [sp.nsimplify(sym(c)) for c in tilted.direction] == [0, sp.Rational(3, 5),
                                                                                       sp.Rational(4, 5)]
    assert parse(FOUCAULT_AXIS.replace("cos(lam)*R0.y + sin(lam)*R0.z", "R0.z")).frame("E").rotation.axis == "z"
    # a symbolic axis that is not provably unit is divided by its norm, and the frames say so
    from lagrangian.output import course_form, render_latex, render_text

    eom = derive(FOUCAULT_AXIS.replace("cos(lam)*R0.y + sin(lam)*R0.z", "l*R0.y + R0.z"))
    form = course_form(eom, ())
    assert "(the axis given, divided by its norm)" in render_text(form)
    assert r"\text{(the axis given, divided by its norm)}" in render_latex(form)


@pytest.mark.parametrize(("axis", "message"), [
    ("0*R0.y", "is the zero vector"),
    ("(l - 1)*R0.y", r"is the zero vector \(with l = 1\)"),
    ("alpha*R0.y + R0.z", "depends on `alpha`"),
    ("cos(Omega*t)*R0.y + R0.z", "depends on `t`"),
    ("R1.z", "is written in `R1`, not in its parent `R0`"),
])
def test_bad_axes_are_refused_clearly(axis: str, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        parse(FOUCAULT_AXIS.replace("cos(lam)*R0.y + sin(lam)*R0.z", axis))


# -- conservative with multipliers -----------------------------------------------------
def test_gravity_and_a_scleronomic_multiplier_is_conservative_with_its_lagrangian() -> None:
    """The pendulum of examples/pendulum_tension.toml (x, y, the rod kept as x² + y² − l² = 0 with
    λ): gravity only and a perfect time-independent constraint, so L = T − U_P, and SymPy's
    LagrangesMethod on that L with the same holonomic constraint finds our equations, λ included."""
    from pathlib import Path

    from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

    eom = lagrangian.derive(lagrangian.load_model(Path(__file__).parents[2] / "examples" / "pendulum_tension.toml"))
    assert eom.constraints and eom.conservative and eom.scleronomic
    m, g, l = sp.symbols("m g l")
    x, y, xd, yd = sp.symbols("x y x_dot y_dot")
    assert sp.expand(sym(eom.L) - (m * (xd**2 + yd**2) / 2 - m * g * y)) == 0  # T − U, U = m g y
    s = eom.to_sympy(time_functions=True)
    X, Y = s.q
    lm = LagrangesMethod(s.L, list(s.q), hol_coneqs=[X**2 + Y**2 - l**2])
    theirs = lm.form_lagranges_equations()  # d/dt ∂L/∂q̇ − ∂L/∂q − (their λ terms) = 0
    lam = dynamicsymbols("lambda_length")
    ours = [eq.lhs - eq.rhs for eq in s.equations]
    assert len(lm.lam_vec) == 1
    matches = [all(sp.simplify(a - b.subs(lm.lam_vec[0], sign * lam)) == 0 for a, b in zip(ours, theirs, strict=True))
               for sign in (1, -1)]
    assert any(matches)  # the same equations, up to the sign convention of λ


def test_a_rheonomic_multiplier_is_not_conservative() -> None:
    """The same rod with a length that changes with t: its reaction works on the motion (−λ b)."""
    from pathlib import Path

    text = (Path(__file__).parents[2] / "examples" / "pendulum_tension.toml").read_text()
    eom = lagrangian.derive(lagrangian.parse_model(text.replace('"x^2 + y^2 - l^2"', '"x^2 + y^2 - (l + t/10)^2"'),
                                                   source="<test>"))
    assert eom.constraints and not eom.scleronomic and not eom.conservative and eom.L is None


# -- masses only where they matter -----------------------------------------------------
ATWOOD = """
    # Atwood's machine: A (m1) and B (m2) hang from a rope over a pulley of inertia J turning
    # about its fixed axle O; the rope does not slip (pulley angle -x/r) and x is A's descent.
    [parameters]
    m1 = 2.0
    m2 = 1.0
    r = 0.1
    J = 0.01
    g = 9.81
    {extra}
    [coordinates]
    x = {{ initial = 0.0, rate = 0.0 }}
    [frames]
    Rp = {{ from = "R0", rotation = ["-x/r", "z"] }}
    [bodies.pulley]
    frame = "Rp"
    {mass}
    center = "{center}"
    inertia = {{ diagonal = ["J/2", "J/2", "J"] }}
    [particles.A]
    mass = "m1"
    position = "-r*R0.x - (1 + x)*R0.y"
    [particles.B]
    mass = "m2"
    position = "r*R0.x - (1 - x)*R0.y"
    [loads]
    weight = {{ gravity = "-g*R0.y" }}
"""


def atwood(mass: str = "", extra: str = "", center: str = "0") -> str:
    return ATWOOD.format(mass=mass, extra=extra, center=center)


def test_atwood_without_a_pulley_mass_is_atwood_with_one() -> None:
    """The pulley's mass enters neither T (its centre is fixed) nor the work of the weights: the
    equations are those of the model that gives it, and (m1 + m2 + J/r²) ẍ = (m1 − m2) g."""
    without = derive(atwood())
    given = derive(atwood(mass='mass = "M"', extra="M = 3.0", center="0.5*R0.y"))
    assert not without.model.body("pulley").mass_given and given.model.body("pulley").mass_given
    assert_same_equations(without, given)
    m1, m2, r, J, g = sp.symbols("m1 m2 r J g")
    M, F = mass_and_forces(without)
    assert sp.simplify(F[0] / M[0, 0] - (m1 - m2) * g / (m1 + m2 + J / r**2)) == 0
    # the pulley's weight is a constant of U: left out, so M has no part in the energy either
    assert sp.Symbol("M") not in sym(given.U).free_symbols


def test_reactions_ask_for_the_mass_and_simulate_runs_without_it() -> None:
    from lagrangian.analysis import reactions

    without = derive(atwood())
    with pytest.raises(ModelError, match="the reactions need the mass of body `pulley`"):
        reactions(without)
    trajectory = lagrangian.simulate(without, 0.5, n_out=3)
    m1, m2, r, J, g = 2.0, 1.0, 0.1, 0.01, 9.81
    assert trajectory.q[-1, 0] == pytest.approx(0.5 * (m1 - m2) * g / (m1 + m2 + J / r**2) * 0.5**2, rel=1e-8)
    # a mass given as a symbol without a value: nothing the motion needs holds it
    unvalued = derive(atwood(mass='mass = "M"', extra="M = {}", center="0.5*R0.y"))
    assert lagrangian.simulate(unvalued, 0.5, n_out=3).q[-1, 0] == pytest.approx(trajectory.q[-1, 0], rel=1e-12)


def test_simulate_cli_runs_with_no_reactions_and_says_why_otherwise(tmp_path, capsys) -> None:  # noqa: ANN001
    from lagrangian.cli.main import main

    model = tmp_path / "atwood.toml"
    model.write_text(textwrap.dedent(atwood(mass='mass = "M"', extra="M = {}", center="0.5*R0.y")))
    assert main(["simulate", str(model), "--t-end", "0.2", "--n-out", "3", "--no-reactions",
                 "-o", str(tmp_path / "out.csv")]) == 0
    capsys.readouterr()
    # Without --no-reactions the run goes on too, and one line says what the reactions would need.
    assert main(["simulate", str(model), "--t-end", "0.2", "--n-out", "3", "-o", str(tmp_path / "r.csv")]) == 0
    out = capsys.readouterr()
    line = next(x for x in (out.out + out.err).splitlines() if x.startswith("reactions:"))
    assert "`M` have no value" in line and "--set" in line
    # Asked for with --reactions, they stop the run and say how to go without them.
    assert main(["simulate", str(model), "--t-end", "0.2", "--n-out", "3", "--reactions",
                 "-o", str(tmp_path / "r.csv")]) != 0
    err = capsys.readouterr().err
    assert "`M` have no value" in err and "--no-reactions" in err


@pytest.mark.parametrize(("change", "message"), [
    (dict(center="x*R0.y"), r"no `mass`, but its centre of mass moves \(with `x`\)"),
    (dict(center="0.1*Rp.x"), r"no `mass`, but its centre of mass moves \(with `x`\)"),
])
def test_a_moving_centre_needs_its_mass(change: dict, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        parse(atwood(**change))


def test_inertia_elsewhere_than_g_needs_the_mass() -> None:
    text = atwood().replace("[bodies.pulley]", '[points]\n    K = "0.05*Rp.x"\n    [bodies.pulley]')
    assert not parse(text.replace("inertia = { diagonal", 'inertia = { at = "O", diagonal')).bodies[0].mass_given
    with pytest.raises(ModelError, match="inertia is given at `K`, not at its centre of mass"):
        parse(text.replace("inertia = { diagonal", 'inertia = { at = "K", diagonal'))


def test_no_mass_in_a_moving_reference_frame_is_refused() -> None:
    text = atwood(extra="Omega = 1.0").replace("[bodies.pulley]", 'W = { from = "R0", rotation = ["Omega*t", "y"] }\n'
                                                "    [reference]\n    frame = \"W\"\n    [bodies.pulley]")
    text = text.replace('Rp = { from = "R0"', 'Rp = { from = "W"')
    with pytest.raises(ModelError, match="no `mass`, but the equations are written in `W`"):
        parse(text)
