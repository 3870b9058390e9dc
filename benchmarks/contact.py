"""Contacts: the bouncing ball to rest, and what locating the impacts costs.

1. examples/bouncing_ball.toml (h0 = 1 m, e = 0.8) from rest to t = 4.5 s, past the accumulation
   time t_inf = 4.064 s, on 1001 output times: `simulate` (every flight in the compiled DOP853, each
   impact located as a terminal event, the accumulation summed, then rest).  Peer in the same run:
   the textbook SciPy loop — `solve_ivp(DOP853)` on the hand-written ball with a terminal event on
   z, restarted at each bounce with v -> -e v — run to the same number of impacts.  Target: the
   ball to rest in under 5 ms.
2. The cost of locating the impacts: the flights of that run integrated again by the compiled DOP853,
   twice through the same calls, with the gap as a terminal event function (each flight ends at its
   impact, located on the dense output to a few ulp) and without any event function to the impact's
   time, known from the first.  A parabola takes DOP853 two steps, so the ball is also timed with
   quadratic air drag (many steps a flight).  Target: with events at most 1.5 x without.

CPU time of the process (`time.process_time`), best of --repeat, runs interleaved: less sensitive
than the wall clock to other jobs on a shared machine.

Run:  .venv/bin/python benchmarks/contact.py [--repeat 20]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

import lagrangian
from lagrangian.numerics import simulate_contact
from lagrangian.numerics._contact import contact_system
from lagrangian.numerics._control import control_block

ROOT = Path(__file__).resolve().parents[1]
G, H0, E, M = 9.81, 1.0, 0.8, 0.1


def _best(fn, repeat: int) -> tuple[float, object]:  # type: ignore[no-untyped-def]
    best, value = float("inf"), None
    for _ in range(repeat):
        start = time.process_time()
        value = fn()
        best = min(best, time.process_time() - start)
    return best, value


def scipy_peer(impacts: int) -> tuple[int, float]:
    """The textbook loop: solve_ivp to the floor, v -> -e v, again; `impacts` impacts, the last time."""
    from scipy.integrate import solve_ivp

    def rhs(t: float, y: np.ndarray) -> list[float]:
        return [y[1], -G]

    def floor(t: float, y: np.ndarray) -> float:
        return y[0]

    floor.terminal, floor.direction = True, -1  # type: ignore[attr-defined]
    t, y, count = 0.0, [H0, 0.0], 0
    while count < impacts:
        sol = solve_ivp(rhs, (t, 10.0), y, method="DOP853", rtol=1e-10, atol=1e-10, events=floor,
                        first_step=None if count == 0 else 0.25 * 2 * y[1] / G)
        t = float(sol.t_events[0][0])
        v = float(sol.y_events[0][0][1])
        y, count = [0.0, -E * v], count + 1
    return count, t


def to_rest(repeat: int) -> None:
    model = lagrangian.load_model(ROOT / "examples" / "bouncing_ball.toml")
    simulate_contact(model, 4.5, n_out=1001)  # derived and compiled once, before timing
    ours, traj = _best(lambda: simulate_contact(model, 4.5, n_out=1001), repeat)
    impacts = sum(1 for e in traj.events if e.kind == "impact")  # type: ignore[union-attr]
    rest = next(e.t for e in traj.events if e.kind == "rest")  # type: ignore[union-attr]
    peer, (count, t_last) = _best(lambda: scipy_peer(impacts), max(3, repeat // 4))
    t_inf = np.sqrt(2 * H0 / G) * (1 + E) / (1 - E)
    print(f"bouncing ball to rest (h0 = {H0} m, e = {E}), t = 0..4.5 s, 1001 outputs, best of {repeat}:")
    print(f"  ours: simulate                   {ours * 1e3:8.2f} ms   {impacts} impacts, then rest at "
          f"t_inf = {rest:.12f} (closed form {t_inf:.12f})")
    print(f"  SciPy solve_ivp loop (same {count} impacts) {peer * 1e3:8.2f} ms   last impact {t_last:.9f}")
    print(f"  ours / SciPy                      {ours / peer:8.3f}      target: ours under 5 ms")


def _lean(lib, p: np.ndarray, events: int):  # type: ignore[no-untyped-def]
    """One flight of the compiled DOP853 from (t, y) to t_end, through the calls `FastPhases.run` makes
    (buffers and pointers kept); with ``events`` terminal event functions falling through 0 (the gaps)."""
    grid = np.array([0.0, 100.0])
    template = control_block("dop853", 0.0, 100.0, grid, 1e-10, 1e-10, None, None, 10**8)
    template[11] = 16
    ctl, y_buf, i_out, Y = template.copy(), np.zeros(2), np.zeros(1, dtype=np.intc), np.zeros((2, 2))
    ev_dir, ev_term = np.full(max(events, 1), -1, dtype=np.intc), np.ones(max(events, 1), dtype=np.intc)
    ev_out = np.zeros((16, 4))
    head = [a.ctypes.data for a in (ctl, y_buf, p, grid)] + [2, i_out.ctypes.data, Y.ctypes.data]
    tail = [a.ctypes.data for a in (ev_dir, ev_term, ev_out)]

    def flight(t: float, y: np.ndarray, t_end: float, h0: float) -> float:
        ctl[:] = template
        ctl[0], ctl[1] = t, h0
        y_buf[:] = y
        i_out[0] = 1
        lib.lg_dop853(*head, float(t_end), *tail)
        return float(ctl[0])

    return flight


def event_cost(repeat: int, drag: float) -> None:
    """The flights of a contact run, integrated again with and without the gap's event function."""
    model = lagrangian.load_model(ROOT / "examples" / "bouncing_ball.toml")
    if drag:  # quadratic air drag: each flight takes many steps, not the two of a parabola
        import symengine as se

        from lagrangian.model import Vector
        from lagrangian.model.spec import PointForce

        zd = se.Symbol("z_dot")
        force = Vector({"R0": (se.Integer(0), se.Integer(0), -drag * zd * se.Abs(zd))})
        model = replace(model, loads=model.loads + (PointForce("drag", force, "P"),))
    traj = simulate_contact(model, 4.5, n_out=2)
    impacts = [e for e in traj.events if e.kind == "impact"]
    starts = [(e.t, np.concatenate([e.q, e.qd_after])) for e in impacts[:-1]]
    ends = [e.t for e in impacts[1:]]
    cs = contact_system(model)
    plain = lagrangian.compile_system(lagrangian.derive(replace(model, constraints=())))
    p = cs.fast.parameter_vector(None)  # type: ignore[union-attr]
    with_gap, without = _lean(cs.fast._lib, p, 1), _lean(plain._lib, p, 0)  # type: ignore[union-attr]
    h0 = [0.25 * 2 * y[1] / G for _, y in starts]

    def run(flight) -> float:  # type: ignore[no-untyped-def]
        last = 0.0
        for (t, y), t_end, h in zip(starts, ends, h0, strict=True):
            last = flight(t, y, 100.0 if flight is with_gap else t_end, h)
        return last

    best = {"with": float("inf"), "without": float("inf")}
    value = {}
    for r in range(repeat):  # interleaved
        for name in (("with", "without") if r % 2 else ("without", "with")):
            flight = with_gap if name == "with" else without
            seconds, value[name] = _best(lambda flight=flight: run(flight), 1)
            best[name] = min(best[name], seconds)
    what = f"with air drag {drag} kg/m" if drag else "a parabola each"
    print(f"locating the impacts: {len(starts)} flights of the ball ({what}) in the compiled DOP853, best of {repeat}:")
    print(f"  with the gap as a terminal event      {best['with'] * 1e3:8.3f} ms   last impact located at "
          f"{value['with']:.12f}")
    print(f"  without events, to the located impact {best['without'] * 1e3:8.3f} ms")
    print(f"  ratio with / without                  {best['with'] / best['without']:8.3f}      target: at most 1.5")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()
    to_rest(args.repeat)
    event_cost(args.repeat, 0.0)
    event_cost(args.repeat, 0.05)


if __name__ == "__main__":
    main()
