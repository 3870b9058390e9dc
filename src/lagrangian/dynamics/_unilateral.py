"""The rows of unilateral contacts: the gap's row (its multiplier the normal reaction) and the sliding row.

`derive` writes a contact's gap g(q, t) like a holonomic complementary constraint — its row
A_k q̇ + b_k = ġ, its multiplier λ_k, the normal reaction (λ_k ≥ 0 while closed) — so the
equations shown are those of the closed contact.  The simulation (`lagrangian.numerics._contact`)
needs, besides, the sliding row of a contact with friction (w = a·q̇ + b, sticking while
|λ_t| ≤ μ λ), and all these rows at once whatever their rank: a block flat on the ground has
four rows (two corners, normal and tangential) for three coordinates.  `contact_rows` builds
them from the equations of the model without its contacts, with the same formulas as every
complementary row (`dynamics._constraints`), and no rank test: which rows act is decided at
each instant by the contact problem (`numerics._impact`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

from ..errors import ModelError
from ..model import Constraint
from ._constraints import ConstraintReaction, ConstraintRow, _reaction, _row
from ._lagrange import EquationsOfMotion

__all__ = ["TANGENT_SUFFIX", "ContactRows", "contact_rows", "with_contact_rows"]

#: The sliding row of contact ``c`` is named ``c_t`` (its multiplier ``lambda_c_t``).
TANGENT_SUFFIX = "_t"


@dataclass(frozen=True, slots=True)
class ContactRows:
    """The rows of one unilateral contact.

    Attributes
    ----------
    contact : the declaration (form ``unilateral``).
    normal : the gap's row: ``expression`` g, ``velocity`` ġ = A q̇ + b, ``bias`` (g̈ = A q̈ + bias).
    tangent : the sliding row w = a·q̇ + b (nonholonomic), None without friction.
    reaction : the effort the multipliers stand for (a force at ``reaction.force_at`` when declared).
    """

    contact: Constraint
    normal: ConstraintRow
    tangent: ConstraintRow | None
    reaction: ConstraintReaction


def contact_rows(eom: EquationsOfMotion, contacts: Sequence[Constraint]) -> tuple[ContactRows, ...]:
    """The rows of ``contacts`` over the kinematics of ``eom`` (the model without them; module docstring).

    Raises
    ------
    ModelError
        A gap or sliding velocity that involves no coordinate, or a multiplier name already taken.
    """
    kin = eom.kinematics
    taken = {p.name for p in eom.model.parameters} | {str(s) for s in (*kin.q, *kin.qd, *kin.qdd)} \
        | {str(r.multiplier) for r in eom.constraints}
    out = []
    for c in contacts:
        normal = _row(kin, c, c.name, c.expression)  # type: ignore[arg-type]
        rows = [normal]
        tangent = None
        if c.slip is not None:
            sliding = replace(c, form="nonholonomic", expression=c.slip)
            tangent = _row(kin, sliding, c.name + TANGENT_SUFFIX, c.slip)
            rows.append(tangent)
        for row in rows:
            if all(a == 0 for a in row.coefficients):
                loc = eom.model.where("constraint", c.name)
                raise ModelError(f"the {'gap' if row is normal else 'sliding velocity'} of contact `{c.name}` involves "
                                 "no coordinate, so no motion opens or closes it", symbol=c.name, file=loc.file,
                                 line=loc.line, fix="write it in terms of the coordinates")
            if str(row.multiplier) in taken:
                loc = eom.model.where("constraint", c.name)
                raise ModelError(f"the multiplier `{row.multiplier}` of contact `{c.name}` has the name of a parameter, "
                                 "a coordinate or another row", symbol=c.name, file=loc.file, line=loc.line,
                                 fix="rename the contact")
            taken.add(str(row.multiplier))
        reaction = _reaction(kin, c, rows, [None] * len(rows), c.frame, None)
        out.append(ContactRows(c, normal, tangent, reaction))
    return tuple(out)


def with_contact_rows(eom: EquationsOfMotion, rows: Sequence[ContactRows]) -> EquationsOfMotion:
    """``eom`` (without contacts) with every contact row appended to its complementary rows, for the numerics."""
    extra = tuple(r for c in rows for r in (c.normal, c.tangent) if r is not None)
    return replace(eom, constraints=tuple(eom.constraints) + extra,
                   reactions=tuple(eom.reactions) + tuple(c.reaction for c in rows))
