"""The transcriptions: how a motion between mesh nodes is made to obey the dynamics.

The time span is cut into N − 1 intervals of equal length h; the state x = (q, q̇) has the
derivative ẋ = (q̇, q̈), where q̈ is a decision variable held to the implicit rows at every
collocation point (`_dynamics`).  Each scheme says where its collocation points lie, which equations
tie the points of an interval together (its *defects*), how it integrates a running cost, and what
input the optimum stands for between the points (the `InputTable` that `_replay` gives `simulate`):

``hermite-simpson`` (default; Betts, *Practical Methods for Optimal Control*, 2nd ed., §4.6.2, its
    separated form; Kelly, SIAM Review 59(4), 2017, §4)
    points: the nodes and each interval's midpoint c, with its own u_c;
        x_c = (x_k + x_{k+1})/2 + h/8 (ẋ_k − ẋ_{k+1})          (the cubic Hermite interpolant at c)
        x_{k+1} = x_k + h/6 (ẋ_k + 4 ẋ_c + ẋ_{k+1})            (Simpson's rule)
    cost: Simpson's rule; input: the parabola through u_k, u_c, u_{k+1} (a ``"quadratic"`` table).
    Fourth order.
``trapezoidal``
    points: the nodes;  x_{k+1} = x_k + h/2 (ẋ_k + ẋ_{k+1});  cost: the trapezoidal rule;
    input: linear between nodes (a ``"linear"`` table).  Second order.
``backward-euler`` (opty's default scheme)
    points: the nodes;  x_{k+1} = x_k + h ẋ_{k+1};  cost: h Σ_{k≥1} L_k (right rectangles);
    input: u_{k+1} held over (t_k, t_{k+1}] (a ``"zoh"`` table of u_1, …, u_{N−1}, u_{N−1}: the hold of
    the value at each interval's right end).  First order.

The implicit midpoint rule is not offered: only (u_k + u_{k+1})/2 enters it, so an input that
alternates from node to node (u_k + (−1)^k ε) leaves every defect unchanged and the optimum is not
unique (Kelly 2017, §4.4); Hermite–Simpson does the same work at fourth order.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..numerics import InputTable

__all__ = ["SCHEMES", "BackwardEuler", "HermiteSimpson", "Scheme", "Trapezoidal", "scheme"]


class Scheme:
    """A transcription (module docstring).  Concrete schemes define, for a mesh of N nodes on [0, 1]:

    1. ``points(N)``: the collocation points τ in [0, 1], increasing, the nodes among them;
    2. ``nodes(N)``: the indices of the nodes among the points (the first and the last point are nodes);
    3. ``weights(N)``: quadrature weights w_j with ∫_0^1 L dτ ≈ Σ_j w_j L(τ_j);
    4. ``defects(ca, X, Xdot, h)``: the equations (= 0) tying the points, given the state x and its
       derivative ẋ at every point as matrices (one column per point) and the interval length h;
    5. ``input_table(t, u)``: u(t) as the scheme stands for it, from its values ``u`` at the points' times
       ``t``: an `InputTable` (`simulate` reads it in its compiled right-hand side).
    """

    name = ""
    order = 0

    def points(self, N: int) -> np.ndarray:
        return np.linspace(0.0, 1.0, N)

    def nodes(self, N: int) -> np.ndarray:
        return np.arange(N)

    def weights(self, N: int) -> np.ndarray:
        raise NotImplementedError

    def defects(self, ca: Any, X: Any, Xdot: Any, h: Any) -> Any:
        raise NotImplementedError

    def input_table(self, t: np.ndarray, u: np.ndarray) -> InputTable:
        raise NotImplementedError


class HermiteSimpson(Scheme):
    name = "hermite-simpson"
    order = 4

    def points(self, N: int) -> np.ndarray:
        return np.linspace(0.0, 1.0, 2 * N - 1)

    def nodes(self, N: int) -> np.ndarray:
        return np.arange(0, 2 * N - 1, 2)

    def weights(self, N: int) -> np.ndarray:
        h = 1.0 / (N - 1)
        w = np.empty(2 * N - 1)
        w[0::2] = h / 3  # a node inside the span ends two intervals: h/6 + h/6
        w[[0, -1]] = h / 6
        w[1::2] = 4 * h / 6
        return w

    def defects(self, ca: Any, X: Any, Xdot: Any, h: Any) -> Any:
        P = X.shape[1]
        k, c, k1 = slice(0, P - 1, 2), slice(1, P, 2), slice(2, P, 2)
        interpolation = X[:, c] - (X[:, k] + X[:, k1]) / 2 - h / 8 * (Xdot[:, k] - Xdot[:, k1])
        simpson = X[:, k1] - X[:, k] - h / 6 * (Xdot[:, k] + 4 * Xdot[:, c] + Xdot[:, k1])
        return ca.vertcat(interpolation, simpson)

    def input_table(self, t: np.ndarray, u: np.ndarray) -> InputTable:
        return InputTable(t, u, "quadratic")  # the knots at the even points, a midpoint between each two


class Trapezoidal(Scheme):
    name = "trapezoidal"
    order = 2

    def weights(self, N: int) -> np.ndarray:
        w = np.full(N, 1.0 / (N - 1))
        w[[0, -1]] /= 2
        return w

    def defects(self, ca: Any, X: Any, Xdot: Any, h: Any) -> Any:
        return X[:, 1:] - X[:, :-1] - h / 2 * (Xdot[:, :-1] + Xdot[:, 1:])

    def input_table(self, t: np.ndarray, u: np.ndarray) -> InputTable:
        return InputTable(t, u, "linear")


class BackwardEuler(Scheme):
    name = "backward-euler"
    order = 1

    def weights(self, N: int) -> np.ndarray:
        w = np.full(N, 1.0 / (N - 1))
        w[0] = 0.0
        return w

    def defects(self, ca: Any, X: Any, Xdot: Any, h: Any) -> Any:
        return X[:, 1:] - X[:, :-1] - h * Xdot[:, 1:]

    def input_table(self, t: np.ndarray, u: np.ndarray) -> InputTable:
        # A zero-order hold reads v_k on [t_k, t_{k+1}], up to the right end between two restarts: v_k = u_{k+1}.
        return InputTable(t, np.append(u[1:], u[-1]), "zoh")


SCHEMES: dict[str, Scheme] = {s.name: s for s in (HermiteSimpson(), Trapezoidal(), BackwardEuler())}


def scheme(name: str) -> Scheme:
    """The scheme called ``name`` (`_problem.METHODS` are the names)."""
    return SCHEMES[name]
