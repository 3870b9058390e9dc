"""The cost of dop853's stiffness test on a run dominated by the right-hand side, and what it saves.

1. The Lagrange top (examples/lagrange_top.toml, its model values) for ``--t-end`` seconds at
   rtol = atol = 1e-10, through `simulate` with ``stiffness_check`` on (the default: the test
   every 1000 accepted steps, as dop853.f), off, and on at *every* step (the worst case, the
   period forced to 1); runs interleaved, best of ``--repeat``.  Reported as ratios to "off".
2. A stiff model: the cart of examples/cart_pendulum.toml held by a damper of 1e9 N s/m.
   dop853 with the test stops after about a thousand steps; Radau runs 10 s; dop853 without the
   test is timed over 1e-3 s only and its steps for 10 s extrapolated (about 10^9).

Run:  .venv/bin/python benchmarks/stiffness_test.py [--repeat 7] [--t-end 200]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import lagrangian
from lagrangian import SimulationError
from lagrangian.numerics import _control

ROOT = Path(__file__).resolve().parents[1]


def _timed(fn, clock=time.perf_counter) -> tuple[float, object]:
    start = clock()
    value = fn()
    return clock() - start, value


def overhead(t_end: float, repeat: int) -> None:
    eom = lagrangian.derive(lagrangian.load_model(ROOT / "examples" / "lagrange_top.toml"))
    system = lagrangian.compile_system(eom)
    period = _control.STIFFNESS_TEST_PERIOD
    variants = {"off": (False, period), "on (every 1000 steps)": (True, period), "on (every step)": (True, 1)}
    best = dict.fromkeys(variants, float("inf"))
    steps = {}
    names = list(variants)
    for r in range(repeat):
        for name in names[r % 3:] + names[:r % 3]:  # the order rotated: no variant always runs first
            check, every = variants[name]
            _control.STIFFNESS_TEST_PERIOD = every
            try:
                # CPU time of the process (the run is in a worker thread): less sensitive than the wall
                # clock to other jobs on a shared machine
                seconds, traj = _timed(
                    lambda check=check: lagrangian.simulate(system, t_end, stiffness_check=check, n_out=101),
                    time.process_time)
            finally:
                _control.STIFFNESS_TEST_PERIOD = period
            best[name] = min(best[name], seconds)
            steps[name] = traj.steps
    print(f"Lagrange top, {t_end:g} s, rtol = atol = 1e-10, {steps['off']} steps (best of {repeat}):")
    for name in variants:
        print(f"  stiffness test {name:<24} {best[name] * 1e3:8.1f} ms   ratio to off {best[name] / best['off']:.3f}"
              f"   steps {steps[name]}")


def stiff_model() -> None:
    text = (ROOT / "examples" / "cart_pendulum.toml").read_text(encoding="utf-8")
    text = text.replace("[coordinates]", "c = { value = 1e9 }\n\n[coordinates]")
    text += 'damper = { damper = ["W", "C"], coefficient = "c" }\n'
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "stiff_cart.toml"
        path.write_text(text, encoding="utf-8")
        eom = lagrangian.derive(lagrangian.load_model(path))
    system = lagrangian.compile_system(eom)
    start = time.perf_counter()
    try:
        lagrangian.simulate(system, 10.0)
        print("dop853 with the test: completed (unexpected)")
    except SimulationError as exc:
        seconds = time.perf_counter() - start
        print(f"cart + damper 1e9 N s/m, 10 s: dop853 with the test stops at t = {exc.t:.3g} after "
              f"{exc.trajectory.steps} steps, {seconds * 1e3:.1f} ms")
    seconds, traj = _timed(lambda: lagrangian.simulate(system, 10.0, method="Radau"))
    print(f"  Radau: {traj.status}, {traj.steps} steps, {seconds:.2f} s")
    seconds, traj = _timed(lambda: lagrangian.simulate(system, 1e-3, stiffness_check=False))
    print(f"  dop853 without the test: {traj.steps} steps for 1e-3 s in {seconds:.2f} s, so about "
          f"{traj.steps * 1e4:.1e} steps and {seconds * 1e4 / 3600:.1f} h for 10 s")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--t-end", type=float, default=200.0)
    args = parser.parse_args(argv)
    overhead(args.t_end, args.repeat)
    stiff_model()
    return 0


if __name__ == "__main__":
    sys.exit(main())
