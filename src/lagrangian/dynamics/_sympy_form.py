"""The equations of a model as SymPy objects: `SympyEquations`, what ``eom.to_sympy()`` returns.

Every expression is converted structurally from SymEngine (``_sympy_()``: no text is
parsed and nothing is simplified), so the SymPy form has exactly the value of the
engine's: M(q, t) q̈ = F(q, q̇, t) [Seed, section II; Goldstein, *Classical Mechanics*,
3rd ed., § 1.4], the n equations L(q_i)

    d/dt(∂T/∂q̇_i) − ∂T/∂q_i = −∂U/∂q_i + Q_i(nc) (+ Σ_k λ_k A_ki),

T, U, L = T − U and the multipliers' formulas.  The first integrals are the analysis stage's:
``lagrangian.sympy_equations(eom)`` (`lagrangian.output.sympy_equations`) gives this form with them,
each converted by `SympyEquations.convert`.

Symbols are named as in the model: ``theta``, ``theta_dot``, ``theta_ddot``, ``t``, the
parameters and the multipliers ``lambda_<constraint>``.  With ``time_functions=True`` the
coordinates are ``sympy.physics.mechanics.dynamicsymbols`` θ(t), and q̇, q̈ are
Derivative(θ(t), t) and Derivative(θ(t), (t, 2)) — the form of SymPy's ``LagrangesMethod``
and ``KanesMethod`` — so that ``sympy.diff(expr, t)`` is the total time derivative.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import symengine as se

from ._constraints import multiplier_formulas

if TYPE_CHECKING:
    import sympy

    from ._lagrange import EquationsOfMotion

# SymPy is imported where a form is made, not with the stage: `import lagrangian.dynamics` stays light.
__all__ = ["SympyEquations", "sympy_form"]


def _no_rows() -> sympy.Matrix:
    import sympy

    return sympy.zeros(0, 0)


@dataclass(frozen=True, eq=False)
class SympyEquations:
    """The equations of motion of one model in SymPy (see the module docstring).

    Parameters
    ----------
    coordinates : tuple of str
        The coordinate names q_i, in order.
    t : SymPy Symbol
        The time symbol (``dynamicsymbols._t`` in the time-function form).
    q : tuple of SymPy expressions
        The coordinates: symbols ``theta``, or θ(t).
    qd : tuple of SymPy expressions
        The rates: symbols ``theta_dot``, or Derivative(θ(t), t).
    qdd : tuple of SymPy expressions
        The accelerations: symbols ``theta_ddot``, or Derivative(θ(t), (t, 2)).
    parameters : tuple of SymPy Symbol
        The model's parameter symbols, in declaration order.
    values : mapping of SymPy Symbol to float
        Their values (symbol → number) where the model gives one, ready for ``subs`` or ``lambdify``.
    M : sympy.Matrix
        M(q, t), n×n, in M q̈ = F(q, q̇, t) (+ Aᵀλ with complementary constraints).
    F : sympy.Matrix
        F(q, q̇, t), n×1.
    equations : tuple of sympy.Eq
        One per coordinate, L(q_i): Γ_i = −∂U/∂q_i + Q_i(nc) (+ Σ_k λ_k A_ki).
    T : SymPy expression
        The kinetic energy T(Σ/R0).
    U : SymPy expression
        The potential U_P (up to a constant).
    L : SymPy expression or None
        T − U when the system is conservative (Remarque 2), else None.
    multipliers : tuple of SymPy expressions
        The λ_k of the complementary constraints.
    A : sympy.Matrix
        The m×n matrix of their rows.
    multiplier_formulas : mapping of str to SymPy expression
        The multipliers' formulas, λ_k name → λ_k(q, q̇, t) in closed form (empty when there is none, or the system is too large
        for one: then λ is found along a motion).
    time_functions : bool
        Whether this is the ``dynamicsymbols`` form.
    first_integrals : mapping of str to SymPy expression, or None
        Name → expression constant along every motion (K, H, E, p_x, ...), from
        ``lagrangian.sympy_equations(eom)``; None from ``eom.to_sympy()``, which does not look for them
        (finding them is the analysis stage's work, `lagrangian.first_integrals`).
    _replace : mapping of SymPy expression to SymPy expression, optional
        The engine's symbols → this form's (θ → θ(t), θ_dot → Derivative(θ(t), t), ...): what
        `convert` applies (set by `EquationsOfMotion.to_sympy`).
    """

    coordinates: tuple[str, ...]
    t: sympy.Symbol
    q: tuple[sympy.Basic, ...]
    qd: tuple[sympy.Basic, ...]
    qdd: tuple[sympy.Basic, ...]
    parameters: tuple[sympy.Symbol, ...]
    values: Mapping[sympy.Symbol, float]
    M: sympy.Matrix
    F: sympy.Matrix
    equations: tuple[sympy.Eq, ...]
    T: sympy.Basic
    U: sympy.Basic
    L: sympy.Basic | None
    multipliers: tuple[sympy.Basic, ...] = ()
    A: sympy.Matrix = field(default_factory=_no_rows)
    multiplier_formulas: Mapping[str, sympy.Basic] = field(default_factory=dict)
    time_functions: bool = False
    first_integrals: Mapping[str, sympy.Basic] | None = None
    _replace: Mapping[sympy.Basic, sympy.Basic] = field(default_factory=dict, repr=False, compare=False)

    def convert(self, expr: se.Basic) -> sympy.Basic:
        """An engine expression of the model (a first integral, a reaction, a body's T) in this form.

        Converted as M, F and the equations are: structurally (no text parsed, nothing simplified),
        with this form's symbols (θ(t) and its derivatives when ``time_functions``).

        Parameters
        ----------
        expr : SymEngine expression
            An expression over the model's coordinates, rates, parameters and t.

        Returns
        -------
        SymPy expression
            The same expression in this form.
        """
        out = _convert(expr)
        return out.xreplace(self._replace) if self._replace else out

    def qdd_solved(self) -> sympy.Matrix:
        """Solve q̈ = M⁻¹ F (without complementary constraints), by LU: small systems only (it grows fast).

        Returns
        -------
        sympy.Matrix
            The accelerations q̈, n×1.
        """
        return self.M.LUsolve(self.F)


def _convert(e: se.Basic) -> sympy.Basic:
    """SymEngine → SymPy, structurally (never through text)."""
    import sympy

    if isinstance(e, sympy.Basic):
        return e
    if hasattr(e, "_sympy_"):
        return e._sympy_()
    return sympy.S(e) if isinstance(e, (int, float)) else sympy.Float(float(e))  # a plain number


def sympy_form(eom: EquationsOfMotion, *, time_functions: bool = False) -> SympyEquations:
    """``eom.to_sympy()``: symbols named as in the model, or SymPy mechanics' ``dynamicsymbols``.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    time_functions : bool, optional
        The ``dynamicsymbols`` form: θ(t) and its derivatives.

    Returns
    -------
    SympyEquations
        The equations in SymPy.

    Examples
    --------
    >>> import lagrangian, sympy
    >>> s = lagrangian.derive(lagrangian.lagrange_top()).to_sympy()
    >>> s.equations[1].lhs.has(sympy.Symbol("theta_ddot"))
    True
    """
    import sympy

    names = eom.coordinates
    q = tuple(sympy.Symbol(str(s)) for s in eom.q)
    qd = tuple(sympy.Symbol(str(s)) for s in eom.qd)
    qdd = tuple(sympy.Symbol(str(s)) for s in eom.qdd)
    t = sympy.Symbol(str(eom.t))
    lam = tuple(sympy.Symbol(str(s)) for s in eom.multipliers)
    replace: dict[sympy.Basic, sympy.Basic] = {}
    if time_functions:
        from sympy.physics.mechanics import dynamicsymbols

        t_new = dynamicsymbols._t
        funcs = tuple(dynamicsymbols(str(s)) for s in eom.q)
        lam_new = tuple(dynamicsymbols(str(s)) for s in eom.multipliers)
        replace = {t: t_new}
        replace.update(zip(qdd, (sympy.Derivative(f, (t_new, 2)) for f in funcs), strict=True))
        replace.update(zip(qd, (sympy.Derivative(f, t_new) for f in funcs), strict=True))
        replace.update(zip(q, funcs, strict=True))
        replace.update(zip(lam, lam_new, strict=True))
        t, lam = t_new, lam_new
        q, qd, qdd = funcs, tuple(replace[s] for s in qd), tuple(replace[s] for s in qdd)

    def conv(e: se.Basic) -> sympy.Basic:
        out = _convert(e)
        return out.xreplace(replace) if replace else out

    parameters = tuple(sympy.Symbol(p.name) for p in eom.model.parameters)
    values = {sympy.Symbol(name): float(v) for name, v in eom.model.parameter_values.items() if v is not None}
    T, U = conv(eom.T), conv(eom.U)
    formulas = multiplier_formulas(eom) if eom.constraints else None
    return SympyEquations(
        coordinates=names, t=t, q=q, qd=qd, qdd=qdd, parameters=parameters, values=values,
        M=sympy.Matrix([[conv(x) for x in row] for row in eom.M]),
        F=sympy.Matrix([conv(x) for x in eom.F]),
        equations=tuple(sympy.Eq(conv(eq.lhs), conv(eq.rhs), evaluate=False) for eq in eom.equations),
        T=T, U=U, L=T - U if eom.conservative else None,
        multipliers=lam,
        A=sympy.Matrix(len(eom.constraints), len(q), [conv(x) for row in eom.A for x in row]),
        multiplier_formulas={str(row.multiplier): conv(f) for row, f in zip(eom.constraints, formulas or (), strict=True)},
        time_functions=time_functions, _replace=replace,
    )
