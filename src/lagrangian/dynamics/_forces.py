"""Generalized forces Q_i of every given effort, by virtual power, load by load.

P*(effort) = Σ_i Q_i q_i*  with the virtual velocity field V*(P) = Σ ∂OP/∂q_i q_i*:
    force F at P:            Q_i = F · ∂OP/∂q_i
    couple C on S (−C on S'): Q_i = C · (∂Ω(S/R0)/∂q̇_i − ∂Ω(S'/R0)/∂q̇_i), S and S' bodies or frames
    gravity on S:            Q_i = m g · ∂OG/∂q_i
    spring, damper A–B:      Q_i = f · ∂AB/∂q_i with f the force on B along AB
    potential U(q, t):       Q_i = −∂U/∂q_i
    potential U(q, q̇, t):   Q_i = d/dt(∂U/∂q̇_i) − ∂U/∂q_i   (a generalized potential, affine in q̇)

A *generalized* (velocity-dependent) potential U = U0(q, t) + Σ_j a_j(q, t) q̇_j gives, from
the Lagrangian T − U, Q_i = Σ_j (∂a_i/∂q_j − ∂a_j/∂q_i) q̇_j + ∂a_i/∂t − ∂U0/∂q_i (Goldstein,
*Classical Mechanics*, §1.5): the Lorentz force of a charge, U = qc (V − A·v), and the
Coriolis inertial force, U = −m Ω·(O'P ∧ V(P/R)), are of that form.  Its rate part is
gyroscopic (no power when a and U0 do not depend on t), so the load is not a potential energy
U_P(q) of Remarque 2: its Q_i are non-conservative, and its U is kept as ``generalized``
(`first_integrals` puts it in L = T − U_P − U).  A U whose ∂U/∂q̇ still holds rates would
put q̈ in Q: the model reader refuses it (`lagrangian.model._assemble`).

A load is *conservative* when its Q_i are −∂U/∂q_i for some U(q, t); this is
detected, not declared: each load proposes the potential of its physics (gravity
U = −m g·OG, spring ½k(ℓ − ℓ0)², constant force −F·OP...) or, for couples and given
generalized forces, a potential is sought by integration, and the identity
Q_i + ∂U/∂q_i ≡ 0 is then verified for every i (so virtual power and −∂U/∂q check
each other).  A load driven by a declared input (``[inputs]``: a motor torque τ, a push F)
is never conservative: an input is any given function of time u(t), so −u q is no potential
energy of the system (its "energy" would change with u at fixed q and q̇); such a load stays
among the non-conservative efforts, and T + U_P is the mechanical energy.  A load whose
magnitude is a constant of the model (a parameter, not an input) does derive from −C q.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se
from symengine.lib.symengine_wrapper import sympy2symengine

from .._identity import are_zero
from ..kinematics import Kinematics
from ..model import Assumptions, Damper, GeneralizedForce, Gravity, Load, PointForce, Potential, Spring, Torque, Vector
from ..model.vectors import sum_of
from ._friction import FRICTION_LOADS, frame_of, friction_q

__all__ = ["LoadForces", "generalized_forces"]

#: Largest generalized force (in printed characters) handed to SymPy's integrator when
#: seeking a potential: integration is the one slow tool here, so only small Q try it.
MAX_INTEGRATION_CHARS = 2000

_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)


@dataclass(frozen=True, slots=True)
class LoadForces:
    """What one load contributes: its Q_i, its virtual power, and its potential if it has one.

    Parameters
    ----------
    name : str
        The load's name.
    kind : str
        Its kind: the load's class in lower case (``"gravity"``, ``"spring"``...), or
        ``"generalized potential"``.
    Q : tuple of SymEngine expressions
        Its Q_i, one per coordinate.
    virtual_power : SymEngine expression
        Σ Q_i q_i*.
    potential : SymEngine expression or None
        U with Q_i = −∂U/∂q_i, or None when not conservative.
    note : str
        The virtual power its Q_i come from, for the report (``P* = C·Ω*``).
    generalized : SymEngine expression, optional
        A generalized potential U(q, q̇, t), affine in the rates, with Q_i = d/dt(∂U/∂q̇_i) − ∂U/∂q_i
        (then ``potential`` is None: its Q_i are in Q_nc); None for every other load.
    held : SymEngine expression, optional
        For a load driven by declared inputs (then ``potential`` is None): the potential it derives
        from while those inputs are held constant (−τ θ of a motor's torque τ), for the first
        integrals of a run that holds them (`analysis.first_integrals` with
        ``inputs={"tau": "constant"}``).
    """

    name: str
    kind: str
    Q: tuple[se.Basic, ...]
    virtual_power: se.Basic  # Σ Q_i q_i*
    potential: se.Basic | None  # U with Q_i = −∂U/∂q_i, or None when not conservative
    note: str
    generalized: se.Basic | None = None
    held: se.Basic | None = None


def _dot_partials(kin: Kinematics, force: Vector, point: str) -> tuple[se.Basic, ...]:
    return tuple(kin.frames.dot(force, v) for v in kin.partial_velocities(point))


def _is_constant_vector(kin: Kinematics, v: Vector) -> bool:
    """Constant in R0 or in the frame the equations are written in: no q, q̇, t in the
    components, and every piece in frames that do not turn relative to R0 (or all of them
    fixed in the reference frame R).

    Such a field F gives the candidate potential U = −F·O'P, which may depend on t through
    the motion of R relative to R0 (a field fixed in R0 seen from a tumbling frame: U(q, t));
    the candidate is then checked (`_derives_from`) like every other.
    """
    free = v.free_symbols()
    if kin.t in free or any(s in free for s in kin.q) or any(s in free for s in kin.qd):
        return False
    if all(kin.omega(f).is_zero() for f in v.frames):  # fixed in the frame of the equations
        return True
    from ._inertial import RelativeFrameTree  # late: `_inertial` builds on this module

    if isinstance(kin.frames, RelativeFrameTree):  # fixed in R0, seen from a moving R
        return all(kin.frames.absolute.omega(f).is_zero() for f in v.frames)
    return False


def _q_of(kin: Kinematics, load: Load) -> tuple[tuple[se.Basic, ...], se.Basic | None, str]:
    """(Q, candidate potential, note) of one load."""
    n = kin.n
    zero = _ZERO
    if isinstance(load, Gravity):
        names = load.on or tuple(b.name for b in kin.model.bodies) + tuple(p.name for p in kin.model.particles)
        masses = {b.name: b.mass for b in kin.model.bodies} | {p.name: p.mass for p in kin.model.particles}
        Q_terms: list[list[se.Basic]] = [[] for _ in range(n)]
        U_terms = []
        moving = set(kin.q) | {kin.t}
        for name in names:
            weight = load.field * masses[name]
            for terms, x in zip(Q_terms, _dot_partials(kin, weight, name), strict=True):
                terms.append(x)
            u = -kin.frames.dot(weight, kin.position(name))
            if u.free_symbols & moving:  # a constant (G fixed: a pulley's axle) is left to the "+ cste"
                U_terms.append(u)
        potential = sum_of(U_terms) if _is_constant_vector(kin, load.field) else None
        return tuple(sum_of(terms) for terms in Q_terms), potential, "P* = Σ m g·V*(G); U = −Σ m g·OG + cste"
    if isinstance(load, PointForce):
        Q = _dot_partials(kin, load.force, load.at)
        potential = (-kin.frames.dot(load.force, kin.position(load.at))
                     if _is_constant_vector(kin, load.force) else None)
        return Q, potential, f"P* = F·V*({load.at})"
    if isinstance(load, Torque):
        # Each side is a body (its frame turns with it) or a frame itself (a massless link).
        on = kin.partial_omegas(frame_of(kin, load.on))
        other = ((Vector.zero(),) * n if load.reaction_on is None
                 else kin.partial_omegas(frame_of(kin, load.reaction_on)))
        Q = tuple(kin.frames.dot(load.torque, a - b) for a, b in zip(on, other, strict=True))
        return Q, None, "P* = C·Ω*"
    if isinstance(load, (Spring, Damper)):
        a, b = load.ends
        d = kin.position(b) - kin.position(a)
        rel = tuple(vb - va for va, vb in zip(kin.partial_velocities(a), kin.partial_velocities(b), strict=True))
        d_rel = tuple(kin.frames.dot(d, r) for r in rel)  # d · ∂AB/∂q_i
        dd = kin.frames.dot(d, d)
        if isinstance(load, Spring):
            if load.rest_length == 0:
                factor = -load.stiffness
                potential = se.Rational(1, 2) * load.stiffness * dd
            else:
                length = se.sqrt(dd)
                factor = -load.stiffness * (length - load.rest_length) / length
                potential = se.Rational(1, 2) * load.stiffness * (length - load.rest_length) ** 2
            return tuple(factor * x for x in d_rel), potential, f"tension k(ℓ − ℓ0) along {a}{b}"
        rate = kin.frames.dot(d, kin.velocity(b) - kin.velocity(a))  # ℓ ℓ̇
        factor = -load.coefficient * rate / dd
        return tuple(factor * x for x in d_rel), None, f"force c ℓ̇ along {a}{b}, opposing the elongation rate"
    if isinstance(load, Potential):
        U = load.energy
        if not any(qd in U.free_symbols for qd in kin.qd):
            return tuple(-U.diff(q) for q in kin.q), U, "Q_i = −∂U/∂q_i"
        # d/dt(∂U/∂q̇_i) with ∂U/∂q̇_i = a_i(q, t): Σ_j ∂a_i/∂q_j q̇_j + ∂a_i/∂t (no q̈: U is affine in q̇)
        rates_part = [U.diff(qd) for qd in kin.qd]
        Q = tuple(se.Add(*[ai.diff(q) * qd for q, qd in zip(kin.q, kin.qd, strict=True)], ai.diff(kin.t)) - U.diff(q)
                  for ai, q in zip(rates_part, kin.q, strict=True))
        return Q, None, "Q_i = d/dt(∂U/∂q̇_i) − ∂U/∂q_i (a generalized potential, depending on the rates)"
    if isinstance(load, GeneralizedForce):
        comps = dict(load.components)
        return tuple(comps.get(c.name, zero) for c in kin.model.coordinates), None, "given generalized force"
    if isinstance(load, FRICTION_LOADS):  # dissipation, joint damper, Coulomb friction (`_friction`)
        return friction_q(kin, load)
    raise TypeError(f"unknown load type {type(load).__name__}")  # pragma: no cover


def _find_potential(kin: Kinematics, Q: tuple[se.Basic, ...]) -> se.Basic | None:
    """U(q) with Q_i = −∂U/∂q_i, when Q depends on q only and ∂Q_i/∂q_j = ∂Q_j/∂q_i."""
    free = set().union(*(x.free_symbols for x in Q))
    if free & (set(kin.qd) | set(kin.qdd) | {kin.t}):
        return None
    if all(x == 0 for x in Q):
        return se.Integer(0)
    if not free & set(kin.q):  # constant Q_i (a robot's joint torques): U = −Σ Q_i q_i, without SymPy's integrator
        return sum_of([-x * q for x, q in zip(Q, kin.q, strict=True) if x != 0])
    n = kin.n
    curl = [Q[i].diff(kin.q[j]) - Q[j].diff(kin.q[i]) for i in range(n) for j in range(i + 1, n)]
    if not all(are_zero(curl)):
        return None
    if sum(len(str(x)) for x in Q) > MAX_INTEGRATION_CHARS:
        return None
    import sympy  # late: the only use here, and SymPy takes most of a second to load

    # U = −∫ Q_1 dq_1, then add whatever each later Q_i still needs (classic potential search).
    U = sympy.Integer(0)
    for qi, Qi in zip(kin.q, Q, strict=True):
        residue = sympy.expand(-Qi._sympy_() - sympy.diff(U, qi._sympy_()))
        if residue == 0:
            continue
        part = sympy.integrate(residue, qi._sympy_())
        if part.has(sympy.Integral):
            return None
        U = U + part
    return sympy2symengine(U)


def _derives_from(kin: Kinematics, Q: tuple[se.Basic, ...], potential: se.Basic) -> bool:
    """Q_i + ∂U/∂q_i ≡ 0 for every i (a structural zero needs no identity test)."""
    residues = [q + potential.diff(s) for q, s in zip(Q, kin.q, strict=True)]
    if all(type(r) is _ZERO_TYPE for r in residues):
        return True
    return all(are_zero(residues))


def generalized_forces(kin: Kinematics, assumptions: Assumptions | None = None, *,
                       only: Sequence[int] | None = None) -> tuple[LoadForces, ...]:
    """Compute Q_i of every load of the model (or of the loads at indices ``only``) by virtual power.

    Each with its potential when it has one.

    Parameters
    ----------
    kin : Kinematics
        The model's kinematics.
    assumptions : Assumptions, optional
        The model's declared signs and ranges: Q_i and the candidate potential are then simplified
        where a sign is proved: a spring from a wall at x = −L with x ≥ −L gives −k x, not
        ``−k sgn(x + L)(|x + L| − L)`` (`lagrangian.model._assumptions`).
    only : sequence of int, optional
        The indices of the loads to compute; None: all.

    Returns
    -------
    tuple of LoadForces
        One per load, in the model's order.
    """
    out = []
    inputs = {p.symbol for p in kin.model.parameters if p.input}
    loads = kin.model.loads if only is None else [kin.model.loads[k] for k in only]
    for load in loads:
        Q, candidate, note = _q_of(kin, load)
        if assumptions is not None and assumptions.active:
            Q = tuple(assumptions.refine(x) for x in Q)
            candidate = None if candidate is None else assumptions.refine(candidate)
        potential = candidate
        if potential is not None and not _derives_from(kin, Q, potential):
            potential = None  # e.g. a field that depends on q: no potential after all
        if potential is None:
            potential = _find_potential(kin, Q)
            if potential is not None and not _derives_from(kin, Q, potential):
                potential = None
        if potential is not None and potential.free_symbols & set(kin.qd):
            potential = None
        held = None
        if potential is not None and any(set(x.free_symbols) & inputs for x in Q):
            held, potential = potential, None  # driven by an input u(t): a given non-conservative effort
        power = sum_of([q * s for q, s in zip(Q, kin.q_star, strict=True) if type(q) is not _ZERO_TYPE])
        generalized = load.energy if isinstance(load, Potential) and load.energy.free_symbols & set(kin.qd) else None
        kind = "generalized potential" if generalized is not None else type(load).__name__.lower()
        out.append(LoadForces(load.name, kind, Q, power, potential, note, generalized, held))
    return tuple(out)

