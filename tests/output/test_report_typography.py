"""French typography of the report: non-breaking spaces before : ; ! ? and inside « », typographic apostrophes,
decimal commas in text and in formulas, minus signs — in every format."""

from __future__ import annotations

import re
from functools import cache

import pytest
import sympy
from lagrangian_test_support import EXAMPLES_DIR

from lagrangian.output import report
from lagrangian.output._notation import Notation
from lagrangian.output._report.document import Math, Para, french_typography, walk
from lagrangian.output._report.render.tex import escape


@cache
def _fr(name: str):  # type: ignore[no-untyped-def]
    return report(EXAMPLES_DIR / name, lang="fr")


def _texts(r) -> list[str]:  # type: ignore[no-untyped-def]
    """Every piece of plain text of a report: titles, paragraphs, list items, cells, fold summaries."""
    out = [r.document.title, r.document.subtitle]
    for s in r.document.sections:
        out.append(s.title)
        for b in walk(s.blocks):
            runs = list(b.runs) if isinstance(b, Para) else []
            runs += [x for item in getattr(b, "items", ()) for x in item]
            runs += [x for row in (*getattr(b, "rows", ()), getattr(b, "header", ())) for cell in row for x in cell]
            out += [x for x in runs if isinstance(x, str)]
            if hasattr(b, "summary") and isinstance(b.summary, str):
                out.append(b.summary)
    return out


def test_the_rules_on_a_sentence():
    text = french_typography("« poids » dérive d'une énergie : Q ; non ! vraiment ? http://x.fr a:b")
    assert text == ("«\u00a0poids\u00a0» dérive d\u2019une énergie\u00a0: Q\u202f; non\u202f! vraiment\u202f? "
                    "http://x.fr a:b")  # a colon with no space before it (a URL, a ratio) is left alone


@pytest.mark.parametrize("name", ["rolling_coin.toml", "block_on_incline.toml", "lagrange_top.toml"])
def test_french_text_has_no_breakable_space_before_high_punctuation_and_no_straight_apostrophe(name):
    for text in _texts(_fr(name)):
        assert not re.search(r" [:;!?»]", text), text
        assert not re.search(r"«[^\u00a0]", text), text
        assert "'" not in text, text
        assert not re.search(r"\d\.\d", text), text  # decimal commas


def test_english_keeps_its_own_typography():
    r = report(EXAMPLES_DIR / "rolling_coin.toml", lang="en")
    texts = _texts(r)
    assert not any("\u00a0" in t or "\u202f:" in t or "\u2019" in t for t in texts)
    assert any(": " in t for t in texts)


def test_numbers_in_french_formulas_take_a_decimal_comma_and_sensible_digits():
    n = Notation(comma=True)
    assert n.latex(sympy.Float(0.632677500051)) == "0{,}632678"  # not 0.632677500051
    assert n.latex(sympy.Float(-2.5e-05)) == r"-2{,}5 \cdot 10^{-5}"
    assert Notation().latex(sympy.Float(0.632677500051)) == "0.632677500051"  # the engine's outputs keep 12 digits
    robot = Notation(decimals=True, comma=True)
    assert robot.latex(sympy.Rational(17, 250)) == "0{,}068" and robot.latex(sympy.Rational(1, 3)) == r"\frac{1}{3}"


def test_values_computed_from_the_model_have_four_significant_digits():
    step6 = " ".join(x for b in walk(_fr("lagrange_top.toml").document.section("step6").blocks)
                     if isinstance(b, Para) for x in b.runs if isinstance(x, str))
    assert re.search(r"≈ 0,4388\u202fJ·s", step6), step6  # K = 0.438791 J·s to 4 digits


def test_latex_keeps_the_spaces_and_lets_babel_space_the_high_punctuation():
    assert escape("«\u00a0poids\u00a0»") == "«~poids~»"
    assert escape("énergie\u00a0: Q\u202f; non") == "énergie : Q ; non"  # babel's french spaces : and ;
    assert escape("−3,1") == r"\ensuremath{-}3,1"  # a minus sign, not a hyphen
    tex = _fr("rolling_coin.toml").latex()
    assert "\u00a0" not in tex and "\u202f" not in tex and "«~" in tex


def test_markdown_and_html_keep_the_typography():
    r = _fr("block_on_incline.toml")
    assert "«\u00a0poids\u00a0»" in r.markdown() and "«\u00a0poids\u00a0»" in r.html()
    assert all("'" not in x for b in walk(r.document.section("step1").blocks) if isinstance(b, Para)
               for x in b.runs if not isinstance(x, Math))
