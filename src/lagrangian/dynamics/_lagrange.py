"""The n Lagrange equations L(q_i) and the equations of motion M q̈ = F.

Seed, section II:

    L(q_i)   d/dt[∂T/∂q̇_i] − ∂T/∂q_i = −∂U_P/∂q_i + Q_i(non-conservative),   i = 1..n

and, when every given effort derives from a potential and every constraint is
perfect and principal (Remarque 2), with L = T − U_P:

    L(q_i)   d/dt[∂L/∂q̇_i] − ∂L/∂q_i = 0.

`derive` computes Γ_i twice: from T (the form shown to the user, term by term as
in the seed) and from its definition ∫ γ·∂OP/∂q_i dm (the matrix form M q̈ = F used
by numerics, see `_inertia`).  The two must agree; the test suite checks it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, NamedTuple

import symengine as se

from .._display import render
from .._identity import are_zero
from ..errors import DerivationError, ModelError
from ..kinematics import Kinematics
from ..model import MAX_OPS_VARIABLE, Assumptions, Model, SignFact, equations_size, max_ops
from ..model.vectors import sum_of
from ._constraints import ConstraintReaction, ConstraintRow, complementary_constraints
from ._energy import KineticEnergyTerm, RigidInertia, kinetic_energy
from ._forces import LoadForces, generalized_forces
from ._inertia import mass_matrix_and_bias
from ._inertial import inertial_forces, reference_kinematics
from ._recursive import AUTO_MIN_DEPTH, RecursiveForm, recursive_form
from ._tree import require_tree, tree_structure

if TYPE_CHECKING:
    from ._sympy_form import SympyEquations

__all__ = ["FORMULATIONS", "EquationsOfMotion", "LagrangeEquation", "derive"]

#: `derive`'s formulations: "auto" (recursive for kinematic trees of at least
#: `AUTO_MIN_DEPTH` moving rotations in series, else the course's), "lagrange", "recursive".
FORMULATIONS = ("auto", "lagrange", "recursive")

#: Largest number of coordinates for which Γ_i = d/dt(∂T/∂q̇_i) − ∂T/∂q_i is grouped by
#: q̈_j and q̇_j (see `lagrange_equations`).
GROUPED_MAX_COORDINATES = 12

_ZERO_TYPE = type(se.Integer(0))


@dataclass(frozen=True, slots=True)
class LagrangeEquation:
    """L(q_i), with every term of the seed's layout.

    Parameters
    ----------
    coordinate : str
        The coordinate q_i.
    dT_dqd : SymEngine expression
        ∂T/∂q̇_i.
    dT_dq : SymEngine expression
        ∂T/∂q_i.
    dU_dq : SymEngine expression
        ∂U_P/∂q_i.
    Q_nc : SymEngine expression
        Q_i of the non-conservative efforts.
    lhs : SymEngine expression
        Γ_i = d/dt(∂T/∂q̇_i) − ∂T/∂q_i.
    rhs : SymEngine expression
        −∂U/∂q_i + Q_i(nc), plus ``multiplier_terms`` when the model keeps constraints complementary.
    multiplier_terms : SymEngine expression
        Σ_k λ_k A_ki of the complementary rows (0 without).
    """

    coordinate: str
    dT_dqd: se.Basic  # ∂T/∂q̇_i
    dT_dq: se.Basic  # ∂T/∂q_i
    dU_dq: se.Basic  # ∂U_P/∂q_i
    Q_nc: se.Basic  # Q_i of the non-conservative efforts
    lhs: se.Basic  # Γ_i
    rhs: se.Basic  # −∂U/∂q_i + Q_i(nc) (+ Σ_k λ_k A_ki)
    multiplier_terms: se.Basic = se.Integer(0)  # noqa: RUF009 (immutable); Σ_k λ_k A_ki of the complementary rows

    def _repr_latex_(self) -> str:
        """L(q_i) as display math in the course's notation (Jupyter); long sides are summarized."""
        return render(self, "latex")


class CourseForm(NamedTuple):
    """What the course's derivation gives: T body by body, the Q_i, the L(q_i), M and F."""

    T_terms: tuple[KineticEnergyTerm, ...]
    inertias: dict[str, RigidInertia]
    loads: tuple[LoadForces, ...]
    equations: tuple[LagrangeEquation, ...]
    M: tuple[tuple[se.Basic, ...], ...]
    F: tuple[se.Basic, ...]


class _FromCourse:
    """A field of `EquationsOfMotion` that, left as None, is taken from the course's derivation on first use.

    A data descriptor as the dataclass field's default (the dataclasses "descriptor-typed
    field"): the default is None, ``__set__`` stores what ``__init__`` or `dataclasses.replace`
    gives, and ``__get__`` answers it, or the course form's value when it is None.
    """

    def __set_name__(self, owner: type, name: str) -> None:
        self.name, self.slot = name, "_" + name

    def __get__(self, obj, objtype=None):
        if obj is None:
            return None
        value = obj.__dict__.get(self.slot)
        return getattr(obj._course, self.name) if value is None else value

    def __set__(self, obj, value) -> None:
        obj.__dict__[self.slot] = value


@dataclass(frozen=True)
class EquationsOfMotion:
    """Everything `derive` finds for a model, as values to print, inspect and reuse.

    With a recursive form, `derive` leaves T_terms, inertias, loads, equations, M and F to
    ``course``, run on first use of any of them: compiling and simulating a robot need none.

    Parameters
    ----------
    model : Model
        The input.
    kinematics : Kinematics
        Its kinematics (Ω, V, γ, V*).
    T_terms : tuple of KineticEnergyTerm
        T(Σ/R0) body by body, with the theorem used; ``T`` is their sum.
    inertias : dict of str to RigidInertia
        The inertia matrix each body's T uses.
    loads : tuple of LoadForces
        Q_i of every load by virtual power, with its potential if conservative.
    equations : tuple of LagrangeEquation
        The n Lagrange equations L(q_i) (Remarque 1: as many as coordinates).
    M : tuple of tuples of SymEngine expressions
        The matrix M(q, t) of M q̈ = F(q, q̇, t), n×n symmetric.
    F : tuple of SymEngine expressions
        The right side F(q, q̇, t), n entries.
    constraints : tuple of ConstraintRow
        The rows of the complementary constraints (step 7), each ``expression = 0`` with its
        multiplier λ_k; then M q̈ = F + Aᵀλ and A q̈ + c = 0 (`dynamics._constraints`).
    reactions : tuple of ConstraintReaction
        Per complementary constraint, the force/moment its multipliers stand for.
    assumptions : tuple of SignFact
        The signs the derivation proved from the model's declared signs and ranges and used to
        simplify (x + L > 0 where x ≥ −L), each with how it was proved; `simulate` checks them along
        the motion.
    recursive : RecursiveForm, optional
        For a kinematic tree, M q̈ = F over named intermediates (`dynamics._recursive`), which the
        compiled code uses; None when the course's derivation is the only one.
    course : callable, optional
        Makes the course's derivation (`CourseForm`) when the fields above it are left out.

    Attributes
    ----------
    q, qd, qdd : tuple of SymEngine Symbol
        The coordinate symbols q_i, q̇_i, q̈_i.
    t : SymEngine Symbol
        The time.
    derived_with : str or None
        The ``formulation`` `derive` made these equations with; None for equations made otherwise
        (by hand, or changed with `dataclasses.replace`, which leaves it out).  With the model, it
        names the equations for the compile plans (`lagrangian.numerics._plans`).
    """

    model: Model
    kinematics: Kinematics
    T_terms: tuple[KineticEnergyTerm, ...] = _FromCourse()  # type: ignore[assignment]
    inertias: dict[str, RigidInertia] = _FromCourse()  # type: ignore[assignment]
    loads: tuple[LoadForces, ...] = _FromCourse()  # type: ignore[assignment]
    equations: tuple[LagrangeEquation, ...] = _FromCourse()  # type: ignore[assignment]
    M: tuple[tuple[se.Basic, ...], ...] = _FromCourse()  # type: ignore[assignment]
    F: tuple[se.Basic, ...] = _FromCourse()  # type: ignore[assignment]
    constraints: tuple[ConstraintRow, ...] = ()
    reactions: tuple[ConstraintReaction, ...] = ()
    assumptions: tuple[SignFact, ...] = ()
    recursive: RecursiveForm | None = field(default=None, repr=False, compare=False)
    course: Callable[[], CourseForm] | None = field(default=None, repr=False, compare=False)
    derived_with: str | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        n = len(self.model.coordinates)
        if any(len(row.coefficients) != n for row in self.constraints):
            raise DerivationError(f"each constraint row must have {n} coefficients A_ki, one per coordinate")
        if len({row.multiplier for row in self.constraints}) != len(self.constraints):
            raise DerivationError("each complementary constraint row must have its own multiplier")
        if self.__dict__.get("_M") is not None:
            self._check(self.M, self.F, self.equations)

    def _check(self, M, F, equations) -> None:
        n = len(self.model.coordinates)
        if len(M) != n or any(len(row) != n for row in M) or len(F) != n:
            raise DerivationError(f"M must be {n}×{n} and F of length {n}, one per coordinate")
        if len(equations) != n:
            raise DerivationError("there must be as many Lagrange equations as coordinates (Remarque 1)")

    @cached_property
    def _course(self) -> CourseForm:
        if self.course is None:
            raise DerivationError("these equations of motion were made without the course's derivation",
                                  fix="derive the model with lagrangian.derive")
        form = self.course()
        self._check(form.M, form.F, form.equations)
        return form

    @property
    def formulation(self) -> str:
        """"recursive" when the compiled code uses `recursive`, else "lagrange"."""
        return "lagrange" if self.recursive is None else "recursive"

    @property
    def q(self) -> tuple[se.Symbol, ...]:
        return self.kinematics.q

    @property
    def qd(self) -> tuple[se.Symbol, ...]:
        return self.kinematics.qd

    @property
    def qdd(self) -> tuple[se.Symbol, ...]:
        return self.kinematics.qdd

    @property
    def t(self) -> se.Symbol:
        return self.kinematics.t

    @property
    def coordinates(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.model.coordinates)

    @property
    def T(self) -> se.Basic:
        """T(Σ/R0)."""
        return se.Add(*(term.expression for term in self.T_terms))

    @property
    def U(self) -> se.Basic:
        """U_P(Σ/R0), up to a constant: the sum of the potentials of the conservative loads."""
        return se.Add(*(f.potential for f in self.loads if f.potential is not None))

    @property
    def conservative(self) -> bool:
        """Whether the system is conservative (Remarque 2), constraints included.

        Every given effort derives from a potential and every constraint is perfect and principal — or
        complementary and scleronomic (`scleronomic`).  The engine's constraints are all perfect (ideal:
        their reactions do no virtual work, so they enter as Σ_k λ_k A_ki).  A scleronomic complementary
        row (b_k ≡ 0, A_k free of t) does no work along the motion either (λ_k A_k·q̇ = −λ_k b_k = 0), so
        the system keeps its Lagrangian L = T − U_P, with d/dt(∂L/∂q̇_i) − ∂L/∂q_i = Σ_k λ_k A_ki (the
        constrained form of Remarque 2; Goldstein, Classical Mechanics, §2.4).  A rheonomic row works on
        the motion (power −λ_k b_k): the system is then not conservative.
        """
        return all(f.potential is not None for f in self.loads) and self.scleronomic

    @property
    def scleronomic(self) -> bool:
        """Every complementary constraint row is independent of t: b_k ≡ 0 and no t in A_k (true without rows)."""
        t = self.t
        return all(t not in a.free_symbols for row in self.constraints for a in row.coefficients) and (
            all(are_zero([row.b for row in self.constraints])))

    @property
    def L(self) -> se.Basic | None:
        """The Lagrangian L = T − U_P when the system is conservative, else None."""
        return self.T - self.U if self.conservative else None

    @property
    def Q_nc(self) -> tuple[se.Basic, ...]:
        """Generalized forces of the non-conservative efforts, Σ over those loads."""
        n = len(self.q)
        return tuple(se.Add(*(f.Q[i] for f in self.loads if f.potential is None)) for i in range(n))

    @property
    def multipliers(self) -> tuple[se.Symbol, ...]:
        """The multipliers λ_k of the complementary constraint rows (empty without complementary constraints)."""
        return tuple(row.multiplier for row in self.constraints)

    @property
    def A(self) -> tuple[tuple[se.Basic, ...], ...]:
        """The m×n matrix A of the complementary rows A q̇ + b = 0."""
        return tuple(row.coefficients for row in self.constraints)

    def equation(self, coordinate: str) -> LagrangeEquation:
        for eq in self.equations:
            if eq.coordinate == coordinate:
                return eq
        raise KeyError(coordinate)

    def to_sympy(self, *, time_functions: bool = False) -> SympyEquations:
        """M, F, the equations L(q_i), T, U, L, the multipliers and λ's formulas as SymPy objects.

        Symbols are named as in the model (``theta``, ``theta_dot``, ``theta_ddot``, the
        parameters); with ``time_functions=True`` the coordinates are SymPy mechanics'
        ``dynamicsymbols`` θ(t) and the rates Derivative(θ(t), t), Derivative(θ(t), (t, 2)).
        The conversion is structural (no text is parsed, nothing is simplified).  The same form
        with the first integrals is ``lagrangian.sympy_equations(eom)``.  See `SympyEquations`
        and docs/interop.md.

        Parameters
        ----------
        time_functions : bool, optional
            With ``time_functions=True`` the coordinates are SymPy mechanics' ``dynamicsymbols`` θ(t) and
            the rates Derivative(θ(t), t), Derivative(θ(t), (t, 2)); else plain symbols named as in the
            model (``theta``, ``theta_dot``, ``theta_ddot``, the parameters).

        Returns
        -------
        SympyEquations
            M, F, the equations, T, U, L and the multipliers' formulas; its ``first_integrals`` is None.
        """
        from ._sympy_form import sympy_form  # SymPy loaded on use, not with the stage

        return sympy_form(self, time_functions=time_functions)

    # -- Jupyter (IPython's display protocol: drawn by the output stage, `lagrangian._display`) -------
    def _repr_latex_(self) -> str:
        """The n equations L(q_i) (and the complementary rows) as display math, bounded in size."""
        return render(self, "latex")

    def _repr_markdown_(self) -> str:
        """The model, its coordinates, then the equations as in `_repr_latex_`."""
        return render(self, "markdown")


def lagrange_equations(kin: Kinematics, T: se.Basic, U: se.Basic,
                       Q_nc: tuple[se.Basic, ...]) -> tuple[LagrangeEquation, ...]:
    """L(q_i) from T, U and Q_nc:  d/dt(∂T/∂q̇_i) − ∂T/∂q_i = −∂U/∂q_i + Q_i(nc).

    Up to `GROUPED_MAX_COORDINATES` coordinates, d/dt(∂T/∂q̇_i) is written grouped by the
    q̈_j and q̇_j, as the course collects terms (``kin.d_dt``).  Grouping costs 2n passes
    over each ∂T/∂q̇_i, O(n⁴) in all for an n-link chain (a second for 40 links), so
    beyond that d/dt is taken by the chain rule with the work on shared subexpressions
    done once (``kin.d_dt.many``): the same functions, with products left as products.
    """
    dT_dqd = [T.diff(qd) for qd in kin.qd]
    if kin.n <= GROUPED_MAX_COORDINATES:
        rates = [kin.d_dt(f) for f in dT_dqd]
    else:
        rates = list(kin.d_dt.many(dT_dqd))
    out = []
    for c, q, p, rate, q_nc in zip(kin.model.coordinates, kin.q, dT_dqd, rates, Q_nc, strict=True):
        dT_dq = T.diff(q)
        dU_dq = U.diff(q)
        lhs = rate if type(dT_dq) is _ZERO_TYPE else rate - dT_dq
        rhs = -dU_dq if type(q_nc) is _ZERO_TYPE else -dU_dq + q_nc
        out.append(LagrangeEquation(c.name, p, dT_dq, dU_dq, q_nc, lhs, rhs))
    return tuple(out)


def _check_size(model: Model, kin: Kinematics, M, F) -> None:
    """Refuse equations of motion past `max_ops` operations before anything compiles or checks them."""
    names = [str(q) for q in kin.q]
    named = {f"M[{a}, {b}]": M[i][j] for i, a in enumerate(names) for j, b in enumerate(names)}
    named.update({f"F[{a}]": F[i] for i, a in enumerate(names)})
    limit = max_ops()
    over = equations_size(named, limit)
    if over is not None:
        total, largest, size = over
        raise ModelError(
            f"the equations of motion M q'' = F of {len(names)} coordinates are too large: {total:,} operations, "
            f"more than the {limit:,} allowed (the largest entry, {largest}, has {size:,}).",
            fix=f"use fewer bodies or coordinates, or simpler positions and rotations; for a model you trust, "
                f"set the environment variable {MAX_OPS_VARIABLE} to a larger number of operations",
            file=model.source)


def derive(model: Model, *, formulation: str = "auto") -> EquationsOfMotion:
    """From a model to its Lagrange equations, following the seed's steps 2–6.

    Parameters
    ----------
    model : Model
        A checked `Model` (`load_model`, `parse_model` or `ModelBuilder.build`).
    formulation : {"auto", "lagrange", "recursive"}, optional
        "recursive" also builds M and F of a kinematic tree by the recursive multibody algorithms
        over named intermediates (`dynamics._recursive`: what the compiled code then uses, linear in
        the number of joints where the expanded entries swell); "auto" (the default) does so for
        trees with at least `AUTO_MIN_DEPTH` moving rotations in series.  The course's equations are
        the same in every case (on first use with a recursive form).

    Returns
    -------
    EquationsOfMotion
        T, U, the Q_i of every load, the n equations L(q_i) and M q̈ = F.

    Raises
    ------
    ModelError
        For data only kinematics can check (non-physical inertia, a fixed point that moves).
    DerivationError
        For ``formulation="recursive"`` on a model that is not a kinematic tree (why, and the fix).
        Also for equations of motion larger than `lagrangian.model._limits.MAX_OPS` operations
        (checked on the course's expanded M and F).
    """
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {', '.join(FORMULATIONS)}, not {formulation!r}")
    kin = reference_kinematics(model)  # relative to R0, or to the model's [reference] frame R (Remarque 3)
    assumptions = Assumptions(model)  # declared signs and ranges: |x + L| = x + L where x ≥ −L
    recursive = None
    if formulation != "lagrange":
        tree = require_tree(kin) if formulation == "recursive" else tree_structure(kin)
        if not isinstance(tree, str) and (formulation == "recursive" or tree.depth >= AUTO_MIN_DEPTH):
            recursive = recursive_form(kin, tree, generalized_forces(kin, assumptions, only=tree.other_loads))

    def course() -> CourseForm:
        T_terms, inertias = kinetic_energy(kin)
        # + Coriolis and entrainment when R is not R0
        loads = generalized_forces(kin, assumptions) + inertial_forces(kin)
        T = sum_of([term.expression for term in T_terms])
        U = sum_of([f.potential for f in loads if f.potential is not None])
        n = kin.n
        Q_nc = tuple(sum_of([f.Q[i] for f in loads if f.potential is None]) for i in range(n))
        equations = lagrange_equations(kin, T, U, Q_nc)
        M, gamma0 = mass_matrix_and_bias(kin, inertias)
        Q_total = tuple(sum_of([f.Q[i] for f in loads]) for i in range(n))
        F = tuple(Q if type(g) is _ZERO_TYPE else Q - g for Q, g in zip(Q_total, gamma0, strict=True))
        _check_size(model, kin, M, F)
        return CourseForm(T_terms, inertias, loads, equations, M, F)

    if recursive is not None:
        return _made_by_derive(EquationsOfMotion(model, kin, recursive=recursive, course=course,
                                                 assumptions=tuple(assumptions.facts)), formulation)
    form = course()
    rows: tuple[ConstraintRow, ...] = ()
    reactions: tuple[ConstraintReaction, ...] = ()
    equations = form.equations
    if model.constraints:  # step 7: the complementary equations, and λ_k A_ki in each L(q_i)
        equations, rows, reactions = complementary_constraints(kin, form.equations)
    return _made_by_derive(EquationsOfMotion(model, kin, form.T_terms, form.inertias, form.loads, equations, form.M,
                                             form.F, rows, reactions, tuple(assumptions.facts)), formulation)


def _made_by_derive(eom: EquationsOfMotion, formulation: str) -> EquationsOfMotion:
    object.__setattr__(eom, "derived_with", formulation)  # a frozen dataclass's field not given to __init__
    return eom
