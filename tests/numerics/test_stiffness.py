"""dop853's stiffness test (Hairer, Nørsett & Wanner, Solving ODEs I, Sec. IV.2; dop853.f).

The cart of examples/cart_pendulum.toml held by a damper of 1e9 N s/m: the cart creeps (at
about F/c ~ 1e-9 m/s) and the pendulum swings as on a fixed point, a smooth solution; but the
Jacobian has an eigenvalue of about -c/m ~ -4e8 /s, so an explicit method's step is held by
stability at h ~ 6/|λ| ~ 1.5e-8 s (10^9 steps for 10 s).  The test stops such a run after
about a thousand steps, saying to use Radau; Radau runs it to the end (checked against the
pendulum on a fixed point).  A spring of 1e16 N/m is stiff in the same sense once the
tolerances let the step reach the stability limit.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian
from lagrangian import SimulationError
from lagrangian.cli.main import main
from lagrangian.numerics import _control

ROOT = Path(__file__).resolve().parents[2]


def _stiff_cart(tmp_path: Path, k: str = "40.0", c: str = "1e9") -> Path:
    """examples/cart_pendulum.toml with the stiffness k and a damper c alongside the spring."""
    text = (ROOT / "examples" / "cart_pendulum.toml").read_text(encoding="utf-8")
    old = 'k = { value = 40.0,'
    assert old in text
    text = text.replace(old, f'k = {{ value = {k},')
    text = text.replace("[coordinates]", f"c = {{ value = {c} }}\n\n[coordinates]")
    text += 'damper = { damper = ["W", "C"], coefficient = "c" }\n'
    path = tmp_path / f"stiff_cart_{k}_{c}.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def stiff_eom(tmp_path_factory):
    return lagrangian.derive(lagrangian.load_model(_stiff_cart(tmp_path_factory.mktemp("stiff"))))


@pytest.mark.slow
def test_the_stiff_spring_stops_at_once_with_the_fix(stiff_eom) -> None:
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(stiff_eom, 10.0)
    err = info.value
    assert "stiff" in err.message and "6.1" in err.message and "Radau" in err.fix
    assert "stiffness_check=False" in err.fix
    # Tested after 1000 accepted steps, then 15 in a row: a few thousand steps, not 10^9.
    assert err.t is not None and 0 < err.t < 1e-4
    part = err.trajectory
    assert part is not None and "(partial)" in part.status and "stiff" in part.status
    assert 1000 <= part.steps < 3000 and part.t[-1] <= err.t


def test_without_the_test_dop853_goes_on(stiff_eom) -> None:
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(stiff_eom, 10.0, stiffness_check=False, max_steps=5000)
    assert "maximum number of steps" in info.value.message and "stiff" not in info.value.message
    assert info.value.trajectory is not None and "(partial)" in info.value.trajectory.status


@pytest.mark.slow
def test_radau_runs_it_to_the_end_as_a_pendulum_on_a_fixed_point(stiff_eom) -> None:
    traj = lagrangian.simulate(stiff_eom, 2.0, method="Radau", n_out=21)
    assert traj.status == "completed" and traj.t[-1] == 2.0
    # The damper holds the cart (it creeps at ~F/c): theta'' = -(g/l) sin(theta) from theta = 0.4 at rest.
    g, l = 9.81, 0.6
    ref = solve_ivp(lambda t, y: [y[1], -g / l * np.sin(y[0])], (0, 2), [0.4, 0.0], t_eval=traj.t,
                    rtol=1e-12, atol=1e-12)
    theta = traj.q[:, traj.coordinates.index("theta")]
    x = traj.q[:, traj.coordinates.index("x")]
    assert np.max(np.abs(x - 0.1)) < 1e-7
    assert np.max(np.abs(theta - ref.y[0])) < 1e-6


def test_a_stiff_spring_at_loose_tolerances(tmp_path: Path) -> None:
    # k = 1e16 N/m, no damper, the fast vibration not excited (x = 0) and below the tolerances:
    # the step grows to the stability limit h ~ 6/omega, omega = sqrt(k/m) ~ 7e7 /s.
    eom = lagrangian.derive(lagrangian.load_model(_stiff_cart(tmp_path, k="1e16", c="0")))
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(eom, 10.0, initial={"x": 0.0}, rtol=1e-6, atol=1e-6)
    assert "stiff" in info.value.message and info.value.t < 1e-3
    assert info.value.trajectory.steps < 5000


def test_the_command_line_keeps_the_part_computed(tmp_path: Path, capsys) -> None:
    path = _stiff_cart(tmp_path)
    out = tmp_path / "part.csv"
    assert main(["simulate", str(path), "-o", str(out)]) == 4
    err = capsys.readouterr().err
    assert "stiff" in err and "--method Radau" in err and "Traceback" not in err
    assert "--no-stiffness-check" in err and str(out) in err
    assert "(partial)" in out.read_text(encoding="utf-8").splitlines()[0]
    # Switched off, dop853 crawls on at its stable step (~1e-8 s) and reaches a short end.
    whole = tmp_path / "whole.csv"
    assert main(["simulate", str(path), "--no-stiffness-check", "--t-end", "1e-4", "-o",
                 str(whole)]) == 0
    assert "stiff" not in capsys.readouterr().err and "completed" in whole.read_text(encoding="utf-8")


@pytest.mark.parametrize("example, t_end", [("lagrange_top.toml", 200.0), ("double_pendulum.toml", 100.0),
                                            ("cart_pendulum.toml", 100.0), ("spherical_pendulum.toml", 100.0),
                                            ("foucault_pendulum.toml", 300.0)])
def test_non_stiff_models_never_trigger_it(example: str, t_end: float, monkeypatch) -> None:
    # Tested at every step (not every 1000th) over long runs at the default tolerances.
    monkeypatch.setattr(_control, "STIFFNESS_TEST_PERIOD", 1)
    eom = lagrangian.derive(lagrangian.load_model(ROOT / "examples" / example))
    traj = lagrangian.simulate(eom, t_end, n_out=11)
    assert traj.status == "completed" and traj.steps > 2000


def test_an_ensemble_flags_the_stiff_member_and_finishes_the_others(tmp_path: Path) -> None:
    path = _stiff_cart(tmp_path)
    ds = lagrangian.numerics.ensemble(path, 1.0, parameters={"c": [0.0, 1e9, 0.5]}, n_out=11, workers=1)
    from lagrangian.numerics._batch import STATUS

    names = [STATUS[int(s)] for s in ds["status"].values]
    assert names == ["ok", "stiff", "ok"]
    assert float(ds["t_final"][1]) < 1e-4 and int(ds["steps"][1]) < 3000


def test_gauss_legendre_with_too_long_a_step_on_the_stiff_spring_says_reduce_dt(tmp_path: Path, capsys) -> None:
    path = _stiff_cart(tmp_path, k="1e16", c="0")
    assert main(["simulate", str(path), "--method", "gauss-legendre", "--dt", "0.001", "--t-end", "0.01"]) == 4
    err = capsys.readouterr().err
    assert "reduce the step" in err and "--dt 0.0001" in err and "check the model" not in err


def test_a_first_step_that_overflows_is_rejected_not_fatal(tmp_path: Path) -> None:
    # k = 1e16 at rest: the first trial step (h ~ 1e-3 from the slow motion) makes the stages
    # overflow; that step is cut (as an infinite error estimate), where the run used to stop at
    # t = 0 with "the state stopped being finite".  Here the step budget ends it instead.
    eom = lagrangian.derive(lagrangian.load_model(_stiff_cart(tmp_path, k="1e16", c="0")))
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(eom, 10.0, initial={"x": 0.0}, max_steps=2000)
    assert "maximum number of steps" in info.value.message and info.value.t > 0


@pytest.mark.slow
def test_steps_below_1e_14_of_the_span_are_an_underflow_not_a_crawl(tmp_path) -> None:
    # Found by `tools/fuzz.py --format urdf` (seed 203, case 1329): a joint damping of 1e308 needs
    # steps of 1e-309 s; near t = 0 the resolution of t is a denormal, so dop853 crawled until
    # max_steps (minutes). A step below 1e-14 of the span can never finish it: stopped at once.
    from pathlib import Path

    import lagrangian
    from lagrangian import SimulationError

    text = (Path(__file__).resolve().parents[2] / "examples" / "rrr_arm.urdf").read_text(encoding="utf-8")
    path = tmp_path / "arm.urdf"
    path.write_text(text.replace('<dynamics damping="0.2"/>', '<dynamics damping="1e308"/>'), encoding="utf-8")
    eom = lagrangian.derive(lagrangian.load_model(path))
    with pytest.raises(SimulationError, match="stopped at t = 0 ") as info:
        lagrangian.simulate(eom, 0.3, n_out=7, max_steps=10**6)
    assert info.value.trajectory is None or info.value.trajectory.t[-1] == 0.0
