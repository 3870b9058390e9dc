"""The Lagrange top for 10 s at rtol = atol = 1e-10: our DOP853 in C against SciPy's DOP853, same run.

Three integrations of the same initial value problem (the seed's top, its model values:
θ(0) = 0.5, φ̇(0) = 50 rad/s, at rest otherwise), on the same output grid (1001 times):

* **ours** — ``simulate(system, 10, method="dop853", rtol=1e-10, atol=1e-10)``: the whole
  run is one call into compiled C (the system is compiled once, before the timing; the
  time includes building the `Trajectory`, its monitors and drift);
* **SciPy + lambdify** — ``scipy.integrate.solve_ivp(method="DOP853")`` driven by
  ``sympy.lambdify`` of SymPy's own M and F of the top (`KanesMethod`), q̈ by
  ``numpy.linalg.solve``: what a SymPy user writes;
* **SciPy + our rhs** — the same SciPy driver with our compiled ``CompiledSystem.rhs``
  (for information: the share of SciPy's own per-step Python cost).

Reported: wall time (best of ``--repeat``), number of right-hand-side calls, the relative
energy drift max|E(t) − E(0)| / |E(0)| on the output grid (E from our compiled monitors for
all three), and the largest difference between the trajectories.  Then the long-run
behaviour: the energy drift of DOP853 and of the symplectic Gauss–Legendre method over
100 s and 1000 s (a symplectic method's energy error stays bounded; DOP853's grows).

Targets: ours ≥ 10× faster than SciPy + lambdify, energy drift ≤ 1e-11.

Run:  .venv/bin/python benchmarks/top_integration.py [--repeat 5] [--long 100 1000]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import scipy
import sympy as sp
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _peers  # noqa: E402

import lagrangian  # noqa: E402
from lagrangian.numerics import compile_system, initial_state, simulate  # noqa: E402

TARGET_SPEEDUP = 10.0
TARGET_DRIFT = 1e-11
T_END = 10.0
TOL = 1e-10


def best_of(repeat: int, fn):
    """(best wall time, best CPU time of this process, last result) of ``repeat`` calls."""
    wall = cpu = float("inf")
    result = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        result = fn()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu, result


def energy_drift(system, p, t, Y) -> float:
    k = system.monitors.index("E")
    E = system.monitor_values(t, np.ascontiguousarray(Y), p)[:, k]
    return float(np.max(np.abs(E - E[0])) / abs(E[0]))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs of each integration, best kept (default 5)")
    parser.add_argument("--long", type=float, nargs="*", default=[100.0, 1000.0],
                        help="durations of the long-run drift comparison (default 100 1000)")
    parser.add_argument("--dt", type=float, default=1e-3, help="Gauss–Legendre step of the long runs")
    args = parser.parse_args(argv)

    print(f"lagrangian {lagrangian.__version__}, scipy {scipy.__version__}, sympy {sp.__version__}, "
          f"numpy {np.__version__}, Python {sys.version.split()[0]}")
    eom = lagrangian.derive(lagrangian.lagrange_top())
    system = compile_system(eom)
    p = system.parameter_vector()
    y0 = initial_state(eom)
    t_eval = np.linspace(0.0, T_END, 1001)
    names = [*eom.coordinates, *(c + "_dot" for c in eom.coordinates)]
    print(f"Lagrange top, y0: {', '.join(f'{k} = {v:g}' for k, v in zip(names, y0, strict=True))}, "
          f"t in [0, {T_END:g}] s, rtol = atol = {TOL:g}, {len(t_eval)} output times")

    # -- SymPy's equations, lambdified, for SciPy
    sym = _peers.sympy_system("top")
    params = dict(zip(system.parameters, p, strict=True))
    single, _ = _peers.lambdify_peer(sym, np.array([params[str(c)] for c in sym.constants]))
    n = system.n

    def lambdified(t, y):
        return np.concatenate([y[n:], single(y[:n], y[n:])])

    def ours_rhs(t, y):
        return system.rhs(t, y, p)

    def run_scipy(fun):
        return solve_ivp(fun, (0.0, T_END), y0, method="DOP853", t_eval=t_eval, rtol=TOL, atol=TOL)

    t_ours, c_ours, traj = best_of(args.repeat, lambda: simulate(system, T_END, method="dop853", rtol=TOL, atol=TOL,
                                                         t_eval=t_eval))
    t_lam, c_lam, sol_lam = best_of(max(1, min(args.repeat, 3)), lambda: run_scipy(lambdified))
    t_sci, c_sci, sol_sci = best_of(max(1, min(args.repeat, 3)), lambda: run_scipy(ours_rhs))
    Y_ours = np.column_stack([traj.q, traj.qd])
    rows = [
        ("ours: simulate(method='dop853'), C", t_ours, c_ours, traj.rhs_calls, traj.steps,
         energy_drift(system, p, traj.t, Y_ours), 0.0),
        ("SciPy DOP853 + SymPy lambdify rhs", t_lam, c_lam, sol_lam.nfev, len(sol_lam.t),
         energy_drift(system, p, sol_lam.t, sol_lam.y.T), float(np.max(np.abs(sol_lam.y.T - Y_ours)))),
        ("SciPy DOP853 + our compiled rhs", t_sci, c_sci, sol_sci.nfev, len(sol_sci.t),
         energy_drift(system, p, sol_sci.t, sol_sci.y.T), float(np.max(np.abs(sol_sci.y.T - Y_ours)))),
    ]
    print(f"\n{'integration':<38} {'wall time':>10} {'CPU time':>10} {'ratio':>8} {'rhs calls':>10} "
          f"{'E drift':>9} {'max |y - y_ours|':>17}")
    for label, secs, cpu, nfev, _, drift, diff in rows:
        ratio = "—" if secs is t_ours else f"{cpu / c_ours:.0f}×"
        print(f"{label:<38} {secs * 1e3:7.1f} ms {cpu * 1e3:7.1f} ms {ratio:>8} {nfev:>10} {drift:9.1e} {diff:17.1e}")
    print(f"(ours: {traj.steps} accepted steps; drift of every first integral: {traj.drift_summary()})")
    print("ratio = SciPy's CPU time / ours (on a shared machine, the wall time of a long run also counts the\n"
          "time slices given to other processes; both are the best of the repeats)")
    # Same ODE, same tableau, same error control: the trajectories must agree to the tolerance's order.
    for label, *_, diff in rows[1:]:
        if not diff < 1e-6:
            raise AssertionError(f"{label} ended far from ours (max difference {diff:.3g}): not the same problem")

    # -- long runs
    print(f"\nlong runs: relative drift of the first integrals (output every {0.1:g} s)")
    print(f"{'method':<46} {'t_end':>7} {'wall time':>10} {'steps':>9} {'E drift':>9} {'K drift':>9} {'H drift':>9}")
    long_rows = []
    for t_end in args.long:
        n_out = int(round(t_end / 0.1)) + 1
        for label, kw in ((f"dop853, rtol = atol = {TOL:g}", dict(method="dop853", rtol=TOL, atol=TOL)),
                          (f"gauss-legendre, dt = {args.dt:g}", dict(method="gauss-legendre", dt=args.dt))):
            t0 = time.perf_counter()
            tr = simulate(system, t_end, n_out=n_out, **kw)
            secs = time.perf_counter() - t0
            long_rows.append((label, t_end, tr.drift["E"]))
            print(f"{label:<46} {t_end:7g} {secs:8.2f} s {tr.steps:>9} {tr.drift['E']:9.1e} {tr.drift['K']:9.1e} "
                  f"{tr.drift['H']:9.1e}")

    speedup = c_lam / c_ours
    drift = rows[0][5]
    print()
    misses = []
    if speedup < TARGET_SPEEDUP:
        misses.append(f"speed-up over SciPy + lambdify {speedup:.1f}× < {TARGET_SPEEDUP:g}×")
    if drift > TARGET_DRIFT:
        misses.append(f"energy drift {drift:.1e} > {TARGET_DRIFT:g}")
    if misses:
        print("targets missed: " + "; ".join(misses))
        return 1
    print(f"targets met: {speedup:.0f}× faster than SciPy + lambdify (≥ {TARGET_SPEEDUP:g}×), "
          f"energy drift {drift:.1e} ≤ {TARGET_DRIFT:g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
