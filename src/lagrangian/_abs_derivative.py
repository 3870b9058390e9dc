"""d|u|/dx written sign(u) du/dx, where SymEngine leaves it unevaluated.

SymEngine differentiates ``abs(u)`` to ``Derivative(abs(u), x)`` and ``sign(u)`` to
``Derivative(sign(u), x)``, and can neither evaluate nor substitute a number into them
("Not Implemented", "expected an object of type Symbol"), nor can SymPy's code printers
print them.  Away from u = 0, where |u| has no derivative, d|u|/dx = sign(u) du/dx and
d sign(u)/dx = 0: `settled` rewrites both, so that the expression can be evaluated and
printed (found by tools/fuzz.py: ``rotation = ["abs(theta)", "x"]``); sign(u) being constant
there, a derivative of any order is sign(u) times that of u.  At u = 0 the
rewritten form gives sign(0) = 0, the mean of the one-sided derivatives.
"""

from __future__ import annotations

import symengine as se

__all__ = ["settled"]


def settled(expr: se.Basic) -> se.Basic:
    """``expr`` with every d|u|/dx replaced by sign(u) du/dx and every d sign(u)/dx by 0."""
    for _ in range(8):  # du/dx may hold another |·| (|x − |y||): a few rounds settle any sane nesting
        derivatives = [d for d in expr.atoms(se.Derivative) if isinstance(d.args[0], (se.Abs, se.sign))]
        if not derivatives:
            return expr
        rewrite = {}
        for d in derivatives:
            inner, variables = d.args[0], d.args[1:]
            u = inner.args[0]
            if isinstance(inner, se.sign):
                rewrite[d] = se.Integer(0)
                continue
            du = u
            for x in variables:
                du = du.diff(x)
            rewrite[d] = se.sign(u) * du  # sign(u) is constant away from u = 0: every order alike
        expr = expr.xreplace(rewrite)
    return expr
