"""Step 1: the principal constraints read back from the parameterization of each model.

Each expectation is the physics of the example (its file's header says which constraints
it has): the top's fixed point, the double pendulum's two hinges, the cart's rail and rod...
and the count 6 N_S + 3 N_P − (equations) = n of the course.
"""

from __future__ import annotations

import pytest
import symengine as se
from lagrangian_test_support import eom_of, plain

import lagrangian
from lagrangian.model.zoo import planar_chain
from lagrangian.output._report.joints import degrees_of_freedom, joints


def _summary(name: str) -> list[tuple]:
    return [(j.kind, j.element, j.support, j.point, j.axis, j.normals, j.equations, j.time_dependent)
            for j in joints(eom_of(name))]


def test_the_top_has_the_fixed_point_O():
    assert _summary("lagrange_top.toml") == [("fixed point", "S", None, "O", None, (), 3, False)]
    assert degrees_of_freedom(eom_of("lagrange_top.toml"), joints(eom_of("lagrange_top.toml"))) == (6, 3, 3)


def test_the_double_pendulum_has_two_hinges_about_x0():
    eom = eom_of("double_pendulum.toml")
    assert _summary("double_pendulum.toml") == [("pivot", "S1", None, "O", "x0", (), 5, False),
                                                ("pivot", "S2", "S1", "A", "x0", (), 5, False)]
    second = joints(eom)[1]
    # Its virtual rotation relative to S1 is θ2* x0.
    assert second.rotation == lagrangian.model.Vector({"R2": (se.Symbol("theta2_star"), 0, 0)})
    assert degrees_of_freedom(eom, joints(eom)) == (12, 10, 2)


def test_pendulums_hang_from_rods():
    (simple,) = joints(eom_of("simple_pendulum.toml"))
    assert (simple.kind, simple.point, simple.normals, simple.length) == ("rod", "O", ("x0",), se.Symbol("l"))
    (spherical,) = joints(eom_of("spherical_pendulum.toml"))
    assert (spherical.kind, spherical.normals, spherical.equations) == ("rod", (), 1)


def test_the_cart_slides_on_its_rail_and_carries_the_pendulum():
    assert _summary("cart_pendulum.toml") == [("line", "C", None, "O", "x0", ("y0", "z0"), 2, False),
                                              ("rod", "P", "C", "C", None, ("y0",), 2, False)]


def test_a_prescribed_pivot_makes_the_constraint_time_dependent():
    (kapitza,) = joints(eom_of("kapitza_pendulum.toml"))
    assert (kapitza.kind, kapitza.point, kapitza.time_dependent) == ("rod", "A", True)


def test_constraints_are_stated_in_the_frame_of_the_equations():
    # The Foucault pendulum is written relative to the Earth frame E: its rod does not move with t there.
    (rod,) = joints(eom_of("foucault_pendulum.toml"))
    assert (rod.kind, rod.time_dependent) == ("rod", False)


def test_a_free_body_has_no_placement_constraint():
    # top_reaction keeps six coordinates for S: only its declared (complementary) constraint remains.
    assert joints(eom_of("top_reaction.toml")) == ()


def test_a_chain_hangs_link_by_link():
    eom = lagrangian.derive(planar_chain(5))
    found = joints(eom)
    assert [(j.kind, j.support, j.point, j.normals) for j in found] == \
        [("rod", None, "O", ("z0",))] + [("rod", f"P{k}", f"P{k}", ("z0",)) for k in range(1, 5)]
    assert [j.length for j in found] == [se.Symbol(f"l{k}") for k in range(1, 6)]
    assert degrees_of_freedom(eom, found) == (15, 10, 5)


@pytest.mark.parametrize("name", ["lagrange_top.toml", "double_pendulum.toml", "cart_pendulum.toml",
                                  "simple_pendulum.toml", "spherical_pendulum.toml"])
def test_every_constraint_is_holonomic_principal_and_perfect(name):
    for j in joints(eom_of(name)):
        assert j.holonomic and j.principal and j.perfect


# -- audit fixes: each test fails on the report as it was before them -------------------------------
from lagrangian_test_support import eom_of as _eom_of  # noqa: E402
from lagrangian_test_support import example_names as _example_names

from lagrangian.output import report as _report  # noqa: E402
from lagrangian.output._report.document import Display as _Display  # noqa: E402
from lagrangian.output._report.document import Items as _Items
from lagrangian.output._report.document import Para as _Para
from lagrangian.output._report.document import Table as _Table  # noqa: E402
from lagrangian.output._report.document import walk as _walk  # noqa: E402


def _section(r, key: str) -> str:  # type: ignore[no-untyped-def]
    """A section's words and mathematics, the displayed equations joined back into one line each."""
    out = []
    for b in _walk(r.document.section(key).blocks):
        if isinstance(b, _Para):
            out.append("".join(x if isinstance(x, str) else f"${x.latex}$" for x in b.runs))
        elif isinstance(b, _Items):
            out += ["".join(x if isinstance(x, str) else f"${x.latex}$" for x in item) for item in b.items]
        elif isinstance(b, _Display):
            out += [" ".join(eq.lines) for eq in b.equations]
        elif isinstance(b, _Table):
            out += [" | ".join("".join(x if isinstance(x, str) else f"${x.latex}$" for x in cell) for cell in row)
                    for row in (b.header, *b.rows)]
    return plain("\n".join(out))


def _all(r) -> str:  # type: ignore[no-untyped-def]
    return plain("\n".join(s.title + "\n" + _section(r, s.key) for s in r.document.sections))


def test_friction_at_a_contact_makes_it_not_perfect():
    step1 = _section(_report(_eom_of("block_on_belt.toml")), "step1")
    assert "n'est pas parfaite" in step1 and "frottement de Coulomb" in step1
    assert "Elle est parfaite" not in step1


def test_a_rolling_coin_names_its_principal_constraint_and_why_rolling_is_perfect():
    step1 = _section(_report(_eom_of("rolling_coin.toml")), "step1")
    assert "en fonction des paramètres principaux" not in step1
    assert r"\overrightarrow{OG}\cdot\vec{z}_{0} = r" in step1
    assert r"\vec{V}^{*}(I\in S) = \vec{0}" in step1
    assert "Le roulement" not in step1  # « la liaison de roulement … Elle est » agrees in gender


def test_the_top_writes_the_seeds_fixed_point_equations():
    step1 = _section(_report(lagrangian.lagrange_top()), "step1")
    assert "x = y = z = 0" in step1


def test_coriolis_on_the_hoop_is_orthogonal_and_q_notation_is_per_load():
    step5 = _section(_report(_eom_of("bead_rotating_hoop.toml")), "step5")
    assert "se compensent" not in step5
    assert r"Q_{\theta}(\text{Coriolis}) = 0$ car la force est orthogonale" in step5
    top5 = _section(_report(lagrangian.lagrange_top()), "step5")
    assert r"Q_{\theta}(\text{poids}) = m g a \sin\theta" in top5
    assert r"Q_{\psi,\,\mathrm{nc}} = Q_{\theta,\,\mathrm{nc}} = Q_{\varphi,\,\mathrm{nc}} = 0" in top5


@pytest.mark.slow
def test_multiplier_coefficients_are_defined_and_do_not_clash_with_inertia():
    r = _report(_eom_of("top_reaction.toml"))
    text = _all(r)
    assert "A_{k" not in text
    assert r"a_{k,i}" in _section(r, "step6") and "multiplicateur de la liaison complémentaire k" in text


@pytest.mark.slow
def test_step_7_gives_the_multiplier_and_the_rods_tension():
    step7 = _section(_report(_eom_of("pendulum_tension.toml")), "step7")
    assert "\n\\lambda = \\frac{" in step7  # one multiplier: λ, not the engine's lambda_length
    assert r"N = m \left(g \cos\theta + l \dot{\theta}^{2}\right)" in step7


def test_jacobi_integral_is_stated_right_and_the_energy_balance_when_none():
    hoop = _section(_report(_eom_of("bead_rotating_hoop.toml")), "integrals")
    assert "pas homogène" not in hoop and "T_2 - T_0" not in hoop
    assert r"h = T(\Sigma/R_{1}) + U_P(\Sigma/R_{1})" in hoop
    belt = _section(_report(_eom_of("block_on_belt.toml")), "integrals")
    assert r"\frac{dE}{dt} = P(\text{frottement})" in belt


@pytest.mark.slow
def test_newton_euler_states_the_theorems_it_projects():
    top = _report(lagrangian.lagrange_top(), verification=True)
    check = _section(top, "check")
    assert r"\overrightarrow{OG}\wedge\vec{P} + \overrightarrow{OO}\wedge\vec{R}_{O}" in check
    assert r"\overrightarrow{OO}\wedge\vec{R}_{O} = \vec{0}" in check
    assert (top.document.section("check").title + check).count("Remarque 4") == 1
    double = _section(_report(_eom_of("double_pendulum.toml"), verification=True), "check")
    assert "en $G_{S_{2}}$" not in double and "Théorème du moment dynamique en $A$" in double
    coin = _section(_report(_eom_of("rolling_coin.toml"), verification=True), "check")
    assert "Théorème de la résultante dynamique" in coin and "Théorème du moment dynamique en $I$" in coin
    assert "Les liaisons étant parfaites" not in coin
    foucault = _section(_report(_eom_of("foucault_pendulum.toml"), verification=True), "check")
    assert "R_{0})" not in foucault


#: English words that must not appear in the French report (load names and terms), and French ones in English.
ENGLISH = ("weight", "entrainment", "given effort", "constraint “", " the ", "Remark")
FRENCH = ("Remarque", "poids", "liaison", "équation", "effort", "entraînement", "théorème", " et ")


@pytest.mark.slow
@pytest.mark.parametrize("name", _example_names())
def test_no_english_in_french_and_no_french_in_english(name):
    eom = _eom_of(name)
    fr = _all(_report(eom, lang="fr"))
    en = _all(_report(eom, lang="en")).replace(" et al.", " al.")  # a citation (Meijaard et al.) is not French
    for word in ENGLISH:
        assert word not in fr, (name, word)
    for word in FRENCH:
        assert word not in en, (name, word)
    assert "e-0" not in fr and "e-0" not in en  # 5·10⁻⁵, not 5e-05
    _constraints_named_in_the_reports_language(eom, {"fr": fr, "en": en})


def _constraints_named_in_the_reports_language(eom, texts):  # type: ignore[no-untyped-def]
    """A declared constraint is named in prose by its description in the report's language, never by its
    identifier (« length », “rolling”, \\text{length}, λ_length): those stay in the JSON and the command line.
    Its multiplier is λ when it is the only one, else λ_1 … λ_k with a table that says which constraint
    each one belongs to; another letter when the model already writes one of its symbols λ (the bicycle)."""
    from lagrangian.model._texts import in_language
    from lagrangian.output._report.build import tex_text

    rows = eom.constraints
    own = {p.name for p in eom.model.parameters} | set(eom.coordinates)
    letter = r"\mu" if own & {"lam", "lambda"} else r"\lambda"
    for lang, text in texts.items():
        other = "en" if lang == "fr" else "fr"
        for con in eom.model.constraints:
            for quoted in (f"« {con.name} »", f"“{con.name}”", tex_text(con.name), rf"\mathrm{{{con.name.split('_')[0]}}}"):
                assert quoted not in text, (lang, quoted)
            if "_" in con.name:
                assert con.name not in text and con.name.replace("_", r"\_") not in text, (lang, con.name)
            assert in_language(con.description, lang) in text, (lang, con.name)
            if in_language(con.description, other) != in_language(con.description, lang):
                assert in_language(con.description, other) not in text, (lang, con.name)
        assert r"\lambda_{\mathrm" not in text
        if len(rows) == 1:
            assert rf"2 x {letter}" in text if eom.model.name.startswith("Pendulum") else rf"{letter}\," in text
            assert rf"{letter}_{{1}}" not in text
        elif rows:
            numbered = ("numérotés dans l'ordre des liaisons du modèle" if lang == "fr"
                        else "numbered in the order of the model's constraints")
            assert numbered in text
            for k in range(1, len(rows) + 1):
                assert rf"{letter}_{{{k}}}" in text, (lang, k)
            assert rf"{letter}_{{{len(rows) + 1}}}" not in text


# -- degrees of freedom, planar motion, the multiplier's derivation ---------------------
#: Degrees of freedom counted by hand from each statement (independent velocities): the rod of
#: `pendulum_tension` leaves one of x, y; the coin's two rolling rows leave ψ̇ and φ̇; the disk rolls
#: (x = r φ); the top's pivot (3 rows) leaves ψ, θ, φ; the bicycle's five rows leave lean, steer and
#: the rear wheel's rate.
DOF = {"pendulum_tension.toml": (2, 1, 0, 1), "rolling_coin.toml": (4, 0, 2, 2),
       "rolling_disk_incline.toml": (2, 1, 0, 1), "top_reaction.toml": (6, 3, 0, 3),
       "whipple_bicycle.toml": (8, 1, 4, 3), "lagrange_top.toml": (3, 0, 0, 3), "double_pendulum.toml": (2, 0, 0, 2)}
#: The plane of the motion when it is planar by construction (None: it is not).
PLANE = {"pendulum_tension.toml": r"(O;\,\vec{x}_{0},\,\vec{y}_{0})", "double_pendulum.toml": r"(O;\,\vec{y}_{0},\,\vec{z}_{0})",
         "rolling_disk_incline.toml": r"(O;\,\vec{x}_{0},\,\vec{z}_{0})", "lagrange_top.toml": None,
         "rolling_coin.toml": None, "top_reaction.toml": None, "whipple_bicycle.toml": None}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(DOF))
def test_step1_counts_the_degrees_of_freedom_and_says_when_the_motion_is_planar(name):
    n, h, k, dof = DOF[name]
    assert n - h - k == dof
    eom = _eom_of(name)
    for lang, word in (("fr", "Degrés de liberté"), ("en", "Degrees of freedom")):
        step1 = _section(_report(eom, lang=lang), "step1")
        assert "Bilan des degrés" not in step1 and "(6 per rigid body, 3 per particle, less one" not in step1
        if k:
            assert f"{word} : " in step1 or f"{word}: " in step1
            assert f"n - h - k = {n} - {h} - {k} = {dof}" in step1
        elif h:
            assert f"n - h = {n} - {h} = {dof}" in step1
        else:
            assert f"n = {n}" in step1
        # Only nonholonomic rows leave more independent positions (n − h) than speeds (n − h − k).
        only_speeds = "ne restreignent que les vitesses" if lang == "fr" else "restrict only the velocities"
        assert (only_speeds in step1) == bool(k)
        if k:
            assert f"n - h = {n - h}" in step1 and f"n - h - k = {dof}" in step1
        plane = PLANE[name]
        planar = "plan par construction" if lang == "fr" else "planar by construction"
        assert (planar in step1) == (plane is not None)
        if plane is not None:
            assert plane in step1


@pytest.mark.slow
def test_a_holonomic_multiplier_comes_from_the_constraint_differentiated_twice():
    eom = _eom_of("pendulum_tension.toml")
    assert "dérivée deux fois par rapport au temps" in _section(_report(eom, lang="fr"), "step7")
    assert "differentiated twice with respect to time" in _section(_report(eom, lang="en"), "step7")


def test_the_jacobi_integral_of_the_hoop_has_one_definition():
    # In R1 the bead's T(Σ/R1) = ½ m R² θ̇² is T_2 and U_P(Σ/R1) already holds the centrifugal potential
    # −½ m R² Ω² sin²θ: h = T(Σ/R1) + U_P(Σ/R1), written the same way wherever the report names it.
    eom = _eom_of("bead_rotating_hoop.toml")
    for lang in ("fr", "en"):
        text = _all(_report(eom, lang=lang))
        assert "T_0" not in text and "T_2 - T_0" not in text
        assert text.count(r"h = T(\Sigma/R_{1}) + U_P(\Sigma/R_{1})") >= 2


@pytest.mark.slow
def test_the_moment_theorem_at_a_moving_point_keeps_its_extra_term():
    # δ_A = d/dt[σ_A] + m V(A) ∧ V(G) at a moving point A.  The double pendulum's joint A: by hand, with
    # V(A) = l1 θ̇1 t1 and V(G2) = V(A) + ½ l2 (θ̇1 + θ̇2) t2 (t_k ⟂ rod k, θ2 relative), V(A) ∧ V(G2) has the
    # magnitude ½ l1 l2 θ̇1 (θ̇1 + θ̇2) |sin θ2|, not zero: the term must be written.  The coin's contact
    # point I moves with G (V(I) = V(G) = ẋ x0 + ẏ y0): the term vanishes, and the report says why.
    l1, l2, th2, w1, w2 = 1.0, 0.8, 0.5, 1.0, 2.0
    assert 0.5 * l1 * l2 * w1 * (w1 + w2) * abs(__import__("math").sin(th2)) > 0.1
    double = _section(_report(_eom_of("double_pendulum.toml"), verification=True), "check")
    assert r"\frac{d}{dt}\left[\vec{\sigma}_{A}(S_{2}/R_{0})\right]_{R_{0}} + m_{2}\,\vec{V}(A/R_{0})\wedge\vec{V}(G_{S_{2}}/R_{0})" in double
    coin = _section(_report(_eom_of("rolling_coin.toml"), verification=True), "check")
    assert r"m\,\vec{V}(I/R_{0})\wedge\vec{V}(G/R_{0}) = \vec{0}" in coin
    top = _section(_report(_eom_of("lagrange_top.toml"), verification=True), "check")
    assert "mobile" not in top


def test_values_of_the_integrals_carry_their_units_and_minus_signs():
    # The simple pendulum at rest at θ0: E = −m g l cos θ0 (J, negative: a minus sign,
    # U+2212, not a hyphen); the top's K and H are angular momenta (J·s), its E an energy (J); the coin's
    # φ̇ is a speed (rad/s).  The values are recomputed here from the model files' numbers.
    import math

    import tomllib
    from lagrangian_test_support import EXAMPLES_DIR

    data = tomllib.loads((EXAMPLES_DIR / "simple_pendulum.toml").read_text(encoding="utf-8"))
    value = {k: (v["value"] if isinstance(v, dict) else v) for k, v in data["parameters"].items()}
    theta0 = data["coordinates"]["theta"]["initial"]
    rate0 = data["coordinates"]["theta"].get("rate", 0.0)
    m, g, l = value["m"], value["g"], value["l"]
    E = 0.5 * m * l**2 * rate0**2 - m * g * l * math.cos(theta0)
    fr = _all(_report(_eom_of("simple_pendulum.toml"), lang="fr"))
    en = _all(_report(_eom_of("simple_pendulum.toml"), lang="en"))
    # 4 significant digits for a value computed from the model's; the unit after a narrow space (`plain` reads
    # it as a space; test_report_typography checks the character)
    assert f"≈ \u2212{abs(E):.4g}".replace(".", ",") + " J" in fr
    assert f"≈ \u2212{abs(E):.4g} J" in en
    top = _all(_report(_eom_of("lagrange_top.toml"), lang="en"))
    assert top.count(" J·s with the model's initial values") == 2 and " J with the model's" in top
    coin = _all(_report(_eom_of("rolling_coin.toml"), lang="en"))
    assert "≈ 10 rad/s" in coin


@pytest.mark.slow
def test_a_constant_speed_and_a_symmetry_integral_are_not_called_jacobi_integrals():
    """The coin's φ̇ = cste (its reduced equations) and a top's σ_O·z0 were printed as « h = T + U_P = φ̇ »,
    the Painlevé–Jacobi integral of a moving frame.  φ̇ = cste is checked here on the textbook coin: T =
    ½ m (ẋ² + ẏ²) + ⅛ m r² ψ̇² + ¼ m r² φ̇², ẋ = r φ̇ cos ψ, ẏ = r φ̇ sin ψ (Lagrange–d'Alembert) gives φ̈ = 0."""
    import sympy

    m, r, t = sympy.symbols("m r t", positive=True)
    x, y, psi, phi = (sympy.Function(n)(t) for n in ("x", "y", "psi", "phi"))
    l1, l2 = sympy.symbols("lambda1 lambda2")
    # m ẍ = λ1, m ÿ = λ2, ½ m r² φ̈ = −r (λ1 cos ψ + λ2 sin ψ), with the rolling rows differentiated once.
    xdd = sympy.diff(r * phi.diff(t) * sympy.cos(psi), t)
    ydd = sympy.diff(r * phi.diff(t) * sympy.sin(psi), t)
    lam = {l1: m * xdd, l2: m * ydd}
    eq = sympy.Rational(1, 2) * m * r**2 * phi.diff(t, 2) + r * (l1 * sympy.cos(psi) + l2 * sympy.sin(psi))
    phidd = sympy.solve(sympy.simplify(eq.subs(lam)), phi.diff(t, 2))
    assert phidd == [0]
    for lang, cste in (("fr", "cste"), ("en", "const")):
        coin = _section(_report(_eom_of("rolling_coin.toml"), lang=lang), "integrals")
        assert rf"\dot{{\varphi}} = \text{{{cste}}}" in coin and r"h = " not in coin and "Painlev" not in coin
        for name in ("sleeping_top.toml", "top_reaction.toml"):
            top = _section(_report(_eom_of(name), lang=lang), "integrals")
            assert r"= \sigma_{O,z_{0}}" in top and "h = " not in top and "Noether" in top


@pytest.mark.slow
def test_a_constraint_without_description_is_named_by_its_rank_not_its_identifier():
    """A model file may give no description: the prose then says « la liaison 1 » / "constraint 1", never the
    identifier (here `rod_len`, which stays in the JSON)."""
    from lagrangian_test_support import EXAMPLES_DIR

    import lagrangian
    from lagrangian.model._toml import parse_model

    text = (EXAMPLES_DIR / "pendulum_tension.toml").read_text(encoding="utf-8")
    head, _, _ = text.partition("[constraints]")
    text = head + '[constraints]\nrod_len = { holonomic = "x^2 + y^2 - l^2", reaction = { force_at = "P", frame = "R0" } }\n'
    eom = lagrangian.derive(parse_model(text))
    for lang, label in (("fr", "La liaison 1"), ("en", "Constraint 1")):
        whole = _all(_report(eom, lang=lang))
        assert "rod_len" not in whole and r"rod\_len" not in whole and r"\mathrm{rod}" not in whole
        assert label in whole


def test_the_pendulums_multiplier_is_written_on_the_constraint():
    # λ is printed with x² + y² replaced by l² (the constraint holds all along the motion); on the circle
    # x = l sin θ, y = −l cos θ it is −N/(2l) with the rod's tension N = m (g cos θ + l θ̇²), the closed
    # form of the simple pendulum (R = 2λ OP, N = −R·OP/l).
    import sympy

    from lagrangian.output._report.build import Context
    from lagrangian.output._report.steps.equations import _multipliers, _on_the_constraints, _simple

    eom = eom_of("pendulum_tension.toml")
    c = Context(eom, (), "en")
    (shown,) = _on_the_constraints(c, [_simple(c, f) for f in _multipliers(c)])
    names = {s.name: s for s in shown.free_symbols}
    assert "l" in names and not {"x"} & set(names)  # the denominator is 2 l², not 2 (x² + y²)
    m, g, l, th, w = sympy.symbols("m g l theta omega")
    on_circle = shown.subs({names["y"]: -l * sympy.cos(th), names["x_dot"]: l * w * sympy.cos(th),
                            names["y_dot"]: l * w * sympy.sin(th), names["m"]: m, names["g"]: g, names["l"]: l})
    assert sympy.simplify(on_circle + m * (g * sympy.cos(th) + l * w**2) / (2 * l)) == 0
