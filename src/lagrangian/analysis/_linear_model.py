"""The result of a linearization: ẋ = A x + B u and M δq̈ + (D + G) δq̇ + (K + N) δq = B u, as values.

`linearize` (in `_linearize`) builds a `LinearModel`; its entries depend only on the parameters
left symbolic, and its methods evaluate them (`numeric`), give the modes and the verdict
(`_modes`) and the state-space objects of SciPy and python-control.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields

import numpy as np
import symengine as se

from .._display import render
from ..dynamics import EquationsOfMotion
from ..errors import AnalysisError

__all__ = ["LinearModel", "LinearizationError", "SecondOrderForm", "to_numpy"]

_ZERO = se.Integer(0)


def _is_structural_zero(e: se.Basic) -> bool:
    return e == _ZERO


class _ColumnlessMatrix(se.MutableDenseMatrix):
    """An n × 0 SymEngine matrix (B without inputs) that prints.

    SymEngine's C++ printer (``DenseMatrix::__str__``, 0.15) loops ``for j < col_ - 1`` in unsigned
    arithmetic: with no column ``col_ - 1`` wraps to 2³² − 1 and the loop reads past the entries, a
    segmentation fault on ``str``/``repr`` of any n × 0 matrix with n > 0.  This one prints one empty
    row ``[]`` per row, as SymEngine prints ``[a, b]`` per row, and is otherwise SymEngine's matrix.
    """

    def __str__(self) -> str:
        return "[]\n" * self.rows

    def __repr__(self) -> str:
        return self.__str__()

    def __reduce__(self) -> tuple[object, tuple[int, int, list[se.Basic]]]:
        return _ColumnlessMatrix, (self.rows, 0, [])


def _printable(obj: object) -> None:
    """Make the n × 0 matrices held by the dataclass ``obj`` `_ColumnlessMatrix`, so that printing
    ``obj`` (its dataclass ``repr``) or the matrix itself does not crash SymEngine."""
    for f in fields(obj):  # type: ignore[arg-type]
        m = getattr(obj, f.name)
        if isinstance(m, se.DenseMatrix) and m.cols == 0 and m.rows > 0 and not isinstance(m, _ColumnlessMatrix):
            object.__setattr__(obj, f.name, _ColumnlessMatrix(m.rows, 0, []))


class LinearizationError(AnalysisError):
    """The linearization cannot be made.

    An incomplete or unknown point, a point that is not an equilibrium or a steady motion, a singular
    mass matrix or constraint Jacobian there.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """


@dataclass(frozen=True, slots=True)
class SecondOrderForm:
    """The small motions M δq̈ + (D + G) δq̇ + (K + N) δq = B u on ``coordinates`` (D, K symmetric; G, N skew).

    Parameters
    ----------
    coordinates : tuple of str
        The coordinates δq.
    M : SymEngine DenseMatrix
        The mass matrix.
    D : SymEngine DenseMatrix
        The damping matrix.
    G : SymEngine DenseMatrix
        The gyroscopic matrix.
    K : SymEngine DenseMatrix
        The stiffness matrix.
    N : SymEngine DenseMatrix
        The circulatory matrix.
    B : SymEngine DenseMatrix
        The input matrix.
    """

    coordinates: tuple[str, ...]
    M: se.DenseMatrix
    D: se.DenseMatrix
    G: se.DenseMatrix
    K: se.DenseMatrix
    N: se.DenseMatrix
    B: se.DenseMatrix

    def __post_init__(self) -> None:
        _printable(self)  # B is n × 0 without inputs


@dataclass(frozen=True, slots=True, eq=False)
class LinearModel:
    """The linear system ẋ = A x + B u about a steady point, and its second-order form when it has one.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations it comes from.
    point : dict of str to SymEngine expression
        The point, name → value (every coordinate and every rate, dependent ones solved).
    coordinates : tuple of str
        The independent coordinates: the state is ``coordinates + speeds``.
    speeds : tuple of str
        The independent speeds (``<c>_dot``).
    dependent_coordinates : tuple of str
        The coordinates eliminated by the constraints.
    dependent_speeds : tuple of str
        The speeds eliminated by the constraints.
    choice : str
        A sentence saying how the dependent ones were chosen.
    inputs : tuple of str
        The names of the inputs u (columns of B).
    A : SymEngine DenseMatrix
        The state matrix; its entries depend only on ``symbols``.
    B : SymEngine DenseMatrix
        The input matrix; its entries depend only on ``symbols``.
    symbols : tuple of SymEngine Symbol
        The parameters left symbolic (the others were given their values).
    values : dict of str to float
        The parameter values substituted.
    second_order : SecondOrderForm or None
        The second-order form, or None with ``second_order_reason``.
    second_order_reason : str
        Why there is no second-order form.
    ignorable : tuple of str
        Independent coordinates that do not act on the motion: their columns of A are zero once the
        other ignorable ones are set aside.
    residual : float
        The relative residual force at the point (0 for an exact equilibrium).
    multipliers : dict of str to SymEngine expression
        The multipliers λ0 of the complementary constraints at the point.
    coordinate_map : SymEngine DenseMatrix, optional
        P, with δq = P δq_i: every coordinate's perturbation from the independent ones (the identity
        without holonomic complementary constraints).
    """

    eom: EquationsOfMotion
    point: dict[str, se.Basic]
    coordinates: tuple[str, ...]
    speeds: tuple[str, ...]
    dependent_coordinates: tuple[str, ...]
    dependent_speeds: tuple[str, ...]
    choice: str
    inputs: tuple[str, ...]
    A: se.DenseMatrix
    B: se.DenseMatrix
    symbols: tuple[se.Symbol, ...]
    values: dict[str, float]
    second_order: SecondOrderForm | None
    second_order_reason: str
    ignorable: tuple[str, ...]
    residual: float
    multipliers: dict[str, se.Basic] = field(default_factory=dict)
    coordinate_map: se.DenseMatrix | None = None

    def __post_init__(self) -> None:
        _printable(self)  # B is n × 0 without inputs

    @property
    def state(self) -> tuple[str, ...]:
        """Names of the state x in order, e.g. ``("theta", "theta_dot")``."""
        return self.coordinates + self.speeds

    @property
    def steady(self) -> bool:
        """Some coordinate moves at the point (a steady motion rather than an equilibrium)."""
        return any(not _is_structural_zero(self.point[c + "_dot"]) for c in self.eom.coordinates)

    def _values(self, values: Mapping[str, float]) -> dict[se.Basic, float]:
        names = {str(s): s for s in self.symbols}
        unknown = sorted(set(values) - set(names))
        if unknown:
            raise LinearizationError(
                f"`{unknown[0]}` is not a symbol of this linearization (its symbols: "
                f"{', '.join(names) or 'none'}).", fix="give values only to the parameters left symbolic")
        missing = [n for n in names if n not in values]
        if missing:
            raise LinearizationError(f"the parameter `{missing[0]}` has no value.",
                                     fix=f"give it one, e.g. `{missing[0]}=1.0`")
        return {names[n]: float(v) for n, v in values.items()}

    def numeric(self, **values: float) -> tuple[np.ndarray, np.ndarray]:
        """The matrices A and B as float arrays.

        Parameters
        ----------
        **values : float
            Values of the symbols left symbolic.

        Returns
        -------
        A : ndarray of shape (nx, nx)
            The state matrix.
        B : ndarray of shape (nx, m)
            The input matrix.
        """
        subs = self._values(values)
        return to_numpy(self.A, subs), to_numpy(self.B, subs)

    def eigenvalues(self, **values: float) -> np.ndarray:
        """The eigenvalues of A (complex), in LAPACK's order.

        Parameters
        ----------
        **values : float
            Values of the symbols left symbolic.

        Returns
        -------
        ndarray of shape (nx,), complex
            The eigenvalues.
        """
        A, _ = self.numeric(**values)
        return np.linalg.eigvals(A) if A.size else np.zeros(0, complex)

    def modes(self, **values: float):
        """Natural frequencies, damping ratios and mode shapes (`lagrangian.analysis.Modes`).

        Parameters
        ----------
        **values : float
            Values of the symbols left symbolic.

        Returns
        -------
        Modes
            The modes of the linearization.
        """
        from ._modes import modes
        return modes(self, **values)

    def stability(self, **values: float):
        """The stability verdict with its reason (`lagrangian.analysis.Stability`).

        Parameters
        ----------
        **values : float
            Values of the symbols left symbolic.

        Returns
        -------
        Stability
            The verdict and its reason.
        """
        from ._modes import stability
        return stability(self, **values)

    def _repr_latex_(self) -> str:
        """ẋ = A x + B u written out, about the point (Jupyter); large states give the sizes only."""
        return render(self, "latex")

    def to_scipy(self, **values: float):
        """The linearization as ``scipy.signal.StateSpace(A, B, I, 0)``: the whole state as output.

        Parameters
        ----------
        **values : float
            Values of the symbols left symbolic.

        Returns
        -------
        scipy.signal.StateSpace
            The continuous-time system.
        """
        from scipy import signal
        A, B = self.numeric(**values)
        n = A.shape[0]
        B = B if B.shape[1] else np.zeros((n, 1))
        return signal.StateSpace(A, B, np.eye(n), np.zeros((n, B.shape[1])))

    def to_control(self, **values: float):
        """The linearization as python-control's ``StateSpace`` (``lagrangian[control]``), states and inputs named.

        Parameters
        ----------
        **values : float
            Values of the symbols left symbolic.

        Returns
        -------
        control.StateSpace
            The continuous-time system, the whole state as output.
        """
        try:
            import control
        except ImportError:  # pragma: no cover - depends on the installation
            raise LinearizationError("python-control is not installed.",
                                     fix="pip install 'lagrangian[control]'") from None
        A, B = self.numeric(**values)
        n = A.shape[0]
        inputs = list(self.inputs) or ["u"]
        B = B if B.shape[1] else np.zeros((n, 1))
        return control.ss(A, B, np.eye(n), np.zeros((n, B.shape[1])),
                          states=list(self.state), inputs=inputs, outputs=list(self.state))


def to_numpy(m: se.DenseMatrix, subs: Mapping[se.Basic, float]) -> np.ndarray:
    """The matrix ``m`` at ``subs`` as a real float array of its shape.

    Parameters
    ----------
    m : SymEngine DenseMatrix
        The matrix.
    subs : mapping of SymEngine expression to float
        The values of its symbols.

    Returns
    -------
    ndarray
        Its value; `LinearizationError` if an entry is not a number there, or complex.
    """
    if m.rows == 0 or m.cols == 0:
        return np.zeros((m.rows, m.cols))
    try:
        out = np.array(m.subs(dict(subs)).tolist(), dtype=complex) if subs else np.array(m.tolist(), dtype=complex)
    except (RuntimeError, TypeError) as exc:
        raise LinearizationError(f"a matrix entry is not a number once the parameters are given: {exc}") from None
    if np.abs(out.imag).max(initial=0.0) > 1e-12 * max(1.0, np.abs(out.real).max(initial=0.0)):
        raise LinearizationError("a matrix entry is complex at this point (a square root of a negative number?).")
    return out.real.copy()
