"""The recursive formulation (`dynamics._recursive`) against the course's derivation and Pinocchio.

M, F, T, U and Hamilton's ∂(T − U)/∂q + Q of the symbolic Newton–Euler / composite-rigid-body
form must equal those of the course's route (virtual power, `_inertia`; T and the L(q_i)) at
random states and random parameter values; the compiled code of both must agree, and the
simulated motions too; with Pinocchio installed, q̈ must equal ``pin.aba``'s on the same robot.
"""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR, random_point

import lagrangian
from lagrangian.dynamics._recursive import AUTO_MIN_DEPTH
from lagrangian.dynamics._tree import tree_structure
from lagrangian.errors import DerivationError
from lagrangian.model.build import ModelBuilder
from lagrangian.model.zoo import ARM_AXES, lagrange_top, planar_chain, relative_chain, serial_arm
from lagrangian.numerics import compile_system, simulate

RTOL = 1e-10



def _course(exprs, values: dict) -> np.ndarray:
    sub = {k: se.RealDouble(v) for k, v in values.items()}
    return np.array([float(e.xreplace(sub)) for e in exprs])


def _close(a, b) -> None:
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert np.max(np.abs(a - b)) <= RTOL * max(1.0, float(np.max(np.abs(b)))), (a, b)


def _check_against_course(model, states: int = 3, seed: int = 1) -> None:
    rec_eom = lagrangian.derive(model, formulation="recursive")
    course = lagrangian.derive(model, formulation="lagrange")
    rec = rec_eom.recursive
    assert rec is not None and course.recursive is None
    n = len(course.q)
    rng = np.random.default_rng(seed)
    for _ in range(states):
        values = random_point(course, rng)
        M = rec.evaluate([e for row in rec.M for e in row], values)
        _close(M, _course([e for row in course.M for e in row], values))
        _close(np.reshape(M, (n, n)), np.reshape(M, (n, n)).T)
        _close(rec.evaluate(rec.F, values), _course(course.F, values))
        # T, U and the right side of Hamilton's ṗ = ∂T/∂q − ∂U/∂q + Q(nc) of the course's L(q_i).
        _close(rec.evaluate([rec.T], values), _course([course.T], values))
        if rec.conservative:
            _close(rec.evaluate([rec.U], values), _course([course.U], values))
        _close(rec.evaluate(rec.dL_dq, values),
               _course([eq.dT_dq - eq.dU_dq + eq.Q_nc for eq in course.equations], values))


@pytest.mark.slow
@pytest.mark.parametrize("n", [3, 4, 5, 6])
def test_planar_chain_in_relative_angles(n: int) -> None:
    _check_against_course(relative_chain(n))


@pytest.mark.slow
@pytest.mark.parametrize("n", [4, 7])
def test_spatial_arm_full_inertia_torques_and_dampers(n: int) -> None:
    # Joints about z, y, y, x, y, x, z; centres off every axis, products of inertia, motor
    # torques (reacting on the previous link) and viscous joint dampers.
    _check_against_course(serial_arm(n, damping=True))


def _prismatic_model() -> lagrangian.Model:
    """A cart on a rail (x) carrying a rotating arm (θ about z0) with a bead sliding on it (r), a
    second link (φ about the arm's y) with a body off its axis, gravity along −z0 and a spring."""
    b = ModelBuilder("cart, arm, bead and link")
    for name, value in (("M0", 2.0), ("m1", 0.7), ("m2", 0.3), ("m3", 0.5), ("L", 0.8), ("g", 9.81), ("k", 3.0),
                        ("A", 0.02), ("B", 0.03), ("C", 0.025), ("h", 0.1)):
        b.parameter(name, value)
    for name in ("x", "theta", "r", "phi"):
        b.coordinate(name, initial=0.1)
    b.frame("R0", None)
    b.frame("R1", "R0", rotation=("theta", "z"))
    b.frame("R2", "R1", rotation=("phi + 1/3", "y"))  # an offset in the angle: α = q + b
    b.particle("cart", mass="M0", position="x*R0.x")
    b.body("arm", frame="R1", mass="m1", center="x*R0.x + L/2*R1.x",
           inertia={"at": "G", "frame": "R1", "diagonal": ["A", "B", "C"]})
    b.particle("bead", mass="m2", position="x*R0.x + r*R1.x")
    b.body("link", frame="R2", mass="m3", center="x*R0.x + L*R1.x + h*R2.x + h*R2.z",
           inertia={"at": "G", "frame": "R2", "matrix": [["A", "0.001", "0"], ["0.001", "B", "0"], ["0", "0", "C"]]})
    b.gravity("weight", "-g*R0.z")
    b.point("anchor", "0.5*R0.y")
    b.spring("rail_spring", ("anchor", "cart"), stiffness="k")
    return b.build()


TREE_EXAMPLES = ["block_on_belt.toml", "block_on_incline.toml", "cart_pendulum.toml", "double_pendulum.toml",
                 "inverted_pendulum_cart.toml", "lagrange_top.toml", "simple_pendulum.toml", "sleeping_top.toml",
                 "spherical_pendulum.toml"]


@pytest.mark.parametrize("name", TREE_EXAMPLES)
def test_every_tree_example(name: str) -> None:
    # Fixed points, inertias given at a point other than G, sliding blocks, friction and the like:
    # the recursive form of every example that is a tree equals the course's derivation.
    _check_against_course(lagrangian.load_model(EXAMPLES_DIR / name), states=2)


def test_prismatic_joints_offsets_and_other_loads() -> None:
    model = _prismatic_model()
    tree = tree_structure(lagrangian.derive(model, formulation="lagrange").kinematics)
    assert not isinstance(tree, str), tree
    assert len(tree.other_loads) == 1  # the spring: its Q_i come from the course's virtual power
    _check_against_course(model)


def test_auto_choice_and_refusals() -> None:
    assert lagrangian.derive(relative_chain(AUTO_MIN_DEPTH)).formulation == "recursive"
    assert lagrangian.derive(relative_chain(AUTO_MIN_DEPTH - 1)).formulation == "lagrange"
    assert lagrangian.derive(lagrange_top()).formulation == "lagrange"
    # Absolute angles: a point's position runs through sibling frames, not one chain.
    assert lagrangian.derive(planar_chain(6)).formulation == "lagrange"
    with pytest.raises(DerivationError, match="not on the chain of frames"):
        lagrangian.derive(planar_chain(3), formulation="recursive")
    b = ModelBuilder("spinning")
    b.parameter("w", 2.0)
    b.parameter("m", 1.0)
    b.coordinate("r")
    b.frame("R0", None)
    b.frame("R1", "R0", rotation=("w*t", "z"))  # a prescribed rotation: time in the tree
    b.particle("P", mass="m", position="r*R1.x")
    with pytest.raises(DerivationError, match="rotation angle"):
        lagrangian.derive(b.build(), formulation="recursive")
    with pytest.raises(ValueError, match="formulation"):
        lagrangian.derive(relative_chain(2), formulation="kane")
    # A frame turning about a general constant axis (docs/model-format.md) is left to the course's route.
    b = ModelBuilder("tilted hinge")
    b.parameter("m", 1.0)
    b.parameter("g", 9.81)
    b.coordinate("a")
    b.frame("R0", None)
    b.frame("R1", "R0", rotation=("a", "0.6*R0.x + 0.8*R0.z"))
    b.particle("P", mass="m", position="R1.y")
    b.gravity("weight", "-g*R0.z")
    with pytest.raises(DerivationError, match="axis other than"):
        lagrangian.derive(b.build(), formulation="recursive")


@pytest.mark.slow
def test_course_form_stays_available() -> None:
    eom = lagrangian.derive(serial_arm(5))
    assert eom.formulation == "recursive"
    assert [eq.coordinate for eq in eom.equations] == [f"q{k}" for k in range(1, 6)]
    course = lagrangian.derive(serial_arm(5), formulation="lagrange")
    values = random_point(course, np.random.default_rng(3))
    _close(_course([e for row in eom.M for e in row], values), _course([e for row in course.M for e in row], values))
    _close(_course([eom.T, eom.U], values), _course([course.T, course.U], values))
    assert "E" in {fi.name for fi in lagrangian.first_integrals(lagrangian.derive(relative_chain(5)))}


def test_intermediates_grow_linearly_for_F_and_quadratically_for_M() -> None:
    def counts(n: int) -> tuple[int, int]:
        rec = lagrangian.derive(relative_chain(n)).recursive
        return len(rec.needed(rec.F)), len(rec.needed([e for row in rec.M for e in row]))

    (f10, m10), (f20, m20) = counts(10), counts(20)
    assert f20 / f10 < 2.2  # linear: 2 for twice the links
    assert m20 / m10 < 4.4  # quadratic: 4


@pytest.mark.slow
def test_compiled_recursive_code_agrees_and_simulates() -> None:
    model = serial_arm(4, damping=True)
    fast = compile_system(lagrangian.derive(model, formulation="recursive"))
    slow = compile_system(lagrangian.derive(model, formulation="lagrange"))
    assert "_w" in fast.source and "_w" not in slow.source
    rng = np.random.default_rng(5)
    Y = rng.uniform(-2, 2, (6, 8))
    values = {f"tau{k}": float(rng.uniform(-1, 1)) for k in range(1, 5)}
    p, q = fast.parameter_vector(values), slow.parameter_vector(values)
    for a, b in zip(fast.mass_forces(0.0, Y, p), slow.mass_forces(0.0, Y, q), strict=True):
        _close(a, b)
    _close(fast.rhs(0.0, Y, p), slow.rhs(0.0, Y, q))
    assert fast.monitors[-2:] == ("T", "U")
    # T alike; U differs by the motors' −τ q, a potential the course finds by integration and the
    # recursive form does not look for (its couples count as non-conservative efforts).
    _close(fast.monitor_values(0.0, Y, p)[:, -2], slow.monitor_values(0.0, Y, q)[:, -2])
    # The motions: DOP853, and Gauss–Legendre through Hamilton's form (∂T/∂q by the adjoints).
    for method in ("dop853", "gauss-legendre"):
        kw = {"dt": 1e-3} if method == "gauss-legendre" else {}
        a = simulate(fast, 0.5, method=method, parameters=values, n_out=11, **kw)
        b = simulate(slow, 0.5, method=method, parameters=values, n_out=11, **kw)
        assert np.max(np.abs(a.q - b.q)) < 1e-8 and np.max(np.abs(a.qd - b.qd)) < 1e-8


@pytest.mark.slow
def test_expanded_form_and_the_symengine_backend() -> None:
    eom = lagrangian.derive(relative_chain(4))
    rec = eom.recursive
    values = random_point(eom, np.random.default_rng(7))
    flat = [e for row in rec.M for e in row]
    expanded = rec.expand(flat + list(rec.F))
    assert all(s in values for e in expanded for s in e.free_symbols)  # no intermediate left
    _close(_course(expanded, values), rec.evaluate(flat + list(rec.F), values))
    # Without a C compiler the course's M and F are evaluated: the same q̈.
    Y = np.random.default_rng(8).uniform(-1, 1, (3, 8))
    c, s = compile_system(eom), compile_system(eom, backend="symengine")
    _close(c.rhs(0.0, Y, c.parameter_vector()), s.rhs(0.0, Y, s.parameter_vector()))


@pytest.mark.slow
def test_energy_is_monitored_and_kept() -> None:
    system = compile_system(lagrangian.derive(relative_chain(6)))
    assert system.integrals == ("E",)
    run = simulate(system, 2.0, n_out=21)
    assert run.integrals == ("E",) and run.drift["E"] < 1e-8
    # E = T + U of the recursive form is the course's energy integral.
    course = lagrangian.derive(relative_chain(6), formulation="lagrange")
    energy = next(fi for fi in lagrangian.first_integrals(course) if fi.name == "E")
    values = {se.Symbol(p.name): p.value for p in course.model.parameters}
    for k in (0, 10, 20):
        values.update({s: x for s, x in zip(course.q, run.q[k], strict=True)} | {s: x for s, x in zip(course.qd, run.qd[k], strict=True)})
        values[course.t] = run.t[k]
        _close([run.monitors["E"][k]], _course([energy.expression], values))


def test_pinocchio_aba_on_the_same_arm() -> None:
    pin = pytest.importorskip("pinocchio")
    n = 7
    system = compile_system(lagrangian.derive(serial_arm(n)))
    rng = np.random.default_rng(11)
    values = {p.name: (float(rng.uniform(-1, 1)) if p.input else float(p.value) * float(rng.uniform(0.7, 1.3)))
              for p in system.eom.model.parameters}
    model = pin.Model()
    joint = 0
    kinds = {"x": pin.JointModelRX, "y": pin.JointModelRY, "z": pin.JointModelRZ}
    for k in range(1, n + 1):
        where = pin.SE3(np.eye(3), np.array([0.0, 0.0, values[f"a{k - 1}"]])) if k > 1 else pin.SE3.Identity()
        joint = model.addJoint(joint, kinds[ARM_AXES[(k - 1) % 7]](), where, f"j{k}")
        P = values[f"P_{k}"]
        inertia = np.array([[values[f"I1_{k}"], -P, 0.0], [-P, values[f"I2_{k}"], P], [0.0, P, values[f"I3_{k}"]]])
        centre = np.array([values[f"cx{k}"], values[f"cy{k}"], values[f"cz{k}"]])
        model.appendBodyToJoint(joint, pin.Inertia(values[f"m{k}"], centre, inertia), pin.SE3.Identity())
    model.gravity.linear = np.array([0.0, 0.0, -values["g"]])
    data = model.createData()
    tau = np.array([values[f"tau{k}"] for k in range(1, n + 1)])
    p = system.parameter_vector(values)
    for _ in range(5):
        q, v = rng.uniform(-np.pi, np.pi, n), rng.uniform(-2, 2, n)
        M, _ = system.mass_forces(0.0, np.concatenate([q, v]), p)
        crba = pin.crba(model, data, q)
        _close(M, np.triu(crba) + np.triu(crba, 1).T)
        _close(system.rhs(0.0, np.concatenate([q, v]), p)[n:], pin.aba(model, data, q, v, tau))
