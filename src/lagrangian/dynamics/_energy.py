"""Kinetic energy T(Σ/R0) of bodies and particles, and the inertia matrices they use.

Rigid body S with a fixed point O (seed, worked example):
    T(S/R0) = ½ Ω(S/R0) · [Π_O(S) Ω(S/R0)]
otherwise, by König's theorem:
    T(S/R0) = ½ m V(G/R0)² + ½ Ω(S/R0) · [Π_G(S) Ω(S/R0)]
Particle:  T = ½ m V(P/R0)².

Ω is taken in the basis where Π is given and T is kept as ½ Σ I_k ω_k² grouped by
equal moments, which yields the course's ½A(θ̇² + ψ̇² sin²θ) + ½C(φ̇ + ψ̇ cosθ)²
with no simplification at all.  The parallel-axis theorem (Huygens) moves Π between
G and another point:  Π_P = Π_G + m [ (d·d) E − d dᵀ ],  d = GP.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import symengine as se

from .._identity import are_zero
from ..errors import ModelError
from ..kinematics import Kinematics
from ..model import Body, Location, NotFinite, real_value

__all__ = ["KineticEnergyTerm", "RigidInertia", "rigid_inertia", "kinetic_energy"]

Matrix3 = tuple[tuple[se.Basic, se.Basic, se.Basic], ...]
#: Relative tolerance on the triangle inequality and the sign of principal moments.
INERTIA_RTOL = 1e-9


@dataclass(frozen=True, slots=True)
class RigidInertia:
    """The inertia matrix a body's dynamics uses: Π at ``point`` ("G" or a fixed point) in ``frame``.

    Parameters
    ----------
    body : str
        The body's name.
    point : str
        ``"G"`` or a fixed point.
    frame : str
        The frame whose basis the matrix is written in.
    matrix : tuple of three tuples of three SymEngine expressions
        Π at ``point``.
    """

    body: str
    point: str
    frame: str
    matrix: Matrix3


@dataclass(frozen=True, slots=True)
class KineticEnergyTerm:
    """T of one body or particle, with the theorem it came from.

    Parameters
    ----------
    name : str
        The body or particle.
    formula : str
        The theorem used: ``"fixed point"``, ``"König"`` or ``"particle"``.
    expression : SymEngine expression
        Its T.
    inertia : RigidInertia, optional
        The inertia used, for a body.
    """

    name: str
    formula: str  # "fixed point", "König" or "particle"
    expression: se.Basic
    inertia: RigidInertia | None = None


def _transport(matrix: Matrix3, mass: se.Basic, d: tuple[se.Basic, ...], sign: int) -> Matrix3:
    """Π ± m[(d·d)E − d dᵀ] (parallel-axis theorem)."""
    dd = d[0] ** 2 + d[1] ** 2 + d[2] ** 2
    out = []
    for k in range(3):
        row = []
        for m_ in range(3):
            shift = (dd if k == m_ else 0) - d[k] * d[m_]
            row.append(matrix[k][m_] + sign * mass * shift)
        out.append(tuple(row))
    return tuple(out)


def rigid_inertia(kin: Kinematics, body: Body) -> tuple[RigidInertia, Matrix3]:
    """The inertia used for T (at the fixed point if there is one, else at G) and Π_G.

    Checks that the given matrix is constant in the body (a frame other than the
    body's may be used only if the rotation between them leaves Π unchanged, as R2
    for the symmetric top) and that Π_G is physical for the parameter values given.

    Parameters
    ----------
    kin : Kinematics
        The model's kinematics.
    body : Body
        The body.

    Returns
    -------
    inertia : RigidInertia
        The inertia used for T.
    inertia_G : tuple of three tuples of three SymEngine expressions
        Π_G.
    """
    model = kin.model
    where = model.where("body", body.name)
    loc = where.of("inertia")  # errors about the inertia point at its line in the file
    inertia = body.inertia
    given: Matrix3 = inertia.matrix
    frame = inertia.frame
    if frame != body.frame:
        _check_invariant(kin, body, loc)

    def gp_components(point: str, loc: Location = loc) -> tuple[se.Basic, ...]:
        d = kin.position(point) - body.center  # GP
        # P must be a point of the body: GP constant in the body's own frame.
        in_body = kin.frames.express(d, body.frame)
        moving = [c for c in in_body if c.free_symbols & (set(kin.q) | {kin.t})]
        if moving and not all(are_zero([se.diff(c, s) for c in in_body for s in (*kin.q, kin.t)])):
            raise ModelError(
                f"point `{point}` moves relative to body `{body.name}` (GP has components {list(in_body)} in "
                f"`{body.frame}`), so the inertia of `{body.name}` cannot be given or taken there",
                symbol=point, fix="give the inertia at G or at a point fixed in the body",
                file=loc.file, line=loc.line)
        return kin.frames.express(d, frame)

    if inertia.at == "G":
        pi_g = given
    else:
        pi_g = _transport(given, body.mass, gp_components(inertia.at), -1)
    _check_physical(kin, body, pi_g, loc)
    fixed = body.fixed_point
    if fixed is None:
        return RigidInertia(body.name, "G", frame, pi_g), pi_g
    if not kin.is_fixed(fixed):
        velocity = kin.velocity(fixed)
        raise ModelError(
            f"`{fixed}` is declared the fixed point of body `{body.name}` but it moves: V({fixed}/R0) = "
            f"{velocity} is not zero",
            symbol=fixed, fix="remove `fixed_point`, or define the point so that it does not move",
            file=where.file, line=where.of("fixed_point").line)
    if inertia.at == fixed:
        return RigidInertia(body.name, fixed, frame, given), pi_g
    moved = _transport(pi_g, body.mass, gp_components(fixed, where.of("fixed_point")), +1)
    return RigidInertia(body.name, fixed, frame, moved), pi_g


def _check_invariant(kin: Kinematics, body: Body, loc) -> None:
    """Π given in frame F must be the same matrix in the body frame: C Π Cᵀ = Π."""
    frame = body.inertia.frame
    cols = [kin.frames.convert(tuple(se.Integer(int(i == k)) for i in range(3)), body.frame, frame)
            for k in range(3)]
    pi = body.inertia.matrix
    # Π' = Cᵀ Π C with C the matrix whose columns are the body axes in F.
    residues = []
    for a in range(3):
        for b in range(3):
            entry = se.Add(*(cols[a][i] * pi[i][j] * cols[b][j] for i in range(3) for j in range(3)))
            residues.append(entry - pi[a][b])
    if not all(are_zero(residues)):
        raise ModelError(
            f"the inertia of body `{body.name}` is given in frame `{frame}`, which turns relative to the body "
            f"(frame `{body.frame}`), and the matrix is not invariant under that rotation",
            symbol=body.name, fix=f"give the inertia in the body frame `{body.frame}`",
            file=loc.file, line=loc.line)


def _check_physical(kin: Kinematics, body: Body, pi_g: Matrix3, loc) -> None:
    """Principal moments at G must be ≥ 0 and obey the triangle inequality I1 ≤ I2 + I3."""
    used = set().union(*(e.free_symbols for row in pi_g for e in row))
    # Only the parameters the entries hold: `subs` converts its whole map on every call.
    values = {se.Symbol(p.name): p.value for p in kin.model.parameters
              if p.value is not None and se.Symbol(p.name) in used}
    entries = [[e.subs(values) for e in row] for row in pi_g]
    if any(e.free_symbols for row in entries for e in row):
        return  # symbolic parameters without values: nothing to check numerically
    try:
        numeric = np.array([[real_value(e) for e in row] for row in entries])
    except NotFinite as exc:
        raise ModelError(
            f"the inertia of body `{body.name}` at G is not finite with the parameters' values: an entry is {exc}",
            fix="check the values of the parameters in the inertia (a double holds at most about 1.8e308)",
            symbol=body.name, file=loc.file, line=loc.line) from None
    moments = np.linalg.eigvalsh(numeric)
    scale = max(float(np.max(np.abs(moments))), 1e-300)
    where = dict(symbol=body.name, file=loc.file, line=loc.line)
    if moments[0] < -INERTIA_RTOL * scale:
        raise ModelError(
            f"the inertia of body `{body.name}` is not physical: at G its principal moments are "
            f"{', '.join(f'{m:.6g}' for m in moments)}, and a moment of inertia cannot be negative",
            fix="check the values and the point where the inertia is given (`at`)", **where)
    if moments[2] > moments[0] + moments[1] + INERTIA_RTOL * scale:
        raise ModelError(
            f"the inertia of body `{body.name}` is not physical: at G its principal moments "
            f"{', '.join(f'{m:.6g}' for m in moments)} violate the triangle inequality I3 ≤ I1 + I2",
            fix="no mass distribution has these moments; check the values", **where)


def _rotational_energy(omega: tuple[se.Basic, ...], pi: Matrix3) -> se.Basic:
    """½ ω·Π ω grouped by equal coefficients: ½A(ω1² + ω2²) + ½Cω3² + Σ Π_kl ω_k ω_l."""
    groups: dict[se.Basic, list[se.Basic]] = {}
    for k in range(3):
        if pi[k][k] != 0 and omega[k] != 0:
            groups.setdefault(pi[k][k], []).append(omega[k] ** 2)
    half = se.Rational(1, 2)
    terms = [half * coeff * se.Add(*squares) for coeff, squares in groups.items()]
    for k in range(3):
        for m_ in range(k + 1, 3):
            if pi[k][m_] != 0 and omega[k] != 0 and omega[m_] != 0:
                terms.append(pi[k][m_] * omega[k] * omega[m_])
    return se.Add(*terms)


def kinetic_energy(kin: Kinematics) -> tuple[tuple[KineticEnergyTerm, ...], dict[str, RigidInertia]]:
    """T(Σ/R0) body by body and particle by particle, and the inertia each body uses."""
    terms = []
    inertias: dict[str, RigidInertia] = {}
    half = se.Rational(1, 2)
    for body in kin.model.bodies:
        used, _ = rigid_inertia(kin, body)
        inertias[body.name] = used
        omega = kin.frames.omega_in(body.frame, used.frame)
        rot = _rotational_energy(omega, used.matrix)
        if used.point == "G":
            v = kin.velocity(body.name)
            t = half * body.mass * kin.frames.dot(v, v) + rot
            terms.append(KineticEnergyTerm(body.name, "König", t, used))
        else:
            terms.append(KineticEnergyTerm(body.name, "fixed point", rot, used))
    for particle in kin.model.particles:
        v = kin.velocity(particle.name)
        terms.append(KineticEnergyTerm(particle.name, "particle", half * particle.mass * kin.frames.dot(v, v)))
    return tuple(terms), inertias

