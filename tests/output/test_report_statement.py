"""The « Énoncé » / "Statement" opening the report: what a teacher hands out before the solution.

Everything it must say is read from the model here (its description in the report's language,
its parameters with their values and units, its bodies and particles with their masses and
inertia, its loads, its declared constraints), so that a statement that forgets one fails; the
French statement carries no English word of the phrase table outside mathematics, and the reverse.
"""

from __future__ import annotations

import re

import pytest
from lagrangian_test_support import eom_of, plain

from lagrangian.model import Gravity
from lagrangian.model._texts import in_language
from lagrangian.output import report
from lagrangian.output._course import course_form
from lagrangian.output._report.build import report_notation, tex_name
from lagrangian.output._report.document import Items, Math, Para, Table, math_of, walk
from lagrangian.output._report.words import _PHRASES, Words

EXAMPLES = ["lagrange_top.toml", "pendulum_tension.toml"]


@pytest.fixture(scope="module", params=[(name, lang) for name in EXAMPLES for lang in ("fr", "en")],
                ids=lambda p: f"{p[0]}-{p[1]}")
def case(request):
    name, lang = request.param
    eom = eom_of(name)
    return eom, lang, report(eom, lang=lang).document


def _runs(blocks):
    for b in walk(blocks):
        if isinstance(b, Para):
            yield from b.runs
        elif isinstance(b, Items):
            for item in b.items:
                yield from item
        elif isinstance(b, Table):
            for row in (b.header, *b.rows):
                for cell in row:
                    yield from cell


def _prose(blocks) -> str:
    """The statement's words, mathematics left out."""
    return plain(" ".join(r for r in _runs(blocks) if isinstance(r, str)))


def _norm(latex: str) -> str:
    """LaTeX with its spacing left out (``\\ ``, ``\\,`` and blanks)."""
    return re.sub(r"\\[ ,]|\s+", "", latex)


def _math(blocks) -> str:
    return _norm(" ".join(math_of(blocks)))


def _statement(document):
    return document.sections[0]


@pytest.mark.slow
def test_the_statement_opens_the_report(case):
    _, lang, document = case
    s = _statement(document)
    assert s.title == ("Énoncé" if lang == "fr" else "Statement")
    assert document.sections[1].key == "step1"


def test_the_statement_says_the_system_in_the_reports_language(case):
    eom, lang, document = case
    prose = _prose(_statement(document).blocks).lower()
    description = in_language(eom.model.description, lang)
    other = in_language(eom.model.description, "en" if lang == "fr" else "fr")
    assert description and description.rstrip(". ").lower() in prose
    assert other != description and other.rstrip(". ").lower() not in prose


def test_every_parameter_is_given_with_its_value_unit_and_description(case):
    eom, lang, document = case
    s = _statement(document)
    table = next(b for b in walk(s.blocks) if isinstance(b, Table))
    notation = report_notation(course_form(eom, ()), eom.model)
    w = Words(lang)
    rows = {"".join(r.latex for r in row[0] if isinstance(r, Math)): row for row in table.rows}
    for p in eom.model.parameters:
        row = rows[notation.symbol(p.name, latex=True)]
        assert "".join(row[1]) == w.number(p.value)
        assert "".join(row[2]) != "" and plain("".join(row[3])) == in_language(p.description, lang)
    assert len(rows) == len(eom.model.parameters)


def test_every_body_and_particle_is_named_with_its_mass_and_inertia(case):
    eom, lang, document = case
    s = _statement(document)
    math = _math(s.blocks)
    notation = report_notation(course_form(eom, ()), eom.model)
    for b in eom.model.bodies:
        assert tex_name(b.name) in math
        assert _norm(notation.latex(b.mass)) in math
        moments = ",".join(_norm(notation.latex(b.inertia.matrix[k][k])) for k in range(3))
        assert moments in math  # the principal moments as given: A, A, C
    for p in eom.model.particles:
        assert tex_name(p.name) in math and _norm(notation.latex(p.mass)) in math
    assert r"R_{0}(O;\vec{x}_{0},\vec{y}_{0},\vec{z}_{0})" in math  # the reference frame and its axes


def test_every_load_and_declared_constraint_is_stated(case):
    eom, lang, document = case
    s = _statement(document)
    prose, math = _prose(s.blocks), _math(s.blocks)
    w = Words(lang)
    for load in eom.model.loads:
        assert w.load(load.name) in prose
        if isinstance(load, Gravity):
            assert r"\vec{g}=" in math
    for con in eom.model.constraints:
        assert in_language(con.description, lang).lower() in prose.lower()
    for row in eom.constraints:  # each declared equation as the engine holds it
        assert _norm(report_notation(course_form(eom, ()), eom.model).latex(row.expression)) in math
    if any(b.fixed_point for b in eom.model.bodies):
        assert "x=y=z=0" in math  # the structural constraint of the top: O fixed point


def _words(text: str) -> set[str]:
    return {x.lower() for x in re.findall(r"[^\W\d_]{4,}", re.sub(r"\{\w+\}", " ", text))}


def test_no_word_of_the_other_language(case):
    """French prose holds no word that only the English phrases use, and the reverse."""
    eom, lang, document = case
    fr = set().union(*(_words(f) for f, _ in _PHRASES.values()))
    en = set().union(*(_words(e) for _, e in _PHRASES.values()))
    foreign = (en - fr) if lang == "fr" else (fr - en)
    found = _words(_prose(_statement(document).blocks)) & foreign
    assert not found, found
