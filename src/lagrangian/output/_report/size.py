"""Long expressions in the report: summarized, cut into lines, or folded.

Three sizes, so that a 40-link chain is reported in seconds and stays readable:

* an engine expression of more than `MAX_OPS` operations (SymEngine's ``count_ops``, about
  six characters each), or met once `BUDGET` operations have been converted, is not
  converted at all: a `Summary` stands in for it, printed ⟨812 terms⟩ (the JSON of
  ``lagrangian derive --json`` has it in full);
* a displayed sum wider than `LINE_WIDTH` is cut into lines between its terms;
* an equation of more than `FOLD_LINES` lines is shown by its first line, with the
  whole of it folded (``<details>`` in HTML and Markdown).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import symengine as se
import sympy

from ...model.vectors import as_expr
from .._course import to_sympy
from .._notation import Notation, Opaque
from .document import Equation

__all__ = ["Summary", "SizeGate", "visible_width", "wrap", "wrap_latex", "wrap_many", "split_top", "MAX_OPS",
           "BUDGET", "LINE_WIDTH", "FOLD_LINES"]

#: Largest expression (operations, `symengine.count_ops`) converted and printed in full.
MAX_OPS = 300
#: Operations converted in all before every further long expression is summarized: printing
#: costs about 0.3 ms per operation, so this bounds a report's printing to a few seconds.
BUDGET = 2000
#: Expressions of at most this many operations are always converted (they cost nothing).
SMALL_OPS = 40
#: Widest displayed line, in visible characters, before a sum is cut between its terms.
LINE_WIDTH = 64
#: Most lines an equation shows before it is folded.
FOLD_LINES = 8


class Summary(Opaque):
    """An expression too long to print, standing in as ⟨812 terms⟩; ``source`` is the engine's expression."""

    def __new__(cls, source: se.Basic, terms_word: str, long_word: str) -> Summary:
        count = _terms(source)
        if count:
            text, latex = f"⟨{count} {terms_word}⟩", rf"\langle {count}\ \text{{{terms_word}}} \rangle"
        else:
            text, latex = f"⟨{long_word}⟩", rf"\langle \text{{{long_word}}} \rangle"
        obj = super().__new__(cls, text, latex)
        obj.source = source
        obj.terms = count
        obj.plain_text, obj.plain_latex = text, latex
        obj.reference = None
        return obj

    def refer(self, reference: str, see_word: str) -> None:
        """Print as ⟨41 terms (see A.3)⟩ from now on: its full form is numbered ``reference``."""
        self.reference = reference
        self.text_form = f"{self.plain_text[:-1]} ({see_word} {reference})⟩"
        self.latex_form = self.plain_latex.replace(r"} \rangle", rf" ({see_word} {reference})}} \rangle")


def _terms(e: se.Basic) -> int:
    """Terms of a sum, also under a numeric factor (−(a + b + c) has 3); 0 for anything else."""
    if isinstance(e, se.Add):
        return len(e.args)
    if isinstance(e, se.Mul):
        args = e.args
        sums = [a for a in args if isinstance(a, se.Add)]
        if len(sums) == 1 and all(a.is_Number for a in args if not isinstance(a, se.Add)):
            return len(sums[0].args)
    return 0


@dataclass
class SizeGate:
    """The converter the report hands to `course_form`: `to_sympy`, or a `Summary` for what is too long.

    Parameters
    ----------
    terms_word : str
        The word for "terms" in the report's language (⟨812 terms⟩).
    long_word : str
        The word for an expression too long, not a sum.
    max_ops : int
        The largest expression converted and printed in full.
    budget : int
        Operations converted in all before every further long expression is summarized.
    used : int
        Operations converted so far.
    summaries : list of Summary
        The summaries made so far.
    _cache : dict
        The conversions made, by expression; not to be given.
    """

    terms_word: str
    long_word: str
    max_ops: int = MAX_OPS
    budget: int = BUDGET
    used: int = 0
    summaries: list[Summary] = field(default_factory=list)
    _cache: dict[se.Basic, sympy.Basic] = field(default_factory=dict)

    def __call__(self, e: se.Basic) -> sympy.Basic:
        e = as_expr(e)
        hit = self._cache.get(e)
        if hit is not None:
            return hit
        ops = se.count_ops(e)
        if ops <= SMALL_OPS or (ops <= self.max_ops and self.used + ops <= self.budget):
            self.used += ops
            out = to_sympy(e)
        else:
            out = Summary(e, self.terms_word, self.long_word)
            self.summaries.append(out)
        self._cache[e] = out
        return out


_ZERO_WIDTH = {"left", "right", "dot", "ddot", "vec", "overrightarrow", "text", "mathrm", "operatorname",
               "displaystyle", "begin", "end"}
_SPACES = {",": 0.3, ";": 0.3, ":": 0.3, "!": 0.0, " ": 0.3, "quad": 2.0, "qquad": 4.0}
_COMMAND = re.compile(r"\\([A-Za-z]+|.)")
_FUNCTIONS = {"sin", "cos", "tan", "sinh", "cosh", "tanh", "exp", "log", "arcsin", "arccos", "arctan"}


def _group(s: str, i: int) -> tuple[str, int]:
    """The braced group starting at ``s[i]`` (or the single character there) and the index after it."""
    if i >= len(s):
        return "", i
    if s[i] != "{":
        if s[i] == "\\":
            m = _COMMAND.match(s, i)
            return (m.group(0), m.end()) if m else (s[i], i + 1)
        return s[i], i + 1
    depth, j = 0, i
    while j < len(s):
        if s[j] == "{" and (j == 0 or s[j - 1] != "\\"):
            depth += 1
        elif s[j] == "}" and s[j - 1] != "\\":
            depth -= 1
            if depth == 0:
                return s[i + 1:j], j + 1
        j += 1
    return s[i + 1:], len(s)


def _width(s: str) -> float:
    total, i = 0.0, 0
    while i < len(s):
        ch = s[i]
        if ch == "\\":
            m = _COMMAND.match(s, i)
            name = m.group(1) if m else ch
            i = m.end() if m else i + 1
            if name in ("frac", "tfrac", "dfrac"):
                num, i = _group(s, i)
                den, i = _group(s, i)
                total += max(_width(num), _width(den)) + 0.4
            elif name in _SPACES:
                total += _SPACES[name]
            elif name in _FUNCTIONS:
                total += 3.3
            elif name not in _ZERO_WIDTH:
                total += 1
        elif ch in "_^":
            group, i = _group(s, i + 1)
            total += 0.6 * _width(group)
        elif ch in "{} ":
            i += 1
        elif ch in "+-=<>,;":
            total += 1.8 if ch in "+-=<>" else 1.2
            i += 1
        else:
            total += 1
            i += 1
    return total


def visible_width(latex: str) -> int:
    """About how many characters wide ``latex`` prints (a fraction as wide as its wider part, indices smaller)."""
    return round(_width(latex))


def _scan(s: str) -> list[tuple[int, int]]:
    """(index, depth before it) for every character, depth counting braces and \\left ... \\right."""
    out, depth, i = [], 0, 0
    while i < len(s):
        out.append((i, depth))
        if s.startswith(r"\left", i) and not s[i + 5:i + 6].isalpha():
            depth += 1
            i += 5
            continue
        if s.startswith(r"\right", i) and not s[i + 6:i + 7].isalpha():
            depth -= 1
            i += 6
            continue
        if s[i] == "\\":
            i += 2
            continue
        if s[i] == "{":
            depth += 1
        elif s[i] == "}":
            depth -= 1
        i += 1
    return out


def split_top(s: str) -> list[str]:
    """The top-level terms of a LaTeX sum, ``"a + b - c"`` → ``["a", "+ b", "- c"]``."""
    pieces, start = [], 0
    for i, depth in _scan(s):
        if depth == 0 and i > start and (s.startswith(" + ", i) or s.startswith(" - ", i)):
            pieces.append(s[start:i].strip())
            start = i + 1
    pieces.append(s[start:].strip())
    return [p for p in pieces if p]


def _parens(s: str) -> list[tuple[int, int]]:
    """Start of every top-level ``\\left(`` of ``s`` and the end of its matching ``\\right)``."""
    out, open_at = [], None
    for i, depth in _scan(s):
        if open_at is None and depth == 0 and s.startswith(r"\left(", i):
            open_at = i
        elif open_at is not None and depth == 1 and s.startswith(r"\right)", i):
            out.append((open_at, i + len(r"\right)")))
            open_at = None
    return out


def _inner(piece: str, group: tuple[int, int]) -> list[str]:
    return split_top(piece[group[0] + len(r"\left("):group[1] - len(r"\right)")])


def _atoms(piece: str, width: int, depth: int = 0) -> list[tuple[str, int]]:
    """``piece`` as (text, depth after it) atoms: a piece too wide is opened at its parenthesized sums.

    The sums opened are those wider than a quarter of the line (a product of two long sums is
    opened at both), else the widest; a short one, such as the argument of a sine, stays whole.
    """
    if visible_width(piece) <= width:
        return [(piece, depth)]
    groups = [g for g in _parens(piece) if len(_inner(piece, g)) >= 2]
    if not groups:
        return [(piece, depth)]
    wide = [g for g in groups if visible_width(piece[g[0]:g[1]]) > width // 4] or \
        [max(groups, key=lambda g: visible_width(piece[g[0]:g[1]]))]
    out: list[tuple[str, int]] = []
    position = 0
    for start, end in wide:
        between = piece[position:start]
        inside: list[tuple[str, int]] = []
        for term in _inner(piece, (start, end)):
            inside += _atoms(term, width, depth + 1)
        if out:  # what follows a closed sum (a power, a space, a factor) stays with it
            text, d = out[-1]
            out[-1] = (text + between.rstrip(), d)
            between = " " if between[-1:].isspace() else ""
        first, d = inside[0]
        inside[0] = (between + r"\left(" + first, d)
        last, _ = inside[-1]
        inside[-1] = (last + r"\right)", depth)
        out += inside
        position = end
    last, _ = out[-1]
    out[-1] = (last + piece[position:], depth)
    return out


def _lay_out(head: str, atoms: list[tuple[str, int]], tail: str, width: int) -> Equation:
    """Atoms filled into lines; a line that ends inside parentheses is closed by ``\\right.`` and reopened."""
    lines: list[str] = []
    if visible_width(head) > width // 2 and head.rstrip().endswith("=") and atoms and \
            visible_width(head + atoms[0][0]) > width:
        lines.append(head.rstrip()[:-1].rstrip())
        head = "= "
    current, depth, empty = head, 0, True
    for text, after in atoms:
        candidate = f"{current} {text}" if not empty and current.strip() else current + text
        if not empty and visible_width(candidate + tail) > width:
            lines.append(current + r" \right." * depth)
            current = r"\left. " * depth + text
        else:
            current = candidate
        depth, empty = after, False
    lines.append(current + tail)
    return Equation(tuple(line.strip() for line in lines))


def wrap_latex(head: str, body: str, tail: str = "", width: int | None = None) -> Equation:
    """``head body tail`` as an `Equation`, cut into lines between the terms of ``body`` when too wide."""
    width = width or LINE_WIDTH
    if visible_width(head + body + tail) <= width:
        return Equation((f"{head}{body}{tail}",))
    atoms = [a for term in split_top(body) for a in _atoms(term, width)]
    return _lay_out(head, atoms, tail, width)


def wrap(n: Notation, head: str, expr: sympy.Basic, tail: str = "", width: int | None = None) -> Equation:
    """``head expr tail`` (``head`` ends with the relation, ``L = ``), cut into lines when too wide."""
    return wrap_latex(head, n.latex(expr), tail, width)


def wrap_many(head: str, pieces: list[str], sep: str, width: int | None = None) -> Equation:
    """``head`` then ``pieces`` joined by ``sep``, cut between (and if need be inside) pieces when too wide."""
    width = width or LINE_WIDTH
    joined = head + sep.join(pieces)
    if visible_width(joined) <= width:
        return Equation((joined,))
    atoms: list[tuple[str, int]] = []
    for k, piece in enumerate(pieces):
        mine = [a for term in split_top(piece) for a in _atoms(term, width)]
        if k < len(pieces) - 1:
            text, d = mine[-1]
            mine[-1] = (text + sep.rstrip(), d)
        atoms += mine
    return _lay_out(head, atoms, "", width)
