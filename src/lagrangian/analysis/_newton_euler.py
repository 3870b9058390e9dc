"""The Newton–Euler cross-check of the Lagrange equations (seed, Remarque 4 and the top's last remark).

For every body (S) of mass m, centre of mass G, taken at a reference point P — its fixed
point when it has one (the top: O), otherwise G — the two vector theorems in the
Galilean frame R0 are

    m γ(G/R0) = Σ F_ext                    (resultant theorem)
    δ_P(S/R0) = Σ M_P(F_ext)               (moment theorem)

with σ_P = Π_P · Ω(S/R0) and δ_P = dσ_P/dt|R0 (derivative in R0 through the frame tree:
components differentiated in the frame where Π is constant, plus Ω(F/R0) ∧ σ).  When the
inertia is not given at P, σ_G = Π_G · Ω and δ_P = δ_G + PG ∧ m γ(G).  A particle has
only the resultant theorem.

When the model writes its equations relative to a non-Galilean reference frame R
(``[reference]``, seed Remarque 3), the kinematics are relative to R: the same theorems hold
with γ(G/R), σ_P(S/R), δ_P(S/R), the Coriolis and entrainment inertial torsors being among the
efforts (`dynamics._inertial.inertial_torsors`); the labels then read R for R0
(``lagrangian verify``: m γ(P/R) = weight + Coriolis + entrainment + R).

Remarque 4 says the Lagrange equation of q_i is a combination of those theorems,
projected on the axes that go with q_i.  The combination is the virtual power of each
torsor for the field V* = ∂V/∂q̇_i (the partial velocities):

    Σ_S [ m γ(G)·∂V(P)/∂q̇_i + δ_P·∂Ω(S)/∂q̇_i ]  ≡  Γ_i = d/dt(∂T/∂q̇_i) − ∂T/∂q_i
    Σ_S [ R_given·∂V(P)/∂q̇_i + M_P,given·∂Ω(S)/∂q̇_i ]  ≡  −∂U/∂q_i + Q_i(nc)

(with a fixed point O, ∂V(O)/∂q̇_i = 0 and only δ_O·∂Ω/∂q̇_i is left).  Perfect
constraints (a fixed point, a hinge, a rod) do no virtual work: their actions drop out of
these projections, and what is left of the vector theorems gives the reactions
(`lagrangian.analysis.reactions`).  Everything here is computed from the kinematics
(γ, Ω, partial velocities) and from the loads as forces and couples — never from T — so
the agreement is a real check; only potentials and given generalized forces, which have
no force form, enter by their generalized forces Q_i.

When every element that moves with q_i turns about one axis e through one point A
(∂Ω/∂q̇_i = e, ∂V(G)/∂q̇_i = e ∧ AG), the projection is "the moment theorem at A
projected on e" (the top: L(ψ) on z0, L(θ) on u, L(φ) on z); when they all translate
along one vector, "the resultant theorem projected on" it.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import symengine as se

from .._identity import are_zero
from ..dynamics import (
    EquationsOfMotion,
    RelativeKinematics,
    friction_efforts,
    inertial_torsors,
    reaction_efforts,
    rigid_inertia,
)
from ..kinematics import Kinematics
from ..model import (
    ORIGIN,
    Assumptions,
    Body,
    CoulombFriction,
    Damper,
    Dissipation,
    GeneralizedForce,
    Gravity,
    JointDamper,
    Particle,
    PointForce,
    Potential,
    Spring,
    Torque,
    Vector,
)
from ..model.vectors import sum_of

__all__ = ["EffortsOnElement", "ElementTheorems", "CoordinateCheck", "Verification", "given_efforts", "verify"]

_ZERO = se.Integer(0)
#: Relative size (to the terms of a sum) above which a double-precision value is surely not
#: rounding noise, so an identity can be rejected before the exact test of `are_zero`.
QUICK_REJECT = 1e-8


@dataclass(frozen=True, slots=True)
class ElementTheorems:
    """The resultant and moment theorems of one body (or particle) in R0, as vectors.

    The constraint actions on the element are what the given efforts leave: ``constraint_force`` =
    m γ(G) − R_given and ``constraint_moment`` = δ_P − M_P(given).

    Parameters
    ----------
    name : str
        The body or particle.
    kind : str
        ``"body"`` or ``"particle"``.
    point : str
        Where the moment theorem is taken: the body's fixed point, or the name of the body/particle
        itself meaning its centre of mass G.
    mass : SymEngine expression
        Its mass m.
    mass_acceleration : Vector
        The mass times the acceleration of G, m γ(G/R0) (γ(G/R) in a reference frame R).
    angular_momentum : Vector
        The angular momentum σ_P(S/R0) = Π_P·Ω (zero for a particle; relative to R in a frame R).
    dynamic_moment : Vector
        The dynamic moment ``δ_P(S/R0) = dσ_P/dt|R0`` (``|R`` in a frame R).
    force : Vector
        Σ of the given forces on the element.
    moment : Vector
        Σ M_P of the given efforts on the element.
    efforts : tuple of str
        The names of the loads acting on it.
    """

    name: str
    kind: str  # "body" or "particle"
    point: str
    mass: se.Basic
    mass_acceleration: Vector  # m γ(G/R0) (γ(G/R) in a reference frame R)
    angular_momentum: Vector  # σ_P(S/R0) = Π_P·Ω (zero for a particle; relative to R in a frame R)
    dynamic_moment: Vector  # δ_P(S/R0) = dσ_P/dt|R0 (|R in a frame R)
    force: Vector  # Σ given forces on the element
    moment: Vector  # Σ M_P of the given efforts on the element
    efforts: tuple[str, ...]  # names of the loads acting on it

    @property
    def constraint_force(self) -> Vector:
        """Resultant of the constraint actions on the element: m γ(G) − Σ F_given."""
        return self.mass_acceleration - self.force

    @property
    def constraint_moment(self) -> Vector:
        """Moment at ``point`` of the constraint actions on the element: δ_P − Σ M_P(given)."""
        return self.dynamic_moment - self.moment


@dataclass(frozen=True, slots=True)
class CoordinateCheck:
    """L(q_i) against the projection of the Newton–Euler theorems on the directions of q_i.

    Parameters
    ----------
    coordinate : str
        The coordinate q_i.
    theorem : str
        ``"moment"`` (at ``point``, projected on ``direction``), ``"resultant"`` (projected on
        ``direction``) or ``"virtual power"`` (projected on the partial velocities and angular
        velocities of q_i, when no single axis or direction describes them).
    point : str or None
        A point or particle name, or ``G_<body>`` for a body's centre of mass.
    direction : Vector or None
        The direction projected on.
    axis : str or None
        The display name of ``direction`` when it is a unit basis vector (``"u"``).
    elements : tuple of str
        The bodies and particles that move with q_i.
    whole_system : bool
        ``elements`` is every element of the model.
    newton_euler : SymEngine expression
        Σ m γ(G)·∂V(P)/∂q̇_i + δ_P·∂Ω/∂q̇_i.
    newton_euler_efforts : SymEngine expression
        The same projection of the given efforts.
    lagrange : SymEngine expression
        Γ_i.
    lagrange_efforts : SymEngine expression
        −∂U/∂q_i + Q_i(nc).
    lhs_agrees : bool
        ``newton_euler`` ≡ ``lagrange``.
    rhs_agrees : bool
        ``newton_euler_efforts`` ≡ ``lagrange_efforts``.
    """

    coordinate: str
    theorem: str
    point: str | None
    direction: Vector | None
    axis: str | None
    elements: tuple[str, ...]  # the bodies and particles that move with q_i
    whole_system: bool  # ``elements`` is every element of the model
    newton_euler: se.Basic  # Σ m γ(G)·∂V(P)/∂q̇_i + δ_P·∂Ω/∂q̇_i
    newton_euler_efforts: se.Basic  # the same projection of the given efforts
    lagrange: se.Basic  # Γ_i
    lagrange_efforts: se.Basic  # −∂U/∂q_i + Q_i(nc)
    lhs_agrees: bool
    rhs_agrees: bool

    @property
    def agrees(self) -> bool:
        return self.lhs_agrees and self.rhs_agrees

    def describe(self, direction_text: str | None = None) -> str:
        """Say which theorem was projected on what, e.g. ``"moment theorem at O projected on u"``.

        Parameters
        ----------
        direction_text : str, optional
            Renders a non-unit direction.

        Returns
        -------
        str
            The description.
        """
        where = "" if self.whole_system else " of " + " + ".join(self.elements)
        shown = self.axis or direction_text or (repr(self.direction) if self.direction is not None else "")
        if self.theorem == "moment":
            return f"moment theorem at {self.point}{where} projected on {shown}"
        if self.theorem == "resultant":
            return f"resultant theorem{where} projected on {shown}"
        return f"theorems{where} projected on the partial velocities of {self.coordinate} (virtual power)"


@dataclass(frozen=True, slots=True)
class Verification:
    """The outcome of `verify`: the vector theorems of every element, and each L(q_i) checked.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations checked.
    theorems : tuple of ElementTheorems
        The vector theorems of every body and particle.
    checks : tuple of CoordinateCheck
        One per coordinate (empty with ``check=False``).
    virtual_power_loads : tuple of str
        The loads that entered by their generalized forces (potentials, given Q_i, forces at points
        carried by no body) rather than as forces.
    virtual_power : tuple of SymEngine expressions
        The sum of those Q_i, one per coordinate.
    """

    eom: EquationsOfMotion
    theorems: tuple[ElementTheorems, ...]
    checks: tuple[CoordinateCheck, ...]
    virtual_power_loads: tuple[str, ...]
    virtual_power: tuple[se.Basic, ...]

    @property
    def agrees(self) -> bool:
        return all(c.agrees for c in self.checks)

    def check(self, coordinate: str) -> CoordinateCheck:
        for c in self.checks:
            if c.coordinate == coordinate:
                return c
        raise KeyError(coordinate)

    def element(self, name: str) -> ElementTheorems:
        for e in self.theorems:
            if e.name == name:
                return e
        raise KeyError(name)


# -- the vector theorems --------------------------------------------------------------------
def _matvec(matrix: tuple[tuple[se.Basic, ...], ...], w: tuple[se.Basic, ...]) -> tuple[se.Basic, ...]:
    return tuple(sum_of([matrix[k][j] * w[j] for j in range(3) if matrix[k][j] != 0 and w[j] != 0])
                 for k in range(3))


def _body_theorems(kin: Kinematics, body: Body, efforts: EffortsOnElement) -> ElementTheorems:
    frames = kin.frames
    m_gamma = kin.acceleration(body.name) * body.mass
    point = body.fixed_point or body.name
    inertia = body.inertia
    if body.fixed_point is not None and inertia.at == body.fixed_point:
        # σ_O = Π_O·Ω with Π_O as given (the top: A θ̇ u + A ψ̇ sinθ w + C (φ̇ + ψ̇ cosθ) z).
        sigma = Vector({inertia.frame: _matvec(inertia.matrix, frames.omega_in(body.frame, inertia.frame))})
        delta = frames.derivative(sigma)
    else:
        _, pi_g = rigid_inertia(kin, body)  # Π_G by the parallel-axis theorem when given elsewhere
        sigma = Vector({inertia.frame: _matvec(pi_g, frames.omega_in(body.frame, inertia.frame))})
        delta = frames.derivative(sigma)
        if body.fixed_point is not None:
            # Transport of the kinetic and dynamic torsors: σ_O = σ_G + OG ∧ m V(G), δ_O = δ_G + OG ∧ m γ(G).
            og = kin.position(body.name) - kin.position(body.fixed_point)
            sigma = sigma + frames.cross(og, kin.velocity(body.name) * body.mass)
            delta = delta + frames.cross(og, m_gamma)
    return ElementTheorems(body.name, "body", point, body.mass, m_gamma, sigma, delta, efforts.force,
                           efforts.moment, efforts.loads)


def _particle_theorems(kin: Kinematics, particle: Particle, efforts: EffortsOnElement) -> ElementTheorems:
    m_gamma = kin.acceleration(particle.name) * particle.mass
    return ElementTheorems(particle.name, "particle", particle.name, particle.mass, m_gamma, Vector.zero(),
                           Vector.zero(), efforts.force, Vector.zero(), efforts.loads)


# -- identities ----------------------------------------------------------------------------------
def _vanish(exprs: list[se.Basic]) -> bool:
    """All of ``exprs`` identically zero: a cheap double-precision rejection, then `are_zero`."""
    exprs = [e for e in exprs if e != 0]
    if not exprs:
        return True
    symbols = sorted(set().union(*(e.free_symbols for e in exprs)), key=str)
    rng = random.Random(7)
    point = {s: se.RealDouble(rng.uniform(0.3, 1.7)) for s in symbols}
    for e in exprs:
        try:
            value = abs(complex(e.subs(point)))
            terms = e.args if e.is_Add else (e,)
            scale = sum(abs(complex(t.subs(point))) for t in terms)
        except (TypeError, RuntimeError, ValueError, OverflowError):  # undefined there, or past 1e308: are_zero decides
            continue
        if value > QUICK_REJECT * scale and value > QUICK_REJECT:
            return False  # eight orders above double rounding: certainly not zero
    if all(are_zero(exprs)):
        return True
    # are_zero evaluates at random points with 200-odd bits, which cos(1e308 θ) defeats (its argument is
    # rounded by far more than 2π): where it finds no zero, an exact expansion may still cancel.
    return all(se.expand(e) == 0 for e in exprs)


def _same(kin: Kinematics, u: Vector, v: Vector) -> list[se.Basic]:
    """Components of u − v in one frame (all zero when u = v)."""
    d = u - v
    return list(kin.frames.express(d, kin.frames.best_frame(d))) if not d.is_zero() else []


def _unit_axis(kin: Kinematics, v: Vector) -> str | None:
    """The display name of ``v`` when it is one basis vector of a frame (``"u"``), else None."""
    pieces = list(v)
    if len(pieces) != 1:
        return None
    frame, comps = pieces[0]
    nonzero = [k for k, c in enumerate(comps) if c != 0]
    if len(nonzero) == 1 and comps[nonzero[0]] == 1:
        return kin.frames.axes(frame)[nonzero[0]]
    return None


def _describe(kin: Kinematics, i: int,
              moving: list[tuple[str, Vector, Vector | None]]) -> tuple[str, str | None, Vector | None]:
    """(theorem, point, direction) for coordinate i, from the partial velocities of the elements.

    ``moving`` holds, for each element that moves with q_i, (name, ∂V(G)/∂q̇_i, ∂Ω/∂q̇_i or
    None for a particle).
    """
    frames = kin.frames
    omegas = [w for _, _, w in moving if w is not None and not w.is_zero()]
    if omegas:
        axes = [frames.lift(omegas[0])]
    else:
        axes = []
        for f in kin.model.frames:
            w = kin.partial_omegas(f.name)[i]
            if not w.is_zero():
                w = frames.lift(w)
                if not any(_vanish(_same(kin, w, a)) for a in axes):
                    axes.append(w)
    model = kin.model
    candidates = [ORIGIN, *(b.fixed_point for b in model.bodies if b.fixed_point),
                  *(p.name for p in model.points), *(p.name for p in model.particles),
                  *(b.name for b in model.bodies)]
    points = list(dict.fromkeys(candidates))
    bodies = {b.name for b in model.bodies}
    for e in axes:
        body_terms = [r for _, _, w in moving if w is not None for r in _same(kin, w, e)]
        if not _vanish(body_terms):
            continue
        for a in points:
            residues = []
            for name, dv, _ in moving:
                ag = kin.position(name) - kin.position(a)
                residues += _same(kin, dv, frames.cross(e, ag) if not ag.is_zero() else Vector.zero())
            if _vanish(residues):
                return "moment", (f"G_{a}" if a in bodies else a), e
    if not omegas:
        first = moving[0][1]
        if all(w is None or w.is_zero() for _, _, w in moving) and _vanish(
                [r for _, dv, _ in moving[1:] for r in _same(kin, dv, first)]):
            return "resultant", None, frames.lift(first)
    return "virtual power", None, None


# -- the given efforts as forces and couples ---------------------------------------------------
@dataclass(frozen=True, slots=True)
class EffortsOnElement:
    """The given efforts on one body or particle: resultant, and moment at ``point``."""

    element: str
    point: str
    force: Vector
    moment: Vector
    loads: tuple[str, ...]


class _Efforts:
    """Collects forces and couples element by element; what no element carries goes by virtual power."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        self.kin = kin = eom.kinematics
        model = eom.model
        self.point = {b.name: b.fixed_point or b.name for b in model.bodies}
        self.point.update({p.name: p.name for p in model.particles})
        self.force = {name: Vector.zero() for name in self.point}
        self.moment = {name: Vector.zero() for name in self.point}
        self.loads: dict[str, list[str]] = {name: [] for name in self.point}
        self.power: list[se.Basic] = [_ZERO] * kin.n  # Σ Q_i of the efforts taken by virtual power
        self.by_power: list[str] = []
        self._carriers: dict[str, str | None] = {}

    def carrier(self, point: str) -> str | None:
        """The body or particle of which ``point`` is a material point (the first, at a joint)."""
        if point not in self._carriers:
            self._carriers[point] = self._find_carrier(point)
        return self._carriers[point]

    def _find_carrier(self, point: str) -> str | None:
        kin, model = self.kin, self.kin.model
        if point in self.point:
            return point
        where = kin.position(point)
        for p in model.particles:
            if _vanish(_same(kin, where, kin.position(p.name))):
                return p.name
        moving = set(kin.q) | {kin.t}
        for b in model.bodies:
            # A point of the body: GA has constant components in the body's frame.
            ga = kin.frames.express(where - kin.position(b.name), b.frame)
            if not any(c.free_symbols & moving for c in ga) or _vanish(
                    [c.diff(s) for c in ga for s in moving if s in c.free_symbols]):
                return b.name
        return None

    def add_force(self, load: str, force: Vector, at: str) -> None:
        if force.is_zero():
            return
        kin = self.kin
        owner = self.carrier(at)
        if owner is not None:
            self.force[owner] = self.force[owner] + force
            arm = kin.position(at) - kin.position(self.point[owner])  # P A
            if not arm.is_zero():
                self.moment[owner] = self.moment[owner] + kin.frames.cross(arm, force)
            self._note(owner, load)
        elif not kin.is_fixed(at):
            # A force at a moving point that no body carries: its virtual power F·V*(A).
            partials = kin.partial_velocities(at)
            self.power = [p + kin.frames.dot(force, v) for p, v in zip(self.power, partials, strict=True)]
            self._note_power(load)
        # else: applied at a fixed point of the ground, it does no virtual work on (Σ).

    def add_couple(self, load: str, couple: Vector, on: str) -> None:
        if on in self.moment:
            self.moment[on] = self.moment[on] + couple
            self._note(on, load)
            return
        frame = on if on not in {b.name for b in self.kin.model.bodies} else self.kin.model.body(on).frame
        partials = self.kin.partial_omegas(frame)
        if any(not w.is_zero() for w in partials):  # a couple on a moving frame that is no body
            self.power = [p + self.kin.frames.dot(couple, w) for p, w in zip(self.power, partials, strict=True)]
            self._note_power(load)

    def _note(self, owner: str, load: str) -> None:
        if load not in self.loads[owner]:
            self.loads[owner].append(load)

    def _note_power(self, load: str) -> None:
        if load not in self.by_power:
            self.by_power.append(load)


def given_efforts(eom: EquationsOfMotion) -> tuple[tuple[EffortsOnElement, ...], tuple[se.Basic, ...], tuple[str, ...]]:
    """The given efforts as forces and couples on each element, and what must go by virtual power.

    Gravity m g at G; a force at its point; a couple on its body (−C on ``reaction_on``);
    a spring pulls B towards A with k(ℓ − ℓ0) along AB (and A towards B); a damper pushes
    with c ℓ̇ against the elongation rate.  Potentials and given generalized forces have no
    force form: their Q_i (from ``eom.loads``) are returned per coordinate instead.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.

    Returns
    -------
    efforts : tuple of EffortsOnElement
        The forces and couples on each element.
    virtual_power : tuple of SymEngine expressions
        The Q_i of the loads with no force form, per coordinate.
    names : tuple of str
        Those loads' names.
    """
    kin = eom.kinematics
    model = eom.model
    acc = _Efforts(eom)
    masses = {b.name: b.mass for b in model.bodies} | {p.name: p.mass for p in model.particles}
    for load in model.loads:
        if isinstance(load, Gravity):
            for name in load.on or tuple(masses):
                acc.add_force(load.name, load.field * masses[name], name)
        elif isinstance(load, PointForce):
            acc.add_force(load.name, load.force, load.at)
        elif isinstance(load, Torque):
            acc.add_couple(load.name, load.torque, load.on)
            if load.reaction_on is not None:
                acc.add_couple(load.name, -load.torque, load.reaction_on)
        elif isinstance(load, (Spring, Damper)):
            a, b = load.ends
            ab = kin.position(b) - kin.position(a)
            ab2 = kin.frames.dot(ab, ab)
            if isinstance(load, Spring):
                if load.rest_length == 0:
                    factor = -load.stiffness
                else:  # tension k(ℓ − ℓ0) pulls B towards A
                    length = se.sqrt(ab2)
                    factor = -load.stiffness * (length - load.rest_length) / length
            else:  # c ℓ̇ against the elongation rate, ℓ ℓ̇ = AB·(V(B) − V(A))
                factor = -load.coefficient * kin.frames.dot(ab, kin.velocity(b) - kin.velocity(a)) / ab2
            acc.add_force(load.name, ab * factor, b)
            acc.add_force(load.name, ab * (-factor), a)
        elif isinstance(load, (JointDamper, CoulombFriction)):  # couples of a joint, a friction force
            for what, vector, where in friction_efforts(kin, load) or ():
                (acc.add_force if what == "force" else acc.add_couple)(load.name, vector, where)
        elif isinstance(load, (Potential, GeneralizedForce, Dissipation)):
            q = next(f.Q for f in eom.loads if f.name == load.name)
            acc.power = [p + x for p, x in zip(acc.power, q, strict=True)]
            acc._note_power(load.name)
    # Complementary constraints: their reactions, linear in the multipliers λ_k, are
    # efforts like the given ones here (the virtual field is not compatible with them).
    for constraint, what, value, at, owner in reaction_efforts(eom):
        if what == "power":
            acc.power = [p + x for p, x in zip(acc.power, value, strict=True)]  # type: ignore[call-overload]
            acc._note_power(constraint)
        elif what == "couple":
            acc.add_couple(constraint, value, owner)  # type: ignore[arg-type]
        elif owner is None:
            acc.add_force(constraint, value, at)  # type: ignore[arg-type]
        else:  # on the material point of `owner` at the contact `at` (rolling without slipping)
            acc.force[owner] = acc.force[owner] + value  # type: ignore[operator]
            arm = kin.position(at) - kin.position(acc.point[owner])  # type: ignore[arg-type]
            acc.moment[owner] = acc.moment[owner] + kin.frames.cross(arm, value)  # type: ignore[arg-type]
            acc._note(owner, constraint)
    # In a non-Galilean frame R: the Coriolis and entrainment torsors at each centre of mass (Remarque 3).
    for torsor in inertial_torsors(kin) if isinstance(kin, RelativeKinematics) else ():
        acc.add_force(torsor.load, torsor.force, torsor.element)
        if not torsor.moment.is_zero():
            acc.add_couple(torsor.load, torsor.moment, torsor.element)
    efforts = tuple(EffortsOnElement(name, acc.point[name], acc.force[name], acc.moment[name],
                                     tuple(acc.loads[name])) for name in acc.point)
    return efforts, tuple(acc.power), tuple(acc.by_power)


# -- the check -----------------------------------------------------------------------------------
def verify(eom: EquationsOfMotion, *, check: bool = True) -> Verification:
    """Check every Lagrange equation against the Newton–Euler theorems, symbolically.

    Parameters
    ----------
    eom : EquationsOfMotion
        The derivation to check (`lagrangian.derive`).  Only its model, kinematics, loads (for
        potentials and given generalized forces) and ``equations`` are read; the Newton–Euler side
        is computed from the kinematics, not from T.
    check : bool, optional
        False: the vector theorems only, no ``checks`` (what the reactions need; the symbolic
        comparison with each L(q_i) is most of the cost for a robot).

    Returns
    -------
    Verification
        The vector theorems of every body and particle, and for each coordinate the
        projection of the dynamic torsors (≡ Γ_i?) and of the given efforts
        (≡ −∂U/∂q_i + Q_i(nc)?), each decided by `lagrangian._identity.are_zero`.

    Examples
    --------
    >>> import lagrangian
    >>> v = verify(lagrangian.derive(lagrangian.lagrange_top()))
    >>> [c.describe() for c in v.checks]
    ['moment theorem at O projected on z0', 'moment theorem at O projected on u', 'moment theorem at O projected on z']
    >>> v.agrees
    True
    """
    kin = eom.kinematics
    model = eom.model
    assumptions = Assumptions(model)
    efforts, extra_power, vp_loads = given_efforts(eom)
    by_name = {e.element: e for e in efforts}
    theorems = tuple([_body_theorems(kin, b, by_name[b.name]) for b in model.bodies]
                     + [_particle_theorems(kin, p, by_name[p.name]) for p in model.particles])
    element_count = len(theorems)
    frames = kin.frames
    checks = []
    for i, coordinate in enumerate(eom.coordinates if check else ()):
        dyn: list[se.Basic] = []
        given: list[se.Basic] = [extra_power[i]] if extra_power[i] != 0 else []
        moving: list[tuple[str, Vector, Vector | None]] = []
        for th in theorems:
            dv_point = kin.partial_velocities(th.point)[i]
            dw = kin.partial_omegas(model.body(th.name).frame)[i] if th.kind == "body" else None
            dv_g = kin.partial_velocities(th.name)[i]
            if dv_g.is_zero() and (dw is None or dw.is_zero()):
                continue
            moving.append((th.name, dv_g, dw))
            dyn.append(frames.dot(th.mass_acceleration, dv_point))
            given.append(frames.dot(th.force, dv_point))
            if dw is not None:
                dyn.append(frames.dot(th.dynamic_moment, dw))
                given.append(frames.dot(th.moment, dw))
        # Under the model's declared signs and ranges, as the derivation is (|x + L| = x + L where x ≥ −L).
        ne, ne_efforts = sum_of(dyn), assumptions.refine(sum_of(given))
        eq = eom.equations[i]
        lhs_ok, rhs_ok = (_vanish([ne - eq.lhs]), _vanish([ne_efforts - eq.rhs]))
        if moving:
            theorem, point, direction = _describe(kin, i, moving)
        else:
            theorem, point, direction = "virtual power", None, None
        axis = _unit_axis(kin, direction) if direction is not None else None
        names = tuple(name for name, _, _ in moving)
        checks.append(CoordinateCheck(coordinate, theorem, point, direction, axis, names,
                                      len(names) == element_count, ne, ne_efforts, eq.lhs, eq.rhs, lhs_ok, rhs_ok))
    return Verification(eom, theorems, tuple(checks), vp_loads, extra_power)
