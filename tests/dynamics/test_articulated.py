"""The articulated-body algorithm (`dynamics._articulated`): q̈ without forming M, against M⁻¹F and Pinocchio.

Its q̈ must equal the solution of the course's M q̈ = F (virtual power, independent of the
recursion) at random states and parameter values, on chains, a 3D arm with couples and
dampers, and branched trees with prismatic joints, a joint with two coordinates and a bead
sliding on a link; its pivots must be those of M (M_jj its diagonal); and the compiled
right-hand side that uses it must equal ``pin.aba`` on the same URDF robots.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import random_point
from urdf_robots import SPATIAL_ARM, TREE, Peer

import lagrangian
from lagrangian.errors import SimulationError
from lagrangian.model.build import ModelBuilder
from lagrangian.model.urdf import UrdfNote, parse_urdf
from lagrangian.model.zoo import lagrange_top, relative_chain, serial_arm
from lagrangian.numerics import compile_system

RTOL = 1e-10



def _close(a, b) -> None:
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert np.max(np.abs(a - b)) <= RTOL * max(1.0, float(np.max(np.abs(b)))), (a, b)


def _branched_tree() -> lagrangian.Model:
    """A hub turning about z0 (a) with two branches: a link that slides along the hub's x (s) and
    turns about that axis' y (b), one node with two coordinates; and a link about the hub's x (c),
    carrying a bead that slides along it (r).  Off-axis centres, products of inertia, gravity, a
    motor torque between the hub and the second link."""
    b = ModelBuilder("branched tree")
    for name, value in (("m1", 1.5), ("m2", 0.8), ("m3", 0.6), ("mb", 0.2), ("L", 0.7), ("h", 0.15), ("g", 9.81),
                        ("A", 0.02), ("B", 0.03), ("C", 0.025), ("P", 0.004)):
        b.parameter(name, value)
    b.input("tau")
    for name in ("a", "s", "b", "c", "r"):
        b.coordinate(name, initial=0.2)
    b.frame("R0", None)
    b.frame("R1", "R0", rotation=("a", "z"))
    b.frame("R2", "R1", rotation=("b", "y"))
    b.frame("R3", "R1", rotation=("c - 1/4", "x"))
    inertia = {"at": "G", "matrix": [["A", "P", "0"], ["P", "B", "-P"], ["0", "-P", "C"]]}
    b.body("hub", frame="R1", mass="m1", center="h*R1.z + h/2*R1.x", inertia={**inertia, "frame": "R1"})
    b.body("slider", frame="R2", mass="m2", center="s*R1.x + h*R2.z + h/3*R2.y", inertia={**inertia, "frame": "R2"})
    b.body("link", frame="R3", mass="m3", center="L*R1.y + L/2*R3.y + h*R3.z", inertia={**inertia, "frame": "R3"})
    b.particle("bead", mass="mb", position="L*R1.y + r*R3.y")
    b.gravity("weight", "-g*R0.z")
    b.torque("motor", "tau*R1.x", on="link", reaction_on="hub")
    return b.build()


def _check_against_course(model, states: int = 2, seed: int = 3) -> None:
    rec = lagrangian.derive(model, formulation="recursive").recursive
    course = lagrangian.derive(model, formulation="lagrange")
    assert rec is not None and rec.qdd is not None
    n = len(course.q)
    rng = np.random.default_rng(seed)
    for _ in range(states):
        values = random_point(course, rng)
        sub = {k: se.RealDouble(v) for k, v in values.items()}
        M = np.array([[float(e.xreplace(sub)) for e in row] for row in course.M])
        F = np.array([float(e.xreplace(sub)) for e in course.F])
        _close(rec.evaluate(rec.qdd, values), np.linalg.solve(M, F))
        pivots = np.reshape(rec.evaluate([x for pair in rec.pivots for x in pair], values), (n, 2))
        _close(pivots[:, 1], np.diag(M))
        assert np.all(pivots[:, 0] > 0) and np.all(pivots[:, 0] <= pivots[:, 1] * (1 + 1e-12))


@pytest.mark.slow
@pytest.mark.parametrize("model", [relative_chain(5), serial_arm(5, damping=True), _branched_tree()],
                         ids=["chain", "arm_with_torques_and_dampers", "branched_tree"])
def test_articulated_accelerations_solve_the_course_equations(model) -> None:
    _check_against_course(model)


def test_a_coordinate_shared_by_several_joints_keeps_the_solve() -> None:
    # A mimic joint turns with another joint's coordinate: no joint of its own for it.
    eom = lagrangian.derive(_urdf(TREE), formulation="recursive")
    assert eom.recursive is not None and eom.recursive.qdd is None and eom.recursive.pivots == ()
    assert "#define LG_ABA" not in compile_system(eom).source


def _urdf(text: str) -> lagrangian.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        return parse_urdf(text, source="robot.urdf", damping=False)


#: `urdf_robots.TREE` with its mimic joint made a joint of its own: a branched tree with welded and
#: massless links, and a slider along a general axis whose link carries two branches (the slide is
#: in both child frames' offsets: `_shared_slides` gives it a joint of its own).
BRANCHED = re.sub(r'<mimic [^>]*/>', "", TREE)
#: The same with its base turning about z (the slide's moment arms then count), or its slider made a
#: hinge about the same axis.
TURNING = BRANCHED.replace('<joint name="bolt" type="fixed">', '<joint name="bolt" type="continuous"><axis xyz="0 0 1"/>')
HINGED = BRANCHED.replace('name="slide" type="prismatic"', 'name="slide" type="revolute"')


@pytest.mark.parametrize("text", [SPATIAL_ARM, TURNING, HINGED], ids=["spatial_arm", "branched_tree", "hinged_tree"])
def test_compiled_articulated_rhs_is_pinocchios_aba(text: str) -> None:
    pin = pytest.importorskip("pinocchio", reason="Pinocchio (`pip install pin`) is the referee")
    eom = lagrangian.derive(_urdf(text), formulation="recursive")
    system = compile_system(eom)
    assert eom.recursive.qdd is not None and "#define LG_ABA 1" in system.source
    peer = Peer(pin, text, list(eom.coordinates))
    n = len(eom.q)
    rng = np.random.default_rng(5)
    tau = rng.uniform(-1, 1, n)
    p = system.parameter_vector({name: float(x) for name, x in zip(eom.model.inputs, tau, strict=True)})
    Y = np.hstack([rng.uniform(-1.2, 1.2, (6, n)), rng.uniform(-2, 2, (6, n))])
    ours = system.rhs(0.0, Y, p)[:, n:]  # batched
    M, F = system.mass_forces(np.zeros(len(Y)), Y, p)
    for y, a, m, f in zip(Y, ours, np.reshape(M, (-1, n, n)), np.reshape(F, (-1, n)), strict=True):
        theirs = peer.acceleration(y[:n], y[n:], tau)
        np.testing.assert_allclose(a, theirs, rtol=RTOL, atol=RTOL)
        np.testing.assert_allclose(a, np.linalg.solve(m, f), rtol=RTOL, atol=RTOL)
        out = np.empty(2 * n)
        assert system.rhs_c(0.0, y, p, out) == 0  # one state
        np.testing.assert_allclose(out[n:], theirs, rtol=RTOL, atol=RTOL)


def test_a_vanishing_pivot_is_a_singular_mass_matrix() -> None:
    # Lagrange's top in Euler angles is a tree of massless frames: at θ = 0 the axes of ψ and φ
    # coincide, D of the outer one vanishes and M is singular: reported as such, not as NaN.
    eom = lagrangian.derive(lagrange_top(), formulation="recursive")
    assert eom.recursive.qdd is not None
    system = compile_system(eom)
    n = len(eom.q)
    y = np.zeros(2 * n)
    y[eom.coordinates.index("theta")] = 0.0
    with pytest.raises(SimulationError, match="singular"):
        system.rhs(0.0, y, system.parameter_vector())
    y[eom.coordinates.index("theta")] = 0.4
    y[n:] = [0.3, -0.2, 5.0]
    M, F = system.mass_forces(0.0, y, system.parameter_vector())
    np.testing.assert_allclose(system.rhs(0.0, y, system.parameter_vector())[n:],
                               np.linalg.solve(np.reshape(M, (n, n)), F), rtol=RTOL, atol=RTOL)


def test_a_slide_shared_by_two_branches_solves_the_course_equations() -> None:
    _check_against_course(_urdf(TURNING))
