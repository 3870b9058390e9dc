"""Matrix work at the point of a linearization: Jacobians, solves, submatrices, tidy entries.

Entries are SymEngine expressions in the parameters left symbolic; when none is left the
solves go through LAPACK, which is exact enough and much faster than a symbolic LU.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import symengine as se
from symengine.lib.symengine_wrapper import sympy2symengine

from .._big_numbers import has_big_numbers

__all__ = ["RANK_RTOL", "TIDY_MAX_CHARS", "choose", "jacobian", "solve", "stack", "sub", "tidy"]

#: Relative size below which a singular value counts as zero when columns are chosen.
RANK_RTOL = 1e-9


def choose(columns: np.ndarray, count: int, order: Sequence[int]) -> list[int]:
    """``count`` columns, taken greedily in ``order``, each raising the numerical rank."""
    chosen: list[int] = []
    if count == 0:
        return chosen
    scale = max(1.0, float(np.abs(columns).max(initial=0.0)))
    for j in order:
        trial = columns[:, chosen + [j]]
        if np.linalg.matrix_rank(trial, tol=RANK_RTOL * scale) == len(chosen) + 1:
            chosen.append(j)
            if len(chosen) == count:
                break
    return chosen


def solve(A: se.DenseMatrix, B: se.DenseMatrix) -> se.DenseMatrix:
    """A⁻¹ B: by LAPACK when A is numeric (B may hold symbols: A⁻¹ is then applied to them), else by
    a symbolic LU.

    A numeric A goes through LAPACK even when its entries are unevaluated numbers such as
    sin(157/500): a symbolic LU would take as pivot an entry that is zero only numerically
    (sin a cos b − cos a sin b with a = b) and divide by it.
    """
    if A.rows == 0:
        return se.zeros(0, B.cols)
    if not A.free_symbols:
        a = np.array(A.tolist(), dtype=float)
        if not B.free_symbols:
            b = np.array(B.tolist(), dtype=float)
            return se.DenseMatrix(np.linalg.solve(a, b).tolist())
        return se.DenseMatrix(np.linalg.inv(a).tolist()) * B
    return A.LUsolve(B)


def jacobian(exprs: Sequence[se.Basic], variables: Sequence[se.Symbol], subs: Mapping[se.Basic, se.Basic]) -> se.DenseMatrix:
    """∂exprs/∂variables evaluated at ``subs``."""
    if not exprs or not variables:
        return se.zeros(len(exprs), len(variables))
    # One SymEngine call for the derivatives and one for the substitution (no Python loop per entry).
    return se.DenseMatrix(list(exprs)).jacobian(se.DenseMatrix(list(variables))).subs(dict(subs))


#: Symbolic entries up to this many characters are put over a common denominator and factored
#: (SymPy's `cancel` and `factor`: −g (m1 + m2)/(l1 m1) rather than the LU's nested fractions).
TIDY_MAX_CHARS = 1500
#: Entries longer than this are left as they are: expanding a nested fraction of that size (the
#: symbolic LU of the bicycle's reduced mass matrix, 10⁵ characters an entry) multiplies its
#: terms out without bound (minutes and gigabytes) to give an entry nobody reads.
EXPAND_MAX_CHARS = 5000


def tidy(m: se.DenseMatrix) -> se.DenseMatrix:
    """Each entry in its shortest form: expanded, or (symbolic and small) cancelled and factored."""
    import sympy  # late: SymPy takes most of a second to load, and only this needs it

    out = []
    for i in range(m.rows):
        row = []
        for j in range(m.cols):
            e = m[i, j]
            best, size = e, len(str(e))
            if size > EXPAND_MAX_CHARS:
                row.append(e)
                continue
            x = se.expand(e)
            if len(str(x)) <= size:
                best, size = x, len(str(x))
            if e.free_symbols and size <= TIDY_MAX_CHARS and not has_big_numbers(best):
                y = sympy2symengine(sympy.factor(sympy.cancel(best._sympy_())))
                if len(str(y)) <= size:
                    best = y
            row.append(best)
        out.append(row)
    return se.DenseMatrix(out) if out else m


def sub(m: se.DenseMatrix, rows: Sequence[int], cols: Sequence[int]) -> se.DenseMatrix:
    """The submatrix of ``m`` on ``rows`` and ``cols``."""
    if not rows or not cols:
        return se.zeros(len(rows), len(cols))
    return se.DenseMatrix([[m[i, j] for j in cols] for i in rows])


def stack(n: int, top_idx: Sequence[int], top: se.DenseMatrix, bottom_idx: Sequence[int],
           bottom: se.DenseMatrix) -> se.DenseMatrix:
    """The n-row matrix whose rows ``top_idx`` are ``top`` and rows ``bottom_idx`` are ``bottom``."""
    out = se.zeros(n, top.cols)
    for r, i in enumerate(top_idx):
        for c in range(top.cols):
            out[i, c] = top[r, c]
    for r, i in enumerate(bottom_idx):
        for c in range(bottom.cols):
            out[i, c] = bottom[r, c]
    return out
