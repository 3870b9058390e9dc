"""The Python builder API: declare a system piece by piece, then `build` a checked `Model`.

The TOML reader (`lagrangian.model.load_model`) goes through this same builder, so
the two ways of describing a system accept and reject exactly the same things.
Expressions may be given as text (read by the safe grammar of `_expr`, never
evaluated) or as SymPy/SymEngine objects.

Every check that can be made without kinematics is made when the model is built
(`_assemble`), with the file and line of the declaration when it came from a file.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from ..errors import ModelError
from ._assemble import Assembler, Raw, location_keys
from ._friction import DEFAULT_REGULARIZATION
from .spec import GALILEAN_FRAME, ORIGIN, Location, Model

__all__ = ["ModelBuilder"]


class ModelBuilder:
    """Declare a system in Python, then call `build`.

    Examples
    --------
    >>> b = ModelBuilder("simple pendulum")
    >>> b.parameter("m", 1.0); b.parameter("l", 0.5); b.parameter("g", 9.81)
    >>> b.coordinate("theta", initial=0.3)
    >>> b.frame("R1", "R0", rotation=("theta", "z"))
    >>> b.particle("P", mass="m", position="l*R1.x")
    >>> b.gravity("weight", "g*R0.x")
    >>> b.build().coordinates[0].name
    'theta'
    """

    def __init__(self, name: str = "model", description: str = "", *, source: str | None = None,
                 title: str | None = None) -> None:
        self.name = name
        self.description = description
        self.title = title
        self.source = source
        self._decl: list[Raw] = []
        self._reference: tuple[Any, Any, Location] | None = None  # (R, O', where): see `reference`
        self._operating_point: Raw | None = None  # see `operating_point`
        self._controls: Raw | None = None  # see `controls`

    # -- declarations -------------------------------------------------------------------
    def _add(self, what: str, name: str, location: Location | None, **data: Any) -> None:
        # A leading underscore is kept for the generated code's own names (_k0, _shared0, _y...).
        if not isinstance(name, str) or not name.isidentifier() or name.startswith("_"):
            raise ModelError(f"`{name}` is not a valid {what} name", symbol=str(name),
                             fix="use letters, digits and underscores, starting with a letter",
                             **location_keys(location or Location(self.source)))
        self._decl.append(Raw(what, name, data, location or Location(self.source)))

    def parameter(self, name: str, value: float | None = None, *, unit: str | None = None,
                  description: str | None = None, positive: bool | None = None, nonnegative: bool | None = None,
                  negative: bool | None = None, nonpositive: bool | None = None,
                  location: Location | None = None) -> None:
        """Declare a parameter (a constant symbol), with an optional numeric value.

        ``positive=True`` (or ``nonnegative``, ``negative``, ``nonpositive``) declares its sign: the
        derivation may simplify with it, and a value that breaks it is refused.
        """
        self._add("parameter", name, location, value=value, unit=unit, description=description,
                  signs={"positive": positive, "nonnegative": nonnegative, "negative": negative,
                         "nonpositive": nonpositive})

    def input(self, name: str, *, unit: str | None = None, description: str | None = None,
              location: Location | None = None) -> None:
        """Declare an input u: a symbol used like a parameter (value 0) that some load must use.

        E.g. ``b.input("tau")`` then ``b.torque("motor", "tau*R1.z", on="S")``; linearization
        gives it a column of B.
        """
        self._add("input", name, location, value=0.0, unit=unit, description=description)

    def coordinate(self, name: str, initial: float | None = None, rate: float | None = None, *,
                   momentum: str | None = None, unit: str | None = None, description: str | None = None,
                   range: Sequence[Any] | None = None, location: Location | None = None) -> None:
        """Declare a principal parameter q_i, with optional q_i(0), q̇_i(0) and a name for its momentum integral.

        ``range=[lower, upper]`` (numbers, or constant expressions in the parameters such as ``"-L"``;
        ``float("inf")`` for an open side) declares where q_i stays: the derivation may simplify with
        it, and `simulate` warns when a motion leaves it.
        """
        self._add("coordinate", name, location, initial=initial, rate=rate, momentum=momentum,
                  unit=unit, description=description, range=range)

    def frame(self, name: str, parent: str | None = GALILEAN_FRAME, *,
              rotation: tuple[Any, Any] | Sequence[tuple[Any, Any]] | None = None,
              axes: Sequence[str] | None = None, location: Location | None = None) -> None:
        """Declare a frame obtained from ``parent`` by one rotation ``(angle, axis)`` or a sequence of them.

        Each rotation is about the axis (``"x"``, ``"y"`` or ``"z"``) of the frame before it,
        as in the seed: R0 →(ψ, z0)→ R1 →(θ, u)→ R2 →(φ, z)→ R.  A single rotation (or the
        first of a sequence) may instead turn about a constant vector of ``parent``, e.g.
        ``("Omega*t", "cos(lat)*R0.y + sin(lat)*R0.z")``: kept when provably unit, else
        divided by its norm (the printed frames say so); the zero vector is refused.
        """
        self._add("frame", name, location, parent=parent, rotation=rotation, axes=axes)

    def point(self, name: str, position: Any, *, relative_to: str = ORIGIN,
              location: Location | None = None) -> None:
        """Declare a point by its position vector from ``relative_to`` (default O)."""
        self._add("point", name, location, position=position, relative_to=relative_to)

    def body(self, name: str, *, frame: str, mass: Any = None, center: Any, inertia: Mapping[str, Any] | None,
             center_from: str = ORIGIN, fixed_point: str | None = None, free: bool = False,
             location: Location | None = None) -> None:
        """Declare a rigid body fixed to ``frame``.

        ``inertia`` is ``{"at": point or "G", "frame": name, "diagonal": [I1, I2, I3]}`` or
        with ``"matrix": [[...], [...], [...]]`` instead of ``"diagonal"``.  ``mass`` may be
        left out (None) for a body whose centre of mass G is fixed (a pulley on a fixed axle):
        it then enters neither T nor the generalized forces; the reactions ask for it.
        ``free=True`` declares a free body (six degrees of freedom): ``frame`` turns from R0 by three
        Euler angles and its origin moves along R0's axes by three coordinates
        (`lagrangian.model._free`); `simulate` then integrates its orientation as a unit quaternion.
        """
        self._add("body", name, location, frame=frame, mass=mass, center=center, center_from=center_from,
                  inertia=inertia, fixed_point=fixed_point, free=free)

    def particle(self, name: str, *, mass: Any, position: Any, relative_to: str = ORIGIN,
                 location: Location | None = None) -> None:
        """Declare a point mass."""
        self._add("particle", name, location, mass=mass, position=position, relative_to=relative_to)

    def gravity(self, name: str, field: Any, *, on: Sequence[str] = (), location: Location | None = None) -> None:
        """Uniform gravity g⃗ (e.g. ``"-g*R0.z"``) on the named bodies and particles (all when empty)."""
        self._add("load", name, location, kind="gravity", field=field, on=tuple(on))

    def force(self, name: str, force: Any, *, at: str, location: Location | None = None) -> None:
        """A force F⃗ applied at point ``at`` (it may depend on q, q̇ and t)."""
        self._add("load", name, location, kind="force", force=force, at=at)

    def torque(self, name: str, torque: Any, *, on: str, reaction_on: str | None = None,
               location: Location | None = None) -> None:
        """A couple C⃗ on ``on``, a body or a frame (a massless link); −C⃗ on ``reaction_on`` (body or frame) when given."""
        self._add("load", name, location, kind="torque", torque=torque, on=on, reaction_on=reaction_on)

    def spring(self, name: str, ends: Sequence[str], *, stiffness: Any, rest_length: Any = 0,
               location: Location | None = None) -> None:
        """A linear spring between two points."""
        self._add("load", name, location, kind="spring", ends=tuple(ends), stiffness=stiffness,
                  rest_length=rest_length)

    def damper(self, name: str, ends: Sequence[str], *, coefficient: Any, location: Location | None = None) -> None:
        """A linear viscous damper between two points."""
        self._add("load", name, location, kind="damper", ends=tuple(ends), coefficient=coefficient)

    def potential(self, name: str, energy: Any, *, location: Location | None = None) -> None:
        """A given potential energy U(q, t)."""
        self._add("load", name, location, kind="potential", energy=energy)

    def generalized_force(self, name: str, components: Mapping[str, Any], *,
                          location: Location | None = None) -> None:
        """Given generalized-force components, e.g. ``{"theta": "-c*theta_dot"}``."""
        self._add("load", name, location, kind="generalized_force", components=dict(components))

    def dissipation(self, name: str, function: Any, *, joints: Sequence[str] = (),
                    location: Location | None = None) -> None:
        """A Rayleigh dissipation function D(q, q̇, t): Q_i = −∂D/∂q̇_i (e.g. ``"1/2*c*x_dot^2"``).

        ``joints``: the coordinates whose joint it acts in (viscous friction in those joints), if any."""
        self._add("load", name, location, kind="dissipation", function=function, joints=tuple(joints))

    def joint_damper(self, name: str, bodies: Sequence[str], *, coefficient: Any,
                     location: Location | None = None) -> None:
        """Viscous friction in the joint between ``bodies`` (S1, S2): couple −c Ω(S2/S1) on S2, +c Ω(S2/S1) on S1."""
        self._add("load", name, location, kind="joint_damper", bodies=tuple(bodies), coefficient=coefficient)

    def coulomb_friction(self, name: str, at: str, *, coefficient: Any, normal_force: Any, surface_velocity: Any = 0,
                         normal: Any = None, regularization: Any = DEFAULT_REGULARIZATION,
                         static_coefficient: Any = None, location: Location | None = None) -> None:
        """Dry friction at the sliding contact point ``at``: ``T = −f N v_s/√(|v_s|² + ε²)``, N given.

        ``regularization=0`` asks for the exact law with stick/slip by events in simulation,
        ``static_coefficient`` f_s ≥ f bounding the reaction while stuck (default f).
        """
        self._add("load", name, location, kind="coulomb", at=at, coefficient=coefficient, normal_force=normal_force,
                  surface_velocity=surface_velocity, normal=normal, regularization=regularization,
                  static_coefficient=static_coefficient)

    def shape(self, on: str, kind: str | None = None, *, radius: Any = None, length: Any = None,
              thickness: Any = None, size: Sequence[Any] | None = None, axis: Any = None, center: Any = None,
              between: Sequence[str] | None = None, mesh: str | None = None, scale: Any = None,
              color: Any = None, opacity: float | None = None, from_point: str | None = None,
              rotation: Sequence[Sequence[float]] | None = None, location: Location | None = None,
              **given: Any) -> None:
        """How body or particle ``on`` looks in the 3-D view and the animation (no part in the dynamics).

        ``kind`` is ``"sphere"`` (``radius``), ``"cylinder"`` (``radius``, ``length``, ``axis``),
        ``"disk"`` (``radius``, ``thickness``, ``axis``), ``"box"`` (``size``: three sides along the
        frame's x, y, z), ``"rod"`` (``between`` two points, or ``length`` and ``axis``; ``radius``)
        or ``"mesh"`` (``mesh``: an STL, OBJ or DAE file, ``scale``).  ``center`` places the shape's
        centre from ``from`` (default: the body's G, the particle); ``axis`` is ``"x"``, ``"-y"``...
        of the body's frame or three numbers; ``color`` a ``#rrggbb`` / CSS name / [r, g, b];
        ``opacity`` in [0, 1]; ``from_point`` is the model file's ``from``; ``rotation`` (instead of
        ``axis``) a constant rotation whose columns are the shape's x, y, z in the frame (URDF's rpy).
        Sizes are numbers or expressions in the parameters.  Several calls give a body several
        shapes.  See ``docs/view.md``.
        """
        if not isinstance(on, str):
            raise ModelError(f"a shape belongs to a body or particle named by text, not `{on}`", symbol=str(on),
                             fix='e.g. b.shape("S", "disk", radius=0.1)', **location_keys(location or Location(self.source)))
        data = dict(kind=kind, radius=radius, length=length, thickness=thickness, size=size, axis=axis,
                    center=center, between=between, mesh=mesh, scale=scale, color=color, opacity=opacity,
                    rotation=rotation)
        if from_point is not None:
            data["from"] = from_point
        data.update(given)  # the model file's keys as written (`from`, or a key no kind has: refused when built)
        self._decl.append(Raw("shape", on, data, location or Location(self.source)))

    def reference(self, frame: str, *, origin: str = ORIGIN, location: Location | None = None) -> None:
        """Write the equations relative to ``frame`` (R) of origin ``origin`` (O'), not R0 (seed, Remarque 3).

        R's rotation from R0 and the position of O' must depend on t only; the inertial
        forces of Coriolis and of entrainment are then added to the given efforts.
        """
        self._reference = (frame, origin, location or Location(self.source))

    def operating_point(self, values: Mapping[str, Any], *, independent: Sequence[str] | None = None,
                        dependent: Sequence[str] | None = None, location: Location | None = None) -> None:
        """The default point of linearization: coordinate and ``<coordinate>_dot`` names to constants.

        Values are numbers or expressions in the parameters (``"-v/rR"``); ``independent``
        names the independent speeds (``["phi_dot", "delta_dot"]``) and ``dependent`` the
        coordinates the holonomic constraints eliminate, for models with complementary
        constraints.  Given once; a second call replaces the first.
        """
        self._operating_point = Raw("operating point", "operating_point",
                                    {"values": values, "independent": independent, "dependent": dependent},
                                    location or Location(self.source))

    def controls(self, values: Mapping[str, Any], *, location: Location | None = None) -> None:
        """A control law per declared input: ``{"F": "-k1*x - k2*x_dot"}`` (expressions of t, the
        coordinates, their rates and the parameters), run by `simulate` unless its ``inputs=`` name
        the input.  Given once; a second call replaces the first."""
        self._controls = Raw("controls", "controls", {"values": values}, location or Location(self.source))

    def constraint(self, name: str, form: str, value: Any, *, on: str | None = None, frame: str = GALILEAN_FRAME,
                   axes: Sequence[str] | None = None, principal: bool = False, reaction: Mapping[str, Any] | None = None,
                   description: str | None = None, location: Location | None = None, restitution: Any = None,
                   friction: Any = None, slip: Any = None) -> None:
        """A constraint kept complementary (with a multiplier), or declared ``principal``.

        ``form`` is ``"holonomic"``, ``"nonholonomic"``, ``"no_slip"``, ``"coincide"`` or
        ``"unilateral"`` (a contact: ``value`` is the gap g(q, t) ≥ 0, with ``restitution`` e and
        optionally ``friction`` μ and ``slip`` w; `lagrangian.model._unilateral`); see
        `lagrangian.model._constraints` and ``docs/constraints.md``.  ``axes`` keeps, of a vector
        constraint, only the rows along those axes of ``frame``.
        """
        self._add("constraint", name, location, form=form, value=value, on=on, frame=frame, axes=axes,
                  principal=principal, reaction=reaction, description=description, restitution=restitution,
                  friction=friction, slip=slip)

    # -- build ----------------------------------------------------------------------------
    def build(self) -> Model:
        """Check every declaration and return the frozen `Model`.

        Raises
        ------
        ModelError
            Naming the file, line and symbol of the first problem found, and its fix.
        """
        return Assembler(self).run()
