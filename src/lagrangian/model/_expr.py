"""The safe expression grammar of model files.

Model files come from strangers, so their text is never evaluated: it is read by
this small recursive-descent parser, which knows only numbers, declared names, the
operators ``+ - * / ^ **``, parentheses, a fixed list of functions and the basis
vectors ``R.x``, ``R.y``, ``R.z`` of declared frames.  Grammar (``^`` and ``**`` bind
tighter than unary minus and associate to the right, so ``-x^2`` is ``-(x^2)``)::

    expr    := term (('+' | '-') term)*
    term    := unary (('*' | '/') unary)*
    unary   := ('+' | '-') unary | power
    power   := atom (('^' | '**') unary)?
    atom    := NUMBER | NAME | NAME '.' AXIS | FUNC '(' expr ')' | '(' expr ')'

Every value is either a scalar (a SymEngine expression) or a `Vector`; the parser
checks the types (no vector in a sine, no product of two vectors) and reports each
mistake with its column.  Decimal numbers are read exactly (``0.1`` is 1/10) so that
symbolic results stay exact.

Reading is linear in the length of the text, and what an expression may cost is
limited (`_limits`): its length, its effective degree, its size once multiplied out,
and every constant in it must be a finite real double.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Collection, Mapping
from dataclasses import dataclass
from fractions import Fraction

import symengine as se

from ._limits import MAX_DEGREE, MAX_LENGTH, MAX_TERMS, Measure, NotFinite, TooLarge, excerpt, real_value
from .vectors import AXES, Vector

__all__ = ["FUNCTIONS", "ExpressionError", "parse_expression"]

#: The only functions a model file may call.
FUNCTIONS: dict[str, Callable[[se.Basic], se.Basic]] = {
    "sin": se.sin,
    "cos": se.cos,
    "tan": se.tan,
    "asin": se.asin,
    "acos": se.acos,
    "atan": se.atan,
    "sinh": se.sinh,
    "cosh": se.cosh,
    "tanh": se.tanh,
    "exp": se.exp,
    "log": se.log,
    "sqrt": se.sqrt,
    "abs": se.Abs,
}

#: Largest numeric exponent accepted (guards against `9^9^9` in untrusted files).
MAX_EXPONENT = 1000
#: Largest number of bits of a number a power may produce (about 10,000 decimal digits),
#: so that `((9^999)^999)^999` is refused before it is computed.
MAX_BITS = 33_000
#: Longest number literal, in characters (`1e99999999` would take minutes to read exactly).
MAX_LITERAL = 100

#: Names with a fixed meaning in every model.
CONSTANTS: dict[str, se.Basic] = {"pi": se.pi}

_TOKEN = re.compile(
    r"(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>\*\*|[-+*/^().,])",
    re.ASCII,
)
_SPACE = re.compile(r"\s*")


class ExpressionError(ValueError):
    """A mistake in an expression, with the 1-based column it was found at.

    Parameters
    ----------
    message : str
        What was wrong.
    column : int
        The 1-based column of the mistake in the expression.
    symbol : str, optional
        The offending name, when there is one.
    fix : str, optional
        How to fix it.
    """

    def __init__(self, message: str, column: int, *, symbol: str | None = None, fix: str | None = None):
        super().__init__(message)
        self.message = message
        self.column = column
        self.symbol = symbol
        self.fix = fix


@dataclass(frozen=True, slots=True)
class _Token:
    kind: str  # "number", "name", "op" or "end"
    text: str
    column: int  # 1-based


def _tokenize(text: str) -> list[_Token]:
    """The tokens of ``text``, in one pass (linear in its length)."""
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"the expression has {len(text):,} characters, more than the {MAX_LENGTH:,} allowed",
                              MAX_LENGTH + 1, fix="shorten it: name repeated parts as parameters, points or "
                              "separate loads")
    tokens: list[_Token] = []
    pos = _SPACE.match(text).end()  # type: ignore[union-attr]
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None:
            raise ExpressionError(
                f"unexpected character `{text[pos]}`",
                pos + 1,
                fix="expressions may use numbers, declared names, + - * / ^ ** and parentheses",
            )
        kind = match.lastgroup or "op"
        tokens.append(_Token(kind, match.group(kind), pos + 1))
        pos = _SPACE.match(text, match.end()).end()  # type: ignore[union-attr]
    tokens.append(_Token("end", "", len(text) + 1))
    return tokens


class _Parser:
    def __init__(self, text: str, names: Mapping[str, se.Basic], frames: Collection[str]):
        self.text = text
        self.names = names
        self.frames = frames
        self.tokens = _tokenize(text)
        self.i = 0
        self.measure = Measure()

    # -- token helpers --------------------------------------------------------------
    @property
    def tok(self) -> _Token:
        return self.tokens[self.i]

    def _advance(self) -> _Token:
        tok = self.tokens[self.i]
        self.i += 1
        return tok

    def _expect(self, text: str) -> _Token:
        if self.tok.text != text:
            found = "the end of the expression" if self.tok.kind == "end" else f"`{self.tok.text}`"
            fix = "close every `(` with a `)`" if text == ")" else f"write `{text}` here"
            raise ExpressionError(f"expected `{text}` but found {found}", self.tok.column, fix=fix)
        return self._advance()

    # -- grammar --------------------------------------------------------------------
    def parse(self) -> se.Basic | Vector:
        if self.tok.kind == "end":
            raise ExpressionError("the expression is empty", 1, fix="write a number or an expression")
        value = self.expr()
        if self.tok.kind != "end":
            raise ExpressionError(
                f"unexpected `{self.tok.text}` after a complete expression",
                self.tok.column,
                fix="an operator such as `*` may be missing",
            )
        for component in _components(value):  # sums are checked here, once (not at each `+`)
            self._checked(component, 1, constants=True)
        return value

    def _since(self, column: int) -> str:
        """The text from ``column`` to the end of the last token read (what the user wrote)."""
        last = self.tokens[self.i - 1]
        return self.text[column - 1:last.column - 1 + len(last.text)]

    def _checked(self, value: se.Basic | Vector, column: int, *, constants: bool = False,
                 written: str | None = None) -> se.Basic | Vector:
        """``value`` once it is within the limits of `_limits` (size, degree, finite real constants).

        ``constants`` walks the whole expression for constant parts; otherwise only
        ``value`` itself is checked when it is constant (its parts were, as they were read).
        ``written`` is the text ``value`` was read from, for the message.
        """
        if isinstance(value, Vector):
            return value
        try:
            self.measure(value)
            if constants:
                _check_constants(value)
            elif not value.free_symbols:
                real_value(value)
        except TooLarge as exc:
            raise ExpressionError(str(exc), column, fix=f"write a smaller expression: the degree of an "
                                  f"expression is limited to {MAX_DEGREE} and its size to {MAX_TERMS} terms once "
                                  "multiplied out") from None
        except NotFinite as exc:
            shown = excerpt(written or str(value), width=60)
            raise ExpressionError(f"`{shown}` is not a finite real number: {exc}", column,
                                  fix="correct the constant: every constant must be a real number that a double "
                                  "holds (0, or between about 5e-324 and 1.8e308 in absolute value)") from None
        return value

    def expr(self) -> se.Basic | Vector:
        value = self.term()
        while self.tok.text in ("+", "-"):
            op = self._advance()
            rhs = self.term()
            value = self._combine(op, value, rhs)
        return value

    def term(self) -> se.Basic | Vector:
        value = self.unary()
        while self.tok.text in ("*", "/"):
            op = self._advance()
            rhs = self.unary()
            value = self._combine(op, value, rhs)
        return value

    def unary(self) -> se.Basic | Vector:
        if self.tok.text in ("+", "-"):
            op = self._advance()
            value = self.unary()
            return -value if op.text == "-" else value
        return self.power()

    def power(self) -> se.Basic | Vector:
        start = self.tok.column
        base = self.atom()
        if self.tok.text in ("^", "**"):
            op = self._advance()
            exponent = self.unary()
            if isinstance(base, Vector) or isinstance(exponent, Vector):
                raise ExpressionError("a vector cannot be raised to a power", op.column,
                                      fix="write the scalar expression, e.g. `l^2`, not a vector")
            if exponent.is_Number:
                # A stranger's `9^9^9` must not hang the parser on integer arithmetic.
                if abs(float(exponent)) > MAX_EXPONENT:
                    raise ExpressionError(f"the exponent `{_short(exponent)}` is too large", op.column,
                                          fix=f"exponents are limited to {MAX_EXPONENT} in absolute value")
                if _bits(base) * abs(exponent.get_num_den()[0] if exponent.is_Rational else 1) > MAX_BITS:
                    raise ExpressionError(f"the power `{_short(base)}^{_short(exponent)}` is too large a number",
                                          op.column, fix="write a smaller number, or keep it symbolic")
                if base == 0 and exponent.is_negative:
                    raise ExpressionError("division by zero: `0` raised to a negative power", op.column,
                                          fix="correct the exponent or the base")
            return self._checked(base**exponent, op.column, written=self._since(start))
        return base

    def atom(self) -> se.Basic | Vector:
        tok = self._advance()
        if tok.kind == "number":
            return _exact_number(tok)
        if tok.text == "(":
            value = self.expr()
            self._expect(")")
            return value
        if tok.kind == "name":
            if self.tok.text == "(":
                return self._call(tok)
            if self.tok.text == ".":
                return self._basis_vector(tok)
            if tok.text in self.names:
                return self.names[tok.text]
            if tok.text in CONSTANTS:
                return CONSTANTS[tok.text]
            if tok.text in self.frames:
                raise ExpressionError(
                    f"`{tok.text}` is a frame, not a scalar", tok.column, symbol=tok.text,
                    fix=f"write one of its basis vectors, `{tok.text}.x`, `{tok.text}.y` or `{tok.text}.z`",
                )
            raise ExpressionError(
                f"unknown symbol `{tok.text}`", tok.column, symbol=tok.text,
                fix=f"declare `{tok.text}` under [parameters] or [coordinates], or correct its spelling",
            )
        found = "the end of the expression" if tok.kind == "end" else f"`{tok.text}`"
        raise ExpressionError(f"expected a number, a name or `(` but found {found}", tok.column,
                              fix="an operand may be missing, e.g. `a*` should be `a*b`")

    def _call(self, name: _Token) -> se.Basic:
        fn = FUNCTIONS.get(name.text)
        if fn is None:
            raise ExpressionError(
                f"unknown function `{name.text}`", name.column, symbol=name.text,
                fix="the functions allowed are " + ", ".join(sorted(FUNCTIONS)),
            )
        self._expect("(")
        arg = self.expr()
        if self.tok.text == ",":
            raise ExpressionError(f"`{name.text}` takes one argument", self.tok.column, symbol=name.text,
                                  fix=f"write `{name.text}(x)` with a single argument")
        self._expect(")")
        if isinstance(arg, Vector):
            raise ExpressionError(f"`{name.text}` of a vector is not defined", name.column, symbol=name.text,
                                  fix="apply functions to scalars only")
        value = fn(arg)
        if value.has(se.zoo) or value.has(se.nan):
            raise ExpressionError(f"`{name.text}({excerpt(str(arg), width=60)})` is not defined (it is infinite)",
                                  name.column, symbol=name.text, fix="correct the argument")
        return self._checked(value, name.column, written=self._since(name.column))

    def _basis_vector(self, frame: _Token) -> Vector:
        self._advance()  # the dot
        axis = self._advance()
        if frame.text not in self.frames:
            if frame.text in self.names or frame.text in CONSTANTS:
                raise ExpressionError(
                    f"`{frame.text}` is a scalar, not a frame: only frames have basis vectors such as `R0.x`",
                    frame.column, symbol=frame.text, fix=f"remove `.{axis.text}`, or name a declared frame",
                )
            raise ExpressionError(
                f"unknown frame `{frame.text}` in `{frame.text}.{axis.text}`", frame.column, symbol=frame.text,
                fix="declare the frame under [frames] (R0 is the Galilean frame), or correct its name",
            )
        if axis.text not in AXES:
            found = "nothing" if axis.kind == "end" else f"`{axis.text}`"
            raise ExpressionError(
                f"frame `{frame.text}` has the axes x, y and z, but `{frame.text}.` is followed by {found}",
                axis.column, symbol=axis.text or frame.text,
                fix=f"write `{frame.text}.x`, `{frame.text}.y` or `{frame.text}.z`",
            )
        return Vector.basis(frame.text, axis.text)

    # -- typed arithmetic -------------------------------------------------------------
    def _combine(self, op: _Token, lhs: se.Basic | Vector, rhs: se.Basic | Vector) -> se.Basic | Vector:
        lv, rv = isinstance(lhs, Vector), isinstance(rhs, Vector)
        if op.text in "+-":
            if lv != rv:
                raise ExpressionError(
                    f"cannot {'add' if op.text == '+' else 'subtract'} a vector and a scalar", op.column,
                    fix="every term of a vector expression must be a vector, e.g. `a*R.z`",
                )
            return lhs + rhs if op.text == "+" else lhs - rhs
        if op.text == "*":
            if lv and rv:
                raise ExpressionError("the product of two vectors is not defined here", op.column,
                                      fix="multiply each basis vector by a scalar, e.g. `l*sin(q)*R0.x`")
            # The vector on the left: SymEngine's `*` with a vector on its right would first try to
            # convert it through SymPy (importing it: most of a second) before giving the vector its turn.
            return self._checked(rhs * lhs if rv else lhs * rhs, op.column)
        # division
        if rv:
            raise ExpressionError("cannot divide by a vector", op.column,
                                  fix="divide by a scalar only, e.g. `(a*R.x)/2`")
        if rhs == 0:
            raise ExpressionError("division by zero", op.column, fix="correct the denominator")
        return self._checked(lhs / rhs, op.column)


def _exact_number(tok: _Token) -> se.Basic:
    """The exact value of a number literal: ``0.1`` is 1/10, ``1e-3`` is 1/1000."""
    exponent = tok.text.lower().partition("e")[2]
    if len(tok.text) > MAX_LITERAL or (exponent and abs(int(exponent)) > MAX_EXPONENT):
        raise ExpressionError(f"the number `{_short(tok.text)}` is too large or too long", tok.column,
                              fix=f"numbers may have at most {MAX_LITERAL} characters and a power of ten "
                              f"of at most {MAX_EXPONENT} in absolute value")
    value = Fraction(tok.text)
    try:
        real_value(value)
    except NotFinite as exc:
        raise ExpressionError(f"the number `{_short(tok.text)}` is not a finite double: {exc}", tok.column,
                              fix="write a number that a double holds: 0, or between about 5e-324 and 1.8e308 "
                                  "in absolute value") from None
    if value.denominator == 1:
        return se.Integer(value.numerator)
    return se.Rational(value.numerator, value.denominator)


def _components(value: se.Basic | Vector) -> list[se.Basic]:
    """The scalar ``value``, or the components of the vector ``value``."""
    if isinstance(value, Vector):
        return [c for comps in value.pieces.values() for c in comps]
    return [value]


def _check_constants(value: se.Basic) -> None:
    """Each largest constant part of ``value`` must be a finite real double (`real_value`)."""
    stack, seen = [value], set()
    while stack:
        e = stack.pop()
        if e in seen:
            continue
        seen.add(e)
        if e.free_symbols:
            stack.extend(e.args)
        else:
            real_value(e)


def _bits(value: se.Basic) -> int:
    """The size in bits of the largest number in ``value`` (at least 1)."""
    if value.is_Rational:
        return max(1, *(abs(int(n)).bit_length() for n in value.get_num_den()))
    return max((_bits(a) for a in value.args), default=1)


def _short(value: object, width: int = 24) -> str:
    """``value`` as text, cut in the middle when it is long (a huge number in a message)."""
    text = str(value)
    return text if len(text) <= width else f"{text[:10]}...{text[-10:]}"


def parse_expression(
    text: str,
    names: Mapping[str, se.Basic],
    frames: Collection[str] = (),
) -> se.Basic | Vector:
    """Parse ``text`` into a SymEngine scalar or a `Vector`, without evaluating it.

    Parameters
    ----------
    text : str
        The expression, e.g. ``"a*R.z"`` or ``"m*g*l*(1 - cos(theta))"``.
    names : mapping of str to SymEngine expression
        The declared scalar names (parameters, coordinates, their rates, ``t``).
    frames : collection of str, optional
        The declared frame names, whose basis vectors ``F.x``, ``F.y``, ``F.z`` may be used.

    Returns
    -------
    SymEngine expression or Vector
        The expression as written (a vector when it uses basis vectors).

    Raises
    ------
    ExpressionError
        With the 1-based column of the mistake and, when there is one, the symbol.

    Examples
    --------
    >>> import symengine as se
    >>> a = se.Symbol("a")
    >>> parse_expression("2^-1*a", {"a": a}) == a / 2
    True
    """
    if not isinstance(text, str):
        raise TypeError("parse_expression reads text only")
    try:
        return _Parser(text, names, frames).parse()
    except RecursionError:
        raise ExpressionError("the expression is nested too deeply", 1,
                              fix="split it, or remove redundant parentheses") from None
