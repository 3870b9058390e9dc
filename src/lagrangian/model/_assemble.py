"""From the builder's raw declarations to a checked, frozen `Model` (`ModelBuilder.build`).

Each declaration (`Raw`) keeps the file and line it came from, so every check here names
them: unknown and duplicated names, frame cycles and frames with two parents, points
defined in terms of each other, bodies without inertia, unused coordinates, loads on
unknown points.  Expressions are read by the safe grammar of `_expr` (never evaluated).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import symengine as se

from .._identity import are_zero
from ..errors import ModelError
from ._assumptions import read_range, read_sign
from ._constraints import build_constraints
from ._controls import build_controls
from ._expr import CONSTANTS, FUNCTIONS, ExpressionError, parse_expression
from ._free import check_free_bodies
from ._friction import FRICTION_KINDS, build_friction_load
from ._limits import NotFinite, excerpt, real_value
from ._operating_point import build_operating_point, check_inputs_used
from ._reference import check_reference
from ._shapes import build_shapes
from .spec import (
    GALILEAN_FRAME,
    GENERAL_AXIS,
    ORIGIN,
    TIME,
    Body,
    Coordinate,
    Damper,
    Frame,
    GeneralizedForce,
    Gravity,
    Inertia,
    Load,
    Location,
    Model,
    Parameter,
    Particle,
    Point,
    PointForce,
    Potential,
    Reference,
    Rotation,
    Spring,
    Torque,
)
from .vectors import Vector, as_expr

__all__ = ["Assembler", "Raw", "RESERVED", "default_axes", "location_keys"]

if TYPE_CHECKING:  # pragma: no cover
    from .build import ModelBuilder

RESERVED = {"t", *CONSTANTS, *FUNCTIONS, GALILEAN_FRAME, ORIGIN, "G"}

#: How a position relative to a point is written, by kind of declaration: one spelling, `from`.
_FROM_EXAMPLES = {
    "point": 'write B = { from = "A", position = "l*R2.x" }: the point it starts from is `from`',
    "particle": 'write from = "A" and position = "l*R2.x" as two keys of [particles.NAME]',
    "body": 'write from = "A" and center = "a*R.z" as two keys of [bodies.NAME] (AG from the point A)',
}


@dataclass(frozen=True, slots=True)
class Raw:
    """A declaration as given, with where it came from."""

    kind: str
    name: str
    data: dict[str, Any]
    location: Location


def default_axes(frame: str) -> tuple[str, str, str]:
    # R0 -> x0 y0 z0, R1 -> x1 y1 z1, R -> x y z, S -> x_S y_S z_S (the seed's habit).
    if frame == "R":
        return ("x", "y", "z")
    if frame.startswith("R") and frame[1:].isdigit():
        return tuple(a + frame[1:] for a in "xyz")  # type: ignore[return-value]
    return tuple(f"{a}_{frame}" for a in "xyz")  # type: ignore[return-value]


def location_keys(location: Location) -> dict[str, Any]:
    return {"file": location.file, "line": location.line}


class Assembler:
    """Turns the raw declarations into a `Model`, one check at a time."""

    def __init__(self, builder: ModelBuilder) -> None:
        self.b = builder
        self.decl = builder._decl
        self.symbols: dict[str, se.Basic] = {"t": TIME}
        self.frame_names: list[str] = [GALILEAN_FRAME]
        self.locations: dict[tuple[str, str], Location] = {}
        #: The (non-input) parameters, by symbol, with their value (None when symbolic).
        self.constants: dict[se.Basic, float | None] = {}

    def of(self, kind: str) -> list[Raw]:
        return [d for d in self.decl if d.kind == kind]

    def error(self, raw: Raw | Location | None, message: str, *, fix: str | None = None,
              symbol: str | None = None, key: str | None = None) -> ModelError:
        """A `ModelError` located at the declaration ``raw`` (at its ``key`` when the file says where)."""
        loc = raw.location if isinstance(raw, Raw) else (raw or Location(self.b.source))
        return ModelError(message, fix=fix, symbol=symbol, **location_keys(loc.of(key)))

    # -- expressions ------------------------------------------------------------------------
    def expr(self, raw: Raw, what: str, value: Any, *, vector: bool | None = False, key: str | None = None) -> Any:
        """Parse ``value`` (text or object) as a scalar (vector=False) or vector (True).

        ``key`` names the declaration's key holding ``value``, to locate errors.
        """
        if isinstance(value, str):
            try:
                parsed = parse_expression(value, self.symbols, self.frame_names)
            except ExpressionError as exc:
                start = raw.location.value_column(key)
                raise ModelError(
                    f"in {what} of {raw.kind} `{raw.name}`: {exc.message} "
                    f"(in `{excerpt(value, exc.column)}`, column {exc.column})",
                    fix=exc.fix or "correct the expression: numbers, declared names, + - * / ^ ** and parentheses",
                    symbol=exc.symbol or raw.name,
                    column=None if start is None else start + exc.column - 1,  # in the file, when known
                    **location_keys(raw.location.of(key)),
                ) from None
        elif isinstance(value, Vector):
            parsed = value
        elif isinstance(value, Mapping):  # { from = "A", position = "…" } where an expression is expected
            raise self.error(raw, f"in {what} of {raw.kind} `{raw.name}`: a table is not an expression; a position "
                                  "relative to a point is given with `from` beside it", symbol=raw.name, key=key,
                             fix=_FROM_EXAMPLES.get(raw.kind, 'write the expression in quotes, e.g. "l*R1.x", and '
                                                               'the point it starts from as from = "A"'))
        else:
            try:
                parsed = as_expr(value)
            except TypeError as exc:
                raise self.error(raw, f"in {what} of {raw.kind} `{raw.name}`: {exc}", symbol=raw.name, key=key,
                                 fix='write a number or an expression in quotes, e.g. "m*g"') from None
            unknown = {str(s) for s in parsed.free_symbols} - set(self.symbols)
            if unknown:
                name = sorted(unknown)[0]
                raise self.error(raw, f"in {what} of {raw.kind} `{raw.name}`: unknown symbol `{name}`",
                                 symbol=name, fix=f"declare `{name}` as a parameter or a coordinate", key=key)
        if vector is True and not isinstance(parsed, Vector):
            if parsed == 0:
                return Vector.zero()
            raise self.error(raw, f"{what} of {raw.kind} `{raw.name}` must be a vector, not the scalar `{value}`",
                             fix="write it on basis vectors, e.g. `l*R1.x` or `-g*R0.z`", symbol=raw.name, key=key)
        if vector is False and isinstance(parsed, Vector):
            raise self.error(raw, f"{what} of {raw.kind} `{raw.name}` must be a scalar, not a vector",
                             fix="remove the basis vectors (`R.x`, ...) from it", symbol=raw.name, key=key)
        return parsed

    def number(self, raw: Raw, value: Any, what: str, key: str) -> float:
        """``value`` as a finite real float (`real_value`, the one check of every number's value)."""
        try:
            return real_value(value)
        except NotFinite as exc:
            raise self.error(raw, f"{what} must be a finite number: `{excerpt(str(value), width=40)}` is {exc}",
                             symbol=raw.name, key=key, fix="write a finite number, at most about 1.8e308 in "
                             "absolute value (not inf or nan)") from None

    # -- the stages of the build ---------------------------------------------------------------
    def run(self) -> Model:
        self.check_names()
        self.check_references()
        parameters = self.parameters()
        coordinates = self.coordinates()
        frames = self.frames()
        self._frame_map = {f.name: f for f in frames}
        points = self.points()
        bodies = self.bodies(points)
        particles = self.particles(points)
        all_points = {p.name: p for p in points}
        all_points.update({b.name: Point(b.name, b.center) for b in bodies})
        all_points.update({p.name: Point(p.name, p.position) for p in particles})
        loads = self.loads(all_points, bodies, particles, coordinates)
        constraints = build_constraints(self, self.of("constraint"), coordinates, all_points,
                                        [b.name for b in bodies], {f.name: f.axes for f in frames})
        operating = build_operating_point(self, self.b._operating_point, parameters, coordinates)
        controls = build_controls(self, getattr(self.b, "_controls", None), parameters, coordinates)
        shapes = build_shapes(self, self.of("shape"), bodies, particles, frames, all_points)
        model = Model(
            name=self.b.name,
            description=self.b.description,
            title=getattr(self.b, "title", None),
            parameters=parameters,
            coordinates=coordinates,
            frames=frames,
            points=tuple(points),
            bodies=bodies,
            particles=particles,
            loads=loads,
            source=self.b.source,
            locations=self.locations,
            constraints=constraints,
            reference=self.reference(all_points, frames, coordinates),
            shapes=shapes,
            **operating,
            controls=controls,
        )
        self.check_coordinates_used(model)
        check_inputs_used(model)
        check_free_bodies(model)
        return model

    def check_names(self) -> None:
        seen: dict[str, Raw] = {}
        for raw in self.decl:
            if raw.kind == "shape":  # a shape is named by its body or particle (`_shapes`)
                continue
            self.locations[(raw.kind, raw.name)] = raw.location
            if raw.kind == "frame" and raw.name == GALILEAN_FRAME:
                continue  # R0 may be re-declared to name its axes
            names = [raw.name]
            if raw.kind == "coordinate":
                names += [raw.name + "_dot", raw.name + "_ddot"]
            for name in names:
                if raw.kind not in ("load", "constraint") and name in RESERVED:
                    raise self.error(raw, f"`{name}` is a reserved name and cannot name a {raw.kind}",
                                     symbol=name, fix="choose another name (t, pi, R0, O, G and the "
                                     "function names are reserved)")
                key = name if raw.kind not in ("load", "constraint") else f"{raw.kind}:{name}"
                if key in seen:
                    first = seen[key]
                    where = f" (first declared as a {first.kind}"
                    where += f" at line {first.location.line})" if first.location.line else ")"
                    if raw.kind == first.kind == "frame":
                        msg = (f"frame `{name}` is defined twice{where}; a frame has exactly one parent")
                    else:
                        msg = f"the name `{name}` is declared twice{where}"
                    raise self.error(raw, msg, symbol=name, fix="rename one of them")
                seen[key] = raw

    #: The data keys of each kind of declaration that hold names of frames, points or bodies.
    _REFERENCES = {
        "frame": ("parent",),
        "point": ("relative_to",),
        "body": ("frame", "center_from", "fixed_point"),
        "particle": ("relative_to",),
        "load": ("on", "at", "reaction_on", "ends"),
    }

    def check_references(self) -> None:
        """Names of frames, points and bodies must be text (a list of names for `on` and `ends`)."""
        for raw in self.decl:
            for key in self._REFERENCES.get(raw.kind, ()):
                value = raw.data.get(key)
                many = key in ("ends",) or (key == "on" and raw.data.get("kind") == "gravity")
                items = value if many and isinstance(value, (tuple, list)) else (value,)
                if not all(v is None or isinstance(v, str) for v in items):
                    raise self.error(raw, f"`{key}` of {raw.kind} `{raw.name}` must be "
                                     + ("a list of names" if many else "a name") + f", not `{value}`",
                                     symbol=raw.name, key=key, fix='write names in quotes, e.g. "R1" or "O"')

    def parameters(self) -> tuple[Parameter, ...]:
        out = []
        for raw in self.decl:
            if raw.kind not in ("parameter", "input"):
                continue
            value = raw.data["value"]
            if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))):
                raise self.error(raw, f"the value of parameter `{raw.name}` must be a number, not `{value}`",
                                 symbol=raw.name, key="value",
                                 fix="write a number, or leave the value out to keep it symbolic")
            if value is not None:
                value = self.number(raw, value, f"the value of parameter `{raw.name}`", "value")
            for key in ("unit", "description"):
                if raw.data[key] is not None and not isinstance(raw.data[key], str):
                    raise self.error(raw, f"`{key}` of {raw.kind} `{raw.name}` must be text, not `{raw.data[key]}`",
                                     symbol=raw.name, key=key, fix=f'write it in quotes, e.g. {key} = "..."')
            sign = read_sign(self, raw, value) if raw.kind == "parameter" else None
            out.append(Parameter(raw.name, value, raw.data["unit"],
                                 raw.data["description"], input=raw.kind == "input", sign=sign))
            self.symbols[raw.name] = se.Symbol(raw.name)
            if raw.kind == "parameter":
                self.constants[self.symbols[raw.name]] = value
        return tuple(out)

    def coordinates(self) -> tuple[Coordinate, ...]:
        out = []
        for raw in self.of("coordinate"):
            values: dict[str, float | None] = {}
            for key in ("initial", "rate"):
                v = raw.data[key]
                if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))):
                    raise self.error(raw, f"`{key}` of coordinate `{raw.name}` must be a finite number, not `{v}`",
                                     symbol=raw.name, key=key, fix=f"write a number, e.g. {key} = 0.0, or leave it out")
                values[key] = None if v is None else self.number(raw, v, f"`{key}` of coordinate `{raw.name}`", key)
            momentum = raw.data["momentum"]
            if momentum is not None and (not isinstance(momentum, str) or not momentum.isidentifier()):
                raise self.error(raw, f"`momentum` of coordinate `{raw.name}` must be a name, not `{momentum}`",
                                 symbol=raw.name, key="momentum", fix='write a name in quotes, e.g. momentum = "K"')
            c = Coordinate(raw.name, values["initial"], values["rate"],
                           raw.data["momentum"], raw.data["unit"], raw.data["description"])
            out.append(c)
            self.symbols[c.name] = c.symbol
            self.symbols[c.rate_symbol.name] = c.rate_symbol
        if not out:
            raise ModelError("the model declares no coordinate", file=self.b.source,
                             fix="declare the principal parameters q_i under [coordinates]")
        # Ranges once every coordinate is known, so that a bound naming one is refused as such.
        return tuple(dataclasses.replace(c, range=read_range(self, raw, c.initial))
                     if raw.data.get("range") is not None else c for c, raw in zip(out, self.of("coordinate"), strict=True))

    def frames(self) -> tuple[Frame, ...]:
        raws = {r.name: r for r in self.of("frame")}
        self.frame_names = [GALILEAN_FRAME, *[n for n in raws if n != GALILEAN_FRAME]]
        root = raws.pop(GALILEAN_FRAME, None)
        if root is not None and (root.data["parent"] not in (None, GALILEAN_FRAME) or root.data["rotation"]):
            raise self.error(root, "R0 is the Galilean frame and has no parent or rotation",
                             symbol=GALILEAN_FRAME, fix="only `axes` may be given for R0",
                             key="rotation" if root.data["rotation"] else "parent")
        if root is not None:
            self.check_axes(root)
        r0_axes = tuple(root.data["axes"]) if root is not None and root.data["axes"] else default_axes("R0")
        ordered: list[Frame] = [Frame(GALILEAN_FRAME, None, None, r0_axes)]
        done = {GALILEAN_FRAME}
        state: dict[str, str] = {}

        def visit(name: str, chain: list[str]) -> None:
            if name in done:
                return
            raw = raws[name]
            if state.get(name) == "visiting":
                cycle = chain[chain.index(name):] + [name]
                raise self.error(raw, "frames " + " → ".join(f"`{c}`" for c in cycle) + " form a cycle",
                                 symbol=name, fix="every frame must descend from R0 through a chain of parents")
            state[name] = "visiting"
            parent = raw.data["parent"]
            if parent is None:
                raise self.error(raw, f"frame `{name}` has no parent", symbol=name,
                                 fix='give it one with `from = "R0"` (or another frame)')
            if parent not in raws and parent != GALILEAN_FRAME:
                raise self.error(raw, f"frame `{name}` comes from unknown frame `{parent}`", symbol=parent,
                                 fix="declare that frame, or correct the name; known frames: "
                                 + ", ".join(self.frame_names), key="parent")
            visit(parent, chain + [name])
            ordered.extend(self.rotation_chain(raw))
            done.add(name)

        for name in raws:
            visit(name, [])
        return tuple(ordered)

    def check_axes(self, raw: Raw) -> None:
        axes = raw.data["axes"]
        if axes is not None and (isinstance(axes, str) or not isinstance(axes, Sequence) or len(axes) != 3
                                 or not all(isinstance(a, str) for a in axes)):
            raise self.error(raw, f"`axes` of frame `{raw.name}` must list three names, not `{axes}`",
                             symbol=raw.name, fix='e.g. axes = ["u", "w", "z"]', key="axes")
        if axes is not None:
            for a in axes:
                # Axis names are printed in the equations and matched in text: identifiers only.
                if not a.isidentifier() or not a.isascii() or a.startswith("_"):
                    raise self.error(raw, f"axis name `{a[:40]!r}` of frame `{raw.name}` is not a name (ASCII letters, "
                                     "digits and `_`, starting with a letter)", symbol=raw.name,
                                     fix='e.g. axes = ["u", "w", "z"] or ["x1", "y1", "z0"]', key="axes")

    def rotation_chain(self, raw: Raw) -> list[Frame]:
        rot = raw.data["rotation"]
        if rot is None:
            steps: list[tuple[Any, str]] = [(0, "z")]  # a frame fixed to its parent
        elif _is_single_rotation(rot):
            steps = [tuple(rot)]
        elif (isinstance(rot, Sequence) and not isinstance(rot, str) and len(rot) > 0
              and all(_is_single_rotation(s) for s in rot)):
            steps = [tuple(s) for s in rot]
        else:
            raise self.error(raw, f"rotation of frame `{raw.name}` must be [angle, axis] or a list of such pairs, "
                             f"not `{rot}`", symbol=raw.name, key="rotation",
                             fix='e.g. rotation = ["theta", "x"], ["Omega*t", "cos(lat)*R0.y + sin(lat)*R0.z"], '
                             'or [["psi", "z"], ["theta", "x"]]')
        self.check_axes(raw)
        axes = raw.data["axes"]
        frames = []
        parent = raw.data["parent"]
        for k, step in enumerate(steps):
            angle, axis = step
            angle_expr = self.expr(raw, "the rotation angle", angle, key="rotation")
            rotation = (Rotation(angle_expr, axis) if axis in ("x", "y", "z")
                        else self.axis_rotation(raw, angle_expr, axis, parent, first=k == 0))
            last = k == len(steps) - 1
            name = raw.name if last else f"_{raw.name}_{k + 1}"
            frame_axes = tuple(axes) if (last and axes) else default_axes(name)
            frames.append(Frame(name, parent, rotation, frame_axes))
            parent = name
        return frames

    def axis_rotation(self, raw: Raw, angle: se.Basic, axis: Any, parent: str, *, first: bool) -> Rotation:
        """A rotation about a constant vector n of the parent (``"cos(lat)*R0.y + sin(lat)*R0.z"``).

        n must be written in the parent's basis, with parameters only (the axis is fixed in
        both frames).  A unit n is kept as written — provably unit: |n|² − 1 ≡ 0, e.g.
        cos²λ + sin²λ — ; any other non-zero n is replaced by n/|n| (``normalized``, which
        the printed frames mention); the zero vector is refused.  A basis vector of the
        parent gives the elementary rotation about that axis.
        """
        fix = (f'write the axis as a constant vector of the parent `{parent}`, e.g. '
               f'"cos(lat)*{parent}.y + sin(lat)*{parent}.z", or one of x, y, z')
        if not first:
            raise self.error(raw, f"in the rotations of frame `{raw.name}`, only the first may turn about a vector "
                             f"(`{axis}`): the frames between the rotations of a sequence have no name to write it in",
                             symbol=raw.name, key="rotation",
                             fix="declare the frame before that rotation under [frames], then this one from it")
        if not isinstance(axis, (str, Vector)):
            raise self.error(raw, f"rotation axis `{axis}` of frame `{raw.name}` is not x, y, z or a vector",
                             symbol=str(axis), key="rotation", fix=fix)
        vector = self.expr(raw, "the rotation axis", axis, vector=True, key="rotation")
        others = [f for f in vector.frames if f != parent]
        if others:
            raise self.error(raw, f"the rotation axis of frame `{raw.name}` is written in `{others[0]}`, not in its "
                             f"parent `{parent}`", symbol=others[0], key="rotation", fix=fix)
        moving = sorted(str(x) for x in vector.free_symbols() if x not in self.constants)
        if moving:
            raise self.error(raw, f"the rotation axis of frame `{raw.name}` depends on `{moving[0]}`: an axis is a "
                             "constant vector of the parent (and of the frame)", symbol=moving[0], key="rotation",
                             fix=fix + "; a moving axis is a chain of rotations")
        comps = vector.pieces.get(parent)
        if comps is None:
            raise self.error(raw, f"the rotation axis of frame `{raw.name}` is the zero vector", symbol=raw.name,
                             key="rotation", fix=fix)
        zero = se.Integer(0)
        for letter, unit in zip("xyz", ((1, 0, 0), (0, 1, 0), (0, 0, 1)), strict=True):
            if all(c == u for c, u in zip(comps, unit, strict=True)):
                return Rotation(angle, letter)  # a basis vector: the elementary rotation
        norm2 = se.expand(sum((c * c for c in comps), zero))
        if are_zero([norm2 - 1])[0]:
            return Rotation(angle, GENERAL_AXIS, comps)
        known = {x: v for x, v in self.constants.items() if v is not None}
        try:
            size = real_value(norm2.subs(known)) if norm2.free_symbols <= set(known) else None
        except NotFinite:
            size = None
        if are_zero([norm2])[0] or size == 0:
            given = ", ".join(f"{x} = {known[x]:g}" for x in sorted(norm2.free_symbols, key=str))
            raise self.error(raw, f"the rotation axis of frame `{raw.name}` is the zero vector"
                             + (f" (with {given})" if given else ""), symbol=raw.name, key="rotation", fix=fix)
        norm = se.sqrt(norm2)
        return Rotation(angle, GENERAL_AXIS, tuple(c / norm for c in comps), normalized=True)

    def points(self) -> list[Point]:
        raws = {r.name: r for r in self.of("point")}
        # Declared points are resolved here; body centres and particles become available as
        # `from` points once they are built (bodies first, then particles in file order).
        resolved: dict[str, Point] = {ORIGIN: Point(ORIGIN, Vector.zero())}
        chain: list[str] = []

        def resolve(name: str, raw: Raw) -> Point:
            if name in resolved:
                return resolved[name]
            if name not in raws:
                raise self.error(raw, f"point `{raw.name}` is given from unknown point `{name}`", symbol=name,
                                 fix="declare it under [points], or use O", key="relative_to")
            if name in chain:
                cycle = chain[chain.index(name):] + [name]
                message = (f"point `{name}` is defined in terms of itself" if len(cycle) == 2 else
                           "points " + " → ".join(f"`{c}`" for c in cycle) + " are defined in terms of each other")
                raise self.error(raws[name], message, symbol=name, key="relative_to",
                                 fix="define at least one point of the chain from O")
            chain.append(name)
            r = raws[name]
            base = resolve(r.data["relative_to"], r)
            offset = self.expr(r, "the position", r.data["position"], vector=True, key="position")
            resolved[name] = Point(name, base.position + offset)
            chain.pop()
            return resolved[name]

        for name, raw in raws.items():
            resolve(name, raw)
        self._points = resolved
        return list(resolved.values())

    def _position(self, raw: Raw, value: Any, relative_to: str, what: str, key: str, from_key: str) -> Vector:
        base = self._points.get(relative_to)
        if base is None:
            raise self.error(raw, f"unknown point `{relative_to}` in {what} of {raw.kind} `{raw.name}`",
                             symbol=relative_to, key=from_key,
                             fix="declare it under [points], use O, or a body or particle declared before")
        return base.position + self.expr(raw, what, value, vector=True, key=key)

    def bodies(self, points: list[Point]) -> tuple[Body, ...]:
        out = []
        for raw in self.of("body"):
            d = raw.data
            if d["frame"] not in self.frame_names:
                raise self.error(raw, f"body `{raw.name}` is attached to unknown frame `{d['frame']}`",
                                 symbol=str(d["frame"]), fix="declare the frame under [frames] first", key="frame")
            given = d["mass"] is not None
            mass = self.mass(raw, d["mass"]) if given else se.Integer(0)
            center = self._position(raw, d["center"], d["center_from"], "the centre of mass", "center", "center_from")
            inertia = self.inertia(raw, d["inertia"], d["frame"])
            fixed = d["fixed_point"]
            if fixed is not None and fixed not in self._points:
                raise self.error(raw, f"fixed point `{fixed}` of body `{raw.name}` is not a declared point",
                                 symbol=str(fixed), fix="declare it under [points] (O is predeclared)",
                                 key="fixed_point")
            if not given:
                self.check_mass_not_needed(raw, center, inertia)
            free = d.get("free", False)
            if not isinstance(free, bool):
                raise self.error(raw, f"`free` of body `{raw.name}` must be true or false, not `{free}`",
                                 symbol=raw.name, key="free", fix="write free = true (without quotes)")
            out.append(Body(raw.name, d["frame"], mass, center, inertia, fixed, mass_given=given, free=free))
            self._points.setdefault(raw.name, Point(raw.name, center))  # its centre, for later `from`
        return tuple(out)

    def check_mass_not_needed(self, raw: Raw, center: Vector, inertia: Inertia) -> None:
        """A body may leave its mass out only where the mass cannot enter the equations.

        That is when its centre G is fixed in R0 (OG holds no coordinate, rate or t, and is
        written in frames that do not turn): T = ½ Ω·Π_G·Ω (Koenig, V(G) = 0) and any force
        at G, its weight included, has no virtual power (V*(G) = 0).  The inertia must then
        be given at G (or at a point that is G), since moving it there needs m (Huygens), and
        the equations written in R0, since inertial forces would need m too.
        """
        fix = f'give it its mass, e.g. mass = "M" under [bodies.{raw.name}]'

        def moving(symbols: set) -> list[str]:
            return sorted(str(x) for x in symbols if x not in self.constants)

        why = moving(center.free_symbols())
        for name in center.frames:
            frame = self._frame_map[name]
            while frame.rotation is not None and not why:
                why = moving(frame.rotation.angle.free_symbols)
                frame = self._frame_map[frame.parent]  # type: ignore[index]
        if why:
            raise self.error(raw, f"body `{raw.name}` has no `mass`, but its centre of mass moves (with `{why[0]}`): "
                             "its mass enters T and the work of its weight", symbol=raw.name,
                             fix=fix + "; only a body whose centre of mass is fixed may leave it out")
        if inertia.at != "G":
            offset = self._points[inertia.at].position - center
            if any(se.expand(c) != 0 for _, comps in offset for c in comps):
                raise self.error(raw, f"body `{raw.name}` has no `mass`, but its inertia is given at `{inertia.at}`, "
                                 "not at its centre of mass: moving it there needs the mass (Huygens)",
                                 symbol=raw.name, key="inertia", fix=fix + ', or give the inertia at = "G"')
        reference = self.b._reference
        if reference is not None and (reference[0], reference[1]) != (GALILEAN_FRAME, ORIGIN):
            raise self.error(raw, f"body `{raw.name}` has no `mass`, but the equations are written in `{reference[0]}`, "
                             "whose inertial forces on the body need it", symbol=raw.name, fix=fix)

    def mass(self, raw: Raw, value: Any) -> se.Basic:
        """The mass of a body or particle: constant (parameters only) and positive where its value is known.

        A mass that changes with t or the coordinates is outside the Lagrange equations of
        the course (variable-mass systems need the momentum flux); a zero mass is a point,
        not a particle or a body; a negative one makes M indefinite.
        """
        mass = self.expr(raw, "the mass", value, key="mass")
        moving = sorted(str(s) for s in mass.free_symbols if s not in self.constants)
        what = "a particle" if raw.kind == "particle" else "a body"
        if moving:
            name = moving[0]
            kind = ("the time" if name == "t" else "an input" if any(p == name for p in self._inputs()) else
                    "a coordinate or a rate")
            raise self.error(raw, f"the mass of {raw.kind} `{raw.name}` depends on `{name}` ({kind}): "
                             f"the mass of {what} is constant", symbol=name, key="mass",
                             fix="write the mass with parameters only, e.g. mass = \"m\"")
        known = {s: v for s, v in self.constants.items() if v is not None}
        if not mass.free_symbols <= set(known):
            return mass  # symbolic: its sign is that of the parameters' values, given later
        try:
            number = real_value(mass.subs(known) if mass.free_symbols else mass)
        except NotFinite as exc:
            raise self.error(raw, f"the mass of {raw.kind} `{raw.name}` must be a finite number: it is {exc}",
                             symbol=raw.name, key="mass", fix="correct the mass or the parameters' values") from None
        if number <= 0:
            given = ", ".join(f"{s} = {known[s]:g}" for s in sorted(mass.free_symbols, key=str))
            point = ("a massless point is a point, not a particle: declare it under [points]" if raw.kind == "particle"
                     else "a body has a positive mass; a massless part is a frame, with points on it")
            raise self.error(raw, f"the mass of {raw.kind} `{raw.name}` is {number:g}"
                             + (f" (with {given})" if given else "") + f": the mass of {what} must be positive",
                             symbol=raw.name, key="mass", fix=f"give it a positive mass; {point}")
        return mass

    def _inputs(self) -> list[str]:
        return [raw.name for raw in self.of("input")]

    def inertia(self, raw: Raw, spec: Mapping[str, Any] | None, body_frame: str) -> Inertia:
        fix = ('give `inertia = { at = "G", frame = "' + body_frame + '", diagonal = ["A", "B", "C"] }`, '
               "or declare a point mass under [particles]")

        def fail(message: str, **kw: Any) -> ModelError:
            return self.error(raw, message, key="inertia", **kw)

        if not spec:
            raise fail(f"body `{raw.name}` has no inertia", symbol=raw.name, fix=fix)
        if not isinstance(spec, Mapping):
            raise fail(f"`inertia` of body `{raw.name}` must be a table", symbol=raw.name, fix=fix)
        unknown = set(spec) - {"at", "frame", "diagonal", "matrix"}
        if unknown:
            key = sorted(unknown)[0]
            raise fail(f"unknown key `{key}` in the inertia of body `{raw.name}`", symbol=key,
                       fix="the keys are at, frame, and diagonal or matrix")
        at = spec.get("at", "G")
        frame = spec.get("frame", body_frame)
        for key, value in (("at", at), ("frame", frame)):
            if not isinstance(value, str):
                raise fail(f"`{key}` of the inertia of body `{raw.name}` must be a name, not `{value}`",
                           symbol=raw.name, fix=f'write the name in quotes, e.g. {key} = "{body_frame}"'
                           if key == "frame" else 'write the name in quotes, e.g. at = "G"')
        if at != "G" and at != raw.name and at not in self._points:
            raise fail(f"inertia of body `{raw.name}` is given at unknown point `{at}`", symbol=at,
                       fix='use "G" for the centre of mass, or a declared point such as "O"')
        if frame not in self.frame_names:
            raise fail(f"inertia of body `{raw.name}` is given in unknown frame `{frame}`", symbol=frame,
                       fix="use the body's frame or a declared frame")
        if ("diagonal" in spec) == ("matrix" in spec):
            raise fail(f"inertia of body `{raw.name}` needs exactly one of `diagonal` and `matrix`",
                       symbol=raw.name, fix=fix)
        zero = se.Integer(0)
        if "diagonal" in spec:
            diag = spec["diagonal"]
            if not isinstance(diag, Sequence) or isinstance(diag, str) or len(diag) != 3:
                raise fail(f"`diagonal` of the inertia of `{raw.name}` must list three moments",
                           symbol=raw.name, fix='e.g. diagonal = ["A", "A", "C"]')
            d = [self.expr(raw, "the inertia", v, key="inertia") for v in diag]
            matrix = ((d[0], zero, zero), (zero, d[1], zero), (zero, zero, d[2]))
        else:
            rows = spec["matrix"]
            if (not isinstance(rows, Sequence) or len(rows) != 3
                    or any(not isinstance(r, Sequence) or isinstance(r, str) or len(r) != 3 for r in rows)):
                raise fail(f"`matrix` of the inertia of `{raw.name}` must be 3 rows of 3 entries", symbol=raw.name,
                           fix='e.g. matrix = [["A", "0", "0"], ["0", "B", "0"], ["0", "0", "C"]]')
            matrix = tuple(  # type: ignore[assignment]
                tuple(self.expr(raw, "the inertia", v, key="inertia") for v in row) for row in rows)
            for i in range(3):
                for j in range(i + 1, 3):
                    if (matrix[i][j] - matrix[j][i]).expand() != 0:
                        raise fail(f"inertia matrix of body `{raw.name}` is not symmetric: entry ({i + 1},{j + 1}) "
                                   f"is `{matrix[i][j]}` but ({j + 1},{i + 1}) is `{matrix[j][i]}`", symbol=raw.name,
                                   fix="an inertia matrix is symmetric; correct one of the two entries")
        at_name = "G" if at == raw.name else at
        return Inertia(at_name, frame, matrix)

    def particles(self, points: list[Point]) -> tuple[Particle, ...]:
        out = []
        for raw in self.of("particle"):
            mass = self.mass(raw, raw.data["mass"])
            position = self._position(raw, raw.data["position"], raw.data["relative_to"], "the position",
                                      "position", "relative_to")
            out.append(Particle(raw.name, mass, position))
            self._points.setdefault(raw.name, Point(raw.name, position))  # for a later particle's `from`
        return tuple(out)

    def loads(self, points: dict[str, Point], bodies: tuple[Body, ...], particles: tuple[Particle, ...],
              coordinates: tuple[Coordinate, ...]) -> tuple[Load, ...]:
        out: list[Load] = []
        massive = {b.name for b in bodies} | {p.name for p in particles}
        body_names = {b.name for b in bodies}

        def need_point(raw: Raw, name: Any, key: str) -> str:
            if name not in points:
                raise self.error(raw, f"load `{raw.name}` refers to unknown point `{name}`", symbol=str(name),
                                 fix="use O, a declared point, a body name (its centre G) or a particle name",
                                 key=key)
            return str(name)

        for raw in self.of("load"):
            d = raw.data
            kind = d["kind"]
            if kind == "gravity":
                for n in d["on"]:
                    if n not in massive:
                        raise self.error(raw, f"gravity `{raw.name}` acts on unknown body or particle `{n}`",
                                         symbol=str(n), fix="list body or particle names in `on`", key="on")
                out.append(Gravity(raw.name, self.expr(raw, "the field", d["field"], vector=True, key="field"),
                                   tuple(d["on"])))
            elif kind == "force":
                out.append(PointForce(raw.name, self.expr(raw, "the force", d["force"], vector=True, key="force"),
                                      need_point(raw, d["at"], "at")))
            elif kind == "torque":
                # A couple acts on a body or on a frame (a massless link: its virtual power is
                # C·Ω*(frame), the same with or without a body attached to it).
                for key, n in (("on", d["on"]), ("reaction_on", d["reaction_on"])):
                    if n is not None and n not in body_names and n not in self.frame_names:
                        raise self.error(raw, f"torque `{raw.name}` acts on unknown body or frame `{n}`",
                                         symbol=str(n), key=key,
                                         fix="name a declared body, or a frame (a massless link; R0 for the ground)")
                out.append(Torque(raw.name, self.expr(raw, "the torque", d["torque"], vector=True, key="torque"),
                                  d["on"], d["reaction_on"]))
            elif kind in ("spring", "damper"):
                ends = d["ends"]
                if len(ends) != 2:
                    raise self.error(raw, f"{kind} `{raw.name}` must join exactly two points, not {len(ends)}: "
                                     + ", ".join(f"`{e}`" for e in ends), symbol=raw.name,
                                     fix=f'e.g. {kind} = ["A", "B"]; use one {kind} per pair of points', key="ends")
                a, b = (need_point(raw, e, "ends") for e in ends)
                if kind == "spring":
                    out.append(Spring(raw.name, (a, b),
                                      self.expr(raw, "the stiffness", d["stiffness"], key="stiffness"),
                                      self.expr(raw, "the rest length", d["rest_length"], key="rest_length")))
                else:
                    out.append(Damper(raw.name, (a, b),
                                      self.expr(raw, "the coefficient", d["coefficient"], key="coefficient")))
            elif kind == "potential":
                energy = self.expr(raw, "the potential", d["energy"], key="energy")
                # A generalized potential U(q, q̇, t) gives Q_i = d/dt(∂U/∂q̇_i) − ∂U/∂q_i: with U affine in the
                # rates that holds no q̈ (the Lorentz force, U = qc (V − A·v)); beyond, q̈ would be in Q.
                rates = [c.rate_symbol for c in coordinates if c.rate_symbol in energy.free_symbols]
                pairs = [(a, b) for k, a in enumerate(rates) for b in rates[k:]]
                zero = are_zero([energy.diff(a).diff(b) for a, b in pairs]) if pairs else []
                bad = [pair for pair, ok in zip(pairs, zero, strict=True) if not ok]
                if bad:
                    a, b = bad[0]
                    raise self.error(raw, f"the potential `{raw.name}` is not affine in the rates (∂²U/∂{a}∂{b} ≠ 0): "
                                     "its generalized forces d/dt(∂U/∂q̇_i) − ∂U/∂q_i would hold the accelerations",
                                     symbol=raw.name, key="energy",
                                     fix="write the part quadratic in the rates as kinetic energy (a mass or an "
                                         "inertia), and keep in the potential only terms U0(q, t) + Σ a_j(q, t) q̇_j")
                out.append(Potential(raw.name, energy))
            elif kind == "generalized_force":
                names = [c.name for c in coordinates]
                comps = []
                for q, value in d["components"].items():
                    if q not in names:
                        raise self.error(raw, f"generalized force `{raw.name}` has a component on `{q}`, "
                                         "which is not a coordinate", symbol=str(q),
                                         fix="use coordinate names: " + ", ".join(names), key="components")
                    comps.append((q, self.expr(raw, f"the component on `{q}`", value, key="components")))
                out.append(GeneralizedForce(raw.name, tuple(comps)))
            elif kind in FRICTION_KINDS:
                out.append(build_friction_load(self, raw, points, body_names))
            else:  # pragma: no cover - the builder methods set `kind`
                raise AssertionError(kind)
        return tuple(out)

    def reference(self, points: dict[str, Point], frames: tuple[Frame, ...],
                  coordinates: tuple[Coordinate, ...]) -> Reference | None:
        """The checked reference frame, or None for R0 (see `lagrangian.model._reference`)."""
        if self.b._reference is None:
            return None
        frame, origin, where = self.b._reference
        symbols = {c.name: c.symbol for c in coordinates} | {c.rate_symbol.name: c.rate_symbol for c in coordinates}
        return check_reference(frame, origin, where, frames=frames, points=points, coordinates=symbols,
                               loads={raw.name: raw.location for raw in self.of("load")})

    def check_coordinates_used(self, model: Model) -> None:
        used: set[se.Basic] = set()
        # Frames matter only when something is attached to or written in them (or in a child).
        referenced: set[str] = set()
        for p in model.points:
            used |= p.position.free_symbols()
            referenced |= set(p.position.pieces)
        for b in model.bodies:
            used |= b.center.free_symbols()
            referenced |= {b.frame, b.inertia.frame, *b.center.pieces}
        for particle in model.particles:
            used |= particle.position.free_symbols()
            referenced |= set(particle.position.pieces)
        for load in model.loads:
            if isinstance(load, Potential):
                used |= load.energy.free_symbols
            elif isinstance(load, GeneralizedForce):
                for _, e in load.components:
                    used |= e.free_symbols
            elif isinstance(load, Gravity):
                referenced |= set(load.field.pieces)
            elif isinstance(load, PointForce):
                referenced |= set(load.force.pieces)
            elif isinstance(load, Torque):
                referenced |= set(load.torque.pieces) | {load.on, load.reaction_on or GALILEAN_FRAME}
        parents = {f.name: f for f in model.frames}
        for name in referenced:
            frame = parents.get(name)
            while frame is not None and frame.rotation is not None:
                used |= frame.rotation.angle.free_symbols
                frame = parents.get(frame.parent)  # type: ignore[arg-type]
        for c in model.coordinates:
            if c.symbol not in used:
                raise ModelError(
                    f"coordinate `{c.name}` is never used: no point, body, particle or load depends on it "
                    "(nor a frame they are attached to or written in), so its Lagrange equation would read 0 = 0",
                    symbol=c.name, fix="use it in a rotation or a position, or remove it",
                    **location_keys(model.where("coordinate", c.name)),
                )


def _is_single_rotation(rot: Any) -> bool:
    # [angle, axis]: the axis is a letter, a vector written as text, or a `Vector`.
    return (isinstance(rot, Sequence) and not isinstance(rot, str) and len(rot) == 2
            and isinstance(rot[1], (str, Vector)))

