"""Modes and stability of a linearized motion ẋ = A x, and their change with a parameter.

**Neutral directions first.**  A state variable whose column of A is zero (an ignorable
coordinate: a shift of the bicycle's x, y, heading or wheel angles gives another steady
motion) or whose row is zero (a conserved speed: the bicycle's rear-wheel rate) carries an
eigenvalue 0 and splits off: det(A − sI) = −s det(A' − sI) with A' the matrix without that
row and column.  Conserved momenta of ignorable coordinates whose speeds stay in the state
(the top's K and H in Euler angles) carry one zero eigenvalue each.  What remains — the
*essential* eigenvalues — decides stability.

**The verdict** (Lyapunov's first method, and the classical theorems for mechanical systems):

* some Re λ > 0: unstable;
* every Re λ < 0: asymptotically stable;
* otherwise, with the second-order form M δq̈ + (D + G) δq̇ + (K + N) δq = 0 on the essential
  coordinates: Lagrange–Dirichlet (D = G = N = 0 and K = ∂²U/∂q² positive definite: U has a
  strict minimum, stable also for the nonlinear motion); Kelvin–Tait–Chetaev (gyroscopic
  forces keep a positive-definite K stable, and may stabilise an indefinite K: then every
  eigenvalue is simple and on the imaginary axis — stable to first order, the sleeping top
  when C²ω² > 4 A m g a); any other case on the imaginary axis is *marginal*: the
  linearization does not decide.

Natural frequencies ω_n = |λ|, damping ratios ζ = −Re λ/|λ|, periods 2π/|Im λ|; for a
conservative system the pulsations solve K φ = ω² M φ (a symmetric-definite problem).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se
from scipy import linalg, optimize

from ._linear_model import LinearizationError, LinearModel
from ._linear_model import to_numpy as _to_numpy
from ._zero_modes import CLUSTER_RTOL, ZeroStructure, ignorable_columns, split_off, zero_structure

__all__ = ["Mode", "Modes", "Stability", "StabilityChange", "Sweep", "eigenvalue_sweep", "modes", "stability"]

#: Relative size (to the spectral radius) below which a real part counts as zero.
AXIS_RTOL = 1e-9


@dataclass(frozen=True, slots=True)
class Mode:
    """One eigenvalue λ of A with its eigenvector.

    Parameters
    ----------
    eigenvalue : complex
        The eigenvalue λ.
    frequency : float
        The natural frequency ``ω_n = |λ|`` (rad/s).
    damped_frequency : float
        The damped frequency ``|Im λ|``.
    period : float or None
        The period ``2π/|Im λ|`` (None for a real λ).
    damping_ratio : float
        The damping ratio ``ζ = −Re λ/|λ|``.
    shape : dict of str to complex
        The eigenvector over the state, normalised so that its largest coordinate component is 1.
    """

    eigenvalue: complex
    frequency: float
    damped_frequency: float
    period: float | None
    damping_ratio: float
    shape: dict[str, complex]


@dataclass(frozen=True, slots=True)
class Modes:
    """The essential modes, the neutral directions split off, and the conservative pulsations.

    Parameters
    ----------
    state : tuple of str
        The state's names.
    essential : tuple of str
        The state variables of the essential motion.
    modes : tuple of Mode
        The essential modes.
    neutral : tuple of (str, str)
        The neutral directions split off: (state variable or "momentum", why).
    pulsations : tuple of float or None
        The pulsations ω from K φ = ω² M φ (conservative systems), ascending.
    shapes : tuple of dict of str to float, or None
        The matching φ, M-normalised.
    zero : ZeroStructure, optional
        The eigenvalue 0: its Jordan blocks, and whether it makes the motion grow.
    """

    state: tuple[str, ...]
    essential: tuple[str, ...]
    modes: tuple[Mode, ...]
    neutral: tuple[tuple[str, str], ...]  # (state variable or "momentum", why)
    pulsations: tuple[float, ...] | None  # ω from K φ = ω² M φ (conservative systems), ascending
    shapes: tuple[dict[str, float], ...] | None  # the matching φ, M-normalised
    zero: ZeroStructure | None = None  # the eigenvalue 0: its Jordan blocks, and whether it makes the motion grow

    @property
    def eigenvalues(self) -> np.ndarray:
        return np.array([m.eigenvalue for m in self.modes])


@dataclass(frozen=True, slots=True)
class Stability:
    """The verdict on a linearized motion, with its reason.

    Parameters
    ----------
    stable : bool or None
        True, False, or None (marginal: the linearization does not decide).
    verdict : str
        "asymptotically stable", "stable", "stable to first order", "unstable" or "marginal".
    reason : str
        The theorem or the eigenvalue that decides it.
    eigenvalues : ndarray
        The eigenvalues of the essential motion.
    """

    stable: bool | None
    verdict: str  # "asymptotically stable", "stable", "stable to first order", "unstable", "marginal"
    reason: str
    eigenvalues: np.ndarray


def _reduce(A: np.ndarray, state: Sequence[str], lin: LinearModel) -> tuple[list[int], list[tuple[str, str]]]:
    """Indices of the essential state, and the neutral variables split off with the reason.

    The ignorable coordinates first (`_zero_modes.ignorable_columns`: a shift of one is another
    steady motion), then, among the rest, variables whose row (conserved to first order) or column
    (acting on none of the others) is zero: each carries an eigenvalue 0, which is neutral only when
    0 is not defective (`_zero_modes.zero_structure`, checked by `_essential`).
    """
    ncoord = len(lin.coordinates)
    ign = ignorable_columns(A, ncoord)
    neutral = [(state[i], "ignorable: a shift of it is another steady motion (eigenvalue 0)") for i in ign]
    keep, split = split_off(A, [i for i in range(A.shape[0]) if i not in ign])
    for i, how in split:
        if how == "row":
            why = "conserved to first order (eigenvalue 0)"
        elif i >= ncoord:
            why = "does not act on the motion (eigenvalue 0)"
        else:
            why = "acts on none of the other variables left (eigenvalue 0)"
        neutral.append((state[i], why))
    return keep, neutral


def _momenta(lin: LinearModel, keep: Sequence[int], neutral: Sequence[tuple[str, str]]) -> int:
    """Zero eigenvalues owed to the conserved momenta of ignorable coordinates whose speed stays."""
    gone = {name for name, _ in neutral}
    state = lin.state
    return sum(1 for c in lin.ignorable if c in gone and c + "_dot" in state and state.index(c + "_dot") in keep)


def _essential(lin: LinearModel, A: np.ndarray) -> tuple[list[int], list[tuple[str, str]], np.ndarray,
                                                         ZeroStructure]:
    keep, neutral = _reduce(A, lin.state, lin)
    lam = np.linalg.eigvals(A[np.ix_(keep, keep)]) if keep else np.zeros(0, complex)
    zeros = _momenta(lin, keep, neutral)
    if zeros:
        scale = max(1.0, float(np.abs(lam).max(initial=0.0)))
        order = np.argsort(np.abs(lam))
        small = [j for j in order[:zeros] if abs(lam[j]) < 1e-7 * scale]
        if len(small) == zeros:
            lam = np.delete(lam, small)
            neutral = neutral + [("momentum", "the conserved momentum of an ignorable coordinate (eigenvalue 0)")] * zeros
    zero = zero_structure(A, lin.state, len(lin.coordinates))
    if any(b >= 2 for b in zero.blocks):  # a Jordan block of 0 split by rounding into ±1e-8: those are 0
        lam = np.where(np.abs(lam) <= CLUSTER_RTOL * max(1.0, float(np.abs(A).max(initial=0.0))), 0.0, lam)
    if zero.secular:  # the variables split off after the ignorable ones carry a defective 0: not neutral
        ign = set(ignorable_columns(A, len(lin.coordinates)))
        neutral = [(x, why) if x == "momentum" or lin.state.index(x) in ign else
                   (x, "eigenvalue 0 of a Jordan chain: not neutral (secular growth)") for x, why in neutral]
    return keep, neutral, lam, zero


def _sorted(lam: np.ndarray) -> np.ndarray:
    return lam[np.lexsort((lam.imag, lam.real))] if lam.size else lam


def modes(lin: LinearModel, **values: float) -> Modes:
    """Eigenvalues, frequencies, damping ratios and mode shapes of the essential motion.

    Parameters
    ----------
    lin : LinearModel
        The linearization.
    **values : float
        Values of the symbols it left symbolic.

    Returns
    -------
    Modes
        The modes.
    """
    A, _ = lin.numeric(**values)
    keep, neutral, lam, zero = _essential(lin, A)
    state = lin.state
    essential = tuple(state[i] for i in keep)
    out = []
    if keep:
        w, V = np.linalg.eig(A[np.ix_(keep, keep)])
        coords = [j for j, i in enumerate(keep) if not state[i].endswith("_dot")] or list(range(len(keep)))
        for k in np.argsort(np.abs(w) + 1e-300 * np.arange(len(w))):
            if not any(np.isclose(w[k], x, rtol=1e-9, atol=1e-12) for x in lam):
                continue  # a momentum's zero eigenvalue
            v = V[:, k]
            j = max(coords, key=lambda j: abs(v[j]))
            v = v / v[j] if abs(v[j]) > 0 else v
            lamk = complex(w[k])
            mag = abs(lamk)
            out.append(Mode(lamk, mag, abs(lamk.imag), 2 * np.pi / abs(lamk.imag) if lamk.imag else None,
                            -lamk.real / mag if mag else 0.0, {essential[i]: complex(v[i]) for i in range(len(keep))}))
    pulsations, shapes = _conservative(lin, values, lam)
    return Modes(state, essential, tuple(out), tuple(neutral), pulsations, shapes, zero)


def _second_order_numeric(lin: LinearModel, values: dict, essential: Sequence[str]):
    """(coordinates, M, D, G, K, N) restricted to the essential coordinates, when the essential
    state is exactly those coordinates and their rates; else None."""
    form = lin.second_order
    if form is None:
        return None
    E = [c for c in form.coordinates if c in essential]
    if sorted(essential) != sorted(E + [c + "_dot" for c in E]) or not E:
        return None
    idx = [form.coordinates.index(c) for c in E]
    subs = lin._values(values)
    mats = [_to_numpy(m, subs)[np.ix_(idx, idx)] for m in (form.M, form.D, form.G, form.K, form.N)]
    return (E, *mats)


def _conservative(lin: LinearModel, values: dict, lam: np.ndarray):
    """The pulsations ω > 0 with det(K − ω² M) = 0 and their shapes φ, for a conservative linearization
    (D = G = N = 0, K ≥ 0); else (None, None).

    The generalized eigenproblem K φ = ω² M φ is solved on every coordinate of the second-order form,
    the ignorable ones included: holding them (restricting M to the others) would give the
    pulsations with the cart held, √(g/l), not those of the motion, √((mc + m) g/(mc l)).  The zero
    roots are the neutral directions (a shift of an ignorable coordinate) and are left out.  The
    pulsations are returned only when ±iω are the essential eigenvalues of A (the same motion, read
    two ways), so that the text can never disagree with the eigenvalues.
    """
    form = lin.second_order
    if form is None or not form.coordinates:
        return None, None
    subs = lin._values(values)
    M, D, G, K, N = (_to_numpy(m, subs) for m in (form.M, form.D, form.G, form.K, form.N))
    scale = max(1.0, float(np.abs(K).max(initial=0.0)), float(np.abs(M).max(initial=0.0)))
    if any(np.abs(x).max(initial=0.0) > 1e-10 * scale for x in (D, G, N)):
        return None, None
    try:
        w2, phi = linalg.eigh(K, M)
    except (linalg.LinAlgError, ValueError):  # M not positive definite at the point
        return None, None
    spread = max(1.0, float(np.abs(w2).max(initial=0.0)))
    if np.any(w2 < -1e-10 * spread):
        return None, None
    kept = [k for k in range(len(w2)) if w2[k] > 1e-10 * spread]
    omegas = np.sqrt(w2[kept])
    radius = max(1.0, float(np.abs(lam).max(initial=0.0)))
    nonzero = np.sort(np.abs(lam[np.abs(lam) > 1e-7 * radius].imag))
    if np.any(np.abs(lam[np.abs(lam) > 1e-7 * radius].real) > 1e-7 * radius) or \
            not np.allclose(nonzero, np.sort(np.repeat(omegas, 2)), rtol=1e-6, atol=1e-9 * radius):
        return None, None  # not ±iω: the second-order form and A do not describe the same motion here
    E = form.coordinates
    return tuple(float(w) for w in omegas), tuple({c: float(phi[i, k]) for i, c in enumerate(E)} for k in kept)


def stability(lin: LinearModel, **values: float) -> Stability:
    """The verdict on the linearized motion, with the theorem or the eigenvalue that decides it.

    Parameters
    ----------
    lin : LinearModel
        The linearization.
    **values : float
        Values of the symbols it left symbolic.

    Returns
    -------
    Stability
        The verdict.
    """
    A, _ = lin.numeric(**values)
    keep, neutral, lam, zero = _essential(lin, A)
    lam = _sorted(lam)
    note = ""
    if neutral:
        names = ", ".join(sorted({n for n, _ in neutral if n != "momentum"}))
        moms = sum(1 for n, _ in neutral if n == "momentum")
        parts = [f"{names} neutral (eigenvalue 0: ignorable or conserved)"] if names else []
        if moms:
            parts.append(f"{moms} conserved {'momenta' if moms > 1 else 'momentum'} (eigenvalue 0)")
        note = " Set aside: " + "; ".join(parts) + "."
    if zero.secular and not (lam.size and float(lam.real.max()) > AXIS_RTOL * max(1.0, float(np.abs(lam).max()))):
        return Stability(False, "unstable (secular growth)", _secular(zero), lam)
    if lam.size == 0:
        return Stability(None, "marginal", "every direction is neutral: the linearization does not decide." + note, lam)
    radius = max(1.0, float(np.abs(lam).max()))
    tol = AXIS_RTOL * radius
    worst = lam[np.argmax(lam.real)]
    so = _second_order_numeric(lin, dict(values), tuple(lin.state[i] for i in keep))
    if worst.real > tol:
        why = f"the eigenvalue {_c(worst)} has a positive real part, so small motions grow (Lyapunov's first method)."
        if so is not None:
            _, _, D, G, K, N = so
            kmin = float(np.linalg.eigvalsh((K + K.T) / 2).min())
            small = max(1e-10 * float(np.abs(K).max(initial=1.0)), 0.0)
            if kmin < -small and np.abs(D).max(initial=0) <= small and np.abs(N).max(initial=0) <= small:
                why = (f"K has a negative eigenvalue ({kmin:.6g}): U_P has no minimum there"
                       + (", and the gyroscopic terms do not stabilise it" if np.abs(G).max(initial=0) > small else "")
                       + f"; the eigenvalue {_c(worst)} has a positive real part: unstable.")
        return Stability(False, "unstable", why + note, lam)
    if worst.real < -tol:
        return Stability(True, "asymptotically stable",
                         f"every eigenvalue has a negative real part (the largest is {worst.real:.6g}): small motions "
                         "decay, asymptotically stable (Lyapunov's first method)." + note, lam)
    if so is not None:
        E, M, D, G, K, N = so
        scale = max(float(np.abs(K).max(initial=0.0)), float(np.abs(M).max(initial=0.0)), 1e-300)
        small = 1e-10 * scale
        kmin = float(np.linalg.eigvalsh((K + K.T) / 2).min())
        no_D, no_N, no_G = (float(np.abs(x).max(initial=0.0)) <= small for x in (D, N, G))
        if no_D and no_N and kmin > small:
            if no_G and any(n != "momentum" and not n.endswith("_dot") for n, _ in neutral):
                names = ", ".join(E)
                return Stability(True, "stable",
                                 f"K = ∂²U/∂q², restricted to the coordinates left once the neutral ones are set aside "
                                 f"({names}), is positive definite: U_P has a strict minimum in them, and the "
                                 "equilibrium is stable in them (Lagrange–Dirichlet), also for the nonlinear motion; "
                                 "the neutral directions may drift (a shift along one is another equilibrium)." + note,
                                 lam)
            if no_G:
                return Stability(True, "stable",
                                 "K = ∂²U/∂q² is positive definite: U_P has a strict minimum at the equilibrium, "
                                 "which is stable (Lagrange–Dirichlet), also for the nonlinear motion." + note, lam)
            return Stability(True, "stable",
                             "K is positive definite and the other terms are gyroscopic (G skew), which do no work: "
                             "stable (Kelvin–Tait–Chetaev)." + note, lam)
        if no_D and no_N and not no_G and _simple_on_axis(lam, tol):
            return Stability(True, "stable to first order",
                             f"K is not positive definite (its smallest eigenvalue is {kmin:.6g}), but the gyroscopic "
                             "terms make every eigenvalue simple and purely imaginary: gyroscopic stabilisation "
                             "(Kelvin–Tait). Stable to first order; the nonlinear motion is not decided by the "
                             "linearization." + note, lam)
    # (Routh's reading needs a Lagrangian system: conservative, and no nonholonomic row, which
    # keeps the energy but not the Lagrangian structure of the reduced equations.)
    if _simple_on_axis(lam, tol) and lin.eom.conservative and all(r.kind == "holonomic" for r in lin.eom.constraints):
        return Stability(True, "stable to first order",
                         "the system is conservative and every eigenvalue left is simple and purely imaginary: the "
                         "linearized motion is bounded (stable to first order; at fixed momenta this is Routh's "
                         "condition on the effective potential)." + note, lam)
    if _simple_on_axis(lam, tol):
        return Stability(None, "marginal",
                         "every eigenvalue is on the imaginary axis: the linearized motion is bounded but the "
                         "linearization does not decide the nonlinear stability (marginal case)." + note, lam)
    return Stability(None, "marginal",
                     "an eigenvalue on the imaginary axis is repeated or zero: the linearization does not decide "
                     "(marginal case)." + note, lam)


def _secular(zero: ZeroStructure) -> str:
    """Why a defective eigenvalue 0 makes the linearized motion grow."""
    size = max(zero.blocks)
    power = "t" if zero.growth == 1 else f"t^{zero.growth}"
    return (f"the eigenvalue 0 is defective: once the ignorable coordinates are set aside, A has a Jordan block "
            f"of size {size} for it (blocks {', '.join(map(str, zero.blocks))}), so a perturbation of {zero.start} "
            f"makes {zero.end} grow like {power}. A shift along such a direction is not another steady motion, and "
            "the linearized motion is unbounded although no eigenvalue has a positive real part (secular growth).")


def _simple_on_axis(lam: np.ndarray, tol: float) -> bool:
    if np.any(np.abs(lam.real) > tol) or np.any(np.abs(lam) <= tol):
        return False
    d = np.abs(lam[:, None] - lam[None, :]) + np.eye(len(lam)) * 1e300
    return bool(d.min() > 1e3 * tol) if len(lam) > 1 else True


def _c(z: complex) -> str:
    return f"{z.real:.6g}" if z.imag == 0 else f"{z.real:.6g} {'+' if z.imag > 0 else '−'} {abs(z.imag):.6g} i"


# -- sweeps ---------------------------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class StabilityChange:
    """Where the essential spectrum changes along a sweep.

    Parameters
    ----------
    value : float
        The parameter's value there.
    kind : str
        ``"stability lost"``, ``"stability gained"``, ``"eigenvalues become complex"``,
        ``"eigenvalues become real"``, ``"becomes asymptotically stable"`` or ``"asymptotic stability
        lost"``.
    eigenvalues : ndarray
        The essential eigenvalues there.
    """

    value: float
    kind: str
    eigenvalues: np.ndarray


@dataclass(frozen=True, slots=True)
class Sweep:
    """The essential eigenvalues of A against one parameter (rows: ``values``).

    Parameters
    ----------
    parameter : str
        The parameter's name.
    values : ndarray of shape (m,)
        Its grid.
    eigenvalues : ndarray of shape (m, k), complex
        Each row sorted by real then imaginary part.
    stable : ndarray of shape (m,)
        1 stable, 0 unstable, NaN marginal.
    changes : tuple of StabilityChange
        Where the spectrum changes.
    """

    parameter: str
    values: np.ndarray
    eigenvalues: np.ndarray  # (len(values), k) complex, each row sorted by real then imaginary part
    stable: np.ndarray  # (len(values),) float: 1 stable, 0 unstable, nan marginal
    changes: tuple[StabilityChange, ...]


def _compiled(lin: LinearModel, name: str, fixed: dict[str, float]):
    """A(value) as a compiled function of the swept parameter (one SymEngine Lambdify, CSE)."""
    syms = {str(s): s for s in lin.symbols}
    if name not in syms:
        known = ", ".join(syms) or "none"
        raise LinearizationError(f"`{name}` is not a symbol of this linearization (symbolic parameters: {known}).",
                                 fix=f"linearize with symbolic=('{name}',) (`--sweep` does it), or sweep a parameter "
                                     "the matrices depend on")
    subs = {syms[k]: float(v) for k, v in fixed.items() if k != name}
    missing = [k for k in syms if k != name and syms[k] not in subs]
    if missing:
        raise LinearizationError(f"the parameter `{missing[0]}` has no value.", fix=f"give it one: `{missing[0]}=...`")
    A = lin.A.subs(subs) if subs else lin.A
    n = A.rows
    flat = [A[i, j] for i in range(n) for j in range(n)]
    try:
        fn = se.Lambdify([syms[name]], flat, cse=True, backend="llvm")
    except (RuntimeError, ValueError, TypeError):  # pragma: no cover - SymEngine built without LLVM
        fn = se.Lambdify([syms[name]], flat, cse=True)
    return lambda x: np.asarray(fn([x]), dtype=float).reshape(n, n)


def _bisect(same_as_left, a: float, b: float) -> float:
    """The point between a and b where ``same_as_left`` turns false, to the last representable digit."""
    lo, hi = a, b
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if same_as_left(mid):
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def eigenvalue_sweep(lin: LinearModel, name: str, values: Sequence[float] | np.ndarray, **fixed: float) -> Sweep:
    """The essential eigenvalues against the parameter ``name``, and where stability changes.

    The linearization must keep ``name`` symbolic (``linearize(..., symbolic=(name,))``); A is
    compiled once.  Between grid points where the verdict (spectral abscissa max Re λ) changes
    sign, the crossing is found by Brent's method; where the number of non-real eigenvalues
    changes (a pair merging on the real axis, the bicycle's weave at 0.684 m/s), by bisection
    to the last representable digit.  ``lagrangian.sweep`` (`lagrangian.numerics.sweep`) calls
    it for a linearization, and maps a contact model's impacts instead.

    Parameters
    ----------
    lin : LinearModel
        A linearization that keeps ``name`` symbolic.
    name : str
        The parameter.
    values : sequence of float or ndarray
        Its grid.
    **fixed : float
        Values of the other symbols left symbolic.

    Returns
    -------
    Sweep
        The eigenvalues over the grid and where stability changes.
    """
    if not isinstance(lin, LinearModel):
        raise LinearizationError(f"eigenvalue_sweep() takes a linearization, not a {type(lin).__name__}.",
                                 fix='e.g. eigenvalue_sweep(linearize(eom, point, symbolic=("Omega",)), "Omega", '
                                     'values); for a model with unilateral contacts, lagrangian.sweep(model, "e", '
                                     'values, t_end=10)')
    grid = np.asarray(values, dtype=float)
    if grid.ndim != 1 or grid.size == 0:
        raise LinearizationError("the sweep has no point.", fix="give a range with at least one value, e.g. v=0:10:0.01")
    A_of = _compiled(lin, name, fixed)
    rng = np.random.default_rng(7)
    probe = [A_of(float(x)) for x in rng.uniform(grid.min(), grid.max() + 1.0, 2)]
    keep0, neutral0 = _reduce(np.abs(probe[0]) + np.abs(probe[1]), lin.state, lin)
    zeros = _momenta(lin, keep0, neutral0)

    def essential(x: float) -> np.ndarray:
        A = A_of(x)[np.ix_(keep0, keep0)]
        lam = np.linalg.eigvals(A) if keep0 else np.zeros(0, complex)
        if zeros:
            order = np.argsort(np.abs(lam))
            lam = np.delete(lam, order[:zeros])
        return _sorted(lam)

    eig = np.array([essential(float(x)) for x in grid])

    def abscissa(x: float) -> float:
        lam = essential(x)
        return float(lam.real.max()) if lam.size else 0.0

    def complex_count(x: float) -> int:
        return int(np.count_nonzero(essential(x).imag))

    alpha = np.array([float(row.real.max()) if row.size else 0.0 for row in eig])
    counts = np.array([int(np.count_nonzero(row.imag)) for row in eig])
    tol = AXIS_RTOL * max(1.0, float(np.abs(eig).max(initial=0.0)))

    def side(a: float) -> int:
        """−1: every eigenvalue in the left half-plane; 0: the rightmost on the axis; +1: one to the right."""
        return -1 if a < -tol else (1 if a > tol else 0)

    sides = np.array([side(a) for a in alpha])
    stable = np.where(sides < 0, 1.0, np.where(sides > 0, 0.0, np.nan))
    changes: list[StabilityChange] = []
    for k in range(len(grid) - 1):
        a, b = float(grid[k]), float(grid[k + 1])
        if sides[k] != sides[k + 1]:
            if sides[k] * sides[k + 1] < 0:  # through the axis: Brent on the spectral abscissa
                x = optimize.brentq(abscissa, a, b, xtol=1e-14, rtol=4 * np.finfo(float).eps, maxiter=200)
            else:  # onto or off the axis (a conservative system losing its minimum): bisection on the side
                x = _bisect(lambda v, s=sides[k]: side(abscissa(v)) == s, a, b)
            before, after = sides[k], sides[k + 1]
            kind = ("stability lost" if after > 0 else "stability gained" if before > 0
                    else "becomes asymptotically stable" if after < 0 else "asymptotic stability lost")
            changes.append(StabilityChange(x, kind, essential(x)))
        if counts[k] != counts[k + 1]:
            x = _bisect(lambda v, c=counts[k]: complex_count(v) == c, a, b)
            kind = "eigenvalues become complex" if counts[k + 1] > counts[k] else "eigenvalues become real"
            changes.append(StabilityChange(x, kind, essential(x)))
    changes.sort(key=lambda c: c.value)
    return Sweep(name, grid, eig, stable, tuple(changes))
