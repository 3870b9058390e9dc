"""Projection onto the constraint manifold, and the checks of the initial state of a constrained run.

Coordinate projection (Hairer, Lubich & Wanner, *Geometric Numerical Integration*, IV.4;
Hairer & Wanner, *Solving ODEs II*, VII.2): q is moved onto f(q, t) = 0 by Newton steps,
then q̇ onto A q̇ + b = 0, both along the kinetic-energy metric (the smallest change of
T-weighted position and velocity):

    Δq = −M⁻¹A_hᵀ (A_h M⁻¹ A_hᵀ)⁻¹ f,        Δq̇ = −M⁻¹Aᵀ (A M⁻¹ Aᵀ)⁻¹ (A q̇ + b).

The velocity step is exact (the rows are linear in q̇); the position one converges
quadratically from a state within a step's error of the manifold.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..dynamics import EquationsOfMotion
from ..errors import SimulationError
from ._mass_spectrum import mass_eigenvalues

if TYPE_CHECKING:  # pragma: no cover
    from ._dae import ConstrainedSystem

__all__ = ["project", "project_many", "check_initial", "CONSISTENCY_TOL", "PROJECTION_ITERATIONS"]

#: Largest constraint residual accepted at the initial state (absolute).
CONSISTENCY_TOL = 1e-8
#: Newton iterations allowed for one projection onto f(q, t) = 0.
PROJECTION_ITERATIONS = 8


def project_many(system: ConstrainedSystem, t, Y: np.ndarray, p: np.ndarray, tol: float) -> tuple[np.ndarray, bool]:
    """States (N, 2n) moved onto f(q, t) = 0 and A q̇ + b = 0 along the metric of M (module docstring)."""
    n = system.n
    Y = np.array(Y, dtype=float).reshape(-1, 2 * n)
    hol = system.holonomic
    changed = False
    if hol.any():
        for _ in range(PROJECTION_ITERATIONS):
            M, _, A, _, _, f = system.parts(t, Y, p)
            fh = f[:, hol]
            bad = np.max(np.abs(fh), axis=1) > tol
            if not bad.any():
                break
            Ah = A[bad][:, hol]
            try:
                X = np.linalg.solve(M[bad], np.swapaxes(Ah, 1, 2))  # M⁻¹ A_hᵀ
                Y[bad, :n] -= (X @ np.linalg.solve(Ah @ X, fh[bad][..., None]))[..., 0]
            except np.linalg.LinAlgError:
                raise _singular(t, Y, bad, fh) from None
            changed = True
        else:
            k = int(np.argmax(np.max(np.abs(fh), axis=1)))
            t_k = float(np.broadcast_to(t, (len(Y),))[k])
            raise SimulationError(
                f"The projection onto the constraints did not converge at t = {t_k:.9g} (residual "
                f"{np.max(np.abs(fh)):.3g}).", fix="lower rtol/atol or max_step, so that the steps stay small "
                "enough for the constraints to be restored", t=t_k, state=Y[k].copy())
    M, _, A, _, g, _ = system.parts(t, Y, p)
    bad = np.max(np.abs(g), axis=1) > tol
    if bad.any():
        try:
            X = np.linalg.solve(M[bad], np.swapaxes(A[bad], 1, 2))
            Y[bad, n:] -= (X @ np.linalg.solve(A[bad] @ X, g[bad][..., None]))[..., 0]
        except np.linalg.LinAlgError:
            raise _singular(t, Y, bad, g) from None
        changed = True
    return Y, changed


def _singular(t, Y: np.ndarray, bad: np.ndarray,
              residual: np.ndarray) -> SimulationError:
    """A_h M⁻¹ A_hᵀ (or M) singular on the way: the Newton step is not defined there."""
    k = int(np.flatnonzero(bad)[0])
    t_k = float(np.broadcast_to(t, (len(Y),))[k])
    return SimulationError(
        f"The projection onto the constraints met a singular Jacobian at t = {t_k:.9g} (residual "
        f"{np.max(np.abs(residual[k])):.3g}): the constraint rows are dependent there, or the constraints "
        "have no solution near this state (a sum of squares set equal to a negative number).",
        fix="check the constraint expressions, and start from a state that satisfies them",
        t=t_k, state=Y[k].copy())


def project(system: ConstrainedSystem, t: float, y: np.ndarray, p: np.ndarray, tol: float) -> tuple[np.ndarray, bool]:
    """One state (2n,) projected (`project_many`).

    Parameters
    ----------
    system : ConstrainedSystem
        The constrained system.
    t : float
        The time.
    y : ndarray of shape (2n,)
        The state.
    p : ndarray
        The parameter vector.
    tol : float
        The tolerance on the constraints.

    Returns
    -------
    y : ndarray of shape (2n,)
        The projected state.
    converged : bool
        Whether the projection met ``tol``.
    """
    Y, changed = project_many(system, t, y, p, tol)
    return Y[0], changed


# -- checks of the initial state ----------------------------------------------------------------------
def _where(eom: EquationsOfMotion, row: str) -> str:
    name = next(r.constraint for r in eom.constraints if r.name == row)
    loc = eom.model.where("constraint", name)
    return f" (declared at {loc.file}:{loc.line})" if loc.file and loc.line else ""


def check_initial(system: ConstrainedSystem, t0: float, y0: np.ndarray, p: np.ndarray) -> None:
    eom = system.eom
    n = system.n
    M, _, A, _, g, f = system.parts(t0, y0, p)
    if not (np.isfinite(M).all() and np.isfinite(A).all()):  # nan: no eigenvalue (LinAlgError), say why
        names = system.coordinates
        bad = ([f"M[{names[i]},{names[j]}]" for i, j in zip(*np.nonzero(~np.isfinite(M)), strict=True)]
               + [f"A[{k},{names[j]}]" for k, j in zip(*np.nonzero(~np.isfinite(A)), strict=True)])
        raise SimulationError(
            f"M(q, t) q'' = F + Aᵀλ is not defined at the initial state (t = {t0:.9g}): {', '.join(bad[:4])}"
            f"{f' and {len(bad) - 4} more' if len(bad) > 4 else ''} not finite; the state is outside the domain of "
            "a function of the model (log or sqrt of a non-positive number, a division by zero) or a value overflows.",
            fix="start from a state where every expression of the model is defined, or correct the expression",
            t=t0, state=np.array(y0, dtype=float))
    w = mass_eigenvalues(M)
    if not w[0] > 1e-12 * max(abs(w[-1]), 1e-300):
        raise SimulationError(f"The mass matrix M is singular at the initial state (smallest eigenvalue {w[0]:.3g}, "
                              f"largest {w[-1]:.3g}: below 1e-12 of it, singular in double precision).",
                              fix="start away from this configuration, or choose coordinates regular there; masses or "
                                  "inertias more than 1e12 apart make M singular too")
    # Redundant rows at this state: each row must add to the rank of A M⁻¹ Aᵀ.
    Wt = np.linalg.solve(M, A.T)
    scale = max(1.0, float(np.max(np.abs(A))))
    kept: list[int] = []
    for k in range(system.m):
        idx = kept + [k]
        S = A[idx] @ Wt[:, idx]
        if np.linalg.matrix_rank(S, tol=1e-9 * scale * scale / max(w[-1], 1e-300)) == len(idx):
            kept.append(k)
            continue
        others = ", ".join(f"`{system.rows[j]}`" for j in kept)
        raise SimulationError(
            f"The constraint row `{system.rows[k]}`{_where(eom, system.rows[k])} is redundant at the initial state: "
            f"its Jacobian row is a combination of those of {others}, so the multipliers are not determined there.",
            fix="start from another state, or remove the repeated constraint (or make it principal)")
    bad_f = [k for k in range(system.m) if system.holonomic[k] and abs(f[k]) > CONSISTENCY_TOL]
    bad_g = [k for k in range(system.m) if abs(g[k]) > CONSISTENCY_TOL]
    if not bad_f and not bad_g:
        return
    try:  # the nearest consistent state, as a suggestion
        fixed: np.ndarray | None = project(system, t0, y0, p, tol=1e-14)[0]
    except SimulationError:
        fixed = None
    if bad_f:
        k = bad_f[0]
        row = eom.constraints[k]
        if fixed is None:
            hint = ("give initial values that satisfy it; none was found near these (check that the constraint "
                    "has a real solution: a sum of squares cannot equal a negative number)")
        else:
            changes = [f"{c} = {fixed[i]:.15g}" for i, c in enumerate(system.coordinates)
                       if abs(fixed[i] - y0[i]) > 1e-15]
            hint = "give initial values that satisfy it, e.g. the nearest such state: " + ", ".join(changes)
        raise SimulationError(
            f"The initial state violates the holonomic constraint `{row.name}`{_where(eom, row.name)}: "
            f"`{str(row.expression).replace('**', '^')}` = {f[k]:.6g} at t = {t0:g}, not 0.",  # in the file's syntax
            fix=hint, t=t0, state=y0.copy())
    if fixed is None:  # pragma: no cover - the velocity step is linear: singular only where the rows are redundant
        fixed = np.array(y0, dtype=float)
    k = bad_g[0]
    changes = [f"{c}_dot = {fixed[n + i]:.15g}" for i, c in enumerate(system.coordinates)
               if abs(fixed[n + i] - y0[n + i]) > 1e-15]
    row = eom.constraints[k]
    what = "the time derivative of the holonomic" if row.kind == "holonomic" else "the nonholonomic"
    raise SimulationError(
        f"The initial rates violate {what} constraint `{row.name}`{_where(eom, row.name)}: "
        f"`{row.velocity}` = {g[k]:.6g} at t = {t0:g}, not 0.",
        fix="give initial rates that satisfy it, e.g. the nearest ones: " + ", ".join(changes),
        t=t0, state=y0.copy())
