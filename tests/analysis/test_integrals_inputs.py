"""First integrals with declared inputs: those that hold with the inputs off, constant, or varying.

The Furuta pendulum (examples/furuta_pendulum.toml): the arm angle φ is cyclic, and its motor
torque τ acts on it alone.  With τ off, p_φ = ∂T/∂φ̇ — written out by hand below — and the
energy hold and are monitored; with τ driving, neither is monitored and no drift is reported as
a fault.  With the motor moved to the pendulum's hinge (τ between arm and pendulum), p_φ still
holds while τ varies, and is still monitored.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import example_text

import lagrangian
from lagrangian.analysis import first_integrals
from lagrangian.numerics import simulate

FURUTA = "examples/furuta_pendulum.toml"


@pytest.fixture(scope="module")
def furuta() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(FURUTA))


def _p_phi_by_hand(values: dict, alpha: float, phi_dot: float, alpha_dot: float) -> float:
    ma, r, mp, lp = (values[k] for k in ("ma", "r", "mp", "lp"))
    return (ma * r**2 / 3 + mp * r**2 + 4 / 3 * mp * lp**2 * math.sin(alpha) ** 2) * phi_dot \
        + mp * r * lp * math.cos(alpha) * alpha_dot


def test_with_the_motor_off_the_momentum_about_its_axis_and_the_energy_hold(furuta):
    found = {fi.name: fi for fi in first_integrals(furuta)}
    assert set(found) == {"p_phi", "E"}
    assert "with the inputs off: tau = 0" in found["p_phi"].reason
    values = furuta.model.parameter_values
    rng = np.random.default_rng(7)
    symbols = {str(s): s for s in (*furuta.q, *furuta.qd)}
    for _ in range(5):
        a, pd, ad = rng.uniform(-3, 3, 3)
        subs = {symbols["phi"]: 0.4, symbols["alpha"]: a, symbols["phi_dot"]: pd, symbols["alpha_dot"]: ad}
        subs.update({se.Symbol(k): v for k, v in values.items() if v is not None})
        assert float(found["p_phi"].expression.subs(subs)) == pytest.approx(_p_phi_by_hand(values, a, pd, ad),
                                                                            rel=1e-12)


@pytest.mark.slow
def test_a_constant_torque_keeps_the_energy_with_its_work_and_a_varying_one_keeps_nothing(furuta):
    constant = first_integrals(furuta, inputs={"tau": "constant"})
    assert [fi.name for fi in constant] == ["E"]
    assert "tau" in str(constant[0].expression)  # U holds −τ φ, the potential of a constant couple
    assert first_integrals(furuta, inputs={"tau": "varying"}) == ()
    with pytest.raises(ValueError, match="`F` is not a declared input"):
        first_integrals(furuta, inputs={"F": "off"})


def test_the_simulation_monitors_what_holds_and_warns_of_nothing_an_input_causes(furuta):
    off = simulate(furuta, 3.0, n_out=301, initial={"alpha": 2.0, "phi_dot": 3.0})
    assert off.integrals == ("p_phi", "E") and not off.warnings
    assert max(off.drift.values()) < 1e-8
    driven = simulate(furuta, 3.0, n_out=301, initial={"alpha": 2.0, "phi_dot": 3.0},
                      inputs={"tau": "0.02*sin(5*t)"})
    assert driven.integrals == () and not driven.warnings
    # the motor does change p_phi: by ∫ τ dt, written out
    p = [_p_phi_by_hand(furuta.model.parameter_values, a, pd, ad)
         for a, pd, ad in zip(driven.q[:, 1], driven.qd[:, 0], driven.qd[:, 1], strict=True)]
    work = 0.02 * (1 - np.cos(5 * driven.t)) / 5
    assert np.allclose(np.array(p) - p[0], work, atol=1e-10)


def test_a_torque_at_the_pendulums_hinge_leaves_the_arms_momentum_monitored():
    text = example_text("furuta_pendulum.toml").replace(
        'motor = { torque = "tau*R0.z", on = "arm", reaction_on = "R0" }',
        'motor = { torque = "tau*R1.x", on = "pendulum", reaction_on = "arm" }')
    eom = lagrangian.derive(lagrangian.parse_model(text))
    assert [fi.name for fi in first_integrals(eom, inputs={"tau": "varying"})] == ["p_phi"]
    traj = simulate(eom, 3.0, n_out=301, initial={"alpha": 2.0, "phi_dot": 3.0}, inputs={"tau": "0.01*sin(4*t)"})
    assert traj.integrals == ("p_phi",) and traj.drift["p_phi"] < 1e-8 and not traj.warnings


def test_a_constant_input_given_as_a_parameter_monitors_the_integrals_of_a_constant_input(furuta):
    traj = simulate(furuta, 2.0, n_out=201, parameters={"tau": 0.01}, initial={"alpha": 2.0})
    assert traj.integrals == ("E",) and traj.drift["E"] < 1e-8 and not traj.warnings


def test_a_robot_in_the_recursive_form_monitors_its_energy_with_its_motors_off():
    from lagrangian.model.urdf import UrdfNote, parse_urdf

    text = example_text("rrr_arm.urdf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        model = parse_urdf(text, source="rrr_arm.urdf", damping=False)
    eom = lagrangian.derive(model, formulation="recursive")
    assert eom.recursive is not None and model.inputs
    off = simulate(eom, 1.0, n_out=11, initial={c.name: 0.3 for c in model.coordinates})
    # With the motors off the waist (about the vertical) keeps its momentum too (`tree_integrals`).
    assert set(off.integrals) == {"p_waist", "E"} and max(off.drift.values()) < 1e-8
    driven = simulate(eom, 1.0, n_out=11, inputs={model.inputs[0]: "0.5*sin(2*t)"})
    assert driven.integrals == () and not driven.warnings
