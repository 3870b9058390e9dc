"""The numeric search for equilibria: where it looks, the roots it finds, and the families of rests.

**Angles.**  A coordinate is an angle when it enters every expression of the equations (M, F at
any rates, the constraint rows) only inside sin, cos or tan, and they are 2π-periodic in it
(checked at random points).  Only an angle wraps: it is searched over (−π, π] and its roots are
identified modulo 2π.  A length never is, even where the static equations happen to vanish for
every value (the bead on a turning parabola at Ω² = 2 g a).

**Where the other coordinates are searched** (`SearchRegion`), in this order: the range given to
`equilibria` (``ranges``, ``--range``), else the model's declared ``range`` (its bounds at the
parameter values), else — no range at all — starting points spread over every scale: 0, ±s·10ʲ
(s = 1, 1.5, 2, 3, 5, 7; j = −3 … 2) and ± each parameter value, with no bound on where a root
may be.  The elastic pendulum's upright rest r = L − m g/k is found so, without a range.  What
was searched is reported (`EquilibriumSearch`): a root beyond the starts' reach can still be missed, and
the list is never presented as complete.

**Families.**  At each root q*, the residual is evaluated along each coordinate q_j over its
region: when it vanishes there to the rounding of its own terms, every q_j is a rest ("q_j any",
the parabola's r at the critical rate).  When it does not but the Jacobian of the static
equations is singular at q* (rank r < d), the rests form a curve (a surface) through q*: it is
followed by pseudo-arclength continuation (Allgower & Georg, *Numerical Continuation Methods*,
1990, ch. 2) and the other roots on it are dropped, q* standing for the family.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se
from scipy import optimize

__all__ = ["EquilibriumSearch", "Root", "SearchRegion", "angles", "near_curve", "region_of", "same", "search", "wrap"]

#: About how many starting points the search uses (the product of the coordinates' start values,
#: sampled when it is larger).
STARTS = 240
#: The most starting points when a coordinate without a range is searched over every scale.
MAX_STARTS = 900
#: A root is accepted when |residual| ≤ TOLERANCE × (the sizes of its terms, and of its change over a
#: relative step of the coordinates) there.
TOLERANCE = 1e-9
#: Mantissas and decades of the starting points of a coordinate without a range.
_MANTISSAS = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0)
_DECADES = range(-3, 3)
_TRIG = (se.sin, se.cos, se.tan)


@dataclass(frozen=True, slots=True)
class SearchRegion:
    """Where one coordinate was searched for equilibria.

    Parameters
    ----------
    coordinate : str
        The coordinate.
    kind : str
        "angle" ((−π, π]), "range" (given), "declared" (the model's range) or "scales" (no range:
        starts over every scale).
    bounds : (float, float)
        The interval searched (±inf for an open side).
    starts : int
        The number of starting points along it.
    """

    coordinate: str
    kind: str
    bounds: tuple[float, float]
    starts: int


@dataclass(frozen=True, slots=True)
class EquilibriumSearch:
    """What `equilibria` did: the closed form, the numeric search and where it looked.

    Parameters
    ----------
    closed_form : bool
        Whether SymPy solved the static equations.
    numeric : bool
        Whether the numeric search ran (every parameter has a value).
    regions : tuple of SearchRegion
        Where it looked, per coordinate.
    starts : int
        The number of starting points in all.
    skipped : str, optional
        Why the numeric search did not run: "values" (a parameter has no value), "continuum" (the
        closed form gives a family of rests already), "not asked" (``numeric=False``); None when it
        ran.
    """

    closed_form: bool
    numeric: bool
    regions: tuple[SearchRegion, ...] = ()
    starts: int = 0
    skipped: str | None = None

    @property
    def unbounded(self) -> tuple[str, ...]:
        """Coordinates searched without a bound on one side or both: a root far away may be missed."""
        return tuple(r.coordinate for r in self.regions if not all(map(math.isfinite, r.bounds)))


@dataclass(frozen=True, slots=True)
class Root:
    """A rest found numerically: ``point`` (active coordinates), ``residual``, ``free`` (coordinates along
    which every value is a rest), ``family`` (the dimension of a curved family of rests through it)."""

    point: dict[str, float]
    residual: float
    free: tuple[str, ...] = ()
    family: int = 0
    curve: np.ndarray | None = None  # points of the curved family, traced (active coordinates, in order)


# -- angles ------------------------------------------------------------------------------------

def _only_in_trig(e: se.Basic, q: se.Symbol) -> bool:
    inside = [f for f in e.atoms(*_TRIG) if q in f.free_symbols]
    bare = e.xreplace({f: se.Symbol(f"_trig{k}") for k, f in enumerate(inside)}) if inside else e
    return q not in bare.free_symbols


def angles(expressions: Sequence[se.Basic], q: Sequence[se.Symbol], names: Sequence[str],
           numbers: Mapping[se.Basic, float], skip: Sequence[str] = ()) -> set[str]:
    """Coordinates that enter ``expressions`` only through sin, cos, tan, 2π-periodically (at two random
    points); ``skip``: coordinates absent from the static equations."""
    rng = np.random.default_rng(1)
    symbols = set().union(*(e.free_symbols for e in expressions)) if expressions else set()
    out = set()
    for name, s in zip(names, q, strict=True):
        if name in skip or not any(s in e.free_symbols for e in expressions):
            continue
        if not all(_only_in_trig(e, s) for e in expressions if s in e.free_symbols):
            continue
        ok = True
        for _ in range(2):
            point = {x: numbers.get(x, float(rng.uniform(0.5, 2.0))) for x in symbols}
            point.update({x: float(rng.uniform(-3, 3)) for x in symbols if x not in numbers})
            shifted = dict(point)
            shifted[s] = point[s] + 2 * math.pi
            for e in expressions:
                if s in e.free_symbols:
                    a, b = complex(e.subs(point)), complex(e.subs(shifted))
                    ok = ok and abs(a - b) <= 1e-9 * (1 + abs(a))
        if ok:
            out.add(name)
    return out


# -- regions -----------------------------------------------------------------------------------

def region_of(name: str, angle: bool, given: tuple[float, float] | None,
              declared: tuple[se.Basic | None, se.Basic | None] | None, numbers: Mapping[se.Basic, float]
              ) -> tuple[str, tuple[float, float]]:
    """(kind, bounds) of one coordinate's search (see the module's docstring)."""
    if given is not None:
        return "range", given
    if angle:
        return "angle", (-math.pi, math.pi)
    if declared is not None:
        bounds = []
        for side, default in zip(declared, (-math.inf, math.inf), strict=True):
            try:
                bounds.append(default if side is None else float(side.subs(dict(numbers))))
            except (RuntimeError, TypeError, ValueError):
                bounds.append(default)
        if all(map(math.isfinite, bounds)) or any(map(math.isfinite, bounds)):
            return "declared", (bounds[0], bounds[1])
    return "scales", (-math.inf, math.inf)


def _start_values(kind: str, bounds: tuple[float, float], k: int, numbers: Mapping[se.Basic, float]) -> list[float]:
    a, b = bounds
    if math.isfinite(a) and math.isfinite(b):
        return list(np.linspace(a, b, k, endpoint=False) + (b - a) / (2 * k))
    sizes = {m * 10.0**j for m in _MANTISSAS for j in _DECADES}
    sizes |= {abs(float(v)) for v in numbers.values() if float(v) != 0 and math.isfinite(float(v))}
    values = {0.0} | sizes | {-s for s in sizes}
    origin = a if math.isfinite(a) else b if math.isfinite(b) else 0.0
    values |= {origin + s for s in sizes} | {origin - s for s in sizes}
    return sorted(v for v in values if a <= v <= b)


def _grid(regions: Sequence[tuple[str, tuple[float, float]]], numbers: Mapping[se.Basic, float]) -> list[np.ndarray]:
    d = len(regions)
    k = max(2, round(STARTS ** (1 / d)))
    axes = [_start_values(kind, bounds, k, numbers) for kind, bounds in regions]
    total = math.prod(len(a) for a in axes)
    limit = 4 * STARTS if all(kind in ("angle", "range") for kind, _ in regions) else MAX_STARTS
    if total <= limit:
        return [np.array(p) for p in itertools.product(*axes)]
    rng = np.random.default_rng(0)
    return [np.array([ax[rng.integers(len(ax))] for ax in axes]) for _ in range(limit)]


# -- the search --------------------------------------------------------------------------------

def wrap(x: float) -> float:
    """x modulo 2π in (−π, π]."""
    y = math.remainder(x, 2 * math.pi)
    return math.pi if y <= -math.pi + 1e-12 else y


def same(a: Mapping[str, float], b: Mapping[str, float], angles: set[str]) -> bool:
    for n in a:
        d = a[n] - b.get(n, math.nan)
        if n in angles:
            d = math.remainder(d, 2 * math.pi)
        if not abs(d) <= 1e-6 * (1 + abs(a[n])):
            return False
    return True


def _inside(x: float, bounds: tuple[float, float]) -> bool:
    a, b = bounds
    return a - 1e-12 * (1 + abs(a)) <= x <= b + 1e-12 * (1 + abs(b))


def search(names: Sequence[str], residual: Callable[[np.ndarray], np.ndarray],
           size: Callable[[np.ndarray], np.ndarray], regions: Sequence[tuple[str, tuple[float, float]]],
           angles: set[str], numbers: Mapping[se.Basic, float]) -> tuple[list[Root], int]:
    """The rests r(q) = 0 of the active coordinates ``names`` over their ``regions``, with the families
    through them, and the number of starting points used.  ``size(q)`` is, per equation, the sum of the
    sizes of its terms, the scale against which a residual is small."""
    if not names:
        return [], 0
    starts = _grid(regions, numbers)

    def accepted(X: np.ndarray) -> np.ndarray:
        """Whether r(x) = 0 to rounding at each row x of X: |r| ≤ TOLERANCE (Σ |terms| + Σ_j |∂r/∂q_j| max(1, |q_j|)),
        the sizes of the terms summed and the change of r over a relative step of q."""
        with np.errstate(all="ignore"):
            R, S = residual(X), size(X)
            scale = np.linalg.norm(S, axis=1)
            for j in range(X.shape[1]):
                h = 1e-7 * np.maximum(1.0, np.abs(X[:, j]))
                E = np.zeros_like(X)
                E[:, j] = h
                dr = (residual(X + E) - residual(X - E)) / 2.0
                scale = scale + np.linalg.norm(dr, axis=1) / 1e-7
            norm = np.linalg.norm(R, axis=1)
            return np.isfinite(norm) & (norm <= TOLERANCE * np.maximum(scale, 1e-300))

    def small(x: np.ndarray) -> bool:
        return bool(accepted(x[None, :])[0])

    found: list[Root] = []
    curves: list[np.ndarray] = []
    X = levenberg_marquardt(residual, np.array(starts))
    for x in X[accepted(X)]:
        point = {n: (wrap(v) if n in angles else float(v)) for n, v in zip(names, x, strict=True)}
        point = {n: 0.0 if abs(v) < 1e-15 else v for n, v in point.items()}  # −0 and 1e-22 are 0
        if not all(_inside(point[n], b) for n, (_, b) in zip(names, regions, strict=True) if n not in angles):
            continue
        if any(_on(root, point, angles) for root in found) or any(near_curve(c, x) for c in curves):
            continue
        free = _free_along(names, x, regions, small, numbers)
        family, curve = 0, None
        if not free:
            family = _rank_deficiency(residual, size, x)
            if family:
                curve = _trace(residual, x, regions, names, angles)
                curves.append(curve)
        point = {n: v for n, v in point.items() if n not in free}
        found = [r for r in found if not (free and _within(r.point, point, angles))
                 and not (curve is not None and near_curve(curve, np.array([r.point[n] for n in names])))]
        found.append(Root(point, float(np.max(np.abs(residual(x)), initial=0.0)), free, family, curve))
    found.sort(key=lambda r: (len(r.free), tuple(r.point.get(n, 0.0) for n in names)))
    return found, len(starts)


def levenberg_marquardt(f: Callable[[np.ndarray], np.ndarray], X0: np.ndarray, iterations: int = 200) -> np.ndarray:
    """Zeros (or least-squares minima) of f from each row of X0, by Levenberg–Marquardt with Marquardt's
    scaling and a central-difference Jacobian (Nocedal & Wright, *Numerical Optimization*, §10.3).

    Every start runs at once, f taking a batch of points (N, d) to (N, m): the search solves hundreds
    of systems of two or three unknowns, which one call of `scipy.optimize.least_squares` each would
    spend seconds on.  A start whose f is not finite stays where it is (its residual says so).
    """
    X = np.array(X0, dtype=float)
    N, d = X.shape
    with np.errstate(all="ignore"):
        R = f(X)
        cost = np.einsum("ki,ki->k", R, R)
        mu = np.full(N, 1e-3)
        live = np.isfinite(cost) & (cost > 0)
        for _ in range(iterations):
            idx = np.flatnonzero(live)
            if not idx.size:
                break
            x, r = X[idx], R[idx]
            J = np.empty((len(idx), r.shape[1], d))
            for j in range(d):
                h = 1e-7 * np.maximum(1.0, np.abs(x[:, j]))
                e = np.zeros_like(x)
                e[:, j] = h
                J[:, :, j] = (f(x + e) - f(x - e)) / (2 * h[:, None])
            H = np.einsum("kij,kil->kjl", J, J)
            g = np.einsum("kij,ki->kj", J, r)
            D = np.einsum("kjj->kj", H).copy()
            D[D == 0] = 1.0
            system = H + mu[idx, None, None] * (D[:, :, None] * np.eye(d))
            ok = np.all(np.isfinite(system), axis=(1, 2)) & np.all(np.isfinite(g), axis=1)
            step = np.zeros_like(x)
            if ok.any():
                step[ok] = np.einsum("kij,kj->ki", np.linalg.pinv(system[ok]), -g[ok])
            y = x + step
            ry = f(y)
            cy = np.einsum("ki,ki->k", ry, ry)
            better = np.isfinite(cy) & (cy < cost[idx])
            moved = idx[better]
            tiny = np.linalg.norm(step[better], axis=1) <= 1e-15 * (1.0 + np.linalg.norm(x[better], axis=1))
            X[moved], R[moved], cost[moved] = y[better], ry[better], cy[better]
            mu[moved] = np.maximum(mu[moved] / 3.0, 1e-12)
            mu[idx[~better]] *= 4.0
            live[moved[tiny]] = False
            live[moved[cy[better] == 0]] = False
            live[idx[~better & ((mu[idx] > 1e16) | ~ok)]] = False
    return X


def _on(root: Root, point: Mapping[str, float], angles: set[str]) -> bool:
    """``point`` is ``root`` or lies on its family of free coordinates."""
    return same(root.point, {n: point[n] for n in root.point}, angles)


def _within(point: Mapping[str, float], family: Mapping[str, float], angles: set[str]) -> bool:
    """A point root lies on a family whose fixed coordinates it shares."""
    return same(family, {n: point.get(n, math.nan) for n in family}, angles)


def _samples(kind: str, bounds: tuple[float, float], numbers: Mapping[se.Basic, float]) -> list[float]:
    if kind == "angle":
        return list(np.linspace(-math.pi, math.pi, 12, endpoint=False) + 0.1)
    values = _start_values(kind, bounds, 12, numbers)
    return values[:: max(1, len(values) // 12)] + values[-1:]


def _free_along(names: Sequence[str], x: np.ndarray, regions: Sequence[tuple[str, tuple[float, float]]],
                small: Callable[[np.ndarray], bool], numbers: Mapping[se.Basic, float]) -> tuple[str, ...]:
    """Coordinates along which the residual vanishes from ``x`` over their whole region (a family)."""
    free = []
    for j, (kind, bounds) in enumerate(regions):
        ok = True
        for v in _samples(kind, bounds, numbers):
            y = x.copy()
            y[j] = v
            ok = ok and small(y)
        if ok:
            free.append(j)
    if len(free) > 1:  # together too (a product of families), at a few random combinations
        rng = np.random.default_rng(3)
        for _ in range(8):
            y = x.copy()
            for j in free:
                pool = _samples(*regions[j], numbers)
                y[j] = pool[rng.integers(len(pool))]
            if not small(y):
                return ()
    return tuple(names[j] for j in free)


def _jacobian(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray) -> np.ndarray:
    cols = []
    for j in range(len(x)):
        h = 1e-6 * max(1.0, abs(x[j]))
        e = np.zeros_like(x)
        e[j] = h
        cols.append((f(x + e) - f(x - e)) / (2 * h))
    return np.array(cols).T


def _rank_deficiency(residual: Callable[[np.ndarray], np.ndarray], size: Callable[[np.ndarray], np.ndarray],
                     x: np.ndarray) -> int:
    """d − rank of ∂r/∂q at x, the rank read against the Jacobian of the terms' sizes (0: an isolated root)."""
    J = _jacobian(residual, x)
    S = _jacobian(size, x)
    scale = max(float(np.abs(S).max(initial=0.0)), float(np.abs(J).max(initial=0.0)), 1e-300)
    s = np.linalg.svd(J, compute_uv=False)
    return int(len(x) - np.count_nonzero(s > 1e-6 * scale)) if len(s) == len(x) else 0


def _trace(residual: Callable[[np.ndarray], np.ndarray], x: np.ndarray,
           regions: Sequence[tuple[str, tuple[float, float]]], names: Sequence[str], angles: set[str],
           steps: int = 400) -> np.ndarray:
    """Points of the curve of rests through x, both ways, by pseudo-arclength continuation."""
    span = [b - a if math.isfinite(b - a) else 2.0 * max(1.0, abs(x[j])) for j, (_, (a, b)) in enumerate(regions)]
    h = 0.01 * max(span)
    out = [x.copy()]
    for sign in (1.0, -1.0):
        y = x.copy()
        prev = None
        for _ in range(steps):
            _, _, vh = np.linalg.svd(_jacobian(residual, y))
            t = vh[-1]
            if prev is not None and float(t @ prev) < 0:
                t = -t
            elif prev is None:
                t = sign * t
            guess = y + h * t
            sol = optimize.least_squares(lambda z, g=guess, t=t: np.append(residual(z), (z - g) @ t), guess,
                                         method="lm", xtol=1e-14, ftol=1e-14)
            z = sol.x
            if np.linalg.norm(z - y) < 0.1 * h or not all(
                    _inside(z[j], b) for j, (_, b) in enumerate(regions) if names[j] not in angles):
                break
            out.append(z.copy())
            if len(out) > 3 and np.linalg.norm(_wrapped(z - x, names, angles)) < 0.5 * h:
                return np.array(out)  # a closed curve
            prev, y = t, z
    return np.array(out)


def _wrapped(d: np.ndarray, names: Sequence[str], angles: set[str]) -> np.ndarray:
    return np.array([math.remainder(v, 2 * math.pi) if n in angles else v for n, v in zip(names, d, strict=True)])


def near_curve(curve: np.ndarray, x: np.ndarray) -> bool:
    """``x`` lies on the traced ``curve`` (within one and a half steps of its points)."""
    if curve.shape[0] < 2:
        return False
    step = max(float(np.linalg.norm(curve[1] - curve[0])), 1e-12)
    return bool(np.min(np.linalg.norm(curve - x, axis=1)) < 1.5 * step)
