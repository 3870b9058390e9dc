"""The course's notation: ψ̇ for psi_dot, φ for phi, A ψ̇² sinθ cosθ rather than A*psi_dot**2*sin(theta)*cos(theta).

`Notation` renders a SymPy expression as terminal text or LaTeX with the factor and
term order a teacher would write:

* terms with a q̈ first, then a positive term free of parameters and linear in a rate or
  a coordinate (ẋ − v_b, ẋ − r φ̇, x − r φ: the coordinate before what it is compared with), then by the first parameter
  they contain (in the order the model declares parameters), then shortest first — so
  Γ_θ prints as ``A θ̈ − A ψ̇² sinθ cosθ + C ψ̇ sinθ (φ̇ + ψ̇ cosθ)``;
* factors: number, parameters (declaration order), sums of parameters (C − A, a sum of constants
  starting with a positive term), rates, accelerations, coordinates, sin, cos, other functions,
  then parenthesized sums;
* a function of a single symbol loses its parentheses (sinθ), a power of a function
  goes on the function (sin²θ), and one-half is written ½.

Nothing here changes an expression's value: it only chooses how to write it.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, field

import sympy

from .._greek import GREEK as _GREEK

__all__ = ["Notation", "Opaque"]

_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")
_FRACTIONS = {(1, 2): "½", (1, 3): "⅓", (2, 3): "⅔", (1, 4): "¼", (3, 4): "¾"}
_FUNCTION_RANK = {"sin": 0, "cos": 1, "tan": 2}
_LATEX_FUNCTIONS = {"sin", "cos", "tan", "sinh", "cosh", "tanh", "exp", "log", "arcsin", "arccos", "arctan"}
_SYMPY_TO_NAME = {"asin": "arcsin", "acos": "arccos", "atan": "arctan", "sign": "sgn"}


def _is_negative(term: sympy.Basic) -> bool:
    coeff = term.as_coeff_Mul()[0]
    return bool(coeff.is_Number and coeff.is_negative)


def _as_sympy(expr: object) -> sympy.Basic:
    """A SymPy expression from a SymPy or SymEngine one, or a number (text is refused)."""
    if isinstance(expr, sympy.Basic):
        return expr
    if hasattr(expr, "_sympy_"):
        return expr._sympy_()
    if isinstance(expr, int) and not isinstance(expr, bool):
        return sympy.Integer(expr)
    if isinstance(expr, float):
        return sympy.Float(expr)
    raise TypeError(f"cannot print a {type(expr).__name__} as an expression")


def _axis_latex(name: str, frames: Collection[str] = ()) -> str:
    r"""An axis with its arrow, its index after it: z0 → \vec{z}_{0}, x_I → \vec{x}_{I}, xE → \vec{x}_{E}.

    A name that is one letter followed by a frame's name (one of ``frames``, or any name that
    starts with a capital: xE, yR1) is that letter indexed by the frame.
    """
    if "_" in name.strip("_"):
        head, _, tail = name.partition("_")
        # z_R_column (a URDF link's frame): the index is itself a name with an index, R_{\mathrm{column}}.
        return rf"\vec{{{head}}}_{{{_base_latex(tail) if '_' in tail else tail}}}"
    rest = name[1:]
    if name[:1].isalpha() and rest and (rest in frames or (rest[0].isupper() and rest.isalnum())):
        return rf"\vec{{{name[0]}}}_{{{rest}}}"
    head = name.rstrip("0123456789")
    tail = name[len(head):]
    return rf"\vec{{{head}}}" + (f"_{{{tail}}}" if tail else "")


def _split_name(name: str) -> tuple[str, str]:
    """``theta_ddot`` → (``theta``, ``ddot``); ``l1`` → (``l1``, ``"")."""
    for suffix in ("_ddot", "_dot", "_star"):
        if name.endswith(suffix):
            return name[: -len(suffix)], suffix[1:]
    return name, ""


def _greek_index(name: str) -> tuple[str, str] | None:
    """``thetaR`` → (``theta``, ``R``), ``theta1`` → (``theta``, ``1``): a Greek letter and its index.

    The index is digits, or starts with a capital (thetaB, omegaZ1): a lower-case tail
    (``thetas``, ``eta`` in ``beta``) is part of a word, not an index.
    """
    for head in sorted(_GREEK, key=len, reverse=True):
        tail = name[len(head):]
        if name.startswith(head) and tail and tail.isalnum() and (tail.isdigit() or tail[0].isupper()):
            return head, tail
    return None


def _base_text(name: str) -> str:
    if name in _GREEK:
        return _GREEK[name][0]
    split = _greek_index(name)
    if split:
        return _GREEK[split[0]][0] + split[1]
    return name


def _base_latex(name: str) -> str:
    if name in _GREEK:
        return _GREEK[name][1]
    if "_" in name:
        # One level of index, its parts separated by commas: lambda_rolling_x1 → λ_{rolling, x₁}; words joined by
        # an underscore stay one name (a URDF link's frame R_upper_arm → R_{upper_arm}, not R_{upper, arm}).
        head, _, tail = name.partition("_")
        words = [part for part in tail.split("_") if part]
        if _is_word(head) and all(_is_word(part) for part in words):
            joined = "\\_".join([head, *words])
            return rf"\mathrm{{{joined}}}"  # upper_arm: one name, not upper with the index arm
        if len(words) > 1 and all(_is_word(part) for part in words):
            joined = "\\_".join(words)
            return rf"{_base_latex(head)}_{{\mathrm{{{joined}}}}}"
        parts = [_base_latex(part) for part in words]
        return f"{_base_latex(head)}_{{{','.join(parts)}}}"
    split = _greek_index(name)
    if split:
        return f"{_GREEK[split[0]][1]}_{{{split[1]}}}"
    head = name.rstrip("0123456789")
    if head and head != name:
        return f"{_base_latex(head)}_{{{name[len(head):]}}}"
    return name if len(name) == 1 else rf"\mathrm{{{name}}}"


def _is_word(part: str) -> bool:
    """A word (``upper``, ``arm``, ``waist``), not a symbol (``x1``, ``xG``, ``theta``, ``G``): set upright, joined by
    ``\\_``."""
    return (len(part) > 2 and part.isalpha() and part.islower() and part not in _GREEK
            and _greek_index(part) is None)


def _split_index(latex: str) -> tuple[str, str]:
    """``\\theta_{1}`` → (``\\theta``, ``_{1}``): a symbol and its index (``""`` when it has none)."""
    depth = 0
    for i, ch in enumerate(latex):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == "_" and depth == 0 and i > 0:
            return latex[:i], latex[i:]
    return latex, ""


def _wordlike(name: str) -> bool:
    """A symbol written as a word (``lat``, ``phi0`` is not): a function before it needs a space."""
    base, _ = _split_name(name)
    head = base.partition("_")[0].rstrip("0123456789")
    return len(head) > 1 and head not in _GREEK


class Opaque(sympy.Dummy):
    """A stand-in that prints as given: ``text`` in terminal text, ``latex`` in LaTeX.

    It behaves as a symbol in every SymPy operation; the report uses it for an expression
    too long to print, shown as a summary such as ⟨812 terms⟩.
    """

    def __new__(cls, text: str, latex: str) -> Opaque:
        obj = super().__new__(cls, "opaque")
        obj.text_form = text
        obj.latex_form = latex
        return obj


@dataclass
class Notation:
    """Renders expressions in the course's notation for one model.

    Parameters
    ----------
    coordinates : sequence of str
        Coordinate names in model order.
    parameters : sequence of str
        Parameter names in declaration order (sets the order of factors).
    rewrite : callable, optional
        Rewrites an expression into the form to print, keeping its value (the report's
        `display_form`); none by default.
    names : mapping of str to (str, str)
        Symbols written otherwise than their name says, name → (text, LaTeX): the report writes the
        multiplier ``lambda_length`` as λ, or λ_1 … λ_k when there are several.
    decimals : bool
        Rationals with a finite decimal expansion written as decimals (17/250 → 0.068, not ⅓): a
        URDF's numbers.
    comma : bool
        French: a decimal comma in numbers (0{,}068 in LaTeX), and floats to 6 significant digits
        (else 12, a point).
    _cache, _keys : dict
        The renderer's caches, filled as it goes; not to be given.
    """

    coordinates: Sequence[str] = ()
    parameters: Sequence[str] = ()
    rewrite: Callable[[sympy.Basic], sympy.Basic] | None = None
    names: Mapping[str, tuple[str, str]] = field(default_factory=dict)
    decimals: bool = False
    comma: bool = False
    _cache: dict[tuple[str, str], str] = field(default_factory=dict, repr=False)
    _keys: dict[tuple[sympy.Basic, bool | None], tuple] = field(default_factory=dict, repr=False)

    # -- symbols ---------------------------------------------------------------------------
    def symbol(self, name: str, latex: bool = False) -> str:
        key = (name, "tex" if latex else "txt")
        if name in self.names:
            return self.names[name][1 if latex else 0]
        if key not in self._cache:
            base, deco = _split_name(name)
            if latex:
                b = _base_latex(base)
                # The dot goes over the letter, the index after it: \dot{\theta}_{1}, not \dot{\theta_{1}}.
                head, sub = _split_index(b)
                out = {"dot": rf"\dot{{{head}}}{sub}", "ddot": rf"\ddot{{{head}}}{sub}", "star": rf"{b}^{{*}}",
                       "": b}[deco]
            else:
                b = _base_text(base)
                split = _greek_index(base)
                # θ̇1, θ̇R: the dot on the letter, not on the index.
                head = _GREEK[split[0]][0] if split else b.rstrip("0123456789")
                word = re.match(r"[A-Za-z]*", head).group()  # type: ignore[union-attr]
                if len(word) > 1 and deco in ("dot", "ddot"):
                    # A word (a URDF joint, `shoulder`): a combining dot would sit on its last letter
                    # ("shouldeṙ"), so the rate keeps the name the user types (--set shoulder_dot=1).
                    out = f"{b}_{deco}"
                else:
                    out = head + {"dot": "\u0307", "ddot": "\u0308", "star": "", "": ""}[deco] + b[len(head):] + \
                        ("*" if deco == "star" else "")
            self._cache[key] = out
        return self._cache[key]

    # -- ordering --------------------------------------------------------------------------
    def _sort_factors(self, factors: list[sympy.Basic]) -> None:
        """Sort ``factors`` by `_factor_key`, in place.

        The key of a parenthesized sum holds its printed text, which is slow to make for a long
        sum; it only matters when two such factors are compared, so it is made only then.
        """
        if sum(1 for f in factors if self._factor_key(f, text=False)[0] == 8) > 1:
            factors.sort(key=self._factor_key)
        else:
            factors.sort(key=lambda f: self._factor_key(f, text=False))

    def _factor_key(self, factor: sympy.Basic, text: bool = True) -> tuple:
        # Cached: a long equation meets the same factors (cos(θ_B + λ), a bracketed sum) thousands
        # of times, and their keys hold printed text.
        key = (factor, text)
        if key not in self._keys:
            self._keys[key] = self._make_factor_key(factor, text)
        return self._keys[key]

    def _make_factor_key(self, factor: sympy.Basic, text: bool) -> tuple:
        base = factor.base if isinstance(factor, sympy.Pow) else factor
        if isinstance(base, sympy.Symbol):
            name, deco = _split_name(base.name)
            if base.name in self.parameters:
                return (0, list(self.parameters).index(base.name), "")
            if name in self.coordinates:
                rank = {"dot": 1, "ddot": 2, "star": 3, "": 4}[deco]
                return (rank, list(self.coordinates).index(name), "")
            return (5, 0, base.name)
        if isinstance(base, sympy.Function):
            return (6, _FUNCTION_RANK.get(type(base).__name__, 9), str(base.args))
        if isinstance(base, sympy.Add) and base.free_symbols and all(s.name in self.parameters for s in base.free_symbols):
            # A sum of constants goes with the constants: 2 (C − A) ψ̇ cosθ.
            return (0, len(self.parameters), str(base) if text else "")
        return (8, 0, str(base) if text else "")

    def _term_key(self, term: sympy.Basic) -> tuple:
        key = (term, None)
        if key not in self._keys:
            self._keys[key] = self._make_term_key(term)
        return self._keys[key]

    def _make_term_key(self, term: sympy.Basic) -> tuple:
        factors = sympy.Mul.make_args(term)
        names = {s.name for s in term.free_symbols}
        has_qdd = any(n.endswith("_ddot") for n in names)
        params = [list(self.parameters).index(n) for n in names if n in self.parameters]
        count = sum(1 for f in factors if not f.is_Number)
        coords = [list(self.coordinates).index(_split_name(n)[0]) for n in names
                  if _split_name(n)[0] in self.coordinates]
        return (0 if has_qdd else 1 if self._leading_rate(term, names) else 2,
                min(params) if params else len(self.parameters), count,
                min(coords) if coords else len(self.coordinates), sympy.default_sort_key(term))

    def _leading_rate(self, term: sympy.Basic, names: set[str]) -> bool:
        """A positive term, free of parameters, linear in a rate or coordinate: ẋ, ẋ cosψ, x (not ẋ², −ẋ, r φ̇)."""
        if term.could_extract_minus_sign() or any(n in self.parameters for n in names):
            return False
        rates = [s for s in term.free_symbols
                 if _split_name(s.name)[1] in ("dot", "") and _split_name(s.name)[0] in self.coordinates]
        return any(term.is_polynomial(r) and sympy.degree(term, r) == 1 for r in rates)

    # -- rendering ---------------------------------------------------------------------------
    def _prepared(self, expr: object) -> sympy.Basic:
        e = _as_sympy(expr)
        return self.rewrite(e) if self.rewrite is not None else e

    def text(self, expr: sympy.Basic) -> str:
        """Write ``expr`` as terminal text, e.g. ``½ A (θ̇² + ψ̇² sin²θ)``.

        Parameters
        ----------
        expr : SymPy expression
            The expression.

        Returns
        -------
        str
            The text.
        """
        return self._render(self._prepared(expr), latex=False)

    def latex(self, expr: sympy.Basic) -> str:
        r"""Write ``expr`` in LaTeX.

        E.g. ``\frac{1}{2} A \left(\dot{\theta}^{2} + \dot{\psi}^{2} \sin^{2}\theta\right)``.

        Parameters
        ----------
        expr : SymPy expression
            The expression.

        Returns
        -------
        str
            The LaTeX.
        """
        return self._render(self._prepared(expr), latex=True)

    def sum(self, parts: Sequence[sympy.Basic], latex: bool = False) -> str:
        """Write ``parts`` one after the other with their signs (e.g. T then U in T + U).

        Parameters
        ----------
        parts : sequence of SymPy expressions
            The parts.
        latex : bool, optional
            LaTeX rather than text.

        Returns
        -------
        str
            The sum.
        """
        minus = "-" if latex else "−"
        out = ""
        for k, p in enumerate(parts):
            text = self._render(self._prepared(p), latex)
            if k == 0:
                out = text
            elif text.startswith(minus):
                out += f" {minus} " + text[len(minus):]
            else:
                out += " + " + text
        return out or "0"

    def terms(self, expr: sympy.Basic, latex: bool = False) -> list[str]:
        """The terms of a sum as `text` / `latex` write them, in the same order, each with its sign.

        The first term carries a sign only when negative; the others start with ``+`` or
        ``−`` (``-`` in LaTeX).  Joined with spaces they give the rendering of ``expr``;
        the report cuts long sums into lines with them.

        Parameters
        ----------
        expr : SymPy expression
            The sum.
        latex : bool, optional
            LaTeX rather than text.

        Returns
        -------
        list of str
            The terms.
        """
        e = self._prepared(expr)
        if not isinstance(e, sympy.Add):
            return [self._render(e, latex)]
        ordered = self._ordered(e)
        return [self._signed(ordered[0], latex, first=True)] + [
            self._signed(term, latex, first=False).strip() for term in ordered[1:]]

    def vector(self, terms: Sequence[tuple[sympy.Basic, str]], latex: bool = False) -> str:
        r"""A vector from (component, axis name) pairs: ``θ̇ u + ψ̇ sinθ w + (φ̇ + ψ̇ cosθ) z``.

        In LaTeX the axes carry arrows (``\vec{u}``); a digit suffix becomes a subscript (z0 → z_0).

        Parameters
        ----------
        terms : sequence of (SymPy expression, str)
            (component, axis name) pairs.
        latex : bool, optional
            LaTeX rather than text.

        Returns
        -------
        str
            The vector.
        """
        if not terms:
            return r"\vec{0}" if latex else "0"
        minus = "-" if latex else "−"
        out = ""
        for k, (c, axis) in enumerate(terms):
            c = self._prepared(c)
            if isinstance(c, sympy.Add):
                body, negative = self._factor(c, latex), False
            else:
                body = self._render(c, latex)
                negative = body.startswith(minus)
                body = body[len(minus):] if negative else body
            name = _axis_latex(axis) if latex else axis
            term = name if body == "1" else (rf"{body}\,{name}" if latex else f"{body} {name}")
            if k == 0:
                out = (minus if negative else "") + term
            else:
                out += (f" {minus} " if negative else " + ") + term
        return out

    def _render(self, e: sympy.Basic, latex: bool) -> str:
        if isinstance(e, sympy.Add):
            return self._add(e, latex)
        return self._signed(e, latex, first=True)

    def _ordered(self, e: sympy.Add) -> list[sympy.Basic]:
        """The terms of a sum in the order they are written; a sum of constants starts with a positive term
        (C − A, not −A + C), and a constant subtracted from the others comes last (x² + y² − l²)."""
        terms = sorted(e.args, key=self._term_key)
        if _is_negative(terms[0]) and all(s.name in self.parameters for s in e.free_symbols):
            first = next((k for k, t in enumerate(terms) if not _is_negative(t)), 0)
            terms.insert(0, terms.pop(first))
        elif (_is_negative(terms[0]) and all(s.name in self.parameters for s in terms[0].free_symbols)
              and not _is_negative(terms[1])):
            # A constant subtracted goes last: x² + y² − l², not −l² + x² + y².
            terms.append(terms.pop(0))
        return terms

    def _add(self, e: sympy.Add, latex: bool) -> str:
        terms = self._ordered(e)
        parts = [self._signed(terms[0], latex, first=True)]
        for term in terms[1:]:
            parts.append(self._signed(term, latex, first=False))
        return "".join(parts)

    def _signed(self, term: sympy.Basic, latex: bool, *, first: bool) -> str:
        coeff, rest = term.as_coeff_Mul()
        negative = coeff.is_negative if coeff.is_Number else False
        if negative:
            coeff = -coeff
        body = self._product(coeff, rest, latex)
        minus = "-" if latex else "−"
        if first:
            return (minus if negative else "") + body
        return (f" {minus} " if negative else " + ") + body

    def _product(self, coeff: sympy.Basic, rest: sympy.Basic, latex: bool) -> str:
        num, den = [], []
        for f in sympy.Mul.make_args(rest):
            if f == 1:
                continue
            if isinstance(f, sympy.Pow) and f.exp.is_Number and f.exp.is_negative:
                den.append(f.base if f.exp == -1 else sympy.Pow(f.base, -f.exp))
            else:
                num.append(f)
        self._sort_factors(num)
        self._sort_factors(den)
        if isinstance(coeff, sympy.Rational) and coeff.q != 1 and not den and self._decimal(coeff):
            head = [self._number(sympy.Float(coeff, 15), latex)]
        elif isinstance(coeff, sympy.Rational) and coeff.q != 1 and not den:
            p, q = int(coeff.p), int(coeff.q)
            if latex:
                c = rf"\frac{{{p}}}{{{q}}}"
            else:
                c = _FRACTIONS.get((p, q), f"{p}/{q}")
            head = [c]
        elif isinstance(coeff, sympy.Rational) and coeff.q != 1:
            head = [self._number(sympy.Integer(coeff.p), latex)] if coeff.p != 1 else []
            den.insert(0, sympy.Integer(coeff.q))
        else:
            head = [] if coeff == 1 else [self._number(coeff, latex)]
        num_parts = head + [self._factor(f, latex) for f in num]
        numerator = " ".join(num_parts) if num_parts else "1"
        if not den:
            return numerator
        den_parts = [self._factor(f, latex) for f in den]
        if latex:
            return rf"\frac{{{numerator}}}{{{' '.join(den_parts)}}}"
        denominator = den_parts[0] if len(den_parts) == 1 else "(" + " ".join(den_parts) + ")"
        if len(num_parts) > 1 and any(" + " in p or " − " in p for p in num_parts):
            numerator = numerator
        return f"{numerator}/{denominator}"

    def _decimal(self, r: sympy.Rational) -> bool:
        """Whether ``r`` is written as a decimal: in `decimals` mode, when its expansion is finite (½, not ⅓)."""
        if not self.decimals:
            return False
        q = int(r.q)
        for f in (2, 5):
            while q % f == 0:
                q //= f
        return q == 1

    def _number(self, n: sympy.Basic, latex: bool) -> str:
        if isinstance(n, sympy.Float):
            text = f"{float(n):.6g}" if self.comma or self.decimals else f"{float(n):.12g}"
            if "e" in text:  # 5e-05 → 5·10⁻⁵
                mantissa, _, exponent = text.partition("e")
                text = (rf"{mantissa} \cdot 10^{{{int(exponent)}}}" if latex
                        else f"{mantissa}·10{str(int(exponent)).translate(_SUPERSCRIPT)}")
            return text.replace(".", "{,}" if latex else ",") if self.comma else text
        if isinstance(n, sympy.Rational) and n.q != 1 and self._decimal(n):
            return self._number(sympy.Float(n, 15), latex)
        if n == sympy.pi:
            return r"\pi" if latex else "π"
        return str(n)

    def _factor(self, f: sympy.Basic, latex: bool) -> str:
        """One factor of a product: parenthesize sums."""
        if isinstance(f, sympy.Add):
            inner = self._add(f, latex)
            return rf"\left({inner}\right)" if latex else f"({inner})"
        return self._atom(f, latex)

    def _atom(self, f: sympy.Basic, latex: bool) -> str:
        if isinstance(f, Opaque):
            return f.latex_form if latex else f.text_form
        if isinstance(f, sympy.Symbol):
            return self.symbol(f.name, latex)
        if f.is_Number or f == sympy.pi:
            return self._number(f, latex)
        if isinstance(f, sympy.Pow):
            return self._power(f, latex)
        if isinstance(f, sympy.Piecewise):  # a Function whose arguments are (value, condition) pairs
            return self._piecewise(f, latex)
        if isinstance(f, sympy.Function):
            return self._function(f, latex)
        if isinstance(f, (sympy.Add, sympy.Mul)):
            inner = self._render(f, latex)
            return rf"\left({inner}\right)" if latex else f"({inner})"
        return sympy.latex(f) if latex else str(f)

    def _piecewise(self, f: sympy.Piecewise, latex: bool) -> str:
        """A function defined by cases (SymPy's simplification of sgn(v) makes one: 0 where v = 0)."""
        rows = []
        for value, condition in f.args:
            shown = self._render(value, latex)
            if condition == sympy.true:
                rows.append(rf"{shown} & \text{{otherwise}}" if latex else f"{shown} otherwise")
            else:
                rows.append(rf"{shown} & \text{{if }} {self._condition(condition, latex)}" if latex
                            else f"{shown} if {self._condition(condition, latex)}")
        if latex:
            return r"\begin{cases} " + r" \\ ".join(rows) + r" \end{cases}"
        return "{" + "; ".join(rows) + "}"

    def _condition(self, condition: sympy.Basic, latex: bool) -> str:
        if isinstance(condition, sympy.core.relational.Relational):
            op = {"==": "=", "!=": r"\neq" if latex else "≠", ">=": r"\geq" if latex else "≥",
                  "<=": r"\leq" if latex else "≤"}.get(condition.rel_op, condition.rel_op)
            return f"{self._render(condition.lhs, latex)} {op} {self._render(condition.rhs, latex)}"
        if isinstance(condition, (sympy.And, sympy.Or)):
            word = (r"\ \text{and}\ " if latex else " and ") if isinstance(condition, sympy.And) else \
                (r"\ \text{or}\ " if latex else " or ")
            return word.join(self._condition(c, latex) for c in condition.args)
        return sympy.latex(condition) if latex else str(condition)

    def _power(self, f: sympy.Pow, latex: bool) -> str:
        base, exp = f.base, f.exp
        if exp == sympy.Rational(1, 2):
            inner = self._render(base, latex)
            return rf"\sqrt{{{inner}}}" if latex else (f"√{inner}" if isinstance(base, sympy.Symbol) else f"√({inner})")
        if isinstance(exp, sympy.Integer):
            sup = rf"^{{{exp}}}" if latex else str(exp).translate(_SUPERSCRIPT)
        else:
            sup = rf"^{{{self._render(exp, latex)}}}" if latex else f"^({self._render(exp, False)})"
        if isinstance(base, sympy.Function) and isinstance(exp, sympy.Integer) and exp > 0:
            return self._function(base, latex, power=sup)
        if isinstance(base, (sympy.Add, sympy.Mul, sympy.Pow)) or (base.is_Number and base < 0):
            inner = self._render(base, latex)
            return (rf"\left({inner}\right){sup}" if latex else f"({inner}){sup}")
        return self._atom(base, latex) + sup

    def _function(self, f: sympy.Function, latex: bool, power: str = "") -> str:
        name = type(f).__name__
        name = _SYMPY_TO_NAME.get(name, name)
        if name == "Abs":
            inner = self._render(f.args[0], latex)
            return (rf"\left|{inner}\right|{power}" if latex else f"|{inner}|{power}")
        args = f.args
        # sgn(ẋ) keeps its parentheses: "sgn ẋ" reads as a product.
        simple = len(args) == 1 and isinstance(args[0], sympy.Symbol) and name != "sgn"
        # cos lat, not coslat: a symbol written as a word is set apart from the function's name.
        gap = (r"\," if latex else " ") if simple and _wordlike(args[0].name) and args[0].name not in self.names else ""
        if simple and not gap and self.symbol(args[0].name, latex)[:1].isascii() and \
                self.symbol(args[0].name, latex)[:1].isalpha():
            gap = " "  # \cos x_{1}, not the unknown command \cosx; cos x in text
        inner = ", ".join(self._render(a, latex) for a in args)
        if latex:
            head = rf"\{name}" if name in _LATEX_FUNCTIONS else rf"\operatorname{{{name}}}"
            if name == "exp" and not power:
                return rf"e^{{{inner}}}"
            return f"{head}{power}{gap}{inner}" if simple else rf"{head}{power}\left({inner}\right)"
        return f"{name}{power}{gap}{inner}" if simple else f"{name}{power}({inner})"
