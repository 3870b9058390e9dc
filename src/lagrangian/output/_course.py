"""The derivation in the course's order and form, as data (steps of the "démarche d'application").

`course_form` turns `EquationsOfMotion` and its first integrals into a `CourseForm`:
plain SymPy expressions with labels, grouped by step, that the text, LaTeX and JSON
renderers (and later the report) print without any further mathematics.  SymEngine
results are converted to SymPy here, which also distributes numeric factors
(−½(2a − 2b) becomes b − a): that is the only "simplification" applied, so the
printed forms are those the derivation produced, term by term, as in the seed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import symengine as se
import sympy
from symengine.lib.symengine_wrapper import sympy2symengine

from .._identity import are_zero
from ..analysis import FirstIntegral
from ..dynamics import EquationsOfMotion
from ..model import GALILEAN_FRAME, ORIGIN, Vector

__all__ = ["CourseForm", "FrameStep", "VectorRow", "EquationRow", "LoadRow", "IntegralRow", "course_form",
           "reference_label", "to_sympy"]


#: Largest expression (SymPy operation count) for which an expanded, trigonometrically
#: simplified form is tried in SymPy; beyond it only SymEngine's expansion is tried.
TIDY_MAX_OPS = 40
#: Largest expression (SymPy operation count) for which SymEngine's expansion is tried (it costs
#: some microseconds where SymPy's costs milliseconds); beyond it the derivation's form is printed.
EXPAND_MAX_OPS = 300


def _from_engine(e: se.Basic) -> sympy.Basic:
    return e._sympy_() if hasattr(e, "_sympy_") else sympy.S(e)


def to_sympy(e: se.Basic) -> sympy.Basic:
    """Convert SymEngine → SymPy (a structural conversion; no text is parsed), in its shortest form.

    The derivation's own form is kept unless expanding and applying the trigonometric
    identities gives a strictly shorter expression: the seed's ½A(θ̇² + ψ̇² sin²θ) stays,
    while a pendulum on a cart's ½m((ẋ cosθ − lθ̇)² + ẋ² sin²θ) becomes ½m(ẋ² − 2lẋθ̇ cosθ + l²θ̇²).
    A longer expression (up to `EXPAND_MAX_OPS`) is expanded by SymEngine first, kept when
    shorter, and then tidied as a small one: Kapitza's L(θ), 56 operations as derived, is
    m l² θ̈ − m l a ν² cos(ν t) sinθ.  Only small expressions get SymPy's expansion
    (`TIDY_MAX_OPS`): simplification only where it pays.  ``√(a²)`` is written ``|a|``, and ``a/|a|``
    ``sgn(a)``: exact Coulomb friction's −f N ẋ/√(ẋ²) prints as −f N sgn(ẋ) (`_signs`).

    Parameters
    ----------
    e : SymEngine expression
        The engine's expression.

    Returns
    -------
    SymPy expression
        The same value, in the shorter of its forms.
    """
    expr = _from_engine(e)
    ops = sympy.count_ops(expr)
    if ops == 0 or ops > EXPAND_MAX_OPS:
        return expr
    expr = _signs(expr)
    if ops > TIDY_MAX_OPS:
        engine = e if isinstance(e, se.Basic) else sympy2symengine(expr)
        expanded_engine = se.expand(engine)
        # Counted by SymEngine first: most long expressions do not shorten, and are not converted twice.
        if se.count_ops(expanded_engine) >= se.count_ops(engine):
            return expr
        expanded = _from_engine(expanded_engine)
        shorter = sympy.count_ops(expanded)
        if shorter >= ops:
            return expr
        expr, ops = expanded, shorter
        if ops > TIDY_MAX_OPS:
            return expr
    if not expr.has(sympy.sin, sympy.cos):
        return expr
    expanded = sympy.expand(expr)
    # sin²x = 1 − cos²x, then expand again: a cheap, exact stand-in for trigsimp (which
    # costs a hundred times more) that removes the sin² + cos² pairs of rotating bases.
    rewritten = sympy.expand(expanded.replace(_is_sine_power, _as_cosines))
    best = min((rewritten, expanded), key=sympy.count_ops)
    return best if sympy.count_ops(best) < ops else expr


def _is_root_of_square(x: sympy.Basic) -> bool:
    return (x.is_Pow and x.exp in (sympy.S.Half, -sympy.S.Half) and x.base.is_Pow and x.base.exp == 2)


def _as_abs(x: sympy.Pow) -> sympy.Basic:
    a = sympy.Abs(x.base.base, evaluate=False)
    return a if x.exp > 0 else 1 / a


def _over_own_abs(x: sympy.Basic) -> bool:
    if not x.is_Mul:
        return False
    bases = {f.base.args[0] for f in x.args if f.is_Pow and f.exp == -1 and isinstance(f.base, sympy.Abs)}
    return any((f.base if f.is_Pow and f.exp in (1, 2) else f) in bases for f in x.args)


def _as_sign(x: sympy.Mul) -> sympy.Basic:
    """a/|a| → sgn(a), a²/|a| → |a| (a real, a ≠ 0: where the expression is defined)."""
    factors = list(x.args)
    for f in list(factors):
        if not (f.is_Pow and f.exp == -1 and isinstance(f.base, sympy.Abs)):
            continue
        a = f.base.args[0]
        for k, g in enumerate(factors):
            if g == a:
                factors[k] = sympy.sign(a)
            elif g.is_Pow and g.base == a and g.exp == 2:
                factors[k] = f.base
            else:
                continue
            factors.remove(f)
            break
    return sympy.Mul(*factors)


def _signs(expr: sympy.Basic) -> sympy.Basic:
    """√(a²) → |a|, then a/|a| → sgn(a) and a²/|a| → |a|: the coordinates and rates are real."""
    if not any(_is_root_of_square(p) for p in expr.atoms(sympy.Pow)):
        return expr
    return expr.replace(_is_root_of_square, _as_abs).replace(_over_own_abs, _as_sign)


def _is_sine_power(x: sympy.Basic) -> bool:
    return x.is_Pow and isinstance(x.base, sympy.sin) and x.exp.is_Integer and x.exp >= 2


def _as_cosines(x: sympy.Pow) -> sympy.Basic:
    angle, k = x.base.args[0], int(x.exp)
    return (1 - sympy.cos(angle) ** 2) ** (k // 2) * sympy.sin(angle) ** (k % 2)


@dataclass(frozen=True, slots=True)
class VectorRow:
    """A vector as a list of (component, axis display name)."""

    terms: tuple[tuple[sympy.Basic, str], ...]


@dataclass(frozen=True, slots=True)
class FrameStep:
    name: str
    parent: str
    angle: sympy.Basic
    axis: str  # display name of the rotation axis (shared by parent and child); "n" for a vector axis
    axes: tuple[str, str, str]
    omega_chain: VectorRow  # Ω(F/R0) as the sum of rotation rates
    omega_components: VectorRow | None  # Ω(F/R0) in the basis where a body's inertia is given
    components_frame: str | None
    axis_vector: VectorRow | None = None  # the axis n in the parent's basis, when not x, y or z
    normalized: bool = False  # n is the given vector divided by its norm


@dataclass(frozen=True, slots=True)
class EnergyRow:
    name: str
    formula: str
    expression: sympy.Basic


@dataclass(frozen=True, slots=True)
class LoadRow:
    name: str
    kind: str
    conservative: bool
    potential: sympy.Basic | None
    Q: tuple[sympy.Basic, ...]
    note: str


@dataclass(frozen=True, slots=True)
class EquationRow:
    coordinate: str
    dT_dqd: sympy.Basic
    dT_dq: sympy.Basic
    dU_dq: sympy.Basic
    Q_nc: sympy.Basic
    lhs: sympy.Basic
    rhs: sympy.Basic
    integral: str | None  # name of the momentum integral when d/dt(∂T/∂q̇) = 0
    using_integrals: sympy.Basic | None  # lhs rewritten with the momentum integrals, when they appear in it


@dataclass(frozen=True, slots=True)
class IntegralRow:
    """``expression`` = ``name`` (constant); ``parts`` is how to write it (T and U separately for E)."""

    name: str
    kind: str
    expression: sympy.Basic
    parts: tuple[sympy.Basic, ...]
    reason: str
    coordinate: str | None


@dataclass(frozen=True, slots=True)
class CourseForm:
    """Every step of the derivation, ready to print.

    Parameters
    ----------
    title : str
        The model's title.
    description : str
        Its description.
    coordinates : tuple of str
        The coordinates, in order.
    parameters : tuple of str
        The parameters, in declaration order.
    frames : tuple of FrameStep
        The frames and their angular velocities.
    virtual_velocities : tuple of (str, VectorRow)
        V*(P) at the points that carry loads.
    T : tuple of EnergyRow
        T of each body and particle.
    T_total : SymPy expression
        T(Σ/R0).
    U : tuple of EnergyRow
        The potential of each conservative load.
    U_total : SymPy expression
        U_P(Σ/R0).
    loads : tuple of LoadRow
        The generalized forces of each load, by virtual power.
    conservative : bool
        Every given effort derives from a potential (Remarque 2).
    L : SymPy expression or None
        The Lagrangian T − U when conservative.
    equations : tuple of EquationRow
        The Lagrange equations L(q_i).
    integrals : tuple of IntegralRow
        The first integrals.
    M : tuple of tuples of SymPy expressions
        The mass matrix of M q̈ = F.
    F : tuple of SymPy expressions
        The right side F.
    reference : str
        The frame the equations are written in, as labels print it: T(Σ/R), Ω(F/R) (R0, or the
        model's [reference] frame, with its origin when it is not O: ``R0(A)``).
    """

    title: str
    description: str
    coordinates: tuple[str, ...]
    parameters: tuple[str, ...]
    frames: tuple[FrameStep, ...]
    virtual_velocities: tuple[tuple[str, VectorRow], ...]  # V*(P) at the points that carry loads
    T: tuple[EnergyRow, ...]
    T_total: sympy.Basic
    U: tuple[EnergyRow, ...]
    U_total: sympy.Basic
    loads: tuple[LoadRow, ...]
    conservative: bool
    L: sympy.Basic | None
    equations: tuple[EquationRow, ...]
    integrals: tuple[IntegralRow, ...]
    M: tuple[tuple[sympy.Basic, ...], ...]
    F: tuple[sympy.Basic, ...]
    reference: str = GALILEAN_FRAME


def reference_label(model) -> str:
    """The name of the frame the equations of ``model`` are written in: R0, R1, or ``R0(A)`` (origin A ≠ O).

    Parameters
    ----------
    model : Model
        The model.

    Returns
    -------
    str
        R0, R1, or ``R0(A)`` (origin A ≠ O).
    """
    ref = model.reference
    if ref is None or ref.is_galilean_frame:
        return GALILEAN_FRAME
    return ref.frame if ref.origin == ORIGIN else f"{ref.frame}({ref.origin})"


#: How an engine expression becomes the printed SymPy expression (`to_sympy` by default).
Converter = Callable[[se.Basic], sympy.Basic]


def _vector_row(eom: EquationsOfMotion, v: Vector, convert: Converter = to_sympy) -> VectorRow:
    terms = []
    for frame, comps in v:
        axes = eom.kinematics.frames.axes(frame)
        for c, name in zip(comps, axes, strict=True):
            if c != 0:
                terms.append((convert(c), name))
    return VectorRow(tuple(terms))


def _loaded_points(model) -> list[str]:
    """The points where given efforts act, in order of first appearance."""
    from ..model import Damper, Gravity, PointForce, Spring

    out: list[str] = []
    for load in model.loads:
        if isinstance(load, Gravity):
            names = load.on or tuple(b.name for b in model.bodies) + tuple(p.name for p in model.particles)
        elif isinstance(load, PointForce):
            names = (load.at,)
        elif isinstance(load, (Spring, Damper)):
            names = load.ends
        else:
            names = ()
        out += [n for n in names if n not in out]
    return out


def _point_label(model, name: str) -> str:
    """A body name stands for its centre of mass: G, or G_S when there are several bodies."""
    if name in {b.name for b in model.bodies}:
        return "G" if len(model.bodies) == 1 else f"G_{name}"
    return name


def course_form(eom: EquationsOfMotion, integrals: tuple[FirstIntegral, ...], *,
                convert: Converter = to_sympy) -> CourseForm:
    """Collect the derivation of ``eom`` in the course's order and notation.

    ``convert`` turns each engine expression into the SymPy expression that is printed
    (`to_sympy` by default).  The report passes one that stands a summary in for an
    expression too long to print (`lagrangian.output._report.size`), so that a 40-link
    chain is collected in a fraction of a second rather than converted in full.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    integrals : tuple of FirstIntegral
        The first integrals to list.
    convert : callable, optional
        Turns each engine expression into the SymPy expression that is printed (`to_sympy` by
        default).  The report passes one that stands a summary in for an expression too long to
        print (`lagrangian.output._report.size`), so that a 40-link chain is collected in a fraction
        of a second rather than converted in full.

    Returns
    -------
    CourseForm
        Every step of the derivation.
    """
    model = eom.model
    kin = eom.kinematics
    inertia_frame = {b.frame: eom.inertias[b.name].frame for b in model.bodies}
    frames = []
    for f in model.frames:
        if f.parent is None or f.name.startswith("_"):
            continue
        rot = f.rotation
        if rot.elementary:  # type: ignore[union-attr]
            axis_name, axis_vector = f.axes["xyz".index(rot.axis)], None  # type: ignore[union-attr]
        else:  # about a constant vector n of the parent
            axis_name, axis_vector = rot.axis, _vector_row(eom, Vector({f.parent: rot.direction}), convert)  # type: ignore
        basis = inertia_frame.get(f.name)
        comps = None
        if basis is not None:
            comps = _vector_row(eom, Vector({basis: kin.frames.omega_in(f.name, basis)}), convert)
        frames.append(FrameStep(f.name, f.parent, convert(rot.angle), axis_name, f.axes,  # type: ignore[union-attr]
                                _vector_row(eom, kin.omega(f.name), convert), comps, basis, axis_vector,
                                rot.normalized))  # type: ignore[union-attr]
    T_rows = tuple(EnergyRow(t.name, t.formula, convert(t.expression)) for t in eom.T_terms)
    U_rows = tuple(EnergyRow(f.name, f.kind, convert(f.potential)) for f in eom.loads if f.potential is not None)
    loads = tuple(LoadRow(f.name, f.kind, f.potential is not None,
                          None if f.potential is None else convert(f.potential),
                          tuple(convert(q) for q in f.Q), f.note) for f in eom.loads)
    by_coordinate = {i.coordinate: i.name for i in integrals if i.kind == "momentum"}
    momenta = [(convert(i.expression), sympy.Symbol(i.name)) for i in integrals if i.kind == "momentum"]
    equations = []
    for eq in eom.equations:
        lhs = convert(eq.lhs)
        rewritten = None
        if eq.coordinate not in by_coordinate:
            # The seed's "ou encore, en tenant compte de L(φ)": A θ̈ − ... + H ψ̇ sinθ = m g a sinθ.
            candidate = lhs
            for p, name in momenta:
                if isinstance(p, sympy.Mul):
                    candidate = candidate.subs(p, name)
            rewritten = candidate if candidate != lhs else None
        equations.append(EquationRow(eq.coordinate, convert(eq.dT_dqd), convert(eq.dT_dq), convert(eq.dU_dq),
                                     convert(eq.Q_nc), lhs, convert(eq.rhs), by_coordinate.get(eq.coordinate),
                                     rewritten))
    integral_rows = []
    for i in integrals:
        expr = convert(i.expression)
        # The energy is written T + U from the displayed T and U, as the seed writes it; U with the
        # inputs the integral holds off at 0 (`first_integrals`: inputs are off by default).
        off = {se.Symbol(u): se.Integer(0) for u in model.inputs if se.Symbol(u) not in i.expression.free_symbols}
        parts = (convert(eom.T), convert(eom.U.xreplace(off) if off else eom.U)) if i.kind == "energy" else (expr,)
        integral_rows.append(IntegralRow(i.name, i.kind, expr, tuple(p for p in parts if p != 0), i.reason,
                                         i.coordinate))
    T_total, U_total = convert(eom.T), convert(eom.U)
    L = None
    if eom.conservative:
        L = T_total - U_total if not are_zero([eom.U])[0] else T_total
    virtual = tuple((_point_label(model, p), _vector_row(eom, kin.virtual_velocity(p), convert)) for p in _loaded_points(model))
    return CourseForm(
        title=model.name,
        description=model.description,
        coordinates=eom.coordinates,
        parameters=tuple(p.name for p in model.parameters),
        frames=tuple(frames),
        virtual_velocities=virtual,
        T=T_rows,
        T_total=T_total,
        U=U_rows,
        U_total=U_total,
        loads=loads,
        conservative=eom.conservative,
        L=L,
        equations=tuple(equations),
        integrals=tuple(integral_rows),
        M=tuple(tuple(convert(x) for x in row) for row in eom.M),
        F=tuple(convert(x) for x in eom.F),
        reference=reference_label(model),
    )
