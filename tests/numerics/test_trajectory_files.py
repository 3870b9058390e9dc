"""`load_trajectory` reads back what `save_trajectory` wrote (CSV and NPZ), and refuses what it did not."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from lagrangian_test_support import eom_of

import lagrangian
from lagrangian.errors import OutputError
from lagrangian.numerics import reaction_columns_along


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_a_saved_trajectory_reads_back(tmp_path, suffix):
    eom = eom_of("lagrange_top.toml")
    traj = lagrangian.simulate(eom, 0.2, n_out=21)
    traj = replace(traj, extra=reaction_columns_along(eom, traj))
    path = lagrangian.save_trajectory(traj, tmp_path / f"top{suffix}")
    back = lagrangian.load_trajectory(path)
    assert back.coordinates == traj.coordinates and back.model_name == traj.model_name
    for name in ("t", "q", "qd", "qdd"):
        np.testing.assert_array_equal(getattr(back, name), getattr(traj, name))  # 17 digits: nothing lost
    assert set(back.monitors) == set(traj.monitors) and set(back.extra) == set(traj.extra)
    assert dict(back.parameters) == dict(traj.parameters) and back.integrals == traj.integrals


@pytest.mark.parametrize("name, content, message", [
    ("x.txt", "1,2", "suffix"),
    ("x.csv", "t,theta\n0,1\n", "not a trajectory"),
    ("y.csv", '# metadata: {"format": "other"}\nt\n0\n', "not a lagrangian trajectory"),
])
def test_other_files_are_refused(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(OutputError, match=message):
        lagrangian.load_trajectory(path)
    with pytest.raises(OutputError, match="does not exist"):
        lagrangian.load_trajectory(tmp_path / "missing.npz")
