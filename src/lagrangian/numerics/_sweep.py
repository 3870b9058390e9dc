"""One verb for both sweeps along a parameter: a linearization's eigenvalues, or a contact model's impacts.

``sweep(lin, name, values, **fixed)``, given a `LinearModel`, is the linear analysis'
`lagrangian.analysis.eigenvalue_sweep`: the essential eigenvalues against ``name``, and where
stability changes (docs/small-motions.md).  ``sweep(model, name, values, t_end=..., **options)``,
given a model with unilateral contacts (a file, a `Model` or its equations), is `impact_sweep` over
the one axis ``name``: impacts, bounces, rest time, energy lost (docs/contacts.md).

The verb lives here, in the first stage that sees both: the linearization is the analysis stage's,
the motions between impacts are simulated by this one.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, overload

import numpy as np

from ..analysis import LinearizationError, LinearModel, Sweep, eigenvalue_sweep
from ._impact_sweep import ImpactSweep, impact_sweep

__all__ = ["sweep"]


@overload
def sweep(source: LinearModel, name: str, values: Sequence[float] | np.ndarray, **fixed: float) -> Sweep: ...
@overload
def sweep(source: Any, name: str, values: Sequence[float] | np.ndarray, **options: Any) -> ImpactSweep: ...


def sweep(source: Any, name: str, values: Sequence[float] | np.ndarray, **keywords: Any) -> Sweep | ImpactSweep:
    """The eigenvalues of a linearization, or the impacts of a contact model, against the parameter ``name``.

    Parameters
    ----------
    source : LinearModel, str, Path, Model or EquationsOfMotion
        A `LinearModel` that keeps ``name`` symbolic (``linearize(..., symbolic=(name,))``), or a
        model with unilateral contacts: a file, a `Model` or its equations.
    name : str
        The swept parameter (for a contact model, also a coordinate or a rate: ``z``, ``z_dot``).
    values : sequence of float or ndarray
        The values of ``name``.
    **keywords : object
        For a linearization, the values of its other symbolic parameters; for a contact model,
        ``t_end`` (required) and `impact_sweep`'s keywords (``min_speed``, ``parameters``, ``initial``,
        `simulate`'s options).

    Returns
    -------
    Sweep or ImpactSweep
        `Sweep` (`lagrangian.analysis.eigenvalue_sweep`) for a linearization: the essential eigenvalues
        at each value and where stability changes; `ImpactSweep` (`impact_sweep`) for a contact model.

    Raises
    ------
    LinearizationError
        A source that is not a linearization, given without ``t_end``; and `eigenvalue_sweep`'s errors.
    SimulationError
        `impact_sweep`'s errors: a model without contacts, an unknown name, no value.
    """
    if isinstance(source, LinearModel):
        return eigenvalue_sweep(source, name, values, **keywords)
    t_end = keywords.pop("t_end", None)
    if t_end is None:
        raise LinearizationError("sweep() takes a linearization (lagrangian.linearize), or a model with "
                                 "unilateral contacts and t_end.",
                                 fix='e.g. sweep(linearize(eom, point, symbolic=("Omega",)), "Omega", values), '
                                     'or sweep("examples/bouncing_ball.toml", "e", values, t_end=10)')
    return impact_sweep(source, {name: values}, t_end, **keywords)
