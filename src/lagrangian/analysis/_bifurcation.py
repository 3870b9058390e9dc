"""The equilibria and their stability against a parameter: a bifurcation diagram.

Each closed-form branch q*(p) of `equilibria` (found once, symbolic in the parameter p) is
followed over a grid of p: where its condition of existence holds, its stability is the
verdict of the linearization there (`linearize`, `stability`).  Between grid values where a
branch appears or disappears, or where its verdict changes, the value is found by bisection.
The bead on the rotating hoop gives the classical pitchfork: θ = 0 stable for Ω² < g/R,
then unstable, while the pair cos θ = g/(R Ω²) is born there, stable (Lagrange–Dirichlet).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ._equilibria import Equilibrium, EquilibriumError, equilibria
from ._linear_model import LinearizationError
from ._linearize import linearize
from ._modes import _bisect

__all__ = ["BifurcationDiagram", "Branch", "bifurcation"]


@dataclass(frozen=True, slots=True)
class Branch:
    """One closed-form branch of equilibria q*(p).

    Parameters
    ----------
    equilibrium : Equilibrium
        The closed-form family of equilibria the branch follows.
    q : ndarray of shape (m, n)
        The equilibria q*(p) over the grid of m values (NaN where the branch does not exist).
    stable : ndarray of shape (m,)
        1 (stable), 0 (unstable) or NaN (absent, or marginal) over the grid.
    changes : tuple of (float, str)
        (p, what) where the branch appears, disappears, gains or loses stability.
    """

    equilibrium: Equilibrium
    q: np.ndarray
    stable: np.ndarray
    changes: tuple[tuple[float, str], ...]


@dataclass(frozen=True, slots=True)
class BifurcationDiagram:
    """The equilibria of a model against one parameter: what `bifurcation` returns.

    Parameters
    ----------
    parameter : str
        The name of the parameter p.
    values : ndarray of shape (m,)
        The grid of p.
    coordinates : tuple of str
        The coordinates, in the order of the columns of each branch's ``q``.
    branches : tuple of Branch
        One closed-form family of equilibria q*(p) each, with its stability over the grid.
    """

    parameter: str
    values: np.ndarray
    coordinates: tuple[str, ...]
    branches: tuple[Branch, ...]


def _exists(e: Equilibrium, numbers: Mapping[str, float]) -> bool:
    if e.condition is None:
        return True
    # The condition's symbols may carry assumptions (positive=True): match them by name.
    return bool(e.condition.subs({s: numbers[s.name] for s in e.condition.free_symbols}))


def _point(e: Equilibrium, coords: Sequence[str], numbers: Mapping[se.Basic, float]) -> np.ndarray:
    out = []
    for c in coords:
        v = e.values[c]
        out.append(float(v) if isinstance(v, float) else complex(v.subs(numbers)).real)
    return np.array(out)


def bifurcation(eom: EquationsOfMotion, parameter: str, values: Sequence[float],
                parameters: Mapping[str, float] | None = None) -> BifurcationDiagram:
    """The closed-form equilibria of ``eom`` and their stability for ``parameter`` over ``values``.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations of an autonomous model.
    parameter : str
        The parameter p to vary.
    values : sequence of float
        The grid of p.
    parameters : mapping of str to float, optional
        Values of the other parameters, overriding the model's.

    Returns
    -------
    BifurcationDiagram
        Each closed-form branch over the grid, with where it changes.

    Raises
    ------
    EquilibriumError
        ``parameter`` is not a parameter of the model, or no equilibrium has a closed form (then
        follow one equilibrium with `linearize` and `sweep` instead).
    """
    names = [p.name for p in eom.model.parameters]
    if parameter not in names:
        raise EquilibriumError(f"`{parameter}` is not a parameter of the model ({', '.join(names)}).",
                               fix="sweep one of the model's parameters")
    grid = np.asarray(values, dtype=float)
    if grid.ndim != 1 or grid.size == 0:
        raise EquilibriumError("the sweep has no point.", fix="give a range with at least one value, e.g. Omega=0:10:0.1")
    fixed = {p.name: p.value for p in eom.model.parameters if p.value is not None}
    fixed.update(parameters or {})
    fixed.pop(parameter, None)
    found = [e for e in equilibria(eom, parameters={**fixed, parameter: float(grid[0])}, all_branches=True,
                                   numeric=False)
             if e.closed_form and not e.free]
    if not found:
        raise EquilibriumError("no equilibrium of this model has a closed form to follow along the parameter.",
                               fix="follow one equilibrium with `lagrangian modes MODEL --at ... --sweep NAME=a:b:step`")
    coords = eom.coordinates

    def state(e: Equilibrium, p: float) -> tuple[bool, np.ndarray | None, float]:
        numbers = {se.Symbol(k): v for k, v in fixed.items()}
        numbers[se.Symbol(parameter)] = p
        if not _exists(e, {str(k): v for k, v in numbers.items()}):
            return False, None, np.nan
        q = _point(e, coords, numbers)
        try:
            st = linearize(eom, dict(zip(coords, q, strict=True)), parameters={**fixed, parameter: p}).stability()
        except LinearizationError:
            return True, q, np.nan
        return True, q, np.nan if st.stable is None else float(st.stable)

    branches = []
    for e in found:
        rows = [state(e, float(p)) for p in grid]
        q = np.array([r[1] if r[1] is not None else np.full(len(coords), np.nan) for r in rows])
        stable = np.array([r[2] for r in rows])
        changes: list[tuple[float, str]] = []
        for k in range(len(grid) - 1):
            a, b = float(grid[k]), float(grid[k + 1])
            if rows[k][0] != rows[k + 1][0]:
                x = _bisect(lambda p, e=e, was=rows[k][0]: state(e, p)[0] == was, a, b)
                changes.append((x, "appears" if rows[k + 1][0] else "disappears"))
            elif rows[k][0] and not _same(stable[k], stable[k + 1]):
                x = _bisect(lambda p, e=e, was=stable[k]: _same(state(e, p)[2], was), a, b)
                after = stable[k + 1]
                changes.append((x, "becomes stable" if after == 1 else "becomes unstable" if after == 0
                                else "becomes marginal"))
        branches.append(Branch(e, q, stable, tuple(changes)))
    return BifurcationDiagram(parameter, grid, tuple(coords), tuple(branches))


def _same(a: float, b: float) -> bool:
    return (np.isnan(a) and np.isnan(b)) or a == b

