"""The package's vector toolkit: vectors in the bases of several frames, and 3-component algebra.

A vector such as ``ψ̇ z0 + θ̇ u + φ̇ z`` is a `Vector`: a sum of *pieces*, one per frame,
each holding the three components in that frame's basis.  Nothing is converted to a
common basis until a dot or cross product needs it (that is the job of
`lagrangian.kinematics`), which keeps expressions as short as the course's.  A `Vector`
has only the linear operations (sum, product by a scalar, component-wise derivative):
they need no knowledge of how frames are oriented.

Components in one basis are 3-tuples of SymEngine expressions (`Components`), on which
kinematics and the recursive dynamics (Newton–Euler, the articulated-body algorithm) work
with `add3`, `cross`, `turn` and `turn_about`.  All of them form no product with a
structural zero (`is_structural_zero`) and add nothing to one: a chain of frames gives
the same expressions as the course, with fewer operations.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from fractions import Fraction

import symengine as se
from symengine.lib.symengine_wrapper import sympy2symengine

__all__ = ["AXES", "Components", "Vector", "add3", "as_expr", "cross", "is_structural_zero", "sum_of", "turn",
           "turn_about"]

#: Index of each axis letter in a frame's basis.
AXES = {"x": 0, "y": 1, "z": 2}

#: Three components of a vector in one frame's basis (x, y, z).
Components = tuple[se.Basic, se.Basic, se.Basic]

_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)


def is_structural_zero(expr: se.Basic) -> bool:
    """``expr == 0`` for a SymEngine expression, without the cost of ``==``.

    SymEngine's zero is a singleton of its own class, so this is a type test (about 40×
    faster than ``expr == 0``, which converts the 0 first).  Like ``==`` it is
    structural: ``0.0`` and ``x - x + 0.0`` are not zero here, ``x - x`` is.
    """
    return type(expr) is _ZERO_TYPE


def sum_of(terms: list[se.Basic]) -> se.Basic:
    """``se.Add(*terms)``, with no call into SymEngine for zero or one term (the same result)."""
    if len(terms) > 1:
        return se.Add(*terms)
    return terms[0] if terms else _ZERO


def as_expr(value: object) -> se.Basic:
    """Turn a number or a SymPy/SymEngine object into a SymEngine expression.

    Text is refused on purpose: model text is only ever read by the grammar in
    `lagrangian.model.parse_expression`, never handed to a converter that could
    evaluate it.
    """
    if isinstance(value, se.Basic):
        return value
    if isinstance(value, (str, bytes)):
        raise TypeError(
            "text is not an expression here; parse it with lagrangian.model.parse_expression"
        )
    if isinstance(value, bool):
        raise TypeError("a boolean is not an expression")
    if isinstance(value, int):
        return se.Integer(value)
    if isinstance(value, Fraction):
        return se.Rational(value.numerator, value.denominator)
    if isinstance(value, float):
        return se.RealDouble(value)
    if hasattr(value, "_sympy_") or type(value).__module__.startswith("sympy"):
        return sympy2symengine(value)
    raise TypeError(f"cannot use a {type(value).__name__} as an expression")



def add3(a: Components, b: Components) -> Components:
    """a + b component-wise, adding nothing to a zero (x + 0 is x: the same expressions)."""
    return tuple(y if type(x) is _ZERO_TYPE else x if type(y) is _ZERO_TYPE else x + y
                 for x, y in zip(a, b, strict=True))


def cross(a: Components, b: Components) -> Components:
    """a ∧ b, forming no product with a zero factor (the same expressions, fewer operations)."""
    nz_a = [type(x) is not _ZERO_TYPE for x in a]
    nz_b = [type(x) is not _ZERO_TYPE for x in b]
    out = []
    for _i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):  # component i of a ∧ b
        plus = nz_a[j] and nz_b[k]
        minus = nz_a[k] and nz_b[j]
        if plus and minus:
            out.append(a[j] * b[k] - a[k] * b[j])
        elif plus:
            out.append(a[j] * b[k])
        elif minus:
            out.append(-(a[k] * b[j]))
        else:
            out.append(_ZERO)
    return tuple(out)


def turn(axis: int, c: se.Basic, s: se.Basic, v: Components) -> Components:
    """Components in the parent of a vector with components ``v`` in the child.

    The child is the parent turned about their common ``axis`` by the angle whose cosine
    and sine are ``c`` and ``s``; products with a zero component are not formed.
    """
    i, j = (axis + 1) % 3, (axis + 2) % 3
    vi, vj = v[i], v[j]
    zi, zj = is_structural_zero(vi), is_structural_zero(vj)
    if zi and zj:
        return v
    out = list(v)
    if zj:
        out[i], out[j] = c * vi, s * vi
    elif zi:
        out[i], out[j] = -s * vj, c * vj
    else:
        out[i], out[j] = c * vi - s * vj, s * vi + c * vj
    return tuple(out)


def turn_about(n: Components, c: se.Basic, s: se.Basic, v: Components) -> Components:
    """`turn` about the unit vector ``n`` (the same components in child and parent): Rodrigues' formula.

    R v = c v + s n ∧ v + (1 − c)(n·v) n, the rotation of angle α (cos α = c, sin α = s)
    about n (e.g. Goldstein, Classical Mechanics, eq. 4.92).
    """
    if all(is_structural_zero(x) for x in v):
        return v
    n_v = sum_of([a * b for a, b in zip(n, v, strict=True) if not is_structural_zero(a) and not is_structural_zero(b)])
    turned = cross(n, v)
    along = (1 - c) * n_v
    return tuple(sum_of([t for t in (c * x, s * w, along * a) if not is_structural_zero(t)])
                 for x, w, a in zip(v, turned, n, strict=True))

class Vector:
    """An immutable sum of pieces ``{frame name: (c_x, c_y, c_z)}``.

    Parameters
    ----------
    pieces : mapping of str to tuple of three SymEngine expressions, optional
        Frame name to its components (c_x, c_y, c_z) in that frame's basis; None: the zero vector.

    Examples
    --------
    >>> import symengine as se
    >>> a = se.Symbol("a")
    >>> v = Vector.basis("R", "z") * a
    >>> (v + v).pieces
    {'R': (0, 0, 2*a)}
    """

    __slots__ = ("_pieces",)
    _pieces: dict[str, tuple[se.Basic, se.Basic, se.Basic]]

    def __init__(self, pieces: Mapping[str, tuple[se.Basic, se.Basic, se.Basic]] | None = None):
        cleaned: dict[str, tuple[se.Basic, se.Basic, se.Basic]] = {}
        for frame, comps in (pieces or {}).items():
            comps = tuple(as_expr(c) for c in comps)
            if len(comps) != 3:
                raise ValueError("a vector piece has exactly three components")
            if any(type(c) is not _ZERO_TYPE for c in comps):
                cleaned[frame] = comps
        object.__setattr__(self, "_pieces", cleaned)

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("Vector is immutable")

    # -- construction -------------------------------------------------------------
    @classmethod
    def basis(cls, frame: str, axis: str) -> Vector:
        """The unit vector ``frame.axis`` (axis is ``x``, ``y`` or ``z``).

        Parameters
        ----------
        frame : str
            The frame's name.
        axis : str
            ``x``, ``y`` or ``z``.

        Returns
        -------
        Vector
            The unit vector.
        """
        comps = [_ZERO, _ZERO, _ZERO]
        comps[AXES[axis]] = se.Integer(1)
        return cls({frame: tuple(comps)})

    @classmethod
    def zero(cls) -> Vector:
        return cls()

    @classmethod
    def _trusted(cls, pieces: dict[str, tuple[se.Basic, se.Basic, se.Basic]]) -> Vector:
        """The vector of ``pieces`` whose components are already three SymEngine expressions.

        What ``Vector(pieces)`` gives, without converting and checking each component
        (the kinematics builds thousands of vectors from its own results); zero pieces
        are dropped all the same.
        """
        v = object.__new__(cls)
        z = _ZERO_TYPE
        object.__setattr__(v, "_pieces", {f: c for f, c in pieces.items()
                                          if not (type(c[0]) is z and type(c[1]) is z and type(c[2]) is z)})
        return v

    # -- access ---------------------------------------------------------------------
    @property
    def pieces(self) -> dict[str, tuple[se.Basic, se.Basic, se.Basic]]:
        """A copy of the pieces, frame name to its three components."""
        return dict(self._pieces)

    @property
    def frames(self) -> tuple[str, ...]:
        return tuple(self._pieces)

    def __iter__(self) -> Iterator[tuple[str, tuple[se.Basic, se.Basic, se.Basic]]]:
        return iter(self._pieces.items())

    def is_zero(self) -> bool:
        """Structural test: no piece has a non-zero component.

        Returns
        -------
        bool
            True when every component is structurally zero (a vector that simplifies to zero may say False).
        """
        return not self._pieces

    def free_symbols(self) -> set[se.Symbol]:
        out: set[se.Symbol] = set()
        for comps in self._pieces.values():
            for c in comps:
                out |= c.free_symbols
        return out

    # -- linear algebra -------------------------------------------------------------
    def __add__(self, other: Vector) -> Vector:
        if not isinstance(other, Vector):
            return NotImplemented
        out = dict(self._pieces)
        for frame, comps in other._pieces.items():
            if frame in out:
                out[frame] = tuple(a + b for a, b in zip(out[frame], comps, strict=True))
            else:
                out[frame] = comps
        return Vector._trusted(out)

    def __neg__(self) -> Vector:
        return self._map(lambda c: -c)

    def __sub__(self, other: Vector) -> Vector:
        if not isinstance(other, Vector):
            return NotImplemented
        return self + (-other)

    def __mul__(self, scalar: object) -> Vector:
        if isinstance(scalar, Vector):
            return NotImplemented
        s = as_expr(scalar)
        z = _ZERO_TYPE
        return Vector._trusted({f: tuple(c if type(c) is z else s * c for c in comps)
                                for f, comps in self._pieces.items()})

    __rmul__ = __mul__

    def __truediv__(self, scalar: object) -> Vector:
        s = as_expr(scalar)
        return self._map(lambda c: c / s)

    def map(self, fn: Callable[[se.Basic], se.Basic]) -> Vector:
        """Apply ``fn`` to every component, piece by piece.

        Parameters
        ----------
        fn : callable
            Applied to each SymEngine component.

        Returns
        -------
        Vector
            The vector of the results.
        """
        return Vector({f: tuple(fn(c) for c in comps) for f, comps in self._pieces.items()})

    def _map(self, fn: Callable[[se.Basic], se.Basic]) -> Vector:
        # `map` for an ``fn`` known to return SymEngine expressions.
        return Vector._trusted({f: tuple(fn(c) for c in comps)
                                for f, comps in self._pieces.items()})

    def diff(self, symbol: se.Symbol) -> Vector:
        """Component-wise partial derivative (the basis vectors are held fixed).

        Parameters
        ----------
        symbol : SymEngine Symbol
            The variable.

        Returns
        -------
        Vector
            The derivative, the basis vectors held fixed.
        """
        return self._map(lambda c: c.diff(symbol))

    def subs(self, mapping: Mapping[se.Basic, se.Basic]) -> Vector:
        return self._map(lambda c: c.subs(mapping))

    # -- comparison and display -----------------------------------------------------
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Vector):
            return NotImplemented
        return bool(self._pieces == other._pieces)

    def __hash__(self) -> int:
        return hash(tuple(sorted((f, c) for f, c in self._pieces.items())))

    def __repr__(self) -> str:
        if not self._pieces:
            return "0"
        terms = []
        for frame, comps in self._pieces.items():
            for axis, c in zip("xyz", comps, strict=True):
                if c != 0:
                    terms.append(f"({c})*{frame}.{axis}")
        return " + ".join(terms)
