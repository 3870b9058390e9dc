"""Terminal text of a derivation, in the order of the course's "démarche d'application".

`render_text` prints a `CourseForm`; with a `Supplement` (`supplement(eom, form)`, what
``lagrangian derive`` passes) it adds the constraints of step 1, the complementary
equations of step 7 with the multipliers λ_k and the reactions they stand for, and the
energy balance dE/dt = P(non-conservative) when no energy integral holds.
"""

from __future__ import annotations

import dataclasses
import functools
import re
from collections.abc import Callable
from dataclasses import dataclass

import sympy

from .._big_numbers import has_big_numbers
from ..analysis import energy_balance
from ..dynamics import (
    FORMULA_MAX_SIZE,
    EquationsOfMotion,
    RelativeKinematics,
    describe_constraints,
    multiplier_formulas,
)
from ..model import SIGN_RELATIONS, Vector, range_text
from ._course import CourseForm, VectorRow, _vector_row, to_sympy
from ._display_form import display_form
from ._notation import Notation

__all__ = ["Supplement", "greek", "kind_words", "literal", "notation", "power_label", "render_text", "supplement"]

_FORMULA = {
    "fixed point": "½ Ω·Π_{P}·Ω",
    "König": "½ m V(G)² + ½ Ω·Π_G·Ω  (König)",
    "particle": "½ m V(P)²",
}

#: Longest dE/dt = P_nc printed whole above its terms (characters).
MAX_SUM_CHARS = 120

#: Load kinds (the engine's lower-cased class names) as words.
_KIND_WORDS = {"pointforce": "point force", "jointdamper": "joint damper", "generalizedforce": "generalized force",
               "coulombfriction": "Coulomb friction"}


def kind_words(kind: str) -> str:
    """A load kind as printed: ``jointdamper`` → ``joint damper``, ``pointforce`` → ``point force``."""
    return _KIND_WORDS.get(kind, kind)


# -- what derive shows beyond the course form ---------------------------------------------------------
@dataclass(frozen=True, slots=True)
class PowerRow:
    """One term of dE/dt = P(non-conservative): ``power`` with its ``name``, ``kind`` and ``note``."""

    name: str
    kind: str
    power: sympy.Basic
    note: str


@dataclass(frozen=True, slots=True)
class ConstraintLine:
    """A declared constraint (step 1) and, when complementary, its rows (step 7).

    ``statement`` is f (one expression) or the three components, in ``axes``, of the vector
    that vanishes; a principal constraint's is the declared relation, not simplified (after
    substitution of the coordinates it is identically zero).  ``rows`` are (row, multiplier,
    equation = 0).  ``kind`` is holonomic for velocity rows that integrate, with ``integrals``
    their φ_k(q, t) = cste when found (`describe_constraints`).  ``contact`` is (e, μ or None) for a
    unilateral constraint, whose statement is the gap g ≥ 0.
    """

    name: str
    role: str
    form: str
    kind: str
    statement: tuple[sympy.Basic, ...]
    axes: tuple[str, ...] | None
    rows: tuple[tuple[str, str, sympy.Basic], ...]
    integrals: tuple[sympy.Basic, ...] = ()
    contact: tuple[sympy.Basic, sympy.Basic | None] | None = None


@dataclass(frozen=True, slots=True)
class ReactionLine:
    """The effort a complementary constraint exerts, in its multipliers (what ``eom.reactions`` says)."""

    constraint: str
    point: str | None
    body: str | None
    counter_point: str | None
    frame: str
    force: VectorRow | None
    moment: VectorRow | None
    generalized: tuple[sympy.Basic, ...]
    note: str
    row_choice: str | None = None  # the rows the engine kept of a vector constraint, and why


@dataclass(frozen=True, slots=True)
class Supplement:
    """What ``derive`` prints besides the `CourseForm`.

    Parameters
    ----------
    reference_omega : VectorRow or None
        Ω(R/R0) of the reference frame R, when the equations are written in a frame R that turns
        (None otherwise).
    constraints : tuple of ConstraintLine
        Every declared constraint (steps 1 and 7).
    multipliers : tuple of (str, SymPy expression or None)
        (λ_k, its formula λ(q, q̇, t), or None when not solved symbolically).
    reactions : tuple of ReactionLine
        The reactions of the complementary constraints.
    balance : tuple of PowerRow or None
        The terms of dE/dt = P(non-conservative), E = T + U, when no energy (or Jacobi) integral
        holds; None otherwise.
    power : SymPy expression or None
        Their sum.
    declared : tuple of str
        The declared signs and ranges (text).
    used : tuple of (SymPy expression, str, str)
        The signs the derivation used, as (expression, relation, reason):
        `lagrangian.model._assumptions`.
    """

    reference_omega: VectorRow | None
    constraints: tuple[ConstraintLine, ...]
    multipliers: tuple[tuple[str, sympy.Basic | None], ...]
    reactions: tuple[ReactionLine, ...]
    balance: tuple[PowerRow, ...] | None
    power: sympy.Basic | None
    declared: tuple[str, ...] = ()
    used: tuple[tuple[sympy.Basic, str, str], ...] = ()


#: Largest expression (SymPy operation count) that `_shortest` tries to cancel and factor.
SHORTEN_MAX_OPS = 120


def _shortest(e: object) -> sympy.Basic:
    """`to_sympy`, then cancelled and factored when that is shorter: λ = m (g y − ẋ² − ẏ²)/(2 (x² + y²))."""
    expr = to_sympy(e)
    if sympy.count_ops(expr) > SHORTEN_MAX_OPS or has_big_numbers(expr):
        return expr
    cancelled = sympy.cancel(expr)
    candidates = [expr, cancelled, sympy.factor(cancelled), to_sympy(sympy.expand(cancelled))]
    return min(candidates, key=sympy.count_ops)


def _declared(e: object) -> sympy.Basic:
    """The relation as the derivation holds it, without `to_sympy`'s tidying (which would make it 0)."""
    return e._sympy_() if hasattr(e, "_sympy_") else sympy.S(e)


def _constraint_lines(eom: EquationsOfMotion) -> tuple[ConstraintLine, ...]:
    out = []
    declared = {c.name: c for c in eom.model.constraints}
    for info in describe_constraints(eom):
        principal = info.role == "principal"
        convert = _declared if principal else to_sympy
        if isinstance(info.statement, Vector) and info.frame is not None:  # a vector statement has its frame
            comps = eom.kinematics.frames.express(info.statement, info.frame)
            statement = tuple(convert(c) for c in comps)
            axes: tuple[str, ...] | None = eom.kinematics.frames.axes(info.frame)
        else:
            statement, axes = (convert(info.statement),), None
        rows = tuple((r.name, r.multiplier.name, to_sympy(r.expression)) for r in info.rows)
        c = declared[info.name]
        contact = (to_sympy(c.restitution), None if c.friction is None else to_sympy(c.friction)) \
            if c.unilateral else None
        out.append(ConstraintLine(info.name, info.role, info.form, info.kind, statement, axes, rows,
                                  tuple(to_sympy(phi) for phi in info.integrals), contact))
    return tuple(out)


def _reaction_lines(eom: EquationsOfMotion) -> tuple[ReactionLine, ...]:
    out = []
    for r in eom.reactions:
        force = _vector_row(eom, Vector({r.frame: r.force_components})) if r.point is not None else None
        moment = _vector_row(eom, Vector({r.frame: r.moment_components})) if r.body is not None else None
        out.append(ReactionLine(r.constraint, r.point, r.body, r.counter_point, r.frame, force, moment,
                                tuple(to_sympy(g) for g in r.generalized), r.note,
                                r.row_choice.text if r.row_choice is not None else None))
    return tuple(out)


def supplement(eom: EquationsOfMotion, form: CourseForm) -> Supplement:
    """Collect what ``derive`` prints besides ``form`` (see `Supplement`).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    form : CourseForm
        Their derivation, collected.

    Returns
    -------
    Supplement
        The rest of what ``derive`` prints.
    """
    kin = eom.kinematics
    reference_omega = (_vector_row(eom, kin.frame_omega)
                       if isinstance(kin, RelativeKinematics) and not kin.frame_omega.is_zero() else None)
    # With several contacts, which of them are closed changes along the motion: no single formula for λ.
    contacts = sum(1 for c in eom.model.constraints if c.unilateral)
    formulas = multiplier_formulas(eom) if eom.constraints and contacts < 2 else None
    multipliers = tuple((m.name, None if formulas is None else _shortest(f))
                        for m, f in zip(eom.multipliers, formulas or (None,) * len(eom.multipliers), strict=True))
    balance: tuple[PowerRow, ...] | None = None
    power = None
    if not any(i.kind in ("energy", "jacobi") for i in form.integrals):
        b = energy_balance(eom)
        kinds = {f.name: kind_words(f.kind) for f in eom.loads}
        balance = tuple(PowerRow(t.name, kinds[t.name] if t.kind == "load" else t.kind, _shortest(t.power), t.note)
                        for t in b.terms)
        power = _shortest(b.P_nc)
    declared = tuple(f"{p.name} {SIGN_RELATIONS[p.sign]}" for p in eom.model.parameters if p.sign is not None)
    declared += tuple(f"{c.name} ∈ {range_text(c.range)}" for c in eom.model.coordinates if c.range is not None)
    used = tuple((to_sympy(f.expression), f.relation, f.reason) for f in eom.assumptions)
    return Supplement(reference_omega, _constraint_lines(eom) if eom.model.constraints else (), multipliers,
                      _reaction_lines(eom), balance, power, declared, used)



# -- text -----------------------------------------------------------------------------------------------
def notation(form: CourseForm) -> Notation:
    """The notation of a derivation; first-integral constants (K, H) order like parameters.

    Expressions are printed in the forms a teacher writes (`display_form`: sin² + cos² = 1,
    angle sums collapsed, common factors out), the same rewriting as the report's, value unchanged.
    """
    constants = form.parameters + tuple(i.name for i in form.integrals)
    return Notation(form.coordinates, constants, rewrite=functools.partial(display_form, parameters=frozenset(constants)))


def as_declared(n: Notation) -> Notation:
    """The same notation without the teacher's rewriting: for what is printed as the user declared it."""
    return dataclasses.replace(n, rewrite=None)


def greek(n: Notation, form: CourseForm, sentence: str) -> str:
    """Write the coordinate names of a sentence in the course's letters (psi → ψ)."""
    for name in form.coordinates:
        sentence = re.sub(rf"(?<![A-Za-z0-9]){re.escape(name)}(?![A-Za-z0-9])", literal(n.symbol(name)), sentence)
    return sentence


def literal(text: str) -> Callable[[re.Match[str]], str]:
    """A replacement for `re.sub` that is ``text`` as it is: a model's names may hold a backslash, which a
    template would read as an escape."""
    return lambda _: text


def _statement(n: Notation, line: ConstraintLine) -> str:
    n = as_declared(n)  # the relation the user wrote, never rewritten (l² sin²θ + l² cos²θ − l² is not 0 = 0)
    if line.contact is not None:  # a contact: g ≥ 0, λ ≥ 0, λ g = 0, Newton's e (and Coulomb's μ) at impacts
        e, mu = line.contact
        lam = line.rows[0][1] if line.rows else "λ"
        law = f"e = {n.text(e)}" + (f", μ = {n.text(mu)}" if mu is not None else "")
        return (f"{n.text(line.statement[0])} ≥ 0, {lam} ≥ 0, {lam}·({n.text(line.statement[0])}) = 0; "
                f"impacts: {law}")
    if line.axes is None:
        return f"{n.text(line.statement[0])} = 0"
    return "; ".join(f"{n.text(c)} = 0 ({axis})" for c, axis in zip(line.statement, line.axes, strict=True) if c != 0) or "0 = 0"


def _kind(n: Notation, line: ConstraintLine) -> str:
    """"; nonholonomic" or "; holonomic, integrable: x − r φ = cste" for a constraint written on the velocities."""
    if line.form not in ("no_slip", "nonholonomic"):
        return ""
    if line.kind != "holonomic":
        return "; nonholonomic" if line.form == "no_slip" else ""
    found = "; ".join(f"{n.text(phi)} = cste" for phi in line.integrals)
    return "; holonomic, integrable" + (f": {found}" if found else "")


def _constraints_text(n: Notation, extra: Supplement) -> list[str]:
    lines = ["", ("Constraints (step 1: principal ones are satisfied by the choice of the q_i; complementary ones "
                  "keep a multiplier λ_k):")]
    for c in extra.constraints:
        head = f"  {c.name} ({c.role}, {c.form.replace('_', ' ')}{_kind(n, c)}): {_statement(n, c)}"
        if c.role == "complementary":
            head += "    λ: " + ", ".join(row[1] for row in c.rows)
        lines.append(head)
    return lines


def _step7_text(n: Notation, form: CourseForm, extra: Supplement) -> list[str]:
    q = [n.symbol(c) for c in form.coordinates]
    lines = ["", ("Complementary equations (step 7), multipliers and reactions (λ_k multiplies +A_ki; a reaction "
                  "is what the constraint exerts on the body):")]
    for c in extra.constraints:
        for row, _, equation in c.rows:
            when = "" if not c.contact else (", while the contact is closed" if row == c.name
                                              else ", while the contact is closed and sticks")
            lines.append(f"  {n.text(equation)} = 0    [{row}{when}]")
    lines += [f"  {r.constraint}: {r.row_choice}" for r in extra.reactions if r.row_choice]
    unsolved = [name for name, formula in extra.multipliers if formula is None]
    for name, formula in extra.multipliers:
        if formula is not None:
            lines.append(f"  {name} = {n.text(formula)}")
    if unsolved and sum(1 for c in extra.constraints if c.contact) > 1:
        lines.append(f"  {', '.join(unsolved)}: depend on which contacts are closed (each phase of the motion has "
                     "its own); `lagrangian simulate` gives them along a motion")
    elif unsolved:
        lines.append(f"  {', '.join(unsolved)}: not solved symbolically (n + m > {FORMULA_MAX_SIZE}); "
                     "`lagrangian simulate` gives them along a motion")
    for r in extra.reactions:
        parts = []
        if r.force is not None:
            parts.append(f"force at {r.point}: R = {n.vector(r.force.terms) if r.force.terms else '0'}"
                         + (f" (−R at {r.counter_point})" if r.counter_point else ""))
        if r.moment is not None:
            parts.append(f"moment on {r.body}: C = {n.vector(r.moment.terms) if r.moment.terms else '0'}")
        if not parts:
            parts.append(";  ".join(f"Q_{qn} = {n.text(g)}" for qn, g in zip(q, r.generalized, strict=True)))
        lines.append(f"  reaction of {r.constraint}: " + ";  ".join(parts))
    return lines


def power_label(t: PowerRow) -> str:
    """``hinge (joint damper)``, ``∂U/∂t (weight)``, ``prescribed motion``, ``λ (length), reaction``."""
    if t.kind in ("explicit time", "prescribed motion"):
        return t.name
    return f"{t.name}, reaction" if t.kind == "constraint" else f"{t.name} ({t.kind})"


def _balance_text(n: Notation, extra: Supplement) -> list[str]:
    assert extra.balance is not None and extra.power is not None
    total = n.text(extra.power)
    # The terms are the non-conservative efforts' power, and where L depends on t, ∂U/∂t and the
    # power that imposes a prescribed motion: not all "non-conservative efforts".
    timed = any(t.kind in ("explicit time", "prescribed motion") for t in extra.balance)
    what = "P" if timed else "P(non-conservative)"
    lines = ["", f"Energy balance (no energy integral), E = T + U_P:  dE/dt = {what}"
             + (f" = {total}" if len(total) <= MAX_SUM_CHARS or len(extra.balance) < 2 else "") + ", term by term:"]
    for t in extra.balance:
        lines.append(f"  {power_label(t)}: {n.text(t.power)}")
    if not extra.balance:
        lines.append("  none: P(non-conservative) ≡ 0")
    return lines


def _multipliers_readable(text: str, extra: Supplement | None) -> str:
    """λ_length rather than lambda_length."""
    if extra is None:
        return text
    for name, _ in extra.multipliers:
        readable = "λ_" + name.removeprefix("lambda_")
        # A function, not a template: the name is the model's text, and `\y` in it is not an escape.
        text = re.sub(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", literal(readable), text)
    return text


def render_text(form: CourseForm, extra: Supplement | None = None) -> str:
    """The derivation as plain Unicode text (ψ̇, θ̈, sin²θ...); ``extra`` adds steps 1 and 7 and the energy balance.

    The sections, in the course's order: the statement (`_statement_text`), the frames and their angular
    velocities (`_frames_text`), the virtual velocities, T and U (`_energies_text`), the generalized forces
    by virtual power (`_forces_text`), the Lagrange equations (`_equations_text`), the first integrals and
    the matrix form M q̈ = F (`_matrix_text`).

    Parameters
    ----------
    form : CourseForm
        The derivation.
    extra : Supplement, optional
        Adds steps 1 and 7 and the energy balance.

    Returns
    -------
    str
        The text.
    """
    n = notation(form)
    lines = _statement_text(n, form, extra)
    if form.frames:
        lines += _frames_text(n, form, extra)
    if form.virtual_velocities:
        lines.append("")
        lines.append("Virtual velocity field compatible with the principal constraints, V*(P) = Σ ∂OP/∂q_i q_i*:")
        for point, row in form.virtual_velocities:
            lines.append(f"  V*({point}) = {n.vector(row.terms)}")
    lines += _energies_text(n, form)
    lines += _forces_text(n, form, extra)
    lines += _equations_text(n, form, extra)
    lines.append("")
    lines.append("First integrals:")
    if not form.integrals:
        lines.append("  none found")
    for i in form.integrals:
        lines.append(f"  {n.sum(i.parts)} = {i.name}    ({greek(n, form, i.reason)})")
    if extra is not None and extra.balance is not None:
        lines += _balance_text(n, extra)
    lines += _matrix_text(n, form)
    return _multipliers_readable("\n".join(lines) + "\n", extra)


def _statement_text(n: Notation, form: CourseForm, extra: Supplement | None) -> list[str]:
    """The title, the principal parameters (n coordinates, n Lagrange equations), a non-Galilean reference,
    the complementary constraints and the assumptions declared (step 1)."""
    q = [n.symbol(c) for c in form.coordinates]
    ref = form.reference
    lines = [form.title]
    if form.description:
        lines.append(form.description)
    lines.append("")
    count = len(form.coordinates)
    lines.append(f"Principal parameters (n = {count}, hence {count} Lagrange equation{'s' * (count > 1)}): "
                 + ", ".join(q))
    if ref != "R0":
        lines.append(f"The equations are written relative to {ref}, which is not Galilean (Remarque 3): T(Σ/{ref}), "
                     "and the Coriolis and entrainment inertial forces among the loads.")
    if extra is not None and extra.constraints:
        lines += _constraints_text(n, extra)
    if extra is not None and extra.declared:
        lines.append("Declared assumptions: " + ", ".join(extra.declared))
        for expr, relation, reason in extra.used:
            lines.append(f"  used to simplify: {n.text(expr)} {relation} 0    ({reason})")
    return lines


def _frames_text(n: Notation, form: CourseForm, extra: Supplement | None) -> list[str]:
    """Each frame from its parent (angle, axis) and its angular velocity Ω(R_i/ref) = Ω(R_i/R_p) + Ω(R_p/ref)."""
    ref = form.reference
    lines = [""]
    relative = f" relative to {ref}:" if ref != "R0" else ":"
    lines.append("Frames (R0 is Galilean) and angular velocities" + relative)
    for f in form.frames:
        axis = f.axis if f.axis_vector is None else n.vector(f.axis_vector.terms)
        note = "    (the axis given, divided by its norm)" if f.normalized else ""
        lines.append(f"  {f.parent} --({n.text(f.angle)}, {axis})--> {f.name}({', '.join(f.axes)}){note}")
    for f in form.frames:
        if f.name == ref and extra is not None and extra.reference_omega is not None:
            lines.append(f"  Ω({f.name}/R0) = {n.vector(extra.reference_omega.terms)}    (prescribed)")
            continue
        text = f"  Ω({f.name}/{ref}) = {n.vector(f.omega_chain.terms)}"
        if f.omega_components is not None:
            alt = n.vector(f.omega_components.terms)
            if alt != n.vector(f.omega_chain.terms):
                text += f" = {alt}"
        lines.append(text)
    return lines


def _energies_text(n: Notation, form: CourseForm) -> list[str]:
    """T(Σ/ref) body by body with the formula used, and U_P (+ cste) load by load."""
    ref = form.reference
    lines = [""]
    lines.append(f"Kinetic energy T(Σ/{ref}):")
    for energy in form.T:
        lines.append(f"  T({energy.name}/{ref}) = {n.text(energy.expression)}    [{energy.formula}]")
    lines.append(f"Potential energy U_P(Σ/{ref}) (+ cste):")
    if form.U:
        for energy in form.U:
            lines.append(f"  {energy.name}: {n.text(energy.expression)}")
    else:
        lines.append("  none: no given effort derives from a potential")
    return lines


def _forces_text(n: Notation, form: CourseForm, extra: Supplement | None) -> list[str]:
    """Each load's Q_i by virtual power, conservative (Q_i = −∂U/∂q_i) or not."""
    q = [n.symbol(c) for c in form.coordinates]
    lines = [""]
    lines.append("Generalized forces, by virtual power:")
    for load in form.loads:
        tag = "conservative, Q_i = −∂U/∂q_i" if load.conservative else "non-conservative"
        comps = ";  ".join(f"Q_{qn} = {n.text(Q)}" for qn, Q in zip(q, load.Q, strict=True))
        lines.append(f"  {load.name} ({kind_words(load.kind)}, {tag}): {comps}")
        if extra is not None and load.note:
            lines.append(f"      {greek(n, form, load.note)}")
    if not form.loads:
        lines.append("  none")
    return lines


def _equations_text(n: Notation, form: CourseForm, extra: Supplement | None) -> list[str]:
    """L(q_i): d/dt(∂T/∂q̇_i) − ∂T/∂q_i = −∂U/∂q_i + Q_i(nc) (+ Σ_k λ_k A_ki) with its pieces, a cyclic
    coordinate's first integral, L = T − U_P when conservative, and the multipliers (step 7)."""
    lines = [""]
    lines.append("Lagrange equations  d/dt(∂T/∂q̇_i) − ∂T/∂q_i = −∂U/∂q_i + Q_i(nc)"
                 + (" + Σ_k λ_k A_ki:" if extra is not None and extra.multipliers else ":"))
    for eq in form.equations:
        qn = n.symbol(eq.coordinate)
        qd = n.symbol(eq.coordinate + "_dot")
        lines.append(f"  L({qn})  ∂T/∂{qd} = {n.text(eq.dT_dqd)};  ∂T/∂{qn} = {n.text(eq.dT_dq)};  "
                     f"∂U/∂{qn} = {n.text(eq.dU_dq)};  Q_{qn}(nc) = {n.text(eq.Q_nc)}")
        if eq.integral is not None:
            p = n.text(eq.dT_dqd)
            lines.append(f"        d/dt[{p}] = 0   ⇒   {p} = {eq.integral}")
        else:
            lines.append(f"        {n.text(eq.lhs)} = {n.text(eq.rhs)}")
            if eq.using_integrals is not None:
                lines.append(f"        or, with the first integrals: {n.text(eq.using_integrals)} = {n.text(eq.rhs)}")
    if form.conservative and form.L is not None:
        lines.append(f"  The system is conservative (Remarque 2): L = T − U_P = {n.sum((form.T_total, -form.U_total))}")
        if extra is not None and extra.multipliers:
            lines.append("  its complementary constraints are perfect and time-independent (no work along the motion): "
                         "d/dt(∂L/∂q̇_i) − ∂L/∂q_i = Σ_k λ_k a_k,i")
    if extra is not None and extra.multipliers:
        lines += _step7_text(n, form, extra)
    return lines


def _matrix_text(n: Notation, form: CourseForm) -> list[str]:
    """M(q, t) q̈ = F(q, q̇, t): M's nonzero entries on and above the diagonal (M is symmetric), then F."""
    q = [n.symbol(c) for c in form.coordinates]
    lines = ["", "Matrix form M(q, t) q̈ = F(q, q̇, t):"]
    for a, row in enumerate(form.M):
        for b, entry in enumerate(row):
            if b >= a and entry != 0:
                lines.append(f"  M[{q[a]},{q[b]}] = {n.text(entry)}")
    for a, f in enumerate(form.F):
        lines.append(f"  F[{q[a]}] = {n.text(f)}")
    return lines
