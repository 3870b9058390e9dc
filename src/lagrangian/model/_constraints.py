"""Constraints declared in a model: step 1 of the seed's démarche, "choix des liaisons principales".

A constraint is either *principal* — eliminated by the choice of the principal
parameters q_i, as every constraint of a model without a ``[constraints]`` table is —
or *complementary*: kept as an equation, with a Lagrange multiplier λ_k, and written
next to the Lagrange equations (step 7, "équations de liaison complémentaires").  Four
forms are understood::

    length  = { holonomic = "x^2 + y^2 - l^2" }           f(q, t) = 0 (scalar, or a vector: one row per axis)
    rolling = { nonholonomic = "x_dot - r*phi_dot" }        a(q, t)·q̇ + b(q, t) = 0
    rolling = { nonholonomic = { x = "1", phi = "-r" } }    the same in Pfaffian form Σ a_i dq_i + b dt = 0
    contact = { no_slip = "I", on = "S", frame = "R1" }     V(I ∈ S/R0) = 0: rolling without slipping
    pivot   = { coincide = ["Q", "O"], frame = "R0" }       OQ − OO = 0: two points kept together

``no_slip`` and ``coincide`` are vector constraints: one scalar row per axis of
``frame`` (rows that vanish identically are dropped by the derivation), each with its
multiplier, and their reaction is automatic (a force at the contact point).  The
reaction of a scalar constraint is the generalized force Σ_k λ_k ∂f_k/∂q_i unless
``reaction = { force_at = "P", moment_on = "S", frame = "R0" }`` says which physical
force (at P) and/or moment (on S) carries it.  ``principal = true`` marks a
constraint that the coordinates already satisfy (it is then only checked and listed
in step 1).

This module holds the data and its model-stage checks (names, linearity in the
rates); everything that needs kinematics is in `lagrangian.dynamics._constraints`.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import symengine as se

from ..errors import ModelError
from ._unilateral import UNILATERAL_KEYS, unilateral_parts
from .vectors import Vector

if TYPE_CHECKING:  # pragma: no cover
    from .build import ModelBuilder

__all__ = ["Constraint", "ReactionSpec", "FORMS", "HOLONOMIC", "NONHOLONOMIC", "read_constraint",
           "build_constraints"]

#: Name of the Galilean frame R0 (`spec.GALILEAN_FRAME`; `spec` imports this module, so it is not imported here).
GALILEAN_FRAME = "R0"
HOLONOMIC = "holonomic"
NONHOLONOMIC = "nonholonomic"
#: The forms a constraint may take, and the kind (holonomic or not) of each.
FORMS = {"holonomic": HOLONOMIC, "nonholonomic": NONHOLONOMIC, "no_slip": NONHOLONOMIC, "coincide": HOLONOMIC,
         "unilateral": HOLONOMIC}
#: Keys every form accepts besides its own.
_COMMON = {"frame", "axes", "principal", "reaction", "description"}
_EXTRA = {"no_slip": {"on"}, "unilateral": UNILATERAL_KEYS}
_EXAMPLES = {
    "holonomic": 'length = { holonomic = "x^2 + y^2 - l^2" }',
    "nonholonomic": 'rolling = { nonholonomic = { x = "1", phi = "-r" } }',
    "no_slip": 'contact = { no_slip = "I", on = "S", frame = "R0" }',
    "coincide": 'pivot = { coincide = ["Q", "O"], frame = "R0" }',
    "unilateral": 'floor = { unilateral = "z", restitution = "e" }',
}


@dataclass(frozen=True, slots=True)
class ReactionSpec:
    """Which physical efforts carry a constraint's reaction: a force at a point and/or a moment on a body.

    Parameters
    ----------
    force_at : str, optional
        The point where a reaction force acts.
    moment_on : str, optional
        The body on which a reaction moment acts.
    frame : str
        The frame whose axes the reaction's components are taken along.
    """

    force_at: str | None = None
    moment_on: str | None = None
    frame: str = GALILEAN_FRAME


@dataclass(frozen=True, slots=True)
class Constraint:
    """One declared constraint (see the module docstring).

    Parameters
    ----------
    name : str
        The declaration's name; multipliers are ``lambda_<name>`` (``lambda_<name>_<axis>`` per row).
    form : str
        ``"holonomic"``, ``"nonholonomic"``, ``"no_slip"``, ``"coincide"`` or ``"unilateral"``.
    expression : SymEngine expression or Vector, optional
        The function f(q, t) (holonomic) or a·q̇ + b (nonholonomic), scalar or `Vector`; None for the point forms.
    points : tuple of str
        The contact point (no_slip) or the two points kept together (coincide).
    body : str, optional
        The rolling body (no_slip).
    frame : str
        The basis whose axes give the scalar rows of a vector constraint.
    principal : bool
        True when the choice of coordinates already satisfies it (no multiplier).
    reaction : ReactionSpec, optional
        The physical efforts that carry its reaction, when declared.
    description : str, optional
        What it is, in words.
    axes : tuple of int, optional
        For a vector constraint, the indices (0, 1, 2) of the axes of ``frame`` whose rows are kept;
        None keeps all three.  A wheel on the ground keeps its two tangential rows when its normal
        row is the derivative of a holonomic contact constraint declared beside it.
    restitution : SymEngine expression, optional
        Of a ``unilateral`` constraint (a contact, gap ``expression`` ≥ 0): Newton's coefficient e.
        See `lagrangian.model._unilateral`.
    friction : SymEngine expression, optional
        Of a ``unilateral`` constraint: the Coulomb coefficient μ, or None.
    slip : SymEngine expression, optional
        Of a ``unilateral`` constraint: the sliding velocity w (linear in the rates; None without
        friction).
    """

    name: str
    form: str
    expression: se.Basic | Vector | None = None
    points: tuple[str, ...] = ()
    body: str | None = None
    frame: str = GALILEAN_FRAME
    principal: bool = False
    reaction: ReactionSpec | None = None
    description: str | None = None
    axes: tuple[int, ...] | None = None
    restitution: se.Basic | None = None
    friction: se.Basic | None = None
    slip: se.Basic | None = None

    def __post_init__(self) -> None:
        if self.form not in FORMS:
            raise ValueError(f"constraint form must be one of {', '.join(FORMS)}, not {self.form!r}")

    @property
    def kind(self) -> str:
        """``"holonomic"`` (f(q, t) = 0) or ``"nonholonomic"`` (linear in the rates)."""
        return FORMS[self.form]

    @property
    def unilateral(self) -> bool:
        """True for a one-sided contact g(q, t) ≥ 0 (`lagrangian.model._unilateral`)."""
        return self.form == "unilateral"

    @property
    def is_vector(self) -> bool:
        return self.form in ("no_slip", "coincide") or isinstance(self.expression, Vector)


# -- the TOML table ---------------------------------------------------------------------------
def read_constraint(reader: Any, builder: ModelBuilder, name: str, value: Any) -> None:
    """Read one entry of ``[constraints]`` (``reader`` is the TOML reader, for locations)."""
    if not isinstance(value, dict):
        raise reader.fail(("constraints", name), f"constraint `{name}` must be a table", symbol=name,
                          fix="e.g. " + _EXAMPLES["holonomic"])
    forms = [k for k in FORMS if k in value]
    if len(forms) != 1:
        raise reader.fail(("constraints", name), f"constraint `{name}` must have exactly one of the keys "
                          + ", ".join(f"`{k}`" for k in FORMS), symbol=name,
                          fix="e.g. " + "; or ".join(_EXAMPLES.values()))
    form = forms[0]
    allowed = {form} | _COMMON | _EXTRA.get(form, set())
    unknown = sorted(set(value) - allowed)
    if unknown:
        raise reader.fail(("constraints", name, unknown[0]), f"unknown key `{unknown[0]}` in constraint `{name}`",
                          symbol=unknown[0], fix="the keys allowed here are " + ", ".join(sorted(allowed)))
    where = reader.located("constraints", name, value, form)
    builder.constraint(name, form, value[form], on=value.get("on"), frame=value.get("frame", GALILEAN_FRAME),
                       axes=value.get("axes"), principal=value.get("principal", False),
                       reaction=value.get("reaction"),
                       description=reader.text(("constraints", name, "description"), value.get("description")),
                       location=where, **{k: value[k] for k in UNILATERAL_KEYS if k in value})


# -- the build stage ------------------------------------------------------------------------------
def _rates_in(expr: se.Basic, rates: Mapping[se.Basic, str]) -> list[str]:
    return sorted(rates[s] for s in expr.free_symbols if s in rates)


class _Checker:
    """Turns the raw ``constraint`` declarations of a `ModelBuilder` into `Constraint` values."""

    def __init__(self, assembler: Any, coordinates: Sequence[Any], points: Collection[str],
                 bodies: Collection[str], frame_axes: Mapping[str, tuple[str, str, str]]) -> None:
        self.a = assembler
        self.frame_axes = frame_axes
        self.coordinates = {c.name: c for c in coordinates}
        self.rates = {c.rate_symbol: c.rate_symbol.name for c in coordinates}
        self.points = set(points)
        self.bodies = set(bodies)

    def fail(self, raw: Any, message: str, fix: str, key: str | None = None, symbol: str | None = None) -> ModelError:
        return self.a.error(raw, message, fix=fix, symbol=symbol or raw.name, key=key)

    def name_of(self, raw: Any, key: str, value: Any, kinds: Collection[str], what: str) -> str:
        if not isinstance(value, str):
            raise self.fail(raw, f"`{key}` of constraint `{raw.name}` must be a name, not `{value}`", key=key,
                            fix=f'write the name of {what} in quotes')
        if value not in kinds:
            raise self.fail(raw, f"constraint `{raw.name}` refers to unknown {what} `{value}`", key=key,
                            symbol=value, fix="declare it first, or correct the name")
        return value

    def frame(self, raw: Any, value: Any, key: str = "frame") -> str:
        return self.name_of(raw, key, value, self.a.frame_names, "frame")

    def build(self, raw: Any) -> Any:
        d = raw.data
        form = d["form"]
        if form not in FORMS:
            raise self.fail(raw, f"constraint `{raw.name}` has unknown form `{form}`", key=None,
                            fix="use one of " + ", ".join(FORMS))
        principal = d["principal"]
        if not isinstance(principal, bool):
            raise self.fail(raw, f"`principal` of constraint `{raw.name}` must be true or false, not `{principal}`",
                            key="principal", fix="write principal = true or leave it out")
        description = d["description"]
        if description is not None and not isinstance(description, str):
            raise self.fail(raw, f"`description` of constraint `{raw.name}` must be text", key="description",
                            fix='write it in quotes, e.g. description = "the rod keeps its length"')
        frame = self.frame(raw, d["frame"])
        value = d["value"]
        expression, body = None, None
        points: tuple[str, ...] = ()
        contact: Sequence[Any] = (None, None, None)
        if form == "unilateral":
            expression, *contact = unilateral_parts(self, raw, d)
        elif form == "holonomic":
            expression = self.a.expr(raw, "the holonomic constraint", value, vector=None, key=form)
            self.check_holonomic(raw, expression)
        elif form == "nonholonomic":
            expression = self.nonholonomic(raw, value)
        elif form == "no_slip":
            points = (self.name_of(raw, form, value, self.points, "point"),)
            if d["on"] is None:
                raise self.fail(raw, f"constraint `{raw.name}` does not say which body rolls on the contact point",
                                key=form, fix=f'add on = "S", the body whose point `{value}` has zero velocity')
            body = self.name_of(raw, "on", d["on"], self.bodies, "body")
        else:  # coincide
            if (isinstance(value, str) or not isinstance(value, Sequence) or len(value) != 2):
                raise self.fail(raw, f"`coincide` of constraint `{raw.name}` must list two points, not `{value}`",
                                key=form, fix='e.g. coincide = ["Q", "O"]')
            points = tuple(self.name_of(raw, form, v, self.points, "point") for v in value)
            if points[0] == points[1]:
                raise self.fail(raw, f"constraint `{raw.name}` keeps point `{points[0]}` on itself", key=form,
                                fix="name two different points")
        reaction = self.reaction(raw, d["reaction"], form)
        vector = form in ("no_slip", "coincide") or isinstance(expression, Vector)
        axes = self.axes(raw, d.get("axes"), frame, vector)
        return Constraint(raw.name, form, expression, points, body, frame, principal, reaction, description, axes,
                          *contact)

    def axes(self, raw: Any, value: Any, frame: str, vector: bool) -> tuple[int, ...] | None:
        """The indices of the rows kept (`axes` = names of axes of `frame`, or x, y, z), in the frame's order."""
        if value is None:
            return None
        names = self.frame_axes.get(frame, ("x", "y", "z"))
        example = f'axes = ["{names[0]}", "{names[1]}"]'
        if not vector:
            raise self.fail(raw, f"constraint `{raw.name}` is scalar: it has one row, so `axes` has nothing to choose",
                            key="axes", fix="remove `axes`; it selects rows of a vector constraint (no_slip, "
                                            "coincide, or a vector expression)")
        if isinstance(value, str) or not isinstance(value, Sequence) or not value \
                or not all(isinstance(v, str) for v in value):
            raise self.fail(raw, f"`axes` of constraint `{raw.name}` must list axis names, not `{value}`",
                            key="axes", fix=f"e.g. {example} (axes of frame `{frame}`)")
        picked = []
        for v in value:
            if v in names:
                picked.append(names.index(v))
            elif v in ("x", "y", "z"):
                picked.append("xyz".index(v))
            else:
                raise self.fail(raw, f"constraint `{raw.name}` keeps the rows along `{v}`, which is not an axis of "
                                f"its frame `{frame}`", key="axes", symbol=v,
                                fix="name axes of the frame: " + ", ".join(f"`{a}`" for a in names)
                                    + " (or x, y, z)")
        if len(set(picked)) != len(picked):
            raise self.fail(raw, f"`axes` of constraint `{raw.name}` names an axis twice", key="axes",
                            fix=f"name each axis once, e.g. {example}")
        return tuple(sorted(picked))

    def check_holonomic(self, raw: Any, expression: Any) -> None:
        comps = [c for _, cs in expression for c in cs] if isinstance(expression, Vector) else [expression]
        rates = sorted({r for c in comps for r in _rates_in(c, self.rates)})
        if rates:
            raise self.fail(raw, f"holonomic constraint `{raw.name}` depends on the rate `{rates[0]}`: a holonomic "
                            "constraint f(q, t) = 0 holds no velocity", key="holonomic", symbol=rates[0],
                            fix="write it as a nonholonomic constraint, "
                                f'e.g. {raw.name} = {{ nonholonomic = "..." }}, if it is linear in the rates')

    def nonholonomic(self, raw: Any, value: Any) -> se.Basic | Vector:
        key = "nonholonomic"
        if isinstance(value, Mapping):
            # Pfaffian form Σ a_i dq_i + b dt = 0: coefficients of the coordinates, and `t` for b.
            terms = []
            for q, coefficient in value.items():
                if q != "t" and q not in self.coordinates:
                    raise self.fail(raw, f"constraint `{raw.name}` has a coefficient on `{q}`, which is not a "
                                    "coordinate", key=key, symbol=str(q),
                                    fix="use coordinate names (and `t` for the term in dt): "
                                        + ", ".join([*self.coordinates, "t"]))
                a = self.a.expr(raw, f"the coefficient of `{q}`", coefficient, key=key)
                rates = _rates_in(a, self.rates)
                if rates:
                    raise self.fail(raw, f"the coefficient of `{q}` in constraint `{raw.name}` holds the rate "
                                    f"`{rates[0]}`: the constraint would not be linear in the velocities", key=key,
                                    symbol=rates[0], fix="coefficients a_i(q, t) depend on coordinates, parameters "
                                                         "and t only")
                terms.append(a if q == "t" else a * self.coordinates[q].rate_symbol)
            if not terms:
                raise self.fail(raw, f"constraint `{raw.name}` has no coefficient", key=key,
                                fix='e.g. { x = "1", phi = "-r" } for x_dot - r*phi_dot = 0')
            expression: se.Basic | Vector = se.Add(*terms)
        else:
            expression = self.a.expr(raw, "the nonholonomic constraint", value, vector=None, key=key)
        comps = [c for _, cs in expression for c in cs] if isinstance(expression, Vector) else [expression]
        if not any(_rates_in(c, self.rates) for c in comps):
            raise self.fail(raw, f"nonholonomic constraint `{raw.name}` holds no rate q̇: it is a relation f(q, t) "
                            "= 0 between the coordinates", key=key,
                            fix=f'declare it holonomic: {raw.name} = {{ holonomic = "..." }}')
        for c in comps:
            for s, name in self.rates.items():
                a = c.diff(s)
                left = _rates_in(a, self.rates)
                if left:
                    raise self.fail(raw, f"constraint `{raw.name}` is not linear in the velocities: its derivative "
                                    f"with respect to `{name}` is `{a}`, which still holds `{left[0]}`", key=key,
                                    symbol=name, fix="only constraints a(q, t)·q̇ + b(q, t) = 0 (linear in the rates) "
                                                     "can be kept with multipliers; a constraint that is not linear "
                                                     "in the velocities is outside the Lagrange method")
        return expression

    def reaction(self, raw: Any, spec: Any, form: str) -> ReactionSpec | None:
        if spec is None:
            return None
        if form in ("no_slip", "coincide"):
            raise self.fail(raw, f"the reaction of `{form}` constraint `{raw.name}` is found automatically (a force "
                            f"at point `{raw.data['value'] if form == 'no_slip' else raw.data['value'][0]}`)",
                            key="reaction", fix="remove `reaction`; its force is given in the constraint's `frame`")
        if not isinstance(spec, Mapping):
            raise self.fail(raw, f"`reaction` of constraint `{raw.name}` must be a table", key="reaction",
                            fix='e.g. reaction = { force_at = "P", frame = "R0" }')
        unknown = sorted(set(spec) - {"force_at", "moment_on", "frame"})
        if unknown:
            raise self.fail(raw, f"unknown key `{unknown[0]}` in the reaction of constraint `{raw.name}`",
                            key="reaction", symbol=unknown[0], fix="the keys are force_at, moment_on and frame")
        if spec.get("force_at") is None and spec.get("moment_on") is None:
            raise self.fail(raw, f"the reaction of constraint `{raw.name}` names neither a point nor a body",
                            key="reaction", fix='give force_at = "P" (a force at P) and/or moment_on = "S"')
        at = spec.get("force_at")
        on = spec.get("moment_on")
        return ReactionSpec(
            None if at is None else self.name_of(raw, "reaction", at, self.points, "point"),
            None if on is None else self.name_of(raw, "reaction", on, self.bodies, "body"),
            self.frame(raw, spec.get("frame", GALILEAN_FRAME), key="reaction"),
        )


def build_constraints(assembler: Any, raws: Sequence[Any], coordinates: Sequence[Any], points: Collection[str],
                      bodies: Collection[str], frame_axes: Mapping[str, tuple[str, str, str]] | None = None
                      ) -> tuple[Constraint, ...]:
    """Check the raw ``constraint`` declarations and return them as `Constraint` values.

    Raises
    ------
    ModelError
        At the declaration's file and line: unknown names, a holonomic constraint that
        holds a rate, a nonholonomic one that holds none or is not linear in the rates.
    """
    checker = _Checker(assembler, coordinates, points, bodies, frame_axes or {})
    return tuple(checker.build(raw) for raw in raws)
