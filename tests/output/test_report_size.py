"""Long expressions: summarized by size, cut into lines between terms, parentheses kept balanced."""

from __future__ import annotations

import re

import symengine as se
from hypothesis import given
from hypothesis import strategies as st

import lagrangian
from lagrangian.model.zoo import planar_chain
from lagrangian.output import Notation
from lagrangian.output._course import to_sympy
from lagrangian.output._report.size import (
    LINE_WIDTH,
    MAX_OPS,
    SMALL_OPS,
    SizeGate,
    Summary,
    split_top,
    visible_width,
    wrap,
    wrap_latex,
    wrap_many,
)


def _undo(lines: tuple[str, ...]) -> str:
    return re.sub(r"\s+", "", " ".join(lines).replace(r"\right.", "").replace(r"\left.", ""))


def test_split_top_keeps_nested_sums_whole():
    assert split_top(r"-a + b \left(c + d\right) - \frac{e + f}{g} + h_{i + j}") == \
        ["-a", r"+ b \left(c + d\right)", r"- \frac{e + f}{g}", "+ h_{i + j}"]


def test_visible_width_counts_what_prints():
    assert visible_width(r"\frac{1}{2} A") <= visible_width(r"12 A")
    assert visible_width(r"\frac{\partial T(\Sigma/R_{0})}{\partial \dot{\psi}}") < 10
    assert visible_width(r"\dot{\theta}") == 1 and visible_width(r"\sin\theta") == 4


def test_the_derivations_long_equations_are_cut_and_keep_their_content():
    eom = lagrangian.derive(lagrangian.load_model("examples/double_pendulum.toml"))
    n = Notation(eom.coordinates, [p.name for p in eom.model.parameters])
    long = 0
    for eq in eom.equations:
        lhs = to_sympy(eq.lhs)
        out = wrap(n, r"\Rightarrow\quad ", lhs, " = 0")
        whole = r"\Rightarrow\quad " + n.latex(lhs) + " = 0"
        assert _undo(out.lines) == re.sub(r"\s+", "", whole)
        for line in out.lines:
            assert line.count(r"\left") == line.count(r"\right")  # each line is valid LaTeX on its own
        too_wide = visible_width(whole) > LINE_WIDTH
        assert (len(out.lines) > 1) == too_wide  # cut exactly when it does not fit
        long += too_wide
    assert long  # L(θ1) of the double pendulum does not fit one line


@given(st.lists(st.integers(min_value=1, max_value=99), min_size=1, max_size=60))
def test_wrapped_sums_fit_the_line_and_lose_nothing(coefficients):
    body = " + ".join(rf"{c} x_{{{k}}}" for k, c in enumerate(coefficients))
    out = wrap_latex("S = ", body)
    assert _undo(out.lines) == re.sub(r"\s+", "", "S = " + body)
    assert all(visible_width(line) <= LINE_WIDTH for line in out.lines)


def test_a_long_product_is_opened_at_its_parentheses():
    inner = " + ".join(rf"a_{{{k}}} \cos\theta_{{{k}}}" for k in range(30))
    out = wrap_latex("Q = ", rf"m g \left({inner}\right)^{{2}}")
    assert len(out.lines) > 2
    assert out.lines[0].endswith(r"\right.") and out.lines[-1].startswith(r"\left.")
    assert out.lines[-1].endswith(r"\right)^{2}")


def test_wrap_many_cuts_between_items():
    out = wrap_many(r"\Rightarrow\quad ", [rf"Q_{{{k}}} = {k} \sin\theta_{{{k}}}" for k in range(20)], r",\quad ")
    assert len(out.lines) > 1 and all(visible_width(line) <= LINE_WIDTH for line in out.lines)


def test_the_gate_summarizes_what_is_too_long():
    eom = lagrangian.derive(planar_chain(12))
    gate = SizeGate("terms", "long expression")
    small = eom.T_terms[0].expression
    big = eom.equations[0].lhs
    assert se.count_ops(big) > MAX_OPS and se.count_ops(small) < MAX_OPS
    assert not isinstance(gate(small), Summary)
    summary = gate(big)
    assert isinstance(summary, Summary) and summary.source is big and gate.summaries == [summary]
    assert gate(big) is summary  # converted once


def test_the_gate_stops_converting_when_its_budget_is_spent():
    eom = lagrangian.derive(planar_chain(12))
    gate = SizeGate("terms", "long expression", budget=100)
    for t in eom.T_terms:
        before = gate.used
        shown = gate(t.expression)
        ops = se.count_ops(t.expression)
        if ops > SMALL_OPS:  # small expressions are always converted; others only within the budget
            assert isinstance(shown, Summary) == (before + ops > 100)
