"""Ensembles: batched compiled members on every core, against a Python loop over `simulate`.

All figures come from one run on the same machine:

1. **Tops**: N Lagrange tops (the seed's top, θ(0) and φ̇(0) spread over a grid) × 10 s at
   rtol = atol = 1e-10 with `lagrangian.ensemble` (summaries only), against a Python loop
   over `simulate` timed on L tops of the same grid; per-member ratio.  Also 1 thread vs
   all threads on the same members (the choice of threads, `_ensemble` docstring).
2. **Memory**: the peak resident memory of a child process running the ensemble into a Zarr
   store, for two member counts 10x apart: it must not grow with the members.
3. **Flip map**: a 100 x 100 grid (10^4 members) of the double pendulum (θ1, θ2 in
   [−3, 3]) for 10 s, each member stopped at its first flip; extrapolated to 10^6.
4. **Dask**: throughput of a `distributed.LocalCluster` with 1 and with 2 worker processes.

Target: 10^5 tops in under 60 s on the 2-core machine.

Run:  .venv/bin/python benchmarks/ensemble.py [--tops 100000] [--loop 1000] [--flip 10000] [--cluster 4000]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import lagrangian
from lagrangian.numerics import compile_system, ensemble, flip_events, grid, simulate
from lagrangian.numerics._ensemble import _cores

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TOL = 1e-10


def top_grid(count: int):
    side = int(np.ceil(np.sqrt(count)))
    thetas = np.linspace(0.2, 1.4, side)
    spins = np.linspace(20.0, 80.0, int(np.ceil(count / side)))
    return grid(theta=thetas, phi_dot=spins)


def memory_of(count: int, n_out: int) -> float:
    """Peak RSS (MiB) of a child process running `count` tops into a Zarr store."""
    code = f"""
import resource, tempfile, numpy as np, lagrangian
from lagrangian.numerics import compile_system, ensemble, grid
top = compile_system(lagrangian.derive(lagrangian.lagrange_top()))
with tempfile.TemporaryDirectory() as d:
    ensemble(top, 1.0, initial={{"phi_dot": np.linspace(20, 80, {count})}}, n_out={n_out}, out=d + "/m.zarr")
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tops", type=int, default=100_000)
    ap.add_argument("--loop", type=int, default=1000)
    ap.add_argument("--flip", type=int, default=10_000)
    ap.add_argument("--cluster", type=int, default=4000)
    ap.add_argument("--n-out", type=int, default=101)
    args = ap.parse_args()
    results: dict = {"cores": _cores(), "n_out": args.n_out}
    top = compile_system(lagrangian.derive(lagrangian.lagrange_top()))

    # 1. tops: ensemble vs a loop over simulate.  Wall and CPU time (all threads of this process):
    # on a shared machine the CPU time per member is the figure that does not depend on the load.
    results["load_average_at_start"] = os.getloadavg()
    g = top_grid(args.tops)
    ensemble(top, 0.1, initial={"phi_dot": [50.0]}, n_out=2)  # imports (xarray), not timed
    t0, c0 = time.perf_counter(), time.process_time()
    ds = ensemble(top, 10.0, initial=g, n_out=args.n_out, rtol=TOL, atol=TOL)
    t_ens, c_ens = time.perf_counter() - t0, time.process_time() - c0
    cols = g.columns()
    pick = np.linspace(0, g.size - 1, args.loop).astype(int)
    t0, c0 = time.perf_counter(), time.process_time()
    for k in pick:
        simulate(top, 10.0, initial={"theta": cols["theta"][k], "phi_dot": cols["phi_dot"][k]}, n_out=args.n_out,
                 rtol=TOL, atol=TOL)
    t_loop, c_loop = time.perf_counter() - t0, time.process_time() - c0
    per_ens, per_loop = t_ens / g.size, t_loop / len(pick)
    sub = {"theta": cols["theta"][pick], "phi_dot": cols["phi_dot"][pick]}
    t0, c0 = time.perf_counter(), time.process_time()
    ensemble(top, 10.0, initial=sub, n_out=args.n_out, rtol=TOL, atol=TOL, workers=1)
    t_one, c_one = time.perf_counter() - t0, time.process_time() - c0
    t0 = time.perf_counter()
    ensemble(top, 10.0, initial=sub, n_out=args.n_out, rtol=TOL, atol=TOL)
    t_all = time.perf_counter() - t0
    results["tops"] = {"members": g.size, "ensemble_s": t_ens, "per_member_ms": 1e3 * per_ens,
                       "cpu_per_member_ms": 1e3 * c_ens / g.size,
                       "loop_members": len(pick), "loop_s": t_loop, "loop_per_member_ms": 1e3 * per_loop,
                       "loop_cpu_per_member_ms": 1e3 * c_loop / len(pick),
                       "wall_speedup_vs_loop": per_loop / per_ens,
                       "cpu_ratio_loop_over_batch_1_thread": (c_loop / len(pick)) / (c_one / len(pick)),
                       "extrapolated_1e5_s": per_ens * 1e5,
                       "extrapolated_1e5_s_on_idle_cores": c_ens / g.size * 1e5 / results["cores"],
                       "threads_1_s": t_one, "threads_all_s": t_all, "thread_speedup": t_one / t_all,
                       "all_ok": bool((ds.status == 0).all()), "max_drift": float(ds.drift.max())}
    print(json.dumps(results["tops"], indent=1), flush=True)

    # 2. memory independent of members
    small, large = memory_of(2000, args.n_out), memory_of(20000, args.n_out)
    results["memory_MiB"] = {"2000": small, "20000": large, "ratio": large / small}
    print(json.dumps(results["memory_MiB"]), flush=True)

    # 3. double-pendulum flip map
    dp = lagrangian.derive(lagrangian.load_model(EXAMPLES / "double_pendulum.toml"))
    side = int(round(np.sqrt(args.flip)))
    flips = [lagrangian.EventSpec(e.name, e.expression, e.direction, terminal=True) for e in flip_events(dp)]
    gm = grid(theta1=np.linspace(-3, 3, side), theta2=np.linspace(-3, 3, side))
    ensemble(dp, 0.1, initial=grid(theta1=[0.1], theta2=[0.1]), events=flips, n_out=2)  # compile, not timed
    t0, c0 = time.perf_counter(), time.process_time()
    fm = ensemble(dp, 10.0, initial=gm, events=flips, n_out=11, rtol=TOL, atol=TOL)
    t_map, c_map = time.perf_counter() - t0, time.process_time() - c0
    results["flip_map"] = {"members": gm.size, "s": t_map, "cpu_s": c_map,
                           "extrapolated_1e6_s": t_map / gm.size * 1e6,
                           "extrapolated_1e6_s_on_idle_cores": c_map / gm.size * 1e6 / results["cores"],
                           "flipped": int(np.isfinite(fm.event_time.values).any(axis=-1).sum())}
    print(json.dumps(results["flip_map"]), flush=True)

    # 4. LocalCluster 1 vs 2 workers
    try:
        import distributed
    except ImportError:
        distributed = None
    if distributed is not None and args.cluster:
        spins = {"phi_dot": np.linspace(20, 80, args.cluster)}
        rates = {}
        for n in (1, 2):
            with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                          dashboard_address=":0", host="127.0.0.1") as cluster, \
                    distributed.Client(cluster) as client:
                ensemble(top, 10.0, initial={"phi_dot": spins["phi_dot"][:4 * n]}, scheduler=client, n_out=2)
                t0 = time.perf_counter()
                ensemble(top, 10.0, initial=spins, scheduler=client, n_out=args.n_out, rtol=TOL, atol=TOL)
                rates[n] = args.cluster / (time.perf_counter() - t0)
        results["dask_members_per_s"] = {"1 worker": rates[1], "2 workers": rates[2], "ratio": rates[2] / rates[1]}
        print(json.dumps(results["dask_members_per_s"]), flush=True)
    results["load_average_at_end"] = os.getloadavg()
    print(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
