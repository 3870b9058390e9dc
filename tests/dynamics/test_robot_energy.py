"""A robot driven by joint torques: inputs τ_j(t) are given non-conservative efforts, constants derive from −τ·q.

An input is any given function of time: d/dt (T + U_gravity) = Σ τ_j q̇_j, the power of the actuators,
so E = T + U_gravity is the mechanical energy and changes by their work (checked with T and U_gravity
from Pinocchio).  A torque that is a constant of the model (a parameter) derives from U = −τ q: then
T + U_gravity − Σ τ_j q_j is a first integral, monitored by `simulate`, in both forms.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import symengine as se
from urdf_robots import DOUBLE_PENDULUM, Peer

import lagrangian
from lagrangian.dynamics._tree import tree_structure
from lagrangian.model.build import ModelBuilder
from lagrangian.model.urdf import UrdfNote, parse_urdf
from lagrangian.model.zoo import serial_arm

TAU = {"tau_shoulder": 1.3, "tau_elbow": -0.6}


def _pendulum() -> lagrangian.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        return parse_urdf(DOUBLE_PENDULUM, source="pendulum.urdf", damping=False)


def _chain_with_a_wind_torque() -> lagrangian.Model:
    """Four links about z, y, y, x; a motor τ between links 1 and 2, and a couple fixed in R0 on link 3."""
    b = ModelBuilder("arm with wind")
    for name, value in (("m", 1.0), ("L", 0.4), ("g", 9.81), ("A", 0.01), ("c", 0.7)):
        b.parameter(name, value)
    b.input("tau")
    b.frame("R0", None)
    for k, axis in enumerate("zyyx", start=1):
        b.coordinate(f"q{k}", initial=0.2 * k)
        b.frame(f"R{k}", f"R{k - 1}", rotation=(f"q{k}", axis))
    center = ""
    for k in range(1, 5):
        center += f"{' + ' if k > 1 else ''}L*R{k}.z"
        b.body(f"link{k}", frame=f"R{k}", mass="m", center=center + f" + L/3*R{k}.x",
               inertia={"at": "G", "frame": f"R{k}", "diagonal": ["A", "2*A", "3*A"]})
    b.gravity("weight", "-g*R0.z")
    b.torque("motor", "tau*R2.y", on="link2", reaction_on="link1")
    b.torque("wind", "c*R0.x", on="link3")
    return b.build()


def test_a_motor_torque_is_a_load_with_a_potential_and_a_couple_fixed_in_r0_stays_a_couple():
    model = _chain_with_a_wind_torque()
    eom = lagrangian.derive(model, formulation="recursive")
    tree = tree_structure(eom.kinematics)
    assert [model.loads[k].name for k in tree.other_loads] == ["motor"] and len(tree.couples) == 1
    assert not eom.recursive.conservative  # the wind's Q depends on q: no potential
    course = lagrangian.derive(model, formulation="lagrange")
    rng = np.random.default_rng(5)
    for _ in range(3):
        values = {s: float(x) for s, x in zip([*eom.q, *eom.qd], rng.uniform(-2, 2, 2 * len(eom.q)), strict=True)}
        values |= {p.symbol: float(p.value) if not p.input else 0.8 for p in model.parameters}
        values[eom.t] = 0.0
        got = eom.recursive.evaluate(eom.recursive.F, values)
        want = [float(f.subs(values)) for f in course.F]
        np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-10)


@pytest.mark.slow
def test_zoo_arm_motors_are_inputs_so_no_potential_and_an_energy_integral_only_with_them_off():
    eom = lagrangian.derive(serial_arm(5), formulation="recursive")
    assert not eom.recursive.conservative and not tree_structure(eom.kinematics).couples
    motors = [f for f in eom.loads if f.kind == "torque"]
    assert motors and all(f.potential is None for f in motors)
    off = {i.name: i for i in lagrangian.first_integrals(eom)}  # the inputs' default regime: off
    assert "E" in off and "with the inputs off" in off["E"].reason
    driven = lagrangian.first_integrals(eom, inputs=dict.fromkeys(eom.model.inputs, "varying"))
    assert "E" not in {i.name for i in driven}


def _chain_with_constant_motors(inputs: bool) -> lagrangian.Model:
    """Three links about z, y, y with a motor between each pair: its torque a constant (or an input)."""
    b = ModelBuilder("arm with constant motors")
    for name, value in (("m", 1.0), ("L", 0.4), ("g", 9.81), ("A", 0.01)):
        b.parameter(name, value)
    for k in (2, 3):
        (b.input if inputs else b.parameter)(f"tau{k}", **({} if inputs else {"value": 0.8 - 0.5 * k}))
    b.frame("R0", None)
    center = ""
    for k, axis in enumerate("zyy", start=1):
        b.coordinate(f"q{k}", initial=0.2 * k, rate=0.3)
        b.frame(f"R{k}", f"R{k - 1}", rotation=(f"q{k}", axis))
        center += f"{' + ' if k > 1 else ''}L*R{k}.z"
        b.body(f"link{k}", frame=f"R{k}", mass="m", center=center + f" + L/3*R{k}.x",
               inertia={"at": "G", "frame": f"R{k}", "diagonal": ["A", "2*A", "3*A"]})
    b.gravity("weight", "-g*R0.z")
    for k in (2, 3):
        b.torque(f"motor{k}", f"tau{k}*R{k}.y", on=f"link{k}", reaction_on=f"link{k - 1}")
    return b.build()


@pytest.mark.slow
@pytest.mark.parametrize("formulation", ["recursive", "lagrange"])
def test_constant_motor_torques_derive_from_minus_tau_q_and_the_energy_is_monitored(formulation):
    eom = lagrangian.derive(_chain_with_constant_motors(inputs=False), formulation=formulation)
    motors = [f for f in eom.loads if f.name.startswith("motor")]
    for f, (k, q) in zip(motors, ((2, eom.q[1]), (3, eom.q[2])), strict=True):
        assert se.expand(f.potential + se.Symbol(f"tau{k}") * q) == 0  # U = −τ q, the course's potential
    run = lagrangian.simulate(eom, 1.0, n_out=5)
    assert "E" in run.integrals and run.drift["E"] < 1e-8
    driven = lagrangian.derive(_chain_with_constant_motors(inputs=True), formulation=formulation)
    assert all(f.potential is None for f in driven.loads if f.name.startswith("motor"))
    assert "E" not in {i.name for i in lagrangian.first_integrals(driven, inputs=dict.fromkeys(("tau2", "tau3"),
                                                                                                "varying"))}
    # Held constant, the inputs' torques derive from −τ q again: the same energy integral as the parameters'.
    held = {i.name: i for i in lagrangian.first_integrals(driven, inputs=dict.fromkeys(("tau2", "tau3"),
                                                                                         "constant"))}
    if formulation == "lagrange":
        want = {i.name: i for i in lagrangian.first_integrals(eom)}["E"].expression
        assert se.expand(held["E"].expression - want) == 0


@pytest.mark.parametrize("formulation", ["recursive", "lagrange"])
def test_mechanical_energy_of_a_urdf_robot_changes_by_the_actuators_work(formulation):
    pin = pytest.importorskip("pinocchio", reason="Pinocchio gives T and U_gravity independently")
    model = _pendulum()
    eom = lagrangian.derive(model, formulation=formulation)
    assert all(f.potential is None for f in eom.loads if f.name == "actuators")  # τ(t): no potential energy
    run = lagrangian.simulate(eom, 2.0, parameters=TAU, initial={"shoulder": 0.4, "elbow": -0.3}, n_out=41)
    # Held at constant values, the torques derive from −τ·q: the run monitors T + U_gravity − τ·q.
    assert "E" in run.integrals and run.drift["E"] < 1e-8
    peer = Peer(pin, DOUBLE_PENDULUM, list(eom.coordinates))
    tau = np.array([TAU["tau_shoulder"], TAU["tau_elbow"]])
    # The actuators' power: T + U_gravity changes by the work Σ τ_j Δq_j.
    work = (run.q - run.q[0]) @ tau
    assert np.abs(work).max() > 0.1  # the torques do work: T + U_gravity alone is not constant
    physical = np.array([sum(peer.energies(q, v)) for q, v in zip(run.q, run.qd, strict=True)])
    np.testing.assert_allclose(physical - physical[0], work, atol=1e-8 * np.abs(physical).max())
    np.testing.assert_allclose(run.monitors["E"] - run.monitors["E"][0], physical - physical[0] - work,
                               atol=1e-8 * np.abs(physical).max())


def test_energy_balance_of_a_damped_urdf_robot_is_the_actuators_and_dampers_power():
    # The course's balance dE/dt = P_nc with E = T + U_gravity, the mechanical energy: the actuators and the damper work.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        model = parse_urdf(DOUBLE_PENDULUM, source="pendulum.urdf")  # <dynamics damping="0.2"> on the elbow
    eom = lagrangian.derive(model)
    balance = lagrangian.energy_balance(eom)
    assert not balance.conserved
    working = {t.name: t.power for t in balance.terms if t.power != 0}
    assert sorted(working) == ["actuators", "joint_damping"]
    rates = {s: float(x) for s, x in zip(eom.qd, (0.7, -1.3), strict=True)}
    assert float(working["joint_damping"].subs(rates)) == pytest.approx(-0.2 * 1.3**2, rel=1e-12)
    taus = {se.Symbol(name): value for name, value in TAU.items()}
    assert float(working["actuators"].subs(rates | taus)) == pytest.approx(1.3 * 0.7 + 0.6 * 1.3, rel=1e-12)
    for name in TAU:  # E is the mechanical energy: no −τ_j q_j
        assert balance.E.diff(se.Symbol(name)) == 0
