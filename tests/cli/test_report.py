"""``lagrangian report``, called in-process: formats, languages, the check, figures, atomic output."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from lagrangian.cli.main import main
from lagrangian_test_support import EXAMPLES_DIR


def test_help_lists_report(capsys):
    assert main([]) == 0
    assert "report" in capsys.readouterr().out
    with pytest.raises(SystemExit) as exc:
        main(["report", "--help"])
    assert exc.value.code == 0
    assert "--lang" in capsys.readouterr().out


def test_default_is_the_top_in_french_markdown(capsys):
    assert main(["report"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("# Équations de Lagrange — Lagrange top")
    assert "angles d'Euler" in out and r"\checkmark" in out  # the Newton–Euler check runs for 3 coordinates


def test_format_from_the_suffix_and_language(tmp_path, capsys):
    for suffix, start in ((".html", "<!DOCTYPE html>"), (".tex", r"\documentclass"), (".md", "# Lagrange's")):
        out = tmp_path / f"pendulum{suffix}"
        assert main(["report", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--lang", "en", "-o", str(out)]) == 0
        assert out.read_text(encoding="utf-8").startswith(start)
    assert capsys.readouterr().out == ""
    assert main(["report", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--format", "tex"]) == 0
    assert capsys.readouterr().out.startswith(r"\documentclass")


def test_no_verify_leaves_the_check_out(capsys):
    assert main(["report", "--no-verify"]) == 0
    assert r"\checkmark" not in capsys.readouterr().out


def test_simulate_adds_the_figures(tmp_path):
    out = tmp_path / "pendulum.html"
    assert main(["report", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--simulate", "2", "-o", str(out)]) == 0
    page = out.read_text(encoding="utf-8")
    assert page.count('src="data:image/png;base64,') >= 2 and 'id="simulation"' in page


def test_a_bad_model_fails_and_leaves_the_old_report(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('[coordinates]\nx = {}\n[particles.P]\nmass = "m"\nposition = "x*R0.x"\n', encoding="utf-8")
    out = tmp_path / "report.html"
    out.write_text("the previous report", encoding="utf-8")
    assert main(["report", str(bad), "-o", str(out)]) == 2
    assert "error" in capsys.readouterr().err
    assert out.read_text(encoding="utf-8") == "the previous report"


def test_a_failed_write_leaves_the_old_report(tmp_path, monkeypatch, capsys):
    out = tmp_path / "report.md"
    out.write_text("the previous report", encoding="utf-8")

    def broken(fd: int) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", broken)
    assert main(["report", "-o", str(out)]) == 3
    assert "No space left" in capsys.readouterr().err
    assert out.read_text(encoding="utf-8") == "the previous report"
    assert [p.name for p in Path(tmp_path).iterdir()] == ["report.md"]
