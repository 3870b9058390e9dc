"""Rates and accelerations of a measured coordinate: local polynomial least squares (Savitzky–Golay).

The regressor needs q̇ and q̈ at each sample; when only q is measured they are estimated by
fitting, around each sample t_i, a polynomial of degree ``order`` to the ``window`` samples
nearest in index, by least squares, and differentiating it at t_i (Savitzky & Golay, *Anal.
Chem.* 36, 1964; the same as ``scipy.signal.savgol_filter`` on a uniform grid, and valid on a
non-uniform one).  A polynomial of degree ``order`` is differentiated exactly; white noise of
standard deviation σ on q leaves an error of about σ/(w h) on q̇ and σ/(w h)² on q̈ (w the
window, h the sample spacing), against a bias growing as (w h)^(order − 1) on q̈: the window
trades one for the other.  Near the ends the window cannot be centred, and its estimates are
poorer: the regression leaves out the first and last ``window // 2`` samples (`trim`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import IdentificationError

__all__ = ["SavitzkyGolay"]


@dataclass(frozen=True)
class SavitzkyGolay:
    """Local polynomial derivatives (module docstring).

    Parameters
    ----------
    window : int
        The number of samples of each fit (odd).
    order : int
        The degree of the polynomial.
    """

    window: int = 21
    order: int = 4

    def __post_init__(self) -> None:
        if not (isinstance(self.window, int) and self.window >= 3 and self.window % 2 == 1):
            raise IdentificationError(f"The derivative filter's window is {self.window!r} samples: it must be an odd "
                                      "number, at least 3.", fix="e.g. SavitzkyGolay(window=21, order=4)")
        if not (isinstance(self.order, int) and 2 <= self.order < self.window):
            raise IdentificationError(f"The derivative filter's order is {self.order!r}: it must be at least 2 (for "
                                      f"q̈) and below the window ({self.window}).",
                                      fix="e.g. SavitzkyGolay(window=21, order=4)")

    @property
    def trim(self) -> int:
        """Samples left out at each end of the record."""
        return self.window // 2

    def derivatives(self, t: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The local fits' values and derivatives (x, ẋ, ẍ) at every sample.

        Parameters
        ----------
        t : ndarray of shape (N,)
            The times.
        x : ndarray of shape (N,) or (N, k)
            The samples.

        Returns
        -------
        x : ndarray
            The smoothed samples.
        xdot : ndarray
            The first derivative ẋ.
        xddot : ndarray
            The second derivative ẍ.
        """
        t = np.asarray(t, dtype=float)
        x = np.asarray(x, dtype=float)
        flat = x.reshape(len(t), -1)
        N, w, d = len(t), self.window, self.order
        if N < w:
            raise IdentificationError(f"The record has {N} samples, fewer than the derivative filter's window ({w}).",
                                      fix=f"give at least {w} samples, or a smaller window")
        start = np.clip(np.arange(N) - w // 2, 0, N - w)
        index = start[:, None] + np.arange(w)[None, :]  # (N, w): the window of each sample
        local = t[index] - t[:, None]
        scale = np.maximum(np.abs(local).max(axis=1), 1e-300)[:, None]
        powers = (local / scale)[:, :, None] ** np.arange(d + 1)[None, None, :]  # (N, w, d + 1)
        spacing = np.diff(t)
        if np.ptp(spacing) <= 1e-9 * np.mean(spacing):
            # A uniform grid: the fit depends only on where the sample sits in its window (w cases).
            where = np.arange(N) - start
            cases = np.unique(where)
            first = np.array([np.flatnonzero(where == k)[0] for k in cases])
            pinv = np.linalg.pinv(powers[first])[np.searchsorted(cases, where)]
        else:
            pinv = np.linalg.pinv(powers)  # (N, d + 1, w)
        coef = np.einsum("nkw,nwc->nkc", pinv, flat[index])  # (N, d + 1, k)
        value = coef[:, 0]
        rate = coef[:, 1] / scale
        acceleration = 2.0 * coef[:, 2] / scale ** 2
        shape = x.shape
        return value.reshape(shape), rate.reshape(shape), acceleration.reshape(shape)
