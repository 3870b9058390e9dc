"""URDF robots of example-robot-data: load, derive, compile and q̈ per state, against Pinocchio in the same run.

For each robot (double pendulum, UR5, Panda with its mimic finger) the script

1. reads the URDF with `lagrangian.load_urdf` and derives it (`lagrangian.derive`), timed;
2. compiles the right-hand side (`compile_system`, generated C), timed;
3. checks our q̈ against Pinocchio's on the same file at random states (``aba``; for the
   Panda, whose mimic joint ``aba`` refuses, M⁻¹(τ − h) from ``crba`` and
   ``nonLinearEffects``), stopping above 1e-9: a benchmark of different physics is worthless;
4. times q̈ for one state per call: ours ``CompiledSystem.rhs_c`` against ``pin.aba`` from
   Python (ratio ours/peer, below 1: ours is faster).

Times are minima over short blocks (the machine is shared).

Run:  .venv/bin/python benchmarks/urdf_robots.py [double_pendulum ur5 panda]
Needs the `robots` extra: pip install -e '.[robots]' (pin, example-robot-data).
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from urdf_robots import Peer, robot_data_file  # noqa: E402

import lagrangian  # noqa: E402
from lagrangian.model.urdf import UrdfNote  # noqa: E402

ROBOTS = {
    "double_pendulum": ("double_pendulum_description/urdf/double_pendulum.urdf", False),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", False),
    "panda": ("panda_description/urdf/panda.urdf", True),
}


def best(fn, repeat: int = 30, number: int = 200) -> float:
    """The smallest time of one call, in seconds, over ``repeat`` blocks of ``number`` calls."""
    out = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            fn()
        out = min(out, (time.perf_counter() - start) / number)
    return out


def run(name: str) -> None:
    import pinocchio as pin

    relative, mimic = ROBOTS[name]
    path = robot_data_file(relative)
    if path is None:
        print(f"{name}: example-robot-data is not installed")
        return
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        model = lagrangian.load_urdf(path, damping=False)
    eom = lagrangian.derive(model)
    derive_s = time.perf_counter() - start
    start = time.perf_counter()
    system = lagrangian.compile_system(eom)
    compile_s = time.perf_counter() - start
    peer = Peer(pin, path.read_text(), list(eom.coordinates), mimic=mimic)
    p = system.parameter_vector()
    n = system.n
    rng = np.random.default_rng(0)
    for _ in range(5):
        q, v = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
        ours = system.rhs(0.0, np.concatenate([q, v]), p)[n:]
        theirs = peer.acceleration(q, v)
        diff = np.max(np.abs(ours - theirs)) / max(1.0, np.max(np.abs(theirs)))
        if diff > 1e-9:
            raise SystemExit(f"{name}: q̈ differs from Pinocchio's by {diff:.2e}")
    y, out = np.concatenate([q, v]), np.empty(2 * n)
    ours_s = best(lambda: system.rhs_c(0.0, y, p, out))
    qp, vp = peer.state(q, v)
    tau = np.zeros(peer.model.nv)
    if mimic:
        peer_s = best(lambda: (pin.crba(peer.model, peer.data, qp),
                               pin.nonLinearEffects(peer.model, peer.data, qp, vp)))
        label = "crba+nle"
    else:
        peer_s = best(lambda: pin.aba(peer.model, peer.data, qp, vp, tau))
        label = "aba"
    print(f"{name:16s} n = {n}  load+derive {derive_s:6.2f} s  compile {compile_s:6.1f} s  "
          f"q̈ ours {ours_s * 1e6:7.2f} µs  pin.{label} {peer_s * 1e6:6.2f} µs  ours/peer {ours_s / peer_s:5.2f}  "
          f"(max rel. diff q̈ {diff:.1e})", flush=True)


if __name__ == "__main__":
    for robot in sys.argv[1:] or list(ROBOTS):
        run(robot)
