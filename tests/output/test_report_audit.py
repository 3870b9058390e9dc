"""The report's wording, checked against the course: points an audit of the reports raised.

Each test names the model of ``examples/`` it reads and the sentence or formula it pins.
"""

from __future__ import annotations

import re
from functools import cache

import pytest
from lagrangian_test_support import EXAMPLES_DIR, plain

from lagrangian.output import report


@cache
def _md(name: str, lang: str = "fr") -> str:
    return plain(report(EXAMPLES_DIR / f"{name}.toml", lang=lang).markdown())


def _section(text: str, title: str) -> str:
    """The Markdown of the section whose heading starts with ``title``."""
    start = text.index(f"## {title}")
    end = text.find("\n## ", start + 3)
    return text[start:end if end >= 0 else len(text)]


@pytest.mark.slow
def test_the_matrix_form_keeps_the_multipliers():
    """pendulum_tension: step 6 has m ẍ = 2xλ, so the appendix cannot say M q̈ = F with F_x = 0 alone."""
    for name in ("pendulum_tension", "rolling_coin"):
        for lang, title in (("fr", "Annexe : forme matricielle"), ("en", "Appendix: matrix form")):
            appendix = _section(_md(name, lang), title)
            assert r"A^{\mathsf{T}}\lambda" in appendix
    appendix = _section(_md("pendulum_tension"), "Annexe")
    # One multiplier: λ a_x (a teacher writes Σ_k λ_k a_{k,x} only when there are several).
    assert r"\left(A^{\mathsf{T}}\lambda\right)_{x} = \lambda\, a_{x} = 2 x \lambda" in appendix
    coin = _section(_md("rolling_coin"), "Annexe")
    assert r"\left(A^{\mathsf{T}}\lambda\right)_{x} = \sum_{k} \lambda_{k}\, a_{k,x} = \lambda_{1} \cos\psi" in coin
    # Without complementary constraints the form stays M q̈ = F.
    assert r"A^{\mathsf{T}}" not in _section(_md("simple_pendulum"), "Annexe")


def test_the_total_potential_is_named_u_p_of_the_system():
    """bead_rotating_hoop printed the total under the last load's name, U_P(entraînement), twice."""
    step4 = _section(_md("bead_rotating_hoop"), "4.")
    assert step4.count(r"U_P(\text{entraînement}) =") == 1
    assert r"U_P(\Sigma/R_{1}) = -\frac{1}{2} m R^{2} \Omega^{2} \sin^{2}\theta - m R g \cos\theta" in step4
    # block_on_belt: the weight's U_P is 0, so the spring's is the only term: no total repeating it.
    step4 = _section(_md("block_on_belt", "en"), "4.")
    assert step4.count(r"\frac{1}{2} k x^{2}") == 1
    assert r"U_P(\Sigma" not in step4


@pytest.mark.slow
def test_a_prescribed_motion_keeps_remark_2_and_names_each_power_by_its_value():
    """Kapitza: L = T − U_P still holds (Remarque 2), but ∂L/∂t ≠ 0, so the energy is no integral; the balance
    is −∂L/∂t + d/dt(T₁ + 2T₀), not a ∂U_P/∂t plus a 'prescribed motion' power that was neither."""
    fr = _md("kapitza_pendulum")
    step6 = _section(fr, "6.")
    assert "conservatif par rapport à" in step6
    assert "dépend explicitement de $`t`$" in step6 and "n'est pas une intégrale première" in step6
    balance = _section(fr, "Intégrales premières")
    assert r"\frac{dE}{dt} = -\frac{\partial L}{\partial t} + \frac{d}{dt}\left(T_1 + 2\,T_0\right)" in balance
    assert "mouvement imposé" not in balance and r"\frac{\partial U_P}{\partial t} =" not in balance
    assert "Painlevé" in balance
    assert "depends on $`t`$ explicitly" in _section(_md("kapitza_pendulum", "en"), "6.")
    # A scleronomic conservative system says nothing of the kind.
    assert "dépend explicitement de $`t`$" not in _md("simple_pendulum")


@pytest.mark.slow
def test_coriolis_forces_do_no_power_and_leave_the_jacobi_integral():
    """bead_rotating_hoop / foucault_pendulum: not 'the system is not conservative' then a Jacobi integral."""
    bead, foucault = _md("bead_rotating_hoop"), _md("foucault_pendulum")
    for text in (bead, foucault):
        step6 = _section(text, "6.")
        assert "Le système n'est pas conservatif" not in step6
        # One definition of h: T(Σ/R) = T_2 there, U_P(Σ/R) holds the entrainment potential.
        assert "aucune puissance réelle" in step6 and re.search(r"h = T\(\\Sigma/([^)]+)\) \+ U_P\(\\Sigma/\1\)", step6)
        # h is written as the integrals section defines it: with T_2 − T_0 only where T(Σ/R) has a T_0 part.
        assert ("T_0" in step6) == ("T_2 - T_0" in _section(text, "Intégrales premières"))
        assert "l'intégrale première de l'énergie" not in _section(text, "Intégrales premières")
    assert r"Q_i(\text{Coriolis}) = 0" in _section(bead, "6.")
    assert r"\sum_{i} Q_i(\text{Coriolis})\,\dot{q}_i = 0" in _section(foucault, "6.")
    assert "remplacée par l'intégrale de Jacobi h" in bead
    assert "L'intégrale de Jacobi h peut remplacer l'une des équations $`L(\\alpha)`$ ou $`L(\\beta)`$" in foucault
    assert r"E = T(\Sigma/R_{0}) + U_P(\Sigma/R_{0})" in bead
    assert "do no work (their real power is zero)" in _md("bead_rotating_hoop", "en")
    # The entrainment potential is written for this model, its symbols defined.
    step4 = _section(bead, "4.")
    assert r"\vec{\Omega}(R_{1}/R_{0})\cdot\Pi_{O}(\Sigma)\cdot\vec{\Omega}(R_{1}/R_{0})" in step4
    assert "O'" not in step4 and "l'opérateur d'inertie de (Σ) en $`O`$" in step4


@pytest.mark.slow
def test_an_energy_integral_may_replace_one_equation_or_another():
    assert "l'une des équations $`L(x)`$ ou $`L(y)`$" in _md("pendulum_tension")


def test_exact_coulomb_friction_shows_its_law_without_epsilon():
    """block_on_incline (regularization = 0): no √(‖v_s‖² + ε²) for an ε that is 0; the sticking rule and f_s."""
    step5 = _section(_md("block_on_incline"), "5.")
    assert r"\varepsilon" not in step5
    # R_t, the tangential part of the support's action: T is the kinetic energy; N is found at step 7.
    assert r"\vec{R}_t = -f N\,\vec{v}_s / \|\vec{v}_s\|,\ \vec{v}_s = \vec{V}(B/R_{0}),\ N = m g \cos\alpha" in step5
    assert r"\|\vec{R}_t\| \le f_{s}\, N" in step5 and "adhérence" in step5 and r"\vec{T}" not in step5
    assert "switches to sticking" in _md("block_on_incline", "en")


def test_a_conservative_load_derives_from_its_u_p():
    assert r"Q_i(\text{poids}) = -\frac{\partial U_P(\text{poids})}{\partial q_i}" in _md("simple_pendulum")


@pytest.mark.slow
def test_one_equation_is_singular_and_reactions_name_their_body():
    assert "l'équation de Lagrange détermine le mouvement" in _section(_md("simple_pendulum"), "7.")
    assert "les $`1`$ équations" not in _md("simple_pendulum")
    en = _md("simple_pendulum", "en")
    assert "All constraints were taken as principal" in en and "the Lagrange equation determines" in en
    assert "La réaction exercée sur ($`S`$) en $`I`$ est" in _md("rolling_coin")
    assert "Sa réaction" not in _md("rolling_coin") and "La réaction exercée sur $`P`$ est" in _md("pendulum_tension")


def test_the_count_of_principal_parameters_is_said_once():
    text = _md("pendulum_tension")
    assert text.count("paramètres principaux.") == 0 and "On a donc $`2`$ paramètres principaux" in text
    assert r"3 \times 1 - 1 = 2" in _section(text, "1.")


def test_english_wording():
    en = _md("simple_pendulum", "en")
    assert "Galilean (inertial) frame" in en
    from lagrangian.output._report.words import Words

    w = Words("en")
    assert w.text("check") == "Newton–Euler cross-check (Remark 4 of the course)"
    assert all("found again" not in w.template(k) for k in ("check intro", "check intro moving") if w.has(k))


def test_units_print_with_superscripts_and_a_centred_dot():
    from lagrangian.output._report.steps.statement import _unit

    assert [_unit(u) for u in ("m/s^2", "kg m^2", "kg*m^2", "m s^-1", "N/m", None)] == \
        ["m/s²", "kg·m²", "kg·m²", "m·s⁻¹", "N/m", ""]


def test_a_velocity_row_that_integrates_is_called_holonomic_with_its_integral():
    import lagrangian
    from lagrangian.output import report

    eom = lagrangian.derive(lagrangian.load_model("examples/rolling_disk_incline.toml"))
    text = plain(report(eom, lang="fr", verification=False).render("md"))
    step1 = text[text.index("## 1."):text.index("## 2.")]
    assert "s'intègre en $`x - r \\varphi = \\text{cste}`$ : elle est donc holonome" in step1
    assert "non holonome" not in step1


@pytest.mark.slow
def test_the_multiplier_terms_are_defined_once_and_symbols_are_math():
    import lagrangian
    from lagrangian.output import report

    eom = lagrangian.derive(lagrangian.load_model("examples/pendulum_tension.toml"))
    for lang, words in (("fr", "est son multiplicateur"), ("en", "is its multiplier")):
        text = report(eom, lang=lang, verification=False).render("md")
        assert text.count(words) == 1
        assert "q̇\\_i" not in text and "q̇_i" not in text and "f\\_k" not in text
