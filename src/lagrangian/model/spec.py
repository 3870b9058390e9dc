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

    ``keys`` optionally records, for the declaration's keys (``"mass"``, ``"inertia"``,
    ...), the line of each and the 1-based column where its text value starts (0 when
    unknown), so that an error can point at the offending key rather than the table.
    It plays no part in comparisons.
    """

    file: str | None = None
    line: int | None = None
    keys: tuple[tuple[str, int, int], ...] = field(default=(), compare=False, repr=False)

    def of(self, key: str | None) -> Location:
        """The location of ``key`` of this declaration (this location when unknown)."""
        for name, line, _ in self.keys:
            if name == key:
                return Location(self.file, line)
        return Location(self.file, self.line)

    def value_column(self, key: str | None) -> int | None:
        """The column where the text value of ``key`` starts in the file, when known."""
        for name, _, column in self.keys:
            if name == key:
                return column or None
        return None


@dataclass(frozen=True, slots=True)
class Parameter:
    """A constant of the problem (mass, length, inertia...), with an optional value.

    ``input`` marks a declared input u (``[inputs]``): a symbol used like a parameter,
    typically the magnitude of a load (a motor torque), whose value is 0 (the input off)
    unless given; linearization makes it a column of B.
    """

    name: str
    value: float | None = None
    unit: str | None = None
    description: str | None = None
    input: bool = False
    #: A declared sign assumption: ``"positive"``, ``"nonnegative"``, ``"negative"``, ``"nonpositive"``
    #: or None (`lagrangian.model._assumptions`): the derivation may simplify with it, and a value
    #: that breaks it is refused.
    sign: str | None = None

    @property
    def symbol(self) -> se.Symbol:
        return se.Symbol(self.name)


@dataclass(frozen=True, slots=True)
class Coordinate:
    """A principal parameter q_i ("paramètre principal"), with q_i(0), q̇_i(0).

    ``momentum`` names the first integral ∂T/∂q̇_i = cste when q_i turns out to be
    cyclic (the seed calls those of ψ and φ ``K`` and ``H``).
    """

    name: str
    initial: float | None = None
    rate: float | None = None
    momentum: str | None = None
    unit: str | None = None
    description: str | None = None
    #: The declared range [lower, upper] of q_i (constant expressions in the parameters; None for
    #: an open side), or None: the derivation may simplify with it (``|x + L| = x + L`` when
    #: x ≥ −L), and `simulate` warns when a motion leaves it (`lagrangian.model._assumptions`).
    range: tuple[se.Basic | None, se.Basic | None] | None = None

    @property
    def symbol(self) -> se.Symbol:
        return se.Symbol(self.name)

    @property
    def rate_symbol(self) -> se.Symbol:
        """q̇_i, spelled ``<name>_dot`` in expressions and in JSON."""
        return se.Symbol(self.name + "_dot")

    @property
    def acceleration_symbol(self) -> se.Symbol:
        """q̈_i, spelled ``<name>_ddot``."""
        return se.Symbol(self.name + "_ddot")


#: The axis letter of a rotation about a constant unit vector n (`Rotation.direction`).
GENERAL_AXIS = "n"


@dataclass(frozen=True, slots=True)
class Rotation:
    """A rotation of ``angle`` about the parent frame's ``axis`` (x, y or z), or about a constant axis n.

    The child frame shares that axis with its parent, as in R0 →(ψ, z0)→ R1.  With
    ``axis = "n"`` the axis is the constant unit vector ``direction`` = (n_x, n_y, n_z),
    its components in the parent's basis — which are also its components in the child's,
    the axis being common to both (the Earth turning about cos λ y0 + sin λ z0).  The
    change of basis is then Rodrigues' formula, v ↦ cos α v + sin α n ∧ v + (1 − cos α)(n·v) n.
    ``normalized`` records that the engine divided the given vector by its norm.
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

    The Galilean frame R0 has no parent and no rotation.  A rotation sequence in a
    model file becomes a chain of frames whose intermediate names start with ``_``.
    """

    name: str
    parent: str | None
    rotation: Rotation | None
    axes: tuple[str, str, str]


@dataclass(frozen=True, slots=True)
class Point:
    """A named point P with its position vector OP from the origin O of R0."""

    name: str
    position: Vector


@dataclass(frozen=True, slots=True)
class Inertia:
    """Inertia matrix Π_P of a body at point ``at``, in the basis of ``frame``.

    ``matrix[k][l]`` is the (k, l) entry of the operator, i.e. diagonal entries are
    the moments of inertia and off-diagonal entries are minus the products of inertia.
    ``at`` is a point name, or ``"G"`` for the centre of mass.
    """

    at: str
    frame: str
    matrix: tuple[tuple[se.Basic, se.Basic, se.Basic], ...]


@dataclass(frozen=True, slots=True)
class Body:
    """A rigid body S attached to ``frame``, with mass m, centre of mass G (OG) and inertia.

    ``mass_given`` is False for a body whose G is fixed and whose mass the model leaves out
    (a pulley on a fixed axle): ``mass`` is then 0, exact for everything the Lagrange
    equations use — T = ½ Ω·Π_G·Ω and m g·∂OG/∂q_i = 0 whatever m — while the reactions,
    which need it, refuse to be computed (`lagrangian.analysis.reactions`).

    ``free`` marks a body declared free (six degrees of freedom: three translations of its
    frame's origin along R0's axes and three Euler angles, checked by `lagrangian.model._free`):
    the equations keep those coordinates, and `simulate` integrates its orientation as a unit
    quaternion, which has no singular configuration (`lagrangian.numerics._free_simulate`).
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
    """A point mass m at position OP."""

    name: str
    mass: se.Basic
    position: Vector


# -- loads ("efforts donnés") -------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class Gravity:
    """Uniform gravity g⃗ acting on ``on`` (body and particle names; all when empty)."""

    name: str
    field: Vector
    on: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class PointForce:
    """A force F⃗ applied at point ``at``; it may depend on q, q̇ and t."""

    name: str
    force: Vector
    at: str


@dataclass(frozen=True, slots=True)
class Torque:
    """A couple C⃗ on ``on`` (a body, or a frame: a massless link); with ``reaction_on``, −C⃗ acts on that body or frame."""

    name: str
    torque: Vector
    on: str
    reaction_on: str | None = None


@dataclass(frozen=True, slots=True)
class Spring:
    """A linear spring between two points: tension k(ℓ − ℓ0), potential ½k(ℓ − ℓ0)²."""

    name: str
    ends: tuple[str, str]
    stiffness: se.Basic
    rest_length: se.Basic


@dataclass(frozen=True, slots=True)
class Damper:
    """A linear viscous damper between two points: force c ℓ̇ along the line."""

    name: str
    ends: tuple[str, str]
    coefficient: se.Basic


@dataclass(frozen=True, slots=True)
class Potential:
    """A given potential energy U(q, t) whose efforts are not otherwise described."""

    name: str
    energy: se.Basic


@dataclass(frozen=True, slots=True)
class GeneralizedForce:
    """Given generalized-force components Q_i, coordinate name to expression."""

    name: str
    components: tuple[tuple[str, se.Basic], ...]


@dataclass(frozen=True, slots=True)
class Dissipation:
    """A Rayleigh dissipation function D(q, q̇, t): Q_i = −∂D/∂q̇_i (e.g. D = ½ c ẋ²).

    ``joints`` names the coordinates whose joint the dissipation acts in (a URDF's ``<dynamics
    damping>``: viscous friction in the joint of q_j, so that joint is not perfect); empty when D says
    nothing of where it acts (air drag on a particle, say).
    """

    name: str
    function: se.Basic
    joints: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class JointDamper:
    """Viscous friction at the joint between ``bodies`` (S1, S2): the couple −c Ω(S2/S1) on S2, +c Ω(S2/S1) on S1.

    Each of S1, S2 is a body or a frame; ``D = ½ c |Ω(S2/S1)|²`` is its dissipation function.
    """

    name: str
    bodies: tuple[str, str]
    coefficient: se.Basic


@dataclass(frozen=True, slots=True)
class CoulombFriction:
    """Dry (Coulomb) friction at a sliding contact point ``at``: ``|T| ≤ f N``, T opposite to the sliding velocity.

    The sliding velocity is v_s = V(at) − ``surface_velocity`` (projected on the tangent
    plane when the surface's unit ``normal`` is given); the friction force is the
    regularised ``T = −f N v_s / √(|v_s|² + ε²)``, ε = ``regularization`` (a velocity).  With
    ε = 0 (a literal zero) it is the exact law ``T = −f N v_s/|v_s|``, and `simulate` switches
    between sliding and sticking by events (`lagrangian.numerics._stickslip`); the contact
    then sticks while the tangential reaction it needs stays within f_s N,
    f_s = ``static_coefficient`` (≥ f; None: f_s = f).
    ``normal_force`` N is given (known from the given forces, e.g. m g cos α).
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

    The shape is fixed in ``frame``; its own axes are that frame's turned by ``rotation`` (a
    constant 3×3 matrix whose columns are the shape's x, y, z in ``frame``'s basis; None: the
    same axes) and its centre is at ``center`` (OP, from O).  Conventions of each kind, in the
    shape's own axes: a ``cylinder``, ``disk`` or ``rod`` lies along z, centred on its centre;
    a ``box`` has ``size`` along x, y, z; a ``mesh`` is drawn as its file gives it, times
    ``scale``, its origin at the centre.  ``ends`` (a rod between two points) replaces
    ``center`` and the axis when given.  ``on`` is the body or particle it belongs to, or a
    frame (a URDF link fixed to the ground).  Sizes are expressions in the parameters.
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

    R's rotation from R0 and the position OO' are prescribed functions of t (checked when
    the model is built); the engine then adds the Coriolis and entrainment inertial forces.
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

    Build one with `load_model` (TOML file), `parse_model` (TOML text) or
    `ModelBuilder` (Python).  ``frames`` starts with R0 and lists every parent before
    its children; ``points`` starts with O.
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
    #: Declared constraints, principal or complementary (`lagrangian.model._constraints`).
    constraints: tuple[Constraint, ...] = ()
    #: The default point of linearization (``[operating_point]``): coordinate and
    #: ``<coordinate>_dot`` names to constant expressions in the parameters, in file order.
    operating_point: tuple[tuple[str, se.Basic], ...] = ()
    #: Independent speeds (``<coordinate>_dot`` names) chosen for the reduction, if given.
    independent_speeds: tuple[str, ...] = ()
    #: Dependent coordinates eliminated by the holonomic constraints, if given.
    dependent_coordinates: tuple[str, ...] = ()
    #: The report's title (``[model] title``, a `Text` when given per language); None: from ``name``.
    title: str | None = None
    #: A control law per declared input (``[controls]``): input name → expression of t, the
    #: coordinates, their rates and the parameters, in file order (`lagrangian.model._controls`).
    controls: tuple[tuple[str, se.Basic], ...] = ()
    #: How bodies and particles look (``[shapes]``, URDF ``<visual>``); what is not given is inferred
    #: by `lagrangian.view3d` from the inertia and the points.
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
        """Where item ``name`` of ``kind`` (e.g. ``"body"``) was declared, if known."""
        return self.locations.get((kind, name), Location(self.source, None))


def _find(items: tuple, name: str, kind: str):
    for item in items:
        if item.name == name:
            return item
    raise KeyError(f"no {kind} named {name!r}")
