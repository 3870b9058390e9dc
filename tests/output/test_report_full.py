"""Full forms of summarized expressions: under their equation (HTML, Markdown), in an appendix (LaTeX), within a budget."""

from __future__ import annotations

import re

import pytest

import lagrangian
from lagrangian.model.zoo import planar_chain
from lagrangian.output import report
from lagrangian.output._course import to_sympy
from lagrangian.output._report.document import Display, FullForms, math_of, walk
from lagrangian.output._report.full_forms import FULL_BUDGET, FULL_WIDTH
from lagrangian.output._report.size import Summary, visible_width


def _undo(lines: tuple[str, ...]) -> str:
    """The LaTeX of cut lines put back on one line (``\\right.`` / ``\\left.`` removed, spaces ignored)."""
    return re.sub(r"\s+", "", " ".join(lines).replace(r"\right.", "").replace(r"\left.", ""))


def _book(r) -> list[tuple[str, tuple[str, ...]]]:
    return [(ref, eq.lines) for s in r.document.sections for b in walk(s.blocks) if isinstance(b, FullForms)
            for ref, eq in b.forms]


@pytest.fixture(scope="module")
def chain6():
    eom = lagrangian.derive(planar_chain(6))
    return eom, report(eom, lang="fr")


def _summaries(latex: str) -> list[str]:
    return re.findall(r"\\langle [^⟩]*?\\rangle", latex)


@pytest.mark.slow
def test_every_summarized_lagrange_equation_of_a_6_link_chain_has_its_full_form(chain6):
    eom, r = chain6
    step6 = r.document.section("step6")
    forms = dict(_book(r))
    shown = [line for b in walk(step6.blocks) if isinstance(b, Display) for eq in b.equations for line in eq.lines]
    summarized = [line for line in shown if r"\langle" in line]
    assert summarized  # the 6-link chain's L(θ_i) are summarized ...
    for line in summarized:  # ... and each summary there refers to a full form that the report holds
        for summary in _summaries(line):
            ref = re.search(r"\(voir (A\.\d+)\)", summary)
            assert ref, summary
            assert ref.group(1) in forms
    # Each fold of full forms comes right after the equation (or the fold of the equation) that refers to it.
    previous = 0
    for k, b in enumerate(step6.blocks):
        if isinstance(b, FullForms):
            above = " ".join(math_of(step6.blocks[previous:k]))
            assert all(f"(voir {ref})" in above for ref, _ in b.forms), b.summary
            previous = k + 1


@pytest.mark.slow
def test_full_forms_are_the_notations_latex_of_the_engines_expressions(chain6):
    eom, r = chain6
    from lagrangian.output._course import course_form
    from lagrangian.output._report.build import report_notation

    n = report_notation(course_form(eom, ()), eom.model)
    engine = {}
    for eq in eom.equations:
        for name in ("dT_dqd", "dT_dq", "dU_dq", "lhs", "rhs"):
            e = getattr(eq, name)
            engine[_undo((n.latex(to_sympy(e)),))] = e
    engine[_undo((n.latex(to_sympy(eom.T)),))] = eom.T
    matched = 0
    for ref, lines in _book(r):
        body = _undo(lines).partition("=")[2]  # after the head (∂T/∂θ̇1 =, d/dt[∂T/∂θ̇1] − ∂T/∂θ1 =, T(Σ/R0) =)
        assert body in engine, (ref, body[:200])
        matched += 1
    assert matched == len(_book(r)) >= 12
    # Every line of a full form is narrow enough for the page (HTML lines must not scroll sideways).
    assert all(visible_width(line) <= FULL_WIDTH + 30 for _, lines in _book(r) for line in lines)


@pytest.mark.slow
def test_html_folds_the_full_forms_and_markdown_too(chain6):
    eom, r = chain6
    html, md = r.html(), r.markdown()
    assert html.count('<details class="full">') == sum(1 for s in r.document.sections for b in walk(s.blocks)
                                                         if isinstance(b, FullForms))
    assert "<summary>L(θ1)\u00a0: formes complètes A.2 — afficher</summary>" in html  # French: no break before :
    assert "(voir&#x000A0;A.2)" in html  # MathML of \text{termes (voir A.2)}
    # Markdown: a collapsed <details> holding ```math blocks.
    fold = md[md.index("formes complètes A.2"):]
    assert fold.index("```math") < fold.index("</details>")
    assert "**A.2**" in md


@pytest.mark.slow
def test_latex_gathers_the_full_forms_in_an_appendix(chain6):
    eom, r = chain6
    tex = r.latex()
    appendix = tex.index(r"\section*{Annexe : formes complètes}")
    assert appendix > tex.index("voir A.2") and tex.index(r"\textbf{A.2}") > appendix
    assert r"\begin{align*}" in tex[appendix:] and r"\end{document}" in tex[appendix:]
    english = report(eom, lang="en").latex()
    assert r"\section*{Appendix: full forms}" in english and "(see A.2)" in english


@pytest.mark.slow
def test_a_40_link_chain_stays_within_the_budget():
    # Its time is measured in benchmarks/report_display_form.py, not here.
    eom = lagrangian.derive(planar_chain(40))
    r = report(eom, lang="fr")
    assert r.html() and r.latex() and r.markdown()
    forms = _book(r)
    assert forms and sum(len(line) for _, lines in forms for line in lines) <= 1.2 * FULL_BUDGET
    # The rest stays summarized, and the report says where the complete equations are.
    text = " ".join(x for s in r.document.sections for b in walk(s.blocks) if hasattr(b, "runs")
                    for x in b.runs if isinstance(x, str))
    assert "lagrangian derive MODEL --json" in text and "300\u202f000 caractères" in text  # a narrow space
    step6 = " ".join(math_of(r.document.section("step6").blocks))
    assert r"\text{termes} \rangle" in step6  # summaries left as they were


def test_a_model_file_is_named_in_the_note():
    from lagrangian.output._report.build import Context

    eom = lagrangian.derive(lagrangian.load_model("examples/double_pendulum.toml"))
    c = Context(eom, (), "en")
    assert c.derive_command == "lagrangian derive examples/double_pendulum.toml --json"


def test_the_budget_leaves_summaries_as_they_are():
    eom = lagrangian.derive(planar_chain(6))
    from lagrangian.output._report.build import Context

    c = Context(eom, (), "fr")
    c.book.budget = 0
    row = c.form.equations[0]
    assert isinstance(row.lhs, Summary)
    assert c.full([("L = ", row.lhs)], "L") == [] and c.book.left_out == [row.lhs] and row.lhs.reference is None
