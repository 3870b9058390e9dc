"""Generalized acceleration components Γ_i from their definition, in matrix form.

Seed, section I:  Γ_i = ∫ γ(P ∈ Σ/R0) · ∂OP/∂q_i dm.  For a rigid body this is

    Γ_i = m γ(G) · ∂V(G)/∂q̇_i + (dσ_G/dt) · ∂Ω/∂q̇_i          (about G), or
    Γ_i = (dσ_O/dt) · ∂Ω/∂q̇_i                               (about a fixed point O),

with σ = Π Ω.  Π is constant in the basis F where it is given, so in F's components
dσ/dt = Π ω̇ + Ω(F/R0) ∧ Π ω.  Every term is linear in q̈, which splits Γ_i into
Σ_j M_ij q̈_j + Γ⁰_i with

    M_ij = Σ m ∂V(G)/∂q̇_i · ∂V(G)/∂q̇_j + ∂Ω/∂q̇_i · Π ∂Ω/∂q̇_j     (symmetric)

and Γ⁰_i the rest.  The Lagrange equations Γ_i = Q_i become M q̈ = F = Q − Γ⁰.
This route never differentiates T twice, so it stays small for long chains
(Kane & Levinson, *Dynamics*, 1985, §6.1, use the same partial-velocity form).
"""

from __future__ import annotations

import symengine as se

from ..kinematics import Kinematics
from ..model.vectors import is_structural_zero as _zero
from ..model.vectors import sum_of
from ._energy import RigidInertia

__all__ = ["mass_matrix_and_bias"]


def _matvec(pi: tuple[tuple[se.Basic, ...], ...], w: tuple[se.Basic, ...]) -> tuple[se.Basic, ...]:
    return tuple(se.Add(*(pi[k][m] * w[m] for m in range(3) if not _zero(pi[k][m]) and not _zero(w[m])))
                 for k in range(3))


def _dot(a: tuple[se.Basic, ...], b: tuple[se.Basic, ...]) -> se.Basic:
    return sum_of([x * y for x, y in zip(a, b, strict=True) if not _zero(x) and not _zero(y)])


def _cross(a: tuple[se.Basic, ...], b: tuple[se.Basic, ...]) -> tuple[se.Basic, ...]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def mass_matrix_and_bias(
    kin: Kinematics, inertias: dict[str, RigidInertia], *, share=None,
) -> tuple[tuple[tuple[se.Basic, ...], ...], tuple[se.Basic, ...]]:
    """M(q, t) and Γ⁰(q, q̇, t) such that Γ = M q̈ + Γ⁰.

    ``share``, when given, is called on each body's γ⁰(G) and dσ⁰/dt (3-tuples of
    components) and returns what Γ⁰ is built from — code generation passes a function
    that names them, so each is computed once and not once per coordinate (an n-link
    chain's Γ⁰ then costs O(n²) rather than O(n³) operations).

    Parameters
    ----------
    kin : Kinematics
        The model's kinematics.
    inertias : dict of str to RigidInertia
        The inertia each body's T uses.
    share : callable, optional
        Called on each body's γ⁰(G) and dσ⁰/dt (3-tuples of components), it returns what Γ⁰ is
        built from — code generation passes a function that names them, so each is computed once
        and not once per coordinate (an n-link chain's Γ⁰ then costs O(n²) rather than O(n³)
        operations).

    Returns
    -------
    M : tuple of tuples of SymEngine expressions
        The n×n mass matrix, symmetric.
    gamma0 : tuple of SymEngine expressions
        Γ⁰, n entries.
    """
    n = kin.n
    M: list[list[list[se.Basic]]] = [[[] for _ in range(n)] for _ in range(n)]  # lists of terms, summed once at the end
    g0: list[list[se.Basic]] = [[] for _ in range(n)]

    def translational(point: str, mass: se.Basic) -> None:
        partials = kin.partial_velocities(point)
        frame = kin.frames.best_frame(*partials, kin.velocity(point))
        V = [kin.frames.express(p, frame) for p in partials]
        acc0 = kin.frames.express(kin.acceleration(point, accelerations=False), frame)
        if share is not None:
            acc0 = share(acc0)
        for i in range(n):
            if all(_zero(c) for c in V[i]):
                continue
            g0[i].append(mass * _dot(V[i], acc0))
            for j in range(i, n):
                # Each pair in the frame that suits it: two partial velocities written in
                # the same frame need no change of basis (l² rather than l²(sin² + cos²)).
                M[i][j].append(mass * kin.frames.dot(partials[i], partials[j]))

    for body in kin.model.bodies:
        used = inertias[body.name]
        if used.point == "G":
            translational(body.name, body.mass)
        F = used.frame
        pi = used.matrix
        w = kin.frames.omega_in(body.frame, F)
        wF = kin.frames.omega_in(F, F)  # Ω(F/R0): transport of Π's basis
        partial = [kin.frames.express(p, F) for p in kin.partial_omegas(body.frame)]
        wdot0 = tuple(kin.d_dt(c, accelerations=False) for c in w)
        dsigma0 = tuple(a + b for a, b in zip(_matvec(pi, wdot0), _cross(wF, _matvec(pi, w)), strict=True))
        if share is not None:
            dsigma0 = share(dsigma0)
        pi_partial = [_matvec(pi, p) for p in partial]
        for i in range(n):
            if all(_zero(c) for c in partial[i]):
                continue
            g0[i].append(_dot(partial[i], dsigma0))
            for j in range(i, n):
                M[i][j].append(_dot(partial[i], pi_partial[j]))

    for particle in kin.model.particles:
        translational(particle.name, particle.mass)

    zero = se.Integer(0)
    matrix = [[zero] * n for _ in range(n)]
    for i in range(n):
        for j in range(i, n):
            matrix[i][j] = matrix[j][i] = sum_of(M[i][j])
    return tuple(tuple(r) for r in matrix), tuple(sum_of(terms) for terms in g0)
