"""Declared ranges and the signs the derivation used, checked along a motion.

Truth: the closed form of the harmonic oscillator, x(t) = x0 cos ωt + (v0/ω) sin ωt with
ω = √(k/m), for the mass on a spring fixed to a wall at x = −L.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from lagrangian_test_support import wall_spring

import lagrangian
from lagrangian import ModelError
from lagrangian.numerics._files import save_trajectory

SPRING = wall_spring(0.4)


@pytest.fixture(scope="module")
def eom() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(SPRING, source="spring.toml"))


@pytest.mark.slow
def test_a_motion_within_its_range_says_nothing(eom) -> None:
    traj = lagrangian.simulate(eom, 5.0, n_out=201)
    assert traj.range_exits == () and not any("range" in w for w in traj.warnings)
    assert np.allclose(traj.q[:, 0], 0.4 * np.cos(np.sqrt(2.0) * traj.t), atol=1e-8)


def test_leaving_the_range_is_named_with_its_time_and_value(eom, tmp_path) -> None:
    x0, v0, w = 0.45, 1.0, np.sqrt(2.0)
    traj = lagrangian.simulate(eom, 3.0, n_out=301, initial={"x": x0, "x_dot": v0})
    (exit_,) = traj.range_exits
    # The first crossing of x = 0.5 by the closed form, and the amplitude.
    t = np.linspace(0.0, 3.0, 300001)
    exact = x0 * np.cos(w * t) + v0 / w * np.sin(w * t)
    crossing = t[np.argmax(exact > 0.5)]
    assert exit_.kind == "range" and exit_.name == "x" and exit_.bounds == "[-0.5, 0.5]"
    assert crossing <= exit_.t < crossing + 0.01 + 1e-12 and exit_.value > 0.5
    assert exit_.extreme == pytest.approx(np.hypot(x0, v0 / w), abs=1e-4)
    (warning,) = [w for w in traj.warnings if "range" in w]
    assert "coordinate `x` left its declared range [-0.5, 0.5] at t = " in warning
    path = save_trajectory(traj, tmp_path / "run.csv")
    meta = next(line for line in path.read_text().splitlines() if line.startswith("# metadata: "))
    (saved,) = json.loads(meta[len("# metadata: "):])["range_exits"]
    assert saved["name"] == "x" and saved["t"] == exit_.t and saved["value"] == exit_.value


def test_a_sign_the_derivation_used_is_checked_with_the_run_values(eom) -> None:
    # With L = 0.3 the mass can cross the wall (x + L < 0), where −k x is no longer the spring's force.
    traj = lagrangian.simulate(eom, 5.0, n_out=501, parameters={"L": 0.3}, initial={"x": 0.45, "x_dot": 1.0})
    kinds = {e.kind: e for e in traj.range_exits}
    assert set(kinds) == {"range", "assumption"}
    broken = kinds["assumption"]
    assert broken.bounds == "L + x ≥ 0" and broken.value < 0
    assert any("the assumption L + x ≥ 0 that the derivation used no longer holds" in w for w in traj.warnings)


def test_a_value_against_a_declared_sign_is_refused(eom) -> None:
    with pytest.raises(ModelError, match=r"parameter `L` is declared positive \(L > 0\), but its value is -1"):
        lagrangian.simulate(eom, 1.0, parameters={"L": -1.0})
