"""A legged robot on a floating base: derive + compile time, and q̈ per state against Pinocchio's FreeFlyer.

For each quadruped of example-robot-data (Solo-12, Unitree A1 and Go2: 12 joints and a free base)
the script

1. in a fresh process with an empty compile cache, reads the URDF with
   ``lagrangian.load_urdf(path, floating_base=True)`` and builds its quaternion-state system
   (`lagrangian.compile_free_system`: the floating-base articulated-body algorithm and the
   composite-rigid-body M as named intermediates, generated C, compiled), timing each step in
   wall and CPU seconds (the process's and the C compiler's); ``lagrangian.derive`` (the course's
   Lagrange equations in yaw-pitch-roll, not needed to simulate) is timed beside it.
   Target: load + build + compile under 5 s;
2. checks our q̈ against ``pin.aba`` on Pinocchio's model of the same file with
   ``JointModelFreeFlyer()`` at random states and joint torques (relative difference ≤ 1e-9,
   else it stops: a benchmark of different physics is worthless), Pinocchio's base velocity
   and acceleration converted (v = R v_local, v̇ = R (a_local + ω ∧ v_local));
3. times one state per call: ours ``FreeBodySystem.rhs_c`` (the whole ẏ: q̈, the quaternion's
   derivative, v̇ in R0), Pinocchio's ``pin.aba(model, data, q, v, τ)``, both from Python.
   Target: ours at least 2× faster (ratio ours/aba ≤ 0.5).

Times are the minimum over short timing blocks (`rhs_vs_peers.per_call`): on a busy shared
machine they show the cost of the code, not other processes' time slices.

Run:  .venv/bin/python benchmarks/floating_base.py [solo12 a1 go2]
Needs the `robots` extra: pip install -e '.[robots]' (pin, example-robot-data).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))
from urdf_robots import robot_data_file

sys.path.insert(0, str(HERE))
from rhs_vs_peers import per_call

import lagrangian
from lagrangian.model.urdf import UrdfNote
from lagrangian.numerics._euler import matrix_from_quaternion

#: (ANYmal B and C, Go1, HyQ and B1 are refused by `lagrangian.model._urdf_read`: a link of each has principal
#: moments that break the triangle inequality A + B ≥ C, which no mass distribution has; the message gives the line.)
ROBOTS = {
    "solo12": "solo_description/robots/solo12.urdf",
    "a1": "a1_description/urdf/a1.urdf",
    "go2": "go2_description/urdf/go2.urdf",
}
TARGET_BUILD_S = 5.0
TARGET_RATIO = 0.5

_CHILD = r"""
import json, resource, sys, time, warnings
t0, c0 = time.perf_counter(), time.process_time()
import lagrangian
from lagrangian.model.urdf import UrdfNote
t1, c1 = time.perf_counter(), time.process_time()
with warnings.catch_warnings():
    warnings.simplefilter("ignore", UrdfNote)
    model = lagrangian.load_urdf(sys.argv[1], floating_base=True, damping=False)
t2, c2 = time.perf_counter(), time.process_time()
system = lagrangian.compile_free_system(model)
t3, c3 = time.perf_counter(), time.process_time()
cc = resource.getrusage(resource.RUSAGE_CHILDREN)
eom = lagrangian.derive(model)
t4, c4 = time.perf_counter(), time.process_time()
print(json.dumps({"import": t1 - t0, "load": t2 - t1, "build": t3 - t2, "cpu": c3 - c1,
                  "cc_cpu": cc.ru_utime + cc.ru_stime, "derive": t4 - t3, "derive_cpu": c4 - c3,
                  "source_kb": len(system.source) / 1024, "formulation": eom.formulation}))
"""


def build_times(path: Path) -> dict:
    """load + compile_free_system (and derive) of one URDF, in a fresh process with an empty compile cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, LAGRANGIAN_CACHE=cache)
        out = subprocess.run([sys.executable, "-c", _CHILD, str(path)], env=env, capture_output=True, text=True,
                             check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def pinocchio_state(pin, model, y: np.ndarray, joints: list[str]):  # type: ignore[no-untyped-def]
    """Pinocchio's (q, v) of our state (r, e, q; v, ω, q̇), and R."""
    n = len(joints)
    R = matrix_from_quaternion(y[3:7])
    q, v = pin.neutral(model), np.zeros(model.nv)
    q[:3], q[3:7] = y[:3], [y[4], y[5], y[6], y[3]]
    v[:3], v[3:6] = R.T @ y[7 + n:10 + n], y[10 + n:13 + n]
    for name, qj, vj in zip(joints, y[7:7 + n], y[13 + n:13 + 2 * n], strict=True):
        j = model.joints[model.getJointId(name)]
        q[j.idx_q:j.idx_q + j.nq] = (np.cos(qj), np.sin(qj)) if j.nq == 2 else qj
        v[j.idx_v] = vj
    return q, v, R


def run(name: str) -> None:
    import pinocchio as pin

    path = robot_data_file(ROBOTS[name])
    if path is None:
        print(f"{name}: example-robot-data is not installed")
        return
    times = build_times(path)
    total_cpu = times["cpu"] + times["cc_cpu"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        system = lagrangian.compile_free_system(lagrangian.load_urdf(path, floating_base=True, damping=False))
    joints = list(system.coordinates[6:])
    peer = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    data = peer.createData()
    order = [0, 1, 2, 3, 4, 5, *(peer.joints[peer.getJointId(j)].idx_v for j in joints)]
    rng = np.random.default_rng(0)
    n, nq = len(joints), 7 + len(joints)
    rows, peer_rows, worst = [], [], 0.0
    for _ in range(50):
        e = rng.normal(size=4)
        y = np.concatenate([rng.normal(size=3), e / np.linalg.norm(e), rng.uniform(-1, 1, n), rng.normal(size=6),
                            rng.uniform(-1, 1, n), [0.0]])
        tau = rng.uniform(-1, 1, n)
        p = system.parameter_vector({f"tau_{j}": t for j, t in zip(joints, tau, strict=True)} if system.model.inputs else None)
        ours = system.rhs(0.0, y, p)[nq:nq + 6 + n]
        q, v, R = pinocchio_state(pin, peer, y, joints)
        t = np.zeros(peer.nv)
        t[order[6:]] = tau
        a = pin.aba(peer, data, q, v, t)[order]
        theirs = np.concatenate([R @ (a[:3] + np.cross(y[nq + 3:nq + 6], R.T @ y[nq:nq + 3])), a[3:]])
        worst = max(worst, float(np.max(np.abs(ours - theirs)) / max(1.0, np.max(np.abs(theirs)))))
        rows.append((0.0, y, p, np.empty_like(y)))
        peer_rows.append((peer, data, q, v, t))
    if worst > 1e-9:
        raise SystemExit(f"{name}: q̈ differs from Pinocchio's by {worst:.2e}")
    ours_s = per_call(system.rhs_c, rows)
    peer_s = per_call(pin.aba, peer_rows)
    ratio = ours_s / peer_s
    print(f"{name:9s} {n} joints + free base: load {times['load']:.2f} s, build+compile {times['build']:.2f} s wall, "
          f"{total_cpu:.2f} s CPU ({times['cpu']:.2f} Python + {times['cc_cpu']:.2f} compiler; target "
          f"< {TARGET_BUILD_S:g} s: {'met' if total_cpu + times['load'] < TARGET_BUILD_S else 'NOT met'}), "
          f"C {times['source_kb']:.0f} kB; derive (course, {times['formulation']}) {times['derive']:.2f} s")
    print(f"{'':9s} q̈ per state: ours {ours_s * 1e6:.2f} µs, pin.aba {peer_s * 1e6:.2f} µs, ours/aba {ratio:.2f} "
          f"(target ≤ {TARGET_RATIO}: {'met' if ratio <= TARGET_RATIO else 'NOT met'}); max rel. diff q̈ {worst:.1e}",
          flush=True)


if __name__ == "__main__":
    for robot in sys.argv[1:] or list(ROBOTS):
        run(robot)
