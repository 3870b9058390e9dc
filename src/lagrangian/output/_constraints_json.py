"""The ``constraints`` section of the ``derive --json`` document (steps 1 and 7 as data).

Present only when the model declares constraints (``[constraints]``); see
``docs/derive-json.md`` for the keys and ``docs/constraints.md`` for the conventions
(λ_k multiplies +A_ki; a reaction force is what the constraint exerts on the body).
"""

from __future__ import annotations

from typing import Any

import sympy

from ..dynamics import EquationsOfMotion, describe_constraints, multiplier_formulas
from ..model import Vector
from ._course import to_sympy

__all__ = ["constraints_section"]


def _s(e: Any) -> str:
    return sympy.sstr(to_sympy(e), order="none")


def _declared(e: Any) -> str:
    """A principal constraint as declared: `to_sympy`'s tidying would make it 0 (the coordinates satisfy it)."""
    return sympy.sstr(e._sympy_() if hasattr(e, "_sympy_") else sympy.S(e), order="none")


def _vector(eom: EquationsOfMotion, v: Vector, frame: str, text=_s) -> list[str]:
    return [text(c) for c in eom.kinematics.frames.express(v, frame)]


def constraints_section(eom: EquationsOfMotion) -> dict[str, Any]:
    """``{"constraints": [...], "multipliers": [...], "multiplier_terms": [...]}`` for ``eom``, or ``{}``.

    With ``"multiplier_formulas"`` (λ_k → λ(q, q̇, t)) when `multiplier_formulas` solves them.
    """
    if not eom.model.constraints:
        return {}
    q = eom.coordinates
    items = []
    for info in describe_constraints(eom):
        text = _declared if info.role == "principal" else _s
        statement = (_vector(eom, info.statement, info.frame, text)
                     if isinstance(info.statement, Vector) and info.frame is not None  # a vector has its frame
                     else text(info.statement))
        rows = [{"name": r.name, "equation": _s(r.expression), "multiplier": r.multiplier.name,
                 "coefficients": {c: _s(a) for c, a in zip(q, r.coefficients, strict=True)}, "b": _s(r.b),
                 "velocity": _s(r.velocity), "acceleration_bias": _s(r.bias)} for r in info.rows]
        reaction = None
        if info.reaction is not None:
            r = info.reaction
            reaction = {
                "point": r.point, "body": r.body, "counter_point": r.counter_point, "frame": r.frame,
                "force": [_s(c) for c in r.force_components] if r.point is not None else None,
                "moment": [_s(c) for c in r.moment_components] if r.body is not None else None,
                "generalized": {c: _s(g) for c, g in zip(q, r.generalized, strict=True)}, "note": r.note,
            }
        item: dict[str, Any] = {"name": info.name, "role": info.role, "form": info.form, "kind": info.kind,
                                "description": info.description, "frame": info.frame, "statement": statement,
                                "rows": rows, "reaction": reaction}
        choice = info.reaction.row_choice if info.reaction is not None else None
        if choice is not None:  # rows chosen by the engine (optional key)
            item["row_choice"] = {"declared_frame": choice.declared_frame, "declared_rows": list(choice.declared_rows),
                                  "rank": choice.rank, "frame": choice.frame, "kept": list(choice.kept),
                                  "note": choice.text}
        declared = next(c for c in eom.model.constraints if c.name == info.name)
        if declared.unilateral:  # a contact: its law (optional key)
            item["contact"] = {"restitution": _s(declared.restitution),
                               "friction": None if declared.friction is None else _s(declared.friction),
                               "slip": None if declared.slip is None else _s(declared.slip)}
        if info.integrals:  # velocity rows that integrate: φ_k(q, t) = cste (optional key)
            item["integrals"] = [_s(phi) for phi in info.integrals]
        items.append(item)
    out: dict[str, Any] = {
        "constraints": items,
        "multipliers": [m.name for m in eom.multipliers],
        "multiplier_terms": [_s(eq.multiplier_terms) for eq in eom.equations],
    }
    contacts = sum(1 for c in eom.model.constraints if c.unilateral)  # several: λ depends on which are closed
    formulas = multiplier_formulas(eom) if eom.constraints and contacts < 2 else None
    if formulas is not None:
        out["multiplier_formulas"] = {m.name: _s(f) for m, f in zip(eom.multipliers, formulas, strict=True)}
    return out
