"""Steady motions by Routh's reduction: the Routhian, the effective potential, and its equilibria.

When coordinates c are cyclic (∂L/∂c = 0 and Q_c(nc) = 0), their momenta p_c = ∂T/∂ċ are
constants P (the seed's K and H).  With T = ½ q̇ᵀ M q̇ + B·q̇ + T0 the momenta are linear in ċ,

    P = M_cc ċ + M_cr ṙ + B_c    ⇒    ċ = M_cc⁻¹ (P − B_c − M_cr ṙ),

and the Routhian R(r, ṙ; P) = L − P·ċ (with ċ so eliminated) is a Lagrangian of the remaining
coordinates r alone (Routh 1877; Goldstein, *Classical Mechanics*, §8.3; Landau–Lifshitz §41):

    R = ½ ṙᵀ a(r) ṙ + (gyroscopic terms linear in ṙ) − U_eff(r; P),
    a = M_rr − M_rc M_cc⁻¹ M_cr,    U_eff = ½ (P − B_c)ᵀ M_cc⁻¹ (P − B_c) − T0 + U.

A *steady motion* — r constant, the cyclic coordinates turning at constant rates — is an
equilibrium of U_eff: ∂U_eff/∂r = 0, which, with P = M_cc ċ + B_c, is a relation between r0 and
the rates ċ (the top's steady precession: m g a = ψ̇ (C ω3 − A ψ̇ cos θ0), ω3 = φ̇ + ψ̇ cos θ0).
Routh's theorem: it is stable (at fixed momenta) when U_eff has a strict minimum there.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import symengine as se
import sympy
from symengine.lib.symengine_wrapper import sympy2symengine

from .._identity import are_zero
from ..dynamics import EquationsOfMotion
from ._effective_potential import StructureError

__all__ = ["RouthReduction", "SteadyMotion", "routh_reduction", "steady_motions"]


@dataclass(frozen=True, slots=True)
class RouthReduction:
    """The Routhian of the remaining coordinates at fixed cyclic momenta (module docstring).

    Parameters
    ----------
    cyclic : tuple of str
        The cyclic coordinates.
    remaining : tuple of str
        The remaining coordinates r.
    momenta : tuple of SymEngine Symbol
        The symbols of the constants P_c (the model's momentum names: K, H, ...).
    rates : tuple of SymEngine expressions
        The cyclic rates ċ_c(r, ṙ, P).
    inertia : SymEngine DenseMatrix
        The inertia a(r).
    effective_potential : SymEngine expression
        The effective potential U_eff(r; P).
    routhian : SymEngine expression
        The Routhian R(r, ṙ; P).
    conditions : tuple of SymEngine expressions
        ∂U_eff/∂r_j with P = M_cc ċ + B_c at ṙ = 0: a steady motion makes them all zero (expressions
        in r and the cyclic rates ċ).
    """

    cyclic: tuple[str, ...]
    remaining: tuple[str, ...]
    momenta: tuple[se.Symbol, ...]
    rates: tuple[se.Basic, ...]
    inertia: se.DenseMatrix
    effective_potential: se.Basic
    routhian: se.Basic
    conditions: tuple[se.Basic, ...]


@dataclass(frozen=True, slots=True)
class SteadyMotion:
    """A steady motion: the remaining coordinates' values, the cyclic rates, the momenta, and Routh's verdict.

    Parameters
    ----------
    coordinates : dict of str to float
        The remaining coordinates' values.
    rates : dict of str to float
        The cyclic rates.
    momenta : dict of str to float
        The momenta.
    stiffness : ndarray
        ∂²U_eff/∂r² at the point (fixed momenta).
    stable : bool or None
        A strict minimum of U_eff: True; a negative eigenvalue: False; else None.
    reason : str
        Routh's verdict, in words.
    """

    coordinates: dict[str, float]
    rates: dict[str, float]
    momenta: dict[str, float]
    stiffness: np.ndarray  # ∂²U_eff/∂r² at the point (fixed momenta)
    stable: bool | None  # strict minimum of U_eff: True; a negative eigenvalue: False; else None
    reason: str


def _simplify(e: se.Basic) -> se.Basic:
    """A SymPy tidy-up (together, trigsimp, factor) when it is shorter; these expressions are small."""
    try:
        s = sympy.factor(sympy.trigsimp(sympy.together(e._sympy_())))
        out = sympy2symengine(s)
    except (TypeError, ValueError, RuntimeError, NotImplementedError, AttributeError):  # pragma: no cover
        return e
    return out if len(str(out)) < len(str(e)) else e


def routh_reduction(eom: EquationsOfMotion) -> RouthReduction:
    """Reduce ``eom`` by its cyclic coordinates (Routh).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.

    Returns
    -------
    RouthReduction
        The Routhian and the conditions of steady motion.

    Raises
    ------
    StructureError
        No cyclic coordinate, no coordinate left, or complementary constraints (their multipliers
        are not eliminated by this reduction).
    """
    if eom.constraints:
        raise StructureError("Routh's reduction needs a model without complementary constraints.",
                             fix="keep the constraints principal, or linearize about the steady motion instead")
    kin = eom.kinematics
    n = kin.n
    tests = []
    for eq in eom.equations:
        tests += [eq.dT_dq - eq.dU_dq, eq.Q_nc]
    zero = are_zero(tests)
    cyc = [i for i in range(n) if zero[2 * i] and zero[2 * i + 1]]
    rem = [i for i in range(n) if i not in cyc]
    names = eom.coordinates
    if not cyc or not rem:
        raise StructureError(f"Routh's reduction needs cyclic coordinates and others: here "
                             f"{'none is cyclic' if not cyc else 'every coordinate is cyclic'}.",
                             fix="for an equilibrium, use lagrangian.equilibria or lagrangian.linearize")
    M = se.DenseMatrix([list(r) for r in eom.M])
    zero_rates = {qd: 0 for qd in kin.qd}
    B = [eom.T.diff(qd).subs(zero_rates) for qd in kin.qd]
    T0 = eom.T.subs(zero_rates)

    def block(rows, cols):
        return se.DenseMatrix([[M[i, j] for j in cols] for i in rows])

    Mcc, Mcr, Mrr = block(cyc, cyc), block(cyc, rem), block(rem, rem)
    coords = {c.name: c for c in eom.model.coordinates}
    P = [se.Symbol(coords[names[i]].momentum or f"p_{names[i]}") for i in cyc]
    Bc = se.DenseMatrix([[B[i]] for i in cyc])
    Pv = se.DenseMatrix([[p] for p in P])
    rd = se.DenseMatrix([[kin.qd[i]] for i in rem])
    Mcc_inv = Mcc.inv(method="LU")
    cdot = Mcc_inv * (Pv - Bc - Mcr * rd)
    rates = tuple(_simplify(cdot[k, 0]) for k in range(len(cyc)))
    a = Mrr - Mcr.T * Mcc_inv * Mcr
    inertia = se.DenseMatrix([[_simplify(a[i, j]) for j in range(len(rem))] for i in range(len(rem))])
    w = Pv - Bc
    U_eff = _simplify((w.T * Mcc_inv * w)[0, 0] / 2 - T0 + eom.U)
    L = eom.T - eom.U
    on = {kin.qd[i]: rates[k] for k, i in enumerate(cyc)}
    R = L.subs(on) - se.Add(*[p * rates[k] for k, p in enumerate(P)])
    # Steady motions: ∂U_eff/∂r = 0 with P = M_cc ċ + B_c (ṙ = 0), in terms of the rates.
    momenta_of_rates = Mcc * se.DenseMatrix([[kin.qd[i]] for i in cyc]) + Bc
    P_subs = {p: momenta_of_rates[k, 0] for k, p in enumerate(P)}
    conditions = tuple(_simplify(U_eff.diff(kin.q[i]).subs(P_subs)) for i in rem)
    return RouthReduction(tuple(names[i] for i in cyc), tuple(names[i] for i in rem), tuple(P), rates, inertia,
                          U_eff, R, conditions)


def steady_motions(eom: EquationsOfMotion, at: Mapping[str, float], parameters: Mapping[str, float] | None = None,
                   ) -> tuple[SteadyMotion, ...]:
    """The steady motions through ``at``, each with Routh's verdict.

    ``at`` gives every remaining coordinate's value and all cyclic rates but as many as there are
    remaining coordinates (those are solved for; real roots only).  The top,
    ``at={"theta": 0.5, "phi_dot": 80}``: the two steady precession rates ψ̇ (slow, fast).  Each comes
    with Routh's verdict from ∂²U_eff/∂r² at fixed momenta.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    at : mapping of str to float
        The values given.
    parameters : mapping of str to float, optional
        Parameter values overriding the model's.

    Returns
    -------
    tuple of SteadyMotion
        One per real root.
    """
    red = routh_reduction(eom)
    kin = eom.kinematics
    names = eom.coordinates
    values = {p.name: p.value for p in eom.model.parameters if p.value is not None}
    values.update(parameters or {})
    numbers = {se.Symbol(k): v for k, v in values.items()}
    missing = [r for r in red.remaining if r not in at]
    if missing:
        raise StructureError(f"the steady motion needs the value of `{missing[0]}`.", fix=f"give `{missing[0]}`")
    rate_names = [c + "_dot" for c in red.cyclic]
    unknown = [r for r in rate_names if r not in at]
    if len(unknown) != len(red.remaining):
        raise StructureError(f"give {len(rate_names) - len(red.remaining)} of the cyclic rates "
                             f"{', '.join(rate_names)}; the other {len(red.remaining)} are solved for.",
                             fix="e.g. the spin, and the precession rate is found")
    subs = dict(numbers)
    subs.update({kin.q[names.index(r)]: at[r] for r in red.remaining})
    subs.update({se.Symbol(r): at[r] for r in rate_names if r in at})
    eqs = [c.subs(subs)._sympy_() for c in red.conditions]
    unknowns = [sympy.Symbol(u) for u in unknown]
    solutions = sympy.solve(eqs, unknowns, dict=True)
    out = []
    for sol in solutions:
        vals = {str(k): complex(v.evalf()) for k, v in sol.items()}
        if any(abs(v.imag) > 1e-12 * max(1.0, abs(v.real)) for v in vals.values()):
            continue
        rates = {r: float(at[r]) if r in at else vals[r].real for r in rate_names}
        out.append(_verdict(eom, red, {r: float(at[r]) for r in red.remaining}, rates, numbers))
    return tuple(out)


def _verdict(eom: EquationsOfMotion, red: RouthReduction, coords: dict[str, float], rates: dict[str, float],
             numbers: dict) -> SteadyMotion:
    kin = eom.kinematics
    names = eom.coordinates
    point = {kin.q[names.index(r)]: v for r, v in coords.items()}
    point.update({kin.qd[names.index(c)]: rates[c + "_dot"] for c in red.cyclic})
    point.update({kin.qd[names.index(r)]: 0.0 for r in red.remaining})
    momenta = {}
    for c, P in zip(red.cyclic, red.momenta, strict=True):
        p = eom.equations[names.index(c)].dT_dqd
        momenta[str(P)] = float(p.subs(numbers).subs(point))
    P_subs = {se.Symbol(k): v for k, v in momenta.items()}
    r_syms = [kin.q[names.index(r)] for r in red.remaining]
    U = red.effective_potential.subs(numbers).subs(P_subs)
    H = np.array([[float(U.diff(a).diff(b).subs(point)) for b in r_syms] for a in r_syms])
    eig = np.linalg.eigvalsh((H + H.T) / 2)
    scale = max(1.0, float(np.abs(H).max()))
    if eig.min() > 1e-12 * scale:
        stable, why = True, ("U_eff has a strict minimum at fixed momenta (∂²U_eff/∂r² positive definite): the "
                             "steady motion is stable (Routh's theorem)")
    elif eig.min() < -1e-12 * scale and len(red.remaining) == 1:
        stable, why = False, ("U_eff has a maximum at fixed momenta (∂²U_eff/∂r² < 0): with one remaining "
                              "coordinate the Routhian has no gyroscopic force, so the steady motion is unstable")
    elif eig.min() < -1e-12 * scale:
        stable, why = None, ("∂²U_eff/∂r² has a negative eigenvalue: U_eff is not a minimum at fixed momenta, "
                             "but the Routhian's gyroscopic terms may still stabilise it (lagrangian.linearize decides)")
    else:
        stable, why = None, "∂²U_eff/∂r² is singular: higher orders decide"
    return SteadyMotion(coords, rates, momenta, H, stable, why)
