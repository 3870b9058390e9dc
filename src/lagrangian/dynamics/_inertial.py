"""Equations written in a non-Galilean frame R(O'): kinematics relative to R and the inertial forces.

Seed, Remarque 3.  Relative to R, moving with respect to the Galilean R0, the Lagrange
equations use T(Σ/R), and every solid (S_j) bears, besides the given efforts, the
inertial force densities

    Coriolis:      f_c = −2 Ω(R/R0) ∧ V(P/R) dm
    entrainment:   f_e = −[γ(O'/R0) + dΩ(R/R0)/dt ∧ O'P + Ω(R/R0) ∧ (Ω(R/R0) ∧ O'P)] dm

whose generalized forces come, as for any effort, from their virtual power
Q_i = ∫ f · ∂V(P/R)/∂q̇_i.  For a rigid body S (mass m, centre G, Π_G, ω = Ω(S/R)),
writing P = G + r and using ∫ r dm = 0, ∫ r ∧ (w ∧ r) dm = Π_G w, the densities integrate
to torsors at G (Ω = Ω(R/R0)):

    Coriolis:     F = −2 m Ω ∧ V(G/R),     M_G = 2 (Π_G Ω) ∧ ω − tr(Π_G) Ω ∧ ω
    entrainment:  F = −m [γ(O'/R0) + Ω̇ ∧ O'G + Ω ∧ (Ω ∧ O'G)],   M_G = −Π_G Ω̇ − Ω ∧ (Π_G Ω)

and Q_i = F · ∂V(G/R)/∂q̇_i + M_G · ∂ω/∂q̇_i.  The Coriolis torsor has zero real power
(F·V(G) + M_G·ω = 0: f_c ⊥ V(P/R)) but not zero virtual power, V*(P) not being
collinear with V(P/R).  When Ω is constant, the entrainment efforts derive from

    U_e = Σ [ m γ(O'/R0)·O'G − ½ m |Ω ∧ O'G|² − ½ Ω·Π_G Ω ]   (= −½ Ω² I_Δ, rotation about Δ ∋ O')

which is proposed and then checked (Q_i ≡ −∂U_e/∂q_i) like every potential.

The kinematics relative to R is the engine's `Kinematics` with two changes: Ω(F/R) =
Ω(F/R0) − Ω(R/R0) in place of Ω(F/R0) (so every derivative is taken in R), and positions
measured from O'.  Orientations are unchanged, so T, M q̈ = F and the given efforts
computed from it are those of the course "par rapport à R".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import symengine as se

from .._identity import are_zero
from ..kinematics import FrameTree, Kinematics, TimeDerivative, rotation_rate
from ..model import INERTIAL_LOAD_NAMES, Model, Point, Vector
from ..model.vectors import is_structural_zero, sum_of
from ._energy import rigid_inertia
from ._forces import LoadForces, _derives_from

if TYPE_CHECKING:  # pragma: no cover
    from ._lagrange import EquationsOfMotion

__all__ = ["RelativeFrameTree", "RelativeKinematics", "InertialTorsor", "reference_kinematics",
           "inertial_torsors", "inertial_forces", "rotating_frame"]

CORIOLIS, ENTRAINMENT = INERTIAL_LOAD_NAMES
Components = tuple[se.Basic, se.Basic, se.Basic]


# -- kinematics relative to R ----------------------------------------------------------------------
class RelativeFrameTree(FrameTree):
    """The frame tree seen from R: Ω(F/R) in place of Ω(F/R0), orientations unchanged.

    ``absolute`` is the tree seen from R0, which gives the motion of R itself.  A frame
    below R turns relative to R by the rotations between them; any other frame by
    Ω(F/R0) − Ω(R/R0) (composition of rotation rates).
    """

    def __init__(self, model: Model, d_dt: TimeDerivative, reference: str) -> None:
        super().__init__(model, d_dt)
        self.reference = reference
        self.absolute = FrameTree(model, d_dt)
        below = {reference}
        for f in model.frames:  # parents come first
            if f.parent in below:
                below.add(f.name)
        self._below = below

    def omega(self, frame: str) -> Vector:
        """Ω(frame/R), one piece per rotation between R and the frame."""
        if frame not in self._omega:
            f = self.frames[frame]
            if frame == self.reference:
                value = Vector.zero()
            elif frame in self._below:
                rot = f.rotation
                if rot is None:  # a frame below R turns relative to its parent
                    raise ValueError(f"frame `{frame}` has no rotation")
                own = Vector._trusted({frame: rotation_rate(rot, self.d_dt(rot.angle, accelerations=False))})
                parent = self.omega(f.parent)  # type: ignore[arg-type]
                value = own if parent.is_zero() else parent + own
            else:
                value = self.absolute.omega(frame) - self.absolute.omega(self.reference)
            self._omega[frame] = value
        return self._omega[frame]


class RelativeKinematics(Kinematics):
    """`Kinematics` relative to the model's reference frame R(O') instead of R0.

    Every name keeps its meaning with R for R0: ``velocity(P)`` is V(P/R) = d O'P/dt|_R,
    ``omega(F)`` is Ω(F/R), ``position(P)`` is O'P.  The motion of R relative to R0 is in
    ``frame_omega`` Ω(R/R0), ``frame_omega_rate`` dΩ(R/R0)/dt and ``origin_acceleration``
    γ(O'/R0), all functions of t only.

    Parameters
    ----------
    model : Model
        A model with a reference frame.
    """

    frames: RelativeFrameTree

    def __init__(self, model: Model) -> None:
        if model.reference is None:
            raise ValueError("RelativeKinematics needs a model with a reference frame")
        super().__init__(model)
        self.reference = model.reference
        self.frames = RelativeFrameTree(model, self.d_dt, model.reference.frame)
        absolute = self.frames.absolute
        origin = self._points[model.reference.origin].position  # OO'
        if not origin.is_zero():
            self._points = {name: Point(name, p.position - origin) for name, p in self._points.items()}
        self.frame_omega = absolute.omega(model.reference.frame)
        self.frame_omega_rate = absolute.derivative(self.frame_omega)
        self.origin_acceleration = absolute.derivative(absolute.derivative(origin))

    def is_fixed(self, point: str) -> bool:
        """True when V(P/R) is identically zero.

        Parameters
        ----------
        point : str
            A point, body or particle name.

        Returns
        -------
        bool
            Whether the point is fixed in R.
        """
        return point == self.reference.origin or all(
            se.expand(c) == 0 for comps in self.velocity(point).pieces.values() for c in comps)


def rotating_frame(eom: EquationsOfMotion) -> bool:
    """Whether the equations of ``eom`` are written in a frame R that turns relative to R0 (Ω(R/R0) ≠ 0).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.

    Returns
    -------
    bool
        True when R turns.
    """
    kin = eom.kinematics
    return isinstance(kin, RelativeKinematics) and not kin.frame_omega.is_zero()


def reference_kinematics(model: Model) -> Kinematics:
    """The kinematics the equations are written in: relative to R0, or to the model's reference frame."""
    if model.reference is None or model.reference.is_galilean_frame:
        return Kinematics(model)
    return RelativeKinematics(model)


# -- the inertial torsors -------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class InertialTorsor:
    """The Coriolis or entrainment inertial efforts on one element, reduced at its centre of mass G.

    ``force`` is the resultant (applied at G, or at the particle), ``moment`` the moment at G
    (zero for a particle); ``element`` is the body or particle name.
    """

    load: str
    element: str
    force: Vector
    moment: Vector


def _matvec(pi: tuple[tuple[se.Basic, ...], ...], w: Components) -> Components:
    return tuple(sum_of([pi[k][m] * w[m] for m in range(3)
                         if not is_structural_zero(pi[k][m]) and not is_structural_zero(w[m])])
                 for k in range(3))


def _cross(a: Components, b: Components) -> Components:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a: Components, b: Components) -> se.Basic:
    return sum_of([x * y for x, y in zip(a, b, strict=True) if not is_structural_zero(x) and not is_structural_zero(y)])


def _point_forces(kin: RelativeKinematics, point: str, mass: se.Basic) -> tuple[Vector, Vector]:
    """(Coriolis, entrainment) resultants on the mass ``mass`` at ``point``."""
    frames = kin.frames
    w, w_rate, a = kin.frame_omega, kin.frame_omega_rate, kin.origin_acceleration
    r = kin.position(point)  # O'P
    coriolis = frames.cross(w, kin.velocity(point)) * (-2 * mass)
    density = a + frames.cross(w_rate, r) + frames.cross(w, frames.cross(w, r))
    return coriolis, density * (-mass)


def inertial_torsors(kin: RelativeKinematics) -> tuple[InertialTorsor, ...]:
    """The Coriolis and entrainment torsors of every body and particle (see the module docstring).

    Parameters
    ----------
    kin : RelativeKinematics
        The kinematics relative to R.

    Returns
    -------
    tuple of InertialTorsor
        One per body and particle.
    """
    out = []
    for body in kin.model.bodies:
        _, pi = rigid_inertia(kin, body)  # Π_G in the basis of body.inertia.frame
        F = body.inertia.frame
        w = kin.frames.express(kin.frame_omega, F)
        w_rate = kin.frames.express(kin.frame_omega_rate, F)
        omega = kin.frames.omega_in(body.frame, F)  # Ω(S/R)
        trace = pi[0][0] + pi[1][1] + pi[2][2]
        pi_w = _matvec(pi, w)
        m_cor = tuple(2 * x - trace * y for x, y in zip(_cross(pi_w, omega), _cross(w, omega), strict=True))
        m_ent = tuple(-x - y for x, y in zip(_matvec(pi, w_rate), _cross(w, pi_w), strict=True))
        coriolis, entrainment = _point_forces(kin, body.name, body.mass)
        out.append(InertialTorsor(CORIOLIS, body.name, coriolis, Vector({F: m_cor})))
        out.append(InertialTorsor(ENTRAINMENT, body.name, entrainment, Vector({F: m_ent})))
    for particle in kin.model.particles:
        coriolis, entrainment = _point_forces(kin, particle.name, particle.mass)
        out.append(InertialTorsor(CORIOLIS, particle.name, coriolis, Vector.zero()))
        out.append(InertialTorsor(ENTRAINMENT, particle.name, entrainment, Vector.zero()))
    return tuple(out)


def _entrainment_potential(kin: RelativeKinematics) -> se.Basic:
    """U_e = Σ [m γ(O'/R0)·O'G − ½ m |Ω ∧ O'G|² − ½ Ω·Π_G Ω], the candidate potential of entrainment."""
    frames = kin.frames
    w = kin.frame_omega
    terms = []
    masses = [(b.name, b.mass) for b in kin.model.bodies] + [(p.name, p.mass) for p in kin.model.particles]
    for name, mass in masses:
        r = kin.position(name)
        swept = frames.cross(w, r)
        terms.append(mass * frames.dot(kin.origin_acceleration, r) - mass * frames.dot(swept, swept) / 2)
    for body in kin.model.bodies:
        _, pi = rigid_inertia(kin, body)
        wF = frames.express(w, body.inertia.frame)
        terms.append(-_dot(wF, _matvec(pi, wF)) / 2)
    return sum_of([t for t in terms if not is_structural_zero(t)])


def _generalized(kin: RelativeKinematics, torsors: list[InertialTorsor]) -> tuple[se.Basic, ...]:
    """Q_i = Σ F·∂V(G/R)/∂q̇_i + M_G·∂Ω(S/R)/∂q̇_i over the torsors."""
    terms: list[list[se.Basic]] = [[] for _ in range(kin.n)]
    frames = {b.name: b.frame for b in kin.model.bodies}
    for tor in torsors:
        for i, v in enumerate(kin.partial_velocities(tor.element)):
            terms[i].append(kin.frames.dot(tor.force, v))
        if tor.element in frames and not tor.moment.is_zero():
            for i, w in enumerate(kin.partial_omegas(frames[tor.element])):
                terms[i].append(kin.frames.dot(tor.moment, w))
    return tuple(sum_of([t for t in row if not is_structural_zero(t)]) for row in terms)


def _real_power(kin: RelativeKinematics, torsors: list[InertialTorsor]) -> se.Basic:
    """Σ F·V(G/R) + M_G·Ω(S/R): the real power of the torsors."""
    frames = {b.name: b.frame for b in kin.model.bodies}
    terms = [kin.frames.dot(t.force, kin.velocity(t.element)) for t in torsors]
    terms += [kin.frames.dot(t.moment, kin.omega(frames[t.element])) for t in torsors if t.element in frames]
    return sum_of(terms)


def inertial_forces(kin: Kinematics) -> tuple[LoadForces, ...]:
    """The Coriolis and entrainment loads of a non-Galilean description (none for R0).

    Returns
    -------
    Up to two `LoadForces`, kinds ``"inertial: Coriolis"`` (when R turns relative to R0) and
    ``"inertial: entrainment"`` (when R turns or O' accelerates): Q_i
    by virtual power of the torsors of `inertial_torsors`; entrainment with its potential
    when it has one (checked: Q_i ≡ −∂U_e/∂q_i), Coriolis never (its Q_i depend on q̇).
    """
    if not isinstance(kin, RelativeKinematics):
        return ()
    torsors = inertial_torsors(kin)
    star = kin.q_star
    out = []
    rotating = not kin.frame_omega.is_zero()
    # A frame in translation has no Coriolis force; one in uniform translation, no inertial force at all.
    present = [CORIOLIS] if rotating else []
    if rotating or not kin.origin_acceleration.is_zero():
        present.append(ENTRAINMENT)
    for name in present:
        mine = [t for t in torsors if t.load == name]
        Q = _generalized(kin, mine)
        power = sum_of([q * s for q, s in zip(Q, star, strict=True) if not is_structural_zero(q)])
        if name == CORIOLIS:
            real, generalized = are_zero([_real_power(kin, mine), sum_of([q * qd for q, qd in zip(Q, kin.qd, strict=True)])])
            virtual = ("zero here (every Q_i ≡ 0)" if all(are_zero(Q))
                       else "not zero (V*(P) is not collinear with V(P/R))")
            note = ("−2 Ω(R/R0) ∧ V(P/R) dm; real power Σ F·V(P/R) " + ("≡ 0" if real else "≢ 0 (unexpected)")
                    + (", Σ Q_i q̇_i ≡ 0" if generalized else ", Σ Q_i q̇_i ≢ 0 (constraints move in R)")
                    + f"; virtual power Σ Q_i q_i* {virtual}")
            out.append(LoadForces(name, "inertial: Coriolis", Q, power, None, note))
            continue
        candidate = _entrainment_potential(kin)
        potential = candidate if _derives_from(kin, Q, candidate) else None
        note = "−[γ(O'/R0) + dΩ/dt ∧ O'P + Ω ∧ (Ω ∧ O'P)] dm; "
        note += ("derives from U = Σ m γ(O'/R0)·O'G − ½ Ω·Π_O'·Ω (−½ Ω² I_Δ for a rotation about a fixed axis)"
                 if potential is not None else "no potential: Ω(R/R0) is not constant")
        out.append(LoadForces(name, "inertial: entrainment", Q, power, potential, note))
    return tuple(out)
