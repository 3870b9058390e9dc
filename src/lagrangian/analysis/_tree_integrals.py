"""First integrals of a kinematic tree from its recursive form, without the course's derivation.

`simulate` monitors the first integrals of the model.  For a tree that takes the recursive route
(`dynamics._recursive`: four moving rotations in series or more) `first_integrals` would first
make the whole course derivation, seconds to minutes for a robot, while the recursive form
already holds what the integrals need, over its named intermediates:

* the momenta p_i = ∂T/∂q̇_i = Σ_j M_ij q̇_j (T homogeneous quadratic in q̇ for a tree with no
  time in it), and Hamilton's right side g_i = ∂T/∂q_i − ∂U/∂q_i + Q_i (``dL_dq``), so that the
  Lagrange equations read ṗ_i = g_i;
* hence p_i is constant when g_i ≡ 0 (q_i cyclic, no effort working on it) — the test of
  `first_integrals`, made here by evaluating g_i at random states through the intermediates
  (`RecursiveForm.evaluate`);
* a rigid translation or rotation of the whole system with generator ξ(q) (`_noether`) gives
  J = Σ_i p_i ξ_i, and dJ/dt = Σ_i g_i ξ_i + p_i ξ̇_i along every motion: J is constant when that
  vanishes identically (E. Noether; the same integrals `first_integrals` finds from T, U, Q);
* the energy T + U when every load derives from a potential U(q) — or does no work while the
  inputs that drive it are off (a motor's torque τ = 0, the simulation's default regime).

The names, kinds and reasons are those of `first_integrals`, so `derive` and `simulate` agree.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ..model.spec import GALILEAN_FRAME
from ._integrals import FirstIntegral, input_regime
from ._noether import _generator, _tidy

__all__ = ["tree_integrals"]

#: Random states at which an identity (g_i ≡ 0, dJ/dt ≡ 0) is tested.
STATES = 5
#: Relative size (to the sizes at the state) below which a value counts as zero.
ZERO_RTOL = 1e-9
#: Intermediates beyond which the tests are not made (the energy alone is monitored): each state costs
#: one pass over them.
MAX_INTERMEDIATES = 20000
#: Coordinates beyond which rigid motions are not sought (a fixed-base robot has none beyond the
#: rotation of its first joint, whose momentum is already found).
NOETHER_MAX = 6


def _states(eom: EquationsOfMotion, count: int, off: Sequence[str] = ()) -> list[dict[se.Basic, float]]:
    """Random states (q, q̇ in [−1.3, 1.3], t) and random parameters in [0.3, 1.7], the same at every state:
    an identity holds whatever the values, as `first_integrals` proves it (a motor's torque τ is not 0),
    except the inputs ``off``, which are 0."""
    rng = random.Random(20240521)
    kin = eom.kinematics
    params = {p.symbol: rng.uniform(0.3, 1.7) for p in eom.model.parameters}
    params.update({se.Symbol(u): 0.0 for u in off})
    out = []
    for _ in range(count):
        state = {s: rng.uniform(-1.3, 1.3) for s in (*kin.q, *kin.qd)}
        state[kin.t] = rng.uniform(0.0, 1.0)
        out.append({**params, **state})
    return out


def _evaluate(eom: EquationsOfMotion, exprs: Sequence[se.Basic], states: Sequence[dict[se.Basic, float]]
              ) -> np.ndarray:
    """``exprs`` (over the recursive form's intermediates) at each of ``states``, one row per state: each
    intermediate in turn, each substitution given only the symbols it holds (a map of thousands per call
    would cost quadratically).  The intermediates needed are found once for all the states."""
    rec = eom.recursive
    needed = rec.needed(exprs)  # type: ignore[union-attr]
    rows = []
    for state in states:
        known = {s: se.RealDouble(float(v)) for s, v in state.items()}
        for s, e in needed:
            known[s] = se.RealDouble(float(e.xreplace({x: known[x] for x in e.free_symbols})))
        rows.append([float(e.xreplace({x: known[x] for x in e.free_symbols})) for e in exprs])
    return np.array(rows)


def tree_integrals(eom: EquationsOfMotion, regime: Mapping[str, str] | None = None) -> tuple[FirstIntegral, ...]:
    """The first integrals of ``eom``'s recursive form, over its intermediates (for the generated code).

    The momenta of the cyclic coordinates, the energy and the Noether integrals; () without a
    recursive form.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    regime : mapping of str to str, optional
        What each input does (`first_integrals`): ``"off"`` (the default) sets it to 0, so a motor
        that does not push leaves its joint's momentum and the energy integrals; an integral that
        holds only so says it in its reason, as `first_integrals` does.

    Returns
    -------
    tuple of FirstIntegral
        Expressions in the intermediates' names.
    """
    rec = eom.recursive
    if rec is None:
        return ()
    regime = input_regime(eom, regime)
    off = [u for u, what in regime.items() if what == "off"]
    varying = {se.Symbol(u) for u, what in regime.items() if what == "varying"}
    suffix = " (with the inputs off: " + ", ".join(f"{u} = 0" for u in off) + ")"
    kin = eom.kinematics
    n = kin.n
    p = [se.Add(*[rec.M[i][j] * kin.qd[j] for j in range(n) if rec.M[i][j] != 0]) for i in range(n)]
    states = _states(eom, STATES, off)
    G = P = G_on = None
    if len(rec.intermediates) <= MAX_INTERMEDIATES:
        try:
            G = _evaluate(eom, rec.dL_dq, states)
            P = _evaluate(eom, p, states)
            # The same with the inputs at values: which momenta hold only because the inputs are off.
            G_on = _evaluate(eom, rec.dL_dq, _states(eom, STATES)) if off else G
        except (RuntimeError, TypeError, ValueError, ZeroDivisionError):  # a state outside the domain: E only
            G = P = G_on = None
    usable = (G is not None and P is not None and G_on is not None
              and bool(np.all(np.isfinite(G)) and np.all(np.isfinite(P)) and np.all(np.isfinite(G_on))))
    out: list[FirstIntegral] = []
    if usable and G is not None and P is not None and G_on is not None:
        scale = np.maximum(1.0, np.abs(G).max(axis=1) + np.abs(P).max(axis=1))
        for i, c in enumerate(eom.model.coordinates):
            if np.all(np.abs(G[:, i]) <= ZERO_RTOL * scale):
                held = bool(np.all(np.abs(G_on[:, i]) <= ZERO_RTOL * np.maximum(1.0, np.abs(G_on).max(axis=1)
                                                                                 + np.abs(P).max(axis=1))))
                out.append(FirstIntegral(c.momentum or f"p_{c.name}", "momentum", p[i],
                                         f"{c.name} is cyclic: ∂L/∂{c.name} = 0 and Q_{c.name}(nc) = 0"
                                         + ("" if held else suffix), c.name))
    constant = [u for u, what in regime.items() if what == "constant"]
    extra = se.Integer(0) if rec.conservative else _energy_potential(eom, off, constant)
    if extra is not None and kin.t not in (rec.U + extra).free_symbols \
            and not ((rec.T.free_symbols | rec.U.free_symbols | extra.free_symbols) & varying):
        out.append(FirstIntegral("E", "energy", rec.T + rec.U + extra,
                                 "energy integral T + U = cste: a kinematic tree with no time in it, every load "
                                 "derives from a potential"
                                 + ("" if rec.conservative else _energy_note(off, constant))))
    if usable and n <= NOETHER_MAX and G is not None and P is not None:
        out += _symmetries(eom, p, G, P, states, out)
    return tuple(out)


def _energy_note(off: Sequence[str], held: Sequence[str]) -> str:
    """What the energy integral of a tree with inputs relies on, as `first_integrals` says it."""
    parts = ([f"with the inputs off: {', '.join(f'{u} = 0' for u in off)}"] if off else []) + \
        ([f"{', '.join(held)} held constant, deriving from −u q"] if held else [])
    return f" ({'; '.join(parts)})" if parts else ""


def _energy_potential(eom: EquationsOfMotion, off: Sequence[str], held: Sequence[str]) -> se.Basic | None:
    """What the energy integral adds to T + U_P when the loads that do not derive from U_P do no work once
    the inputs ``off`` are 0 — or derive from a potential while the inputs ``held`` are constant (−τ q of a
    constant motor torque, `LoadForces.held`, or of a torque whose value is a parameter); None when some
    load works all the same (a joint damper, a torque varying with the state or in time)."""
    from ..dynamics import generalized_forces
    from ..model.spec import JointDamper, Torque

    zero = {se.Symbol(u): se.Integer(0) for u in off}
    constant = {se.Symbol(u) for u in held}
    inputs = {p.symbol for p in eom.model.parameters if p.input}

    def potential_of(f) -> se.Basic | None:
        if all(q.xreplace(zero) == 0 for q in f.Q):
            return se.Integer(0)  # it vanishes with the inputs off
        if f.potential is not None:
            return f.potential
        if f.held is not None and {s for q in f.Q for s in q.free_symbols} & inputs <= constant:
            return f.held
        return None

    rec = eom.recursive
    extra: list[se.Basic] = []
    for f in rec.loads if rec is not None else ():
        if f.potential is None:  # the other loads' potentials are in rec.U already
            u = potential_of(f)
            if u is None:
                return None
            extra.append(u)
    torques = []
    for k, load in enumerate(eom.model.loads):
        if isinstance(load, JointDamper):
            return None
        if isinstance(load, Torque) and not load.torque.subs(zero).is_zero():
            torques.append(k)
    if torques:  # the couples of the recursion, which rec.U never holds: their Q by virtual power
        for f in generalized_forces(eom.kinematics, only=torques):
            u = potential_of(f)
            if u is None:
                return None
            extra.append(u)
    return se.Add(*extra)


def _rigid_motions(eom: EquationsOfMotion, states: Sequence[dict]):
    """(kind, axis, ξ at the states, ξ̇ at the states) of each rigid translation or rotation the coordinates
    can follow, ξ solved numerically from Σ_i ∂V(P)/∂q̇_i ξ_i = e (or e ∧ OP), Σ_i ∂Ω(S)/∂q̇_i ξ_i = 0 (or e)
    (`_noether`), ξ̇ = Σ_j ∂ξ/∂q_j q̇_j by a central difference along q̇."""
    kin, model = eom.kinematics, eom.model
    express = kin.frames.express
    n = kin.n
    centres = [b.name for b in model.bodies] + [p.name for p in model.particles]
    flat = []
    for name in centres:
        flat += [x for v in kin.partial_velocities(name) for x in express(v, GALILEAN_FRAME)]
        flat += list(express(kin.position(name), GALILEAN_FRAME))
    for body in model.bodies:
        flat += [x for w in kin.partial_omegas(body.frame) for x in express(w, GALILEAN_FRAME)]
    params = [p.symbol for p in model.parameters]
    fn = se.Lambdify([*kin.q, *params, kin.t], flat)
    c, b = len(centres), len(model.bodies)

    def system(q: np.ndarray, state: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        v = np.asarray(fn(np.array([*q, *(state[s] for s in params), state[kin.t]], dtype=float)), dtype=float)
        k = 0
        V, OP, W = [], [], []
        for _ in range(c):
            V.append(v[k:k + 3 * n].reshape(n, 3).T)
            OP.append(v[k + 3 * n:k + 3 * n + 3])
            k += 3 * n + 3
        for _ in range(b):
            W.append(v[k:k + 3 * n].reshape(n, 3).T)
            k += 3 * n
        return np.array(V), np.array(OP), np.array(W)

    def xi(q: np.ndarray, state: dict, kind: str, axis: int) -> tuple[np.ndarray, float]:
        V, OP, W = system(q, state)
        e = np.eye(3)[axis]
        rows = [V.reshape(-1, n), W.reshape(-1, n)]
        rhs = [np.tile(e, c) if kind == "translation" else np.cross(e, OP).ravel(),
               np.zeros(3 * b) if kind == "translation" else np.tile(e, b)]
        R, r = np.vstack(rows), np.concatenate(rhs)
        x, *_ = np.linalg.lstsq(R, r, rcond=None)
        return x, float(np.abs(R @ x - r).max(initial=0.0)) / max(1.0, float(np.abs(R).max(initial=0.0)))

    for kind in ("translation", "rotation"):
        for axis in range(3):
            X, Xd = [], []
            for state in states:
                q = np.array([state[s] for s in kin.q])
                qd = np.array([state[s] for s in kin.qd])
                x, residual = xi(q, state, kind, axis)
                h = 1e-6
                xp, rp = xi(q + h * qd, state, kind, axis)
                xm, rm = xi(q - h * qd, state, kind, axis)
                if max(residual, rp, rm) > 1e-9 or not np.all(np.isfinite(x)):
                    break
                X.append(x)
                Xd.append((xp - xm) / (2 * h))
            else:
                yield kind, axis, np.array(X), np.array(Xd)


def _symmetries(eom: EquationsOfMotion, p: Sequence[se.Basic], G: np.ndarray, P: np.ndarray,
                states: Sequence[dict], found: Sequence[FirstIntegral]) -> list[FirstIntegral]:
    """J = Σ p_i ξ_i for each rigid translation or rotation with dJ/dt = Σ g_i ξ_i + p_i ξ̇_i ≡ 0, new; the
    test is numeric, and ξ is solved symbolically (`_noether._generator`) only for the integrals kept."""
    model = eom.model
    if model.reference is not None and not model.reference.is_galilean_frame:
        return []
    named = next((f.axes for f in model.frames if f.name == GALILEAN_FRAME and getattr(f, "axes", None)), None)
    axes = tuple(named) if named else ("x0", "y0", "z0")
    values = [P[:, list(p).index(fi.expression)] if fi.kind == "momentum" else
              _evaluate(eom, [fi.expression], states)[:, 0] for fi in found]
    out = []
    for kind, axis, X, Xd in _rigid_motions(eom, states):
        if not np.any(np.abs(X) > 1e-12):
            continue
        rate = np.einsum("ki,ki->k", G, X) + np.einsum("ki,ki->k", P, Xd)
        size = np.abs(G * X).sum(axis=1) + np.abs(P * Xd).sum(axis=1) + 1.0
        if np.any(np.abs(rate) > 1e-6 * size):  # ξ̇ by a central difference: 1e-6, not the rounding
            continue
        J = np.einsum("ki,ki->k", P, X)
        V = np.array([*values, J]).T
        tol = 1e-9 * max(1.0, float(np.abs(V).max()))
        if np.linalg.matrix_rank(V, tol=tol) <= (np.linalg.matrix_rank(V[:, :-1], tol=tol) if values else 0):
            continue  # a combination of those found (K of the top is σ_O·z0)
        generator = _generator(eom, kind, axis)
        if generator is None:  # pragma: no cover - found numerically above
            continue
        values.append(J)
        xi = [_tidy(x) for x in generator[0]]
        a = axes[axis]
        if kind == "translation":
            name, why = f"P_{a}", (f"Noether: L is invariant under a translation along {a} and no other effort "
                                   f"works on it, so the momentum P(Σ/R0)·{a} = Σ p_i ξ_i is constant")
        else:
            name, why = f"sigma_O_{a}", (f"Noether: L is invariant under a rotation about O{a} and no other "
                                         f"effort works on it, so the angular momentum σ_O(Σ/R0)·{a} = Σ p_i ξ_i "
                                         "is constant")
        out.append(FirstIntegral(name, "symmetry", se.Add(*[pi * x for pi, x in zip(p, xi, strict=True) if x != 0]), why))
    return out
