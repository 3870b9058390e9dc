"""The cart-pole swing-up: its optimum obeys the cart-pole's equations written here by hand, and opty
finds the same objective with the same scheme and nodes.

The cart-pole (examples/inverted_pendulum_cart.toml: cart mc on a rail, bob m on a massless rod of
length l, θ from the ascending vertical, a force F on the cart), from T and U by hand:

    T = ½ (mc + m) ẋ² + m l ẋ θ̇ cos θ + ½ m l² θ̇²,   U = m g l cos θ,   Q = (F, 0)
    (mc + m) ẍ + m l cos θ θ̈ − m l sin θ θ̇² = F
    m l cos θ ẍ + m l² θ̈ − m g l sin θ = 0
"""

import numpy as np
import pytest

pytest.importorskip("casadi")

from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.optimal import optimize

MC, MB, L, G = 1.0, 0.2, 0.6, 9.81
T_END = 2.0
SWING_UP = {"t_end": T_END, "initial": {"x": 0, "theta": "pi", "x_dot": 0, "theta_dot": 0},
            "final": {"x": 0, "theta": 0, "x_dot": 0, "theta_dot": 0}, "bounds": {"F": (-20, 20), "x": (-2, 2)}}


def hand_residual(q, qd, qdd, F):
    """M(q) q̈ − F(q, q̇, u) of the cart-pole, rows of shape (P, 2)."""
    x_dd, th_dd = qdd[:, 0], qdd[:, 1]
    th, th_d = q[:, 1], qd[:, 1]
    r1 = (MC + MB) * x_dd + MB * L * np.cos(th) * th_dd - MB * L * np.sin(th) * th_d ** 2 - F
    r2 = MB * L * np.cos(th) * x_dd + MB * L ** 2 * th_dd - MB * G * L * np.sin(th)
    return np.column_stack([r1, r2])


@pytest.fixture(scope="module")
def cart_pole():
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "inverted_pendulum_cart.toml"))


@pytest.fixture(scope="module")
def swing_up(cart_pole):
    return optimize(cart_pole, nodes=30, **SWING_UP)


@pytest.mark.slow
def test_the_optimum_obeys_the_hand_derived_equations_at_every_collocation_point(swing_up):
    best = swing_up
    assert best.status == "optimal" and best.violation < 1e-8
    assert len(best.t) == 2 * 30 - 1  # nodes and midpoints
    residual = hand_residual(best.q, best.qd, best.qdd, best.column("F"))
    assert np.max(np.abs(residual)) < 1e-8


def test_the_optimum_meets_the_hermite_simpson_defects_between_its_points(swing_up):
    best = swing_up
    x = np.column_stack([best.q, best.qd])
    xdot = np.column_stack([best.qd, best.qdd])
    h = best.t[2] - best.t[0]
    k, c, k1 = slice(0, -1, 2), slice(1, None, 2), slice(2, None, 2)
    interpolation = x[c] - (x[k] + x[k1]) / 2 - h / 8 * (xdot[k] - xdot[k1])
    simpson = x[k1] - x[k] - h / 6 * (xdot[k] + 4 * xdot[c] + xdot[k1])
    assert np.max(np.abs(interpolation)) < 1e-8 and np.max(np.abs(simpson)) < 1e-8
    assert np.allclose(best.q[0], [0, np.pi]) and np.allclose(best.q[-1], [0, 0], atol=1e-12)
    assert np.max(np.abs(best.column("F"))) <= 20 + 1e-6 and np.max(np.abs(best.q[:, 0])) <= 2 + 1e-6


def test_the_optimum_replays_through_the_integrator(swing_up):
    replay = swing_up.replay
    assert replay is not None and replay.within
    assert replay.local_error < 1e-3


@pytest.mark.slow
def test_opty_finds_the_same_objective_with_backward_euler(cart_pole):
    # opty (Moore & van den Bogert, JOSS 2018) transcribes x' = f with backward Euler: (x_i − x_{i−1})/h =
    # f(x_i, u_i), i = 1..N−1, the scheme `backward-euler` writes; the objective h Σ_{i≥1} F_i² is its
    # right-rectangle quadrature.  Both start from the same guess (θ from π to 0 in a line).
    pytest.importorskip("cyipopt")
    opty = pytest.importorskip("opty")
    import sympy as sm
    import sympy.physics.mechanics as me

    N = 30
    h = T_END / (N - 1)
    t = me.dynamicsymbols._t
    x, th, v, w, F = me.dynamicsymbols("x theta v w F")
    eom = sm.Matrix([x.diff(t) - v, th.diff(t) - w,
                     (MC + MB) * v.diff(t) + MB * L * sm.cos(th) * w.diff(t) - MB * L * sm.sin(th) * w ** 2 - F,
                     MB * L * sm.cos(th) * v.diff(t) + MB * L ** 2 * w.diff(t) - MB * G * L * sm.sin(th)])

    def objective(free):
        return h * np.sum(free[4 * N + 1:] ** 2)

    def gradient(free):
        out = np.zeros_like(free)
        out[4 * N + 1:] = 2 * h * free[4 * N + 1:]
        return out

    ends = (x.func(0.0), th.func(0.0) - np.pi, v.func(0.0), w.func(0.0),
            x.func(T_END), th.func(T_END), v.func(T_END), w.func(T_END))
    problem = opty.Problem(objective, gradient, eom, (x, th, v, w), N, h, instance_constraints=ends,
                           bounds={F: (-20.0, 20.0), x: (-2.0, 2.0)}, integration_method="backward euler",
                           backend="numpy")
    problem.add_option("print_level", 0)
    guess = np.zeros(5 * N)
    guess[N:2 * N] = np.pi * (1 - np.linspace(0, 1, N))
    _, info = problem.solve(guess)
    assert info["status"] == 0
    ours = optimize(cart_pole, nodes=N, method="backward-euler", verify=False, **SWING_UP)
    assert ours.status == "optimal"
    assert ours.objective == pytest.approx(info["obj_val"], rel=1e-8)


@pytest.mark.slow
def test_the_plan_then_the_lqr_holds_the_rod_up_as_the_hand_written_equations_do(cart_pole, swing_up):
    # The plan's force (Lagrange's parabola through each interval's u_k, u_c, u_k+1), then the LQR's
    # F = −K x from T on, on the cart-pole's equations by hand, integrated by SciPy phase by phase.
    from scipy.integrate import solve_ivp

    fb = lagrangian.lqr(cart_pole, at={"x": 0, "theta": 0}, Q={"theta": 10}, R=0.5)
    gains = fb.K[0]
    t_out = np.linspace(0.0, 5.0, 51)
    start = {"x": 0, "theta": np.pi, "x_dot": 0, "theta_dot": 0}
    held = lagrangian.simulate(cart_pole, 5.0, initial=start, t_eval=t_out,
                               inputs={"F": lagrangian.Switch(swing_up.input_table("F"), fb, at=T_END)})

    def f(s, y, force):
        th, xd, thd = y[1], y[2], y[3]
        F = force(s, y)
        M = np.array([[MC + MB, MB * L * np.cos(th)], [MB * L * np.cos(th), MB * L ** 2]])
        rhs = np.array([F + MB * L * np.sin(th) * thd ** 2, MB * G * L * np.sin(th)])
        return [xd, thd, *np.linalg.solve(M, rhs)]

    t, u = swing_up.t, swing_up.column("F")
    y = np.array([0.0, np.pi, 0.0, 0.0])
    for k in range(0, len(t) - 1, 2):
        a, c, b = t[k:k + 3]
        ua, uc, ub = u[k:k + 3]

        def plan(s, _, a=a, b=b, c=c, ua=ua, uc=uc, ub=ub):
            return (ua * (s - c) * (s - b) / ((a - c) * (a - b)) + uc * (s - a) * (s - b) / ((c - a) * (c - b))
                    + ub * (s - a) * (s - c) / ((b - a) * (b - c)))
        y = solve_ivp(f, (a, b), y, args=(plan,), method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]
    late = solve_ivp(f, (T_END, 5.0), y, args=(lambda s, z: -gains @ z,), method="DOP853", rtol=1e-12,
                     atol=1e-12, t_eval=t_out[t_out >= T_END])
    assert np.abs(held.q[t_out >= T_END] - late.y[:2].T).max() < 1e-7
    assert abs(held.q[-1, 1]) < 1e-3 and abs(held.q[-1, 0]) < 1e-2  # caught and held upright
