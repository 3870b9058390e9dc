"""The compiled closed loop, inputs in time, and a basin-of-attraction ensemble.

All figures come from one run on the same machine:

1. **Closed loop vs open loop** (target: within 1.3×).  The cart-pole
   (examples/inverted_pendulum_cart.toml) with the LQR law u = u* − K (x − x*) compiled into its
   right-hand side, against the same model compiled without a law (F held at 0): the cost of one
   right-hand-side evaluation (`CompiledSystem.rhs_c`, one state per call), and the cost of one
   whole run with the same steps budget (dop853 with a fixed step dt, so both take the same
   steps and the same number of evaluations).
2. **Expression vs Python function**: the same forcing F = 2 sin(3t) − 0.5 ẋ given as an
   expression (compiled in) and as a Python callable ``u(t, y)`` (one call back into Python per
   evaluation, the slow path), on the same adaptive run (equal results, equal evaluations).
3. **Basin map** (target: 10^4 LQR-stabilized pendulums in under 5 s on 2 cores): a
   100 × 100 grid of initial (θ, θ̇) of the closed-loop cart-pole for 5 s, each member stopped
   when it falls (|θ| > 1.5), with `lagrangian.ensemble` on 2 threads; first call (compiling the
   law, if not cached) and a second call.

Run:  .venv/bin/python benchmarks/closed_loop.py [--members 10000] [--repeat 5]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

import lagrangian
from lagrangian.numerics import compile_system, ensemble, grid, simulate

CART_POLE = Path(__file__).resolve().parents[1] / "examples" / "inverted_pendulum_cart.toml"


def interleaved(fns, repeat: int) -> list[float]:  # type: ignore[no-untyped-def]
    """The best time of each function, the functions run in turn ``repeat`` times (a shared, loaded
    machine slows every one of them alike within a round)."""
    times: list[list[float]] = [[] for _ in fns]
    for _ in range(repeat):
        for k, fn in enumerate(fns):
            start = time.perf_counter()
            fn()
            times[k].append(time.perf_counter() - start)
    return [min(t) for t in times]


def batch_call(system, states: np.ndarray):  # type: ignore[no-untyped-def]
    """One call of the compiled right-hand side over ``states`` (the C loop, no Python per state)."""
    p = system.parameter_vector()
    T = np.zeros(len(states))
    return lambda: system.rhs(T, states, p)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--members", type=int, default=10_000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()

    eom = lagrangian.derive(lagrangian.load_model(CART_POLE))
    fb = lagrangian.lqr(eom, {"x": 0, "theta": 0}, Q={"theta": 10})
    open_loop = compile_system(eom)
    closed = compile_system(eom, inputs=fb)

    print("1. closed loop (LQR compiled in) vs open loop, cart-pole")
    kw = {"initial": {"theta": 0.2}, "dt": 1e-4, "n_out": 11}  # 10^5 fixed steps of dop853: same steps budget
    a = simulate(open_loop, 10.0, **kw)
    b = simulate(closed, 10.0, inputs=fb, **kw)
    assert a.steps == b.steps and a.rhs_calls == b.rhs_calls
    # The same states for both (those of the closed-loop run), 10^5 of them per call.
    states = np.ascontiguousarray(np.tile(np.column_stack([b.q, b.qd]), (10_000, 1)))
    t_open, t_closed = interleaved([batch_call(open_loop, states), batch_call(closed, states)], 3 * args.repeat)
    t_open, t_closed = t_open / len(states), t_closed / len(states)
    print(f"   per rhs call (compiled loop over {len(states)} states): open {t_open * 1e9:6.1f} ns   "
          f"closed {t_closed * 1e9:6.1f} ns   ratio {t_closed / t_open:.2f}")
    run_open, run_closed = interleaved([lambda: simulate(open_loop, 10.0, **kw),
                                        lambda: simulate(closed, 10.0, inputs=fb, **kw)], 3 * args.repeat)
    print(f"   per run ({a.steps} steps, {a.rhs_calls} rhs calls): open {run_open * 1e3:7.2f} ms   "
          f"closed {run_closed * 1e3:7.2f} ms   ratio {run_closed / run_open:.2f}   (target < 1.3)")
    print(f"   per rhs call within the run: open {run_open / a.rhs_calls * 1e9:6.1f} ns   "
          f"closed {run_closed / b.rhs_calls * 1e9:6.1f} ns")

    print("2. expression (compiled) vs Python function u(t, y), same forcing, adaptive dop853, 10 s")
    expr = compile_system(eom, inputs={"F": "2*sin(3*t) - 0.5*x_dot"})
    fast = simulate(expr, 10.0, n_out=101)
    slow = simulate(eom, 10.0, n_out=101, inputs={"F": lambda t, y: 2 * math.sin(3 * t) - 0.5 * y[2]})
    assert np.abs(fast.q - slow.q).max() < 1e-12 and fast.rhs_calls == slow.rhs_calls
    t_fast = interleaved([lambda: simulate(expr, 10.0, n_out=101)], args.repeat)[0]
    t_slow = interleaved([lambda: simulate(eom, 10.0, n_out=101,
                                           inputs={"F": lambda t, y: 2 * math.sin(3 * t) - 0.5 * y[2]})], 1)[0]
    print(f"   {fast.rhs_calls} rhs calls: expression {t_fast * 1e3:.2f} ms, function {t_slow * 1e3:.2f} ms "
          f"(includes its set-up), ratio {t_slow / t_fast:.0f}x; max |q difference| "
          f"{np.abs(fast.q - slow.q).max():.1e}")

    side = round(math.sqrt(args.members))
    print(f"3. basin map: {side} x {side} = {side * side} closed-loop cart-poles x 5 s, 2 threads")
    members = grid(theta=np.linspace(-1.4, 1.4, side), theta_dot=np.linspace(-4.0, 4.0, side))
    fell = lagrangian.EventSpec("fell", "abs(theta) - 1.5", direction=1, terminal=True)
    for label in ("first call ", "second call"):
        start = time.perf_counter()
        ds = ensemble(eom, 5.0, inputs=fb, initial=members, events=[fell], n_out=51, workers=2)
        elapsed = time.perf_counter() - start
        caught = float((ds.status.values == 0).mean())
        print(f"   {label}: {elapsed:.2f} s ({side * side / elapsed:,.0f} members/s), caught {caught:.1%}, "
              f"mean steps {float(ds.steps.mean()):.0f}   (target < 5 s)")


if __name__ == "__main__":
    main()
