"""The pace check (`lg_pace_hopeless` in ``codegen/runtime/integrators.c``): a run that ``max_steps`` cannot see through
is stopped as soon as that is plain, with the same error ``max_steps`` would give at the end.

An undamped spring of 1e16 N/m on 1 kg (ω = 1e8 rad/s) is not stiff in Hairer's sense: the step
is held by accuracy, about 19 steps a period at the default tolerances.  Over 1 s that is some
3e8 steps, more than the default 1e8; the run used to crawl for minutes (a fuzz case
took 100 s with ``stiffness = "exp(k)"``) and is now stopped after two windows of 2^20 steps.
The projection is checked against the steps the same oscillator takes over 1000 periods.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from lagrangian_test_support import mutated_example

import lagrangian
from lagrangian import SimulationError

ROOT = Path(__file__).resolve().parents[2]
WINDOW = 2**20
PERIOD = 2 * math.pi / 1e8  # of the oscillator below: ω = √(k/m) = 1e8 rad/s

OSCILLATOR = """
[parameters]
m = 1.0
k = 1e16
[coordinates]
x = { initial = 1e-3, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = { spring = ["O", "P"], stiffness = "k", rest_length = "0" }
"""


@pytest.fixture(scope="module")
def oscillator(tmp_path_factory):
    path = tmp_path_factory.mktemp("pace") / "oscillator.toml"
    path.write_text(OSCILLATOR, encoding="utf-8")
    return lagrangian.compile_system(lagrangian.derive(lagrangian.load_model(path)))


@pytest.fixture(scope="module")
def steps_per_period(oscillator) -> float:
    traj = lagrangian.simulate(oscillator, 1000 * PERIOD, n_out=3)
    assert traj.status == "completed"
    return traj.steps / 1000


@pytest.mark.slow
def test_a_run_max_steps_cannot_finish_stops_after_two_windows(oscillator, steps_per_period) -> None:
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(oscillator, 1.0, n_out=3)
    err = info.value
    needed = steps_per_period / PERIOD  # steps for 1 s at the pace of a completed run
    assert needed > 1e8  # the premise: the default max_steps cannot finish it
    part = err.trajectory
    assert part is not None and "(partial)" in part.status
    assert part.steps == 2 * WINDOW  # not 1e8
    projected = float(err.message.split("would need about ")[1].split(" steps")[0])
    assert projected == pytest.approx(needed, rel=0.02)
    assert "max_steps (100000000)" in err.message and "raise max_steps" in err.fix
    assert 0 < err.t < 0.01


@pytest.mark.slow
def test_a_run_that_fits_in_max_steps_is_not_stopped(oscillator, steps_per_period) -> None:
    # About 2.6 windows of steps, with max_steps a little above: every projection is below it.
    periods = round(2.6 * WINDOW / steps_per_period)
    traj = lagrangian.simulate(oscillator, periods * PERIOD, n_out=3, max_steps=int(3.0 * WINDOW))
    assert traj.status == "completed" and traj.steps > 2 * WINDOW


def test_a_fixed_step_knows_its_count_at_once(oscillator) -> None:
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(oscillator, 1.0, n_out=3, method="gauss-legendre", dt=1e-9)
    assert info.value.trajectory.steps == 0 and "would need about 1e+09 steps" in info.value.message
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(oscillator, 1.0, n_out=3, dt=1e-9)  # dop853 at a fixed step
    assert info.value.trajectory.steps == 0 and "would need about 1e+09 steps" in info.value.message


@pytest.mark.slow
def test_the_fuzz_case_of_an_undamped_spring_of_exp_40(tmp_path: Path) -> None:
    # tools/fuzz.py seed 102, case 20375: examples/cart_pendulum.toml with stiffness = "exp(k)",
    # k = 40 (2.4e17 N/m): 100 s to reach max_steps; now the error after 2^21 steps.
    path = mutated_example(tmp_path, "cart_pendulum.toml", 'stiffness = "k"', 'stiffness = "exp(k)"')
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(lagrangian.derive(lagrangian.load_model(path)), 0.3, n_out=7)
    assert "would need about" in info.value.message and info.value.trajectory.steps == 2 * WINDOW


def test_the_control_block_has_the_size_the_c_side_copies() -> None:
    # lg_batch copies C_SIZE doubles from the block control_block makes: a shorter one would be read past its end.
    import re

    from lagrangian.codegen import runtime_source
    from lagrangian.numerics import _control

    source = runtime_source("integrators.c")
    names = re.search(r"enum \{ (C_T,[^}]*)\}", source).group(1)
    entries = [name.strip() for name in names.split(",")]
    assert entries.index("C_SIZE") == _control.CONTROL_SIZE
    ctl = _control.control_block("dop853", 0.0, 1.0, [0.0, 1.0], 1e-9, 1e-9, None, None, 10)
    assert ctl.shape == (_control.CONTROL_SIZE,)
