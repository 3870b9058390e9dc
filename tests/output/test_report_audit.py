"""The report's wording, checked against the course: points an audit of the reports raised.

Each test names the model of ``examples/`` it reads and the sentence or formula it pins.
"""

from __future__ import annotations

from functools import lru_cache

from lagrangian.output import report
from lagrangian.output._report_doc import math_of
from lagrangian_test_support import EXAMPLES_DIR


@lru_cache(maxsize=None)
def _md(name: str, lang: str = "fr") -> str:
    return report(EXAMPLES_DIR / f"{name}.toml", lang=lang).markdown()


def _section(text: str, title: str) -> str:
    """The Markdown of the section whose heading starts with ``title``."""
    start = text.index(f"## {title}")
    end = text.find("\n## ", start + 3)
    return text[start:end if end >= 0 else len(text)]


def test_the_matrix_form_keeps_the_multipliers():
    """pendulum_tension: step 6 has m ẍ = 2xλ, so the appendix cannot say M q̈ = F with F_x = 0 alone."""
    for name in ("pendulum_tension", "rolling_coin"):
        for lang, title in (("fr", "Annexe : forme matricielle"), ("en", "Appendix: matrix form")):
            appendix = _section(_md(name, lang), title)
            assert r"A^{\mathsf{T}}\lambda" in appendix
    appendix = _section(_md("pendulum_tension"), "Annexe")
    assert r"\left(A^{\mathsf{T}}\lambda\right)_{x} = \sum_{k} \lambda_{k}\, a_{k,x} = 2 x \lambda" in appendix
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
