"""Complementary constraints: multipliers in L(q_i), the complementary equations, the reactions.

Seed, steps 1 and 7: a constraint kept *complementary* is not eliminated by the choice of
the q_i; its reaction then stays in the Lagrange equations as a non-conservative effort
("Q_i(nc) ... de tous les efforts ... de liaison"), and the constraint itself is written
next to them.  With each scalar row k written at velocity level as

    Σ_i A_ki(q, t) q̇_i + b_k(q, t) = 0       (holonomic f_k(q, t) = 0: A_ki = ∂f_k/∂q_i, b_k = ∂f_k/∂t)

and the reaction perfect (its virtual power vanishes for every virtual velocity field
compatible with the constraint, A q* = 0), its generalized force is Σ_k λ_k A_ki, so

    L(q_i)   d/dt[∂T/∂q̇_i] − ∂T/∂q_i = −∂U/∂q_i + Q_i(nc) + Σ_k λ_k A_ki

with one unknown multiplier λ_k per row.  **Sign convention**: λ_k multiplies +A_ki,
i.e. the reaction's virtual power is Σ_k λ_k (Σ_i A_ki q_i*); a reaction force is what
the constraint exerts *on* the body (on the point named first).  Differentiating each
row once more (holonomic rows twice in all) gives A q̈ + c = 0 with c = Ȧ q̇ + ḃ, so
M q̈ = F + Aᵀ λ and A q̈ = −c determine q̈ and λ together (`multiplier_formulas`,
`lagrangian.numerics` along a motion).

The reaction is turned into physical efforts: a ``no_slip`` row k along axis e_k of
its frame is exactly the virtual power of the force λ_k e_k at the contact point, and
so is a ``coincide`` row (on the constraint manifold); for a scalar constraint with
``reaction = { force_at = "P", moment_on = "S" }`` the force R at P and moment C on S
are solved from  R·∂V(P)/∂q̇_i + C·∂Ω(S)/∂q̇_i = Σ_k λ_k A_ki  for every i.
"""

from __future__ import annotations

import dataclasses
import math
import random
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se
from symengine.lib.symengine_wrapper import sympy2symengine

from .._abs_derivative import settled
from .._identity import are_zero, is_zero
from ..errors import DerivationError, ModelError
from ..kinematics import Kinematics
from ..model import GALILEAN_FRAME, Constraint, Vector
from ..model.vectors import sum_of

__all__ = [
    "FORMULA_MAX_SIZE",
    "MULTIPLIER_PREFIX",
    "ConstraintInfo",
    "ConstraintReaction",
    "ConstraintRow",
    "SLIDING_SUFFIX",
    "RowChoice",
    "admissible_integrals",
    "complementary_constraints",
    "describe_constraints",
    "integrate_row",
    "multiplier_formulas",
    "multiplier_symbol",
    "reaction_efforts",
    "sliding_row",
]

#: Multipliers are named ``lambda_<row>`` (λ_length, λ_rolling_x0, ...).
MULTIPLIER_PREFIX = "lambda_"
#: Relative size below which a singular value counts as zero in the rank tests.
RANK_RTOL = 1e-9
#: Relative size above which a row's coefficient in a dependency Σ_j c_j A_j = 0 is not noise.
DEPENDENCE_RTOL = 1e-6
#: Largest n + m for which `multiplier_formulas` solves for λ symbolically.
FORMULA_MAX_SIZE = 6

_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)


@dataclass(frozen=True, slots=True)
class ConstraintRow:
    """One scalar complementary constraint, with its multiplier λ_k.

    Attributes
    ----------
    name : the row's name: the constraint's, or ``<constraint>_<axis>`` for a vector constraint.
    constraint : the declaration it comes from.
    kind : ``"holonomic"`` (``expression`` is f(q, t)) or ``"nonholonomic"`` (a·q̇ + b).
    expression : the complementary equation of step 7 is ``expression = 0``.
    coefficients : A_k1..A_kn (∂f/∂q_i, or the coefficient of q̇_i).
    b : ∂f/∂t, or the part of a nonholonomic row free of rates.
    multiplier : λ_k.
    velocity : A_k q̇ + b_k (for a holonomic row, df_k/dt).
    bias : c_k, the q̈-free part of d/dt(velocity): the rows hold A q̈ + c = 0 along a motion.
    """

    name: str
    constraint: str
    kind: str
    expression: se.Basic
    coefficients: tuple[se.Basic, ...]
    b: se.Basic
    multiplier: se.Symbol
    velocity: se.Basic
    bias: se.Basic


@dataclass(frozen=True, slots=True)
class RowChoice:
    """The rows the engine kept of a vector constraint whose rows in its declared frame are dependent.

    Attributes
    ----------
    declared_frame, declared_rows : the frame the constraint was written in, and its non-zero rows there.
    rank : the rank of those rows at generic states (fewer than the rows).
    frame : the frame whose axes carry the kept rows (exactly ``rank`` non-zero components there),
        or None when ``rank`` rows of the declared frame were kept (pivoted QR).
    kept : the names of the kept rows.
    """

    declared_frame: str
    declared_rows: tuple[str, ...]
    rank: int
    frame: str | None
    kept: tuple[str, ...]

    @property
    def text(self) -> str:
        """The choice in one sentence (derive's step 7, the JSON's ``row_choice``, the reaction's note)."""
        declared = (f"written in {self.declared_frame}, the {len(self.declared_rows)} rows "
                    f"{', '.join(self.declared_rows)} have rank {self.rank} at generic states")
        kept = ", ".join(self.kept)
        if self.frame is not None:
            return (f"rows chosen by the engine: {declared}; the same vector is written along the axes of "
                    f"{self.frame}, where exactly {self.rank} of its components are not identically zero: {kept}")
        return (f"rows chosen by the engine: {declared}; {kept} are kept (rank-revealing QR with column pivoting "
                "at a generic state, independent at the others), the other rows being combinations of them")


@dataclass(frozen=True, slots=True)
class ConstraintReaction:
    """The effort a complementary constraint exerts, in terms of its multipliers.

    Attributes
    ----------
    constraint : the declaration's name.
    point : where ``force`` acts (on the body or particle it belongs to), or None.
    body : the body ``moment`` acts on, or None.
    counter_point : a point that receives −``force`` (the second point of a ``coincide``
        constraint when it moves), or None.
    frame : the basis of ``force_components`` and ``moment_components``.
    force, moment : vectors, linear in the multipliers (zero when not carried).
    generalized : Σ_k λ_k A_ki, its generalized force on each coordinate (always given).
    note : how it was found, and where it holds.
    """

    constraint: str
    point: str | None
    body: str | None
    counter_point: str | None
    frame: str
    force: Vector
    moment: Vector
    force_components: tuple[se.Basic, se.Basic, se.Basic]
    moment_components: tuple[se.Basic, se.Basic, se.Basic]
    generalized: tuple[se.Basic, ...]
    note: str
    #: When the engine chose the rows of a vector constraint (`_independent_rows`): which and why.
    row_choice: RowChoice | None = None

    @property
    def physical(self) -> bool:
        """True when the reaction is known as a force and/or a moment (not only as generalized forces)."""
        return self.point is not None or self.body is not None


def multiplier_symbol(row: str) -> se.Symbol:
    """λ of the row named ``row``."""
    return se.Symbol(MULTIPLIER_PREFIX + row)


# -- rows ------------------------------------------------------------------------------------------
def _error(kin: Kinematics, c: Constraint, message: str, fix: str, key: str | None = None) -> ModelError:
    loc = kin.model.where("constraint", c.name).of(key or c.form)
    return ModelError(message, fix=fix, symbol=c.name, file=loc.file, line=loc.line)


def _axis_names(kin: Kinematics, frame: str) -> tuple[str, str, str]:
    return kin.frames.axes(frame)


def _raw_rows(kin: Kinematics, c: Constraint, frame: str | None = None) -> list[tuple[str, int | None, se.Basic]]:
    """(row name, axis index or None, expression) for every scalar row, zero rows included.

    A vector form's rows are its components along the axes of ``frame`` (default: the declared one).
    """
    if c.form == "no_slip":
        body = kin.model.body(c.body)  # type: ignore[arg-type]
        # Each vector lifted to the highest frame where it reads the same (φ̇ y2 = φ̇ y1 about a
        # common axis), so that Ω ∧ GI is formed where it is shortest: −r φ̇ x1, not r φ̇ (sin²φ + cos²φ).
        lift = kin.frames.lift
        GI = lift(kin.position(c.points[0]) - kin.position(body.name))
        value: se.Basic | Vector = kin.velocity(body.name) + kin.frames.cross(lift(kin.omega(body.frame)), GI, c.frame)
    elif c.form == "coincide":
        value = kin.position(c.points[0]) - kin.position(c.points[1])
    else:
        value = c.expression
    if not isinstance(value, Vector):
        return [(c.name, None, value)]
    frame = frame or c.frame
    comps = kin.frames.express(value, frame)
    axes = _axis_names(kin, frame)
    # `axes` keeps only some rows: a wheel's normal row is the derivative of its holonomic contact.
    kept = c.axes if c.axes is not None and frame == c.frame else (0, 1, 2)
    return [(f"{c.name}_{axes[k]}", k, comps[k]) for k in kept]


def _row(kin: Kinematics, c: Constraint, name: str, expr: se.Basic) -> ConstraintRow:
    if c.kind == "holonomic":
        A = tuple(expr.diff(q) for q in kin.q)
        b = expr.diff(kin.t)
        velocity = kin.d_dt(expr, accelerations=False)
    else:
        A = tuple(expr.diff(qd) for qd in kin.qd)
        b = expr.xreplace({qd: _ZERO for qd in kin.qd})
        velocity = expr
    bias = kin.d_dt(velocity, accelerations=False)
    return ConstraintRow(name, c.name, c.kind, expr, A, b, multiplier_symbol(name), velocity, bias)


def _rows_of(kin: Kinematics, c: Constraint) -> tuple[list[ConstraintRow], list[int | None], str, RowChoice | None]:
    """The complementary rows of ``c`` with their axes, the frame of those axes, and the choice of
    `_independent_rows` when the engine chose the rows (None otherwise)."""
    raw = _raw_rows(kin, c)
    zero = are_zero([e for _, _, e in raw])
    if c.principal:
        left = [name for (name, _, e), z in zip(raw, zero, strict=True) if not z]
        if left:
            expr = next(e for (name, _, e), z in zip(raw, zero, strict=True) if not z)
            raise _error(kin, c, f"constraint `{c.name}` is declared principal, but the coordinates do not satisfy it: "
                         f"`{left[0]}` = `{expr}` is not identically zero",
                         fix="make it complementary (remove `principal = true`): it then gets a multiplier; or "
                             "choose coordinates that satisfy it", key="principal")
        return [], [], c.frame, None
    kept = [(name, axis, e) for (name, axis, e), z in zip(raw, zero, strict=True) if not z]
    if not kept:
        raise _error(kin, c, f"complementary constraint `{c.name}` is identically satisfied by the coordinates, so "
                     "it has no multiplier and no reaction to find",
                     fix="declare it principal (`principal = true`), or remove it")
    rows = [_row(kin, c, name, e) for name, _, e in kept]
    if c.unilateral and c.slip is not None:  # a contact with friction: its sliding row, active while it sticks
        rows.append(sliding_row(kin, c))
        kept.append((rows[-1].name, None, c.slip))
    for row in rows:
        if all(are_zero(row.coefficients)):
            raise _error(kin, c, f"constraint row `{row.name}` = `{str(row.expression).replace('**', '^')}` involves no coordinate "
                         f"{'' if c.kind == 'holonomic' else 'rate '}, so it cannot be satisfied by the motion",
                         fix="check the expression: it must involve the coordinates "
                             + ("(f(q, t) = 0)" if c.kind == "holonomic" else "through their rates (a·q̇ + b = 0)"))
    return _independent_rows(kin, c, rows, [axis for _, axis, _ in kept])


#: The sliding row of the contact ``c`` (with friction) is named ``c_t``, its multiplier ``lambda_c_t``.
SLIDING_SUFFIX = "_t"


def sliding_row(kin: Kinematics, c: Constraint) -> ConstraintRow:
    """The row w = a(q, t)·q̇ + b(q, t) = 0 of a unilateral contact with friction: while closed it sticks, and its
    multiplier is the tangential reaction, bounded by Coulomb's law (`lagrangian.numerics._contact`)."""
    return _row(kin, dataclasses.replace(c, form="nonholonomic", expression=c.slip), c.name + SLIDING_SUFFIX,
                c.slip)


# -- rows chosen by the engine ---------------------------------------------------------------------
#: Seeds of the generic random states at which the rank of a vector constraint's rows is measured.
ROW_CHOICE_SEEDS = (3, 11, 29)


def _augmented(kin: Kinematics, rows: Sequence[ConstraintRow], seed: int) -> np.ndarray:
    """[A | b] of ``rows`` at the random state drawn from ``seed`` (parameters at their values)."""
    matrix = [[*r.coefficients, r.b] for r in rows]
    symbols = set().union(*(e.free_symbols for row in matrix for e in row))
    return _numeric(matrix, _random_values(symbols, kin.model.parameter_values, seed))


def _rank(a: np.ndarray) -> int:
    """The numeric rank of rows at a random state; full when a coefficient is undefined there (the rows are
    then taken as declared, and the integration judges them at the states the motion reaches)."""
    if not np.isfinite(a).all():
        return min(a.shape)
    return int(np.linalg.matrix_rank(a, tol=RANK_RTOL * max(1.0, float(np.abs(a).max(initial=0.0)))))


def _candidate_frames(kin: Kinematics, declared: str) -> list[str]:
    """Frames in which to write a vector constraint's rows: the declared frame's ancestors, nearest
    first, then the other declared frames, then the intermediate frames of rotation sequences."""
    frames = kin.model.frames
    parent = {f.name: f.parent for f in frames}
    chain = []
    name = parent[declared]
    while name is not None:
        chain.append(name)
        name = parent[name]
    named = [n for n in chain if not n.startswith("_")] + [f.name for f in frames
                                                            if f.name not in chain and not f.name.startswith("_")]
    hidden = [n for n in chain if n.startswith("_")] + [f.name for f in frames
                                                         if f.name not in chain and f.name.startswith("_")]
    return [n for n in named + hidden if n != declared]


def _independent_rows(kin: Kinematics, c: Constraint, rows: list[ConstraintRow],
                      axes: list[int | None]) -> tuple[list[ConstraintRow], list[int | None], str, RowChoice | None]:
    """An independent set of rows for the vector constraint ``c`` whose rows in its frame are dependent.

    The components of V(I ∈ S/R0) in the disk's own frame are three rows of rank two for a
    disk rolling on a plane (its vertical component vanishes identically): rolling is two
    conditions, written along three axes.  The rank r is measured at generic random states
    (`ROW_CHOICE_SEEDS`; SVD, relative tolerance `RANK_RTOL`), then

    1. the same vector is written in the nearest frame where exactly r of its components are
       non-zero and independent (the declared frame's ancestors first): the heading frame of
       the disk.  Those rows are independent wherever the constraint's rank is r, unlike any
       fixed subset of the disk-frame rows (they are cos φ and sin φ times one row: either
       subset loses rank where the disk has turned a quarter of a turn);
    2. failing that, r rows of the declared frame are kept by a rank-revealing QR with column
       pivoting of Aᵀ at the first state, checked independent at the others.

    Rows whose coefficients are dependent but whose terms b are not ([A | b] of larger rank)
    ask for incompatible velocities: refused, as is a set with no independent subset.
    An explicit ``axes`` is the user's choice and is kept as given (`_check_rank` judges it).
    """
    if len(rows) < 2 or c.axes is not None:
        return rows, axes, c.frame, None
    states = [_augmented(kin, rows, seed) for seed in ROW_CHOICE_SEEDS]
    rank = max(_rank(a[:, :-1]) for a in states)
    if rank == len(rows):
        return rows, axes, c.frame, None
    names = ", ".join(f"`{r.name}`" for r in rows)
    if any(_rank(a) > _rank(a[:, :-1]) for a in states):
        raise _error(kin, c, f"the {len(rows)} rows of constraint `{c.name}` ({names}) are inconsistent: their "
                     f"coefficients A have rank {rank} at a generic state but [A | b] has rank {rank + 1}, so they "
                     "ask for different velocities of the same combination of coordinates and no motion satisfies "
                     "them all", fix="check the constraint's expression (its components contradict each other), "
                     "or keep only the rows you mean with `axes`")
    declared = f"written in {c.frame}, its {len(rows)} rows {names} have rank {rank} at generic states"
    for frame in _candidate_frames(kin, c.frame):
        raw = _raw_rows(kin, c, frame)
        nonzero = [(name, axis, e) for (name, axis, e), z in zip(raw, are_zero([e for _, _, e in raw]), strict=True) if not z]
        if len(nonzero) != rank:
            continue
        chosen = [_row(kin, c, name, e) for name, _, e in nonzero]
        if all(_rank(_augmented(kin, chosen, seed)[:, :-1]) == rank for seed in ROW_CHOICE_SEEDS):
            choice = RowChoice(c.frame, tuple(r.name for r in rows), rank, frame, tuple(r.name for r in chosen))
            return chosen, [a for _, a, _ in nonzero], frame, choice
    # No frame has exactly r non-zero components: keep r rows of the declared frame (pivoted QR of Aᵀ).
    import scipy.linalg  # late: only this rare path needs it

    _, _, pivots = scipy.linalg.qr(states[0][:, :-1].T, pivoting=True, mode="economic")
    keep = sorted(int(k) for k in pivots[:rank])
    if not all(_rank(a[keep, :-1]) == rank for a in states):  # pragma: no cover - a generic state is generic
        raise _error(kin, c, f"constraint `{c.name}`: {declared}, and no {rank} of them stay independent",
                     fix="write the constraint in a frame where its components are independent (`frame`), or keep "
                         "the rows you mean with `axes`")
    choice = RowChoice(c.frame, tuple(r.name for r in rows), rank, None, tuple(rows[k].name for k in keep))
    return [rows[k] for k in keep], [axes[k] for k in keep], c.frame, choice


# -- reactions ------------------------------------------------------------------------------------
def _random_values(symbols: set[se.Basic], model_values: dict[str, float | None], seed: int) -> dict[se.Basic, float]:
    rng = random.Random(seed)
    out = {}
    for s in sorted(symbols, key=str):
        v = model_values.get(str(s))
        out[s] = float(v) if v is not None else rng.uniform(0.3, 1.7)
    return out


def _numeric(matrix: Sequence[Sequence[se.Basic]], values: dict[se.Basic, float]) -> np.ndarray:
    """The matrix at ``values`` (d|ψ|/dψ as sign ψ, `settled`); nan where SymEngine cannot evaluate an
    entry, so that the rank tests take the rows as declared."""
    sub = {k: se.RealDouble(v) for k, v in values.items()}

    def value(e: se.Basic) -> float:
        try:
            return complex(settled(e).xreplace(sub)).real
        except (RuntimeError, TypeError, ValueError, OverflowError):
            return math.nan

    return np.array([[value(e) for e in row] for row in matrix], dtype=float)


def _solve_reaction(kin: Kinematics, c: Constraint, rows: list[ConstraintRow],
                    generalized: tuple[se.Basic, ...]) -> tuple[Vector, Vector, str]:
    """Force at ``force_at`` and moment on ``moment_on`` whose virtual power is Σ_i Q_i q_i* (module docstring)."""
    spec = c.reaction
    assert spec is not None
    frame = spec.frame
    columns: list[tuple[str, int, tuple[se.Basic, ...]]] = []  # (force|moment, axis, J[:, column])
    if spec.force_at is not None:
        partials = [kin.frames.express(v, frame) for v in kin.partial_velocities(spec.force_at)]
        columns += [("force", k, tuple(p[k] for p in partials)) for k in range(3)]
    if spec.moment_on is not None:
        partials = [kin.frames.express(w, frame) for w in kin.partial_omegas(kin.model.body(spec.moment_on).frame)]
        columns += [("moment", k, tuple(p[k] for p in partials)) for k in range(3)]
    n = kin.n
    J = [[col[2][i] for col in columns] for i in range(n)]
    symbols = set().union(*(e.free_symbols for row in J for e in row), *(g.free_symbols for g in generalized))
    values = _random_values(symbols, kin.model.parameter_values, seed=7)
    Jn = _numeric(J, values)
    # Independent columns (greedy), then as many independent rows among them.
    chosen_cols: list[int] = []
    for j in range(len(columns)):
        trial = Jn[:, chosen_cols + [j]]
        if np.linalg.matrix_rank(trial, tol=RANK_RTOL * max(1.0, np.abs(Jn).max())) == len(chosen_cols) + 1:
            chosen_cols.append(j)
    chosen_rows: list[int] = []
    for i in range(n):
        trial = Jn[np.ix_(chosen_rows + [i], chosen_cols)]
        if np.linalg.matrix_rank(trial, tol=RANK_RTOL * max(1.0, np.abs(Jn).max())) == len(chosen_rows) + 1:
            chosen_rows.append(i)
    r = len(chosen_cols)
    solution = [_ZERO] * len(columns)
    if r:
        K = se.DenseMatrix([[J[i][j] for j in chosen_cols] for i in chosen_rows])
        rhs = se.DenseMatrix([[generalized[i]] for i in chosen_rows])
        x = K.LUsolve(rhs)
        for k, j in enumerate(chosen_cols):
            solution[j] = se.expand(x[k, 0]) if len(str(x[k, 0])) < 400 else x[k, 0]
    residues = [sum_of([J[i][j] * solution[j] for j in range(len(columns)) if type(solution[j]) is not _ZERO_TYPE])
                - generalized[i] for i in range(n)]
    if not all(are_zero(residues)):
        where = " and ".join(x for x in (spec.force_at and f"a force at `{spec.force_at}`",
                                          spec.moment_on and f"a moment on `{spec.moment_on}`") if x)
        raise _error(kin, c, f"the reaction of constraint `{c.name}` cannot be {where}: no such effort has the "
                     "virtual power Σ_k λ_k ∂f_k/∂q_i q_i* of the constraint",
                     fix="name the point where the reaction acts (force_at) and/or the body it turns (moment_on), "
                         "or leave `reaction` out to get the generalized forces only", key="reaction")
    force = [_ZERO, _ZERO, _ZERO]
    moment = [_ZERO, _ZERO, _ZERO]
    for (what, k, _), value in zip(columns, solution, strict=True):
        (force if what == "force" else moment)[k] = value
    free = len(columns) - r
    note = ("solved from R·∂V/∂q̇_i + C·∂Ω/∂q̇_i = Σ_k λ_k A_ki"
            + (f"; {free} component(s) do no virtual work, are not determined by the equations and are set to 0"
               if free else ""))
    return Vector({frame: tuple(force)}), Vector({frame: tuple(moment)}), note


def _reaction(kin: Kinematics, c: Constraint, rows: list[ConstraintRow], axes: list[int | None],
              frame: str, chosen: RowChoice | None) -> ConstraintReaction:
    """The reaction of ``c``; ``frame`` is the basis of the rows of a vector form, ``chosen`` the
    choice of `_independent_rows` when the engine chose them (it opens the reaction's note)."""
    reaction = _reaction_of(kin, c, rows, axes, frame)
    if chosen is None:
        return reaction
    return dataclasses.replace(reaction, note=f"{chosen.text}. {reaction.note}", row_choice=chosen)


def _reaction_of(kin: Kinematics, c: Constraint, rows: list[ConstraintRow], axes: list[int | None],
                 frame: str) -> ConstraintReaction:
    n = kin.n
    generalized = tuple(sum_of([r.multiplier * r.coefficients[i] for r in rows
                                if type(r.coefficients[i]) is not _ZERO_TYPE]) for i in range(n))
    zero3 = (_ZERO, _ZERO, _ZERO)
    if c.form in ("no_slip", "coincide"):
        comps = [_ZERO, _ZERO, _ZERO]
        for row, axis in zip(rows, axes, strict=True):
            comps[axis] = row.multiplier  # type: ignore[index]
        force = Vector({frame: tuple(comps)})
        counter = None
        if c.form == "no_slip":
            note = (f"force on `{c.body}` at the contact point `{c.points[0]}`: row k is the virtual power of "
                    "λ_k e_k there, exactly")
            point = c.points[0]
        else:
            point = c.points[0]
            counter = None if kin.is_fixed(c.points[1]) else c.points[1]
            note = (f"force at `{point}`" + (f", and its opposite at `{counter}`" if counter else "")
                    + "; exact where the constraint holds")
        return ConstraintReaction(c.name, point, None, counter, frame, force, Vector.zero(),
                                  tuple(comps), zero3, generalized, note)
    if c.reaction is None:
        return ConstraintReaction(c.name, None, None, None, GALILEAN_FRAME, Vector.zero(), Vector.zero(), zero3,
                                  zero3, generalized, "generalized forces Σ_k λ_k A_ki only (no `reaction` declared)")
    force, moment, note = _solve_reaction(kin, c, rows, generalized)
    frame = c.reaction.frame
    return ConstraintReaction(c.name, c.reaction.force_at, c.reaction.moment_on, None, frame, force, moment,
                              kin.frames.express(force, frame), kin.frames.express(moment, frame), generalized, note)


# -- redundancy --------------------------------------------------------------------------------------
def _check_rank(kin: Kinematics, rows: list[ConstraintRow], constraints: dict[str, Constraint]) -> None:
    """Rows whose coefficients are combinations of earlier ones, at a generic state: a `ModelError` naming them.

    The rows named are the minimal dependent set: those with a non-negligible coefficient in
    the one combination Σ_j c_j A_j = 0 of the first dependent row with the independent rows
    before it (the left null vector of that block of A, from its SVD).
    """
    A = [list(r.coefficients) for r in rows]
    symbols = set().union(*(e.free_symbols for row in A for e in row))
    An = _numeric(A, _random_values(symbols, kin.model.parameter_values, seed=3))
    if not np.isfinite(An).all():  # undefined at the random state (log(x − 5)): nothing to judge there
        return
    scale = max(1.0, float(np.abs(An).max()))
    kept: list[int] = []
    for k, row in enumerate(rows):
        if np.linalg.matrix_rank(An[kept + [k]], tol=RANK_RTOL * scale) == len(kept) + 1:
            kept.append(k)
            continue
        # The block has rank len(kept): its left null space is one direction, U's last column.
        U, _, _ = np.linalg.svd(An[kept + [k]])
        c = U[:, -1]
        involved = [j for j, cj in zip(kept, c[:-1], strict=True) if abs(cj) > DEPENDENCE_RTOL * abs(c).max()]
        others = ", ".join(f"`{rows[j].name}`" for j in involved)
        what = f"is a combination of {others} only" if involved else "vanishes"
        names = [f"`{row.constraint}`"] + list(dict.fromkeys(f"`{rows[j].constraint}`" for j in involved))
        if all(rows[j].constraint == row.constraint for j in involved) and constraints[row.constraint].axes:
            # Rows of one vector constraint whose `axes` were listed by hand: list fewer.
            raise _error(kin, constraints[row.constraint],
                         f"the rows of constraint `{row.constraint}` kept by its `axes` are redundant: row "
                         f"`{row.name}` {what} (rank < {len(rows)} at a generic state), so their multipliers are "
                         "not determined", key="axes",
                         fix="list fewer axes in `axes`, or leave `axes` out: the engine then keeps an independent "
                             "set of rows by itself and says which")
        raise _error(kin, constraints[row.constraint],
                     f"the complementary constraints are redundant: row `{row.name}` {what} "
                     f"(the Jacobian A of the {len(rows)} rows has rank < {len(rows)} at a generic state), so their "
                     "multipliers are not determined",
                     fix=f"remove `{row.constraint}`, or keep only its rows that say something new with `axes` "
                         f"(axes = [...] of its frame), or declare one of {', '.join(dict.fromkeys(names))} principal "
                         "(the engine chooses the rows within one vector constraint, not between two: which "
                         "reaction carries the effort is for the model to say)")


# -- the entry point -------------------------------------------------------------------------------
def complementary_constraints(kin: Kinematics, equations: tuple) -> tuple[tuple, tuple[ConstraintRow, ...],
                                                                          tuple[ConstraintReaction, ...]]:
    """The rows, the reactions, and ``equations`` with Σ_k λ_k A_ki added to each right-hand side.

    Raises
    ------
    ModelError
        A principal constraint the coordinates do not satisfy, a complementary one they
        satisfy identically, a row that involves no coordinate, redundant rows, a declared
        reaction that no force at that point (or moment on that body) can carry, or a
        multiplier name already taken.
    """
    rows: list[ConstraintRow] = []
    reactions: list[ConstraintReaction] = []
    by_name = {c.name: c for c in kin.model.constraints}
    for c in kin.model.constraints:
        own, axes, frame, chosen = _rows_of(kin, c)
        if not own:
            continue
        rows += own
        reactions.append(_reaction(kin, c, own, axes, frame, chosen))
    if not rows:
        return equations, (), ()
    taken = {p.name for p in kin.model.parameters} | {str(s) for s in (*kin.q, *kin.qd, *kin.qdd)}
    seen: set[str] = set()
    for r in rows:
        if r.multiplier.name in taken:
            raise _error(kin, by_name[r.constraint], f"the multiplier `{r.multiplier.name}` of constraint row "
                         f"`{r.name}` has the name of a parameter or coordinate", fix="rename one of them")
        if r.name in seen:  # a contact `c` with friction has the row `c_t`: a constraint of that name repeats it
            raise _error(kin, by_name[r.constraint], f"two constraint rows are named `{r.name}`",
                         fix="rename the constraint (the sliding row of a contact `c` with friction is `c_t`)")
        seen.add(r.name)
    # The rows of unilateral contacts may be dependent (a ball between two walls): which of them act is
    # decided along the motion (`numerics._contact`); the bilateral ones must be independent.
    bilateral = [r for r in rows if not by_name[r.constraint].unilateral]
    if bilateral:
        _check_rank(kin, bilateral, by_name)
    out = []
    for i, eq in enumerate(equations):
        terms = sum_of([r.multiplier * r.coefficients[i] for r in rows if type(r.coefficients[i]) is not _ZERO_TYPE])
        out.append(dataclasses.replace(eq, multiplier_terms=terms, rhs=eq.rhs + terms)
                   if type(terms) is not _ZERO_TYPE else eq)
    return tuple(out), tuple(rows), tuple(reactions)


# -- consequences -------------------------------------------------------------------------------------
def admissible_integrals(eom, integrals: Sequence) -> tuple:
    """The first integrals that survive the complementary constraints' reactions.

    p_i = ∂T/∂q̇_i stays constant only if no reaction works on q_i (A_ki ≡ 0 for every
    row k); the energy (or Jacobi) integral only if the reactions do no work on the real
    motion: their power Σ_k λ_k (A_k q̇) = −Σ_k λ_k b_k vanishes when every b_k ≡ 0
    (time-independent, homogeneous constraints).

    Parameters
    ----------
    eom : EquationsOfMotion
        Equations with complementary constraints.
    integrals : sequence of FirstIntegral
        The first integrals of the unconstrained system.

    Returns
    -------
    tuple of FirstIntegral
        Those that still hold.
    """
    rows = eom.constraints
    if not rows:
        return tuple(integrals)
    n = len(eom.q)
    column_zero = are_zero([r.coefficients[i] for i in range(n) for r in rows])
    m = len(rows)
    free = [all(column_zero[i * m:(i + 1) * m]) for i in range(n)]
    b_zero = all(are_zero([r.b for r in rows]))
    out = []
    for fi in integrals:
        if fi.kind == "momentum":
            if free[eom.coordinates.index(fi.coordinate)]:
                why = f"; no complementary constraint acts on {fi.coordinate} (A_k,{fi.coordinate} = 0)"
                out.append(dataclasses.replace(fi, reason=fi.reason + why))
        elif b_zero:
            why = "; the reactions of the complementary constraints do no work (b_k = 0: Σ_k λ_k A_k q̇ = 0)"
            if any(c.unilateral for c in eom.model.constraints):
                why += ("; between impacts (an impact takes ½ Σ_k P_k (1 − e_k) |ġ_k⁻| of it, and friction at "
                        "an impact some more)")
            out.append(dataclasses.replace(fi, reason=fi.reason + why))
    return tuple(out)


def multiplier_formulas(eom) -> tuple[se.Basic, ...] | None:
    """The multipliers λ(q, q̇, t) in closed form, from M q̈ = F + Aᵀλ and A q̈ + c = 0 (None when too large).

    λ = (A M⁻¹ Aᵀ)⁻¹ (−c − A M⁻¹ F): solved symbolically only while n + m ≤
    `FORMULA_MAX_SIZE`; larger systems get their multipliers numerically along a motion.
    Public as ``lagrangian.dynamics.multiplier_formulas``; λ_k multiplies +A_ki (the pendulum
    in Cartesian coordinates: the rod's tension is −2 l λ, docs/constraints.md).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.

    Returns
    -------
    tuple of SymEngine expressions or None
        One formula per row of ``eom.constraints`` (in that order), or None without complementary
        rows or beyond `FORMULA_MAX_SIZE`.
    """
    rows = eom.constraints
    n, m = len(eom.q), len(rows)
    if not m or n + m > FORMULA_MAX_SIZE:
        return None
    M = se.DenseMatrix([list(r) for r in eom.M])
    A = se.DenseMatrix([list(r.coefficients) for r in rows])
    F = se.DenseMatrix([[f] for f in eom.F])
    c = se.DenseMatrix([[r.bias] for r in rows])
    try:
        X = M.LUsolve(A.T)  # M⁻¹ Aᵀ
        y = M.LUsolve(F)    # M⁻¹ F
        S = A * X
        lam = S.LUsolve(-c - A * y)
    except (RuntimeError, ValueError, ZeroDivisionError) as exc:  # pragma: no cover - singular symbolic pivots
        raise DerivationError(f"the multipliers could not be solved for symbolically: {exc}",
                              fix="use their values along a simulation") from None
    return tuple(lam[k, 0] for k in range(m))


def reaction_efforts(eom) -> list[tuple[str, str, object, str | None, str | None]]:
    """The complementary reactions as efforts on the system, for the Newton–Euler theorems.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.

    Returns
    -------
    list of tuple
        Items ``(constraint, what, value, at, owner)``: ``what`` is ``"force"`` (``value`` a
        `Vector` applied at point ``at``; ``owner`` the body whose material point receives it at a
        rolling contact, else None: the point's carrier), ``"couple"`` (on body ``owner``) or
        ``"power"`` (``value`` the generalized forces Σ_k λ_k A_ki, for a reaction with no physical
        form).
    """
    out: list[tuple[str, str, object, str | None, str | None]] = []
    forms = {c.name: c for c in eom.model.constraints}
    for r in eom.reactions:
        if not r.physical:
            out.append((r.constraint, "power", r.generalized, None, None))
            continue
        if r.point is not None and not r.force.is_zero():
            c = forms[r.constraint]
            out.append((r.constraint, "force", r.force, r.point, c.body if c.form == "no_slip" else None))
            if r.counter_point is not None:
                out.append((r.constraint, "force", -r.force, r.counter_point, None))
        if r.body is not None and not r.moment.is_zero():
            out.append((r.constraint, "couple", r.moment, None, r.body))
    return out


# -- integrable velocity rows -------------------------------------------------------------------------------
#: Most coordinates (plus t) a velocity row may involve for the integrability test (Frobenius: O(n³) triples).
INTEGRABLE_MAX_VARIABLES = 10


def _exact(coefficients: Sequence[se.Basic], variables: Sequence[se.Basic]) -> bool:
    """Is Σ_v c_v dv closed (∂c_u/∂v = ∂c_v/∂u for every pair), hence exact on a simply connected domain?"""
    pairs = [(u, v) for u in range(len(variables)) for v in range(u + 1, len(variables))]
    return all(are_zero([coefficients[u].diff(variables[v]) - coefficients[v].diff(variables[u])
                         for u, v in pairs]))


def _potential(coefficients: Sequence[se.Basic], variables: Sequence[se.Basic]) -> se.Basic | None:
    """φ with dφ = Σ_v c_v dv (the form being closed), integrating one variable after the other; None
    when SymPy finds no closed form."""
    import sympy  # late: the only use here, and SymPy takes most of a second to load

    phi = sympy.Integer(0)
    for c, v in zip(coefficients, variables, strict=True):
        rest = sympy.expand(c._sympy_() - sympy.diff(phi, v._sympy_()))
        if rest == 0:
            continue
        term = sympy.integrate(rest, v._sympy_())
        if term.has(sympy.Integral):
            return None
        phi += term
    out = sympy2symengine(phi)  # SymPy → SymEngine by structure, no text
    if not all(is_zero(out.diff(v) - c) for c, v in zip(coefficients, variables, strict=True)):
        return None
    return out


def _frobenius(a: Sequence[se.Basic], variables: Sequence[se.Basic]) -> bool:
    """ω ∧ dω = 0 for ω = Σ_v a_v dv: the Pfaffian equation ω = 0 is integrable (Frobenius)."""
    n = len(variables)
    terms = []
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(j + 1, n):
                ai, aj, ak = a[i], a[j], a[k]
                xi, xj, xk = variables[i], variables[j], variables[k]
                terms.append(ai * (aj.diff(xk) - ak.diff(xj)) + aj * (ak.diff(xi) - ai.diff(xk))
                             + ak * (ai.diff(xj) - aj.diff(xi)))
    return all(are_zero(terms))


def integrate_row(kin: Kinematics, row: ConstraintRow) -> tuple[bool, se.Basic | None]:
    """Whether the velocity row a(q, t)·q̇ + b(q, t) = 0 integrates to φ(q, t) = cste, and φ when found.

    The row is the Pfaffian form ω = Σ_i a_i dq_i + b dt = 0 in (q, t).  It is integrable
    when some factor μ makes μω exact, dφ = μω: tried with μ = 1 (a_i constant, or
    ∂a_i/∂q_j = ∂a_j/∂q_i and ∂a_i/∂t = ∂b/∂q_i) and with μ = 1/a_k for each coefficient;
    otherwise Frobenius' ω ∧ dω = 0 still decides (integrable, φ not found).  A rolling disk
    on an incline, ẋ − r φ̇ = 0, gives x − r φ = cste; a coin rolling on a plane
    (ẋ − r φ̇ cos ψ = 0) is not integrable.
    """
    variables = [*kin.q, kin.t]
    coefficients = [*row.coefficients, row.b]
    used = [k for k, c in enumerate(coefficients) if type(c) is not _ZERO_TYPE]
    # Variables that the form involves: those with a coefficient, and those its coefficients depend on.
    symbols = set().union(*(coefficients[k].free_symbols for k in used))
    keep = [k for k, v in enumerate(variables) if k in used or v in symbols]
    if not used or len(keep) > INTEGRABLE_MAX_VARIABLES:
        return False, None
    xs = [variables[k] for k in keep]
    cs = [coefficients[k] for k in keep]
    factors = [se.Integer(1)] + [1 / c for c in cs if type(c) is not _ZERO_TYPE and c != 1]
    for mu in factors:
        scaled = [se.expand(mu * c) for c in cs]
        if _exact(scaled, xs):
            phi = _potential(scaled, xs)
            if phi is not None:
                return True, phi
    return _frobenius(cs, xs), None


# -- plain data for reports and JSON (steps 1 and 7) -------------------------------------------------------
@dataclass(frozen=True, slots=True)
class ConstraintInfo:
    """One declared constraint as the report shows it in steps 1 and 7.

    Attributes
    ----------
    name, form, description : as declared.
    kind : ``"holonomic"`` or ``"nonholonomic"``: as declared, except that a complementary
        constraint written on the velocities (``nonholonomic``, ``no_slip``) whose every row
        integrates (`integrate_row`) is holonomic: the disk rolling on an incline,
        ẋ − r φ̇ = 0, is x − r φ = cste written on the velocities.  The derivation still
        keeps such rows at velocity level (``ConstraintRow.kind``).
    integrals : for such a constraint, φ_k(q, t) of each row (φ_k = cste along every motion;
        the constant is set by the initial state), when found in closed form; else empty.
    role : ``"principal"`` (eliminated by the choice of coordinates; checked, no multiplier)
        or ``"complementary"`` (rows with multipliers, written after the Lagrange equations).
    statement : the relation as the derivation sees it: f(q, t) or a·q̇ + b (scalar), or the
        vector that must vanish (V(I ∈ S/R0) for ``no_slip``, OP − OQ for ``coincide``).
    frame : the basis of the rows of a vector constraint (None for a scalar one).
    rows : its complementary rows (empty when principal).
    reaction : the reaction its multipliers stand for (None when principal).
    """

    name: str
    role: str
    form: str
    kind: str
    description: str | None
    statement: se.Basic | Vector
    frame: str | None
    rows: tuple[ConstraintRow, ...]
    reaction: ConstraintReaction | None
    integrals: tuple[se.Basic, ...] = ()


def describe_constraints(eom) -> tuple[ConstraintInfo, ...]:
    """Every declared constraint of ``eom.model``, principal and complementary, as `ConstraintInfo`.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.

    Returns
    -------
    tuple of ConstraintInfo
        One per declared constraint.
    """
    kin = eom.kinematics
    out = []
    for c in eom.model.constraints:
        raw = _raw_rows(kin, c)
        if len(raw) == 1 and raw[0][1] is None:
            statement: se.Basic | Vector = raw[0][2]
            frame = None
        else:
            comps = [_ZERO, _ZERO, _ZERO]
            for _, axis, e in raw:
                comps[axis] = e  # type: ignore[index]
            statement, frame = Vector({c.frame: tuple(comps)}), c.frame
        rows = tuple(r for r in eom.constraints if r.constraint == c.name)
        reaction = next((r for r in eom.reactions if r.constraint == c.name), None)
        kind = c.kind
        integrals: tuple[se.Basic, ...] = ()
        if c.kind == "nonholonomic" and rows:
            found = [integrate_row(kin, r) for r in rows]
            if all(ok for ok, _ in found):
                kind = "holonomic"
                integrals = (tuple(phi for _, phi in found if phi is not None)
                             if all(phi is not None for _, phi in found) else ())
        out.append(ConstraintInfo(c.name, "principal" if c.principal else "complementary", c.form, kind,
                                  c.description, statement, frame, rows, reaction, integrals))
    return tuple(out)
