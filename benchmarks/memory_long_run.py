"""Peak memory of long runs: 10^4, 10^5 and 10^6 integration steps use the same memory.

Each run happens in a fresh Python process (started by a fresh parent, so that the
parent's ``getrusage(RUSAGE_CHILDREN).ru_maxrss`` is the peak resident set size of that one
run): import `lagrangian`, derive and compile the Lagrange top (the compiled library is
cached on disk after the first run), then ``simulate`` it with fixed steps (``dt``), so that
the number of steps is exactly ``t_end / dt``, on the same modest output grid (1001 times).
A baseline process does everything but the integration.

The integration runs in C and writes only the output grid, which is preallocated: the
number of steps must not show in the peak memory ("flat": the 10^6-step run within a few
per cent, or a few MiB, of the 10^4-step one).

Run:  .venv/bin/python benchmarks/memory_long_run.py [--method dop853|gauss-legendre] [--dt 1e-3]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time

#: "Flat": the largest run may exceed the smallest by at most this much.
TOLERANCE_MIB = 4.0
TOLERANCE_REL = 0.05

CHILD = r"""
import json, resource, sys, time
import lagrangian
from lagrangian.numerics import compile_system, simulate
steps, dt, method, n_out = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3], int(sys.argv[4])
system = compile_system(lagrangian.derive(lagrangian.lagrange_top()))
out = {"steps": 0, "seconds": 0.0, "drift": None}
if steps:
    t0 = time.perf_counter()
    traj = simulate(system, steps * dt, method=method, dt=dt, n_out=n_out)
    out = {"steps": traj.steps, "seconds": time.perf_counter() - t0, "drift": traj.drift["E"],
           "rhs_calls": traj.rhs_calls}
out["self_maxrss_kib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps(out))
"""

PARENT = r"""
import resource, subprocess, sys
child = subprocess.run([sys.executable, "-c", sys.argv[1], *sys.argv[2:]], capture_output=True, text=True)
if child.returncode:
    sys.stderr.write(child.stderr)
    sys.exit(child.returncode)
print(child.stdout.strip())
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
"""


def measure(steps: int, dt: float, method: str, n_out: int) -> dict:
    """One run in a fresh child of a fresh parent; ru_maxrss in KiB (Linux)."""
    proc = subprocess.run([sys.executable, "-c", PARENT, CHILD, str(steps), repr(dt), method, str(n_out)],
                          capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"the run of {steps} steps failed:\n{proc.stderr}")
    report, children_kib = proc.stdout.strip().splitlines()[-2:]
    out = json.loads(report)
    out["children_maxrss_kib"] = int(children_kib)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--method", default="dop853", choices=["dop853", "gauss-legendre"])
    parser.add_argument("--dt", type=float, default=1e-3, help="fixed step (default 1e-3 s)")
    parser.add_argument("--n-out", type=int, default=1001, help="output times of every run (default 1001)")
    parser.add_argument("--steps", type=int, nargs="*", default=[10**4, 10**5, 10**6])
    parser.add_argument("--no-contrast", action="store_true",
                        help="skip the contrast run that stores every step of the largest run")
    args = parser.parse_args(argv)

    import lagrangian

    print(f"lagrangian {lagrangian.__version__}, Python {sys.version.split()[0]}, {sys.platform}")
    print(f"Lagrange top, method={args.method!r}, fixed dt = {args.dt:g} s, {args.n_out} output times; "
          "each run in a fresh process")
    measure(0, args.dt, args.method, args.n_out)  # compile once, so no run pays the compiler
    print(f"\n{'run':<26} {'steps':>10} {'rhs calls':>11} {'time':>8} {'E drift':>8} {'peak RSS':>11} "
          f"{'ratio':>6}  {'(child: own peak)':>17}")
    rows = []
    for steps in [0, *args.steps]:
        t0 = time.perf_counter()
        r = measure(steps, args.dt, args.method, args.n_out)
        r["wall"] = time.perf_counter() - t0
        r["asked"] = steps
        rows.append(r)
        # t advances by repeated addition of dt, so t_end may be reached one (tiny) step late.
        if steps and not steps <= r["steps"] <= steps + 1:
            raise AssertionError(f"asked for {steps} steps, the run took {r['steps']}")
    base = next(r for r in rows if r["asked"] == min(args.steps))
    for r in rows:
        label = "baseline (no integration)" if r["asked"] == 0 else f"t_end = {r['asked'] * args.dt:g} s"
        mib = r["children_maxrss_kib"] / 1024
        ratio = f"{r['children_maxrss_kib'] / base['children_maxrss_kib']:.3f}" if r["asked"] else "—"
        drift = "—" if r["drift"] is None else f"{r['drift']:.1e}"
        calls = f"{r.get('rhs_calls', 0):,}" if r["steps"] else "—"
        secs = f"{r['seconds']:.2f} s" if r["steps"] else "—"
        own = f"{r['self_maxrss_kib'] / 1024:.1f} MiB"
        print(f"{label:<26} {r['steps']:>10,} {calls:>11} {secs:>8} {drift:>8} {mib:7.1f} MiB {ratio:>6}  {own:>17}")

    largest = max(rows, key=lambda r: r["asked"])
    if not args.no_contrast:
        # The same run, storing every step: the memory this benchmark would see if results were kept.
        steps = largest["asked"]
        c = measure(steps, args.dt, args.method, steps + 1)
        mib = c["children_maxrss_kib"] / 1024
        print(f"{'(contrast) every step out':<26} {c['steps']:>10,} {c['rhs_calls']:>11,} {c['seconds']:6.2f} s "
              f"{c['drift']:8.1e} {mib:7.1f} MiB {c['children_maxrss_kib'] / base['children_maxrss_kib']:6.3f}  "
              f"{c['self_maxrss_kib'] / 1024:13.1f} MiB")
    grow_mib = (largest["children_maxrss_kib"] - base["children_maxrss_kib"]) / 1024
    rel = grow_mib * 1024 / base["children_maxrss_kib"]
    print("peak RSS: ru_maxrss of RUSAGE_CHILDREN in the run's parent; ratio: against the smallest run")
    print(f"\n{largest['steps']:,} steps against {base['steps']:,}: {grow_mib:+.1f} MiB ({100 * rel:+.1f} %); "
          f"the integration itself adds {(base['children_maxrss_kib'] - rows[0]['children_maxrss_kib']) / 1024:+.1f} "
          "MiB to the baseline process")
    if grow_mib > TOLERANCE_MIB and rel > TOLERANCE_REL:
        print(f"target missed: peak RSS grows with the number of steps (> {TOLERANCE_MIB:g} MiB and "
              f"> {100 * TOLERANCE_REL:g} %)")
        return 1
    print(f"target met: peak RSS flat in the number of steps (within {TOLERANCE_MIB:g} MiB or "
          f"{100 * TOLERANCE_REL:g} %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
