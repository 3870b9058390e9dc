"""The model: frozen, validated data describing a mechanical system (Σ).

These values hold no derivation.  They are what a model file or the Python
`ModelBuilder` says, checked and with every expression already parsed into
SymEngine, in the course's vocabulary: parameters, principal parameters
(generalized coordinates q_i), frames given by chains of elementary rotations,
points, rigid bodies, particles and loads ("efforts donnés").
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import symengine as se

from ._constraints import Constraint, ReactionSpec
from .vectors import Vector

__all__ = [
    "GALILEAN_FRAME",
    "GENERAL_AXIS",
    "ORIGIN",
    "TIME",
    "Location",
    "Parameter",
    "Coordinate",
    "Rotation",
    "Frame",
    "Point",
    "Inertia",
    "Body",
    "Particle",
    "Gravity",
    "PointForce",
    "Torque",
    "Spring",
    "Damper",
    "Potential",
    "GeneralizedForce",
    "Dissipation",
    "JointDamper",
    "CoulombFriction",
    "Reference",
    "Load",
    "Shape",
    "SHAPE_KINDS",
    "Model",
    "Constraint",
    "ReactionSpec",
]

#: Name of the Galilean reference frame R0, root of the frame tree.
GALILEAN_FRAME = "R0"
#: Name of the origin O of R0.
ORIGIN = "O"
#: The time t.
TIME = se.Symbol("t")


@dataclass(frozen=True, slots=True)
class Location:
    """Where something was declared: a file and a 1-based line (either may be unknown).

    Parameters
    ----------
    file : str, optional
        The file, when known.
    line : int, optional
        The 1-based line of the declaration in ``file``, when known.
    keys : tuple of (str, int, int)
        For the declaration's keys (``"mass"``, ``"inertia"``, ...), the key, its line and the 1-based
        column where its text value starts (0 when unknown), so that an error can point at the
        offending key rather than the table.  It plays no part in comparisons.
    """

    file: str | None = None
    line: int | None = None
    keys: tuple[tuple[str, int, int], ...] = field(default=(), compare=False, repr=False)

    def of(self, key: str | None) -> Location:
        """The location of ``key`` of this declaration (this location when unknown).

        Parameters
        ----------
        key : str or None
            A key of the declaration (``"mass"``), or None.

        Returns
        -------
        Location
            The file and the line of ``key``; this location when the key's line is unknown.
        """
        for name, line, _ in self.keys:
            if name == key:
                return Location(self.file, line)
        return Location(self.file, self.line)

    def value_column(self, key: str | None) -> int | None:
        """The column where the text value of ``key`` starts in the file, when known.

        Parameters
        ----------
        key : str or None
            A key of the declaration (``"mass"``), or None.

        Returns
        -------
        int or None
            The 1-based column, or None when unknown.
        """
        for name, _, column in self.keys:
            if name == key:
                return column or None
        return None


@dataclass(frozen=True, slots=True)
class Parameter:
    """A constant of the problem (mass, length, inertia...), with an optional value.

    Parameters
    ----------
    name : str
        The symbol's name, as written in expressions.
    value : float, optional
        Its numeric value, when given.
    unit : str, optional
        Its unit, for display only.
    description : str, optional
        What it is, in words.
    input : bool
        Marks a declared input u (``[inputs]``): a symbol used like a parameter, typically the
        magnitude of a load (a motor torque), whose value is 0 (the input off) unless given;
        linearization makes it a column of B.
    sign : str, optional
        A declared sign assumption: ``"positive"``, ``"nonnegative"``, ``"negative"``,
        ``"nonpositive"`` or None (`lagrangian.model._assumptions`): the derivation may simplify with
        it, and a value that breaks it is refused.
    """

    name: str
    value: float | None = None
    unit: str | None = None
    description: str | None = None
    input: bool = False
    sign: str | None = None

    @property
    def symbol(self) -> se.Symbol:
        return se.Symbol(self.name)


@dataclass(frozen=True, slots=True)
class Coordinate:
    """A principal parameter q_i ("paramètre principal"), with q_i(0), q̇_i(0).

    Parameters
    ----------
    name : str
        The coordinate's name, as written in expressions.
    initial : float, optional
        Its initial value q_i(0), when given.
    rate : float, optional
        Its initial rate q̇_i(0), when given.
    momentum : str, optional
        The name of the first integral ∂T/∂q̇_i = cste when q_i turns out to be cyclic (the seed
        calls those of ψ and φ ``K`` and ``H``).
    unit : str, optional
        Its unit, for display only.
    description : str, optional
        What it is, in words.
    range : tuple of (expression or None, expression or None), optional
        The declared range [lower, upper] of q_i (constant expressions in the parameters; None for
        an open side), or None: the derivation may simplify with it (``|x + L| = x + L`` when
        x ≥ −L), and `simulate` warns when a motion leaves it (`lagrangian.model._assumptions`).
    """

    name: str
    initial: float | None = None
    rate: float | None = None
    momentum: str | None = None
    unit: str | None = None
    description: str | None = None
    range: tuple[se.Basic | None, se.Basic | None] | None = None

    @property
    def symbol(self) -> se.Symbol:
        return se.Symbol(self.name)

    @property
    def rate_symbol(self) -> se.Symbol:
        """The rate q̇_i, spelled ``<name>_dot`` in expressions and in JSON."""
        return se.Symbol(self.name + "_dot")

    @property
    def acceleration_symbol(self) -> se.Symbol:
        """The acceleration q̈_i, spelled ``<name>_ddot``."""
        return se.Symbol(self.name + "_ddot")


#: The axis letter of a rotation about a constant unit vector n (`Rotation.direction`).
GENERAL_AXIS = "n"


@dataclass(frozen=True, slots=True)
class Rotation:
    """A rotation of ``angle`` about the parent frame's ``axis`` (x, y or z), or about a constant axis n.

    The child frame shares that axis with its parent, as in R0 →(ψ, z0)→ R1.

    Parameters
    ----------
    angle : SymEngine expression
        The angle of the rotation, an expression of the coordinates and t.
    axis : str
        ``"x"``, ``"y"`` or ``"z"``; or ``"n"``, the constant unit vector ``direction``.
    direction : tuple of three SymEngine expressions, optional
        With ``axis = "n"``: (n_x, n_y, n_z), the axis' components in the parent's basis — which are
        also its components in the child's, the axis being common to both (the Earth turning about
        cos λ y0 + sin λ z0).  The change of basis is then Rodrigues' formula,
        v ↦ cos α v + sin α n ∧ v + (1 − cos α)(n·v) n.
    normalized : bool
        Records that the engine divided the given vector by its norm.
    """

    angle: se.Basic
    axis: str
    direction: tuple[se.Basic, se.Basic, se.Basic] | None = None
    normalized: bool = False

    def __post_init__(self) -> None:
        if self.axis not in ("x", "y", "z", GENERAL_AXIS):
            raise ValueError(f"rotation axis must be x, y, z or n, not {self.axis!r}")
        if (self.axis == GENERAL_AXIS) != (self.direction is not None):
            raise ValueError("a rotation about n needs its direction, and only it has one")

    @property
    def elementary(self) -> bool:
        """True for a rotation about the parent's x, y or z."""
        return self.axis != GENERAL_AXIS

    @property
    def unit_vector(self) -> tuple[se.Basic, se.Basic, se.Basic]:
        """The components of the rotation axis (unit) in the parent's (and the child's) basis."""
        if self.direction is not None:
            return self.direction
        one, zero = se.Integer(1), se.Integer(0)
        return tuple(one if a == self.axis else zero for a in "xyz")


@dataclass(frozen=True, slots=True)
class Frame:
    """A frame: its parent, the elementary rotation from it, and display names of its axes.

    A rotation sequence in a model file becomes a chain of frames whose intermediate names start
    with ``_``.

    Parameters
    ----------
    name : str
        The frame's name.
    parent : str or None
        The frame it turns from; None for the Galilean frame R0.
    rotation : Rotation or None
        The elementary rotation from ``parent``; None for R0.
    axes : tuple of three str
        The display names of its axes (``"x1"``, ``"y1"``, ``"z1"``).
    """

    name: str
    parent: str | None
    rotation: Rotation | None
    axes: tuple[str, str, str]


@dataclass(frozen=True, slots=True)
class Point:
    """A named point P with its position vector OP from the origin O of R0.

    Parameters
    ----------
    name : str
        The point's name.
    position : Vector
        OP, from the origin O of R0.
    """

    name: str
    position: Vector


@dataclass(frozen=True, slots=True)
class Inertia:
    """Inertia matrix Π_P of a body at point ``at``, in the basis of ``frame``.

    Parameters
    ----------
    at : str
        A point name, or ``"G"`` for the centre of mass.
    frame : str
        The frame whose basis the matrix is written in.
    matrix : tuple of three tuples of three SymEngine expressions
        ``matrix[k][l]`` is the (k, l) entry of the operator, i.e. diagonal entries are the moments
        of inertia and off-diagonal entries are minus the products of inertia.
    """

    at: str
    frame: str
    matrix: tuple[tuple[se.Basic, se.Basic, se.Basic], ...]


@dataclass(frozen=True, slots=True)
class Body:
    """A rigid body S attached to ``frame``, with mass m, centre of mass G (OG) and inertia.

    Parameters
    ----------
    name : str
        The body's name.
    frame : str
        The frame the body is fixed in.
    mass : SymEngine expression
        Its mass m.
    center : Vector
        OG, the position of its centre of mass from O.
    inertia : Inertia
        Its inertia operator, at a point and in a basis.
    fixed_point : str, optional
        A point of the body fixed in R0, when declared.
    mass_given : bool
        False for a body whose G is fixed and whose mass the model leaves out (a pulley on a fixed
        axle): ``mass`` is then 0, exact for everything the Lagrange equations use —
        T = ½ Ω·Π_G·Ω and m g·∂OG/∂q_i = 0 whatever m — while the reactions, which need it, refuse
        to be computed (`lagrangian.analysis.reactions`).
    free : bool
        Marks a body declared free (six degrees of freedom: three translations of its frame's origin
        along R0's axes and three Euler angles, checked by `lagrangian.model._free`): the equations
        keep those coordinates, and `simulate` integrates its orientation as a unit quaternion, which
        has no singular configuration (`lagrangian.numerics._free_simulate`).
    """

    name: str
    frame: str
    mass: se.Basic
    center: Vector
    inertia: Inertia
    fixed_point: str | None = None
    mass_given: bool = True
    free: bool = False


@dataclass(frozen=True, slots=True)
class Particle:
    """A point mass m at position OP.

    Parameters
    ----------
    name : str
        The particle's name.
    mass : SymEngine expression
        Its mass m.
    position : Vector
        OP, from the origin O of R0.
    """

    name: str
    mass: se.Basic
    position: Vector


# -- loads ("efforts donnés") -------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class Gravity:
    """Uniform gravity g⃗ acting on ``on`` (body and particle names; all when empty).

    Parameters
    ----------
    name : str
        The load's name.
    field : Vector
        The field g⃗.
    on : tuple of str
        The bodies and particles it acts on; all of them when empty.
    """

    name: str
    field: Vector
    on: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class PointForce:
    """A force F⃗ applied at point ``at``; it may depend on q, q̇ and t.

    Parameters
    ----------
    name : str
        The load's name.
    force : Vector
        The force F⃗.
    at : str
        The point it is applied at.
    """

    name: str
    force: Vector
    at: str


@dataclass(frozen=True, slots=True)
class Torque:
    """A couple C⃗ on ``on`` (a body, or a frame: a massless link).

    Parameters
    ----------
    name : str
        The load's name.
    torque : Vector
        The couple C⃗.
    on : str
        The body or frame it acts on.
    reaction_on : str, optional
        A body or frame on which −C⃗ acts, when given.
    """

    name: str
    torque: Vector
    on: str
    reaction_on: str | None = None


@dataclass(frozen=True, slots=True)
class Spring:
    """A linear spring between two points: tension k(ℓ − ℓ0), potential ½k(ℓ − ℓ0)².

    Parameters
    ----------
    name : str
        The load's name.
    ends : tuple of two str
        The points it joins.
    stiffness : SymEngine expression
        The stiffness k.
    rest_length : SymEngine expression
        The rest length ℓ0.
    """

    name: str
    ends: tuple[str, str]
    stiffness: se.Basic
    rest_length: se.Basic


@dataclass(frozen=True, slots=True)
class Damper:
    """A linear viscous damper between two points: force c ℓ̇ along the line.

    Parameters
    ----------
    name : str
        The load's name.
    ends : tuple of two str
        The points it joins.
    coefficient : SymEngine expression
        The coefficient c.
    """

    name: str
    ends: tuple[str, str]
    coefficient: se.Basic


@dataclass(frozen=True, slots=True)
class Potential:
    """A given potential energy U(q, t) whose efforts are not otherwise described.

    Parameters
    ----------
    name : str
        The load's name.
    energy : SymEngine expression
        U(q, t).
    """

    name: str
    energy: se.Basic


@dataclass(frozen=True, slots=True)
class GeneralizedForce:
    """Given generalized-force components Q_i, coordinate name to expression.

    Parameters
    ----------
    name : str
        The load's name.
    components : tuple of (str, SymEngine expression)
        Each coordinate's name with its component Q_i.
    """

    name: str
    components: tuple[tuple[str, se.Basic], ...]


@dataclass(frozen=True, slots=True)
class Dissipation:
    """A Rayleigh dissipation function D(q, q̇, t): Q_i = −∂D/∂q̇_i (e.g. D = ½ c ẋ²).

    Parameters
    ----------
    name : str
        The load's name.
    function : SymEngine expression
        D(q, q̇, t).
    joints : tuple of str
        The coordinates whose joint the dissipation acts in (a URDF's ``<dynamics damping>``: viscous
        friction in the joint of q_j, so that joint is not perfect); empty when D says nothing of where
        it acts (air drag on a particle, say).
    """

    name: str
    function: se.Basic
    joints: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class JointDamper:
    """Viscous friction at the joint between ``bodies`` (S1, S2): the couple −c Ω(S2/S1) on S2, +c Ω(S2/S1) on S1.

    ``D = ½ c |Ω(S2/S1)|²`` is its dissipation function.

    Parameters
    ----------
    name : str
        The load's name.
    bodies : tuple of two str
        S1 and S2, each a body or a frame.
    coefficient : SymEngine expression
        The coefficient c.
    """

    name: str
    bodies: tuple[str, str]
    coefficient: se.Basic


@dataclass(frozen=True, slots=True)
class CoulombFriction:
    """Dry (Coulomb) friction at a sliding contact point ``at``: ``|T| ≤ f N``, T opposite to the sliding velocity.

    The sliding velocity is v_s = V(at) − ``surface_velocity`` (projected on the tangent plane when
    the surface's unit ``normal`` is given); the friction force is the regularised
    ``T = −f N v_s / √(|v_s|² + ε²)``.  With ε = 0 (a literal zero) it is the exact law
    ``T = −f N v_s/|v_s|``, and `simulate` switches between sliding and sticking by events
    (`lagrangian.numerics._stickslip`); the contact then sticks while the tangential reaction it
    needs stays within f_s N.

    Parameters
    ----------
    name : str
        The load's name.
    at : str
        The contact point.
    coefficient : SymEngine expression
        The friction coefficient f.
    normal_force : SymEngine expression
        The normal force N, given (known from the given forces, e.g. m g cos α).
    surface_velocity : Vector
        The velocity of the surface the point slides on.
    normal : Vector or None
        The surface's unit normal, when given.
    regularization : SymEngine expression
        The regularization ε, a velocity.
    static_coefficient : SymEngine expression, optional
        The static coefficient f_s (≥ f); None: f_s = f.
    """

    name: str
    at: str
    coefficient: se.Basic
    normal_force: se.Basic
    surface_velocity: Vector
    normal: Vector | None
    regularization: se.Basic
    static_coefficient: se.Basic | None = None

    @property
    def exact(self) -> bool:
        """Whether this is the exact (unregularised) law, ε = 0: stick/slip by events in simulation."""
        return bool(self.regularization == 0)


#: Any of the loads a model declares: each is applied by virtual power (Q_i = Σ F·∂V/∂q̇_i), or
#: through a potential U or a dissipation function.
Load = (Gravity | PointForce | Torque | Spring | Damper | Potential | GeneralizedForce | Dissipation | JointDamper
        | CoulombFriction)


#: The kinds of a declared `Shape`, each with its size keys: what the 3-D view and the animation draw.
SHAPE_KINDS = ("sphere", "cylinder", "disk", "box", "rod", "mesh")


@dataclass(frozen=True, slots=True)
class Shape:
    """How a body or particle looks (``[shapes]`` of a model file, URDF ``<visual>``): no part in the dynamics.

    Conventions of each kind, in the shape's own axes: a ``cylinder``, ``disk`` or ``rod`` lies along
    z, centred on its centre; a ``box`` has ``size`` along x, y, z; a ``mesh`` is drawn as its file
    gives it, times ``scale``, its origin at the centre.  Sizes are expressions in the parameters.

    Parameters
    ----------
    on : str
        The body or particle it belongs to, or a frame (a URDF link fixed to the ground).
    kind : str
        ``"sphere"``, ``"cylinder"``, ``"disk"``, ``"box"``, ``"rod"`` or ``"mesh"``.
    frame : str
        The frame the shape is fixed in.
    center : Vector
        Its centre, OP from O.
    rotation : tuple of three tuples of three float, optional
        A constant 3×3 matrix whose columns are the shape's x, y, z in ``frame``'s basis; None: the
        same axes as ``frame``.
    radius : SymEngine expression, optional
        The radius of a sphere, cylinder, disk or rod.
    length : SymEngine expression, optional
        The length of a cylinder or rod (the thickness of a disk).
    size : tuple of three SymEngine expressions, optional
        The sides of a box along x, y, z.
    ends : tuple of two str, optional
        A rod between two points: replaces ``center`` and the axis when given.
    mesh : str, optional
        The mesh file (STL, OBJ or DAE).
    scale : tuple of three float
        The mesh's scale along x, y, z.
    color : str, optional
        Its colour, ``#rrggbb``.
    opacity : float, optional
        Its opacity, in [0, 1].
    location : Location
        Where it was declared.
    """

    on: str
    kind: str
    frame: str
    center: Vector
    rotation: tuple[tuple[float, float, float], ...] | None = None
    radius: se.Basic | None = None
    length: se.Basic | None = None
    size: tuple[se.Basic, se.Basic, se.Basic] | None = None
    ends: tuple[str, str] | None = None
    mesh: str | None = None
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    color: str | None = None
    opacity: float | None = None
    location: Location = field(default=Location(), compare=False)

    def __post_init__(self) -> None:
        if self.kind not in SHAPE_KINDS:
            raise ValueError(f"shape kind must be one of {SHAPE_KINDS}, not {self.kind!r}")


@dataclass(frozen=True, slots=True)
class Reference:
    """The equations are written relative to frame ``frame`` (R) of origin ``origin`` (O') — seed, Remarque 3.

    R's rotation from R0 and the position OO' are prescribed functions of t (checked when the model
    is built); the engine then adds the Coriolis and entrainment inertial forces.

    Parameters
    ----------
    frame : str
        The frame R.
    origin : str
        The point O'.
    """

    frame: str
    origin: str = ORIGIN

    @property
    def is_galilean_frame(self) -> bool:
        """R is R0 itself and O' is O: no inertial force at all."""
        return self.frame == GALILEAN_FRAME and self.origin == ORIGIN


@dataclass(frozen=True, slots=True)
class Model:
    """A validated description of a system (Σ), ready for `lagrangian.derive`.

    Build one with `load_model` (TOML file), `parse_model` (TOML text) or `ModelBuilder` (Python).

    Parameters
    ----------
    name : str
        The model's name.
    description : str
        What it is, in words.
    parameters : tuple of Parameter
        The parameters and the inputs, in declaration order.
    coordinates : tuple of Coordinate
        The principal parameters q_i, in order.
    frames : tuple of Frame
        Starts with R0 and lists every parent before its children.
    points : tuple of Point
        Starts with O.
    bodies : tuple of Body
        The rigid bodies.
    particles : tuple of Particle
        The point masses.
    loads : tuple of Load
        The given efforts.
    source : str, optional
        The file it was read from, when there is one.
    locations : mapping of (str, str) to Location
        Where each declaration (kind, name) was made, for messages.
    reference : Reference, optional
        The frame the equations are written in; None: R0.
    constraints : tuple of Constraint
        Declared constraints, principal or complementary (`lagrangian.model._constraints`).
    operating_point : tuple of (str, SymEngine expression)
        The default point of linearization (``[operating_point]``): coordinate and
        ``<coordinate>_dot`` names to constant expressions in the parameters, in file order.
    independent_speeds : tuple of str
        Independent speeds (``<coordinate>_dot`` names) chosen for the reduction, if given.
    dependent_coordinates : tuple of str
        Dependent coordinates eliminated by the holonomic constraints, if given.
    title : str, optional
        The report's title (``[model] title``, a `Text` when given per language); None: from ``name``.
    controls : tuple of (str, SymEngine expression)
        A control law per declared input (``[controls]``): input name → expression of t, the
        coordinates, their rates and the parameters, in file order (`lagrangian.model._controls`).
    shapes : tuple of Shape
        How bodies and particles look (``[shapes]``, URDF ``<visual>``); what is not given is
        inferred by `lagrangian.view3d` from the inertia and the points.
    """

    name: str
    description: str
    parameters: tuple[Parameter, ...]
    coordinates: tuple[Coordinate, ...]
    frames: tuple[Frame, ...]
    points: tuple[Point, ...]
    bodies: tuple[Body, ...]
    particles: tuple[Particle, ...]
    loads: tuple[Load, ...]
    source: str | None = None
    locations: Mapping[tuple[str, str], Location] = field(default_factory=dict)
    reference: Reference | None = None  # None: the equations are written in R0
    constraints: tuple[Constraint, ...] = ()
    operating_point: tuple[tuple[str, se.Basic], ...] = ()
    independent_speeds: tuple[str, ...] = ()
    dependent_coordinates: tuple[str, ...] = ()
    title: str | None = None
    controls: tuple[tuple[str, se.Basic], ...] = ()
    shapes: tuple[Shape, ...] = ()

    def __post_init__(self) -> None:
        if not self.frames or self.frames[0].name != GALILEAN_FRAME:
            raise ValueError("the first frame of a model must be the Galilean frame R0")
        seen: set[str] = set()
        for frame in self.frames:
            if frame.parent is not None and frame.parent not in seen:
                raise ValueError(f"frame {frame.name!r} is listed before its parent")
            seen.add(frame.name)

    # -- lookups ----------------------------------------------------------------------
    def frame(self, name: str) -> Frame:
        return _find(self.frames, name, "frame")

    def point(self, name: str) -> Point:
        return _find(self.points, name, "point")

    def body(self, name: str) -> Body:
        return _find(self.bodies, name, "body")

    def coordinate(self, name: str) -> Coordinate:
        return _find(self.coordinates, name, "coordinate")

    @property
    def inputs(self) -> tuple[str, ...]:
        """Names of the declared inputs (``[inputs]``), in declaration order."""
        return tuple(p.name for p in self.parameters if p.input)

    @property
    def parameter_values(self) -> dict[str, float | None]:
        return {p.name: p.value for p in self.parameters}

    def where(self, kind: str, name: str) -> Location:
        """Where item ``name`` of ``kind`` (e.g. ``"body"``) was declared, if known.

        Parameters
        ----------
        kind : str
            The kind of declaration: ``"body"``, ``"coordinate"``, ``"load"``...
        name : str
            Its name.

        Returns
        -------
        Location
            Its file and line; the model's file and no line when unknown.
        """
        return self.locations.get((kind, name), Location(self.source, None))


def _find(items: tuple, name: str, kind: str):
    for item in items:
        if item.name == name:
            return item
    raise KeyError(f"no {kind} named {name!r}")
