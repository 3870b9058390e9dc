"""Models whose equations are not defined at the initial state (found by tools/fuzz.py).

``rotation = ["phi^phi", "z"]`` with phi = 0 puts log(0) in M: the eigenvalue check of the
initial state met a matrix of nan and raised NumPy's `LinAlgError`.  Now a `SimulationError`
names the entries that are not finite and the state.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from lagrangian_test_support import mutated_example

import lagrangian
from lagrangian import SimulationError
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
@pytest.mark.parametrize("example", ["lagrange_top.toml", "top_reaction.toml"])
def test_m_not_finite_at_the_start_is_a_simulation_error(tmp_path: Path, example: str) -> None:
    path = mutated_example(tmp_path, example, 'rotation = ["phi", "z"]', 'rotation = ["phi^phi", "z"]')
    eom = lagrangian.derive(lagrangian.load_model(path))
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(eom, 0.1, n_out=3)
    assert "not finite" in info.value.message and "initial state" in info.value.message
    assert "M[" in info.value.message and info.value.fix


def test_the_command_line_says_it_in_one_message(tmp_path: Path, capsys) -> None:
    path = mutated_example(tmp_path, "lagrange_top.toml", 'rotation = ["phi", "z"]', 'rotation = ["phi^phi", "z"]')
    assert main(["simulate", str(path), "--t-end", "0.1"]) == 4
    err = capsys.readouterr().err
    assert "not finite" in err and "Traceback" not in err


# -- gauss-legendre's step -------------------------------------------------------
STIFF = """\
[model]
name = "Stiff spring"

[parameters]
m = 1.0
k = 1e8

[coordinates]
x = { initial = 0.1, rate = 0.0 }

[particles.P]
mass = "m"
position = "x*R0.x"

[loads]
spring = { potential = "k*x^2/2" }
"""


def test_gauss_legendre_default_step_runs_the_top_for_1000_s() -> None:
    # 1/10 of the output spacing (dt = 0.1) stopped at t = 13.1: the spin phi_dot ~ 48 rad/s turns
    # too far in one step for the implicit stages to converge; the step is now halved until they do.
    eom = lagrangian.derive(lagrangian.load_model(ROOT / "examples" / "lagrange_top.toml"))
    traj = lagrangian.simulate(eom, 1000.0, method="gauss-legendre")
    assert traj.t[-1] == 1000.0 and traj.status == "completed"
    assert traj.steps % 10_000 == 0 and traj.steps > 10_000  # fixed steps that divide the spacing
    assert max(abs(d) for d in traj.drift.values()) < 1e-5


@pytest.mark.slow
def test_a_stiff_spring_says_reduce_dt_and_the_default_step_adapts(tmp_path: Path, capsys) -> None:
    path = tmp_path / "stiff.toml"
    path.write_text(STIFF, encoding="utf-8")
    assert main(["simulate", str(path), "--method", "gauss-legendre", "--t-end", "1", "--dt", "0.001"]) == 4
    err = capsys.readouterr().err
    assert "reduce the step" in err and "--dt 0.0001" in err and "check the model" not in err
    eom = lagrangian.derive(lagrangian.load_model(path))
    traj = lagrangian.simulate(eom, 1.0, method="gauss-legendre", n_out=11)
    assert traj.status == "completed" and max(abs(d) for d in traj.drift.values()) < 1e-6


def test_finite_numbers_that_overflow_once_multiplied_are_a_model_error(tmp_path: Path) -> None:
    # Found by tools/fuzz.py: 1e308 is a finite double, but T has its square; code generation
    # raised a bare ValueError ("non-finite number inf").
    path = mutated_example(tmp_path, "block_on_incline.toml", 'position = "x*I.x"', 'position = "(x*I.x)*1e308"')
    eom = lagrangian.derive(lagrangian.load_model(path))
    with pytest.raises(lagrangian.ModelError) as info:
        lagrangian.compile_system(eom)
    assert "overflow a double" in info.value.message and info.value.fix


def test_first_integrals_of_a_rotation_through_abs(tmp_path: Path) -> None:
    # Found by tools/fuzz.py: SymEngine cannot evaluate d|theta|/dtheta numerically ("Not
    # Implemented"); the identity test now leaves such an expression "not shown zero".
    path = mutated_example(tmp_path, "lagrange_top.toml", 'rotation = ["theta", "x"]', 'rotation = ["abs(theta)", "x"]')
    eom = lagrangian.derive(lagrangian.load_model(path))
    names = {i.name for i in lagrangian.first_integrals(eom)}
    assert {"K", "H"} <= names  # psi and phi stay cyclic


def test_a_noether_candidate_that_overflows_is_not_taken_as_independent() -> None:
    # Found by tools/fuzz.py (the Whipple bicycle without its constraints): values past 1e308 at
    # the random states made NumPy's SVD fail inside the rank test.
    import symengine as se

    from lagrangian.analysis._noether import _independent

    eom = lagrangian.derive(lagrangian.load_model(ROOT / "examples" / "simple_pendulum.toml"))
    candidate = se.exp(se.exp(se.exp(eom.qd[0] + 10)))
    assert _independent(eom, [], candidate) is False


@pytest.mark.slow
def test_nonholonomic_integrals_of_a_rotation_through_asin(tmp_path: Path) -> None:
    # Found by tools/fuzz.py (campaign seed 101, case 1578): asin(phi) in the disk's rotation is not
    # real at the random sample point of the rolling constraint's rows (phi > 1); SymEngine's
    # float() raised "Not Implemented" in `first_integrals` and in `derive` on the command line.
    path = mutated_example(tmp_path, "rolling_disk_incline.toml", 'rotation = ["phi", "y"]',
                           'rotation = ["asin(phi)", "y"]')
    eom = lagrangian.derive(lagrangian.load_model(path))
    lagrangian.first_integrals(eom)  # no error; no speed claimed constant from a complex sample
    assert main(["derive", str(path)]) == 0


@pytest.mark.slow
def test_a_rotation_through_abs_compiles_with_the_sign_of_its_angle(tmp_path: Path) -> None:
    # Found by tools/fuzz.py (seed 101, case 7230): SymEngine leaves d|psi|/dpsi unevaluated and the C
    # printer raised a bare ValueError in `compile`. d|u|/du is sign(u), its higher derivatives 0.
    import numpy as np

    path = mutated_example(tmp_path, "spherical_pendulum.toml", 'rotation = ["psi", "z"]',
                           'rotation = ["abs(psi)", "z"]')
    eom = lagrangian.derive(lagrangian.load_model(path))
    plain = lagrangian.derive(lagrangian.load_model(ROOT / "examples" / "spherical_pendulum.toml"))
    start = {"psi": 0.4, "psi_dot": 0.7}  # psi > 0: |psi| = psi, the same motion as the example's
    ours = lagrangian.simulate(eom, 0.5, n_out=6, initial=start)
    ref = lagrangian.simulate(plain, 0.5, n_out=6, initial=start)
    np.testing.assert_allclose(ours.q, ref.q, rtol=1e-9, atol=1e-9)
    with pytest.raises(SimulationError, match="singular"):  # at psi = 0, sign(0) = 0: no inertia along psi
        lagrangian.simulate(eom, 0.5, n_out=6, initial={"psi": 0.0})


def test_a_backslash_in_an_axis_name_is_refused_at_load(tmp_path: Path) -> None:
    # Found by tools/fuzz.py (seed 101, case 6195): axes = ["x1", "\\y1", "z0"] was accepted, then a
    # regular-expression template met `\y` in `derive`'s text (re.error). Axis names are identifiers.
    path = mutated_example(tmp_path, "rolling_coin.toml", 'axes = ["x1", "y1", "z0"]', 'axes = ["x1", "\\\\y1", "z0"]')
    with pytest.raises(lagrangian.ModelError, match="is not a name") as info:
        lagrangian.load_model(path)
    assert info.value.line == 32
    assert main(["derive", str(path)]) == 2


@pytest.mark.slow
def test_linearize_with_a_denormal_mass_is_a_clean_error(tmp_path: Path) -> None:
    # Found by tools/fuzz.py (seed 101, case 5296): mass = "5e-324" made NumPy's SVD fail inside
    # the rank test of M; `equilibria` printed a traceback. Now a LinearizationError, and the
    # equilibria are still listed.
    from lagrangian.analysis import LinearizationError

    path = mutated_example(tmp_path, "cart_pendulum.toml", 'mass = "m"', 'mass = "5e-324"')
    eom = lagrangian.derive(lagrangian.load_model(path))
    with pytest.raises(LinearizationError):
        lagrangian.linearize(eom, {"x": 0.0, "theta": 0.0})
    assert main(["equilibria", str(path)]) == 0
