"""Robot-sized systems: derive + compile time and memory, and q̈ per state against Pinocchio.

Two systems, each in relative joint coordinates as a robot is written:

* ``chain``: `relative_chain(n)`, the planar n-link pendulum of point masses in relative
  angles (Pinocchio: revolute joints about z, point masses at the tips, gravity along x0);
* ``arm``: `serial_arm(n)`, a 3D arm of revolute joints about z, y, y, x, y, x, z, ... with
  off-axis centres of mass and full inertia matrices (Pinocchio: ``JointModelRZ/RY/RX``, the
  same placements and ``pin.Inertia``), motor torques as the joint torques τ.

The script

1. times `lagrangian.derive` + `compile_system` of the 20-link chain and the 10-joint arm in a
   fresh process with an empty compile cache (wall and CPU time of the process and of the C
   compiler), and the peak memory (resident set of Python and of the compiler) at n = 30;
   targets: under 3 s each, under 500 MB;
2. for each n checks that our q̈ equals ``pin.aba``'s at random states, random joint torques
   (relative difference ≤ ``--rtol``, else it stops: a benchmark of different physics is
   worthless), then times one state per call (ours: ``CompiledSystem.rhs_c``; Pinocchio:
   ``pin.aba`` and ``pin.rnea`` + ``pin.crba`` + a linear solve, from Python) and states in
   batches (ours: ``rhs`` on a (100, 2n) array; Pinocchio: a Python loop over ``pin.aba`` and its
   own batched call ``pin.abaInParallel`` on one thread, the faster of the two is the peer).
   Target: ours at least 2× faster than ``pin.aba`` (ratio ours/aba ≤ 0.5) at every n from 2
   to 30, single and batched.  The ``M⁻¹F`` columns time, in the same run, our route before the
   articulated-body algorithm (`dynamics._articulated`): M and F compiled, then the Cholesky
   solve (the same system with ``recursive.qdd`` removed); its q̈ is checked equal too.

Times are the minimum over short timing blocks (`rhs_vs_peers.per_call`), so a busy shared
machine shows the cost of the code, not other processes' time slices; CPU times of the
compile are reported next to wall times for the same reason.

Run:  .venv/bin/python benchmarks/robot_chains.py [--sizes 2 5 10 20 30] [--systems chain arm] [--quick]
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rhs_vs_peers import per_call  # noqa: E402

import lagrangian  # noqa: E402
from lagrangian.model.zoo import ARM_AXES, relative_chain, serial_arm  # noqa: E402
from lagrangian.numerics import compile_system  # noqa: E402

TARGET_COMPILE_S = 3.0
TARGET_MEMORY_MB = 500.0
TARGET_RATIO = 0.5
SIZES = (2, 3, 4, 5, 6, 8, 10, 12, 15, 20, 25, 30)
BATCH = 10_000
CHUNK = 100  # states per batched call

MAKERS = {"chain": relative_chain, "arm": serial_arm}

# -- 1. derive + compile, in a fresh process ------------------------------------------------------
_CHILD = r"""
import json, os, resource, sys, time
t0, c0 = time.perf_counter(), time.process_time()
import lagrangian
from lagrangian.model.zoo import relative_chain, serial_arm
from lagrangian.numerics import compile_system
kind, n, formulation = sys.argv[1], int(sys.argv[2]), sys.argv[3]
model = (relative_chain if kind == "chain" else serial_arm)(n)
t1, c1 = time.perf_counter(), time.process_time()
eom = lagrangian.derive(model, formulation=formulation)
t2, c2 = time.perf_counter(), time.process_time()
system = compile_system(eom)
t3, c3 = time.perf_counter(), time.process_time()
me, cc = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
# The compiler's own peak memory: a child forked from this (large) process counts this process's
# pages, so the same compiles run again from a small Python process, one unit after the other (the
# build runs as many at once as there are cores: its peak is at most that many times this one).
import subprocess, tempfile
from lagrangian.codegen import generate_c
from lagrangian.numerics._compile import FLAGS, compiler, unit_flags
units = generate_c(eom, system.first_integrals, ()).units
cc_rss = 0
with tempfile.TemporaryDirectory() as tmp:
    for k, unit in enumerate(units):
        c_file = os.path.join(tmp, f"unit{k}.c")
        with open(c_file, "w") as f:
            f.write(unit)
        small = ("import resource, subprocess, sys; subprocess.run(sys.argv[1:], check=True); "
                 "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
        flags = [w for w in FLAGS if w != "-shared"] + list(unit_flags(unit, part=k > 0))
        cc_rss = max(cc_rss, int(subprocess.run([sys.executable, "-S", "-c", small, *compiler(), *flags, "-c", "-o",
                                                 os.path.join(tmp, f"unit{k}.o"), c_file], capture_output=True,
                                                text=True, check=True).stdout.split()[-1]))
print(json.dumps({"derive": t2 - t1, "compile": t3 - t2, "cpu": c3 - c1, "cc_cpu": cc.ru_utime + cc.ru_stime,
                  "rss_mb": me.ru_maxrss / 1024, "cc_rss_mb": cc_rss / 1024,
                  "source_kb": len(system.source) / 1024, "formulation": eom.formulation}))
"""


def derive_and_compile(kind: str, n: int, formulation: str = "auto") -> dict:
    """Time and memory of derive + compile_system of one system, fresh process, empty cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, LAGRANGIAN_CACHE=cache)
        out = subprocess.run([sys.executable, "-c", _CHILD, kind, str(n), formulation], env=env,
                             capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


# -- 2. Pinocchio's model of the same systems --------------------------------------------------------
def pinocchio_model(kind: str, n: int, values: dict[str, float]):
    """Pinocchio's model of ``kind`` with our parameter ``values`` (same joints, same coordinates)."""
    import pinocchio as pin

    model = pin.Model()
    joint = 0
    joints = {"x": pin.JointModelRX, "y": pin.JointModelRY, "z": pin.JointModelRZ}
    for k in range(1, n + 1):
        if kind == "chain":
            where = pin.SE3(np.eye(3), np.array([values[f"l{k - 1}"], 0.0, 0.0])) if k > 1 else pin.SE3.Identity()
            joint = model.addJoint(joint, pin.JointModelRZ(), where, f"joint{k}")
            model.appendBodyToJoint(joint, pin.Inertia(values[f"m{k}"], np.array([values[f"l{k}"], 0.0, 0.0]),
                                                       np.zeros((3, 3))), pin.SE3.Identity())
        else:
            where = pin.SE3(np.eye(3), np.array([0.0, 0.0, values[f"a{k - 1}"]])) if k > 1 else pin.SE3.Identity()
            joint = model.addJoint(joint, joints[ARM_AXES[(k - 1) % len(ARM_AXES)]](), where, f"joint{k}")
            P = values[f"P_{k}"]
            inertia = np.array([[values[f"I1_{k}"], -P, 0.0], [-P, values[f"I2_{k}"], P], [0.0, P, values[f"I3_{k}"]]])
            centre = np.array([values[f"cx{k}"], values[f"cy{k}"], values[f"cz{k}"]])
            model.appendBodyToJoint(joint, pin.Inertia(values[f"m{k}"], centre, inertia), pin.SE3.Identity())
    model.gravity.linear = np.array([values["g"], 0.0, 0.0] if kind == "chain" else [0.0, 0.0, -values["g"]])
    return model


def random_values(system, rng: np.random.Generator) -> dict[str, float]:
    """The model's values, each scaled by a factor in [0.7, 1.3] (inputs: torques in [−1, 1] N·m)."""
    values = {}
    for p in system.eom.model.parameters:
        values[p.name] = float(rng.uniform(-1, 1)) if p.input else float(p.value) * float(rng.uniform(0.7, 1.3))
    return values


def compare(kind: str, n: int, rng: np.random.Generator, rtol: float, quick: bool) -> dict:
    import pinocchio as pin

    model = MAKERS[kind](n)
    system = compile_system(lagrangian.derive(model))
    values = random_values(system, rng)
    values["g"] = 9.81
    p = system.parameter_vector(values)
    pm = pinocchio_model(kind, n, values)
    data = pm.createData()
    tau = np.array([values.get(f"tau{k}", 0.0) for k in range(1, n + 1)])
    states = 200
    Q = rng.uniform(-np.pi, np.pi, (states, n))
    V = rng.uniform(-1.5, 1.5, (states, n))
    Y = np.hstack([Q, V])
    ours = system.rhs(0.0, Y, p)[:, n:]
    theirs = np.array([pin.aba(pm, data, q, v, tau) for q, v in zip(Q, V, strict=True)])
    diff = float(np.max(np.abs(ours - theirs)) / max(1.0, float(np.max(np.abs(theirs)))))
    if not diff <= rtol:
        raise SystemExit(f"{kind}{n}: our q'' and pin.aba's differ by {diff:.2e} (> {rtol:g}); not timing")
    budget = 0.2 if quick else 0.6
    out = np.empty(2 * n)
    rows = [(0.0, np.ascontiguousarray(y), p, out) for y in Y]
    ours_single = per_call(system.rhs_c, rows, budget)
    aba_rows = [(pm, data, np.ascontiguousarray(q), np.ascontiguousarray(v), tau) for q, v in zip(Q, V, strict=True)]
    aba_single = per_call(pin.aba, aba_rows, budget)

    def rnea_crba(q, v):
        b = pin.rnea(pm, data, q, v, np.zeros(n))
        M = pin.crba(pm, data, q)
        M = np.triu(M) + np.triu(M, 1).T  # crba fills the upper triangle
        return np.linalg.solve(M, tau - b)

    check = np.array([rnea_crba(q, v) for q, v in zip(Q[:5], V[:5], strict=True)])
    if not np.allclose(check, theirs[:5], rtol=1e-8, atol=1e-8):
        raise SystemExit(f"{kind}{n}: pin.rnea + pin.crba disagree with pin.aba")
    rnea_single = per_call(rnea_crba, [(np.ascontiguousarray(q), np.ascontiguousarray(v)) for q, v in zip(Q, V, strict=True)],
                           budget)
    # Batches of CHUNK states, timed like single calls (the minimum over short blocks): a 10⁴-state
    # call lasts long enough on a shared machine to be cut by other processes' time slices.
    YB = np.tile(Y, (BATCH // states, 1))
    chunks = [np.ascontiguousarray(YB[k:k + CHUNK]) for k in range(0, len(YB), CHUNK)]
    ours_batch = per_call(system.rhs, [(0.0, c, p) for c in chunks], budget) / CHUNK

    def aba_loop(Qc, Vc):
        for q, v in zip(Qc, Vc, strict=True):
            pin.aba(pm, data, q, v, tau)

    aba_loop_batch = per_call(aba_loop, [(np.ascontiguousarray(c[:, :n]), np.ascontiguousarray(c[:, n:]))
                                         for c in chunks], budget) / CHUNK
    # Pinocchio's own batched call: abaInParallel on one thread (ours is one thread too), states as columns.
    pool = pin.ModelPool(pm, 1)
    taus = np.asfortranarray(np.tile(tau[:, None], (1, CHUNK)))
    acc = np.asfortranarray(np.empty((n, CHUNK)))
    pool_rows = [(1, pool, np.asfortranarray(c[:, :n].T), np.asfortranarray(c[:, n:].T), taus, acc) for c in chunks]
    pin.abaInParallel(*pool_rows[0])
    if not np.allclose(acc.T, system.rhs(0.0, chunks[0], p)[:, n:], rtol=1e-8, atol=1e-8):
        raise SystemExit(f"{kind}{n}: pin.abaInParallel disagrees with our q''")
    pool_batch = per_call(pin.abaInParallel, pool_rows, budget) / CHUNK
    # The route before the articulated-body algorithm, in the same run: M q'' = F by Cholesky.
    solve_single = solve_batch = float("nan")
    if system.eom.recursive is not None and system.eom.recursive.qdd is not None:
        eom_m = copy.copy(system.eom)  # not dataclasses.replace: that would derive the course's form
        object.__setattr__(eom_m, "recursive", dataclasses.replace(system.eom.recursive, qdd=None, pivots=()))
        solve = compile_system(eom_m)
        if not np.allclose(solve.rhs(0.0, Y, p)[:, n:], ours, rtol=1e-9, atol=1e-9 * float(np.max(np.abs(ours)))):
            raise SystemExit(f"{kind}{n}: the articulated-body q'' and M^-1 F differ")
        solve_single = per_call(solve.rhs_c, rows, budget)
        solve_batch = per_call(solve.rhs, [(0.0, c, p) for c in chunks], budget) / CHUNK
    return {"n": n, "diff": diff, "ours": ours_single, "aba": aba_single, "rnea_crba": rnea_single,
            "ours_batch": ours_batch, "aba_batch": min(aba_loop_batch, pool_batch), "aba_loop_batch": aba_loop_batch,
            "pool_batch": pool_batch, "solve": solve_single, "solve_batch": solve_batch}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=list(SIZES))
    parser.add_argument("--systems", nargs="+", default=["chain", "arm"], choices=sorted(MAKERS))
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--quick", action="store_true", help="shorter timing budgets")
    parser.add_argument("--baseline", action="store_true",
                        help="also time formulation='lagrange' (the expanded entries; about a minute)")
    parser.add_argument("--skip-compile", action="store_true", help="only the per-state table")
    parser.add_argument("--skip-peers", action="store_true", help="only the compile table")
    parser.add_argument("--seed", type=int, default=13)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    print(f"lagrangian {getattr(lagrangian, '__version__', '?')}, Python {sys.version.split()[0]}, "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}")
    ok = True
    if not args.skip_compile:
        print("\n1. derive + compile_system, fresh process, empty compile cache "
              f"(targets: < {TARGET_COMPILE_S:g} s; < {TARGET_MEMORY_MB:g} MB at n = 30)")
        print(f"{'system':<10} {'formulation':<11} {'derive s':>9} {'compile s':>10} {'total s':>8} "
              f"{'CPU py s':>9} {'CPU cc s':>9} {'RSS py MB':>10} {'RSS cc MB':>10} {'C kB':>7}")
        cases = [("chain", 20), ("arm", 10), ("chain", 30), ("arm", 30)]
        for kind, n in cases:
            for formulation in (("auto", "lagrange") if args.baseline and n < 30 else ("auto",)):
                r = derive_and_compile(kind, n, formulation)
                total = r["derive"] + r["compile"]
                print(f"{kind + str(n):<10} {r['formulation']:<11} {r['derive']:9.2f} {r['compile']:10.2f} "
                      f"{total:8.2f} {r['cpu']:9.2f} {r['cc_cpu']:9.2f} {r['rss_mb']:10.0f} {r['cc_rss_mb']:10.0f} "
                      f"{r['source_kb']:7.0f}")
                if formulation == "auto":
                    if n < 30 and r["cpu"] + r["cc_cpu"] > TARGET_COMPILE_S:
                        ok = False
                    if n == 30 and max(r["rss_mb"], r["cc_rss_mb"]) > TARGET_MEMORY_MB:
                        ok = False
    if args.skip_peers:
        return 0 if ok else 1
    try:
        import pinocchio as pin
    except ImportError as exc:
        print(f"\n2. skipped: Pinocchio is not installed ({exc}); `pip install pin`")
        return 0 if ok else 1
    print(f"\n2. q'' per state against Pinocchio {pin.__version__} (µs; ratio ours/aba, target ≤ {TARGET_RATIO})")
    for kind in args.systems:
        print(f"\n{kind}: {'n':>3} {'|Δq̈|':>8} {'ours':>7} {'M⁻¹F':>7} {'aba':>7} {'rnea+crba':>10} {'ratio':>6} "
              f"{'(M⁻¹F)':>7} {'ours N':>7} {'M⁻¹F N':>7} {'loop N':>7} {'pool N':>7} {'ratio N':>8} {'(M⁻¹F)':>7}")
        for n in args.sizes:
            r = compare(kind, n, rng, args.rtol, args.quick)
            single, batch = r["ours"] / r["aba"], r["ours_batch"] / r["aba_batch"]
            ok = ok and single <= TARGET_RATIO and batch <= TARGET_RATIO
            print(f"{'':7}{n:3d} {r['diff']:8.1e} {r['ours'] * 1e6:7.2f} {r['solve'] * 1e6:7.2f} {r['aba'] * 1e6:7.2f} "
                  f"{r['rnea_crba'] * 1e6:10.2f} {single:6.2f} {r['solve'] / r['aba']:7.2f} "
                  f"{r['ours_batch'] * 1e6:7.3f} {r['solve_batch'] * 1e6:7.3f} {r['aba_loop_batch'] * 1e6:7.2f} "
                  f"{r['pool_batch'] * 1e6:7.2f} {batch:8.3f} {r['solve_batch'] / r['aba_batch']:7.3f}")
    print("\nall targets met" if ok else "\nsome targets NOT met (see above)")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
