"""`InputTable`: an input u(t) given by samples, with a declared interpolation.

Between the sample times t_0 < t_1 < … < t_{N−1} with values v_k, the input is

``"zoh"`` (zero-order hold, as a digital controller applies a command)
    u(t) = v_k on t_k ≤ t < t_{k+1}: right-continuous, a jump at each sample;
``"linear"``
    u(t) = v_k + (t − t_k)(v_{k+1} − v_k)/(t_{k+1} − t_k): continuous, its slope jumps at each sample;
``"quadratic"`` (an odd number of samples N = 2m + 1: knots t_0, t_2, …, t_{2m} and one sample
    between each two)
    on t_{2j} ≤ t ≤ t_{2j+2}, the parabola through the three samples (t_{2j}, v_{2j}),
    (t_{2j+1}, v_{2j+1}), (t_{2j+2}, v_{2j+2}) — Lagrange's quadratic: with a = t_{2j},
    c = t_{2j+1}, b = t_{2j+2},
        u(t) = v_{2j} (t − c)(t − b)/((a − c)(a − b)) + v_{2j+1} (t − a)(t − b)/((c − a)(c − b))
               + v_{2j+2} (t − a)(t − c)/((b − a)(b − c));
    continuous, its slope jumps at the knots only.  This is the input Hermite–Simpson collocation
    stands for: u_k, u_c, u_{k+1} at an interval's ends and midpoint (Betts, *Practical Methods for
    Optimal Control*, 2nd ed., §4.6.2; Kelly, SIAM Review 59(4), 2017, §4.3);
``"cubic"``
    the C² cubic spline through the samples with not-a-knot ends (de Boor, *A Practical Guide
    to Splines*, ch. IV; SciPy's ``CubicSpline`` default): its third derivative jumps at each
    interior sample.

Outside [t_0, t_{N−1}] every kind holds the end value (v_0 before, v_{N−1} after): a table
never extrapolates.

Each kind is smooth between two breakpoints and not across one — every sample time, or for
``"quadratic"`` every knot — so the compiled integrators stop at every breakpoint and start
again (`codegen/runtime/integrators.c`, ``lg_run``): an error estimate never straddles a jump of u (zoh) or of
its derivatives (linear, quadratic, cubic), which would make DOP853 shrink its step blindly
around each sample until the kink is resolved, at the cost of many rejected steps and of its
order there.

``"quadratic"`` and ``"cubic"`` are read the same way, by the compiled code as here: a polynomial
piece per interval between two samples, c0 s³ + c1 s² + c2 s + c3 with s = t − t_k (for the
parabola, c0 = 0 and both halves of a knot interval hold the same parabola, expanded about their
own left sample).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import SimulationError

__all__ = ["INTERPOLATIONS", "InputTable"]

#: The interpolation kinds, in the order of their smoothness.
INTERPOLATIONS = ("zoh", "linear", "quadratic", "cubic")
#: The kinds read as a polynomial piece per interval (`InputTable.coefficients`).
_PIECEWISE = ("quadratic", "cubic")


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class InputTable:
    """Samples (t_k, v_k) of an input and how to read between them (module docstring).

    Parameters
    ----------
    t : ndarray of shape (N,)
        N ≥ 2 strictly increasing finite times.
    values : ndarray of shape (N,)
        Finite values.
    interpolation : {"zoh", "linear", "quadratic", "cubic"}, optional
        ``"zoh"``, ``"linear"`` (default), ``"quadratic"`` (N odd ≥ 3) or ``"cubic"``.
    name : str, optional
        Where the samples came from, for messages (``force in run.csv``).

    Raises
    ------
    SimulationError
        Times that do not increase, a NaN or infinite number, lengths that differ, fewer
        than two samples (an even number for ``"quadratic"``), an unknown interpolation.

    Examples
    --------
    >>> u = InputTable([0.0, 1.0, 2.0], [0.0, 2.0, 0.0], interpolation="linear")
    >>> float(u(0.5)), float(u(3.0))
    (1.0, 0.0)
    >>> float(InputTable([0.0, 1.0], [5.0, 7.0], interpolation="zoh")(1.0))
    7.0
    >>> float(InputTable([0.0, 1.0, 2.0], [0.0, 1.0, 4.0], interpolation="quadratic")(1.5))  # t²
    2.25
    """

    t: np.ndarray
    values: np.ndarray
    interpolation: str = "linear"
    name: str = ""  # where the samples came from, for messages (``force in run.csv``)
    _coefficients: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        what = f"The input table{' ' + self.name if self.name else ''}"
        if self.interpolation not in INTERPOLATIONS:
            raise SimulationError(f"{what}: unknown interpolation `{self.interpolation}`.",
                                  fix="use " + ", ".join(f"'{k}'" for k in INTERPOLATIONS))
        try:
            t = np.asarray(self.t, dtype=float)
            v = np.asarray(self.values, dtype=float)
        except (TypeError, ValueError):
            raise SimulationError(f"{what}: the times and values must be numbers.",
                                  fix="give two 1-D sequences of numbers of the same length") from None
        if t.ndim != 1 or v.ndim != 1:
            raise SimulationError(f"{what}: times and values must be 1-D (shapes {t.shape} and {v.shape}).",
                                  fix="give one value per time")
        if len(t) != len(v):
            raise SimulationError(f"{what} has {len(t)} times but {len(v)} values.", fix="give one value per time")
        if len(t) < 2:
            raise SimulationError(f"{what} has {len(t)} sample{'s' if len(t) != 1 else ''}; at least 2 are needed.",
                                  fix="give the input at two times at least (a constant is a number: inputs={'F': 2.0})")
        for label, a in (("time", t), ("value", v)):
            bad = np.flatnonzero(~np.isfinite(a))
            if len(bad):
                raise SimulationError(f"{what}: the {label} of sample {bad[0]} is {a[bad[0]]}, not a finite number.",
                                      fix="remove or fill the missing samples (NaN) before giving the table")
        steps = np.diff(t)
        if np.any(steps <= 0):
            k = int(np.flatnonzero(steps <= 0)[0])
            raise SimulationError(f"{what}: the times must increase strictly, but t[{k + 1}] = {t[k + 1]:.9g} "
                                  f"follows t[{k}] = {t[k]:.9g}.",
                                  fix="sort the samples by time and merge repeated times")
        if self.interpolation == "quadratic" and len(t) % 2 == 0:
            raise SimulationError(f"{what} has {len(t)} samples; a quadratic table needs an odd number (the knots "
                                  "and one sample between each two).",
                                  fix="give the knots t_0, t_2, ... and one sample inside each interval, "
                                      "or use 'linear' or 'cubic'")
        object.__setattr__(self, "t", _readonly(t))
        object.__setattr__(self, "values", _readonly(v))
        pieces = {"cubic": _spline, "quadratic": _parabolas}.get(self.interpolation)
        object.__setattr__(self, "_coefficients", _readonly(pieces(t, v) if pieces else np.zeros((0, 4))))

    # -- reading -------------------------------------------------------------------------------
    @classmethod
    def from_csv(cls, path: str | Path, column: str, *, time_column: str = "t",
                 interpolation: str = "linear") -> InputTable:
        """The table of ``column`` against ``time_column`` in a CSV file with a header row.

        Lines that begin with ``#`` are comments: a trajectory written by ``save_trajectory`` or ``-o`` is
        read as it is.

        Parameters
        ----------
        path : str or Path
            The CSV file.
        column : str
            The column of the values.
        time_column : str, optional
            The column of the times.
        interpolation : {"zoh", "linear", "quadratic", "cubic"}, optional
            How to read between the samples.

        Returns
        -------
        InputTable
            The table, named after the column and the file.

        Raises
        ------
        SimulationError
            A file that cannot be read, a column that is not there (the columns are listed),
            a cell that is not a number (with its row), or the table's own errors.
        """
        path = Path(path)
        try:
            with path.open(newline="", encoding="utf-8") as handle:
                rows = list(csv.reader(handle))
        except (OSError, UnicodeDecodeError) as exc:
            raise SimulationError(f"The input file `{path}` cannot be read ({exc}).",
                                  fix="give the path of a CSV file with a header row, e.g. t,F") from None
        except csv.Error as exc:
            raise SimulationError(f"`{path}` is not a CSV file ({exc}).", fix="write it with comma-separated "
                                  "columns and a header row") from None
        # blank rows, and the comment lines (`#`) that a trajectory file written by lagrangian begins with
        rows = [r for r in rows if any(cell.strip() for cell in r) and not r[0].lstrip().startswith("#")]
        if not rows:
            raise SimulationError(f"The input file `{path}` is empty.", fix="write a header row (e.g. t,F) and samples")
        header = [cell.strip() for cell in rows[0]]
        for name in (time_column, column):
            if name not in header:
                raise SimulationError(f"`{path}` has no column `{name}` (its columns: {', '.join(header)}).",
                                      fix="name the column in the file's header, or choose one of its columns")
        i, j = header.index(time_column), header.index(column)
        times, values = [], []
        for line, row in enumerate(rows[1:], start=2):
            try:
                times.append(_cell(row, i))
                values.append(_cell(row, j))
            except ValueError as exc:
                raise SimulationError(f"`{path}`, line {line}: {exc}.",
                                      fix="write plain decimal numbers in the time and input columns") from None
        return cls(np.array(times), np.array(values), interpolation, name=f"`{column}` of `{path}`")

    # -- values -----------------------------------------------------------------------------------
    @property
    def breakpoints(self) -> np.ndarray:
        """The times where u or a derivative of it jumps: every sample time (``"quadratic"``: every knot)."""
        return self.t[0::2] if self.interpolation == "quadratic" else self.t

    @property
    def coefficients(self) -> np.ndarray:
        """The polynomial pieces of a ``"quadratic"`` or ``"cubic"`` table; else empty.

        Shape (N − 1, 4): piece k is c0 s³ + c1 s² + c2 s + c3 with s = t − t_k.
        """
        return self._coefficients

    def __call__(self, t: float | np.ndarray, window: float | None = None) -> np.ndarray:
        """u at ``t`` (any shape).  ``window``: a time inside the interval whose piece is used
        (the compiled code's rule between two restarts: the piece of that interval, even at its
        right end); None: the piece of each t itself (zoh right-continuous)."""
        t = np.asarray(t, dtype=float)
        ts, v = self.t, self.values
        where = t if window is None else np.full_like(t, window)
        k = np.clip(np.searchsorted(ts, where, side="right") - 1, 0, len(ts) - 2)
        if self.interpolation == "zoh":
            k0 = np.searchsorted(ts, where, side="right") - 1
            out = v[np.clip(k0, 0, len(ts) - 1)]
        elif self.interpolation == "linear":
            out = v[k] + (t - ts[k]) * (v[k + 1] - v[k]) / (ts[k + 1] - ts[k])
        else:  # a polynomial piece (quadratic, cubic)
            c = self._coefficients[k]
            s = t - ts[k]
            out = ((c[..., 0] * s + c[..., 1]) * s + c[..., 2]) * s + c[..., 3]
        out = np.where(where < ts[0], v[0], np.where(where >= ts[-1], v[-1], out))
        return out

    def data(self) -> np.ndarray:
        """The numbers the compiled code reads: times, values, then (quadratic, cubic) the coefficients.

        Returns
        -------
        ndarray
            Times, values, then (quadratic, cubic) the coefficients.
        """
        return np.concatenate([self.t, self.values, self._coefficients.ravel()])

    def __repr__(self) -> str:
        return (f"InputTable({len(self.t)} samples on [{self.t[0]:g}, {self.t[-1]:g}], "
                f"interpolation={self.interpolation!r})")


def _cell(row: list[str], k: int) -> float:
    if k >= len(row) or not row[k].strip():
        raise ValueError(f"column {k + 1} is empty")
    text = row[k].strip()
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"`{text}` is not a number") from None
    if not math.isfinite(value):
        raise ValueError(f"`{text}` is not a finite number")
    return value


def _parabolas(t: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The quadratic table's pieces (N − 1, 4), highest power first: on each sample interval, the parabola
    of its knot interval (module docstring) expanded about the interval's left sample.

    In Newton's form on a knot interval (a, c, b), u = v_a + d1 (t − a) + d2 (t − a)(t − c) with the
    divided differences d1 = (v_c − v_a)/(c − a), d2 = ((v_b − v_c)/(b − c) − d1)/(b − a); about a it is
    d2 s² + (d1 − d2 (c − a)) s + v_a, about c it is d2 s² + (d1 + d2 (c − a)) s + v_c.
    """
    a, c, b = t[0:-1:2], t[1::2], t[2::2]
    va, vc, vb = v[0:-1:2], v[1::2], v[2::2]
    d1 = (vc - va) / (c - a)
    d2 = ((vb - vc) / (b - c) - d1) / (b - a)
    out = np.zeros((len(t) - 1, 4))
    out[0::2, 1], out[0::2, 2], out[0::2, 3] = d2, d1 - d2 * (c - a), va
    out[1::2, 1], out[1::2, 2], out[1::2, 3] = d2, d1 + d2 * (c - a), vc
    return out


def _spline(t: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The not-a-knot cubic spline's pieces (N − 1, 4), highest power first (SciPy's ``CubicSpline``)."""
    from scipy.interpolate import CubicSpline

    return np.ascontiguousarray(CubicSpline(t, v, bc_type="not-a-knot").c.T)
