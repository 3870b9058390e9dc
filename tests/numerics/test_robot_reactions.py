"""A robot's reaction columns: the ground's wrench on the arm, cheap path (R0 components, no
symbolic check) equal to the display path, and to Pinocchio's transmitted force f[1]."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import symengine as se
from urdf_robots import SPATIAL_ARM, Peer

import lagrangian
from lagrangian.analysis import reactions
from lagrangian.model import Vector
from lagrangian.model.urdf import UrdfNote, parse_urdf
from lagrangian.model.zoo import serial_arm
from lagrangian.numerics import reaction_columns_along


def _arm() -> lagrangian.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        return parse_urdf(SPATIAL_ARM, source="arm.urdf", damping=False)


def test_r0_components_are_the_shortest_frames_components_turned_to_r0():
    eom = lagrangian.derive(serial_arm(3))
    kin = eom.kinematics
    fast, shown = reactions(eom, display=False), reactions(eom)
    assert [r.name for r in fast] == [r.name for r in shown] and fast
    rng = np.random.default_rng(3)
    values = {s: se.RealDouble(float(x)) for s, x in zip([*eom.q, *eom.qd, *eom.qdd],
                                                        rng.uniform(-1, 1, 3 * len(eom.q)), strict=True)}
    values |= {p.symbol: se.RealDouble(1.0 + k / 7) for k, p in enumerate(eom.model.parameters)}
    for a, b in zip(fast, shown, strict=True):
        assert a.frame == "R0"
        turned = kin.frames.express(Vector({b.frame: b.force_components}), "R0")
        for x, y in zip(a.force_components, turned, strict=True):
            assert abs(float(x.subs(values)) - float(y.subs(values))) < 1e-12 * (1 + abs(float(y.subs(values))))


def test_ground_wrench_on_a_urdf_arm_is_pinocchios_transmitted_force():
    pin = pytest.importorskip("pinocchio", reason="Pinocchio is the referee")
    model = _arm()
    eom = lagrangian.derive(model)
    traj = lagrangian.simulate(eom, 0.05, n_out=4, initial={"j1_dot": 1.0, "j3_dot": -2.0, "j2": 0.4})
    columns = reaction_columns_along(eom, traj)
    (force_name,) = [k[:-3] for k in columns if k.endswith("_x0") and not k.startswith("M_")]
    peer = Peer(pin, SPATIAL_ARM, list(eom.coordinates))
    first = peer.model.getJointId("j1")
    for k in range(len(traj)):
        qp, vp = peer.state(traj.q[k], traj.qd[k])
        a = np.zeros(peer.model.nv)
        a[peer.v_index] = traj.qdd[k]
        pin.rnea(peer.model, peer.data, qp, vp, a)
        pin.forwardKinematics(peer.model, peer.data, qp)
        wrench = peer.data.oMi[first].act(peer.data.f[first])  # in R0, about its origin
        ours_f = np.array([columns[f"{force_name}_{a}"][k] for a in ("x0", "y0", "z0")])
        ours_m = np.array([columns[f"M_{force_name}_{a}"][k] for a in ("x0", "y0", "z0")])
        np.testing.assert_allclose(ours_f, wrench.linear, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(ours_m, wrench.angular, rtol=1e-9, atol=1e-9)
