"""The minimum-effort transfer of a linear system against its closed form, and each scheme's order.

A mass m on a spring k, driven by a force F: m ẍ + k x = F, i.e. ẋ = A x + B F with A = [[0, 1],
[−k/m, 0]], B = [0, 1/m]ᵀ.  The least ∫_0^T F² dt that takes x(0) = x0 to x(T) = xT is (Kirk,
*Optimal Control Theory*, §5.2; Brockett, *Finite Dimensional Linear Systems*, §13)

    J* = dᵀ W(T)⁻¹ d,   d = xT − e^{AT} x0,   W(T) = ∫_0^T e^{As} B Bᵀ e^{Aᵀs} ds   (controllability Gramian),

W computed here by Van Loan's block exponential (Van Loan, IEEE TAC 23, 1978): none of it uses the
package.  The collocated optimum converges to J* at the order of its scheme (slope of log error
against log N).
"""

import numpy as np
import pytest
import scipy.linalg as sl

pytest.importorskip("casadi")

import lagrangian
from lagrangian.model import parse_model
from lagrangian.optimal import optimize

SPRING = """
[model]
name = "Mass on a spring"
[parameters]
m = 2.0
k = 3.0
[inputs]
F = {}
[coordinates]
x = { initial = 0.0, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = { potential = "1/2*k*x^2" }
push = { force = "F*R0.x", at = "P" }
"""
M, K, T = 2.0, 3.0, 2.0
X0, XT = np.array([1.0, 0.5]), np.array([-0.3, 0.0])


def gramian_cost() -> float:
    A = np.array([[0.0, 1.0], [-K / M, 0.0]])
    B = np.array([[0.0], [1.0 / M]])
    E = sl.expm(np.block([[-A, B @ B.T], [np.zeros((2, 2)), A.T]]) * T)
    W = E[2:, 2:].T @ E[:2, 2:]  # Van Loan: ∫_0^T e^{As} B Bᵀ e^{Aᵀs} ds
    d = XT - sl.expm(A * T) @ X0
    return float(d @ np.linalg.solve(W, d))


@pytest.fixture(scope="module")
def spring():
    return lagrangian.derive(parse_model(SPRING))


def transfer(eom, nodes: int, method: str) -> float:
    best = optimize(eom, t_end=T, initial={"x": X0[0], "x_dot": X0[1]}, final={"x": XT[0], "x_dot": XT[1]},
                    nodes=nodes, method=method, tolerance=1e-12, verify=False)
    assert best.status == "optimal"
    return best.objective


def test_hermite_simpson_reaches_the_gramian_cost_to_a_millionth(spring):
    J = gramian_cost()
    assert abs(transfer(spring, 33, "hermite-simpson") - J) / J < 1e-6


@pytest.mark.parametrize("method, order, nodes", [
    ("hermite-simpson", 4, (5, 9, 17, 33)),
    ("trapezoidal", 2, (5, 9, 17, 33)),
    # backward Euler's error changes sign on coarse meshes: its first-order regime starts later
    ("backward-euler", 1, (33, 65, 129, 257)),
])
def test_each_scheme_converges_at_its_order(spring, method, order, nodes):
    J = gramian_cost()
    errors = [abs(transfer(spring, N, method) - J) / J for N in nodes]
    slope = -np.polyfit(np.log(np.array(nodes) - 1.0), np.log(errors), 1)[0]
    assert abs(slope - order) < 0.2, (method, errors, slope)
