"""The Whipple bicycle benchmark: examples/whipple_bicycle.toml linearized about upright straight-ahead
motion against the published equations of Meijaard, Papadopoulos, Ruina & Schwab (2007), Proc. R. Soc. A
463, 1955–1982 (tests/reference/_whipple.py), and against the same bicycle built with SymPy's KanesMethod
and linearized by SymPy (tests/reference/_sympy_bicycle.py).
"""

from __future__ import annotations

import functools
import json
import sys
from pathlib import Path

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.analysis import eigenvalue_sweep
from lagrangian.cli.main import main

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _sympy_bicycle  # noqa: E402
import _whipple  # noqa: E402

MODEL = EXAMPLES_DIR / "whipple_bicycle.toml"
LEAN_STEER = ["phi", "delta", "phi_dot", "delta_dot"]
SPEEDS = np.linspace(0.0, 10.0, 21)
#: The issue's tolerance on A (relative to its largest entry) and on the speeds of Table 2.
RTOL_A = 1e-10
TOL_SPEED = 1e-8


@functools.cache
def _eom() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(MODEL))


@functools.cache
def _symbolic_in_v() -> lagrangian.LinearModel:
    return lagrangian.linearize(_eom(), symbolic=("v",))


def _lean_steer(lin: lagrangian.LinearModel, **values: float) -> np.ndarray:
    A, _ = lin.numeric(**values)
    k = [lin.state.index(name) for name in LEAN_STEER]
    return A[np.ix_(k, k)]


def _close(ours: np.ndarray, theirs: np.ndarray, rtol: float = RTOL_A) -> bool:
    return bool(np.max(np.abs(ours - theirs)) <= rtol * np.max(np.abs(theirs)))


def test_the_reference_closed_forms_give_the_published_matrices():
    # _whipple's Appendix-A formulas against the numbers the paper prints (15 digits).
    m = _whipple.matrices()
    for key, published in _whipple.PUBLISHED.items():
        np.testing.assert_allclose(m[key], published, rtol=0, atol=1e-13 * np.abs(published).max())


@pytest.mark.slow
def test_the_model_describes_the_benchmark():
    eom = _eom()
    assert eom.coordinates == ("x", "y", "psi", "phi", "thetaB", "delta", "thetaR", "thetaF")
    kinds = {row.name: row.kind for row in eom.constraints}
    # The pitch is fixed by the front contact (holonomic); each wheel rolls without slip (two rows each).
    assert kinds == {"front_contact": "holonomic", "rear_rolling_x1": "nonholonomic",
                     "rear_rolling_y1": "nonholonomic", "front_rolling_x1": "nonholonomic",
                     "front_rolling_y1": "nonholonomic"}
    lin = lagrangian.linearize(eom, parameters={"v": 5.0})
    assert lin.dependent_coordinates == ("thetaB",)
    assert set(lin.speeds) == {"phi_dot", "delta_dot", "thetaR_dot"}
    assert set(LEAN_STEER) <= set(lin.state)
    # The steady motion: straight ahead at v, the wheels rolling (rates −v/r), no pitch rate.
    values = {p.name: p.value for p in eom.model.parameters}
    point = {k: float(v.subs({}) if hasattr(v, "subs") else v) for k, v in lin.point.items()}
    assert point["x_dot"] == pytest.approx(5.0, rel=1e-14)
    assert point["thetaR_dot"] == pytest.approx(-5.0 / values["rR"], rel=1e-14)
    assert point["thetaF_dot"] == pytest.approx(-5.0 / values["rF"], rel=1e-14)
    assert point["thetaB_dot"] == pytest.approx(0.0, abs=1e-14)


@pytest.mark.slow
@pytest.mark.parametrize("v", SPEEDS)
def test_lean_and_steer_rows_of_A_are_the_papers(v):
    # A for (φ, δ, φ̇, δ̇) = [[0, I], [−M⁻¹(g K0 + v² K2), −M⁻¹ v C1]] (eq. (A 1)), at this speed and from A(v).
    theirs = _whipple.state_matrix(v)
    assert _close(_lean_steer(lagrangian.linearize(_eom(), parameters={"v": float(v)})), theirs)
    assert _close(_lean_steer(_symbolic_in_v(), v=float(v)), theirs)
    # Nothing else acts on lean and steer: their rows are zero in every other column.
    lin = lagrangian.linearize(_eom(), parameters={"v": float(v)})
    A, _ = lin.numeric()
    rows = [lin.state.index(n) for n in LEAN_STEER]
    others = [k for k, n in enumerate(lin.state) if n not in LEAN_STEER]
    assert np.max(np.abs(A[np.ix_(rows, others)])) <= 1e-12 * np.max(np.abs(A))


@pytest.mark.slow
def test_cli_json_reproduces_the_papers_A(capsys):
    for v in (0.0, 4.0, 10.0):
        assert main(["linearize", str(MODEL), "--set", f"v={v}", "--json"]) == 0
        doc = json.loads(capsys.readouterr().out)
        assert set(LEAN_STEER) <= set(doc["state"])
        k = [doc["state"].index(name) for name in LEAN_STEER]
        A = np.array(doc["A"], dtype=float)[np.ix_(k, k)]
        assert _close(A, _whipple.state_matrix(v))


@pytest.mark.slow
def test_sympy_kanes_method_gives_the_same_A():
    # The same bicycle built with SymPy's KanesMethod and linearized by SymPy (nothing of lagrangian).
    for v, theirs in zip(range(11), _sympy_bicycle.linearized_A(range(11)), strict=True):
        assert _close(_lean_steer(_symbolic_in_v(), v=float(v)), theirs)


def test_eigenvalues_at_5_m_per_s_are_the_papers():
    lam = np.sort_complex(_symbolic_in_v().modes(v=5.0).eigenvalues)
    theirs = np.sort_complex(np.linalg.eigvals(_whipple.state_matrix(5.0)))
    np.testing.assert_allclose(lam, theirs, rtol=1e-10)
    assert _symbolic_in_v().stability(v=5.0).stable is True


def test_sweep_finds_the_speeds_of_table_2():
    s = eigenvalue_sweep(_symbolic_in_v(), "v", np.arange(0.0, 10.0 + 1e-9, 0.01))
    found = {c.kind: c.value for c in s.changes}
    assert abs(found["eigenvalues become complex"] - _whipple.V_WEAVE_REAL) < 5e-7  # the paper gives 6 digits
    assert abs(found["stability gained"] - _whipple.V_WEAVE) < TOL_SPEED
    assert abs(found["stability lost"] - _whipple.V_CAPSIZE) < TOL_SPEED
    # Self-stable exactly between the weave and capsize speeds.
    inside = (s.values > _whipple.V_WEAVE) & (s.values < _whipple.V_CAPSIZE)
    assert np.all(s.stable[inside] == 1.0) and np.all(s.stable[~inside] == 0.0)


@pytest.mark.slow
def test_cli_modes_sweep_draws_the_figure_and_reports_the_speeds(tmp_path, capsys):
    assert main(["modes", str(MODEL), "--sweep", "v=0:10:0.01", "--plot", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "v = 4.2923825" in out and "v = 6.0242620" in out and "v = 0.68428" in out
    assert (tmp_path / "eigenvalues.png").stat().st_size > 10_000
