"""`lagrangian derive` on a robot: the course's view summarized, --expanded in full, --intermediates."""

from __future__ import annotations

import re

import pytest

import lagrangian
from lagrangian.analysis import first_integrals
from lagrangian.cli.main import main
from lagrangian.model.zoo import serial_arm
from lagrangian.output import course_form, needed_intermediates, render_text
from lagrangian.output._text import supplement


@pytest.mark.slow
def test_a_robots_course_view_is_summarized_and_expanded_on_request(capsys):
    assert main(["derive", "zoo:serial_arm:4"]) == 0
    short = capsys.readouterr().out
    assert "Lagrange equations" in short and "Matrix form M(q, t) q̈ = F(q, q̇, t):" in short
    assert "M[q4,q4] = m4 (cy4² + cz4²) + I1_4" in short  # short entries stay whole
    assert re.search(r"F\[q1\] = ⟨\d+ terms⟩", short) and "`lagrangian derive --expanded`" in short
    assert len(short) < 25_000  # the report's budget: a few thousand operations printed in all
    assert main(["derive", "zoo:serial_arm:4", "--expanded"]) == 0
    full = capsys.readouterr().out
    eom = lagrangian.derive(serial_arm(4))
    form = course_form(eom, first_integrals(eom))
    assert full == render_text(form, supplement(eom, form))  # the course's view, whole: what derive printed before
    assert "⟨" not in full and len(full) > 3 * len(short)


@pytest.mark.slow
def test_intermediates_listing_defines_every_name_before_use(capsys):
    assert main(["derive", "zoo:serial_arm:5", "--intermediates"]) == 0
    out = capsys.readouterr().out
    head, where = out.split("\nwhere\n")
    rec = lagrangian.derive(serial_arm(5)).recursive
    defined = re.findall(r"^  (w\d+) = (.*)$", where, flags=re.M)
    assert len(defined) == len(needed_intermediates(rec)) and f"{len(defined)} named intermediates" in head
    seen: set[str] = set()
    for name, formula in defined:
        assert set(re.findall(r"\bw\d+\b", formula)) <= seen, name
        seen.add(name)
    assert set(re.findall(r"\bw\d+\b", head)) <= seen
    # the motors' τ_j are inputs: in F, never in U (no potential −τ_j q_j)
    assert "F[q5] = τ5 − w" in head and "U = " in head and "τ1 q1" not in head


def test_intermediates_of_a_model_without_them_is_a_clear_error(capsys):
    assert main(["derive", "zoo:serial_arm:3", "--intermediates"]) == 2  # 3 joints: the course's route
    err = capsys.readouterr().err
    assert "derived by the course's route" in err and "leave out --intermediates" in err


def test_intermediates_are_text_only(capsys):
    assert main(["derive", "zoo:serial_arm:4", "--intermediates", "--json"]) != 0
    assert "--intermediates prints text only" in capsys.readouterr().err
