"""Small motions: derive + linearize against SymPy's KanesMethod + linearize, same bicycle, same run.

Three questions, each answered with a peer timed in the same run:

1. **The Whipple bicycle** (Meijaard et al. 2007): ours is ``load_model`` + ``derive`` +
   ``linearize(symbolic=("v",))``, which gives A(v) for every speed at once; the peer builds the same
   bicycle with ``sympy.physics.mechanics.KanesMethod`` (the model of SymPy's own test suite,
   tests/reference/_sympy_bicycle.py) and linearizes it with ``KanesMethod.linearize`` — what a
   SymPy user does.  Both A(v) are checked against each other, and against the paper's closed
   forms, at v = 0 … 10 before any figure is printed.  Target: ours ≥ 50× faster.
2. **A 20-link planar chain** linearized about its hanging equilibrium (target: under 1 s for
   ``linearize``); the peer is SymPy's LagrangesMethod + linearize on the 5-link chain (the 20-link
   one takes SymPy far too long), and our time for the same 5-link chain.
3. **A 1000-point eigenvalue sweep** of the bicycle (target: under 1 s): ours is
   ``analysis.eigenvalue_sweep`` (A(v) compiled once, eigenvalues, the stability changes found by root
   finding); the peer is ``sympy.lambdify`` of SymPy's A(v) and ``numpy.linalg.eigvals`` on the
   same grid (no root finding).

Run:  .venv/bin/python benchmarks/linearize_vs_sympy.py [--quick]   (about 2 min; --quick skips
the SymPy bicycle, which takes about 80 s on a 2-core VM)
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp
from sympy.physics import mechanics as me

import lagrangian
from lagrangian.analysis import eigenvalue_sweep
from lagrangian.model.zoo import planar_chain

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "reference"))
import _sympy_bicycle  # noqa: E402
import _whipple  # noqa: E402

BICYCLE = ROOT / "examples" / "whipple_bicycle.toml"
LEAN_STEER = ["phi", "delta", "phi_dot", "delta_dot"]
TARGET_RATIO = 50.0
TARGET_CHAIN_S = 1.0
TARGET_SWEEP_S = 1.0


def _lean_steer(lin, v: float) -> np.ndarray:
    A, _ = lin.numeric(v=v)
    k = [lin.state.index(n) for n in LEAN_STEER]
    return A[np.ix_(k, k)]


def _ours_bicycle():
    t0 = time.perf_counter()
    eom = lagrangian.derive(lagrangian.load_model(BICYCLE))
    t1 = time.perf_counter()
    lin = lagrangian.linearize(eom, symbolic=("v",))
    t2 = time.perf_counter()
    return lin, t1 - t0, t2 - t1


def bicycle(quick: bool) -> None:
    print("Whipple bicycle: derive + linearize about upright straight-ahead motion, A(v) symbolic in v")
    best = None
    for _ in range(3):
        lin, derive_s, lin_s = _ours_bicycle()
        if best is None or derive_s + lin_s < sum(best[1:]):
            best = (lin, derive_s, lin_s)
    lin, derive_s, lin_s = best
    speeds = np.linspace(0.0, 10.0, 11)
    err_paper = max(np.max(np.abs(_lean_steer(lin, v) - _whipple.state_matrix(v))) / np.max(np.abs(_whipple.state_matrix(v)))
                    for v in speeds)
    print(f"  ours: derive {derive_s * 1e3:.0f} ms + linearize {lin_s * 1e3:.0f} ms = {(derive_s + lin_s):.3f} s;"
          f" max relative difference from the paper's A(v), v = 0..10: {err_paper:.1e}")
    if quick:
        print("  SymPy KanesMethod + linearize: skipped (--quick)")
        return
    t0 = time.perf_counter()
    A_sympy = _sympy_bicycle.derive_and_linearize()
    peer_s = time.perf_counter() - t0
    v = _sympy_bicycle.V
    f = sp.lambdify(v, A_sympy, modules="numpy")
    err_peer = max(np.max(np.abs(_lean_steer(lin, x) - np.asarray(f(x), dtype=float)))
                   / np.max(np.abs(_whipple.state_matrix(x))) for x in speeds)
    if err_peer > 1e-10 or err_paper > 1e-10:
        sys.exit(f"A(v) differ (peer {err_peer:.1e}, paper {err_paper:.1e}): no timing is worth printing")
    ratio = peer_s / (derive_s + lin_s)
    print(f"  SymPy KanesMethod + linearize (all parameters symbolic): {peer_s:.1f} s;"
          f" max relative difference from ours: {err_peer:.1e}")
    print(f"  speed-up: {ratio:.0f}x (target >= {TARGET_RATIO:.0f}x: {'met' if ratio >= TARGET_RATIO else 'MISSED'})")
    return f


def chain() -> None:
    print("Planar n-link chain (point masses, absolute angles) about its hanging equilibrium")
    for n in (5, 10, 20):
        eom = lagrangian.derive(planar_chain(n))
        point = {f"theta{k}": 0 for k in range(1, n + 1)}
        t0 = time.perf_counter()
        lin = lagrangian.linearize(eom, point)
        lin_s = time.perf_counter() - t0
        w = np.asarray(lin.modes().pulsations)
        note = f" (target < {TARGET_CHAIN_S:.0f} s: {'met' if lin_s < TARGET_CHAIN_S else 'MISSED'})" if n == 20 else ""
        print(f"  n = {n:2d}: linearize {lin_s * 1e3:7.1f} ms, {len(w)} pulsations from {w.min():.4f} to"
              f" {w.max():.4f} rad/s{note}")
        if n == 5:
            ours5 = lin_s
            A5 = lin.numeric()[0]
    # The peer on the 5-link chain: LagrangesMethod + Linearizer, then the same A numerically.
    model = planar_chain(5)
    values = {p.name: p.value for p in model.parameters}
    q = me.dynamicsymbols("theta1:6")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    t0 = time.perf_counter()
    g = sp.Symbol("g")
    P, particles, forces = O, [], []
    for k in range(5):
        m_k, l_k = sp.Symbol(f"m{k + 1}"), sp.Symbol(f"l{k + 1}")
        frame = N.orientnew(f"R{k + 1}", "Axis", (q[k], N.z))
        P = P.locatenew(f"P{k + 1}", l_k * frame.x)
        P.set_vel(N, P.pos_from(O).dt(N))
        particles.append(me.Particle(f"p{k + 1}", P, m_k))
        forces.append((P, m_k * g * N.x))
    L = me.Lagrangian(N, *particles)
    method = me.LagrangesMethod(L, q, forcelist=forces, frame=N)
    method.form_lagranges_equations()
    op = [{qi: 0 for qi in q}, {qi.diff(): 0 for qi in q}, {qi.diff().diff(): 0 for qi in q}]
    A, *_ = method.linearize(q_ind=q, qd_ind=[qi.diff() for qi in q], op_point=op, A_and_B=True)
    peer_s = time.perf_counter() - t0
    A_peer = np.array(A.xreplace({sp.Symbol(k): v for k, v in values.items() if v is not None}), dtype=float)
    # ±i ω with real parts of rounding size: compare the sorted imaginary parts.
    same = np.allclose(np.sort(np.linalg.eigvals(A_peer).imag), np.sort(np.linalg.eigvals(A5).imag), rtol=1e-9)
    print(f"  n =  5, SymPy LagrangesMethod + linearize: {peer_s:.2f} s (same eigenvalues: {same});"
          f" ours/peer = {ours5 / peer_s:.4f}")


def sweep_bicycle(peer_A) -> None:
    print("Bicycle: eigenvalues on 1001 speeds v = 0..10 m/s")
    lin, _, _ = _ours_bicycle()
    grid = np.arange(0.0, 10.0 + 1e-9, 0.01)
    t0 = time.perf_counter()
    s = eigenvalue_sweep(lin, "v", grid)
    ours_s = time.perf_counter() - t0
    found = ", ".join(f"{c.kind} at {c.value:.9f}" for c in s.changes)
    print(f"  ours: analysis.eigenvalue_sweep {ours_s * 1e3:.0f} ms (compile once, eigenvalues, root finding): {found}"
          f" (target < {TARGET_SWEEP_S:.0f} s: {'met' if ours_s < TARGET_SWEEP_S else 'MISSED'})")
    if peer_A is not None:
        t0 = time.perf_counter()
        eig = [np.linalg.eigvals(np.asarray(peer_A(x), dtype=float)) for x in grid]
        peer_s = time.perf_counter() - t0
        print(f"  peer: sympy.lambdify of SymPy's A(v) + numpy eigvals: {peer_s * 1e3:.0f} ms (no root finding);"
              f" ours/peer = {ours_s / peer_s:.2f}; {len(eig)} spectra")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="skip the SymPy bicycle (about 80 s)")
    args = parser.parse_args()
    peer_A = bicycle(args.quick)
    chain()
    sweep_bicycle(peer_A)


if __name__ == "__main__":
    main()
