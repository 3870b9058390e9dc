"""A model's texts in French and English: ``description = { fr = "…", en = "…" }`` and ``[model] title``."""

from __future__ import annotations

import pickle

import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.model._texts import Text, in_language
from lagrangian.output import report

PENDULUM = """\
[model]
name = "pendulum"
title = { fr = "Pendule simple", en = "Simple pendulum" }
description = { fr = "Un point au bout d'une tige", en = "A point on a rod" }

[parameters]
m = { value = 1.0, unit = "kg", description = { fr = "masse de P", en = "mass of P" } }
l = { value = 0.5, unit = "m", description = "OP = l" }
g = 9.81

[coordinates]
theta = { initial = 0.5, description = { fr = "angle avec la verticale descendante", en = "angle from the downward vertical" } }

[frames]
R1 = { from = "R0", rotation = ["theta", "x"], axes = ["x0", "y1", "z1"] }

[particles]
P = { mass = "m", position = "-l*R1.z" }

[loads]
weight = { gravity = "-g*R0.z" }
"""


@pytest.mark.slow
def test_texts_in_both_languages_and_a_plain_one():
    model = lagrangian.parse_model(PENDULUM)
    m, l = model.parameters[0].description, model.parameters[1].description
    assert isinstance(m, Text) and m == "mass of P" and m.in_language("fr") == "masse de P"
    assert l == "OP = l" and in_language(l, "fr") == "OP = l"  # a plain string serves both languages
    assert in_language(model.title, "fr") == "Pendule simple" and str(model.title) == "Simple pendulum"
    assert pickle.loads(pickle.dumps(m)).in_language("fr") == "masse de P"
    fr, en = report(model, lang="fr").document, report(model, lang="en").document
    assert (fr.title, fr.subtitle) == ("Pendule simple", "Un point au bout d\u2019une tige")  # French apostrophe
    assert (en.title, en.subtitle) == ("Simple pendulum", "A point on a rod")
    assert "masse de P" in report(model, lang="fr").markdown() and "mass of P" not in report(model, lang="fr").markdown()
    assert "angle from the downward vertical" in report(model, lang="en").markdown()


#: English words that the examples' texts use, and French ones: none may show in the other language's report.
ENGLISH = {"mass", "length", "angle of", "rod", "of the", "gravitational", "moment of inertia", "rolling", "position of",
           "radius", "the", "with", "from", "Pendulum", "top", "wheel", "frame", "spring", "belt"}
FRENCH = {"masse", "longueur", "tige", "de la", "du", "pesanteur", "moment d'inertie", "roulement", "rayon", "avec",
          "Pendule", "toupie", "roue", "cadre", "ressort", "tapis"}


def _words(text: str, words: set[str]) -> set[str]:
    import re

    return {w for w in words if re.search(rf"(?<![\w']){re.escape(w)}(?![\w'])", text)}


@pytest.mark.slow
def test_the_examples_texts_are_in_the_reports_language():
    """The title, subtitle and the tables of constants and coordinates of every example: French words only in
    the French report, English only in the English one (word lists)."""
    from lagrangian.output._report.document import Table, walk

    for path in sorted(EXAMPLES_DIR.glob("*.toml")):
        model = lagrangian.load_model(path)
        for lang, foreign in (("fr", ENGLISH), ("en", FRENCH)):
            doc = report(model, lang=lang).document if path.stem == "lagrange_top" else None
            texts = [in_language(model.title, lang) or "", in_language(model.description, lang) or ""]
            texts += [in_language(p.description, lang) or "" for p in model.parameters]
            texts += [in_language(c.description, lang) or "" for c in model.coordinates]
            texts += [in_language(c.description, lang) or "" for c in model.constraints]
            assert not _words(" ".join(texts), foreign), (path.name, lang, _words(" ".join(texts), foreign))
            if doc is not None:  # the texts reach the report: its title, subtitle and tables
                cells = " ".join(run for s in doc.sections for b in walk(s.blocks) if isinstance(b, Table)
                                 for row in b.rows for cell in row for run in cell if isinstance(run, str))
                assert not _words(" ".join([doc.title, doc.subtitle, cells]), foreign), (lang, doc.title)


@pytest.mark.slow
def test_a_urdf_robots_texts_are_in_the_reports_language():
    # A URDF has no French: the loader writes the robot's, the joints' and the inputs' texts in both
    # languages (liaison pivot, glissière, encastrement; couple de l'actionneur), the loads are named.
    import re

    model = lagrangian.load_model(EXAMPLES_DIR / "rrr_arm.urdf")
    english = {"joint", "torque", "actuator", "actuators", "weight", "damping", "link", "links", "limits", "speed",
               "the", "of", "with", "along", "robot with", "gravitational"}
    french = {"liaison", "couple", "actionneur", "actionneurs", "poids", "amortissement", "corps", "limites",
              "vitesse", "de la", "du", "selon", "pesanteur"}
    for lang, foreign in (("fr", english), ("en", french)):
        text = report(model, lang=lang).markdown()
        prose = re.sub(r"```math.*?```", "", re.sub(r"\$`.*?`\$", "", text), flags=re.S)
        prose = re.sub(r"`[^`]*`", "", prose)  # the joints' names, as the file writes them
        assert not _words(prose, foreign), (lang, _words(prose, foreign))
    fr = report(model, lang="fr").markdown()
    assert "liaison pivot" in fr and "couple de l\u2019actionneur de la liaison" in fr and "«\u00a0actionneurs\u00a0»" in fr
