"""The reference a careful hand coder writes: the swing-ups transcribed directly in CasADi, equations by hand.

What `lagrangian.optimize` generates is held against this (benchmarks/optimize_vs_opty.py): the same
problem, the same scheme, the same nodes, the same guess and IPOPT options, written the way CasADi's
own examples and a user who knows it would — the equations of motion typed in as M(q) q̈ − F(q, q̇, u)
for one point (an ``SX`` function), mapped over the points of an ``MX`` program (one small graph
differentiated once, evaluated P times), exact Hessian.  Nothing here uses the package.

The equations, from T and U by hand (θ from the ascending vertical, rods massless, bobs point masses):

cart-pole (cart mc, bob m, rod l):
    (mc + m) ẍ + m l cos θ θ̈ − m l sin θ θ̇² = F,       m l cos θ ẍ + m l² θ̈ − m g l sin θ = 0
double pendulum on a cart (cart mc, bobs m1, m2, rods l1, l2, absolute angles θ1, θ2):
    M = [[mc + m1 + m2, (m1 + m2) l1 cos θ1, m2 l2 cos θ2],
         [·, (m1 + m2) l1², m2 l1 l2 cos(θ1 − θ2)],
         [·, ·, m2 l2²]]
    F = [(m1 + m2) l1 θ̇1² sin θ1 + m2 l2 θ̇2² sin θ2 + F,
         (m1 + m2) g l1 sin θ1 − m2 l1 l2 θ̇2² sin(θ1 − θ2),
         m2 g l2 sin θ2 + m2 l1 l2 θ̇1² sin(θ1 − θ2)]
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import casadi as ca
import numpy as np

__all__ = ["MODELS", "HandRun", "solve_by_hand"]


def cart_pole_residual(q, v, a, u):
    mc, m, l, g = 1.0, 0.2, 0.6, 9.81
    th, w = q[1, :], v[1, :]
    r1 = (mc + m) * a[0, :] + m * l * ca.cos(th) * a[1, :] - m * l * ca.sin(th) * w ** 2 - u
    r2 = m * l * ca.cos(th) * a[0, :] + m * l ** 2 * a[1, :] - m * g * l * ca.sin(th)
    return ca.vertcat(r1, r2)


def double_pendulum_cart_residual(q, v, a, u):
    mc, m1, m2, l1, l2, g = 1.0, 0.3, 0.3, 0.5, 0.5, 9.81
    t1, t2, w1, w2 = q[1, :], q[2, :], v[1, :], v[2, :]
    c1, c2, s1, s2 = ca.cos(t1), ca.cos(t2), ca.sin(t1), ca.sin(t2)
    c12, s12 = ca.cos(t1 - t2), ca.sin(t1 - t2)
    r1 = ((mc + m1 + m2) * a[0, :] + (m1 + m2) * l1 * c1 * a[1, :] + m2 * l2 * c2 * a[2, :]
          - (m1 + m2) * l1 * w1 ** 2 * s1 - m2 * l2 * w2 ** 2 * s2 - u)
    r2 = ((m1 + m2) * l1 * c1 * a[0, :] + (m1 + m2) * l1 ** 2 * a[1, :] + m2 * l1 * l2 * c12 * a[2, :]
          - (m1 + m2) * g * l1 * s1 + m2 * l1 * l2 * w2 ** 2 * s12)
    r3 = (m2 * l2 * c2 * a[0, :] + m2 * l1 * l2 * c12 * a[1, :] + m2 * l2 ** 2 * a[2, :]
          - m2 * g * l2 * s2 - m2 * l1 * l2 * w1 ** 2 * s12)
    return ca.vertcat(r1, r2, r3)


@dataclass(frozen=True)
class HandModel:
    """A swing-up: n coordinates (x, then angles from π to 0), its residual, duration and bounds."""

    n: int
    residual: Callable
    t_end: float
    force: float
    rail: float = 2.0


MODELS = {"cart-pole": HandModel(2, cart_pole_residual, 2.0, 20.0),
          "double pendulum on a cart": HandModel(3, double_pendulum_cart_residual, 3.0, 60.0)}


@dataclass(frozen=True)
class HandRun:
    objective: float
    status: str
    iterations: int
    setup: float  # building the program and the solver (CasADi's derivatives)
    solve: float  # IPOPT


def solve_by_hand(model: HandModel, N: int, method: str, hessian: str = "exact") -> HandRun:
    """The swing-up of ``model`` on N nodes with ``method`` (``"hermite-simpson"`` or ``"backward-euler"``)."""
    start = time.perf_counter()
    n = model.n
    W = 3 * n + 1  # q, q̇, q̈, u at each point
    z = ca.SX.sym("z", W)
    point = ca.Function("point", [z], [model.residual(z[:n], z[n:2 * n], z[2 * n:3 * n], z[3 * n])])
    P = 2 * N - 1 if method == "hermite-simpson" else N
    Z = ca.MX.sym("Z", W, P)
    q, v, a, u = Z[:n, :], Z[n:2 * n, :], Z[2 * n:3 * n, :], Z[3 * n, :]
    x, xdot = ca.vertcat(q, v), ca.vertcat(v, a)
    h = model.t_end / (N - 1)
    if method == "hermite-simpson":
        k, c, k1 = slice(0, P - 1, 2), slice(1, P, 2), slice(2, P, 2)
        defects = ca.vertcat(x[:, c] - (x[:, k] + x[:, k1]) / 2 - h / 8 * (xdot[:, k] - xdot[:, k1]),
                             x[:, k1] - x[:, k] - h / 6 * (xdot[:, k] + 4 * xdot[:, c] + xdot[:, k1]))
        cost = h / 6 * (ca.sumsqr(u[:, k]) + 4 * ca.sumsqr(u[:, c]) + ca.sumsqr(u[:, k1]))
    else:
        defects = x[:, 1:] - x[:, :-1] - h * xdot[:, 1:]
        cost = h * ca.sumsqr(u[:, 1:])
    g = ca.vertcat(ca.vec(point.map(P)(Z)), ca.vec(defects))
    low, high = np.full((W, P), -np.inf), np.full((W, P), np.inf)
    low[0], high[0] = -model.rail, model.rail
    low[3 * n], high[3 * n] = -model.force, model.force
    start_state = np.r_[0.0, np.full(n - 1, np.pi), np.zeros(n)]
    low[:2 * n, 0] = high[:2 * n, 0] = start_state
    low[:2 * n, -1] = high[:2 * n, -1] = 0.0
    guess = np.zeros((W, P))
    guess[1:n] = np.pi * (1 - np.linspace(0.0, 1.0, P))
    options = {"ipopt": {"print_level": 0, "sb": "yes", "tol": 1e-8}, "print_time": False}
    if hessian != "exact":
        options["ipopt"]["hessian_approximation"] = "limited-memory"
    solver = ca.nlpsol("hand", "ipopt", {"x": ca.vec(Z), "f": cost, "g": g}, options)
    built = time.perf_counter()
    out = solver(x0=guess.T.ravel(), lbx=low.T.ravel(), ubx=high.T.ravel(), lbg=0.0, ubg=0.0)
    done = time.perf_counter()
    stats = solver.stats()
    return HandRun(float(out["f"]), str(stats["return_status"]), int(stats["iter_count"]), built - start,
                   done - built)
