"""The full forms of summarized expressions: ⟨41 terms (see A.3)⟩ written in full, within a size budget.

A `Summary` in a Lagrange equation of step 6, or in T(Σ/R) and U_P(Σ/R) of step 4, is given a
number A.k the first time an equation shows it, and its full form — the engine's expression
written by `Notation`, cut into lines a few terms long — goes under that equation (`FullForms`:
folded in HTML and Markdown, in an appendix in LaTeX); from then on it prints as
⟨41 terms (see A.3)⟩.  The full forms of one report hold at most `FULL_BUDGET` characters of
LaTeX, so that a 40-link chain is still reported in seconds: the summaries met once it is spent
stay as they are, and the report's notes say that ``lagrangian derive MODEL --json`` gives the
complete equations.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import symengine as se
import sympy

from .._course import to_sympy
from .._notation import Notation
from .document import Block, Equation, FullForms
from .size import Summary, wrap_latex

__all__ = ["FullFormBook", "FULL_BUDGET", "CHARS_PER_OP", "FULL_WIDTH", "summaries_in"]

#: Characters of LaTeX that the full forms of one report may hold in all (about 27,000 operations:
#: printing them costs about 1.5 s, converting them to MathML about as much).
FULL_BUDGET = 300_000
#: Characters of LaTeX an operation (`symengine.count_ops`) prints as, at most (9 to 11.5 measured on
#: the planar chains): how a full form's size is foreseen before it is printed.
CHARS_PER_OP = 12
#: Widest line of a full form (visible characters): narrower than the report's own lines, since a line
#: opened inside parentheses may overrun it by a term's width, and the page must not scroll sideways.
FULL_WIDTH = 52


def summaries_in(expr: sympy.Basic) -> list[Summary]:
    """The summaries ``expr`` holds, each once, in the order of a walk through it (``expr`` itself first)."""
    if isinstance(expr, Summary):
        return [expr]
    if not isinstance(expr, sympy.Basic):
        return []
    out: list[Summary] = []
    for node in sympy.preorder_traversal(expr):
        if isinstance(node, Summary) and node not in out:
            out.append(node)
    return out


@dataclass
class FullFormBook:
    """The numbered full forms of one report, and what the budget left out."""

    n: Notation
    see_word: str
    budget: int = FULL_BUDGET
    used: int = 0
    numbered: list[Summary] = field(default_factory=list)
    left_out: list[Summary] = field(default_factory=list)

    def _full(self, s: Summary) -> str | None:
        """The LaTeX of ``s`` in full, or None (and ``s`` left out) when it would overrun the budget."""
        if self.used + CHARS_PER_OP * se.count_ops(s.source) > self.budget:
            self.left_out.append(s)
            return None
        latex = self.n.latex(to_sympy(s.source))
        self.used += len(latex)
        self.numbered.append(s)
        s.refer(f"A.{len(self.numbered)}", self.see_word)
        return latex

    def forms(self, parts: Sequence[tuple[str, sympy.Basic]]) -> tuple[tuple[str, Equation], ...]:
        """The full forms of the summaries in ``parts`` — (head, expression as printed) — not written before.

        A part that is one summary is written ``head`` + its full form (``\\frac{∂T}{∂ψ̇} = …``); a
        summary inside a larger expression is written ⟨41 terms⟩ = its full form.  Call it before
        printing the equation, so that the equation's summaries already carry their numbers.
        """
        out: list[tuple[str, Equation]] = []
        for head, expr in parts:
            for s in summaries_in(expr):
                if s.reference is not None or s in self.left_out:
                    continue
                latex = self._full(s)
                if latex is not None:
                    lead = head if s is expr else f"{s.plain_latex} = "
                    out.append((s.reference, wrap_latex(lead, latex, width=FULL_WIDTH)))
        return tuple(out)

    def blocks(self, parts: Sequence[tuple[str, sympy.Basic]], label: str, words) -> list[Block]:
        """`forms` as one `FullForms` block labelled after ``label`` (``L(θ1)``), or nothing."""
        forms = self.forms(parts)
        if not forms:
            return []
        refs = forms[0][0] if len(forms) == 1 else words.text("refs", first=forms[0][0], last=forms[-1][0])
        title = words.text("full forms", label=label, refs=refs)
        return [FullForms(title, words.text("show it", what=title), forms)]
