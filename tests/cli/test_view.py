"""`lagrangian view` and `simulate --view`, in-process: the page, a saved trajectory, the still, the errors."""

from __future__ import annotations

import json
import re

import pytest
from lagrangian_test_support import EXAMPLES_DIR

from lagrangian.cli.main import main


def _scene(page: str) -> dict:
    data = re.search(r'<script type="application/json" id="lgv-1-data">(.*?)</script>', page, re.DOTALL).group(1)
    return json.loads(data)


def test_a_model_at_rest_and_a_saved_trajectory(tmp_path, capsys):
    model = str(EXAMPLES_DIR / "double_pendulum.toml")
    assert main(["view", model, "-o", str(tmp_path / "rest.html")]) == 0
    rest = _scene((tmp_path / "rest.html").read_text(encoding="utf-8"))
    assert rest["frames"] == 1 and rest["title"] == "Double pendulum"
    assert main(["simulate", model, "--t-end", "0.5", "--n-out", "51", "-o", str(tmp_path / "dp.npz"),
                 "--view", str(tmp_path / "dp.html")]) == 0
    assert f"wrote {tmp_path / 'dp.npz'}, {tmp_path / 'dp.html'}" in capsys.readouterr().out
    assert _scene((tmp_path / "dp.html").read_text(encoding="utf-8"))["frames"] == 51
    assert main(["view", model, str(tmp_path / "dp.npz"), "--trace", "A", "--vector", "V(S2)",
                 "-o", str(tmp_path / "again.html")]) == 0
    again = _scene((tmp_path / "again.html").read_text(encoding="utf-8"))
    assert again["frames"] == 51 and [again["tracks"][k]["name"] for k in again["traces"]] == ["A"]
    assert [a["name"] for a in again["arrows"] if a["shown"]] == ["V(S2)"]


@pytest.mark.slow
def test_a_still_picture(tmp_path):
    assert main(["view", "--set", "theta=0.7", "-o", str(tmp_path / "top.png")]) == 0
    assert (tmp_path / "top.png").read_bytes().startswith(b"\x89PNG\r\n\x1a\n")


def test_mistakes_are_refused_before_any_work(tmp_path, capsys):
    model = str(EXAMPLES_DIR / "simple_pendulum.toml")
    assert main(["simulate", model, "--view", str(tmp_path / "v.gif")]) == 3
    assert "the view is an HTML page" in capsys.readouterr().err
    assert main(["view", model, "-o", str(tmp_path / "v.pdf")]) == 3
    assert main(["view", model, "--ghost", "x.csv"]) == 3
    assert main(["view", model, str(tmp_path / "missing.csv")]) == 3
    assert "does not exist" in capsys.readouterr().err
    assert main(["view", model, "--trace", "Q", "-o", str(tmp_path / "v.html")]) == 3
    assert "no point `Q` to trace" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())
