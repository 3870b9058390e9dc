"""`save_plots`: every example writes its figures and animation; a failed write harms nothing."""

from __future__ import annotations

import os
import struct

import pytest
from lagrangian_test_support import example_names
from matplotlib.figure import Figure
from PIL import Image

from lagrangian.errors import OutputError
from lagrangian.plotting import KINDS, applicable_kinds, save_figure, save_plots
from lagrangian.plotting._save import figure_name

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: Figures at 30 dpi: from 81 pixels (the 2.7 in high time series of one coordinate) to a few hundred.
MIN_SIDE, MAX_SIDE = 75, 2000

#: What the classic examples must draw: the top its apex figures and R_O, planar pendulums no apex.
EXPECTED = {
    "lagrange_top.toml": ["time_series", "phase", "apex_sphere", "nutation", "drift", "reaction_O"],
    "double_pendulum.toml": ["time_series", "phase", "drift", "reaction_O"],
    "simple_pendulum.toml": ["time_series", "phase", "drift", "reaction"],
    "spherical_pendulum.toml": ["time_series", "phase", "drift", "reaction"],
    "cart_pendulum.toml": ["time_series", "phase", "drift", "reaction"],
    # Complementary constraints: the reaction plot shows the multipliers' reactions.
    "pendulum_tension.toml": ["time_series", "phase", "drift", "reaction"],
    "rolling_disk_incline.toml": ["time_series", "phase", "drift", "reaction"],
    # The coin's axis of symmetry is its axle, which stays horizontal (a great circle): no apex figures.
    "rolling_coin.toml": ["time_series", "phase", "drift", "reaction"],
    "top_reaction.toml": ["time_series", "phase", "apex_sphere", "nutation", "drift", "reaction"],
}


def test_expected_examples_exist(examples):
    assert set(EXPECTED) <= set(examples)


@pytest.mark.slow
@pytest.mark.parametrize("name", example_names())
def test_every_example_writes_its_plots(run, name, tmp_path):
    eom, traj = run(name)
    written = save_plots(traj, eom, tmp_path / "plots", frames=3, dpi=30)
    stems = [figure_name(kind, eom) for kind in applicable_kinds(traj, eom)]
    assert stems[:2] == ["time_series", "phase"] and "drift" in stems
    if name in EXPECTED:
        assert stems == EXPECTED[name]
    assert [p.name for p in written] == [f"{stem}.png" for stem in stems] + ["animation.gif"]
    assert sorted(p.name for p in (tmp_path / "plots").iterdir()) == sorted(p.name for p in written)
    for path in written[:-1]:
        data = path.read_bytes()
        assert data[:8] == PNG_SIGNATURE
        width, height = struct.unpack(">II", data[16:24])  # the IHDR chunk
        assert MIN_SIDE <= width <= MAX_SIDE and MIN_SIDE <= height <= MAX_SIDE, (path.name, width, height)
        with Image.open(path) as im:
            im.verify()
    with Image.open(written[-1]) as im:
        assert im.format == "GIF" and im.n_frames == 3
        assert MIN_SIDE <= min(im.size)


@pytest.mark.slow
def test_formats_and_kinds(run, tmp_path):
    eom, traj = run("simple_pendulum.toml")
    written = save_plots(traj, eom, tmp_path, animation=False, formats=("svg", "pdf"), kinds=("phase",))
    assert [p.name for p in written] == ["phase.svg", "phase.pdf"]
    assert written[0].read_bytes().lstrip().startswith(b"<?xml")
    assert written[1].read_bytes().startswith(b"%PDF")


def test_applicable_kinds_are_known(run):
    eom, traj = run("lagrange_top.toml")
    assert set(applicable_kinds(traj, eom)) == set(KINDS)


def test_unknown_format_kind_or_animation(run, tmp_path):
    eom, traj = run("simple_pendulum.toml")
    with pytest.raises(OutputError, match="bmp"):
        save_plots(traj, eom, tmp_path, formats=("bmp",))
    with pytest.raises(OutputError, match="sketch"):
        save_plots(traj, eom, tmp_path, kinds=("sketch",))
    with pytest.raises(OutputError, match="avi"):
        save_plots(traj, eom, tmp_path, animation_format="avi")
    assert not list(tmp_path.iterdir())


def test_failed_write_leaves_the_existing_file_intact(run, tmp_path, monkeypatch):
    eom, traj = run("simple_pendulum.toml")
    old = tmp_path / "time_series.png"
    old.write_bytes(b"the plot of yesterday")

    def broken_savefig(self, handle, **kwargs):
        handle.write(b"half a plot")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Figure, "savefig", broken_savefig)
    with pytest.raises(OutputError, match="No space left on device") as info:
        save_plots(traj, eom, tmp_path, animation=False)
    assert "older file is unchanged" in str(info.value)
    assert old.read_bytes() == b"the plot of yesterday"
    assert [p.name for p in tmp_path.iterdir()] == ["time_series.png"]  # no temporary file left


def test_failed_animation_leaves_the_existing_file_intact(run, tmp_path, monkeypatch):
    from PIL import Image as PILImage

    eom, traj = run("simple_pendulum.toml")
    old = tmp_path / "animation.gif"
    old.write_bytes(b"GIF89a yesterday")

    def broken_save(self, fp, *args, **kwargs):
        fp.write(b"GIF89a half")
        raise OSError(5, "Input/output error")

    monkeypatch.setattr(PILImage.Image, "save", broken_save)
    with pytest.raises(OutputError, match="Input/output error"):
        save_plots(traj, eom, tmp_path, kinds=(), frames=3, dpi=30)
    assert old.read_bytes() == b"GIF89a yesterday"
    assert [p.name for p in tmp_path.iterdir()] == ["animation.gif"]


def test_unwritable_folder(run, tmp_path):
    eom, traj = run("simple_pendulum.toml")
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(OutputError, match="folder"):
        save_plots(traj, eom, blocker / "plots", animation=False)
    with pytest.raises(OutputError, match="Cannot write"):
        save_figure(Figure(), blocker / "x.png")


def test_save_figure_refuses_unknown_suffix(tmp_path):
    with pytest.raises(OutputError, match="unknown image format"):
        save_figure(Figure(), tmp_path / "x.bmp")
    assert not os.listdir(tmp_path)
