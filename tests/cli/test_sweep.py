"""``lagrangian sweep``: grids, maps, Ctrl-C and --resume."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

xr = pytest.importorskip("xarray")
pytest.importorskip("zarr")

from lagrangian_test_support import interrupt_when_started  # noqa: E402

from lagrangian import EventSpec, lagrange_top, load_model  # noqa: E402
from lagrangian.cli._settings import SettingError  # noqa: E402
from lagrangian.cli._sweep import parse_grid  # noqa: E402
from lagrangian.cli.main import main  # noqa: E402
from lagrangian.numerics import _compile, flip_events, open_ensemble, simulate  # noqa: E402

SRC = str(Path(_compile.__file__).resolve().parents[2])
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("item, message", [
    ("theta=0:1", "NAME=START:STOP:COUNT"),
    ("theta=0:1e400:3", "finite"),
    ("theta=__import__('os'):1:3", "plain decimal"),
    ("theta=0:1:2.5", "whole number"),
    ("theta=0:1:٣", "whole number"),
    ("spin=0:1:3", "not a parameter"),
])
def test_bad_grid_axes_are_refused(item, message):
    with pytest.raises(SettingError, match=message):
        parse_grid([item], lagrange_top())


@pytest.mark.slow
def test_two_axes_draw_the_flip_map_and_the_store_reads_back(tmp_path, capsys):
    out, image = tmp_path / "flip.zarr", tmp_path / "flip.png"
    code = main(["sweep", str(EXAMPLES / "double_pendulum.toml"), "--grid", "theta1=-3:3:6", "--grid",
                 "theta2=2:3:3", "--t-end", "4", "--stop-when", "flip", "--out", str(out), "--plot", str(image),
                 "--n-out", "5", "--workers", "2"])
    assert code == 0, capsys.readouterr().err
    assert image.stat().st_size > 10_000 and image.read_bytes()[:4] == b"\x89PNG"
    ds = open_ensemble(out)
    assert ds.status.dims == ("theta1", "theta2")
    # The member theta1 = 3, theta2 = 3 (arm 2 started near the top): its first flip, as simulate finds it.
    m = ds.sel(theta1=3.0, theta2=3.0)
    first = np.nanmin(m.event_time.values)
    model = load_model(EXAMPLES / "double_pendulum.toml")
    flips = [EventSpec(e.name, e.expression, e.direction, terminal=True) for e in flip_events(model)]
    tr = simulate(model, 4, initial={"theta1": 3.0, "theta2": 3.0}, n_out=5, events=flips)
    assert first == pytest.approx(tr.events[0].t, rel=1e-13) and m.t_final.item() == first
    assert "wrote" in capsys.readouterr().out


@pytest.mark.slow
def test_an_existing_store_is_not_overwritten(tmp_path, capsys):
    out = tmp_path / "s.zarr"
    args = ["sweep", "zoo:lagrange_top", "--grid", "phi_dot=20:40:3", "--t-end", "0.2", "--out", str(out)]
    assert main(args) == 0
    assert main(args) == 3
    assert "already exists" in capsys.readouterr().err


@pytest.mark.slow
def test_ctrl_c_keeps_finished_members_and_resume_finishes(tmp_path):
    env = {**os.environ, "PYTHONPATH": SRC, "LAGRANGIAN_CACHE": str(tmp_path / "cache")}
    out = tmp_path / "tops.zarr"
    args = [sys.executable, "-m", "lagrangian.cli.main", "sweep", "zoo:lagrange_top", "--grid",
            "phi_dot=30:80:1500", "--t-end", "10", "--n-out", "11", "--out", str(out), "--workers", "2"]
    seen = interrupt_when_started(args + ["--progress"], env, b"members", delay=0.2)
    stderr = seen.process.stderr
    assert seen.process.returncode == 130, stderr
    assert seen.said is not None and seen.said < 1.0, "the one-line message comes within a second"
    assert seen.stopped < 3.0 and "Traceback" not in stderr
    last = stderr.replace("\r", "\n").strip().splitlines()[-1]
    assert last.startswith("lagrangian: interrupted after ") and "finish with --resume" in last, last
    partial = xr.open_zarr(out)  # the store opens, and says which members are done
    status = partial.status.values
    assert (status == -1).any() and (status == 0).any()
    done = np.flatnonzero(status == 0)[:1]
    resumed = subprocess.run(args + ["--resume"], capture_output=True, text=True, env=env, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    final = open_ensemble(out)
    assert (final.status.values == 0).all()
    # Rows finished before the interruption are kept as they were; rows finished by the resume match simulate.
    np.testing.assert_array_equal(final.state_final.values[done], partial.state_final.values[done])
    k = int(np.flatnonzero(status == -1)[-1])
    tr = simulate(lagrange_top(), 10, initial={"phi_dot": float(final.phi_dot.values[k])}, n_out=11)
    np.testing.assert_array_equal(final.state_final.values[k, :3], tr.q[-1])
