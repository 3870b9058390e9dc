"""Small motions in closed form: the linearized equations and the pulsations in the parameters' letters.

Two cases the numeric linearization cannot write in letters:

* **A point given by a closed-form equilibrium** that holds only for some values, such as the bead
  on the hoop turning at Ω, cos θ0 = g/(R Ω²) (`equilibria`: it exists iff R Ω² > g).  The point
  is written with a symbol θ0 and its defining relation, one parameter of that relation is
  eliminated (g = R Ω² cos θ0), and the second-order form at rest,

      M0 = M(q0),  D + G = −∂F/∂q̇ |0,  K + N = −∂F/∂q |0        (M q̈ = F, no constraint, no input),

  simplified: the bead's K = m R² Ω² sin²θ0, hence ω0² = Ω² sin²θ0.
* **Pulsations**: for a conservative form (D = G = N = 0) of at most `MAX_DEGREE` coordinates, the
  nonzero roots ω² of det(K − ω² M) = 0 (a polynomial in ω² of that degree), each simplified: the
  cart's inverted pendulum hanging, ω² = (mc + m) g/(mc l).

Parameters whose value is positive are assumed positive while simplifying.  Everything is SymPy on
the engine's expressions converted structurally (``_sympy_()``); no text is parsed.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy

from ..dynamics import EquationsOfMotion

__all__ = ["ClosedPoint", "closed_point", "pulsations_squared"]

#: Most coordinates for which det(K − ω² M) = 0 is solved in letters.
MAX_DEGREE = 2
#: Longest simplified pulsation (characters of its text) given in letters.
MAX_CHARS = 200
#: Seconds SymPy may spend on a closed form before the numbers are shown instead.
TIMEOUT = 5.0


@dataclass(frozen=True)
class ClosedPoint:
    """The equilibrium as a closed form: ``values`` (coordinate → SymPy expression, with ``symbols`` such as
    θ0 for the coordinates defined implicitly), ``relations`` (θ0 → cos θ0 = g/(R Ω²)), ``definitions``
    (θ0 → its value, acos(g/(R Ω²))), ``eliminated`` (g → R Ω² cos θ0), ``condition`` (of existence, or
    None) and the second-order form at rest, ``M, D, G, K, N`` (SymPy matrices in ``coordinates``)."""

    coordinates: tuple[str, ...]
    values: dict[str, sympy.Basic]
    symbols: dict[str, sympy.Symbol]
    relations: dict[str, sympy.Basic]
    definitions: dict[str, sympy.Basic]
    eliminated: dict[sympy.Symbol, sympy.Basic]
    condition: sympy.Basic | None
    M: sympy.Matrix
    D: sympy.Matrix
    G: sympy.Matrix
    K: sympy.Matrix
    N: sympy.Matrix


def _with_timeout(work):
    """``work()`` in a daemon thread, or None after `TIMEOUT` seconds (SymPy cannot be interrupted)."""
    out: list = []

    def run() -> None:
        try:
            out.append(work())
        except Exception:  # noqa: BLE001 - any SymPy failure: the numbers are shown instead
            out.append(None)

    th = threading.Thread(target=run, daemon=True)
    th.start()
    th.join(TIMEOUT)
    return out[0] if out else None


def _assumed(eom: EquationsOfMotion, values: Mapping[str, float]) -> dict[sympy.Symbol, sympy.Symbol]:
    """Plain parameter symbols → the same symbols assumed positive where the value is."""
    return {sympy.Symbol(p.name): sympy.Symbol(p.name, positive=True) for p in eom.model.parameters
            if (value := values.get(p.name, p.value)) is not None and value > 0}


def _simplify(e: sympy.Basic, positive: Mapping, back: Mapping) -> sympy.Basic:
    e = sympy.Integer(e) if isinstance(e, int) else e  # Matrix entries are SymPy objects, or 0
    x = sympy.factor(sympy.trigsimp(sympy.cancel(e.xreplace(positive))))
    return x.xreplace(back)


def closed_point(eom: EquationsOfMotion, point: Mapping[str, float], values: Mapping[str, float]) -> ClosedPoint | None:
    """The closed-form equilibrium at ``point`` (numbers) and the second-order form there in letters, or None.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    point : mapping of str to float
        A numeric equilibrium, coordinate name to value.
    values : mapping of str to float
        The parameter values.

    Returns
    -------
    ClosedPoint or None
        None when there is no closed-form branch there, the model has constraints or inputs, or
        SymPy fails within `TIMEOUT`.
    """
    from ._equilibria import equilibria

    if eom.constraints or getattr(eom.model, "inputs", ()):
        return None
    try:
        found = equilibria(eom, parameters=dict(values), numeric=False)
    except Exception:  # noqa: BLE001 - no closed form then
        return None
    names = list(eom.coordinates)
    match = next((e for e in found if e.closed_form and not e.free and e.numeric is not None
                  and all(abs(e.numeric[c] - point[c]) <= 1e-9 * (1 + abs(point[c])) for c in names)), None)
    if match is None or all(not match.values[c].free_symbols for c in names):
        return None
    return _with_timeout(lambda: _build(eom, match, values))


def _build(eom: EquationsOfMotion, match, values: Mapping[str, float]) -> ClosedPoint | None:
    names = list(eom.coordinates)
    positive = _assumed(eom, values)
    back = {v: k for k, v in positive.items()}
    qvals: dict[str, sympy.Basic] = {}
    symbols: dict[str, sympy.Symbol] = {}
    relations: dict[str, sympy.Basic] = {}
    definitions: dict[str, sympy.Basic] = {}
    eliminated: dict[sympy.Symbol, sympy.Basic] = {}
    for c in names:
        v = match.values[c]._sympy_()
        inner = v if not isinstance(-v, (sympy.acos, sympy.asin)) else -v
        if isinstance(inner, (sympy.acos, sympy.asin)) and inner.args[0].free_symbols:
            s = sympy.Symbol(f"{c}_0", real=True)
            u = inner.args[0]
            trig = sympy.cos if isinstance(inner, sympy.acos) else sympy.sin
            relations[c] = sympy.Eq(trig(s), u)
            symbols[c], definitions[c], qvals[c] = s, v, s
            # eliminate one parameter of u, preferably one it is proportional to (g in g/(R Ω²): g = R Ω² cos θ0)
            num, den = sympy.fraction(sympy.together(u))

            def rank(x: sympy.Symbol, num: sympy.Expr = num, den: sympy.Expr = den) -> tuple:
                linear = x not in den.free_symbols and sympy.degree(num, x) == 1
                return (not linear, str(x) not in values, str(x))

            for p in sorted(u.free_symbols, key=rank):
                sol = sympy.solve(sympy.Eq(trig(s), u), p)
                if len(sol) == 1 and not sol[0].has(sympy.I):
                    eliminated[p] = sol[0]
                    break
        else:
            qvals[c] = v
    if not relations:
        return None
    q = [sympy.Symbol(c) for c in names]
    qd = [sympy.Symbol(c + "_dot") for c in names]
    at = {**{s: qvals[c] for s, c in zip(q, names, strict=True)}, **{s: 0 for s in qd}}
    F = sympy.Matrix([f._sympy_() for f in eom.F])
    M = sympy.Matrix([[e._sympy_() for e in row] for row in eom.M])

    def at_point(m: sympy.Matrix) -> sympy.Matrix:
        return m.xreplace(at).xreplace(eliminated).applyfunc(lambda e: _simplify(e, positive, back))

    M0 = at_point(M)
    Kf = at_point(-F.jacobian(q))
    Df = at_point(-F.jacobian(qd))
    D, G = (Df + Df.T) / 2, (Df - Df.T) / 2
    K, N = (Kf + Kf.T) / 2, (Kf - Kf.T) / 2

    def simp(m: sympy.Matrix) -> sympy.Matrix:
        return m.applyfunc(lambda e: _simplify(e, positive, back))

    return ClosedPoint(tuple(names), qvals, symbols, relations, definitions, eliminated, match.condition, simp(M0),
                       simp(D), simp(G), simp(K), simp(N))


def pulsations_squared(M: sympy.Matrix, K: sympy.Matrix, positive: Sequence[str] = ()) -> list[sympy.Basic] | None:
    """The nonzero roots ω² of det(K − ω² M) = 0 in letters, or None when the form is too large or a root too long.

    Parameters
    ----------
    M : sympy.Matrix
        The mass matrix of the small motions.
    K : sympy.Matrix
        Their stiffness matrix.
    positive : sequence of str, optional
        Names of symbols known to be positive.

    Returns
    -------
    list of SymPy expressions or None
        The roots, in the order SymPy gives (their order at the parameters' generic values is not
        decided), or None.
    """
    n = M.shape[0]
    if n == 0 or n > MAX_DEGREE:
        return None
    assumed = {sympy.Symbol(p): sympy.Symbol(p, positive=True) for p in positive}
    back = {v: k for k, v in assumed.items()}

    def work() -> list[sympy.Basic] | None:
        w2 = sympy.Symbol("omega2")
        poly = sympy.factor(sympy.cancel((K - w2 * M).xreplace(assumed).det()))
        roots = [r for r in sympy.solve(poly, w2) if r != 0]
        out = [_simplify(r, {}, back) for r in roots]
        return out if out and all(len(str(r)) <= MAX_CHARS for r in out) else None

    return _with_timeout(work)

