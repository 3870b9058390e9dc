"""`zoo.spatial_chain`: closed form for one rod, SymPy's KanesMethod and Pinocchio's ABA for two."""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se
import sympy as sp
from sympy.physics import mechanics as me

import lagrangian
from lagrangian._identity import are_zero
from lagrangian.model import zoo
from lagrangian.model.zoo import spatial_chain


def _ours_qdd(eom, params: dict[str, float]):
    """q̈(q, q̇) from our M and F, evaluated numerically (M q̈ = F solved, never inverted)."""
    n = len(eom.q)
    names = sorted(params)
    fn = se.Lambdify([*eom.q, *eom.qd, *(se.Symbol(p) for p in names)],
                     [e for row in eom.M for e in row] + list(eom.F), backend="lambda")

    def qdd(q, qd):
        out = np.asarray(fn([*q, *qd, *(params[p] for p in names)]), dtype=float).ravel()
        return np.linalg.solve(out[: n * n].reshape(n, n), out[n * n:])

    return qdd


def test_exported_and_structure() -> None:
    assert "spatial_chain" in zoo.__all__
    model = spatial_chain(3)
    assert [c.name for c in model.coordinates] == ["alpha1", "beta1", "alpha2", "beta2", "alpha3", "beta3"]
    assert {p.name for p in model.parameters} == {"g", *(f"{s}{k}" for s in "ml" for k in (1, 2, 3))}
    assert all(p.value is not None for p in model.parameters)
    assert all(c.initial is not None and c.rate is not None for c in model.coordinates)
    # Absolute angles: every rod frame comes from R0 through its own S<k> only.
    parents = {f.name: f.parent for f in model.frames}
    assert all(parents[f"S{k}"] == "R0" and parents[f"R{k}"] == f"S{k}" for k in (1, 2, 3))


@pytest.mark.parametrize("bad", [0, -2, 1.0, False, "2"])
def test_rejects_bad_length(bad: object) -> None:
    with pytest.raises(ValueError):
        spatial_chain(bad)  # type: ignore[arg-type]


def test_one_rod_closed_form() -> None:
    """A thin rod about a fixed end: T = ½ (m l²/3)(α̇² cos²β + β̇²), U = −m g (l/2) cos α cos β."""
    eom = lagrangian.derive(spatial_chain(1))
    a, b = eom.q
    m, l, g = se.Symbol("m1"), se.Symbol("l1"), se.Symbol("g")
    I = m * l**2 / 3
    expected_M = [[I * se.cos(b) ** 2, 0], [0, I]]
    assert all(are_zero([eom.M[i][j] - expected_M[i][j] for i in range(2) for j in range(2)]))
    assert all(are_zero([eom.U + m * g * l / 2 * se.cos(a) * se.cos(b)]))
    assert eom.conservative


def _sympy_kane(n: int):
    """The same chain written independently with sympy.physics.mechanics, in Kane's form."""
    a = me.dynamicsymbols(f"a1:{n + 1}")
    b = me.dynamicsymbols(f"b1:{n + 1}")
    q = [x for pair in zip(a, b, strict=True) for x in pair]
    u = me.dynamicsymbols(f"u1:{2 * n + 1}")
    m, lengths, g = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}"), sp.Symbol("g")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    prev, bodies, loads = O, [], []
    for k in range(n):
        R = N.orientnew(f"S{k}", "Axis", [a[k], N.x])
        R = R.orientnew(f"R{k}", "Axis", [b[k], R.y])
        G = prev.locatenew(f"G{k}", -lengths[k] / 2 * R.z)
        G.v2pt_theory(prev, N, R)
        P = prev.locatenew(f"P{k}", -lengths[k] * R.z)
        P.v2pt_theory(prev, N, R)
        I = m[k] * lengths[k] ** 2 / 12
        bodies.append(me.RigidBody(f"rod{k}", G, R, m[k], (me.inertia(R, I, I, 0), G)))
        loads.append((G, -m[k] * g * N.z))
        prev = P
    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff(me.dynamicsymbols._t) - ui for qi, ui in zip(q, u, strict=True)])
    kane.kanes_equations(bodies, loads)
    qs, us = sp.symbols(f"q0:{2 * n}"), sp.symbols(f"w0:{2 * n}")
    rep = {**dict(zip(q, qs, strict=True)), **dict(zip(u, us, strict=True))}
    fn = sp.lambdify([qs, us, [g, *m, *lengths]], [kane.mass_matrix.xreplace(rep), kane.forcing.xreplace(rep)])
    return fn


@pytest.mark.slow
def test_two_rods_agree_with_sympy_kane() -> None:
    n = 2
    eom = lagrangian.derive(spatial_chain(n))
    rng = np.random.default_rng(7)
    params = {name: float(rng.uniform(0.5, 1.5)) for name in ("g", "m1", "m2", "l1", "l2")}
    ours = _ours_qdd(eom, params)
    theirs = _sympy_kane(n)
    for _ in range(3):
        q = rng.uniform(-1.2, 1.2, 2 * n)
        qd = rng.uniform(-2.0, 2.0, 2 * n)
        M, F = theirs(q, qd, [params[k] for k in ("g", "m1", "m2", "l1", "l2")])
        expected = np.linalg.solve(np.asarray(M, dtype=float), np.asarray(F, dtype=float).ravel())
        np.testing.assert_allclose(ours(q, qd), expected, rtol=1e-10, atol=1e-12)


def test_two_rods_agree_with_pinocchio_aba() -> None:
    """Pinocchio's robot of universal joints (RX then RY, relative angles) moves as our chain.

    Its state is mapped to ours through its own kinematics: rod k's direction
    d = −R_k z = (−sin β_k, sin α_k cos β_k, −cos α_k cos β_k) in our absolute angles,
    ḋ = ω × d and d̈ = ω̇ × d + ω × (ω × d).
    """
    pin = pytest.importorskip("pinocchio")
    n = 2
    eom = lagrangian.derive(spatial_chain(n))
    rng = np.random.default_rng(11)
    params = {name: float(rng.uniform(0.5, 1.5)) for name in ("m1", "m2", "l1", "l2")} | {"g": 9.81}
    model = pin.Model()
    j, rods = 0, []
    for k in (1, 2):
        where = pin.SE3(np.eye(3), np.array([0.0, 0.0, -params["l1"]])) if k == 2 else pin.SE3.Identity()
        j = model.addJoint(j, pin.JointModelRX(), where, f"x{k}")
        j = model.addJoint(j, pin.JointModelRY(), pin.SE3.Identity(), f"y{k}")
        m, length = params[f"m{k}"], params[f"l{k}"]
        I = m * length**2 / 12
        model.appendBodyToJoint(j, pin.Inertia(m, np.array([0.0, 0.0, -length / 2]), np.diag([I, I, 0.0])),
                                pin.SE3.Identity())
        rods.append(j)
    model.gravity.linear = np.array([0.0, 0.0, -params["g"]])
    data = model.createData()
    frame = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    ours = _ours_qdd(eom, params)

    def to_ours(q, v, a):
        pin.forwardKinematics(model, data, q, v, a)
        angles, rates, accelerations = [], [], []
        for jid in rods:
            d = data.oMi[jid].rotation @ np.array([0.0, 0.0, -1.0])
            w = pin.getVelocity(model, data, jid, frame).angular
            wd = pin.getAcceleration(model, data, jid, frame).angular
            dd, ddd = np.cross(w, d), np.cross(wd, d) + np.cross(w, np.cross(w, d))
            al, be = np.arctan2(d[1], -d[2]), -np.arcsin(d[0])
            sa, ca, sb, cb = np.sin(al), np.cos(al), np.sin(be), np.cos(be)
            da, db = np.array([0.0, ca * cb, sa * cb]), np.array([-cb, -sa * sb, ca * sb])
            ad, bd = dd @ da / cb**2, dd @ db
            d_aa, d_ab, d_bb = (np.array([0.0, -sa * cb, ca * cb]), np.array([0.0, -ca * sb, -sa * sb]),
                                np.array([sb, -sa * cb, ca * cb]))
            curvature = d_aa * ad * ad + 2 * d_ab * ad * bd + d_bb * bd * bd
            angles += [al, be]
            rates += [ad, bd]
            accelerations += [(ddd - curvature) @ da / cb**2, (ddd - curvature) @ db]
        return np.array(angles), np.array(rates), np.array(accelerations)

    for _ in range(3):
        q = rng.uniform(-0.6, 0.6, 2 * n)
        v = rng.uniform(-1.5, 1.5, 2 * n)
        a = pin.aba(model, data, q, v, np.zeros(2 * n))
        qo, vo, ao = to_ours(q, v, a)
        np.testing.assert_allclose(ours(qo, vo), ao, rtol=1e-9, atol=1e-10)
