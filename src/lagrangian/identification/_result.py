"""The result of `identify`: estimates with standard errors, the base combinations, the residuals."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import IdentificationError

__all__ = ["BaseEstimate", "Identification"]


@dataclass(frozen=True)
class BaseEstimate:
    """One identifiable combination Σ c_j θ_j (a base parameter), its estimate and standard error.

    Parameters
    ----------
    text : str
        The combination, as text.
    coefficients : mapping of str to float
        Its coefficients c_j, by parameter.
    estimate : float
        Its estimate.
    std : float
        Its standard error.
    """

    text: str
    coefficients: Mapping[str, float]
    estimate: float
    std: float


@dataclass(frozen=True)
class Identification:
    """Parameters fitted to measurements (`lagrangian.identify`).

    ``fit["l"]`` is the estimate of ``l`` and ``fit.std["l"]`` its standard error (the square root
    of the diagonal of ``covariance``); a parameter that the equations determine only in a
    combination with others has no estimate of its own: ``fit["m"]`` then raises an
    `IdentificationError` that names the combination, and ``fit.base`` holds every combination.

    Parameters
    ----------
    model_name : str
        The model's name.
    route : str
        ``"regressor"`` (linear least squares on Y(q, q̇, q̈) θ = −r₀) or ``"shooting"`` (nonlinear
        least squares on simulated motions, forward sensitivities for the Jacobian).
    parameters : tuple of str
        The parameters asked for.
    estimates : mapping of str to float
        Name → value, for the parameters identified on their own.
    std : mapping of str to float
        Name → standard error, likewise.
    base : tuple of BaseEstimate
        The identifiable combinations (one per parameter when all are identifiable).
    covariance : ndarray
        The covariance matrix of the estimated quantities (the parameters, or the base combinations,
        then for shooting the initial states).
    covariance_names : tuple of str
        Its rows' names.
    t : ndarray of shape (N,)
        The sample times.
    residuals : ndarray of shape (N, k)
        The fit's residuals at ``t``, columns ``residual_names`` (the equations M q̈ − F for the
        regressor, the measured columns for shooting), in the data's units.
    residual_names : tuple of str
        Their names.
    sigma : mapping of str to float
        Residual column → its standard deviation at the optimum (the noise level).
    status : str
        How the fit went.
    iterations : int
        The solver's iterations.
    condition : float
        The condition number of the weighted Jacobian (regressor or sensitivities) of the estimated
        quantities.
    initial : mapping of str to float
        For shooting, the estimated state at the first sample (name → value).
    notes : tuple of str
        What the user should know (samples left out, segments used...).
    """

    model_name: str
    route: str
    parameters: tuple[str, ...]
    estimates: Mapping[str, float]
    std: Mapping[str, float]
    base: tuple[BaseEstimate, ...]
    covariance: np.ndarray
    covariance_names: tuple[str, ...]
    t: np.ndarray
    residuals: np.ndarray
    residual_names: tuple[str, ...]
    sigma: Mapping[str, float]
    status: str = "converged"
    iterations: int = 0
    condition: float = 1.0
    initial: Mapping[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    def __getitem__(self, name: str) -> float:
        if name in self.estimates:
            return self.estimates[name]
        if name not in self.parameters:
            raise IdentificationError(f"`{name}` was not among the parameters fitted.",
                                      fix="the parameters fitted are " + ", ".join(self.parameters))
        combos = [b.text for b in self.base if name in b.coefficients]
        where = ("it enters only " + "; ".join(f"`{c}`" for c in combos)) if combos else \
            "it does not act on the motion at all"
        raise IdentificationError(f"`{name}` is not identifiable on its own: {where}.",
                                  fix="read the combinations in fit.base, or fix the other parameters of the "
                                      "combination at known values")

    def __contains__(self, name: object) -> bool:
        return name in self.estimates

    @property
    def identifiable(self) -> tuple[str, ...]:
        """The identifiable combinations, as text."""
        return tuple(b.text for b in self.base)

    @property
    def full_rank(self) -> bool:
        """Every parameter asked for is identified on its own."""
        return all(name in self.estimates for name in self.parameters)

    def summary(self) -> str:
        """A plain-text table: estimate ± standard error for each parameter or combination.

        Returns
        -------
        str
            The table.
        """
        lines = [f"identification of `{self.model_name}` ({self.route}): {self.status}"]
        width = max([len(b.text) for b in self.base] + [9])
        for b in self.base:
            rel = f"  ({b.std / abs(b.estimate):.1e} relative)" if b.estimate else ""
            lines.append(f"  {b.text:<{width}} = {b.estimate:.10g} ± {b.std:.3g}{rel}")
        if self.initial:
            lines.append("  initial state: " + ", ".join(f"{k} = {v:.6g}" for k, v in self.initial.items()))
        lines.append("  residual std: " + ", ".join(f"{k} {v:.3g}" for k, v in self.sigma.items()))
        if not self.full_rank:
            alone = set(self.estimates)
            rest = [p for p in self.parameters if p not in alone]
            lines.append(f"  not identifiable on their own: {', '.join(rest)} (only in the combinations above)")
        lines.extend(f"  note: {note}" for note in self.notes)
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready document (schema ``lagrangian.identify/1``); what is not determined (NaN) is null.

        Returns
        -------
        dict of str to object
            The document.
        """

        def number(x: float) -> float | None:
            return float(x) if np.isfinite(x) else None

        return {
            "schema": "lagrangian.identify/1",
            "model": self.model_name,
            "route": self.route,
            "status": self.status,
            "parameters": list(self.parameters),
            "estimates": {k: number(v) for k, v in self.estimates.items()},
            "std": {k: number(v) for k, v in self.std.items()},
            "identifiable": [{"combination": b.text, "coefficients": {k: float(c) for k, c in b.coefficients.items()},
                              "estimate": number(b.estimate), "std": number(b.std)} for b in self.base],
            "initial": {k: number(v) for k, v in self.initial.items()},
            "sigma": {k: number(v) for k, v in self.sigma.items()},
            "covariance": {"names": list(self.covariance_names),
                           "matrix": [[number(x) for x in row] for row in np.asarray(self.covariance)]},
            "iterations": int(self.iterations),
            "condition": number(self.condition),
            "samples": len(self.t),
            "notes": list(self.notes),
        }

    def _repr_markdown_(self) -> str:
        return "```\n" + self.summary() + "\n```"
