"""Optimal motions: `lagrangian.optimize` against opty and against CasADi written by hand, in one run.

    .venv/bin/python benchmarks/optimize_vs_opty.py            # cart-pole and double pendulum on a cart, N = 100, 200
    .venv/bin/python benchmarks/optimize_vs_opty.py --quick    # N = 100 only, the cart-pole's opty run only
    .venv/bin/python benchmarks/optimize_vs_opty.py --no-opty  # ours and the hand-written CasADi only

Three solvers of the same swing-ups (examples/optimal/cart_pole_swing_up.toml,
double_pendulum_cart_swing_up.toml: from hanging to upright at rest, least ∫F² dt, bounded force and
rail), same nodes, same scheme, same start (the angles on a line from π to 0, all else 0):

* ours: `lagrangian.optimize` from the model file: derive (load + Lagrange's equations), transcribe
  (the SymEngine → CasADi conversion, the program), set up (CasADi's solver and derivatives), solve;
* by hand: the transcription a careful CasADi user writes with the equations typed in
  (benchmarks/_casadi_by_hand.py), the same structure: what our generated program adds must be
  close to nothing (target: within 1.5×);
* opty 1.5 (Moore & van den Bogert): the equations from sympy.physics.mechanics' KanesMethod (the way
  opty's examples derive them), its Cython code generation and compilation, IPOPT through cyipopt.
  opty transcribes with backward Euler (or the midpoint rule): the comparison is made with backward
  Euler, where all three solve the same program and must find the same objective (target: ours ≥ 50×
  faster end to end).

Every figure names its IPOPT build and its Hessian: ours and by hand, CasADi's bundled IPOPT with the
exact Hessian (CasADi's automatic differentiation); opty, Debian's IPOPT through cyipopt with the
limited-memory quasi-Newton Hessian (opty gives IPOPT no Hessian).  Times are the best of a few
runs in one process, ours and by hand taking turns (opty's, one run: each compiles its C extension
anew).  Last, the replay accuracy of each scheme (the final state reached by the optimized inputs,
replayed by `simulate`'s compiled DOP853 at 1e-10, against the optimum's), which is why
Hermite–Simpson is the default.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from _casadi_by_hand import MODELS, solve_by_hand

import lagrangian
from lagrangian.optimal import load_problem, optimize
from lagrangian.optimal._solve import ipopt_build

PROBLEMS = {"cart-pole": ROOT / "examples/optimal/cart_pole_swing_up.toml",
            "double pendulum on a cart": ROOT / "examples/optimal/double_pendulum_cart_swing_up.toml"}
#: Runs of each measurement, ours and by hand taking turns (a shared machine's load falls on both alike).
REPEATS = 5


def ours(name: str, N: int, method: str, hessian: str = "exact") -> dict:
    """End to end from the model file: derive, transcribe, set up, solve (no replay)."""
    problem = load_problem(PROBLEMS[name])
    start = time.perf_counter()
    eom = lagrangian.derive(lagrangian.load_model(problem.model))
    derived = time.perf_counter()
    best = optimize(dataclasses.replace(problem, model=eom), nodes=N, method=method, hessian=hessian, verify=False)
    end = time.perf_counter()
    s = best.seconds
    return {"objective": best.objective, "status": best.status, "iterations": best.iterations,
            "derive": derived - start, "after_derive": s["transcribe"] + s["setup"] + s["solve"],
            "transcribe": s["transcribe"], "setup": s["setup"], "solve": s["solve"],
            "total": (derived - start) + (end - derived)}


def best_of_both(name: str, N: int, method: str) -> tuple[dict, dict]:
    """The fastest of `REPEATS` runs of ours and of the hand-written transcription, taking turns."""
    runs = [(ours(name, N, method), hand(name, N, method)) for _ in range(REPEATS)]
    return (min((o for o, _ in runs), key=lambda r: r["total"]), min((h for _, h in runs), key=lambda r: r["total"]))


def hand(name: str, N: int, method: str) -> dict:
    r = solve_by_hand(MODELS[name], N, method)
    return {"objective": r.objective, "status": r.status, "iterations": r.iterations, "setup": r.setup,
            "solve": r.solve, "total": r.setup + r.solve}


# -- opty ---------------------------------------------------------------------------------------------
def opty_equations(name: str):
    """The swing-up's equations in opty's form (KanesMethod, u = q̇): states, input, implicit eom."""
    import sympy as sm
    import sympy.physics.mechanics as me

    t = me.dynamicsymbols._t
    N_frame = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N_frame, 0)
    g = 9.81
    F = me.dynamicsymbols("F")
    if name == "cart-pole":
        masses, lengths = [0.2], [0.6]
        mc = 1.0
    else:
        masses, lengths = [0.3, 0.3], [0.5, 0.5]
        mc = 1.0
    n = 1 + len(masses)
    q = me.dynamicsymbols(f"q0:{n}")
    u = me.dynamicsymbols(f"u0:{n}")
    cart = O.locatenew("C", q[0] * N_frame.x)
    cart.set_vel(N_frame, u[0] * N_frame.x)
    particles = [me.Particle("Pc", cart, mc)]
    loads = [(cart, F * N_frame.x)]
    previous = cart
    for k, (m, l) in enumerate(zip(masses, lengths, strict=True), start=1):
        # θ from the ascending vertical N.z, turning about N.y: the rod's direction is sin θ x + cos θ z
        bob = previous.locatenew(f"P{k}", l * (sm.sin(q[k]) * N_frame.x + sm.cos(q[k]) * N_frame.z))
        bob.set_vel(N_frame, bob.pos_from(O).dt(N_frame).subs({qi.diff(t): ui for qi, ui in zip(q, u, strict=True)}))
        particles.append(me.Particle(f"B{k}", bob, m))
        loads.append((bob, -m * g * N_frame.z))
        previous = bob
    kane = me.KanesMethod(N_frame, q_ind=q, u_ind=u, kd_eqs=[qi.diff(t) - ui for qi, ui in zip(q, u, strict=True)])
    kane.kanes_equations(particles, loads)
    states = sm.Matrix([*q, *u])
    eom = kane.mass_matrix_full * states.diff(t) - kane.forcing_full
    return q, u, F, eom


def opty_run(name: str, N: int) -> dict:
    import opty

    start = time.perf_counter()
    q, u, F, eom = opty_equations(name)
    derived = time.perf_counter()
    spec = MODELS[name]
    n, h = spec.n, spec.t_end / (N - 1)
    width = 2 * n * N

    def objective(free):
        return h * np.sum(free[width + 1:] ** 2)  # backward Euler's right rectangles, as ours

    def gradient(free):
        out = np.zeros_like(free)
        out[width + 1:] = 2 * h * free[width + 1:]
        return out

    ends = [q[0].func(0.0), *(qk.func(0.0) - np.pi for qk in q[1:]), *(uk.func(0.0) for uk in u),
            *(qk.func(spec.t_end) for qk in q), *(uk.func(spec.t_end) for uk in u)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        problem = opty.Problem(objective, gradient, eom, (*q, *u), N, h, instance_constraints=tuple(ends),
                               bounds={F: (-spec.force, spec.force), q[0]: (-spec.rail, spec.rail)},
                               integration_method="backward euler")
    problem.add_option("print_level", 0)
    problem.add_option("tol", 1e-8)
    set_up = time.perf_counter()
    guess = np.zeros(width + N)
    for k in range(1, n):
        guess[k * N:(k + 1) * N] = np.pi * (1 - np.linspace(0.0, 1.0, N))
    _, info = problem.solve(guess)
    done = time.perf_counter()
    return {"objective": float(info["obj_val"]), "status": info["status_msg"].decode()[:40],
            "derive": derived - start, "setup": set_up - derived, "solve": done - set_up, "total": done - start}


def debian_ipopt() -> str:
    try:
        import cyipopt

        version = ".".join(str(v) for v in cyipopt.IPOPT_VERSION)
        return f"IPOPT {version} (Debian, through cyipopt {cyipopt.__version__}, MUMPS)"
    except Exception:  # noqa: BLE001
        return "IPOPT (cyipopt)"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--no-opty", action="store_true")
    args = parser.parse_args()
    sizes = (100,) if args.quick else (100, 200)
    ours_build = f"{ipopt_build()}, exact Hessian"
    print(f"ours and by hand: {ours_build}")
    if not args.no_opty:
        print(f"opty {__import__('opty').__version__}: {debian_ipopt()}, limited-memory Hessian (opty gives none)")
    # warm-up: CasADi loads its IPOPT plugin, our C compiler cache is filled for the replays below
    ours("cart-pole", 20, "hermite-simpson")
    hand("cart-pole", 20, "hermite-simpson")

    print("\nHermite–Simpson (the default), ours against CasADi by hand; seconds, best of", REPEATS)
    print(f"{'problem':<28}{'N':>5}{'ours: derive':>14}{'transcribe':>12}{'set-up':>9}{'solve':>9}{'total':>9}"
          f"{'hand: total':>13}{'ours/hand':>11}{'iter':>6}{'J ours':>14}{'J hand':>14}")
    for name in PROBLEMS:
        for N in sizes:
            o, hd = best_of_both(name, N, "hermite-simpson")
            print(f"{name:<28}{N:>5}{o['derive']:>14.4f}{o['transcribe']:>12.4f}{o['setup']:>9.4f}{o['solve']:>9.4f}"
                  f"{o['total']:>9.4f}{hd['total']:>13.4f}{o['total'] / hd['total']:>11.2f}{o['iterations']:>6}"
                  f"{o['objective']:>14.8f}{hd['objective']:>14.8f}")
    cp = min((ours("cart-pole", 100, "hermite-simpson") for _ in range(2 * REPEATS)),
             key=lambda r: r["after_derive"])
    print(f"\ncart-pole swing-up, N = 100, Hermite–Simpson, after derive (transcribe + set-up + solve): "
          f"{cp['after_derive']:.3f} s (target < 0.2 s)")

    print("\nbackward Euler (opty's scheme): ours, by hand, opty; seconds")
    print(f"{'problem':<28}{'N':>5}{'ours':>9}{'hand':>9}{'opty: derive':>14}{'set-up':>9}{'solve':>9}{'total':>9}"
          f"{'opty/ours':>11}{'ours/hand':>11}{'J ours':>14}{'J hand':>14}{'J opty':>14}")
    for name in PROBLEMS:
        for N in sizes:
            o, hd = best_of_both(name, N, "backward-euler")
            run_opty = not args.no_opty and not (args.quick and name != "cart-pole")
            op = opty_run(name, N) if run_opty else None
            line = f"{name:<28}{N:>5}{o['total']:>9.4f}{hd['total']:>9.4f}"
            if op is not None:
                line += (f"{op['derive']:>14.2f}{op['setup']:>9.2f}{op['solve']:>9.3f}{op['total']:>9.2f}"
                         f"{op['total'] / o['total']:>11.0f}")
            else:
                line += " " * 52
            line += f"{o['total'] / hd['total']:>11.2f}{o['objective']:>14.8f}{hd['objective']:>14.8f}"
            line += f"{op['objective']:>14.8f}" if op is not None else ""
            print(line)

    print("\nreplay accuracy, cart-pole, N = 100: the optimized inputs replayed by simulate (DOP853 in C, "
          "rtol = atol = 1e-10, each input the table of what the scheme stands for) from the initial state; "
          "final-state error |x(T) − x_N|∞")
    problem = load_problem(PROBLEMS["cart-pole"])
    for method in ("backward-euler", "trapezoidal", "hermite-simpson"):
        best = optimize(problem, nodes=100, method=method)
        r = best.replay
        print(f"  {method:<16} final-state error {r.final_error:9.2e}   local error {r.local_error:9.2e}   "
              f"J = {best.objective:.6f}   replay {best.seconds['replay']:.3f} s")


if __name__ == "__main__":
    main()
