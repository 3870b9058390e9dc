"""Derivation time of `lagrangian.derive` against SymPy's `LagrangesMethod`, same systems, same run.

For each system the script

1. builds the model with `lagrangian` (timed apart: "build") and derives M, F with
   ``lagrangian.derive(model)`` (best of ``--repeat`` runs: "ours");
2. builds the same system with `sympy.physics.mechanics` (ReferenceFrame, Point,
   Particle, RigidBody) and times ``Lagrangian`` + ``LagrangesMethod`` +
   ``form_lagranges_equations`` + ``mass_matrix`` + ``forcing`` (one run: "SymPy");
3. checks that both give the same q̈ = M⁻¹F at random states and random parameter
   values (numpy solve, relative tolerance ``--rtol``).

Systems: the Lagrange top (Euler angles ψ, θ, φ body-fixed z-x-z, inertia diag(A, A, C)
at the fixed point O, gravity) and the planar n-link pendulum `planar_chain(n)` for
n = 1..--max-n; then our time alone for the long chains of ``--ours-only``.

Run:  .venv/bin/python benchmarks/derive_vs_sympy.py [--max-n 12] [--ours-only 20 40]
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable

import numpy as np
import symengine as se
import sympy as sp
from sympy.core.cache import clear_cache
from sympy.physics import mechanics as me

import lagrangian
from lagrangian.model.zoo import lagrange_top, planar_chain

#: Targets of the benchmark (README): speed-up on every compared row, and the 40-link chain.
TARGET_RATIO = 100.0
TARGET_40_LINK_S = 1.0
#: A timing loop of our derive lasts about this long (short derivations are looped)...
OURS_LOOP_S = 0.1
#: ... with at most this many calls.
OURS_MAX_NUMBER = 1000


# -- SymPy reference systems ------------------------------------------------------------------
class SympySystem:
    """A system described with sympy.physics.mechanics, ready for LagrangesMethod."""

    def __init__(self, q: list, make_lagrangian: Callable[[], sp.Expr]) -> None:
        self.q = q
        self.make_lagrangian = make_lagrangian
        self.M: sp.Matrix | None = None
        self.F: sp.Matrix | None = None

    def derive(self) -> None:
        L = self.make_lagrangian()
        lm = me.LagrangesMethod(L, self.q)
        lm.form_lagranges_equations()
        self.M = lm.mass_matrix
        self.F = lm.forcing


def sympy_planar_chain(n: int) -> SympySystem:
    """Point masses m_k on rods l_k, absolute angles θ_k from the downward vertical N.x."""
    q = me.dynamicsymbols(" ".join(f"theta{k}" for k in range(1, n + 1)), seq=True)
    m = sp.symbols(" ".join(f"m{k}" for k in range(1, n + 1)), seq=True)
    lengths = sp.symbols(" ".join(f"l{k}" for k in range(1, n + 1)), seq=True)
    g = sp.Symbol("g")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    particles = []
    prev = O
    for k in range(n):
        Rk = N.orientnew(f"R{k + 1}", "Axis", [q[k], N.z])
        P = prev.locatenew(f"P{k + 1}", lengths[k] * Rk.x)
        part = me.Particle(f"P{k + 1}", P, m[k])
        part.potential_energy = -m[k] * g * P.pos_from(O).dot(N.x)  # x0 points down
        particles.append(part)
        prev = P

    def make_lagrangian() -> sp.Expr:
        # Velocities are left for Point.vel to compute from the positions, inside the timing.
        return me.Lagrangian(N, *particles)

    return SympySystem(list(q), make_lagrangian)


def sympy_lagrange_top() -> SympySystem:
    """The heavy symmetric top: ψ, θ, φ body-fixed z-x-z, Π_O = diag(A, A, C), OG = a z."""
    psi, theta, phi = me.dynamicsymbols("psi theta phi")
    m, g, a, A, C = sp.symbols("m g a A C")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Body", [psi, theta, phi], "ZXZ")
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", a * B.z)
    top = me.RigidBody("S", G, B, m, (me.inertia(B, A, A, C), O))
    top.potential_energy = m * g * G.pos_from(O).dot(N.z)

    def make_lagrangian() -> sp.Expr:
        return me.Lagrangian(N, top)

    return SympySystem([psi, theta, phi], make_lagrangian)


# -- numerical comparison -----------------------------------------------------------------------
def _ours_qdd(eom, params: dict[str, float]) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    n = len(eom.q)
    names = sorted(params)
    args = [*eom.q, *eom.qd, *(se.Symbol(p) for p in names)]
    fn = se.Lambdify(args, [e for row in eom.M for e in row] + list(eom.F), backend="lambda")
    pvals = [params[p] for p in names]

    def qdd(q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        out = np.asarray(fn([*q, *qd, *pvals]), dtype=float).ravel()
        return np.linalg.solve(out[: n * n].reshape(n, n), out[n * n:])

    return qdd


def _sympy_qdd(system: SympySystem,
               params: dict[str, float]) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    n = len(system.q)
    t = me.dynamicsymbols._t
    qs = sp.symbols(f"q0:{n}")
    us = sp.symbols(f"u0:{n}")
    # Replace q̇ first, then q, so that Derivative(q(t), t) is not touched by the second step.
    rep_d = {qi.diff(t): ui for qi, ui in zip(system.q, us, strict=True)}
    rep_q = dict(zip(system.q, qs, strict=True))
    exprs = [e.xreplace(rep_d).xreplace(rep_q) for e in [*system.M, *system.F]]
    names = sorted(params)
    fn = sp.lambdify([*qs, *us, *(sp.Symbol(p) for p in names)], exprs, modules="numpy")
    pvals = [params[p] for p in names]

    def qdd(q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        out = np.array(fn(*q, *qd, *pvals), dtype=float).ravel()
        return np.linalg.solve(out[: n * n].reshape(n, n), out[n * n:])

    return qdd


#: Where random states are drawn, per coordinate name (default: any angle); the top's
#: nutation θ keeps away from 0 and π, where Euler angles are singular and M is too.
Q_RANGES = {"theta": (0.3, 2.8)}


def same_accelerations(eom, system: SympySystem, *, states: int, rtol: float, seed: int) -> float:
    """Largest relative difference ‖q̈_ours − q̈_sympy‖ / ‖q̈_sympy‖ over random states.

    Parameters get random values in [0.5, 1.5], q and q̇ random values; raises above ``rtol``.
    """
    rng = np.random.default_rng(seed)
    params = {p.name: float(rng.uniform(0.5, 1.5)) for p in eom.model.parameters}
    ours, theirs = _ours_qdd(eom, params), _sympy_qdd(system, params)
    n = len(eom.q)
    low, high = zip(*(Q_RANGES.get(name, (-np.pi, np.pi)) for name in eom.coordinates), strict=True)
    worst = 0.0
    for _ in range(states):
        q = rng.uniform(low, high)
        qd = rng.uniform(-2.0, 2.0, n)
        a, b = ours(q, qd), theirs(q, qd)
        err = float(np.linalg.norm(a - b) / max(np.linalg.norm(b), 1e-300))
        worst = max(worst, err)
        if not err <= rtol:
            raise AssertionError(f"{eom.model.name}: q̈ differ at q={q}, q̇={qd}: ours {a}, SymPy {b} "
                                 f"(relative difference {err:.3g})")
    return worst


# -- timing -------------------------------------------------------------------------------------
def time_ours(make_model: Callable[[], lagrangian.Model], repeat: int,
              loop_s: float = OURS_LOOP_S):  # type: ignore[no-untyped-def]
    """(best build time, best derive time per call, an EquationsOfMotion), as `timeit` measures.

    Each of the ``repeat`` rounds builds a fresh model (timed apart), then calls
    ``lagrangian.derive(model)`` ``number`` times in a loop and keeps the time per call;
    ``number`` is 1 for long derivations and grows for short ones until a loop lasts about
    ``loop_s`` seconds, so that a sub-millisecond row is not one noisy sample.  Nothing is
    cached between calls: each derive builds its own kinematics from the model.
    """
    build_best = derive_best = float("inf")
    eom = None
    number = 1
    for _ in range(repeat):
        t0 = time.perf_counter()
        model = make_model()
        t1 = time.perf_counter()
        for _ in range(number):
            eom = lagrangian.derive(model)
        t2 = time.perf_counter()
        build_best = min(build_best, t1 - t0)
        derive_best = min(derive_best, (t2 - t1) / number)
        if t2 - t1 < loop_s and derive_best > 0:
            number = max(number, min(OURS_MAX_NUMBER, int(loop_s / derive_best) + 1))
    return build_best, derive_best, eom


def time_sympy(make_system: Callable[[], SympySystem]) -> tuple[float, SympySystem]:
    """One cold run: SymPy's cache is emptied first, so no row profits from expressions of the one before."""
    system = make_system()
    clear_cache()
    t0 = time.perf_counter()
    system.derive()
    return time.perf_counter() - t0, system


def _fmt_s(seconds: float) -> str:
    return f"{seconds * 1e3:10.2f} ms" if seconds < 1 else f"{seconds:10.3f} s "


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-n", type=int, default=12,
                        help="longest planar chain compared with SymPy (default 12)")
    parser.add_argument("--ours-only", type=int, nargs="*", default=[20, 40],
                        help="chain lengths timed with lagrangian alone (default 20 40)")
    parser.add_argument("--repeat", type=int, default=5, help="repeats of our derivation, best kept (default 5)")
    parser.add_argument("--states", type=int, default=5, help="random states checked per system (default 5)")
    parser.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance on q̈ (default 1e-8)")
    parser.add_argument("--seed", type=int, default=2026, help="seed of the random states")
    args = parser.parse_args(argv)

    rows: list[tuple[str, str, str, str, str, str]] = []
    header = ("system", "build", "ours (derive)", "SymPy LagrangesMethod", "ratio", "max rel. diff q̈")
    widths = (16, 13, 13, 21, 9, 15)

    def emit(row: tuple[str, ...]) -> None:
        print("  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in enumerate(zip(row, widths, strict=True))), flush=True)

    print(f"lagrangian {lagrangian.__version__}, symengine {se.__version__}, sympy {sp.__version__}, "
          f"Python {sys.version.split()[0]}")
    emit(header)
    emit(tuple("-" * w for w in widths))
    misses = []
    cases: list[tuple[str, Callable, Callable]] = [("Lagrange top", lagrange_top, sympy_lagrange_top)]
    cases += [(f"planar chain {n}", lambda n=n: planar_chain(n), lambda n=n: sympy_planar_chain(n))
              for n in range(1, args.max_n + 1)]
    for label, ours_model, sympy_system in cases:
        build, ours, eom = time_ours(ours_model, args.repeat)
        theirs, system = time_sympy(sympy_system)
        diff = same_accelerations(eom, system, states=args.states, rtol=args.rtol, seed=args.seed)
        ratio = theirs / ours
        if ratio < TARGET_RATIO:
            misses.append(f"{label}: {ratio:.0f}× < {TARGET_RATIO:.0f}×")
        row = (label, _fmt_s(build), _fmt_s(ours), _fmt_s(theirs), f"{ratio:8.0f}×", f"{diff:.1e}")
        rows.append(row)
        emit(row)
    for n in args.ours_only:
        build, ours, _ = time_ours(lambda n=n: planar_chain(n), max(1, min(args.repeat, 3)))
        if n == 40 and ours >= TARGET_40_LINK_S:
            misses.append(f"planar chain 40: {ours:.2f} s ≥ {TARGET_40_LINK_S} s")
        emit((f"planar chain {n}", _fmt_s(build), _fmt_s(ours), "—", "—", "—"))
    print()
    if misses:
        print("targets missed: " + "; ".join(misses))
        return 1
    print(f"targets met: ≥{TARGET_RATIO:.0f}× faster than LagrangesMethod on every row"
          + (f", 40-link chain < {TARGET_40_LINK_S:.0f} s" if 40 in args.ours_only else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
