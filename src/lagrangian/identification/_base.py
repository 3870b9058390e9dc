"""Base parameters: the combinations of θ that the equations determine, by QR with column pivoting.

When the regressor Y (stacked over many states) has rank r below the number of parameters P,
some parameters act only in fixed combinations (a link turning about a vertical axis through
its centre of mass shows neither its mass nor its first moment; two links in series show only
certain sums of their inertias).  The QR factorisation with column pivoting
Y Π = Q [R₁ R₂] picks r independent columns Y₁ and writes the others as Y₂ = Y₁ β with
β = R₁⁻¹ R₂, so that

    Y θ = Y₁ (θ₁ + β θ₂) = Y₁ θ_b,

and the r base parameters θ_b = θ₁ + β θ₂ are what any record can identify (Gautier &
Khalil, *IEEE Trans. Robot. Autom.* 6, 1990; Gautier, *J. Robot. Syst.* 8, 1991).  The rank is
read from R's diagonal with the columns scaled to unit norm (so that a kilogram and a kg·m²
weigh alike), relative to its largest entry.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg

__all__ = ["RANK_TOLERANCE", "BaseParameters", "base_parameters"]

#: |R_kk| / |R_00| below this (columns scaled to unit norm) counts as zero: the column depends on the
#: earlier ones.  Round-off in Y is near 1e-14; a genuinely independent column rarely falls below 1e-6.
RANK_TOLERANCE = 1e-8
#: Coefficients of β (columns scaled to unit norm) smaller than this are round-off: dropped.
COEFFICIENT_TOLERANCE = 1e-9


@dataclass(frozen=True)
class BaseParameters:
    """The base parameters of a regressor's columns (module docstring).

    Parameters
    ----------
    names : tuple of str
        The parameters, in the order of Y's columns.
    independent : tuple of int
        Indices of the r columns Y₁ (each base parameter is led by one).
    dependent : tuple of int
        Indices of the other columns.
    beta : ndarray of shape (r, P − r)
        The coefficients β: θ_b = θ[independent] + β θ[dependent].
    zero : tuple of int
        Indices of the columns that are zero (the parameter does not act at all).
    """

    names: tuple[str, ...]
    independent: tuple[int, ...]
    dependent: tuple[int, ...]
    beta: np.ndarray
    zero: tuple[int, ...]

    @property
    def rank(self) -> int:
        return len(self.independent)

    @property
    def full(self) -> bool:
        return len(self.dependent) == 0

    def matrix(self) -> np.ndarray:
        """The matrix K of the base parameters, θ_b = K θ.

        Returns
        -------
        ndarray of shape (r, P)
            K.
        """
        K = np.zeros((self.rank, len(self.names)))
        K[np.arange(self.rank), list(self.independent)] = 1.0
        if self.dependent:
            K[:, list(self.dependent)] = self.beta
        return K

    def combination(self, k: int, digits: int = 6) -> str:
        """Base parameter k as text: ``Izz_column + 0.09 m_upper_arm + mx_upper_arm``.

        Parameters
        ----------
        k : int
            The base parameter's index.
        digits : int, optional
            Significant digits of the coefficients.

        Returns
        -------
        str
            The combination.
        """
        return format_combination(self.names, self.matrix()[k], digits)

    def combinations(self, digits: int = 6) -> list[str]:
        return [self.combination(k, digits) for k in range(self.rank)]

    def alone(self) -> list[str]:
        """The parameters identified on their own: a base parameter that no other enters.

        Returns
        -------
        list of str
            Their names.
        """
        K = self.matrix()
        out = []
        for k, j in enumerate(self.independent):
            if np.count_nonzero(K[k]) == 1:
                out.append(self.names[j])
        return out


def format_combination(names: Sequence[str], row: np.ndarray, digits: int = 6) -> str:
    """Σ row_j names_j as text, unit coefficients unwritten."""
    parts = []
    for name, c in zip(names, row, strict=True):
        if c == 0:
            continue
        sign = "-" if c < 0 else "+"
        size = abs(c)
        text = name if abs(size - 1.0) < 1e-12 else f"{size:.{digits}g} {name}"
        parts.append((sign, text))
    if not parts:
        return "0"
    first = ("-" if parts[0][0] == "-" else "") + parts[0][1]
    return " ".join([first, *(f"{s} {t}" for s, t in parts[1:])])


def base_parameters(Y: np.ndarray, names: Sequence[str]) -> BaseParameters:
    """The base parameters of the stacked regressor ``Y`` (rows: equations at many states; columns: ``names``).

    The rank comes from the QR factorisation with column pivoting (module docstring).  The r
    columns kept are then the first ones, in the order of ``names``, that are independent of those
    kept before them (Gram–Schmidt with the same tolerance), so that the combinations do not depend
    on the states Y was evaluated at: each is led by its earliest parameter
    (``mx_upper_arm + 0.5 m_forearm``).  Should the two disagree, the pivots of the QR are kept.

    Parameters
    ----------
    Y : ndarray of shape (rows, P)
        The stacked regressor.
    names : sequence of str
        The parameters of its columns.

    Returns
    -------
    BaseParameters
        The base parameters.
    """
    Y = np.asarray(Y, dtype=float)
    P = Y.shape[1]
    norms = np.linalg.norm(Y, axis=0)
    top = float(norms.max(initial=0.0))
    zero = tuple(int(j) for j in np.flatnonzero(norms <= 1e-12 * max(top, 1e-300)))
    live = [j for j in range(P) if j not in zero]
    if not live:
        return BaseParameters(tuple(names), (), tuple(range(P)), np.zeros((0, P)), zero)
    scaled = Y[:, live] / norms[live]
    _, R, piv = scipy.linalg.qr(scaled, mode="economic", pivoting=True)
    diag = np.abs(np.diag(R))
    rank = int(np.sum(diag > RANK_TOLERANCE * diag[0]))
    independent = _first_independent(scaled, rank)
    if independent is None:
        independent = sorted(int(k) for k in piv[:rank])
    independent = [live[k] for k in independent]
    dependent = [j for j in live if j not in independent]
    beta = np.zeros((rank, P - rank))
    if dependent:
        coef, *_ = np.linalg.lstsq(Y[:, independent] / norms[independent], Y[:, dependent] / norms[dependent],
                                   rcond=None)
        coef[np.abs(coef) < COEFFICIENT_TOLERANCE] = 0.0
        # back to the parameters' own units: Y₂ = Y₁ β with Y = scaled · norms
        beta[:, : len(dependent)] = coef * norms[dependent][None, :] / norms[independent][:, None]
    return BaseParameters(tuple(names), tuple(independent), tuple(dependent) + zero, beta, zero)


def _first_independent(scaled: np.ndarray, rank: int) -> list[int] | None:
    """Indices of the first ``rank`` columns, in order, each independent of those before it; None if they
    are not exactly ``rank``."""
    basis = np.zeros((scaled.shape[0], 0))
    kept = []
    for j in range(scaled.shape[1]):
        column = scaled[:, j]
        residual = column - basis @ (basis.T @ column)
        residual -= basis @ (basis.T @ residual)  # twice is enough (Kahan, Parlett)
        size = float(np.linalg.norm(residual))
        if size > RANK_TOLERANCE:
            kept.append(j)
            basis = np.column_stack([basis, residual / size])
    return kept if len(kept) == rank else None
