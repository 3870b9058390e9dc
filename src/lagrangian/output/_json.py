"""The ``derive --json`` document: a stable, versioned interface for other programs.

Schema: ``derive.schema.json`` beside this module (JSON Schema draft 2020-12), and
``docs/derive-json.md``.  Expressions are strings in SymPy's syntax
(``A*psi_dot*sin(theta)**2``): ``q``, ``q_dot`` for q̇, ``q_ddot`` for q̈, ``t``, the
parameter names, ``+ - * / **``, parentheses and the functions of the model grammar.
``sympy.sympify`` reads them back (in the reader's program: they are our output).

Versioning: ``version`` is an integer bumped on any incompatible change (a key
removed or its meaning changed); keys may be added within a version.
"""

from __future__ import annotations

from typing import Any

import sympy

from ..analysis import energy_balance
from ..dynamics import EquationsOfMotion
from ._constraints_json import constraints_section
from ._course import CourseForm, to_sympy

__all__ = ["SCHEMA_ID", "SCHEMA_VERSION", "derive_document"]

#: The ``schema`` key of a ``lagrangian derive --json`` document (``derive.schema.json``).
SCHEMA_ID = "lagrangian.derive"
#: The ``version`` key of that document: the version of its layout.
SCHEMA_VERSION = 1


def _s(e: sympy.Basic) -> str:
    return sympy.sstr(e, order="none")


def derive_document(form: CourseForm, *, parameters: dict[str, float | None],
                    initial: dict[str, dict[str, float | None]], source: str | None,
                    package_version: str, eom: EquationsOfMotion | None = None) -> dict[str, Any]:
    """The JSON object printed by ``lagrangian derive --json``.

    With ``eom`` whose model declares constraints, the optional keys ``constraints``,
    ``multipliers``, ``multiplier_terms`` and ``multiplier_formulas`` are added
    (`_constraints_json`); ``reference`` when the equations are written in a non-Galilean
    frame; ``energy_balance`` when no energy (or Jacobi) integral holds.

    Parameters
    ----------
    form : CourseForm
        The derivation.
    parameters : dict of str to float or None
        The parameter values.
    initial : dict of str to dict of str to float or None
        The initial values and rates, by coordinate.
    source : str or None
        The model file.
    package_version : str
        ``lagrangian.__version__``.
    eom : EquationsOfMotion, optional
        With a model that declares constraints, the optional keys ``constraints``,
        ``multipliers``, ``multiplier_terms`` and ``multiplier_formulas`` are added
        (`_constraints_json`); ``reference`` when the equations are written in a non-Galilean
        frame; ``energy_balance`` when no energy (or Jacobi) integral holds.

    Returns
    -------
    dict of str to object
        The JSON object.
    """
    q = list(form.coordinates)
    doc = {
        "schema": SCHEMA_ID,
        "version": SCHEMA_VERSION,
        "generator": f"lagrangian {package_version}",
        "model": {"name": form.title, "description": form.description, "source": source},
        "coordinates": q,
        "rates": [c + "_dot" for c in q],
        "accelerations": [c + "_ddot" for c in q],
        "parameters": parameters,
        "initial_conditions": initial,
        "kinetic_energy": _s(form.T_total),
        "potential_energy": _s(form.U_total),
        "conservative": form.conservative,
        "lagrangian": None if form.L is None else _s(form.L),
        "generalized_forces": [
            {"load": f.name, "kind": f.kind, "conservative": f.conservative,
             "potential": None if f.potential is None else _s(f.potential),
             "Q": {c: _s(x) for c, x in zip(q, f.Q, strict=True)}, "note": f.note}
            for f in form.loads
        ],
        "equations": [
            {"coordinate": e.coordinate, "lhs": _s(e.lhs), "rhs": _s(e.rhs),
             "dT_dqdot": _s(e.dT_dqd), "dT_dq": _s(e.dT_dq), "dU_dq": _s(e.dU_dq), "Q_nonconservative": _s(e.Q_nc)}
            for e in form.equations
        ],
        "mass_matrix": [[_s(x) for x in row] for row in form.M],
        "forcing": [_s(x) for x in form.F],
        "first_integrals": {i.name: _s(i.expression) for i in form.integrals},
        "first_integral_details": [
            {"name": i.name, "kind": i.kind, "coordinate": i.coordinate, "reason": i.reason}
            for i in form.integrals
        ],
    }
    if eom is not None:
        doc.update(constraints_section(eom))
        ref = eom.model.reference
        if ref is not None and not ref.is_galilean_frame:
            doc["reference"] = {"frame": ref.frame, "origin": ref.origin}
        if not any(i.kind in ("energy", "jacobi") for i in form.integrals):
            doc["energy_balance"] = _balance(eom)
        doc.update(_assumptions(eom))
    return doc


def _assumptions(eom: EquationsOfMotion) -> dict[str, Any]:
    """The declared signs and ranges, and the signs the derivation proved and used (optional key)."""
    model = eom.model
    signs = {p.name: p.sign for p in model.parameters if p.sign is not None}
    ranges = {c.name: [None if b is None else _s(to_sympy(b)) for b in c.range]
              for c in model.coordinates if c.range is not None}
    if not signs and not ranges:
        return {}
    return {"assumptions": {
        "signs": signs, "ranges": ranges,
        "used": [{"expression": _s(to_sympy(f.expression)), "relation": f.relation, "general": f.general,
                  "reason": f.reason} for f in eom.assumptions],
    }}


def _balance(eom: EquationsOfMotion) -> dict[str, Any]:
    """dE/dt = P(non-conservative) term by term (`lagrangian.analysis.energy_balance`)."""
    b = energy_balance(eom)
    return {"energy": _s(to_sympy(b.E)), "power": _s(to_sympy(b.P_nc)), "conserved": b.conserved,
            "terms": [{"name": t.name, "kind": t.kind, "power": _s(to_sympy(t.power)), "note": t.note}
                      for t in b.terms]}
