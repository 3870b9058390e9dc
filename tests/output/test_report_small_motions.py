"""The report's opt-in section "Petits mouvements au voisinage d'une position d'équilibre".

Checked against closed forms written here: the simple pendulum's ω0² = g/l (and its value
√(g/l) with the model's numbers), the bead on the hoop's δθ̈ = (Ω² − g/R) δθ, unstable at
the bottom when Ω² > g/R; and the section renders in every format and both languages, while
a report that does not ask for it is unchanged.
"""

from __future__ import annotations

import math

import pytest
import sympy
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.cli.main import main
from lagrangian.output import course_form, report
from lagrangian.output._report.document import Display, Para, math_of, walk
from lagrangian.output._report.words import Words
from lagrangian.output._text import notation

TITLES = {"fr": "Petits mouvements au voisinage d\u2019une position d\u2019équilibre",
          "en": "Small motions about an equilibrium"}


def _pendulum():
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "simple_pendulum.toml"))


@pytest.mark.parametrize("lang", ["fr", "en"])
def test_simple_pendulum_pulsation_is_g_over_l_in_every_format(lang):
    eom = _pendulum()
    r = report(eom, lang=lang, small_motions={"theta": 0})
    section = r.document.section("small motions")
    assert section.title == TITLES[lang]
    # ω0² = g/l, written by the report's notation from the closed form.
    n = notation(course_form(eom, lagrangian.first_integrals(eom)))
    g, l = sympy.symbols("g l")
    maths = math_of(section.blocks)
    assert rf"\omega_{{0}}^{{2}} = {n.latex(g / l)}" in maths
    # The linearized equation m l² δθ̈ + m g l δθ = 0 (the report orders the factors its own way).
    eq = next(line for b in walk(section.blocks) if isinstance(b, Display) for e in b.equations for line in e.lines)
    lhs = eq.replace(r"\,", " ")
    assert r"\delta \ddot{\theta}" in lhs and r"\delta \theta" in lhs and lhs.endswith("= 0")
    # The value √(g/l) with the model's g = 9.81, l = 0.5, and the period 2π/ω0, as the language writes numbers.
    w = Words(lang)
    omega = math.sqrt(9.81 / 0.5)
    assert any(w.number(omega) in m for m in maths) and any(w.number(2 * math.pi / omega) in m for m in maths)
    # The stability argument: Lagrange–Dirichlet.
    text = " ".join(x for b in section.blocks if isinstance(b, Para) for x in b.runs if isinstance(x, str))
    assert "Lagrange–Dirichlet" in text
    for fmt in ("md", "html", "tex"):
        out = r.render(fmt)
        assert TITLES[lang] in out or TITLES[lang].replace("'", "&#x27;") in out
    assert r"\begin{pmatrix}" not in r.markdown()  # one coordinate: no 1 × 1 matrices


def test_the_bead_at_the_bottom_of_a_fast_hoop_is_unstable():
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bead_rotating_hoop.toml"))
    section = report(eom, lang="en", small_motions={"theta": 0}).document.section("small motions")
    maths = " ".join(math_of(section.blocks))
    # m R² δθ̈ + m R (g − R Ω²) δθ = 0: the stiffness changes sign at Ω² = g/R (here 36 > 19.62).
    assert r"\Omega^{2}" in maths
    text = " ".join(x for b in section.blocks if isinstance(b, Para) for x in b.runs if isinstance(x, str))
    assert "unstable" in text and "no minimum" in text
    w = Words("en")
    assert w.number(math.sqrt(6.0**2 - 9.81 / 0.5)) in maths


@pytest.mark.slow
def test_a_point_that_holds_for_the_given_values_only_is_written_in_closed_form():
    # cos θ0 = g/(R Ω²) is an equilibrium for the model's numbers, not for every g, R, Ω; it exists iff R Ω² > g.
    # By hand: m R² δθ̈ = (m R² Ω² cos 2θ0 − m g R cos θ0) δθ, and with g = R Ω² cos θ0 the stiffness is
    # m R² Ω² (cos²θ0 − cos 2θ0) = m R² Ω² sin²θ0: ω0² = Ω² sin²θ0 (5.0306 rad/s with the model's numbers).
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bead_rotating_hoop.toml"))
    theta0 = math.acos(9.81 / (0.5 * 36.0))
    section = report(eom, lang="fr", small_motions={"theta": theta0}).document.section("small motions")
    assert not [b for b in section.blocks if isinstance(b, Para) and b.style == "note"]  # letters, not numbers
    maths = math_of(section.blocks)
    assert r"\cos\theta_{0} = \frac{g}{R \Omega^{2}}" in maths and r"R \Omega^{2} > g" in maths
    assert r"\omega_{0}^{2} = \Omega^{2} \sin^{2}\theta_{0}" in maths
    w = Words("fr")
    assert any(w.number(6.0 * math.sin(theta0)) in m for m in maths)  # ω0 = Ω sin θ0, numerically
    assert any(r"\mathrm{s^{-1}}" in m for m in maths)  # the eigenvalues of A carry their unit


def test_without_the_option_the_report_has_no_such_section():
    r = report(_pendulum(), lang="fr")
    assert all(s.key != "small motions" for s in r.document.sections)


def test_cli_report_small_motions(tmp_path, capsys):
    out = tmp_path / "pendulum.md"
    assert main(["report", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--small-motions", "--at", "theta=0",
                 "--no-verify", "-o", str(out)]) == 0
    assert TITLES["fr"] in out.read_text()
    assert main(["report", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--at", "theta=0"]) == 2
    assert "--small-motions" in capsys.readouterr().err
    assert main(["report", str(EXAMPLES_DIR / "double_pendulum.toml"), "--small-motions", "--at", "theta1=0"]) == 2
    assert "`theta2`" in capsys.readouterr().err


def test_steady_precession_sets_the_neutral_directions_aside_and_gives_the_nutation():
    # ω3 = (A ψ̇² cosθ0 + m g a)/(C ψ̇) makes θ0 = 0.5, ψ̇ = 2 a steady precession (the θ equation at rest in θ).
    top = lagrangian.lagrange_top()
    v = dict(top.parameter_values)
    theta0, psi_dot = 0.5, 2.0
    omega3 = (v["A"] * psi_dot**2 * math.cos(theta0) + v["m"] * v["g"] * v["a"]) / (v["C"] * psi_dot)
    point = {"psi": 0, "theta": theta0, "phi": 0, "psi_dot": psi_dot, "phi_dot": omega3 - psi_dot * math.cos(theta0)}
    section = report(lagrangian.derive(top), lang="en", small_motions=point).document.section("small motions")
    assert section.title == "Small motions about a steady motion"
    text = " ".join(x for b in section.blocks if isinstance(b, Para) for x in b.runs if isinstance(x, str))
    assert "set aside" in text and "2 conserved momenta" in text and "Routh" in text
    assert r"\psi" in " ".join(math_of(section.blocks))


def test_a_symbolic_linearization_is_reported_with_the_models_values(tmp_path):
    eom = _pendulum()
    lin = lagrangian.linearize(eom, {"theta": 0}, symbolic=("g",))
    maths = math_of(report(eom, lang="en", small_motions=lin).document.section("small motions").blocks)
    assert any(Words("en").number(math.sqrt(9.81 / 0.5)) in m for m in maths)
    # A parameter with no value at all: the equations are written, the numbers are not.
    model = tmp_path / "pendulum.toml"
    model.write_text((EXAMPLES_DIR / "simple_pendulum.toml").read_text().replace("l = { value = 0.5, ", "l = { "))
    section = report(lagrangian.load_model(model), lang="fr", small_motions={"theta": 0}).document.section(
        "small motions")
    text = " ".join(x for b in section.blocks if isinstance(b, Para) for x in b.runs if isinstance(x, str))
    assert "demandent une valeur pour" in text and "Lagrange–Dirichlet" not in text
