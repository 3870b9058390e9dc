"""Free bodies: a rigid body with six degrees of freedom, written in the course's coordinates.

A body declared ``free = true`` moves without any constraint.  Its configuration is given
the way the course writes it: the position of its frame's origin, x R0.x + y R0.y + z R0.z
(three coordinates), and the orientation of its frame by three elementary rotations about
the axes of the previous frame (three Euler angles: ψ, θ, φ about z, x, z in the course;
yaw, pitch, roll about z, y, x for a robot's base).  The Lagrange equations, the first
integrals and the report keep those coordinates.

Any such set of three angles is singular somewhere (θ = 0 for z-x-z, where ψ and φ turn about
the same axis and M loses rank); a tumbling body goes through it.  `simulate` therefore
integrates a free body's orientation as a unit quaternion and its angular velocity in the
body's basis (`lagrangian.numerics._free_simulate`), and converts back to the angles where
they are regular.  This module checks the declaration (`check_free_bodies`, called when a
model is built) and describes each free body for the numerics (`free_joints`).

Reference: the course (SMP5, ch. IV, Euler angles); H. Goldstein, *Classical Mechanics*,
§4.4–4.6 (Euler angles and their singularity); J. Diebel, *Representing attitude: Euler
angles, unit quaternions, and rotation vectors* (2006), for the conversions.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import symengine as se

from ..errors import ModelError
from .spec import GALILEAN_FRAME, Body, Frame, Model

__all__ = ["FreeJoint", "check_free_bodies", "free_joints", "inertia_problem"]

#: A principal moment below this fraction of the largest one is zero: no inertia about that axis.
_ZERO_MOMENT = 1e-12


@dataclass(frozen=True, slots=True)
class FreeJoint:
    """One free body's six coordinates.

    Parameters
    ----------
    body : str
        The body's name.
    frames : tuple of three str
        The three frames of its orientation, from R0's child to the body's own frame.
    translation : tuple of three str
        The coordinates x, y, z of its frame's origin along R0's x, y, z.
    angles : tuple of three str
        The three Euler angles, in the order of the rotations.
    sequence : str
        The axes of the three rotations, each about the previous frame's axis (``"zxz"``).
    """

    body: str
    frames: tuple[str, str, str]
    translation: tuple[str, str, str]
    angles: tuple[str, str, str]
    sequence: str

    @property
    def frame(self) -> str:
        """The body's frame (the last of `frames`)."""
        return self.frames[2]

    @property
    def proper(self) -> bool:
        """Proper Euler angles (first and last axes alike, z-x-z): singular where the middle angle is 0 or π.

        Otherwise (z-y-x, Cardan or Tait–Bryan angles) singular where it is ±π/2.
        """
        return self.sequence[0] == self.sequence[2]

    @property
    def coordinates(self) -> tuple[str, ...]:
        """The six coordinate names: translation, then angles."""
        return (*self.translation, *self.angles)


def _fail(model: Model, body: Body, message: str, fix: str, key: str | None = "free") -> ModelError:
    where = model.where("body", body.name).of(key)
    return ModelError(message, fix=fix, file=where.file, line=where.line, symbol=body.name)


_FIX_FRAMES = ('give the body a frame turned from R0 by three Euler angles, each a coordinate: R = { from = "R0", '
               'rotation = [["psi", "z"], ["theta", "x"], ["phi", "z"]] }')
_FIX_CENTER = ('place the body with three coordinates along R0\'s axes, e.g. center = "x*R0.x + y*R0.y + z*R0.z" '
               '(plus a constant offset in the body\'s frame when G is not its origin)')


def free_joint(model: Model, body: Body) -> FreeJoint:
    """The `FreeJoint` of ``body`` (declared free), or a `ModelError` saying what does not fit."""
    coordinates = {c.symbol: c.name for c in model.coordinates}
    if not body.mass_given:
        raise _fail(model, body, f"body `{body.name}` is declared free but has no `mass`: a free body's mass "
                    "enters its translation", f'give it its mass, e.g. mass = "m" under [bodies.{body.name}]')
    if body.fixed_point is not None:
        raise _fail(model, body, f"body `{body.name}` is declared free and has the fixed point "
                    f"`{body.fixed_point}`: a free body has none", "remove `fixed_point`, or `free`", "fixed_point")
    chain: list[Frame] = []
    frame = model.frame(body.frame)
    while frame.parent is not None and len(chain) < 4:
        chain.append(frame)
        frame = model.frame(frame.parent)
    chain.reverse()
    if len(chain) != 3 or chain[0].parent != GALILEAN_FRAME:
        raise _fail(model, body, f"body `{body.name}` is declared free, but its frame `{body.frame}` is "
                    f"{len(chain)} rotation{'s' * (len(chain) != 1)} from R0 (through "
                    + " → ".join(["R0", *(f.name for f in chain)]) + "): a free body's frame turns from R0 by "
                    "exactly three Euler angles", _FIX_FRAMES)
    angles, axes = [], ""
    for f in chain:
        rotation = f.rotation
        name = coordinates.get(rotation.angle) if rotation is not None else None
        if rotation is None or not rotation.elementary or name is None:
            what = ("a rotation about a general axis" if rotation is not None and not rotation.elementary else
                    f"the angle `{rotation.angle}`" if rotation is not None else "no rotation")
            raise _fail(model, body, f"body `{body.name}` is declared free, but frame `{f.name}` of its orientation "
                        f"has {what}: each of the three rotations of a free body is a coordinate about an axis "
                        "x, y or z of the previous frame", _FIX_FRAMES)
        if axes and axes[-1] == rotation.axis:
            raise _fail(model, body, f"body `{body.name}` is declared free, but two successive rotations of its "
                        f"frame turn about the same axis `{rotation.axis}`: the three angles would describe only "
                        "two independent rotations", _FIX_FRAMES)
        angles.append(name)
        axes += rotation.axis
    pieces = dict(body.center.pieces)
    stray = [f for f in pieces if f not in (GALILEAN_FRAME, chain[2].name)
             and any(c != 0 for c in pieces[f])]
    if stray:
        raise _fail(model, body, f"body `{body.name}` is declared free, but its centre of mass has a part written "
                    f"in frame `{stray[0]}`: the origin of a free body's frame moves along R0's axes, and G sits "
                    "at a constant place in the body's frame", _FIX_CENTER, "center")
    translation = []
    for axis, component in zip("xyz", pieces.get(GALILEAN_FRAME, (se.Integer(0),) * 3), strict=True):
        name = coordinates.get(component)
        if name is None:
            raise _fail(model, body, f"body `{body.name}` is declared free, but the {axis} component of its position "
                        f"along R0 is `{component}`, not a coordinate of its own", _FIX_CENTER, "center")
        translation.append(name)
    own = pieces.get(chain[2].name, ())
    moving = sorted({str(s) for c in own for s in c.free_symbols} & set(coordinates.values()) | (
        {"t"} if any(se.Symbol("t") in c.free_symbols for c in own) else set()))
    if moving:
        raise _fail(model, body, f"body `{body.name}` is declared free, but its centre of mass moves in its own frame "
                    f"(with `{moving[0]}`)", _FIX_CENTER, "center")
    six = [*translation, *angles]
    repeated = sorted({c for c in six if six.count(c) > 1})
    if repeated:
        raise _fail(model, body, f"body `{body.name}` is declared free, but coordinate `{repeated[0]}` serves twice "
                    "among its six: a free body needs six coordinates of its own", _FIX_CENTER)
    return FreeJoint(body.name, (chain[0].name, chain[1].name, chain[2].name), tuple(translation),  # type: ignore[arg-type]
                     tuple(angles), axes)  # type: ignore[arg-type]


def free_joints(model: Model) -> tuple[FreeJoint, ...]:
    """The `FreeJoint` of every body declared free, in declaration order (checked).

    Parameters
    ----------
    model : Model
        A checked model.

    Returns
    -------
    tuple of FreeJoint
        One per free body.
    """
    return tuple(free_joint(model, b) for b in model.bodies if b.free)


def inertia_problem(mass: float, inertia: np.ndarray) -> str | None:
    """Why a free body with this mass and inertia at G (3×3) cannot move freely, or None.

    A free body translates and turns about every axis: its mass and each principal moment of
    inertia at G must be positive, else a row of its Newton–Euler equations reads 0 = 0 and its
    acceleration (or ω̇ about that axis) is not defined.

    Parameters
    ----------
    mass : float
        The body's mass.
    inertia : ndarray of shape (3, 3)
        Its inertia matrix at G.

    Returns
    -------
    str or None
        The reason, or None when the body can move freely.
    """
    if not (np.isfinite(mass) and mass > 0):
        return f"its mass is {mass:g}"
    moments = np.linalg.eigvalsh((inertia + inertia.T) / 2)
    top = float(np.max(np.abs(moments)))
    if not (np.all(np.isfinite(moments)) and top > 0):
        return "its inertia at G is zero"
    if moments[0] <= _ZERO_MOMENT * top:
        return (f"its principal moments of inertia at G are {', '.join(f'{m:.6g}' for m in moments)}: the one about "
                "some axis is zero (a thin rod or a point), so its rotation about that axis has no inertia")
    return None


def _values(model: Model, overrides: Mapping[str, float] | None = None) -> dict[se.Basic, float]:
    values = {p.symbol: p.value for p in model.parameters if p.value is not None}
    values.update({se.Symbol(k): float(v) for k, v in (overrides or {}).items()})
    return values


def numeric_inertia(model: Model, body: Body, overrides: Mapping[str, float] | None = None
                    ) -> tuple[float, np.ndarray] | None:
    """(m, Π_G in the body's basis) at the parameters' values, or None when a value is missing.

    Only for an inertia given at G in the body's own frame (what a free body's check needs
    before any kinematics; the numerics check the general case on the tree's Π_G).
    """
    inertia = body.inertia
    if inertia.at != "G" or inertia.frame != body.frame:
        return None
    values = _values(model, overrides)
    try:
        mass = float(body.mass.subs(values))
        matrix = np.array([[float(x.subs(values)) for x in row] for row in inertia.matrix])
    except (RuntimeError, TypeError, ValueError):
        return None  # a parameter without a value: checked at run time, with the values given then
    return mass, matrix


def check_free_bodies(model: Model) -> None:
    """Check every body declared free (`free_joint`) and, where the values are known, its mass and inertia."""
    for body in model.bodies:
        if not body.free:
            continue
        free_joint(model, body)
        numbers = numeric_inertia(model, body)
        problem = inertia_problem(*numbers) if numbers is not None else None
        if problem:
            raise _fail(model, body, f"body `{body.name}` is declared free, and {problem}: a free body translates "
                        "and turns about every axis, so its mass and each principal moment of inertia at G must be "
                        "positive", "give the body its mass and inertia (a point mass is a particle, not a free body)",
                        "inertia")
