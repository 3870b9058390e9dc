"""The eigenvalues (and vectors) of a mass matrix, scaled so that LAPACK can find them.

M is symmetric positive definite where the coordinates are regular; its eigenvalues say
whether it is singular (the smallest below 1e-12 of the largest) and along which rates.
LAPACK's symmetric QR iteration does not converge on entries near the overflow threshold
(a mass of 1e308 gives "Eigenvalues did not converge", found by tools/fuzz.py): the matrix
is divided by its largest entry first, and the eigenvalues multiplied back (the vectors do
not change).  The symmetric part is formed as ½M + ½Mᵀ of the scaled matrix, which cannot
overflow.
"""

from __future__ import annotations

import numpy as np

__all__ = ["mass_eigenvalues", "mass_eigh"]


def _scaled(M: np.ndarray) -> tuple[np.ndarray, float]:
    size = float(np.max(np.abs(M))) if M.size else 1.0
    size = size if size > 0 and np.isfinite(size) else 1.0
    S = M / size
    return 0.5 * S + 0.5 * S.T, size


def mass_eigenvalues(M: np.ndarray) -> np.ndarray:
    """The eigenvalues of the symmetric part of M, ascending."""
    S, size = _scaled(np.asarray(M, dtype=float))
    return np.linalg.eigvalsh(S) * size


def mass_eigh(M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues (ascending) and unit eigenvectors (columns) of the symmetric part of M."""
    S, size = _scaled(np.asarray(M, dtype=float))
    w, v = np.linalg.eigh(S)
    return w * size, v
