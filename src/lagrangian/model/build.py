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

    Expressions (type ``expression`` below) are text in the model files' grammar (``"l*R1.x"``,
    ``"m*g"``), numbers or SymEngine expressions; a vector expression is a sum of basis vectors
    ``F.x``, ``F.y``, ``F.z`` of the declared frames.  Each declaration takes ``location``, where it
    was read from (file, line), for the messages of a reader such as the TOML one; None means the
    builder's ``source`` and no line.

    Parameters
    ----------
    name : str
        The model's name.
    description : str
        What it is, in words.
    source : str, optional
        The file the declarations come from, for error messages.
    title : str, optional
        The report's title; None: from ``name``.

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

        Parameters
        ----------
        name : str
            The symbol's name.
        value : float, optional
            Its value; None leaves it to be given when simulating.
        unit : str, optional
            Its unit, for display only.
        description : str, optional
            What it is, in words.
        positive, nonnegative, negative, nonpositive : bool, optional
            ``positive=True`` (or one of the others) declares its sign: the derivation may simplify with
            it, and a value that breaks it is refused.
        location : Location, optional
            Where it was declared.
        """
        self._add("parameter", name, location, value=value, unit=unit, description=description,
                  signs={"positive": positive, "nonnegative": nonnegative, "negative": negative,
                         "nonpositive": nonpositive})

    def input(self, name: str, *, unit: str | None = None, description: str | None = None,
              location: Location | None = None) -> None:
        """Declare an input u: a symbol used like a parameter (value 0) that some load must use.

        E.g. ``b.input("tau")`` then ``b.torque("motor", "tau*R1.z", on="S")``; linearization
        gives it a column of B.

        Parameters
        ----------
        name : str
            The input's name.
        unit : str, optional
            Its unit, for display only.
        description : str, optional
            What it is, in words.
        location : Location, optional
            Where it was declared.
        """
        self._add("input", name, location, value=0.0, unit=unit, description=description)

    def coordinate(self, name: str, initial: float | None = None, rate: float | None = None, *,
                   momentum: str | None = None, unit: str | None = None, description: str | None = None,
                   range: Sequence[Any] | None = None, location: Location | None = None) -> None:
        """Declare a principal parameter q_i, with optional q_i(0), q̇_i(0) and a name for its momentum integral.

        Parameters
        ----------
        name : str
            The coordinate's name.
        initial : float, optional
            The initial value q_i(0).
        rate : float, optional
            The initial rate q̇_i(0).
        momentum : str, optional
            The name of the first integral ∂T/∂q̇_i = cste should q_i be cyclic.
        unit : str, optional
            Its unit, for display only.
        description : str, optional
            What it is, in words.
        range : sequence of two expressions, optional
            ``[lower, upper]`` (numbers, or constant expressions in the parameters such as ``"-L"``;
            ``float("inf")`` for an open side) declares where q_i stays: the derivation may simplify with
            it, and `simulate` warns when a motion leaves it.
        location : Location, optional
            Where it was declared.
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

        Parameters
        ----------
        name : str
            The frame's name.
        parent : str, optional
            The frame it turns from (default R0).
        rotation : (expression, str) or sequence of them, optional
            One rotation ``(angle, axis)`` or several, in order; None: a frame fixed to its parent (no
            rotation).
        axes : sequence of three str, optional
            Display names of its axes.
        location : Location, optional
            Where it was declared.
        """
        self._add("frame", name, location, parent=parent, rotation=rotation, axes=axes)

    def point(self, name: str, position: Any, *, relative_to: str = ORIGIN,
              location: Location | None = None) -> None:
        """Declare a point by its position vector from ``relative_to`` (default O).

        Parameters
        ----------
        name : str
            The point's name.
        position : vector expression
            Its position from ``relative_to``.
        relative_to : str, optional
            The point the position starts from.
        location : Location, optional
            Where it was declared.
        """
        self._add("point", name, location, position=position, relative_to=relative_to)

    def body(self, name: str, *, frame: str, mass: Any = None, center: Any, inertia: Mapping[str, Any] | None,
             center_from: str = ORIGIN, fixed_point: str | None = None, free: bool = False,
             location: Location | None = None) -> None:
        """Declare a rigid body fixed to ``frame``.

        Parameters
        ----------
        name : str
            The body's name.
        frame : str
            The frame it is fixed in.
        mass : expression, optional
            Its mass; may be left out (None) for a body whose centre of mass G is fixed (a pulley on a
            fixed axle): it then enters neither T nor the generalized forces; the reactions ask for it.
        center : vector expression
            Its centre of mass G, from ``center_from``.
        inertia : mapping of str to object or None
            ``{"at": point or "G", "frame": name, "diagonal": [I1, I2, I3]}`` or with
            ``"matrix": [[...], [...], [...]]`` instead of ``"diagonal"``.
        center_from : str, optional
            The point ``center`` starts from.
        fixed_point : str, optional
            A point of the body fixed in R0.
        free : bool, optional
            ``free=True`` declares a free body (six degrees of freedom): ``frame`` turns from R0 by three
            Euler angles and its origin moves along R0's axes by three coordinates
            (`lagrangian.model._free`); `simulate` then integrates its orientation as a unit quaternion.
        location : Location, optional
            Where it was declared.
        """
        self._add("body", name, location, frame=frame, mass=mass, center=center, center_from=center_from,
                  inertia=inertia, fixed_point=fixed_point, free=free)

    def particle(self, name: str, *, mass: Any, position: Any, relative_to: str = ORIGIN,
                 location: Location | None = None) -> None:
        """Declare a point mass.

        Parameters
        ----------
        name : str
            The particle's name.
        mass : expression
            Its mass.
        position : vector expression
            Its position from ``relative_to``.
        relative_to : str, optional
            The point the position starts from.
        location : Location, optional
            Where it was declared.
        """
        self._add("particle", name, location, mass=mass, position=position, relative_to=relative_to)

    def gravity(self, name: str, field: Any, *, on: Sequence[str] = (), location: Location | None = None) -> None:
        """Uniform gravity g⃗ (e.g. ``"-g*R0.z"``) on the named bodies and particles (all when empty).

        Parameters
        ----------
        name : str
            The load's name.
        field : vector expression
            The field g⃗.
        on : sequence of str, optional
            The bodies and particles it acts on; all when empty.
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="gravity", field=field, on=tuple(on))

    def force(self, name: str, force: Any, *, at: str, location: Location | None = None) -> None:
        """A force F⃗ applied at point ``at`` (it may depend on q, q̇ and t).

        Parameters
        ----------
        name : str
            The load's name.
        force : vector expression
            The force F⃗.
        at : str
            The point it is applied at.
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="force", force=force, at=at)

    def torque(self, name: str, torque: Any, *, on: str, reaction_on: str | None = None,
               location: Location | None = None) -> None:
        """A couple C⃗ on ``on``, a body or a frame (a massless link); −C⃗ on ``reaction_on`` (body or frame) when given.

        Parameters
        ----------
        name : str
            The load's name.
        torque : vector expression
            The couple C⃗.
        on : str
            The body or frame it acts on.
        reaction_on : str, optional
            The body or frame on which −C⃗ acts.
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="torque", torque=torque, on=on, reaction_on=reaction_on)

    def spring(self, name: str, ends: Sequence[str], *, stiffness: Any, rest_length: Any = 0,
               location: Location | None = None) -> None:
        """A linear spring between two points.

        Parameters
        ----------
        name : str
            The load's name.
        ends : sequence of two str
            The points it joins.
        stiffness : expression
            The stiffness k: tension k(ℓ − ℓ0).
        rest_length : expression, optional
            The rest length ℓ0.
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="spring", ends=tuple(ends), stiffness=stiffness,
                  rest_length=rest_length)

    def damper(self, name: str, ends: Sequence[str], *, coefficient: Any, location: Location | None = None) -> None:
        """A linear viscous damper between two points.

        Parameters
        ----------
        name : str
            The load's name.
        ends : sequence of two str
            The points it joins.
        coefficient : expression
            The coefficient c: force c ℓ̇ along the line.
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="damper", ends=tuple(ends), coefficient=coefficient)

    def potential(self, name: str, energy: Any, *, location: Location | None = None) -> None:
        """A given potential energy U(q, t).

        Parameters
        ----------
        name : str
            The load's name.
        energy : expression
            U(q, t).
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="potential", energy=energy)

    def generalized_force(self, name: str, components: Mapping[str, Any], *,
                          location: Location | None = None) -> None:
        """Given generalized-force components, e.g. ``{"theta": "-c*theta_dot"}``.

        Parameters
        ----------
        name : str
            The load's name.
        components : mapping of str to expression
            Each coordinate's name to its component Q_i.
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="generalized_force", components=dict(components))

    def dissipation(self, name: str, function: Any, *, joints: Sequence[str] = (),
                    location: Location | None = None) -> None:
        """A Rayleigh dissipation function D(q, q̇, t): Q_i = −∂D/∂q̇_i (e.g. ``"1/2*c*x_dot^2"``).

        Parameters
        ----------
        name : str
            The load's name.
        function : expression
            D(q, q̇, t).
        joints : sequence of str, optional
            The coordinates whose joint it acts in (viscous friction in those joints), if any.
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="dissipation", function=function, joints=tuple(joints))

    def joint_damper(self, name: str, bodies: Sequence[str], *, coefficient: Any,
                     location: Location | None = None) -> None:
        """Declare viscous friction in the joint between ``bodies`` (S1, S2): −c Ω(S2/S1) on S2, +c Ω(S2/S1) on S1.

        Parameters
        ----------
        name : str
            The load's name.
        bodies : sequence of two str
            S1 and S2, each a body or a frame.
        coefficient : expression
            The coefficient c.
        location : Location, optional
            Where it was declared.
        """
        self._add("load", name, location, kind="joint_damper", bodies=tuple(bodies), coefficient=coefficient)

    def coulomb_friction(self, name: str, at: str, *, coefficient: Any, normal_force: Any, surface_velocity: Any = 0,
                         normal: Any = None, regularization: Any = DEFAULT_REGULARIZATION,
                         static_coefficient: Any = None, location: Location | None = None) -> None:
        """Dry friction at the sliding contact point ``at``: ``T = −f N v_s/√(|v_s|² + ε²)``, N given.

        Parameters
        ----------
        name : str
            The load's name.
        at : str
            The contact point.
        coefficient : expression
            The friction coefficient f.
        normal_force : expression
            The normal force N, known from the given forces.
        surface_velocity : vector expression, optional
            The velocity of the surface; v_s = V(at) − surface_velocity.
        normal : vector expression, optional
            The surface's unit normal: v_s is then projected on the tangent plane.
        regularization : expression, optional
            The regularization ε, a velocity; ``regularization=0`` asks for the exact law with stick/slip by events in
            simulation.
        static_coefficient : expression, optional
            The static coefficient f_s ≥ f, bounding the reaction while stuck (default f).
        location : Location, optional
            Where it was declared.
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

        Sizes are numbers or expressions in the parameters.  Several calls give a body several shapes.
        See ``docs/view.md``.

        Parameters
        ----------
        on : str
            The body or particle (or frame).
        kind : str, optional
            ``"sphere"`` (``radius``), ``"cylinder"`` (``radius``, ``length``, ``axis``), ``"disk"``
            (``radius``, ``thickness``, ``axis``), ``"box"`` (``size``: three sides along the frame's x,
            y, z), ``"rod"`` (``between`` two points, or ``length`` and ``axis``; ``radius``) or ``"mesh"``
            (``mesh``: an STL, OBJ or DAE file, ``scale``).
        radius : expression, optional
            Of a sphere, cylinder, disk or rod.
        length : expression, optional
            Of a cylinder or rod.
        thickness : expression, optional
            Of a disk.
        size : sequence of three expressions, optional
            A box's sides along the frame's x, y, z.
        axis : str or sequence of three float, optional
            ``"x"``, ``"-y"``... of the body's frame, or three numbers.
        center : vector expression, optional
            The shape's centre from ``from`` (default: the body's G, the particle).
        between : sequence of two str, optional
            The two points a rod joins.
        mesh : str, optional
            An STL, OBJ or DAE file.
        scale : float or sequence of three float, optional
            The mesh's scale.
        color : str or sequence of three float, optional
            A ``#rrggbb`` / CSS name / [r, g, b].
        opacity : float, optional
            In [0, 1].
        from_point : str, optional
            The model file's ``from``: the point ``center`` starts from.
        rotation : sequence of three sequences of three float, optional
            Instead of ``axis``, a constant rotation whose columns are the shape's x, y, z in the frame
            (URDF's rpy).
        location : Location, optional
            Where it was declared.
        **given
            The model file's keys as written (a key no kind has is refused when built).
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

        Parameters
        ----------
        frame : str
            The frame R.
        origin : str, optional
            The point O' (default O).
        location : Location, optional
            Where it was declared.
        """
        self._reference = (frame, origin, location or Location(self.source))

    def operating_point(self, values: Mapping[str, Any], *, independent: Sequence[str] | None = None,
                        dependent: Sequence[str] | None = None, location: Location | None = None) -> None:
        """Set the default point of linearization: coordinate and ``<coordinate>_dot`` names to constants.

        Given once; a second call replaces the first.

        Parameters
        ----------
        values : mapping of str to expression
            Numbers or expressions in the parameters (``"-v/rR"``).
        independent : sequence of str, optional
            The independent speeds (``["phi_dot", "delta_dot"]``), for models with complementary
            constraints.
        dependent : sequence of str, optional
            The coordinates the holonomic constraints eliminate, for models with complementary
            constraints.
        location : Location, optional
            Where it was declared.
        """
        self._operating_point = Raw("operating point", "operating_point",
                                    {"values": values, "independent": independent, "dependent": dependent},
                                    location or Location(self.source))

    def controls(self, values: Mapping[str, Any], *, location: Location | None = None) -> None:
        """Declare a control law per declared input, run by `simulate` unless its ``inputs=`` name the input.

        Given once; a second call replaces the first.

        Parameters
        ----------
        values : mapping of str to expression
            Input name to law: ``{"F": "-k1*x - k2*x_dot"}`` (expressions of t, the coordinates, their
            rates and the parameters).
        location : Location, optional
            Where it was declared.
        """
        self._controls = Raw("controls", "controls", {"values": values}, location or Location(self.source))

    def constraint(self, name: str, form: str, value: Any, *, on: str | None = None, frame: str = GALILEAN_FRAME,
                   axes: Sequence[str] | None = None, principal: bool = False, reaction: Mapping[str, Any] | None = None,
                   description: str | None = None, location: Location | None = None, restitution: Any = None,
                   friction: Any = None, slip: Any = None) -> None:
        """A constraint kept complementary (with a multiplier), or declared ``principal``.

        See `lagrangian.model._constraints` and ``docs/constraints.md``.

        Parameters
        ----------
        name : str
            The constraint's name; its multipliers are ``lambda_<name>``.
        form : str
            ``"holonomic"``, ``"nonholonomic"``, ``"no_slip"``, ``"coincide"`` or ``"unilateral"`` (a
            contact: `lagrangian.model._unilateral`).
        value : expression or vector expression
            The function in f(q, t) = 0 (holonomic), a·q̇ + b = 0 (nonholonomic), the gap g(q, t) ≥ 0 (unilateral), the
            point or points of the point forms.
        on : str, optional
            The rolling body (no_slip).
        frame : str, optional
            The frame whose axes give the scalar rows of a vector constraint.
        axes : sequence of str, optional
            Keeps, of a vector constraint, only the rows along those axes of ``frame``.
        principal : bool, optional
            True when the choice of coordinates already satisfies it (no multiplier).
        reaction : mapping of str to object, optional
            The physical efforts that carry its reaction (a force at a point, a moment on a body).
        description : str, optional
            What it is, in words.
        location : Location, optional
            Where it was declared.
        restitution : expression, optional
            Newton's coefficient e of a unilateral constraint.
        friction : expression, optional
            The Coulomb coefficient μ of a unilateral constraint.
        slip : vector expression, optional
            The sliding velocity w of a unilateral constraint with friction.
        """
        self._add("constraint", name, location, form=form, value=value, on=on, frame=frame, axes=axes,
                  principal=principal, reaction=reaction, description=description, restitution=restitution,
                  friction=friction, slip=slip)

    # -- build ----------------------------------------------------------------------------
    def build(self) -> Model:
        """Check every declaration and return the frozen `Model`.

        Returns
        -------
        Model
            The checked model.

        Raises
        ------
        ModelError
            Naming the file, line and symbol of the first problem found, and its fix.
        """
        return Assembler(self).run()
