"""Unilateral contacts in the outputs: derive's text and JSON, and the report's theorem of percussions."""

from __future__ import annotations

import json

import jsonschema
import pytest
from lagrangian_test_support import EXAMPLES_DIR, plain

import lagrangian
from lagrangian.cli.main import main
from lagrangian.output._report.document import Table, walk
from lagrangian.output._report.render.markdown import render_markdown

SCHEMA = json.loads((EXAMPLES_DIR.parent / "src" / "lagrangian" / "output" / "derive.schema.json").read_text())


@pytest.fixture(scope="module")
def ball() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bouncing_ball.toml"))


@pytest.mark.parametrize(("lang", "title", "words"), [
    ("fr", "Chocs : théorème des percussions", ("loi de Newton", "complémentarité linéaire", "choc")),
    ("en", "Impacts: the theorem of percussions", ("Newton's law", "linear complementarity", "impact")),
])
def test_the_report_states_the_theorem_of_percussions_and_lists_the_events(
        ball: lagrangian.EquationsOfMotion, lang: str, title: str, words: tuple[str, ...]) -> None:
    traj = lagrangian.simulate(ball, 2.0, n_out=21)
    r = lagrangian.report(ball, lang=lang, events=traj.events)
    [section] = [s for s in r.document.sections if s.key == "impacts"]
    assert plain(section.title) == title
    text = plain(render_markdown(r.document))
    for w in words:
        assert w in text
    assert r"\left[\frac{\partial T}{\partial \dot{q}_{i}}\right]_{t^{-}}^{t^{+}} = \sum_{k} P_{k}\, a_{k,i}" in text
    assert r"z \geq 0" in text  # step 1 writes the gap as an inequality
    tables = [b for b in walk(section.blocks) if isinstance(b, Table)]
    events = tables[-1]
    impacts = [e for e in traj.events if e.kind == "impact"]
    assert len(events.rows) == len(impacts) == 3
    decimal = "," if lang == "fr" else "."
    assert events.rows[0][0] == (f"0{decimal}451524",)


def test_the_report_of_a_model_with_contacts_has_no_event_table_without_a_simulation(
        ball: lagrangian.EquationsOfMotion) -> None:
    r = lagrangian.report(ball, lang="en")
    [section] = [s for s in r.document.sections if s.key == "impacts"]
    assert len([b for b in walk(section.blocks) if isinstance(b, Table)]) == 1  # the contacts' coefficients
    assert "impacts" not in [s.key for s in lagrangian.report(EXAMPLES_DIR / "simple_pendulum.toml").document.sections]


@pytest.mark.slow
def test_the_report_command_lists_the_events_of_its_simulation(tmp_path, monkeypatch) -> None:
    pytest.importorskip("matplotlib")
    import lagrangian.plotting

    monkeypatch.setattr(lagrangian.plotting, "applicable_kinds", lambda traj, eom: ())  # the events, not the figures
    out = tmp_path / "rope.md"
    assert main(["report", str(EXAMPLES_DIR / "slack_rope_pendulum.toml"), "--lang", "en", "--simulate", "1.5",
                 "--no-verify", "-o", str(out)]) == 0
    text = out.read_text()
    assert "| lift-off | the rope:" in text and "| impact | the rope:" in text


def test_derive_writes_the_complementarity_of_each_contact(capsys) -> None:
    assert main(["derive", str(EXAMPLES_DIR / "rocking_block.toml")]) == 0
    text = capsys.readouterr().out
    assert "left (complementary, unilateral): y − b sinθ − h cosθ ≥ 0, λ_left ≥ 0" in text
    assert "impacts: e = e, μ = μ" in text
    assert "[left_t, while the contact is closed and sticks]" in text
    assert "depend on which contacts are closed" in text  # no single formula for λ with two contacts


@pytest.mark.slow
def test_the_json_gives_each_contacts_law(capsys) -> None:
    assert main(["derive", str(EXAMPLES_DIR / "rocking_block.toml"), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    left = next(c for c in doc["constraints"] if c["name"] == "left")
    assert left["form"] == "unilateral" and left["contact"]["restitution"] == "e"
    assert left["contact"]["friction"] == "mu" and [r["name"] for r in left["rows"]] == ["left", "left_t"]
    assert "multiplier_formulas" not in doc
