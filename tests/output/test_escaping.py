"""Text from a model file reaches LaTeX and Markdown escaped once, and as text."""

from __future__ import annotations

import re
from pathlib import Path

import lagrangian
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
PENDULUM = (ROOT / "examples" / "simple_pendulum.toml").read_text(encoding="utf-8")


def _model(tmp_path: Path, name: str, description: str, unit: str = "kg") -> Path:
    text = re.sub(r'(?m)^name = .*$', lambda _: f'name = "{name}"', PENDULUM)
    text = re.sub(r'(?m)^title = .*$', lambda _: f'title = "{name}"', text)  # the report's heading
    text = re.sub(r'(?m)^description = .*$', lambda _: f'description = "{description}"', text)
    text = text.replace('unit = "kg"', f'unit = "{unit}"')
    path = tmp_path / "model.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_derive_latex_escapes_a_backslash_once(tmp_path: Path, capsys) -> None:
    path = _model(tmp_path, r"A\\B_c {x} 50%", r"one \\ backslash")
    assert main(["derive", "--latex", str(path)]) == 0
    out = capsys.readouterr().out
    assert r"\section*{A\textbackslash{}B\_c \{x\} 50\%}" in out
    assert r"one \textbackslash{} backslash" in out and r"\textbackslash\{\}" not in out


def test_markdown_report_shows_raw_html_as_text(tmp_path: Path) -> None:
    path = _model(tmp_path, "<iframe src=x></iframe>", "<script>alert(1)</script>", unit="<b>kg</b>")
    md = lagrangian.report(path, lang="en").markdown()
    for tag in ("iframe", "script", "b"):
        assert not re.search(rf"(?<!\\)<{tag}[ >]", md), tag  # every < of the file's text is escaped
    assert r"\<iframe src=x\>" in md and r"\<script\>alert(1)\</script\>" in md and r"\<b\>kg\</b\>" in md
