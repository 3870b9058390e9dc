"""The equations of a model and their first integrals as SymPy objects: `sympy_equations`.

``eom.to_sympy()`` (the dynamics stage, `lagrangian.dynamics.SympyEquations`) converts what the
derivation gives: M, F, the equations L(q_i), T, U, L, the multipliers and their formulas.  The first
integrals (K, H, E, ...) are found by the analysis stage (`lagrangian.first_integrals`); here they join
the same form, each converted as the equations are (`SympyEquations.convert`: structurally, with the
form's symbols, θ(t) included).
"""

from __future__ import annotations

import dataclasses

from ..analysis import first_integrals
from ..dynamics import EquationsOfMotion, SympyEquations

__all__ = ["sympy_equations"]


def sympy_equations(eom: EquationsOfMotion, *, time_functions: bool = False) -> SympyEquations:
    """``eom.to_sympy(time_functions=...)`` with the first integrals: ``first_integrals`` name → expression.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations (`lagrangian.derive`); their first integrals are found by `lagrangian.first_integrals`.
    time_functions : bool, optional
        The ``dynamicsymbols`` form: θ(t) and its derivatives, as in `EquationsOfMotion.to_sympy`.

    Returns
    -------
    SympyEquations
        The equations in SymPy, with ``first_integrals`` filled.

    Examples
    --------
    >>> import lagrangian, sympy
    >>> s = lagrangian.sympy_equations(lagrangian.derive(lagrangian.lagrange_top()))
    >>> sorted(s.first_integrals)
    ['E', 'H', 'K']
    >>> s.first_integrals["H"].has(sympy.Symbol("phi_dot"))
    True
    """
    s = eom.to_sympy(time_functions=time_functions)
    return dataclasses.replace(s, first_integrals={fi.name: s.convert(fi.expression) for fi in first_integrals(eom)})
