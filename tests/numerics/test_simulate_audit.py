"""simulate(): the drift scale, progress that does not change the run, SciPy step counts,
validation before the run, clear errors, NPZ = CSV, and the DAE options through `simulate`."""

import math

import numpy as np
import pytest
import scipy.integrate
from lagrangian_test_support import EXAMPLES_DIR as EXAMPLES

import lagrangian
from lagrangian.errors import SimulationError
from lagrangian.numerics import compile_system, default_tolerance, save_trajectory, simulate
from lagrangian.numerics._trajectory import conservation, drift_scale


@pytest.fixture(scope="module")
def top():
    return compile_system(lagrangian.derive(lagrangian.lagrange_top()))


@pytest.fixture(scope="module")
def pendulum():
    return compile_system(lagrangian.derive(lagrangian.load_model(EXAMPLES / "simple_pendulum.toml")))


# -- the drift of an integral that starts near 0 ------------------------------------------------------

def test_pendulum_released_horizontally_has_a_small_energy_drift(pendulum):
    # E(t0) = -m g l cos(pi/2) = -3e-16: divided by it, round-off looked like a drift of 1e7.
    traj = simulate(pendulum, 10.0, initial={"theta": 1.5707963267948966, "theta_dot": 0.0})
    assert abs(traj.monitors["E"][0]) < 1e-14
    assert traj.drift["E"] < 1e-8 and traj.warnings == ()
    # S = max |T| + |U| over the run: m g l (cos θ goes from 0 to ±1), up to the swing's T.
    assert traj.scales["E"] == pytest.approx(np.max(np.abs(traj.monitors["T"]) + np.abs(traj.monitors["U"])))


def test_top_at_theta_half_pi_has_a_small_K_drift_and_no_warning(top):
    traj = simulate(top, 10.0, initial={"theta": math.pi / 2})
    assert all(traj.drift[name] < 1e-8 for name in traj.integrals), traj.drift
    assert traj.warnings == ()
    # K's terms A ψ' sin²θ and C cosθ (φ' + ψ' cosθ) are large and cancel: S is their size, not |K(t0)|.
    assert traj.scales["K"] > 1e3 * abs(traj.monitors["K"][0])


def test_conservation_scale_is_the_size_of_the_terms():
    M = np.array([[[2.0, 1.0], [1.0, 3.0]]] * 2)
    qd = np.array([[1.0, -2.0], [1.0, -2.0]])
    monitors = {"p": np.array([0.0, 1e-12]), "E": np.array([1.0, 1.0 + 1e-9]), "T": np.array([5.0, 4.0]),
                "U": np.array([-4.0, -3.0])}
    drift, scales = conservation(monitors, ("p", "E"), momenta={"p": 0}, M=M, qd=qd)
    assert scales["p"] == pytest.approx(2.0 + 2.0)  # |2·1| + |1·(-2)| + |p - Σ M q'| (= 0)
    assert scales["E"] == pytest.approx(9.0)
    assert drift["p"] == pytest.approx(1e-12 / 4) and drift["E"] == pytest.approx(1e-9 / 9)
    assert drift_scale(np.zeros(3)) == 1.0  # an integral that stays 0: absolute drift


# -- progress does not change the run --------------------------------------------------------------

@pytest.mark.parametrize("method", ["dop853", "gauss-legendre"])
def test_trajectory_is_bit_identical_with_and_without_progress(top, method):
    seen = []
    quiet = simulate(top, 10.0, method=method)
    shown = simulate(top, 10.0, method=method, progress=lambda fraction, t: seen.append((fraction, t)))
    for name in ("t", "q", "qd", "qdd"):
        np.testing.assert_array_equal(getattr(shown, name), getattr(quiet, name))
    assert (shown.steps, shown.rhs_calls, shown.drift) == (quiet.steps, quiet.rhs_calls, quiet.drift)
    assert seen[-1] == (1.0, 10.0) and [f for f, _ in seen] == sorted(f for f, _ in seen)


def test_scipy_methods_have_a_progress_report(top):
    seen = []
    simulate(top, 1.0, method="LSODA", progress=lambda fraction, t: seen.append(fraction), n_out=11)
    assert seen[-1] == 1.0 and seen == sorted(seen)


# -- SciPy: the real step count, errors as SimulationError ---------------------------------------------

def test_scipy_runs_report_the_integrators_accepted_steps(top):
    traj = simulate(top, 2.0, method="RK45", rtol=1e-8, atol=1e-8, n_out=11)
    p = top.parameter_vector()
    y0 = lagrangian.numerics.initial_state(top.eom)
    solver = scipy.integrate.RK45(lambda t, y: top.rhs(t, y, p), 0.0, y0, 2.0, rtol=1e-8, atol=1e-8)
    steps = 0
    while solver.status == "running":
        solver.step()
        steps += 1
    assert traj.steps == steps and traj.steps != len(traj.t)


def test_radau_with_an_atol_that_underflows_raises_a_simulation_error(top):
    with pytest.raises(SimulationError) as exc:
        simulate(top, 1.0, method="Radau", rtol=1e-13, atol=1e-300)
    assert "Radau" in exc.value.message and "t = " in exc.value.message and "atol" in exc.value.fix


def test_rhs_of_a_non_finite_state_says_overflow_not_singular(top):
    y = np.array([0.0, 0.3, 0.0, np.inf, 0.0, 80.0])
    with pytest.raises(SimulationError) as exc:
        top.rhs(1.5, y, top.parameter_vector())
    assert "overflowed (blow-up) at t = 1.5" in exc.value.message and "singular" not in exc.value.message


# -- validation before the run ---------------------------------------------------------------------

@pytest.mark.parametrize("options, message", [
    ({"tolerance": 0.0}, "must be a positive number"),
    ({"tolerance": -1e-9}, "must be a positive number"),
    ({"tolerance": math.nan}, "must be a positive number"),
    ({"rtol": 1e-300}, "below 1e-14"),
    ({"atol": 0.0}, "positive finite"),
    ({"t_end": math.inf}, "not finite"),
    ({"t_end": math.nan}, "not finite"),
    ({"n_out": 10**8}, "GiB of memory"),
])
def test_bad_options_are_refused_with_a_clear_message(pendulum, options, message):
    options = {"t_end": 1.0, **options}
    with pytest.raises(SimulationError) as exc:
        simulate(pendulum, **options)
    assert message in exc.value.message


def test_default_tolerance_flags_a_drift_at_a_loose_rtol(top):
    loose = simulate(top, 10.0, rtol=1e-3, atol=1e-3)
    assert loose.tolerance == default_tolerance("dop853", 1e-3) == 1e-6
    assert max(loose.drift.values()) > 1e-6 and any("drifted" in w for w in loose.warnings)
    tight = simulate(top, 10.0)
    assert tight.tolerance == pytest.approx(1e-7) and tight.warnings == ()
    assert simulate(top, 1.0, method="gauss-legendre").tolerance == 1e-6


def test_gauss_legendre_honours_a_dt_larger_than_the_output_spacing(pendulum):
    traj = simulate(pendulum, 1.0, method="gauss-legendre", dt=0.05, n_out=101)
    assert traj.steps == 20 and len(traj.t) == 101
    fine = simulate(pendulum, 1.0, method="gauss-legendre", dt=0.003, n_out=101)
    assert fine.steps in (400, 401)  # dt rounded down to 0.0025, so that whole steps fill each spacing
    np.testing.assert_allclose(traj.q, fine.q, atol=1e-4)


# -- files ----------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_npz_holds_every_column_of_the_csv(tmp_path):
    traj = simulate(EXAMPLES / "pendulum_tension.toml", 0.5, n_out=11)
    assert traj.extra  # multipliers and reactions
    csv = save_trajectory(traj, tmp_path / "a.csv")
    npz = np.load(save_trajectory(traj, tmp_path / "a.npz"))
    lines = csv.read_text().splitlines()
    header = next(line for line in lines if not line.startswith("#"))
    table = np.loadtxt(csv, delimiter=",", comments="#", skiprows=lines.index(header) + 1)
    assert list(npz["columns"]) == header.split(",") == traj.columns()
    np.testing.assert_array_equal(npz["table"], table)
    for name in traj.extra:
        np.testing.assert_array_equal(npz[f"extra_{name}"], table[:, header.split(",").index(name)])


# -- constrained models: stabilization through the public simulate ---------------------------------

@pytest.mark.slow
def test_stabilization_and_baumgarte_reach_the_dae_through_simulate(pendulum):
    traj = simulate(EXAMPLES / "pendulum_tension.toml", 0.5, n_out=11, stabilization="baumgarte",
                    baumgarte=(10.0, 10.0))
    assert traj.method == "dop853 + baumgarte"
    assert simulate(EXAMPLES / "pendulum_tension.toml", 0.5, n_out=11).method == "dop853 + projection"
    with pytest.raises(SimulationError, match="complementary"):
        simulate(pendulum.eom, 0.5, stabilization="baumgarte")


@pytest.mark.slow
def test_two_terminal_events_in_one_step_keep_only_the_first():
    """A crossing after the first terminal event of a step never happened: it is not recorded."""
    from lagrangian.numerics import EventSpec

    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES / "simple_pendulum.toml"))
    events = [EventSpec("late", "theta - 0.2", terminal=True), EventSpec("early", "theta - 0.19", terminal=True)]
    run = lagrangian.simulate(eom, 5.0, initial={"theta": 0.0, "theta_dot": 3.0}, rtol=1e-3, atol=1e-3,
                              events=events)
    assert [e.name for e in run.events] == ["early"]
    assert run.t[-1] <= run.events[0].t < run.t[-1] + 0.01 and run.status != "completed"


@pytest.mark.slow
def test_a_terminal_event_stops_a_stick_slip_run():
    from lagrangian.numerics import EventSpec

    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES / "block_on_incline.toml"))
    run = lagrangian.simulate(eom, 1.0, events=[EventSpec("stop", "x + 0.05", terminal=True)])
    assert [e.name for e in run.events] == ["stop"]
    assert run.t[-1] < 0.07 and run.column("x")[-1] == pytest.approx(-0.05, abs=2e-3)
