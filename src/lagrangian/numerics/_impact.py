"""Lagrange's equations in impulsive form, and the contact problems they lead to (linear complementarity).

**Impacts.** Over an impact of vanishing duration the positions do not change and every finite
force does no impulse, so integrating L(q_i) across it leaves only the percussions P_k of the
contacts (the theorem of percussions in Lagrange's form; Pfeiffer & Glocker, *Multibody Dynamics
with Unilateral Contacts*, ch. 6; Brogliato, *Nonsmooth Mechanics*, ch. 4):

    M(q) (q̇⁺ − q̇⁻) = Σ_k A_kᵀ P_k + A_Bᵀ P_B,           A_B q̇⁺ + b_B = 0   (bilateral rows kept)

with, for every contact k whose gap is closed (g_k = 0), its normal velocity s_k = A_k q̇ + b_k
and Newton's law  s_k⁺ ≥ −e_k s_k⁻,  P_k ≥ 0,  P_k (s_k⁺ + e_k s_k⁻) = 0  (an impacting contact
with s_k⁻ < 0; a resting one has target 0).  With Coulomb friction at a contact its tangential
percussion P_t is bounded, |P_t| ≤ μ P_k: it sticks (w⁺ = 0) or slides (P_t = −μ P_k sign w⁺).
Eliminating q̇⁺ gives a linear complementarity problem in the percussions alone,

    w = W z + q ≥ 0,   z ≥ 0,   zᵀ w = 0,       W = J N Jᵀ,   q = J q̇⁻ + b_J − target,

where J stacks the normal (and tangential) rows of the candidate contacts and
N = M⁻¹ − M⁻¹A_Bᵀ(A_B M⁻¹ A_Bᵀ)⁻¹A_B M⁻¹ is the inverse inertia left by the bilateral rows
(`delassus`), so that q̇⁺ = q̇⁻ + N Jᵀ z.  W is symmetric positive semi-definite, so without
friction the post-impact velocity is unique (the minimum of the kinetic-energy distance
½(q̇⁺ − q̇⁻)ᵀM(q̇⁺ − q̇⁻) under A q̇⁺ ≥ −e s⁻), and T⁺ − T⁻ = ½ Σ_k P_k (s_k⁺ + s_k⁻): when the
contacts that receive a percussion approach (s_k⁻ ≤ 0) it is −½ Σ_k (1 − e_k) P_k |s_k⁻| ≤ 0 for
e ≤ 1 (the simulation warns of any increase).

**Persistent contact.** The same W decides which contacts stay closed in a smooth motion: with
the accelerations a = J q̈ + ċ of the closed gaps, a = a_free + W λ ≥ 0, λ ≥ 0, λᵀa = 0
(and a_t = 0, |λ_t| ≤ μ λ while a contact with friction sticks).

Both are solved exactly: by enumeration of the contacts' modes (open, closed or sticking,
sliding either way) for small sets (`enumerate_modes`), by Lemke's complementary pivoting for
larger frictionless ones (`lemke`).  A problem with no solution (two contacts that ask for
opposite velocities of one coordinate) is a `SimulationError`.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence

import numpy as np

from ..errors import SimulationError

__all__ = [
    "CLOSED",
    "MAX_COMBINATIONS",
    "MODE_NAMES",
    "OPEN",
    "SLIDE_NEG",
    "SLIDE_POS",
    "delassus",
    "enumerate_modes",
    "lemke",
    "solve_lcp",
]

#: A contact's mode: open (no percussion), closed (normal row active; sticking when it has friction),
#: sliding with w⁺ ≥ 0 (P_t = −μ P_n) or with w⁺ ≤ 0 (P_t = +μ P_n).
OPEN, CLOSED, SLIDE_POS, SLIDE_NEG = 0, 1, 2, 3
MODE_NAMES = {OPEN: "open", CLOSED: "closed", SLIDE_POS: "sliding +", SLIDE_NEG: "sliding -"}
#: Most mode combinations enumerated; beyond, a frictionless problem goes to `lemke`.
MAX_COMBINATIONS = 4096
#: Condition number above which a combination's linear system counts as singular (solved by least squares,
#: kept only when consistent).
SINGULAR_COND = 1e12


def delassus(M: np.ndarray, J: np.ndarray, A_b: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(W, X): W = J N Jᵀ and X = N Jᵀ, N the inverse inertia left by the bilateral rows A_b (module docstring).

    A unit percussion z_k on row k changes the velocities by X[:, k]; X solves
    [M −A_bᵀ; A_b 0][X; Y] = [Jᵀ; 0], so the bilateral rows keep holding after the impact.
    """
    rhs = J.T if A_b is None or not len(A_b) else np.concatenate([J.T, A_b.T], axis=1)
    Y = np.linalg.solve(M, rhs)
    X = Y[:, :J.shape[0]]
    if A_b is not None and len(A_b):
        Y_b = Y[:, J.shape[0]:]
        X = X - Y_b @ np.linalg.solve(A_b @ Y_b, A_b @ X)
    return J @ X, X


def _combination(W: np.ndarray, q: np.ndarray, modes: Sequence[int], mu: np.ndarray,
                 tangent: Sequence[int]) -> np.ndarray | None:
    """z for one mode per contact (the equations of its closed and sticking rows), or None when singular."""
    r = len(q)
    eq_rows: list[int] = []
    columns: list[np.ndarray] = []
    for i, mode in enumerate(modes):
        if mode == OPEN:
            continue
        col = np.zeros(r)
        col[i] = 1.0
        eq_rows.append(i)
        t = tangent[i]
        if t >= 0:
            if mode == CLOSED:  # sticking: the tangential row is an equation, its percussion an unknown
                stick = np.zeros(r)
                stick[t] = 1.0
                columns.append(col)
                columns.append(stick)
                eq_rows.append(t)
                continue
            col[t] = -mu[i] if mode == SLIDE_POS else mu[i]
        columns.append(col)
    if not columns:
        return np.zeros(r)
    E = np.column_stack(columns)
    K = W[eq_rows] @ E
    rhs = -q[eq_rows]
    if np.linalg.cond(K) <= SINGULAR_COND:
        return E @ np.linalg.solve(K, rhs)
    # Dependent rows (a block flat on the ground: four rows, three coordinates): the reactions are not unique;
    # the least-norm ones are kept when the equations are consistent (statically indeterminate, not impossible).
    y = np.linalg.lstsq(K, rhs, rcond=None)[0]
    if np.linalg.norm(K @ y - rhs) > 1e-9 * (np.linalg.norm(rhs) + np.linalg.norm(K) * np.linalg.norm(y) + 1e-300):
        return None
    return E @ y


def _feasible(z: np.ndarray, w: np.ndarray, modes: Sequence[int], mu: np.ndarray, tangent: Sequence[int],
              tol_w: np.ndarray, tol_z: float) -> bool:
    for i, mode in enumerate(modes):
        t = tangent[i]
        if mode == OPEN:
            if w[i] < -tol_w[i]:
                return False
            continue
        if z[i] < -tol_z:
            return False
        if t < 0:
            continue
        if mode == CLOSED and abs(z[t]) > mu[i] * max(z[i], 0.0) + tol_z:
            return False
        if mode == SLIDE_POS and w[t] < -tol_w[t]:
            return False
        if mode == SLIDE_NEG and w[t] > tol_w[t]:
            return False
    return True


def enumerate_modes(W: np.ndarray, q: np.ndarray, *, mu: np.ndarray | None = None,
                    tangent: Sequence[int] | None = None, allowed: Sequence[Sequence[int]] | None = None,
                    order: Callable[[tuple[int, ...]], float] | None = None, tol_w: np.ndarray | None = None,
                    tol_z: float | None = None, choose: Callable[[np.ndarray], float] | None = None
                    ) -> tuple[np.ndarray, tuple[int, ...]] | None:
    """An exact solution of the contact problem by trying every combination of modes.

    Parameters
    ----------
    W, q : the problem w = W z + q (rows: one normal row per contact, 0..m−1, then the tangential rows).
    mu : μ per contact (unused where it has no tangential row).
    tangent : per contact, the index of its tangential row in W, or −1.
    allowed : per contact, the modes to try (default: open/closed, and the two slides with friction).
    order : sort key of a combination; the first feasible one in that order is returned, unless
        ``choose`` is given: then every feasible combination is scored by ``choose(z)`` and the
        smallest wins (ties keep ``order``).
    tol_w, tol_z : feasibility tolerances of w (per row) and of the percussions.

    Returns
    -------
    (z, modes), or None when no combination is feasible.
    """
    m = len(q) if tangent is None else len(tangent)
    tangent = list(tangent) if tangent is not None else [-1] * m
    mu = np.zeros(m) if mu is None else np.asarray(mu, dtype=float)
    if allowed is None:
        allowed = [(OPEN, CLOSED, SLIDE_POS, SLIDE_NEG) if tangent[i] >= 0 else (OPEN, CLOSED) for i in range(m)]
    scale = float(np.max(np.abs(q), initial=0.0))
    tol_w = np.full(len(q), 1e-9 * scale) if tol_w is None else tol_w
    combos = list(itertools.product(*allowed))
    if order is not None:
        combos.sort(key=order)
    best: tuple[float, np.ndarray, tuple[int, ...]] | None = None
    for modes in combos:
        z = _combination(W, q, modes, mu, tangent)
        if z is None or not np.isfinite(z).all():
            continue
        w = W @ z + q
        tz = 1e-9 * float(np.max(np.abs(z), initial=0.0)) if tol_z is None else tol_z
        if not _feasible(z, w, modes, mu, tangent, tol_w, tz):
            continue
        if choose is None:
            return z, tuple(modes)
        score = choose(z)
        if best is None or score < best[0] - 1e-12 * abs(best[0]):
            best = (score, z, tuple(modes))
    return None if best is None else (best[1], best[2])


def lemke(W: np.ndarray, q: np.ndarray, max_pivots: int = 1000) -> np.ndarray | None:
    """z ≥ 0 with w = W z + q ≥ 0 and zᵀw = 0 by Lemke's complementary pivoting, or None (ray: no solution).

    The classical scheme with the covering vector 1 and an artificial variable z0 (Cottle, Pang &
    Stone, *The Linear Complementarity Problem*, Sec. 4.4); it ends in a solution for every
    positive semi-definite W whose problem is feasible.
    """
    n = len(q)
    if np.all(q >= 0):
        return np.zeros(n)
    # Tableau rows: w − W z − 1 z0 = q; columns: w (0..n−1), z (n..2n−1), z0 (2n), rhs (2n+1).
    T = np.zeros((n, 2 * n + 2))
    T[:, :n] = np.eye(n)
    T[:, n:2 * n] = -W
    T[:, 2 * n] = -1.0
    T[:, -1] = q
    basis = list(range(n))
    row = int(np.argmin(q))
    entering = 2 * n

    def pivot(r: int, c: int) -> None:
        T[r] /= T[r, c]
        for i in range(n):
            if i != r and T[i, c] != 0.0:
                T[i] -= T[i, c] * T[r]

    leaving = basis[row]
    pivot(row, entering)
    basis[row] = entering
    tol = 1e-12 * max(1.0, float(np.abs(W).max(initial=0.0)), float(np.abs(q).max()))
    for _ in range(max_pivots):
        entering = leaving + n if leaving < n else leaving - n  # the complement of the variable that left
        col = T[:, entering]
        ratios = np.where(col > tol, T[:, -1] / np.where(col > tol, col, 1.0), np.inf)
        if not np.isfinite(ratios).any():
            return None  # secondary ray: no solution
        best = np.min(ratios)
        candidates = np.flatnonzero(ratios <= best + tol)
        # Prefer z0 leaving: the solution is then reached.
        row = next((int(r) for r in candidates if basis[r] == 2 * n), int(candidates[0]))
        leaving = basis[row]
        pivot(row, entering)
        basis[row] = entering
        if leaving == 2 * n:
            z = np.zeros(n)
            for r, var in enumerate(basis):
                if n <= var < 2 * n:
                    z[var - n] = T[r, -1]
            return z
    return None


def solve_lcp(W: np.ndarray, q: np.ndarray, *, mu: np.ndarray | None = None, tangent: Sequence[int] | None = None,
              allowed: Sequence[Sequence[int]] | None = None, order: Callable[[tuple[int, ...]], float] | None = None,
              tol_w: np.ndarray | None = None, tol_z: float | None = None,
              choose: Callable[[np.ndarray], float] | None = None, what: str = "the contact problem"
              ) -> tuple[np.ndarray, tuple[int, ...]] | None:
    """`enumerate_modes` for small sets, `lemke` for larger frictionless ones (module docstring)."""
    m = len(q) if tangent is None else len(tangent)
    has_friction = tangent is not None and any(t >= 0 for t in tangent)
    count = int(np.prod([len(a) for a in allowed])) if allowed is not None else \
        (4 ** m if has_friction else 2 ** m)
    if count <= MAX_COMBINATIONS:
        return enumerate_modes(W, q, mu=mu, tangent=tangent, allowed=allowed, order=order, tol_w=tol_w, tol_z=tol_z,
                               choose=choose)
    if has_friction:
        raise SimulationError(f"{what} has {m} contacts with friction closing at once ({count} combinations of "
                              f"their modes, more than {MAX_COMBINATIONS}).",
                              fix="make some of these contacts frictionless, or avoid that they close together")
    z = lemke(W, q)
    if z is None:
        return None
    w = W @ z + q
    return z, tuple(CLOSED if z[i] > 0 or abs(w[i]) <= 1e-9 * max(1.0, abs(q[i])) else OPEN for i in range(m))
