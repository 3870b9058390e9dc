"""The linearized equations reduced to independent coordinates and speeds: ẋ = A x + B u.

Once `linearize` (in `_linearize`) has checked the point — dependent coordinates and speeds
chosen, rates solved, residual force zero, multipliers λ0 found — the steps here take the
Jacobians of the equations there and reduce them, each a named step as SymPy's `Linearizer`
forms its block and coefficient matrices:

1. `velocity_maps`: δq̇ = C δu + S W δq, C = [I; −A_d⁻¹ A_i], S the map −A_d⁻¹ into the
   dependent rows.
2. `jacobians`: D_f = −∂F/∂q̇, K_f = −∂F/∂q − Σ_k λ0_k ∂A_k/∂q, B_f = ∂F/∂u, W = ∂(A q̇ + b)/∂q.
3. `coordinate_map`: δq = P δq_i, P = [I; −Φ_d⁻¹ Φ_i] (implicit-function theorem).
4. `reduced_matrices`: J = S W and M_r = Cᵀ M0 C, C_r = Cᵀ (M0 J + D_f) C,
   K_r = Cᵀ [K_f + (M0 J + D_f) J] P, B_r = Cᵀ B_f.
5. `state_matrices`: A = [[(J P)_i, C_i], [−M_r⁻¹ K_r, −M_r⁻¹ C_r]], B = [[0], [M_r⁻¹ B_r]].
6. `ignorable` and `second_order`: the coordinates nothing depends on, and
   M δq̈ + (D + G) δq̇ + (K + N) δq = B u when the reduced equations are second order.

References: Meirovitch, *Methods of Analytical Dynamics* (1970), ch. 6; Meijaard et al.,
Proc. R. Soc. A 463 (2007) 1955–1982, §4.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ._linear_algebra import jacobian as _jacobian
from ._linear_algebra import solve as _solve
from ._linear_algebra import stack as _stack
from ._linear_algebra import sub as _sub
from ._linear_algebra import tidy as _tidy
from ._linear_model import SecondOrderForm

__all__ = ["Reduced", "coordinate_map", "ignorable", "jacobians", "multipliers", "reduced_matrices", "second_order",
           "state_matrices", "velocity_maps"]

#: The reduced matrices of step 4 and the kinematic rows (C_i, (J P)_i) of the independent coordinates.
Reduced = tuple[se.DenseMatrix, se.DenseMatrix, se.DenseMatrix, se.DenseMatrix,
                tuple[se.DenseMatrix, se.DenseMatrix]]


def velocity_maps(A_at: se.DenseMatrix, ind_s: list[int], dep_s: list[int], n: int) -> tuple[se.DenseMatrix, se.DenseMatrix]:
    """C = ∂q̇/∂u (n × p) and S (n × m): δq̇_d = −A_d⁻¹ (A_i δu + W δq) placed in the dependent rows."""
    m = A_at.rows
    if not m:
        return se.eye(n), se.zeros(n, 0)
    Ad = _sub(A_at, list(range(m)), dep_s)
    Ai = _sub(A_at, list(range(m)), ind_s) if ind_s else se.zeros(m, 0)
    Ad_inv = _solve(Ad, se.eye(m))
    C = _stack(n, ind_s, se.eye(len(ind_s)), dep_s, -(Ad_inv * Ai)) if ind_s else se.zeros(n, 0)
    S = _stack(n, ind_s, se.zeros(len(ind_s), m), dep_s, -Ad_inv)
    return C, S


def multipliers(A_at: se.DenseMatrix, F0: se.DenseMatrix) -> se.DenseMatrix:
    """λ0 with F0 + A0ᵀ λ0 = 0 (least squares; exact at a steady point)."""
    AAT = A_at * A_at.T
    return _solve(AAT, -(A_at * F0))


def jacobians(eom: EquationsOfMotion, F_p: Sequence[se.Basic], dF_dq: se.DenseMatrix, u_syms: Sequence[se.Symbol],
              lam0: se.DenseMatrix, psubs: Mapping[se.Basic, se.Basic], at_all: Mapping[se.Basic, se.Basic],
              ) -> tuple[se.DenseMatrix, se.DenseMatrix, se.DenseMatrix, se.DenseMatrix | None]:
    """Step 2: (K_f, D_f, B_f, W) at the point, with the parameters' values ``psubs``.

    K_f = −∂F/∂q − Σ_k λ0_k ∂A_k/∂q (the multipliers' forces Aᵀ λ0 vary with q), D_f = −∂F/∂q̇,
    B_f = ∂F/∂u (n × 0 without inputs) and W = ∂(A q̇ + b)/∂q (None without constraint rows).
    ``dF_dq`` is ∂F/∂q at the point, already taken to check the residual.
    """
    q, qd, rows = eom.q, eom.qd, eom.constraints
    n, m = len(q), len(rows)
    qs, qds = list(q), list(qd)
    Kf = -dF_dq
    W = None
    if m:
        lamA = [se.Add(*[lam0[k, 0] * rows[k].coefficients[i].subs(psubs) for k in range(m)]) for i in range(n)]
        Kf = Kf - _jacobian(lamA, qs, at_all)
        vel = [se.Add(*[r.coefficients[i] * qd[i] for i in range(n)], r.b).subs(psubs) for r in rows]
        W = _jacobian(vel, qs, {**at_all})
    Df = -_jacobian(F_p, qds, at_all)
    Bf = _jacobian(F_p, u_syms, at_all) if u_syms else se.zeros(n, 0)
    return Kf, Df, Bf, W


def coordinate_map(A_at: se.DenseMatrix, holo: Sequence[int], dep_c: Sequence[int], ind_c: Sequence[int],
                   n: int) -> se.DenseMatrix:
    """Step 3: P with δq = P δq_i; the holonomic rows Φ δq = 0 give δq_d = −Φ_d⁻¹ Φ_i δq_i."""
    h = len(holo)
    if not h:
        return se.eye(n)
    Phi = _sub(A_at, list(holo), list(range(n)))
    Phi_d = _sub(Phi, list(range(h)), list(dep_c))
    Phi_i = _sub(Phi, list(range(h)), list(ind_c))
    dq_d = -_solve(Phi_d, Phi_i)
    return _stack(n, ind_c, se.eye(len(ind_c)), dep_c, dq_d)


def reduced_matrices(M0: se.DenseMatrix, Kf: se.DenseMatrix, Df: se.DenseMatrix, Bf: se.DenseMatrix,
                     W: se.DenseMatrix | None, Csym: se.DenseMatrix, S: se.DenseMatrix, P: se.DenseMatrix,
                     ind_c: Sequence[int]) -> Reduced:
    """Step 4: the dynamics projected on the admissible velocities (Cᵀ A0ᵀ = 0 removes δλ).

    With J = S W (δq̇ = C δu + J δq; 0 without constraint rows),

        M_r = Cᵀ M0 C,  C_r = Cᵀ (M0 J + D_f) C,  K_r = Cᵀ [K_f + (M0 J + D_f) J] P,  B_r = Cᵀ B_f,

    and the kinematic rows of the independent coordinates, δq̇_i = C_i δu + (J P)_i δq_i.
    """
    n = M0.rows
    J = S * W if W is not None else se.zeros(n, n)
    MJD = M0 * J + Df
    Mr = Csym.T * M0 * Csym
    Cr = Csym.T * MJD * Csym
    Kr = Csym.T * (Kf + MJD * J) * P
    Br = Csym.T * Bf
    kin_c = (_sub(Csym, list(ind_c), list(range(Csym.cols))), _sub(J * P, list(ind_c), list(range(P.cols))))
    return Mr, Cr, Kr, Br, kin_c


def state_matrices(reduced: Reduced, n_inputs: int) -> tuple[se.DenseMatrix, se.DenseMatrix]:
    """Step 5: ẋ = A x + B u on x = (δq_i, δu), tidied.

        A = [[(J P)_i, C_i], [−M_r⁻¹ K_r, −M_r⁻¹ C_r]],   B = [[0], [M_r⁻¹ B_r]].
    """
    Mr, Cr, Kr, Br, kin_c = reduced
    ni, nu = kin_c[1].rows, Mr.rows
    Minv_C = _solve(Mr, Cr)
    Minv_K = _solve(Mr, Kr)
    Minv_B = _solve(Mr, Br) if Br.cols else se.zeros(nu, 0)
    A = se.zeros(ni + nu, ni + nu)
    for r in range(ni):
        for c in range(ni):
            A[r, c] = kin_c[1][r, c]
        for c in range(nu):
            A[r, ni + c] = kin_c[0][r, c]
    for r in range(nu):
        for c in range(ni):
            A[ni + r, c] = -Minv_K[r, c]
        for c in range(nu):
            A[ni + r, ni + c] = -Minv_C[r, c]
    B = se.zeros(ni + nu, n_inputs)
    for r in range(nu):
        for c in range(n_inputs):
            B[ni + r, c] = Minv_B[r, c]
    return _tidy(A), _tidy(B)


def ignorable(An: np.ndarray, ni: int, names: Sequence[str]) -> tuple[str, ...]:
    """Coordinates nothing depends on, found repeatedly: the bicycle's y first (δẏ = v δψ is its
    only use of ψ), then its heading ψ."""
    keep = list(range(An.shape[0]))
    out: list[int] = []
    changed = True
    while changed:
        changed = False
        for c in range(ni):
            if c in keep and not np.any(An[np.ix_(keep, [c])]):
                keep.remove(c)
                out.append(c)
                changed = True
    return tuple(names[c] for c in sorted(out))


def _rounding_to_zero(skew: se.DenseMatrix, whole: se.DenseMatrix) -> se.DenseMatrix:
    """The skew part of a numeric matrix (a point held by computed torques) with its rounding dropped:
    entries below 1e-12 of the matrix's largest are 0, so that a symmetric K does not show N ≈ 1e−16."""
    entries = [whole[i, j] for i in range(whole.rows) for j in range(whole.cols)]
    if any(e.free_symbols for e in entries) or any(skew[i, j].free_symbols for i in range(skew.rows)
                                                   for j in range(skew.cols)):
        return skew
    try:
        scale = max((abs(float(e)) for e in entries), default=0.0)
    except (TypeError, RuntimeError):  # complex or not a number: left as it is
        return skew
    return skew.applyfunc(lambda e: se.Integer(0) if abs(float(e)) <= 1e-12 * scale else e)


def second_order(coords: Sequence[str], ind_c: Sequence[int], ind_s: Sequence[int], reduced: Reduced,
                 ignorable: Sequence[str]) -> tuple[SecondOrderForm | None, str]:
    """M δq̈ + (D + G) δq̇ + (K + N) δq = B u on the coordinates whose rates are the independent speeds.

    It exists when every other independent coordinate is ignorable (a zero column of A): then
    δq̇_c = δu_c for the coordinates kept and the reduced equations are second order in them.
    D, K are the symmetric and G, N the skew-symmetric parts of C_r and K_r (damping, stiffness,
    gyroscopic, circulatory).
    """
    Mr, Cr, Kr, Br, _ = reduced
    speeds_coord = list(ind_s)  # the coordinate index of each independent speed
    kept = [i for i in speeds_coord if i in ind_c]
    if len(kept) != len(speeds_coord):
        return None, ("an independent speed is the rate of a dependent coordinate: the reduced equations are "
                      "first order only")
    others = [c for c in ind_c if c not in speeds_coord]
    if any(coords[c] not in ignorable for c in others):
        return None, ("an independent coordinate whose rate is not an independent speed acts on the motion: "
                      "the reduced equations are first order only (see A)")
    cols = [list(ind_c).index(i) for i in kept]
    K_full = _sub(Kr, list(range(Kr.rows)), cols)
    Msym = Mr
    Dsym = (Cr + Cr.T) / 2
    Gskew = (Cr - Cr.T) / 2
    Ksym = (K_full + K_full.T) / 2
    Nskew = (K_full - K_full.T) / 2
    Gskew, Nskew = _rounding_to_zero(Gskew, Cr), _rounding_to_zero(Nskew, K_full)
    form = SecondOrderForm(tuple(coords[i] for i in kept), _tidy(Msym), _tidy(Dsym), _tidy(Gskew), _tidy(Ksym),
                           _tidy(Nskew), _tidy(Br))
    return form, ""
