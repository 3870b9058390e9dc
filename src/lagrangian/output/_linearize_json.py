"""The ``linearize --json`` / ``modes --json`` document: schema ``lagrangian.linearize``, version 1.

Schema: ``linearize.schema.json`` beside this module (JSON Schema draft 2020-12), and
``docs/small-motions.md``.  About a point (q0, q̇0) the linearized motion is

    M δq̈ + (D + G) δq̇ + (K + N) δq = B₂ u        (second order, when it exists)
    ẋ = A x + B u,  x = (δq_i, δu)                 (state space, always)

Matrices are lists of rows.  When every parameter has a value (no ``symbols``) their entries
are numbers; otherwise every entry is a string in SymPy's syntax (``-g/l``), which
``sympy.sympify`` reads back (in the reader's program: they are our output).  Eigenvalues,
modes and the stability verdict need numbers: they are null when symbols are left, unless
they were computed at given values of the symbols (``modes_at``).

Versioning: ``version`` is an integer bumped on any incompatible change; keys may be added.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import symengine as se
import sympy

__all__ = [
    "LINEARIZE_SCHEMA_ID",
    "LINEARIZE_SCHEMA_VERSION",
    "linearize_document",
    "matrix_rows",
    "modes_section",
    "sweep_section",
]

#: The ``schema`` key of a ``lagrangian linearize --json`` document (``linearize.schema.json``).
LINEARIZE_SCHEMA_ID = "lagrangian.linearize"
LINEARIZE_SCHEMA_VERSION = 1


def _expr(e: se.Basic) -> str:
    return sympy.sstr(e._sympy_(), order="none")


def _number(x: float) -> float | None:
    """A JSON number (a non-finite one would not be JSON: null)."""
    x = float(x)
    return x if math.isfinite(x) else None


def _entry(e: se.Basic, numeric: bool) -> float | str | None:
    if numeric:
        return _number(float(complex(e).real))
    return _expr(e)


def matrix_rows(m: se.DenseMatrix, numeric: bool) -> list[list[float | str | None]]:
    """A SymEngine matrix as a list of rows (entries read one by one: a matrix with no column
    is never printed, which SymEngine does not survive)."""
    return [[_entry(m[i, j], numeric) for j in range(m.cols)] for i in range(m.rows)]


def _value(e: se.Basic) -> float | str | None:
    """A point's value: a number when it is one, else its expression."""
    if not e.free_symbols:
        try:
            return _number(float(complex(e).real))
        except (RuntimeError, TypeError, ValueError):
            pass
    return _expr(e)


def _complex(z: complex) -> list[float | None]:
    return [_number(z.real), _number(z.imag)]


def linearize_document(lin: Any, *, source: str | None, package_version: str,
                       stability: Any = None, modes: Any = None, sweep: Any = None,
                       modes_at: dict[str, float] | None = None) -> dict[str, Any]:
    """The JSON object printed by ``lagrangian linearize --json`` and ``lagrangian modes --json``.

    Parameters
    ----------
    lin : LinearModel
        A `lagrangian.analysis.LinearModel`.
    source : str or None
        The model file.
    package_version : str
        ``lagrangian.__version__``.
    stability : Stability, optional
        `Stability` of ``lin`` (computed when None and ``lin`` has no symbols left).
    modes : Modes, optional
        `Modes` of ``lin``, likewise.
    sweep : Sweep, optional
        A `Sweep` (``modes --sweep``): adds the key ``sweep``.
    modes_at : dict of str to float, optional
        The values of the symbols at which ``stability`` and ``modes`` were computed (a sweep's
        parameter at the model's value): adds the key ``modes_at``.

    Returns
    -------
    dict of str to object
        The JSON object.
    """
    numeric = not lin.symbols
    model = lin.eom.model
    so = lin.second_order
    if numeric and stability is None:
        stability = lin.stability()
    if numeric and modes is None:
        modes = lin.modes()
    doc: dict[str, Any] = {
        "schema": LINEARIZE_SCHEMA_ID,
        "version": LINEARIZE_SCHEMA_VERSION,
        "generator": f"lagrangian {package_version}",
        "model": {"name": model.name, "description": model.description, "source": source},
        "point": {name: _value(v) for name, v in lin.point.items()},
        "steady": bool(lin.steady),
        "residual": _number(lin.residual),
        "parameters": {k: _number(v) for k, v in lin.values.items()},
        "symbols": [str(s) for s in lin.symbols],
        "numeric": numeric,
        "coordinates": list(lin.coordinates),
        "speeds": list(lin.speeds),
        "state": list(lin.state),
        "inputs": list(lin.inputs),
        "dependent_coordinates": list(lin.dependent_coordinates),
        "dependent_speeds": list(lin.dependent_speeds),
        "choice": lin.choice,
        "ignorable": list(lin.ignorable),
        "multipliers": {k: _value(v) for k, v in lin.multipliers.items()},
        "second_order": None if so is None else {"coordinates": list(so.coordinates), "B": matrix_rows(so.B, numeric)},
        "second_order_reason": lin.second_order_reason or None,
    }
    for key in ("M", "D", "G", "K", "N"):
        doc[key] = None if so is None else matrix_rows(getattr(so, key), numeric)
    doc["A"] = matrix_rows(lin.A, numeric)
    doc["B"] = matrix_rows(lin.B, numeric)
    if stability is None:
        doc["eigenvalues"] = doc["essential_eigenvalues"] = None
    else:
        # Every eigenvalue of A (what eig(A) gives), and those left once the neutral directions are set aside
        # (ignorable coordinates, conserved speeds and momenta: eigenvalue 0), which decide the verdict.
        A, _ = lin.numeric(**(modes_at or {}))
        lam = np.linalg.eigvals(A) if A.size else np.zeros(0, complex)
        lam = lam[np.lexsort((lam.imag, lam.real))] if lam.size else lam
        doc["eigenvalues"] = [_complex(z) for z in lam]
        doc["essential_eigenvalues"] = [_complex(z) for z in np.asarray(stability.eigenvalues)]
    doc["stable"] = None if stability is None else stability.stable
    doc["stability_verdict"] = None if stability is None else stability.verdict
    doc["stability_reason"] = (stability.reason if stability is not None else
                               "symbolic parameters left (" + ", ".join(doc["symbols"]) + "): give them values to "
                               "decide stability")
    doc["modes"] = None if modes is None else modes_section(modes)
    if modes_at:
        doc["modes_at"] = {k: _number(v) for k, v in modes_at.items()}
    if sweep is not None:
        doc["sweep"] = sweep_section(sweep)
    return doc


def modes_section(m: Any) -> dict[str, Any]:
    return {
        "essential": list(m.essential),
        "neutral": [{"name": name, "reason": why} for name, why in m.neutral],
        "pulsations": None if m.pulsations is None else [_number(w) for w in m.pulsations],
        # The Jordan blocks of the eigenvalue 0 once the ignorable coordinates are set aside, and whether they make
        # the linearized motion grow like t^growth (a perturbation of `start` makes `end` grow).
        "zero_eigenvalue": None if m.zero is None else {"blocks": list(m.zero.blocks), "secular": m.zero.secular,
                                                         "growth": m.zero.growth, "start": m.zero.start,
                                                         "end": m.zero.end},
        "modes": [{"eigenvalue": _complex(x.eigenvalue), "frequency": _number(x.frequency),
                   "damped_frequency": _number(x.damped_frequency),
                   "period": None if x.period is None else _number(x.period),
                   "damping_ratio": _number(x.damping_ratio),
                   "shape": {k: _complex(v) for k, v in x.shape.items()}} for x in m.modes],
    }


def sweep_section(s: Any) -> dict[str, Any]:
    """The sweep: the parameter's values, the essential eigenvalues at each, and where they change."""
    eig = np.asarray(s.eigenvalues)
    stable = np.asarray(s.stable, dtype=float)
    return {
        "parameter": s.parameter,
        "values": [_number(x) for x in np.asarray(s.values, dtype=float)],
        "eigenvalues": [[_complex(z) for z in row] for row in eig],
        "stable": [None if math.isnan(x) else bool(x) for x in stable],
        "changes": [{"value": _number(c.value), "kind": c.kind,
                     "eigenvalues": [_complex(z) for z in np.asarray(c.eigenvalues)]} for c in s.changes],
    }

