"""Simulation with complementary constraints (`lagrangian.numerics._dae_run`): drift control and
reporting, the multipliers along a motion, the two backends, bad initial states, events."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lagrangian_test_support import EXAMPLES_DIR, mutated_example

import lagrangian
from lagrangian.errors import SimulationError
from lagrangian.numerics import save_trajectory, simulate
from lagrangian.numerics._dae import ConstrainedSystem
from lagrangian.numerics._dae_run import simulate_dae

PENDULUM = EXAMPLES_DIR / "pendulum_tension.toml"
#: The projection restores the constraints to 1e-3 atol (1e-13 at the default atol = 1e-10).
PROJECTED = 1e-12


def eom_of(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))


@pytest.fixture(scope="module")
def pendulum() -> ConstrainedSystem:
    return ConstrainedSystem(eom_of("pendulum_tension.toml"))


@pytest.mark.slow
def test_simulate_dispatches_models_with_complementary_constraints() -> None:
    traj = simulate(PENDULUM, 0.5, n_out=51)
    assert traj.method == "dop853 + projection"
    assert {"lambda_length", "R_length_x0", "R_length_y0", "R_length_z0"} <= set(traj.extra)
    assert {"drift_length", "drift_length_dot"} <= set(traj.monitors)
    assert traj.integrals == ("E",)
    assert set(traj.drift) == {"E", "drift_length", "drift_length_dot"}
    assert "lambda_length" in traj.columns() and len(traj.column("lambda_length")) == 51


@pytest.mark.slow
def test_projection_keeps_the_constraints_to_round_off(pendulum) -> None:
    traj = simulate_dae(pendulum, 3.0, rtol=1e-6, atol=1e-6, n_out=301)
    assert traj.drift["drift_length"] <= 1e-3 * 1e-6 and traj.drift["drift_length_dot"] <= 1e-3 * 1e-6
    assert np.max(np.abs(traj.q[:, 0] ** 2 + traj.q[:, 1] ** 2 - 0.25)) == pytest.approx(
        traj.drift["drift_length"], rel=1e-6, abs=1e-15)


@pytest.mark.slow
def test_without_stabilization_the_drift_grows_and_is_reported(pendulum) -> None:
    free = simulate_dae(pendulum, 3.0, rtol=1e-6, atol=1e-6, n_out=301, stabilization="none")
    projected = simulate_dae(pendulum, 3.0, rtol=1e-6, atol=1e-6, n_out=301)
    assert free.drift["drift_length"] > 1e3 * projected.drift["drift_length"]
    residual = free.monitors["drift_length"]
    assert abs(residual[-1]) > abs(residual[10])  # f(q) drifts away: the index reduction alone does not hold it
    assert free.drift["drift_length"] == pytest.approx(np.max(np.abs(residual)))


def test_baumgarte_bounds_the_drift(pendulum) -> None:
    free = simulate_dae(pendulum, 10.0, method="RK45", rtol=1e-6, atol=1e-6, n_out=101, stabilization="none")
    damped = simulate_dae(pendulum, 10.0, method="RK45", rtol=1e-6, atol=1e-6, n_out=101,
                          stabilization="baumgarte")
    assert damped.method == "rk45 + baumgarte"
    grown = np.abs(free.monitors["drift_length"])
    assert grown[-1] > 10 * grown[10]  # unstabilised: f grows along the run
    assert damped.drift["drift_length"] < free.drift["drift_length"] / 100


def test_implicit_method_with_baumgarte(pendulum) -> None:
    traj = simulate_dae(pendulum, 1.0, method="Radau", rtol=1e-8, atol=1e-8, n_out=11)
    reference = simulate_dae(pendulum, 1.0, n_out=11)
    assert traj.method == "Radau + baumgarte"
    assert np.allclose(traj.q, reference.q, rtol=0, atol=1e-6)


def test_tolerance_warns_about_the_constraint_drift(pendulum) -> None:
    traj = simulate_dae(pendulum, 2.0, rtol=1e-5, atol=1e-5, stabilization="none", tolerance=1e-12)
    assert any("constraint residual drift_length" in w for w in traj.warnings)


def test_energy_and_multipliers_along_the_motion(pendulum) -> None:
    traj = simulate_dae(pendulum, 2.0)
    assert traj.drift["E"] < 1e-9
    # The multiplier is the one of the augmented equations: m q̈ = F + Aᵀλ at each output.
    x, y = traj.q.T
    lam = traj.extra["lambda_length"]
    assert np.allclose(traj.qdd[:, 0], 2 * lam * x, rtol=0, atol=1e-10)
    assert np.allclose(traj.qdd[:, 1], -9.81 + 2 * lam * y, rtol=0, atol=1e-10)
    assert np.allclose(traj.extra["R_length_x0"], 2 * lam * x) and np.all(traj.extra["R_length_z0"] == 0)


def test_symengine_backend_agrees_with_c(pendulum) -> None:
    other = ConstrainedSystem(pendulum.eom, backend="symengine")
    rng = np.random.default_rng(5)
    Y = rng.uniform(-1, 1, (7, 4))
    p = pendulum.parameter_vector()
    for a, b in zip(pendulum.rhs(0.3, Y, p, (2.0, 3.0)), other.rhs(0.3, Y, p, (2.0, 3.0)), strict=True):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12)
    for a, b in zip(pendulum.parts(0.3, Y, p), other.parts(0.3, Y, p), strict=True):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12)
    lam = rng.uniform(-1, 1, (7, 1))
    assert np.allclose(pendulum.reaction_values(0.3, Y, lam, p), other.reaction_values(0.3, Y, lam, p))
    t1 = simulate_dae(pendulum, 0.5, n_out=11)
    t2 = simulate_dae(other, 0.5, n_out=11)
    assert np.allclose(t1.q, t2.q, rtol=0, atol=1e-12) and other.backend == "symengine"


@pytest.mark.slow
def test_initial_state_off_the_constraint_is_refused_with_the_residual_and_a_fix() -> None:
    with pytest.raises(SimulationError) as exc:
        simulate(PENDULUM, 1.0, initial={"x": 0.3})
    err = exc.value
    assert "violates the holonomic constraint `length`" in err.message
    assert f"{0.3**2 + 0.4387912809451864**2 - 0.25:.6g}" in err.message
    assert "pendulum_tension.toml:" in err.message  # where the constraint is declared
    # The suggested state satisfies the constraint.
    values = dict(part.split(" = ") for part in err.fix.split(": ", 1)[1].split(", "))
    x = float(values.get("x", 0.3))
    y = float(values.get("y", -0.4387912809451864))
    assert x**2 + y**2 == pytest.approx(0.25, abs=1e-12)


@pytest.mark.slow
def test_a_constraint_with_no_real_solution_is_refused_without_a_suggestion(tmp_path) -> None:
    # tools/fuzz.py seed 103, case 4496: x² + y² + l² = 0 (a "--" for "-"); the search for the nearest
    # consistent state met a singular Jacobian at x = y = 0 and escaped as numpy's LinAlgError.
    path = mutated_example(tmp_path, "pendulum_tension.toml", 'holonomic = "x^2 + y^2 - l^2"',
                           'holonomic = "x^2 + y^2 -- l^2"')
    with pytest.raises(SimulationError) as exc:
        simulate(path, 0.3)
    assert "violates the holonomic constraint `length`" in exc.value.message
    assert "none was found near these" in exc.value.fix and "real solution" in exc.value.fix


@pytest.mark.slow
def test_initial_rates_off_a_nonholonomic_constraint_are_refused() -> None:
    with pytest.raises(SimulationError) as exc:
        simulate(EXAMPLES_DIR / "rolling_coin.toml", 1.0, initial={"y_dot": 0.5})
    assert "violate the nonholonomic constraint `rolling_y1`" in exc.value.message
    assert "y_dot = 0" in exc.value.fix


REDUNDANT_HERE = """
[parameters]
m = 1.0
[coordinates]
x = { initial = 1.0, rate = 0.0 }
y = { initial = 0.0, rate = 0.7 }
[particles.P]
mass = "m"
position = "x*R0.x + y*R0.y"
[constraints]
a = { nonholonomic = "x_dot" }
b = { nonholonomic = "x*x_dot + y*y_dot" }
"""


@pytest.mark.slow
def test_constraints_redundant_at_the_initial_state_are_named() -> None:
    eom = lagrangian.derive(lagrangian.parse_model(REDUNDANT_HERE, source="redundant.toml"))
    with pytest.raises(SimulationError, match=r"row `b` \(declared at redundant.toml:\d+\) is redundant at the "
                                              r"initial state.*`a`"):
        simulate(eom, 1.0)
    simulate(eom, 0.1, initial={"y": 0.5, "y_dot": 0.0}, n_out=3)  # elsewhere the two rows are independent


@pytest.mark.parametrize(("options", "words"), [
    ({"method": "gauss-legendre"}, "Gauss-Legendre"),
    ({"method": "Radau", "stabilization": "projection"}, "needs an explicit method"),
    ({"dt": 1e-3}, "Fixed steps"),
    ({"stabilization": "magic"}, "Unknown stabilization"),
    ({"method": "Euler"}, "Unknown method"),
])
def test_bad_options_are_explained(pendulum, options: dict, words: str) -> None:
    with pytest.raises(SimulationError, match=words):
        simulate_dae(pendulum, 1.0, **options)


def test_events_and_terminal_events(pendulum) -> None:
    period = simulate_dae(pendulum, 3.0, events=["x"])
    times = [e.t for e in period.events]
    assert len(times) >= 4
    half_periods = np.diff(times)
    assert np.allclose(half_periods, half_periods[0], rtol=1e-8)
    for e in period.events:
        assert abs(e.q[0]) < 1e-10 and abs(e.q[0] ** 2 + e.q[1] ** 2 - 0.25) < PROJECTED
    stop = simulate_dae(pendulum, 3.0, events=[lagrangian.numerics.EventSpec("x0", "x", terminal=True)])
    assert stop.status == "stopped by a terminal event" and stop.t[-1] <= times[0] + 1e-12
    assert stop.events[0].t == pytest.approx(times[0], rel=1e-10)


def test_trajectory_with_multipliers_saves_to_csv(pendulum, tmp_path) -> None:
    traj = simulate_dae(pendulum, 0.2, n_out=5)
    path = save_trajectory(traj, tmp_path / "traj.csv")
    text = path.read_text()
    assert "lambda_length" in text and "drift_length_dot" in text and "R_length_y0" in text


def test_parameters_and_initial_overrides(pendulum) -> None:
    slow = simulate_dae(pendulum, 1.0, parameters={"g": 1.62}, n_out=11)
    assert slow.parameters["g"] == 1.62
    # Tension at rest at the start: m g cos θ0 with the new g.
    R = np.hypot(slow.extra["R_length_x0"][0], slow.extra["R_length_y0"][0])
    assert R == pytest.approx(1.62 * np.cos(0.5), rel=1e-9)


@pytest.mark.slow
@settings(max_examples=10)
@given(theta0=st.floats(-2.5, 2.5), rate=st.floats(-4.0, 4.0))
def test_property_drift_stays_bounded_and_tension_holds(pendulum, theta0: float, rate: float) -> None:
    """From any consistent state (θ0, θ̇0): constraints kept to 1e-3 atol, T = m(g cos θ + l θ̇²)."""
    l, g = 0.5, 9.81
    initial = {"x": l * np.sin(theta0), "y": -l * np.cos(theta0),
               "x_dot": l * np.cos(theta0) * rate, "y_dot": l * np.sin(theta0) * rate}
    traj = simulate_dae(pendulum, 1.0, initial=initial, n_out=21)
    assert traj.drift["drift_length"] <= 1e-13 and traj.drift["drift_length_dot"] <= 1e-13
    x, y = traj.q.T
    theta = np.arctan2(x, -y)
    theta_dot = (x * traj.qd[:, 1] - y * traj.qd[:, 0]) / l**2
    assert np.allclose(-2 * l * traj.extra["lambda_length"], g * np.cos(theta) + l * theta_dot**2,
                       rtol=1e-8, atol=1e-8)


@pytest.mark.slow
def test_a_mass_of_1e308_is_a_singular_mass_matrix_not_a_lapack_failure(tmp_path) -> None:
    # tools/fuzz.py seed 104, case 2448: top_reaction with mass = "(m)*1e308": LAPACK's eigenvalue
    # iteration did not converge on M (numpy's LinAlgError); scaled first, M is found singular in double
    # precision (its smallest eigenvalue below 1e-12 of its largest), which it is.
    from lagrangian.numerics._mass_spectrum import mass_eigenvalues

    path = mutated_example(tmp_path, "top_reaction.toml", '\nmass = "m"\n', '\nmass = "(m)*1e308"\n')
    with pytest.raises(SimulationError) as exc:
        simulate(path, 0.3)
    assert "singular" in exc.value.message and "1e12 apart" in exc.value.fix
    # The scaled eigenvalues are those of the matrix (checked on one LAPACK handles unscaled).
    rng = np.random.default_rng(3)
    B = rng.normal(size=(4, 4))
    M = B @ B.T + np.eye(4)
    assert np.allclose(mass_eigenvalues(M * 1e300) / 1e300, np.linalg.eigvalsh(M), rtol=1e-12)
