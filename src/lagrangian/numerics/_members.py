"""The members of an ensemble: which initial states and parameter values, and how they are laid out.

An ensemble is N members, each an initial state y0 = (q(t0), q̇(t0)) and a parameter
vector p.  They come from

* arrays, one value per member: ``initial={"theta": thetas, "phi_dot": spins}`` (a dict
  of equal-length arrays, scalars broadcast), or a (N, len(names)) array with ``names=``;
* a grid, the outer product of named axes: ``grid(theta1=np.linspace(-3, 3, 400),
  theta2=np.linspace(-3, 3, 400))`` — 160 000 members laid out in C order (the last axis
  varies fastest), whose Dataset keeps the grid's own dimensions.

A name is a coordinate (``theta``), a rate (``theta_dot``) or a parameter (``g``): a grid
sorts its axes into the state and the parameters by name, wherever it is passed.  Names
not swept keep the model's values (or the ``initial=``/``parameters=`` scalars).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import SimulationError
from ._setup import initial_state

__all__ = ["Grid", "grid", "Members", "members"]


@dataclass(frozen=True)
class Grid:
    """Named axes whose outer product is the set of members (see `grid`).

    Parameters
    ----------
    axes : tuple of (str, ndarray)
        Each axis's name and values, in order.
    """

    axes: tuple[tuple[str, np.ndarray], ...]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(values) for _, values in self.axes)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape, dtype=np.int64))

    def columns(self) -> dict[str, np.ndarray]:
        """Each axis's value for every member, flattened in C order (the last axis fastest).

        Returns
        -------
        dict of str to ndarray
            By axis name, one value per member.
        """
        mesh = np.meshgrid(*(values for _, values in self.axes), indexing="ij")
        return {name: m.ravel() for (name, _), m in zip(self.axes, mesh, strict=True)}


def grid(**axes) -> Grid:
    """The grid of members over named axes: ``grid(theta=np.linspace(0.1, 1.5, 50), phi_dot=[20, 50, 80])``.

    Each keyword is a coordinate, a rate (``<coordinate>_dot``) or a parameter of the
    model, and its values a 1-D sequence of finite numbers; the members are every
    combination (C order: the last axis varies fastest).

    Parameters
    ----------
    **axes : sequence of float
        Each keyword is a coordinate, a rate (``<coordinate>_dot``) or a parameter of the model, and
        its values a 1-D sequence of finite numbers; the members are every combination (C order: the
        last axis varies fastest).

    Returns
    -------
    Grid
        The grid.

    Raises
    ------
    SimulationError
        For an empty grid, an axis that is empty, not 1-D, or holds a non-finite value.

    >>> g = grid(theta=[0.1, 0.2], phi_dot=[10.0, 20.0, 30.0])
    >>> g.shape, g.size
    ((2, 3), 6)
    >>> g.columns()["phi_dot"].tolist()
    [10.0, 20.0, 30.0, 10.0, 20.0, 30.0]
    """
    if not axes:
        raise SimulationError("A grid needs at least one axis.", fix="e.g. grid(theta=np.linspace(0.1, 1.5, 50))")
    out = []
    for name, values in axes.items():
        array = np.asarray(values, dtype=float)
        if array.ndim != 1 or len(array) == 0:
            raise SimulationError(f"The grid axis `{name}` must be a non-empty 1-D sequence of numbers "
                                  f"(it has shape {array.shape}).", fix=f"e.g. {name}=np.linspace(0, 1, 11)")
        if not np.all(np.isfinite(array)):
            raise SimulationError(f"The grid axis `{name}` holds a value that is not finite.",
                                  fix="give finite numbers only")
        out.append((name, array))
    return Grid(tuple(out))


@dataclass(frozen=True)
class Members:
    """N members as arrays: ``Y0`` (N, 2n) initial states, ``P`` (N, n_params) parameter values.

    ``swept`` maps each name that varies (or was given per member) to its values (N,);
    ``grid`` is the `Grid` they came from, or None for a plain list of members; ``L`` (N, law
    size) each member's numbers of the inputs' law (its own feedback gains), or None.
    """

    Y0: np.ndarray
    P: np.ndarray
    swept: dict[str, np.ndarray]
    grid: Grid | None
    L: np.ndarray | None = None

    @property
    def count(self) -> int:
        return len(self.Y0)


def _columns(value, what: str, names: tuple[str, ...] | None) -> dict[str, np.ndarray]:
    if value is None:
        return {}
    if isinstance(value, Mapping):
        return {str(k): np.asarray(v, dtype=float) for k, v in value.items()}
    array = np.asarray(value, dtype=float)
    if array.ndim != 2 or names is None or array.shape[1] != len(names):
        raise SimulationError(f"`{what}` must be a dict of arrays, a grid, or a (members x names) array with "
                              f"{what}_names= naming its columns.",
                              fix=f"e.g. {what}={{'theta': np.linspace(0.1, 1.5, 100)}}")
    return {name: array[:, k] for k, name in enumerate(names)}


def members(system, initial=None, parameters=None, *, initial_names=None, parameter_names=None) -> Members:
    """The `Members` of an ensemble of ``system`` (a `CompiledSystem`); see the module docstring.

    Raises
    ------
    SimulationError
        A name that is neither a coordinate, a rate nor a parameter (or given twice), arrays
        of different lengths, a non-finite value, or a value missing from the model.
    """
    grids = [g for g in (initial, parameters) if isinstance(g, Grid)]
    if len(grids) > 1:
        raise SimulationError("Only one grid can be given.", fix="put every axis in one grid(...)")
    the_grid = grids[0] if grids else None
    given: dict[str, np.ndarray] = {}
    state_names = {c for c in system.coordinates} | {c + "_dot" for c in system.coordinates}
    for value, what, names, allowed in ((initial, "initial", initial_names, state_names),
                                        (parameters, "parameters", parameter_names, set(system.parameters))):
        if isinstance(value, Grid):
            continue
        for name, column in _columns(value, what, names).items():
            if name not in allowed:
                kind = "a coordinate or a rate" if what == "initial" else "a parameter"
                raise SimulationError(f"`{name}` in `{what}` is not {kind} of `{system.eom.model.name}`.",
                                      fix="the names are " + ", ".join(sorted(allowed)) if allowed else
                                      "this model has none")
            given[name] = column
    grid_columns = the_grid.columns() if the_grid is not None else {}
    for name in grid_columns:
        if name not in state_names and name not in system.parameters:
            raise SimulationError(f"The grid axis `{name}` is neither a coordinate, a rate nor a parameter of "
                                  f"`{system.eom.model.name}`.",
                                  fix="the names are " + ", ".join(sorted(state_names | set(system.parameters))))
        if name in given:
            raise SimulationError(f"`{name}` is given both in the grid and in a dict.", fix="give it once")
    lengths = {name: len(np.atleast_1d(v)) for name, v in given.items() if np.ndim(v) > 0}
    count = the_grid.size if the_grid is not None else max(lengths.values(), default=1)
    for name, length in lengths.items():
        if length != count:
            raise SimulationError(f"`{name}` has {length} values, but the ensemble has {count} members.",
                                  fix="give every per-member array the same length (or a single number)")
        if np.ndim(given[name]) != 1:
            raise SimulationError(f"`{name}` must be one number or a 1-D array.", fix="flatten it")
    columns = {name: np.broadcast_to(v, (count,)) for name, v in given.items()}
    columns.update(grid_columns)
    for name, column in columns.items():
        if not np.all(np.isfinite(column)):
            raise SimulationError(f"`{name}` holds a value that is not finite.", fix="give finite numbers only")

    # The model's values (or the scalars given) as the base, checked once by the single-run helpers.
    scalar_state = {k: float(v[0]) for k, v in columns.items() if k in state_names}
    scalar_params = {k: float(v[0]) for k, v in columns.items() if k in system.parameters}
    y_base = initial_state(system.eom, scalar_state)
    p_base = system.parameter_vector(scalar_params)[: len(system.parameters)]
    n = system.n
    Y0 = np.tile(y_base, (count, 1))
    P = np.tile(p_base, (count, 1))
    for name, column in columns.items():
        if name in state_names:
            rate = name.endswith("_dot") and name[:-4] in system.coordinates
            index = system.coordinates.index(name[:-4] if rate else name) + (n if rate else 0)
            Y0[:, index] = column
        else:
            P[:, system.parameters.index(name)] = column
    swept = {name: np.asarray(column, dtype=float).copy() for name, column in columns.items()}
    return Members(np.ascontiguousarray(Y0), np.ascontiguousarray(P), swept, the_grid)
