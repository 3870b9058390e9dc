"""Problems that cannot be stated get a clear `ProblemError`; problems without a solution a clear status."""

import math
import os
import signal
import threading

import numpy as np
import pytest

pytest.importorskip("casadi")

from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.errors import ProblemError
from lagrangian.optimal import (
    Objective,
    _solve,
    optimize,
)

SWING = {"t_end": 3.0, "initial": {"theta": 0, "theta_dot": 0}, "final": {"theta": "pi", "theta_dot": 0},
         "bounds": {"tau": (-5, 5)}}


@pytest.fixture(scope="module")
def pendulum():
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "torque_pendulum.toml"))


@pytest.mark.parametrize("change, message", [
    ({"bounds": {"torque": (-1, 1)}}, (r"names `torque`, which is neither .* the names are theta, theta_dot, "
                                       r"theta_ddot, tau")),
    ({"initial": {"phi": 0}}, r"`initial` names `phi`"),
    ({"bounds": {"tau": (5, -5)}}, r"bounds of `tau` are reversed: low 5 > high -5"),
    ({"bounds": {"tau": (-1,)}}, r"must be a pair"),
    ({"nodes": 1}, r"at least 2 nodes"),
    ({"method": "midpoint"}, r"Unknown method `midpoint`"),
    ({"objective": "speed"}, r"Unknown objective `speed`"),
    ({"objective": "time"}, r"the final time is fixed"),
    ({"bounds": {"t_end": (1, 2), "tau": (-5, 5)}}, r"`t_end` has bounds, but the final time is fixed"),
    ({"t_end": -1.0}, r"not after t_start"),
    ({"initial": {"theta": 0, "theta_dot": 0, "tau": 9}}, r"initial value tau = 9 is outside its bounds"),
    ({"path": ["theta <"]}, r"not a comparison"),
    ({"path": ["theta + phi <= 1"]}, r"unknown symbol `phi`"),
    ({"objective": {"effort": {"torque": 1.0}}}, r"effort weighs `torque`, which is not an input"),
    ({"objective": {"effort": -1.0}}, r"weight must be a finite number ≥ 0"),
    ({"parameters": {"tau": 1.0}}, r"`tau` is an input"),
    ({"parameters": {"mass": 1.0}}, r"`mass` is not a parameter"),
    ({"final": {"theta": "pi*q", "theta_dot": 0}}, r"unknown symbol `q`"),
    ({"final": {"theta": math.inf}}, r"not finite"),
])
def test_a_problem_that_cannot_be_stated_is_refused_with_its_reason(pendulum, change, message):
    with pytest.raises(ProblemError, match=message):
        optimize(pendulum, **{**SWING, **change})


def test_a_model_without_inputs_has_nothing_to_optimize():
    with pytest.raises(ProblemError, match="has no input, so there is nothing to optimize"):
        optimize(EXAMPLES_DIR / "simple_pendulum.toml", t_end=1.0)


def test_an_infeasible_problem_returns_a_status_not_an_error(pendulum):
    # |tau| <= 0.5 cannot lift the bob to the top in 1 s
    best = optimize(pendulum, t_end=1.0, initial={"theta": 0, "theta_dot": 0}, final={"theta": "pi", "theta_dot": 0},
                    bounds={"tau": (-0.5, 0.5)}, nodes=20)
    assert best.status == "infeasible" and not best.success
    assert best.violation > 1e-3 and best.replay is None
    assert "infeasible" in best.message and "Widen the bounds" in best.message


def test_ctrl_c_returns_the_last_iterate_marked_interrupted(pendulum, monkeypatch):
    # A real SIGINT, sent once the solver is under way (after its handler is in place).
    enter = _solve._Stop.__enter__

    def enter_then_interrupt(self):
        out = enter(self)
        threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT)).start()
        return out

    monkeypatch.setattr(_solve._Stop, "__enter__", enter_then_interrupt)
    # a problem that takes IPOPT well over 0.05 s: many nodes, a tight tolerance, a guess far away
    best = optimize(pendulum, **{**SWING, "bounds": {"tau": (-3, 3)}}, nodes=400, t_guess=None)
    assert best.status == "interrupted" and not best.success
    assert "interrupted (Ctrl-C)" in best.message and best.replay is None
    assert np.all(np.isfinite(best.q)) and best.iterations >= 0
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # the handler is given back


def test_a_warm_start_from_the_optimum_needs_few_iterations(pendulum):
    cold = optimize(pendulum, nodes=40, verify=False, **SWING)
    warm = optimize(pendulum, nodes=40, verify=False, warm_start=cold, **SWING)
    assert warm.status == "optimal" and warm.objective == pytest.approx(cold.objective, rel=1e-8)
    assert warm.iterations <= 3 < cold.iterations
    # another parameter value: the previous optimum is a start close to the new one
    heavier = optimize(pendulum, nodes=40, verify=False, warm_start=cold, parameters={"m": 1.02}, **SWING)
    fresh = optimize(pendulum, nodes=40, verify=False, parameters={"m": 1.02}, **SWING)
    assert heavier.objective == pytest.approx(fresh.objective, rel=1e-6)
    assert heavier.iterations < fresh.iterations
    # another mesh: the previous motion serves as a guess
    finer = optimize(pendulum, nodes=60, verify=False, warm_start=cold, **SWING)
    assert finer.status == "optimal" and finer.objective == pytest.approx(cold.objective, rel=1e-3)


def test_a_guess_from_a_simulation_or_a_mapping_is_accepted(pendulum):
    by_simulation = optimize(pendulum, nodes=30, verify=False, guess="simulate", **SWING)
    by_values = optimize(pendulum, nodes=30, verify=False, guess={"theta": np.linspace(0, np.pi, 30)}, **SWING)
    assert by_simulation.status == by_values.status == "optimal"
    assert by_simulation.objective == pytest.approx(by_values.objective, rel=1e-6)
    with pytest.raises(ProblemError, match="Unknown guess"):
        optimize(pendulum, nodes=30, guess="random", **SWING)


def test_objective_terms_weigh_what_they_say(pendulum):
    # Tracking a reference that is itself a solution of the dynamics costs nothing but the effort it needs.
    base = optimize(pendulum, nodes=30, verify=False, **SWING)
    track = Objective(track={"theta": (base.t, base.column("theta"))}, track_weights={"theta": 1e3})
    follow = optimize(pendulum, t_end=3.0, initial={"theta": 0, "theta_dot": 0}, bounds={"tau": (-5, 5)}, nodes=30,
                      objective=track, verify=False)
    assert follow.status == "optimal" and follow.objective < 1e-6
    assert np.max(np.abs(follow.column("theta") - base.column("theta"))) < 1e-3
    # A terminal cost instead of the final condition: the bob ends near the top, at a price.
    soft = optimize(pendulum, t_end=3.0, initial={"theta": 0, "theta_dot": 0}, bounds={"tau": (-5, 5)}, nodes=30,
                    objective={"effort": 1.0, "terminal": "1e4*(theta - pi)^2 + 1e4*theta_dot^2"}, verify=False)
    assert soft.status == "optimal" and abs(soft.q[-1, 0] - np.pi) < 0.05 and soft.objective < base.objective
    # A path constraint that bites: the speed is kept below what the free optimum reaches.
    top = float(np.max(np.abs(base.qd)))
    slow = optimize(pendulum, nodes=30, verify=False, path=[f"-{0.9 * top} <= theta_dot <= {0.9 * top}"], **SWING)
    assert slow.status == "optimal" and np.max(np.abs(slow.qd)) <= 0.9 * top + 1e-6
    assert slow.objective > base.objective


@pytest.mark.slow
def test_an_input_inside_a_parameter_only_subexpression_is_replayed_right():
    # The C code computes parameter-only subexpressions once per parameter set (2 F l here): the replay
    # must remake them as the input changes, or it would integrate F = 0.
    from lagrangian.model import parse_model

    text = (EXAMPLES_DIR / "torque_pendulum.toml").read_text(encoding="utf-8").replace(
        'motor = { torque = "tau*R0.y"', 'motor = { torque = "2*tau*l*R0.y"')
    eom = lagrangian.derive(parse_model(text))
    best = optimize(eom, nodes=30, **{**SWING, "bounds": {"tau": (-2.5, 2.5)}})
    assert best.status == "optimal" and best.replay.within and best.replay.max_error < 1e-3


def test_conditions_must_be_mappings(pendulum):
    with pytest.raises(ProblemError, match="`initial` must map names to values, not list"):
        optimize(pendulum, t_end=1.0, initial=[0, 0])


def test_without_casadi_the_error_says_how_to_install_it(monkeypatch):
    import sys

    from lagrangian.errors import OptimizationError
    from lagrangian.optimal._casadi import casadi

    monkeypatch.setitem(sys.modules, "casadi", None)  # import casadi now raises ImportError
    with pytest.raises(OptimizationError, match=r"pip install 'lagrangian\[optimize\]'"):
        casadi()
