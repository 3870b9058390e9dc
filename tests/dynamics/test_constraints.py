"""Complementary constraints in the derivation: rows, multipliers, reactions, errors.

Independent truths: closed forms (the pendulum's tension m(g cos θ + l θ̇²), the disk's
friction force −⅓ m g sin α and normal force m g cos α), and SymPy's
``LagrangesMethod`` / ``KanesMethod`` with the same constraints (oracles in tests only).
SymPy writes its equations as Γ_i + Σ λ_k A_ki − Q_i = 0, so its multipliers are minus
ours (we write Γ_i = Q_i + Σ λ_k A_ki: the reaction's generalized force is +λ A).
"""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se
import sympy as sp
import sympy.physics.mechanics as me
from lagrangian_test_support import EXAMPLES_DIR, mutated_example

import lagrangian
from lagrangian._identity import is_zero
from lagrangian.dynamics._constraints import multiplier_formulas
from lagrangian.errors import ModelError

RNG_SEED = 20261123
RTOL = 1e-9


def eom_of(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))


def model_text(name: str) -> str:
    return (EXAMPLES_DIR / name).read_text(encoding="utf-8")


def S(name: str) -> se.Symbol:
    return se.Symbol(name)


PENDULUM = """
[parameters]
m = 1.0
l = 0.5
g = 9.81
[coordinates]
x = { initial = 0.2397127693021015, rate = 0.0 }
y = { initial = -0.4387912809451864, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x + y*R0.y"
[loads]
weight = { gravity = "-g*R0.y" }
[constraints]
"""


def derive_text(text: str, source: str = "model.toml") -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(text, source=source))


# -- the pendulum: rows, step 7, tension -------------------------------------------------------------
def test_pendulum_rows_equations_and_multiplier_terms() -> None:
    eom = eom_of("pendulum_tension.toml")
    x, y, lam = S("x"), S("y"), S("lambda_length")
    (row,) = eom.constraints
    assert (row.name, row.kind, row.multiplier) == ("length", "holonomic", lam)
    assert is_zero(row.expression - (x**2 + y**2 - S("l") ** 2))  # step 7: f = 0
    assert row.coefficients == (2 * x, 2 * y) and row.b == 0
    assert eom.multipliers == (lam,) and eom.A == ((2 * x, 2 * y),)
    # L(x): m ẍ = 2 λ x;  L(y): m ÿ = −m g + 2 λ y.
    assert is_zero(eom.equation("x").rhs - 2 * lam * x)
    assert is_zero(eom.equation("y").rhs - (-S("g") * S("m") + 2 * lam * y))
    assert is_zero(eom.equation("y").multiplier_terms - 2 * lam * y)
    # The unconstrained M q̈ = F is unchanged: the multipliers are apart.
    assert eom.F[0] == 0 and lam not in eom.F[1].free_symbols


def test_pendulum_tension_closed_form_and_sign() -> None:
    """T = −R·OP/l = m (g cos θ + l θ̇²), positive when the rod pulls P towards O."""
    eom = eom_of("pendulum_tension.toml")
    (lam,) = multiplier_formulas(eom)
    (reaction,) = eom.reactions
    assert reaction.point == "P" and reaction.frame == "R0"
    m, g, l, th, thd = (S(n) for n in ("m", "g", "l", "theta", "theta_dot"))
    x, y = l * se.sin(th), -l * se.cos(th)
    on_circle = {S("x"): x, S("y"): y, S("x_dot"): l * se.cos(th) * thd, S("y_dot"): l * se.sin(th) * thd}
    lam_on = lam.xreplace(on_circle)
    R = [c.xreplace({S("lambda_length"): lam_on}).xreplace(on_circle) for c in reaction.force_components]
    tension = -(R[0] * x + R[1] * y) / l
    assert is_zero(tension - m * (g * se.cos(th) + l * thd**2))
    # At rest at the bottom the rod holds the weight: T = m g > 0 and R points up, towards O.
    bottom = {m: 1.0, g: 9.81, l: 0.5, th: 0.0, thd: 0.0}
    assert float(tension.subs(bottom)) == pytest.approx(9.81)
    assert float(R[1].subs(bottom)) == pytest.approx(9.81) and float(lam_on.subs(bottom)) < 0


@pytest.mark.slow
def test_pendulum_multipliers_match_sympy_lagranges_method() -> None:
    m, g, l = sp.symbols("m g l")
    x, y = me.dynamicsymbols("x y")
    N = me.ReferenceFrame("N")
    P = me.Point("P")
    P.set_vel(N, x.diff() * N.x + y.diff() * N.y)
    L = me.Particle("bob", P, m).kinetic_energy(N)
    lm = me.LagrangesMethod(L, [x, y], hol_coneqs=[x**2 + y**2 - l**2], forcelist=[(P, -m * g * N.y)], frame=N)
    lm.form_lagranges_equations()
    t = me.dynamicsymbols._t
    eom = eom_of("pendulum_tension.toml")
    (lam,) = multiplier_formulas(eom)
    lam = lam._sympy_()
    xs, ys, xd, yd = sp.symbols("x y x_dot y_dot")
    # Our q̈ = M⁻¹(F + Aᵀλ) and −λ satisfy SymPy's equations (module docstring).
    ours_qdd = {x.diff(t, 2): 2 * lam * xs / m, y.diff(t, 2): -g + 2 * lam * ys / m}
    residual = lm.eom.xreplace(ours_qdd).xreplace({lm.lam_vec[0]: -lam}).xreplace(
        {x.diff(t): xd, y.diff(t): yd}).xreplace({x: xs, y: ys})
    assert sp.simplify(residual) == sp.zeros(2, 1)
    # With +λ they would not: the sign convention is tested, not assumed.
    wrong = lm.eom.xreplace(ours_qdd).xreplace({lm.lam_vec[0]: lam}).xreplace(
        {x.diff(t): xd, y.diff(t): yd}).xreplace({x: xs, y: ys})
    assert sp.simplify(wrong) != sp.zeros(2, 1)


# -- the disk on the incline ------------------------------------------------------------------------------
def test_incline_friction_force_closed_form() -> None:
    eom = eom_of("rolling_disk_incline.toml")
    (row,) = eom.constraints
    assert (row.name, row.kind) == ("rolling_x1", "nonholonomic")
    assert is_zero(row.expression - (S("x_dot") - S("r") * S("phi_dot")))
    (lam,) = multiplier_formulas(eom)
    m, g, alpha = S("m"), S("g"), S("alpha")
    assert is_zero(lam + m * g * se.sin(alpha) / 3)  # −⅓ m g sin α: along −x1, up the slope
    (reaction,) = eom.reactions
    assert (reaction.point, reaction.frame) == ("I", "R1")
    assert reaction.force_components == (S("lambda_rolling_x1"), 0, 0)


INCLINE_NORMAL = """
[parameters]
m = 1.0
r = 0.1
g = 9.81
alpha = 0.3
[coordinates]
x = { initial = 0.0, rate = 0.0 }
z = { initial = 0.1, rate = 0.0 }
phi = { initial = 0.0, rate = 0.0 }
[frames]
R1 = { from = "R0", rotation = ["alpha", "y"] }
R2 = { from = "R1", rotation = ["phi", "y"] }
[points]
I = "x*R1.x + (z - r)*R1.z"
[bodies.S]
frame = "R2"
mass = "m"
center = "x*R1.x + z*R1.z"
inertia = { at = "G", frame = "R2", diagonal = ["m*r^2/4", "m*r^2/2", "m*r^2/4"] }
[loads]
weight = { gravity = "-g*R0.z" }
[constraints]
contact = { holonomic = "z - r", reaction = { force_at = "I", frame = "R1" } }
"""


def test_incline_normal_force_from_a_holonomic_multiplier() -> None:
    """With the height of G complementary too, its multiplier is the normal force m g cos α."""
    eom = derive_text(INCLINE_NORMAL + 'rolling = { nonholonomic = { x = "1", phi = "-r" } }\n')
    assert [r.name for r in eom.constraints] == ["contact", "rolling"]
    lam_contact, lam_rolling = multiplier_formulas(eom)
    m, g, alpha = S("m"), S("g"), S("alpha")
    assert is_zero(lam_contact - m * g * se.cos(alpha))
    assert is_zero(lam_rolling + m * g * se.sin(alpha) / 3)
    contact, rolling = eom.reactions
    assert [se.expand(c) for c in contact.force_components] == [0, 0, S("lambda_contact")]
    assert not rolling.physical  # no `reaction` declared: generalized forces only
    assert rolling.generalized == (S("lambda_rolling"), 0, -S("r") * S("lambda_rolling"))


# -- the coin: nonholonomic rows against SymPy's KanesMethod -------------------------------------------------
def _coin_kane() -> tuple[list, sp.Matrix, dict]:
    m, r = sp.symbols("m r")
    x, y, psi, phi = q = me.dynamicsymbols("x y psi phi")
    u = me.dynamicsymbols("u1:5")
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", (psi, N.z))
    R2 = R1.orientnew("R2", "Axis", (phi, R1.y))
    R2.set_ang_vel(N, u[2] * N.z + u[3] * R1.y)
    G = me.Point("G")
    G.set_vel(N, u[0] * N.x + u[1] * N.y)
    I = G.locatenew("I", -r * N.z)
    I.v2pt_theory(G, N, R2)
    coin = me.RigidBody("S", G, R2, m, (me.inertia(R2, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4), G))
    kde = [qi.diff() - ui for qi, ui in zip(q, u, strict=True)]
    nonholonomic = [I.vel(N).dot(R1.x), I.vel(N).dot(R1.y)]
    km = me.KanesMethod(N, q_ind=q, u_ind=[u[2], u[3]], u_dependent=[u[0], u[1]], kd_eqs=kde,
                        velocity_constraints=nonholonomic)
    km.kanes_equations([coin], [])
    rhs = km.rhs()
    # rhs = (q̇, u̇) with u̇ in KanesMethod's order of the speeds; ours is u1..u4 (ẍ, ÿ, ψ̈, φ̈).
    order = [list(km.u).index(ui) for ui in u]
    return q, sp.Matrix([rhs[4 + k] for k in order]), {"u": u}


@pytest.mark.slow
def test_coin_accelerations_match_sympy_kanes_method() -> None:
    eom = eom_of("rolling_coin.toml")
    assert [r.name for r in eom.constraints] == ["rolling_x1", "rolling_y1"]
    q, rhs, extra = _coin_kane()
    u = extra["u"]
    lam = multiplier_formulas(eom)
    # q̈ = M⁻¹ (F + Aᵀ λ) from the engine, at consistent states.
    M = se.DenseMatrix([list(r) for r in eom.M])
    A = se.DenseMatrix([list(r.coefficients) for r in eom.constraints])
    F = se.DenseMatrix([[f] for f in eom.F]) + A.T * se.DenseMatrix([[x] for x in lam])
    qdd = M.LUsolve(F)
    rng = np.random.default_rng(RNG_SEED)
    for _ in range(3):
        psi, phi, psid, phid = rng.uniform(-2, 2, 4)
        v = 0.1 * phid  # r φ̇ along the heading
        state = {"x": 0.3, "y": -0.2, "psi": psi, "phi": phi,
                 "x_dot": v * np.cos(psi), "y_dot": v * np.sin(psi), "psi_dot": psid, "phi_dot": phid}
        values = {S(k): val for k, val in state.items()} | {S("m"): 0.01, S("r"): 0.1, S("g"): 9.81}
        ours = np.array([float(qdd[i, 0].subs(values)) for i in range(4)])
        kane = {sp.Symbol("m"): 0.01, sp.Symbol("r"): 0.1}
        kane.update({qi: state[str(qi.func)] for qi in q})
        kane.update({ui: state[str(qi.func) + "_dot"] for qi, ui in zip(q, u, strict=True)})
        theirs = np.array([float(e) for e in rhs.subs(kane)])
        assert np.allclose(ours, theirs, rtol=RTOL, atol=1e-12), (ours, theirs)


# -- the top ---------------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_top_pivot_rows_and_reaction_at_O() -> None:
    eom = eom_of("top_reaction.toml")
    assert [r.name for r in eom.constraints] == ["pivot_x0", "pivot_y0", "pivot_z0"]
    assert all(r.kind == "holonomic" for r in eom.constraints)
    (reaction,) = eom.reactions
    assert reaction.point == "O_S" and reaction.counter_point is None  # O is fixed
    assert reaction.force_components == tuple(S(f"lambda_pivot_{a}") for a in ("x0", "y0", "z0"))
    # L(x_G): m ẍ_G = λ_x: the resultant theorem along x0, with R_O the only other force.
    assert is_zero(eom.equation("xG").rhs - S("lambda_pivot_x0"))
    # K (of ψ alone) is lost, σ_O·z0 of the whole top stays (Noether: rotations about O z0 keep the pivot).
    assert {fi.name for fi in lagrangian.first_integrals(eom)} == {"H", "E", "sigma_O_z0"}


# -- first integrals -------------------------------------------------------------------------------------------
def test_momentum_of_a_coordinate_the_reaction_acts_on_is_not_an_integral() -> None:
    # x is cyclic in T and U, but the rod pulls on it: p_x = m ẋ is not constant.
    names = {fi.name for fi in lagrangian.first_integrals(eom_of("pendulum_tension.toml"))}
    assert names == {"E"}


def test_time_dependent_constraint_removes_the_energy_integral() -> None:
    text = PENDULUM.replace("l = 0.5", "l = 0.5\nv = 0.1") + 'length = { holonomic = "x^2 + y^2 - (l + v*t)^2" }\n'
    eom = derive_text(text)
    assert eom.constraints[0].b != 0
    assert lagrangian.first_integrals(eom) == ()


def test_model_without_constraints_is_unchanged() -> None:
    eom = lagrangian.derive(lagrangian.lagrange_top())
    assert eom.constraints == () and eom.reactions == () and eom.multipliers == ()
    assert all(eq.multiplier_terms == 0 for eq in eom.equations)


# -- principal constraints -----------------------------------------------------------------------------------------
def test_principal_constraint_satisfied_by_the_coordinates_gets_no_multiplier() -> None:
    # OP = l, written with the coordinate θ: satisfied through sin² + cos² = 1 (step 1, principal).
    text = model_text("simple_pendulum.toml") + (
        '\n[constraints]\nrod = { holonomic = "(l*sin(theta))^2 + (l*cos(theta))^2 - l^2", principal = true }\n')
    eom = derive_text(text)
    assert eom.constraints == () and eom.reactions == ()
    assert eom.model.constraints[0].principal and eom.model.constraints[0].kind == "holonomic"


def test_principal_no_slip_is_checked() -> None:
    # The disk with x = r φ chosen by the coordinates: rolling without slipping holds identically.
    text = model_text("rolling_disk_incline.toml")
    text = text.replace('x = { initial = 0.0, rate = 0.0, unit = "m", description = { fr = "distance de G vers le bas de la pente", '
                        'en = "distance of G down the slope" } }\n',
                        "").replace('"x*R1.x"', '"r*phi*R1.x"').replace('"x*R1.x + r*R1.z"', '"r*phi*R1.x + r*R1.z"')
    eom = derive_text(text.replace('frame = "R1", description', 'frame = "R1", principal = true, description'))
    assert eom.coordinates == ("phi",) and eom.constraints == ()
    with pytest.raises(ModelError, match="complementary constraint `rolling` is identically satisfied"):
        derive_text(text)


def test_principal_constraint_the_coordinates_break_is_an_error() -> None:
    text = PENDULUM + 'length = { holonomic = "x^2 + y^2 - l^2", principal = true }\n'
    with pytest.raises(ModelError, match="declared principal, but the coordinates do not satisfy it") as exc:
        derive_text(text)
    assert exc.value.line == text.splitlines().index(
        'length = { holonomic = "x^2 + y^2 - l^2", principal = true }') + 1


# -- bad input --------------------------------------------------------------------------------------------------------
def _line(text: str, needle: str) -> int:
    return next(k for k, line in enumerate(text.splitlines(), start=1) if needle in line)


@pytest.mark.parametrize(("constraint", "words"), [
    ('bad = { nonholonomic = "x_dot^2 + y_dot" }', "not linear in the velocities"),
    ('bad = { nonholonomic = "sin(x_dot)" }', "not linear in the velocities"),
    ('bad = { nonholonomic = { x = "y_dot" } }', "holds the rate `y_dot`"),
    ('bad = { holonomic = "x + y_dot" }', "depends on the rate `y_dot`"),
    ('bad = { nonholonomic = "x + y" }', "holds no rate"),
    ('bad = { nonholonomic = { z = "1" } }', "`z`, which is not a coordinate"),
    ('bad = { coincide = ["P", "P"] }', "keeps point `P` on itself"),
    ('bad = { coincide = ["P", "Q"] }', "unknown point `Q`"),
    ('bad = { no_slip = "P" }', "does not say which body"),
    ('bad = { holonomic = "x", frame = "R9" }', "unknown frame `R9`"),
    ('bad = { holonomic = "x", reaction = { at = "P" } }', "unknown key `at`"),
    ('bad = { holonomic = "x", reaction = {} }', "names neither a point nor a body"),
    ('bad = { holonomic = "x", principal = "yes" }', "must be true or false"),
    ('bad = { holonomic = "x", rolling = "P" }', "unknown key `rolling`"),
    ('bad = { description = "nothing" }', "exactly one of the keys"),
    ('bad = { holonomic = "x", axes = ["x0"] }', "is scalar"),
    ('bad = { coincide = ["P", "O"], axes = ["w"] }', "`w`, which is not an axis of its frame `R0`"),
    ('bad = { coincide = ["P", "O"], axes = ["x", "x0"] }', "names an axis twice"),
    ('bad = { coincide = ["P", "O"], axes = "x0" }', "must list axis names"),
    ("bad = 3", "must be a table"),
])
def test_bad_constraints_name_the_constraint_and_its_line(constraint: str, words: str) -> None:
    text = PENDULUM + constraint + "\n"
    with pytest.raises(ModelError) as exc:
        derive_text(text)
    err = exc.value
    assert words in err.message, err.message
    assert err.file == "model.toml" and err.line == _line(text, "bad =")
    assert err.fix


def test_axes_keep_the_rows_that_a_holonomic_contact_leaves() -> None:
    # No slip at I in R1 has rows x1, y1 (zero: dropped) and z1 = d/dt(z − r), redundant with `contact`
    # (next test); `axes` keeps x1 only, which is rolling ẋ − r φ̇ = 0, as the Pfaffian form says.
    kept = derive_text(INCLINE_NORMAL + 'rolling = { no_slip = "I", on = "S", frame = "R1", axes = ["x1"] }\n')
    pfaff = derive_text(INCLINE_NORMAL + 'rolling = { nonholonomic = { x = "1", phi = "-r" } }\n')
    assert [r.name for r in kept.constraints] == ["contact", "rolling_x1"]
    row, ref = kept.constraints[1], pfaff.constraints[1]
    assert row.kind == "nonholonomic"
    assert all(is_zero(a - b) for a, b in zip(row.coefficients, ref.coefficients, strict=True))
    # The same axis named as x (the letter) or as the frame's axis name.
    letter = derive_text(INCLINE_NORMAL + 'rolling = { no_slip = "I", on = "S", frame = "R1", axes = ["x"] }\n')
    assert [r.name for r in letter.constraints] == ["contact", "rolling_x1"]


def test_redundant_constraints_are_named() -> None:
    text = INCLINE_NORMAL + 'rolling = { no_slip = "I", on = "S", frame = "R1" }\n'
    with pytest.raises(ModelError, match=r"row `rolling_z1` is a combination of `contact`") as exc:
        derive_text(text)
    assert exc.value.line == _line(text, "rolling =")
    assert "redundant" in exc.value.message


def test_two_copies_of_a_constraint_are_redundant() -> None:
    text = PENDULUM + 'a = { holonomic = "x^2 + y^2 - l^2" }\nb = { holonomic = "2*(x^2 + y^2 - l^2)" }\n'
    with pytest.raises(ModelError, match=r"row `b` is a combination of `a`"):
        derive_text(text)


def test_a_declared_reaction_that_no_force_there_can_carry_is_an_error() -> None:
    # A force at the geometric contact point I (not the disk's material point) cannot make
    # rolling's virtual power −r λ φ*: the reaction needs `no_slip` (or no `reaction`).
    text = INCLINE_NORMAL + 'rolling = { nonholonomic = { x = "1", phi = "-r" }, reaction = { force_at = "I" } }\n'
    with pytest.raises(ModelError, match="the reaction of constraint `rolling` cannot be a force at `I`"):
        derive_text(text)


def test_constraint_identically_satisfied_or_never_satisfiable() -> None:
    with pytest.raises(ModelError, match="identically satisfied"):
        derive_text(PENDULUM + 'bad = { holonomic = "x - x" }\n')
    with pytest.raises(ModelError, match="involves no coordinate"):
        derive_text(PENDULUM + 'bad = { holonomic = "l" }\n')


def test_multiplier_name_taken_by_a_parameter() -> None:
    text = PENDULUM.replace("g = 9.81", "g = 9.81\nlambda_length = 1.0") + 'length = { holonomic = "x^2 + y^2 - l^2" }\n'
    with pytest.raises(ModelError, match="multiplier `lambda_length`"):
        derive_text(text)


def test_builder_declares_the_same_constraints_as_the_file() -> None:
    b = lagrangian.ModelBuilder("pendulum")
    for name, value in (("m", 1.0), ("l", 0.5), ("g", 9.81)):
        b.parameter(name, value)
    b.coordinate("x", 0.2397127693021015, 0.0)
    b.coordinate("y", -0.4387912809451864, 0.0)
    b.particle("P", mass="m", position="x*R0.x + y*R0.y")
    b.gravity("weight", "-g*R0.y")
    b.constraint("length", "holonomic", "x^2 + y^2 - l^2", reaction={"force_at": "P", "frame": "R0"})
    built = lagrangian.derive(b.build())
    from_file = eom_of("pendulum_tension.toml")
    assert built.constraints == from_file.constraints
    assert [r.force_components for r in built.reactions] == [r.force_components for r in from_file.reactions]


# -- integrable velocity rows: holonomic constraints written on the velocities --------------------------
def test_rolling_on_an_incline_integrates_to_x_minus_r_phi() -> None:
    from lagrangian.dynamics._constraints import describe_constraints

    (info,) = describe_constraints(eom_of("rolling_disk_incline.toml"))
    assert (info.form, info.kind) == ("no_slip", "holonomic")
    (phi,) = info.integrals
    assert is_zero(phi - (S("x") - S("r") * S("phi")))
    # The derivation still keeps the row at velocity level (the simulation's constraint).
    assert [r.kind for r in info.rows] == ["nonholonomic"]


def test_a_coin_rolling_on_a_plane_stays_nonholonomic() -> None:
    from lagrangian.dynamics._constraints import describe_constraints

    (info,) = describe_constraints(eom_of("rolling_coin.toml"))
    assert (info.kind, info.integrals) == ("nonholonomic", ())


@pytest.mark.parametrize(("relation", "integral"), [
    ("x_dot - l*cos(t)", S("x") - S("l") * se.sin(S("t"))),                      # b = ∂φ/∂t
    ("x*x_dot + y*y_dot", (S("x") ** 2 + S("y") ** 2) / 2),                        # ∂a_x/∂y = ∂a_y/∂x
    ("x*x_dot - x^2*y_dot", se.log(S("x")) - S("y")),                              # exact once divided by −x²
])
def test_declared_velocity_rows_that_integrate_are_holonomic(relation, integral) -> None:
    from lagrangian.dynamics._constraints import describe_constraints

    (info,) = describe_constraints(derive_text(PENDULUM + f'c = {{ nonholonomic = "{relation}" }}\n'))
    assert info.kind == "holonomic"
    (phi,) = info.integrals
    assert is_zero(phi - integral) or is_zero(phi + integral)


def test_an_integrable_row_without_a_closed_form_is_still_holonomic() -> None:
    from lagrangian.dynamics._constraints import describe_constraints

    # y ẋ − x ẏ = 0: y/x = cste (factor 1/x², not among those tried); Frobenius decides.
    (info,) = describe_constraints(derive_text(PENDULUM + 'c = { nonholonomic = "y*x_dot - x*y_dot" }\n'))
    assert (info.kind, info.integrals) == ("holonomic", ())


def test_rows_undefined_at_the_random_state_are_taken_as_declared():
    # A coefficient that is nan at the random state (NumPy's SVD fails on it) does not decide the rank.
    import numpy as np

    from lagrangian.dynamics._constraints import _rank

    assert _rank(np.array([[np.nan, 1.0], [0.0, 1.0]])) == 2
    assert _rank(np.array([[1.0, 1.0], [2.0, 2.0]])) == 1


def test_a_rotation_by_abs_psi_derives(tmp_path):
    # tools/fuzz.py seed 107, case 16912: top_reaction's R1 turned by |ψ|.  SymEngine leaves d|ψ|/dψ
    # unevaluated and will not substitute a number into it (RuntimeError in the rank test of the ball
    # joint's rows); the rows are taken as declared, and the derivation goes on to the 3 multipliers.
    path = mutated_example(tmp_path, "top_reaction.toml", 'rotation = ["psi", "z"]', 'rotation = ["abs(psi)", "z"]')
    eom = lagrangian.derive(lagrangian.load_model(path))
    assert len([r for r in eom.constraints if r.constraint == "pivot"]) == 3
