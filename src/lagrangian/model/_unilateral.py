"""Unilateral constraints (contacts) declared in a model: a gap g(q, t) ≥ 0 and what happens at it.

A ``[constraints]`` entry with the key ``unilateral`` is one-sided::

    floor = { unilateral = "z - r", restitution = "e" }                         # g(q, t) = z − r ≥ 0
    wall  = { unilateral = "x", restitution = "0", friction = "mu", slip = "y_dot + r*phi_dot" }

* ``unilateral``: the gap g(q, t), a scalar of the coordinates, the parameters and t (no rate);
  the contact is *closed* where g = 0 and *open* where g > 0.  While closed it acts as a
  complementary holonomic constraint g = 0 whose multiplier λ is the normal reaction, λ ≥ 0
  (it pushes, never pulls): the complementarity g ≥ 0, λ ≥ 0, λ g = 0.
* ``restitution``: Newton's coefficient e ∈ [0, 1] (required): at an impact the normal
  velocity ġ⁺ = −e ġ⁻ (0: plastic, the contact closes; 1: elastic).
* ``friction``: the Coulomb coefficient μ ≥ 0 of the contact (optional), with ``slip``: the
  tangential sliding velocity w = a(q, t)·q̇ + b(q, t) of the contact point (linear in the rates),
  required with ``friction``.  At an impact the tangential percussion is bounded, |P_t| ≤ μ P_n
  (the contact sticks, w⁺ = 0, or slides against w⁺); while closed the contact sticks (w = 0,
  a row with the multiplier λ_t) as long as |λ_t| ≤ μ λ.

The coefficients are constants (parameters only).  Where their values are known, e outside
[0, 1] and μ < 0 are refused here, at the declaration's line; `simulate` checks values given
with ``--set``.  The numerics are `lagrangian.numerics._contact`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import symengine as se

__all__ = ["UNILATERAL_KEYS", "coefficient_values_error", "unilateral_parts"]

#: The keys a unilateral constraint accepts besides the common ones (`description`, `reaction`).
UNILATERAL_KEYS = {"restitution", "friction", "slip"}


def _rates_in(expr: se.Basic, rates: Mapping[se.Basic, str]) -> list[str]:
    return sorted(rates[s] for s in expr.free_symbols if s in rates)


def coefficient_values_error(name: str, e: float | None, mu: float | None) -> str | None:
    """Why the values of e and μ are not physical (None when they are, or are unknown).

    Parameters
    ----------
    name : str
        The constraint's name.
    e : float or None
        Newton's coefficient of restitution.
    mu : float or None
        The Coulomb coefficient μ.

    Returns
    -------
    str or None
        The reason, or None.
    """
    if e is not None and not 0.0 <= e <= 1.0:
        return f"the restitution coefficient of contact `{name}` is e = {e:g}, outside [0, 1]"
    if mu is not None and not mu >= 0.0:
        return f"the friction coefficient of contact `{name}` is μ = {mu:g}, negative"
    return None


def _value(checker: Any, expr: se.Basic) -> float | None:
    """The value of a constant expression at the parameters' values (None when one has no value)."""
    values = {}
    for s in expr.free_symbols:
        v = checker.a.constants.get(s)
        if v is None:
            return None
        values[s] = se.RealDouble(float(v))
    try:
        return float(expr.xreplace(values))
    except (RuntimeError, TypeError, ValueError):
        return None


def _constant(checker: Any, raw: Any, key: str, what: str, value: Any) -> se.Basic:
    expr = checker.a.expr(raw, what, value, key=key)
    moving = sorted(str(s) for s in expr.free_symbols if s not in checker.a.constants)
    if moving:
        raise checker.fail(raw, f"the {what} of contact `{raw.name}` depends on `{moving[0]}`: it must be a constant "
                           "(numbers and parameters)", key=key, symbol=moving[0],
                           fix=f'e.g. {key} = "0.8", or a parameter declared under [parameters]')
    return expr


def unilateral_parts(checker: Any, raw: Any, d: Mapping[str, Any]) -> tuple[se.Basic, se.Basic, se.Basic | None,
                                                                          se.Basic | None]:
    """(g, e, μ, w) of a ``unilateral`` declaration, checked (module docstring).

    ``checker`` is the constraint checker of `lagrangian.model._constraints` (its assembler,
    its rates and its ``fail``).

    Raises
    ------
    ModelError
        At the declaration's line: a gap that is a vector or holds a rate, a missing or
        non-constant restitution, e outside [0, 1] or μ < 0 at the parameters' values,
        friction without ``slip`` (or ``slip`` without friction), a slip that is not linear in
        the rates or holds none, and ``principal`` or ``axes`` (a contact is neither).
    """
    name = raw.name
    gap = checker.a.expr(raw, "the gap of the unilateral constraint", d["value"], vector=False, key="unilateral")
    rates = _rates_in(gap, checker.rates)
    if rates:
        raise checker.fail(raw, f"the gap of contact `{name}` depends on the rate `{rates[0]}`: a gap g(q, t) ≥ 0 is "
                           "a distance, which holds no velocity", key="unilateral", symbol=rates[0],
                           fix='write the distance between the surfaces, e.g. unilateral = "z - r"')
    if d.get("principal"):
        raise checker.fail(raw, f"contact `{name}` cannot be principal: a unilateral constraint opens and closes, so "
                           "no choice of coordinates eliminates it", key="principal",
                           fix="remove `principal = true`")
    if d.get("axes") is not None:
        raise checker.fail(raw, f"contact `{name}` is scalar (one gap): `axes` has nothing to choose", key="axes",
                           fix="remove `axes`")
    if d.get("restitution") is None:
        raise checker.fail(raw, f"contact `{name}` does not say how it bounces", key="unilateral",
                           fix='add restitution = "e" (Newton\'s coefficient: 0 plastic, 1 elastic)')
    e = _constant(checker, raw, "restitution", "restitution coefficient", d["restitution"])
    mu = slip = None
    if d.get("friction") is not None:
        mu = _constant(checker, raw, "friction", "friction coefficient", d["friction"])
        if d.get("slip") is None:
            raise checker.fail(raw, f"contact `{name}` has friction but no sliding velocity", key="friction",
                               fix='add slip = "...", the tangential velocity of the contact point, linear in the '
                                   'rates (e.g. slip = "x_dot + r*phi_dot")')
        slip = checker.a.expr(raw, "the sliding velocity", d["slip"], vector=False, key="slip")
        if not _rates_in(slip, checker.rates):
            raise checker.fail(raw, f"the sliding velocity of contact `{name}` holds no rate q̇", key="slip",
                               fix="write the tangential velocity of the contact point, e.g. \"x_dot + r*phi_dot\"")
        for s, rate in checker.rates.items():
            left = _rates_in(slip.diff(s), checker.rates)
            if left:
                raise checker.fail(raw, f"the sliding velocity of contact `{name}` is not linear in the rates: its "
                                   f"derivative with respect to `{rate}` still holds `{left[0]}`", key="slip",
                                   symbol=rate, fix="write w = a(q, t)·q̇ + b(q, t), the velocity of the contact "
                                                    "point along the tangent")
    elif d.get("slip") is not None:
        raise checker.fail(raw, f"contact `{name}` gives a sliding velocity but no friction coefficient", key="slip",
                           fix='add friction = "mu", or remove `slip` (a frictionless contact needs none)')
    problem = coefficient_values_error(name, _value(checker, e), None if mu is None else _value(checker, mu))
    if problem is not None:
        key = "restitution" if "restitution" in problem else "friction"
        raise checker.fail(raw, problem, key=key,
                           fix="0 ≤ e ≤ 1 (0: plastic, 1: elastic) and μ ≥ 0" if key == "restitution"
                           else "give a coefficient μ ≥ 0")
    return gap, e, mu, slip
