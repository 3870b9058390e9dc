"""Generalized forces of dissipative efforts: Rayleigh functions, joint dampers, Coulomb friction.

Seed: Q_i(non-conservative) holds "all non-conservative efforts, given and constraint"
(efforts of non-perfect constraints included), each by its virtual power P* = Σ Q_i q_i*:

    Rayleigh function D(q, q̇, t):      Q_i = −∂D/∂q̇_i
    joint damper between S1 and S2:     couple −c Ω(S2/S1) on S2 and +c Ω(S2/S1) on S1, so
                                        Q_i = −c Ω(S2/S1) · ∂Ω(S2/S1)/∂q̇_i = −∂D/∂q̇_i,
                                        D = ½ c |Ω(S2/S1)|²
    Coulomb friction at P:              T = −f N v_s / √(|v_s|² + ε²),  Q_i = T · ∂V(P)/∂q̇_i

For dry friction the sliding velocity v_s is V(P) − V(surface point at P), projected on
the tangent plane when the surface's unit normal n is given: v_s − (v_s·n) n.  The law
|T| ≤ f N with T = −f N v_s/|v_s| when sliding is *regularised*: below the speed ε the
friction grows linearly with v_s (a very stiff viscous law), which makes sticking a slow
creep of speed of order ε·(tangential load)/(f N) instead of an exact rest.  It keeps the
equations smooth ODEs that any integrator takes (stiff for small ε: take ε small against
the sliding speeds of interest but not smaller than needed, or use an implicit method such
as Radau).  N is given by the user from the normal equation when it is known from the given
forces (a block on a plane: N = m g cos α); a normal reaction that must be solved for (a
multiplier of a complementary constraint) is not supported by this load.

With ε = 0 (``regularization = 0``) the law is the exact T = −f N v_s/|v_s|, undefined at
v_s = 0: the derivation writes it as it is, and simulation switches between a sliding model
and a stuck one by events (`lagrangian.numerics._stickslip`).  That needs one sliding
direction, v_s = w e with e a unit axis of one of the model's frames: `sliding_direction`
finds it.

All velocities here are relative to the frame the equations are written in (R0 or R).
"""

from __future__ import annotations

from dataclasses import dataclass

import symengine as se

from .._identity import are_zero
from ..errors import ModelError
from ..kinematics import Kinematics
from ..model import CoulombFriction, Dissipation, JointDamper, Vector
from ..model.vectors import is_structural_zero

__all__ = ["FRICTION_LOADS", "frame_of", "friction_q", "friction_efforts", "sliding_velocity", "friction_force",
           "dissipation_function", "sliding_direction", "SlidingDirection"]

#: The load types whose generalized forces are computed here.
FRICTION_LOADS = (Dissipation, JointDamper, CoulombFriction)


def frame_of(kin: Kinematics, name: str) -> str:
    """The frame of a body, or the frame itself."""
    bodies = {b.name: b.frame for b in kin.model.bodies}
    return bodies.get(name, name)


def _relative_rotation(kin: Kinematics, load: JointDamper) -> tuple[Vector, tuple[Vector, ...]]:
    """Ω(S2/S1) and its partial rates ∂Ω(S2/S1)/∂q̇_i."""
    a, b = (frame_of(kin, n) for n in load.bodies)
    omega = kin.omega(b) - kin.omega(a)
    partials = tuple(wb - wa for wa, wb in zip(kin.partial_omegas(a), kin.partial_omegas(b), strict=True))
    return omega, partials


def sliding_velocity(kin: Kinematics, load: CoulombFriction) -> Vector:
    """v_s = V(P) − V_surface, projected on the tangent plane when the normal is given."""
    v = kin.velocity(load.at) - load.surface_velocity
    if load.normal is not None:
        v = v - load.normal * kin.frames.dot(v, load.normal)
    return v


@dataclass(frozen=True, slots=True)
class SlidingDirection:
    """The sliding velocity v_s = w e at a contact with one sliding direction.

    Parameters
    ----------
    frame : str
        The frame of e = ``frame``.``axis``.
    axis : str
        Its axis.
    speed : SymEngine expression
        The sliding speed w = v_s·e (affine in q̇).
    """

    frame: str
    axis: str
    speed: se.Basic

    @property
    def vector(self) -> Vector:
        """The unit vector e."""
        return Vector.basis(self.frame, self.axis)

    @property
    def label(self) -> str:
        """E.g. ``"I.x"``."""
        return f"{self.frame}.{self.axis}"


def sliding_direction(kin: Kinematics, load: CoulombFriction) -> SlidingDirection:
    """The axis e of a frame along which v_s always lies, and w = v_s·e.

    The frames are tried in the model's order (R0 first); the first one in which two of
    v_s's three components vanish identically gives e.  A contact whose v_s turns in every
    frame (a puck sliding freely on a plane) has no such axis.

    Parameters
    ----------
    kin : Kinematics
        The model's kinematics.
    load : CoulombFriction
        The friction load.

    Returns
    -------
    SlidingDirection
        The axis and the speed.

    Raises
    ------
    ModelError
        When v_s is identically zero, or has no fixed direction in any frame.
    """
    v = sliding_velocity(kin, load)
    for frame in kin.frames.frames:
        comps = [se.expand(c) for c in kin.frames.express(v, frame)]
        live = [k for k, zero in enumerate(are_zero(comps)) if not zero]
        if not live:
            raise ModelError(f"The sliding velocity of the Coulomb contact `{load.name}` at `{load.at}` is "
                             "identically zero, so it never slides.",
                             fix="check the point, the surface velocity and the normal, or remove the load")
        if len(live) == 1:
            return SlidingDirection(frame, "xyz"[live[0]], comps[live[0]])
    raise ModelError(f"The sliding velocity of the Coulomb contact `{load.name}` at `{load.at}` has no fixed "
                     "direction in any frame of the model; the exact stick/slip law (regularization = 0) "
                     "handles one sliding direction only.",
                     fix="use the regularised law (give regularization a positive speed, e.g. 1e-3), or add a "
                         "frame one of whose axes carries the sliding velocity")


def friction_force(kin: Kinematics, load: CoulombFriction) -> Vector:
    """T = −f N v_s / √(|v_s|² + ε²), the regularised Coulomb force at the contact point (exact for ε = 0)."""
    v = sliding_velocity(kin, load)
    speed2 = kin.frames.dot(v, v)
    return v * (-load.coefficient * load.normal_force / se.sqrt(speed2 + load.regularization ** 2))


def friction_q(kin: Kinematics, load: Dissipation | JointDamper | CoulombFriction
               ) -> tuple[tuple[se.Basic, ...], None, str]:
    """(Q, no potential, note) of one dissipative load (see the module docstring)."""
    if isinstance(load, Dissipation):
        return tuple(-load.function.diff(qd) for qd in kin.qd), None, "Q_i = −∂D/∂q̇_i (Rayleigh dissipation function)"
    if isinstance(load, JointDamper):
        omega, partials = _relative_rotation(kin, load)
        couple = omega * (-load.coefficient)
        Q = tuple(kin.frames.dot(couple, w) for w in partials)
        s1, s2 = load.bodies
        return Q, None, (f"couple −c Ω({s2}/{s1}) on {s2}, +c Ω({s2}/{s1}) on {s1}; "
                         f"Q_i = −∂D/∂q̇_i with D = ½ c |Ω({s2}/{s1})|²")
    force = friction_force(kin, load)
    Q = tuple(kin.frames.dot(force, v) for v in kin.partial_velocities(load.at))
    if load.exact:
        return Q, None, (f"Coulomb friction at {load.at}: T = −f N v_s/‖v_s‖ (exact; sticking handled by the "
                         "simulation with |T| ≤ f_s N), N given")
    return Q, None, (f"Coulomb friction at {load.at}: T = −f N v_s/√(|v_s|² + ε²), |T| ≤ f N, "
                     "N given (regularised stick/slip)")


def dissipation_function(kin: Kinematics, load: JointDamper) -> se.Basic:
    """D = ½ c |Ω(S2/S1)|² of a joint damper."""
    omega, _ = _relative_rotation(kin, load)
    return load.coefficient * kin.frames.dot(omega, omega) / 2


def friction_efforts(kin: Kinematics, load: Dissipation | JointDamper | CoulombFriction
                     ) -> list[tuple[str, Vector, str]] | None:
    """The load as forces and couples, for the Newton–Euler check.

    Parameters
    ----------
    kin : Kinematics
        The model's kinematics.
    load : Dissipation or JointDamper or CoulombFriction
        The load.

    Returns
    -------
    list of tuple or None
        ``("force", F, point)`` and ``("couple", C, body or frame)`` items; None when it has no force
        form (a Rayleigh function).
    """
    if isinstance(load, Dissipation):
        return None
    if isinstance(load, JointDamper):
        omega, _ = _relative_rotation(kin, load)
        s1, s2 = load.bodies
        couple = omega * (-load.coefficient)
        return [("couple", couple, s2), ("couple", -couple, s1)]
    force = friction_force(kin, load)
    return [] if all(is_structural_zero(c) for _, comps in force for c in comps) else [("force", force, load.at)]

