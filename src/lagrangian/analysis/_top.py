"""The heavy symmetric top analysed the way a textbook does: U_eff, turning angles, nutation, precession.

Generic route (any model with one remaining coordinate θ, every other one cyclic; see
`reduce_cyclic`): E = ½ a(θ) θ̇² + U_eff(θ).  With the parameter values and the initial
state, θ moves between the turning angles θ1 ≤ θ2 where U_eff(θ) = E;

* nutation period  T = 2 ∫_{θ1}^{θ2} dθ / θ̇,  θ̇ = sqrt(2(E − U_eff(θ))/a(θ));
* mean rate of each cyclic coordinate ⟨ċ⟩ = (2/T) ∫_{θ1}^{θ2} ċ(θ) dθ / θ̇ (the mean
  precession rate ⟨ψ̇⟩ for the top);
* the apex of the axis draws waves, loops or cusps as the precession rate
  ψ̇ = (K − H cosθ)/(A sin²θ) keeps its sign, changes sign, or vanishes at a turning angle.

Closed forms, when the model *is* a symmetric top (T = ½A(θ̇² + ψ̇² sin²θ) + ½C(φ̇ + ψ̇ cosθ)²,
U = U0 + m g a cosθ, detected on the mass matrix and U; C absent for a spherical pendulum):
with u = cosθ and E' = E − H²/(2C) − U0,

    u̇² = f(u) = (2E' − 2 m g a u)(1 − u²)/A − ((K − H u)/A)²,

a cubic whose two roots in [−1, 1] bracketing cosθ0 give θ1, θ2 (Viète's trigonometric
formula), and T = 2∫ du/sqrt(f) = 4 K(k)/sqrt(|α|(u3 − u1)) with α = 2 m g a/A and
k² the ratio of the physical root span to u3 − u1 (Goldstein, Classical Mechanics, §5.7).

Sleeping top (θ = 0 or π, where det M_cc = 0, with the momenta that state allows, K = H):
stable when U_eff''(θ_s) > 0; for the top at θ = 0 this is C²ω² > 4 A m g a, ω = H/C.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import symengine as se
from scipy import special

from .._identity import are_zero
from ..dynamics import EquationsOfMotion
from ..errors import AnalysisError
from ._effective_potential import (
    Curve,
    CyclicReduction,
    EffectivePotential,
    SingularPassage,
    StructureError,
    reduce_cyclic,
    tidy,
    turning_points,
    well_integrals,
)

__all__ = ["TopAnalysis", "TopForm", "NutationCubic", "Nutation", "SleepingTop", "SteadyPrecession",
           "analyse_top", "AnalysisError", "StructureError"]

#: |ψ̇| at a turning angle below this fraction of the larger one counts as zero (a cusp):
#: the turning angles are found to ~1e-15, so a true zero shows as ~1e-15 relative.
CUSP_TOLERANCE = 1e-8
#: det M_cc below this fraction of the product of its diagonal (its Hadamard bound) at θ0:
#: the cyclic momenta do not determine the rates there (a sleeping position, θ0 = 0 or π).
SINGULAR_RTOL = 1e-12
#: Safety factor on the rounding noise of E − U_eff (a few ulps of the level per evaluation).
NOISE_ULPS = 64


@dataclass(frozen=True, slots=True)
class TopForm:
    """A symmetric top's constants, read from M and U: A = M_θθ, C = M_φφ, U = U0 + (m g a) cosθ."""

    A: se.Basic
    C: se.Basic | None
    mga: se.Basic
    U0: se.Basic
    values: tuple[float, float | None, float, float]  # A, C, m g a, U0 as numbers


@dataclass(frozen=True, slots=True)
class NutationCubic:
    """u̇² = f(u) = c3 u³ + c2 u² + c1 u + c0 (u = cosθ): its roots, θ1, θ2 and the elliptic period."""

    coefficients: tuple[float, float, float, float]  # c3, c2, c1, c0
    reduced_energy: float  # E' = E − H²/(2C) − U0
    roots: tuple[float, ...]  # real roots, increasing
    physical: tuple[float, float]  # the two that bracket cosθ0
    theta1: float
    theta2: float
    period: float  # 4K(k)/sqrt(|α|(u3 − u1)), or 2π/sqrt(−c2) when m g a = 0
    modulus: float | None  # k² (scipy.special.ellipk's m)


@dataclass(frozen=True, slots=True)
class Nutation:
    """θ between θ1 and θ2: period, mean cyclic rates, the apex curve."""

    theta1: float
    theta2: float
    period: float
    mean_rates: dict[str, float]
    turning_rates: tuple[float, float]  # precession rate at θ1 and at θ2
    apex_curve: str  # "waves", "loops", "cusps", "circle" (steady precession) or "plane"
    apex_reason: str
    steady: bool  # θ1 = θ2 to the resolution of E − U_eff: a circle
    method: str  # "quadrature" or "small oscillations" (nutation too small for quadrature)


@dataclass(frozen=True, slots=True)
class SleepingTop:
    """Stability of the sleeping state θ = θ_s (0 or π) with the spin of the motion analysed."""

    theta: float
    stiffness: se.Basic  # U_eff''(θ_s) with K = K_s, symbolic in H and the parameters
    stiffness_value: float
    stable: bool | None  # None: U_eff'' = 0, undecided at second order
    spin: float | None  # ω = H/C
    criterion: tuple[float, float] | None  # (C²ω², 4 A m g a cosθ_s): stable iff the first is larger
    critical_spin: float | None  # ω_c = sqrt(4 A m g a cosθ_s)/C when that is real


@dataclass(frozen=True, slots=True)
class SteadyPrecession:
    """θ̇ = 0 circles at θ0 with the same spin momentum: the two precession rates (None if not real)."""

    theta: float
    rates: tuple[float, float] | None


@dataclass(frozen=True, slots=True)
class TopAnalysis:
    """Everything `analyse_top` finds; see the module docstring for the formulas.

    Parameters
    ----------
    reduction : CyclicReduction
        The reduction to θ.
    parameters : dict of str to float
        The parameter values used.
    initial : dict of str to float
        The initial state.
    constants : dict of str to float
        K, H, E at the initial state.
    rates : dict of str to SymEngine expression
        The cyclic rates ċ_i(θ, θ̇, K, H), tidied.
    inertia : SymEngine expression
        The inertia a(θ).
    effective_potential : SymEngine expression
        The effective potential U_eff(θ, K, H), tidied.
    U_eff : EffectivePotential
        The same with the numbers in, callable.
    nutation : Nutation or None
        The nutation; None when θ0 is a sleeping position (det M_cc = 0).
    top : TopForm or None
        The symmetric top's closed forms, when it is one.
    cubic : NutationCubic or None
        The cubic in u = cos θ, for a symmetric top.
    sleeping : tuple of SleepingTop
        The sleeping positions and their stability.
    steady : SteadyPrecession or None
        The steady precession.
    notes : tuple of str
        Remarks on the analysis.
    """

    reduction: CyclicReduction
    parameters: dict[str, float]
    initial: dict[str, float]
    constants: dict[str, float]  # K, H, E at the initial state
    rates: dict[str, se.Basic]  # ċ_i(θ, θ̇, K, H), tidied
    inertia: se.Basic  # a(θ)
    effective_potential: se.Basic  # U_eff(θ, K, H), tidied
    U_eff: EffectivePotential  # the same with the numbers in, callable
    nutation: Nutation | None  # None when θ0 is a sleeping position (det M_cc = 0)
    top: TopForm | None
    cubic: NutationCubic | None
    sleeping: tuple[SleepingTop, ...]
    steady: SteadyPrecession | None
    notes: tuple[str, ...]

    @property
    def theta1(self) -> float:
        return self._nutation().theta1

    @property
    def theta2(self) -> float:
        return self._nutation().theta2

    @property
    def period(self) -> float:
        return self._nutation().period

    @property
    def precession_rate(self) -> float:
        """⟨ψ̇⟩, the mean rate of the precession coordinate over a nutation period."""
        return self._nutation().mean_rates[self.reduction.precession]

    @property
    def apex_curve(self) -> str:
        return self._nutation().apex_curve

    def _nutation(self) -> Nutation:
        if self.nutation is None:
            raise AnalysisError(f"There is no nutation to describe: {self.notes[0]}",
                                fix="start with the axis away from θ = 0 or π, and with K ≠ ±H")
        return self.nutation


def _values(eom: EquationsOfMotion, parameters: Mapping[str, float] | None,
            initial: Mapping[str, float] | None) -> tuple[dict[str, float], dict[str, float]]:
    given = dict(parameters or {})
    known = [p.name for p in eom.model.parameters]
    state_names = list(eom.coordinates) + [c + "_dot" for c in eom.coordinates]
    for values, names, what in ((given, known, "parameter"), (dict(initial or {}), state_names, "coordinate or rate")):
        unknown = sorted(set(values) - set(names))
        if unknown:
            raise AnalysisError(f"`{unknown[0]}` is not a {what} of `{eom.model.name}`.",
                                fix="known names: " + ", ".join(names))
    params = {}
    for p in eom.model.parameters:
        v = given.get(p.name, p.value)
        if v is None or not math.isfinite(float(v)):
            raise AnalysisError(f"The parameter `{p.name}` has no finite value.",
                                fix=f"give it a value in the model file or with `--set {p.name}=...`")
        params[p.name] = float(v)
    overrides = dict(initial or {})
    state = {}
    for c in eom.model.coordinates:
        for key, default in ((c.name, c.initial), (c.name + "_dot", c.rate)):
            v = overrides.get(key, default)
            if v is None or not math.isfinite(float(v)):
                raise AnalysisError(f"`{key}` has no finite initial value.",
                                    fix=f"give it in the model file or with `--set {key}=...`")
            state[key] = float(v)
    return params, state


def _top_form(red: CyclicReduction, eom: EquationsOfMotion, numbers: dict[se.Basic, float]) -> TopForm | None:
    """The symmetric top's A, C, m g a when T and U have its form exactly (course convention, θ from z0)."""
    if red.energy_name != "E" or len(red.cyclic) > 2:
        return None
    th = red.symbol
    r = eom.coordinates.index(red.coordinate)
    coupling = [eom.M[eom.coordinates.index(c)][r] for c in red.cyclic]
    A = eom.M[r][r]
    ip = red.cyclic.index(red.precession)
    checks = [A.diff(th), *coupling]
    C = None
    if red.spin is not None:
        is_ = red.cyclic.index(red.spin)
        C = red.block[is_][is_]
        checks += [C.diff(th), red.block[ip][is_] - C * se.cos(th),
                   red.block[ip][ip] - A * se.sin(th) ** 2 - C * se.cos(th) ** 2]
    else:
        checks.append(red.block[0][0] - A * se.sin(th) ** 2)
    U = red.regular_part
    up, down = _at(U, th, se.Integer(0)), _at(U, th, se.pi)
    if up is None or down is None:  # U undefined at a pole (cos(log θ)): not the top's U0 + m g a cos θ
        return None
    U0, mga = se.expand((up + down) / 2), se.expand((up - down) / 2)
    checks.append(U - U0 - mga * se.cos(th))
    if not all(are_zero(checks)):
        return None
    vals = tuple(None if x is None else float(x.subs(numbers)) for x in (A, C, mga, U0))
    return TopForm(A, C, mga, U0, vals)  # type: ignore[arg-type]


def _cubic_roots(c: tuple[float, float, float, float]) -> tuple[float, ...]:
    """Real roots of c3 u³ + c2 u² + c1 u + c0, by Viète's trigonometric formula, polished by Newton."""
    c3, c2, c1, c0 = c
    if c3 == 0.0:
        disc = c1 * c1 - 4 * c2 * c0
        if c2 == 0.0 or disc < 0:
            return ()
        roots = [(-c1 - math.copysign(math.sqrt(disc), c1)) / (2 * c2)]
        roots.append(c0 / (c2 * roots[0]) if roots[0] != 0 else -c1 / c2)
        return tuple(sorted(roots))
    b, cc, d = c2 / c3, c1 / c3, c0 / c3
    p = cc - b * b / 3
    q = 2 * b**3 / 27 - b * cc / 3 + d
    if p >= 0:  # one real root (not the nutation case, where f(±1) ≤ 0 ≤ f(cosθ0))
        return tuple(np.sort(np.roots(c)[np.abs(np.roots(c).imag) < 1e-12].real))
    r = 2 * math.sqrt(-p / 3)
    arg = max(-1.0, min(1.0, 3 * q / (p * r)))
    phase = math.acos(arg) / 3
    roots = [r * math.cos(phase - 2 * math.pi * k / 3) - b / 3 for k in range(3)]
    polished = []
    for u in roots:
        for _ in range(3):
            f, df = ((c3 * u + c2) * u + c1) * u + c0, (3 * c3 * u + 2 * c2) * u + c1
            if df == 0:
                break
            step = f / df
            if abs(step) > 1e-6 * (1 + abs(u)):  # near a double root Newton wanders: keep Viète's value
                break
            u -= step
        polished.append(u)
    return tuple(sorted(polished))


def _cubic(top: TopForm, K: float, H: float, theta0: float, rate0: float) -> NutationCubic | None:
    A, C, mga, U0 = top.values
    # E' = E − H²/(2C) − U0, written from the initial state rather than as a difference of
    # the (much larger) E and H²/(2C).
    u0, s0 = math.cos(theta0), math.sin(theta0)
    Ep = 0.5 * A * rate0**2 + mga * u0 + (0.0 if s0 == 0 else (K - H * u0) ** 2 / (2 * A * s0 * s0))
    coefficients = (2 * mga / A, -2 * Ep / A - H * H / A**2, -2 * mga / A + 2 * K * H / A**2, 2 * Ep / A - K * K / A**2)
    roots = _cubic_roots(coefficients)
    if coefficients[0] == 0.0:
        if len(roots) != 2:
            return None
        lo, hi = roots
        period, modulus = 2 * math.pi / math.sqrt(-coefficients[1]), None
    else:
        if len(roots) != 3:
            return None
        u1, u2, u3 = roots
        alpha = abs(coefficients[0])
        lo, hi = (u1, u2) if coefficients[0] > 0 else (u2, u3)
        modulus = (hi - lo) / (u3 - u1)
        period = 4 * special.ellipk(modulus) / math.sqrt(alpha * (u3 - u1))
    n = round(theta0 / (2 * math.pi))
    sign = 1.0 if theta0 - 2 * math.pi * n >= 0 else -1.0
    angles = sorted(2 * math.pi * n + sign * math.acos(max(-1.0, min(1.0, u))) for u in (lo, hi))
    return NutationCubic(coefficients, Ep, roots, (lo, hi), angles[0], angles[1], float(period), modulus)


def _apex(prec: str, coordinate: str, rates: tuple[float, float], steady: bool) -> tuple[str, str]:
    r1, r2 = rates
    t1, t2 = coordinate + "1", coordinate + "2"
    scale = max(abs(r1), abs(r2))
    dot = prec + "_dot"
    if steady:
        return "circle", f"{coordinate} stays at one angle (steady precession, {dot} = {r1:.6g}): the apex draws a circle"
    if scale == 0.0:
        return "plane", f"{dot} = 0 all along: the axis swings in a fixed vertical plane"
    values = f"{dot}({t1}) = {r1:.6g}, {dot}({t2}) = {r2:.6g}"
    for t, r in ((t1, r1), (t2, r2)):
        if abs(r) <= CUSP_TOLERANCE * scale:
            return "cusps", f"{dot} vanishes at {t} ({values}): the apex stops on that circle and draws cusps"
    if r1 * r2 < 0:
        return "loops", f"{dot} changes sign between {t1} and {t2} ({values}): the apex draws loops"
    return "waves", f"{dot} keeps one sign ({values}): the apex draws waves between the two circles"


def _taylor(expr: se.Basic, x: se.Symbol, at: se.Basic, order: int) -> list[se.Basic]:
    out, d = [], expr
    for k in range(order + 1):
        out.append(se.expand(d.subs({x: at}) / math.factorial(k)))
        d = d.diff(x)
    return out


def _sleeping(red: CyclicReduction, top: TopForm | None, numbers: dict[se.Basic, float]) -> tuple[SleepingTop, ...]:
    """U_eff''(θ_s) at θ_s = 0, π where det M_cc = 0, with the momenta that state allows (K = H for the top).

    N and det M_cc both vanish to second order there, so U_eff = N/(2 det) + W is
    expanded as a quotient of Taylor series: N/det = q0 + q1 x + q2 x² + …
    """
    if not red.angle or len(red.cyclic) > 2:
        return ()
    out = []
    for theta_s, at in ((0.0, se.Integer(0)), (math.pi, se.pi)):
        try:
            entry = _sleeping_at(red, top, numbers, theta_s, at)
        except RuntimeError:  # SymEngine: an expression undefined at the pole (log θ at θ = 0)
            entry = None
        if entry is not None:
            out.append(entry)
    return tuple(out)


def _sleeping_at(red: CyclicReduction, top: TopForm | None, numbers: dict[se.Basic, float], theta_s: float,
                 at: se.Basic) -> SleepingTop | None:
    """`_sleeping` at one pole θ_s (0 or π), or None where the top cannot sleep there."""
    th, P = red.symbol, red.momentum_symbols
    ip = red.cyclic.index(red.precession)
    if not are_zero([red.determinant.subs({th: at})])[0]:
        return None
    if red.spin is not None:  # (K_s − B_ψ, H − B_φ) in the range of M_cc(θ_s)
        is_ = red.cyclic.index(red.spin)
        m_ss = red.block[is_][is_].subs({th: at})
        if are_zero([m_ss])[0]:
            return None
        K_s = red.offset[ip] + (P[is_] - red.offset[is_]) * red.block[ip][is_].subs({th: at}) / m_ss
    else:
        K_s = red.offset[ip]
    K_s = se.expand(K_s.subs({th: at}))
    n = _taylor(red.numerator.subs({P[ip]: K_s}), th, at, 4)
    d = _taylor(red.determinant, th, at, 4)
    w = _taylor(red.regular_part, th, at, 2)
    if not all(are_zero(n[:2] + d[:2])) or are_zero([d[2]])[0]:
        return None
    q0 = n[2] / d[2]
    q1 = (n[3] - q0 * d[3]) / d[2]
    q2 = (n[4] - q0 * d[4] - q1 * d[3]) / d[2]
    if not are_zero([q1 / 2 + w[1]])[0]:  # not an equilibrium of θ
        return None
    stiffness = tidy(q2 + 2 * w[2], P)
    value = float(stiffness.subs(numbers))
    stable = None if value == 0.0 else value > 0
    spin = criterion = critical = None
    if top is not None and top.C is not None:
        A, C, mga, _ = top.values
        spin = numbers[P[red.cyclic.index(red.spin)]] / C
        rhs = 4 * A * mga * math.cos(theta_s)
        criterion = ((C * spin) ** 2, rhs)  # type: ignore[operator]
        critical = math.sqrt(rhs) / C if rhs > 0 else None  # type: ignore[operator]
    return SleepingTop(theta_s, stiffness, value, stable, spin, criterion, critical)


def _steady(red: CyclicReduction, numbers: dict[se.Basic, float], theta0: float) -> SteadyPrecession | None:
    """θ̇ = 0 at θ0 with U_eff'(θ0) = 0: a quadratic in the precession momentum K (the spin kept)."""
    if len(red.cyclic) > 2:
        return None
    th = red.symbol
    K = red.momentum_of(red.precession)
    fixed = {s: v for s, v in numbers.items() if s != K}
    fixed[th] = theta0
    if abs(float(red.determinant.subs(fixed))) < 1e-12:
        return None
    slope = red.effective_potential.diff(th).subs(fixed)
    c0 = float(slope.subs({K: 0}))
    c1 = float(slope.diff(K).subs({K: 0}))
    c2 = float(slope.diff(K).diff(K).subs({K: 0})) / 2
    disc = c1 * c1 - 4 * c2 * c0
    if c2 == 0.0 or disc < 0:
        return SteadyPrecession(theta0, None)
    ks = ((-c1 - math.sqrt(disc)) / (2 * c2), (-c1 + math.sqrt(disc)) / (2 * c2))
    rate = red.rates[red.cyclic.index(red.precession)].subs({**fixed, red.rate: 0})
    values = sorted((float(rate.subs({K: k})) for k in ks), key=abs)
    return SteadyPrecession(theta0, (values[0], values[1]))


def _singular_angles(red: CyclicReduction) -> tuple[float, ...]:
    """θ = 0 and/or π when det M_cc vanishes there identically (the axis along the vertical)."""
    if not red.angle:
        return ()
    values = ((v, _at(red.determinant, red.symbol, at)) for v, at in ((0.0, se.Integer(0)), (math.pi, se.pi)))
    return tuple(v for v, det in values if det is not None and are_zero([det])[0])


def _at(e: se.Basic, symbol: se.Symbol, at: se.Basic) -> se.Basic | None:
    """e at symbol = at, or None where SymEngine finds it undefined (log θ at θ = 0: cos of an infinity)."""
    try:
        return e.subs({symbol: at})
    except RuntimeError:
        return None


def _nutation(red: CyclicReduction, curve: Curve, slopes: Curve, level: float, theta0: float,
              rate0: float) -> Nutation:
    """θ1, θ2, the period and mean rates, the apex curve.

    E − U_eff(θ) is known to about ε = NOISE_ULPS·eps·|E|.  Turning angles closer than
    the width 2 sqrt(2ε/U_eff'') of that noise are one circle (steady precession).  For a
    half-width Δ below (ε/U_eff'')^¼ the quadrature's noise, ~ε/(U_eff'' Δ²), would exceed
    the error O(Δ²) of the small-oscillation limit T = 2π sqrt(a/U_eff''), ⟨ċ⟩ = ċ(θ̄), which is
    used instead; both errors are then below about sqrt(ε/U_eff'') (~1e-7 relative).
    """
    def gap(x: npt.ArrayLike) -> float | np.ndarray:
        values = level - curve(x)[..., 0]
        return float(values) if values.ndim == 0 else values

    lo, hi = turning_points(gap, slopes.scalar, theta0, rate0, angle=red.angle, name=red.coordinate)
    for base in _singular_angles(red):  # e.g. K = H = 0: the axis swings through the vertical
        k = math.floor((lo - base) / (2 * math.pi)) + 1
        if base + 2 * math.pi * k < hi:
            value = base + 2 * math.pi * k
            raise SingularPassage(
                f"{red.coordinate} passes through {value:.6g}, where det M_cc = 0 (the axis along the vertical): "
                f"there the Euler angles are singular and {red.coordinate} does not nutate between two turning "
                "angles, so the nutation analysis does not apply.",
                fix="give the top some spin or precession (K ≠ ±H) so that the axis avoids the vertical")
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    stiffness = float(slopes(np.array([mid]))[0, 1])
    noise = NOISE_ULPS * np.finfo(float).eps * max(abs(level), np.finfo(float).tiny)
    steady = stiffness > 0 and half <= math.sqrt(2 * noise / stiffness)
    ip = red.cyclic.index(red.precession)
    if stiffness > 0 and half <= (noise / stiffness) ** 0.25:
        values = curve(np.array([theta0 if steady else mid]))[0]  # a circle stays at θ0
        period = 2 * math.pi * math.sqrt(values[1] / stiffness)
        means = {c: float(values[2 + k]) for k, c in enumerate(red.cyclic)}
        method = "small oscillations"
    else:
        totals = well_integrals(curve, level, lo, hi)
        period = float(totals[0])
        means = {c: float(totals[1 + k] / period) for k, c in enumerate(red.cyclic)}
        method = "quadrature"
    ends = curve(np.array([lo, hi]))
    turning = (float(ends[0, 2 + ip]), float(ends[1, 2 + ip]))
    kind, reason = _apex(red.precession, red.coordinate, turning, steady)
    return Nutation(lo, hi, period, means, turning, kind, reason, steady, method)


def analyse_top(eom: EquationsOfMotion, *, parameters: Mapping[str, float] | None = None,
                initial: Mapping[str, float] | None = None) -> TopAnalysis:
    """Analyse a heavy symmetric top (or any model with one remaining and the other coordinates cyclic).

    Parameters
    ----------
    eom : EquationsOfMotion
        The derived equations (``lagrangian.derive(model)``).
    parameters : mapping of str to float, optional
        Parameter values overriding the model's (``{"C": 0.02}``).
    initial : mapping of str to float, optional
        Initial-state overrides, coordinates and rates (``{"theta": 0.3, "phi_dot": 80}``).

    Returns
    -------
    TopAnalysis
        U_eff, turning angles θ1 ≤ θ2, nutation period, mean precession rate, apex curve,
        the cubic in u = cosθ (for a symmetric top), sleeping-top stability, steady precession.

    Raises
    ------
    StructureError
        The model does not have one remaining coordinate and the others cyclic, or no energy integral.
    AnalysisError
        Unknown or missing values, an unbounded motion, a motion through a singular angle.

    Examples
    --------
    >>> import lagrangian
    >>> top = analyse_top(lagrangian.derive(lagrangian.lagrange_top()), initial={"psi_dot": 0.0})
    >>> top.apex_curve, round(top.theta1, 12)
    ('cusps', 0.5)
    """
    red = reduce_cyclic(eom)
    params, state = _values(eom, parameters, initial)
    numbers: dict[se.Basic, float] = {se.Symbol(k): v for k, v in params.items()}
    at_start = {**numbers, **{q: state[c] for c, q in zip(eom.coordinates, eom.q, strict=True)},
                **{qd: state[c + "_dot"] for c, qd in zip(eom.coordinates, eom.qd, strict=True)}}
    constants = {}
    for name, symbol, expr in zip(red.momenta, red.momentum_symbols, red.momentum_expressions, strict=True):
        constants[name] = numbers[symbol] = float(expr.subs(at_start))
    constants[red.energy_name] = float(red.energy_expression.subs(at_start))
    th, theta0, rate0 = red.symbol, state[red.coordinate], state[red.coordinate + "_dot"]
    order = [red.momentum_of(red.precession)] + [s for s in red.momentum_symbols if s != red.momentum_of(red.precession)]
    U_sym = tidy(red.effective_potential, order)
    U_num = EffectivePotential(th, U_sym.subs(numbers))
    free_rates = [r.subs({red.rate: 0}) for r in red.rates]
    # The θ-free terms of U_eff (H²/(2C) for the top, often most of E) are left out of the
    # numerics, and the level is U_var(θ0) + ½ a θ̇0² on the same function: E − U_eff(θ) is
    # then computed without cancelling a large constant, and vanishes exactly at θ0 when θ̇0 = 0.
    U_var = se.Add(*(term for term in se.Add.make_args(U_sym) if th in term.free_symbols))
    curve = Curve(th, [U_var.subs(numbers), red.inertia.subs(numbers), *(r.subs(numbers) for r in free_rates)])
    start = curve(np.array([theta0]))[0]
    level = float(start[0] + 0.5 * start[1] * rate0**2)
    top = _top_form(red, eom, numbers)
    notes: list[str] = []
    nutation = cubic = None
    at0 = {**numbers, th: theta0}
    hadamard = math.prod(abs(float(red.block[i][i].subs(at0))) for i in range(len(red.cyclic)))
    if abs(float(red.determinant.subs(at0))) <= SINGULAR_RTOL * hadamard:
        notes.append(f"{red.coordinate}(0) = {theta0:g} is a sleeping position (det M_cc = 0): the Euler angles "
                     "are singular there and there is no nutation to describe; see the sleeping-top criterion.")
    else:
        slopes = Curve(th, [U_var.diff(th).subs(numbers), U_var.diff(th).diff(th).subs(numbers)])
        try:
            nutation = _nutation(red, curve, slopes, level, theta0, rate0)
        except SingularPassage as exc:
            notes.append(exc.message)
        ip = red.cyclic.index(red.precession)
        if top is not None and nutation is not None:
            ih = red.cyclic.index(red.spin) if red.spin else None
            cubic = _cubic(top, constants[red.momenta[ip]], 0.0 if ih is None else constants[red.momenta[ih]],
                           theta0, rate0)
    if top is None:
        notes.append("T and U are not exactly those of a symmetric top (½A(θ̇² + ψ̇² sin²θ) + ½C(φ̇ + ψ̇ cosθ)², "
                     "U0 + m g a cosθ), so the cubic in cosθ and the classic criteria do not apply; the generic "
                     "results do.")
    return TopAnalysis(
        reduction=red, parameters=params, initial=state, constants=constants,
        rates={c: tidy(r, order) for c, r in zip(red.cyclic, red.rates, strict=True)}, inertia=red.inertia,
        effective_potential=U_sym, U_eff=U_num, nutation=nutation, top=top, cubic=cubic,
        sleeping=_sleeping(red, top, numbers), steady=_steady(red, numbers, theta0), notes=tuple(notes))
