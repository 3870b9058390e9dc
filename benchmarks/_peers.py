"""The peers of the numeric benchmarks, each built for the same systems as ours.

* SymPy: the Lagrange top, the planar chain (absolute angles, point masses) and the spatial
  chain (absolute direction angles, thin rods) described with ``sympy.physics.mechanics``
  and put in Kane's form M(q) u̇ = F(q, u) with u = q̇ (`KanesMethod`);
* `sympy.lambdify` of those M and F, q̈ by ``numpy.linalg.solve``;
* PyDy's ``generate_ode_function`` of the same M and F (Cython, else lambdify; with and
  without its symbolic LU solve);
* Pinocchio's ABA on the same mechanism as a robot (revolute joints, relative angles),
  with the maps between its coordinates and ours.

Every peer is checked against our q̈ before it is timed (`check`).  The optional peers
(PyDy, Pinocchio) are imported lazily; `available()` says which could be loaded and why not.
"""

from __future__ import annotations

import importlib
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from sympy.physics import mechanics as me

__all__ = ["SympySystem", "sympy_system", "lambdify_peer", "pydy_peer", "PinocchioPeer", "pinocchio_peer",
           "available", "random_parameters", "random_states", "universal_to_ours"]


def available(module: str) -> tuple[object | None, str]:
    """(module, "") when it can be imported, else (None, why)."""
    try:
        return importlib.import_module(module), ""
    except Exception as exc:  # noqa: BLE001 - any failure to load means "skip this peer"
        return None, f"{type(exc).__name__}: {exc}"


# -- the systems in sympy.physics.mechanics ------------------------------------------------------
@dataclass
class SympySystem:
    """M(q) u̇ = F(q, u) from `KanesMethod`, with u_i = q̇_i, and the symbols they use."""

    q: list
    u: list
    constants: list  # sympy Symbols, named as our parameters
    M: sp.Matrix
    F: sp.Matrix
    seconds: float = 0.0  # time of KanesMethod + kanes_equations
    extra: dict = field(default_factory=dict)


def _kane(N, q, u, bodies, loads) -> tuple[sp.Matrix, sp.Matrix]:
    kd = [qi.diff(me.dynamicsymbols._t) - ui for qi, ui in zip(q, u, strict=True)]
    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    kane.kanes_equations(bodies, loads)
    return kane.mass_matrix, kane.forcing


def _top():
    psi, theta, phi = q = me.dynamicsymbols("psi theta phi")
    u = me.dynamicsymbols("u1:4")
    m, g, a, A, C = consts = sp.symbols("m g a A C")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Body", [psi, theta, phi], "ZXZ")
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", a * B.z)
    G.v2pt_theory(O, N, B)
    top = me.RigidBody("S", G, B, m, (me.inertia(B, A, A, C), O))
    return N, list(q), list(u), list(consts), [top], [(G, -m * g * N.z)]


def _planar(n: int):
    q = list(me.dynamicsymbols(f"theta1:{n + 1}"))
    u = list(me.dynamicsymbols(f"w1:{n + 1}"))
    m = sp.symbols(f"m1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    prev, particles, loads = O, [], []
    for k in range(n):
        Rk = N.orientnew(f"R{k + 1}", "Axis", [q[k], N.z])
        P = prev.locatenew(f"P{k + 1}", lengths[k] * Rk.x)
        P.v2pt_theory(prev, N, Rk)
        particles.append(me.Particle(f"P{k + 1}", P, m[k]))
        loads.append((P, m[k] * g * N.x))  # x0 points down
        prev = P
    return N, q, u, [g, *m, *lengths], particles, loads


def _spatial(n: int):
    a = list(me.dynamicsymbols(f"alpha1:{n + 1}"))
    b = list(me.dynamicsymbols(f"beta1:{n + 1}"))
    q = [x for pair in zip(a, b, strict=True) for x in pair]
    u = list(me.dynamicsymbols(f"u1:{2 * n + 1}"))
    m = sp.symbols(f"m1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    prev, bodies, loads = O, [], []
    for k in range(n):
        S = N.orientnew(f"S{k + 1}", "Axis", [a[k], N.x])
        R = S.orientnew(f"R{k + 1}", "Axis", [b[k], S.y])
        G = prev.locatenew(f"G{k + 1}", -lengths[k] / 2 * R.z)
        G.v2pt_theory(prev, N, R)
        P = prev.locatenew(f"P{k + 1}", -lengths[k] * R.z)
        P.v2pt_theory(prev, N, R)
        rod = m[k] * lengths[k] ** 2 / 12
        bodies.append(me.RigidBody(f"rod{k + 1}", G, R, m[k], (me.inertia(R, rod, rod, 0), G)))
        loads.append((G, -m[k] * g * N.z))
        prev = P
    return N, q, u, [g, *m, *lengths], bodies, loads


def sympy_system(kind: str, n: int = 0) -> SympySystem:
    """``kind`` = "top", "planar" or "spatial" (n links), in Kane's form; KanesMethod timed."""
    import time

    N, q, u, consts, bodies, loads = {"top": lambda: _top(), "planar": lambda: _planar(n),
                                      "spatial": lambda: _spatial(n)}[kind]()
    t0 = time.perf_counter()
    M, F = _kane(N, q, u, bodies, loads)
    return SympySystem(q, u, consts, M, F, time.perf_counter() - t0)


# -- sympy.lambdify ------------------------------------------------------------------------------
def lambdify_peer(system: SympySystem, p: np.ndarray):
    """(single(q, u) -> q̈, batch(Q, U) -> Q̈): lambdified M and F, ``numpy.linalg.solve``.

    ``p`` holds the constants' values in ``system.constants`` order.
    """
    n = len(system.q)
    qs, us = sp.symbols(f"q0:{n}"), sp.symbols(f"u0:{n}")
    t = me.dynamicsymbols._t
    rep_d = {qi.diff(t): ui for qi, ui in zip(system.q, us, strict=True)}
    rep = {**dict(zip(system.q, qs, strict=True)), **dict(zip(system.u, us, strict=True))}
    exprs = [e.xreplace(rep_d).xreplace(rep) for e in (system.M, system.F)]
    fn = sp.lambdify([qs, us, system.constants], exprs, modules="numpy", cse=True)
    # For a batch: the entries as a flat list (a Matrix of arrays and scalars cannot be built).
    flat = sp.lambdify([qs, us, system.constants], [*exprs[0], *exprs[1]], modules="numpy", cse=True)
    pv = list(p)

    def single(q: np.ndarray, u: np.ndarray) -> np.ndarray:
        M, F = fn(q, u, pv)
        return np.linalg.solve(M, F.ravel())

    def batch(Q: np.ndarray, U: np.ndarray) -> np.ndarray:
        # Each entry of M and F broadcasts over the N states; constant entries are filled.
        count = len(Q)
        entries = flat(Q.T, U.T, pv)
        Mb = np.empty((count, n, n))
        Fb = np.empty((count, n))
        for i in range(n):
            Fb[:, i] = entries[n * n + i]
            for j in range(n):
                Mb[:, i, j] = entries[i * n + j]
        return np.linalg.solve(Mb, Fb[..., None])[..., 0]

    return single, batch


# -- PyDy ------------------------------------------------------------------------------------------
def pydy_peer(system: SympySystem, p: np.ndarray, *, generator: str, symbolic_lu: bool = False,
              tmp_dir: str | None = None):
    """PyDy's generated right-hand side, as single(q, u) -> q̈; raises when it cannot be built.

    ``generator`` is "cython" or "lambdify"; ``symbolic_lu`` asks PyDy to solve M u̇ = F
    symbolically by LU inside the generated code (``linear_sys_solver="sympy"``, Cython only).
    """
    from pydy.codegen.ode_function_generators import generate_ode_function

    n = len(system.q)
    kw: dict = {}
    if generator == "cython":  # its build files go to tmp_dir (the caller removes it), not the cwd
        kw["tmp_dir"] = tempfile.mkdtemp(prefix="pydy_", dir=tmp_dir)
    if symbolic_lu:
        kw["linear_sys_solver"] = "sympy"
    rhs = generate_ode_function(system.F, system.q, system.u, system.constants, mass_matrix=system.M,
                                coordinate_derivatives=sp.Matrix(system.u), generator=generator,
                                constants_arg_type="array", **kw)
    x = np.empty(2 * n)
    pv = np.ascontiguousarray(p, dtype=float)

    def single(q: np.ndarray, u: np.ndarray) -> np.ndarray:
        x[:n] = q
        x[n:] = u
        return rhs(x, 0.0, pv)[n:]

    single.rhs = rhs  # type: ignore[attr-defined]
    return single


# -- Pinocchio -----------------------------------------------------------------------------------
@dataclass
class PinocchioPeer:
    """A Pinocchio model of one of our systems, and the maps between the two coordinate sets.

    ``to_ours(q, v)`` gives our (q, q̇) of Pinocchio's state; ``qdd_to_ours(q, v, a)`` our q̈
    of Pinocchio's joint accelerations at that state.
    """

    model: object
    data: object
    to_ours: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]
    qdd_to_ours: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]

    def aba(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> np.ndarray:
        import pinocchio as pin

        return pin.aba(self.model, self.data, q, v, tau)


def _identity_maps():
    return (lambda q, v: (q.copy(), v.copy())), (lambda q, v, a: a.copy())


def pinocchio_peer(kind: str, n: int, params: dict[str, float]) -> PinocchioPeer:
    """Pinocchio's model of our ``kind`` system ("top", "planar", "spatial") with ``params``."""
    import pinocchio as pin

    model = pin.Model()
    g = params["g"]
    if kind == "top":
        # Euler angles ZXZ are three revolute joints in series: RZ (psi), RX (theta), RZ (phi).
        j = 0
        for joint, name in ((pin.JointModelRZ(), "psi"), (pin.JointModelRX(), "theta"), (pin.JointModelRZ(), "phi")):
            j = model.addJoint(j, joint, pin.SE3.Identity(), name)
        m, a, A, C = (params[k] for k in ("m", "a", "A", "C"))
        inertia_G = np.diag([A - m * a * a, A - m * a * a, C])  # Huygens: Π_O = Π_G + m a² (x x + y y)
        model.appendBodyToJoint(j, pin.Inertia(m, np.array([0.0, 0.0, a]), inertia_G), pin.SE3.Identity())
        model.gravity.linear = np.array([0.0, 0.0, -g])
        to_ours, qdd_to_ours = _identity_maps()
    elif kind == "planar":
        # Relative angles phi_k = theta_k - theta_{k-1}, joints about z, point masses at the tips.
        j = 0
        for k in range(1, n + 1):
            where = pin.SE3(np.eye(3), np.array([params[f"l{k - 1}"], 0.0, 0.0])) if k > 1 else pin.SE3.Identity()
            j = model.addJoint(j, pin.JointModelRZ(), where, f"joint{k}")
            model.appendBodyToJoint(j, pin.Inertia(params[f"m{k}"], np.array([params[f"l{k}"], 0.0, 0.0]),
                                                   np.zeros((3, 3))), pin.SE3.Identity())
        model.gravity.linear = np.array([g, 0.0, 0.0])  # x0 points down

        def to_ours(q, v):
            return np.cumsum(q), np.cumsum(v)

        def qdd_to_ours(q, v, a):
            return np.cumsum(a)
    elif kind == "spatial":
        model, to_ours, qdd_to_ours = _pin_spatial(n, params)
    else:
        raise ValueError(kind)
    return PinocchioPeer(model, model.createData(), to_ours, qdd_to_ours)


def _direction_angles(d, dd, ddd):
    """Our absolute angles (α, β), rates and accelerations of a rod direction d = R0-components of −Rk.z.

    d = (−sin β, sin α cos β, −cos α cos β); the two partial derivatives are orthogonal,
    of norms |cos β| and 1, so rates and accelerations are projections.
    """
    b = -np.arcsin(np.clip(d[0], -1.0, 1.0))
    a = np.arctan2(d[1], -d[2])
    sa, ca, sb, cb = np.sin(a), np.cos(a), np.sin(b), np.cos(b)
    da = np.array([0.0, ca * cb, sa * cb])
    db = np.array([-cb, -sa * sb, ca * sb])
    ad = dd @ da / cb**2
    bd = dd @ db
    daa = np.array([0.0, -sa * cb, ca * cb])
    dab = np.array([0.0, -ca * sb, -sa * sb])
    dbb = np.array([sb, -sa * cb, ca * cb])
    rest = ddd - (daa * ad * ad + 2 * dab * ad * bd + dbb * bd * bd)
    return (a, b), (ad, bd), (rest @ da / cb**2, rest @ db)


def _rx(t: float) -> np.ndarray:
    c, s = np.cos(t), np.sin(t)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _ry(t: float) -> np.ndarray:
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def universal_to_ours(q: np.ndarray, v: np.ndarray, a: np.ndarray | None = None):
    """Our (q, q̇, q̈) of a chain of universal joints (RX then RY, relative angles) at (q, v, a).

    Rod k's rotation is R_k = R_{k−1} Rx(α_k) Ry(β_k); its angular velocity and acceleration
    are summed along the chain, and its direction d_k = −R_k z with ḋ = ω × d,
    d̈ = ω̇ × d + ω × (ω × d) gives our absolute angles (`_direction_angles`).
    """
    a = np.zeros_like(v) if a is None else a
    R, w, wd = np.eye(3), np.zeros(3), np.zeros(3)
    x, y, mz = np.eye(3)[0], np.eye(3)[1], np.array([0.0, 0.0, -1.0])
    out_q, out_v, out_a = [], [], []
    for k in range(len(q) // 2):
        al, be = q[2 * k], q[2 * k + 1]
        ald, bed = v[2 * k], v[2 * k + 1]
        aldd, bedd = a[2 * k], a[2 * k + 1]
        ax1 = R @ x  # joint axes in R0
        w_s = w + ald * ax1
        wd_s = wd + aldd * ax1 + np.cross(w, ald * ax1)
        Rs = R @ _rx(al)
        ax2 = Rs @ y
        w = w_s + bed * ax2
        wd = wd_s + bedd * ax2 + np.cross(w_s, bed * ax2)
        R = Rs @ _ry(be)
        d = R @ mz
        dd, ddd = np.cross(w, d), np.cross(wd, d) + np.cross(w, np.cross(w, d))
        (qa, qb), (va, vb), (aa, ab) = _direction_angles(d, dd, ddd)
        out_q += [qa, qb]
        out_v += [va, vb]
        out_a += [aa, ab]
    return np.array(out_q), np.array(out_v), np.array(out_a)


def _pin_spatial(n: int, params: dict[str, float]):
    """Thin rods on universal joints (RX then RY, relative angles): the same T and U as ours."""
    import pinocchio as pin

    model = pin.Model()
    j = 0
    for k in range(1, n + 1):
        where = pin.SE3(np.eye(3), np.array([0.0, 0.0, -params[f"l{k - 1}"]])) if k > 1 else pin.SE3.Identity()
        j = model.addJoint(j, pin.JointModelRX(), where, f"joint{k}x")
        j = model.addJoint(j, pin.JointModelRY(), pin.SE3.Identity(), f"joint{k}y")
        m, length = params[f"m{k}"], params[f"l{k}"]
        rod = m * length**2 / 12
        model.appendBodyToJoint(j, pin.Inertia(m, np.array([0.0, 0.0, -length / 2]), np.diag([rod, rod, 0.0])),
                                pin.SE3.Identity())
    model.gravity.linear = np.array([0.0, 0.0, -params["g"]])

    def to_ours(q, v):
        return universal_to_ours(q, v)[:2]

    def qdd_to_ours(q, v, a):
        return universal_to_ours(q, v, a)[2]

    return model, to_ours, qdd_to_ours


# -- random parameters and states ---------------------------------------------------------------------
def random_parameters(kind: str, names: tuple[str, ...], rng: np.random.Generator) -> dict[str, float]:
    """Parameter values drawn in [0.5, 1.5] (the top's: A > m a² so that Π_G is positive)."""
    values = {name: float(rng.uniform(0.5, 1.5)) for name in names}
    if kind == "top":
        values.update(m=float(rng.uniform(0.5, 1.5)), a=float(rng.uniform(0.05, 0.2)), g=9.81)
        values["A"] = values["m"] * values["a"] ** 2 + float(rng.uniform(0.005, 0.02))
        values["C"] = float(rng.uniform(0.005, 0.02))
    else:
        values["g"] = 9.81
    return values


def random_states(kind: str, n_coords: int, count: int, rng: np.random.Generator):
    """``count`` states: (Q, U) in *Pinocchio's* coordinates and (Qo, Uo) in ours, the same states.

    The top's θ stays in [0.3, 2.8] (Euler angles are singular at 0 and π) and φ̇ is large
    (a spinning top).  The planar chain's relative angles are anywhere.  The spatial chain's
    joint angles are in [−0.6, 0.6], and a state is kept only when every rod has |β_k| < 1.2
    in our angles (|cos β_k| > 0.36): regular in both coordinate sets.
    """
    if kind == "top":
        Q = np.column_stack([rng.uniform(-np.pi, np.pi, count), rng.uniform(0.3, 2.8, count),
                             rng.uniform(-np.pi, np.pi, count)])
        U = rng.uniform(-2, 2, (count, 3))
        U[:, 2] *= 20
        return Q, U, Q.copy(), U.copy()
    if kind == "planar":
        Q = rng.uniform(-np.pi, np.pi, (count, n_coords))
        U = rng.uniform(-1.5, 1.5, (count, n_coords))
        return Q, U, np.cumsum(Q, axis=1), np.cumsum(U, axis=1)
    rows: list = []
    while len(rows) < count:
        q = rng.uniform(-0.6, 0.6, n_coords)
        v = rng.uniform(-1.5, 1.5, n_coords)
        qo, vo, _ = universal_to_ours(q, v)
        if np.all(np.abs(qo[1::2]) < 1.2):
            rows.append((q, v, qo, vo))
    Q, U, Qo, Uo = (np.array([r[i] for r in rows]) for i in range(4))
    return Q, U, Qo, Uo


