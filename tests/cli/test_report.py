"""``lagrangian report``, called in-process: formats, languages, the check, figures, atomic output."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from lagrangian_test_support import EXAMPLES_DIR

from lagrangian.cli.main import main


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
    assert out.startswith("# Mouvement de Lagrange\n")  # the model's French title
    assert "angles d’Euler" in out and r"\checkmark" in out  # the Newton–Euler check runs for 3 coordinates


@pytest.mark.slow
def test_format_from_the_suffix_and_language(tmp_path, capsys):
    for suffix, start in ((".html", "<!DOCTYPE html>"), (".tex", r"\documentclass"), (".md", "# Simple pendulum\n")):
        out = tmp_path / f"pendulum{suffix}"
        assert main(["report", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--lang", "en", "-o", str(out)]) == 0
        assert out.read_text(encoding="utf-8").startswith(start)
    assert capsys.readouterr().out == ""
    assert main(["report", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--format", "tex"]) == 0
    assert capsys.readouterr().out.startswith(r"\documentclass")


def test_no_verify_leaves_the_check_out(capsys):
    assert main(["report", "--no-verify"]) == 0
    assert r"\checkmark" not in capsys.readouterr().out


@pytest.mark.slow
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


@pytest.mark.slow
def test_simulate_to_tex_writes_the_figures_beside_it_with_french_captions(tmp_path):
    """-o top.tex goes through Report.save: PNG files beside it, \\includegraphics, captions in French."""
    out = tmp_path / "top.tex"
    assert main(["report", "--simulate", "1", "--set", "theta=0.5", "-o", str(out)]) == 0
    tex = out.read_text(encoding="utf-8")
    pngs = sorted(p.name for p in tmp_path.glob("top-figure-*.png"))
    # The statement's 3-D view and the motion's (still pictures), then the six plots.
    assert len(pngs) == 8 and all((tmp_path / p).read_bytes().startswith(b"\x89PNG") for p in pngs)
    assert tex.count(r"\includegraphics") == 8 and r"\fbox" not in tex and r"\usepackage{graphicx}" in tex
    assert "Le mouvement simulé (vue 3D" in tex and "Le système dans sa position initiale" in tex
    assert "Trajectoire de l’apex sur la sphère unité" in tex and "Réaction \\(R_{O}(t)\\)" in tex and "R\\_O" not in tex
    assert "Figure 3 : }" not in tex and "Figure 6 : }" not in tex


@pytest.mark.slow
def test_markdown_output_refers_to_figure_files(tmp_path):
    out = tmp_path / "top.md"
    assert main(["report", "--no-verify", "--simulate", "0.5", "-o", str(out)]) == 0
    md = out.read_text(encoding="utf-8")
    assert "data:image" not in md
    pngs = sorted(p.name for p in tmp_path.glob("top-figure-*.png"))
    assert pngs and all(f"]({name})" in md for name in pngs)


@pytest.mark.slow
def test_markdown_of_a_model_file_with_figures_writes_png_files(tmp_path):
    """``lagrangian report examples/lagrange_top.toml --simulate 2 -o top.md``: top.md, PNG files, no data: URI."""
    out = tmp_path / "top.md"
    assert main(["report", str(EXAMPLES_DIR / "lagrange_top.toml"), "--simulate", "2", "-o", str(out)]) == 0
    md = out.read_text(encoding="utf-8")
    pngs = sorted(p.name for p in tmp_path.glob("top-figure-*.png"))
    assert len(pngs) >= 2 and all((tmp_path / p).read_bytes().startswith(b"\x89PNG") for p in pngs)
    assert "data:image" not in md and all(f"]({name})" in md for name in pngs)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(pngs + ["top.md"])


@pytest.mark.slow
def test_the_notes_name_the_derive_command_for_the_model(capsys):
    assert main(["report", "zoo:planar_chain:14", "--no-verify", "--format", "html"]) == 0
    assert "lagrangian derive zoo:planar_chain:14 --json" in capsys.readouterr().out


def test_set_changes_the_values_shown_without_simulate(capsys):
    assert main(["report", "--no-verify", "--set", "g=1.62", "--set", "theta=0.5"]) == 0
    out = capsys.readouterr().out
    assert "| $`g`$ | 1,62 |" in out and "| 9,81 |" not in out
    assert "0,5" in out


@pytest.mark.slow
def test_zoo_models_by_name(capsys):
    assert main(["report", "zoo:planar_chain:3", "--lang", "en", "--no-verify"]) == 0
    out = capsys.readouterr().out
    assert r"\theta_{3}" in out
    for bad in ("zoo:nothing", "zoo:planar_chain", "zoo:planar_chain:x", "zoo:lagrange_top:3"):
        assert main(["report", bad]) == 2
        assert "zoo" in capsys.readouterr().err
