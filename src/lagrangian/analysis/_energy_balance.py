"""The energy balance dE/dt = P_nc, for systems whose energy is not a first integral.

With E = T + U (U the sum of the potentials of the conservative loads), the Lagrange
equations L(q_i) multiplied by q̇_i and summed give, with T = T2 + T1 + T0 (the parts of
degree 2, 1, 0 in q̇):

    Σ q̇_i Γ_i = d/dt(T2 − T0) + ∂T/∂t,     Σ q̇_i (−∂U/∂q_i) = −dU/dt + ∂U/∂t

so that along every motion

    dE/dt = Σ_loads Σ_i Q_i q̇_i  +  Σ ∂U/∂t  +  [d/dt(T1 + 2 T0) − ∂T/∂t]  −  Σ_k λ_k b_k

* the first sum is the real power of each non-conservative effort (friction, dampers,
  driving forces, Coriolis forces — zero for those);
* ∂U/∂t is the explicit time dependence of a potential (a field that changes with time,
  the entrainment potential of an accelerated frame);
* the bracket is the real power of the constraint efforts that impose a prescribed motion
  (rheonomic constraints: a pivot moved by hand, a frame turned at a given rate); it is
  zero when the constraints do not depend on t (then T = T2);
* the last sum is the real power of the reactions of complementary constraints
  (multipliers λ_k, rows A_k q̇ + b_k = 0 of ``eom.constraints``): Σ_k λ_k A_k·q̇, which
  along every motion that satisfies the constraints is −Σ_k λ_k b_k — zero for a
  constraint that does not depend on t (b_k ≡ 0: a scleronomic reaction does no real
  power, as `first_integrals` assumes when it offers E).

The bracket holds q̈ (through dT1/dt); it is replaced by M⁻¹(F + Aᵀλ), so every term is a
function of q, q̇, t (and λ).  When P_nc ≡ 0 — and only then — E is constant: this is the
balance to report when `first_integrals` offers no energy integral.
"""

from __future__ import annotations

from dataclasses import dataclass

import symengine as se

from .._identity import are_zero
from ..dynamics import EquationsOfMotion
from ..model.vectors import is_structural_zero, sum_of

__all__ = ["PowerTerm", "EnergyBalance", "energy_balance"]


@dataclass(frozen=True, slots=True)
class PowerTerm:
    """One contribution to dE/dt: ``power`` (a function of q, q̇, t) and where it comes from.

    Parameters
    ----------
    name : str
        The load, for a ``"load"`` term; else a name for the term.
    kind : str
        ``"load"`` (real power Σ Q_i q̇_i of a non-conservative load), ``"explicit time"`` (∂U/∂t of
        a conservative load), ``"prescribed motion"`` (power of the constraints that impose a motion
        depending on t) or ``"constraint"`` (real power −λ_k b_k = λ_k A_k·q̇ of a complementary
        constraint's reaction).
    power : SymEngine expression
        The power, a function of q, q̇ and t.
    note : str
        Where it comes from, in words.
    """

    name: str
    kind: str
    power: se.Basic
    note: str


@dataclass(frozen=True, slots=True)
class EnergyBalance:
    """The balance dE/dt = ``P_nc`` along every motion, with E = T + U.

    Parameters
    ----------
    E : SymEngine expression
        T + U, the energy whose rate is balanced.
    terms : tuple of PowerTerm
        The contributions to its rate, in the order of the loads.
    P_nc : SymEngine expression
        Σ of the terms' powers.
    conserved : bool
        P_nc ≡ 0 (E is then a first integral).
    """

    E: se.Basic
    terms: tuple[PowerTerm, ...]
    P_nc: se.Basic
    conserved: bool

    def term(self, name: str) -> PowerTerm:
        for t in self.terms:
            if t.name == name:
                return t
        raise KeyError(name)


def accelerations(eom: EquationsOfMotion) -> tuple[se.Basic, ...]:
    """q̈ = M⁻¹(F + Aᵀλ), symbolically (λ the multipliers of the complementary rows, if any)."""
    n = len(eom.q)
    rhs = list(eom.F)
    for row in eom.constraints:
        rhs = [r + row.multiplier * a for r, a in zip(rhs, row.coefficients, strict=True)]
    if n == 1:
        return (rhs[0] / eom.M[0][0],)
    solution = se.DenseMatrix(eom.M).LUsolve(se.DenseMatrix(n, 1, rhs))
    return tuple(solution[i, 0] for i in range(n))


def _prescribed_motion_power(eom: EquationsOfMotion) -> se.Basic | None:
    """d/dt(T1 + 2 T0) − ∂T/∂t with q̈ eliminated, or None when T = T2 and ∂T/∂t ≡ 0."""
    kin = eom.kinematics
    n = len(eom.q)
    T = eom.T
    half = se.Rational(1, 2)
    T2 = sum_of([half * eom.M[i][j] * kin.qd[i] * kin.qd[j] for i in range(n) for j in range(n)
                 if not is_structural_zero(eom.M[i][j])])
    T0 = T.subs({qd: 0 for qd in kin.qd})
    T1 = T - T2 - T0
    dT_dt = T.diff(kin.t)
    t1_zero, t0_zero, explicit_zero = are_zero([T1, T0, dT_dt])
    if t1_zero and t0_zero and explicit_zero:
        return None
    K = sum_of(([] if t1_zero else [T1]) + ([] if t0_zero else [2 * T0]))
    rate = sum_of([K.diff(q) * qd for q, qd in zip(kin.q, kin.qd, strict=True)] + [K.diff(kin.t)])
    by_acceleration = [K.diff(qd) for qd in kin.qd]
    if not all(are_zero(by_acceleration)):
        rate = rate + sum_of([c * a for c, a in zip(by_acceleration, accelerations(eom), strict=True)])
    return rate - dT_dt


def energy_balance(eom: EquationsOfMotion) -> EnergyBalance:
    """The power P_nc with dE/dt = P_nc for E = T + U, term by term (see the module docstring).

    Parameters
    ----------
    eom : EquationsOfMotion
        The derivation (`lagrangian.derive`), in R0 or in a non-Galilean frame R (then T is T(Σ/R)
        and the inertial loads appear among the terms).

    Returns
    -------
    EnergyBalance
        E, the power terms and their sum P_nc; ``conserved`` when P_nc ≡ 0.

    Examples
    --------
    >>> import lagrangian
    >>> b = energy_balance(lagrangian.derive(lagrangian.lagrange_top()))
    >>> b.terms, b.conserved
    ((), True)
    """
    kin = eom.kinematics
    terms: list[PowerTerm] = []
    for f in eom.loads:
        if f.potential is None:
            power = sum_of([Q * qd for Q, qd in zip(f.Q, kin.qd, strict=True) if not is_structural_zero(Q)])
            works = not are_zero([power])[0]
            terms.append(PowerTerm(f.name, "load", power if works else se.Integer(0),
                                   f"real power Σ Q_i q̇_i of `{f.name}`"
                                   + ("" if works else ": it does no work")))
        else:
            explicit = f.potential.diff(kin.t)
            if not is_structural_zero(explicit) and not are_zero([explicit])[0]:
                terms.append(PowerTerm(f"∂U/∂t ({f.name})", "explicit time", explicit,
                                       f"the potential of `{f.name}` depends on t explicitly"))
    prescribed = _prescribed_motion_power(eom)
    if prescribed is not None:
        terms.append(PowerTerm("prescribed motion", "prescribed motion", prescribed,
                               "d/dt(T1 + 2 T0) − ∂T/∂t: real power of the constraint efforts that impose a "
                               "motion depending on t (rheonomic constraints)"))
    for row, b_zero in zip(eom.constraints, are_zero([row.b for row in eom.constraints]), strict=True):
        # λ_k A_k·q̇ = −λ_k b_k on the motions that satisfy the row (A_k q̇ + b_k = 0).
        power = se.Integer(0) if b_zero else -row.multiplier * row.b
        terms.append(PowerTerm(f"λ ({row.name})", "constraint", power,
                               f"real power λ_k A_k·q̇ = −λ_k b_k of the reaction of complementary constraint "
                               f"`{row.name}`" + (": b_k = 0, it does no work" if b_zero else "")))
    P_nc = sum_of([t.power for t in terms if not is_structural_zero(t.power)])
    return EnergyBalance(eom.T + eom.U, tuple(terms), P_nc, are_zero([P_nc])[0])
