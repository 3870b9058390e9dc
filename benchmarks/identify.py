"""Identification: the 7-joint arm's regressor on 10^4 samples, and what sensitivities cost, with peers in the same run.

1. The Panda of example-robot-data (its fingers welded: 7 revolute joints, 70 standard inertial
   parameters, `load_urdf(..., inertial_parameters=True)`): derive, generate and compile the
   inverse-dynamics regressor (timed), check it against Pinocchio's
   ``computeJointTorqueRegressor`` at a few states (stops above 1e-9), then time
   - ours: `Regressor.evaluate` on 10^4 samples (one call), and the base-parameter regressor
     (the base parameters by QR from 100 random states, then the base columns of the 10^4
     samples) — the target is under 1 s;
   - Pinocchio: ``computeJointTorqueRegressor`` over the same 10^4 samples from Python (the loop
     a user writes; its C++ cost alone is printed beside it, from the same loop minus an empty one).
2. Sensitivities: a plain `simulate` against the same run with sensitivities to every parameter
   and to every initial value (`simulate(..., sensitivities=[...])`), same tolerances, on the
   pendulum, the double pendulum and the cart on a rail with a pendulum; ratio with/without.
3. `identify` end to end on the cart-pendulum record of the tests (regressor, shooting).

Times are minima over a few repeats (the machine is shared); BLAS threads can slow the SVDs of
a loaded 2-core machine tenfold: run with OPENBLAS_NUM_THREADS=1 for stable figures.

Run:  .venv/bin/python benchmarks/identify.py [--quick]
Needs the `robots` extra for part 1 (pin, example-robot-data).
"""

from __future__ import annotations

import re
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "tests" / "identification"))
from urdf_robots import Peer, robot_data_file

import lagrangian
from lagrangian.identification import Regressor, base_parameters
from lagrangian.model.urdf import inertial_parameter_names, parse_urdf

SAMPLES = 10_000


def best(fn, repeat: int = 5) -> float:
    out = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        out = min(out, time.perf_counter() - start)
    return out


def panda_regressor() -> None:
    import pinocchio as pin

    path = robot_data_file("panda_description/urdf/panda.urdf")
    if path is None:
        print("panda: example-robot-data is not installed")
        return
    text = re.sub(r"<mimic[^>]*/>", "", path.read_text()).replace('type="prismatic"', 'type="fixed"')
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = parse_urdf(text, inertial_parameters=True, damping=False)
    eom = lagrangian.derive(model)
    derived = time.perf_counter() - start
    groups = inertial_parameter_names(model)
    fitted = [name for names in groups.values() for name in names]
    start = time.perf_counter()
    regressor = Regressor(eom, fitted)
    built = time.perf_counter() - start
    n = regressor.n
    p = np.array([model.parameter_values[name] for name in regressor.parameters])
    peer = Peer(pin, text, list(eom.coordinates))
    joints = {j.name: j.child for j in lagrangian.model.urdf.read_urdf(path).joints.values()}
    order = ("m", "mx", "my", "mz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz")
    ours_order = ("m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz")
    columns = []
    for body in groups:
        joint = next(j for j, child in joints.items() if child == body)
        first = 10 * (peer.model.getJointId(joint) - 1)
        columns += [first + order.index(k) for k in ours_order]
    rng = np.random.default_rng(0)
    q, v, a = (rng.uniform(-2, 2, (SAMPLES, n)) for _ in range(3))
    y = np.hstack([q, v])
    _, Y = regressor.evaluate(0.0, y[:5], a[:5], p)
    worst = 0.0
    for k in range(5):
        Yp = pin.computeJointTorqueRegressor(peer.model, peer.data, *peer.state(q[k], v[k]), a[k])
        worst = max(worst, float(np.abs(Yp[np.ix_(peer.v_index, columns)] - Y[k]).max()))
    if worst > 1e-9:
        raise SystemExit(f"our regressor differs from Pinocchio's by {worst:.2e}: not timing different physics")
    ours = best(lambda: regressor.evaluate(0.0, y, a, p))
    structural = base_parameters(regressor.evaluate(0.0, y[:100], a[:100], p)[1].reshape(-1, len(fitted)), fitted)
    cols = list(structural.independent)

    def base_regressor():
        _, Yall = regressor.evaluate(0.0, y, a, p)
        return base_parameters(Yall[:100].reshape(-1, len(fitted)), fitted), Yall[:, :, cols]

    ours_base = best(base_regressor)
    states = [peer.state(qi, vi) for qi, vi in zip(q, v, strict=True)]

    def pinocchio():
        for (qp, vp), ak in zip(states, a, strict=True):
            pin.computeJointTorqueRegressor(peer.model, peer.data, qp, vp, ak)

    def empty():
        for (_qp, _vp), _ak in zip(states, a, strict=True):  # the loop and unpacking alone, subtracted from the peer's time
            pass

    theirs = best(pinocchio, 3)
    loop = best(empty, 3)
    print(f"Panda, 7 joints, 70 inertial parameters ({structural.rank} base parameters)")
    print(f"  load_urdf + derive {derived:.2f} s; regressor generated and compiled {built:.2f} s "
          f"({len(regressor.source) / 1e3:.0f} kB of C); max |ours - Pinocchio's| {worst:.1e}")
    print(f"  {SAMPLES} samples                                 time      ours/peer")
    print(f"  ours: Regressor.evaluate (7 x 70 per sample)      {ours * 1e3:7.1f} ms   {ours / theirs:.2f}")
    print(f"  ours: base parameters + base regressor (7 x {structural.rank})  {ours_base * 1e3:7.1f} ms   "
          f"{ours_base / theirs:.2f}   target < 1 s: {'met' if ours_base < 1 else 'NOT met'}")
    print(f"  Pinocchio computeJointTorqueRegressor, Python loop {theirs * 1e3:7.1f} ms")
    print(f"    of which the C++ calls                          {(theirs - loop) * 1e3:7.1f} ms   "
          f"(ours/C++: {ours / (theirs - loop):.2f})")


MODELS = {
    "pendulum": (ROOT / "examples" / "simple_pendulum.toml", {}),
    "double pendulum": (ROOT / "examples" / "double_pendulum.toml", {}),
    "cart on a spring with a pendulum": (ROOT / "examples" / "cart_pendulum.toml", {}),
}


def sensitivity_cost(t_end: float) -> None:
    from lagrangian.numerics import compile_system, simulate

    print(f"\nsensitivities, {t_end:g} s at rtol = atol = 1e-10 (plain run vs with sensitivities)")
    print("  model                            n  columns   plain     with S    ratio  central differences  steps (same)")
    for name, (path, initial) in MODELS.items():
        system = compile_system(lagrangian.derive(lagrangian.load_model(path)))
        params = [p.name for p in system.eom.model.parameters if not p.input
                  and system.eom.model.parameter_values[p.name] is not None]
        states = [*system.coordinates, *(c + "_dot" for c in system.coordinates)]
        names = params + [s + "(t0)" for s in states]
        simulate(system, 0.1, sensitivities=names)  # compiled once, outside the timing
        plain = best(lambda system=system, initial=initial: simulate(system, t_end, initial=initial, n_out=201))
        with_s = best(lambda system=system, initial=initial, names=names: simulate(
            system, t_end, initial=initial, n_out=201, sensitivities=names))
        a = simulate(system, t_end, initial=initial, n_out=201)
        b = simulate(system, t_end, initial=initial, n_out=201, sensitivities=names)
        same = "yes" if np.array_equal(a.q, b.q) and a.steps == b.steps else "no"
        # central differences need two runs per column, at a tighter tolerance to be as accurate
        print(f"  {name:<32} {system.n}  {len(names):>3}      {plain * 1e3:6.2f} ms {with_s * 1e3:7.2f} ms "
              f"{with_s / plain:6.1f}  {2 * len(names):>6} runs ({2 * len(names) * plain * 1e3:.1f} ms)  "
              f"{a.steps} ({same})")


def identify_end_to_end() -> None:
    from test_identify import CART_POLE, TRUE, cart_pole_record

    from lagrangian.identification import SavitzkyGolay, Shooting, identify

    eom = lagrangian.derive(lagrangian.parse_model(CART_POLE))
    record = cart_pole_record(6.0, 200.0, 1e-5, seed=3)
    identify(eom, record, ["mc", "m", "c"], values={"l": TRUE["l"]})  # compile outside the timing
    regressor = best(lambda: identify(eom, record, ["mc", "m", "c"], values={"l": TRUE["l"]},
                                      derivatives=SavitzkyGolay(31, 4)), 3)
    record = cart_pole_record(4.0, 100.0, 1e-4, seed=4)
    guess = {"mc": 1.0, "m": 0.2, "c": 0.5, "l": 0.6}
    identify(eom, record, list(guess), guess=guess, shooting=Shooting(segments=8))
    shooting = best(lambda: identify(eom, record, list(guess), guess=guess, shooting=Shooting(segments=8)), 3)
    single = best(lambda: identify(eom, record, list(guess), guess=guess, shooting=Shooting(segments=1)), 3)
    print("\nidentify, cart and pendulum with friction (compiled code cached)")
    print(f"  regressor, 1201 samples, mc, m, c             {regressor * 1e3:7.1f} ms")
    print(f"  shooting, 401 samples, mc, m, c, l, 8 segments {shooting * 1e3:7.1f} ms")
    print(f"  shooting, the same, single shooting           {single * 1e3:7.1f} ms")


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    panda_regressor()
    sensitivity_cost(2.0 if quick else 10.0)
    identify_end_to_end()
