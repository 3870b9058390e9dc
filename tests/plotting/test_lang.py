"""Titles and captions in the report's language: the course's French words, never an empty caption."""

from __future__ import annotations

import pytest

from lagrangian.plotting import KINDS, applicable_kinds, figure_caption, plot_trajectory


@pytest.mark.parametrize("lang", ["fr", "en"])
def test_every_kind_has_a_caption(run, lang):
    eom, _ = run("lagrange_top.toml")
    captions = [figure_caption(kind, eom, lang) for kind in KINDS]
    assert all(c.strip() for c in captions) and len(set(captions)) == len(KINDS)
    if lang == "fr":
        assert "Trajectoire de l'apex sur la sphère unité" in captions
        assert "Réaction R_O(t)" in captions
        assert any("intégrales premières" in c for c in captions)


def _titles(fig) -> str:
    parts = [fig._suptitle.get_text() if fig._suptitle is not None else ""]
    parts += [ax.get_title() for ax in fig.axes] + [ax.get_ylabel() for ax in fig.axes]
    return "\n".join(parts)


@pytest.mark.slow
def test_french_titles(run):
    eom, traj = run("lagrange_top.toml")
    kinds = applicable_kinds(traj, eom)
    assert {"apex_sphere", "nutation", "reaction"} <= set(kinds)
    titles = {kind: _titles(plot_trajectory(traj, eom, kind, lang="fr")) for kind in kinds}
    assert "sur la sphère unité" in titles["apex_sphere"]
    assert "vu de dessus" in titles["nutation"]
    assert "réaction au point fixe O" in titles["reaction"]
    assert "dérive relative des intégrales premières" in titles["drift"]
    assert "portraits de phase" in titles["phase"]
    for kind, text in titles.items():
        for english in ("unit sphere", "seen from above", "relative drift", "phase portraits", "reaction at"):
            assert english not in text, (kind, english)


def _texts(fig) -> list[str]:
    """Every text of a drawn figure: titles, labels, legends and the tick labels the formatters wrote."""
    import matplotlib.text

    fig.canvas.draw()
    texts = [t.get_text() for t in fig.findobj(matplotlib.text.Text)]
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            texts += [t.get_text() for t in axis.get_ticklabels()] + [axis.get_offset_text().get_text()]
    return [t for t in texts if t]


@pytest.mark.slow
def test_french_figures_write_decimal_commas(run):
    """28,65° and 0,5 in a French figure (ticks, legends, titles), 28.65° and 0.5 in an English one."""
    import re

    import matplotlib.pyplot as plt

    eom, traj = run("lagrange_top.toml")
    for kind in ("nutation", "time_series"):
        fr = _texts(plot_trajectory(traj, eom, kind, lang="fr"))
        en = _texts(plot_trajectory(traj, eom, kind, lang="en"))
        plain = [re.sub(r"\$[^$]*\$", "", t) for t in fr]
        assert not [t for t in plain if re.search(r"\d\.\d", t)], fr
        assert any(re.search(r"\d,\d", t) for t in fr), fr
        assert any(re.search(r"\d\.\d", t) for t in en) and not any(re.search(r"\d,\d", t) for t in en), en
    plt.close("all")


def test_report_captions_set_their_symbols_as_math():
    """q_i(t), q̇_i(t), U_P, R_O(t) of the plotting captions are mathematics in the report, not raw underscores."""
    from lagrangian.output._report.document import Math
    from lagrangian.output._report.steps.extras import caption_runs

    assert caption_runs("Paramètres q_i(t) et vitesses q̇_i(t)") == (
        "Paramètres ", Math("q_{i}(t)"), " et vitesses ", Math(r"\dot{q}_{i}(t)"))
    assert caption_runs("Énergies T, U_P, E") == ("Énergies T, ", Math("U_{P}"), ", E")
    assert caption_runs("Réaction R_O(t)") == ("Réaction ", Math("R_{O}(t)"))
